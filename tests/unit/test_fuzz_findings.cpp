// Reproducers of what fuzzing the file readers and the C API found (fuzz/, scripts/fuzz.sh; the
// C API's are in test_c_api.cpp), and of what
// reading the readers alongside found and the fuzz targets' sanitizers confirmed: each input
// once read out of bounds, was undefined behaviour or became wrong data silently; now each
// is refused with a sciray::Error that names the file and what is wrong (or, where the
// input is valid, read correctly).
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <catch2/catch.hpp>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <span>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

#include "sciray/accel/trace.hpp"
#include "sciray/geometry/isosurface_grid.hpp"
#include "sciray/geometry/triangle_mesh.hpp"
#include "sciray/io/obj.hpp"
#include "sciray/io/pdb.hpp"
#include "sciray/io/points.hpp"
#include "sciray/io/volume.hpp"
#include "sciray/io/vtk.hpp"
#include "sciray/render/camera.hpp"
#include "sciray/scene/world.hpp"
#include "sciray/volume/macrocells.hpp"
#include "sciray/volume/particle.hpp"
#include "sciray/volume/structured_regular.hpp"

// The sciray tool's JSON readers (examples/sciray is not on the tests' include path).
#include "../../examples/sciray/shading_json.hpp"
#include "../../examples/sciray/volume_scene.hpp"

