#include "frame_objects.hpp"

namespace sciray::ospray {

namespace {
ColorFormat color_format(OSPFrameBufferFormat format) {
  switch (format) {
    case OSP_FB_NONE: return ColorFormat::none;
    case OSP_FB_RGBA8: return ColorFormat::rgba8;
    case OSP_FB_SRGBA: return ColorFormat::srgba;
    case OSP_FB_RGBA32F: return ColorFormat::rgba32f;
  }
  throw Error("frame buffer: unknown format " + std::to_string(static_cast<unsigned>(format)));
}
unsigned engine_channels(std::uint32_t channels) {
  unsigned c = channel_color;
  if (channels & OSP_FB_DEPTH) c |= channel_depth;
  if (channels & OSP_FB_ACCUM) c |= channel_accum;
  if (channels & OSP_FB_VARIANCE) c |= channel_variance;
  return c;
}
}  // namespace

FrameBufferObject::FrameBufferObject(int width, int height, OSPFrameBufferFormat format, std::uint32_t channels)
    : Object(OSP_FRAMEBUFFER, ""), frame_(width, height, color_format(format), engine_channels(channels)),
      channels_(channels) {}

const void* FrameBufferObject::map(OSPFrameBufferChannel channel) {
  const void* mapped = nullptr;
  switch (channel) {
    case OSP_FB_COLOR:
      if (frame_.format() == ColorFormat::none)
        throw Error("frame buffer: cannot map OSP_FB_COLOR of an OSP_FB_NONE frame buffer");
      mapped = frame_.format() == ColorFormat::rgba32f ? static_cast<const void*>(frame_.color32f().data())
                                                        : static_cast<const void*>(frame_.color8().data());
      break;
    case OSP_FB_DEPTH:
      if (!(channels_ & OSP_FB_DEPTH)) throw Error("frame buffer: cannot map OSP_FB_DEPTH: it was not created with it");
      mapped = frame_.depth().data();
      break;
    case OSP_FB_ACCUM:
      throw Error("frame buffer: OSP_FB_ACCUM cannot be mapped (OSPRay keeps it internal too)");
    default:
      throw Error("frame buffer: mapping channel " + std::to_string(static_cast<unsigned>(channel)) +
                  " is not supported yet (supported: OSP_FB_COLOR, OSP_FB_DEPTH)");
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
