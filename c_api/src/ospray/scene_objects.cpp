#include "scene_objects.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <optional>
#include <sstream>
#include <string>
#include <type_traits>

namespace sciray::ospray {

namespace {

/// The 1D data array parameter `id` of `owner`, with its element type among `accepted`.
const Data* get_data(const Object& owner, const Param* p, const std::string& id,
                     std::initializer_list<OSPDataType> accepted) {
  if (!p || (!p->object && is_object_type(p->type))) return nullptr;  // absent, or set to NULL
  if (!p->object || p->object->kind() != OSP_DATA)
    throw Error(owner.name() + ": parameter '" + id + "' must be an OSPData array, got " +
                type_name(p->object ? p->object->kind() : p->type));
  const auto* data = static_cast<const Data*>(p->object.get());
  if (std::find(accepted.begin(), accepted.end(), data->element_type()) == accepted.end()) {
    std::string expected;
    for (auto t : accepted) expected += (expected.empty() ? "" : " or ") + type_name(t);
    throw Error(owner.name() + ": parameter '" + id + "' must be an array of " + expected + ", got an array of " +
                type_name(data->element_type()));
  }
  if (data->dimensions() != 1) throw Error(owner.name() + ": parameter '" + id + "' must be a 1D array");
  return data;
}

float read_float(const std::byte* p) {
  float v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

}  // namespace

void CameraObject::on_commit() {
  const Vec3f position = get_vec3f("position", {0.f, 0.f, 0.f});
  const Vec3f direction = get_vec3f("direction", {0.f, 0.f, 1.f});
  const Vec3f up = get_vec3f("up", {0.f, 1.f, 0.f});
  const auto stereo = [&] { return stereo_mode_from_int(subtype(), get_int("stereoMode", OSP_STEREO_NONE)); };
  Camera camera;
  if (subtype() == "perspective") {
    PerspectiveCamera c;
    c.position = position, c.direction = direction, c.up = up;
    c.fovy = get_float("fovy", c.fovy);
    c.aspect = get_float("aspect", c.aspect);
    c.aperture_radius = get_float("apertureRadius", c.aperture_radius);
    c.focus_distance = get_float("focusDistance", c.focus_distance);
    c.stereo_mode = stereo();
    c.interpupillary_distance = get_float("interpupillaryDistance", c.interpupillary_distance);
    camera = c;
  } else if (subtype() == "orthographic") {
    OrthographicCamera c;
    c.position = position, c.direction = direction, c.up = up;
    c.height = get_float("height", c.height);
    c.aspect = get_float("aspect", c.aspect);
    camera = c;
  } else {
    PanoramicCamera c;
    c.position = position, c.direction = direction, c.up = up;
    c.stereo_mode = stereo();
    c.interpupillary_distance = get_float("interpupillaryDistance", c.interpupillary_distance);
    camera = c;
  }
  std::visit([](const auto& c) { prepare(c); }, camera);  // validates, naming the bad parameter
  camera_ = camera;
}

void Material::on_commit() {
  // The factory creates only types the engine has.
  sciray::Material material = *material_of_type(subtype());
  if (subtype() == "metal" && find("ior"))
    throw Error(name() + ": parameter 'ior' (a spectral array) is not supported; pass RGB 'eta' and 'k'");
  for_each_parameter(material, [&](const char* id, auto& field) { read_into(id, field); });
  try {
    validate(material);
  } catch (const Error& e) {
    throw Error(name() + ": " + e.what());
  }
  // Maps: texture2d images for every map of the type; a volume texture as obj map_kd only
  // (it colours planes: slices). Each map's transform as OSPRay names it.
  Ref<TextureObject> volume_map_kd;
  std::vector<ImageMap> image_maps;
  for_each_map(material, [&](const char* id, TextureMap&) {
    const std::string map = id;
    Ref<TextureObject> texture = get_object<TextureObject>(map, OSP_TEXTURE, false);
    if (!texture) return;
    if (!texture->committed()) throw Error(name() + ": parameter '" + map + "': its texture has not been committed");
    if (texture->volume_model()) {
      if (map != "map_kd")
        throw Error(name() + ": parameter '" + map + "': a volume texture colours only an obj material's map_kd; "
                             "give a texture2d");
      volume_map_kd = std::move(texture);
      return;
    }
    const auto vec2 = [&](const std::string& key, TexCoord<float> fallback) {
      const Param* p = find(key);
      if (!p) return fallback;
      if (p->type != OSP_VEC2F) throw Error(name() + ": parameter '" + key + "' must be a vec2f, got " + type_name(p->type));
      TexCoord<float> v;
      std::memcpy(&v, p->bytes.data(), sizeof v);
      return v;
    };
    TexCoordTransform transform;
    if (const Param* p = find(map + ".transform")) {
      if (p->type != OSP_AFFINE2F)
        throw Error(name() + ": parameter '" + map + ".transform' must be an affine2f, got " + type_name(p->type));
      std::memcpy(&transform, p->bytes.data(), sizeof transform);  // vx, vy, p: as OSPRay's affine2f
    } else if (has(map + ".rotation") || has(map + ".scale") || has(map + ".translation")) {
      const TexCoord<float> scale = vec2(map + ".scale", {1.f, 1.f});
      if (!(scale.u != 0.f && scale.v != 0.f))
        throw Error(name() + ": parameter '" + map + ".scale' must not be zero");
      transform = TexCoordTransform::of_texture(get_float(map + ".rotation", 0.f), scale,
                                                vec2(map + ".translation", {0.f, 0.f}));
    }
    if (!transform.finite()) throw Error(name() + ": parameter '" + map + "': its transform is not finite");
    image_maps.push_back({map, std::move(texture), transform});
  });
  material_ = std::move(material);
  volume_map_kd_ = std::move(volume_map_kd);
  image_maps_ = std::move(image_maps);
}

sciray::Material Material::material() const {
  sciray::Material m = material_;
  for_each_map(m, [&](const char* id, TextureMap& map) {
    for (const ImageMap& image : image_maps_)
      if (image.name == id) map = {image.texture->image(), image.transform};
  });
  return m;
}

std::optional<Vec3f> Material::base_color() const {
  if (const auto* obj = std::get_if<ObjMaterial>(&material_)) return obj->kd;
  if (const auto* principled = std::get_if<PrincipledMaterial>(&material_)) return principled->base_color;
  return std::nullopt;
}

sciray::Material Material::without_base_color() const {
  sciray::Material m = material();
  if (auto* obj = std::get_if<ObjMaterial>(&m)) obj->kd = {1.f, 1.f, 1.f};
  if (auto* principled = std::get_if<PrincipledMaterial>(&m)) principled->base_color = {1.f, 1.f, 1.f};
  return m;
}

std::uint64_t Material::version() const {
  std::uint64_t v = std::max(version_, volume_map_kd_ ? volume_map_kd_->version() : 0);
  for (const ImageMap& image : image_maps_) v = std::max(v, image.texture->version());
  return v;
}

namespace {

/// Appends `components` floats of every element of `data` to `out` (honouring its byte
/// strides), then `pad_to - components` ones: a vec3f colour becomes RGBA with alpha 1.
void append_floats(PaddedVector<float>& out, const Data& data, int components, int pad_to = 0) {
  pad_to = std::max(pad_to, components);
  out.reserve(out.size() + static_cast<std::size_t>(pad_to) * data.size());
  for (std::uint64_t i = 0; i < data.size(); ++i) {
    for (int c = 0; c < components; ++c) out.push_back(read_float(data.element(i) + 4 * c));
    for (int c = components; c < pad_to; ++c) out.push_back(1.f);
  }
}

/// An RGBA colour array (vec4f, or vec3f with alpha 1) copied into `out`.
void append_colors(PaddedVector<float>& out, const Data& data) {
  append_floats(out, data, data.element_type() == OSP_VEC4F ? 4 : 3, 4);
}

/// An OSPRay enum parameter (set as int, uint or uchar) in [0, count), by its names.
int get_enum(const Object& owner, int value, const char* id, std::initializer_list<const char*> names) {
  if (value >= 0 && value < static_cast<int>(names.size())) return value;
  std::string known;
  int i = 0;
  for (const char* n : names) known += (i ? ", " : "") + std::string(n) + " = " + std::to_string(i), ++i;
  throw Error(owner.name() + ": parameter '" + id + "' has unknown value " + std::to_string(value) + " (" + known +
              ")");
}

}  // namespace

void Geometry::on_commit() {
  // The factory creates no other types.
  if (subtype() == "sphere")
    commit_spheres();
  else if (subtype() == "curve")
    commit_curves();
  else if (subtype() == "box")
    commit_boxes();
  else if (subtype() == "plane")
    commit_planes();
  else if (subtype() == "isosurface")
    commit_isosurface();
  else
    commit_mesh();
}

void Geometry::commit_mesh() {
  const Data* position = get_data(*this, find("vertex.position"), "vertex.position", {OSP_VEC3F});
  if (!position) throw Error(name() + ": required parameter 'vertex.position' (array of vec3f) is missing");
  const Data* index = get_data(*this, find("index"), "index", {OSP_VEC3UI, OSP_VEC3I, OSP_VEC4UI, OSP_VEC4I});
  if (!index) throw Error(name() + ": required parameter 'index' (array of vec3ui or vec4ui) is missing");
  const Data* normal = get_data(*this, find("vertex.normal"), "vertex.normal", {OSP_VEC3F});
  const Data* color = get_data(*this, find("vertex.color"), "vertex.color", {OSP_VEC4F, OSP_VEC3F});
  const Data* texcoord = get_data(*this, find("vertex.texcoord"), "vertex.texcoord", {OSP_VEC2F});

  // A copy, padded for Embree: the application's arrays carry no padding guarantee.
  auto mesh = std::make_shared<MeshData>();
  append_floats(mesh->positions, *position, 3);
  const bool quads = index->element_type() == OSP_VEC4UI || index->element_type() == OSP_VEC4I;
  mesh->vertices_per_face = quads ? 4 : 3;
  mesh->indices.reserve(mesh->vertices_per_face * index->size());
  for (std::uint64_t f = 0; f < index->size(); ++f)
    for (unsigned c = 0; c < mesh->vertices_per_face; ++c) {
      std::uint32_t v;
      std::memcpy(&v, index->element(f) + 4 * c, sizeof v);  // a negative int becomes out of range
      mesh->indices.push_back(v);
    }
  if (normal) append_floats(mesh->normals, *normal, 3);
  if (color) append_colors(mesh->vertex_colors, *color);
  if (texcoord) append_floats(mesh->texcoords, *texcoord, 2);
  TriangleMesh check(mesh);
  check.validate();  // names the bad index or vertex: "mesh: 'index' of face 3 refers to ..."
  bounds_ = check.bounds();
  primitive_count_ = check.face_count();
  mesh_ = std::move(mesh);
}

void Geometry::commit_spheres() {
  const Data* position = get_data(*this, find("sphere.position"), "sphere.position", {OSP_VEC3F});
  if (!position) throw Error(name() + ": required parameter 'sphere.position' (array of vec3f) is missing");
  const Data* radius = get_data(*this, find("sphere.radius"), "sphere.radius", {OSP_FLOAT});
  const Data* texcoord = get_data(*this, find("sphere.texcoord"), "sphere.texcoord", {OSP_VEC2F});
  const auto type = static_cast<SphereType>(
      get_enum(*this, get_int("type", OSP_SPHERE), "type", {"OSP_SPHERE", "OSP_DISC", "OSP_ORIENTED_DISC"}));
  // Normals orient discs only; otherwise the parameter is reported as unused.
  const Data* normal = type == SphereType::oriented_disc
                           ? get_data(*this, find("sphere.normal"), "sphere.normal", {OSP_VEC3F})
                           : nullptr;
  SphereIntersector intersector = SphereIntersector::sciray;
  if (const Param* p = find("intersector")) {
    if (p->type != OSP_STRING)
      throw Error(name() + ": parameter 'intersector' must be a string, got " + type_name(p->type));
    if (p->string == "embree")
      intersector = SphereIntersector::embree;
    else if (p->string != "sciray")
      throw Error(name() + ": parameter 'intersector' has unknown value '" + p->string + "' (sciray, embree)");
  }

  auto data = std::make_shared<SphereData>();
  append_floats(data->positions, *position, 3);
  if (radius) append_floats(data->radii, *radius, 1);
  data->radius = get_float("radius", 0.01f);
  if (normal) append_floats(data->normals, *normal, 3);
  if (texcoord) append_floats(data->texcoords, *texcoord, 2);
  Spheres check(data);
  check.set_type(type).set_intersector(intersector);
  check.validate();  // "sphere: 'sphere.radius' 2 must be positive, got -1"
  bounds_ = check.bounds();
  primitive_count_ = check.count();
  sphere_type_ = type;
  sphere_intersector_ = intersector;
  spheres_ = std::move(data);
}

void Geometry::commit_curves() {
  const Data* index = get_data(*this, find("index"), "index", {OSP_UINT, OSP_INT});
  if (!index) throw Error(name() + ": required parameter 'index' (array of uint) is missing");
  const auto type_of = [&](int value) {
    return static_cast<CurveType>(
        get_enum(*this, value, "type", {"OSP_ROUND", "OSP_FLAT", "OSP_RIBBON", "OSP_DISJOINT"}));
  };
  const auto basis_of = [&](int value) {
    return static_cast<CurveBasis>(get_enum(*this, value, "basis",
                                            {"OSP_LINEAR", "OSP_BEZIER", "OSP_BSPLINE", "OSP_HERMITE", "OSP_CATMULL_ROM"}));
  };

  auto data = std::make_shared<CurveData>();
  // As OSPRay: `vertex.position` with one `radius` makes round linear curves (and wins
  // over `vertex.position_radius`, which is then reported unused); otherwise
  // `vertex.position_radius`, `type` and `basis` are required.
  const Data* position = get_data(*this, find("vertex.position"), "vertex.position", {OSP_VEC3F});
  const Data* tangent = nullptr;
  const Data* normal = nullptr;
  if (position) {
    const float radius = get_float("radius", 0.01f);
    if (!(radius >= 0.f) || !std::isfinite(radius))
      throw Error(name() + ": parameter 'radius' must be finite and not negative, got " + std::to_string(radius));
    data->type = type_of(get_int("type", OSP_ROUND));
    data->basis = basis_of(get_int("basis", OSP_LINEAR));
    if (data->type != CurveType::round || data->basis != CurveBasis::linear)
      throw Error(name() + ": 'vertex.position' with a constant 'radius' needs type OSP_ROUND and basis OSP_LINEAR "
                           "(as in OSPRay); give 'vertex.position_radius' for other curves");
    data->position_radius.reserve(4 * position->size());
    for (std::uint64_t i = 0; i < position->size(); ++i) {
      for (int c = 0; c < 3; ++c) data->position_radius.push_back(read_float(position->element(i) + 4 * c));
      data->position_radius.push_back(radius);
    }
  } else {
    const Data* position_radius =
        get_data(*this, find("vertex.position_radius"), "vertex.position_radius", {OSP_VEC4F});
    if (!position_radius)
      throw Error(name() + ": required parameter 'vertex.position_radius' (array of vec4f) is missing (or give "
                           "'vertex.position' and 'radius' for round linear curves)");
    if (!has("type"))
      throw Error(name() + ": required parameter 'type' (OSPCurveType: OSP_ROUND, OSP_FLAT, OSP_RIBBON or "
                           "OSP_DISJOINT) is missing");
    if (!has("basis"))
      throw Error(name() + ": required parameter 'basis' (OSPCurveBasis: OSP_LINEAR, OSP_BEZIER, OSP_BSPLINE, "
                           "OSP_HERMITE or OSP_CATMULL_ROM) is missing");
    data->type = type_of(get_int("type", OSP_UNKNOWN_CURVE_TYPE));
    data->basis = basis_of(get_int("basis", OSP_UNKNOWN_CURVE_BASIS));
    append_floats(data->position_radius, *position_radius, 4);
    // Read only where the curve uses them, as OSPRay: otherwise reported unused.
    if (data->type == CurveType::ribbon)
      normal = get_data(*this, find("vertex.normal"), "vertex.normal", {OSP_VEC3F});
    if (data->basis == CurveBasis::hermite)
      tangent = get_data(*this, find("vertex.tangent"), "vertex.tangent", {OSP_VEC4F});
  }
  data->indices.reserve(index->size());
  for (std::uint64_t s = 0; s < index->size(); ++s) {
    std::uint32_t v;
    std::memcpy(&v, index->element(s), sizeof v);  // a negative int becomes out of range
    data->indices.push_back(v);
  }
  if (const Data* color = get_data(*this, find("vertex.color"), "vertex.color", {OSP_VEC4F, OSP_VEC3F}))
    append_colors(data->colors, *color);
  if (tangent) append_floats(data->tangents, *tangent, 4);
  if (normal) append_floats(data->normals, *normal, 3);

  Curves check(data);
  try {
    check.validate();  // "curve: 'index' 3 starts a segment at vertex 9 that needs vertex 10 but ..."
  } catch (const Error& e) {
    if (!position) throw;
    // The positions arrived as `vertex.position`: name that, not the array made from it.
    std::string message = e.what();
    const std::string from = "'vertex.position_radius'", to = "'vertex.position'";
    for (auto at = message.find(from); at != std::string::npos; at = message.find(from, at + to.size()))
      message.replace(at, from.size(), to);
    throw Error(message);
  }
  bounds_ = check.bounds();
  primitive_count_ = check.segment_count();
  curves_ = std::move(data);
}

namespace {

/// A box3f element: lower x, y, z, then upper x, y, z.
Box3f read_box(const std::byte* p) {
  Box3f b;
  b.lower = {read_float(p), read_float(p + 4), read_float(p + 8)};
  b.upper = {read_float(p + 12), read_float(p + 16), read_float(p + 20)};
  return b;
}

}  // namespace

void Geometry::commit_boxes() {
  const Data* box = get_data(*this, find("box"), "box", {OSP_BOX3F});
  if (!box) throw Error(name() + ": required parameter 'box' (array of box3f) is missing");
  auto data = std::make_shared<BoxData>();
  data->boxes = box->to_vector<Box3f>(read_box);
  const Boxes check(data->boxes);
  check.validate();  // "box: 'box' 1 is not a finite box with lower <= upper"
  bounds_ = check.bounds();
  primitive_count_ = check.count();
  boxes_ = std::move(data);
}

void Geometry::commit_planes() {
  const Data* coefficients = get_data(*this, find("plane.coefficients"), "plane.coefficients", {OSP_VEC4F});
  if (!coefficients)
    throw Error(name() + ": required parameter 'plane.coefficients' (array of vec4f) is missing");
  const Data* bounds = get_data(*this, find("plane.bounds"), "plane.bounds", {OSP_BOX3F});
  auto data = std::make_shared<PlaneData>();
  data->planes = coefficients->to_vector<Planes::Plane>([](const std::byte* p) {
    return Planes::Plane{read_float(p), read_float(p + 4), read_float(p + 8), read_float(p + 12)};
  });
  if (bounds) data->bounds = bounds->to_vector<Box3f>(read_box);
  const Planes check(data->planes, data->bounds);
  check.validate();  // "plane: 'plane.coefficients' 0 has a zero normal (a, b, c)"
  bounds_ = check.bounds();  // unbounded planes add nothing
  primitive_count_ = check.count();
  planes_ = std::move(data);
}

namespace {

std::string format_vec(const Vec3f& v) {
  std::ostringstream out;
  out << "(" << v.x << ", " << v.y << ", " << v.z << ")";
  return out.str();
}

/// Why `material` cannot colour `geometry` yet ("" where it can): a volume texture
/// colours planes only (slices), and isosurfaces take no colour. What a model's commit
/// and every world build (the material may be recommitted later) check.
std::string cannot_colour(const Geometry& geometry, const Material* material) {
  if (!material) return {};
  if (material->volume_map_kd() && !geometry.planes())
    return "its material's 'map_kd' (a volume texture) is not supported yet on " + geometry.subtype() +
           " geometry; volume textures colour plane geometry only (slices)";
  return {};
}

}  // namespace

void GeometricModel::on_commit() {
  // Read into locals: a commit that fails leaves the model as it was.
  Ref<Geometry> geometry = get_object<Geometry>("geometry", OSP_GEOMETRY, true);
  if (!geometry->committed()) throw Error(name() + ": its geometry has not been committed");
  Ref<Material> material;
  if (const Param* p = find("material"); p && p->object) {
    if (p->object->kind() == OSP_MATERIAL) {
      material = static_cast<Material*>(p->object.get());
    } else if (p->object->kind() == OSP_DATA) {
      const Data* list = get_data(*this, p, "material", {OSP_MATERIAL});
      if (list->size() != 1)
        throw Error(name() + ": parameter 'material': per-primitive materials are not supported yet; pass one");
      material = static_cast<Material*>(list->object(0));
    } else {
      throw Error(name() + ": parameter 'material' must be an OSPMaterial, got " + type_name(p->object->kind()));
    }
  } else if (p) {
    throw Error(name() + ": parameter 'material' as a renderer material index is not supported yet; pass an "
                         "OSPMaterial");
  }
  PaddedVector<float> face_colors;
  if (const Data* color = get_data(*this, find("color"), "color", {OSP_VEC4F, OSP_VEC3F})) {
    if (geometry->curves())
      throw Error(name() + ": parameter 'color': per-primitive colours of curve geometry are not supported yet; give "
                           "the curve's 'vertex.color'");
    if (geometry->isosurface_volume())
      throw Error(name() + ": parameter 'color': per-primitive colours of isosurface geometry are not supported yet "
                           "(isosurfaces show the renderer's default grey)");
    const std::size_t primitives = geometry->primitive_count();
    if (color->size() != primitives)
      throw Error(name() + ": parameter 'color' has " + std::to_string(color->size()) + " colours but the geometry has " +
                  std::to_string(primitives) + " primitives");
    append_colors(face_colors, *color);
  }
  if (const std::string why = cannot_colour(*geometry, material.get()); !why.empty()) throw Error(name() + ": " + why);
  // Shading is two-sided, so the side matters only to clipping geometry.
  const bool invert_normals = get_bool("invertNormals", false);
  get_int("id", 0);
  geometry_ = std::move(geometry);
  material_ = std::move(material);
  face_colors_ = std::move(face_colors);
  invert_normals_ = invert_normals;
}

std::optional<Vec3f> GeometricModel::material_color() const {
  if (!material_) return std::nullopt;
  return material_->base_color();  // as last committed: a material commit reaches the world
}

TextureObject* GeometricModel::volume_texture() const { return material_ ? material_->volume_map_kd() : nullptr; }

std::uint64_t GeometricModel::version() const {
  std::uint64_t v = version_;
  if (geometry_) v = std::max(v, geometry_->version());
  if (material_) v = std::max(v, material_->version());
  return v;
}

// ---- volumes ------------------------------------------------------------------------------

namespace {

std::string format_counts(const std::array<std::uint64_t, 3>& n) {
  return std::to_string(n[0]) + "x" + std::to_string(n[1]) + "x" + std::to_string(n[2]);
}

/// The engine volume over `data` (voxels of type Voxel): read in place where the array
/// is compact and aligned and the layout is linear (the volume then holds a reference to
/// the array, and with it the application's memory), otherwise copied. Float voxels must
/// be finite.
template <class Voxel>
EngineVolume make_structured_regular(const Object& owner, const Data& data, const VolumeGrid& grid,
                                     VolumeFilter filter, bool bricked, bool& zero_copy) {
  const auto& n = data.counts();
  const VolumeDims dims{static_cast<std::int64_t>(n[0]), static_cast<std::int64_t>(n[1]),
                        static_cast<std::int64_t>(n[2])};
  const std::byte* base = data.element(0);
  const bool in_place = data.compact() && reinterpret_cast<std::uintptr_t>(base) % alignof(Voxel) == 0;
  std::shared_ptr<std::vector<Voxel>> copy;
  const Voxel* voxels = reinterpret_cast<const Voxel*>(base);
  if (!in_place) {
    copy = std::make_shared<std::vector<Voxel>>(static_cast<std::size_t>(data.size()));
    Voxel* to = copy->data();
    for (std::uint64_t k = 0; k < n[2]; ++k)
      for (std::uint64_t j = 0; j < n[1]; ++j)
        for (std::uint64_t i = 0; i < n[0]; ++i) std::memcpy(to++, data.element(i, j, k), sizeof(Voxel));
    voxels = copy->data();
  }
  if constexpr (std::is_floating_point_v<Voxel>) {
    const std::uint64_t count = data.size();
    for (std::uint64_t i = 0; i < count; ++i)
      if (!std::isfinite(voxels[i]))
        throw Error(owner.name() + ": parameter 'data': voxel (" + std::to_string(i % n[0]) + ", " +
                    std::to_string(i / n[0] % n[1]) + ", " + std::to_string(i / n[0] / n[1]) + ") is not finite");
  }
  if (bricked) {
    zero_copy = false;
    return std::make_shared<const StructuredRegular<Voxel, BrickedLayout>>(BrickedLayout<Voxel>(voxels, dims), grid,
                                                                           filter);
  }
  zero_copy = in_place;
  // The application's array stays alive (and its deleter uncalled) while any engine
  // volume, also one a frame in flight holds, reads it.
  std::shared_ptr<const void> keep =
      copy ? std::shared_ptr<const void>(copy)
           : std::shared_ptr<const void>(base, [hold = Ref<Data>(const_cast<Data*>(&data))](const void*) {});
  return std::make_shared<const StructuredRegular<Voxel>>(LinearLayout<Voxel>(voxels, dims, std::move(keep)), grid,
                                                          filter);
}

/// The engine model of `volume` with `tf`, `density_scale` and `anisotropy` (builds its
/// macrocells).
EngineVolumetricModel make_volumetric_model(const EngineVolume& volume, const TransferFunction& tf,
                                            float density_scale, float anisotropy = 0.f) {
  return std::visit(
      [&](const auto& v) -> EngineVolumetricModel {
        using T = std::decay_t<decltype(v)>;
        if constexpr (std::is_same_v<T, std::monostate>)
          throw Error("volumetric model: its volume has not been committed");
        else
          return VolumetricModel<std::remove_const_t<typename T::element_type>>(v, tf, density_scale, anisotropy);
      },
      volume);
}

/// Which engine volume `model` is built over (to tell a recommitted volume's new engine
/// volume from the one the model has).
const void* volume_of(const EngineVolumetricModel& model) {
  return std::visit(
      [](const auto& m) -> const void* {
        if constexpr (std::is_same_v<std::decay_t<decltype(m)>, std::monostate>)
          return nullptr;
        else
          return &m.volume();
      },
      model);
}
const void* volume_of(const EngineVolume& volume) {
  return std::visit(
      [](const auto& v) -> const void* {
        if constexpr (std::is_same_v<std::decay_t<decltype(v)>, std::monostate>)
          return nullptr;
        else
          return v.get();
      },
      volume);
}

/// Adds a copy of `model` to `world`.
void add_volume(shim::EngineWorld& world, const EngineVolumetricModel& model) {
  std::visit(
      [&](const auto& m) {
        if constexpr (!std::is_same_v<std::decay_t<decltype(m)>, std::monostate>) world.add_volume(m);
      },
      model);
}

}  // namespace

void VolumeObject::on_commit() {
  // The factory creates no other types.
  const std::string voxel_types = "uchar, short, ushort, float or double";
  const Param* p = find("data");
  if (!p || (!p->object && is_object_type(p->type)))  // absent, or set to NULL
    throw Error(name() + ": required parameter 'data' (3D array of " + voxel_types + ") is missing");
  if (!p->object || p->object->kind() != OSP_DATA)
    throw Error(name() + ": parameter 'data' must be an OSPData array, got " +
                type_name(p->object ? p->object->kind() : p->type));
  const auto& data = static_cast<const Data&>(*p->object);
  const OSPDataType type = data.element_type();
  if (type != OSP_UCHAR && type != OSP_SHORT && type != OSP_USHORT && type != OSP_FLOAT && type != OSP_DOUBLE)
    throw Error(name() + ": parameter 'data' must be an array of " + voxel_types + ", got an array of " +
                type_name(type) + (type == OSP_HALF ? " (half voxels are not supported yet)" : ""));
  const auto& n = data.counts();
  if (n[0] < 2 || n[1] < 2 || n[2] < 2) {
    const std::string got = n[1] == 1 && n[2] == 1 ? "a 1D array of " + std::to_string(n[0])
                            : n[2] == 1           ? "a 2D array of " + std::to_string(n[0]) + "x" + std::to_string(n[1])
                                                  : "a 3D array of " + format_counts(n);
    throw Error(name() + ": parameter 'data' must be a 3D array with at least 2 voxels in every direction (its "
                         "dimensions are the grid's), got " + got);
  }

  VolumeGrid grid;
  grid.origin = get_vec3f("gridOrigin", {0.f, 0.f, 0.f});
  grid.spacing = get_vec3f("gridSpacing", {1.f, 1.f, 1.f});
  if (!(grid.spacing.x > 0.f && grid.spacing.y > 0.f && grid.spacing.z > 0.f))
    throw Error(name() + ": parameter 'gridSpacing' must be positive on every axis, got " + format_vec(grid.spacing));
  grid.cell_centered = get_bool("cellCentered", false);

  VolumeFilter filter = VolumeFilter::linear;
  switch (const int f = get_int("filter", OSP_VOLUME_FILTER_LINEAR)) {
    case OSP_VOLUME_FILTER_NEAREST: filter = VolumeFilter::nearest; break;
    case OSP_VOLUME_FILTER_LINEAR: filter = VolumeFilter::linear; break;
    case OSP_VOLUME_FILTER_CUBIC: filter = VolumeFilter::cubic; break;
    default:
      throw Error(name() + ": parameter 'filter' has unknown value " + std::to_string(f) +
                  " (OSP_VOLUME_FILTER_NEAREST = 0, OSP_VOLUME_FILTER_LINEAR = 100, OSP_VOLUME_FILTER_CUBIC = 200)");
  }

  bool bricked = false;
  if (const Param* layout = find("layout")) {
    if (layout->type != OSP_STRING)
      throw Error(name() + ": parameter 'layout' must be a string, got " + type_name(layout->type));
    if (layout->string == "bricked")
      bricked = true;
    else if (layout->string != "linear")
      throw Error(name() + ": parameter 'layout' has unknown value '" + layout->string + "' (linear, bricked)");
  }

  // Read into locals: a commit that fails leaves the volume as it was.
  bool zero_copy = false;
  EngineVolume volume;
  switch (type) {
    case OSP_UCHAR: volume = make_structured_regular<std::uint8_t>(*this, data, grid, filter, bricked, zero_copy); break;
    case OSP_SHORT: volume = make_structured_regular<std::int16_t>(*this, data, grid, filter, bricked, zero_copy); break;
    case OSP_USHORT:
      volume = make_structured_regular<std::uint16_t>(*this, data, grid, filter, bricked, zero_copy);
      break;
    case OSP_FLOAT: volume = make_structured_regular<float>(*this, data, grid, filter, bricked, zero_copy); break;
    default: volume = make_structured_regular<double>(*this, data, grid, filter, bricked, zero_copy); break;
  }
  bounds_ = std::visit(
      [](const auto& v) -> Box3f {
        if constexpr (std::is_same_v<std::decay_t<decltype(v)>, std::monostate>)
          return {};
        else
          return v->bounds();
      },
      volume);
  volume_ = std::move(volume);
  zero_copy_ = zero_copy;
}

void TransferFunctionObject::on_commit() {
  // The factory creates no other types.
  const Data* color = get_data(*this, find("color"), "color", {OSP_VEC3F});
  if (!color) throw Error(name() + ": required parameter 'color' (array of vec3f) is missing");
  const Data* opacity = get_data(*this, find("opacity"), "opacity", {OSP_FLOAT});
  if (!opacity) throw Error(name() + ": required parameter 'opacity' (array of float) is missing");
  std::array<float, 2> range{0.f, 1.f};  // OSPRay's default
  if (const Param* p = find("value")) {
    if (p->type != OSP_BOX1F && p->type != OSP_VEC2F)
      throw Error(name() + ": parameter 'value' must be a box1f (or vec2f) range, got " + type_name(p->type));
    std::memcpy(range.data(), p->bytes.data(), sizeof range);
  }
  // Validates: "transferFunction: 'value' must be a finite range with lo < hi, got [1, 1]"
  tf_ = std::make_shared<const TransferFunction>(
      color->to_vector<Vec3f>([](const std::byte* e) { return Vec3f{read_float(e), read_float(e + 4), read_float(e + 8)}; }),
      opacity->to_vector<float>(read_float), range);
}

void VolumetricModelObject::on_commit() {
  // Read into locals: a commit that fails leaves the model as it was.
  Ref<VolumeObject> volume = get_object<VolumeObject>("volume", OSP_VOLUME, true);
  if (!volume->committed()) throw Error(name() + ": its volume has not been committed");
  Ref<TransferFunctionObject> tf =
      get_object<TransferFunctionObject>("transferFunction", OSP_TRANSFER_FUNCTION, true);
  if (!tf->committed()) throw Error(name() + ": its transfer function has not been committed");
  const float density_scale = get_float("densityScale", 1.f);
  if (!(density_scale >= 0.f) || !std::isfinite(density_scale))
    throw Error(name() + ": parameter 'densityScale' must be finite and not negative, got " +
                std::to_string(density_scale));
  const float anisotropy = get_float("anisotropy", 0.f);
  if (!(anisotropy >= -1.f && anisotropy <= 1.f))
    throw Error(name() + ": parameter 'anisotropy' must be in [-1, 1], got " + std::to_string(anisotropy));
  // OSPRay's `gradientShadingScale` is not read: reported unused.

  std::lock_guard lock(mutex_);
  EngineVolumetricModel model;
  if (volume_of(model_) == volume_of(volume->volume()) && density_scale == density_scale_) {
    // The same engine volume: keep its macrocell ranges.
    model = model_;
    if (model_tf_version_ != tf->version() || transfer_function_.get() != tf.get())
      std::visit(
          [&](auto& m) {
            if constexpr (!std::is_same_v<std::decay_t<decltype(m)>, std::monostate>)
              m.set_transfer_function(*tf->transfer_function());
          },
          model);
  } else {
    model = make_volumetric_model(volume->volume(), *tf->transfer_function(), density_scale);
  }
  std::visit(
      [&](auto& m) {
        if constexpr (!std::is_same_v<std::decay_t<decltype(m)>, std::monostate>) m.set_anisotropy(anisotropy);
      },
      model);
  model_ = std::move(model);
  model_volume_version_ = volume->version();
  model_tf_version_ = tf->version();
  volume_ = std::move(volume);
  transfer_function_ = std::move(tf);
  density_scale_ = density_scale;
  anisotropy_ = anisotropy;
}

std::uint64_t VolumetricModelObject::version() const {
  std::uint64_t v = version_;
  if (volume_) v = std::max(v, volume_->version());
  if (transfer_function_) v = std::max(v, transfer_function_->version());
  return v;
}

EngineVolumetricModel VolumetricModelObject::engine_model(VolumeBuildStats& stats) {
  std::lock_guard lock(mutex_);
  ++stats.volumes;
  if (model_volume_version_ != volume_->version()) {
    model_ = make_volumetric_model(volume_->volume(), *transfer_function_->transfer_function(), density_scale_,
                                   anisotropy_);
    model_volume_version_ = volume_->version();
    model_tf_version_ = transfer_function_->version();
    ++stats.macrocells_built;
  } else if (model_tf_version_ != transfer_function_->version()) {
    std::visit(
        [&](auto& m) {
          if constexpr (!std::is_same_v<std::decay_t<decltype(m)>, std::monostate>)
            m.set_transfer_function(*transfer_function_->transfer_function());
        },
        model_);
    model_tf_version_ = transfer_function_->version();
    ++stats.transfer_functions;
  }
  return model_;
}

// ---- isosurfaces and volume textures -------------------------------------------------------

namespace {

/// The engine isosurface of `volume` (finds the macrocells that hold an isovalue).
std::shared_ptr<const Isosurface> make_isosurface(const EngineVolume& volume, const std::vector<float>& isovalues) {
  return std::visit(
      [&](const auto& v) -> std::shared_ptr<const Isosurface> {
        if constexpr (std::is_same_v<std::decay_t<decltype(v)>, std::monostate>)
          throw Error("isosurface: its volume has not been committed");
        else
          return std::make_shared<const Isosurface>(v, isovalues);
      },
      volume);
}

}  // namespace

void Geometry::commit_isosurface() {
  // OSPRay 3 takes the volume itself (OSPRay 2 took a volumetric model).
  const Param* p = find("volume");
  if (!p || !p->object) throw Error(name() + ": required parameter 'volume' (OSPVolume) is missing");
  if (p->object->kind() != OSP_VOLUME)
    throw Error(name() + ": parameter 'volume' must be OSPVolume, got " + type_name(p->object->kind()) +
                (p->object->kind() == OSP_VOLUMETRIC_MODEL
                     ? " (in OSPRay 3 an isosurface takes the volume itself, not a volumetric model)"
                     : ""));
  Ref<VolumeObject> volume = static_cast<VolumeObject*>(p->object.get());
  if (!volume->committed()) throw Error(name() + ": its volume has not been committed");

  const Param* iso = find("isovalue");
  if (!iso || (!iso->object && is_object_type(iso->type)))
    throw Error(name() + ": required parameter 'isovalue' (float, or array of float) is missing");
  std::vector<float> isovalues;
  const bool array = static_cast<bool>(iso->object);
  if (array) {
    if (iso->object->kind() != OSP_DATA)
      throw Error(name() + ": parameter 'isovalue' must be a float or an array of float, got " +
                  type_name(iso->object->kind()));
    isovalues = get_data(*this, iso, "isovalue", {OSP_FLOAT})->to_vector<float>(read_float);
  } else if (iso->type == OSP_FLOAT) {
    isovalues = {read_float(iso->bytes.data())};
  } else {
    throw Error(name() + ": parameter 'isovalue' must be a float or an array of float, got " + type_name(iso->type));
  }
  if (isovalues.empty()) throw Error(name() + ": parameter 'isovalue' is an empty array");
  for (std::size_t i = 0; i < isovalues.size(); ++i)
    if (!std::isfinite(isovalues[i]))
      throw Error(name() + ": parameter 'isovalue' " + (array ? "element " + std::to_string(i) + " " : "") +
                  "is not finite, got " + std::to_string(isovalues[i]));

  auto surface = make_isosurface(volume->volume(), isovalues);
  std::lock_guard lock(iso_mutex_);
  isosurface_ = std::move(surface);
  isosurface_volume_version_ = volume->version();
  primitive_count_ = isovalues.size();  // OSPRay's primitives of an isosurface: its isovalues
  isovalues_ = std::move(isovalues);
  iso_volume_ = std::move(volume);
}

std::shared_ptr<const Isosurface> Geometry::isosurface() {
  std::lock_guard lock(iso_mutex_);
  if (!iso_volume_) return nullptr;
  if (isosurface_volume_version_ != iso_volume_->version()) {
    // The volume was recommitted: the new one's macrocells.
    isosurface_ = make_isosurface(iso_volume_->volume(), isovalues_);
    isosurface_volume_version_ = iso_volume_->version();
  }
  return isosurface_;
}

std::uint32_t Geometry::isovalue_index(const Vec3f& p) const {
  if (!iso_volume_ || isovalues_.empty()) return 0;
  const float value = std::visit(
      [&](const auto& v) -> float {
        if constexpr (std::is_same_v<std::decay_t<decltype(v)>, std::monostate>)
          return 0.f;
        else
          return v->template sample<simd::scalar>(p);
      },
      iso_volume_->volume());
  std::uint32_t best = 0;
  for (std::uint32_t i = 1; i < isovalues_.size(); ++i)
    if (std::abs(isovalues_[i] - value) < std::abs(isovalues_[best] - value)) best = i;
  return best;
}

Box3f Geometry::bounds() const { return iso_volume_ ? iso_volume_->bounds() : bounds_; }

std::uint64_t Geometry::version() const {
  return std::max(version_, iso_volume_ ? iso_volume_->version() : 0);
}

void TextureObject::commit_texture2d() {
  const int format = get_int("format", OSP_TEXTURE_FORMAT_INVALID);
  const Param* p = find("data");
  if (!p || !p->object) throw Error(name() + ": required parameter 'data' (a 2D array of texels) is missing");
  if (p->object->kind() != OSP_DATA)
    throw Error(name() + ": parameter 'data' must be an OSPData array, got " + type_name(p->object->kind()));
  const auto* data = static_cast<const Data*>(p->object.get());
  if (data->counts()[2] != 1) throw Error(name() + ": parameter 'data' must be a 2D array");
  // The layouts sciray reads; the element type must agree with the format.
  struct Layout {
    int format;
    OSPDataType type;
    const char* type_name;
    int channels;
    bool srgb;
  };
  static constexpr Layout layouts[] = {
      {OSP_TEXTURE_RGB32F, OSP_VEC3F, "OSP_VEC3F", 3, false},    {OSP_TEXTURE_RGBA32F, OSP_VEC4F, "OSP_VEC4F", 4, false},
      {OSP_TEXTURE_R32F, OSP_FLOAT, "OSP_FLOAT", 1, false},      {OSP_TEXTURE_RGB8, OSP_VEC3UC, "OSP_VEC3UC", 3, false},
      {OSP_TEXTURE_RGBA8, OSP_VEC4UC, "OSP_VEC4UC", 4, false},   {OSP_TEXTURE_SRGB, OSP_VEC3UC, "OSP_VEC3UC", 3, true},
      {OSP_TEXTURE_SRGBA, OSP_VEC4UC, "OSP_VEC4UC", 4, true},    {OSP_TEXTURE_R8, OSP_UCHAR, "OSP_UCHAR", 1, false},
      {OSP_TEXTURE_L8, OSP_UCHAR, "OSP_UCHAR", 1, true}};
  const Layout* layout = nullptr;
  for (const Layout& l : layouts)
    if (l.format == format) layout = &l;
  if (!layout)
    throw Error(name() + ": parameter 'format' " + std::to_string(format) +
                " is not supported (RGB32F, RGBA32F, R32F, RGB8, RGBA8, SRGB, SRGBA, R8 and L8 are)");
  if (data->element_type() != layout->type)
    throw Error(name() + ": parameter 'data' holds " + type_name(data->element_type()) + " elements but 'format' " +
                std::to_string(format) + " needs " + layout->type_name);
  const bool bytes = layout->type == OSP_VEC3UC || layout->type == OSP_VEC4UC || layout->type == OSP_UCHAR;
  std::vector<Vec3f> texels = data->to_vector<Vec3f>([&](const std::byte* e) {
    float c[3];
    for (int k = 0; k < 3; ++k) {
      const int channel = layout->channels == 1 ? 0 : k;
      float v = bytes ? static_cast<float>(reinterpret_cast<const std::uint8_t*>(e)[channel]) / 255.f
                      : reinterpret_cast<const float*>(e)[channel];
      c[k] = layout->srgb ? srgb_to_linear(v) : v;
    }
    return Vec3f{c[0], c[1], c[2]};
  });
  const bool nearest = get_int("filter", OSP_TEXTURE_FILTER_LINEAR) == OSP_TEXTURE_FILTER_NEAREST;
  try {
    image_ = std::make_shared<const Texture2D>(static_cast<int>(data->counts()[0]), static_cast<int>(data->counts()[1]),
                                               std::move(texels), nearest);
  } catch (const Error& e) {
    throw Error(name() + ": " + e.what());
  }
}

void TextureObject::on_commit() {
  if (subtype() == "texture2d") return commit_texture2d();
  const Param* p = find("volume");
  if (!p || !p->object) throw Error(name() + ": required parameter 'volume' (OSPVolumetricModel) is missing");
  if (p->object->kind() != OSP_VOLUMETRIC_MODEL)
    throw Error(name() + ": parameter 'volume' must be OSPVolumetricModel, got " + type_name(p->object->kind()) +
                (p->object->kind() == OSP_VOLUME
                     ? " (a volume texture takes the volumetric model, whose transfer function gives the colours)"
                     : ""));
  Ref<VolumetricModelObject> model = static_cast<VolumetricModelObject*>(p->object.get());
  if (!model->committed()) throw Error(name() + ": its volumetric model has not been committed");
  model_ = std::move(model);
}

std::uint64_t TextureObject::version() const { return std::max(version_, model_ ? model_->version() : 0); }

namespace {

/// The slices of `model`: its planes coloured by its material's volume texture, times
/// `colors` (the model's colours times kd, or kd alone), sampling the texture's volume
/// and transfer function as currently committed.
VolumeSlice model_slice(const GeometricModel& model, const PlaneData& data, std::vector<float> colors) {
  const VolumetricModelObject& source = *model.volume_texture()->volume_model();
  const TransferFunction& tf = *source.transfer_function()->transfer_function();
  return std::visit(
      [&](const auto& v) -> VolumeSlice {
        if constexpr (std::is_same_v<std::decay_t<decltype(v)>, std::monostate>)
          throw Error("volume texture: its volume has not been committed");
        else
          return VolumeSlice(data.planes, data.bounds, v, tf, std::move(colors));
      },
      source.volume()->volume());
}

}  // namespace

namespace {

/// Why `model`'s geometry cannot clip whatever its placement ("" where it can): what a
/// group's commit and every world build check. (A non-uniformly scaled sphere depends
/// on the instance and is checked at the build.)
std::string cannot_clip(const GeometricModel& model) {
  const Geometry& geometry = *model.geometry();
  if (geometry.curves()) return "curve geometry cannot clip yet";
  if (geometry.spheres() && geometry.sphere_type() != SphereType::sphere)
    return "discs (sphere geometry of type OSP_DISC or OSP_ORIENTED_DISC) enclose nothing and cannot clip; use "
           "OSP_SPHERE";
  if (geometry.planes() && !geometry.planes()->bounds.empty())
    return "planes with 'plane.bounds' are not supported as clipping geometry yet; clip with unbounded planes or a box";
  if (geometry.isosurface_volume()) return "isosurface geometry cannot clip yet";
  return {};
}

/// The committed models of the object array `id` of `group`, if it is set.
std::vector<Ref<GeometricModel>> read_models(const Object& group, const Data* list, const std::string& id) {
  std::vector<Ref<GeometricModel>> models;
  if (!list) return models;
  for (std::uint64_t i = 0; i < list->size(); ++i) {
    auto* model = static_cast<GeometricModel*>(list->object(i));
    const std::string element = group.name() + ": parameter '" + id + "' element " + std::to_string(i);
    if (!model) throw Error(element + " is NULL");
    if (!model->committed()) throw Error(element + " has not been committed");
    models.emplace_back(model);
  }
  return models;
}

}  // namespace

void Group::on_commit() {
  // Read into locals: a commit that fails leaves the group as it was.
  auto models = read_models(*this, get_data(*this, find("geometry"), "geometry", {OSP_GEOMETRIC_MODEL}), "geometry");
  auto clipping = read_models(
      *this, get_data(*this, find("clippingGeometry"), "clippingGeometry", {OSP_GEOMETRIC_MODEL}), "clippingGeometry");
  for (std::size_t i = 0; i < clipping.size(); ++i)
    if (const std::string why = cannot_clip(*clipping[i]); !why.empty())
      throw Error(name() + ": parameter 'clippingGeometry' element " + std::to_string(i) + ": " + why);
  std::vector<Ref<VolumetricModelObject>> volumes;
  if (const Data* list = get_data(*this, find("volume"), "volume", {OSP_VOLUMETRIC_MODEL}))
    for (std::uint64_t i = 0; i < list->size(); ++i) {
      auto* model = static_cast<VolumetricModelObject*>(list->object(i));
      const std::string element = name() + ": parameter 'volume' element " + std::to_string(i);
      if (!model) throw Error(element + " is NULL");
      if (!model->committed()) throw Error(element + " has not been committed");
      volumes.emplace_back(model);
    }
  models_ = std::move(models);
  clipping_models_ = std::move(clipping);
  volumes_ = std::move(volumes);
}

Box3f Group::bounds() const {
  Box3f box;
  for (const auto& m : models_) box.extend(m->geometry()->bounds());
  for (const auto& v : volumes_) box.extend(v->bounds());
  return box;
}

std::uint64_t Group::geometry_version() const {
  std::uint64_t v = version_;
  for (const auto& m : models_) v = std::max(v, m->version());
  return v;
}

std::uint64_t Group::version() const {
  std::uint64_t v = geometry_version();
  for (const auto& m : clipping_models_) v = std::max(v, m->version());
  for (const auto& m : volumes_) v = std::max(v, m->version());
  return v;
}

void Instance::on_commit() {
  // Read into locals: a commit that fails leaves the instance as it was.
  Ref<Group> group = get_object<Group>("group", OSP_GROUP, true);
  if (!group->committed()) throw Error(name() + ": its group has not been committed");
  Affine3f transform;
  if (const Param* p = find("transform")) {
    if (p->type != OSP_AFFINE3F) throw Error(name() + ": parameter 'transform' must be an affine3f, got " + type_name(p->type));
    float m[12];
    std::memcpy(m, p->bytes.data(), sizeof m);
    for (float v : m)
      if (!std::isfinite(v)) throw Error(name() + ": parameter 'transform' is not finite");
    transform = {{m[0], m[1], m[2]}, {m[3], m[4], m[5]}, {m[6], m[7], m[8]}, {m[9], m[10], m[11]}};
    const float det = transform.determinant();
    if (det == 0.f || !std::isfinite(det)) throw Error(name() + ": parameter 'transform' is singular");
  }
  if (!group->volumes().empty() && !transform.identity())
    throw Error(name() + ": parameter 'transform': its group has volumes, and volumes in transformed instances are "
                         "not supported yet (place the group with the identity transform and the volume with its "
                         "'gridOrigin' and 'gridSpacing')");
  group_ = std::move(group);
  transform_ = transform;
}

// The transformed box of the group's bounds: the engine's instance is the exact
// transform of the group, so this encloses it under any (also non-uniform) transform.
Box3f Instance::bounds() const { return transform_.transform(group_->bounds()); }

std::uint64_t Instance::version() const { return std::max(version_, group_ ? group_->version() : 0); }

void Light::on_commit() {
  sciray::Light light;
  if (subtype() == "hdri") {
    auto* map = get_object<TextureObject>("map", OSP_TEXTURE, true);
    if (!map->committed() || !map->image()) throw Error(name() + ": parameter 'map' must be a committed texture2d");
    light = HdriLight(map->image(), get_vec3f("up", {0.f, 1.f, 0.f}), get_vec3f("direction", {0.f, 0.f, 1.f}));
  } else {
    light = *light_of_type(subtype());  // the factory creates only types the engine has
  }
  for_each_parameter(light, [&](const char* id, auto& field) { read_into(id, field); });
  try {
    validate(light);
  } catch (const Error& e) {
    throw Error(name() + ": " + e.what());
  }
  light_ = std::move(light);
}

void World::on_commit() {
  instances_.clear();
  lights_.clear();
  if (const Data* list = get_data(*this, find("instance"), "instance", {OSP_INSTANCE}))
    for (std::uint64_t i = 0; i < list->size(); ++i) {
      auto* instance = static_cast<Instance*>(list->object(i));
      if (!instance || !instance->committed())
        throw Error(name() + ": parameter 'instance' element " + std::to_string(i) + " is NULL or not committed");
      instances_.emplace_back(instance);
    }
  if (const Data* list = get_data(*this, find("light"), "light", {OSP_LIGHT}))
    for (std::uint64_t i = 0; i < list->size(); ++i) {
      auto* light = static_cast<Light*>(list->object(i));
      if (!light || !light->committed())
        throw Error(name() + ": parameter 'light' element " + std::to_string(i) + " is NULL or not committed");
      lights_.emplace_back(light);
    }
}

std::uint64_t World::version() const {
  std::uint64_t v = version_;
  for (const auto& i : instances_) v = std::max(v, i->version());
  for (const auto& l : lights_) v = std::max(v, l->version());
  return v;
}

Box3f World::bounds() const {
  Box3f box;
  for (const auto& i : instances_) box.extend(i->bounds());
  return box;
}

namespace {

/// `colors` (RGBA per primitive, or empty) times the material colour `kd` if any, or `kd`
/// alone for each of `count` primitives; empty when there is neither.
std::vector<float> tinted_colors(const PaddedVector<float>& colors, const std::optional<Vec3f>& kd,
                                 std::size_t count) {
  std::vector<float> out(colors.begin(), colors.end());
  if (!kd) return out;
  if (out.empty()) out.assign(4 * count, 1.f);
  for (std::size_t i = 0; 4 * i < out.size(); ++i) out[4 * i] *= kd->x, out[4 * i + 1] *= kd->y, out[4 * i + 2] *= kd->z;
  return out;
}

/// The mesh of `model`: the geometry's data shared; the model's per-face colours, if
/// any, held by `keep_alive`.
TriangleMesh model_mesh(const GeometricModel& model, std::vector<std::shared_ptr<const void>>& keep_alive) {
  const std::shared_ptr<const MeshData>& data = model.geometry()->mesh();
  TriangleMesh mesh(data);
  if (!model.face_colors().empty()) {
    auto colors = std::make_shared<const PaddedVector<float>>(model.face_colors());
    keep_alive.push_back(data);
    keep_alive.push_back(colors);
    TriangleMesh::SharedArrays arrays = mesh.arrays();
    arrays.face_colors = {colors->data(), colors->size() / 4, 4 * sizeof(float)};
    mesh = TriangleMesh::shared(arrays);
  }
  if (const auto kd = model.material_color()) mesh.set_material_color(*kd);
  return mesh;
}

/// The spheres of `model`. They read the geometry's arrays in place; only the colours
/// (the model's per-sphere colours times kd, or kd alone) are new, and `keep_alive` holds
/// them and the geometry's data.
Spheres model_spheres(const GeometricModel& model, std::vector<std::shared_ptr<const void>>& keep_alive) {
  const Geometry& geometry = *model.geometry();
  const SphereData& d = *geometry.spheres();
  keep_alive.push_back(geometry.spheres());
  const std::size_t n = d.count();
  Spheres::SharedArrays a;
  a.positions = {d.positions.data(), n, 3 * sizeof(float)};
  if (!d.radii.empty()) a.radii = {d.radii.data(), n, sizeof(float)};
  a.radius = d.radius;
  if (!d.normals.empty()) a.normals = {d.normals.data(), n, 3 * sizeof(float)};
  if (!d.texcoords.empty()) a.texcoords = {d.texcoords.data(), n, 2 * sizeof(float)};
  // Spheres have no material colour of their own: kd multiplies the colours, as a mesh
  // shades its face colours.
  if (!model.face_colors().empty() || model.material_color()) {
    auto colors = std::make_shared<PaddedVector<float>>();
    const std::vector<float> tinted = tinted_colors(model.face_colors(), model.material_color(), n);
    colors->assign(tinted.begin(), tinted.end());
    a.colors = {colors->data(), colors->size() / 4, 4 * sizeof(float)};
    keep_alive.push_back(std::move(colors));
  }
  Spheres spheres = Spheres::shared(a);
  spheres.set_type(geometry.sphere_type()).set_intersector(geometry.sphere_intersector());
  return spheres;
}

/// The curves of `model`: shared, or with kd a copy whose vertex colours it multiplies.
Curves model_curves(const GeometricModel& model) {
  std::shared_ptr<const CurveData> data = model.geometry()->curves();
  const auto kd = model.material_color();
  if (!kd) return Curves(data);
  auto copy = std::make_shared<CurveData>(*data);
  if (copy->colors.empty()) copy->colors.assign(4 * copy->vertex_count(), 1.f);
  for (std::size_t v = 0; 4 * v < copy->colors.size(); ++v)
    copy->colors[4 * v] *= kd->x, copy->colors[4 * v + 1] *= kd->y, copy->colors[4 * v + 2] *= kd->z;
  return Curves(std::shared_ptr<const CurveData>(std::move(copy)));
}

// ---- clipping geometry -------------------------------------------------------------------

/// The scale of `m`'s linear part where it is a rotation (or a reflection) times a
/// uniform scale, which maps spheres onto spheres; none where it scales non-uniformly
/// or shears.
std::optional<float> uniform_scale(const Affine3f& m) {
  const Vec3f columns[3] = {m.vx, m.vy, m.vz};
  const float s2 = (dot(m.vx, m.vx) + dot(m.vy, m.vy) + dot(m.vz, m.vz)) / 3.f;
  const float tolerance = 1e-5f * s2;  // float rotations are orthogonal to a few ulps
  for (int i = 0; i < 3; ++i) {
    if (std::abs(dot(columns[i], columns[i]) - s2) > tolerance) return std::nullopt;
    if (std::abs(dot(columns[i], columns[(i + 1) % 3])) > tolerance) return std::nullopt;
  }
  return std::sqrt(s2);
}

/// Whether `m`'s linear part maps every axis onto an axis (a scale, also negative, and
/// a permutation of the axes): it then maps a box exactly onto the box around its
/// transformed corners.
bool maps_axes_to_axes(const Affine3f& m) {
  const auto on_one_axis = [](const Vec3f& c) {
    return static_cast<int>(c.x != 0.f) + static_cast<int>(c.y != 0.f) + static_cast<int>(c.z != 0.f) == 1;
  };
  return on_one_axis(m.vx) && on_one_axis(m.vy) && on_one_axis(m.vz);
}

/// `box` placed by `m` as a closed mesh of 12 triangles: exact under any transform.
std::shared_ptr<const MeshData> box_mesh(const Box3f& box, const Affine3f& m) {
  auto mesh = std::make_shared<MeshData>();
  for (int k = 0; k < 8; ++k) {
    const Vec3f p = m.point({k & 1 ? box.upper.x : box.lower.x, k & 2 ? box.upper.y : box.lower.y,
                             k & 4 ? box.upper.z : box.lower.z});
    mesh->positions.insert(mesh->positions.end(), {p.x, p.y, p.z});
  }
  mesh->indices = {0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4,
                   2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1, 3, 5, 3, 7, 5};
  return mesh;
}

/// The positions and faces of `mesh` placed by `m` (the geometry's own data where `m`
/// is the identity).
std::shared_ptr<const MeshData> placed_mesh(const std::shared_ptr<const MeshData>& mesh, const Affine3f& m) {
  if (m.identity()) return mesh;
  auto placed = std::make_shared<MeshData>();
  placed->vertices_per_face = mesh->vertices_per_face;
  placed->indices = mesh->indices;
  placed->positions.reserve(mesh->positions.size());
  for (std::size_t v = 0; v < mesh->vertex_count(); ++v) {
    const float* x = &mesh->positions[3 * v];
    const Vec3f p = m.point({x[0], x[1], x[2]});
    placed->positions.insert(placed->positions.end(), {p.x, p.y, p.z});
  }
  return placed;
}

/// An edge shared by an odd number of faces, its vertices welded by position (so that a
/// mesh with vertices per face is closed too). A mesh without one is closed, and the
/// parity of a ray's crossings tells its inside from its outside.
struct OpenEdge {
  std::uint32_t a, b;
  std::size_t faces;
};

std::optional<OpenEdge> open_edge(const MeshData& mesh) {
  const std::size_t n = mesh.vertex_count();
  const auto position = [&](std::uint32_t v) {
    return std::array<float, 3>{mesh.positions[3 * v], mesh.positions[3 * v + 1], mesh.positions[3 * v + 2]};
  };
  std::vector<std::uint32_t> order(n);
  for (std::size_t v = 0; v < n; ++v) order[v] = static_cast<std::uint32_t>(v);
  std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) { return position(a) < position(b); });
  std::vector<std::uint32_t> weld(n);  // the lowest-sorted vertex at the same position
  for (std::size_t i = 0; i < n; ++i)
    weld[order[i]] = i > 0 && position(order[i]) == position(order[i - 1]) ? weld[order[i - 1]] : order[i];

