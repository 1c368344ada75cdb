#pragma once
// Transforms that change while the shutter is open, as OSPRay's `motion.*` parameters
// and Embree's motion blur define them: keys spaced evenly over a time range and
// interpolated linearly between neighbours: matrices element by element, quaternion
// decompositions with their rotation on the shortest arc (slerp). sciray interpolates
// exactly as Embree does, so that shading (normals, clipping, camera rays) agrees with
// what Embree traced.
#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "sciray/error.hpp"
#include "sciray/math/affine.hpp"
#include "sciray/simd/packet.hpp"

namespace sciray {

/// A rotation as the quaternion r + i·I + j·J + k·K (OSPRay's quatf stores it as i, j,
/// k, r).
struct Quaternion {
  float r = 1.f, i = 0.f, j = 0.f, k = 0.f;
};

inline float dot(const Quaternion& a, const Quaternion& b) { return a.r * b.r + a.i * b.i + a.j * b.j + a.k * b.k; }

/// The unit quaternion between unit quaternions `a` and `b` at `t`, along the shorter arc
/// (q and -q are one rotation).
inline Quaternion slerp(const Quaternion& a, Quaternion b, float t) {
  float cos_theta = dot(a, b);
  if (cos_theta < 0.f) b = {-b.r, -b.i, -b.j, -b.k}, cos_theta = -cos_theta;
  float wa = 1.f - t, wb = t;
  // Nearly parallel: the arc is a line (and sin θ would divide by ~0).
  if (cos_theta < 0.9995f) {
    const float theta = std::acos(cos_theta), sin_theta = std::sin(theta);
    wa = std::sin((1.f - t) * theta) / sin_theta, wb = std::sin(t * theta) / sin_theta;
  }
  Quaternion q{wa * a.r + wb * b.r, wa * a.i + wb * b.i, wa * a.j + wb * b.j, wa * a.k + wb * b.k};
  const float norm = std::sqrt(dot(q, q));
  return {q.r / norm, q.i / norm, q.j / norm, q.k / norm};
}

/// Embree's RTCQuaternionDecomposition: the transform translation · rotation · S, where S
/// scales, skews (upper triangle: xy, xz, yz) and then shifts (OSPRay's `motion.pivot`
/// sets the shift, so that rotations turn about the pivot's opposite).
struct QuaternionDecomposition {
  Vec3f scale{1.f, 1.f, 1.f};
  Vec3f skew{0.f, 0.f, 0.f};
  Vec3f shift{0.f, 0.f, 0.f};
  Quaternion rotation;  ///< unit length
  Vec3f translation{0.f, 0.f, 0.f};

  Affine3f matrix() const {
    const Quaternion& q = rotation;
    const Vec3f rx{1.f - 2.f * (q.j * q.j + q.k * q.k), 2.f * (q.i * q.j + q.r * q.k), 2.f * (q.i * q.k - q.r * q.j)};
    const Vec3f ry{2.f * (q.i * q.j - q.r * q.k), 1.f - 2.f * (q.i * q.i + q.k * q.k), 2.f * (q.j * q.k + q.r * q.i)};
    const Vec3f rz{2.f * (q.i * q.k + q.r * q.j), 2.f * (q.j * q.k - q.r * q.i), 1.f - 2.f * (q.i * q.i + q.j * q.j)};
    const Affine3f s{{scale.x, 0.f, 0.f}, {skew.x, scale.y, 0.f}, {skew.y, skew.z, scale.z}, shift};
    return Affine3f{rx, ry, rz, translation} * s;
  }
};

inline Affine3f lerp(const Affine3f& a, const Affine3f& b, float t) {
  const auto mix = [t](const Vec3f& x, const Vec3f& y) { return x * (1.f - t) + y * t; };
  return {mix(a.vx, b.vx), mix(a.vy, b.vy), mix(a.vz, b.vz), mix(a.p, b.p)};
}

inline QuaternionDecomposition lerp(const QuaternionDecomposition& a, const QuaternionDecomposition& b, float t) {
  const auto mix = [t](const Vec3f& x, const Vec3f& y) { return x * (1.f - t) + y * t; };
  return {mix(a.scale, b.scale), mix(a.skew, b.skew), mix(a.shift, b.shift), slerp(a.rotation, b.rotation, t),
          mix(a.translation, b.translation)};
}

/// A placement over time: one transform (static), or keys as matrices or as quaternion
/// decompositions spaced evenly over [start, end]. Embree shows an object placed by a
/// moving transform only from start until (not at) end; a camera holds its first or last
/// key outside the range.
class MotionTransform {
public:
  MotionTransform() = default;
  explicit MotionTransform(const Affine3f& transform) : matrices_{transform} {}
  MotionTransform(std::vector<Affine3f> keys, float start, float end) : matrices_(std::move(keys)) {
    set_range(start, end);
    if (matrices_.empty()) throw Error("motion transform: no keys");
  }
  MotionTransform(std::vector<QuaternionDecomposition> keys, float start, float end)
      : matrices_(), decompositions_(std::move(keys)) {
    set_range(start, end);
    if (decompositions_.empty()) throw Error("motion transform: no keys");
  }

