#include "commands.hpp"

#include <cstring>

#include "../data.hpp"

namespace sciray::ospray::offload {

namespace {
enum class Call : std::uint8_t {
  new_object,
  new_holder,
  new_frame_buffer,
  new_data,
  update_data,
  copy_data,
  set_param,
  remove_param,
  commit,
  release,
  retain,
  render_frame,
  shutdown,
};

std::uint64_t id_of(const void* handle) {
  return reinterpret_cast<std::uintptr_t>(handle);
}

/// The array's elements, compacted, the first dimension fastest.
std::vector<std::byte> compact_elements(const Data& data) {
  const std::size_t element = size_of(data.element_type());
  std::vector<std::byte> out(data.size() * element);
  std::byte* next = out.data();
  const auto& n = data.counts();
  for (std::uint64_t k = 0; k < n[2]; ++k)
    for (std::uint64_t j = 0; j < n[1]; ++j)
      for (std::uint64_t i = 0; i < n[0]; ++i, next += element) std::memcpy(next, data.element(i, j, k), element);
  return out;
}

/// FNV-1a, to notice whether a shared array changed.
std::uint64_t hash_of(std::span<const std::byte> bytes) {
  std::uint64_t h = 14695981039346656037ull;
  for (const std::byte b : bytes) h = (h ^ static_cast<std::uint64_t>(b)) * 1099511628211ull;
  return h;
}

/// The array's shape, then whether its elements follow (for arrays sharing the
/// application's memory) and the elements.
void put_array(mpi::Writer& out, const void* handle, const Data& data, std::span<const std::byte> elements) {
  out.put(id_of(handle));
  out.put<std::int32_t>(data.element_type());
  for (const std::uint64_t n : data.counts()) out.put(n);
  out.put(data.shares_memory());
  if (data.shares_memory()) out.put_span(elements);
}
}  // namespace

void CommandLog::new_object(OSPDataType kind, const std::string& type, const void* handle) {
  std::lock_guard lock(mutex_);
  out_.put(Call::new_object);
  out_.put<std::int32_t>(kind);
  out_.put_string(type);
  out_.put(id_of(handle));
}

void CommandLog::new_holder(OSPDataType kind, const void* handle, const void* content) {
  std::lock_guard lock(mutex_);
  out_.put(Call::new_holder);
  out_.put<std::int32_t>(kind);
  out_.put(id_of(handle));
  out_.put(id_of(content));
}

void CommandLog::new_frame_buffer(const void* handle, int width, int height, OSPFrameBufferFormat format,
                                  std::uint32_t channels) {
  std::lock_guard lock(mutex_);
  out_.put(Call::new_frame_buffer);
  out_.put(id_of(handle));
  out_.put<std::int32_t>(width);
  out_.put<std::int32_t>(height);
  out_.put<std::int32_t>(format);
  out_.put(channels);
}

void CommandLog::new_data(const void* handle, const Data& data) {
  const std::vector<std::byte> elements = data.shares_memory() ? compact_elements(data) : std::vector<std::byte>();
  std::lock_guard lock(mutex_);
  out_.put(Call::new_data);
  put_array(out_, handle, data, elements);
  sent_elements_[handle] = hash_of(elements);
}

void CommandLog::update_data(const void* handle, const Data& data) {
  const std::vector<std::byte> elements = compact_elements(data);
  const std::uint64_t hash = hash_of(elements);
  std::lock_guard lock(mutex_);
  if (const auto sent = sent_elements_.find(handle); sent != sent_elements_.end() && sent->second == hash) return;
  out_.put(Call::update_data);
  put_array(out_, handle, data, elements);
  sent_elements_[handle] = hash;
}

void CommandLog::copy_data(const void* source, const void* destination, std::uint64_t i1, std::uint64_t i2,
                           std::uint64_t i3) {
  std::lock_guard lock(mutex_);
  out_.put(Call::copy_data);
  out_.put(id_of(source));
  out_.put(id_of(destination));
  out_.put(i1), out_.put(i2), out_.put(i3);
}

void CommandLog::set_param(const void* handle, const char* id, OSPDataType type, const void* value) {
  std::lock_guard lock(mutex_);
  out_.put(Call::set_param);
  out_.put(id_of(handle));
  out_.put_string(id);
  out_.put<std::int32_t>(type);
  if (type == OSP_STRING)
    out_.put_string(static_cast<const char*>(value));
  else if (is_object_type(type))
    out_.put(id_of(*static_cast<const void* const*>(value)));
  else if (type == OSP_VOID_PTR)
    out_.put<std::uint64_t>(0);  // an address on the application's rank means nothing elsewhere
  else
    out_.put_span(std::span(static_cast<const std::byte*>(value), size_of(type)));
}

void CommandLog::remove_param(const void* handle, const char* id) {
  std::lock_guard lock(mutex_);
  out_.put(Call::remove_param);
  out_.put(id_of(handle));
  out_.put_string(id);
}

void CommandLog::commit(const void* handle) {
  std::lock_guard lock(mutex_);
  out_.put(Call::commit);
  out_.put(id_of(handle));
}

void CommandLog::release(const void* handle) {
  std::lock_guard lock(mutex_);
  out_.put(Call::release);
  out_.put(id_of(handle));
}

void CommandLog::retain(const void* handle) {
  std::lock_guard lock(mutex_);
  out_.put(Call::retain);
  out_.put(id_of(handle));
}

void CommandLog::render_frame(const void* fb, const void* renderer, const void* camera, const void* world,
                              std::uint32_t frame_id) {
  std::lock_guard lock(mutex_);
  out_.put(Call::render_frame);
  for (const void* handle : {fb, renderer, camera, world}) out_.put(id_of(handle));
  out_.put(frame_id);
}

void CommandLog::shutdown() {
  std::lock_guard lock(mutex_);
  out_.put(Call::shutdown);
}

std::vector<std::byte> CommandLog::take() {
  std::lock_guard lock(mutex_);
  std::vector<std::byte> batch;
  std::swap(batch, out_.bytes());
  return batch;
}

// ---- replay on a worker -------------------------------------------------------------------

OSPObject Replayer::local(std::uint64_t handle) const {
  if (handle == 0) return nullptr;
  const auto found = handles_.find(handle);
  if (found == handles_.end())
    throw Error("mpiOffload worker: a command names object " + std::to_string(handle) +
                " that the application's rank never created here");
  return found->second;
}

void Replayer::add(std::uint64_t handle, OSPObject object) {
  if (!object) throw Error("mpiOffload worker: creating an object the application's rank created failed");
  handles_[handle] = object;  // an address the application's rank reuses names its new object
}

std::vector<std::byte> Replayer::local_elements(OSPDataType type, std::vector<std::byte> elements) const {
  if (!is_object_type(type)) return elements;
  for (std::size_t at = 0; at + sizeof(std::uint64_t) <= elements.size(); at += sizeof(void*)) {
    std::uint64_t handle;
    std::memcpy(&handle, &elements[at], sizeof handle);
    const OSPObject object = local(handle);
    std::memcpy(&elements[at], &object, sizeof object);
  }
  return elements;
}

bool Replayer::replay(std::span<const std::byte> batch, const RenderFrame& render_frame) {
  static_assert(sizeof(void*) == sizeof(std::uint64_t), "handles travel as 64-bit values");
  mpi::Reader in(batch);
  while (!in.done()) {
    switch (in.get<Call>()) {
      case Call::new_object: {
        const auto kind = static_cast<OSPDataType>(in.get<std::int32_t>());
        const std::string type = in.get_string();
        const auto handle = in.get<std::uint64_t>();
        const char* t = type.c_str();
        OSPObject object = nullptr;
        switch (kind) {
          case OSP_LIGHT: object = ospNewLight(t); break;
          case OSP_CAMERA: object = ospNewCamera(t); break;
          case OSP_GEOMETRY: object = ospNewGeometry(t); break;
          case OSP_VOLUME: object = ospNewVolume(t); break;
          case OSP_MATERIAL: object = ospNewMaterial(t); break;
          case OSP_TRANSFER_FUNCTION: object = ospNewTransferFunction(t); break;
          case OSP_TEXTURE: object = ospNewTexture(t); break;
          case OSP_RENDERER: object = ospNewRenderer(t); break;
          case OSP_IMAGE_OPERATION: object = ospNewImageOperation(t); break;
          case OSP_GROUP: object = ospNewGroup(); break;
          case OSP_WORLD: object = ospNewWorld(); break;
          default: throw Error("mpiOffload worker: cannot create objects of type " + type_name(kind));
        }
        add(handle, object);
        break;
      }
      case Call::new_holder: {
        const auto kind = static_cast<OSPDataType>(in.get<std::int32_t>());
        const auto handle = in.get<std::uint64_t>();
        const OSPObject content = local(in.get<std::uint64_t>());
        OSPObject object = nullptr;
        if (kind == OSP_GEOMETRIC_MODEL) object = ospNewGeometricModel(static_cast<OSPGeometry>(content));
        if (kind == OSP_VOLUMETRIC_MODEL) object = ospNewVolumetricModel(static_cast<OSPVolume>(content));
        if (kind == OSP_INSTANCE) object = ospNewInstance(static_cast<OSPGroup>(content));
        add(handle, object);
        break;
      }
      case Call::new_frame_buffer: {
        const auto handle = in.get<std::uint64_t>();
        const auto width = in.get<std::int32_t>(), height = in.get<std::int32_t>();
        const auto format = static_cast<OSPFrameBufferFormat>(in.get<std::int32_t>());
        const auto channels = in.get<std::uint32_t>();
        add(handle, ospNewFrameBuffer(width, height, format, channels));
        break;
      }
      case Call::new_data: {
        const auto handle = in.get<std::uint64_t>();
        const auto type = static_cast<OSPDataType>(in.get<std::int32_t>());
        const auto n1 = in.get<std::uint64_t>(), n2 = in.get<std::uint64_t>(), n3 = in.get<std::uint64_t>();
        if (!in.get<bool>()) {  // an array the API owns: filled by ospCopyData, replayed as such
          add(handle, ospNewData(type, n1, n2, n3));
          break;
        }
        auto* memory = new std::vector<std::byte>(local_elements(type, in.get_vector<std::byte>()));
        const auto release_memory = [](const void* user, const void*) {
          delete static_cast<const std::vector<std::byte>*>(user);
        };
        const OSPData data = ospNewSharedData(memory->data(), type, n1, 0, n2, 0, n3, 0, release_memory, memory);
        if (!data) delete memory;
        add(handle, data);
        array_memory_[handle] = memory;
        break;
      }
      case Call::update_data: {
        const auto handle = in.get<std::uint64_t>();
        const auto type = static_cast<OSPDataType>(in.get<std::int32_t>());
        for (int i = 0; i < 3; ++i) in.get<std::uint64_t>();
        in.get<bool>();
        const auto elements = local_elements(type, in.get_vector<std::byte>());
        const auto found = array_memory_.find(handle);
        if (found == array_memory_.end() || found->second->size() != elements.size())
          throw Error("mpiOffload worker: an update for an array it does not share");
        std::memcpy(found->second->data(), elements.data(), elements.size());
        break;
      }
      case Call::copy_data: {
        const OSPObject source = local(in.get<std::uint64_t>());
        const OSPObject destination = local(in.get<std::uint64_t>());
        const auto i1 = in.get<std::uint64_t>(), i2 = in.get<std::uint64_t>(), i3 = in.get<std::uint64_t>();
        ospCopyData(static_cast<OSPData>(source), static_cast<OSPData>(destination), i1, i2, i3);
        break;
      }
      case Call::set_param: {
        const OSPObject object = local(in.get<std::uint64_t>());
        const std::string id = in.get_string();
        const auto type = static_cast<OSPDataType>(in.get<std::int32_t>());
        if (type == OSP_STRING) {
          const std::string value = in.get_string();
          ospSetParam(object, id.c_str(), type, value.c_str());
        } else if (is_object_type(type) || type == OSP_VOID_PTR) {
          const OSPObject value = type == OSP_VOID_PTR ? nullptr : local(in.get<std::uint64_t>());
          if (type == OSP_VOID_PTR) in.get<std::uint64_t>();
          ospSetParam(object, id.c_str(), type, &value);
        } else {
          const auto value = in.get_vector<std::byte>();
          ospSetParam(object, id.c_str(), type, value.data());
        }
        break;
      }
      case Call::remove_param: {
        const OSPObject object = local(in.get<std::uint64_t>());
        ospRemoveParam(object, in.get_string().c_str());
        break;
      }
      case Call::commit: ospCommit(local(in.get<std::uint64_t>())); break;
      case Call::release: ospRelease(local(in.get<std::uint64_t>())); break;
      case Call::retain: ospRetain(local(in.get<std::uint64_t>())); break;
      case Call::render_frame: {
        const auto fb = static_cast<OSPFrameBuffer>(local(in.get<std::uint64_t>()));
        const auto renderer = static_cast<OSPRenderer>(local(in.get<std::uint64_t>()));
        const auto camera = static_cast<OSPCamera>(local(in.get<std::uint64_t>()));
        const auto world = static_cast<OSPWorld>(local(in.get<std::uint64_t>()));
        render_frame(fb, renderer, camera, world, in.get<std::uint32_t>());
        break;
      }
      case Call::shutdown: return false;
      default: throw Error("mpiOffload worker: unknown command (the ranks run different builds of sciray?)");
    }
  }
  return true;
}

}  // namespace sciray::ospray::offload
