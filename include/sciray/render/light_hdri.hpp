#pragma once
// The environment light (OSPRay `hdri`): radiance from every direction read from a
// latitude-longitude map, sampled in proportion to the map's luminance. Also the sky of
// the `sunSky` light (render/sky.hpp).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <numbers>
#include <vector>

#include "sciray/error.hpp"
#include "sciray/math/affine.hpp"
#include "sciray/math/vec.hpp"
#include "sciray/render/texture.hpp"

namespace sciray {

/// OSPRay's `intensityQuantity` values (OSPIntensityQuantity): what a light's
/// `intensity` (times `color`) measures.
enum class IntensityQuantity : std::uint8_t { radiance = 0, irradiance = 1, intensity = 2, power = 3, scale = 4 };

/// An environment map in latitude-longitude layout: `direction` is where the map's centre
/// (u = 0.5, v = 0.5) lies, `up` is v = 1, and u = 0.75 lies towards `direction` x `up`
/// (u = 0.25 opposite), OSPRay 3.1's layout measured with its runtime: with the default frame (up +y,
/// direction +z) the view along +x shows u = 0.25, along -x u = 0.75, along -z the seam.
/// `intensity` (times `color`) scales the map.
class HdriLight {
public:
  Vec3f color{1.f, 1.f, 1.f};
  float intensity = 1.f;
  bool visible = true;
  IntensityQuantity quantity = IntensityQuantity::scale;  ///< scale or radiance: both scale the map

  HdriLight() = default;
  HdriLight(std::shared_ptr<const Texture2D> map, Vec3f up = {0.f, 1.f, 0.f}, Vec3f direction = {0.f, 0.f, 1.f})
      : map_(std::move(map)) {
    if (!map_) throw Error("hdri light: parameter 'map' is missing");
    set_frame(up, direction);
    distribution_ = std::make_shared<const Distribution>(*map_);
  }

  const Texture2D* map() const { return map_.get(); }
  Vec3f up() const { return up_; }
  Vec3f direction() const { return forward_; }

  /// The same map turned by the linear part of `xfm` (an instance's transform); the
  /// sampling distribution, which lives in the map's (u, v), is shared.
  HdriLight rotated(const Affine3f& xfm) const {
    HdriLight out = *this;
    out.set_frame(xfm.vector(up_), xfm.vector(forward_));
    return out;
  }

  /// The map's radiance (without colour and intensity) in world direction `w`.
  Vec3f lookup(const Vec3f& w) const {
    const auto [u, v] = to_uv(w);
    return map_->sample(u, v);
  }

  struct Direction {
    Vec3f w;
    float pdf;  // solid angle
  };
  Direction sample(float u1, float u2) const {
    const Distribution& d = *distribution_;
    const int h = map_->height(), wdt = map_->width();
    const int row = pick(d.marginal.data(), h, u2);
    const float dv = (u2 - d.marginal[row]) / std::max(d.marginal[row + 1] - d.marginal[row], 1e-30f);
    const float* cdf = &d.conditional[static_cast<std::size_t>(row) * (wdt + 1)];
    const int column = pick(cdf, wdt, u1);
    const float du = (u1 - cdf[column]) / std::max(cdf[column + 1] - cdf[column], 1e-30f);
    const float u = (static_cast<float>(column) + std::clamp(du, 0.f, 1.f)) / static_cast<float>(wdt);
    const float v = (static_cast<float>(row) + std::clamp(dv, 0.f, 1.f)) / static_cast<float>(h);
    const Vec3f w = from_uv(u, v);
    return {w, pdf_uv(u, v)};
  }
  float pdf(const Vec3f& w) const {
    const auto [u, v] = to_uv(w);
    return pdf_uv(u, v);
  }

private:
  /// Piecewise-constant densities over the map's texels, in (u, v).
  struct Distribution {
    explicit Distribution(const Texture2D& map) {
      const int wdt = map.width(), h = map.height();
      weight.assign(static_cast<std::size_t>(wdt) * h, 0.f);
      conditional.assign(static_cast<std::size_t>(wdt + 1) * h, 0.f);
      marginal.assign(static_cast<std::size_t>(h) + 1, 0.f);
      for (int y = 0; y < h; ++y) {
        const float sin_theta =
            std::sin((static_cast<float>(y) + 0.5f) / static_cast<float>(h) * std::numbers::pi_v<float>);
        float* cdf = &conditional[static_cast<std::size_t>(y) * (wdt + 1)];
        for (int x = 0; x < wdt; ++x) {
          const Vec3f& t = map.texel(x, y);
          // A floor keeps every direction reachable, so the estimator stays unbiased.
          const float w = (0.2126f * t.x + 0.7152f * t.y + 0.0722f * t.z + 1e-4f) * sin_theta;
          weight[static_cast<std::size_t>(y) * wdt + x] = w;
          cdf[x + 1] = cdf[x] + w;
        }
        marginal[y + 1] = marginal[y] + cdf[wdt];
        for (int x = 1; x <= wdt; ++x) cdf[x] = cdf[wdt] > 0.f ? cdf[x] / cdf[wdt] : static_cast<float>(x) / wdt;
      }
      total = marginal[h];
      for (int y = 1; y <= h; ++y) marginal[y] = total > 0.f ? marginal[y] / total : static_cast<float>(y) / h;
      total /= static_cast<float>(wdt * h);  // mean weight, so weight/total is the texel's density in (u,v)
    }
    std::vector<float> weight, conditional, marginal;
    float total = 0.f;
  };

