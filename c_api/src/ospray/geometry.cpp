// OSPRay's geometries (mesh, sphere, curve, box, plane, isosurface, subdivision) and geometric models.
#include "scene_common.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <string>
#include <type_traits>

namespace sciray::ospray {

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
  else if (subtype() == "subdivision")
    commit_subdivision();
  else
    commit_mesh();
}

void Geometry::commit_mesh() {
  // A deforming mesh (`motion.vertex.position`: one vec3f array per time step, spread
  // over `time`) takes its topology and attributes from the first step.
  std::vector<const Data*> steps;
  if (const Data* list = get_data(*this, find("motion.vertex.position"), "motion.vertex.position", {OSP_DATA})) {
    if (list->size() < 2)
      throw Error(name() + ": parameter 'motion.vertex.position' needs at least two time steps, got " +
                  std::to_string(list->size()));
    for (std::uint64_t k = 0; k < list->size(); ++k) {
      const std::string element = "parameter 'motion.vertex.position' element " + std::to_string(k);
      const Object* object = list->object(k);
      if (!object) throw Error(name() + ": " + element + " is NULL");
      const auto* step = static_cast<const Data*>(object);
      if (step->element_type() != OSP_VEC3F || step->dimensions() != 1)
        throw Error(name() + ": " + element + " must be a 1D array of vec3f, got an array of " +
                    type_name(step->element_type()));
      if (k > 0 && step->size() != steps[0]->size())
        throw Error(name() + ": " + element + " has " + std::to_string(step->size()) + " vertices but element 0 has " +
                    std::to_string(steps[0]->size()));
      steps.push_back(step);
    }
  }
  const Data* position =
      steps.empty() ? get_data(*this, find("vertex.position"), "vertex.position", {OSP_VEC3F}) : steps[0];
  if (!position)
    throw Error(name() + ": required parameter 'vertex.position' (array of vec3f) is missing (or give "
                         "'motion.vertex.position' for a deforming mesh)");
  std::pair<float, float> time{0.f, 1.f};
  if (const Param* t = find("time"); t && !steps.empty()) {
    time = read_range(*this, *t, "time");
    if (time.first > time.second)
      throw Error(name() + ": parameter 'time' must have lower <= upper, got [" + std::to_string(time.first) + ", " +
                  std::to_string(time.second) + "]");
  }
  const std::size_t vertices = position->size();
  const Data* index = get_data(*this, find("index"), "index", {OSP_VEC3UI, OSP_VEC3I, OSP_VEC4UI, OSP_VEC4I});
  // Without `index`, as OSPRay: consecutive vertices make triangles, or quads with `quadSoup`.
  const bool quad_soup = get_bool("quadSoup", false);
  const bool quads = index ? index->element_type() == OSP_VEC4UI || index->element_type() == OSP_VEC4I : quad_soup;
  const unsigned corners = quads ? 4 : 3;
  if (!index && vertices % corners != 0)
    throw Error(name() + ": without 'index', 'vertex.position' must hold " + (quads ? "4" : "3") + " vertices per " +
                (quads ? "quad ('quadSoup')" : "triangle") + ", got " + std::to_string(vertices));
  const std::size_t faces = index ? index->size() : vertices / corners;
  PaddedVector<std::uint32_t> indices;
  indices.reserve(corners * faces);
  for (std::size_t f = 0; f < faces; ++f)
    for (unsigned c = 0; c < corners; ++c) {
      std::uint32_t v = static_cast<std::uint32_t>(corners * f + c);
      if (index) std::memcpy(&v, index->element(f) + 4 * c, sizeof v);  // a negative int becomes out of range
      if (v >= vertices)
        throw Error(name() + ": 'index' of face " + std::to_string(f) + " refers to vertex " + std::to_string(v) +
                    " but 'vertex.position' has " + std::to_string(vertices));
      indices.push_back(v);
    }

  // Attributes per vertex (`vertex.*`) or, as OSPRay's face-varying ones (`normal`,
  // `color`, `texcoord`), per face corner; a face-varying one wins over its per-vertex one.
  struct Attribute {
    const Data* data = nullptr;
    bool face_varying = false;
    std::string id;
  };
  const auto attribute = [&](const std::string& id, std::initializer_list<OSPDataType> types) {
    if (const Data* d = get_data(*this, find(id), id, types)) return Attribute{d, true, id};
    return Attribute{get_data(*this, find("vertex." + id), "vertex." + id, types), false, "vertex." + id};
  };
  // A deforming mesh's normals may change too: one vec3f array per time step, per vertex
  // (`motion.vertex.normal`) or per face corner (`motion.normal`). As in OSPRay they are
  // read only beside `motion.vertex.position`, replace the rigid normals, and may have
  // more steps than the positions (the rest is ignored).
  Attribute motion_normal;
  std::vector<Attribute> normal_steps;
  if (!steps.empty()) {
    if (const Data* d = get_data(*this, find("motion.normal"), "motion.normal", {OSP_DATA}))
      motion_normal = {d, true, "motion.normal"};
    else
      motion_normal = {get_data(*this, find("motion.vertex.normal"), "motion.vertex.normal", {OSP_DATA}), false,
                       "motion.vertex.normal"};
  }
  if (const Data* list = motion_normal.data) {
    if (list->size() < steps.size())
      throw Error(name() + ": parameter '" + motion_normal.id + "' has " + std::to_string(list->size()) +
                  " time steps but 'motion.vertex.position' has " + std::to_string(steps.size()));
    for (std::size_t k = 0; k < steps.size(); ++k) {
      const std::string element = motion_normal.id + "[" + std::to_string(k) + "]";
      const auto* step = static_cast<const Data*>(list->object(k));
      if (!step) throw Error(name() + ": parameter '" + element + "' is NULL");
      if (step->element_type() != OSP_VEC3F || step->dimensions() != 1)
        throw Error(name() + ": parameter '" + element + "' must be a 1D array of vec3f, got an array of " +
                    type_name(step->element_type()));
      normal_steps.push_back({step, motion_normal.face_varying, element});
    }
  }
  const Attribute normal = motion_normal.data ? Attribute{} : attribute("normal", {OSP_VEC3F});
  const Attribute color = attribute("color", {OSP_VEC4F, OSP_VEC3F});
  const Attribute texcoord = attribute("texcoord", {OSP_VEC2F});
  const bool face_varying =
      normal.face_varying || motion_normal.face_varying || color.face_varying || texcoord.face_varying;

  // A copy, padded for Embree: the application's arrays carry no padding guarantee.
  auto mesh = std::make_shared<MeshData>();
  mesh->vertices_per_face = corners;
  const auto copy_positions = [&](const Data& from, PaddedVector<float>& to) {
    if (!face_varying) return append_floats(to, from, 3);
    // One vertex per face corner, so that every attribute can be per vertex.
    to.reserve(3 * corners * faces);
    for (std::size_t k = 0; k < corners * faces; ++k)
      for (int c = 0; c < 3; ++c) to.push_back(read_float(from.element(indices[k]) + 4 * c));
  };
  copy_positions(*position, mesh->positions);
  for (const Data* step : steps) copy_positions(*step, mesh->motion_positions.emplace_back());
  mesh->time_start = time.first, mesh->time_end = time.second;
  if (!face_varying) {
    mesh->indices = std::move(indices);
  } else {
    mesh->indices.resize(corners * faces);
    for (std::size_t k = 0; k < corners * faces; ++k) mesh->indices[k] = static_cast<std::uint32_t>(k);
  }
  const auto read = [&](const Attribute& a, PaddedVector<float>& out, int components, int pad_to) {
    if (!a.data) return;
    const int element_components = a.data->element_type() == OSP_VEC4F ? 4 : components;
    if (!face_varying) return append_per_item(out, *this, a.id, *a.data, vertices, "vertices", false, element_components, pad_to);
    const std::size_t items = a.face_varying ? corners * faces : vertices;
    per_item_count(*this, a.id, *a.data, items, a.face_varying ? "face corners" : "vertices");
    for (std::size_t k = 0; k < corners * faces; ++k) {
      const std::byte* e = a.data->element(a.face_varying ? k : indices[k]);
      for (int c = 0; c < element_components; ++c) out.push_back(read_float(e + 4 * c));
      for (int c = element_components; c < pad_to; ++c) out.push_back(1.f);
    }
  };
  read(normal, mesh->normals, 3, 3);
  for (const Attribute& step : normal_steps) read(step, mesh->motion_normals.emplace_back(), 3, 3);
  read(color, mesh->vertex_colors, 3, 4);
  read(texcoord, mesh->texcoords, 2, 2);
  TriangleMesh check(mesh);
  check.validate();  // names the bad vertex: "mesh: 'vertex.position' 3 is not finite"
  bounds_ = check.bounds();
  primitive_count_ = check.face_count();
  mesh_ = std::move(mesh);
}

