#pragma once
// What the BSDF tests share: a flat shading point, directions by angle, and directional
// albedo estimated from sample().
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>

#include "sciray/math/random.hpp"
#include "sciray/render/bsdf.hpp"

namespace sciray_test {

inline constexpr float pi = std::numbers::pi_v<float>;

inline sciray::ShadingPoint flat(bool entering = true) {
  sciray::ShadingPoint sp;
  sp.n = sp.ng = {0.f, 0.f, 1.f};
  sp.entering = entering;
  return sp;
}

/// A unit direction `degrees` away from +z.
inline sciray::Vec3f at_angle(float degrees, float phi = 0.7f) {
  const float theta = degrees * pi / 180.f;
  return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}

inline bool finite(const sciray::Vec3f& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

/// Mean and its standard error of a channel of sample weights.
struct Estimate {
  double mean[3] = {}, standard_error[3] = {};
};

/// Directional albedo for wo as the mean sample weight (absorbed samples count as 0).
/// `spread`: the shading point moves over a square of this size (carPaint's flakes).
inline Estimate sampled_albedo(const sciray::Material& m, sciray::ShadingPoint sp, const sciray::Vec3f& wo, int n,
                               std::uint64_t seed, float spread = 0.f) {
  sciray::Pcg32 rng(seed, 7);
  double sum[3] = {}, sum2[3] = {};
  for (int i = 0; i < n; ++i) {
    if (spread > 0.f) sp.p = {spread * rng.next_float(), spread * rng.next_float(), 0.f};
    const float u = rng.next_float(), u1 = rng.next_float(), u2 = rng.next_float();
    const auto s = sample(m, sp, wo, u, u1, u2);
    if (!s) continue;
    for (int c = 0; c < 3; ++c) sum[c] += s->weight[c], sum2[c] += double(s->weight[c]) * s->weight[c];
  }
  Estimate e;
  for (int c = 0; c < 3; ++c) {
    e.mean[c] = sum[c] / n;
    e.standard_error[c] = std::sqrt(std::max(0., sum2[c] / n - e.mean[c] * e.mean[c]) / n);
  }
  return e;
}

/// ∫ f(wi) dwi over the unit sphere, stratified in (z, phi): strata² cells, each jittered by
/// two numbers from `rng` (z's first).
template <class F>
double sphere_integral(int strata, sciray::Pcg32& rng, F&& f) {
  double integral = 0.;
  for (int i = 0; i < strata; ++i)
    for (int j = 0; j < strata; ++j) {
      const float z = 1.f - 2.f * (static_cast<float>(i) + rng.next_float()) / strata;
      const float phi = 2.f * pi * (static_cast<float>(j) + rng.next_float()) / strata;
      const float r = std::sqrt(std::max(0.f, 1.f - z * z));
      integral += f(sciray::Vec3f{r * std::cos(phi), r * std::sin(phi), z});
    }
  return integral * 4. * pi / (strata * strata);
}

}  // namespace sciray_test
