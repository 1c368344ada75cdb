// The scene objects' shared parameter reading.
#include "scene_common.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "data.hpp"

namespace sciray::ospray {

namespace {

/// A one-element array holding the single value (or object) of `p`, of element type `type`.
Ref<Object> one_element_array(const Param& p, OSPDataType type) {
  const Object* handle = p.object.get();
  const void* value = is_object_type(type) ? static_cast<const void*>(&handle) : p.bytes.data();
  const Data view(value, type, {1, 1, 1}, {0, 0, 0}, nullptr, nullptr);
  Ref<Object> array(new Data(type, {1, 1, 1}));
  array->release();  // the Ref holds the only reference
  static_cast<Data&>(*array).copy_from(view, {0, 0, 0});
  return array;
}

}  // namespace

const Data* get_data(const Object& owner, const Param* p, const std::string& id,
                     std::initializer_list<OSPDataType> accepted, bool any_dimensions) {
  if (!p || (!p->object && is_object_type(p->type))) return nullptr;  // absent, or set to NULL
  const auto accepts = [&](OSPDataType t) { return std::find(accepted.begin(), accepted.end(), t) != accepted.end(); };
  std::string expected;
  for (auto t : accepted) expected += (expected.empty() ? "" : " or ") + type_name(t);
  const Data* data = nullptr;
  if (p->object && p->object->kind() == OSP_DATA) {
    data = static_cast<const Data*>(p->object.get());
  } else {
    // OSPRay's convention: a single value where an array is expected is a one-element array.
    const OSPDataType type = p->object ? p->object->kind() : p->type;
    if (!accepts(type))
      throw Error(owner.name() + ": parameter '" + id + "' must be an OSPData array of " + expected + " (or one " +
                  expected + "), got " + type_name(type));
    if (!p->as_array) p->as_array = one_element_array(*p, type);
    data = static_cast<const Data*>(p->as_array.get());
  }
  if (!accepts(data->element_type()))
    throw Error(owner.name() + ": parameter '" + id + "' must be an array of " + expected + ", got an array of " +
                type_name(data->element_type()));
  if (!any_dimensions && data->dimensions() != 1)
    throw Error(owner.name() + ": parameter '" + id + "' must be a 1D array");
  return data;
}

std::size_t per_item_count(const Object& owner, const std::string& id, const Data& data, std::size_t items,
                           const char* item_name, bool broadcast) {
  if (broadcast && data.size() == 1) return 1;
  if (data.size() < items)
    throw Error(owner.name() + ": parameter '" + id + "' has " + std::to_string(data.size()) + " elements but there are " +
                std::to_string(items) + " " + item_name + (broadcast ? " (give one for all, or one for each)" : ""));
  return items;
}

void append_per_item(PaddedVector<float>& out, const Object& owner, const std::string& id, const Data& data,
                     std::size_t items, const char* item_name, bool broadcast, int components, int pad_to) {
  const std::size_t given = per_item_count(owner, id, data, items, item_name, broadcast);
  pad_to = std::max(pad_to, components);
  out.reserve(out.size() + static_cast<std::size_t>(pad_to) * items);
  for (std::size_t i = 0; i < items; ++i) {
    const std::byte* e = data.element(given == 1 ? 0 : i);
    for (int c = 0; c < components; ++c) out.push_back(read_float(e + 4 * c));
    for (int c = components; c < pad_to; ++c) out.push_back(1.f);
  }
}

void append_floats(PaddedVector<float>& out, const Data& data, int components, int pad_to) {
  pad_to = std::max(pad_to, components);
  out.reserve(out.size() + static_cast<std::size_t>(pad_to) * data.size());
  for (std::uint64_t i = 0; i < data.size(); ++i) {
    for (int c = 0; c < components; ++c) out.push_back(read_float(data.element(i) + 4 * c));
    for (int c = components; c < pad_to; ++c) out.push_back(1.f);
  }
}

int get_enum(const Object& owner, int value, const char* id, std::initializer_list<const char*> names, int first) {
  if (value >= first && value - first < static_cast<int>(names.size())) return value - first;
  std::string known;
  int i = 0;
  for (const char* n : names) known += (i ? ", " : "") + std::string(n) + " = " + std::to_string(first + i), ++i;
  throw Error(owner.name() + ": parameter '" + id + "' has unknown value " + std::to_string(value) + " (" + known +
              ")");
}

std::pair<float, float> read_range(const Object& owner, const Param& p, const std::string& id) {
  if (p.type != OSP_BOX1F && p.type != OSP_VEC2F)
    throw Error(owner.name() + ": parameter '" + id + "' must be a box1f, got " + type_name(p.type));
  const float lower = read_float(p.bytes.data()), upper = read_float(p.bytes.data() + 4);
  if (!std::isfinite(lower) || !std::isfinite(upper))
    throw Error(owner.name() + ": parameter '" + id + "' is not finite");
  return {lower, upper};
}

Affine3f read_affine(const std::byte* p) {
  float m[12];
  std::memcpy(m, p, sizeof m);
  return {{m[0], m[1], m[2]}, {m[3], m[4], m[5]}, {m[6], m[7], m[8]}, {m[9], m[10], m[11]}};
}

namespace {

void check_affine(const Object& owner, const Affine3f& m, const std::string& what) {
  for (const Vec3f& v : {m.vx, m.vy, m.vz, m.p})
    if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z))
      throw Error(owner.name() + ": " + what + " is not finite");
  const float det = m.determinant();
  if (det == 0.f || !std::isfinite(det)) throw Error(owner.name() + ": " + what + " is singular");
}

}  // namespace

