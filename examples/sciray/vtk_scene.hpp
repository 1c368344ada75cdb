#pragma once
// What the tool makes of a VTK file: image data (.vti, legacy structured points) is a
// structured volume, poly data (.vtp, legacy polydata) a mesh — or, with no polygons, a
// point cloud of spheres — coloured by an array through the colour map, and an
// unstructured grid (.vtu, legacy) an unstructured volume (volume_scene.hpp).
#include <cmath>
#include <utility>
#include <filesystem>
#include <optional>
#include <string>
#include <variant>

#include "sciray/error.hpp"
#include "sciray/io/points.hpp"
#include "sciray/io/vtk.hpp"
#include "sciray/io/vtk_image.hpp"
#include "sciray/io/vtk_legacy.hpp"
#include "sciray/io/vtk_polydata.hpp"
#include "sciray/testing/scenes.hpp"

namespace sciray_tool {

inline bool is_vtk_file(const std::string& path) {
  const auto ext = std::filesystem::path(path).extension();
  return ext == ".vtu" || ext == ".vti" || ext == ".vtp" || ext == ".vtk";
}

struct VtkOptions {
  std::string field;     ///< image data: the array to render (empty: its Scalars)
  std::string color_by;  ///< poly data: the point or cell array that colours it (empty: none)
  float radius = 0.f;    ///< point clouds: the spheres' radius (0: from the points' spacing)
  std::string radius_by;  ///< point clouds: scale each radius by this point array (see io::PointOptions)
  float radius_exponent = 1.f;
  bool sizes_spheres() const { return radius != 0.f || !radius_by.empty(); }
};

/// Poly data into `scene`: its triangles, or its points as spheres.
inline void add_poly_data(sciray::io::PolyDataFile poly, const VtkOptions& opt, sciray::testing::StandardScene& scene) {
  if (!opt.color_by.empty()) sciray::io::color_by(poly, opt.color_by, sciray::testing::colormap);
  if (!poly.points_only()) {
    if (!opt.radius_by.empty())
      throw sciray::Error("--radius-by: sizes the spheres of point clouds; " + poly.source + " has polygons");
    scene.mesh = std::move(poly.mesh);
    return;
  }
  if (!(opt.radius >= 0.f) || !std::isfinite(opt.radius)) throw sciray::Error("--radius must be finite and positive");
  sciray::io::PointCloud cloud;
  cloud.source = poly.source;
  cloud.positions = std::move(poly.mesh.positions);
  sciray::SphereData spheres;
  spheres.radius = opt.radius > 0.f ? opt.radius : sciray::io::default_radius(cloud);
  if (!opt.radius_by.empty()) {
    const sciray::io::VtkArray* by = nullptr;
    for (const auto& a : poly.point_arrays)
      if (a.name == opt.radius_by) by = &a;
    if (!by || by->components != 1)
      throw sciray::Error(poly.source + ": --radius-by: no point array '" + opt.radius_by + "' of one component");
    spheres.radii = sciray::io::scaled_radii([&](std::size_t i) { return by->values[i]; }, cloud.count(),
                                             spheres.radius, opt.radius_exponent, opt.radius_by, poly.source);
  }
  spheres.positions = std::move(cloud.positions);
  spheres.colors = std::move(poly.mesh.vertex_colors);
  scene.spheres = std::move(spheres);
}

/// Reads the VTK file `path` into `scene` (a volume, a mesh or spheres), or returns its
/// unstructured grid for the caller to add as a volume.
inline std::optional<sciray::io::UnstructuredGridFile> load_vtk(const std::string& path, const VtkOptions& opt,
                                                                sciray::testing::StandardScene& scene) {
  const auto ext = std::filesystem::path(path).extension();
  const bool poly_data = ext == ".vtp";
  if (!opt.color_by.empty() && ext != ".vtp" && ext != ".vtk")
    throw sciray::Error("--color-by: colours poly data (.vtp, legacy .vtk) by one of its arrays");
  if (opt.sizes_spheres() && ext != ".vtp" && ext != ".vtk")
    throw sciray::Error("--radius and --radius-by: size the spheres of point clouds (.vtp, legacy .vtk poly data)");
  if (!opt.field.empty() && poly_data) throw sciray::Error("--field: picks a volume's array; colour poly data with --color-by");
  if (ext == ".vtu") return sciray::io::read_vtu(path);
  if (ext == ".vti") {
    scene.volume = sciray::io::read_vti(path, opt.field);
  } else if (poly_data) {
    add_poly_data(sciray::io::read_vtp(path), opt, scene);
  } else {
    auto file = sciray::io::read_legacy_vtk(path, opt.field);
    if (auto* grid = std::get_if<sciray::io::UnstructuredGridFile>(&file)) {
      if (!opt.color_by.empty() || opt.sizes_spheres())
        throw sciray::Error("--color-by, --radius and --radius-by: apply to poly data; " + path + " holds an unstructured grid");
      return std::move(*grid);
    }
    if (auto* poly = std::get_if<sciray::io::PolyDataFile>(&file)) {
      if (!opt.field.empty()) throw sciray::Error("--field: picks a volume's array; colour poly data with --color-by");
      add_poly_data(std::move(*poly), opt, scene);
    } else {
      if (!opt.color_by.empty() || opt.sizes_spheres())
        throw sciray::Error("--color-by, --radius and --radius-by: apply to poly data; " + path + " holds image data");
      scene.volume = std::move(std::get<sciray::io::VolumeFile>(file));
    }
  }
  return std::nullopt;
}

}  // namespace sciray_tool