namespace {

/// The bounds Embree gives `geometry` (as OSPRay reports them), which programs frame
/// their cameras by, so sciray reports the same: a curve's segments' own bounds — tight
/// around a B-spline, grown by the larger end radius around a linear segment — and a
/// subdivision surface's tessellated patches, inside its control cage.
template <class G>
Box3f embree_bounds(const G& geometry_of) {
  static const accel::Device device;  // one for all bounds queries; Embree devices are thread-safe
  accel::Scene scene(device);
  const RTCGeometry geometry = geometry_of.template create_embree_geometry<simd::scalar>(device);
  scene.attach(geometry);
  rtcReleaseGeometry(geometry);
  scene.commit();
  return scene.bounds();
}

}  // namespace

void Geometry::commit_spheres() {
  const Data* position = get_data(*this, find("sphere.position"), "sphere.position", {OSP_VEC3F});
  if (!position) throw Error(name() + ": required parameter 'sphere.position' (array of vec3f) is missing");
  const Data* radius = get_data(*this, find("sphere.radius"), "sphere.radius", {OSP_FLOAT});
  const Data* texcoord = get_data(*this, find("sphere.texcoord"), "sphere.texcoord", {OSP_VEC2F});
  const auto type = static_cast<SphereType>(get_enum(*this, get_int("type", OSP_SPHERE), "type",
                                                     {"OSP_SPHERE", "OSP_DISC", "OSP_ORIENTED_DISC"}, OSP_SPHERE));
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
  const std::size_t count = position->size();
  append_floats(data->positions, *position, 3);
  // A one-element `sphere.radius` is the radius of every sphere, as `radius` is.
  data->radius = get_float("radius", 0.01f);
  if (radius && per_item_count(*this, "sphere.radius", *radius, count, "spheres", true) == 1)
    data->radius = read_float(radius->element(0));
  else if (radius)
    append_per_item(data->radii, *this, "sphere.radius", *radius, count, "spheres", false, 1);
  if (normal) append_per_item(data->normals, *this, "sphere.normal", *normal, count, "spheres", false, 3);
  if (texcoord) append_per_item(data->texcoords, *this, "sphere.texcoord", *texcoord, count, "spheres", false, 2);
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
  // Per-vertex arrays need to cover only the vertices the segments use (OSPRay reads
  // what it needs): longer ones are cut, shorter ones padded past the last vertex used.
  const std::size_t vertices = data->vertex_count();
  const std::uint32_t span = data->basis == CurveBasis::linear || data->basis == CurveBasis::hermite ? 2 : 4;
  std::size_t used = 0;
  for (std::uint32_t first : data->indices)
    used = std::max(used, std::min<std::size_t>(vertices, static_cast<std::size_t>(first) + span));
  const auto per_vertex = [&](PaddedVector<float>& out, const char* id, const Data& array, int components, int pad_to,
                              float fill) {
    append_per_item(out, *this, id, array, std::min(used, vertices), "vertices the segments use", false, components,
                    pad_to);
    out.resize(static_cast<std::size_t>(pad_to) * vertices, fill);
  };
  if (const Data* color = get_data(*this, find("vertex.color"), "vertex.color", {OSP_VEC4F, OSP_VEC3F}))
    per_vertex(data->colors, "vertex.color", *color, color->element_type() == OSP_VEC4F ? 4 : 3, 4, 1.f);
  if (tangent) per_vertex(data->tangents, "vertex.tangent", *tangent, 4, 4, 0.f);
  if (normal) per_vertex(data->normals, "vertex.normal", *normal, 3, 3, 0.f);

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
  bounds_ = embree_bounds(check);
  primitive_count_ = check.segment_count();
  curves_ = std::move(data);
}

