#include "object.hpp"

#include <cmath>

namespace sciray::ospray {

std::size_t size_of(OSPDataType type) {
  switch (type) {
    case OSP_BOOL: return sizeof(bool);
    case OSP_CHAR:
    case OSP_UCHAR: return 1;
    case OSP_VEC2C:
    case OSP_VEC2UC: return 2;
    case OSP_VEC3C:
    case OSP_VEC3UC: return 3;
    case OSP_VEC4C:
    case OSP_VEC4UC: return 4;
    case OSP_SHORT:
    case OSP_USHORT:
    case OSP_HALF: return 2;
    case OSP_VEC2S:
    case OSP_VEC2US:
    case OSP_VEC2H: return 4;
    case OSP_VEC3S:
    case OSP_VEC3US:
    case OSP_VEC3H: return 6;
    case OSP_VEC4S:
    case OSP_VEC4US:
    case OSP_VEC4H: return 8;
    case OSP_INT:
    case OSP_UINT:
    case OSP_FLOAT: return 4;
    case OSP_VEC2I:
    case OSP_VEC2UI:
    case OSP_VEC2F:
    case OSP_LONG:
    case OSP_ULONG:
    case OSP_DOUBLE:
    case OSP_BOX1I:
    case OSP_BOX1F: return 8;
    case OSP_VEC3I:
    case OSP_VEC3UI:
    case OSP_VEC3F: return 12;
    case OSP_VEC4I:
    case OSP_VEC4UI:
    case OSP_VEC4F:
    case OSP_VEC2L:
    case OSP_VEC2UL:
    case OSP_VEC2D:
    case OSP_BOX2I:
    case OSP_BOX2F:
    case OSP_LINEAR2F:
    case OSP_QUATF: return 16;
    case OSP_VEC3L:
    case OSP_VEC3UL:
    case OSP_VEC3D:
    case OSP_BOX3I:
    case OSP_BOX3F:
    case OSP_AFFINE2F: return 24;
    case OSP_VEC4L:
    case OSP_VEC4UL:
    case OSP_VEC4D:
    case OSP_BOX4I:
    case OSP_BOX4F: return 32;
    case OSP_LINEAR3F: return 36;
    case OSP_AFFINE3F: return 48;
    case OSP_VOID_PTR: return sizeof(void*);
    default: return is_object_type(type) ? sizeof(void*) : 0;
  }
}

std::string type_name(OSPDataType type) {
  switch (type) {
    case OSP_BOOL: return "bool";
    case OSP_STRING: return "string";
    case OSP_CHAR: return "char";
    case OSP_UCHAR: return "uchar";
    case OSP_SHORT: return "short";
    case OSP_USHORT: return "ushort";
    case OSP_INT: return "int";
    case OSP_UINT: return "uint";
    case OSP_LONG: return "long";
    case OSP_ULONG: return "ulong";
    case OSP_HALF: return "half";
    case OSP_FLOAT: return "float";
    case OSP_DOUBLE: return "double";
    case OSP_VEC2UC: return "vec2uc";
    case OSP_VEC3UC: return "vec3uc";
    case OSP_VEC4UC: return "vec4uc";
    case OSP_VEC2US: return "vec2us";
    case OSP_VEC3US: return "vec3us";
    case OSP_VEC4US: return "vec4us";
    case OSP_VEC2H: return "vec2h";
    case OSP_VEC3H: return "vec3h";
    case OSP_VEC4H: return "vec4h";
    case OSP_VEC2F: return "vec2f";
    case OSP_VEC3F: return "vec3f";
    case OSP_VEC4F: return "vec4f";
    case OSP_VEC2I: return "vec2i";
    case OSP_VEC3I: return "vec3i";
    case OSP_VEC4I: return "vec4i";
    case OSP_VEC2UI: return "vec2ui";
    case OSP_VEC3UI: return "vec3ui";
    case OSP_VEC4UI: return "vec4ui";
    case OSP_BOX1F: return "box1f";
    case OSP_BOX3F: return "box3f";
    case OSP_LINEAR2F: return "linear2f";
    case OSP_AFFINE2F: return "affine2f";
    case OSP_LINEAR3F: return "linear3f";
    case OSP_AFFINE3F: return "affine3f";
    case OSP_VOID_PTR: return "void*";
    case OSP_OBJECT: return "OSPObject";
    case OSP_DATA: return "OSPData";
    case OSP_CAMERA: return "OSPCamera";
    case OSP_FRAMEBUFFER: return "OSPFrameBuffer";
    case OSP_FUTURE: return "OSPFuture";
    case OSP_GEOMETRIC_MODEL: return "OSPGeometricModel";
    case OSP_GEOMETRY: return "OSPGeometry";
    case OSP_GROUP: return "OSPGroup";
    case OSP_IMAGE_OPERATION: return "OSPImageOperation";
    case OSP_INSTANCE: return "OSPInstance";
    case OSP_LIGHT: return "OSPLight";
    case OSP_MATERIAL: return "OSPMaterial";
    case OSP_RENDERER: return "OSPRenderer";
    case OSP_TEXTURE: return "OSPTexture";
    case OSP_TRANSFER_FUNCTION: return "OSPTransferFunction";
    case OSP_VOLUME: return "OSPVolume";
    case OSP_VOLUMETRIC_MODEL: return "OSPVolumetricModel";
    case OSP_WORLD: return "OSPWorld";
    default: return "type " + std::to_string(static_cast<unsigned>(type));
  }
}

std::string Object::name() const {
  std::string kind = type_name(kind_);
  if (kind.rfind("OSP", 0) == 0) kind = kind.substr(3);
  for (auto& c : kind) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (kind == "geometricmodel") kind = "geometric model";
  if (kind == "framebuffer") kind = "frame buffer";
  if (kind == "volumetricmodel") kind = "volumetric model";
  if (kind == "transferfunction") kind = "transfer function";
  if (kind == "imageoperation") kind = "image operation";
  return subtype_.empty() ? kind : subtype_ + " " + kind;
}

void Object::set_param(const std::string& id, OSPDataType type, const void* mem) {
  if (id.empty()) throw Error(name() + ": parameter name is empty");
  if (!mem) throw Error(name() + ": parameter '" + id + "': value pointer is NULL");
  Param p;
  p.type = type;
  if (type == OSP_STRING) {
    p.string = static_cast<const char*>(mem);
  } else if (is_object_type(type)) {
    auto* handle = *static_cast<Object* const*>(mem);
    if (handle) {
      if (!Registry::instance().alive(handle))
        throw Error(name() + ": parameter '" + id + "': the object handle is invalid or was released");
      // OSP_OBJECT is a wildcard; a specific kind must match the object's.
      if (type != OSP_OBJECT && handle->kind() != type)
        throw Error(name() + ": parameter '" + id + "' was set as " + type_name(type) + " but the object is " +
                    type_name(handle->kind()));
      p.type = handle->kind();
      if (refers_to(*handle, *this))
        throw Error(name() + ": parameter '" + id + "': " + handle->name() + " refers to this " + name() +
                    " (directly or through other objects): a cycle of references, never released");
    }
    p.object = handle;
  } else {
    const std::size_t n = size_of(type);
    if (n == 0) throw Error(name() + ": parameter '" + id + "': unsupported type " + type_name(type));
    p.bytes.resize(n);
    std::memcpy(p.bytes.data(), mem, n);
  }
  staged_[id] = std::move(p);
}

const Object* first_referring_to(std::span<const Object* const> from, const Object& target) {
  // Each object visited once, with the start it was first reached from.
  std::vector<std::pair<const Object*, const Object*>> to_visit;
  std::unordered_set<const Object*> seen;
  for (const Object* start : from)
    if (seen.insert(start).second) to_visit.emplace_back(start, start);
  while (!to_visit.empty()) {
    const auto [o, start] = to_visit.back();
    to_visit.pop_back();
    if (o == &target) return start;
    o->for_each_reference([&, start = start](const Object& next) {
      if (seen.insert(&next).second) to_visit.emplace_back(&next, start);
    });
  }
  return nullptr;
}

void Object::for_each_reference(const std::function<void(const Object&)>& visit) const {
  for (const auto* params : {&staged_, &committed_})
    for (const auto& [id, p] : *params)
      if (p.object) visit(*p.object);
}

std::vector<std::string> Object::commit() {
  auto previous = committed_;
  committed_ = staged_;
  for (auto& [id, p] : committed_) p.used = false;
  debug_messages_.clear();
  try {
    on_commit();
  } catch (...) {
    committed_ = std::move(previous);  // a failed commit leaves the object as it was
    throw;
  }
  version_ = next_version();
  std::vector<std::string> unused;
  for (const auto& [id, p] : committed_)
    if (!p.used) unused.push_back(id);
  return unused;
}

const Param* Object::find(const std::string& id) const {
  const auto it = committed_.find(id);
  if (it == committed_.end()) return nullptr;
  it->second.used = true;
  return &it->second;
}

namespace {
[[noreturn]] void wrong_type(const Object& o, const std::string& id, const Param& p, const char* expected) {
  throw Error(o.name() + ": parameter '" + id + "' must be " + expected + ", got " + type_name(p.type));
}
template <class T>
T load(const Param& p, std::size_t index = 0) {
  T v;
  std::memcpy(&v, p.bytes.data() + index * sizeof(T), sizeof(T));
  return v;
}
}  // namespace

float Object::get_float(const std::string& id, float fallback) const {
  const Param* p = find(id);
  if (!p) return fallback;
  switch (p->type) {
    case OSP_FLOAT: return load<float>(*p);
    case OSP_DOUBLE: return static_cast<float>(load<double>(*p));
    case OSP_INT: return static_cast<float>(load<std::int32_t>(*p));
    case OSP_UINT: return static_cast<float>(load<std::uint32_t>(*p));
    default: wrong_type(*this, id, *p, "a float");
  }
}

int Object::get_int(const std::string& id, int fallback) const {
  const Param* p = find(id);
  if (!p) return fallback;
  switch (p->type) {
    case OSP_INT: return load<std::int32_t>(*p);
    case OSP_UINT: return static_cast<int>(load<std::uint32_t>(*p));
    case OSP_UCHAR: return load<std::uint8_t>(*p);
    case OSP_SHORT: return load<std::int16_t>(*p);
    case OSP_USHORT: return load<std::uint16_t>(*p);
    case OSP_LONG: return static_cast<int>(load<std::int64_t>(*p));
    case OSP_ULONG: return static_cast<int>(load<std::uint64_t>(*p));
    default: wrong_type(*this, id, *p, "an integer");
  }
}

std::optional<std::uint32_t> Object::get_user_id() const {
  const Param* p = find("id");
  if (!p) return std::nullopt;
  if (p->type != OSP_UINT) wrong_type(*this, "id", *p, "a uint (OSPRay reads the user id only as OSP_UINT)");
  const auto id = load<std::uint32_t>(*p);
  if (id == 0xFFFFFFFFu) return std::nullopt;
  return id;
}

bool Object::get_bool(const std::string& id, bool fallback) const {
  const Param* p = find(id);
  if (!p) return fallback;
  if (p->type == OSP_BOOL) return load<bool>(*p);
  if (p->type == OSP_INT) return load<std::int32_t>(*p) != 0;
  wrong_type(*this, id, *p, "a bool");
}

Vec3f Object::get_vec3f(const std::string& id, Vec3f fallback) const {
  const Param* p = find(id);
  if (!p) return fallback;
  Vec3f v;
  if (p->type == OSP_VEC3F) {
    v = {load<float>(*p, 0), load<float>(*p, 1), load<float>(*p, 2)};
  } else if (p->type == OSP_FLOAT) {
    const float f = load<float>(*p);
    v = {f, f, f};
  } else if (p->type == OSP_VEC3I) {
    v = {float(load<std::int32_t>(*p, 0)), float(load<std::int32_t>(*p, 1)), float(load<std::int32_t>(*p, 2))};
  } else {
    wrong_type(*this, id, *p, "a vec3f");
  }
  if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z))
    throw Error(name() + ": parameter '" + id + "' is not finite");
  return v;
}

std::array<float, 4> Object::get_color4(const std::string& id, std::array<float, 4> fallback) const {
  const Param* p = find(id);
  if (!p) return fallback;
  if (p->type == OSP_VEC4F) return {load<float>(*p, 0), load<float>(*p, 1), load<float>(*p, 2), load<float>(*p, 3)};
  // OSPRay's promotions: a vec3f or a float colour gets alpha 0.
  if (p->type == OSP_VEC3F) return {load<float>(*p, 0), load<float>(*p, 1), load<float>(*p, 2), 0.f};
  if (p->type == OSP_FLOAT) return {load<float>(*p), load<float>(*p), load<float>(*p), 0.f};
  wrong_type(*this, id, *p, "a vec4f, vec3f or float colour");
}

}  // namespace sciray::ospray
