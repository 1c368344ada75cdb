// VTK XML unstructured grids (io/vtk.hpp): every encoding VTK writes (ASCII, base64,
// appended raw and base64, zlib blocks, 32- and 64-bit headers, both byte orders) read to
// the same grid; the real finite-element files of the shared data; bad files named.
#include <catch2/catch.hpp>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>


#include "sciray/io/vtk.hpp"
#include "support/vtk_xml_writer.hpp"

using namespace sciray;
using namespace sciray_test;

namespace {

/// A grid of one hexahedron and one tetrahedron on top of it, a point array "T" = z and a
/// vector cell array "v", written as VTK would with `e`.
std::string vtu_text(const Encoding& e) {
  const std::vector<float> points = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1, 0.5f, 0.5f, 2};
  const std::vector<std::int64_t> connectivity = {0, 1, 2, 3, 4, 5, 6, 7, 4, 5, 6, 8}, offsets = {8, 12};
  const std::vector<std::uint8_t> types = {12, 10};
  std::vector<double> t;
  for (std::size_t i = 2; i < points.size(); i += 3) t.push_back(points[i]);
  const std::vector<double> v = {3, 4, 0, 0, 0, 2};
  XmlWriter w{e, {}};
  std::string body = "<UnstructuredGrid>\n<Piece NumberOfPoints=\"9\" NumberOfCells=\"2\">\n";
  body += "<PointData Scalars=\"T\">\n" + w.array("T", "Float64", 1, t) + "</PointData>\n";
  body += "<CellData>\n" + w.array("v", "Float64", 3, v) + "</CellData>\n";
  body += "<Points>\n" + w.array("Points", "Float32", 3, points) + "</Points>\n";
  body += "<Cells>\n" + w.array("connectivity", "Int64", 1, connectivity) + w.array("offsets", "Int64", 1, offsets) +
          w.array("types", "UInt8", 1, types) + "</Cells>\n";
  body += "</Piece>\n</UnstructuredGrid>\n";
  return w.file("UnstructuredGrid", body);
}

std::string write_file(const std::string& name, const std::string& text) {
  const auto path = std::filesystem::temp_directory_path() / ("sciray_vtk_test_" + name);
  std::ofstream(path, std::ios::binary) << text;
  return path.string();
}

}  // namespace

TEST_CASE("VTK .vtu: every encoding reads to the same grid", "[io][vtk]") {
  for (const Encoding& e : xml_encodings) {
    INFO("format " << e.format << (e.appended_base64 ? " base64" : "") << (e.compressed ? ", zlib" : "")
                   << (e.header64 ? ", UInt64 headers" : "") << (e.big_endian ? ", big-endian" : ""));
    const io::UnstructuredGridFile grid = io::read_vtu(write_file("grid.vtu", vtu_text(e)));
    REQUIRE(grid.points.size() == 9);
    CHECK(grid.points[8].z == 2.f);
    CHECK(grid.connectivity == std::vector<std::int64_t>{0, 1, 2, 3, 4, 5, 6, 7, 4, 5, 6, 8});
    CHECK(grid.offsets == std::vector<std::int64_t>{8, 12});
    CHECK(grid.types == std::vector<std::uint8_t>{12, 10});
    REQUIRE(grid.point_arrays.size() == 1);
    CHECK(grid.point_arrays[0].values[8] == 2.0);
    CHECK(grid.default_point_array == "T");
    REQUIRE(grid.cell_arrays.size() == 1);
    CHECK(grid.cell_arrays[0].components == 3);
    // The default field is the Scalars array T = z; "v" is the cells' vector, by its magnitude.
    const Unstructured by_point(io::unstructured_volume(grid, "", "grid.vtu"));
    CHECK(by_point.sample({0.3f, 0.6f, 0.25f}) == Approx(0.25f));
    CHECK(by_point.sample({0.5f, 0.5f, 1.5f}) == Approx(1.5f));
    const Unstructured by_cell(io::unstructured_volume(grid, "v", "grid.vtu"));
    CHECK(by_cell.sample({0.5f, 0.5f, 0.5f}) == 5.f);
    CHECK(by_cell.sample({0.5f, 0.5f, 1.2f}) == 2.f);
  }
}

