// The PLY reader: the shipped real meshes, the three encodings of the same data, polygon
// handling, colours, skipping of unknown elements and properties, and every error path.
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <bit>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "sciray/io/ply.hpp"
#include "support/temp_dir.hpp"

using sciray_test::TempDir;
namespace {

using sciray::MeshData;
using sciray::io::parse_ply;
using sciray::io::read_ply;

enum class Encoding { ascii, binary_little_endian, binary_big_endian };
constexpr Encoding all_encodings[] = {Encoding::ascii, Encoding::binary_little_endian,
                                      Encoding::binary_big_endian};

std::string_view format_name(Encoding encoding) {
  switch (encoding) {
    case Encoding::ascii: return "ascii";
    case Encoding::binary_little_endian: return "binary_little_endian";
    case Encoding::binary_big_endian: return "binary_big_endian";
  }
  return "";
}

struct TestProperty {
  std::string type;  ///< a PLY type name; a list's item type
  std::string name;
  std::string count_type;  ///< non-empty for a list
};

/// An element and its entries: each row holds the values in property order, a list as
/// its length followed by its items.
struct TestElement {
  std::string name;
  std::vector<TestProperty> properties;
  std::vector<std::vector<double>> rows;
};

template <class T>
void append_binary(std::string& out, double value, bool big_endian) {
  const auto bits = std::bit_cast<sciray::io::ply_detail::UnsignedOfSize<T>>(static_cast<T>(value));
  for (std::size_t i = 0; i < sizeof(T); ++i) {
    const std::size_t shift = 8 * (big_endian ? sizeof(T) - 1 - i : i);
    out.push_back(static_cast<char>((bits >> shift) & 0xff));
  }
}

void append_value(std::string& out, const std::string& type, double value, Encoding encoding) {
  if (encoding == Encoding::ascii) {
    char text[64];
    const bool is_float = type == "float" || type == "float32";
    const bool is_double = type == "double" || type == "float64";
    const auto result = is_float    ? std::to_chars(text, text + sizeof text, static_cast<float>(value))
                        : is_double ? std::to_chars(text, text + sizeof text, value)
                                    : std::to_chars(text, text + sizeof text, static_cast<long long>(value));
    out.append(text, result.ptr);
    out.push_back(' ');
    return;
  }
  const bool big = encoding == Encoding::binary_big_endian;
  if (type == "char" || type == "int8") append_binary<std::int8_t>(out, value, big);
  else if (type == "uchar" || type == "uint8") append_binary<std::uint8_t>(out, value, big);
  else if (type == "short" || type == "int16") append_binary<std::int16_t>(out, value, big);
  else if (type == "ushort" || type == "uint16") append_binary<std::uint16_t>(out, value, big);
  else if (type == "int" || type == "int32") append_binary<std::int32_t>(out, value, big);
  else if (type == "uint" || type == "uint32") append_binary<std::uint32_t>(out, value, big);
  else if (type == "float" || type == "float32") append_binary<float>(out, value, big);
  else if (type == "double" || type == "float64") append_binary<double>(out, value, big);
  else FAIL("test writer: unknown type " << type);
}

/// A PLY file holding `elements`; `extra_header` lines go after the format line.
std::string make_ply(Encoding encoding, const std::vector<TestElement>& elements,
                     const std::string& extra_header = "") {
  std::string out =
      "ply\nformat " + std::string(format_name(encoding)) + " 1.0\ncomment written by test_ply\n";
  out += extra_header;
  for (const TestElement& element : elements) {
    out += "element " + element.name + " " + std::to_string(element.rows.size()) + "\n";
    for (const TestProperty& property : element.properties)
      out += property.count_type.empty()
                 ? "property " + property.type + " " + property.name + "\n"
                 : "property list " + property.count_type + " " + property.type + " " + property.name + "\n";
  }
  out += "end_header\n";
  for (const TestElement& element : elements)
    for (const std::vector<double>& row : element.rows) {
      std::size_t next = 0;
      for (const TestProperty& property : element.properties) {
        if (property.count_type.empty()) {
          append_value(out, property.type, row.at(next++), encoding);
          continue;
        }
        const auto length = static_cast<std::size_t>(row.at(next));
        append_value(out, property.count_type, row.at(next++), encoding);
        for (std::size_t i = 0; i < length; ++i) append_value(out, property.type, row.at(next++), encoding);
      }
      if (encoding == Encoding::ascii) out.back() = '\n';
    }
  return out;
}

MeshData parse(const std::string& file) {
  return parse_ply(std::as_bytes(std::span(file.data(), file.size())), "test.ply");
}

const std::vector<TestProperty> xyz_properties = {{"float", "x", ""}, {"float", "y", ""}, {"float", "z", ""}};
const TestProperty index_list = {"int", "vertex_indices", "uchar"};

/// A unit square's corners, for polygon tests: 0 (0,0), 1 (1,0), 2 (1,1), 3 (0,1), 4 (0.5,1.5).
TestElement square_vertices() {
  return {"vertex", xyz_properties, {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0.5, 1.5, 0}}};
}

