// Spheres, discs and curves: both sphere intersectors on every ISA against an analytic
// double-precision reference, validation, and images against stored references.
//
// References are regenerated with
//   SCIRAY_UPDATE_REFERENCES=1 ./build/tests/sciray_tests "[reference]"
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdlib>
#include <limits>
#include <vector>

#include "sciray/geometry/sphere_intersect.hpp"
#include "sciray/io/frame_io.hpp"
#include "sciray/shim/engine.hpp"
#include "sciray/testing/image_compare.hpp"
#include "sciray/testing/scenes.hpp"
#include "support/isas.hpp"

using namespace sciray;
using sciray::test_support::supported_isas;

namespace {

/// The nearest hit over all spheres, in double precision on the same float rays.
shim::TraceResult reference_hit(const SphereData& spheres, const Ray<float>& ray) {
  shim::TraceResult best{std::numeric_limits<float>::infinity(), 0, 0, -1, -1, -1};
  double best_t = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < spheres.count(); ++i) {
    double f[3], d[3], fd = 0, dd = 0, miss2 = 0;
    for (int k = 0; k < 3; ++k) {
      f[k] = double(ray.org[k]) - spheres.positions[3 * i + k];
      d[k] = ray.dir[k];
      fd += f[k] * d[k], dd += d[k] * d[k];
    }
    for (int k = 0; k < 3; ++k) miss2 += (f[k] - fd / dd * d[k]) * (f[k] - fd / dd * d[k]);
    const double r = spheres.radii.empty() ? spheres.radius : spheres.radii[i];
    const double disc = dd * (r * r - miss2);
    if (disc < 0) continue;
    for (double t : {(-fd - std::sqrt(disc)) / dd, (-fd + std::sqrt(disc)) / dd})
      if (t > ray.tnear && t < best_t) {
        best_t = t;
        // u: the cosine between ray and normal, small where the hit grazes the silhouette.
        best = {static_cast<float>(t), static_cast<float>(std::sqrt(disc / dd) / r), 0, static_cast<std::int32_t>(i), 0, -1};
        break;
      }
  }
  return best;
}

/// Rays from outside the unit cube through random points inside it.
std::vector<Ray<float>> rays_into_unit_cube(std::size_t count) {
  std::vector<Ray<float>> rays(count);
  for (std::size_t i = 0; i < count; ++i) {
    const Vec3f target{testing::hash_uniform(7 * i + 100), testing::hash_uniform(7 * i + 101),
                       testing::hash_uniform(7 * i + 102)};
    const Vec3f dir = normalize(Vec3f{testing::hash_uniform(7 * i + 103) - 0.5f,
                                      testing::hash_uniform(7 * i + 104) - 0.5f,
                                      testing::hash_uniform(7 * i + 105) - 0.5f});
    rays[i].org = target - dir * 2.f;
    rays[i].dir = dir;
  }
  return rays;
}

}  // namespace

TEST_CASE("both sphere intersectors on every ISA find the analytic nearest sphere", "[spheres][simd]") {
  const SphereData data = testing::random_spheres(300, 3);
  const auto rays = rays_into_unit_cube(4000);
  std::vector<shim::TraceResult> expected(rays.size());
  std::size_t hits = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) hits += (expected[i] = reference_hit(data, rays[i])).prim_id >= 0;
  REQUIRE(hits > rays.size() / 2);

  for (auto intersector : {SphereIntersector::sciray, SphereIntersector::embree}) {
    for (auto isa : supported_isas()) {
      INFO((intersector == SphereIntersector::sciray ? "sciray" : "embree") << " on " << simd::isa_name(isa));
      accel::Device device;
      shim::EngineWorld world(device);
      world.add(Spheres(data).set_intersector(intersector));
      shim::kernels(isa).commit(world);
      std::vector<shim::TraceResult> got(rays.size());
      shim::kernels(isa).trace(world, rays, got);
      std::size_t wrong_sphere = 0, worst_ulps = 0;
      for (std::size_t i = 0; i < rays.size(); ++i) {
        if (got[i].prim_id != expected[i].prim_id) {
          ++wrong_sphere;
          continue;
        }
        // Near the silhouette t depends ever more steeply on the inputs' rounding: there
        // no method can promise ulps, so the bound applies where the cosine is >= 0.25.
        if (expected[i].prim_id < 0 || expected[i].u < 0.25f) continue;
        const float ulp = std::nextafter(expected[i].t, INFINITY) - expected[i].t;
        worst_ulps = std::max(worst_ulps, static_cast<std::size_t>(std::fabs(got[i].t - expected[i].t) / ulp));
      }
      // Rays grazing a silhouette may round either way; there are none such here at 1e-6.
      CHECK(wrong_sphere == 0);
      CHECK(worst_ulps <= 4);  // measured: 4 for both intersectors
    }
  }
}

