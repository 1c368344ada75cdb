// The OBJ reader: groups and materials split into meshes, the .mtl mapped to sciray's
// materials with their texture maps, vertex unification, triangulation, and every error.
#include <algorithm>
#include <catch2/catch.hpp>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "sciray/io/obj.hpp"
#include "support/temp_dir.hpp"

using sciray_test::TempDir;
namespace {

using Catch::Contains;
using sciray::MeshData;
using sciray::ObjMaterial;
using sciray::PrincipledMaterial;
using sciray::Vec3f;
using sciray::io::ObjScene;
using sciray::io::read_obj;

/// A width x height PNG of `channels` 8-bit channels, top row first, at `name` in `dir`.
void write_png(const TempDir& dir, const std::string& name, int width, int height, int channels,
               const std::vector<std::uint8_t>& pixels) {
  std::filesystem::create_directories((dir.path() / name).parent_path());
  sciray::io::write_png(dir.path() / name, width, height, channels, pixels.data());
}

constexpr const char* cube_positions = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n";
constexpr const char* cube_normals = "vn 0 0 -1\nvn 0 0 1\nvn -1 0 0\nvn 1 0 0\nvn 0 -1 0\nvn 0 1 0\n";
constexpr const char* cube_texcoords = "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n";

/// The cube's six faces as quads, face k with normal k and texcoords 1..4.
std::string cube_face(int k) {
  static const int corners[6][4] = {{1, 4, 3, 2}, {5, 6, 7, 8}, {1, 5, 8, 4}, {2, 3, 7, 6}, {1, 2, 6, 5}, {4, 8, 7, 3}};
  std::string f = "f";
  for (int c = 0; c < 4; ++c)
    f += ' ' + std::to_string(corners[k][c]) + '/' + std::to_string(c + 1) + '/' + std::to_string(k + 1);
  return f + "\n";
}

const sciray::io::ObjMesh& mesh_named(const ObjScene& scene, const std::string& name, std::uint32_t material) {
  const auto found = std::find_if(scene.meshes.begin(), scene.meshes.end(),
                                  [&](const auto& m) { return m.name == name && m.material == material; });
  REQUIRE(found != scene.meshes.end());
  return *found;
}

bool near(const Vec3f& a, const Vec3f& b, float eps = 1e-5f) {
  return std::abs(a.x - b.x) < eps && std::abs(a.y - b.y) < eps && std::abs(a.z - b.z) < eps;
}

double area(const float* a, const float* b, const float* c) {
  const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
  const double x = u[1] * v[2] - u[2] * v[1], y = u[2] * v[0] - u[0] * v[2], z = u[0] * v[1] - u[1] * v[0];
  return 0.5 * std::sqrt(x * x + y * y + z * z);
}

double total_area(const MeshData& mesh) {
  double sum = 0;
  for (std::size_t f = 0; f < mesh.face_count(); ++f)
    sum += area(&mesh.positions[3 * mesh.indices[3 * f]], &mesh.positions[3 * mesh.indices[3 * f + 1]],
                &mesh.positions[3 * mesh.indices[3 * f + 2]]);
  return sum;
}

}  // namespace