TestElement faces(std::vector<std::vector<double>> rows, std::vector<TestProperty> extra_properties = {}) {
  std::vector<TestProperty> properties = {index_list};
  properties.insert(properties.end(), extra_properties.begin(), extra_properties.end());
  return {"face", properties, std::move(rows)};
}

/// A unit cube with per-vertex normals and RGBA colours, and quads with per-face colours.
std::vector<TestElement> cube_elements() {
  TestElement vertices{"vertex",
                       {{"float", "x", ""},
                        {"float", "y", ""},
                        {"float", "z", ""},
                        {"float", "nx", ""},
                        {"float", "ny", ""},
                        {"float", "nz", ""},
                        {"uchar", "red", ""},
                        {"uchar", "green", ""},
                        {"uchar", "blue", ""},
                        {"uchar", "alpha", ""}},
                       {}};
  const double n = 1 / std::sqrt(3.0);
  for (int corner = 0; corner < 8; ++corner) {
    const double x = corner & 1, y = (corner >> 1) & 1, z = (corner >> 2) & 1;
    vertices.rows.push_back(
        {x, y, z, (2 * x - 1) * n, (2 * y - 1) * n, (2 * z - 1) * n, 255 * x, 255 * y, 128, 200});
  }
  TestElement quads = faces({{4, 0, 2, 3, 1, 255, 0, 0},
                             {4, 4, 5, 7, 6, 0, 255, 0},
                             {4, 0, 1, 5, 4, 0, 0, 255},
                             {4, 2, 6, 7, 3, 255, 255, 0},
                             {4, 0, 4, 6, 2, 0, 255, 255},
                             {4, 1, 3, 7, 5, 255, 0, 255}},
                            {{"uchar", "red", ""}, {"uchar", "green", ""}, {"uchar", "blue", ""}});
  return {vertices, quads};
}

void require_same(const MeshData& a, const MeshData& b) {
  REQUIRE(a.vertices_per_face == b.vertices_per_face);
  REQUIRE(a.positions == b.positions);
  REQUIRE(a.indices == b.indices);
  REQUIRE(a.normals == b.normals);
  REQUIRE(a.vertex_colors == b.vertex_colors);
  REQUIRE(a.face_colors == b.face_colors);
}

std::vector<std::uint32_t> indices_of(const MeshData& mesh) {
  return {mesh.indices.begin(), mesh.indices.end()};
}
std::vector<float> face_colors_of(const MeshData& mesh) {
  return {mesh.face_colors.begin(), mesh.face_colors.end()};
}


}  // namespace

