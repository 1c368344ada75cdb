// VTK image data (.vti), poly data (.vtp) and legacy (.vtk) files (io/vtk_image.hpp,
// io/vtk_polydata.hpp, io/vtk_legacy.hpp): each format in each encoding VTK writes, made
// here as text, read to the same known values; files VTK 9.1 itself wrote (embedded);
// colouring by an array; the shared star catalogue; bad files named.
#include <zlib.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <string>
#include <type_traits>
#include <variant>
#include <vector>

#include "sciray/io/vtk_image.hpp"
#include "sciray/io/vtk_legacy.hpp"
#include "sciray/io/vtk_polydata.hpp"
#include "sciray/testing/scenes.hpp"
#include "support/vtk_xml_writer.hpp"

using namespace sciray;
using namespace sciray_test;

namespace {

std::string write_file(const std::string& name, const std::string& text) {
  const auto path = std::filesystem::temp_directory_path() / ("sciray_vtk_formats_" + name);
  std::ofstream(path, std::ios::binary) << text;
  return path.string();
}

/// f = x + 2y + 3z at the points of a 4x3x2 grid (x fastest), as a type T.
template <class T>
std::vector<T> image_values(T scale = 1) {
  std::vector<T> f;
  for (int z = 0; z < 2; ++z)
    for (int y = 0; y < 3; ++y)
      for (int x = 0; x < 4; ++x) f.push_back(static_cast<T>(scale * static_cast<T>(x + 2 * y + 3 * z)));
  return f;
}

/// An image of f = x + 2y + 3z over a 4x3x2 grid at origin (1,2,3) with spacing (0.5,1,2),
/// with the same values as other types, a vector (3f, 4f, 0), and a cell array 10 * cell.
std::string vti_text(const Encoding& e) {
  XmlWriter w{e, {}};
  std::vector<float> vec;
  for (float f : image_values<float>()) vec.insert(vec.end(), {3 * f, 4 * f, 0});
  std::vector<float> cells;
  for (int c = 0; c < 6; ++c) cells.push_back(10.f * static_cast<float>(c));
  std::string body =
      "<ImageData WholeExtent=\"0 3 0 2 0 1\" Origin=\"1 2 3\" Spacing=\"0.5 1 2\" Direction=\"1 0 0 0 1 0 0 0 1\">\n"
      "<Piece Extent=\"0 3 0 2 0 1\">\n<PointData Scalars=\"f\">\n";
  body += w.array("f", "Float32", 1, image_values<float>());
  body += w.array("u8", "UInt8", 1, image_values<std::uint8_t>());
  body += w.array("i16", "Int16", 1, image_values<std::int16_t>(-1));
  body += w.array("u16", "UInt16", 1, image_values<std::uint16_t>());
  body += w.array("f64", "Float64", 1, image_values<double>());
  body += w.array("i32", "Int32", 1, image_values<std::int32_t>());
  body += w.array("vec", "Float32", 3, vec);
  body +=
      "</PointData>\n<CellData>\n" + w.array("cells", "Float32", 1, cells) + "</CellData>\n</Piece>\n</ImageData>\n";
  return w.file("ImageData", body);
}

/// The value of voxel i of a volume, whatever its type.
double voxel(const io::VolumeFile& v, std::size_t i) {
  const auto as = [&](auto zero) {
    std::memcpy(&zero, v.voxels->data() + i * sizeof(zero), sizeof(zero));
    return static_cast<double>(zero);
  };
  switch (v.kind) {
    case io::VoxelKind::uint8: return as(std::uint8_t{});
    case io::VoxelKind::int16: return as(std::int16_t{});
    case io::VoxelKind::uint16: return as(std::uint16_t{});
    case io::VoxelKind::float32: return as(float{});
    case io::VoxelKind::float64: return as(double{});
  }
  return 0;
}

/// Checks the 4x3x2 image's geometry and that voxel i is `scale` * f.
void check_image(const io::VolumeFile& v, io::VoxelKind kind, double scale) {
  CHECK(v.kind == kind);
  REQUIRE(v.dims == VolumeDims{4, 3, 2});
  CHECK_FALSE(v.grid.cell_centered);
  CHECK(v.grid.origin.x == 1.f);
  CHECK(v.grid.origin.y == 2.f);
  CHECK(v.grid.origin.z == 3.f);
  CHECK(v.grid.spacing.x == 0.5f);
  CHECK(v.grid.spacing.y == 1.f);
  CHECK(v.grid.spacing.z == 2.f);
  REQUIRE(v.voxels->size() == 24 * io::voxel_size(kind));
  const std::vector<double> f = image_values<double>();
  for (std::size_t i = 0; i < 24; ++i) CHECK(voxel(v, i) == Approx(scale * f[i]));
}

/// Two triangles and a quad over 6 points in the z = 0 plane, point scalars s = 0..5, cell
/// scalars c = 10, 20, 30, point normals +z; `x4` is point 4's x.
std::string vtp_text(const Encoding& e, float x4 = 2) {
  XmlWriter w{e, {}};
  const std::vector<float> points = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0, x4, 0, 0, 2, 1, 0};
  const std::vector<std::int64_t> connectivity = {0, 1, 2, 1, 3, 2, 1, 4, 5, 3};
  const std::vector<std::int32_t> offsets = {3, 6, 10};
  const std::vector<float> s = {0, 1, 2, 3, 4, 5}, normals = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
  const std::vector<std::int32_t> c = {10, 20, 30};
  std::string body =
      "<PolyData>\n<Piece NumberOfPoints=\"6\" NumberOfVerts=\"0\" NumberOfLines=\"0\" NumberOfStrips=\"0\" "
      "NumberOfPolys=\"3\">\n<PointData Scalars=\"s\" Normals=\"N\">\n";
  body += w.array("s", "Float32", 1, s) + w.array("N", "Float32", 3, normals);
  body += "</PointData>\n<CellData Scalars=\"c\">\n" + w.array("c", "Int32", 1, c) + "</CellData>\n";
  body += "<Points>\n" + w.array("Points", "Float32", 3, points) + "</Points>\n";
  body += "<Polys>\n" + w.array("connectivity", "Int64", 1, connectivity) + w.array("offsets", "Int32", 1, offsets) +
          "</Polys>\n</Piece>\n</PolyData>\n";
  return w.file("PolyData", body);
}

