// Clipping geometry: what lies inside a clipping volume is not there, for Embree's own
// primitives and sciray's, direct and instanced, on every ISA.
#include <catch2/catch.hpp>

#include <cmath>
#include <memory>
#include <vector>

#include "sciray/io/frame_io.hpp"
#include "sciray/shim/engine.hpp"
#include "sciray/testing/image_compare.hpp"
#include "sciray/testing/scenes.hpp"
#include "support/isas.hpp"
#include "support/trace.hpp"

using namespace sciray;
using sciray::test_support::supported_isas;
using sciray::test_support::trace;

namespace {

/// A closed cube [lower, upper] as 12 outward-facing triangles.
MeshData cube_mesh(const Vec3f& lower, const Vec3f& upper) {
  MeshData m;
  for (int k = 0; k < 8; ++k)
    m.positions.insert(m.positions.end(), {k & 1 ? upper.x : lower.x, k & 2 ? upper.y : lower.y,
                                           k & 4 ? upper.z : lower.z});
  m.indices = {0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4,
               2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1, 3, 5, 3, 7, 5};
  return m;
}

}  // namespace

TEST_CASE("a clipped front face shows what lies behind it", "[clipping][simd]") {
  // A solid box and a sphere inside it; a clipping sphere bites into the box's front.
  const std::vector<Ray<float>> rays{{{0.f, 0.f, -5.f}, {0.f, 0.f, 1.f}},    // through the bite
                                     {{0.9f, 0.f, -5.f}, {0.f, 0.f, 1.f}}};  // beside it
  for (auto isa : supported_isas()) {
    for (auto intersector : {SphereIntersector::sciray, SphereIntersector::embree}) {
      INFO(simd::isa_name(isa) << (intersector == SphereIntersector::sciray ? " sciray" : " embree"));
      accel::Device device;
      shim::EngineWorld world(device);
      world.add(TriangleMesh(cube_mesh({-1.f, -1.f, -1.f}, {1.f, 1.f, 1.f})));
      SphereData ball;
      ball.positions = {0.f, 0.f, 0.f};
      ball.radius = 0.3f;
      world.add(Spheres(ball).set_intersector(intersector));
      auto clipping = std::make_shared<Clipping>();
      clipping->add_sphere({0.f, 0.f, -1.f}, 0.8f);  // removes the front face and the ball's front half
      world.set_clipping(clipping);
      const auto got = trace(isa, world, rays);
      // The ball's near side (z = -0.3) is inside the clipping sphere; its far side
      // (z = +0.3, 1.3 from the clipping centre) is not.
      CHECK(got[0].geom_id == 1);
      CHECK(got[0].t == Approx(5.3f).epsilon(1e-5));
      CHECK(got[1].geom_id == 0);
      CHECK(got[1].t == Approx(4.f).epsilon(1e-5));

      // Inverted: only what is inside the clipping sphere remains.
      clipping = std::make_shared<Clipping>();
      clipping->add_sphere({0.f, 0.f, -1.f}, 0.8f, true);
      world.set_clipping(clipping);
      const auto inverted = trace(isa, world, rays);
      CHECK(inverted[0].geom_id == 0);
      CHECK(inverted[0].t == Approx(4.f).epsilon(1e-5));
      CHECK(inverted[1].geom_id == -1);  // x = 0.9 at z = -1 is outside the sphere of 0.8
    }
  }
}