  struct Uv {
    float u, v;
  };
  void set_frame(Vec3f up, Vec3f direction) {
    const float upl = length(up), dl = length(direction);
    if (!(upl > 0.f) || !std::isfinite(upl)) throw Error("hdri light: parameter 'up' must be a finite non-zero vector");
    if (!(dl > 0.f) || !std::isfinite(dl)) throw Error("hdri light: parameter 'direction' must be a finite non-zero vector");
    up_ = up / upl;
    const Vec3f d = direction - up_ * dot(direction, up_);
    if (length(d) < 1e-6f * dl) throw Error("hdri light: 'direction' is parallel to 'up'");
    forward_ = normalize(d);
    side_ = cross(forward_, up_);  // u = 0.75
  }
  Vec3f from_uv(float u, float v) const {
    const float theta = v * std::numbers::pi_v<float>, phi = 2.f * std::numbers::pi_v<float> * (u - 0.5f);
    const float s = std::sin(theta);
    return forward_ * (s * std::cos(phi)) + side_ * (s * std::sin(phi)) - up_ * std::cos(theta);
  }
  Uv to_uv(const Vec3f& w) const {
    const float theta = std::acos(std::clamp(-dot(w, up_), -1.f, 1.f));
    const float phi = std::atan2(dot(w, side_), dot(w, forward_));
    return {phi / (2.f * std::numbers::pi_v<float>) + 0.5f, theta / std::numbers::pi_v<float>};
  }
  float pdf_uv(float u, float v) const {
    // A NaN direction (a ray that went wrong upstream) gets no light, and no undefined
    // float-to-int conversion below.
    if (!std::isfinite(u) || !std::isfinite(v)) return 0.f;
    const Distribution& d = *distribution_;
    const int wdt = map_->width(), h = map_->height();
    const int x = std::clamp(static_cast<int>(u * wdt), 0, wdt - 1), y = std::clamp(static_cast<int>(v * h), 0, h - 1);
    const float sin_theta = std::sin(v * std::numbers::pi_v<float>);
    if (sin_theta <= 0.f || d.total <= 0.f) return 0.f;
    // Texel probability / texel area in (u,v), over the Jacobian 2 pi^2 sin(theta).
    const float p_uv = d.weight[static_cast<std::size_t>(y) * wdt + x] / d.total;
    return p_uv / (2.f * std::numbers::pi_v<float> * std::numbers::pi_v<float> * sin_theta);
  }
  /// The bin i of the n-bin `cdf` (n + 1 values) with cdf[i] <= u < cdf[i + 1].
  static int pick(const float* cdf, int n, float u) {
    return static_cast<int>(std::upper_bound(cdf + 1, cdf + n, u) - cdf) - 1;
  }

  std::shared_ptr<const Texture2D> map_;
  Vec3f up_{0.f, 1.f, 0.f}, forward_{0.f, 0.f, 1.f}, side_{1.f, 0.f, 0.f};
  /// Shared: lights are copied into every world build and every rotated placement.
  std::shared_ptr<const Distribution> distribution_;
};

}  // namespace sciray