void check_poly(const io::PolyDataFile& p) {
  REQUIRE(p.mesh.vertex_count() == 6);
  CHECK(p.mesh.positions[12] == 2.f);
  CHECK(p.mesh.vertices_per_face == 3);
  CHECK(std::vector<std::uint32_t>(p.mesh.indices.begin(), p.mesh.indices.end()) ==
        std::vector<std::uint32_t>{0, 1, 2, 1, 3, 2, 1, 4, 5, 1, 5, 3});  // the quad as a fan from its first point
  CHECK(p.triangle_cells == std::vector<std::uint32_t>{0, 1, 2, 2});
  CHECK_FALSE(p.points_only());
  CHECK(p.skipped_vertices_and_lines == 0);
  REQUIRE(p.point_arrays.size() == 2);
  CHECK(p.point_arrays[0].name == "s");
  CHECK(p.point_arrays[0].values == std::vector<double>{0, 1, 2, 3, 4, 5});
  REQUIRE(p.cell_arrays.size() == 1);
  CHECK(p.cell_arrays[0].values == std::vector<double>{10, 20, 30});
  CHECK(p.default_point_array == "s");
  CHECK(p.default_cell_array == "c");
  REQUIRE(p.mesh.normals.size() == 18);
  CHECK(p.mesh.normals[17] == 1.f);
}

/// Numbers as a legacy file stores them: ASCII text, or big-endian bytes; then a newline.
template <class T>
std::string legacy_values(bool binary, const std::vector<T>& values) {
  if (binary) {
    const std::vector<std::uint8_t> raw = bytes_of(values, true);
    return std::string(raw.begin(), raw.end()) + "\n";
  }
  std::string text;
  for (std::size_t i = 0; i < values.size(); ++i) text += std::to_string(+values[i]) + (i % 9 == 8 ? "\n" : " ");
  return text + "\n";
}

std::string legacy_head(bool binary, const std::string& version, const std::string& dataset) {
  return "# vtk DataFile Version " + version + "\nwritten by test_vtk_formats\n" + (binary ? "BINARY" : "ASCII") +
         "\nDATASET " + dataset + "\n";
}

/// The 4x3x2 image as STRUCTURED_POINTS: f, a vector (3f, 4f, 0), a FIELD array g = f as
/// bytes, and cell scalars c = 10 * cell as shorts.
std::string legacy_image(bool binary) {
  std::vector<double> vec;
  for (double f : image_values<double>()) vec.insert(vec.end(), {3 * f, 4 * f, 0});
  std::vector<std::int16_t> c;
  for (std::int16_t i = 0; i < 6; ++i) c.push_back(static_cast<std::int16_t>(10 * i));
  return legacy_head(binary, "3.0", "STRUCTURED_POINTS") + "DIMENSIONS 4 3 2\nORIGIN 1 2 3\nSPACING 0.5 1 2\n" +
         "POINT_DATA 24\nSCALARS f float 1\nLOOKUP_TABLE default\n" + legacy_values(binary, image_values<float>()) +
         "VECTORS v double\n" + legacy_values(binary, vec) + "FIELD FieldData 1\ng 1 24 unsigned_char\n" +
         legacy_values(binary, image_values<std::uint8_t>()) + "CELL_DATA 6\nSCALARS c short\nLOOKUP_TABLE default\n" +
         legacy_values(binary, c);
}

/// A hexahedron and a tetrahedron on top of it, point scalars T = z and a cell vector v,
/// with version 5's OFFSETS/CONNECTIVITY cells or the older count-then-points cells.
std::string legacy_grid(bool binary, bool version5) {
  const std::vector<float> points = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1,    0,    0, 0,
                                     1, 1, 0, 1, 1, 1, 1, 0, 1, 1, 0.5f, 0.5f, 2};
  std::vector<double> t;
  for (std::size_t i = 2; i < points.size(); i += 3) t.push_back(points[i]);
  std::string text = legacy_head(binary, version5 ? "5.1" : "4.2", "UNSTRUCTURED_GRID") + "POINTS 9 float\n" +
                     legacy_values(binary, points);
  if (version5)
    text += "CELLS 3 12\nOFFSETS vtktypeint64\n" + legacy_values(binary, std::vector<std::int64_t>{0, 8, 12}) +
            "CONNECTIVITY vtktypeint64\n" +
            legacy_values(binary, std::vector<std::int64_t>{0, 1, 2, 3, 4, 5, 6, 7, 4, 5, 6, 8});
  else
    text += "CELLS 2 14\n" + legacy_values(binary, std::vector<std::int32_t>{8, 0, 1, 2, 3, 4, 5, 6, 7, 4, 4, 5, 6, 8});
  text += "CELL_TYPES 2\n" + legacy_values(binary, std::vector<std::int32_t>{12, 10});
  text += "CELL_DATA 2\nVECTORS v float\n" + legacy_values(binary, std::vector<float>{3, 4, 0, 0, 0, 2});
  text += "POINT_DATA 9\nSCALARS T double\nLOOKUP_TABLE default\n" + legacy_values(binary, t);
  return text;
}

/// The two triangles and a quad of vtp_text as POLYDATA.
std::string legacy_poly(bool binary, bool version5) {
  std::string text = legacy_head(binary, version5 ? "5.1" : "4.2", "POLYDATA") + "POINTS 6 float\n" +
                     legacy_values(binary, std::vector<float>{0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0, 2, 0, 0, 2, 1, 0});
  if (version5)
    text += "POLYGONS 4 10\nOFFSETS vtktypeint64\n" + legacy_values(binary, std::vector<std::int64_t>{0, 3, 6, 10}) +
            "CONNECTIVITY vtktypeint64\n" +
            legacy_values(binary, std::vector<std::int64_t>{0, 1, 2, 1, 3, 2, 1, 4, 5, 3});
  else
    text += "POLYGONS 3 13\n" + legacy_values(binary, std::vector<std::int32_t>{3, 0, 1, 2, 3, 1, 3, 2, 4, 1, 4, 5, 3});
  text += "CELL_DATA 3\nSCALARS c int\nLOOKUP_TABLE default\n" +
          legacy_values(binary, std::vector<std::int32_t>{10, 20, 30});
  text += "POINT_DATA 6\nSCALARS s float\nLOOKUP_TABLE default\n" +
          legacy_values(binary, std::vector<float>{0, 1, 2, 3, 4, 5}) + "NORMALS N float\n" +
          legacy_values(binary, std::vector<float>{0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1});
  return text;
}