TEST_CASE("ply: the same cube reads identically from ascii and both binary byte orders", "[io][ply]") {
  TempDir dir("sciray_test_ply_");
  const MeshData ascii = read_ply(dir.write("cube_ascii.ply", make_ply(Encoding::ascii, cube_elements())));
  const MeshData little =
      read_ply(dir.write("cube_le.ply", make_ply(Encoding::binary_little_endian, cube_elements())));
  const MeshData big =
      read_ply(dir.write("cube_be.ply", make_ply(Encoding::binary_big_endian, cube_elements())));
  require_same(ascii, little);
  require_same(ascii, big);

  REQUIRE(little.vertex_count() == 8);
  REQUIRE(little.face_count() == 6);
  REQUIRE(little.vertices_per_face == 4);
  CHECK(indices_of(little) ==
        std::vector<std::uint32_t>{0, 2, 3, 1, 4, 5, 7, 6, 0, 1, 5, 4, 2, 6, 7, 3, 0, 4, 6, 2, 1, 3, 7, 5});
  const float n = static_cast<float>(1 / std::sqrt(3.0));
  CHECK(little.positions[3 * 7 + 0] == 1.0f);
  CHECK(little.positions[3 * 6 + 0] == 0.0f);
  CHECK(little.normals[3 * 1 + 0] == n);
  CHECK(little.normals[3 * 1 + 1] == -n);
  CHECK(little.vertex_colors[4 * 3 + 0] == 1.0f);
  CHECK(little.vertex_colors[4 * 3 + 2] == static_cast<float>(128 / 255.0));
  CHECK(little.vertex_colors[4 * 3 + 3] == static_cast<float>(200 / 255.0));
  CHECK(face_colors_of(little) ==
        std::vector<float>{1, 0, 0, 1, 0, 1, 0, 1, 0, 0, 1, 1, 1, 1, 0, 1, 0, 1, 1, 1, 1, 0, 1, 1});
}

TEST_CASE("ply: unknown elements and properties of every type are skipped", "[io][ply]") {
  const std::vector<TestElement> plain = cube_elements();
  std::vector<TestElement> cluttered = plain;
  TestElement& vertices = cluttered[0];
  TestElement& quads = cluttered[1];
  // Every scalar type and two list layouts, interleaved with the known properties.
  vertices.properties = {{"char", "tag", ""},           {"float", "x", ""},
                         {"double", "samples", "uint"}, {"float", "y", ""},
                         {"ushort", "flags", ""},       {"float", "z", ""},
                         {"float", "nx", ""},           {"int", "neighbours", "uchar"},
                         {"float", "ny", ""},           {"double", "confidence", ""},
                         {"float", "nz", ""},           {"int", "id", ""},
                         {"uchar", "red", ""},          {"short", "offset", ""},
                         {"uchar", "green", ""},        {"uint", "serial", ""},
                         {"uchar", "blue", ""},         {"float64", "weight", ""},
                         {"uchar", "alpha", ""},        {"uint8", "label", ""}};
  for (std::size_t v = 0; v < vertices.rows.size(); ++v) {
    const std::vector<double> known = plain[0].rows[v];
    vertices.rows[v] = {-5,       known[0], 3,        0.5,      1.5,  2.5,      known[1],
                        65535,    known[2], known[3], 2,        7,    8,        known[4],
                        0.125,    known[5], -100000,  known[6], -300, known[7], 4000000000,
                        known[8], 1e300,    known[9], 255};
  }
  quads.properties.push_back({"ushort", "material", "int"});
  for (std::vector<double>& row : quads.rows) row.insert(row.end(), {2, 65535, 1});
  quads.properties.insert(quads.properties.begin(), {"float", "area", ""});
  for (std::vector<double>& row : quads.rows) row.insert(row.begin(), 0.25);
  const TestElement before{"camera", {{"float", "view_px", ""}, {"int", "tags", "ushort"}}, {{1.5, 2, 8, 9}}};
  const TestElement between{
      "edge", {{"int", "vertex1", ""}, {"int", "vertex2", ""}}, {{0, 1}, {1, 2}, {2, 3}}};
  const TestElement after{"tristrips", {index_list}, {{5, 0, 1, 2, 3, -1}}};
  cluttered.insert(cluttered.begin() + 1, between);
  cluttered.insert(cluttered.begin(), before);
  cluttered.push_back(after);
  const std::string header_noise = "comment another comment\nobj_info made by hand\n";

  for (const Encoding encoding : all_encodings) {
    INFO(format_name(encoding));
    require_same(parse(make_ply(encoding, cluttered, header_noise)), parse(make_ply(encoding, plain)));
  }
}

