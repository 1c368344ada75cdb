#include "frame_objects.hpp"

#include "data.hpp"

namespace sciray::ospray {

namespace {
ColorFormat color_format(OSPFrameBufferFormat format) {
  switch (format) {
    case OSP_FB_NONE: return ColorFormat::none;
    case OSP_FB_RGBA8: return ColorFormat::rgba8;
    case OSP_FB_SRGBA: return ColorFormat::gamma22;  // OSPRay's encoding, not the sRGB curve
    case OSP_FB_RGBA32F: return ColorFormat::rgba32f;
  }
  throw Error("frame buffer: unknown format " + std::to_string(static_cast<unsigned>(format)));
}
unsigned engine_channels(std::uint32_t channels) {
  static constexpr std::pair<OSPFrameBufferChannel, Channel> pairs[] = {
      {OSP_FB_DEPTH, channel_depth},           {OSP_FB_ACCUM, channel_accum},
      {OSP_FB_VARIANCE, channel_variance},     {OSP_FB_NORMAL, channel_normal},
      {OSP_FB_ALBEDO, channel_albedo},         {OSP_FB_ID_PRIMITIVE, channel_id_primitive},
      {OSP_FB_ID_OBJECT, channel_id_object},   {OSP_FB_ID_INSTANCE, channel_id_instance}};
  unsigned c = channel_color;
  for (const auto& [osp, engine] : pairs)
    if (channels & osp) c |= engine;
  return c;
}
}  // namespace

void ImageOperationObject::on_commit() {
  if (subtype() == "debug") {
    operation_ = DebugMark{};
    return;
  }
  // The factory creates no other types.
  TonemapperParams p;
  p.exposure = get_float("exposure", p.exposure);
  p.contrast = get_float("contrast", p.contrast);
  p.shoulder = get_float("shoulder", p.shoulder);
  p.mid_in = get_float("midIn", p.mid_in);
  p.mid_out = get_float("midOut", p.mid_out);
  p.hdr_max = get_float("hdrMax", p.hdr_max);
  p.aces_color = get_bool("acesColor", p.aces_color);
  operation_ = Tonemapper(p);  // its errors name the tonemapper and the parameter
}

FrameBufferObject::FrameBufferObject(int width, int height, OSPFrameBufferFormat format, std::uint32_t channels)
    : Object(OSP_FRAMEBUFFER, ""),
      frame_(width, height, color_format(format), engine_channels(channels), sciray::ErrorEstimate::ospray),
      channels_(channels) {}

void FrameBufferObject::on_commit() {
  std::vector<ImageOperation> operations;
  const auto add = [&](const Object* o, const std::string& what) {
    if (!o) throw Error(name() + ": parameter 'imageOperation'" + what + " is NULL");
    if (o->kind() != OSP_IMAGE_OPERATION)
      throw Error(name() + ": parameter 'imageOperation'" + what + " must be an OSPImageOperation, got " +
                  type_name(o->kind()));
    operations.push_back(static_cast<const ImageOperationObject*>(o)->operation());
  };
  if (const Param* p = find("imageOperation"); p && p->object) {
    if (p->object->kind() == OSP_DATA) {
      const auto& list = static_cast<const Data&>(*p->object);
      if (list.element_type() != OSP_IMAGE_OPERATION && list.element_type() != OSP_OBJECT)
        throw Error(name() + ": parameter 'imageOperation' must be an array of OSPImageOperation, got an array of " +
                    type_name(list.element_type()));
      for (std::uint64_t i = 0; i < list.size(); ++i) add(list.object(i), " element " + std::to_string(i));
    } else {
      add(p->object.get(), "");  // a single operation, as ospSetObject would pass it
    }
  }
  std::lock_guard lock(mutex_);
  frame_.set_image_operations(std::move(operations));
}

const void* FrameBufferObject::map(OSPFrameBufferChannel channel) {
  const auto require = [&](OSPFrameBufferChannel c, const char* name) {
    if (!(channels_ & c)) throw Error(std::string("frame buffer: cannot map ") + name + ": it was not created with it");
  };
  const void* mapped = nullptr;
  switch (channel) {
    case OSP_FB_COLOR:
      if (frame_.format() == ColorFormat::none)
        throw Error("frame buffer: cannot map OSP_FB_COLOR of an OSP_FB_NONE frame buffer");
      mapped = frame_.format() == ColorFormat::rgba32f ? static_cast<const void*>(frame_.color32f().data())
                                                        : static_cast<const void*>(frame_.color8().data());
      break;
    case OSP_FB_DEPTH:
      require(channel, "OSP_FB_DEPTH");
      mapped = frame_.depth().data();
      break;
    case OSP_FB_NORMAL:
      require(channel, "OSP_FB_NORMAL");
      mapped = frame_.normal().data();
      break;
    case OSP_FB_ALBEDO:
      require(channel, "OSP_FB_ALBEDO");
      mapped = frame_.albedo().data();
      break;
    case OSP_FB_ID_PRIMITIVE:
      require(channel, "OSP_FB_ID_PRIMITIVE");
      mapped = frame_.primitive_id().data();
      break;
    case OSP_FB_ID_OBJECT:
      require(channel, "OSP_FB_ID_OBJECT");
      mapped = frame_.object_id().data();
      break;
    case OSP_FB_ID_INSTANCE:
      require(channel, "OSP_FB_ID_INSTANCE");
      mapped = frame_.instance_id().data();
      break;
    case OSP_FB_ACCUM:
      throw Error("frame buffer: OSP_FB_ACCUM cannot be mapped (OSPRay keeps it internal too)");
    case OSP_FB_VARIANCE:
      throw Error("frame buffer: OSP_FB_VARIANCE cannot be mapped (OSPRay keeps it internal too); ospGetVariance "
                  "reports the estimate");
    default:
      throw Error("frame buffer: cannot map channel " + std::to_string(static_cast<unsigned>(channel)) +
                  ": it is not an OSPFrameBufferChannel value");
  }
  std::lock_guard lock(mutex_);
  mapped_.insert(mapped);
  return mapped;
}

void FrameBufferObject::unmap(const void* mapped) {
  std::lock_guard lock(mutex_);
  const auto it = mapped_.find(mapped);
  if (it == mapped_.end()) throw Error("frame buffer: ospUnmapFrameBuffer of a pointer this frame buffer did not map");
  mapped_.erase(it);
}

Future::Future(std::function<void(FrameControl&)> task) : Object(OSP_FUTURE, "") {
  start_ = std::chrono::steady_clock::now();
  thread_ = std::thread([this, task = std::move(task)] {
    task(control_);
    std::lock_guard lock(mutex_);
    end_ = std::chrono::steady_clock::now();
    done_ = true;
    done_signal_.notify_all();
  });
}

Future::~Future() {
  if (thread_.joinable()) thread_.join();
}

bool Future::ready() const {
  std::lock_guard lock(mutex_);
  return done_;
}

void Future::wait() {
  std::unique_lock lock(mutex_);
  done_signal_.wait(lock, [&] { return done_; });
}

float Future::duration_seconds() const {
  std::lock_guard lock(mutex_);
  return done_ ? std::chrono::duration<float>(end_ - start_).count() : 0.f;
}

}  // namespace sciray::ospray
