#include "scene.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <mutex>

#include <pybind11/stl.h>

#include "arrays.hpp"
#include "shading_json.hpp"
#include "sciray/io/vtk.hpp"
#include "sciray/testing/scenes.hpp"
#include "volume_scene.hpp"

namespace sciray_python {

namespace {

using sciray::PaddedVector;

/// Keeps a Python object alive from engine objects, which may be released without the GIL.
std::shared_ptr<const void> hold(py::object object) {
  return {new py::object(std::move(object)), [](const void* p) {
            py::gil_scoped_acquire gil;
            delete static_cast<const py::object*>(p);
          }};
}

using Keep = std::vector<std::shared_ptr<const void>>;

/// Keyword parameters as the tool's JSON (numbers, strings, sequences, nested dicts, and
/// Material objects for a mix material's parts).
nlohmann::json json_of(py::handle value, const std::string& name) {
  if (value.is_none()) return nullptr;
  if (py::isinstance<py::bool_>(value)) return value.cast<bool>();
  if (py::isinstance<py::int_>(value)) return value.cast<std::int64_t>();
  if (py::isinstance<py::float_>(value)) return value.cast<double>();
  if (py::isinstance<py::str>(value)) return value.cast<std::string>();
  if (py::isinstance<Material>(value)) return value.cast<const Material&>().json;
  if (py::isinstance<py::dict>(value)) {
    nlohmann::json object = nlohmann::json::object();
    for (const auto& [key, item] : value.cast<py::dict>()) {
      const auto k = py::str(key).cast<std::string>();
      object[k] = json_of(item, name + "." + k);
    }
    return object;
  }
  if (py::hasattr(value, "tolist")) return json_of(value.attr("tolist")(), name);  // numpy arrays and scalars
  if (py::isinstance<py::list>(value) || py::isinstance<py::tuple>(value)) {
    nlohmann::json array = nlohmann::json::array();
    for (const auto& item : value) array.push_back(json_of(item, name));
    return array;
  }
  type_error(name, "expected a number, string, sequence or dict, got " +
                       py::str(py::type::handle_of(value).attr("__name__")).cast<std::string>());
}

nlohmann::json json_of(const py::kwargs& params) {
  nlohmann::json object = nlohmann::json::object();
  for (const auto& [key, item] : params) {
    const auto k = py::str(key).cast<std::string>();
    object[k] = json_of(item, k);
  }
  return object;
}

template <class T>
void keep_copy(Keep& keep, const Rows<T>& rows) {
  if (rows.copy) keep.push_back(rows.copy);
}

/// Two finite numbers lo < hi (or lo == hi, widened), or the finite range of `values`.
std::array<float, 2> value_range_of(py::handle given, const sciray::StridedView<float>& values, const char* argument) {
  if (!given.is_none()) {
    const auto r = float_rows(given, {argument, 1});
    if (r.view.count != 2 || !std::isfinite(*r.view.element(0)) || !std::isfinite(*r.view.element(1)))
      value_error(argument, "expected two finite numbers (lo, hi)");
    return {*r.view.element(0), *r.view.element(1)};
  }
  float lo = std::numeric_limits<float>::infinity(), hi = -lo;
  for (std::size_t i = 0; i < values.count; ++i)
    if (const float v = *values.element(i); std::isfinite(v)) lo = std::min(lo, v), hi = std::max(hi, v);
  if (lo > hi) return {0.f, 1.f};
  return {lo, hi};
}

/// RGBA per item from `scalars` through `colormap` (rows of RGB, evenly spread; default
/// sciray's viridis-like map) over `scalar_range` (default: the scalars' finite range).
std::shared_ptr<PaddedVector<float>> scalar_colors(py::handle scalars, py::handle scalar_range, py::handle colormap,
                                                   std::size_t count, const char* per) {
  const auto s = float_rows(scalars, {"scalars", 1});
  if (s.view.count != count)
    value_error("scalars", "has " + std::to_string(s.view.count) + " values but there are " + std::to_string(count) +
                               " " + per);
  const auto [lo, hi] = value_range_of(scalar_range, s.view, "scalar_range");
  std::vector<sciray::Vec3f> table;
  if (!colormap.is_none()) {
    const auto rows = float_rows(colormap, {"colormap", 3});
    if (rows.view.count < 2) value_error("colormap", "needs at least 2 colours");
    for (std::size_t i = 0; i < rows.view.count; ++i) {
      const float* c = rows.view.element(i);
      table.push_back({c[0], c[1], c[2]});
    }
  }
  auto out = std::make_shared<PaddedVector<float>>();
  out->reserve(4 * count);
  for (std::size_t i = 0; i < count; ++i) {
    const float v = *s.view.element(i);
    const float x = hi > lo ? std::clamp((v - lo) / (hi - lo), 0.f, 1.f) : 0.5f;
    sciray::Vec3f c = sciray::testing::colormap(x);
    if (!table.empty()) {
      const float at = x * static_cast<float>(table.size() - 1);
      const std::size_t k = std::min(static_cast<std::size_t>(at), table.size() - 2);
      const float f = at - static_cast<float>(k);
      c = table[k] * (1.f - f) + table[k + 1] * f;
    }
    // NaN scalars (missing values) show grey.
    if (!std::isfinite(v)) c = {0.5f, 0.5f, 0.5f};
    out->insert(out->end(), {c.x, c.y, c.z, 1.f});
  }
  return out;
}

sciray::CurveBasis curve_basis(const std::string& name) {
  const std::pair<const char*, sciray::CurveBasis> bases[] = {{"linear", sciray::CurveBasis::linear},
                                                              {"bezier", sciray::CurveBasis::bezier},
                                                              {"bspline", sciray::CurveBasis::bspline},
                                                              {"catmull-rom", sciray::CurveBasis::catmull_rom}};
  for (const auto& [n, b] : bases)
    if (name == n) return b;
  value_error("basis", "expected linear, bezier, bspline or catmull-rom, got '" + name + "'");
}

sciray::CurveType curve_type(const std::string& name) {
  if (name == "round") return sciray::CurveType::round;
  if (name == "flat") return sciray::CurveType::flat;
  value_error("type", "expected round or flat, got '" + name + "'");
}

std::optional<sciray::Material> material_of(const std::optional<Material>& m) {
  if (!m) return std::nullopt;
  return m->material;
}

int add_mesh(Scene& scene, py::object vertices, py::object indices, py::object normals, py::object colors,
             py::object face_colors, py::object texcoords, py::object scalars, py::object scalar_range,
             py::object colormap, const std::optional<Material>& material) {
  if (indices.is_none()) {
    // A triangle soup: three vertices a face.
    const py::ssize_t n = numeric_array(vertices, "vertices").shape(0);
    if (n % 3 != 0)
      value_error("vertices", "without indices, a triangle soup needs a multiple of 3 vertices, got " + std::to_string(n));
    py::array soup = padded_array(py::dtype::of<std::uint32_t>(), {n / 3, 3});
    for (py::ssize_t i = 0; i < n; ++i) static_cast<std::uint32_t*>(soup.mutable_data())[i] = static_cast<std::uint32_t>(i);
    indices = soup;
  }
  if (!colors.is_none() && !scalars.is_none()) type_error("colors", "give colors or scalars, not both");
  SceneEntry entry;
  entry.kind = "mesh";
  entry.material = material_of(material);
  entry.build = [=]() -> Built {
    const py::array index_array = numeric_array(indices, "indices");
    const int corners = index_array.ndim() == 2 && index_array.shape(1) == 4 ? 4 : 3;
    const auto positions = float_rows(vertices, {"vertices", 3, false, true});
    const auto faces = index_rows(index_array, {"indices", corners, false, true});
    Keep keep{hold(vertices), hold(indices)};
    keep_copy(keep, positions), keep_copy(keep, faces);
    sciray::TriangleMesh::SharedArrays arrays;
    arrays.positions = positions.view, arrays.indices = faces.view, arrays.vertices_per_face = static_cast<unsigned>(corners);
    bool all_shared = positions.shared() && faces.shared();
    const auto optional = [&](const py::object& given, const RowSpec& spec, sciray::StridedView<float>& into) {
      if (given.is_none()) return;
      const auto rows = float_rows(given, spec);
      into = rows.view, all_shared = all_shared && rows.shared();
      keep_copy(keep, rows), keep.push_back(hold(given));
    };
    optional(normals, {"normals", 3}, arrays.normals);
    optional(colors, {"colors", 4, true}, arrays.vertex_colors);
    optional(face_colors, {"face_colors", 4, true}, arrays.face_colors);
    optional(texcoords, {"texcoords", 2}, arrays.texcoords);
    if (!scalars.is_none()) {
      auto mapped = scalar_colors(scalars, scalar_range, colormap, positions.view.count, "vertices");
      arrays.vertex_colors = {mapped->data(), positions.view.count, 4 * sizeof(float)};
      keep.push_back(std::move(mapped)), all_shared = false;
    }
    auto mesh = std::make_shared<sciray::TriangleMesh>(sciray::TriangleMesh::shared(arrays));
    naming_arguments("add_mesh",
                     {{"mesh: ", ""}, {"'vertex.position'", "vertices"}, {"'index'", "indices"}, {"'vertex.normal'", "normals"},
                      {"'vertex.color'", "colors"}, {"'color'", "face_colors"}, {"'vertex.texcoord'", "texcoords"}},
                     [&] { mesh->validate(); });
    return {[mesh, keep](EngineWorld& world, std::uint32_t m) { world.add(sciray::TriangleMesh(*mesh), m); }, all_shared};
  };
  return scene.add(std::move(entry));
}

int add_spheres(Scene& scene, py::object centers, py::object radius, py::object colors, py::object scalars,
                py::object scalar_range, py::object colormap, py::object texcoords, const std::optional<Material>& material) {
  if (!colors.is_none() && !scalars.is_none()) type_error("colors", "give colors or scalars, not both");
  SceneEntry entry;
  entry.kind = "spheres";
  entry.material = material_of(material);
  entry.build = [=]() -> Built {
    const auto positions = float_rows(centers, {"centers", 3});
    Keep keep{hold(centers)};
    keep_copy(keep, positions);
    sciray::Spheres::SharedArrays arrays;
    arrays.positions = positions.view;
    bool all_shared = positions.shared();
    if (py::isinstance<py::float_>(radius) || py::isinstance<py::int_>(radius)) {
      arrays.radius = radius.cast<float>();
    } else {
      const auto radii = float_rows(radius, {"radius", 1});
      arrays.radii = radii.view, all_shared = all_shared && radii.shared();
      keep_copy(keep, radii), keep.push_back(hold(radius));
    }
    if (!colors.is_none()) {
      const auto rows = float_rows(colors, {"colors", 4, true});
      arrays.colors = rows.view, all_shared = all_shared && rows.shared();
      keep_copy(keep, rows), keep.push_back(hold(colors));
    }
    if (!texcoords.is_none()) {
      const auto rows = float_rows(texcoords, {"texcoords", 2});
      arrays.texcoords = rows.view, all_shared = all_shared && rows.shared();
      keep_copy(keep, rows), keep.push_back(hold(texcoords));
    }
    if (!scalars.is_none()) {
      auto mapped = scalar_colors(scalars, scalar_range, colormap, positions.view.count, "spheres");
      arrays.colors = {mapped->data(), positions.view.count, 4 * sizeof(float)};
      keep.push_back(std::move(mapped)), all_shared = false;
    }
    auto spheres = std::make_shared<sciray::Spheres>(sciray::Spheres::shared(arrays));
    naming_arguments("add_spheres",
                     {{"sphere: ", ""}, {"'sphere.position'", "centers"}, {"'sphere.radius'", "radius"}, {"'radius'", "radius"},
                      {"'color'", "colors"}, {"'sphere.texcoord'", "texcoords"}},
                     [&] { spheres->validate(); });
    return {[spheres, keep](EngineWorld& world, std::uint32_t m) { world.add(sciray::Spheres(*spheres), m); }, all_shared};
  };
  return scene.add(std::move(entry));
}

int add_curves(Scene& scene, py::object vertices, py::object radius, py::object indices, py::object colors,
               const std::string& basis_name, const std::string& type_name, const std::optional<Material>& material) {
  const sciray::CurveBasis basis = curve_basis(basis_name);
  const sciray::CurveType type = curve_type(type_name);
  SceneEntry entry;
  entry.kind = "curves";
  entry.material = material_of(material);
  entry.build = [=]() -> Built {
    const py::array given = numeric_array(vertices, "vertices");
    const bool with_radius = given.ndim() == 2 && given.shape(1) == 4;
    const auto points = float_rows(given, {"vertices", with_radius ? 4 : 3});
    const std::size_t n = points.view.count;
    sciray::CurveData data;
    data.basis = basis, data.type = type;
    std::optional<Rows<float>> radii;
    float one_radius = 0.f;
    if (!with_radius) {
      if (py::isinstance<py::float_>(radius) || py::isinstance<py::int_>(radius))
        one_radius = radius.cast<float>();
      else if (radii = float_rows(radius, {"radius", 1}); radii->view.count != n)
        value_error("radius", "has " + std::to_string(radii->view.count) + " values but there are " +
                                  std::to_string(n) + " vertices");
    }
    for (std::size_t i = 0; i < n; ++i) {
      const float* p = points.view.element(i);
      const float r = with_radius ? p[3] : radii ? *radii->view.element(i) : one_radius;
      if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
        value_error("vertices", "vertex " + std::to_string(i) + " is not finite");
      if (!(r > 0.f) || !std::isfinite(r))
        value_error(with_radius ? "vertices" : "radius",
                    "the radius of vertex " + std::to_string(i) + " must be positive and finite, got " + std::to_string(r));
      data.position_radius.insert(data.position_radius.end(), {p[0], p[1], p[2], r});
    }
    // Control points a segment reads after its first: 1 for linear, 3 for the cubics.
    const std::size_t reach = basis == sciray::CurveBasis::linear ? 1 : 3;
    if (indices.is_none()) {
      // One curve through every vertex.
      for (std::size_t s = 0; s + reach < n; ++s) data.indices.push_back(static_cast<std::uint32_t>(s));
    } else {
      const auto starts = index_rows(indices, {"indices", 1});
      for (std::size_t s = 0; s < starts.view.count; ++s) {
        const std::uint32_t first = *starts.view.element(s);
        if (first + reach >= n)
          value_error("indices", "segment " + std::to_string(s) + " starts at vertex " + std::to_string(first) +
                                     " and reads " + std::to_string(reach) + " after it, but there are " +
                                     std::to_string(n) + " vertices");
        data.indices.push_back(first);
      }
    }
    if (data.indices.empty()) value_error("vertices", "too few vertices for one segment of a " + basis_name + " curve");
    if (!colors.is_none()) {
      const auto rows = float_rows(colors, {"colors", 4, true});
      if (rows.view.count != n)
        value_error("colors", "has " + std::to_string(rows.view.count) + " rows but there are " + std::to_string(n) +
                                  " vertices");
      for (std::size_t i = 0; i < n; ++i) data.colors.insert(data.colors.end(), rows.view.element(i), rows.view.element(i) + 4);
    }
    auto curves = std::make_shared<const sciray::CurveData>(std::move(data));
    // Curves are always copied: Embree reads their vertices as x, y, z, radius.
    return {[curves](EngineWorld& world, std::uint32_t m) { world.add(sciray::Curves(curves), m); }, false};
  };
  return scene.add(std::move(entry));
}

/// A structured volume of `values` (x fastest) in its voxel type, passed to `use`.
template <class Use>
void with_structured_volume(const Voxels& voxels, const sciray::VolumeGrid& grid, Use&& use) {
  const auto owner = hold(voxels.array);
  const auto make = [&](auto voxel_tag) {
    using Voxel = decltype(voxel_tag);
    const auto* data = static_cast<const Voxel*>(voxels.array.data());
    use(std::make_shared<const sciray::StructuredRegular<Voxel>>(sciray::LinearLayout<Voxel>(data, voxels.dims, owner),
                                                                  grid));
  };
  const py::array& a = voxels.array;
  if (py::isinstance<py::array_t<std::uint8_t>>(a)) return make(std::uint8_t{});
  if (py::isinstance<py::array_t<std::int16_t>>(a)) return make(std::int16_t{});
  if (py::isinstance<py::array_t<std::uint16_t>>(a)) return make(std::uint16_t{});
  if (py::isinstance<py::array_t<float>>(a)) return make(float{});
  return make(double{});
}

sciray::VolumeGrid grid_of(py::handle spacing, py::handle origin, bool cell_centered) {
  sciray::VolumeGrid grid;
  grid.spacing = vec3_of(spacing, "spacing");
  grid.origin = vec3_of(origin, "origin");
  grid.cell_centered = cell_centered;
  if (!(grid.spacing.x > 0.f && grid.spacing.y > 0.f && grid.spacing.z > 0.f))
    value_error("spacing", "must be positive");
  return grid;
}

struct ModelOptions {
  std::optional<TransferFunction> transfer_function;
  std::optional<float> density;
  float anisotropy = 0.f;
  float gradient_shading = 0.f;
};

template <class Volume>
Adder volume_adder(std::shared_ptr<const Volume> volume, const ModelOptions& opt) {
  if (opt.density && !(*opt.density > 0.f)) value_error("density", "must be positive");
  const std::array<float, 2> range = volume->value_range();
  sciray::TransferFunction tf = opt.transfer_function ? opt.transfer_function->over(range)
                                                      : sciray_tool::default_transfer_function(range);
  sciray::VolumetricModel<Volume> model(volume, std::move(tf), opt.density.value_or(sciray_tool::default_density(*volume)),
                                        opt.anisotropy);
  model.set_gradient_shading_scale(opt.gradient_shading);
  return [model](EngineWorld& world, std::uint32_t) { world.add_volume(model); };
}

int add_volume(Scene& scene, py::object values, py::object spacing, py::object origin, bool cell_centered,
               const ModelOptions& options) {
  const sciray::VolumeGrid grid = grid_of(spacing, origin, cell_centered);
  SceneEntry entry;
  entry.kind = "volume", entry.geometry = false;
  entry.build = [=]() -> Built {
    const Voxels voxels = voxels_of(values, "values");
    Adder adder;
    naming_arguments("add_volume", {{"volumetric model: ", ""}, {"'densityScale'", "density"}}, [&] {
      with_structured_volume(voxels, grid, [&](auto volume) { adder = volume_adder(volume, options); });
    });
    return {adder, voxels.shared};
  };
  return scene.add(std::move(entry));
}

/// An unstructured volume from VTK's arrays (read_vtu's, pyvista's): points, connectivity,
/// cell types (VTK's codes: tetrahedra, voxels, hexahedra, wedges, pyramids and their
/// quadratic forms, read by their corners), offsets (where each cell ends; None for linear
/// cells only: from their sizes), and values per point or per cell. Always copied.
int add_unstructured(Scene& scene, py::object points, py::object connectivity, py::object cell_types,
                     py::object values, py::object cell_values, py::object offsets, const ModelOptions& options) {
  if (values.is_none() == cell_values.is_none()) type_error("values", "give values (per point) or cell_values, one of them");
  SceneEntry entry;
  entry.kind = "unstructured", entry.geometry = false;
  entry.build = [=]() -> Built {
    sciray::io::UnstructuredGridFile grid;
    const auto positions = float_rows(points, {"points", 3});
    for (std::size_t i = 0; i < positions.view.count; ++i) {
      const float* p = positions.view.element(i);
      grid.points.push_back({p[0], p[1], p[2]});
    }
    const auto index = index_rows(connectivity, {"connectivity", 1});
    for (std::size_t i = 0; i < index.view.count; ++i) grid.connectivity.push_back(*index.view.element(i));
    const auto types = index_rows(cell_types, {"cell_types", 1});
    for (std::size_t c = 0; c < types.view.count; ++c) {
      const std::uint32_t type = *types.view.element(c);
      if (type > 255) value_error("cell_types", "cell " + std::to_string(c) + " has type " + std::to_string(type));
      grid.types.push_back(static_cast<std::uint8_t>(type));
    }
    if (!offsets.is_none()) {
      const auto ends = index_rows(offsets, {"offsets", 1});
      if (ends.view.count != types.view.count)
        value_error("offsets", "has " + std::to_string(ends.view.count) + " entries but there are " +
                                   std::to_string(types.view.count) + " cell types");
      for (std::size_t c = 0; c < ends.view.count; ++c) grid.offsets.push_back(*ends.view.element(c));
    } else {
      std::int64_t end = 0;
      for (std::size_t c = 0; c < grid.types.size(); ++c) {
        const int type = grid.types[c];
        const int size = type == 10 ? 4 : type == 11 || type == 12 ? 8 : type == 13 ? 6 : type == 14 ? 5 : 0;
        if (size == 0)
          value_error("offsets", "needed for cell " + std::to_string(c) + " of VTK type " + std::to_string(type) +
                                     " (offsets may be left out for linear cells only: 10, 11, 12, 13, 14)");
        grid.offsets.push_back(end += size);
      }
    }
    for (std::size_t c = 0; c < grid.offsets.size(); ++c)
      if (static_cast<std::uint64_t>(grid.offsets[c]) > grid.connectivity.size() || (c && grid.offsets[c] < grid.offsets[c - 1]))
        value_error("offsets", "cell " + std::to_string(c) + " ends at " + std::to_string(grid.offsets[c]) +
                                   ", not within the " + std::to_string(grid.connectivity.size()) +
                                   " connectivity entries after the cell before");
    const bool per_point = !values.is_none();
    const auto data = float_rows(per_point ? values : cell_values, {per_point ? "values" : "cell_values", 1});
    sciray::io::VtkArray array{"values", 1, {}};
    for (std::size_t i = 0; i < data.view.count; ++i) array.values.push_back(*data.view.element(i));
    (per_point ? grid.point_arrays : grid.cell_arrays).push_back(std::move(array));
    Adder adder;
    naming_arguments("add_unstructured",
                     {{"unstructured volume: ", ""}, {"'vertex.position'", "points"}, {"'vertex.data'", "values"},
                      {"'cell.data'", "cell_values"}, {"'index'", "connectivity"}, {"'cell.type'", "cell_types"},
                      {"'cell.index'", "offsets"}},
                     [&] {
                       auto volume = std::make_shared<const sciray::Unstructured>(
                           sciray::io::unstructured_volume(grid, "values", "cell_types"));
                       adder = volume_adder(std::move(volume), options);
                     });
    return {adder, false};
  };
  return scene.add(std::move(entry));
}

int add_isosurface(Scene& scene, py::object values, py::object isovalues, py::object spacing, py::object origin,
                   bool cell_centered, py::object colors, const std::optional<Material>& material) {
  const sciray::VolumeGrid grid = grid_of(spacing, origin, cell_centered);
  SceneEntry entry;
  entry.kind = "isosurface";
  entry.material = material_of(material);
  entry.build = [=]() -> Built {
    const Voxels voxels = voxels_of(values, "values");
    const auto levels = float_rows(py::module_::import("numpy").attr("atleast_1d")(isovalues), {"isovalues", 1});
    std::vector<float> levels_vector;
    for (std::size_t i = 0; i < levels.view.count; ++i) levels_vector.push_back(*levels.view.element(i));
    std::vector<float> rgba;
    if (!colors.is_none()) {
      const auto rows = float_rows(py::module_::import("numpy").attr("atleast_2d")(colors), {"colors", 4, true});
      for (std::size_t i = 0; i < rows.view.count; ++i)
        rgba.insert(rgba.end(), rows.view.element(i), rows.view.element(i) + 4);
    }
    std::shared_ptr<const sciray::Isosurface> surface;
    naming_arguments("add_isosurface", {{"isosurface: ", ""}, {"'isovalue'", "isovalues"}}, [&] {
      with_structured_volume(voxels, grid, [&](auto volume) {
        auto s = std::make_shared<sciray::Isosurface>(volume, levels_vector);
        s->set_colors(rgba);
        surface = std::move(s);
      });
    });
    return {[surface](EngineWorld& world, std::uint32_t m) { world.add(sciray::Isosurface(*surface), m); }, voxels.shared};
  };
  return scene.add(std::move(entry));
}

}  // namespace

sciray::TransferFunction TransferFunction::over(std::array<float, 2> data_range) const {
  return naming_arguments("TransferFunction", {}, [&] {
    return sciray::TransferFunction(colors, opacities, value_range.value_or(data_range));
  });
}

Scene::Scene(const std::string& isa)
    : kernels_(&sciray::shim::kernels(sciray::shim::select_isa(isa))),
      device_(std::make_unique<sciray::accel::Device>()),
      world_(std::make_unique<EngineWorld>(*device_)) {}

Scene::~Scene() {
  // The world's geometry refers to arrays the entries hold: it goes first.
  world_.reset();
}

int Scene::add(SceneEntry entry) {
  entry.built = entry.build();
  entry.index = entry.geometry ? geometries_++ : volumes_++;
  entries_.push_back(std::move(entry));
  dirty_ = true;
  return entries_.back().index;
}

void Scene::commit() {
  std::vector<Built> builts;
  for (SceneEntry& entry : entries_) builts.push_back(entry.build());
  install(std::move(builts));
}

void Scene::commit_if_changed() {
  if (!dirty_) return;
  std::vector<Built> builts;
  for (const SceneEntry& entry : entries_) builts.push_back(entry.built);
  install(std::move(builts));
}

void Scene::install(std::vector<Built> builts) {
  // Taken with the GIL: other Python threads may add to the scene while the world builds.
  const std::size_t count = builts.size();
  std::vector<std::optional<sciray::Material>> wanted;
  for (std::size_t i = 0; i < count; ++i) wanted.push_back(entries_[i].material);
  auto world = std::make_unique<EngineWorld>(*device_);
  std::vector<sciray::Material> materials;
  {
    // Built beside the world frames are reading, which only the swap below waits for.
    py::gil_scoped_release release;
    for (std::size_t i = 0; i < count; ++i) {
      std::uint32_t material = sciray::no_material;
      if (wanted[i]) material = static_cast<std::uint32_t>(materials.size()), materials.push_back(*wanted[i]);
      builts[i].add(*world, material);
    }
    kernels_->commit(*world);
    std::unique_lock lock(frames_lock_);
    std::swap(world_, world);
    std::swap(materials_, materials);
  }
  for (std::size_t i = 0; i < count; ++i) std::swap(entries_[i].built, builts[i]);
  dirty_ = entries_.size() != count;  // added to meanwhile: the next frame commits again
  // The old world goes first, then the old engine objects (and the arrays they kept), with the GIL.
  world.reset();
}

sciray::Box3f Scene::bounds() {
  commit_if_changed();
  return with_world([](const EngineWorld& world, const auto&) { return world.bounds(); });
}

Material make_material(const std::string& type, const py::kwargs& params) {
  nlohmann::json j = json_of(params);
  j["type"] = type;
  return {type, sciray_tool::material_from_json(j, "Material('" + type + "')"), j};
}

void bind_scene(py::module_& m) {
  py::class_<Material>(m, "Material", "An OSPRay material: Material('principled', baseColor=(1, 0.8, 0.3), roughness=0.2)")
      .def(py::init(&make_material), py::arg("type"))
      .def_readonly("type", &Material::type)
      .def("__repr__", [](const Material& self) { return "sciray.Material(" + self.json.dump() + ")"; });
  py::class_<Light>(m, "Light", "An OSPRay light: Light('distant', direction=(0, -1, 0), intensity=3)")
      .def(py::init([](const std::string& type, const py::kwargs& params) {
             nlohmann::json j = json_of(params);
             j["type"] = type;
             return Light{type, sciray_tool::light_from_json(j, "Light('" + type + "')"), j};
           }),
           py::arg("type"))
      .def_readonly("type", &Light::type)
      .def("__repr__", [](const Light& self) { return "sciray.Light(" + self.json.dump() + ")"; });
  py::class_<TransferFunction>(m, "TransferFunction",
                               "Colours (rows of RGB) and opacities, each spread evenly over value_range (default: the "
                               "volume's range of values)")
      .def(py::init([](py::object colors, py::object opacities, py::object value_range) {
             TransferFunction tf;
             const auto c = float_rows(colors, {"colors", 3});
             for (std::size_t i = 0; i < c.view.count; ++i) tf.colors.push_back({c.view.element(i)[0], c.view.element(i)[1], c.view.element(i)[2]});
             const auto o = float_rows(opacities, {"opacities", 1});
             for (std::size_t i = 0; i < o.view.count; ++i) tf.opacities.push_back(*o.view.element(i));
             if (!value_range.is_none()) tf.value_range = value_range_of(value_range, {}, "value_range");
             tf.over({0.f, 1.f});  // names what is wrong now
             return tf;
           }),
           py::arg("colors"), py::arg("opacities"), py::arg("value_range") = py::none());

  py::class_<Scene, std::shared_ptr<Scene>>(m, "Scene", "Geometry and volumes from numpy arrays, with lights")
      .def(py::init<const std::string&>(), py::arg("isa") = "auto")
      .def("add_mesh", &add_mesh, py::arg("vertices"), py::arg("indices") = py::none(), py::kw_only(),
           py::arg("normals") = py::none(), py::arg("colors") = py::none(), py::arg("face_colors") = py::none(),
           py::arg("texcoords") = py::none(), py::arg("scalars") = py::none(), py::arg("scalar_range") = py::none(),
           py::arg("colormap") = py::none(), py::arg("material") = py::none())
      .def("add_spheres", &add_spheres, py::arg("centers"), py::arg("radius") = 0.01f, py::kw_only(),
           py::arg("colors") = py::none(), py::arg("scalars") = py::none(), py::arg("scalar_range") = py::none(),
           py::arg("colormap") = py::none(), py::arg("texcoords") = py::none(), py::arg("material") = py::none())
      .def("add_curves", &add_curves, py::arg("vertices"), py::arg("radius") = 0.01f, py::kw_only(),
           py::arg("indices") = py::none(), py::arg("colors") = py::none(), py::arg("basis") = "linear",
           py::arg("type") = "round", py::arg("material") = py::none())
      .def(
          "add_volume",
          [](Scene& scene, py::object values, py::object spacing, py::object origin, bool cell_centered,
             std::optional<TransferFunction> tf, std::optional<float> density, float anisotropy, float gradient_shading) {
            return add_volume(scene, values, spacing, origin, cell_centered, {tf, density, anisotropy, gradient_shading});
          },
          py::arg("values"), py::kw_only(), py::arg("spacing") = py::make_tuple(1, 1, 1),
          py::arg("origin") = py::make_tuple(0, 0, 0), py::arg("cell_centered") = false,
          py::arg("transfer_function") = py::none(), py::arg("density") = py::none(), py::arg("anisotropy") = 0.f,
          py::arg("gradient_shading") = 0.f)
      .def(
          "add_unstructured",
          [](Scene& scene, py::object points, py::object connectivity, py::object cell_types, py::object values,
             py::object cell_values, py::object offsets, std::optional<TransferFunction> tf, std::optional<float> density,
             float anisotropy, float gradient_shading) {
            return add_unstructured(scene, points, connectivity, cell_types, values, cell_values, offsets,
                                    {tf, density, anisotropy, gradient_shading});
          },
          py::arg("points"), py::arg("connectivity"), py::arg("cell_types"), py::kw_only(),
          py::arg("values") = py::none(), py::arg("cell_values") = py::none(), py::arg("offsets") = py::none(),
          py::arg("transfer_function") = py::none(), py::arg("density") = py::none(), py::arg("anisotropy") = 0.f,
          py::arg("gradient_shading") = 0.f)
      .def("add_isosurface", &add_isosurface, py::arg("values"), py::arg("isovalues"), py::kw_only(),
           py::arg("spacing") = py::make_tuple(1, 1, 1), py::arg("origin") = py::make_tuple(0, 0, 0),
           py::arg("cell_centered") = false, py::arg("colors") = py::none(), py::arg("material") = py::none())
      .def("add_light", &Scene::add_light, py::arg("light"))
      .def("commit", &Scene::commit)
      .def_property_readonly("bounds",
                             [](Scene& scene) {
                               const sciray::Box3f b = scene.bounds();
                               return py::make_tuple(py::make_tuple(b.lower.x, b.lower.y, b.lower.z),
                                                     py::make_tuple(b.upper.x, b.upper.y, b.upper.z));
                             })
      .def_property_readonly("isa", [](const Scene& scene) { return std::string(sciray::simd::isa_name(scene.kernels().isa)); })
      .def_property_readonly("geometry_count", &Scene::geometry_count)
      .def_property_readonly("volume_count", &Scene::volume_count)
      .def_property_readonly(
          "contents",
          [](const Scene& scene) {
            py::list out;
            for (const SceneEntry& e : scene.entries())
              out.append(py::dict(py::arg("kind") = e.kind, py::arg("index") = e.index,
                                  py::arg("shared") = e.built.shared));
            return out;
          },
          "What was added, in order: kind, index (as add_* returned it) and whether the engine reads the caller's "
          "arrays in place (shared) or copies of them");
}

}  // namespace sciray_python