  std::vector<std::uint64_t> edges;
  const unsigned k = mesh.vertices_per_face;
  edges.reserve(mesh.indices.size());
  for (std::size_t f = 0; f < mesh.face_count(); ++f)
    for (unsigned c = 0; c < k; ++c) {
      std::uint32_t a = weld[mesh.indices[f * k + c]], b = weld[mesh.indices[f * k + (c + 1) % k]];
      if (a == b) continue;  // a triangle in a quad mesh repeats its last vertex
      if (a > b) std::swap(a, b);
      edges.push_back(std::uint64_t{a} << 32 | b);
    }
  std::sort(edges.begin(), edges.end());
  for (std::size_t i = 0, j = 0; i < edges.size(); i = j) {
    while (j < edges.size() && edges[j] == edges[i]) ++j;
    if ((j - i) % 2 != 0) return OpenEdge{static_cast<std::uint32_t>(edges[i] >> 32),
                                          static_cast<std::uint32_t>(edges[i] & 0xffffffffu), j - i};
  }
  return std::nullopt;
}

/// Adds the geometry of the clipping model `model`, placed by `m`, to `clipping`.
void add_clipper(Clipping& clipping, const GeometricModel& model, const Affine3f& m) {
  if (const std::string why = cannot_clip(model); !why.empty()) throw Error(why);
  const Geometry& geometry = *model.geometry();
  const bool invert = model.invert_normals();
  if (const auto& spheres = geometry.spheres()) {
    const std::optional<float> scale = uniform_scale(m);
    if (!scale)
      throw Error("its instance's transform scales non-uniformly (a sphere becomes an ellipsoid), which clipping "
                  "spheres do not support yet");
    for (std::size_t i = 0; i < spheres->count(); ++i) {
      const float* c = &spheres->positions[3 * i];
      const float radius = spheres->radii.empty() ? spheres->radius : spheres->radii[i];
      clipping.add_sphere(m.point({c[0], c[1], c[2]}), *scale * radius, invert);
    }
  } else if (const auto& boxes = geometry.boxes()) {
    const bool analytic = maps_axes_to_axes(m);
    for (const Box3f& box : boxes->boxes)
      if (analytic)
        clipping.add_box(m.transform(box), invert);
      else
        clipping.add_mesh(box_mesh(box, m), invert);  // rotated or sheared: exact as a mesh
  } else if (const auto& planes = geometry.planes()) {
    // The cofactor matrix is the inverse transpose times the determinant: a mirroring
    // transform would turn the normal around, and with it the side that is clipped.
    const float side = m.determinant() < 0.f ? -1.f : 1.f;
    for (const Planes::Plane& plane : planes->planes) {
      const Vec3f n{plane.a, plane.b, plane.c};
      const Vec3f on_plane = n * (-plane.d / dot(n, n));
      const Vec3f normal = normalize(m.normal(n) * side);
      clipping.add_plane(normal, -dot(normal, m.point(on_plane)), invert);
    }
  } else {
    const std::shared_ptr<const MeshData>& mesh = geometry.mesh();
    if (const auto edge = open_edge(*mesh))
      throw Error("only a closed mesh can clip, but the edge between vertices " + std::to_string(edge->a) + " and " +
                  std::to_string(edge->b) + " belongs to " + std::to_string(edge->faces) + " face" +
                  (edge->faces == 1 ? "" : "s"));
    clipping.add_mesh(placed_mesh(mesh, m), invert);
  }
}

}  // namespace

