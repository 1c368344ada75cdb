// Catmull-Clark subdivision surfaces (Embree's, behind sciray's Subdivision) against the
// limit points of a cube worked out by hand, creases, attribute interpolation and
// validation; and OSPRay's `subdivision` geometry through the C API.
#include <ospray/ospray.h>
#include <ospray/ospray_util.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "sciray/shim/engine.hpp"
#include "support/api_fixture.hpp"
#include "support/c_api_scenes.hpp"

using namespace sciray;

namespace {

/// The cube [-1, 1]^3 as six quads, outward facing.
SubdivisionData cube() {
  SubdivisionData d;
  for (int i = 0; i < 8; ++i)
    d.positions.insert(d.positions.end(), {i & 1 ? 1.f : -1.f, i & 2 ? 1.f : -1.f, i & 4 ? 1.f : -1.f});
  d.indices = {0, 2, 3, 1, 4, 5, 7, 6, 0, 1, 5, 4, 2, 6, 7, 3, 0, 4, 6, 2, 1, 3, 7, 5};
  d.face_sizes.assign(6, 4);
  return d;
}

/// The cube's 12 edges.
const std::vector<std::uint32_t> cube_edges = {0, 1, 2, 3, 4, 5, 6, 7, 0, 2, 1, 3, 4, 6, 5, 7, 0, 4, 1, 5, 2, 6, 3, 7};

struct SurfaceHit {
  Vec3f position, normal, color;
  TexCoord<float> uv;
  bool has_color;
};

/// The hit of a ray from outside towards the origin along `dir` (scalar path), with its
/// surface sample.
SurfaceHit hit_towards_centre(const shim::EngineWorld& world, Vec3f dir) {
  dir = normalize(dir);
  const Ray<float> ray{dir * -10.f, dir};
  const auto hit = accel::intersect<simd::scalar>(world.scene(), ray, true);
  REQUIRE(hit.hit);
  const auto s = world.all<Subdivision>().front().surface<simd::scalar>(hit, true);
  return {ray.org + ray.dir * hit.t, s.normal, s.color, s.uv, s.has_color};
}

std::vector<Vec3f> directions(std::size_t n) {
  std::vector<Vec3f> out;
  for (std::size_t i = 0; i < n; ++i)  // a spiral over the sphere
    out.push_back(Vec3f{std::cos(2.4f * i) * std::sqrt(1.f - std::pow(1.f - 2.f * (i + 0.5f) / n, 2.f)),
                        std::sin(2.4f * i) * std::sqrt(1.f - std::pow(1.f - 2.f * (i + 0.5f) / n, 2.f)),
                        1.f - 2.f * (i + 0.5f) / n});
  return out;
}

float max_abs(const Vec3f& p) {
  return std::max({std::fabs(p.x), std::fabs(p.y), std::fabs(p.z)});
}

}  // namespace

TEST_CASE("subdivision: the limit surface of a smooth cube passes the limit points worked out by hand",
          "[subdivision]") {
  // One Catmull-Clark step of the cube, then the limit stencils: a face centre's limit
  // point (valence 4) lies at 68/81 along its axis, a corner's (valence 3) at (1/2, 1/2, 1/2).
  accel::Device device;
  shim::EngineWorld world(device);
  SubdivisionData data = cube();
  data.level = 16.f;
  world.add(Subdivision(std::move(data)));
  world.commit<simd::scalar>();
  const SurfaceHit face = hit_towards_centre(world, {0.f, 0.f, -1.f});
  CHECK(face.position.z == Approx(68.f / 81.f).margin(2e-3));
  CHECK(std::fabs(face.normal.z) == Approx(1.f).margin(1e-4));
  const SurfaceHit corner = hit_towards_centre(world, {-1.f, -1.f, -1.f});
  CHECK(length(corner.position) == Approx(std::sqrt(0.75f)).margin(2e-3));
  CHECK(std::fabs(dot(corner.normal, normalize(Vec3f{1.f, 1.f, 1.f}))) == Approx(1.f).margin(1e-3));
  CHECK_FALSE(face.has_color);
  // Everywhere strictly inside the cage, between the corners' and the face centres' radii.
  for (const Vec3f& d : directions(400)) {
    const SurfaceHit h = hit_towards_centre(world, d);
    INFO("direction " << d.x << " " << d.y << " " << d.z);
    CHECK(max_abs(h.position) < 68.f / 81.f + 2e-3f);
    CHECK(length(h.position) > 0.8f);
    CHECK(length(h.position) < std::sqrt(0.75f) + 2e-3f);
    // The smooth normal is close to the tessellation's and faces away from the centre.
    CHECK(std::fabs(dot(h.normal, normalize(h.position))) > 0.8f);
  }
  // The bounds are the cage's, which hold the surface.
  CHECK(world.bounds().upper.x == 1.f);
}

