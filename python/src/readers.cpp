// The file readers, returning numpy arrays (and Material objects) that the Scene's add_*
// take: meshes, OBJ scenes, point clouds, molecules, volumes and VTK files.
#include <pybind11/stl.h>

#include "arrays.hpp"
#include "scene.hpp"
#include "sciray/io/obj.hpp"
#include "sciray/io/pdb.hpp"
#include "sciray/io/ply.hpp"
#include "sciray/io/points.hpp"
#include "sciray/io/volume.hpp"
#include "sciray/io/vtk.hpp"
#include "sciray/io/vtk_image.hpp"
#include "sciray/io/vtk_polydata.hpp"
#include "sciray/testing/scenes.hpp"

namespace sciray_python {

namespace {

using sciray::PaddedVector;

template <class T>
py::ssize_t rows(const std::vector<T, sciray::PaddedAllocator<T>>& values, int columns) {
  return static_cast<py::ssize_t>(values.size()) / columns;
}

py::dict mesh_dict(const sciray::MeshData& mesh) {
  py::dict d;
  const int corners = static_cast<int>(mesh.vertices_per_face);
  d["vertices"] = array_of<float>(mesh.positions, {rows(mesh.positions, 3), 3});
  d["indices"] = array_of<std::uint32_t>(mesh.indices, {rows(mesh.indices, corners), corners});
  if (!mesh.normals.empty()) d["normals"] = array_of<float>(mesh.normals, {rows(mesh.normals, 3), 3});
  if (!mesh.vertex_colors.empty()) d["colors"] = array_of<float>(mesh.vertex_colors, {rows(mesh.vertex_colors, 4), 4});
  if (!mesh.face_colors.empty()) d["face_colors"] = array_of<float>(mesh.face_colors, {rows(mesh.face_colors, 4), 4});
  if (!mesh.texcoords.empty()) d["texcoords"] = array_of<float>(mesh.texcoords, {rows(mesh.texcoords, 2), 2});
  return d;
}

/// VTK data arrays by name: (tuples,) for one component, (tuples, components) otherwise.
py::dict vtk_arrays(const std::vector<sciray::io::VtkArray>& arrays) {
  py::dict d;
  for (const auto& a : arrays) {
    const auto tuples = static_cast<py::ssize_t>(a.tuples());
    d[py::str(a.name)] = a.components == 1 ? array_of<double>(a.values, {tuples})
                                           : array_of<double>(a.values, {tuples, a.components});
  }
  return d;
}

/// A volume file's voxels as a (z, y, x) array sharing the reader's memory.
py::dict volume_dict(const sciray::io::VolumeFile& file) {
  auto* owner = new std::shared_ptr<std::vector<std::byte>>(file.voxels);
  const py::capsule free_owner(owner, [](void* p) { delete static_cast<std::shared_ptr<std::vector<std::byte>>*>(p); });
  const auto [nx, ny, nz] = file.dims;
  py::dtype dtype = py::dtype::of<std::uint8_t>();
  switch (file.kind) {
    case sciray::io::VoxelKind::uint8: break;
    case sciray::io::VoxelKind::int16: dtype = py::dtype::of<std::int16_t>(); break;
    case sciray::io::VoxelKind::uint16: dtype = py::dtype::of<std::uint16_t>(); break;
    case sciray::io::VoxelKind::float32: dtype = py::dtype::of<float>(); break;
    case sciray::io::VoxelKind::float64: dtype = py::dtype::of<double>(); break;
  }
  py::dict d;
  d["values"] = py::array(dtype, {nz, ny, nx}, {}, file.voxels->data(), free_owner);
  d["spacing"] = py::make_tuple(file.grid.spacing.x, file.grid.spacing.y, file.grid.spacing.z);
  d["origin"] = py::make_tuple(file.grid.origin.x, file.grid.origin.y, file.grid.origin.z);
  d["cell_centered"] = file.grid.cell_centered;
  if (file.range) d["value_range"] = py::make_tuple((*file.range)[0], (*file.range)[1]);
  return d;
}

template <class F>
auto reading(F&& read) {
  py::gil_scoped_release release;  // other Python threads run while a large file is read
  return read();
}

}  // namespace

void bind_readers(py::module_& m) {
  m.def(
      "wavy_torus", [](std::size_t triangles) { return mesh_dict(sciray::testing::wavy_torus(triangles)); },
      py::arg("triangles") = 400'000, "The sciray tool's default scene: a wavy torus mesh with normals and colours");
  m.def(
      "read_ply",
      [](const std::string& path) { return mesh_dict(reading([&] { return sciray::io::read_ply(path); })); },
      py::arg("path"), "A PLY mesh: vertices, indices and, where the file has them, normals, colors, texcoords");
  m.def(
      "read_obj",
      [](const std::string& path) {
        const sciray::io::ObjScene scene = reading([&] { return sciray::io::read_obj(path); });
        py::list materials, meshes;
        for (std::size_t i = 0; i < scene.materials.size(); ++i) {
          const char* type = sciray::type_name(scene.materials[i]);
          materials.append(Material{type, scene.materials[i], {{"type", type}, {"name", scene.material_names[i]}}});
        }
        for (const auto& part : scene.meshes) {
          py::dict d = mesh_dict(part.mesh);
          d["name"] = part.name;
          d["material"] = part.material == sciray::no_material ? py::object(py::none()) : materials[part.material];
          meshes.append(d);
        }
        return py::dict(py::arg("meshes") = meshes, py::arg("materials") = materials,
                        py::arg("warnings") = scene.warnings);
      },
      py::arg("path"),
      "A Wavefront OBJ scene: meshes (each a dict for Scene.add_mesh, with its name and Material) and the .mtl's "
      "materials");
  m.def(
      "read_points",
      [](const std::string& path, const std::string& radius_property) {
        sciray::io::PointOptions options;
        options.radius_property = radius_property;
        const sciray::io::PointCloud cloud = reading([&] { return sciray::io::read_points(path, options); });
        const auto n = static_cast<py::ssize_t>(cloud.count());
        py::dict d, scalars;
        d["centers"] = array_of<float>(cloud.positions, {n, 3});
        if (!cloud.radii.empty()) d["radius"] = array_of<float>(cloud.radii, {n});
        for (const auto& s : cloud.scalars) scalars[py::str(s.name)] = array_of<float>(s.values, {n});
        d["scalars"] = scalars;
        if (cloud.find("red")) d["colors"] = array_of<float>(sciray::io::file_colors(cloud), {n, 4});
        return d;
      },
      py::arg("path"), py::arg("radius_property") = "radius",
      "Points (a PLY of vertices only, .xyz, .xyzr, .f32xyzr): centers, radius (if the file has radii), colors "
      "(if it has red, green, blue) and every other property in scalars");
  m.def(
      "read_pdb",
      [](const std::string& path) {
        const sciray::io::Molecule molecule = reading([&] { return sciray::io::read_pdb(path); });
        const auto n = static_cast<py::ssize_t>(molecule.atoms.size());
        std::vector<float> centers, radii, colors;
        std::vector<std::uint8_t> elements;
        for (const auto& a : molecule.atoms) {
          centers.insert(centers.end(), {a.position.x, a.position.y, a.position.z});
          radii.push_back(a.radius);
          colors.insert(colors.end(), {a.color.x, a.color.y, a.color.z, 1.f});
          elements.push_back(a.element);
        }
        std::vector<std::uint32_t> bonds;
        for (const auto& b : molecule.bonds) bonds.insert(bonds.end(), {b[0], b[1]});
        return py::dict(py::arg("centers") = array_of<float>(centers, {n, 3}),
                        py::arg("radius") = array_of<float>(radii, {n}),
                        py::arg("colors") = array_of<float>(colors, {n, 4}),
                        py::arg("elements") = array_of<std::uint8_t>(elements, {n}),
                        py::arg("bonds") = array_of<std::uint32_t>(bonds, {static_cast<py::ssize_t>(molecule.bonds.size()), 2}));
      },
      py::arg("path"), "A PDB molecule: atom centers (Å), van der Waals radius, CPK colors, atomic numbers, bonds");
  m.def(
      "read_volume", [](const std::string& path) { return volume_dict(reading([&] { return sciray::io::read_volume(path); })); },
      py::arg("path"),
      "A raw (with its JSON sidecar or a name_XxYxZ_type.raw name) or NRRD volume: values as a (z, y, x) array of "
      "its voxel type, spacing, origin");
  m.def(
      "read_vti",
      [](const std::string& path, const std::string& field) {
        return volume_dict(reading([&] { return sciray::io::read_vti(path, field); }));
      },
      py::arg("path"), py::arg("field") = "", "A VTK image (.vti): one point or cell array as read_volume's values");
  m.def(
      "read_vtp",
      [](const std::string& path) {
        const sciray::io::PolyDataFile poly = reading([&] { return sciray::io::read_vtp(path); });
        py::dict d = mesh_dict(poly.mesh);
        d["point_data"] = vtk_arrays(poly.point_arrays);
        d["cell_data"] = vtk_arrays(poly.cell_arrays);
        d["triangle_cells"] = array_of<std::uint32_t>(poly.triangle_cells, {static_cast<py::ssize_t>(poly.triangle_cells.size())});
        return d;
      },
      py::arg("path"),
      "VTK poly data (.vtp): vertices, the polygons' and strips' triangles as indices (empty for a point cloud), "
      "point_data and cell_data arrays by name, and the cell of each triangle");
  m.def(
      "read_vtu",
      [](const std::string& path) {
        const sciray::io::UnstructuredGridFile grid = reading([&] { return sciray::io::read_vtu(path); });
        std::vector<float> points;
        for (const auto& p : grid.points) points.insert(points.end(), {p.x, p.y, p.z});
        const auto size = [](const auto& v) { return static_cast<py::ssize_t>(v.size()); };
        return py::dict(py::arg("points") = array_of<float>(points, {size(grid.points), 3}),
                        py::arg("connectivity") = array_of<std::int64_t>(grid.connectivity, {size(grid.connectivity)}),
                        py::arg("offsets") = array_of<std::int64_t>(grid.offsets, {size(grid.offsets)}),
                        py::arg("cell_types") = array_of<std::uint8_t>(grid.types, {size(grid.types)}),
                        py::arg("point_data") = vtk_arrays(grid.point_arrays),
                        py::arg("cell_data") = vtk_arrays(grid.cell_arrays));
      },
      py::arg("path"),
      "A VTK unstructured grid (.vtu): points, connectivity, offsets (where each cell ends), cell_types (VTK's "
      "codes), point_data and cell_data arrays by name");
}

}  // namespace sciray_python