void Geometry::commit_subdivision() {
  const Data* position = get_data(*this, find("vertex.position"), "vertex.position", {OSP_VEC3F});
  if (!position) throw Error(name() + ": required parameter 'vertex.position' (array of vec3f) is missing");
  const Data* index = get_data(*this, find("index"), "index", {OSP_UINT, OSP_INT});
  if (!index) throw Error(name() + ": required parameter 'index' (array of uint) is missing");
  const Data* face = get_data(*this, find("face"), "face", {OSP_UINT, OSP_INT});
  const auto read_uints = [](const Data& from, std::size_t components, PaddedVector<std::uint32_t>& to) {
    to.reserve(components * from.size());
    for (std::uint64_t i = 0; i < from.size(); ++i)
      for (std::size_t c = 0; c < components; ++c) {
        std::uint32_t v;
        std::memcpy(&v, from.element(i) + 4 * c, sizeof v);  // a negative int becomes out of range
        to.push_back(v);
      }
  };

  auto data = std::make_shared<SubdivisionData>();
  append_floats(data->positions, *position, 3);
  read_uints(*index, 1, data->indices);
  if (face) {
    read_uints(*face, 1, data->face_sizes);
  } else {
    // Without `face`, as OSPRay: all quads.
    if (data->indices.size() % 4 != 0)
      throw Error(name() + ": without 'face' every face is a quad, so 'index' must hold a multiple of 4 indices, got " +
                  std::to_string(data->indices.size()));
    data->face_sizes.assign(data->indices.size() / 4, 4);
  }

  // OSPRay takes only a vec2ui `edgeCrease.index` and ignores a vec2i one with a message
  // at debug level (its own subdivision_cube scene passes one, and its reference images
  // show no edge creases): so does sciray.
  const Param* edge_crease = find("edgeCrease.index");
  if (edge_crease && edge_crease->object && edge_crease->object->kind() == OSP_DATA &&
      static_cast<const Data*>(edge_crease->object.get())->element_type() == OSP_VEC2I) {
    debug_message("ignoring 'edgeCrease.index' (an array of vec2i; edge creases take vec2ui, as in OSPRay)");
    find("edgeCrease.weight");
    edge_crease = nullptr;
  }
  if (const Data* creases = get_data(*this, edge_crease, "edgeCrease.index", {OSP_VEC2UI})) {
    read_uints(*creases, 2, data->edge_creases);
    const Data* weights = get_data(*this, find("edgeCrease.weight"), "edgeCrease.weight", {OSP_FLOAT});
    if (!weights) throw Error(name() + ": 'edgeCrease.index' needs 'edgeCrease.weight' (array of float)");
    append_floats(data->edge_crease_weights, *weights, 1);
  }
  if (const Data* creases = get_data(*this, find("vertexCrease.index"), "vertexCrease.index", {OSP_UINT, OSP_INT})) {
    read_uints(*creases, 1, data->vertex_creases);
    const Data* weights = get_data(*this, find("vertexCrease.weight"), "vertexCrease.weight", {OSP_FLOAT});
    if (!weights) throw Error(name() + ": 'vertexCrease.index' needs 'vertexCrease.weight' (array of float)");
    append_floats(data->vertex_crease_weights, *weights, 1);
  }

  // Attributes per control vertex (`vertex.*`) or per face corner (`color`, `texcoord`,
  // which win). Per-vertex arrays need only cover the vertices `index` uses (OSPRay's
  // scenes pad the positions for Embree, not the colours); the rest are filled.
  std::size_t used = 0;
  for (std::uint32_t v : data->indices)
    used = std::max<std::size_t>(used, std::min<std::size_t>(v, position->size() - 1) + 1);
  const auto attribute = [&](const std::string& id, std::initializer_list<OSPDataType> types, int pad_to,
                             PaddedVector<float>& out, bool& face_varying) {
    const Data* values = get_data(*this, find(id), id, types);
    face_varying = values != nullptr;
    if (!values) values = get_data(*this, find("vertex." + id), "vertex." + id, types);
    if (!values) return;
    const int components = values->element_type() == OSP_VEC4F ? 4 : values->element_type() == OSP_VEC3F ? 3 : 2;
    const std::size_t items = face_varying ? data->indices.size() : used;
    append_per_item(out, *this, face_varying ? id : "vertex." + id, *values, items,
                    face_varying ? "face corners" : "vertices 'index' uses", false, components, pad_to);
    if (!face_varying) out.resize(static_cast<std::size_t>(pad_to) * position->size(), 0.f);
  };
  attribute("color", {OSP_VEC4F, OSP_VEC3F}, 4, data->colors, data->face_varying_colors);
  attribute("texcoord", {OSP_VEC2F}, 2, data->texcoords, data->face_varying_texcoords);
  if (const Data* levels = get_data(*this, find("index.level"), "index.level", {OSP_FLOAT})) {
    per_item_count(*this, "index.level", *levels, data->indices.size(), "indices");
    append_per_item(data->edge_levels, *this, "index.level", *levels, data->indices.size(), "indices", false, 1);
  }
  data->level = get_float("level", 5.f);
  data->mode = static_cast<SubdivisionMode>(get_enum(*this, get_int("mode", OSP_SUBDIVISION_SMOOTH_BOUNDARY), "mode",
                                                     {"OSP_SUBDIVISION_NO_BOUNDARY", "OSP_SUBDIVISION_SMOOTH_BOUNDARY",
                                                      "OSP_SUBDIVISION_PIN_CORNERS", "OSP_SUBDIVISION_PIN_BOUNDARY",
                                                      "OSP_SUBDIVISION_PIN_ALL"}));
  const Subdivision check(data);
  check.validate();  // "subdivision: 'face' 2 has 2 vertices; a face needs at least 3"
  bounds_ = embree_bounds(check);
  primitive_count_ = data->face_count();
  subdivision_ = std::move(data);
}

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
  // OSPRay's (a, b, c, d) is the plane a·x + b·y + c·z = d (measured against OSPRay 3.1's
  // runtime: (0, 0, 1, -0.4) lies at z = -0.4); sciray's Planes read a·x + b·y + c·z + d = 0.
  data->planes = coefficients->to_vector<Planes::Plane>([](const std::byte* p) {
    return Planes::Plane{read_float(p), read_float(p + 4), read_float(p + 8), -read_float(p + 12)};
  });
  if (bounds) data->bounds = bounds->to_vector<Box3f>(read_box);
  const Planes check(data->planes, data->bounds);
  check.validate();  // "plane: 'plane.coefficients' 0 has a zero normal (a, b, c)"
  bounds_ = check.bounds();  // unbounded planes add nothing
  primitive_count_ = check.count();
  planes_ = std::move(data);
}

