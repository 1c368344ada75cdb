#pragma once
// Lights with OSPRay's types and parameters, and how renderers sample them. A light's
// `color * intensity` is measured in its `quantity` (OSPRay's `intensityQuantity`), whose
// default and accepted values are OSPRay's: see `accepts` and `emitted`.
//
// Sampling runs per ray (scalar): `sample` picks a direction towards the light from a
// point and returns the radiance divided by the pdf; `eval` returns the radiance and pdf
// of a direction found otherwise (by BSDF sampling), which multiple importance sampling
// weighs against. Delta lights (no size) have an infinite pdf and are never hit. Sample
// point (0, 0), where OSPRay's scivis samples every light, lands where it does in OSPRay:
// the centre of a sphere, disk or cone, a ring's inner edge along c0, a quad's `position`,
// the direction to a cylinder's centre.
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
#include "sciray/math/affine.hpp"
#include "sciray/math/motion.hpp"
#include "sciray/math/vec.hpp"
#include "sciray/render/light_cylinder.hpp"
#include "sciray/render/light_distribution.hpp"
#include "sciray/render/light_hdri.hpp"

namespace sciray {

struct LightCommon {
  Vec3f color{1.f, 1.f, 1.f};
  float intensity = 1.f;
  bool visible = true;  ///< seen by camera rays (area and environment lights)
};

/// Radiance from every direction (OSPRay `ambient`); `quantity` radiance or irradiance.
struct AmbientLight : LightCommon {
  IntensityQuantity quantity = IntensityQuantity::radiance;
};

/// A light at infinity travelling along `direction`; a disk of `angular_diameter` degrees
/// (the sun: 0.53) casts soft shadows. `quantity` irradiance or radiance (of the disk).
struct DistantLight : LightCommon {
  Vec3f direction{0.f, 0.f, 1.f};
  float angular_diameter = 0.f;
  IntensityQuantity quantity = IntensityQuantity::irradiance;
};

/// A point light, or with `radius` > 0 a sphere (OSPRay `sphere`). `quantity` intensity,
/// power or radiance; with a `distribution` (photometric, its axis `direction`, c0 `c0`
/// or OSPRay's default) scale only: color * intensity * the table is the intensity.
struct SphereLight : LightCommon {
  Vec3f position{0.f, 0.f, 0.f};
  float radius = 0.f;
  Vec3f direction{0.f, 0.f, 1.f};
  std::optional<Vec3f> c0;
  IntensityDistribution distribution;
  IntensityQuantity quantity = IntensityQuantity::intensity;
};

/// A spot light emitting along `direction` within `opening_angle` degrees (full angle),
/// fading out linearly in cosine over `penumbra_angle` inside it; with `radius` > 0 a
/// disk facing `direction`, a ring with `inner_radius` > 0. Without size it emits as a
/// small Lambertian disk: intensity times the cosine to `direction`. `quantity`
/// intensity, power or radiance; with a `distribution` scale (or radiance).
struct SpotLight : LightCommon {
  Vec3f position{0.f, 0.f, 0.f};
  Vec3f direction{0.f, 0.f, 1.f};
  float opening_angle = 180.f;
  float penumbra_angle = 5.f;
  float radius = 0.f;
  float inner_radius = 0.f;
  std::optional<Vec3f> c0;  ///< where the ring's sample (0, 0) and C = 0 lie
  IntensityDistribution distribution;
  IntensityQuantity quantity = IntensityQuantity::intensity;
};

/// A parallelogram at `position` spanned by `edge1` and `edge2`, emitting to the side of
/// edge1 x edge2 (to both, shaped by the table, with a `distribution`, whose c0 defaults
/// to `edge2`). `quantity` radiance, intensity or power; with a distribution scale.
struct QuadLight : LightCommon {
  Vec3f position{0.f, 0.f, 0.f};
  Vec3f edge1{1.f, 0.f, 0.f};
  Vec3f edge2{0.f, 1.f, 0.f};
  std::optional<Vec3f> c0;
  IntensityDistribution distribution;
  IntensityQuantity quantity = IntensityQuantity::radiance;
};

/// The side of a cylinder from `position0` to `position1` (OSPRay `cylinder`), emitting
/// outwards; its caps do not emit. `quantity` radiance, intensity or power.
struct CylinderLight : LightCommon {
  Vec3f position0{0.f, 0.f, 0.f};
  Vec3f position1{0.f, 0.f, 1.f};
  float radius = 1.f;
  IntensityQuantity quantity = IntensityQuantity::radiance;
};

using Light = std::variant<AmbientLight, DistantLight, SphereLight, SpotLight, QuadLight, CylinderLight, HdriLight>;

inline const char* type_name(const Light& light) {
  static constexpr const char* names[] = {"ambient", "distant", "sphere", "spot", "quad", "cylinder", "hdri"};
  return names[light.index()];
}

/// A default light of OSPRay type `type` among those described by parameters alone
/// (ambient, distant, sphere, spot, quad, cylinder; `hdri` needs its map, `sunSky` is a
/// sky and a sun, render/sky.hpp); nullopt otherwise.
inline std::optional<Light> light_of_type(std::string_view type) {
  if (type == "ambient") return AmbientLight{};
  if (type == "distant") return DistantLight{};
  if (type == "sphere") return SphereLight{};
  if (type == "spot") return SpotLight{};
  if (type == "quad") return QuadLight{};
  if (type == "cylinder") return CylinderLight{};
  return std::nullopt;
}

/// Calls read(name, field) for every parameter of `light` under its OSPRay name (field:
/// float&, bool& or Vec3f&). Not listed, as they are not plain values: `quantity`
/// (intensityQuantity), `c0` and `distribution` (intensityDistribution), and an `hdri`
/// light's map, up and direction, set when it is constructed.
template <class Read>
void for_each_parameter(Light& light, Read&& read) {
  std::visit(
      [&](auto& l) {
        using L = std::decay_t<decltype(l)>;
        read("color", l.color), read("intensity", l.intensity), read("visible", l.visible);
        if constexpr (std::is_same_v<L, DistantLight>) {
          read("direction", l.direction), read("angularDiameter", l.angular_diameter);
        } else if constexpr (std::is_same_v<L, SphereLight>) {
          read("position", l.position), read("radius", l.radius), read("direction", l.direction);
        } else if constexpr (std::is_same_v<L, SpotLight>) {
          read("position", l.position), read("direction", l.direction), read("openingAngle", l.opening_angle);
          read("penumbraAngle", l.penumbra_angle), read("radius", l.radius), read("innerRadius", l.inner_radius);
        } else if constexpr (std::is_same_v<L, QuadLight>) {
          read("position", l.position), read("edge1", l.edge1), read("edge2", l.edge2);
        } else if constexpr (std::is_same_v<L, CylinderLight>) {
          read("position0", l.position0), read("position1", l.position1), read("radius", l.radius);
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

/// Cosine-weighted direction around the unit normal `n`, per lane for packets.
template <class T>
Vec3<T> sample_cosine(const Vec3<T>& n, const T& u1, const T& u2) {
  using std::cos, std::sin;  // xsimd's for packets, by argument-dependent lookup
  const T r = simd::sqrt(u1), phi = T(2.f * pi) * u2;
  const Vec3<T> t = perpendicular(n), b = cross(n, t);
  return t * (r * cos(phi)) + b * (r * sin(phi)) + n * simd::sqrt(simd::max(T(0.f), T(1.f) - u1));
}

inline float cos_half_opening(const SpotLight& s) { return std::cos(radians(0.5f * std::min(s.opening_angle, 360.f))); }

/// OSPRay's spot fall-off: linear in the cosine from the opening angle's edge over the
/// penumbra (at most half the opening angle).
inline float spot_falloff(const SpotLight& s, float cos_angle) {
  const float half = 0.5f * std::min(s.opening_angle, 360.f);
  const float cos_outer = std::cos(radians(half));
  const float cos_inner = std::cos(radians(half - std::clamp(s.penumbra_angle, 0.f, half)));
  if (cos_angle <= cos_outer) return 0.f;
  if (cos_angle >= cos_inner) return 1.f;
  return (cos_angle - cos_outer) / (cos_inner - cos_outer);
}

inline float ring_area(const SpotLight& s) { return pi * (s.radius * s.radius - s.inner_radius * s.inner_radius); }
inline float lateral_area(const CylinderLight& c) { return 2.f * pi * c.radius * length(c.position1 - c.position0); }

inline PhotometricFrame spot_frame(const SpotLight& s) {
  return photometric_frame(s.direction, s.c0 ? *s.c0 : default_c0(s.direction));
}
inline PhotometricFrame sphere_frame(const SphereLight& s) {
  return photometric_frame(s.direction, s.c0 ? *s.c0 : default_c0(s.direction));
}
/// A quad's table is measured around edge1 x edge2, c0 defaulting to edge2.
inline PhotometricFrame quad_frame(const QuadLight& q) {
  return photometric_frame(cross(q.edge1, q.edge2), q.c0 ? *q.c0 : q.edge2);
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

/// A sphere this small seen from a point is a point light to OSPRay, for precision: no
/// surface to hit, its intensity over the squared distance.
inline bool point_like(const SphereLight& s, float dist) { return !(s.radius > 0.005f * dist); }

}  // namespace detail

/// Whether `light` takes `color * intensity` in quantity `q` (as OSPRay does).
inline bool accepts(const Light& light, IntensityQuantity q) {
  using Q = IntensityQuantity;
  return std::visit(
      [&](const auto& l) {
        using L = std::decay_t<decltype(l)>;
        if constexpr (std::is_same_v<L, AmbientLight>) return q == Q::radiance || q == Q::irradiance;
        else if constexpr (std::is_same_v<L, DistantLight>) return q == Q::irradiance || q == Q::radiance;
        else if constexpr (std::is_same_v<L, SphereLight>)
          return l.distribution ? q == Q::scale : q == Q::intensity || q == Q::power || q == Q::radiance;
        else if constexpr (std::is_same_v<L, SpotLight>)
          return l.distribution ? q == Q::scale || q == Q::radiance
                                : q == Q::intensity || q == Q::power || q == Q::radiance;
        else if constexpr (std::is_same_v<L, QuadLight>)
          return l.distribution ? q == Q::scale : q == Q::radiance || q == Q::intensity || q == Q::power;
        else if constexpr (std::is_same_v<L, CylinderLight>)
          return q == Q::radiance || q == Q::intensity || q == Q::power;
        else return q == Q::scale || q == Q::radiance;
      },
      light);
}

/// What `light` emits, from `color * intensity` in its `quantity`: the radiance of
/// ambient, quad, cylinder and hdri (its map's scale) lights, the irradiance of a
/// distant light, the radiant intensity (W/sr, before any table or fall-off) of sphere
/// and spot lights. Conversions are OSPRay's: a sphere's radiance is its intensity over
/// its disk's area, a spot's over its ring's area and its power over the cosine-weighted
/// cap of its opening angle (its emission carries a cosine), a quad's and a cylinder's
/// intensity is the radiance times their area (times pi, their power).
inline Vec3f emitted(const Light& light) {
  using Q = IntensityQuantity;
  using detail::pi;
  return std::visit(
      [&](const auto& l) -> Vec3f {
        using L = std::decay_t<decltype(l)>;
        const Vec3f ci = l.color * l.intensity;
        if constexpr (std::is_same_v<L, AmbientLight>) {
          return l.quantity == Q::irradiance ? ci / pi : ci;
        } else if constexpr (std::is_same_v<L, DistantLight>) {
          if (l.quantity != Q::radiance) return ci;
          // The disk's solid angle 2 pi (1 - cos(a / 2)), as 4 pi sin^2(a / 4): no cancellation for a small a.
          const float s = std::sin(detail::radians(0.25f * l.angular_diameter));
          return ci * (4.f * pi * s * s);
        } else if constexpr (std::is_same_v<L, SphereLight>) {
          if (l.quantity == Q::power) return ci / (4.f * pi);
          if (l.quantity == Q::radiance) return ci * (pi * l.radius * l.radius);
          return ci;
        } else if constexpr (std::is_same_v<L, SpotLight>) {
          if (l.quantity == Q::radiance) return ci * detail::ring_area(l);
          if (l.quantity == Q::power) {
            const float c = detail::cos_half_opening(l);
            return ci / (pi * (1.f - c * c));
          }
          return ci;
        } else if constexpr (std::is_same_v<L, QuadLight>) {
          const float area = length(cross(l.edge1, l.edge2));
          if (l.quantity == Q::intensity || l.quantity == Q::scale) return ci / area;
          if (l.quantity == Q::power) return ci / (pi * area);
          return ci;
        } else if constexpr (std::is_same_v<L, CylinderLight>) {
          const float area = detail::lateral_area(l);
          if (l.quantity == Q::intensity) return ci * (pi / area);
          if (l.quantity == Q::power) return ci / (pi * area);
          return ci;
        } else {
          return ci;
        }
      },
      light);
}

/// `light` placed by an instance's transform: points and vectors transformed, sizes given
/// by radii kept (as OSPRay). What a quad or cylinder emits was fixed by its own size
/// (when given as intensity or power): scaled, it keeps its radiance.
inline Light transformed(const Light& light, const Affine3f& xfm) {
  using Q = IntensityQuantity;
  return std::visit(
      [&](const auto& l) -> Light {
        using L = std::decay_t<decltype(l)>;
        L out = l;
        if constexpr (std::is_same_v<L, DistantLight>) {
          out.direction = xfm.vector(l.direction);
        } else if constexpr (std::is_same_v<L, SphereLight> || std::is_same_v<L, SpotLight>) {
          out.position = xfm.point(l.position);
          out.direction = xfm.vector(l.direction);
          out.c0 = xfm.vector(l.c0 ? *l.c0 : default_c0(l.direction));
        } else if constexpr (std::is_same_v<L, QuadLight>) {
          out.position = xfm.point(l.position);
          out.edge1 = xfm.vector(l.edge1), out.edge2 = xfm.vector(l.edge2);
          if (l.c0) out.c0 = xfm.vector(*l.c0);
          if (l.quantity != Q::radiance)
            out.intensity *= length(cross(out.edge1, out.edge2)) / length(cross(l.edge1, l.edge2));
        } else if constexpr (std::is_same_v<L, CylinderLight>) {
          out.position0 = xfm.point(l.position0), out.position1 = xfm.point(l.position1);
          if (l.quantity != Q::radiance) out.intensity *= detail::lateral_area(out) / detail::lateral_area(l);
        } else if constexpr (std::is_same_v<L, HdriLight>) {
          out = l.rotated(xfm);
        }
        return out;
      },
      light);
}

/// A light of a group that a moving instance places: `light` in the group's space, placed
/// by `motion` at each ray's time (as OSPRay places it).
struct MovingLight {
  Light light;
  MotionTransform motion;
  Light at(float time) const { return transformed(light, motion.at(time)); }
};

/// Throws an Error naming the first bad parameter of `light`.
inline void validate(const Light& light) {
  const std::string type = type_name(light);
  const auto fail = [&](const char* parameter, const std::string& what) {
    throw Error(type + " light: parameter '" + parameter + "' " + what);
  };
  const auto finite = [](const Vec3f& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); };
  const auto finite_nonnegative = [](float x) { return x >= 0.f && std::isfinite(x); };
  std::visit(
      [&](const auto& l) {
        using L = std::decay_t<decltype(l)>;
        if (!finite(l.color) || l.color.x < 0.f || l.color.y < 0.f || l.color.z < 0.f)
          fail("color", "must be finite and not negative");
        if (!finite_nonnegative(l.intensity)) fail("intensity", "must be finite and not negative");
        if (!accepts(light, l.quantity)) {
          std::string why = "value " + std::to_string(static_cast<int>(l.quantity)) + " is not supported by " + type;
          if constexpr (std::is_same_v<L, SphereLight> || std::is_same_v<L, SpotLight> || std::is_same_v<L, QuadLight>)
            why += l.distribution ? " lights with 'intensityDistribution'" : " lights without 'intensityDistribution'";
          else
            why += " lights";
          fail("intensityQuantity", why);
        }
        if constexpr (std::is_same_v<L, DistantLight>) {
          if (!finite(l.direction) || length(l.direction) == 0.f) fail("direction", "must be a finite non-zero vector");
          if (!(l.angular_diameter >= 0.f && l.angular_diameter < 180.f))
            fail("angularDiameter", "must be in [0, 180) degrees");
        } else if constexpr (std::is_same_v<L, SphereLight>) {
          if (!finite(l.position)) fail("position", "must be finite");
          if (!finite_nonnegative(l.radius)) fail("radius", "must be finite and not negative");
          if (!finite(l.direction) || length(l.direction) == 0.f) fail("direction", "must be a finite non-zero vector");
          if (l.c0 && (!finite(*l.c0) || length(*l.c0) == 0.f)) fail("c0", "must be a finite non-zero vector");
        } else if constexpr (std::is_same_v<L, SpotLight>) {
          if (!finite(l.position)) fail("position", "must be finite");
          if (!finite(l.direction) || length(l.direction) == 0.f) fail("direction", "must be a finite non-zero vector");
          if (!(l.opening_angle > 0.f && l.opening_angle <= 360.f)) fail("openingAngle", "must be in (0, 360] degrees");
          if (!finite_nonnegative(l.penumbra_angle)) fail("penumbraAngle", "must not be negative");
          if (!finite_nonnegative(l.radius)) fail("radius", "must be finite and not negative");
          if (!finite_nonnegative(l.inner_radius) || (l.inner_radius > 0.f && !(l.inner_radius < l.radius)))
            fail("innerRadius", "must be in [0, radius)");
          if (l.c0 && (!finite(*l.c0) || length(*l.c0) == 0.f)) fail("c0", "must be a finite non-zero vector");
        } else if constexpr (std::is_same_v<L, QuadLight>) {
          if (!finite(l.position)) fail("position", "must be finite");
          if (!finite(l.edge1) || !finite(l.edge2) || length(cross(l.edge1, l.edge2)) == 0.f)
            fail("edge1", "and 'edge2' must be finite and span a parallelogram of non-zero area");
          if (l.c0 && (!finite(*l.c0) || length(*l.c0) == 0.f)) fail("c0", "must be a finite non-zero vector");
        } else if constexpr (std::is_same_v<L, CylinderLight>) {
          if (!finite(l.position0)) fail("position0", "must be finite");
          if (!finite(l.position1) || !(length(l.position1 - l.position0) > 0.f))
            fail("position1", "must be finite and differ from 'position0'");
          if (!(l.radius > 0.f) || !std::isfinite(l.radius)) fail("radius", "must be finite and positive");
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
  const Vec3f emission = emitted(light);
  return std::visit(
      [&](const auto& l) -> std::optional<LightSample> {
        using L = std::decay_t<decltype(l)>;
        if constexpr (std::is_same_v<L, AmbientLight>) {
          if (dot(n, n) == 0.f) {  // a point in a medium: light from the whole sphere
            const float z = 1.f - 2.f * u1, r = std::sqrt(std::max(0.f, 1.f - z * z)), phi = 2.f * pi * u2;
            const float pdf = 1.f / (4.f * pi);
            return LightSample{{r * std::cos(phi), r * std::sin(phi), z}, inf, emission / pdf, pdf};
          }
          const Vec3f w = detail::sample_cosine(n, u1, u2);
          const float pdf = dot(w, n) / pi;
          if (!(pdf > 0.f)) return std::nullopt;
          return LightSample{w, inf, emission / pdf, pdf};
        } else if constexpr (std::is_same_v<L, DistantLight>) {
          const Vec3f to_light = -normalize(l.direction);
          if (l.angular_diameter <= 0.f) return LightSample{to_light, inf, emission, inf};
          const float cos_max = std::cos(detail::radians(0.5f * l.angular_diameter));
          const float solid_angle = 2.f * pi * (1.f - cos_max);
          // Irradiance spread evenly over the disk: radiance = E / solid angle.
          return LightSample{detail::sample_cone(to_light, cos_max, u1, u2), inf, emission, 1.f / solid_angle};
        } else if constexpr (std::is_same_v<L, SphereLight>) {
          const Vec3f d = l.position - p;
          const float dist2 = dot(d, d), dist = std::sqrt(dist2);
          if (!(dist > l.radius)) return std::nullopt;  // inside the light
          LightSample s;
          if (detail::point_like(l, dist)) {
            s = {d / dist, dist, emission / dist2, inf};
          } else {
            const float cos_max = std::sqrt(std::max(0.f, 1.f - l.radius * l.radius / dist2));
            const float solid_angle = 2.f * pi * (1.f - cos_max);
            const Vec3f w = detail::sample_cone(d / dist, cos_max, u1, u2);
            const float t = detail::hit_sphere(p, w, l.position, l.radius);
            const Vec3f radiance = emission / (pi * l.radius * l.radius);
            s = {w, std::isfinite(t) ? t : dist, radiance * solid_angle, 1.f / solid_angle};
          }
          if (l.distribution) {
            const PhotometricFrame f = detail::sphere_frame(l);
            s.weight = s.weight * l.distribution(f, -dot(f.axis, s.dir), -s.dir);
          }
          return s;
        } else if constexpr (std::is_same_v<L, SpotLight>) {
          const PhotometricFrame f = detail::spot_frame(l);
          Vec3f q = l.position;
          if (l.radius > 0.f) {
            // OSPRay's ring parametrization: u1 the squared radius, u2 the angle from c0.
            const float r = std::sqrt(l.inner_radius * l.inner_radius +
                                      u1 * (l.radius * l.radius - l.inner_radius * l.inner_radius));
            const float phi = 2.f * pi * u2;
            q = q + f.c0 * (r * std::cos(phi)) + f.c90 * (r * std::sin(phi));
          }
          const Vec3f d = q - p;
          const float dist2 = dot(d, d), dist = std::sqrt(dist2);
          if (!(dist > 0.f)) return std::nullopt;
          const Vec3f w = d / dist;
          const float cos_angle = -dot(w, f.axis);
          float shape = detail::spot_falloff(l, cos_angle);
          if (shape <= 0.f) return std::nullopt;
          // A table replaces the Lambertian cosine the plain spot emits with.
          shape *= l.distribution ? l.distribution(f, cos_angle, -w) : std::abs(cos_angle);
          if (l.radius <= 0.f) return LightSample{w, dist, emission * (shape / dist2), inf};
          const float pdf = dist2 / (std::abs(cos_angle) * detail::ring_area(l));
          // Radiance I / (ring area * cos): the ring's cosine cancels the intensity's.
          return LightSample{w, dist, emission * (shape / dist2), pdf};
        } else if constexpr (std::is_same_v<L, QuadLight>) {
          const Vec3f q = l.position + l.edge1 * u1 + l.edge2 * u2;
          const Vec3f normal_area = cross(l.edge1, l.edge2);
          const float area = length(normal_area);
          const Vec3f d = q - p;
          const float dist2 = dot(d, d), dist = std::sqrt(dist2);
          if (!(dist > 0.f)) return std::nullopt;
          const Vec3f w = d / dist;
          const float cos_light = -dot(w, normal_area) / area;
          if (l.distribution) {  // both sides, radiance = table / cos: weight independent of the cosine
            const float shape = l.distribution(detail::quad_frame(l), cos_light, -w);
            if (!(std::abs(cos_light) > 0.f)) return std::nullopt;
            return LightSample{w, dist, emission * (shape * area / dist2), dist2 / (std::abs(cos_light) * area)};
          }
          if (cos_light <= 0.f) return std::nullopt;  // the back of the quad
          const float pdf = dist2 / (cos_light * area);
          return LightSample{w, dist, emission / pdf, pdf};
        } else if constexpr (std::is_same_v<L, CylinderLight>) {
          const auto bounds = detail::cylinder_bounds(l.position0, l.position1, l.radius, p);
          if (!bounds || !(bounds->solid_angle > 0.f)) return std::nullopt;
          // Sample (0, 0), OSPRay's scivis sample, is the direction to the centre standing
          // for the whole light, as in OSPRay: radiance times the bounds' solid angle.
          const bool scivis = u1 == 0.f && u2 == 0.f;
          const detail::BilinearWarp warp = detail::cosine_warp(*bounds, n);
          const auto [su, sv] = warp.sample(u1, u2);
          const Vec3f w = scivis ? normalize((l.position0 + l.position1) * 0.5f - p) : bounds->sample(su, sv);
          const float t = detail::cylinder_side_entry(l.position0, l.position1, l.radius, p, w);
          if (!std::isfinite(t)) return std::nullopt;  // through a cap or past the side: rejected
          const float pdf = (scivis ? 1.f : warp.pdf(su, sv)) / bounds->solid_angle;
          if (!(pdf > 0.f)) return std::nullopt;
          return LightSample{w, t, emission / pdf, pdf};
        } else {
          static_assert(std::is_same_v<L, HdriLight>);
          const auto s = l.sample(u1, u2);
          if (!(s.pdf > 0.f)) return std::nullopt;
          return LightSample{s.w, inf, emission * l.lookup(s.w) / s.pdf, s.pdf};
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
  const Vec3f emission = emitted(light);
  return std::visit(
      [&](const auto& l) -> LightEval {
        using L = std::decay_t<decltype(l)>;
        if constexpr (std::is_same_v<L, AmbientLight>) {
          if (max_dist < inf) return none;
          return {emission, dot(n, n) == 0.f ? 1.f / (4.f * pi) : std::max(0.f, dot(w, n)) / pi};
        } else if constexpr (std::is_same_v<L, DistantLight>) {
          if (max_dist < inf || l.angular_diameter <= 0.f) return none;
          const float cos_max = std::cos(detail::radians(0.5f * l.angular_diameter));
          if (dot(w, -normalize(l.direction)) < cos_max) return none;
          const float solid_angle = 2.f * pi * (1.f - cos_max);
          return {emission / solid_angle, 1.f / solid_angle};
        } else if constexpr (std::is_same_v<L, SphereLight>) {
          const Vec3f d = l.position - p;
          const float dist2 = dot(d, d);
          if (l.radius <= 0.f || dist2 <= l.radius * l.radius || detail::point_like(l, std::sqrt(dist2))) return none;
          const float t = detail::hit_sphere(p, w, l.position, l.radius);
          if (!(t < max_dist)) return none;
          const float cos_max = std::sqrt(std::max(0.f, 1.f - l.radius * l.radius / dist2));
          Vec3f radiance = emission / (pi * l.radius * l.radius);
          if (l.distribution) {
            const PhotometricFrame f = detail::sphere_frame(l);
            radiance = radiance * l.distribution(f, -dot(f.axis, w), -w);
          }
          return {radiance, 1.f / (2.f * pi * (1.f - cos_max))};
        } else if constexpr (std::is_same_v<L, SpotLight>) {
          if (l.radius <= 0.f) return none;
          const PhotometricFrame f = detail::spot_frame(l);
          const float cos_angle = -dot(w, f.axis);
          const float falloff = detail::spot_falloff(l, cos_angle);
          if (falloff <= 0.f) return none;
          const float t = dot(p - l.position, f.axis) / cos_angle;
          if (!(t > 0.f && t < max_dist)) return none;
          const Vec3f r = p + w * t - l.position;
          const float r2 = dot(r, r);
          if (r2 > l.radius * l.radius || r2 < l.inner_radius * l.inner_radius) return none;
          const float area = detail::ring_area(l);
          const float shape = l.distribution ? l.distribution(f, cos_angle, -w) / std::abs(cos_angle) : 1.f;
          return {emission * (falloff * shape / area), t * t / (std::abs(cos_angle) * area)};
        } else if constexpr (std::is_same_v<L, QuadLight>) {
          const Vec3f normal_area = cross(l.edge1, l.edge2);
          const float area = length(normal_area);
          const float denom = dot(w, normal_area);
          if (denom >= 0.f && !l.distribution) return none;  // the back emits only with a table
          const float t = dot(l.position - p, normal_area) / denom;
          if (!(t > 0.f && t < max_dist)) return none;
          // Barycentric-like coordinates of the hit in the parallelogram.
          const Vec3f r = p + w * t - l.position;
          const Vec3f c1 = cross(l.edge2, normal_area), c2 = cross(normal_area, l.edge1);
          const float a = dot(r, c1) / dot(l.edge1, c1), b = dot(r, c2) / dot(l.edge2, c2);
          if (a < 0.f || a > 1.f || b < 0.f || b > 1.f) return none;
          const float cos_light = -denom / area;
          const float shape =
              l.distribution ? l.distribution(detail::quad_frame(l), cos_light, -w) / std::abs(cos_light) : 1.f;
          return {emission * shape, t * t / (std::abs(cos_light) * area)};
        } else if constexpr (std::is_same_v<L, CylinderLight>) {
          const auto bounds = detail::cylinder_bounds(l.position0, l.position1, l.radius, p);
          if (!bounds || !(bounds->solid_angle > 0.f)) return none;
          if (!(detail::cylinder_side_entry(l.position0, l.position1, l.radius, p, w) < max_dist)) return none;
          const auto [su, sv] = bounds->square_of(w);
          return {emission, detail::cosine_warp(*bounds, n).pdf(su, sv) / bounds->solid_angle};
        } else {
          static_assert(std::is_same_v<L, HdriLight>);
          if (max_dist < inf) return none;
          return {emission * l.lookup(w), l.pdf(w)};
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