TEST_CASE("a ray restarted at a reported sphere hit finds the far side, not the same hit", "[spheres]") {
  // Past a clipped hit a ray is restarted at the distance reported, which the refinement
  // step moved off the quadratic's root: the bounds must be tested on the refined roots,
  // or about one ray in twenty finds the same near hit again and passes through.
  const Vec3f center{0.3f, -0.2f, 0.1f};
  const float radius = 0.7f;
  int restarted = 0;
  for (int i = 0; i < 4000; ++i) {
    const float x = -0.6f + 1.2f * static_cast<float>(i % 63) / 62.f, y = -0.6f + 1.2f * static_cast<float>(i / 63) / 63.f;
    Ray<float> ray{{x + center.x, y + center.y, -50.f - 0.37f * static_cast<float>(i % 7)}, {0.f, 0.f, 1.f}};
    const PrimitiveHit<simd::scalar> near = intersect_sphere<simd::scalar>(ray, center, radius);
    if (!near.hit) continue;
    ray.tnear = near.t;
    const PrimitiveHit<simd::scalar> far = intersect_sphere<simd::scalar>(ray, center, radius);
    INFO("ray " << i);
    REQUIRE(far.hit);
    CHECK(far.t > near.t);
    // The far side: the hit's offset from the centre points along the ray.
    CHECK(dot(far.ng, ray.dir) > 0.f);
    ++restarted;
  }
  CHECK(restarted > 2500);
}

TEST_CASE("discs face the ray, oriented discs face their normal", "[spheres]") {
  SphereData data;
  data.positions = {0.f, 0.f, 0.f};
  data.radius = 1.f;
  data.normals = {0.f, 0.f, 1.f};
  const auto hit_at = [&](SphereType type, SphereIntersector intersector, Ray<float> ray) {
    accel::Device device;
    shim::EngineWorld world(device);
    world.add(Spheres(data).set_type(type).set_intersector(intersector));
    const auto& kernels = shim::kernels(shim::select_isa());
    kernels.commit(world);
    std::vector<shim::TraceResult> result(1);
    kernels.trace(world, {&ray, 1}, result);
    return result[0];
  };
  for (auto intersector : {SphereIntersector::sciray, SphereIntersector::embree}) {
    INFO((intersector == SphereIntersector::sciray ? "sciray" : "embree"));
    // Seen along x, a disc facing the ray is a full disc at the centre plane.
    const Ray<float> along_x{{-5.f, 0.5f, 0.5f}, {1.f, 0.f, 0.f}};
    CHECK(hit_at(SphereType::disc, intersector, along_x).t == Approx(5.f).epsilon(1e-6));
    CHECK(hit_at(SphereType::sphere, intersector, along_x).t == Approx(5.f - std::sqrt(0.5f)).epsilon(1e-6));
    // The oriented disc lies in z = 0: edge-on from x it is missed, from z it is hit.
    CHECK(hit_at(SphereType::oriented_disc, intersector, along_x).prim_id == -1);
    const Ray<float> along_z{{0.5f, 0.5f, -3.f}, {0.f, 0.f, 1.f}};
    CHECK(hit_at(SphereType::oriented_disc, intersector, along_z).t == Approx(3.f).epsilon(1e-6));
    const Ray<float> outside{{0.8f, 0.8f, -3.f}, {0.f, 0.f, 1.f}};
    CHECK(hit_at(SphereType::oriented_disc, intersector, outside).prim_id == -1);
  }
}

TEST_CASE("sphere validation names the bad value", "[spheres][errors]") {
  const auto fails_with = [](SphereData data, const std::string& expected, SphereType type = SphereType::sphere) {
    INFO(expected);
    CHECK_THROWS_WITH(Spheres(std::move(data)).set_type(type).validate(), Catch::Contains(expected));
  };
  SphereData ok;
  ok.positions = {0, 0, 0, 1, 1, 1};
  CHECK_NOTHROW(Spheres(ok).validate());
  fails_with(SphereData{}, "'sphere.position' is missing");
  SphereData nan = ok;
  nan.positions[4] = std::nanf("");
  fails_with(nan, "'sphere.position' 1 is not finite");
  SphereData short_radii = ok;
  short_radii.radii = {1.f};
  fails_with(short_radii, "'sphere.radius' has 1 elements but there are 2 spheres");
  SphereData negative = ok;
  negative.radii = {1.f, -2.f};
  fails_with(negative, "'sphere.radius' 1 must be positive");
  SphereData zero = ok;
  zero.radius = 0.f;
  fails_with(zero, "'radius' must be positive");
  fails_with(ok, "needs 'sphere.normal'", SphereType::oriented_disc);
  SphereData colors = ok;
  colors.colors = {1, 0, 0, 1};
  fails_with(colors, "'color' has 1 elements but there are 2 spheres");
}