TEST_CASE("subdivision: infinitely sharp edge creases reproduce the cage", "[subdivision]") {
  accel::Device device;
  shim::EngineWorld world(device);
  SubdivisionData data = cube();
  data.edge_creases = {cube_edges.begin(), cube_edges.end()};
  data.edge_crease_weights.assign(12, std::numeric_limits<float>::infinity());
  world.add(Subdivision(std::move(data)));
  world.commit<simd::scalar>();
  CHECK(hit_towards_centre(world, {0.f, 0.f, 1.f}).position.z == Approx(-1.f).margin(1e-4));
  CHECK(length(hit_towards_centre(world, {1.f, 1.f, 1.f}).position) == Approx(std::sqrt(3.f)).margin(1e-3));
  for (const Vec3f& d : directions(200)) {
    const SurfaceHit h = hit_towards_centre(world, d);
    CHECK(max_abs(h.position) == Approx(1.f).margin(1e-3));  // on the cage's faces (to Embree's tessellation)
  }
  // A finite crease weight rounds the edges less than none does: between the two.
  accel::Device device2;
  shim::EngineWorld semi_sharp(device2);
  SubdivisionData data2 = cube();
  data2.edge_creases = {cube_edges.begin(), cube_edges.end()};
  data2.edge_crease_weights.assign(12, 2.f);
  semi_sharp.add(Subdivision(std::move(data2)));
  semi_sharp.commit<simd::scalar>();
  const float corner = length(hit_towards_centre(semi_sharp, {1.f, 1.f, 1.f}).position);
  CHECK(corner > std::sqrt(0.75f) + 0.05f);
  CHECK(corner < std::sqrt(3.f) - 0.05f);
}

TEST_CASE("subdivision: colours and texture coordinates interpolate per vertex", "[subdivision]") {
  // Subdivision is affine-invariant, so attributes that are an affine function of the
  // control points interpolate to the same function of the limit point.
  accel::Device device;
  shim::EngineWorld world(device);
  SubdivisionData data = cube();
  const auto color_of = [](const float* p) {
    return std::vector<float>{0.5f + 0.5f * p[0], 0.5f + 0.25f * p[1], 0.5f - 0.5f * p[2], 1.f};
  };
  for (std::size_t i = 0; i < 8; ++i) {
    const float* p = &data.positions[3 * i];
    const auto c = color_of(p);
    data.colors.insert(data.colors.end(), c.begin(), c.end());
    data.texcoords.insert(data.texcoords.end(), {p[0] + p[1], p[2]});
  }
  data.level = 16.f;
  world.add(Subdivision(std::move(data)));
  world.commit<simd::scalar>();
  for (const Vec3f& d : directions(100)) {
    const SurfaceHit h = hit_towards_centre(world, d);
    REQUIRE(h.has_color);
    const float p[3] = {h.position.x, h.position.y, h.position.z};
    const auto expected = color_of(p);
    CHECK(h.color.x == Approx(expected[0]).margin(2e-3));
    CHECK(h.color.y == Approx(expected[1]).margin(2e-3));
    CHECK(h.color.z == Approx(expected[2]).margin(2e-3));
    CHECK(h.uv.u == Approx(p[0] + p[1]).margin(4e-3));
    CHECK(h.uv.v == Approx(p[2]).margin(2e-3));
  }
}