TEST_CASE("ply: polygons become triangles or quads", "[io][ply]") {
  const Encoding encoding = GENERATE(from_range(std::begin(all_encodings), std::end(all_encodings)));
  INFO(format_name(encoding));
  SECTION("triangles only stay triangles") {
    const MeshData mesh = parse(make_ply(encoding, {square_vertices(), faces({{3, 0, 1, 2}, {3, 0, 2, 3}})}));
    REQUIRE(mesh.vertices_per_face == 3);
    REQUIRE(indices_of(mesh) == std::vector<std::uint32_t>{0, 1, 2, 0, 2, 3});
  }
  SECTION("one quad makes a quad mesh; triangles repeat their last index") {
    const MeshData mesh =
        parse(make_ply(encoding, {square_vertices(), faces({{3, 2, 4, 3}, {4, 0, 1, 2, 3}, {3, 0, 1, 4}})}));
    REQUIRE(mesh.vertices_per_face == 4);
    REQUIRE(indices_of(mesh) == std::vector<std::uint32_t>{2, 4, 3, 3, 0, 1, 2, 3, 0, 1, 4, 4});
  }
  SECTION("a pentagon becomes a triangle fan") {
    const MeshData mesh = parse(make_ply(encoding, {square_vertices(), faces({{5, 0, 1, 2, 4, 3}})}));
    REQUIRE(mesh.vertices_per_face == 3);
    REQUIRE(indices_of(mesh) == std::vector<std::uint32_t>{0, 1, 2, 0, 2, 4, 0, 4, 3});
  }
  SECTION("a pentagon in a quad mesh becomes degenerate quads") {
    const MeshData mesh =
        parse(make_ply(encoding, {square_vertices(), faces({{5, 0, 1, 2, 4, 3}, {4, 0, 1, 2, 3}})}));
    REQUIRE(mesh.vertices_per_face == 4);
    REQUIRE(indices_of(mesh) == std::vector<std::uint32_t>{0, 1, 2, 2, 0, 2, 4, 4, 0, 4, 3, 3, 0, 1, 2, 3});
  }
  SECTION("other index types and the name vertex_index") {
    TestElement polygons = faces({{3, 0, 1, 2}, {5, 0, 1, 2, 4, 3}});
    polygons.properties[0] = {"ushort", "vertex_index", "int"};
    const MeshData mesh = parse(make_ply(encoding, {square_vertices(), polygons}));
    REQUIRE(indices_of(mesh) == std::vector<std::uint32_t>{0, 1, 2, 0, 1, 2, 0, 2, 4, 0, 4, 3});
  }
}

TEST_CASE("ply: faces may come before the vertices", "[io][ply]") {
  for (const Encoding encoding : all_encodings) {
    INFO(format_name(encoding));
    const MeshData mesh =
        parse(make_ply(encoding, {faces({{3, 4, 1, 2}, {5, 0, 1, 2, 4, 3}}), square_vertices()}));
    REQUIRE(mesh.vertex_count() == 5);
    REQUIRE(indices_of(mesh) == std::vector<std::uint32_t>{4, 1, 2, 0, 1, 2, 0, 2, 4, 0, 4, 3});
    std::string truncated = make_ply(encoding, {faces({{5, 0, 1, 2, 4, 3}}), square_vertices()});
    truncated.resize(truncated.size() - 8);
    REQUIRE_THROWS_WITH(parse(truncated), Catch::Contains("vertex 4") && Catch::Contains("truncated"));
  }
}

TEST_CASE("ply: face colours repeat for each output face", "[io][ply]") {
  const std::vector<TestProperty> rgb = {{"uchar", "red", ""}, {"uchar", "green", ""}, {"uchar", "blue", ""}};
  for (const Encoding encoding : all_encodings) {
    INFO(format_name(encoding));
    const MeshData mesh =
        parse(make_ply(encoding, {square_vertices(),
                                  faces({{3, 0, 1, 2, 255, 0, 0}, {5, 0, 1, 2, 4, 3, 0, 51, 255}}, rgb)}));
    REQUIRE(mesh.face_count() == 4);
    REQUIRE(face_colors_of(mesh) ==
            std::vector<float>{1, 0, 0, 1, 0, 0.2f, 1, 1, 0, 0.2f, 1, 1, 0, 0.2f, 1, 1});
    REQUIRE(mesh.vertex_colors.empty());
    REQUIRE(mesh.normals.empty());
  }
}