TEST_CASE("curve validation names the bad value", "[curves][errors]") {
  const auto fails_with = [](CurveData data, const std::string& expected) {
    INFO(expected);
    CHECK_THROWS_WITH(Curves(std::move(data)).validate(), Catch::Contains(expected));
  };
  CurveData ok;
  ok.position_radius = {0, 0, 0, 0.1f, 1, 0, 0, 0.1f, 2, 0, 0, 0.1f};
  ok.indices = {0, 1};
  CHECK_NOTHROW(Curves(ok).validate());
  CurveData out_of_range = ok;
  out_of_range.indices = {0, 2};
  fails_with(out_of_range, "'index' 1 starts a segment at vertex 2 that needs vertex 3");
  CurveData cubic = ok;
  cubic.basis = CurveBasis::bspline;
  fails_with(cubic, "needs vertex 3");
  CurveData hermite = ok;
  hermite.basis = CurveBasis::hermite;
  fails_with(hermite, "needs 'vertex.tangent'");
  CurveData nan = ok;
  nan.position_radius[5] = std::nanf("");
  fails_with(nan, "'vertex.position_radius' 1 is not finite");
  CurveData negative = ok;
  negative.position_radius[3] = -1.f;
  fails_with(negative, "negative radius");
  CurveData colors = ok;
  colors.colors = {1, 0, 0, 1};
  fails_with(colors, "'vertex.color' has 1 elements but there are 3 vertices");
  CurveData disjoint_cubic = ok;
  disjoint_cubic.position_radius.insert(disjoint_cubic.position_radius.end(), {3, 0, 0, 0.1f, 4, 0, 0, 0.1f});
  disjoint_cubic.basis = CurveBasis::bezier;
  disjoint_cubic.type = CurveType::disjoint;
  disjoint_cubic.indices = {0};
  fails_with(disjoint_cubic, "'disjoint' is only defined for basis 'linear'");
}

TEST_CASE("a round linear tube is hit where the cylinder is", "[curves]") {
  CurveData tube;
  tube.position_radius = {-1, 0, 0, 0.25f, 1, 0, 0, 0.25f};
  tube.indices = {0};
  tube.colors = {1, 0, 0, 1, 0, 0, 1, 1};
  for (auto isa : supported_isas()) {
    INFO(simd::isa_name(isa));
    accel::Device device;
    shim::EngineWorld world(device);
    world.add(Curves(tube));
    shim::kernels(isa).commit(world);
    std::vector<Ray<float>> rays;
    for (float y : {0.f, 0.1f, 0.2f, 0.3f}) rays.push_back({{0.5f, y, -2.f}, {0.f, 0.f, 1.f}});
    std::vector<shim::TraceResult> got(rays.size());
    shim::kernels(isa).trace(world, rays, got);
    for (int k = 0; k < 3; ++k) {
      const float y = rays[k].org.y;
      CHECK(got[k].t == Approx(2.f - std::sqrt(0.25f * 0.25f - y * y)).epsilon(1e-4));
      CHECK(got[k].u == Approx(0.75f).margin(1e-3));  // the curve parameter along the segment
    }
    CHECK(got[3].prim_id == -1);
  }
}

TEST_CASE("spheres and streamlines match their stored reference images", "[spheres][curves][reference]") {
  struct Case {
    const char* file;
    bool spheres;
  };
  for (const Case c : {Case{"spheres_scivis.png", true}, Case{"streamlines_scivis.png", false}}) {
    INFO(c.file);
    accel::Device device;
    shim::EngineWorld world(device);
    if (c.spheres)
      world.add(Spheres(testing::random_spheres(2000, 5)));
    else
      world.add(Curves(testing::streamlines(150, 100, 0.06f)));
    const auto& kernels = shim::kernels(shim::select_isa());
    kernels.commit(world);
    SciVisParams params;
    params.background_color = {0.1f, 0.1f, 0.12f};
    params.background_alpha = 1.f;
    params.lights = default_lights({0.5f, -0.7f, -0.6f});
    FrameBuffer fb(160, 160, ColorFormat::srgba);
    kernels.render_scivis(world, params, frame_bounds(world.bounds(), 1.f), fb, nullptr);
    const std::string reference = std::string(SCIRAY_REFERENCE_DIR "/") + c.file;
    if (std::getenv("SCIRAY_UPDATE_REFERENCES")) io::write_color(fb, reference);
    const auto diff = testing::compare_images(io::color_image(fb), io::read_png(reference), 2.5 / 255);
    INFO(testing::describe(diff));
    // The same tolerance as the mesh reference: rounding-level noise, no wrong region.
    CHECK(diff.rmse <= 0.005);
    CHECK(diff.local_mean_error_max <= 0.02);
  }
}
