#pragma once
// What the scene objects' sources share: reading parameters and array elements in
// OSPRay's conventions, and the few engine helpers more than one object family uses.
#include <cstring>
#include <functional>
#include <initializer_list>
#include <sstream>
#include <string>

#include "scene_objects.hpp"

namespace sciray::ospray {

/// The 1D (or, with `any_dimensions`, 2D or 3D) data array parameter `p` (named `id`) of
/// `owner`, with its element type among
/// `accepted`; null where it is absent or set to NULL. As in OSPRay, a single value (or
/// object) of an accepted type stands for a one-element array.
const Data* get_data(const Object& owner, const Param* p, const std::string& id,
                     std::initializer_list<OSPDataType> accepted, bool any_dimensions = false);

inline float read_float(const std::byte* p) {
  float v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

/// A box3f element: lower x, y, z, then upper x, y, z.
/// The elements of a 1D array of uint32 or uint64 (OSPRay takes either for indices).
std::vector<std::uint64_t> read_indices(const Data& data);
/// The elements of an array of float.
std::vector<float> read_floats(const Data& data);
/// The elements of an array of uchar, short, ushort, float or double as floats, x fastest.
std::vector<float> read_voxels_as_floats(const Data& data);

/// An affine3f parameter's 12 floats: the linear part's columns, then the translation.
Affine3f read_affine(const std::byte* p);

inline Box3f read_box(const std::byte* p) {
  Box3f b;
  b.lower = {read_float(p), read_float(p + 4), read_float(p + 8)};
  b.upper = {read_float(p + 12), read_float(p + 16), read_float(p + 20)};
  return b;
}

/// Appends `components` floats of every element of `data` to `out` (honouring its byte
/// strides), then `pad_to - components` ones: a vec3f colour becomes RGBA with alpha 1.
void append_floats(PaddedVector<float>& out, const Data& data, int components, int pad_to = 0);

/// OSPRay's per-item arrays (per vertex, per primitive): how many of `data`'s elements
/// give the `items` values — all `items` (elements beyond them are ignored, as OSPRay
/// does), or 1 where `broadcast` and the array has one element for all. Fewer is an
/// error naming the parameter and `item_name` ("vertices", "primitives").
std::size_t per_item_count(const Object& owner, const std::string& id, const Data& data, std::size_t items,
                           const char* item_name, bool broadcast = false);

/// append_floats for a per-item array (see per_item_count): `items` values, a single
/// element repeated where it stands for all.
void append_per_item(PaddedVector<float>& out, const Object& owner, const std::string& id, const Data& data,
                     std::size_t items, const char* item_name, bool broadcast, int components, int pad_to = 0);

/// An RGBA colour array (vec4f, or vec3f with alpha 1) copied into `out`.
inline void append_colors(PaddedVector<float>& out, const Data& data) {
  append_floats(out, data, data.element_type() == OSP_VEC4F ? 4 : 3, 4);
}

/// An OSPRay enum parameter (set as int, uint or uchar) whose names have the values
/// first, first + 1, ...: its index among them.
int get_enum(const Object& owner, int value, const char* id, std::initializer_list<const char*> names,
             int first = 0);

inline std::string format_vec(const Vec3f& v) {
  std::ostringstream out;
  out << "(" << v.x << ", " << v.y << ", " << v.z << ")";
  return out.str();
}

/// Where a camera or an instance is placed, from `owner`'s parameters as `find` returns
/// them (marking them used): `motion.transform` (affine3f keys), else the quaternion
/// decompositions of `motion.scale`, `motion.pivot`, `motion.rotation` and
/// `motion.translation` (as many keys as the shortest array), else the one `transform`.
/// Two or more keys span `time` (box1f, default [0, 1]); one key is a static transform.
MotionTransform read_placement(const Object& owner, const std::function<const Param*(const std::string&)>& find);

/// A box1f (or vec2f) parameter `p` named `id` as (lower, upper).
std::pair<float, float> read_range(const Object& owner, const Param& p, const std::string& id);

/// Why `material` cannot colour `geometry` yet ("" where it can): a volume texture
/// colours planes only (slices). What a model's commit and every world build (the
/// material may be recommitted later) check.
std::string cannot_colour(const Geometry& geometry, const Material* material);

/// Adds a copy of `model` to `world`, placed by `placement` (an instance's); returns the
/// engine's index of the placed volume.
std::size_t add_volume(shim::EngineWorld& world, const EngineVolumetricModel& model, const MotionTransform& placement);

}  // namespace sciray::ospray