BuiltWorld::Origin BuiltWorld::origin(std::int32_t inst_id, std::int32_t geom_id) const {
  // The C API places everything through instances: a world has no direct geometry.
  const std::size_t first_instance = world->geometry_count();
  if (inst_id < 0 || static_cast<std::size_t>(inst_id) < first_instance ||
      static_cast<std::size_t>(inst_id) - first_instance >= instances.size())
    throw Error("world: a hit reports instance id " + std::to_string(inst_id) + ", which the world does not have");
  const PlacedInstance& placed = instances[static_cast<std::size_t>(inst_id) - first_instance];
  const BuiltGroup& group = *groups[placed.group];
  if (geom_id < 0 || static_cast<std::size_t>(geom_id) >= group.models.size())
    throw Error("world: a hit reports geometry id " + std::to_string(geom_id) + ", which its group does not have");
  return {placed.instance.get(), group.models[static_cast<std::size_t>(geom_id)].get()};
}

std::shared_ptr<const BuiltGroup> World::build_group(Group& group, const shim::IsaKernels& kernels) {
  auto built = std::make_shared<BuiltGroup>();
  built->device = device_;
  built->source = &group;
  built->version = group.geometry_version();  // its clipping models are the world's
  built->kernels = &kernels;
  if (group.models().empty()) return built;
  built->group = std::make_shared<shim::EngineWorld::GroupType>(*device_);
  for (std::size_t k = 0; k < group.models().size(); ++k) {
    const auto& model = group.models()[k];
    Geometry& geometry = *model->geometry();
    // The material may have been recommitted (with a texture or colour) since the model.
    if (const std::string why = cannot_colour(geometry, model->material()); !why.empty())
      throw Error("parameter 'geometry' element " + std::to_string(k) + " (" + model->name() + " of " +
                  geometry.name() + "): " + why);
    // Geometries bake their material's base colour into their colours, except
    // isosurfaces, which have none.
    const std::uint32_t material = material_index(model->material(), !geometry.isosurface());
    if (geometry.spheres()) {
      built->group->add(model_spheres(*model, built->keep_alive), material);
    } else if (geometry.curves()) {
      built->group->add(model_curves(*model), material);
    } else if (geometry.boxes()) {
      // Boxes and planes own their primitives with the model's colours.
      const auto& data = *geometry.boxes();
      built->group->add(
          Boxes(data.boxes, tinted_colors(model->face_colors(), model->material_color(), data.boxes.size())), material);
    } else if (geometry.planes()) {
      const auto& data = *geometry.planes();
      auto colors = tinted_colors(model->face_colors(), model->material_color(), data.planes.size());
      if (model->volume_texture())
        built->group->add(model_slice(*model, data, std::move(colors)), material);  // planes coloured by a volume
      else
        built->group->add(Planes(data.planes, data.bounds, std::move(colors)), material);
    } else if (const auto isosurface = geometry.isosurface()) {
      built->group->add(*isosurface, material);  // a copy: the volume is shared
    } else {
      built->group->add(model_mesh(*model, built->keep_alive), material);
    }
    built->models.push_back(model);
  }
  // Committed with the world, through the kernels (sciray's intersectors are per ISA).
  return built;
}

