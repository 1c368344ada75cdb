#include "scene_objects.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

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
  const float aspect = get_float("aspect", 1.f);
  if (subtype() == "perspective") {
    PerspectiveCamera c{position, direction, up, get_float("fovy", 60.f), aspect};
    prepare(c);  // validates, naming the bad parameter
    camera_ = c;
  } else {
    OrthographicCamera c{position, direction, up, get_float("height", 1.f), aspect};
    prepare(c);
    camera_ = c;
  }
}

void Material::on_commit() {
  const Vec3f kd = get_vec3f("kd", {0.8f, 0.8f, 0.8f});
  const float d = get_float("d", 1.f);
  if (!(d >= 0.f && d <= 1.f)) throw Error(name() + ": parameter 'd' (opacity) must be in [0, 1]");
  kd_ = kd;
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
    const std::size_t primitives = geometry->primitive_count();
    if (color->size() != primitives)
      throw Error(name() + ": parameter 'color' has " + std::to_string(color->size()) + " colours but the geometry has " +
                  std::to_string(primitives) + " primitives");
    append_colors(face_colors, *color);
  }
  get_bool("invertNormals", false);  // shading is two-sided, so the side does not matter
  get_int("id", 0);
  geometry_ = std::move(geometry);
  material_ = std::move(material);
  face_colors_ = std::move(face_colors);
}

std::optional<Vec3f> GeometricModel::material_color() const {
  if (!material_) return std::nullopt;
  return material_->kd();  // as last committed: a material commit reaches the world
}

std::uint64_t GeometricModel::version() const {
  std::uint64_t v = version_;
  if (geometry_) v = std::max(v, geometry_->version());
  if (material_) v = std::max(v, material_->version());
  return v;
}

void Group::on_commit() {
  models_.clear();
  if (const Data* list = get_data(*this, find("geometry"), "geometry", {OSP_GEOMETRIC_MODEL}))
    for (std::uint64_t i = 0; i < list->size(); ++i) {
      auto* model = static_cast<GeometricModel*>(list->object(i));
      if (!model) throw Error(name() + ": parameter 'geometry' element " + std::to_string(i) + " is NULL");
      if (!model->committed())
        throw Error(name() + ": parameter 'geometry' element " + std::to_string(i) + " has not been committed");
      models_.emplace_back(model);
    }
}

Box3f Group::bounds() const {
  Box3f box;
  for (const auto& m : models_) box.extend(m->geometry()->bounds());
  return box;
}

std::uint64_t Group::version() const {
  std::uint64_t v = version_;
  for (const auto& m : models_) v = std::max(v, m->version());
  return v;
}

void Instance::on_commit() {
  group_ = get_object<Group>("group", OSP_GROUP, true);
  if (!group_->committed()) throw Error(name() + ": its group has not been committed");
  transform_ = {};
  if (const Param* p = find("transform")) {
    if (p->type != OSP_AFFINE3F) throw Error(name() + ": parameter 'transform' must be an affine3f, got " + type_name(p->type));
    float m[12];
    std::memcpy(m, p->bytes.data(), sizeof m);
    for (float v : m)
      if (!std::isfinite(v)) throw Error(name() + ": parameter 'transform' is not finite");
    transform_ = {{m[0], m[1], m[2]}, {m[3], m[4], m[5]}, {m[6], m[7], m[8]}, {m[9], m[10], m[11]}};
    if (dot(cross(transform_.vx, transform_.vy), transform_.vz) == 0.f)
      throw Error(name() + ": parameter 'transform' is singular");
  }
}

Box3f Instance::bounds() const {
  Box3f box;
  const Box3f local = group_->bounds();
  if (local.empty()) return box;
  for (int k = 0; k < 8; ++k)
    box.extend(transform_.point({k & 1 ? local.upper.x : local.lower.x, k & 2 ? local.upper.y : local.lower.y,
                                 k & 4 ? local.upper.z : local.lower.z}));
  return box;
}

std::uint64_t Instance::version() const { return std::max(version_, group_ ? group_->version() : 0); }

