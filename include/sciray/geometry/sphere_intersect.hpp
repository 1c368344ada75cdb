#pragma once
// Ray–sphere and ray–disc intersection written once over the lane type, so the scalar
// instantiation is the reference the packet ones are tested against.
//
// The textbook quadratic (b² − 4ac) cancels catastrophically when the sphere is small
// against its distance from the ray origin: b² and 4ac agree in every float digit and
// their difference is noise, which shows as holes and speckles (tests/stability). Here the
// discriminant is computed from the ray's closest approach to the centre, a vector that
// is small exactly when it matters, and the near root from c/q so it does not cancel
// either (Haines, Günther, Wald, Akenine-Möller, Ray Tracing Gems ch. 7, 2019).
#include <limits>

#include "sciray/math/ray.hpp"
#include "sciray/simd/packet.hpp"

namespace sciray {

/// Where each lane's ray first meets a primitive inside (tnear, tfar), if it does.
template <class Arch>
struct PrimitiveHit {
  simd::Mask<Arch> hit;
  simd::Float<Arch> t;
  Vec3<simd::Float<Arch>> ng;  ///< geometric normal, not normalized
  simd::Float<Arch> u = simd::Float<Arch>(0.f), v = simd::Float<Arch>(0.f);
};

/// The nearer root of |org + t dir − center| = radius inside (tnear, tfar); the far one
/// when the ray starts inside the sphere or the near one is before tnear. The bounds are
/// tested on the refined roots, the distances reported: a ray restarted at a reported
/// hit (past a clipped one) finds the far side, not the same hit again.
template <class Arch>
PrimitiveHit<Arch> intersect_sphere(const Ray<simd::Float<Arch>>& ray, const Vec3<simd::Float<Arch>>& center,
                                    const simd::Float<Arch>& radius) {
  using F = simd::Float<Arch>;
  const Vec3<F> f = ray.org - center;
  const F a = dot(ray.dir, ray.dir);
  const F b = -dot(f, ray.dir);  // half of the textbook b, negated
  const F c = dot(f, f) - radius * radius;
  // b² − ac = a (r² − |f + (b/a) dir|²): the perpendicular from the centre to the ray.
  const F miss_distance = length(f + ray.dir * (b / a));
  const F discriminant = a * (radius - miss_distance) * (radius + miss_distance);
  const F root = simd::sqrt(simd::max(discriminant, F(0.f)));
  const F q = b + simd::select(b >= F(0.f), root, -root);
  const F t0 = c / q, t1 = q / a;
  const auto valid = discriminant >= F(0.f);
  // One refinement step from an estimated root: the quadratic for the offset s along the
  // ray has coefficients of the size of the radius, not of the distance, so its small
  // root is accurate to the float precision of the hit point. This makes t correct to
  // about an ulp however far the ray started (tests/stability).
  const auto refine = [&](const F& t) {
    const Vec3<F> g = f + ray.dir * t;  // from f, not org: no rounding at org's magnitude
    const F bg = -dot(g, ray.dir);
    const F cg = (dot(g, g) - radius * radius);
    const F rg = simd::sqrt(simd::max(bg * bg - a * cg, F(0.f)));
    const F qg = bg + simd::select(bg >= F(0.f), rg, -rg);
    const F s = cg / qg;
    return simd::select(simd::abs(s) < radius, t + s, t);  // no step where q vanishes (grazing)
  };
  const auto inside = [&](const F& t) { return valid & (t > ray.tnear) & (t < ray.tfar); };
  PrimitiveHit<Arch> hit;
  hit.t = refine(simd::min(t0, t1));
  hit.hit = inside(hit.t);
  // Only where the near side lies before tnear can the far one count.
  if (const auto try_far = valid & (hit.t <= ray.tnear); simd::any(try_far)) {
    const F t_far = refine(simd::max(t0, t1));
    const auto far_ok = try_far & inside(t_far);
    hit.t = simd::select(far_ok, t_far, hit.t);
    hit.hit = hit.hit | far_ok;
  }
  hit.ng = ray.org + ray.dir * hit.t - center;
  return hit;
}

/// A disc of `radius` around `center`, perpendicular to `normal` (OSPRay's oriented disc)
/// or, when `facing_ray`, to each ray (OSPRay's disc: a sprite that always faces the viewer).
template <class Arch>
PrimitiveHit<Arch> intersect_disc(const Ray<simd::Float<Arch>>& ray, const Vec3<simd::Float<Arch>>& center,
                                  const simd::Float<Arch>& radius, const Vec3<simd::Float<Arch>>& normal) {
  using F = simd::Float<Arch>;
  const F denominator = dot(ray.dir, normal);
  const F t = dot(center - ray.org, normal) / denominator;
  const Vec3<F> offset = ray.org + ray.dir * t - center;
  PrimitiveHit<Arch> hit;
  hit.hit = (denominator != F(0.f)) & (t > ray.tnear) & (t < ray.tfar) & (dot(offset, offset) <= radius * radius);
  hit.t = t;
  hit.ng = normal;
  return hit;
}

/// The textbook quadratic, kept only so that the stability tests can show where it fails.
inline PrimitiveHit<simd::scalar> intersect_sphere_textbook(const Ray<float>& ray, const Vec3f& center, float radius) {
  const Vec3f f = ray.org - center;
  const float a = dot(ray.dir, ray.dir), b = 2.f * dot(f, ray.dir), c = dot(f, f) - radius * radius;
  const float discriminant = b * b - 4.f * a * c;
  PrimitiveHit<simd::scalar> hit{false, std::numeric_limits<float>::infinity(), {}};
  if (discriminant < 0.f) return hit;
  const float t = (-b - std::sqrt(discriminant)) / (2.f * a);
  hit.hit = t > ray.tnear && t < ray.tfar;
  hit.t = t;
  hit.ng = ray.org + ray.dir * t - center;
  return hit;
}

}  // namespace sciray