// Files VTK 9.1 wrote (vtkXMLImageDataWriter appended raw with zlib; vtkUnstructuredGridWriter
// and vtkPolyDataWriter BINARY, file version 5.1, with their METADATA blocks).
const char vtk_written_image[] =
    "<VTKFile type=\042ImageData\042 version=\0420.1\042 byte_order=\042LittleEndian\042 header_type=\042U"
    "Int32\042 compressor=\042vtkZLibDataCompressor\042>\n"
    "  <ImageData WholeExtent=\0420 3 0 2 0 1\042 Origin=\0421 2 3\042 Spacing=\0420.5 1 2\042 Direction=\042"
    "1 0 0 0 1 0 0 0 1\042>\n"
    "    <Piece Extent=\0420 3 0 2 0 1\042                                                       >\n"
    "      <PointData Scalars=\042f\042>\n"
    "        <DataArray type=\042Float32\042 Name=\042f\042 format=\042appended\042 RangeMin=\0420\042    "
    "                RangeMax=\04210\042                   offset=\0420\042                   />\n"
    "      </PointData>\n"
    "      <CellData>\n"
    "      </CellData>\n"
    "    </Piece>\n"
    "  </ImageData>\n"
    "  <AppendedData encoding=\042raw\042>\n"
    "   _\001\000\000\000\000\200\000\000`\000\000\000*\000\000\000x^c`\000\201\006{ \341\000D\016\010\272"
    "\001\210\027 \321\007\200\370\001\232\334\00149\006G\004-\000\304\n"
    "\216\000\322\345\020\024\n"
    "  </AppendedData>\n"
    "</VTKFile>\n";
const char vtk_written_grid[] =
    "# vtk DataFile Version 5.1\n"
    "vtk output\n"
    "BINARY\n"
    "DATASET UNSTRUCTURED_GRID\n"
    "POINTS 9 float\n"
    "\000\000\000\000\000\000\000\000\000\000\000\000\077\200\000\000\000\000\000\000\000\000\000\000\077\200"
    "\000\000\077\200\000\000\000\000\000\000\000\000\000\000\077\200\000\000\000\000\000\000\000\000\000\000"
    "\000\000\000\000\077\200\000\000\077\200\000\000\000\000\000\000\077\200\000\000\077\200\000\000\077\200"
    "\000\000\077\200\000\000\000\000\000\000\077\200\000\000\077\200\000\000\077\000\000\000\077\000\000\000"
    "@\000\000\000\n"
    "CELLS 3 12\n"
    "OFFSETS vtktypeint64\n"
    "\000\000\000\000\000\000\000\000\000\000\000\000\000\000\000\010\000\000\000\000\000\000\000\014\n"
    "CONNECTIVITY vtktypeint64\n"
    "\000\000\000\000\000\000\000\000\000\000\000\000\000\000\000\001\000\000\000\000\000\000\000\002\000\000"
    "\000\000\000\000\000\003\000\000\000\000\000\000\000\004\000\000\000\000\000\000\000\005\000\000\000\000"
    "\000\000\000\006\000\000\000\000\000\000\000\007\000\000\000\000\000\000\000\004\000\000\000\000\000\000"
    "\000\005\000\000\000\000\000\000\000\006\000\000\000\000\000\000\000\010\n"
    "CELL_TYPES 2\n"
    "\000\000\000\014\000\000\000\n"
    "\n"
    "CELL_DATA 2\n"
    "VECTORS v float\n"
    "@@\000\000@\200\000\000\000\000\000\000\000\000\000\000\000\000\000\000@\000\000\000\n"
    "POINT_DATA 9\n"
    "SCALARS T double\n"
    "LOOKUP_TABLE default\n"
    "\000\000\000\000\000\000\000\000\000\000\000\000\000\000\000\000\000\000\000\000\000\000\000\000\000\000"
    "\000\000\000\000\000\000\077\360\000\000\000\000\000\000\077\360\000\000\000\000\000\000\077\360\000\000"
    "\000\000\000\000\077\360\000\000\000\000\000\000@\000\000\000\000\000\000\000\n";
const char vtk_written_poly[] =
    "# vtk DataFile Version 5.1\n"
    "vtk output\n"
    "BINARY\n"
    "DATASET POLYDATA\n"
    "POINTS 6 float\n"
    "\000\000\000\000\000\000\000\000\000\000\000\000\077\200\000\000\000\000\000\000\000\000\000\000\000\000"
    "\000\000\077\200\000\000\000\000\000\000\077\200\000\000\077\200\000\000\000\000\000\000@\000\000\000"
    "\000\000\000\000\000\000\000\000@\000\000\000\077\200\000\000\000\000\000\000\n"
    "METADATA\n"
    "INFORMATION 1\n"
    "NAME L2_NORM_RANGE LOCATION vtkDataArray\n"
    "DATA 2 0 2.23607 \n"
    "\n"
    "VERTICES 2 1\n"
    "OFFSETS vtktypeint64\n"
    "\000\000\000\000\000\000\000\000\000\000\000\000\000\000\000\001\n"
    "CONNECTIVITY vtktypeint64\n"
    "\000\000\000\000\000\000\000\000\n"
    "POLYGONS 4 10\n"
    "OFFSETS vtktypeint64\n"
    "\000\000\000\000\000\000\000\000\000\000\000\000\000\000\000\003\000\000\000\000\000\000\000\006\000\000"
    "\000\000\000\000\000\n"
    "\n"
    "CONNECTIVITY vtktypeint64\n"
    "\000\000\000\000\000\000\000\000\000\000\000\000\000\000\000\001\000\000\000\000\000\000\000\002\000\000"
    "\000\000\000\000\000\001\000\000\000\000\000\000\000\003\000\000\000\000\000\000\000\002\000\000\000\000"
    "\000\000\000\001\000\000\000\000\000\000\000\004\000\000\000\000\000\000\000\005\000\000\000\000\000\000"
    "\000\003\n"
    "CELL_DATA 4\n"
    "SCALARS c int\n"
    "LOOKUP_TABLE default\n"
    "\000\000\000\007\000\000\000\n"
    "\000\000\000\024\000\000\000\036\n"
    "METADATA\n"
    "INFORMATION 0\n"
    "\n"
    "POINT_DATA 6\n"
    "SCALARS s float\n"
    "LOOKUP_TABLE default\n"
    "\000\000\000\000\077\200\000\000@\000\000\000@@\000\000@\200\000\000@\240\000\000\n"
    "METADATA\n"
    "INFORMATION 0\n"
    "\n";

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "no error";
}