void Light::on_commit() {
  color_ = get_vec3f("color", {1.f, 1.f, 1.f});
  intensity_ = get_float("intensity", 1.f);
  if (!(intensity_ >= 0.f) || !std::isfinite(intensity_))
    throw Error(name() + ": parameter 'intensity' must be finite and not negative");
  if (subtype() == "distant") {
    direction_ = get_vec3f("direction", {0.f, 0.f, 1.f});
    if (length(direction_) == 0.f) throw Error(name() + ": parameter 'direction' must not be zero");
  }
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

/// The factor an instance transform scales radii by: the cube root of |det|, exact for
/// uniform scale and an approximation otherwise (spheres stay spheres).
float radius_scale(const Affine& xfm) { return std::cbrt(std::abs(dot(cross(xfm.vx, xfm.vy), xfm.vz))); }

Vec3f load3(const float* p) { return {p[0], p[1], p[2]}; }
void store3(float* p, const Vec3f& v) { p[0] = v.x, p[1] = v.y, p[2] = v.z; }

/// The mesh of `model` placed by `xfm`: shared when nothing changes, else a copy.
TriangleMesh place_mesh(const GeometricModel& model, const Affine& xfm) {
  std::shared_ptr<const MeshData> data = model.geometry()->mesh();
  if (!xfm.identity() || !model.face_colors().empty()) {
    // Until Embree instancing lands, a transformed instance holds its own copy.
    auto copy = std::make_shared<MeshData>(*data);
    for (std::size_t v = 0; v < copy->vertex_count(); ++v)
      store3(&copy->positions[3 * v], xfm.point(load3(&copy->positions[3 * v])));
    for (std::size_t v = 0; 3 * v < copy->normals.size(); ++v)
      store3(&copy->normals[3 * v], xfm.normal(load3(&copy->normals[3 * v])));
    if (!model.face_colors().empty()) copy->face_colors = model.face_colors();
    data = std::move(copy);
  }
  TriangleMesh mesh(data);
  if (const auto kd = model.material_color()) mesh.set_material_color(*kd);
  return mesh;
}

/// The spheres of `model` placed by `xfm`. They read the geometry's arrays in place; only
/// what changes (transformed centres, radii and normals; colours) is new, and `keep_alive`
/// holds it and the geometry's data for as long as the world exists.
Spheres place_spheres(const GeometricModel& model, const Affine& xfm,
                      std::vector<std::shared_ptr<const void>>& keep_alive) {
  const Geometry& geometry = *model.geometry();
  const SphereData& d = *geometry.spheres();
  keep_alive.push_back(geometry.spheres());
  const std::size_t n = d.count();
  const auto owned = [&](PaddedVector<float> values) {
    auto held = std::make_shared<const PaddedVector<float>>(std::move(values));
    keep_alive.push_back(held);
    return held->data();
  };

  Spheres::SharedArrays a;
  a.positions = {d.positions.data(), n, 3 * sizeof(float)};
  if (!d.radii.empty()) a.radii = {d.radii.data(), n, sizeof(float)};
  a.radius = d.radius;
  if (!d.normals.empty()) a.normals = {d.normals.data(), n, 3 * sizeof(float)};
  if (!xfm.identity()) {
    PaddedVector<float> centers(d.positions.size());
    for (std::size_t i = 0; i < n; ++i) store3(&centers[3 * i], xfm.point(load3(&d.positions[3 * i])));
    a.positions = {owned(std::move(centers)), n, 3 * sizeof(float)};
    const float scale = radius_scale(xfm);
    a.radius *= scale;
    if (!d.radii.empty()) {
      PaddedVector<float> radii(d.radii);
      for (float& r : radii) r *= scale;
      a.radii = {owned(std::move(radii)), n, sizeof(float)};
    }
    if (!d.normals.empty()) {
      PaddedVector<float> normals(d.normals.size());
      for (std::size_t i = 0; i < n; ++i) store3(&normals[3 * i], normalize(xfm.normal(load3(&d.normals[3 * i]))));
      a.normals = {owned(std::move(normals)), n, 3 * sizeof(float)};
    }
  }
  // Spheres have no material colour of their own: the model's per-sphere colours times
  // kd, or kd alone, as a mesh shades its face colours.
  const auto kd = model.material_color();
  if (!model.face_colors().empty() || kd) {
    PaddedVector<float> colors = model.face_colors();
    if (colors.empty()) colors.assign(4 * n, 1.f);
    if (kd)
      for (std::size_t i = 0; 4 * i < colors.size(); ++i)
        colors[4 * i] *= kd->x, colors[4 * i + 1] *= kd->y, colors[4 * i + 2] *= kd->z;
    a.colors = {owned(std::move(colors)), model.face_colors().empty() ? n : model.face_colors().size() / 4,
                4 * sizeof(float)};
  }
  Spheres spheres = Spheres::shared(a);
  spheres.set_type(geometry.sphere_type()).set_intersector(geometry.sphere_intersector());
  return spheres;
}

/// The curves of `model` placed by `xfm`: shared when nothing changes, else a copy with
/// the control points transformed (radii scaled by radius_scale) and kd applied to the
/// vertex colours.
Curves place_curves(const GeometricModel& model, const Affine& xfm) {
  std::shared_ptr<const CurveData> data = model.geometry()->curves();
  const auto kd = model.material_color();
  if (xfm.identity() && !kd) return Curves(data);
  auto copy = std::make_shared<CurveData>(*data);
  if (!xfm.identity()) {
    const float scale = radius_scale(xfm);
    for (std::size_t v = 0; v < copy->vertex_count(); ++v) {
      float* p = &copy->position_radius[4 * v];
      store3(p, xfm.point(load3(p)));
      p[3] *= scale;
    }
    for (std::size_t v = 0; 4 * v < copy->tangents.size(); ++v) {
      float* t = &copy->tangents[4 * v];  // a derivative: transformed as a vector
      store3(t, xfm.vector(load3(t)));
      t[3] *= scale;
    }
    for (std::size_t v = 0; 3 * v < copy->normals.size(); ++v)
      store3(&copy->normals[3 * v], normalize(xfm.normal(load3(&copy->normals[3 * v]))));
  }
  if (kd) {
    if (copy->colors.empty()) copy->colors.assign(4 * copy->vertex_count(), 1.f);
    for (std::size_t v = 0; 4 * v < copy->colors.size(); ++v)
      copy->colors[4 * v] *= kd->x, copy->colors[4 * v + 1] *= kd->y, copy->colors[4 * v + 2] *= kd->z;
  }
  return Curves(std::shared_ptr<const CurveData>(std::move(copy)));
}

}  // namespace