std::string cannot_colour(const Geometry& geometry, const Material* material) {
  if (!material) return {};
  if (!material->volume_map_kd()) return {};
  if (geometry.spheres() && geometry.sphere_type() != SphereType::sphere)
    return "its material's 'map_kd' (a volume texture) colours spheres of type OSP_SPHERE only, not discs";
  if (!geometry.planes() && !geometry.spheres())
    return "its material's 'map_kd' (a volume texture) is not supported yet on " + geometry.subtype() +
           " geometry; volume textures colour plane geometry (slices) and spheres only";
  return {};
}

void GeometricModel::on_commit() {
  // Read into locals: a commit that fails leaves the model as it was.
  Ref<Geometry> geometry = get_object<Geometry>("geometry", OSP_GEOMETRY, true);
  if (!geometry->committed()) throw Error(name() + ": its geometry has not been committed");
  // `index`: per primitive, which element of `material` and `color` it takes (OSPRay's
  // indirection; the lists may then be shorter than the primitives).
  const std::size_t primitives = geometry->primitive_count();
  std::vector<std::uint32_t> slots;
  if (const Data* index = get_data(*this, find("index"), "index", {OSP_UCHAR, OSP_UINT})) {
    per_item_count(*this, "index", *index, primitives, "primitives");
    for (std::size_t p = 0; p < primitives; ++p) {
      std::uint32_t slot = 0;
      if (index->element_type() == OSP_UCHAR)
        slot = static_cast<std::uint8_t>(*index->element(p));
      else
        std::memcpy(&slot, index->element(p), sizeof slot);
      slots.push_back(slot);
    }
  }
  // The element of a list of `size` that primitive p takes (by `index`), range-checked.
  const auto slot_of = [&](std::size_t p, std::size_t size, const char* id) {
    const std::uint32_t slot = slots[p];
    if (slot >= size)
      throw Error(name() + ": parameter 'index' element " + std::to_string(p) + " is " + std::to_string(slot) +
                  ", but '" + id + "' has " + std::to_string(size) + " elements");
    return static_cast<std::size_t>(slot);
  };

  // `material`: one OSPMaterial, or indices into the renderer's `material` list, either
  // one for all primitives or one per primitive (OSPRay's material lists).
  Ref<Material> material;
  std::vector<MaterialChoice> choices;
  if (const Data* list = get_data(*this, find("material"), "material", {OSP_MATERIAL, OSP_UINT, OSP_INT})) {
    const bool objects = list->element_type() == OSP_MATERIAL;
    const std::size_t given = !slots.empty() ? list->size()
                                             : per_item_count(*this, "material", *list, primitives, "primitives", true);
    for (std::size_t i = 0; i < given; ++i) {
      MaterialChoice choice{nullptr, 0};
      if (objects) {
        auto* object = static_cast<Material*>(list->object(i));
        if (!object) throw Error(name() + ": parameter 'material' element " + std::to_string(i) + " is NULL");
        choice.object = object;
      } else {
        std::int32_t index;
        std::memcpy(&index, list->element(i), sizeof index);
        if (list->element_type() == OSP_INT && index < 0)
          throw Error(name() + ": parameter 'material' element " + std::to_string(i) + " is a negative index " +
                      std::to_string(index) + " into the renderer's materials");
        choice.renderer_index = static_cast<std::uint32_t>(index);
      }
      choices.push_back(std::move(choice));
    }
    if (!slots.empty() && choices.size() > 1) {
      std::vector<MaterialChoice> per_primitive;
      for (std::size_t p = 0; p < primitives; ++p) per_primitive.push_back(choices[slot_of(p, choices.size(), "material")]);
      choices = std::move(per_primitive);
    }
    if (choices.size() == 1 && choices[0].object) {
      material = choices[0].object;
      choices.clear();
    }
  }
  // One colour is for every primitive; otherwise one per primitive (an isosurface's are
  // its isovalues), except on curves, whose segments sciray does not colour apart.
  PaddedVector<float> face_colors;
  std::optional<std::array<float, 4>> uniform_color;
  if (const Data* color = get_data(*this, find("color"), "color", {OSP_VEC4F, OSP_VEC3F})) {
    const bool per_primitive = !geometry->curves();
    const int components = color->element_type() == OSP_VEC4F ? 4 : 3;
    const float alpha = components == 4 ? read_float(color->element(0) + 12) : 1.f;
    // One translucent colour is spread over the primitives, whose colours carry alpha.
    if (color->size() == 1 && (!per_primitive || alpha == 1.f)) {
      uniform_color = {read_float(color->element(0)), read_float(color->element(0) + 4),
                       read_float(color->element(0) + 8), alpha};
    } else if (per_primitive && !slots.empty()) {
      for (std::size_t p = 0; p < primitives; ++p) {
        const std::byte* e = color->element(slot_of(p, color->size(), "color"));
        for (int c = 0; c < 4; ++c) face_colors.push_back(c < components ? read_float(e + 4 * c) : 1.f);
      }
    } else if (per_primitive) {
      append_per_item(face_colors, *this, "color", *color, primitives, "primitives", true, components, 4);
    } else {
      throw Error(name() + ": parameter 'color' has " + std::to_string(color->size()) + " colours; " +
                  geometry->subtype() + " geometry takes one colour for all its primitives (per-primitive colours "
                  "of " + geometry->subtype() + " geometry are not supported yet)");
    }
  }
  if (const std::string why = cannot_colour(*geometry, material.get()); !why.empty()) throw Error(name() + ": " + why);
  for (const MaterialChoice& choice : choices)
    if (const std::string why = cannot_colour(*geometry, choice.object.get()); !why.empty())
      throw Error(name() + ": " + why);
  // Shading is two-sided, so the side matters only to clipping geometry.
  const bool invert_normals = get_bool("invertNormals", false);
  const std::optional<std::uint32_t> user_id = get_user_id();
  geometry_ = std::move(geometry);
  material_ = std::move(material);
  material_choices_ = std::move(choices);
  face_colors_ = std::move(face_colors);
  uniform_color_ = uniform_color;
  invert_normals_ = invert_normals;
  user_id_ = user_id;
}

