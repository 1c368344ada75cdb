#pragma once
// What a round curve encloses: the inside of each segment's tube, as Embree draws the
// segment (its RTC_GEOMETRY_TYPE_*_CURVE manual page), for clipping geometry.
//   round linear   the cone touching the spheres at both ends, plus those spheres: the
//                  convex hull of the two spheres, which is also the union of the spheres
//                  of linearly interpolated centre and radius;
//   disjoint       the cone frustum between the two end discs, capped flat;
//   round cubic    (Bézier, B-spline, Catmull-Rom, Hermite) the sweep of a circle of radius
//                  r(t) centred on c(t) in the plane normal to c'(t), t in [0, 1].
// Flat curves and ribbons enclose nothing. Neighbouring segments overlap at their joints;
// a point is inside a curve where it is inside any of its segments.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "sciray/error.hpp"
#include "sciray/geometry/curves.hpp"
#include "sciray/math/box.hpp"

namespace sciray {

class CurveSegmentSolid {
public:
  /// Segment `s` of `curves`, which Curves::validate accepts, of type round or disjoint.
  static CurveSegmentSolid of(const CurveData& curves, std::size_t s) {
    const std::uint32_t first = curves.indices[s];
    const auto vertex = [&](const PaddedVector<float>& values, std::uint32_t i) {
      const float* v = &values[4 * std::size_t{i}];
      return Control{{v[0], v[1], v[2]}, v[3]};
    };
    CurveSegmentSolid solid;
    if (curves.basis == CurveBasis::linear) {
      solid.shape_ = curves.type == CurveType::disjoint ? Shape::capped_cone : Shape::sphere_hull;
      for (std::uint32_t k = 0; k < 2; ++k) {
        const Control c = vertex(curves.position_radius, first + k);
        solid.position_[k] = c.position, solid.radius_[k] = c.radius;
        solid.bounds_.extend(c.position - splat(c.radius));
        solid.bounds_.extend(c.position + splat(c.radius));
      }
      return solid;
    }
    solid.shape_ = Shape::swept_disc;
    // The segment's control points, then its Bézier control points (whose convex hull
    // holds the curve, and whose radii bound the radius), then its power basis.
    std::array<Control, 4> input;
    if (curves.basis == CurveBasis::hermite)
      input = {vertex(curves.position_radius, first), vertex(curves.position_radius, first + 1),
               vertex(curves.tangents, first), vertex(curves.tangents, first + 1)};
    else
      for (std::uint32_t k = 0; k < 4; ++k) input[k] = vertex(curves.position_radius, first + k);
    const auto& to_bezier = bezier_matrix(curves.basis);
    std::array<Control, 4> b;
    float max_radius = 0.f;
    for (int row = 0; row < 4; ++row) {
      for (int k = 0; k < 4; ++k) b[row] = b[row] + input[k] * to_bezier[row][k];
      solid.bounds_.extend(b[row].position);
      max_radius = std::max(max_radius, b[row].radius);
    }
    solid.bounds_.lower = solid.bounds_.lower - splat(max_radius);
    solid.bounds_.upper = solid.bounds_.upper + splat(max_radius);
    const std::array<Control, 4> power{b[0], (b[1] - b[0]) * 3.f, (b[0] - b[1] * 2.f + b[2]) * 3.f,
                                       b[3] - b[0] + (b[1] - b[2]) * 3.f};
    for (int k = 0; k < 4; ++k) solid.position_[k] = power[k].position, solid.radius_[k] = power[k].radius;
    return solid;
  }

  /// Encloses the segment's solid.
  const Box3f& bounds() const { return bounds_; }

  /// Whether `p` lies strictly inside the segment's solid.
  bool contains(const Vec3f& p) const {
    if (p.x < bounds_.lower.x || p.y < bounds_.lower.y || p.z < bounds_.lower.z || p.x > bounds_.upper.x ||
        p.y > bounds_.upper.y || p.z > bounds_.upper.z)
      return false;
    switch (shape_) {
      case Shape::sphere_hull: return in_sphere_hull(p);
      case Shape::capped_cone: return in_capped_cone(p);
      case Shape::swept_disc: return in_swept_disc(p);
    }
    return false;
  }

private:
  enum class Shape : std::uint8_t { sphere_hull, capped_cone, swept_disc };

  /// A control point: position and radius, combined linearly together.
  struct Control {
    Vec3f position{};
    float radius = 0.f;
    Control operator+(const Control& o) const { return {position + o.position, radius + o.radius}; }
    Control operator-(const Control& o) const { return {position - o.position, radius - o.radius}; }
    Control operator*(float s) const { return {position * s, radius * s}; }
  };

  /// Row i: the weights of the segment's control points (Hermite: p0, p1, t0, t1) in its
  /// i-th Bézier control point. The same curve, written in the Bézier basis.
  static const std::array<std::array<float, 4>, 4>& bezier_matrix(CurveBasis basis) {
    static constexpr std::array<std::array<float, 4>, 4> bezier{
        {{1.f, 0.f, 0.f, 0.f}, {0.f, 1.f, 0.f, 0.f}, {0.f, 0.f, 1.f, 0.f}, {0.f, 0.f, 0.f, 1.f}}};
    static constexpr std::array<std::array<float, 4>, 4> bspline{{{1.f / 6, 4.f / 6, 1.f / 6, 0.f},
                                                                  {0.f, 4.f / 6, 2.f / 6, 0.f},
                                                                  {0.f, 2.f / 6, 4.f / 6, 0.f},
                                                                  {0.f, 1.f / 6, 4.f / 6, 1.f / 6}}};
    // Catmull-Rom: the curve runs from p1 to p2 with tangents (p2 - p0) / 2, (p3 - p1) / 2.
    static constexpr std::array<std::array<float, 4>, 4> catmull_rom{
        {{0.f, 1.f, 0.f, 0.f}, {-1.f / 6, 1.f, 1.f / 6, 0.f}, {0.f, 1.f / 6, 1.f, -1.f / 6}, {0.f, 0.f, 1.f, 0.f}}};
    static constexpr std::array<std::array<float, 4>, 4> hermite{
        {{1.f, 0.f, 0.f, 0.f}, {1.f, 0.f, 1.f / 3, 0.f}, {0.f, 1.f, 0.f, -1.f / 3}, {0.f, 1.f, 0.f, 0.f}}};
    switch (basis) {
      case CurveBasis::bspline: return bspline;
      case CurveBasis::catmull_rom: return catmull_rom;
      case CurveBasis::hermite: return hermite;
      default: return bezier;
    }
  }

