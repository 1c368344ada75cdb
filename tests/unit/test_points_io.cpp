// The point-cloud readers (io/points.hpp): PLY vertices in the three encodings and every
// scalar type, .xyz, .xyzr and .f32xyzr files, spheres made of them (radius, colours by a
// property or the file's own), and every error message.
#include <bit>
#include <catch2/catch.hpp>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "sciray/io/ply.hpp"
#include "sciray/io/points.hpp"
#include "sciray/testing/scenes.hpp"
#include "support/temp_dir.hpp"

using sciray_test::TempDir;
namespace {

using Catch::Contains;
using sciray::SphereData;
using sciray::Vec3f;
using sciray::io::PointCloud;
using sciray::io::PointOptions;
using sciray::io::read_points;
using sciray::io::to_spheres;
namespace fs = std::filesystem;


template <class T>
void append_binary(std::string& out, double value, bool big_endian) {
  const auto bits = std::bit_cast<sciray::io::ply_detail::UnsignedOfSize<T>>(static_cast<T>(value));
  for (std::size_t i = 0; i < sizeof(T); ++i)
    out.push_back(static_cast<char>((bits >> (8 * (big_endian ? sizeof(T) - 1 - i : i))) & 0xff));
}

/// One value of PLY type `type` (a name as sciray spells it: int8 ... float64).
void append_value(std::string& out, const std::string& type, double value, const std::string& format) {
  if (format == "ascii") {
    char text[64];
    const auto end = type == "float32"   ? std::to_chars(text, text + 64, static_cast<float>(value)).ptr
                     : type == "float64" ? std::to_chars(text, text + 64, value).ptr
                                         : std::to_chars(text, text + 64, static_cast<long long>(value)).ptr;
    out.append(text, end);
    out.push_back(' ');
    return;
  }
  const bool big = format == "binary_big_endian";
  if (type == "int8")
    append_binary<std::int8_t>(out, value, big);
  else if (type == "uint8")
    append_binary<std::uint8_t>(out, value, big);
  else if (type == "int16")
    append_binary<std::int16_t>(out, value, big);
  else if (type == "uint16")
    append_binary<std::uint16_t>(out, value, big);
  else if (type == "int32")
    append_binary<std::int32_t>(out, value, big);
  else if (type == "uint32")
    append_binary<std::uint32_t>(out, value, big);
  else if (type == "float32")
    append_binary<float>(out, value, big);
  else
    append_binary<double>(out, value, big);
}

/// A PLY file of one vertex element: `properties` as "type name" (a "list" type is a uchar
/// count then uint8 items; its row value is the count, the items are 7), the rows in order,
/// and `more_header` (e.g. an empty face element) after the vertex element.
std::string make_ply(const std::string& format, const std::vector<std::string>& properties,
                     const std::vector<std::vector<double>>& rows, const std::string& more_header = "") {
  std::string out = "ply\nformat " + format + " 1.0\ncomment written by test_points_io\nelement vertex ";
  out += std::to_string(rows.size()) + "\n";
  for (const std::string& property : properties)
    out += property.starts_with("list ") ? "property list uchar uint8 " + property.substr(5) + "\n"
                                         : "property " + property + "\n";
  out += more_header + "end_header\n";
  for (const std::vector<double>& row : rows) {
    for (std::size_t p = 0; p < properties.size(); ++p) {
      const std::string type = properties[p].substr(0, properties[p].find(' '));
      if (type != "list") {
        append_value(out, type, row.at(p), format);
        continue;
      }
      append_value(out, "uint8", row.at(p), format);
      for (int item = 0; item < static_cast<int>(row.at(p)); ++item) append_value(out, "uint8", 7, format);
    }
    if (format == "ascii") out.back() = '\n';
  }
  return out;
}

std::string f32_records(const std::vector<float>& values) {
  std::string out;
  for (float v : values) append_binary<float>(out, v, false);
  return out;
}

std::vector<float> as_vector(const sciray::PaddedVector<float>& values) {
  return {values.begin(), values.end()};
}

constexpr const char* encodings[] = {"ascii", "binary_little_endian", "binary_big_endian"};

Vec3f gray(float s) {
  return {s, s, s};
}

}  // namespace

