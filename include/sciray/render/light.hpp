#pragma once
// Lights with OSPRay's types and parameters, and how renderers sample them. Each light's
// `intensity` has OSPRay's default quantity: irradiance for `distant`, radiant intensity
// (W/sr) for `sphere` and `spot`, radiance for `quad`, `hdri` and `ambient`.
//
// Sampling runs per ray (scalar): `sample` picks a direction towards the light from a
// point and returns the radiance divided by the pdf; `eval` returns the radiance and pdf
// of a direction found otherwise (by BSDF sampling), which multiple importance sampling
// weighs against. Delta lights (no size) have an infinite pdf and are never hit.
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <numbers>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "sciray/error.hpp"
#include "sciray/math/vec.hpp"
#include "sciray/render/texture.hpp"

namespace sciray {

struct LightCommon {
  Vec3f color{1.f, 1.f, 1.f};
  float intensity = 1.f;
  bool visible = true;  ///< seen by camera rays (area and environment lights)
};

/// Radiance from every direction (OSPRay `ambient`).
struct AmbientLight : LightCommon {};

/// A light at infinity travelling along `direction`; a disk of `angular_diameter` degrees
/// (the sun: 0.53) casts soft shadows.
struct DistantLight : LightCommon {
  Vec3f direction{0.f, 0.f, 1.f};
  float angular_diameter = 0.f;
};

/// A point light, or with `radius` > 0 a sphere (OSPRay `sphere`).
struct SphereLight : LightCommon {
  Vec3f position{0.f, 0.f, 0.f};
  float radius = 0.f;
};

/// A spot light emitting along `direction` within `opening_angle` degrees (full angle),
/// fading out over `penumbra_angle` inside it; with `radius` > 0 a disk facing `direction`.
struct SpotLight : LightCommon {
  Vec3f position{0.f, 0.f, 0.f};
  Vec3f direction{0.f, 0.f, 1.f};
  float opening_angle = 180.f;
  float penumbra_angle = 5.f;
  float radius = 0.f;
};

/// A parallelogram at `position` spanned by `edge1` and `edge2`, emitting to the side of
/// edge1 x edge2.
struct QuadLight : LightCommon {
  Vec3f position{0.f, 0.f, 0.f};
  Vec3f edge1{1.f, 0.f, 0.f};
  Vec3f edge2{0.f, 1.f, 0.f};
};

/// An environment map in latitude-longitude layout: `direction` is where the map's centre
/// (u = 0.5, v = 0.5) lies, `up` is v = 1. Sampled in proportion to its luminance.
class HdriLight : public LightCommon {
public:
  HdriLight() = default;
  HdriLight(std::shared_ptr<const Texture2D> map, Vec3f up = {0.f, 1.f, 0.f}, Vec3f direction = {0.f, 0.f, 1.f})
      : map_(std::move(map)), up_(up), direction_(direction) {
    if (!map_) throw Error("hdri light: parameter 'map' is missing");
    const float upl = length(up_), dl = length(direction_);
    if (!(upl > 0.f) || !std::isfinite(upl)) throw Error("hdri light: parameter 'up' must be a finite non-zero vector");
    if (!(dl > 0.f) || !std::isfinite(dl)) throw Error("hdri light: parameter 'direction' must be a finite non-zero vector");
    up_ = up_ / upl;
    const Vec3f d = direction_ - up_ * dot(direction_, up_);
    if (length(d) < 1e-6f * dl) throw Error("hdri light: 'direction' is parallel to 'up'");
    forward_ = normalize(d);
    side_ = cross(up_, forward_);
    build_distribution();
  }