MotionTransform read_placement(const Object& owner, const std::function<const Param*(const std::string&)>& find) {
  const auto keys = [&](std::size_t count) {
    if (count < 2) return std::pair{0.f, 1.f};
    const Param* time = find("time");
    if (!time) return std::pair{0.f, 1.f};
    const auto range = read_range(owner, *time, "time");
    if (range.first > range.second)
      throw Error(owner.name() + ": parameter 'time' must have lower <= upper, got [" + std::to_string(range.first) +
                  ", " + std::to_string(range.second) + "]");
    return range;
  };
  if (const Data* data = get_data(owner, find("motion.transform"), "motion.transform", {OSP_AFFINE3F})) {
    if (data->size() == 0) throw Error(owner.name() + ": parameter 'motion.transform' is empty");
    std::vector<Affine3f> matrices;
    for (std::uint64_t k = 0; k < data->size(); ++k) {
      matrices.push_back(read_affine(data->element(k)));
      check_affine(owner, matrices.back(), "parameter 'motion.transform' element " + std::to_string(k));
    }
    const auto [start, end] = keys(matrices.size());
    return MotionTransform(std::move(matrices), start, end);
  }
  const char* const srt[] = {"motion.scale", "motion.pivot", "motion.rotation", "motion.translation"};
  const Data* arrays[4];
  std::uint64_t count = 0;
  bool any = false;
  for (int a = 0; a < 4; ++a) {
    arrays[a] = get_data(owner, find(srt[a]), srt[a], {a == 2 ? OSP_QUATF : OSP_VEC3F});
    if (!arrays[a]) continue;
    count = any ? std::min(count, arrays[a]->size()) : arrays[a]->size();
    any = true;
  }
  if (any) {
    if (count == 0) throw Error(owner.name() + ": its 'motion.*' arrays are empty");
    std::vector<QuaternionDecomposition> decompositions(count);
    for (std::uint64_t k = 0; k < count; ++k) {
      QuaternionDecomposition& d = decompositions[k];
      const auto vec3 = [&](int a) {
        const std::byte* e = arrays[a]->element(k);
        const Vec3f v{read_float(e), read_float(e + 4), read_float(e + 8)};
        if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z))
          throw Error(owner.name() + ": parameter '" + srt[a] + "' element " + std::to_string(k) + " is not finite");
        return v;
      };
      if (arrays[0]) d.scale = vec3(0);
      if (arrays[1]) d.shift = vec3(1);
      if (arrays[3]) d.translation = vec3(3);
      if (arrays[2]) {
        // OSPRay's quatf (rkcommon's) lies in memory as i, j, k, r: the real part last.
        const std::byte* e = arrays[2]->element(k);
        const Quaternion q{read_float(e + 12), read_float(e), read_float(e + 4), read_float(e + 8)};
        const float norm = std::sqrt(dot(q, q));
        if (!(std::abs(norm - 1.f) <= 1e-3f))
          throw Error(owner.name() + ": parameter 'motion.rotation' element " + std::to_string(k) +
                      " must be a unit quaternion, its length is " + std::to_string(norm));
        d.rotation = {q.r / norm, q.i / norm, q.j / norm, q.k / norm};
      }
      check_affine(owner, d.matrix(), "the 'motion.*' transform of key " + std::to_string(k));
    }
    const auto [start, end] = keys(decompositions.size());
    return MotionTransform(std::move(decompositions), start, end);
  }
  // An instance also takes OSPRay's older name `xfm` (OSPRay 3.1 reads it, and its test
  // scenes use it) where it has no `transform`.
  const char* id = owner.kind() == OSP_INSTANCE && !find("transform") && find("xfm") ? "xfm" : "transform";
  const Param* p = find(id);
  if (!p) return {};
  if (p->type != OSP_AFFINE3F)
    throw Error(owner.name() + ": parameter '" + id + "' must be an affine3f, got " + type_name(p->type));
  const Affine3f transform = read_affine(p->bytes.data());
  check_affine(owner, transform, std::string("parameter '") + id + "'");
  return MotionTransform(transform);
}

}  // namespace sciray::ospray