std::uint32_t World::material_index(Material* material, bool baked) {
  if (!material) return no_material;
  for (std::size_t i = 0; i < materials_.size(); ++i)
    if (materials_[i].material.get() == material && materials_[i].baked == baked) return static_cast<std::uint32_t>(i);
  materials_.push_back({material, baked});
  return static_cast<std::uint32_t>(materials_.size() - 1);
}

std::shared_ptr<const BuiltWorld> World::built(const shim::IsaKernels& kernels, BuildLog& log) {
  std::lock_guard lock(build_mutex_);
  const std::uint64_t current = version();
  if (built_ && built_->version == current && built_->kernels == &kernels) return built_;

  if (!device_) device_ = std::make_shared<accel::Device>();
  auto built = std::make_shared<BuiltWorld>();
  built->device = device_;
  built->world = std::make_unique<shim::EngineWorld>(*built->device);
  built->kernels = &kernels;
  std::map<const Group*, std::size_t> group_index;  // this build's groups, by OSPRay group
  std::size_t reused = 0;
  VolumeBuildStats volumes;
  for (std::size_t i = 0; i < instances_.size(); ++i) {
    const auto& instance = instances_[i];
    Group* group = instance->group();
    // The engine places volumes directly in the world: only where the instance does not
    // move them. (The group may have gained volumes after the instance's commit.)
    if (!group->volumes().empty() && !instance->transform().identity())
      throw Error(name() + ": instance " + std::to_string(i) +
                  " places a group with volumes by a transform other than the identity: volumes in transformed "
                  "instances are not supported yet");
    for (const auto& model : group->volumes()) add_volume(*built->world, model->engine_model(volumes));
    auto [at, added] = group_index.try_emplace(group, built->groups.size());
    if (added) {
      const auto cached = group_cache_.find(group);
      if (cached != group_cache_.end() && cached->second->version == group->geometry_version() &&
          cached->second->kernels == &kernels) {
        built->groups.push_back(cached->second);  // its BVH carries over as it is
        ++reused;
      } else {
        try {
          built->groups.push_back(build_group(*group, kernels));
        } catch (const Error& e) {
          throw Error(name() + ": the group of instance " + std::to_string(i) + ", " + e.what());
        }
      }
    }
    const BuiltGroup& placed = *built->groups[at->second];
    if (!placed.group) continue;  // no geometry: nothing to place
    built->world->add_instance(placed.group, instance->transform());
    built->instances.push_back({instance, at->second});
  }
  // Every instance's clipping geometry, also of groups with nothing to render, clips the
  // whole world.
  built->world->set_clipping(build_clipping());
  // Through the device's kernels: builds the new groups (spheres register sciray's
  // intersector compiled for its ISA), then the top-level BVH over the instances.
  kernels.commit(*built->world);

  for (const auto& light : lights_) built->lights.push_back(light->light());
  for (const MaterialEntry& entry : materials_)
    built->materials.push_back(entry.baked ? entry.material->without_base_color() : entry.material->material());
  // Only a successful build replaces the cache: groups no instance uses any more go.
  group_cache_.clear();
  for (const auto& [group, index] : group_index) group_cache_.emplace(group, built->groups[index]);
  built->version = current;
  built_ = built;

  std::string summary = "world: built with " + std::to_string(instances_.size()) + " instances of " +
                        std::to_string(built->groups.size()) + " groups (" +
                        std::to_string(built->groups.size() - reused) + " built, " + std::to_string(reused) +
                        " reused)";
  if (volumes.volumes)
    summary += ", " + std::to_string(volumes.volumes) + " volumes (" + std::to_string(volumes.macrocells_built) +
               " rebuilt for a recommitted volume, " + std::to_string(volumes.transfer_functions) +
               " given a recommitted transfer function without rebuilding their macrocells)";
  // The device's total: a previous build a frame still holds counts too.
  if (log.want_memory) summary += ", engine memory " + std::to_string(built->world->memory_bytes()) + " bytes";
  log.debug.push_back(std::move(summary));
  return built_;
}