  const Texture2D* map() const { return map_.get(); }

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
    const int h = map_->height(), wdt = map_->width();
    const int row = pick(marginal_.data(), h, u2);
    const float dv = (u2 - marginal_[row]) / std::max(marginal_[row + 1] - marginal_[row], 1e-30f);
    const float* cdf = &conditional_[static_cast<std::size_t>(row) * (wdt + 1)];
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
  struct Uv {
    float u, v;
  };
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
    const int wdt = map_->width(), h = map_->height();
    const int x = std::clamp(static_cast<int>(u * wdt), 0, wdt - 1), y = std::clamp(static_cast<int>(v * h), 0, h - 1);
    const float sin_theta = std::sin(v * std::numbers::pi_v<float>);
    if (sin_theta <= 0.f || total_ <= 0.f) return 0.f;
    // Texel probability / texel area in (u,v), over the Jacobian 2 pi^2 sin(theta).
    const float p_uv = weight_[static_cast<std::size_t>(y) * wdt + x] / total_;
    return p_uv / (2.f * std::numbers::pi_v<float> * std::numbers::pi_v<float> * sin_theta);
  }
  /// The bin i of the n-bin `cdf` (n + 1 values) with cdf[i] <= u < cdf[i + 1].
  static int pick(const float* cdf, int n, float u) {
    return static_cast<int>(std::upper_bound(cdf + 1, cdf + n, u) - cdf) - 1;
  }
  void build_distribution() {
    const int wdt = map_->width(), h = map_->height();
    weight_.assign(static_cast<std::size_t>(wdt) * h, 0.f);
    conditional_.assign(static_cast<std::size_t>(wdt + 1) * h, 0.f);
    marginal_.assign(static_cast<std::size_t>(h) + 1, 0.f);
    for (int y = 0; y < h; ++y) {
      const float sin_theta = std::sin((static_cast<float>(y) + 0.5f) / static_cast<float>(h) * std::numbers::pi_v<float>);
      float* cdf = &conditional_[static_cast<std::size_t>(y) * (wdt + 1)];
      for (int x = 0; x < wdt; ++x) {
        const Vec3f& t = map_->texel(x, y);
        // A floor keeps every direction reachable, so the estimator stays unbiased.
        const float w = (0.2126f * t.x + 0.7152f * t.y + 0.0722f * t.z + 1e-4f) * sin_theta;
        weight_[static_cast<std::size_t>(y) * wdt + x] = w;
        cdf[x + 1] = cdf[x] + w;
      }
      marginal_[y + 1] = marginal_[y] + cdf[wdt];
      for (int x = 1; x <= wdt; ++x) cdf[x] = cdf[wdt] > 0.f ? cdf[x] / cdf[wdt] : static_cast<float>(x) / wdt;
    }
    total_ = marginal_[h];
    for (int y = 1; y <= h; ++y) marginal_[y] = total_ > 0.f ? marginal_[y] / total_ : static_cast<float>(y) / h;
    total_ /= static_cast<float>(wdt * h);  // mean weight, so weight/total is the texel's density in (u,v)
  }

  std::shared_ptr<const Texture2D> map_;
  Vec3f up_{0.f, 1.f, 0.f}, direction_{0.f, 0.f, 1.f}, forward_{0.f, 0.f, 1.f}, side_{1.f, 0.f, 0.f};
  std::vector<float> weight_, conditional_, marginal_;
  float total_ = 0.f;
};

using Light = std::variant<AmbientLight, DistantLight, SphereLight, SpotLight, QuadLight, HdriLight>;

inline const char* type_name(const Light& light) {
  static constexpr const char* names[] = {"ambient", "distant", "sphere", "spot", "quad", "hdri"};
  return names[light.index()];
}

/// A default light of OSPRay type `type` among those described by parameters alone
/// (ambient, distant, sphere, spot, quad; `hdri` needs its map); nullopt otherwise.
inline std::optional<Light> light_of_type(std::string_view type) {
  if (type == "ambient") return AmbientLight{};
  if (type == "distant") return DistantLight{};
  if (type == "sphere") return SphereLight{};
  if (type == "spot") return SpotLight{};
  if (type == "quad") return QuadLight{};
  return std::nullopt;
}