TEST_CASE("ply: float colours are kept and alpha defaults to 1", "[io][ply]") {
  TestElement vertices = square_vertices();
  vertices.properties.insert(vertices.properties.end(),
                             {{"float", "red", ""}, {"double", "green", ""}, {"float", "blue", ""}});
  for (std::vector<double>& row : vertices.rows) row.insert(row.end(), {0.25, 0.5, 0.75});
  for (const Encoding encoding : all_encodings) {
    INFO(format_name(encoding));
    const MeshData mesh = parse(make_ply(encoding, {vertices, faces({{3, 0, 1, 2}})}));
    REQUIRE(mesh.vertex_colors.size() == 4 * 5);
    for (std::size_t v = 0; v < 5; ++v) {
      CHECK(mesh.vertex_colors[4 * v + 0] == 0.25f);
      CHECK(mesh.vertex_colors[4 * v + 1] == 0.5f);
      CHECK(mesh.vertex_colors[4 * v + 2] == 0.75f);
      CHECK(mesh.vertex_colors[4 * v + 3] == 1.0f);
    }
  }
}

TEST_CASE("ply: a point cloud without faces and a file with CRLF header lines", "[io][ply]") {
  const MeshData points = parse(make_ply(Encoding::binary_little_endian, {square_vertices()}));
  REQUIRE(points.vertex_count() == 5);
  REQUIRE(points.face_count() == 0);

  const MeshData crlf = parse(
      "ply\r\nformat ascii 1.0\r\nelement vertex 3\r\nproperty float x\r\nproperty float y\r\n"
      "property float z\r\nelement face 1\r\nproperty list uchar int vertex_indices\r\n"
      "end_header\r\n0 0 0\r\n1 0 0\r\n+0 1 0\r\n3 0 1 2\r\n");
  REQUIRE(crlf.vertex_count() == 3);
  REQUIRE(indices_of(crlf) == std::vector<std::uint32_t>{0, 1, 2});
}

TEST_CASE("ply: malformed files give errors that say what is wrong", "[io][ply]") {
  using Catch::Contains;
  const std::string vertex_header =
      "element vertex 3\nproperty float x\nproperty float y\nproperty float z\n";
  const std::string triangle = "element face 1\nproperty list uchar int vertex_indices\nend_header\n";

  REQUIRE_THROWS_WITH(read_ply("/nonexistent/sciray/mesh.ply"),
                      Contains("/nonexistent/sciray/mesh.ply: cannot open the file"));
  REQUIRE_THROWS_WITH(parse(""), Contains("does not start with the line 'ply'"));
  REQUIRE_THROWS_WITH(parse("plx\nformat ascii 1.0\nend_header\n"),
                      Contains("test.ply") && Contains("does not start with the line 'ply'"));
  REQUIRE_THROWS_WITH(parse("ply\nformat binary_middle_endian 1.0\nend_header\n"),
                      Contains("unknown format 'binary_middle_endian'"));
  REQUIRE_THROWS_WITH(parse("ply\nformat ascii 2.0\nend_header\n"),
                      Contains("unsupported PLY version '2.0'"));
  REQUIRE_THROWS_WITH(parse("ply\nformat ascii 1.0\n" + vertex_header), Contains("no 'end_header'"));
  REQUIRE_THROWS_WITH(parse("ply\nformat ascii 1.0\nelement vertex 1\nproperty float33 x\nend_header\n"),
                      Contains("header line 4") && Contains("unknown type 'float33' of property 'x'"));
  REQUIRE_THROWS_WITH(
      parse("ply\nformat ascii 1.0\nelement vertex 1\nproperty list float int x\nend_header\n"),
      Contains("count type 'float'"));
  REQUIRE_THROWS_WITH(parse("ply\nformat ascii 1.0\nelement vertex 1\nproperti float x\nend_header\n"),
                      Contains("unknown header keyword 'properti'"));
  REQUIRE_THROWS_WITH(parse("ply\nformat ascii 1.0\nelement vertex 99999999999999999999999\nend_header\n"),
                      Contains("not a non-negative 64-bit integer"));
  REQUIRE_THROWS_WITH(parse("ply\nformat ascii 1.0\nelement vertex 1\nproperty float y\nproperty float z\n"
                            "end_header\n1 2\n"),
                      Contains("element 'vertex' has no property 'x'"));
  REQUIRE_THROWS_WITH(parse("ply\nformat ascii 1.0\n" + vertex_header + "property float nx\nend_header\n"),
                      Contains("has normal properties but no property 'ny'"));
  REQUIRE_THROWS_WITH(parse("ply\nformat ascii 1.0\nelement face 0\nproperty list uchar int vertex_indices\n"
                            "end_header\n"),
                      Contains("no element 'vertex'"));
  REQUIRE_THROWS_WITH(parse("ply\nformat ascii 1.0\n" + vertex_header +
                            "element face 1\nproperty int id\n"
                            "end_header\n0 0 0\n1 0 0\n0 1 0\n7\n"),
                      Contains("no list property 'vertex_indices'"));
  REQUIRE_THROWS_WITH(parse("ply\nformat ascii 1.0\n" + vertex_header +
                            "property char red\nproperty char green\n"
                            "property char blue\nend_header\n"),
                      Contains("property 'red' of element 'vertex' has type int8"));
  REQUIRE_THROWS_WITH(
      parse("ply\nformat ascii 1.0\n" + vertex_header + triangle + "0 0 0\n1 abc 0\n0 1 0\n3 0 1 2\n"),
      Contains("line 11, vertex 1, property 'y': cannot parse 'abc' as float32"));
  REQUIRE_THROWS_WITH(
      parse("ply\nformat ascii 1.0\n" + vertex_header + triangle + "0 0 0\n1 0 0\n0 1 0\n3 0 1 2.5\n"),
      Contains("line 13, face 0, property 'vertex_indices': cannot parse '2.5' as int32"));
  REQUIRE_THROWS_WITH(
      parse("ply\nformat ascii 1.0\n" + vertex_header + triangle + "0 0 0\n1 0 0\n0 1 0\n300 0 1 2\n"),
      Contains("value 300 does not fit uint8"));
  REQUIRE_THROWS_WITH(
      parse("ply\nformat ascii 1.0\n" + vertex_header + triangle + "0 0 0\n1 0 0\n0 1 0\n3 0 1\n"),
      Contains("line 14, face 0, property 'vertex_indices'") && Contains("truncated"));
}