TEST_CASE("a closed clipping mesh clips as the analytic box it encloses", "[clipping][render]") {
  // Random spheres cut by a box, once as a clipping box and once as a clipping mesh.
  const auto render = [](bool as_mesh, bool invert) {
    accel::Device device;
    shim::EngineWorld world(device);
    world.add(Spheres(testing::random_spheres(500, 9)));
    auto clipping = std::make_shared<Clipping>();
    const Vec3f lower{0.3f, 0.25f, -1.f}, upper{1.5f, 0.8f, 0.6f};
    if (as_mesh)
      clipping->add_mesh(std::make_shared<MeshData>(cube_mesh(lower, upper)), invert);
    else
      clipping->add_box({lower, upper}, invert);
    world.set_clipping(clipping);
    const auto& kernels = shim::kernels(shim::select_isa());
    kernels.commit(world);
    FrameBuffer fb(96, 96, ColorFormat::rgba32f);
    SciVisParams params;
    params.lights = default_lights({0.5f, -0.7f, -0.6f});
    kernels.render_scivis(world, params, frame_bounds(Box3f{{0, 0, 0}, {1, 1, 1}}, 1.f), fb, nullptr);
    return io::color_image(fb);
  };
  for (bool invert : {false, true}) {
    INFO("invert " << invert);
    const auto box = render(false, invert), mesh = render(true, invert);
    const auto diff = testing::compare_images(mesh, box, 1e-3);
    INFO(testing::describe(diff));
    // Parity at a point on the cube's own faces may round either way: a few pixels.
    CHECK(diff.differing_pixels <= 4);
  }
  // And the clipping does something: the clipped image differs from the inverted one.
  CHECK(testing::compare_images(render(false, false), render(false, true), 1e-3).differing_pixels > 500);
}

TEST_CASE("planes clip the half-space behind their normal, instances in world space", "[clipping][instancing]") {
  for (auto isa : supported_isas()) {
    INFO(simd::isa_name(isa));
    accel::Device device;
    shim::EngineWorld world(device);
    auto group = std::make_shared<shim::EngineWorld::GroupType>(device);
    SphereData unit;
    unit.positions = {0.f, 0.f, 0.f};
    unit.radius = 1.f;
    group->add(Spheres(unit));
    world.add_instance(group, Affine3f::translate({10.f, 0.f, 0.f}));
    auto clipping = std::make_shared<Clipping>();
    clipping->add_plane({0.f, 0.f, 1.f}, 0.f);  // clips z < 0: the sphere's near half
    world.set_clipping(clipping);
    const std::vector<Ray<float>> rays{{{10.f, 0.f, -5.f}, {0.f, 0.f, 1.f}}, {{10.f, 0.5f, -5.f}, {0.f, 0.f, 1.f}}};
    const auto got = trace(isa, world, rays);
    CHECK(got[0].t == Approx(6.f).epsilon(1e-5));  // the far side, z = +1
    CHECK(got[1].t == Approx(5.f + std::sqrt(0.75f)).epsilon(1e-5));
    CHECK(got[0].inst_id == 0);
  }
}

TEST_CASE("clipping input is checked", "[clipping][errors]") {
  Clipping clipping;
  CHECK_THROWS_WITH(clipping.add_sphere({0, 0, 0}, -1.f), Catch::Contains("positive radius"));
  CHECK_THROWS_WITH(clipping.add_box({{0, 0, 0}, {-1, 1, 1}}), Catch::Contains("lower <= upper"));
  CHECK_THROWS_WITH(clipping.add_plane({0, 0, 0}, 1.f), Catch::Contains("non-zero normal"));
  MeshData broken = cube_mesh({0, 0, 0}, {1, 1, 1});
  broken.indices[5] = 99;
  CHECK_THROWS_WITH(clipping.add_mesh(std::make_shared<MeshData>(broken)), Catch::Contains("refers to vertex 99"));
}