/// Calls read(name, field) for every parameter of `light` under its OSPRay name (field:
/// float&, bool& or Vec3f&); an `hdri` light's map, up and direction are set when it is
/// constructed, so only its common parameters are listed.
template <class Read>
void for_each_parameter(Light& light, Read&& read) {
  std::visit(
      [&](auto& l) {
        using L = std::decay_t<decltype(l)>;
        read("color", l.color), read("intensity", l.intensity), read("visible", l.visible);
        if constexpr (std::is_same_v<L, DistantLight>) {
          read("direction", l.direction), read("angularDiameter", l.angular_diameter);
        } else if constexpr (std::is_same_v<L, SphereLight>) {
          read("position", l.position), read("radius", l.radius);
        } else if constexpr (std::is_same_v<L, SpotLight>) {
          read("position", l.position), read("direction", l.direction), read("openingAngle", l.opening_angle);
          read("penumbraAngle", l.penumbra_angle), read("radius", l.radius);
        } else if constexpr (std::is_same_v<L, QuadLight>) {
          read("position", l.position), read("edge1", l.edge1), read("edge2", l.edge2);
        }
      },
      light);
}

/// A light sampled from a point.
struct LightSample {
  Vec3f dir;          ///< unit direction towards the light
  float dist;         ///< distance to the light (inf for lights at infinity)
  Vec3f weight;       ///< radiance * (cosine at the light where it has area) / pdf
  float pdf;          ///< solid-angle pdf; inf for delta lights
};

/// Radiance arriving along a direction and the pdf `sample` would have chosen it with.
struct LightEval {
  Vec3f radiance;
  float pdf;
};

namespace detail {

constexpr float pi = std::numbers::pi_v<float>;
inline float radians(float degrees) { return degrees * pi / 180.f; }

/// A direction in the cone of half-angle acos(cos_max) around `axis`, uniformly.
inline Vec3f sample_cone(const Vec3f& axis, float cos_max, float u1, float u2) {
  const float cos_theta = 1.f - u1 * (1.f - cos_max);
  const float sin_theta = std::sqrt(std::max(0.f, 1.f - cos_theta * cos_theta));
  const float phi = 2.f * pi * u2;
  const Vec3f t = perpendicular(axis), b = cross(axis, t);
  return t * (sin_theta * std::cos(phi)) + b * (sin_theta * std::sin(phi)) + axis * cos_theta;
}

/// Cosine-weighted direction around the unit normal `n`.
inline Vec3f sample_cosine(const Vec3f& n, float u1, float u2) {
  const float r = std::sqrt(u1), phi = 2.f * pi * u2;
  const Vec3f t = perpendicular(n), b = cross(n, t);
  return t * (r * std::cos(phi)) + b * (r * std::sin(phi)) + n * std::sqrt(std::max(0.f, 1.f - u1));
}

inline float spot_falloff(const SpotLight& s, const Vec3f& from_light) {
  const float cos_outer = std::cos(radians(0.5f * std::min(s.opening_angle, 360.f)));
  const float cos_inner = std::cos(radians(std::max(0.f, 0.5f * std::min(s.opening_angle, 360.f) - s.penumbra_angle)));
  const float c = dot(from_light, normalize(s.direction));
  if (c <= cos_outer) return 0.f;
  if (c >= cos_inner || cos_inner <= cos_outer) return 1.f;
  const float x = (c - cos_outer) / (cos_inner - cos_outer);
  return x * x * (3.f - 2.f * x);
}

/// Ray-sphere distance (the near root in front of the origin) or inf.
inline float hit_sphere(const Vec3f& org, const Vec3f& dir, const Vec3f& center, float radius) {
  const Vec3f oc = org - center;
  const float b = dot(oc, dir);
  const Vec3f perp = oc - dir * b;  // stable discriminant (Ray Tracing Gems ch. 7)
  const float disc = radius * radius - dot(perp, perp);
  if (disc < 0.f) return std::numeric_limits<float>::infinity();
  const float q = -b - std::copysign(std::sqrt(disc), b);
  const float c = dot(oc, oc) - radius * radius;
  float t0 = c / q, t1 = q;
  if (t0 > t1) std::swap(t0, t1);
  return t0 > 0.f ? t0 : (t1 > 0.f ? t1 : std::numeric_limits<float>::infinity());
}

}  // namespace detail