TEST_CASE("points: PLY vertices read the same from ascii and both binary byte orders", "[io][points]") {
  const TempDir dir("sciray_test_points_");
  const std::vector<std::string> properties = {"float32 x",       "float32 y",      "float64 z",
                                               "list neighbours", "float64 radius", "uint16 intensity"};
  const std::vector<std::vector<double>> rows = {
      {0.5, -1.25, 3, 2, 0.125, 7}, {1e6, 2, -3e-3, 0, 2, 65535}, {-4, 5.5, 6, 1, 0, 0}};
  for (const char* format : encodings) {
    // An empty face element and another element are skipped, wherever they are.
    const std::string file =
        dir.write(std::string(format) + ".ply", make_ply(format, properties, rows,
                                                         "element face 0\nproperty list uchar int vertex_indices\n"
                                                         "element camera 0\nproperty float view_px\n"));
    INFO(format);
    REQUIRE(sciray::io::is_point_cloud_file(file));
    const PointCloud cloud = read_points(file, {});
    REQUIRE(cloud.count() == 3);
    CHECK(as_vector(cloud.positions) == std::vector<float>{0.5f, -1.25f, 3, 1e6f, 2, -3e-3f, -4, 5.5f, 6});
    CHECK(as_vector(cloud.radii) == std::vector<float>{0.125f, 2, 0});
    REQUIRE(cloud.scalars.size() == 1);  // the list is not a scalar
    CHECK(cloud.scalars[0].name == "intensity");
    CHECK(cloud.scalars[0].type == "uint16");
    CHECK(as_vector(cloud.scalars[0].values) == std::vector<float>{7, 65535, 0});
    CHECK(cloud.property_names() == std::vector<std::string>{"x", "y", "z", "radius", "intensity"});
  }
}

TEST_CASE("points: every PLY scalar type, as coordinates and as properties", "[io][points]") {
  const TempDir dir("sciray_test_points_");
  const std::vector<std::string> types = {"int8", "uint8", "int16", "uint16", "int32", "uint32", "float32", "float64"};
  const std::vector<std::vector<double>> extremes = {
      {-128, 127},       {0, 255},          {-32768, 32767}, {0, 65535}, {-2147483648.0, 2147483647.0},
      {0, 4294967295.0}, {-1.5f, 3.25e38f}, {-2.5, 1e300}};
  for (const char* format : encodings)
    for (std::size_t t = 0; t < types.size(); ++t) {
      // Coordinates of this type (small values), and a property of it at both ends of its range.
      std::vector<std::string> properties = {types[t] + " x", types[t] + " y", types[t] + " z", types[t] + " value"};
      const std::string file =
          dir.write("types.ply", make_ply(format, properties, {{1, 2, 3, extremes[t][0]}, {4, 5, 6, extremes[t][1]}}));
      INFO(format << " " << types[t]);
      const PointCloud cloud = read_points(file);
      CHECK(as_vector(cloud.positions) == std::vector<float>{1, 2, 3, 4, 5, 6});
      REQUIRE(cloud.scalars.size() == 1);
      CHECK(cloud.scalars[0].type == types[t]);
      CHECK(cloud.scalars[0].values[0] == static_cast<float>(extremes[t][0]));
      CHECK(cloud.scalars[0].values[1] == static_cast<float>(extremes[t][1]));  // 1e300 becomes +inf
    }
}

