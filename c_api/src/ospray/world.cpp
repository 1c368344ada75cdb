// OSPRay's groups, instances and worlds, and the engine worlds built from them.
#include "scene_common.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <type_traits>

namespace sciray::ospray {

namespace {

/// The volume texture of `model`'s material (its `map_kd`): its volume and transfer
/// function as currently committed, placed by the material's `map_kd.transform`.
std::shared_ptr<const VolumeTexture> model_volume_texture(const GeometricModel& model) {
  const TextureObject& texture = *model.volume_texture();
  const TransferFunction& tf = *texture.transfer_function()->transfer_function();
  return std::visit(
      [&](const auto& v) -> std::shared_ptr<const VolumeTexture> {
        if constexpr (std::is_same_v<std::decay_t<decltype(v)>, std::monostate>)
          throw Error("volume texture: its volume has not been committed");
        else
          return std::make_shared<const VolumeTexture>(v, tf, model.material()->volume_map_transform());
      },
      texture.sampled_volume()->volume());
}

/// The slices of `model`: its planes coloured by its material's volume texture, times
/// `colors` (the model's colours times kd, or kd alone).
VolumeSlice model_slice(const GeometricModel& model, const PlaneData& data, std::vector<float> colors) {
  return VolumeSlice(data.planes, data.bounds, *model_volume_texture(model), std::move(colors));
}

}  // namespace

namespace {

/// Why `model`'s geometry cannot clip whatever its placement ("" where it can): what a
/// group's commit and every world build check. (A non-uniformly scaled sphere depends
/// on the instance and is checked at the build.)
std::string cannot_clip(const GeometricModel& model) {
  const Geometry& geometry = *model.geometry();
  if (const auto& curves = geometry.curves();
      curves && curves->type != CurveType::round && curves->type != CurveType::disjoint)
    return "flat curves and ribbons (curve geometry of type OSP_FLAT or OSP_RIBBON) enclose nothing and cannot clip; "
           "use OSP_ROUND";
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
  std::vector<Ref<Light>> lights;
  if (const Data* list = get_data(*this, find("light"), "light", {OSP_LIGHT}))
    for (std::uint64_t i = 0; i < list->size(); ++i) {
      auto* light = static_cast<Light*>(list->object(i));
      if (!light || !light->committed())
        throw Error(name() + ": parameter 'light' element " + std::to_string(i) + " is NULL or not committed");
      lights.emplace_back(light);
    }
  models_ = std::move(models);
  clipping_models_ = std::move(clipping);
  volumes_ = std::move(volumes);
  lights_ = std::move(lights);
  bvh_ = {get_bool("compactMode", false), get_bool("dynamicScene", false)};
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
  for (const auto& l : lights_) v = std::max(v, l->version());
  return v;
}

void Instance::on_commit() {
  // Read into locals: a commit that fails leaves the instance as it was.
  Ref<Group> group = get_object<Group>("group", OSP_GROUP, true);
  if (!group->committed()) throw Error(name() + ": its group has not been committed");
  MotionTransform placement = read_placement(*this, [this](const std::string& id) { return find(id); });
  const std::optional<std::uint32_t> user_id = get_user_id();
  group_ = std::move(group);
  placement_ = std::move(placement);
  user_id_ = user_id;
}

// The transformed box of the group's bounds: the engine's instance is the exact
// transform of the group, so this encloses it under any (also non-uniform) transform.
Box3f Instance::bounds() const { return placement_.transform(group_->bounds()); }

std::uint64_t Instance::version() const { return std::max(version_, group_ ? group_->version() : 0); }

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
  regions_.clear();
  if (const Data* list = get_data(*this, find("region"), "region", {OSP_BOX3F}))
    regions_ = list->to_vector<Box3f>([](const std::byte* element) {
      float b[6];
      std::memcpy(b, element, sizeof b);
      return Box3f{{b[0], b[1], b[2]}, {b[3], b[4], b[5]}};
    });
  for (std::size_t i = 0; i < regions_.size(); ++i) {
    const Box3f& r = regions_[i];
    if (!(r.lower.x < r.upper.x && r.lower.y < r.upper.y && r.lower.z < r.upper.z) ||
        !std::isfinite(r.lower.x + r.lower.y + r.lower.z + r.upper.x + r.upper.y + r.upper.z))
      throw Error(name() + ": parameter 'region' element " + std::to_string(i) +
                  " is empty or not finite (lower must be below upper on every axis)");
  }
  bvh_ = {get_bool("compactMode", false), get_bool("dynamicScene", false)};
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

/// The mesh of `model`: the geometry's data shared; the model's colours (per face, held
/// by `keep_alive`, or one for all), if any, replace the vertex colours.
TriangleMesh model_mesh(const GeometricModel& model, std::vector<std::shared_ptr<const void>>& keep_alive) {
  const std::shared_ptr<const MeshData>& data = model.geometry()->mesh();
  TriangleMesh mesh(data);
  if (!model.face_colors().empty() || model.uniform_color()) {
    keep_alive.push_back(data);
    TriangleMesh::SharedArrays arrays = mesh.arrays();
    arrays.vertex_colors = {};  // the model's colours override the geometry's
    if (!model.uniform_color()) {
      auto colors = std::make_shared<const PaddedVector<float>>(model.face_colors());
      arrays.face_colors = {colors->data(), colors->size() / 4, 4 * sizeof(float)};
      keep_alive.push_back(std::move(colors));
    }
    mesh = TriangleMesh::shared(arrays);
  }
  if (const auto tint = model.tint()) mesh.set_material_color(*tint);
  return mesh;
}

/// The subdivision surface of `model`: the geometry's data shared; the model's colours
/// (per face, or one for all) replace the surface's own, and its kd multiplies them.
Subdivision model_subdivision(const GeometricModel& model) {
  Subdivision surface(model.geometry()->subdivision());
  if (model.uniform_color())
    surface.ignore_own_colors();
  else if (!model.face_colors().empty())
    surface.set_face_colors(model.face_colors());
  if (const auto tint = model.tint()) surface.set_material_color(*tint);
  return surface;
}

/// The spheres of `model`. They read the geometry's arrays in place; only the colours
/// (the model's per-sphere colours times kd, or kd alone) are new, and `keep_alive` holds
/// them and the geometry's data. A volume texture as the material's `map_kd` colours them
/// too.
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
  if (!model.face_colors().empty() || model.tint()) {
    auto colors = std::make_shared<PaddedVector<float>>();
    const std::vector<float> tinted = tinted_colors(model.face_colors(), model.tint(), n);
    colors->assign(tinted.begin(), tinted.end());
    a.colors = {colors->data(), colors->size() / 4, 4 * sizeof(float)};
    keep_alive.push_back(std::move(colors));
  }
  Spheres spheres = Spheres::shared(a);
  spheres.set_type(geometry.sphere_type()).set_intersector(geometry.sphere_intersector());
  if (model.volume_texture()) spheres.set_volume_texture(model_volume_texture(model));
  return spheres;
}

/// The curves of `model`: shared, or with kd (or one model colour, which replaces the
/// vertex colours) a copy whose vertex colours it multiplies.
Curves model_curves(const GeometricModel& model) {
  std::shared_ptr<const CurveData> data = model.geometry()->curves();
  const auto tint = model.tint();
  if (!tint) return Curves(data);
  auto copy = std::make_shared<CurveData>(*data);
  if (copy->colors.empty() || model.uniform_color()) copy->colors.assign(4 * copy->vertex_count(), 1.f);
  const float alpha = model.uniform_alpha();
  for (std::size_t v = 0; 4 * v < copy->colors.size(); ++v)
    copy->colors[4 * v] *= tint->x, copy->colors[4 * v + 1] *= tint->y, copy->colors[4 * v + 2] *= tint->z,
                  copy->colors[4 * v + 3] *= alpha;
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

/// The curves `curves` placed by `m`, which scales uniformly by `scale`: their control
/// points, radii and (Hermite) tangents; the colours, which clipping does not read, are
/// left behind.
std::shared_ptr<const CurveData> placed_curves(const CurveData& curves, const Affine3f& m, float scale) {
  auto placed = std::make_shared<CurveData>();
  placed->indices = curves.indices;
  placed->type = curves.type;
  placed->basis = curves.basis;
  const auto place = [&](const PaddedVector<float>& from, PaddedVector<float>& to, bool points) {
    to.reserve(from.size());
    for (std::size_t v = 0; 4 * v < from.size(); ++v) {
      const Vec3f x{from[4 * v], from[4 * v + 1], from[4 * v + 2]};
      const Vec3f y = points ? m.point(x) : m.vector(x);
      to.insert(to.end(), {y.x, y.y, y.z, scale * from[4 * v + 3]});
    }
  };
  place(curves.position_radius, placed->position_radius, true);
  place(curves.tangents, placed->tangents, false);
  return placed;
}

/// Adds the geometry of the clipping model `model`, placed by `m`, to `clipping`.
void add_clipper(Clipping& clipping, const GeometricModel& model, const Affine3f& m) {
  if (const std::string why = cannot_clip(model); !why.empty()) throw Error(why);
  const Geometry& geometry = *model.geometry();
  const bool invert = model.invert_normals();
  if (const auto& spheres = geometry.spheres()) {
    const std::optional<float> scale = uniform_scale(m);
    if (!scale) {  // ellipsoids: clipped as spheres in their own space
      auto local = std::make_shared<Clipping>();
      add_clipper(*local, model, Affine3f{});
      clipping.add_placed(std::move(local), MotionTransform(m));
      return;
    }
    for (std::size_t i = 0; i < spheres->count(); ++i) {
      const float* c = &spheres->positions[3 * i];
      const float radius = spheres->radii.empty() ? spheres->radius : spheres->radii[i];
      clipping.add_sphere(m.point({c[0], c[1], c[2]}), *scale * radius, invert);
    }
  } else if (const auto& curves = geometry.curves()) {
    const std::optional<float> scale = uniform_scale(m);
    if (!scale)
      throw Error(
          "its instance's transform scales non-uniformly (a round tube becomes elliptic), which clipping "
          "curves do not support yet");
    clipping.add_curves(m.identity() ? curves : placed_curves(*curves, m, *scale), invert);
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
  } else if (const auto& subdivision = geometry.subdivision()) {
    // Catmull-Clark subdivision commutes with affine maps: place the control cage.
    auto placed = std::make_shared<SubdivisionData>(*subdivision);
    for (std::size_t v = 0; 3 * v < placed->positions.size(); ++v) {
      float* p = &placed->positions[3 * v];
      const Vec3f q = m.point({p[0], p[1], p[2]});
      p[0] = q.x, p[1] = q.y, p[2] = q.z;
    }
    clipping.add_subdivision(std::move(placed), invert);
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
  built->group->set_bvh(group.bvh());
  for (std::size_t k = 0; k < group.models().size(); ++k) {
    const auto& model = group.models()[k];
    Geometry& geometry = *model->geometry();
    // The material may have been recommitted (with a texture or colour) since the model.
    if (const std::string why = cannot_colour(geometry, model->material()); !why.empty())
      throw Error("parameter 'geometry' element " + std::to_string(k) + " (" + model->name() + " of " +
                  geometry.name() + "): " + why);
    // Geometries bake their material's base colour into their colours, except
    // isosurfaces without a colour per isovalue: their material is tinted by the model's
    // one colour. The renderer's materials and per-primitive ones are not baked (the
    // colours multiply their base colour when shading).
    const bool uncoloured_iso = geometry.isosurface_volume() && model->face_colors().empty();
    const std::optional<Vec3f> iso_tint = uncoloured_iso ? model->uniform_color() : std::nullopt;
    std::uint32_t material = uncoloured_iso ? material_index(model->material(), false, iso_tint)
                                            : material_index(model->material(), true);
    std::vector<std::uint32_t> primitive_materials;
    for (const GeometricModel::MaterialChoice& choice : model->material_choices())
      primitive_materials.push_back(choice.object ? material_index(choice.object.get(), false, iso_tint)
                                                  : material_index(nullptr, false, iso_tint, choice.renderer_index));
    if (primitive_materials.size() == 1) material = primitive_materials[0], primitive_materials.clear();
    const auto add = [&](auto geometry_of_model) {
      built->group->add(std::move(geometry_of_model), material, primitive_materials);
    };
    if (geometry.spheres()) {
      add(model_spheres(*model, built->keep_alive));
    } else if (geometry.curves()) {
      add(model_curves(*model));
    } else if (geometry.boxes()) {
      // Boxes and planes own their primitives with the model's colours.
      const auto& data = *geometry.boxes();
      add(Boxes(data.boxes, tinted_colors(model->face_colors(), model->tint(), data.boxes.size())));
    } else if (geometry.planes()) {
      const auto& data = *geometry.planes();
      auto colors = tinted_colors(model->face_colors(), model->tint(), data.planes.size());
      if (model->volume_texture())
        add(model_slice(*model, data, std::move(colors)));  // planes coloured by a volume
      else
        add(Planes(data.planes, data.bounds, std::move(colors)));
    } else if (geometry.subdivision()) {
      add(model_subdivision(*model));
    } else if (const auto isosurface = geometry.isosurface()) {
      Isosurface shells = *isosurface;  // a copy: the volume is shared
      if (!uncoloured_iso)
        shells.set_colors(tinted_colors(model->face_colors(), model->tint(), geometry.primitive_count()));
      add(std::move(shells));
    } else {
      add(model_mesh(*model, built->keep_alive));
    }
    if (const auto id = model->user_id()) built->group->set_object_id(static_cast<std::uint32_t>(k), *id);
    built->models.push_back(model);
  }
  // Committed with the world, through the kernels (sciray's intersectors are per ISA).
  return built;
}

std::uint32_t World::material_index(Material* material, bool baked, const std::optional<Vec3f>& tint,
                                    std::optional<std::uint32_t> renderer_index) {
  if (!material && !tint && !renderer_index) return no_material;
  for (std::size_t i = 0; i < materials_.size(); ++i) {
    const MaterialEntry& e = materials_[i];
    const bool same_tint = e.tint.has_value() == tint.has_value() &&
                           (!tint || (e.tint->x == tint->x && e.tint->y == tint->y && e.tint->z == tint->z));
    if (e.material.get() == material && e.baked == baked && same_tint && e.renderer_index == renderer_index)
      return static_cast<std::uint32_t>(i);
  }
  materials_.push_back({material, baked, tint, renderer_index});
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
  built->world->set_bvh(bvh_);
  built->kernels = &kernels;
  std::map<const Group*, std::size_t> group_index;  // this build's groups, by OSPRay group
  std::size_t reused = 0;
  VolumeBuildStats volumes;
  // Each volumetric model once in the engine, placed by every instance of its groups.
  std::map<const VolumetricModelObject*, std::size_t> placed_models;
  for (std::size_t i = 0; i < instances_.size(); ++i) {
    const auto& instance = instances_[i];
    Group* group = instance->group();
    // What the id channels show: the user ids, else the indices in the world and group.
    const std::uint32_t instance_id = instance->user_id().value_or(static_cast<std::uint32_t>(i));
    for (std::size_t k = 0; k < group->volumes().size(); ++k) {
      const auto& model = group->volumes()[k];
      try {
        std::size_t volume;
        if (const auto placed = placed_models.find(model.get()); placed != placed_models.end())
          volume = built->world->place_volume(placed->second, instance->placement());
        else
          volume = placed_models.emplace(model.get(), add_volume(*built->world, model->engine_model(volumes),
                                                                 instance->placement()))
                       .first->second;
        built->world->set_volume_ids(volume, static_cast<std::int32_t>(model->user_id().value_or(static_cast<std::uint32_t>(k))),
                                     static_cast<std::int32_t>(instance_id));
      } catch (const Error& e) {
        throw Error(name() + ": instance " + std::to_string(i) + " (" + instance->name() + "), its group's " +
                    model->name() + ": " + e.what());
      }
    }
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
    const std::uint32_t engine_instance = built->world->add_instance(placed.group, instance->placement());
    built->world->set_instance_id(engine_instance, instance_id);
    built->instances.push_back({instance, at->second});
  }
  // Every instance's clipping geometry, also of groups with nothing to render, clips the
  // whole world.
  built->world->set_clipping(build_clipping());
  // Through the device's kernels: builds the new groups (spheres register sciray's
  // intersector compiled for its ISA), then the top-level BVH over the instances.
  kernels.commit(*built->world);

  for (const auto& light : lights_)
    for (const sciray::Light& l : light->lights()) built->lights.push_back(l);
  // Lights in groups are placed by every instance of their group; by a moving instance
  // at each ray's time.
  for (const Ref<Instance>& instance : instances_)
    for (const auto& light : instance->group()->lights())
      for (const sciray::Light& l : light->lights()) {
        if (instance->placement().moving())
          built->moving_lights.push_back({l, instance->placement()});
        else
          built->lights.push_back(transformed(l, instance->placement().key(0)));
      }
  for (const MaterialEntry& entry : materials_) {
    if (entry.renderer_index) {  // filled in per frame, from the renderer's list
      built->renderer_materials.push_back({built->materials.size(), *entry.renderer_index, entry.tint});
      built->materials.push_back(ObjMaterial{});
    } else if (!entry.material) {  // a model's colour on a surface without a material
      ObjMaterial colored;
      colored.kd = *entry.tint;
      built->materials.push_back(colored);
    } else if (entry.baked) {
      built->materials.push_back(entry.material->with_base_color({1.f, 1.f, 1.f}));
    } else {
      built->materials.push_back(entry.tint ? entry.material->with_base_color(*entry.tint) : entry.material->material());
    }
  }
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
    if (models.empty()) continue;
    // A moving instance's clipping geometry stays in its group's space, placed at each
    // ray's time; a static instance's is placed once.
    const bool moving = instance.placement().moving();
    const auto local = moving ? std::make_shared<Clipping>() : nullptr;
    for (std::size_t k = 0; k < models.size(); ++k) {
      try {
        if (moving)
          add_clipper(*local, *models[k], Affine3f{});
        else
          add_clipper(*clipping, *models[k], instance.placement().key(0));
      } catch (const Error& e) {
        throw Error(name() + ": the group of instance " + std::to_string(i) + ", parameter 'clippingGeometry' " +
                    "element " + std::to_string(k) + " (" + models[k]->geometry()->name() + "): " + e.what());
      }
    }
    if (moving) {
      try {
        clipping->add_placed(local, instance.placement());
      } catch (const Error& e) {
        throw Error(name() + ": instance " + std::to_string(i) + " placing clipping geometry: " + e.what());
      }
    }
  }
  return clipping->empty() ? nullptr : clipping;
}

}  // namespace sciray::ospray
