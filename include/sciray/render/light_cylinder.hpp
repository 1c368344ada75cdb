#pragma once
// How a cylinder light is sampled, as OSPRay samples it: directions in the solid angle of
// a rectangle that bounds the side as seen from the shaded point, drawn with the
// area-preserving map of spherical rectangles (Ureña, Fajardo and King 2013, "An
// Area-Preserving Parametrization for Spherical Rectangles") from a unit square warped
// towards the receiver's cosine at the rectangle's corners (Hart et al. 2020, "Practical
// Product Sampling by Fitting and Composing Warps", the bilinear warp); a direction that
// enters the cylinder through a cap, or misses it, is rejected. Unbiased, and low in
// noise even close to the light, where sampling the side by area is not.
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <utility>

#include "sciray/math/vec.hpp"

namespace sciray::detail {

/// The rectangle bounding a cylinder's side seen from a point outside it, in the frame of
/// that point: it lies in the plane through the side's silhouette lines, `depth` away
/// along `toward` (perpendicular to the axis), spanning [-half_width, half_width] along
/// `across` and [lower, upper] along `axis`.
struct CylinderBounds {
  Vec3f axis, toward, across;  ///< unit and orthogonal
  float depth, half_width, lower, upper;
  float solid_angle;

  /// The direction towards the rectangle's point (x across, y along the axis).
  Vec3f direction(float x, float y) const { return normalize(across * x + axis * y + toward * depth); }

  /// The direction that the unit square's (u1, u2) maps to, uniformly in solid angle
  /// (Ureña et al. 2013, section 3, for the rectangle at z = -depth, x in
  /// [-half_width, half_width], y in [lower, upper]).
  Vec3f sample(float u1, float u2) const {
    constexpr float two_pi = 2.f * std::numbers::pi_v<float>;
    const float x0 = -half_width, x1 = half_width, z0 = -depth;
    const Vec3f v00{x0, lower, z0}, v01{x0, upper, z0}, v10{x1, lower, z0}, v11{x1, upper, z0};
    // The normals of the spherical rectangle's edges (great-circle planes), and its
    // internal angles between neighbouring edges.
    const Vec3f n0 = normalize(cross(v00, v10)), n1 = normalize(cross(v10, v11));
    const Vec3f n2 = normalize(cross(v11, v01)), n3 = normalize(cross(v01, v00));
    const auto angle = [](const Vec3f& a, const Vec3f& b) { return std::acos(std::clamp(-dot(a, b), -1.f, 1.f)); };
    const float k = two_pi - angle(n2, n3) - angle(n3, n0);
    const float area = angle(n0, n1) + angle(n1, n2) - k;
    // u1 picks the x whose sub-rectangle [x0, x] holds the fraction u1 of the solid angle.
    const float au = u1 * area + k;
    const float fu = (std::cos(au) * n0.z - n2.z) / std::sin(au);
    const float cu = std::clamp(std::copysign(1.f / std::sqrt(fu * fu + n0.z * n0.z), fu), -1.f, 1.f);
    const float xu = std::clamp(-cu * z0 / std::sqrt(std::max(1.f - cu * cu, 1e-12f)), x0, x1);
    // u2 is uniform in the sine of the elevation along the column at xu.
    const float dist = std::sqrt(xu * xu + z0 * z0);
    const float h0 = lower / std::sqrt(dist * dist + lower * lower);
    const float h1 = upper / std::sqrt(dist * dist + upper * upper);
    const float hv = h0 + u2 * (h1 - h0);
    const float yv = hv * hv < 1.f - 1e-6f ? hv * dist / std::sqrt(1.f - hv * hv) : upper;
    return direction(xu, yv);
  }

  /// The inverse of `sample`: where in the unit square the direction w towards the
  /// rectangle lies. u is the solid angle of the rectangle's part left of w's column over
  /// the whole; v the sine of w's elevation along that column, scaled to [0, 1].
  std::pair<float, float> square_of(const Vec3f& w) const {
    const float along = dot(w, toward);
    const float x = depth * dot(w, across) / along, y = depth * dot(w, axis) / along;
    const auto corner = [&](float cx, float cy) {
      return std::atan(cx * cy / (depth * std::sqrt(depth * depth + cx * cx + cy * cy)));
    };
    const float left = corner(x, upper) - corner(x, lower) + corner(half_width, upper) - corner(half_width, lower);
    const float dist = std::sqrt(x * x + depth * depth);
    const auto sine = [&](float cy) { return cy / std::sqrt(dist * dist + cy * cy); };
    const float u = left / solid_angle, v = (sine(y) - sine(lower)) / (sine(upper) - sine(lower));
    return {std::clamp(u, 0.f, 1.f), std::clamp(v, 0.f, 1.f)};
  }
};

/// Hart et al. 2020's bilinear warp of the unit square: points drawn in proportion to the
/// bilinear interpolation of four corner weights, w00 at (0, 0), w10 at (1, 0), w01 at
/// (0, 1), w11 at (1, 1); uniform where all are zero.
struct BilinearWarp {
  float w00, w10, w01, w11;