TEST_CASE("points: .xyz, .xyzr and .f32xyzr files", "[io][points]") {
  const TempDir dir("sciray_test_points_");
  const PointCloud xyz =
      read_points(dir.write("a.xyz", "# x y z\n\n1 2 3\r\n  +4.5\t-5e-1 6   # a comment\n\n  # another\n7 8 9"));
  CHECK(as_vector(xyz.positions) == std::vector<float>{1, 2, 3, 4.5f, -0.5f, 6, 7, 8, 9});
  CHECK(xyz.radii.empty());
  CHECK(xyz.scalars.empty());

  const PointCloud xyzr = read_points(dir.write("a.XYZR", "1 2 3 0.5\n4 5 6 0\n1e-50 1 1 2\n"));
  CHECK(as_vector(xyzr.positions) == std::vector<float>{1, 2, 3, 4, 5, 6, 0, 1, 1});
  CHECK(as_vector(xyzr.radii) == std::vector<float>{0.5f, 0, 2});
  CHECK(xyzr.property_names() == std::vector<std::string>{"x", "y", "z", "radius"});

  const PointCloud raw = read_points(dir.write("a.f32xyzr", f32_records({1, 2, 3, 0.25f, -1, -2, -3, 4})));
  CHECK(as_vector(raw.positions) == std::vector<float>{1, 2, 3, -1, -2, -3});
  CHECK(as_vector(raw.radii) == std::vector<float>{0.25f, 4});
  CHECK(read_points(dir.write("empty.f32xyzr", "")).count() == 0);

  // The format may be given instead of taken from the extension.
  PointOptions options;
  options.format = sciray::io::PointFormat::xyzr;
  CHECK(read_points(dir.write("points.txt", "1 2 3 4\n"), options).radii.size() == 1);
  CHECK(sciray::io::is_point_cloud_file(dir.write("b.xyz", "")));
  CHECK_FALSE(sciray::io::is_point_cloud_file(dir.write("b.obj", "")));
}

TEST_CASE("points: a real mesh's vertices, and is_point_cloud_file tells meshes apart", "[io][points]") {
  const std::string bunny = std::string(SCIRAY_DATA_DIR) + "/meshes/bunny.ply";
  const PointCloud cloud = read_points(bunny);
  const sciray::MeshData mesh = sciray::io::read_ply(bunny);
  CHECK(cloud.count() == 35947);
  CHECK(cloud.positions == mesh.positions);
  CHECK(cloud.property_names() == std::vector<std::string>{"x", "y", "z", "confidence", "intensity"});
  CHECK_FALSE(sciray::io::is_point_cloud_file(bunny));  // it has faces
  CHECK_FALSE(sciray::io::is_point_cloud_file("/nonexistent/sciray/points.ply"));
}

TEST_CASE("points: spheres coloured by a property through the colour map", "[io][points]") {
  const TempDir dir("sciray_test_points_");
  const std::string file = dir.write(
      "c.ply", make_ply("binary_little_endian", {"float32 x", "float32 y", "float32 z", "float32 temperature"},
                        {{0, 0, 0, 10}, {1, 0, 0, 30}, {0, 1, 0, 20}, {0, 0, 1, NAN}}));
  PointOptions options;
  options.color_by = "temperature";
  options.radius = 0.5f;
  const SphereData spheres = to_spheres(read_points(file, options), options, sciray::testing::colormap);
  REQUIRE(spheres.colors.size() == 16);
  CHECK(spheres.radius == 0.5f);
  CHECK(spheres.radii.empty());
  const auto color = [&](std::size_t i) {
    return Vec3f{spheres.colors[4 * i], spheres.colors[4 * i + 1], spheres.colors[4 * i + 2]};
  };
  const auto same = [](Vec3f a, Vec3f b) { return a.x == b.x && a.y == b.y && a.z == b.z; };
  CHECK(same(color(0), sciray::testing::colormap(0.f)));   // the smallest value
  CHECK(same(color(1), sciray::testing::colormap(1.f)));   // the largest
  CHECK(same(color(2), sciray::testing::colormap(0.5f)));  // half way
  CHECK(same(color(3), Vec3f{0.5f, 0.f, 0.f}));            // NaN: VTK's NaN colour
  CHECK(spheres.colors[3] == 1.f);

  // A given range clamps; x, y and z are properties too.
  options.color_by = "x";
  options.range = std::array<double, 2>{0.5, 0.75};
  const SphereData by_x = to_spheres(read_points(file), options, gray);
  CHECK(as_vector(by_x.colors) == std::vector<float>{0, 0, 0, 1, 1, 1, 1, 1, 0, 0, 0, 1, 0, 0, 0, 1});
  const PointCloud cloud = read_points(file);
  CHECK(sciray::io::finite_range(cloud, "temperature") == std::array<double, 2>{10, 30});
  CHECK(sciray::io::finite_range(cloud, "z") == std::array<double, 2>{0, 1});
}

