// Boxes and planes (sciray's own packet intersectors as Embree user geometry) on every ISA
// against analytic answers, and their validation.
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <vector>

#include "sciray/shim/engine.hpp"
#include "sciray/testing/scenes.hpp"
#include "support/isas.hpp"
#include "support/trace.hpp"

using namespace sciray;
using sciray::test_support::supported_isas;
using sciray::test_support::trace_geometry;

TEST_CASE("boxes are hit on the face the slab test names, from outside and inside", "[boxes][simd]") {
  const Box3f box{{-1.f, -2.f, -3.f}, {1.f, 2.f, 3.f}};
  std::vector<Ray<float>> rays;
  std::vector<double> expected_t;
  std::vector<int> expected_axis;  // the face's axis
  for (std::size_t i = 0; i < 2000; ++i) {
    const Vec3f dir = normalize(Vec3f{testing::hash_uniform(3 * i) - 0.5f, testing::hash_uniform(3 * i + 1) - 0.5f,
                                      testing::hash_uniform(3 * i + 2) - 0.5f});
    const bool inside = i % 2;
    const Vec3f org = inside ? Vec3f{0.2f, -0.3f, 0.5f} : dir * -10.f;
    rays.push_back({org, dir});
    // The analytic answer in double: entry from outside, exit from inside.
    double t_enter = -INFINITY, t_exit = INFINITY;
    int enter_axis = 0, exit_axis = 0;
    for (int k = 0; k < 3; ++k) {
      const double a = (double(box.lower[k]) - org[k]) / dir[k], b = (double(box.upper[k]) - org[k]) / dir[k];
      if (std::min(a, b) > t_enter) t_enter = std::min(a, b), enter_axis = k;
      if (std::max(a, b) < t_exit) t_exit = std::max(a, b), exit_axis = k;
    }
    expected_t.push_back(inside ? t_exit : t_enter);
    expected_axis.push_back(inside ? exit_axis : enter_axis);
  }
  for (auto isa : supported_isas()) {
    INFO(simd::isa_name(isa));
    const auto got = trace_geometry(isa, Boxes({box}), rays);
    for (std::size_t i = 0; i < rays.size(); ++i) {
      INFO("ray " << i);
      REQUIRE(got[i].prim_id == 0);
      CHECK(got[i].t == Approx(expected_t[i]).epsilon(1e-5));
    }
  }
  // Normals, through the scalar path's geometric normal: the face's axis, facing the ray
  // on entry and along it on exit.
  accel::Device device;
  shim::EngineWorld world(device);
  world.add(Boxes({box}));
  world.commit<simd::scalar>();
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const auto hit = accel::intersect<simd::scalar>(world.scene(), rays[i], true);
    const int k = expected_axis[i];
    INFO("ray " << i);
    CHECK(std::fabs(hit.ng[k]) == 1.f);
    CHECK(hit.ng[(k + 1) % 3] == 0.f);
    CHECK((hit.ng[k] * rays[i].dir[k] < 0) == (i % 2 == 0));
  }
}

TEST_CASE("planes, bounded and unbounded", "[planes][simd]") {
  // z = 2 (0x + 0y + 1z - 2 = 0), and a tilted plane through the origin bounded to a box.
  const std::vector<Ray<float>> rays{{{0.f, 0.f, -1.f}, {0.f, 0.f, 1.f}},
                                     {{1e5f, -3e4f, -1.f}, {0.f, 0.f, 1.f}},  // far out: unbounded still hits
                                     {{0.f, 0.f, 5.f}, {0.f, 0.6f, -0.8f}}};
  for (auto isa : supported_isas()) {
    INFO(simd::isa_name(isa));
    const auto unbounded = trace_geometry(isa, Planes({{0.f, 0.f, 1.f, -2.f}}), rays);
    CHECK(unbounded[0].t == Approx(3.f));
    CHECK(unbounded[1].t == Approx(3.f));
    CHECK(unbounded[2].t == Approx(3.f / 0.8f));
    const Box3f small{{-1.f, -1.f, 1.f}, {1.f, 1.f, 3.f}};
    const auto bounded = trace_geometry(isa, Planes({{0.f, 0.f, 1.f, -2.f}}, {small}), rays);
    CHECK(bounded[0].t == Approx(3.f));
    CHECK(bounded[1].prim_id == -1);  // outside the bounds
    CHECK(bounded[2].prim_id == -1);  // y = 2.25 at the plane: outside
  }
}

TEST_CASE("box and plane validation names the bad value", "[boxes][planes][errors]") {
  CHECK_THROWS_WITH(Boxes({}).validate(), Catch::Contains("box: 'box' is missing"));
  CHECK_THROWS_WITH(Boxes({Box3f{{0, 0, 0}, {1, -1, 1}}}).validate(), Catch::Contains("'box' 0 is not a finite box"));
  CHECK_THROWS_WITH(Boxes({Box3f{{0, 0, 0}, {1, 1, 1}}}, {1, 0, 0}).validate(),
                    Catch::Contains("'color' has 0 elements but there are 1"));
  CHECK_THROWS_WITH(Planes({{0, 0, 0, 1}}).validate(), Catch::Contains("'plane.coefficients' 0 has a zero normal"));
  CHECK_THROWS_WITH(Planes({{0, std::nanf(""), 1, 1}}).validate(), Catch::Contains("0 is not finite"));
  CHECK_THROWS_WITH(Planes({{0, 0, 1, 1}, {1, 0, 0, 0}}, {Box3f{{0, 0, 0}, {1, 1, 1}}}).validate(),
                    Catch::Contains("'plane.bounds' has 1 elements but there are 2 planes"));
}
