// Triangle/quad meshes: validation names bad input; Embree sees what sciray validated;
// shading interpolates what the mesh holds.
#include <catch2/catch.hpp>

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