  float pdf(float u, float v) const {
    const float total = w00 + w10 + w01 + w11;
    if (!(total > 0.f)) return 1.f;
    return 4.f * ((1.f - u) * (1.f - v) * w00 + u * (1.f - v) * w10 + (1.f - u) * v * w01 + u * v * w11) / total;
  }

  std::pair<float, float> sample(float u1, float u2) const {
    if (!(w00 + w10 + w01 + w11 > 0.f)) return {u1, u2};
    const float u = sample_linear(w00 + w01, w10 + w11, u1);
    return {u, sample_linear((1.f - u) * w00 + u * w10, (1.f - u) * w01 + u * w11, u2)};
  }

  /// Inverts the CDF of the density a0 (1 - x) + a1 x on [0, 1] at r, in the form that
  /// keeps its precision where a0 and a1 are close (no division by a1 - a0).
  static float sample_linear(float a0, float a1, float r) {
    const float denominator = a0 + std::sqrt(std::max(0.f, a0 * a0 + r * (a1 * a1 - a0 * a0)));
    return denominator > 0.f ? std::min(1.f, r * (a0 + a1) / denominator) : r;
  }
};

/// The warp towards the cosine to the normal n at the rectangle's corners (OSPRay's
/// choice); a zero n (a point in a medium) gives no warp.
inline BilinearWarp cosine_warp(const CylinderBounds& b, const Vec3f& n) {
  const auto cosine = [&](float x, float y) { return std::max(0.f, dot(b.direction(x, y), n)); };
  return {cosine(-b.half_width, b.lower), cosine(b.half_width, b.lower), cosine(-b.half_width, b.upper),
          cosine(b.half_width, b.upper)};
}

/// The solid angle of the rectangle [-c, c] x [0, y] at distance b (y may be negative):
/// twice the corner formula atan(x y / (b sqrt(b^2 + x^2 + y^2))).
inline float rectangle_solid_angle(float c, float b, float y) {
  return 2.f * std::atan(c * y / (b * std::sqrt(b * b + c * c + y * y)));
}

/// The bounds of the side of the cylinder from p0 to p1 seen from p; nullopt for a point
/// on or inside the tube (its side faces away).
inline std::optional<CylinderBounds> cylinder_bounds(const Vec3f& p0, const Vec3f& p1, float radius, const Vec3f& p) {
  const Vec3f d = p1 - p0;
  const float height = length(d);
  const Vec3f axis = d / height;
  const float lower = dot(p0 - p, axis);  // the cylinder spans [lower, lower + height] along the axis from p
  const Vec3f to_axis = (p0 - p) - axis * lower;
  const float dist = length(to_axis);
  if (!(dist > radius)) return std::nullopt;
  // The silhouette lines touch the tube where it is seen at a right angle: depth
  // dist (1 - s^2), half a width radius sqrt(1 - s^2) apart.
  const float s = radius / dist, cos2 = (1.f - s) * (1.f + s);
  CylinderBounds b;
  b.axis = axis;
  b.toward = to_axis / dist;
  b.across = cross(axis, b.toward);
  b.depth = dist * cos2;
  b.half_width = radius * std::sqrt(cos2);
  // The visible side lies between depths dist - radius and b.depth; projected onto the
  // rectangle's plane its axial extent grows by at most depth / (dist - radius) = 1 + s.
  const float upper = lower + height;
  b.lower = lower < 0.f ? lower * (1.f + s) : lower;
  b.upper = upper > 0.f ? upper * (1.f + s) : upper;
  b.solid_angle = rectangle_solid_angle(b.half_width, b.depth, b.upper) -
                  rectangle_solid_angle(b.half_width, b.depth, b.lower);
  return b;
}

/// The distance along the unit ray (org, w) to where it enters the cylinder from p0 to p1
/// through its side; inf where it enters through a cap, misses, or starts inside.
inline float cylinder_side_entry(const Vec3f& p0, const Vec3f& p1, float radius, const Vec3f& org, const Vec3f& w) {
  constexpr float inf = std::numeric_limits<float>::infinity();
  const Vec3f d = p1 - p0;
  const float height = length(d);
  const Vec3f axis = d / height;
  // The ray and its origin projected onto the plane perpendicular to the axis: the near
  // root of |op + wp t| = radius.
  const Vec3f o = org - p0;
  const Vec3f op = o - axis * dot(o, axis), wp = w - axis * dot(w, axis);
  const float a = dot(wp, wp), b = dot(op, wp), c = dot(op, op) - radius * radius;
  if (!(a > 0.f) || !(c > 0.f) || b >= 0.f) return inf;  // parallel to the axis, inside, or moving away
  // b^2 - a c from the ray's closest approach to the axis: no cancellation at grazing
  // incidence (the stable form of Ray Tracing Gems ch. 7).
  const Vec3f closest = op - wp * (b / a);
  const float disc = a * (radius * radius - dot(closest, closest));
  if (disc < 0.f) return inf;
  const float t = c / (-b + std::sqrt(disc));  // = (-b - sqrt(disc)) / a, stable for b < 0
  const float z = dot(o + w * t, axis);
  return z >= 0.f && z <= height ? t : inf;
}

}  // namespace sciray::detail