TEST_CASE("obj: a cube in groups with two materials, normals, texcoords and a texture", "[io][obj]") {
  TempDir dir("sciray_test_obj_");
  // 2x1 RGBA: left opaque red, right half-transparent blue (top row = the only row).
  write_png(dir, "textures/checker.png", 2, 1, 4, {255, 0, 0, 255, 0, 0, 255, 128});
  dir.write("cube.mtl",
            "# two materials\n"
            "newmtl red\nKd 0.8 0.1 0.1\nKs 0.2 0.3 0.4\nNs 50\nd 0.75\nillum 2\n"
            "newmtl textured\nKd 1 1 1\nTr 0.25\nmap_Kd -s 2 3 1 -o 0.5 0.25 0 textures/checker.png\n"
            "map_Ka textures/checker.png\n");
  const ObjScene scene = read_obj(dir.write(
      "cube.obj", std::string("mtllib cube.mtl\n") + cube_positions + cube_texcoords + cube_normals +
                      "g front_back\nusemtl red\n" + cube_face(0) + cube_face(1) + "g sides\nusemtl textured\n" +
                      cube_face(2) + cube_face(3) + "usemtl red\n" + cube_face(4) + cube_face(5)));
  REQUIRE(scene.meshes.size() == 3);
  REQUIRE(scene.materials.size() == 2);
  CHECK(scene.material_names == std::vector<std::string>{"red", "textured"});
  for (const char* name : {"front_back", "sides"}) {
    const MeshData& mesh = mesh_named(scene, name, 0).mesh;
    CHECK(mesh.face_count() == 4);
    CHECK(mesh.vertex_count() == 8);  // two quads of 4 corners, each corner its own normal
    CHECK(mesh.normals.size() == 3 * mesh.vertex_count());
    CHECK(mesh.texcoords.size() == 2 * mesh.vertex_count());
    CHECK(mesh.vertices_per_face == 3);
  }
  const MeshData& sides = mesh_named(scene, "sides", 1).mesh;
  CHECK(sides.face_count() == 4);
  // Every vertex of the -x face has normal (-1, 0, 0) and lies at x = 0.
  for (std::size_t v = 0; v < sides.vertex_count(); ++v) {
    const float x = sides.positions[3 * v], nx = sides.normals[3 * v];
    CHECK(((x == 0.f && nx == -1.f) || (x == 1.f && nx == 1.f)));
  }

  const auto& red = std::get<ObjMaterial>(scene.materials[0]);
  CHECK(near(red.kd, {0.8f, 0.1f, 0.1f}));
  CHECK(near(red.ks, {0.2f, 0.3f, 0.4f}));
  CHECK(red.ns == 50.f);
  CHECK(red.d == 0.75f);
  CHECK(!red.map_kd);
  const auto& textured = std::get<ObjMaterial>(scene.materials[1]);
  CHECK(textured.d == Approx(0.75f));  // Tr is 1 - d
  REQUIRE(textured.map_kd);
  REQUIRE(textured.map_kd.texture->width() == 2);
  CHECK(near(textured.map_kd.texture->texel(0, 0), {1.f, 0.f, 0.f}));  // sRGB 255 is linear 1
  CHECK(near(textured.map_kd.texture->texel(1, 0), {0.f, 0.f, 1.f}));
  REQUIRE(textured.map_kd.alpha);  // an RGBA map_Kd cuts out by its alpha, as OSPRay's
  CHECK(textured.map_kd.alpha->texel(1, 0).x == Approx(128.f / 255.f));
  const auto uv = textured.map_kd.transform({1.f, 1.f});  // -s 2 3, -o 0.5 0.25
  CHECK(uv.u == Approx(2.5f));
  CHECK(uv.v == Approx(3.25f));
  REQUIRE(scene.warnings.size() == 1);
  CHECK_THAT(scene.warnings[0], Contains("cube.mtl: material 'textured': map_Ka 'textures/checker.png' is ignored"));
}

