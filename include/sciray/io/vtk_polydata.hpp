#pragma once
// VTK poly data, XML `.vtp` (PolyData), read into a triangle mesh and its data arrays:
// polygons are fan-triangulated and triangle strips cut into triangles (alternate ones
// turned so all face the same way); vertices and lines are not surfaces and are counted,
// not drawn. Every point is kept, so poly data without polygons (a point cloud of Verts)
// is its points and their arrays, for the caller to draw as spheres. The point and cell
// arrays are kept by name; color_by() colours the mesh by one of them through a colour map.
// Every encoding io/vtk.hpp reads is read here through its helpers; the pieces of a file
// are joined into one mesh.
//
// The builder here (vtk_detail::add_poly_piece) also makes the mesh of a legacy POLYDATA
// file (io/vtk_legacy.hpp).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <pugixml.hpp>
#include <string>
#include <vector>

#include "sciray/error.hpp"
#include "sciray/geometry/mesh_data.hpp"
#include "sciray/io/vtk.hpp"
#include "sciray/io/vtk_image.hpp"  // choose_array, array_names
#include "sciray/math/vec.hpp"

namespace sciray::io {

struct PolyDataFile {
  std::string source;  ///< the file it was read from, for messages
  /// Every point (x,y,z), and the triangles of the polygons and strips; no triangles: the
  /// points are a point cloud. `normals` and `texcoords` come from the point data's Normals
  /// and TCoords attributes when it has them.
  MeshData mesh;
  std::vector<VtkArray> point_arrays, cell_arrays;      ///< cell arrays: Verts, Lines, Polys, Strips in order
  std::string default_point_array, default_cell_array;  ///< the Scalars attribute of PointData / CellData
  std::vector<std::uint32_t> triangle_cells;            ///< the cell (index into cell arrays) of each triangle
  std::size_t skipped_vertices_and_lines = 0;           ///< Verts and Lines cells, which make no triangles

