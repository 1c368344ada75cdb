// Curves: per-vertex colours along a segment follow the curve's basis.
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>

#include "sciray/geometry/curves.hpp"

using namespace sciray;

namespace {

/// The colour of segment 0 at parameter u, where control point k carries only colour
/// channel k (r, g, b, alpha): the four channels are then the points' weights.
std::array<float, 4> weights_at(CurveBasis basis, float u) {
  CurveData d;
  d.position_radius = {-3.f, 0.f, 0.f, 0.5f, -1.f, 0.f, 0.f, 0.5f, 1.f, 0.f, 0.f, 0.5f, 3.f, 0.f, 0.f, 0.5f};
  d.indices = {0};
  d.colors = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  d.basis = basis;
  const Curves curves(d);
  accel::Hit<simd::scalar> hit{};
  hit.hit = true;
  hit.u = u;
  hit.ng = {0.f, 0.f, 1.f};
  const auto s = curves.surface<simd::scalar>(hit, true);
  return {s.color.x, s.color.y, s.color.z, s.alpha};
}

void check_weights(CurveBasis basis, float u, const std::array<float, 4>& expected) {
  INFO("basis " << static_cast<int>(basis) << ", u = " << u);
  const auto w = weights_at(basis, u);
  for (int k = 0; k < 3; ++k) CHECK(w[k] == Approx(expected[k]).margin(1e-6));
  // Alpha carries point 3's weight, kept an opacity where Catmull-Rom's is negative.
  CHECK(w[3] == Approx(std::clamp(expected[3], 0.f, 1.f)).margin(1e-6));
}

}  // namespace

// OSPRay 3.1 weighs a cubic segment's vertex colours with the curve's own basis functions
// over all four control points. Measured with OSPRay 3.1's runtime (ao renderer, ambient
// light, one-hot colours on the points of a uniform B-spline along x): at u = 0.031 the
// colour's r:g:b was 0.151 : 0.666 : 0.183, the B-spline weights (0.152, 0.666, 0.183,
// 0.000); sciray had blended points 1 and 2 only (0 : 0.969 : 0.031). Catmull-Rom gave
// negative red there, as its weights do; Bézier the Bernstein weights.
TEST_CASE("curve colours follow the curve's basis functions", "[curve]") {
  for (const float u : {0.f, 0.031f, 0.25f, 0.5f, 0.8f, 1.f}) {
    const float s = 1.f - u, u2 = u * u, u3 = u2 * u, s3 = s * s * s;
    check_weights(CurveBasis::bspline, u,
                  {s3 / 6.f, (3.f * u3 - 6.f * u2 + 4.f) / 6.f, (3.f * s3 - 6.f * s * s + 4.f) / 6.f, u3 / 6.f});
    check_weights(CurveBasis::catmull_rom, u,
                  {(-u3 + 2.f * u2 - u) / 2.f, (3.f * u3 - 5.f * u2 + 2.f) / 2.f, (-3.f * u3 + 4.f * u2 + u) / 2.f,
                   (u3 - u2) / 2.f});
    check_weights(CurveBasis::bezier, u, {s3, 3.f * s * s * u, 3.f * s * u2, u3});
    // Linear and Hermite segments blend their two end points.
    check_weights(CurveBasis::linear, u, {s, u, 0.f, 0.f});
    check_weights(CurveBasis::hermite, u, {s, u, 0.f, 0.f});
  }
}

TEST_CASE("curve colour alpha stays an opacity where Catmull-Rom weights overshoot", "[curve]") {
  // Alpha 1 on the inner points and 0 on the outer ones: the Catmull-Rom blend exceeds 1
  // between them (1.125 at u = 0.5), which no opacity can be.
  CurveData d;
  d.position_radius = {-3.f, 0.f, 0.f, 0.5f, -1.f, 0.f, 0.f, 0.5f, 1.f, 0.f, 0.f, 0.5f, 3.f, 0.f, 0.f, 0.5f};
  d.indices = {0};
  d.colors = {1, 1, 1, 0, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 0};
  d.basis = CurveBasis::catmull_rom;
  const Curves curves(d);
  accel::Hit<simd::scalar> hit{};
  hit.hit = true;
  hit.u = 0.5f;
  hit.ng = {0.f, 0.f, 1.f};
  const auto s = curves.surface<simd::scalar>(hit, true);
  CHECK(s.alpha == 1.f);
  CHECK(s.color.x == Approx(1.f));
}