/// A linear ramp from blue to red, so that mapped colours can be checked exactly.
Vec3f ramp(float s) {
  return Vec3f{s, 0.f, 1.f - s};
}

}  // namespace

TEST_CASE("VTK .vti: every encoding reads f = x + 2y + 3z", "[io][vtk]") {
  for (const Encoding& e : xml_encodings) {
    INFO("format " << describe(e));
    const std::string path = write_file("image.vti", vti_text(e));
    check_image(io::read_vti(path), io::VoxelKind::float32, 1);  // the Scalars array, f
    check_image(io::read_vti(path, "u8"), io::VoxelKind::uint8, 1);
    check_image(io::read_vti(path, "i16"), io::VoxelKind::int16, -1);
    check_image(io::read_vti(path, "u16"), io::VoxelKind::uint16, 1);
    check_image(io::read_vti(path, "f64"), io::VoxelKind::float64, 1);
    check_image(io::read_vti(path, "i32"), io::VoxelKind::float32, 1);  // a type a volume does not hold
    check_image(io::read_vti(path, "vec"), io::VoxelKind::float32, 5);  // |(3f, 4f, 0)|
    // A cell array: a cell-centred volume of 3x2x1 cells whose corner is the origin.
    const io::VolumeFile cells = io::read_vti(path, "cells");
    CHECK(cells.grid.cell_centered);
    CHECK(cells.dims == VolumeDims{3, 2, 1});
    CHECK(cells.grid.origin.x == 1.f);
    CHECK(voxel(cells, 5) == 50.0);
  }
}

TEST_CASE("VTK .vti: pieces, extents and a negative spacing", "[io][vtk]") {
  // Two pieces sharing the plane x = 1 of the extent [1,4]x[0,2]x[0,1], z spacing -2.
  const auto piece = [](int x0, int x1) {
    std::string values;
    for (int z = 0; z < 2; ++z)
      for (int y = 0; y < 3; ++y)
        for (int x = x0; x <= x1; ++x) values += std::to_string(x - 1 + 2 * y + 3 * z) + " ";
    return "<Piece Extent=\"" + std::to_string(x0) + " " + std::to_string(x1) +
           " 0 2 0 1\"><PointData><DataArray type=\"Float64\" Name=\"f\" format=\"ascii\">" + values +
           "</DataArray></PointData></Piece>\n";
  };
  const std::string text =
      "<VTKFile type=\"ImageData\" version=\"1.0\"><ImageData WholeExtent=\"1 4 0 2 0 1\" "
      "Origin=\"0.5 2 7\" Spacing=\"0.5 1 -2\">\n" +
      piece(1, 2) + piece(2, 4) + "</ImageData></VTKFile>\n";
  const io::VolumeFile v = io::read_vti(write_file("pieces.vti", text));
  REQUIRE(v.dims == VolumeDims{4, 3, 2});
  CHECK(v.kind == io::VoxelKind::float64);
  // The z axis is flipped to a positive spacing: the first plane is the file's last.
  CHECK(v.grid.origin.x == 1.f);
  CHECK(v.grid.origin.z == 5.f);
  CHECK(v.grid.spacing.z == 2.f);
  const std::vector<double> f = image_values<double>();
  for (std::size_t i = 0; i < 12; ++i) CHECK(voxel(v, i) == f[i + 12]);
  for (std::size_t i = 12; i < 24; ++i) CHECK(voxel(v, i) == f[i - 12]);
}

TEST_CASE("VTK .vtp: every encoding reads two triangles and a quad", "[io][vtk]") {
  for (const Encoding& e : xml_encodings) {
    INFO("format " << describe(e));
    check_poly(io::read_vtp(write_file("poly.vtp", vtp_text(e))));
  }
}