/// Throws an Error naming the first bad parameter of `light`.
inline void validate(const Light& light) {
  const std::string type = type_name(light);
  const auto fail = [&](const char* parameter, const char* what) {
    throw Error(type + " light: parameter '" + parameter + "' " + what);
  };
  const auto finite = [](const Vec3f& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); };
  std::visit(
      [&](const auto& l) {
        using L = std::decay_t<decltype(l)>;
        if (!finite(l.color) || l.color.x < 0.f || l.color.y < 0.f || l.color.z < 0.f)
          fail("color", "must be finite and not negative");
        if (!(l.intensity >= 0.f) || !std::isfinite(l.intensity)) fail("intensity", "must be finite and not negative");
        if constexpr (std::is_same_v<L, DistantLight>) {
          if (!finite(l.direction) || length(l.direction) == 0.f) fail("direction", "must be a finite non-zero vector");
          if (!(l.angular_diameter >= 0.f && l.angular_diameter < 180.f))
            fail("angularDiameter", "must be in [0, 180) degrees");
        } else if constexpr (std::is_same_v<L, SphereLight>) {
          if (!finite(l.position)) fail("position", "must be finite");
          if (!(l.radius >= 0.f) || !std::isfinite(l.radius)) fail("radius", "must be finite and not negative");
        } else if constexpr (std::is_same_v<L, SpotLight>) {
          if (!finite(l.position)) fail("position", "must be finite");
          if (!finite(l.direction) || length(l.direction) == 0.f) fail("direction", "must be a finite non-zero vector");
          if (!(l.opening_angle > 0.f && l.opening_angle <= 360.f)) fail("openingAngle", "must be in (0, 360] degrees");
          if (!(l.penumbra_angle >= 0.f) || !std::isfinite(l.penumbra_angle)) fail("penumbraAngle", "must not be negative");
          if (!(l.radius >= 0.f) || !std::isfinite(l.radius)) fail("radius", "must be finite and not negative");
        } else if constexpr (std::is_same_v<L, QuadLight>) {
          if (!finite(l.position)) fail("position", "must be finite");
          if (!finite(l.edge1) || !finite(l.edge2) || length(cross(l.edge1, l.edge2)) == 0.f)
            fail("edge1", "and 'edge2' must be finite and span a parallelogram of non-zero area");
        } else if constexpr (std::is_same_v<L, HdriLight>) {
          if (!l.map()) fail("map", "is missing");
        }
      },
      light);
}

