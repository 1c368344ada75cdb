// Triangle/quad meshes: validation names bad input; Embree sees what sciray validated;
// shading interpolates what the mesh holds.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <map>

#include "sciray/accel/trace.hpp"
#include "sciray/geometry/triangle_mesh.hpp"
#include "sciray/scene/world.hpp"
#include "sciray/testing/scenes.hpp"

using namespace sciray;

namespace {

/// A unit square in z = 0 made of two triangles, or of one quad.
MeshData square(bool quad) {
  MeshData m;
  m.positions = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
  if (quad) {
    m.vertices_per_face = 4;
    m.indices = {0, 1, 2, 3};
  } else {
    m.indices = {0, 1, 2, 0, 2, 3};
  }
  return m;
}

Ray<float> down_at(float x, float y) {
  Ray<float> r;
  r.org = {x, y, 1.f};
  r.dir = {0.f, 0.f, -1.f};
  return r;
}

}  // namespace

TEST_CASE("mesh validation names the bad value", "[mesh][errors]") {
  SECTION("index out of range") {
    MeshData m = square(false);
    m.indices[4] = 9;
    CHECK_THROWS_WITH(TriangleMesh(m).validate(),
                      Catch::Contains("'index' of face 1 refers to vertex 9 but 'vertex.position' has 4"));
  }
  SECTION("NaN vertex") {
    MeshData m = square(false);
    m.positions[7] = std::nanf("");
    CHECK_THROWS_WITH(TriangleMesh(m).validate(), Catch::Contains("'vertex.position' 2 is not finite"));
  }
  SECTION("missing arrays") {
    MeshData m;
    CHECK_THROWS_WITH(TriangleMesh(m).validate(), Catch::Contains("'vertex.position' is missing"));
    m.positions = {0, 0, 0};
    CHECK_THROWS_WITH(TriangleMesh(m).validate(), Catch::Contains("'index' is missing"));
  }
  SECTION("normals of the wrong count") {
    MeshData m = square(false);
    m.normals = {0, 0, 1};
    CHECK_THROWS_WITH(TriangleMesh(m).validate(), Catch::Contains("'vertex.normal' has 1 elements but there are 4"));
  }
  SECTION("shared arrays with a too-small stride") {
    const float positions[9] = {};
    const std::uint32_t indices[3] = {0, 1, 2};
    TriangleMesh::SharedArrays arrays;
    arrays.positions = {positions, 3, 8};
    arrays.indices = {indices, 1, 12};
    CHECK_THROWS_WITH(TriangleMesh::shared(arrays).validate(), Catch::Contains("'vertex.position' byte stride 8"));
  }
  SECTION("world commit reports the geometry's error") {
    accel::Device device;
    World<TriangleMesh> world(device);
    MeshData m = square(true);
    m.indices[3] = 4;
    world.add(TriangleMesh(m));
    CHECK_THROWS_WITH(world.commit(), Catch::Contains("refers to vertex 4"));
  }
}

TEST_CASE("triangle and quad meshes hit where the geometry is", "[mesh][accel]") {
  for (bool quad : {false, true}) {
    accel::Device device;
    World<TriangleMesh> world(device);
    MeshData m = square(quad);
    m.vertex_colors = {0, 0, 0, 1, 1, 0, 0, 1, 1, 1, 0, 1, 0, 1, 0, 1};  // colour = (x, y, 0)
    world.add(TriangleMesh(std::move(m)));
    world.commit();
    CHECK(world.bounds().upper == Vec3f{1.f, 1.f, 0.f});
    for (const auto& [x, y] : {std::pair{0.2f, 0.1f}, {0.9f, 0.7f}, {0.3f, 0.6f}, {0.55f, 0.5f}}) {
      const auto hit = accel::intersect<simd::scalar>(world.scene(), down_at(x, y), true);
      REQUIRE(hit.hit);
      CHECK(hit.t == Approx(1.f));
      // Interpolated vertex colours reproduce the hit position on both halves of a quad.
      const auto s = world.all<TriangleMesh>()[0].surface<simd::scalar>(hit, true);
      CHECK(s.color.x == Approx(x).margin(1e-5));
      CHECK(s.color.y == Approx(y).margin(1e-5));
      CHECK(std::abs(s.normal.z) == Approx(1.f));
    }
    CHECK_FALSE(accel::intersect<simd::scalar>(world.scene(), down_at(1.5f, 0.5f), true).hit);
    Ray<float> shadow = down_at(0.5f, 0.5f);
    CHECK(accel::occluded<simd::scalar>(world.scene(), shadow, true));
    shadow.tfar = 0.5f;
    CHECK_FALSE(accel::occluded<simd::scalar>(world.scene(), shadow, true));
  }
}

