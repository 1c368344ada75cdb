#pragma once
// Photometric lights: a measured luminous intensity distribution (OSPRay's
// `intensityDistribution`) that scales a light's emission by direction, as photometric
// (IES / EULUMDAT type C) data does. The table is sampled uniformly in the polar angle
// gamma from the light's main axis, 0 to 180 degrees (first dimension, at least two
// values), and, if it has a second dimension, uniformly in the azimuth C from the c0
// half-plane, [0, 360) degrees, wrapping around.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <memory>
#include <numbers>
#include <vector>

#include "sciray/error.hpp"
#include "sciray/math/vec.hpp"

namespace sciray {

/// The frame photometric data is measured in: `axis` is gamma = 0, `c0` the direction
/// of C = 0 and `c90` of C = 90 degrees, all unit and orthogonal.
struct PhotometricFrame {
  Vec3f axis, c0, c90;
};

/// OSPRay's construction of that frame from a light's main axis and a c0 hint that need
/// not be orthogonal to it: c90 = c0 x axis, then c0 made orthogonal. A hint parallel to
/// the axis (where OSPRay's frame has no direction) gives some perpendicular c0.
inline PhotometricFrame photometric_frame(const Vec3f& axis, const Vec3f& c0_hint) {
  const Vec3f a = normalize(axis);
  Vec3f c90 = cross(c0_hint, a);
  const float l = length(c90);
  c90 = l > 1e-6f * length(c0_hint) ? c90 / l : cross(perpendicular(a), a);
  return {a, cross(a, c90), c90};
}

/// OSPRay's default c0 for a light with `direction` (sphere and spot lights): a vector
/// built from the direction's components that is not parallel to it.
inline Vec3f default_c0(const Vec3f& direction) {
  return std::abs(direction.x) < std::abs(direction.y) ? Vec3f{0.f, direction.z, direction.y}
                                                       : Vec3f{direction.z, 0.f, direction.x};
}

class IntensityDistribution {
public:
  IntensityDistribution() = default;
  /// `values`: gamma_count * c_count floats, gamma fastest (OSPRay's 1D or 2D data).
  IntensityDistribution(std::vector<float> values, std::size_t gamma_count, std::size_t c_count = 1)
      : values_(std::make_shared<const std::vector<float>>(std::move(values))), gammas_(gamma_count), cs_(c_count) {
    if (gammas_ < 2) throw Error("'intensityDistribution' needs at least two gamma angles");
    if (cs_ < 1 || values_->size() != gammas_ * cs_)
      throw Error("'intensityDistribution' must hold gamma count x C count values");
    for (float v : *values_)
      if (!(v >= 0.f) || !std::isfinite(v)) throw Error("'intensityDistribution' values must be finite and not negative");
  }

  explicit operator bool() const { return values_ != nullptr; }

  /// The table's factor for the direction `dir` leaving the light, whose cosine to the
  /// frame's axis is `cos_gamma`: linear in gamma and (for 2D data) in C.
  float operator()(const PhotometricFrame& f, float cos_gamma, const Vec3f& dir) const {
    constexpr float pi = std::numbers::pi_v<float>;
    // A NaN direction (a ray that went wrong upstream) gets no light, and no undefined
    // float-to-int conversion below.
    if (!std::isfinite(cos_gamma)) return 0.f;
    const float u = std::acos(std::clamp(cos_gamma, -1.f, 1.f)) * static_cast<float>(gammas_ - 1) / pi;
    const std::size_t g0 = std::min(static_cast<std::size_t>(u), gammas_ - 1), g1 = std::min(g0 + 1, gammas_ - 1);
    const float gt = u - static_cast<float>(g0);
    const auto row = [&](std::size_t c) {
      const float* r = values_->data() + c * gammas_;
      return r[g0] + (r[g1] - r[g0]) * gt;
    };
    if (cs_ == 1) return row(0);
    // C from c0 towards c90 in [0, 2 pi], as OSPRay computes it (from the reversed
    // direction, so that C = 0 falls on the c0 half-plane).
    const float v = (std::atan2(-dot(dir, f.c90), -dot(dir, f.c0)) + pi) * static_cast<float>(cs_) / (2.f * pi);
    if (!std::isfinite(v)) return 0.f;
    const std::size_t c0 = std::min(static_cast<std::size_t>(v), cs_ - 1), c1 = (c0 + 1) % cs_;
    const float ct = v - static_cast<float>(c0);
    return row(c0) + (row(c1) - row(c0)) * ct;
  }

  std::size_t gamma_count() const { return gammas_; }
  std::size_t c_count() const { return cs_; }

private:
  std::shared_ptr<const std::vector<float>> values_;  ///< shared: lights are copied per world build
  std::size_t gammas_ = 0, cs_ = 1;
};

}  // namespace sciray