TEST_CASE("points: spheres coloured by the file's own colours", "[io][points]") {
  const TempDir dir("sciray_test_points_");
  const std::vector<std::string> properties = {"float32 x",   "float32 y",  "float32 z",  "uint8 red",
                                               "uint8 green", "uint8 blue", "uint8 alpha"};
  const std::string file = dir.write(
      "rgba.ply", make_ply("binary_big_endian", properties, {{0, 0, 0, 255, 0, 51, 255}, {1, 1, 1, 0, 255, 0, 0}}));
  PointOptions options;
  options.file_colors = true;
  const SphereData spheres = to_spheres(read_points(file), options);
  CHECK(as_vector(spheres.colors) == std::vector<float>{1, 0, 0.2f, 1, 0, 1, 0, 0});

  // Float colours without alpha are opaque, and clamped to [0, 1].
  const std::string floats = dir.write(
      "rgb.ply",
      make_ply("ascii", {"float32 x", "float32 y", "float32 z", "float32 red", "float32 green", "float64 blue"},
               {{0, 0, 0, 0.25, 1.5, -1}}));
  CHECK(as_vector(to_spheres(read_points(floats), options).colors) == std::vector<float>{0.25f, 1, 0, 1});
  const std::string shorts =
      dir.write("rgb16.ply",
                make_ply("ascii", {"float32 x", "float32 y", "float32 z", "uint16 red", "uint16 green", "uint16 blue"},
                         {{0, 0, 0, 65535, 0, 65535}}));
  CHECK(as_vector(to_spheres(read_points(shorts), options).colors) == std::vector<float>{1, 0, 1, 1});
}

TEST_CASE("points: the spheres' radius: the file's, the option, else from the spacing", "[io][points]") {
  const TempDir dir("sciray_test_points_");
  std::string cube, plane;
  for (int i = 0; i < 10; ++i)
    for (int j = 0; j < 10; ++j) {
      plane += std::to_string(i) + " " + std::to_string(j) + " 5\n";
      for (int k = 0; k < 10; ++k) cube += std::to_string(i) + " " + std::to_string(j) + " " + std::to_string(k) + "\n";
    }
  // 1000 points filling a 9x9x9 box: spacing 0.9; 100 filling a 9x9 square: spacing 0.9.
  CHECK(to_spheres(read_points(dir.write("cube.xyz", cube))).radius == Approx(0.18f));
  CHECK(to_spheres(read_points(dir.write("plane.xyz", plane))).radius == Approx(0.18f));
  CHECK(to_spheres(read_points(dir.write("line.xyz", "0 0 0\n2 0 0\n4 0 0\n"))).radius == Approx(0.2f * 4 / 3));
  CHECK(to_spheres(read_points(dir.write("one.xyz", "1 2 3\n"))).radius == 1.f);

  PointOptions options;
  options.radius = 0.05f;
  CHECK(to_spheres(read_points(dir.write("cube.xyz", cube)), options).radius == 0.05f);
  const SphereData own = to_spheres(read_points(dir.write("r.xyzr", "0 0 0 0.5\n1 1 1 0.25\n")), options);
  CHECK(as_vector(own.radii) == std::vector<float>{0.5f, 0.25f});
  CHECK(as_vector(own.positions) == std::vector<float>{0, 0, 0, 1, 1, 1});
  CHECK(own.colors.empty());

  // Radii may come from another PLY property.
  options.radius_property = "size";
  const std::string sized = dir.write(
      "size.ply",
      make_ply("ascii", {"float32 x", "float32 y", "float32 z", "uint8 size", "float32 radius"}, {{0, 0, 0, 3, 9}}));
  const PointCloud cloud = read_points(sized, options);
  CHECK(cloud.property_names() == std::vector<std::string>{"x", "y", "z", "size", "radius"});
  CHECK(as_vector(to_spheres(read_points(sized, options), options).radii) == std::vector<float>{3});
}