TEST_CASE("VTK .vtp: strips, vertices and lines, pieces", "[io][vtk]") {
  // Piece 0: a vertex, a line, a triangle and a strip of 4 triangles; piece 1: one triangle.
  const std::string text =
      "<VTKFile type=\"PolyData\"><PolyData>\n"
      "<Piece NumberOfPoints=\"6\" NumberOfVerts=\"1\" NumberOfLines=\"1\" NumberOfStrips=\"1\" NumberOfPolys=\"1\">"
      "<CellData><DataArray type=\"Float32\" Name=\"id\" format=\"ascii\">0 1 2 3</DataArray></CellData>"
      "<Points><DataArray type=\"Float32\" NumberOfComponents=\"3\" format=\"ascii\">"
      "0 0 0 1 0 0 0 1 0 1 1 0 0 2 0 1 2 0</DataArray></Points>"
      "<Verts><DataArray type=\"Int32\" Name=\"connectivity\" format=\"ascii\">5</DataArray>"
      "<DataArray type=\"Int32\" Name=\"offsets\" format=\"ascii\">1</DataArray></Verts>"
      "<Lines><DataArray type=\"Int32\" Name=\"connectivity\" format=\"ascii\">0 5</DataArray>"
      "<DataArray type=\"Int32\" Name=\"offsets\" format=\"ascii\">2</DataArray></Lines>"
      "<Strips><DataArray type=\"Int32\" Name=\"connectivity\" format=\"ascii\">0 1 2 3 4 5</DataArray>"
      "<DataArray type=\"Int32\" Name=\"offsets\" format=\"ascii\">6</DataArray></Strips>"
      "<Polys><DataArray type=\"Int32\" Name=\"connectivity\" format=\"ascii\">0 1 3</DataArray>"
      "<DataArray type=\"Int32\" Name=\"offsets\" format=\"ascii\">3</DataArray></Polys></Piece>\n"
      "<Piece NumberOfPoints=\"3\" NumberOfPolys=\"1\">"
      "<CellData><DataArray type=\"Float32\" Name=\"id\" format=\"ascii\">4</DataArray></CellData>"
      "<Points><DataArray type=\"Float32\" NumberOfComponents=\"3\" format=\"ascii\">5 0 0 6 0 0 5 1 "
      "0</DataArray></Points>"
      "<Polys><DataArray type=\"Int32\" Name=\"connectivity\" format=\"ascii\">0 1 2</DataArray>"
      "<DataArray type=\"Int32\" Name=\"offsets\" format=\"ascii\">3</DataArray></Polys></Piece>\n"
      "</PolyData></VTKFile>\n";
  const io::PolyDataFile p = io::read_vtp(write_file("strips.vtp", text));
  CHECK(p.mesh.vertex_count() == 9);
  CHECK(p.skipped_vertices_and_lines == 2);
  // VTK's cell order is vertices, lines, polygons, strips; every other strip triangle turned.
  CHECK(std::vector<std::uint32_t>(p.mesh.indices.begin(), p.mesh.indices.end()) ==
        std::vector<std::uint32_t>{0, 1, 3, 0, 1, 2, 2, 1, 3, 2, 3, 4, 4, 3, 5, 6, 7, 8});
  CHECK(p.triangle_cells == std::vector<std::uint32_t>{2, 3, 3, 3, 3, 4});
  REQUIRE(p.cell_arrays.size() == 1);
  CHECK(p.cell_arrays[0].values == std::vector<double>{0, 1, 2, 3, 4});
  // Every triangle faces +z.
  for (std::size_t t = 0; t < p.mesh.face_count(); ++t) {
    const auto at = [&](int k) {
      const std::size_t i = p.mesh.indices[3 * t + static_cast<std::size_t>(k)];
      return Vec3f{p.mesh.positions[3 * i], p.mesh.positions[3 * i + 1], p.mesh.positions[3 * i + 2]};
    };
    CHECK(cross(at(1) - at(0), at(2) - at(0)).z > 0.f);
  }
}

TEST_CASE("VTK .vtp: colour by a point or a cell array", "[io][vtk]") {
  io::PolyDataFile p = io::read_vtp(write_file("colors.vtp", vtp_text({"binary"})));
  const auto color = [](const PaddedVector<float>& colors, std::size_t i) {
    return Vec3f{colors[4 * i], colors[4 * i + 1], colors[4 * i + 2]};
  };
  // Point array s = 0..5: its ends map to the colour map's ends, vertex by vertex.
  CHECK(io::color_by(p, "s", ramp) == std::array<double, 2>{0, 5});
  REQUIRE(p.mesh.vertex_colors.size() == 24);
  CHECK(p.mesh.face_colors.empty());
  CHECK(color(p.mesh.vertex_colors, 0).x == 0.f);
  CHECK(color(p.mesh.vertex_colors, 0).z == 1.f);
  CHECK(color(p.mesh.vertex_colors, 5).x == 1.f);
  CHECK(color(p.mesh.vertex_colors, 2).x == Approx(0.4f));
  CHECK(p.mesh.vertex_colors[23] == 1.f);  // opaque
  // Cell array c = 10, 20, 30: each triangle its cell's colour, the quad's two alike.
  CHECK(io::color_by(p, "c", ramp) == std::array<double, 2>{10, 30});
  CHECK(p.mesh.vertex_colors.empty());
  REQUIRE(p.mesh.face_colors.size() == 16);
  CHECK(color(p.mesh.face_colors, 0).x == 0.f);
  CHECK(color(p.mesh.face_colors, 1).x == 0.5f);
  CHECK(color(p.mesh.face_colors, 2).x == 1.f);
  CHECK(color(p.mesh.face_colors, 3).x == 1.f);
  // A given range, clamped; the default array (Scalars s); the shared viridis-like map.
  io::color_by(p, "c", ramp, {.component = -1, .range = std::array<double, 2>{20, 60}});
  CHECK(color(p.mesh.face_colors, 0).x == 0.f);
  CHECK(color(p.mesh.face_colors, 2).x == 0.25f);
  io::color_by(p, "", testing::colormap);
  CHECK(color(p.mesh.vertex_colors, 0).x == testing::colormap(0.f).x);
  CHECK(color(p.mesh.vertex_colors, 5).y == testing::colormap(1.f).y);
  // A vector by its magnitude or by one component; NaN takes VTK's NaN colour.
  p.point_arrays.push_back({"v", 2, {3, 4, 0, 0, 0, 1, 6, 8, 0, 2, std::nan(""), 0}});
  CHECK(io::color_by(p, "v", ramp) == std::array<double, 2>{0, 10});
  CHECK(color(p.mesh.vertex_colors, 0).x == 0.5f);
  CHECK(color(p.mesh.vertex_colors, 5).x == 0.5f);
  CHECK(color(p.mesh.vertex_colors, 5).z == 0.f);
  CHECK(io::color_by(p, "v", ramp, {.component = 1, .range = std::nullopt}) == std::array<double, 2>{0, 8});
}

TEST_CASE("VTK .vtp: the star catalogue is a point cloud", "[io][vtk]") {
  io::PolyDataFile stars = io::read_vtp(SCIRAY_DATA_DIR "/points/stars.vtp");  // zlib, base64, Verts only
  CHECK(stars.mesh.vertex_count() == 107857);
  CHECK(stars.points_only());
  CHECK(stars.skipped_vertices_and_lines == 107857);
  REQUIRE(stars.point_arrays.size() == 3);
  CHECK(stars.point_arrays[0].name == "lum");
  CHECK(stars.point_arrays[2].name == "_rgba");
  CHECK(stars.point_arrays[2].components == 4);
  CHECK(stars.default_point_array == "_rgba");
  // The file's own RangeMin and RangeMax of the luminosity.
  const std::array<double, 2> range = io::color_by(stars, "lum", testing::colormap);
  CHECK(range[0] == Approx(2.9484922e-6));
  CHECK(range[1] == Approx(67483.875));
  CHECK(stars.mesh.vertex_colors.size() == 4 * 107857);
}