  std::size_t key_count() const { return quaternion() ? decompositions_.size() : matrices_.size(); }
  bool moving() const { return key_count() > 1; }
  bool quaternion() const { return !decompositions_.empty(); }
  float start() const { return start_; }
  float end() const { return end_; }
  const std::vector<Affine3f>& matrices() const { return matrices_; }
  const std::vector<QuaternionDecomposition>& decompositions() const { return decompositions_; }

  /// Key `i` as a matrix.
  Affine3f key(std::size_t i) const { return quaternion() ? decompositions_.at(i).matrix() : matrices_.at(i); }

  /// The transform at `time` (clamped to the key range).
  Affine3f at(float time) const {
    const std::size_t n = key_count();
    if (n == 1) return key(0);
    const float range = end_ - start_;
    const float local = range > 0.f ? std::clamp((time - start_) / range, 0.f, 1.f) * static_cast<float>(n - 1)
                                     : (time < start_ ? 0.f : static_cast<float>(n - 1));
    const std::size_t segment = std::min(static_cast<std::size_t>(local), n - 2);
    const float f = local - static_cast<float>(segment);
    if (quaternion()) return lerp(decompositions_[segment], decompositions_[segment + 1], f).matrix();
    return lerp(matrices_[segment], matrices_[segment + 1], f);
  }

  /// Normals of points placed at `time` (one per lane): the transform's cofactor, as
  /// Affine3f::normal, at each lane's own time when it moves.
  template <class T>
  Vec3<T> normal(const Vec3<T>& n, const T& time) const {
    if (!moving()) return key(0).normal(n);
    if constexpr (std::is_same_v<T, float>) {
      return at(time).normal(n);
    } else {
      constexpr int W = static_cast<int>(T::size);
      alignas(64) float out[3][W];
      for (int i = 0; i < W; ++i) {
        const Vec3f v = at(simd::lane(time, i)).normal(Vec3f{simd::lane(n.x, i), simd::lane(n.y, i), simd::lane(n.z, i)});
        out[0][i] = v.x, out[1][i] = v.y, out[2][i] = v.z;
      }
      return {T::load_aligned(out[0]), T::load_aligned(out[1]), T::load_aligned(out[2])};
    }
  }

  /// A box around `box` placed at any time in the range: the keys' placements, and for
  /// rotations (which leave the keys' hull) intermediate times too.
  Box3f transform(const Box3f& box) const {
    Box3f out;
    const std::size_t n = key_count();
    const int steps = quaternion() && n > 1 ? 16 : 1;
    for (std::size_t i = 0; i < n; ++i) {
      out.extend(key(i).transform(box));
      if (i + 1 < n)
        for (int s = 1; s < steps; ++s) {
          const float f = static_cast<float>(s) / static_cast<float>(steps);
          out.extend(lerp(decompositions_[i], decompositions_[i + 1], f).matrix().transform(box));
        }
    }
    return out;
  }

private:
  void set_range(float start, float end) {
    if (!(start <= end) || !std::isfinite(start) || !std::isfinite(end))
      throw Error("motion transform: the time range must be finite with start <= end");
    start_ = start, end_ = end;
  }

  std::vector<Affine3f> matrices_{Affine3f{}};
  std::vector<QuaternionDecomposition> decompositions_;
  float start_ = 0.f, end_ = 1.f;
};

}  // namespace sciray
