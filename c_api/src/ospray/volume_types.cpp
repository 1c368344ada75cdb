// OSPRay's volume types beyond the regular grid and the unstructured mesh (volume.cpp):
// particle, structuredSpherical, vdb and amr, each read from OSPRay's parameters into the
// engine type's data, which checks it and names what is wrong.
#include "scene_common.hpp"

#include <cstring>
#include <string>

namespace sciray::ospray {

namespace {

/// The T stored at `e` (an array's element, which need not be aligned for T).
template <class T>
T bytes_as(const std::byte* e) {
  T value;
  std::memcpy(&value, e, sizeof value);
  return value;
}

}  // namespace

/// The elements of a 1D array of uint32 or uint64 (OSPRay takes either for indices).
std::vector<std::uint64_t> read_indices(const Data& data) {
  return data.element_type() == OSP_UINT ? data.to_vector<std::uint64_t>(bytes_as<std::uint32_t>)
                                         : data.to_vector<std::uint64_t>(bytes_as<std::uint64_t>);
}

std::vector<float> read_floats(const Data& data) {
  std::vector<float> out(static_cast<std::size_t>(data.size()));
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = read_float(data.element(i));
  return out;
}

std::vector<float> read_voxels_as_floats(const Data& data) {
  switch (data.element_type()) {
    case OSP_UCHAR: return data.to_vector<float>(bytes_as<std::uint8_t>);
    case OSP_SHORT: return data.to_vector<float>(bytes_as<std::int16_t>);
    case OSP_USHORT: return data.to_vector<float>(bytes_as<std::uint16_t>);
    case OSP_DOUBLE: return data.to_vector<float>([](const std::byte* e) { return static_cast<float>(bytes_as<double>(e)); });
    default: return data.to_vector<float>(read_float);
  }
}

namespace {

const std::initializer_list<OSPDataType> voxel_types = {OSP_UCHAR, OSP_SHORT, OSP_USHORT, OSP_FLOAT, OSP_DOUBLE};

std::vector<Vec3f> read_vec3fs(const Data& data) {
  return data.to_vector<Vec3f>([](const std::byte* e) { return Vec3f{read_float(e), read_float(e + 4), read_float(e + 8)}; });
}

/// The float arrays an array of arrays `list` (parameter `id` of `owner`) holds, one per
/// element, each in memory order (x fastest).
std::vector<std::vector<float>> read_float_arrays(const Object& owner, const Data& list, const std::string& id) {
  std::vector<std::vector<float>> out;
  for (std::size_t i = 0; i < list.size(); ++i) {
    const auto* array = static_cast<const Data*>(list.object(i));
    if (!array) throw Error(owner.name() + ": parameter '" + id + "' element " + std::to_string(i) + " is NULL");
    if (array->element_type() != OSP_FLOAT)
      throw Error(owner.name() + ": parameter '" + id + "' element " + std::to_string(i) +
                  " must be an array of float, got " + type_name(array->element_type()));
    out.push_back(read_voxels_as_floats(*array));
  }
  return out;
}

}  // namespace

/// The array parameter `id` of this volume, which must be set.
const Data& VolumeObject::required_data(const char* id, std::initializer_list<OSPDataType> types, const char* what) const {
  const Data* d = get_data(*this, find(id), id, types);
  if (!d) throw Error(name() + ": required parameter '" + id + "' (" + what + ") is missing");
  return *d;
}

VolumeFilter VolumeObject::filter_param(const char* id, VolumeFilter fallback) const {
  const int fallback_code = fallback == VolumeFilter::nearest  ? OSP_VOLUME_FILTER_NEAREST
                            : fallback == VolumeFilter::cubic ? OSP_VOLUME_FILTER_CUBIC
                                                              : OSP_VOLUME_FILTER_LINEAR;
  switch (const int f = get_int(id, fallback_code)) {
    case OSP_VOLUME_FILTER_NEAREST: return VolumeFilter::nearest;
    case OSP_VOLUME_FILTER_LINEAR: return VolumeFilter::linear;
    case OSP_VOLUME_FILTER_CUBIC: return VolumeFilter::cubic;
    default:
      throw Error(name() + ": parameter '" + id + "' has unknown value " + std::to_string(f) +
                  " (OSP_VOLUME_FILTER_NEAREST = 0, OSP_VOLUME_FILTER_LINEAR = 100, OSP_VOLUME_FILTER_CUBIC = 200)");
  }
}

/// OSPRay's `particle`: particle.position, particle.radius, particle.weight,
/// radiusSupportFactor, clampMaxCumulativeValue, estimateValueRanges, background.
EngineVolume VolumeObject::commit_particle() {
  ParticleData p;
  p.positions = read_vec3fs(required_data("particle.position", {OSP_VEC3F}, "array of vec3f"));
  p.radii = read_floats(required_data("particle.radius", {OSP_FLOAT}, "array of float"));
  if (const Data* weights = get_data(*this, find("particle.weight"), "particle.weight", {OSP_FLOAT}))
    p.weights = read_floats(*weights);
  p.radius_support_factor = get_float("radiusSupportFactor", p.radius_support_factor);
  p.clamp_max_cumulative_value = get_float("clampMaxCumulativeValue", p.clamp_max_cumulative_value);
  p.estimate_value_ranges = get_bool("estimateValueRanges", p.estimate_value_ranges);
  p.background = get_float("background", p.background);
  get_int("maxIteratorDepth", 0);  // Open VKL's interval iterator's: no counterpart here
  return std::make_shared<const Particles>(std::move(p));  // its errors name it "particle volume"
}

/// OSPRay's `structuredSpherical`: data (its dimensions are the grid's), gridOrigin,
/// gridSpacing (radius, inclination and azimuth, angles in degrees), background.
EngineVolume VolumeObject::commit_structured_spherical() {
  StructuredSphericalData s;
  const Data* given = get_data(*this, find("data"), "data", voxel_types, true);
  if (!given) throw Error(name() + ": required parameter 'data' (3D array of uchar, short, ushort, float or double) is missing");
  const Data& data = *given;
  const auto& n = data.counts();
  s.dimensions = {static_cast<std::int64_t>(n[0]), static_cast<std::int64_t>(n[1]), static_cast<std::int64_t>(n[2])};
  s.values = read_voxels_as_floats(data);
  s.grid_origin = get_vec3f("gridOrigin", s.grid_origin);
  s.grid_spacing = get_vec3f("gridSpacing", s.grid_spacing);
  s.background = get_float("background", s.background);
  return std::make_shared<const StructuredSpherical>(std::move(s));  // its errors name it "structuredSpherical volume"
}

/// OSPRay's `vdb`: node.level, node.origin, node.format, node.data (an array of arrays:
/// one value for a tile, 8x8x8 for a dense leaf) or nodesPackedDense and nodesPackedTile,
/// indexToObject (affine3f, or an array of 12 floats), filter, gradientFilter, background.
EngineVolume VolumeObject::commit_vdb() {
  VdbData v;
  v.level = required_data("node.level", {OSP_UINT}, "array of uint32").to_vector<std::uint32_t>(bytes_as<std::uint32_t>);
  v.origin = required_data("node.origin", {OSP_VEC3I}, "array of vec3i").to_vector<std::array<std::int32_t, 3>>(
      bytes_as<std::array<std::int32_t, 3>>);
  if (const Data* format = get_data(*this, find("node.format"), "node.format", {OSP_UINT}))
    v.format = format->to_vector<std::uint32_t>(bytes_as<std::uint32_t>);
  if (const Data* nodes = get_data(*this, find("node.data"), "node.data", {OSP_DATA}))
    v.data = read_float_arrays(*this, *nodes, "node.data");
  if (const Data* dense = get_data(*this, find("nodesPackedDense"), "nodesPackedDense", {OSP_FLOAT}))
    v.packed_dense = read_floats(*dense);
  if (const Data* tiles = get_data(*this, find("nodesPackedTile"), "nodesPackedTile", {OSP_FLOAT}))
    v.packed_tile = read_floats(*tiles);
  if (const Data* temporal = get_data(*this, find("node.temporalFormat"), "node.temporalFormat", {OSP_UINT}))
    v.temporal_format = temporal->to_vector<std::uint32_t>(bytes_as<std::uint32_t>);
  for (const char* id : {"node.temporallyStructuredNumTimesteps", "node.temporallyUnstructuredIndices",
                         "node.temporallyUnstructuredTimes"})
    v.temporal_arrays = v.temporal_arrays || find(id) != nullptr;
  if (const Param* p = find("indexToObject")) {
    if (p->type == OSP_AFFINE3F) {
      v.index_to_object = read_affine(p->bytes.data());
    } else {
      const Data* m = get_data(*this, p, "indexToObject", {OSP_FLOAT});
      if (!m || m->size() != 12)
        throw Error(name() + ": parameter 'indexToObject' must be an affine3f or an array of 12 floats");
      const std::vector<float> f = read_floats(*m);  // a row-major 3x3 matrix, then the translation
      v.index_to_object = {{f[0], f[3], f[6]}, {f[1], f[4], f[7]}, {f[2], f[5], f[8]}, {f[9], f[10], f[11]}};
    }
  }
  v.filter = filter_param("filter", VolumeFilter::linear);
  if (find("gradientFilter")) v.gradient_filter = filter_param("gradientFilter", v.filter);
  v.background = get_float("background", v.background);
  return std::make_shared<const Vdb>(std::move(v));  // its errors name it "vdb volume" and the node
}

/// OSPRay's `amr`: block.bounds, block.level, block.data (an array of float arrays, one
/// value per cell, x fastest), cellWidth, gridOrigin, gridSpacing, method, background.
EngineVolume VolumeObject::commit_amr() {
  AmrData a;
  a.block_bounds = required_data("block.bounds", {OSP_BOX3I}, "array of box3i").to_vector<AmrBox>(bytes_as<AmrBox>);
  a.block_level = required_data("block.level", {OSP_INT}, "array of int").to_vector<std::int32_t>(bytes_as<std::int32_t>);
  a.block_data = read_float_arrays(*this, required_data("block.data", {OSP_DATA}, "array of arrays of float"), "block.data");
  a.cell_width = read_floats(required_data("cellWidth", {OSP_FLOAT}, "array of float"));
  a.grid_origin = get_vec3f("gridOrigin", a.grid_origin);
  a.grid_spacing = get_vec3f("gridSpacing", a.grid_spacing);
  const int method = get_int("method", static_cast<int>(OSP_AMR_CURRENT));
  if (method < 0 || method > 255)
    throw Error(name() + ": parameter 'method' has unknown value " + std::to_string(method) +
                " (OSP_AMR_CURRENT = 0, OSP_AMR_FINEST = 1, OSP_AMR_OCTANT = 2)");
  a.method = static_cast<AmrMethod>(method);
  a.background = get_float("background", a.background);
  return std::make_shared<const Amr>(std::move(a));  // its errors name it "amr volume" and the block
}

}  // namespace sciray::ospray