TEST_CASE("points: radii scaled by a property, (value / median)^exponent", "[io][points]") {
  const TempDir dir("sciray_test_points_");
  const std::string file = dir.write(
      "lum.ply", make_ply("ascii", {"float32 x", "float32 y", "float32 z", "float32 lum"},
                          {{0, 0, 0, 1}, {1, 0, 0, 16}, {2, 0, 0, 81}}));
  PointOptions options;
  options.radius = 0.5f;
  options.radius_by = "lum";
  options.radius_exponent = 0.25f;
  // The median (16) keeps the radius; 1 and 81 are a half and one and a half times it.
  CHECK_THAT(as_vector(to_spheres(read_points(file), options).radii),
             Catch::Matchers::Approx(std::vector<float>{0.25f, 0.5f, 0.75f}));
  // With the file's own radii, each is scaled.
  const std::string own = dir.write("r.xyzr", "0 0 0 1\n1 0 0 2\n2 0 0 4\n");
  options.radius_by = "x", options.radius_exponent = 1.f;
  REQUIRE_THROWS_WITH(to_spheres(read_points(own), options),
                      Contains("point 0 has x 0, and a radius needs a positive finite value"));
  options.radius_by = "radius";
  CHECK_THAT(as_vector(to_spheres(read_points(own), options).radii), Catch::Matchers::Approx(std::vector<float>{0.5f, 2, 8}));
  options.radius_by = "brightness";
  REQUIRE_THROWS_WITH(to_spheres(read_points(file), options),
                      Contains("no point property 'brightness' to size the spheres by; the points have x, y, z, lum"));
}