TEST_CASE("ply: bad data values are reported in every encoding", "[io][ply]") {
  using Catch::Contains;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double infinity = std::numeric_limits<double>::infinity();
  for (const Encoding encoding : all_encodings) {
    INFO(format_name(encoding));
    for (const bool extra_property : {false, true}) {  // the fast binary paths and the general one
      INFO("extra property: " << extra_property);
      std::vector<TestProperty> extras;
      if (extra_property) extras.push_back({"int", "material", ""});
      const auto with_faces = [&](std::vector<std::vector<double>> rows) {
        if (extra_property)
          for (std::vector<double>& row : rows) row.push_back(9);
        return make_ply(encoding, {square_vertices(), faces(std::move(rows), extras)});
      };
      REQUIRE_THROWS_WITH(parse(with_faces({{3, 0, 1, 2}, {3, 0, 1, 2}, {3, 4, 5, 0}})),
                          Contains("face 2, property 'vertex_indices'") &&
                              Contains("vertex index 5 is out of range: the file has 5 vertices"));
      REQUIRE_THROWS_WITH(
          parse(with_faces({{3, 0, 1, 2}, {3, 0, -1, 2}})),
          Contains("face 1, property 'vertex_indices'") && Contains("vertex index -1 is negative"));
      REQUIRE_THROWS_WITH(parse(with_faces({{3, 0, 1, 2}, {2, 0, 1}})),
                          Contains("face 1, property 'vertex_indices'") &&
                              Contains("face has 2 vertices; a face needs at least 3"));
      REQUIRE_THROWS_WITH(parse(with_faces({{0}})), Contains("face 0") && Contains("face has 0 vertices"));
    }
    for (const double bad : {nan, infinity}) {
      TestElement vertices = square_vertices();
      vertices.rows[3][1] = bad;
      REQUIRE_THROWS_WITH(parse(make_ply(encoding, {vertices})),
                          Contains("vertex 3") && Contains("not finite"));
      vertices.properties[1].type = "double";  // binary: positions that are not all float
      REQUIRE_THROWS_WITH(parse(make_ply(encoding, {vertices})),
                          Contains("vertex 3") && Contains("not finite"));
      vertices.properties.push_back({"int", "neighbours", "uchar"});  // binary: records with a list
      for (std::vector<double>& row : vertices.rows) row.insert(row.end(), {1, 0});
      REQUIRE_THROWS_WITH(parse(make_ply(encoding, {vertices})),
                          Contains("vertex 3") && Contains("not finite"));
    }
  }
}