  bool points_only() const { return mesh.indices.empty(); }
};

namespace vtk_detail {

/// Cells as VTK lists them: their points one cell after another, and where each cell ends.
struct PolyCells {
  std::vector<std::int64_t> connectivity, offsets;
};

/// Appends a piece of `xyz` points and its Verts, Lines, Polys and Strips (in that order,
/// VTK's order of cells) to `out`: positions, triangles and the cell of each.
/// `names` name the points and the four lists in messages.
inline void add_poly_piece(PolyDataFile& out, const std::vector<double>& xyz, const std::array<PolyCells, 4>& cells,
                           std::size_t first_cell, const Context& c,
                           const std::array<const char*, 5>& names = {"Points", "Verts", "Lines", "Polys", "Strips"}) {
  const std::size_t base = out.mesh.vertex_count(), points = xyz.size() / 3;
  if (base + points > std::numeric_limits<std::uint32_t>::max())
    c.fail("has more than 2^32 points, more than a mesh's 32-bit indices address");
  check_finite_points(xyz, names[0], base, c);
  for (const double v : xyz) out.mesh.positions.push_back(static_cast<float>(v));
  std::size_t cell = first_cell;
  for (int kind = 0; kind < 4; ++kind) {
    const PolyCells& list = cells[static_cast<std::size_t>(kind)];
    if (kind < 2) out.skipped_vertices_and_lines += list.offsets.size();
    std::int64_t begin = 0;
    for (std::size_t i = 0; i < list.offsets.size(); ++i, ++cell) {
      const std::int64_t end = list.offsets[i];
      const auto where = [&] {
        return std::string(names[static_cast<std::size_t>(kind) + 1]) + " cell " + std::to_string(i);
      };
      if (end < begin || end > static_cast<std::int64_t>(list.connectivity.size()))
        c.fail(where() + ": offset " + std::to_string(end) + " is outside [" + std::to_string(begin) + ", " +
               std::to_string(list.connectivity.size()) + "]");
      const auto at = [&](std::int64_t k) {
        const std::int64_t p = list.connectivity[static_cast<std::size_t>(k)];
        if (p < 0 || p >= static_cast<std::int64_t>(points))
          c.fail(where() + " refers to point " + std::to_string(p) + ", but there are " + std::to_string(points) +
                 " points");
        return static_cast<std::uint32_t>(base + static_cast<std::size_t>(p));
      };
      if (cell > std::numeric_limits<std::uint32_t>::max()) c.fail("has more than 2^32 cells");
      const auto triangle = [&](std::uint32_t a, std::uint32_t b, std::uint32_t d) {
        out.mesh.indices.insert(out.mesh.indices.end(), {a, b, d});
        out.triangle_cells.push_back(static_cast<std::uint32_t>(cell));
      };
      if (kind == 2) {  // a polygon: a fan from its first point
        for (std::int64_t k = begin + 1; k + 1 < end; ++k) triangle(at(begin), at(k), at(k + 1));
      } else if (kind == 3) {  // a strip: every other triangle turned to face as the first
        for (std::int64_t k = begin; k + 2 < end; ++k)
          (k - begin) % 2 == 0 ? triangle(at(k), at(k + 1), at(k + 2)) : triangle(at(k + 1), at(k), at(k + 2));
      } else {
        for (std::int64_t k = begin; k < end; ++k) at(k);  // checked, not drawn
      }
      begin = end;
    }
  }
}

/// The point data's Normals and TCoords attribute arrays as the mesh's normals and texture
/// coordinates (the first two components of TCoords).
inline void attach_normals_and_texcoords(PolyDataFile& out, const std::string& normals, const std::string& tcoords) {
  for (const VtkArray& a : out.point_arrays) {
    if (!normals.empty() && a.name == normals && a.components == 3 && a.tuples() == out.mesh.vertex_count()) {
      out.mesh.normals.assign(a.values.begin(), a.values.end());
    } else if (!tcoords.empty() && a.name == tcoords && a.components >= 2 && a.tuples() == out.mesh.vertex_count()) {
      out.mesh.texcoords.clear();
      for (std::size_t t = 0; t < a.tuples(); ++t)
        for (std::size_t k = 0; k < 2; ++k)
          out.mesh.texcoords.push_back(static_cast<float>(a.values[t * static_cast<std::size_t>(a.components) + k]));
    }
  }
}

}  // namespace vtk_detail

/// Reads a .vtp file: every piece, joined.
inline PolyDataFile read_vtp(const std::string& path) {
  using namespace vtk_detail;
  const XmlFile file(path, "PolyData");
  const Context& c = file.c;
  const pugi::xml_node poly = file.root.child("PolyData");
  if (!poly.child("Piece")) c.fail("no PolyData Piece");
  PolyDataFile out;
  out.source = path;
  std::size_t total_cells = 0;
  int index = 0;
  for (const pugi::xml_node piece : poly.children("Piece")) {
    const std::string where = "Piece " + std::to_string(index);
    const std::size_t points = piece.attribute("NumberOfPoints").as_ullong();
    static constexpr const char* names[4] = {"Verts", "Lines", "Polys", "Strips"};
    std::array<PolyCells, 4> cells;
    std::size_t piece_cells = 0;
    for (std::size_t kind = 0; kind < 4; ++kind) {
      const std::size_t count = piece.attribute((std::string("NumberOf") + names[kind]).c_str()).as_ullong();
      piece_cells += count;
      if (count == 0) continue;
      for (const pugi::xml_node a : piece.child(names[kind]).children("DataArray")) {
        const std::string name = a.attribute("Name").as_string();
        if (name != "connectivity" && name != "offsets") continue;
        const VtkArray v = read_values(a, c, name == "offsets" ? count : 0);
        auto& target = name == "offsets" ? cells[kind].offsets : cells[kind].connectivity;
        for (double x : v.values) target.push_back(whole_number(x));
      }
      if (cells[kind].offsets.size() != count)
        c.fail(where + " " + names[kind] + " needs an 'offsets' array of NumberOf" + names[kind] + " = " +
               std::to_string(count) + " entries");
    }
    std::vector<double> xyz;
    if (points > 0) {
      const pugi::xml_node p = piece.child("Points").child("DataArray");
      if (!p) c.fail(where + " has " + std::to_string(points) + " points but no Points array");
      VtkArray a = read_values(p, c, points);
      if (a.components != 3) c.fail("Points must have 3 components, got " + std::to_string(a.components));
      xyz = std::move(a.values);
    }
    add_poly_piece(out, xyz, cells, total_cells, c);
    total_cells += piece_cells;
    // Arrays: the first piece names them; later pieces add their tuples to the same names.
    for (const bool point : {true, false}) {
      const pugi::xml_node data = piece.child(point ? "PointData" : "CellData");
      std::vector<VtkArray>& arrays = point ? out.point_arrays : out.cell_arrays;
      if (index == 0) {
        (point ? out.default_point_array : out.default_cell_array) = data.attribute("Scalars").as_string();
        for (const pugi::xml_node a : data.children("DataArray"))
          arrays.push_back(read_values(a, c, point ? points : piece_cells));
        continue;
      }
      for (VtkArray& array : arrays) {
        pugi::xml_node node;
        for (const pugi::xml_node a : data.children("DataArray"))
          if (array.name == a.attribute("Name").as_string()) node = a;
        if (!node)
          c.fail(where + " has no " + (point ? "PointData" : "CellData") + " array '" + array.name +
                 "', which Piece 0 has");
        const VtkArray more = read_values(node, c, point ? points : piece_cells);
        if (more.components != array.components)
          c.fail(where + ": array '" + array.name + "' has another number of components than in Piece 0");
        array.values.insert(array.values.end(), more.values.begin(), more.values.end());
      }
    }
    ++index;
  }
  const pugi::xml_node point_data = poly.child("Piece").child("PointData");
  attach_normals_and_texcoords(out, point_data.attribute("Normals").as_string(),
                               point_data.attribute("TCoords").as_string());
  return out;
}

struct ColorByOptions {
  int component = -1;                          ///< which component; -1: the magnitude of a vector
  std::optional<std::array<double, 2>> range;  ///< the values mapped to 0 and 1; default: the array's own
};

/// Colours the mesh by array `name` through `colormap` (from [0,1] to linear RGB): a point
/// array sets mesh.vertex_colors, a cell array mesh.face_colors (each triangle its cell's
/// colour), and the other is cleared. Empty `name`: the point data's Scalars, else the first
/// point array, else the cell data's Scalars, else the first cell array. The range maps
/// linearly to [0,1], clamped; NaN values take VTK's NaN colour (0.5, 0, 0). Returns the
/// range used (by default the finite values' own).
inline std::array<double, 2> color_by(PolyDataFile& file, const std::string& name,
                                      const std::function<Vec3f(float)>& colormap, const ColorByOptions& options = {}) {
  vtk_detail::Context c;
  c.file = file.source;
  std::vector<std::string> point_names, cell_names;
  for (const VtkArray& a : file.point_arrays) point_names.push_back(a.name);
  for (const VtkArray& a : file.cell_arrays) cell_names.push_back(a.name);
  const vtk_detail::ArrayChoice choice =
      vtk_detail::choose_array(point_names, cell_names, file.default_point_array, file.default_cell_array, name, c);
  const VtkArray& a = choice.cell ? file.cell_arrays[choice.index] : file.point_arrays[choice.index];
  if (options.component >= a.components)
    c.fail("array '" + a.name + "' has " + std::to_string(a.components) + " components, so no component " +
           std::to_string(options.component));
  if (choice.cell && file.points_only())
    c.fail("cell array '" + a.name + "' colours faces, and the file has no polygons or strips");
  std::size_t needed = file.mesh.vertex_count();  // tuples the colours read
  if (choice.cell) {
    needed = 0;
    for (const std::uint32_t cell : file.triangle_cells) needed = std::max<std::size_t>(needed, cell + std::size_t{1});
  }
  if (a.tuples() < needed)
    c.fail("array '" + a.name + "' has " + std::to_string(a.tuples()) + " tuples, " + std::to_string(needed) +
           " needed");
  const auto n = static_cast<std::size_t>(a.components);
  std::vector<double> value(a.tuples());
  for (std::size_t t = 0; t < value.size(); ++t) {
    if (options.component >= 0 || n == 1) {
      value[t] = a.values[t * n + static_cast<std::size_t>(std::max(options.component, 0))];
      continue;
    }
    double sum = 0;
    for (std::size_t k = 0; k < n; ++k) sum += a.values[t * n + k] * a.values[t * n + k];
    value[t] = std::sqrt(sum);
  }
  std::array<double, 2> range{std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
  if (options.range) {
    range = *options.range;
  } else {
    for (double v : value)
      if (std::isfinite(v)) range[0] = std::min(range[0], v), range[1] = std::max(range[1], v);
    if (range[0] > range[1]) range = {0, 0};
  }
  const auto rgba = [&](double v, PaddedVector<float>& colors) {
    Vec3f rgb{0.5f, 0.f, 0.f};  // VTK's NaN colour
    if (!std::isnan(v)) {
      const double s = range[1] > range[0] ? (v - range[0]) / (range[1] - range[0]) : 0.0;
      rgb = colormap(static_cast<float>(std::clamp(s, 0.0, 1.0)));
    }
    colors.insert(colors.end(), {rgb.x, rgb.y, rgb.z, 1.f});
  };
  file.mesh.vertex_colors.clear();
  file.mesh.face_colors.clear();
  if (choice.cell) {
    for (const std::uint32_t cell : file.triangle_cells) rgba(value[cell], file.mesh.face_colors);
  } else {
    for (std::size_t i = 0; i < file.mesh.vertex_count(); ++i) rgba(value[i], file.mesh.vertex_colors);
  }
  return range;
}

}  // namespace sciray::io
