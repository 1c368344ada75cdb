#pragma once
// The Henyey–Greenstein phase function (1941), which scatters light in a participating
// medium: the density of the new direction depends only on the cosine to the old one,
// with mean cosine g (g > 0 forward, g < 0 back, 0 isotropic). Directions are
// directions of travel: cos_theta = dot(incoming direction, outgoing direction).
#include <algorithm>
#include <cmath>
#include <numbers>

#include "sciray/math/vec.hpp"

namespace sciray {

/// |g| beyond this is a delta lobe in all but name; both functions clamp to it so that
/// the density stays finite (at g = 0.999 it peaks at 1.6e5 per steradian).
inline constexpr float max_anisotropy = 0.999f;

/// The phase function's density per steradian (it integrates to 1 over the sphere).
inline float henyey_greenstein(float cos_theta, float g) {
  g = std::clamp(g, -max_anisotropy, max_anisotropy);
  const float d = 1.f + g * g - 2.f * g * cos_theta;
  return (1.f - g * g) / (4.f * std::numbers::pi_v<float> * d * std::sqrt(d));
}

/// A direction scattered from travel direction `dir` (unit), by inverting the phase
/// function's cumulative distribution of cos_theta; its pdf is henyey_greenstein.
inline Vec3f sample_henyey_greenstein(const Vec3f& dir, float g, float u1, float u2) {
  g = std::clamp(g, -max_anisotropy, max_anisotropy);
  float cos_theta;
  if (std::abs(g) < 1e-3f) {
    cos_theta = 1.f - 2.f * u1;
  } else {
    const float s = (1.f - g * g) / (1.f - g + 2.f * g * u1);
    cos_theta = std::clamp((1.f + g * g - s * s) / (2.f * g), -1.f, 1.f);
  }
  const float sin_theta = std::sqrt(std::max(0.f, 1.f - cos_theta * cos_theta));
  const float phi = 2.f * std::numbers::pi_v<float> * u2;
  const Vec3f t = perpendicular(dir), b = cross(dir, t);
  return t * (sin_theta * std::cos(phi)) + b * (sin_theta * std::sin(phi)) + dir * cos_theta;
}

}  // namespace sciray