TEST_CASE("VTK legacy: STRUCTURED_POINTS, ASCII and BINARY", "[io][vtk]") {
  for (const bool binary : {false, true}) {
    INFO((binary ? "BINARY" : "ASCII"));
    const std::string path = write_file("image.vtk", legacy_image(binary));
    const auto volume = [&](const std::string& field) {
      return std::get<io::VolumeFile>(io::read_legacy_vtk(path, field));
    };
    check_image(volume(""), io::VoxelKind::float32, 1);
    check_image(volume("v"), io::VoxelKind::float32, 5);
    check_image(volume("g"), io::VoxelKind::uint8, 1);  // a FIELD array
    const io::VolumeFile cells = volume("c");
    CHECK(cells.kind == io::VoxelKind::int16);
    CHECK(cells.grid.cell_centered);
    CHECK(cells.dims == VolumeDims{3, 2, 1});
    CHECK(voxel(cells, 4) == 40.0);
  }
}

TEST_CASE("VTK legacy: UNSTRUCTURED_GRID in both cell layouts samples as a volume", "[io][vtk]") {
  for (const bool binary : {false, true})
    for (const bool version5 : {false, true}) {
      INFO((binary ? "BINARY" : "ASCII") << (version5 ? ", version 5.1" : ", version 4.2"));
      const std::string path = write_file("grid.vtk", legacy_grid(binary, version5));
      const io::UnstructuredGridFile grid = std::get<io::UnstructuredGridFile>(io::read_legacy_vtk(path));
      REQUIRE(grid.points.size() == 9);
      CHECK(grid.connectivity == std::vector<std::int64_t>{0, 1, 2, 3, 4, 5, 6, 7, 4, 5, 6, 8});
      CHECK(grid.offsets == std::vector<std::int64_t>{8, 12});
      CHECK(grid.types == std::vector<std::uint8_t>{12, 10});
      CHECK(grid.default_point_array == "T");
      const Unstructured by_point(io::unstructured_volume(grid, "", path));  // T = z
      CHECK(by_point.sample({0.3f, 0.6f, 0.25f}) == Approx(0.25f));
      CHECK(by_point.sample({0.5f, 0.5f, 1.5f}) == Approx(1.5f));
      const Unstructured by_cell(io::unstructured_volume(grid, "v", path));
      CHECK(by_cell.sample({0.5f, 0.5f, 0.5f}) == 5.f);
      CHECK(by_cell.sample({0.5f, 0.5f, 1.2f}) == 2.f);
    }
}

TEST_CASE("VTK legacy: POLYDATA in both cell layouts", "[io][vtk]") {
  for (const bool binary : {false, true})
    for (const bool version5 : {false, true}) {
      INFO((binary ? "BINARY" : "ASCII") << (version5 ? ", version 5.1" : ", version 4.2"));
      check_poly(
          std::get<io::PolyDataFile>(io::read_legacy_vtk(write_file("poly.vtk", legacy_poly(binary, version5)))));
    }
}

TEST_CASE("VTK legacy: every kind of attribute, escaped names, CRLF lines", "[io][vtk]") {
  for (const bool binary : {false, true}) {
    INFO((binary ? "BINARY" : "ASCII"));
    std::vector<float> tensor(27);
    for (std::size_t i = 0; i < tensor.size(); ++i) tensor[i] = static_cast<float>(i);
    std::string text = legacy_head(binary, "3.0", "POLYDATA") + "FIELD FieldData 1\nTIME 1 1 double\n" +
                       legacy_values(binary, std::vector<double>{0.5}) + "POINTS 3 float\n" +
                       legacy_values(binary, std::vector<float>{0, 0, 0, 1, 0, 0, 0, 1, 0}) + "POLYGONS 1 4\n" +
                       legacy_values(binary, std::vector<std::int32_t>{3, 0, 1, 2}) + "POINT_DATA 3\n";
    // Colour scalars are bytes in binary files and [0,1] numbers in ASCII ones.
    text += "COLOR_SCALARS rgb 3\n" +
            (binary ? legacy_values(true, std::vector<std::uint8_t>{255, 0, 0, 0, 255, 0, 0, 0, 255})
                    : legacy_values(false, std::vector<float>{1, 0, 0, 0, 1, 0, 0, 0, 1}));
    text += "TEXTURE_COORDINATES uv 2 float\n" + legacy_values(binary, std::vector<float>{0, 0, 1, 0, 0, 1});
    text += "TENSORS t float\n" + legacy_values(binary, tensor);
    text += "GLOBAL_IDS ids vtkIdType\n" + legacy_values(binary, std::vector<std::int32_t>{7, 8, 9});
    text += "SCALARS two%20words double 2\nLOOKUP_TABLE mine\n" +
            legacy_values(binary, std::vector<double>{1, 2, 3, 4, 5, 6});
    text += "LOOKUP_TABLE mine 2\n" + (binary ? legacy_values(true, std::vector<std::uint8_t>(8, 255))
                                              : legacy_values(false, std::vector<float>(8, 1.f)));
    if (!binary)  // Windows line ends
      for (std::size_t at = text.find('\n'); at != std::string::npos; at = text.find('\n', at + 2))
        text.insert(at, "\r");
    const auto p = std::get<io::PolyDataFile>(io::read_legacy_vtk(write_file("attributes.vtk", text)));
    CHECK(p.mesh.face_count() == 1);
    REQUIRE(p.point_arrays.size() == 5);
    CHECK(p.point_arrays[0].name == "rgb");
    CHECK(p.point_arrays[0].values == std::vector<double>{255, 0, 0, 0, 255, 0, 0, 0, 255});
    CHECK(p.default_point_array == "rgb");  // the first scalars
    CHECK(std::vector<float>(p.mesh.texcoords.begin(), p.mesh.texcoords.end()) == std::vector<float>{0, 0, 1, 0, 0, 1});
    CHECK(p.point_arrays[2].components == 9);
    CHECK(p.point_arrays[2].values[26] == 26.0);
    CHECK(p.point_arrays[3].values == std::vector<double>{7, 8, 9});
    CHECK(p.point_arrays[4].name == "two words");
    CHECK(p.point_arrays[4].components == 2);
  }
}