TEST_CASE("VTK .vtu: the shared finite-element grids", "[io][vtk]") {
  const io::UnstructuredGridFile can = io::read_vtu(SCIRAY_DATA_DIR "/unstructured/can.vtu");  // appended raw, UInt64
  CHECK(can.points.size() == 6724);
  CHECK(can.types.size() == 4800);
  const Unstructured eqps(io::unstructured_volume(can, "EQPS", "can.vtu"));
  CHECK(eqps.cell_count() == 4800);
  // The crushed can: some elements fold over themselves, and are kept.
  CHECK(eqps.folded_cells() == 51);
  const io::UnstructuredGridFile jaw = io::read_vtu(SCIRAY_DATA_DIR "/unstructured/kiefer_jaw.vtu");  // zlib, base64
  CHECK(jaw.points.size() == 102578);
  const Unstructured stress(io::unstructured_volume(jaw, "", "kiefer_jaw.vtu"));  // quadratic tetrahedra
  CHECK(stress.cell_count() == 56786);
  // The file's own RangeMin and RangeMax of the stress.
  CHECK(stress.value_range()[0] == Approx(0.014035f));
  CHECK(stress.value_range()[1] == Approx(23.269f));
  const io::UnstructuredGridFile notch = io::read_vtu(SCIRAY_DATA_DIR "/unstructured/notch_disp.vtu");
  const Unstructured displacement(io::unstructured_volume(notch, "Nodal Displacement", "notch_disp.vtu"));
  CHECK(displacement.cell_count() == 2192);  // quadratic hexahedra and wedges, by their corners
}

TEST_CASE("VTK .vtu: bad files are named", "[io][vtk][errors]") {
  const auto error_of = [](const std::function<void()>& f) {
    try {
      f();
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const std::string good = vtu_text({"appended"});
  const std::string truncated = write_file("truncated.vtu", good.substr(0, good.size() - 60) + "</AppendedData></VTKFile>");
  CHECK_THAT(error_of([&] { io::read_vtu(truncated); }),
             Catch::Contains("truncated.vtu: DataArray 'connectivity': the data block is truncated (64 bytes, 96 needed)"));
  const std::string not_xml = write_file("not_xml.vtu", "<VTKFile type=\"UnstructuredGrid\"><Unstructured");
  CHECK_THAT(error_of([&] { io::read_vtu(not_xml); }), Catch::Contains("not_xml.vtu: not valid XML"));
  std::string wrong_type = vtu_text({"ascii"});
  wrong_type.replace(wrong_type.find("Float32"), 7, "Float16");
  CHECK_THAT(error_of([&] { io::read_vtu(write_file("wrong_type.vtu", wrong_type)); }),
             Catch::Contains("DataArray 'Points': unknown type 'Float16'"));
  std::string bad_offset = vtu_text({"ascii"});
  bad_offset.replace(bad_offset.find("\n8 12"), 5, "\n8 13");
  CHECK_THAT(error_of([&] { io::read_vtu(write_file("bad_offset.vtu", bad_offset)); }),
             Catch::Contains("cell 1: offset 13 is outside [8, 12]"));
  const io::UnstructuredGridFile grid = io::read_vtu(write_file("grid.vtu", good));
  CHECK(error_of([&] { io::unstructured_volume(grid, "pressure", "grid.vtu"); }) ==
        "grid.vtu: has no array 'pressure' (its arrays: 'T', 'v')");
  io::UnstructuredGridFile surface = grid;
  surface.types[1] = 5;  // a triangle
  CHECK(error_of([&] { io::unstructured_volume(surface, "", "grid.vtu"); }) ==
        "grid.vtu: cell 1 has VTK type 5, which is not a volume cell (tetrahedra, voxels, hexahedra, wedges, pyramids "
        "and their quadratic forms are)");
  std::string dangling = vtu_text({"ascii"});
  dangling.replace(dangling.find("4 5 6 8 "), 8, "4 5 6 9 ");  // the tetrahedron's apex, one past the last point
  CHECK_THAT(error_of([&] { io::read_vtu(write_file("dangling.vtu", dangling)); }),
             Catch::Contains("dangling.vtu: Cells 'connectivity' value 11 refers to point 9, but there are 9 points"));
  // A coordinate beyond float's range would become infinite.
  std::string far = vtu_text({"ascii"});
  far.replace(far.find("0.500000 0.500000 2.000000"), 26, "0.500000 1e300 2.000000");
  CHECK_THAT(error_of([&] { io::read_vtu(write_file("far.vtu", far)); }),
             Catch::Contains("far.vtu: Points: point 8 is (0.5, 1e+300, 2), not finite as a float"));
  CHECK_THAT(error_of([&] { io::read_vtu("/nonexistent.vtu"); }), Catch::Contains("/nonexistent.vtu: cannot open file"));
}