TEST_CASE("subdivision: face-varying attributes keep the values of each face", "[subdivision]") {
  // Per face corner, every face is its own patch: a colour given to all of a face's
  // corners is that face's colour everywhere on it (subdivision reproduces constants),
  // though the faces share their vertices.
  accel::Device device;
  shim::EngineWorld world(device);
  SubdivisionData data = cube();
  for (std::size_t corner = 0; corner < 24; ++corner) {
    const float f = static_cast<float>(corner / 4);
    data.colors.insert(data.colors.end(), {f / 5.f, 1.f - f / 5.f, 0.25f, 1.f});
    data.texcoords.insert(data.texcoords.end(), {f, 2.f * f});
  }
  data.face_varying_colors = data.face_varying_texcoords = true;
  world.add(Subdivision(std::move(data)));
  world.commit<simd::scalar>();
  for (const Vec3f& d : directions(100)) {
    const Vec3f dir = normalize(d);
    const Ray<float> ray{dir * -10.f, dir};
    const auto hit = accel::intersect<simd::scalar>(world.scene(), ray, true);
    REQUIRE(hit.hit);
    const auto s = world.all<Subdivision>().front().surface<simd::scalar>(hit, true);
    const float f = static_cast<float>(hit.prim_id);
    CHECK(s.color.x == Approx(f / 5.f).margin(1e-5));
    CHECK(s.color.y == Approx(1.f - f / 5.f).margin(1e-5));
    CHECK(s.uv.u == Approx(f).margin(1e-5));
    CHECK(s.uv.v == Approx(2.f * f).margin(1e-5));
  }
}

TEST_CASE("subdivision: bad input is named", "[subdivision]") {
  const auto fails = [](SubdivisionData d, const std::string& message) {
    INFO(message);
    CHECK_THROWS_WITH(Subdivision(std::move(d)).validate(), Catch::Contains(message));
  };
  CHECK_NOTHROW(Subdivision(cube()).validate());
  SubdivisionData d = cube();
  d.indices.back() = 8;
  fails(d, "'index' 23 refers to vertex 8 but 'vertex.position' has 8");
  d = cube(), d.face_sizes.back() = 3;
  fails(d, "the 'face' sizes add up to 23 vertices but 'index' has 24");
  d = cube(), d.face_sizes = {4, 4, 4, 4, 4, 2, 2};
  fails(d, "'face' 5 has 2 vertices; a face needs at least 3");
  d = cube(), d.positions[4] = std::numeric_limits<float>::quiet_NaN();
  fails(d, "'vertex.position' 1 is not finite");
  d = cube(), d.edge_creases = {0, 9}, d.edge_crease_weights = {1.f};
  fails(d, "'edgeCrease.index' 0 refers to vertex 9 but 'vertex.position' has 8");
  d = cube(), d.edge_creases = {0, 1}, d.edge_crease_weights = {1.f, 2.f};
  fails(d, "'edgeCrease.index' has 1 elements but 'edgeCrease.weight' has 2");
  d = cube(), d.vertex_creases = {3}, d.vertex_crease_weights = {-1.f};
  fails(d, "'vertexCrease.weight' 0 must not be negative or NaN");
  d = cube(), d.colors.assign(4 * 7, 1.f);
  fails(d, "'vertex.color' has 7 elements but there are 8 vertices");
  d = cube(), d.texcoords.assign(2 * 8, 0.f), d.face_varying_texcoords = true;
  fails(d, "'texcoord' has 8 elements but there are 24 face corners");
  d = cube(), d.level = 0.f;
  fails(d, "'level' must be finite and positive");
  d = cube(), d.mode = static_cast<SubdivisionMode>(7);
  fails(d, "'mode' has unknown value 7");
}

TEST_CASE("subdivision: a closed surface clips its inside and an open one is refused", "[subdivision][clipping]") {
  accel::Device device;
  Clipping clipping, inverted;
  clipping.add_subdivision(std::make_shared<const SubdivisionData>(cube()));
  inverted.add_subdivision(std::make_shared<const SubdivisionData>(cube()), true);
  clipping.commit(device);
  inverted.commit(device);
  // The limit surface, not the cage, bounds the clipped region: x = 0.9 lies between.
  for (const Vec3f& p : {Vec3f{0.f, 0.f, 0.f}, Vec3f{0.8f, 0.f, 0.f}, Vec3f{0.3f, -0.4f, 0.45f}}) {
    CHECK(clipping.clipped(p, 0.f));
    CHECK_FALSE(inverted.clipped(p, 0.f));
  }
  for (const Vec3f& p : {Vec3f{0.9f, 0.f, 0.f}, Vec3f{0.f, 0.f, 2.f}, Vec3f{0.75f, 0.75f, 0.75f}}) {
    CHECK_FALSE(clipping.clipped(p, 0.f));
    CHECK(inverted.clipped(p, 0.f));
  }
  SubdivisionData open = cube();
  open.indices.resize(20), open.face_sizes.resize(5);
  Clipping refuses;
  CHECK_THROWS_WITH(refuses.add_subdivision(std::make_shared<const SubdivisionData>(std::move(open))),
                    Catch::Contains("only a closed subdivision surface can clip"));
}