TEST_CASE("ply: counts the data cannot hold fail before allocating", "[io][ply]") {
  using Catch::Contains;
  for (const Encoding encoding : all_encodings) {
    INFO(format_name(encoding));
    std::string file = make_ply(encoding, {square_vertices(), faces({{3, 0, 1, 2}})});
    file.replace(file.find("element vertex 5"), 16, "element vertex 4000000000");
    REQUIRE_THROWS_WITH(parse(file), Contains("element 'vertex' declares 4000000000 entries") &&
                                         Contains("truncated or the count is wrong"));
    file = make_ply(encoding, {square_vertices(), faces({{3, 0, 1, 2}})});
    file.replace(file.find("element face 1"), 14, "element face 18446744073709551615");
    REQUIRE_THROWS_WITH(parse(file), Contains("element 'face' declares 18446744073709551615 entries"));
  }
  std::string file = make_ply(Encoding::binary_little_endian, {square_vertices(), faces({{3, 0, 1, 2}})});
  file.replace(file.find("element face 1"), 14, "element face 2");
  REQUIRE_THROWS_WITH(parse(file), Contains("face 1, property 'vertex_indices'") && Contains("truncated"));
  file = make_ply(Encoding::ascii, {square_vertices()});
  file.replace(file.find("element vertex 5"), 16, "element vertex 5000000000");
  REQUIRE_THROWS_WITH(parse(file), Contains("at most 4294967295"));
}

TEST_CASE("ply: a generated 2M-triangle binary file loads", "[io][ply]") {
  constexpr std::uint32_t cells = 1000, side = cells + 1;
  std::string file = "ply\nformat binary_little_endian 1.0\nelement vertex " + std::to_string(side * side) +
                     "\nproperty float x\nproperty float y\nproperty float z\nelement face " +
                     std::to_string(2 * cells * cells) +
                     "\nproperty list uchar uint vertex_indices\nend_header\n";
  for (std::uint32_t j = 0; j < side; ++j)
    for (std::uint32_t i = 0; i < side; ++i)
      for (const float value :
           {static_cast<float>(i), static_cast<float>(j), static_cast<float>((i + j) % 7)})
        append_binary<float>(file, value, false);
  for (std::uint32_t j = 0; j < cells; ++j)
    for (std::uint32_t i = 0; i < cells; ++i) {
      const std::uint32_t v = j * side + i;
      for (const std::array<std::uint32_t, 3>& triangle :
           {std::array{v, v + 1, v + side + 1}, std::array{v, v + side + 1, v + side}}) {
        file.push_back(3);
        for (const std::uint32_t index : triangle) append_binary<std::uint32_t>(file, index, false);
      }
    }
  TempDir dir("sciray_test_ply_");
  const MeshData mesh = read_ply(dir.write("grid.ply", file));
  REQUIRE(mesh.vertex_count() == side * side);
  REQUIRE(mesh.face_count() == 2 * cells * cells);
  REQUIRE(mesh.vertices_per_face == 3);
  const std::size_t last_vertex = side * side - 1;
  CHECK(mesh.positions[3 * last_vertex] == static_cast<float>(cells));
  CHECK(mesh.positions[3 * last_vertex + 2] == static_cast<float>((2 * cells) % 7));
  CHECK(std::vector<std::uint32_t>(mesh.indices.end() - 3, mesh.indices.end()) ==
        std::vector<std::uint32_t>{last_vertex - side - 1, last_vertex, last_vertex - 1});
}

#ifdef SCIRAY_DATA_DIR