/// Samples `light` from point `p` with surface normal `n` (used by `ambient` to sample
/// the cosine-weighted hemisphere; a zero `n`, a point in a medium, samples the whole
/// sphere uniformly). nullopt where the light cannot reach p.
inline std::optional<LightSample> sample(const Light& light, const Vec3f& p, const Vec3f& n, float u1, float u2) {
  using detail::pi;
  constexpr float inf = std::numeric_limits<float>::infinity();
  return std::visit(
      [&](const auto& l) -> std::optional<LightSample> {
        using L = std::decay_t<decltype(l)>;
        const Vec3f power = l.color * l.intensity;
        if constexpr (std::is_same_v<L, AmbientLight>) {
          if (dot(n, n) == 0.f) {  // a point in a medium: light from the whole sphere
            const float z = 1.f - 2.f * u1, r = std::sqrt(std::max(0.f, 1.f - z * z)), phi = 2.f * pi * u2;
            const float pdf = 1.f / (4.f * pi);
            return LightSample{{r * std::cos(phi), r * std::sin(phi), z}, inf, power / pdf, pdf};
          }
          const Vec3f w = detail::sample_cosine(n, u1, u2);
          const float pdf = dot(w, n) / pi;
          if (!(pdf > 0.f)) return std::nullopt;
          return LightSample{w, inf, power / pdf, pdf};
        } else if constexpr (std::is_same_v<L, DistantLight>) {
          const Vec3f to_light = -normalize(l.direction);
          if (l.angular_diameter <= 0.f) return LightSample{to_light, inf, power, inf};
          const float cos_max = std::cos(detail::radians(0.5f * l.angular_diameter));
          const float solid_angle = 2.f * pi * (1.f - cos_max);
          // Irradiance spread evenly over the disk: radiance = E / solid angle.
          return LightSample{detail::sample_cone(to_light, cos_max, u1, u2), inf, power, 1.f / solid_angle};
        } else if constexpr (std::is_same_v<L, SphereLight>) {
          const Vec3f d = l.position - p;
          const float dist2 = dot(d, d), dist = std::sqrt(dist2);
          if (!(dist > l.radius)) return std::nullopt;  // inside the light
          if (l.radius <= 0.f) return LightSample{d / dist, dist, power / dist2, inf};
          const float sin2 = l.radius * l.radius / dist2;
          const float cos_max = std::sqrt(std::max(0.f, 1.f - sin2));
          const float solid_angle = 2.f * pi * (1.f - cos_max);
          const Vec3f w = detail::sample_cone(d / dist, cos_max, u1, u2);
          const float t = detail::hit_sphere(p, w, l.position, l.radius);
          const Vec3f radiance = power / (pi * l.radius * l.radius);
          return LightSample{w, std::isfinite(t) ? t : dist, radiance * solid_angle, 1.f / solid_angle};
        } else if constexpr (std::is_same_v<L, SpotLight>) {
          const Vec3f axis = normalize(l.direction);
          if (l.radius <= 0.f) {
            const Vec3f d = l.position - p;
            const float dist2 = dot(d, d), dist = std::sqrt(dist2);
            if (!(dist > 0.f)) return std::nullopt;
            const float falloff = detail::spot_falloff(l, -d / dist);
            if (falloff <= 0.f) return std::nullopt;
            return LightSample{d / dist, dist, power * (falloff / dist2), inf};
          }
          // A disk facing `direction`, its area sampled uniformly.
          const float r = l.radius * std::sqrt(u1), phi = 2.f * pi * u2;
          const Vec3f t = perpendicular(axis), b = cross(axis, t);
          const Vec3f q = l.position + t * (r * std::cos(phi)) + b * (r * std::sin(phi));
          const Vec3f d = q - p;
          const float dist2 = dot(d, d), dist = std::sqrt(dist2);
          if (!(dist > 0.f)) return std::nullopt;
          const Vec3f w = d / dist;
          const float cos_light = -dot(w, axis);
          if (cos_light <= 0.f) return std::nullopt;
          const float falloff = detail::spot_falloff(l, -w);
          if (falloff <= 0.f) return std::nullopt;
          const float area = pi * l.radius * l.radius;
          const float pdf = dist2 / (cos_light * area);
          const Vec3f radiance = power * (falloff / area);  // intensity / projected area
          return LightSample{w, dist, radiance / pdf, pdf};
        } else if constexpr (std::is_same_v<L, QuadLight>) {
          const Vec3f q = l.position + l.edge1 * u1 + l.edge2 * u2;
          const Vec3f normal_area = cross(l.edge1, l.edge2);
          const float area = length(normal_area);
          const Vec3f d = q - p;
          const float dist2 = dot(d, d), dist = std::sqrt(dist2);
          if (!(dist > 0.f)) return std::nullopt;
          const Vec3f w = d / dist;
          const float cos_light = -dot(w, normal_area) / area;
          if (cos_light <= 0.f) return std::nullopt;  // the back of the quad
          const float pdf = dist2 / (cos_light * area);
          return LightSample{w, dist, power / pdf, pdf};
        } else {
          static_assert(std::is_same_v<L, HdriLight>);
          const auto s = l.sample(u1, u2);
          if (!(s.pdf > 0.f)) return std::nullopt;
          return LightSample{s.w, inf, power * l.lookup(s.w) / s.pdf, s.pdf};
        }
      },
      light);
}