TEST_CASE("obj: PBR materials become principled, emission and normal maps included", "[io][obj]") {
  TempDir dir("sciray_test_obj_");
  write_png(dir, "normal.png", 1, 1, 3, {128, 128, 255});
  write_png(dir, "height.png", 1, 1, 1, {77});
  write_png(dir, "rough.png", 1, 1, 1, {51});
  dir.write("pbr.mtl",
            "newmtl metal\nKd 0.9 0.8 0.7\nPr 0.3\nPm 1\nPs 0.2\nPc 0.4\nPcr 0.1\naniso 0.5\nanisor 0.25\nNi 1.33\n"
            "d 0.5\nmap_Pr rough.png\nnorm -bm 0.5 normal.png\n"
            "newmtl lamp\nKd 0 0 0\nKe 4 3 2\n"
            "newmtl bumpy\nKd 0.5 0.5 0.5\nbump height.png\n");
  std::string obj = std::string("mtllib pbr.mtl\n") + cube_positions + "usemtl metal\nf 1 2 3\nusemtl lamp\nf 1 3 4\n" +
                    "usemtl bumpy\nf 5 6 7\nf 5 7 8\n";
  const auto file = dir.write("pbr.obj", obj);
  const ObjScene scene = read_obj(file);
  REQUIRE(scene.materials.size() == 3);
  const auto& metal = std::get<PrincipledMaterial>(scene.materials[0]);
  CHECK(near(metal.base_color, {0.9f, 0.8f, 0.7f}));
  CHECK(metal.roughness == Approx(0.3f));
  CHECK(metal.metallic == 1.f);
  CHECK(metal.sheen == Approx(0.2f));
  CHECK(metal.coat == Approx(0.4f));
  CHECK(metal.coat_roughness == Approx(0.1f));
  CHECK(metal.anisotropy == Approx(0.5f));
  CHECK(metal.rotation == Approx(0.25f));
  CHECK(metal.ior == Approx(1.33f));
  CHECK(metal.opacity == 0.5f);
  REQUIRE(metal.map_roughness);
  CHECK(metal.map_roughness.texture->texel(0, 0).x == Approx(0.2f));  // scalar maps stay linear
  REQUIRE(metal.map_normal);
  CHECK(metal.normal == 0.5f);
  const Vec3f up = metal.map_normal.at({0.5f, 0.5f});
  CHECK(std::abs(up.x) < 0.01f);
  CHECK(up.z == Approx(1.f).margin(0.01));
  const auto& lamp = std::get<PrincipledMaterial>(scene.materials[1]);
  CHECK(near(lamp.emissive_color, {4.f, 3.f, 2.f}));
  CHECK(lamp.ior == 1.5f);  // Ni absent
  const auto& bumpy = std::get<ObjMaterial>(scene.materials[2]);
  CHECK(!bumpy.map_bump);  // a grey bump map is a height map: skipped, with a warning
  REQUIRE(scene.warnings.size() == 1);
  CHECK_THAT(scene.warnings[0], Contains("material 'bumpy': map_Bump 'height.png' is ignored: a normal map needs 3"));

  SECTION("forced to obj, the PBR values are reported as ignored") {
    const ObjScene as_obj = read_obj(file, {sciray::io::ObjMaterialModel::obj});
    CHECK(std::holds_alternative<ObjMaterial>(as_obj.materials[0]));
    CHECK(std::get<ObjMaterial>(as_obj.materials[0]).map_bump);
    const auto warned = [&](const std::string& what) {
      return std::any_of(as_obj.warnings.begin(), as_obj.warnings.end(),
                         [&](const std::string& w) { return w.find(what) != std::string::npos; });
    };
    CHECK(warned("material 'metal': the PBR parameters are ignored"));
    CHECK(warned("material 'metal': -bm is ignored"));
    CHECK(warned("material 'lamp': Ke is ignored"));
  }
  SECTION("forced to principled") {
    const ObjScene as_principled = read_obj(file, {sciray::io::ObjMaterialModel::principled});
    CHECK(std::get<PrincipledMaterial>(as_principled.materials[2]).base_color.x == 0.5f);
  }
}