TEST_CASE("VTK: files VTK itself wrote", "[io][vtk]") {
  check_image(io::read_vti(write_file("vtk_image.vti", std::string(vtk_written_image, sizeof vtk_written_image - 1))),
              io::VoxelKind::float32, 1);
  const auto grid = std::get<io::UnstructuredGridFile>(
      io::read_legacy_vtk(write_file("vtk_grid.vtk", std::string(vtk_written_grid, sizeof vtk_written_grid - 1))));
  CHECK(grid.offsets == std::vector<std::int64_t>{8, 12});
  CHECK(Unstructured(io::unstructured_volume(grid, "v", "vtk_grid.vtk")).sample({0.5f, 0.5f, 0.5f}) == 5.f);
  const auto poly = std::get<io::PolyDataFile>(
      io::read_legacy_vtk(write_file("vtk_poly.vtk", std::string(vtk_written_poly, sizeof vtk_written_poly - 1))));
  CHECK(poly.mesh.face_count() == 4);
  CHECK(poly.skipped_vertices_and_lines == 1);  // a vertex, cell 0
  CHECK(poly.triangle_cells == std::vector<std::uint32_t>{1, 2, 3, 3});
  CHECK(poly.cell_arrays[0].values == std::vector<double>{7, 10, 20, 30});
}