TEST_CASE("shared arrays are used in place", "[mesh]") {
  // Padding after the last vertex and index, as Embree reads 16 bytes at a time.
  float positions[9 + 4] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  std::uint32_t indices[3 + 4] = {0, 1, 2};
  TriangleMesh::SharedArrays arrays;
  arrays.positions = {positions, 3, 12};
  arrays.indices = {indices, 1, 12};
  accel::Device device;
  World<TriangleMesh> world(device);
  world.add(TriangleMesh::shared(arrays));
  world.commit();
  CHECK(world.all<TriangleMesh>()[0].owned_bytes() == 0);
  CHECK(accel::intersect<simd::scalar>(world.scene(), down_at(0.2f, 0.2f), true).hit);
  CHECK(world.memory_bytes() > 0);  // Embree's BVH
}

TEST_CASE("the procedural torus is closed and consistently oriented", "[mesh][testing]") {
  const MeshData tris = testing::wavy_torus(20'000);
  const MeshData quads = testing::wavy_torus(20'000, true);
  CHECK(tris.face_count() == 2 * quads.face_count());
  CHECK(tris.face_count() == Approx(20'000).epsilon(0.05));
  TriangleMesh(tris).validate();
  TriangleMesh(quads).validate();
  // A closed surface: every edge is shared by exactly two triangles.
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> edges;
  for (std::size_t f = 0; f < tris.face_count(); ++f)
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = tris.indices[3 * f + k], b = tris.indices[3 * f + (k + 1) % 3];
      ++edges[{std::min(a, b), std::max(a, b)}];
    }
  for (const auto& [edge, count] : edges) REQUIRE(count == 2);
}

TEST_CASE("deforming mesh: normals of each time step are interpolated at the ray's time", "[mesh][motion]") {
  // A unit quad in z = 0 that stays put while its normals turn about the y axis: 0, 45
  // and 90 degrees from +z at three time steps over [0, 1] (motion.vertex.normal). As in
  // OSPRay (Mesh.ispc), a normal is lerped between the two steps around the ray's time
  // and then normalized, so at the fraction f between steps at angles a and a + 45° it
  // points at a + atan2(f sin 45°, 1 - f + f cos 45°) — halfway, the bisector.
  constexpr float pi = 3.14159265f, step = pi / 4.f;
  MeshData m = square(true);
  m.motion_positions = {m.positions, m.positions, m.positions};
  for (int k = 0; k < 3; ++k) {
    auto& normals = m.motion_normals.emplace_back();
    for (int v = 0; v < 4; ++v) normals.insert(normals.end(), {std::sin(k * step), 0.f, std::cos(k * step)});
  }
  const auto expected_angle = [&](float time) {
    const float x = 2.f * time, k = std::min(std::floor(x), 1.f), f = x - k;
    return k * step + std::atan2(f * std::sin(step), 1.f - f + f * std::cos(step));
  };
  accel::Device device;
  World<TriangleMesh> world(device);
  world.add(TriangleMesh(m));
  world.commit();
  const TriangleMesh& mesh = world.all<TriangleMesh>()[0];

  // One ray at a time: 0, 22.5, 45 and 67.5 degrees.
  for (const float time : {0.f, 0.25f, 0.5f, 0.75f}) {
    INFO("time " << time);
    Ray<float> ray = down_at(0.3f, 0.6f);
    ray.time = time;
    const auto hit = accel::intersect<simd::scalar>(world.scene(), ray, true);
    REQUIRE(hit.hit);
    const auto s = mesh.surface<simd::scalar>(hit, true);
    CHECK(s.normal.x == Approx(std::sin(2.f * time * step)).margin(1e-6));
    CHECK(s.normal.y == Approx(0.f).margin(1e-6));
    CHECK(s.normal.z == Approx(std::cos(2.f * time * step)).margin(1e-6));
  }

  // A packet whose lanes lie in both segments between the steps.
  using A = xsimd::sse2;
  using F = simd::Float<A>;
  const F time{0.1f, 0.3f, 0.6f, 0.95f};
  Ray<F> rays;
  rays.org = {F{0.2f, 0.4f, 0.6f, 0.8f}, F(0.5f), F(1.f)};
  rays.dir = {F(0.f), F(0.f), F(-1.f)};
  rays.time = time;
  const auto hit = accel::intersect<A>(world.scene(), rays, F(0.f) == F(0.f));
  REQUIRE(simd::all(hit.hit));
  const auto s = mesh.surface<A>(hit, hit.hit);
  for (int i = 0; i < 4; ++i) {
    INFO("lane " << i << " at time " << simd::lane(time, i));
    const float angle = expected_angle(simd::lane(time, i));
    CHECK(simd::lane(s.normal.x, i) == Approx(std::sin(angle)).margin(1e-6));
    CHECK(simd::lane(s.normal.z, i) == Approx(std::cos(angle)).margin(1e-6));
  }

  // Normals need one array per time step of the positions, each with one per vertex.
  MeshData fewer = m;
  fewer.motion_normals.pop_back();
  CHECK_THROWS_WITH(TriangleMesh(fewer).validate(),
                    Catch::Contains("'motion.vertex.normal' has 2 time steps but 'motion.vertex.position' has 3"));
  MeshData short_step = m;
  short_step.motion_normals[2].resize(9);
  CHECK_THROWS_WITH(TriangleMesh(short_step).validate(),
                    Catch::Contains("'motion.vertex.normal[2]' has 3 elements but there are 4 vertices"));
}