TEST_CASE("obj: one vertex per distinct position, texcoord and normal", "[io][obj]") {
  TempDir dir("sciray_test_obj_");
  std::string faces;
  for (int k = 0; k < 6; ++k) faces += cube_face(k);
  SECTION("per-face normals: 24 vertices") {
    const ObjScene scene =
        read_obj(dir.write("flat.obj", std::string(cube_positions) + cube_texcoords + cube_normals + faces));
    REQUIRE(scene.meshes.size() == 1);
    CHECK(scene.meshes[0].name.empty());
    CHECK(scene.meshes[0].mesh.vertex_count() == 24);
    CHECK(scene.meshes[0].mesh.face_count() == 12);
    CHECK(scene.materials.empty());  // faces without usemtl take the engine's default
    CHECK(scene.meshes[0].material == sciray::no_material);
  }
  SECTION("positions alone, relative indices and vertex colours: 8 vertices") {
    std::string obj = "o cube\n";
    for (int v = 0; v < 8; ++v)
      obj += "v " + std::to_string(v & 1) + ' ' + std::to_string(v >> 1 & 1) + ' ' + std::to_string(v >> 2) +
             " 0.5 0.25 1\n";
    obj += "f -8 -7 -5 -6\nf 5 6 8 7\nf 1 3 7 5\nf 2 6 8 4\nf 1 5 6 2\nf 3 4 8 7\n";
    const ObjScene scene = read_obj(dir.write("smooth.obj", obj));
    REQUIRE(scene.meshes.size() == 1);
    const MeshData& mesh = scene.meshes[0].mesh;
    CHECK(scene.meshes[0].name == "cube");
    CHECK(mesh.vertex_count() == 8);
    CHECK(mesh.face_count() == 12);
    CHECK(mesh.normals.empty());
    CHECK(mesh.texcoords.empty());
    REQUIRE(mesh.vertex_colors.size() == 32);
    CHECK(mesh.vertex_colors[0] == 0.5f);
    CHECK(mesh.vertex_colors[3] == 1.f);
    CHECK(total_area(mesh) == Approx(6.0));
  }
  SECTION("faces with and without normals go to separate meshes") {
    const ObjScene scene = read_obj(dir.write(
        "mixed.obj", std::string(cube_positions) + cube_normals + "f 1//1 2//1 3//1\nf 1 3 4\nf 1//1 3//1 4//1\n"));
    REQUIRE(scene.meshes.size() == 2);
    CHECK(scene.meshes[0].mesh.normals.size() == 3 * scene.meshes[0].mesh.vertex_count());
    CHECK(scene.meshes[0].mesh.face_count() == 2);
    CHECK(scene.meshes[0].mesh.vertex_count() == 4);
    CHECK(scene.meshes[1].mesh.normals.empty());
    CHECK(scene.meshes[0].material == scene.meshes[1].material);
  }
}

TEST_CASE("obj: quads and pentagons are triangulated by tinyobjloader", "[io][obj]") {
  TempDir dir("sciray_test_obj_");
  SECTION("a quad splits along its shorter diagonal") {
    // Corner 2 is pulled in, so the diagonal 1-3 is longer than 2-4... by construction 2-4 is shorter.
    const ObjScene scene = read_obj(dir.write("quad.obj", "v 0 0 0\nv 1.5 1.5 0\nv 4 0 0\nv 1.5 -1 0\nf 1 2 3 4\n"));
    const MeshData& mesh = scene.meshes[0].mesh;
    REQUIRE(mesh.face_count() == 2);
    CHECK(total_area(mesh) == Approx(0.5 * 4 * 2.5));
    for (std::size_t f = 0; f < 2; ++f) {  // both triangles use the diagonal 2-4 (indices 1 and 3)
      const auto* t = &mesh.indices[3 * f];
      CHECK(std::count_if(t, t + 3, [&](std::uint32_t i) { return mesh.positions[3 * i] == 1.5f; }) == 2);
    }
  }
  SECTION("a convex and a concave pentagon give 3 triangles covering them") {
    const ObjScene convex =
        read_obj(dir.write("convex.obj", "v 0 0 0\nv 2 0 0\nv 3 1 0\nv 1 2 0\nv -1 1 0\nf 1 2 3 4 5\n"));
    CHECK(convex.meshes[0].mesh.face_count() == 3);
    CHECK(total_area(convex.meshes[0].mesh) == Approx(5.0));
    // An arrow: the fan from vertex 1 would cover area outside it.
    const ObjScene concave =
        read_obj(dir.write("concave.obj", "v 0 0 0\nv 4 0 0\nv 4 4 0\nv 2 1 0\nv 0 4 0\nf 1 2 3 4 5\n"));
    CHECK(concave.meshes[0].mesh.face_count() == 3);
    CHECK(total_area(concave.meshes[0].mesh) == Approx(16.0 - 0.5 * 4 * 3));
    CHECK(concave.warnings.empty());
  }
}