  /// Inside some sphere of centre p0 + s·axis and radius r0 + k·s, s in [0, span]. The
  /// distance to that sphere's surface, |p - c(s)| - r(s), is convex in s: its minimum is
  /// where d/ds = 0, s = a + k·h / sqrt(1 - k²) (a along the axis, h off it), clamped.
  bool in_sphere_hull(const Vec3f& p) const {
    const Vec3f d = position_[1] - position_[0];
    const float span = std::sqrt(dot(d, d));
    const float dr = radius_[1] - radius_[0];
    if (span <= std::abs(dr)) {  // one sphere holds the other
      const int big = dr > 0.f ? 1 : 0;
      const Vec3f f = p - position_[big];
      return dot(f, f) < radius_[big] * radius_[big];
    }
    const Vec3f axis = d / span;
    const float k = dr / span;
    const Vec3f f = p - position_[0];
    const float a = dot(f, axis);
    const float h = std::sqrt(std::max(dot(f, f) - a * a, 0.f));
    const float s = std::clamp(a + k * h / std::sqrt(1.f - k * k), 0.f, span);
    const Vec3f off = f - axis * s;
    const float r = radius_[0] + k * s;
    return r > 0.f && dot(off, off) < r * r;
  }

  /// Between the end discs and within the cone's radius there.
  bool in_capped_cone(const Vec3f& p) const {
    const Vec3f d = position_[1] - position_[0];
    const float length2 = dot(d, d);
    if (!(length2 > 0.f)) return false;
    const Vec3f f = p - position_[0];
    const float t = dot(f, d) / length2;
    if (t < 0.f || t > 1.f) return false;
    const Vec3f off = f - d * t;
    const float r = radius_[0] + (radius_[1] - radius_[0]) * t;
    return r > 0.f && dot(off, off) < r * r;
  }

  /// In the disc at some t: where g(t) = (p - c(t))·c'(t) vanishes, within r(t) of c(t).
  /// Within the tube, where the radius is below the curve's radius of curvature (Embree's
  /// condition for drawing the sweep), g' = -|c'|² + (p - c)·c'' < 0, so every root that
  /// matters is simple and shows as a sign change; 16 samples find the roots unless three
  /// crowd into one sixteenth of the segment, and bisection refines each.
  bool in_swept_disc(const Vec3f& p) const {
    constexpr int samples = 16, bisections = 24;
    const auto g = [&](float t) { return dot(p - centre(t), tangent(t)); };
    const auto in_disc = [&](float t) {
      const Vec3f off = p - centre(t);
      const float r = (((radius_[3] * t + radius_[2]) * t) + radius_[1]) * t + radius_[0];
      return r > 0.f && dot(off, off) < r * r;
    };
    float t0 = 0.f, g0 = g(0.f);
    for (int i = 1; i <= samples; ++i) {
      if (g0 == 0.f && in_disc(t0)) return true;
      const float t1 = static_cast<float>(i) / samples, g1 = g(t1);
      if (g0 != 0.f && g1 != 0.f && (g0 < 0.f) != (g1 < 0.f)) {
        float lo = t0, hi = t1;
        const bool rising = g0 < 0.f;
        for (int b = 0; b < bisections; ++b) {
          const float mid = 0.5f * (lo + hi);
          ((g(mid) < 0.f) == rising ? lo : hi) = mid;
        }
        if (in_disc(0.5f * (lo + hi))) return true;
      }
      t0 = t1, g0 = g1;
    }
    return g0 == 0.f && in_disc(1.f);
  }

  Vec3f centre(float t) const { return ((position_[3] * t + position_[2]) * t + position_[1]) * t + position_[0]; }
  Vec3f tangent(float t) const { return (position_[3] * (3.f * t) + position_[2] * 2.f) * t + position_[1]; }

  Shape shape_ = Shape::sphere_hull;
  Box3f bounds_;
  // Linear shapes: the end points' centres and radii in [0] and [1]. The swept disc: the
  // power basis, c(t) = Σ position_[k]·t^k and r(t) = Σ radius_[k]·t^k.
  std::array<Vec3f, 4> position_{};
  std::array<float, 4> radius_{};
};

/// The segments of `curves` as solids; flat curves and ribbons enclose nothing (an error).
inline std::vector<CurveSegmentSolid> curve_solids(const CurveData& curves) {
  if (curves.type == CurveType::flat || curves.type == CurveType::ribbon)
    throw Error("curve: flat curves and ribbons enclose nothing; only round or disjoint curves have an inside");
  std::vector<CurveSegmentSolid> solids;
  solids.reserve(curves.indices.size());
  for (std::size_t s = 0; s < curves.indices.size(); ++s) solids.push_back(CurveSegmentSolid::of(curves, s));
  return solids;
}

}  // namespace sciray