TEST_CASE("points: malformed files give errors that say what is wrong", "[io][points]") {
  const TempDir dir("sciray_test_points_");
  const auto read = [&](const std::string& name, const std::string& contents) {
    return read_points(dir.write(name, contents));
  };
  REQUIRE_THROWS_WITH(read_points("/nonexistent/sciray/p.xyz"), Contains("/nonexistent/sciray/p.xyz: cannot open"));
  REQUIRE_THROWS_WITH(read("p.las", ""), Contains("p.las") && Contains("unknown point file extension '.las'"));

  // Text.
  REQUIRE_THROWS_WITH(read("p.xyz", "1 2 3\n# c\n4 5\n"), Contains("p.xyz: line 3: 2 values, expected 3 (x y z)"));
  REQUIRE_THROWS_WITH(read("p.xyz", "1 2 3 4\n"), Contains("line 1: 4 values, expected 3"));
  REQUIRE_THROWS_WITH(read("p.xyzr", "1 2 3\n"), Contains("line 1: 3 values, expected 4 (x y z r)"));
  REQUIRE_THROWS_WITH(read("p.xyz", "\n1 2 3\n1 two 3\n"), Contains("line 3: 'two' is not a number"));
  REQUIRE_THROWS_WITH(read("p.xyz", "1 2 3\n1 2 3,\n"), Contains("line 2: '3,' is not a number"));
  REQUIRE_THROWS_WITH(read("p.xyz", "1 2 3\n1 nan 3\n"),
                      Contains("line 2, point 1: coordinates (1, nan, 3) are not finite"));
  REQUIRE_THROWS_WITH(read("p.xyz", "1 2 1e39\n"), Contains("line 1, point 0: coordinates (1, 2, inf)"));
  REQUIRE_THROWS_WITH(read("p.xyzr", "1 2 3 -0.5\n"), Contains("line 1, point 0: radius -0.5 is negative"));
  REQUIRE_THROWS_WITH(read("p.xyzr", "1 2 3 inf\n"), Contains("radius inf is not finite"));

  // Raw records.
  REQUIRE_THROWS_WITH(read("p.f32xyzr", std::string(33, '\0')),
                      Contains("p.f32xyzr: the file has 33 bytes, not a multiple of 16"));
  REQUIRE_THROWS_WITH(read("p.f32xyzr", f32_records({0, 0, 0, 1, 0, INFINITY, 0, 1})),
                      Contains("point 1, byte offset 16: coordinates (0, inf, 0) are not finite"));
  REQUIRE_THROWS_WITH(read("p.f32xyzr", f32_records({0, 0, 0, -2})),
                      Contains("point 0") && Contains("radius -2 is negative"));

  // PLY.
  const std::vector<std::string> xyzr = {"float32 x", "float32 y", "float32 z", "float32 radius"};
  REQUIRE_THROWS_WITH(read("p.ply", "ply\nformat ascii 1.0\nelement face 0\nend_header\n"),
                      Contains("p.ply: the header has no element 'vertex'"));
  REQUIRE_THROWS_WITH(read("p.ply", make_ply("ascii", {"float32 x", "float32 z"}, {{1, 2}})),
                      Contains("element 'vertex' has no property 'y'"));
  REQUIRE_THROWS_WITH(read("p.ply", make_ply("ascii", {"float32 x", "float32 y", "list z"}, {{1, 2, 0}})),
                      Contains("property 'z' of element 'vertex' must be a scalar, not a list"));
  REQUIRE_THROWS_WITH(
      read("p.ply", make_ply("ascii", {"float32 x", "float32 y", "float32 z", "uint8 x"}, {{1, 2, 3, 4}})),
      Contains("property 'x' of element 'vertex' is declared twice"));
  REQUIRE_THROWS_WITH(read("p.ply", "ply\nformat ascii 1.0\nelement vertex 1\nend_header\n"),
                      Contains("element 'vertex' has no property 'x'"));
  REQUIRE_THROWS_WITH(read("p.ply",
                           "ply\nformat binary_little_endian 1.0\nelement vertex 1000000000000\n"
                           "property float x\nproperty float y\nproperty float z\nend_header\n" +
                               std::string(24, '\0')),
                      Contains("element 'vertex' declares 1000000000000 entries of at least 12 bytes each, but "
                               "only 24 bytes"));
  REQUIRE_THROWS_WITH(read("p.ply",
                           "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                           "property float z\nend_header\n0 0 0\n1 1 1\n"),
                      Contains("entries of at least 6 bytes"));
  REQUIRE_THROWS_WITH(
      read("p.ply", make_ply("binary_little_endian", xyzr, {{0, 0, 0, 1}, {0, NAN, 0, 1}})),
      Contains("p.ply: vertex 1, byte offset ") && Contains(": coordinates (0, nan, 0) are not finite"));
  REQUIRE_THROWS_WITH(read("p.ply", make_ply("binary_big_endian", xyzr, {{0, 0, 0, 1}, {0, 0, 0, -1}})),
                      Contains("vertex 1, byte offset") && Contains("radius -1 is negative"));
  REQUIRE_THROWS_WITH(read("p.ply", make_ply("ascii", xyzr, {{0, 0, 0, 1}, {0, 0, 0, -1}})),
                      Contains("line 11, vertex 1: radius -1 is negative"));
  std::string text = make_ply("ascii", xyzr, {{0, 0, 0, 1}, {0, 0, 0, 1}});
  text.replace(text.rfind("0 0 0 1"), 7, "0 0 abc 1");
  REQUIRE_THROWS_WITH(read("p.ply", text), Contains("line 11, vertex 1, property 'z': cannot parse 'abc' as float32"));
  // A list property takes the value-by-value binary path, which finds truncation and bad points too.
  std::string listed = make_ply("binary_little_endian", {"float32 x", "float32 y", "float32 z", "list n"},
                                {{0, 0, 0, 1}, {INFINITY, 0, 0, 0}});
  REQUIRE_THROWS_WITH(read("p.ply", listed),
                      Contains("vertex 1, byte offset " + std::to_string(listed.find("end_header\n") + 11 + 14) +
                               ": coordinates (inf, 0, 0) are not finite"));
  listed = make_ply("binary_little_endian", {"float32 x", "float32 y", "float32 z", "list n"}, {{0, 0, 0, 4}});
  listed.resize(listed.size() - 2);
  REQUIRE_THROWS_WITH(read("p.ply", listed), Contains("vertex 0, property 'n'") && Contains("truncated"));
}

TEST_CASE("points: making spheres gives errors that name the property", "[io][points]") {
  const TempDir dir("sciray_test_points_");
  const std::string file = dir.write(
      "s.ply", make_ply("ascii", {"float32 x", "float32 y", "float32 z", "int8 red", "uint8 green", "float32 lum"},
                        {{0, 0, 0, 1, 2, 3}}));
  PointOptions options;
  options.color_by = "luminosity";
  REQUIRE_THROWS_WITH(to_spheres(read_points(file), options, gray),
                      Contains("s.ply: no point property 'luminosity' to colour by; the points have x, y, z, red, "
                               "green, lum"));
  REQUIRE_THROWS_WITH(sciray::io::finite_range(read_points(file), "t"), Contains("no point property 't'"));
  options.color_by = "lum";
  REQUIRE_THROWS_WITH(to_spheres(read_points(file), options), Contains("colouring by 'lum' needs a colour map"));
  options.range = std::array<double, 2>{0, NAN};
  REQUIRE_THROWS_WITH(to_spheres(read_points(file), options, gray),
                      Contains("the colour range [0, nan] is not finite"));
  options.file_colors = true;
  REQUIRE_THROWS_WITH(to_spheres(read_points(file), options, gray),
                      Contains("colour by the property 'lum' or by the file's colours, not both"));
  options = {};
  options.file_colors = true;
  REQUIRE_THROWS_WITH(to_spheres(read_points(file), options),
                      Contains("no point property 'blue' for the file's colours; the points have x, y, z"));
  REQUIRE_THROWS_WITH(to_spheres(read_points(dir.write("p.xyz", "1 2 3\n")), options),
                      Contains("no point property 'red' for the file's colours; the points have x, y, z"));
  const std::string signed_colors = dir.write(
      "i.ply", make_ply("ascii", {"float32 x", "float32 y", "float32 z", "int8 red", "uint8 green", "uint8 blue"},
                        {{0, 0, 0, 1, 2, 3}}));
  REQUIRE_THROWS_WITH(to_spheres(read_points(signed_colors), options),
                      Contains("property 'red' has type int8; a colour must be an unsigned integer"));

  options = {};
  options.radius = -1.f;
  REQUIRE_THROWS_WITH(to_spheres(read_points(file), options), Contains("the radius must be finite and positive"));
  REQUIRE_THROWS_WITH(to_spheres(read_points(dir.write("e.xyz", "# nothing\n"))),
                      Contains("e.xyz: no points to make spheres of"));
  REQUIRE_THROWS_WITH(to_spheres(read_points(dir.write("z.xyzr", "0 0 0 1\n1 1 1 0\n"))),
                      Contains("z.xyzr: point 1 has radius 0, and a sphere needs a positive radius"));
}