TEST_CASE("obj: JPEG textures, Windows paths and one texture for many materials", "[io][obj]") {
  TempDir dir("sciray_test_obj_");
  const std::uint8_t grey[3] = {200, 200, 200};
  REQUIRE(stbi_write_jpg((dir.path() / "grey.jpg").c_str(), 1, 1, 3, grey, 95));
  write_png(dir, "maps/kd.png", 1, 1, 3, {255, 255, 255});
  dir.write("lib/m.mtl",
            "newmtl a\nKd 1 1 1\nmap_Kd ..\\maps\\kd.png\nmap_Ks ../grey.jpg\n"
            "newmtl b\nKd 1 1 1\nmap_Kd ../maps/kd.png\n");
  const ObjScene scene = read_obj(dir.write(
      "scene.obj", std::string("mtllib lib\\m.mtl\n") + cube_positions + "usemtl a\nf 1 2 3\nusemtl b\nf 1 3 4\n"));
  REQUIRE(scene.materials.size() == 2);
  const auto& a = std::get<ObjMaterial>(scene.materials[0]);
  const auto& b = std::get<ObjMaterial>(scene.materials[1]);
  REQUIRE(a.map_ks);
  CHECK(a.map_ks.texture->texel(0, 0).x == Approx(sciray::srgb_to_linear(200.f / 255.f)).margin(0.02));
  CHECK(a.map_kd.texture == b.map_kd.texture);  // loaded once
  CHECK(!a.map_kd.alpha);                       // RGB: nothing to cut out
}

TEST_CASE("obj: warnings for what is read but not rendered", "[io][obj]") {
  TempDir dir("sciray_test_obj_");
  dir.write("both.mtl", "newmtl m\nd 0.5\nTr 0.9\n");
  const ObjScene scene = read_obj(
      dir.write("warn.obj", std::string("mtllib both.mtl\n") + cube_positions + "usemtl m\nl 1 2\np 3\nf 1 2 3\n"));
  REQUIRE(scene.warnings.size() == 2);
  CHECK_THAT(scene.warnings[0], Contains("Both `d` and `Tr`"));
  CHECK_THAT(scene.warnings[1], Contains("warn.obj: 2 line (l) and point (p) elements are ignored"));
  CHECK(std::get<ObjMaterial>(scene.materials[0]).d == 0.5f);  // d wins
}