std::shared_ptr<Clipping> World::build_clipping() const {
  auto clipping = std::make_shared<Clipping>();
  for (std::size_t i = 0; i < instances_.size(); ++i) {
    const Instance& instance = *instances_[i];
    const auto& models = instance.group()->clipping_models();
    for (std::size_t k = 0; k < models.size(); ++k) {
      try {
        add_clipper(*clipping, *models[k], instance.transform());
      } catch (const Error& e) {
        throw Error(name() + ": the group of instance " + std::to_string(i) + ", parameter 'clippingGeometry' " +
                    "element " + std::to_string(k) + " (" + models[k]->geometry()->name() + "): " + e.what());
      }
    }
  }
  return clipping->empty() ? nullptr : clipping;
}

void Renderer::on_commit() {
  const auto common = [&](auto params) {
    const auto background = get_color4("backgroundColor", {0.f, 0.f, 0.f, 0.f});
    params.background_color = {background[0], background[1], background[2]};
    params.background_alpha = background[3];
    params.max_path_length = get_int("maxPathLength", params.max_path_length);
    params.min_contribution = get_float("minContribution", params.min_contribution);
    params.volume_sampling_rate = get_float("volumeSamplingRate", params.volume_sampling_rate);
    if (auto* backplate = get_object<TextureObject>("map_backplate", OSP_TEXTURE, false)) {
      if (!backplate->committed() || !backplate->image())
        throw Error(name() + ": parameter 'map_backplate' must be a committed texture2d");
      params.backplate = backplate->image();
    }
    return params;
  };
  shim::RendererConfig config;
  if (subtype() == "scivis") {
    SciVisParams p = common(SciVisParams{});
    p.shadows = get_bool("shadows", p.shadows);
    p.ao_samples = get_int("aoSamples", p.ao_samples);
    p.ao_distance = get_float("aoDistance", p.ao_distance);
    config = p;
  } else if (subtype() == "ao") {
    AOParams p = common(AOParams{});
    p.ao_samples = get_int("aoSamples", p.ao_samples);
    p.ao_distance = get_float("aoDistance", p.ao_distance);
    p.ao_intensity = get_float("aoIntensity", p.ao_intensity);
    config = p;
  } else {
    PathTracerParams p = common(PathTracerParams{});
    p.roulette_path_length = get_int("roulettePathLength", p.roulette_path_length);
    p.max_contribution = get_float("maxContribution", p.max_contribution);
    config = p;
  }
  // What the renderers check of their parameters, checked now with no lights or materials.
  std::visit(
      [&](const auto& p) {
        validate(p, 0, subtype());  // names "<type> renderer: parameter ..."
        if constexpr (!std::is_same_v<std::decay_t<decltype(p)>, PathTracerParams>) {
          if (p.ao_samples < 0) throw Error(name() + ": parameter 'aoSamples' must not be negative");
          if (!(p.ao_distance > 0.f)) throw Error(name() + ": parameter 'aoDistance' must be positive");
        } else {
          if (p.roulette_path_length < 0) throw Error(name() + ": parameter 'roulettePathLength' must not be negative");
          if (!(p.max_contribution > 0.f)) throw Error(name() + ": parameter 'maxContribution' must be positive");
        }
      },
      config);
  FrameSettings settings;
  settings.pixel_samples = get_int("pixelSamples", 1);
  settings.variance_threshold = get_float("varianceThreshold", 0.f);
  try {
    settings.pixel_filter = pixel_filter_from_int(get_int("pixelFilter", static_cast<int>(PixelFilter::gauss)));
    validate(settings);
  } catch (const Error& e) {
    throw Error(name() + ": parameter " + e.what());
  }
  config_ = std::move(config);
  settings_ = settings;
}

shim::RendererConfig Renderer::config(const BuiltWorld& world) const {
  shim::RendererConfig config = config_;
  std::visit(
      [&](auto& p) {
        p.lights = world.lights;
        p.materials = world.materials;
      },
      config);
  return config;
}

}  // namespace sciray::ospray