std::optional<Vec3f> GeometricModel::material_color() const {
  if (!material_) return std::nullopt;
  return material_->base_color();  // as last committed: a material commit reaches the world
}

std::optional<Vec3f> GeometricModel::uniform_color() const {
  if (!uniform_color_) return std::nullopt;
  const Vec3f rgb{(*uniform_color_)[0], (*uniform_color_)[1], (*uniform_color_)[2]};
  const std::optional<Vec3f> kd = material_color();
  return kd ? rgb * *kd : rgb;
}

TextureObject* GeometricModel::volume_texture() const { return material_ ? material_->volume_map_kd() : nullptr; }

std::uint64_t GeometricModel::version() const {
  std::uint64_t v = version_;
  if (geometry_) v = std::max(v, geometry_->version());
  if (material_) v = std::max(v, material_->version());
  return v;
}

// ---- isosurfaces and volume textures -------------------------------------------------------

namespace {

/// The engine isosurface of `volume` (finds the macrocells that hold an isovalue).
std::shared_ptr<const Isosurface> make_isosurface(const EngineVolume& volume, const std::vector<float>& isovalues) {
  return std::visit(
      [&](const auto& v) -> std::shared_ptr<const Isosurface> {
        using V = std::decay_t<decltype(v)>;
        if constexpr (std::is_same_v<V, std::monostate>)
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

}  // namespace sciray::ospray