TEST_CASE("clipping geometry placed by a moving transform clips where it is at each ray's time", "[clipping][motion]") {
  // A clipping sphere of radius 0.5 on the cube's front face, carried from x = -0.5 at
  // time 0 to x = +0.5 at time 1: rays down +z at x = -0.5 and x = +0.5 pass the front
  // face (t = 4) and reach the back face (t = 6) only while the sphere is over them.
  // From time 1 on the moving placement is gone, as Embree shows a moving instance.
  const auto ray = [](float x, float time) {
    Ray<float> r{{x, 0.f, -5.f}, {0.f, 0.f, 1.f}};
    r.time = time;
    return r;
  };
  for (auto isa : supported_isas()) {
    INFO(simd::isa_name(isa));
    accel::Device device;
    shim::EngineWorld world(device);
    world.add(TriangleMesh(cube_mesh({-1.f, -1.f, -1.f}, {1.f, 1.f, 1.f})));
    auto sphere = std::make_shared<Clipping>();
    sphere->add_sphere({0.f, 0.f, -1.f}, 0.5f);
    auto clipping = std::make_shared<Clipping>();
    clipping->add_placed(
        sphere,
        MotionTransform({Affine3f::translate({-0.5f, 0.f, 0.f}), Affine3f::translate({0.5f, 0.f, 0.f})}, 0.f, 1.f));
    world.set_clipping(clipping);
    const auto got =
        trace(isa, world,
              {ray(-0.5f, 0.f), ray(0.5f, 0.f), ray(-0.5f, 0.99f), ray(0.5f, 0.99f), ray(0.f, 0.5f), ray(0.5f, 1.f)});
    CHECK(got[0].t == Approx(6.f).epsilon(1e-5));  // time 0: the sphere is over x = -0.5
    CHECK(got[1].t == Approx(4.f).epsilon(1e-5));
    CHECK(got[2].t == Approx(4.f).epsilon(1e-5));  // time 0.99: over x = +0.49
    CHECK(got[3].t == Approx(6.f).epsilon(1e-5));
    CHECK(got[4].t == Approx(6.f).epsilon(1e-5));  // halfway: over x = 0
    CHECK(got[5].t == Approx(4.f).epsilon(1e-5));  // time 1: no longer there
  }
}

TEST_CASE("a clipping sphere under a non-uniform scale clips as its ellipsoid", "[clipping]") {
  // The sphere of radius 0.5 about (0, 0, -0.5), scaled by (2, 1, 2): the ellipsoid about
  // (0, 0, -1) with semi-axes 1, 0.5 and 1. Its front face bite reaches x = ±1 along x
  // but only y = ±0.5 along y; on the face (z = -1) points inside satisfy x² + 4y² < 1.
  accel::Device device;
  shim::EngineWorld world(device);
  world.add(TriangleMesh(cube_mesh({-1.f, -1.f, -1.f}, {1.f, 1.f, 1.f})));
  auto sphere = std::make_shared<Clipping>();
  sphere->add_sphere({0.f, 0.f, -0.5f}, 0.5f);
  auto clipping = std::make_shared<Clipping>();
  Affine3f scale;
  scale.vx = {2.f, 0.f, 0.f}, scale.vz = {0.f, 0.f, 2.f};
  clipping->add_placed(sphere, MotionTransform(scale));
  world.set_clipping(clipping);
  const std::vector<Ray<float>> rays{{{0.8f, 0.f, -5.f}, {0.f, 0.f, 1.f}},     // x² + 4y² = 0.64
                                     {{0.f, 0.4f, -5.f}, {0.f, 0.f, 1.f}},     // 0.64
                                     {{0.f, 0.6f, -5.f}, {0.f, 0.f, 1.f}},     // 1.44
                                     {{0.6f, 0.45f, -5.f}, {0.f, 0.f, 1.f}}};  // 1.17
  const auto got = trace(shim::select_isa(), world, rays);
  CHECK(got[0].t == Approx(6.f).epsilon(1e-5));
  CHECK(got[1].t == Approx(6.f).epsilon(1e-5));
  CHECK(got[2].t == Approx(4.f).epsilon(1e-5));
  CHECK(got[3].t == Approx(4.f).epsilon(1e-5));
  CHECK_THROWS_WITH(Clipping().add_placed(sphere, MotionTransform(Affine3f::scale(0.f))),
                    Catch::Contains("clipping placement 0: its transform is singular"));
}