TEST_CASE("VTK: bad files are named", "[io][vtk][errors]") {
  // .vti
  const std::string image = vti_text({"appended"});
  const std::string truncated =
      write_file("truncated.vti", image.substr(0, image.find("\n</AppendedData>") - 10) + "</AppendedData></VTKFile>");
  CHECK_THAT(error_of([&] { io::read_vti(truncated, "cells"); }),
             Catch::Contains("truncated.vti: DataArray 'cells': the data block is truncated (14 bytes, 24 needed)"));
  const std::string good = write_file("good.vti", vti_text({"ascii"}));
  CHECK(error_of([&] { io::read_vti(good, "pressure"); }) ==
        good +
            ": has no point or cell array 'pressure' (its point arrays: 'f', 'u8', 'i16', 'u16', 'f64', 'i32', "
            "'vec'; its cell arrays: 'cells')");
  std::string rotated = vti_text({"ascii"});
  rotated.replace(rotated.find("1 0 0 0 1 0 0 0 1"), 17, "0 1 0 1 0 0 0 0 1");
  CHECK_THAT(error_of([&] { io::read_vti(write_file("rotated.vti", rotated)); }),
             Catch::Contains("rotated.vti: ImageData Direction '0 1 0 1 0 0 0 0 1' is not the identity"));
  std::string miscounted = vti_text({"ascii"});
  miscounted.replace(miscounted.find("Piece Extent=\"0 3 0 2 0 1\""), 26, "Piece Extent=\"0 3 0 2 0 2\"");
  CHECK_THAT(error_of([&] { io::read_vti(write_file("miscounted.vti", miscounted)); }),
             Catch::Contains("miscounted.vti: DataArray 'f': has 24 tuples, 36 expected"));
  std::string empty = vti_text({"ascii"});
  empty.replace(empty.find("Piece Extent=\"0 3 0 2 0 1\""), 26, "Piece Extent=\"0 3 2 0 0 1\"");
  CHECK_THAT(error_of([&] { io::read_vti(write_file("empty.vti", empty)); }),
             Catch::Contains("empty.vti: Piece Extent '0 3 2 0 0 1' is empty along axis 1"));
  // 16 pieces of 2^60 samples each: their sum once wrapped past 2^64 to 0, and the file was
  // said to hold too few; each piece's array is what falls short.
  std::string huge = "<VTKFile type=\"ImageData\"><ImageData WholeExtent=\"0 1048575 0 1048575 0 1048575\">\n";
  for (int p = 0; p < 16; ++p)
    huge += "<Piece Extent=\"0 1048575 0 1048575 0 1048575\"><PointData><DataArray type=\"Float32\" Name=\"f\" "
            "format=\"ascii\">0</DataArray></PointData></Piece>\n";
  huge += "</ImageData></VTKFile>\n";
  CHECK_THAT(error_of([&] { io::read_vti(write_file("huge.vti", huge)); }),
             Catch::Contains("huge.vti: DataArray 'f': has 1 tuples, 1152921504606846976 expected"));
  const std::string poly = write_file("poly.vtp", vtp_text({"ascii"}));
  CHECK_THAT(error_of([&] { io::read_vti(poly); }),
             Catch::Contains("poly.vtp: a VTK file of type 'PolyData', not ImageData"));
  CHECK_THAT(error_of([&] { io::read_vti("/nonexistent.vti"); }),
             Catch::Contains("/nonexistent.vti: cannot open file"));

  // .vtp
  CHECK_THAT(error_of([&] { io::read_vtp(write_file("nan.vtp", vtp_text({"binary"}, std::nanf("")))); }),
             Catch::Contains("nan.vtp: Points: point 4 is (nan, 0, 0), not finite as a float"));
  std::string outside = vtp_text({"ascii"});
  outside.replace(outside.find("4 5 3 "), 6, "4 9 3 ");
  CHECK_THAT(error_of([&] { io::read_vtp(write_file("outside.vtp", outside)); }),
             Catch::Contains("outside.vtp: Polys cell 2 refers to point 9, but there are 6 points"));
  std::string four = vtp_text({"ascii"});
  four.replace(four.find("NumberOfPolys=\"3\""), 17, "NumberOfPolys=\"4\"");
  CHECK_THAT(error_of([&] { io::read_vtp(write_file("four.vtp", four)); }),
             Catch::Contains("four.vtp: DataArray 'offsets': has 3 tuples, 4 expected"));
  io::PolyDataFile mesh = io::read_vtp(poly);
  CHECK(error_of([&] { io::color_by(mesh, "pressure", ramp); }) ==
        poly + ": has no point or cell array 'pressure' (its point arrays: 's', 'N'; its cell arrays: 'c')");
  CHECK_THAT(error_of([&] { io::color_by(mesh, "N", ramp, {.component = 3, .range = std::nullopt}); }),
             Catch::Contains("array 'N' has 3 components, so no component 3"));
  io::PolyDataFile cloud = mesh;
  cloud.mesh.indices.clear();
  CHECK_THAT(error_of([&] { io::color_by(cloud, "c", ramp); }),
             Catch::Contains("cell array 'c' colours faces, and the file has no polygons or strips"));

  // Legacy
  const std::string binary_image = legacy_image(true);
  const std::size_t vectors = binary_image.find("VECTORS v double\n") + 17;
  CHECK_THAT(error_of([&] { io::read_legacy_vtk(write_file("cut.vtk", binary_image.substr(0, vectors + 100))); }),
             Catch::Contains("cut.vtk: byte " + std::to_string(vectors) +
                             ": POINT_DATA VECTORS 'v': the binary data is truncated: 576 bytes of double needed, 100 "
                             "left in the file"));
  std::string count = legacy_image(false);
  count.replace(count.find("POINT_DATA 24"), 13, "POINT_DATA 25");
  CHECK_THAT(error_of([&] { io::read_legacy_vtk(write_file("count.vtk", count)); }),
             Catch::Contains("count.vtk: line 8: POINT_DATA 25 does not match the dataset's 24 points"));
  std::string short_values = legacy_image(false);
  short_values.replace(short_values.find("10.000000 \nVECTORS"), 10, "");
  CHECK_THAT(error_of([&] { io::read_legacy_vtk(write_file("short.vtk", short_values)); }),
             Catch::Contains("short.vtk: line 14: POINT_DATA SCALARS 'f': value 23 of 24 is 'VECTORS', not a number"));
  std::string long_values = legacy_grid(false, false);
  long_values.replace(long_values.find("CELL_TYPES 2\n12 10 \n"), 20, "CELL_TYPES 2\n12 10 10\n");
  CHECK_THAT(
      error_of([&] { io::read_legacy_vtk(write_file("long.vtk", long_values)); }),
      Catch::Contains("long.vtk: line 14: unexpected keyword '10' in DATASET UNSTRUCTURED_GRID (a number where a "
                      "keyword should be: more values than the section's count?)"));
  std::string types = legacy_grid(false, true);
  types.replace(types.find("CELL_TYPES 2"), 12, "CELL_TYPES 3");
  CHECK_THAT(error_of([&] { io::read_legacy_vtk(write_file("types.vtk", types)); }),
             Catch::Contains("types.vtk: line 16: CELL_TYPES 3 does not match the 2 CELLS"));
  std::string nan_point = legacy_grid(false, true);
  nan_point.replace(nan_point.find("\n0.000000 1.000000 0.000000"), 9, "\nnan");  // point 3
  CHECK_THAT(error_of([&] { io::read_legacy_vtk(write_file("nan.vtk", nan_point)); }),
             Catch::Contains("nan.vtk: POINTS: point 3 is (nan, 1, 0), not finite as a float"));
  std::string far_point = legacy_poly(true, true);
  const std::size_t connectivity = far_point.find("CONNECTIVITY vtktypeint64\n") + 26;
  far_point[connectivity + 8 * 9 + 7] = 12;  // the quad's last point
  CHECK_THAT(error_of([&] { io::read_legacy_vtk(write_file("far.vtk", far_point)); }),
             Catch::Contains("far.vtk: POLYGONS cell 2 refers to point 12, but there are 6 points"));
  std::string rectilinear = legacy_image(false);
  rectilinear.replace(rectilinear.find("STRUCTURED_POINTS"), 17, "RECTILINEAR_GRID");
  CHECK_THAT(error_of([&] { io::read_legacy_vtk(write_file("rectilinear.vtk", rectilinear)); }),
             Catch::Contains("rectilinear.vtk: line 4: DATASET RECTILINEAR_GRID is not supported (STRUCTURED_POINTS, "
                             "UNSTRUCTURED_GRID and POLYDATA are)"));
  std::string bits = legacy_image(false);
  bits.replace(bits.find("SCALARS f float"), 15, "SCALARS f bit  ");
  CHECK_THAT(error_of([&] { io::read_legacy_vtk(write_file("bits.vtk", bits)); }),
             Catch::Contains("bits.vtk: line 10: POINT_DATA SCALARS 'f': data type 'bit' is not supported"));
  const std::string legacy = write_file("legacy.vtk", legacy_image(true));
  CHECK(error_of([&] { io::read_legacy_vtk(legacy, "pressure"); }) ==
        legacy + ": has no point or cell array 'pressure' (its point arrays: 'f', 'v', 'g'; its cell arrays: 'c')");
  CHECK_THAT(error_of([&] { io::read_legacy_vtk(poly); }),
             Catch::Contains("poly.vtp: not a legacy VTK file: the first line is '<?xml version=\"1.0\"?>'"));
  std::string unnumbered = legacy_image(false);
  unnumbered.replace(unnumbered.find("Version ") + 8, 1, "x");
  CHECK_THAT(error_of([&] { io::read_legacy_vtk(write_file("unnumbered.vtk", unnumbered)); }),
             Catch::Contains("unnumbered.vtk: the version in '# vtk DataFile Version x.") &&
                 Catch::Contains("' is not a number"));
  std::string overflowing = legacy_image(false);
  overflowing.replace(overflowing.find("Version ") + 8, 1, "99999999999");
  CHECK_THAT(error_of([&] { io::read_legacy_vtk(write_file("overflowing.vtk", overflowing)); }),
             Catch::Contains("overflowing.vtk: the version in '# vtk DataFile Version 99999999999") &&
                 Catch::Contains("' is not a number"));
  std::string neither = legacy_image(false);
  neither.replace(neither.find("ASCII"), 5, "TEXT ");
  CHECK_THAT(error_of([&] { io::read_legacy_vtk(write_file("neither.vtk", neither)); }),
             Catch::Contains("neither.vtk: line 3 must say ASCII or BINARY, not 'TEXT'"));
  CHECK_THAT(error_of([&] { io::read_legacy_vtk("/nonexistent.vtk"); }),
             Catch::Contains("/nonexistent.vtk: cannot open file"));
}