namespace {

using Catch::Contains;
namespace fs = std::filesystem;

/// A folder of this process's own for the readers that take a path, removed at exit.
struct TempFolder {
  fs::path path = fs::temp_directory_path() / ("sciray-fuzz-findings-" + std::to_string(::getpid()));
  TempFolder() { fs::create_directories(path); }
  ~TempFolder() {
    std::error_code ignored;
    fs::remove_all(path, ignored);
  }
};

/// Writes `bytes` to `name` in the TempFolder and returns its path.
fs::path write_temp(const std::string& name, std::string_view bytes) {
  static const TempFolder folder;
  const fs::path path = folder.path / name;
  std::ofstream(path, std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  return path;
}

/// A .vtu of one point whose Points array is the first block of raw appended data `appended`
/// (zlib-compressed, UInt64 headers), and no cells.
std::string vtu_with_appended(std::string_view appended) {
  return std::string(
             "<VTKFile type=\"UnstructuredGrid\" header_type=\"UInt64\" compressor=\"vtkZLibDataCompressor\">"
             "<UnstructuredGrid><Piece NumberOfPoints=\"1\" NumberOfCells=\"0\"><Points>"
             "<DataArray type=\"Float32\" NumberOfComponents=\"3\" format=\"appended\" offset=\"0\"/>"
             "</Points></Piece></UnstructuredGrid><AppendedData encoding=\"raw\">_") +
         std::string(appended) + "</AppendedData></VTKFile>";
}

/// A .vtu of one tetrahedron whose connectivity and types arrays are the ASCII `connectivity`, `types`.
std::string vtu_tetrahedron(const std::string& connectivity, const std::string& types) {
  return "<VTKFile type=\"UnstructuredGrid\"><UnstructuredGrid><Piece NumberOfPoints=\"4\" NumberOfCells=\"1\">"
         "<PointData><DataArray type=\"Float32\" Name=\"s\">0 1 2 3</DataArray></PointData>"
         "<Points><DataArray type=\"Float32\" NumberOfComponents=\"3\">0 0 0 1 0 0 0 1 0 0 0 1</DataArray></Points>"
         "<Cells><DataArray type=\"Float64\" Name=\"connectivity\">" +
         connectivity +
         "</DataArray>"
         "<DataArray type=\"Int64\" Name=\"offsets\">4</DataArray>"
         "<DataArray type=\"Float64\" Name=\"types\">" +
         types + "</DataArray></Cells></Piece></UnstructuredGrid></VTKFile>";
}

std::span<const std::byte> bytes_of(std::string_view text) {
  return std::as_bytes(std::span(text.data(), text.size()));
}

}  // namespace

TEST_CASE("fuzz: an empty .f32xyzr file is an empty cloud, which to_spheres refuses by name", "[fuzz][points]") {
  // Found by fuzz_points (UBSan): parse_f32xyzr offset the empty arrays' null data.
  const sciray::io::PointCloud cloud = sciray::io::parse_points({}, "empty.f32xyzr");
  REQUIRE(cloud.count() == 0);
  REQUIRE_THROWS_WITH(sciray::io::to_spheres(cloud), Contains("empty.f32xyzr") && Contains("no points"));
}

TEST_CASE("fuzz: a PLY point cloud of 0 vertices is an empty cloud", "[fuzz][points]") {
  // Found next to the above (UBSan in fuzz_points): plan_vertices offset the empty positions' null data.
  const std::string_view ply =
      "ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\nproperty float z\n"
      "property float intensity\nend_header\n";
  const sciray::io::PointCloud cloud = sciray::io::parse_points(bytes_of(ply), "none.ply");
  REQUIRE(cloud.count() == 0);
  REQUIRE_THROWS_WITH(sciray::io::to_spheres(cloud), Contains("none.ply") && Contains("no points"));
}

TEST_CASE("fuzz: a .vtu zlib header counting 2^61 blocks is refused, not read past", "[fuzz][vtk]") {
  // Found reading payload() (ASan in fuzz_vtu: heap-buffer-overflow): (3 + blocks) * 8
  // wrapped to 24, so the check passed and block sizes were read past the header's end.
  const std::string header(
      "\x00\x00\x00\x00\x00\x00\x00\x20"  // 2^61 blocks
      "\x10\x00\x00\x00\x00\x00\x00\x00"  // of 16 bytes
      "\x10\x00\x00\x00\x00\x00\x00\x00"  // the last one too
      "\x00\x00\x00\x00\x00\x00\x00\x00",
      32);
  const fs::path path = write_temp("blocks.vtu", vtu_with_appended(header));
  REQUIRE_THROWS_WITH(sciray::io::read_vtu(path.string()),
                      Contains("blocks.vtu") && Contains("2305843009213693952 zlib blocks, more than its"));
  fs::remove(path);
}

TEST_CASE("fuzz: .vtu zlib block sizes that add up past 2^64 are refused", "[fuzz][vtk]") {
  // Found next to the above: sizes 2^64-1 and 2 summed to 1, so zlib was handed 2^64-1
  // bytes of a 1-byte buffer (zlib is not instrumented, so ASan could not see it read past).
  const std::string header(
      "\x02\x00\x00\x00\x00\x00\x00\x00"  // 2 blocks
      "\x0c\x00\x00\x00\x00\x00\x00\x00"  // of 12 bytes
      "\x0c\x00\x00\x00\x00\x00\x00\x00"
      "\xff\xff\xff\xff\xff\xff\xff\xff"  // compressed: 2^64-1
      "\x02\x00\x00\x00\x00\x00\x00\x00"  // and 2 bytes
      "x",
      41);
  const fs::path path = write_temp("sizes.vtu", vtu_with_appended(header));
  REQUIRE_THROWS_WITH(sciray::io::read_vtu(path.string()),
                      Contains("sizes.vtu") && Contains("sizes add up to more than 64 bits hold"));
  fs::remove(path);
}

TEST_CASE("fuzz: .vtu cell types and indices beyond their integer types are refused", "[fuzz][vtk]") {
  // Found reading read_vtu (UBSan in fuzz_vtu): converting the double 300 to a byte, or
  // 1e300 to an int64, was undefined behaviour; 3.5 was truncated to 3 silently.
  const fs::path path = write_temp("cells.vtu", vtu_tetrahedron("0 1 2 3", "300"));
  REQUIRE_THROWS_WITH(sciray::io::read_vtu(path.string()),
                      Contains("cells.vtu") && Contains("Cells 'types' value 0 is 300, not a VTK cell type"));
  std::ofstream(path, std::ios::binary) << vtu_tetrahedron("0 1 2 1e300", "10");
  REQUIRE_THROWS_WITH(sciray::io::read_vtu(path.string()),
                      Contains("cells.vtu") && Contains("Cells 'connectivity' value 3 is 1e+300, not an index"));
  std::ofstream(path, std::ios::binary) << vtu_tetrahedron("0 1 2 3.5", "10.5");
  REQUIRE_THROWS_WITH(sciray::io::read_vtu(path.string()), Contains("value 3 is 3.5, not an index"));
  // The same grid with whole numbers (in a Float64 array) reads.
  std::ofstream(path, std::ios::binary) << vtu_tetrahedron("0 1 2 3", "10");
  const sciray::io::UnstructuredGridFile grid = sciray::io::read_vtu(path.string());
  CHECK(grid.connectivity == std::vector<std::int64_t>{0, 1, 2, 3});
  CHECK(grid.types == std::vector<std::uint8_t>{10});
  fs::remove(path);
}

TEST_CASE("fuzz: a raw volume's sidecar origin or range beyond float's range is refused", "[fuzz][volume]") {
  // Found reading read_sidecar while fuzzing read_volume: 1e300 passed as "finite" and
  // became an infinite float origin or range, silently.
  const fs::path raw = write_temp("big.raw", std::string(8, '\0'));
  const fs::path sidecar = write_temp("big.json", R"({"dims": [2, 2, 2], "type": "uint8", "origin": [0, 1e300, 0]})");
  REQUIRE_THROWS_WITH(sciray::io::read_volume(raw), Contains("big.json: 'origin' value 1e+300 does not fit a float"));
  write_temp("big.json", R"({"dims": [2, 2, 2], "type": "uint8", "range": [-1e39, 0]})");
  REQUIRE_THROWS_WITH(sciray::io::read_volume(raw), Contains("big.json: 'range' value -1e+39 does not fit a float"));
  write_temp("big.json", R"({"dims": [2, 2, 2], "type": "uint8", "spacing": [1, 1e39, 1]})");
  REQUIRE_THROWS_WITH(sciray::io::read_volume(raw),
                      Contains("big.json: 'spacing' must be an array of 3 positive numbers"));
  // At float's limits the values still read.
  write_temp("big.json", R"({"dims": [2, 2, 2], "type": "uint8", "origin": [0, -3.4e38, 0], "range": [0, 3.4e38]})");
  const sciray::io::VolumeFile volume = sciray::io::read_volume(raw);
  CHECK(volume.grid.origin[1] == -3.4e38f);
  CHECK(volume.range == std::array<float, 2>{0.f, 3.4e38f});
  fs::remove(raw), fs::remove(sidecar);
}

TEST_CASE("fuzz: PDB atoms at coordinates like 1e30 still get their distance bonds", "[fuzz][pdb]") {
  // Found reading add_distance_bonds (UBSan in fuzz_pdb): the grid cell of x = 1e30,
  // converted to int64, was undefined behaviour.
  const std::string text =
      "ATOM      1  C   ALA A   1       0.000   0.000   0.000  1.00  0.00           C\n"
      "ATOM      2  C   ALA A   1       1.500   0.000   0.000  1.00  0.00           C\n"
      "ATOM      3  C   ALA A   1        1e30   0.000   0.000  1.00  0.00           C\n"
      "ATOM      4  C   ALA A   1        1e30   1.000  -1e30  1.00  0.00           C\n"
      "ATOM      5  C   ALA A   1        1e30   1.000  -1e30  1.00  0.00           C\n";
  const sciray::io::Molecule molecule = sciray::io::parse_pdb(text, "far.pdb");
  REQUIRE(molecule.atoms.size() == 5);
  CHECK(molecule.atoms[2].position.x == 1e30f);
  // Atoms 4 and 5 coincide (closer than 0.4 A: no bond); the far ones bond to no near one.
  CHECK(molecule.bonds == std::vector<std::array<std::uint32_t, 2>>{{0, 1}});
}

TEST_CASE("fuzz: an .obj naming a library too long for the file system says it cannot open it", "[fuzz][obj]") {
  // Found by fuzz_obj: std::filesystem::exists threw filesystem_error (File name too long)
  // out of read_obj instead of a sciray::Error.
  const std::string name(300, 'm');
  const fs::path path = write_temp("long.obj", "mtllib " + name + ".mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  REQUIRE_THROWS_WITH(sciray::io::read_obj(path), Contains("long.obj: line 1: mtllib '" + name + ".mtl': cannot open"));
  write_temp("long.obj", "mtllib f.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl m\nf 1 2 3\n");
  write_temp("f.mtl", "newmtl m\nmap_Kd " + name + ".png\n");
  REQUIRE_THROWS_WITH(sciray::io::read_obj(path), Contains("f.mtl") && Contains("cannot open"));
  fs::remove(path);
}

TEST_CASE("fuzz: the tool's JSON with a number beyond double is invalid JSON, named", "[fuzz][tool]") {
  // Found by fuzz_transfer_function: nlohmann throws out_of_range (406), not parse_error, for
  // 1e400, and it escaped read_transfer_function (and parse_json_argument, read_camera).
  const fs::path tf = write_temp("tf.json", R"({"colors": [[0, 0, 1e400]], "opacities": [1]})");
  REQUIRE_THROWS_WITH(sciray_tool::read_transfer_function(tf.string(), {0.f, 1.f}),
                      Contains("tf.json: invalid JSON") && Contains("number overflow"));
  REQUIRE_THROWS_WITH(sciray_tool::parse_json_argument(R"({"type": "obj", "kd": 1e400})", "--material"),
                      Contains("--material: invalid JSON") && Contains("number overflow"));
  // The transfer function's own checks now name the file too.
  write_temp("tf.json", R"({"colors": [[-1, 0, 0]], "opacities": [1]})");
  REQUIRE_THROWS_WITH(sciray_tool::read_transfer_function(tf.string(), {0.f, 1.f}),
                      Contains("tf.json: transferFunction: 'color' 0 must be finite and not negative"));
  fs::remove(tf);
}

TEST_CASE("fuzz: the tool's JSON numbers beyond float's range are refused, named", "[fuzz][tool]") {
  // 1e300 parses as a double; nlohmann's get<float>() made it an infinity (an undefined
  // conversion), which reached the scene silently.
  const fs::path tf = write_temp("tf.json", R"({"colors": [[0, 0, 1]], "opacities": [1], "range": [0, 1e300]})");
  REQUIRE_THROWS_WITH(sciray_tool::read_transfer_function(tf.string(), {0.f, 1.f}),
                      Contains("tf.json: \"range\": 1e+300 does not fit a float"));
  const auto material = [](const std::string& text) {
    return sciray_tool::material_from_json(sciray_tool::parse_json_argument(text, "--material"), "--material");
  };
  REQUIRE_THROWS_WITH(material(R"({"type": "obj", "ns": -1e300})"),
                      Contains("--material: \"ns\": -1e+300 does not fit a float"));
  REQUIRE_THROWS_WITH(material(R"({"type": "obj", "kd": [0, 1e39, 0]})"),
                      Contains("--material: \"kd\": 1e+39 does not fit a float"));
  // The largest float still fits.
  write_temp("tf.json", R"({"colors": [[0, 0, 1]], "opacities": [1], "range": [0, 3.4028234e38]})");
  CHECK(sciray_tool::read_transfer_function(tf.string(), {0.f, 1.f}).value_range()[1] ==
        std::numeric_limits<float>::max());
  fs::remove(tf);
}

#ifdef SCIRAY_TOOL
TEST_CASE("fuzz: a camera file with a number beyond double or float is refused, named", "[fuzz][tool]") {
  // read_camera is the tool's own (main.cpp): run the tool.
  const auto tool_output = [](const std::string& camera_json) {
    const fs::path camera = write_temp("camera.json", camera_json);
    const std::string command = std::string(SCIRAY_TOOL) + " render --size 8x8 --camera " + camera.string() + " 2>&1";
    FILE* pipe = popen(command.c_str(), "r");
    REQUIRE(pipe);
    std::string output;
    char buffer[4096];
    while (const std::size_t n = std::fread(buffer, 1, sizeof buffer, pipe)) output.append(buffer, n);
    const int status = pclose(pipe);
    INFO(output);
    CHECK(WIFEXITED(status));
    CHECK(WEXITSTATUS(status) == 1);
    fs::remove(camera);
    return output;
  };
  CHECK_THAT(tool_output(R"({"position": [0, 0, 1e400], "look_at": [0, 0, 0]})"),
             Contains("camera.json: invalid JSON") && Contains("number overflow"));
  CHECK_THAT(tool_output(R"({"position": [0, 0, 1e300], "look_at": [0, 0, 0]})"),
             Contains("camera.json: \"position\": 1e+300 does not fit a float"));
  CHECK_THAT(tool_output(R"({"position": [0, 0, 5], "look_at": [0, 0, 0], "fovy": 1e39})"),
             Contains("camera.json: \"fovy\": 1e+39 does not fit a float"));
}
#endif

// From the C API target: a particle volume whose particles are tiny against its box asked
// for more macrocells than any integer holds; the float was converted to one (undefined,
// INT64_MIN here, so one macrocell where 128 were due), and so were cell positions.
TEST_CASE("fuzz: macrocells over a box 1e36 cells wide are 128 a side, and far boxes land in the last", "[fuzz][volume]") {
  const sciray::Box3f box{{0.f, 0.f, 0.f}, {1e30f, 1.f, 1.f}};
  const sciray::MacrocellGrid grid = sciray::MacrocellGrid::over(box, 1e-6f, 4);
  CHECK(grid.counts == std::array<std::int64_t, 3>{128, 128, 128});
  std::vector<float> ranges = grid.empty_ranges();
  grid.widen({{9e29f, 0.f, 0.f}, {1e38f, 0.f, 0.f}}, 0.25f, 0.75f, ranges);
  CHECK(ranges[2 * grid.index(127, 0, 0)] == 0.25f);
  CHECK(ranges[2 * grid.index(127, 0, 0) + 1] == 0.75f);
  CHECK(ranges[2 * grid.index(115, 0, 0)] == 0.25f);  // 9e29 / (1e30 / 128) = 115.2
  CHECK(ranges[2 * grid.index(114, 0, 0)] > 1.f);     // untouched: +inf
  const float nan = std::numeric_limits<float>::quiet_NaN();
  CHECK(sciray::MacrocellGrid::over({{0.f, 0.f, 0.f}, {nan, 1.f, 1.f}}, 1.f, 4).counts[0] == 1);
}

// From the C API target: particles far from the origin. A macrocell index is the offset of a
// particle's support edge, padded by 1e-6 of the box's largest coordinate, over the
// macrocell size; with particles at x = ±1e30 of radius 1 that is about 5e24 along y, beyond
// any integer, and it was converted to one (undefined: INT64_MIN here, so no macrocell was
// widened and empty space skipping stepped over the particles). Found with it: particles
// whose box is wider than a float holds made infinite macrocells.
TEST_CASE("fuzz: particles far from the origin widen their macrocells, and boxes wider than a float are refused",
          "[fuzz][volume]") {
  sciray::ParticleData d;
  d.positions = {{-1e30f, 0.f, 0.f}, {1e30f, 0.f, 0.f}};
  d.radii = {1.f, 1.f};
  const sciray::Particles particles(d);
  const sciray::MacrocellGrid grid = particles.macrocell_grid(4);
  REQUIRE(grid.counts[0] > 1);
  std::vector<float> ranges = grid.empty_ranges();
  particles.widen_macrocell_ranges(grid, 4, ranges);
  const auto peak_at_x = [&](std::int64_t x) {
    float peak = 0.f;
    for (std::int64_t z = 0; z < grid.counts[2]; ++z)
      for (std::int64_t y = 0; y < grid.counts[1]; ++y) peak = std::max(peak, ranges[2 * grid.index(x, y, z) + 1]);
    return peak;
  };
  CHECK(peak_at_x(0) >= 1.f);  // each particle's weight, 1, reaches the macrocells at its end
  CHECK(peak_at_x(grid.counts[0] - 1) >= 1.f);

  d.positions = {{-3e38f, 0.f, 0.f}, {3e38f, 0.f, 0.f}};
  REQUIRE_THROWS_WITH(sciray::Particles(d), Contains("particle volume: the particles' supports span [-3e+38, 3e+38] "
                                                     "along x, wider than a float holds"));
}

// From the C API target: a camera at x = 3.4e38 sent the path tracer's rays to Embree, whose
// traversal asserts on coordinates beyond 1.8e18: an abort in Debian's build of Embree.
TEST_CASE("fuzz: rays beyond Embree's range miss instead of aborting, and a camera that far is refused",
          "[fuzz][accel]") {
  sciray::accel::Device device;
  sciray::World<sciray::TriangleMesh> world(device);
  sciray::MeshData square;
  square.positions = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
  square.indices = {0, 1, 2, 0, 2, 3};
  world.add(sciray::TriangleMesh(std::move(square)));
  world.commit();

  using A = xsimd::sse2;
  using F = sciray::simd::Float<A>;
  const float huge = 3.4e38f, nan = std::numeric_limits<float>::quiet_NaN();
  sciray::Ray<F> rays;  // lanes 0 and 2 look down at the square; 1 starts at x = 3.4e38, 3 at z = NaN
  rays.org = {F{0.5f, huge, 0.5f, 0.5f}, F(0.5f), F{1.f, 1.f, 1.f, nan}};
  rays.dir = {F(0.f), F(0.f), F(-1.f)};
  const auto all_lanes = F(0.f) == F(0.f);
  const auto hit = sciray::accel::intersect<A>(world.scene(), rays, all_lanes).hit;
  const auto blocked = sciray::accel::occluded<A>(world.scene(), rays, all_lanes);
  for (int lane = 0; lane < 4; ++lane) {
    INFO("lane " << lane);
    CHECK(sciray::simd::lane(hit, lane) == (lane % 2 == 0));
    CHECK(sciray::simd::lane(blocked, lane) == (lane % 2 == 0));
  }
  sciray::Ray<float> far_ray;
  far_ray.org = {huge, 0.5f, 1.f};
  far_ray.dir = {0.f, 0.f, -1.f};
  CHECK_FALSE(sciray::accel::intersect<sciray::simd::scalar>(world.scene(), far_ray, true).hit);

  CHECK_THROWS_WITH(sciray::detail::view_basis("perspective", {huge, -3.5f, 4.f}, {0.f, 0.f, -1.f}, {0.f, 1.f, 0.f}, 1.f),
                    Contains("'position' has a coordinate of magnitude 3.4e+38, beyond 1.8e18"));
}

// From the C API target: an AO ray along a cell face of an isosurface's macrocell entered it
// at a NaN position (0 × ∞ in o + d·t), which the cell walk converted to an integer
// (undefined behaviour, which GCC reports with -fsanitize=float-cast-overflow: not part of
// its -fsanitize=undefined, so scripts/sanitize.sh address adds it; clang's includes it).
// This ray reaches the same arithmetic: it starts outside the box along x with a direction
// of 1e-39 there, so it enters at t = ∞, where y and z (direction 0) are NaN.
TEST_CASE("fuzz: an exact isosurface's cell walk from a NaN entry point finds nothing", "[fuzz][isosurface]") {
  auto voxels = std::make_shared<std::vector<float>>(27);
  for (std::size_t i = 0; i < voxels->size(); ++i) (*voxels)[i] = static_cast<float>(i % 4) / 4.f;
  const auto volume = std::make_shared<const sciray::StructuredRegular<float>>(
      sciray::LinearLayout<float>(voxels->data(), {3, 3, 3}, voxels), sciray::VolumeGrid{});
  const sciray::GridIsosurface isosurface(volume, {0.5f});
  REQUIRE(isosurface.primitive_count() == 1);
  sciray::Ray<float> ray;
  ray.org = {-1.f, 1.f, 1.f};
  ray.dir = {1e-39f, 0.f, 0.f};
  CHECK_FALSE(isosurface.first_crossing(ray, 0).hit);
}
