#include "scene_objects.hpp"

#include <algorithm>

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
  kd_ = get_vec3f("kd", {0.8f, 0.8f, 0.8f});
  const float d = get_float("d", 1.f);
  if (!(d >= 0.f && d <= 1.f)) throw Error(name() + ": parameter 'd' (opacity) must be in [0, 1]");
}

void Geometry::on_commit() {
  // Only "mesh" reaches here: the factory refuses other types.
  const Data* position = get_data(*this, find("vertex.position"), "vertex.position", {OSP_VEC3F});
  if (!position) throw Error(name() + ": required parameter 'vertex.position' (array of vec3f) is missing");
  const Data* index = get_data(*this, find("index"), "index", {OSP_VEC3UI, OSP_VEC3I, OSP_VEC4UI, OSP_VEC4I});
  if (!index) throw Error(name() + ": required parameter 'index' (array of vec3ui or vec4ui) is missing");
  const Data* normal = get_data(*this, find("vertex.normal"), "vertex.normal", {OSP_VEC3F});
  const Data* color = get_data(*this, find("vertex.color"), "vertex.color", {OSP_VEC4F, OSP_VEC3F});

  // A copy, padded for Embree: the application's arrays carry no padding guarantee.
  auto mesh = std::make_shared<MeshData>();
  mesh->positions.reserve(3 * position->size());
  for (std::uint64_t i = 0; i < position->size(); ++i)
    for (int c = 0; c < 3; ++c) mesh->positions.push_back(read_float(position->element(i) + 4 * c));
  const bool quads = index->element_type() == OSP_VEC4UI || index->element_type() == OSP_VEC4I;
  mesh->vertices_per_face = quads ? 4 : 3;
  mesh->indices.reserve(mesh->vertices_per_face * index->size());
  for (std::uint64_t f = 0; f < index->size(); ++f)
    for (unsigned c = 0; c < mesh->vertices_per_face; ++c) {
      std::uint32_t v;
      std::memcpy(&v, index->element(f) + 4 * c, sizeof v);  // a negative int becomes out of range
      mesh->indices.push_back(v);
    }
  if (normal)
    for (std::uint64_t i = 0; i < normal->size(); ++i)
      for (int c = 0; c < 3; ++c) mesh->normals.push_back(read_float(normal->element(i) + 4 * c));
  if (color) {
    const int components = color->element_type() == OSP_VEC4F ? 4 : 3;
    for (std::uint64_t i = 0; i < color->size(); ++i) {
      for (int c = 0; c < components; ++c) mesh->vertex_colors.push_back(read_float(color->element(i) + 4 * c));
      if (components == 3) mesh->vertex_colors.push_back(1.f);
    }
  }
  TriangleMesh check(mesh);
  check.validate();  // names the bad index or vertex: "mesh: 'index' of face 3 refers to ..."
  bounds_ = check.bounds();
  mesh_ = std::move(mesh);
}

void GeometricModel::on_commit() {
  geometry_ = get_object<Geometry>("geometry", OSP_GEOMETRY, true);
  if (!geometry_->committed()) throw Error(name() + ": its geometry has not been committed");
  material_ = nullptr;
  if (const Param* p = find("material"); p && p->object) {
    if (p->object->kind() == OSP_MATERIAL) {
      material_ = static_cast<Material*>(p->object.get());
    } else if (p->object->kind() == OSP_DATA) {
      const Data* list = get_data(*this, p, "material", {OSP_MATERIAL});
      if (list->size() != 1)
        throw Error(name() + ": parameter 'material': per-primitive materials are not supported yet; pass one");
      material_ = static_cast<Material*>(list->object(0));
    } else {
      throw Error(name() + ": parameter 'material' must be an OSPMaterial, got " + type_name(p->object->kind()));
    }
  } else if (p) {
    throw Error(name() + ": parameter 'material' as a renderer material index is not supported yet; pass an "
                         "OSPMaterial");
  }
  material_color_.reset();
  if (material_) material_color_ = material_->kd();
  face_colors_.clear();
  if (const Data* color = get_data(*this, find("color"), "color", {OSP_VEC4F, OSP_VEC3F})) {
    const std::size_t faces = geometry_->mesh()->face_count();
    if (color->size() != faces)
      throw Error(name() + ": parameter 'color' has " + std::to_string(color->size()) + " colours but the geometry has " +
                  std::to_string(faces) + " primitives");
    const int components = color->element_type() == OSP_VEC4F ? 4 : 3;
    for (std::uint64_t i = 0; i < color->size(); ++i) {
      for (int c = 0; c < components; ++c) face_colors_.push_back(read_float(color->element(i) + 4 * c));
      if (components == 3) face_colors_.push_back(1.f);
    }
  }
  get_bool("invertNormals", false);  // shading is two-sided, so the side does not matter
  get_int("id", 0);
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

std::shared_ptr<const BuiltWorld> World::built(std::vector<std::string>& warnings) {
  std::lock_guard lock(build_mutex_);
  const std::uint64_t current = version();
  if (built_ && built_->version == current) return built_;

  auto built = std::make_shared<BuiltWorld>();
  built->device = std::make_shared<accel::Device>();
  built->world = std::make_unique<shim::MeshWorld>(*built->device);
  for (const auto& instance : instances_) {
    const Affine& xfm = instance->transform();
    for (const auto& model : instance->group()->models()) {
      std::shared_ptr<const MeshData> data = model->geometry()->mesh();
      if (!xfm.identity() || !model->face_colors().empty()) {
        // Until Embree instancing lands, a transformed instance holds its own copy.
        auto copy = std::make_shared<MeshData>(*data);
        for (std::size_t v = 0; v < copy->vertex_count(); ++v) {
          const Vec3f p = xfm.point({copy->positions[3 * v], copy->positions[3 * v + 1], copy->positions[3 * v + 2]});
          copy->positions[3 * v] = p.x, copy->positions[3 * v + 1] = p.y, copy->positions[3 * v + 2] = p.z;
        }
        for (std::size_t v = 0; 3 * v < copy->normals.size(); ++v) {
          const Vec3f n = xfm.normal({copy->normals[3 * v], copy->normals[3 * v + 1], copy->normals[3 * v + 2]});
          copy->normals[3 * v] = n.x, copy->normals[3 * v + 1] = n.y, copy->normals[3 * v + 2] = n.z;
        }
        if (!model->face_colors().empty()) copy->face_colors = model->face_colors();
        data = std::move(copy);
      }
      TriangleMesh mesh(data);
      if (model->material_color()) mesh.set_material_color(*model->material_color());
      built->world->add(std::move(mesh));
      built->origins.push_back({instance, model});
    }
  }
  built->world->commit();

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