// ---- the C API ----------------------------------------------------------------------

namespace {

OSPGeometry new_cube_subdivision(float level) {
  const SubdivisionData d = cube();
  OSPGeometry g = ospNewGeometry("subdivision");
  sciray_test::set_array(g, "vertex.position", d.positions.data(), OSP_VEC3F, 8);
  sciray_test::set_array(g, "index", d.indices.data(), OSP_UINT, d.indices.size());
  ospSetFloat(g, "level", level);
  ospCommit(g);
  return g;
}

}  // namespace

TEST_CASE("subdivision: picks land on the limit surface through the C API", "[c_api][subdivision]") {
  sciray_test::ApiFixture api;
  sciray_test::GeometryScene scene(new_cube_subdivision(16.f));
  const OSPPickResult centre = scene.pick(0.5f, 0.5f);
  REQUIRE(centre.hasHit == 1);
  CHECK(centre.worldPosition[2] == Approx(-68.f / 81.f).margin(2e-3));
  CHECK(centre.primID == 0);  // the face facing -z
  const OSPBounds b = ospGetBounds(scene.geometry);
  CHECK(b.upper[0] <= 1.f);  // Embree's bounds of the tessellation, within the cage
  CHECK(b.upper[0] > 0.8f);
  // Every renderer shows it.
  for (const char* type : {"scivis", "ao", "pathtracer"}) {
    INFO(type);
    OSPRenderer renderer = ospNewRenderer(type);
    ospCommit(renderer);
    OSPFrameBuffer fb = ospNewFrameBuffer(32, 32, OSP_FB_RGBA32F, OSP_FB_COLOR);
    ospRenderFrameBlocking(fb, renderer, scene.camera, scene.world);
    const auto* pixels = static_cast<const float*>(ospMapFrameBuffer(fb, OSP_FB_COLOR));
    CHECK(pixels[4 * (16 * 32 + 16) + 3] == Approx(1.f));  // the centre is covered
    CHECK(pixels[3] == Approx(0.f));                       // a corner is background
    ospUnmapFrameBuffer(pixels, fb);
    ospRelease(fb);
    ospRelease(renderer);
  }
  CHECK(api.messages.errors.empty());
}

TEST_CASE("subdivision: bad parameters are named through the error callback", "[c_api][subdivision][errors]") {
  sciray_test::ApiFixture api;
  OSPGeometry g = new_cube_subdivision(5.f);
  CHECK(api.messages.errors.empty());
  const std::uint32_t faces[3] = {4, 4, 4};
  sciray_test::set_array(g, "face", faces, OSP_UINT, 3);
  ospCommit(g);
  api.expect_error("subdivision: the 'face' sizes add up to 12 vertices but 'index' has 24");
  ospRemoveParam(g, "face");
  const std::uint32_t crease[2] = {0, 11};
  const float weight = 1.f;
  sciray_test::set_array(g, "edgeCrease.index", crease, OSP_VEC2UI, 1);
  sciray_test::set_array(g, "edgeCrease.weight", &weight, OSP_FLOAT, 1);
  ospCommit(g);
  api.expect_error("'edgeCrease.index' 0 refers to vertex 11 but 'vertex.position' has 8");
  ospRemoveParam(g, "edgeCrease.index");
  ospRemoveParam(g, "edgeCrease.weight");
  ospSetInt(g, "mode", 9);
  ospCommit(g);
  api.expect_error("parameter 'mode' has unknown value 9");
  ospSetInt(g, "mode", OSP_SUBDIVISION_PIN_ALL);
  const float two_colors[8] = {1, 0, 0, 1, 0, 1, 0, 1};
  sciray_test::set_array(g, "vertex.color", two_colors, OSP_VEC4F, 2);
  ospCommit(g);
  api.expect_error("'vertex.color' has 2 elements but there are 8 vertices 'index' uses");
  ospRemoveParam(g, "vertex.color");
  ospCommit(g);
  CHECK(api.messages.errors.empty());
  ospRelease(g);
}