TEST_CASE("obj: every error names the file and what is wrong", "[io][obj]") {
  TempDir dir("sciray_test_obj_");
  const std::string v = cube_positions;  // lines 1-8
  const auto error_of = [&](const std::string& obj) {
    const auto file = dir.write("bad.obj", obj);
    try {
      read_obj(file);
    } catch (const sciray::Error& e) {
      return std::string(e.what());
    }
    FAIL("no error for:\n" << obj);
    return std::string();
  };
  const auto at = [&](int line) { return (dir.path() / "bad.obj").string() + ": line " + std::to_string(line) + ": "; };
  CHECK_THROWS_WITH(read_obj(dir.path() / "nothing.obj"), Contains("nothing.obj: cannot open the file"));
  CHECK_THROWS_WITH(read_obj(dir.path()), Contains(dir.path().string() + ": cannot open the file"));
  CHECK_THAT(error_of(v + "f 1 2 9\n"), Contains(at(9) + "f refers to v 9 but the file has 8"));
  CHECK_THAT(error_of(v + "vt 0 0\nf 1/1 2/2 3/1\n"), Contains(at(10) + "f refers to vt 2 but the file has 1"));
  CHECK_THAT(error_of(v + "vn 0 0 1\nf 1//1 2//1 3//2\n"), Contains(at(10) + "f refers to vn 2 but the file has 1"));
  CHECK_THAT(error_of(v + "f 1 2 -9\n"),
             Contains(at(9) + "f vertex '-9': relative index -9 reaches before the first v (there are 8 so far)"));
  CHECK_THAT(error_of(v + "f 0 1 2\n"), Contains(at(9) + "f vertex '0': '0' is not an index (they start at 1)"));
  CHECK_THAT(error_of(v + "f 1 2 x\n"), Contains(at(9) + "f vertex 'x': 'x' is not an index"));
  CHECK_THAT(error_of(v + "f 1/1/1/1 2 3\n"), Contains(at(9) + "f vertex '1/1/1/1' has more than 3 indices"));
  CHECK_THAT(error_of(v + "f 1 2\n"), Contains(at(9) + "face has 2 vertices; a face needs at least 3"));
  CHECK_THAT(error_of("v 0 nan 0\n" + v + "f 1 2 3\n"), Contains(at(1) + "v value 'nan' is not finite"));
  CHECK_THAT(error_of("v 0 0 1e39\n" + v + "f 1 2 3\n"), Contains(at(1) + "v value '1e39' is not finite"));
  CHECK_THAT(error_of(v + "vn 0 abc 1\nf 1 2 3\n"), Contains(at(9) + "vn value 'abc' is not a number"));
  CHECK_THAT(error_of(v + "vt\nf 1 2 3\n"), Contains(at(9) + "vt has 0 values; it needs 1"));
  CHECK_THAT(error_of(v), Contains("bad.obj: no faces (f lines): nothing to render"));
  // Truncated: inside a vertex, inside a face.
  CHECK_THAT(error_of(v + "f 1 2 3\nv 1 0."), Contains(at(10) + "v has 2 values; it needs 3 (is the file truncated?)"));
  CHECK_THAT(error_of(v + "vn 0 0 1\nf 1//1 2//1 3/"), Contains(at(10) + "f vertex '3/' has an empty index"));

  // Material libraries and materials.
  CHECK_THAT(error_of("# scene\nmtllib missing.mtl\n" + v + "f 1 2 3\n"),
             Contains(at(2) + "mtllib 'missing.mtl': cannot open " + (dir.path() / "missing.mtl").string()));
  CHECK_THAT(error_of(v + "usemtl red\nf 1 2 3\n"),
             Contains(at(9) + "usemtl 'red': the file names no material library (mtllib)"));
  dir.write("one.mtl", "newmtl red\nKd 1 0 0\n");
  CHECK_THAT(error_of("mtllib one.mtl\n" + v + "usemtl blue\nf 1 2 3\n"),
             Contains(at(10) + "usemtl 'blue': no material of that name in the material libraries"));
  CHECK_THAT(error_of(v + "usemtl red\nmtllib one.mtl\nf 1 2 3\n"),
             Contains(at(9) + "usemtl 'red': its mtllib is on line 10, after it"));
  const std::string mtl = (dir.path() / "m.mtl").string();
  dir.write("m.mtl", "newmtl red\nKd 1 0 0\n\nnewmtl tex\nKd 1 1 1\nmap_Kd gone.png\n");
  CHECK_THAT(
      error_of("mtllib m.mtl\n" + v + "usemtl tex\nf 1 2 3\n"),
      Contains(mtl + ": line 6: material 'tex', map_Kd 'gone.png': cannot open " + (dir.path() / "gone.png").string()));
  dir.write("bad.png", "not a png");
  dir.write("m.mtl", "newmtl tex\nKd 1 1 1\nmap_Ks bad.png\n");
  CHECK_THAT(error_of("mtllib m.mtl\n" + v + "usemtl tex\nf 1 2 3\n"),
             Contains(mtl + ": line 3: material 'tex', map_Ks 'bad.png': read_png:"));
  dir.write("m.mtl", "newmtl tex\nKd 1 1 1\nmap_Kd image.gif\n");
  dir.write("image.gif", "GIF89a");
  CHECK_THAT(error_of("mtllib m.mtl\n" + v + "usemtl tex\nf 1 2 3\n"), Contains("map_Kd 'image.gif': read_png:"));
  dir.write("m.mtl", "newmtl glassy\nd 1.5\n");
  CHECK_THAT(error_of("mtllib m.mtl\n" + v + "usemtl glassy\nf 1 2 3\n"),
             Contains(mtl + ": material 'glassy': obj material: parameter 'd' must be in [0, 1]"));
  dir.write("m.mtl", "newmtl rough\nPr 2\n");
  CHECK_THAT(error_of("mtllib m.mtl\n" + v + "usemtl rough\nf 1 2 3\n"),
             Contains("material 'rough': principled material: parameter 'roughness' must be in [0, 1]"));
  write_png(dir, "t.png", 1, 1, 3, {1, 2, 3});
  dir.write("m.mtl", "newmtl tex\nmap_Kd -s 0 1 1 t.png\n");
  CHECK_THAT(error_of("mtllib m.mtl\n" + v + "usemtl tex\nf 1 2 3\n"), Contains("-s or -o is zero or not finite"));
}