std::shared_ptr<const BuiltWorld> World::built(const shim::IsaKernels& kernels, std::vector<std::string>& warnings) {
  std::lock_guard lock(build_mutex_);
  const std::uint64_t current = version();
  if (built_ && built_->version == current && built_->kernels == &kernels) return built_;

  auto built = std::make_shared<BuiltWorld>();
  built->device = std::make_shared<accel::Device>();
  built->world = std::make_unique<shim::EngineWorld>(*built->device);
  built->kernels = &kernels;
  for (const auto& instance : instances_) {
    const Affine& xfm = instance->transform();
    for (const auto& model : instance->group()->models()) {
      const Geometry& geometry = *model->geometry();
      if (geometry.spheres())
        built->world->add(place_spheres(*model, xfm, built->keep_alive));
      else if (geometry.curves())
        built->world->add(place_curves(*model, xfm));
      else
        built->world->add(place_mesh(*model, xfm));
      built->origins.push_back({instance, model});
    }
  }
  // Through the device's kernels: spheres register sciray's intersector compiled for its ISA.
  kernels.commit(*built->world);

  // scivis takes ambient light plus one distant light.
  SciVisParams& lights = built->lights;
  lights.ambient_intensity = 0.f;
  lights.light_intensity = 0.f;
  lights.ambient_color = {0.f, 0.f, 0.f};
  bool have_distant = false;
  for (const auto& light : lights_) {
    if (light->subtype() == "ambient") {
      lights.ambient_color += light->color() * light->intensity();
      lights.ambient_intensity = 1.f;
    } else if (!have_distant) {
      lights.light_direction = light->direction();
      lights.light_color = light->color();
      lights.light_intensity = light->intensity();
      have_distant = true;
    } else {
      warnings.push_back("world: only one distant light is used yet; further distant lights are ignored");
    }
  }
  built->version = current;
  built_ = built;
  return built_;
}

void Renderer::on_commit() {
  background_ = get_color4("backgroundColor", {0.f, 0.f, 0.f, 0.f});
}

}  // namespace sciray::ospray