/// What `light` contributes along the ray (p, w) if nothing is closer than `max_dist`;
/// `n` as for `sample`. Zero for delta lights.
inline LightEval eval(const Light& light, const Vec3f& p, const Vec3f& n, const Vec3f& w, float max_dist) {
  using detail::pi;
  constexpr LightEval none{{0.f, 0.f, 0.f}, 0.f};
  constexpr float inf = std::numeric_limits<float>::infinity();
  return std::visit(
      [&](const auto& l) -> LightEval {
        using L = std::decay_t<decltype(l)>;
        const Vec3f power = l.color * l.intensity;
        if constexpr (std::is_same_v<L, AmbientLight>) {
          if (max_dist < inf) return none;
          return {power, dot(n, n) == 0.f ? 1.f / (4.f * pi) : std::max(0.f, dot(w, n)) / pi};
        } else if constexpr (std::is_same_v<L, DistantLight>) {
          if (max_dist < inf || l.angular_diameter <= 0.f) return none;
          const float cos_max = std::cos(detail::radians(0.5f * l.angular_diameter));
          if (dot(w, -normalize(l.direction)) < cos_max) return none;
          const float solid_angle = 2.f * pi * (1.f - cos_max);
          return {power / solid_angle, 1.f / solid_angle};
        } else if constexpr (std::is_same_v<L, SphereLight>) {
          if (l.radius <= 0.f) return none;
          const float t = detail::hit_sphere(p, w, l.position, l.radius);
          if (!(t < max_dist)) return none;
          const Vec3f d = l.position - p;
          const float dist2 = dot(d, d);
          if (dist2 <= l.radius * l.radius) return none;
          const float cos_max = std::sqrt(std::max(0.f, 1.f - l.radius * l.radius / dist2));
          return {power / (pi * l.radius * l.radius), 1.f / (2.f * pi * (1.f - cos_max))};
        } else if constexpr (std::is_same_v<L, SpotLight>) {
          if (l.radius <= 0.f) return none;
          const Vec3f axis = normalize(l.direction);
          const float denom = dot(w, axis);
          if (denom >= 0.f) return none;  // the disk emits along its axis only
          const float t = dot(l.position - p, axis) / denom;
          if (!(t > 0.f && t < max_dist)) return none;
          const Vec3f q = p + w * t;
          const Vec3f r = q - l.position;
          if (dot(r, r) > l.radius * l.radius) return none;
          const float falloff = detail::spot_falloff(l, -w);
          const float area = pi * l.radius * l.radius;
          return {power * (falloff / area), t * t / (-denom * area)};
        } else if constexpr (std::is_same_v<L, QuadLight>) {
          const Vec3f normal_area = cross(l.edge1, l.edge2);
          const float area = length(normal_area);
          const float denom = dot(w, normal_area);
          if (denom >= 0.f) return none;
          const float t = dot(l.position - p, normal_area) / denom;
          if (!(t > 0.f && t < max_dist)) return none;
          // Barycentric-like coordinates of the hit in the parallelogram.
          const Vec3f r = p + w * t - l.position;
          const Vec3f c1 = cross(l.edge2, normal_area), c2 = cross(normal_area, l.edge1);
          const float a = dot(r, c1) / dot(l.edge1, c1), b = dot(r, c2) / dot(l.edge2, c2);
          if (a < 0.f || a > 1.f || b < 0.f || b > 1.f) return none;
          const float cos_light = -denom / area;
          return {power, t * t / (cos_light * area)};
        } else {
          static_assert(std::is_same_v<L, HdriLight>);
          if (max_dist < inf) return none;
          return {power * l.lookup(w), l.pdf(w)};
        }
      },
      light);
}

/// Whether `light` has no extent (point, spot without radius, distant without diameter):
/// only light sampling can find it.
inline bool is_delta(const Light& light) {
  return std::visit(
      [](const auto& l) {
        using L = std::decay_t<decltype(l)>;
        if constexpr (std::is_same_v<L, DistantLight>) return l.angular_diameter <= 0.f;
        else if constexpr (std::is_same_v<L, SphereLight> || std::is_same_v<L, SpotLight>) return l.radius <= 0.f;
        else return false;
      },
      light);
}

/// Lights at infinity (seen where a ray escapes the scene).
inline bool at_infinity(const Light& light) {
  return std::holds_alternative<AmbientLight>(light) || std::holds_alternative<DistantLight>(light) ||
         std::holds_alternative<HdriLight>(light);
}

/// The lights the scivis renderer used before lights were configurable, and what a scene
/// without lights gets: white ambient light of 0.2 and a distant light of irradiance 0.8π travelling
/// along `direction`.
inline std::vector<Light> default_lights(Vec3f direction = {0.f, 0.f, -1.f}) {
  AmbientLight ambient;
  ambient.intensity = 0.2f;
  DistantLight distant;
  distant.direction = direction;
  // Irradiance 0.8π: a white Lambertian surface facing it reflects radiance 0.8.
  distant.intensity = 0.8f * std::numbers::pi_v<float>;
  return {ambient, distant};
}

}  // namespace sciray