namespace {

std::filesystem::path mesh_path(const std::string& name) {
  return std::filesystem::path(SCIRAY_DATA_DIR) / "meshes" / name;
}

std::string file_contents(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

}  // namespace

TEST_CASE("ply: the real meshes load with their documented sizes", "[io][ply][data]") {
  struct Expected {
    const char* file;
    std::size_t vertices;
    std::size_t triangles;
  };
  const Expected expected =
      GENERATE(Expected{"bunny.ply", 35947, 69451}, Expected{"lucy.ply", 49987, 99970},
               Expected{"horse.ply", 48485, 96966}, Expected{"turbineblade.ply", 99519, 199034},
               Expected{"footbones.ply", 2154, 4204});
  INFO(expected.file);
  const MeshData mesh = read_ply(mesh_path(expected.file));
  REQUIRE(mesh.vertex_count() == expected.vertices);
  REQUIRE(mesh.face_count() == expected.triangles);
  REQUIRE(mesh.vertices_per_face == 3);
  REQUIRE(mesh.normals.empty());
  REQUIRE(mesh.face_colors.empty());
  REQUIRE(*std::max_element(mesh.indices.begin(), mesh.indices.end()) < mesh.vertex_count());
  for (int axis = 0; axis < 3; ++axis) {
    float lower = std::numeric_limits<float>::infinity(), upper = -lower;
    for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
      lower = std::min(lower, mesh.positions[3 * v + static_cast<std::size_t>(axis)]);
      upper = std::max(upper, mesh.positions[3 * v + static_cast<std::size_t>(axis)]);
    }
    CHECK(std::isfinite(lower));
    CHECK(std::isfinite(upper));
    CHECK(upper > lower);
    CHECK(upper - lower < 1e4f);
  }
}

TEST_CASE("ply: real mesh values match an independent decoding", "[io][ply][data]") {
  SECTION("bunny (ascii, extra vertex properties)") {
    const MeshData mesh = read_ply(mesh_path("bunny.ply"));
    CHECK(mesh.positions[0] == -0.0378297f);
    CHECK(mesh.positions[1] == 0.12794f);
    CHECK(mesh.positions[2] == 0.00447467f);
    CHECK(std::vector<std::uint32_t>(mesh.indices.begin(), mesh.indices.begin() + 3) ==
          std::vector<std::uint32_t>{20399, 21215, 21216});
    CHECK(std::vector<std::uint32_t>(mesh.indices.end() - 3, mesh.indices.end()) ==
          std::vector<std::uint32_t>{17345, 17346, 17277});
    CHECK(mesh.vertex_colors.empty());
  }
  SECTION("lucy (binary little endian)") {
    const MeshData mesh = read_ply(mesh_path("lucy.ply"));
    CHECK(mesh.positions[0] == 728.8809814453125f);
    CHECK(mesh.positions[1] == 5.004640102386475f);
    CHECK(mesh.positions[2] == 31.22330093383789f);
    CHECK(std::vector<std::uint32_t>(mesh.indices.begin(), mesh.indices.begin() + 3) ==
          std::vector<std::uint32_t>{49494, 29144, 49518});
  }
  SECTION("horse (binary big endian, uchar colours)") {
    const MeshData mesh = read_ply(mesh_path("horse.ply"));
    CHECK(mesh.positions[0] == -0.002022000029683113f);
    CHECK(mesh.positions[1] == -0.04017850011587143f);
    CHECK(mesh.positions[4] == -0.0620185025036335f);
    CHECK(std::vector<std::uint32_t>(mesh.indices.begin(), mesh.indices.begin() + 3) ==
          std::vector<std::uint32_t>{26289, 26288, 26287});
    REQUIRE(mesh.vertex_colors.size() == 4 * mesh.vertex_count());
    // The file's colours are all (255, 255, 255).
    for (const float channel : mesh.vertex_colors) REQUIRE(channel == 1.0f);
  }
}

TEST_CASE("ply: truncated real files are reported as truncated", "[io][ply][data]") {
  using Catch::Contains;
  SECTION("binary, cut inside the faces") {
    const std::string bytes = file_contents(mesh_path("lucy.ply"));
    const std::string half = bytes.substr(0, bytes.size() / 2);
    REQUIRE_THROWS_WITH(parse(half), Contains("test.ply: face ") && Contains("the file is truncated"));
  }
  SECTION("binary big endian, cut inside the vertices") {
    const std::string bytes = file_contents(mesh_path("horse.ply"));
    REQUIRE_THROWS_WITH(parse(bytes.substr(0, bytes.size() / 4)), Contains("truncated"));
  }
  SECTION("ascii, cut at a line end inside the vertices") {
    const std::string bytes = file_contents(mesh_path("bunny.ply"));
    const std::string half = bytes.substr(0, bytes.rfind('\n', bytes.size() / 2) + 1);
    const auto line = std::count(half.begin(), half.end(), '\n') + 1;
    REQUIRE_THROWS_WITH(parse(half), Contains("line " + std::to_string(line) + ", vertex ") &&
                                         Contains("the file is truncated"));
  }
}

#endif  // SCIRAY_DATA_DIR
