#pragma once
// Where a volumetric model sits in the world: directly (its object space is the world's)
// or by an instance's transform, which may move over the shutter (math/motion.hpp).
//
// A placed volume is marched in its object space, as OSPRay does: each world ray is
// carried there by the inverse transform with its direction left unnormalized, so that a
// point at parameter t is the same point in both spaces. Distances along the ray, and
// with them the transfer function's opacity (per unit of t: per world unit for the
// camera's unit-length rays), mean what they mean for a direct volume; sampling steps
// are a fraction of a cell of the volume as placed. Positions and normals go back to the
// world for clipping and lighting.
#include <cmath>
#include <string>

#include "sciray/error.hpp"
#include "sciray/math/affine.hpp"
#include "sciray/math/box.hpp"
#include "sciray/math/motion.hpp"
#include "sciray/math/ray.hpp"

namespace sciray {

/// One packet of world rays as a placed volume sees them.
template <class Arch>
struct VolumeRay {
  using F = simd::Float<Arch>;
  VolumeRay() = default;
  /// Rays of a volume placed directly in the world.
  VolumeRay(const Ray<F>& world_ray, const simd::Mask<Arch>& lanes) : ray(world_ray), active(lanes) {}

  Ray<F> ray;                     ///< in object space; same t as `world`
  simd::Mask<Arch> active{};      ///< lanes at a time when the volume is there
  const Ray<F>* world = nullptr;  ///< null where object space is world space
  Vec3<F> to_object[3]{};         ///< world-to-object linear part's columns (where `world`)

  /// The world position of the ray at parameter t.
  Vec3<F> world_point(const F& t) const {
    const Ray<F>& r = world ? *world : ray;
    return r.org + r.dir * t;
  }
  /// An object-space normal (e.g. a gradient) as a world normal, not normalized: by the
  /// inverse transpose, for any invertible transform.
  Vec3<F> world_normal(const Vec3<F>& n) const {
    if (!world) return n;
    return {dot(to_object[0], n), dot(to_object[1], n), dot(to_object[2], n)};
  }
  /// How much t one object-space unit of length along each lane's ray takes.
  F t_per_unit() const {
    if (!world) return F(1.f);
    return F(1.f) / simd::sqrt(dot(ray.dir, ray.dir));
  }
};

class VolumePlacement {
public:
  /// Directly in the world.
  VolumePlacement() = default;
  /// By `motion` (one key: a static transform); every key must be invertible. `what`
  /// names the volume in errors.
  VolumePlacement(MotionTransform motion, const std::string& what) : motion_(std::move(motion)), direct_(false) {
    for (std::size_t k = 0; k < motion_.key_count(); ++k) {
      const float det = motion_.key(k).determinant();
      if (det == 0.f || !std::isfinite(det))
        throw Error(what + ": its transform is singular or not finite" +
                    (motion_.moving() ? " at key " + std::to_string(k) : std::string()));
    }
    direct_ = !motion_.moving() && motion_.key(0).identity();
    if (!motion_.moving()) inverse_ = motion_.key(0).inverse();
  }

  bool direct() const { return direct_; }
  const MotionTransform& motion() const { return motion_; }

  /// The world box around an object-space box, at any time of the motion.
  Box3f world_bounds(const Box3f& object_bounds) const {
    return direct_ ? object_bounds : motion_.transform(object_bounds);
  }

  /// How long a world-space stretch of one object unit is at least, roughly (the
  /// shortest transformed axis over the keys): for sizing world steps from object ones.
  float smallest_scale() const {
    if (direct_) return 1.f;
    float s = INFINITY;
    for (std::size_t k = 0; k < motion_.key_count(); ++k) {
      const Affine3f m = motion_.key(k);
      s = std::min({s, length(m.vx), length(m.vy), length(m.vz)});
    }
    return s;
  }

  /// The packet `world` of the active lanes in object space, at each lane's time.
  template <class Arch>
  VolumeRay<Arch> object_ray(const Ray<simd::Float<Arch>>& world, const simd::Mask<Arch>& active) const {
    using F = simd::Float<Arch>;
    VolumeRay<Arch> out;
    if (direct_) {
      out.ray = world, out.active = active;
      return out;
    }
    out.world = &world;
    out.ray = world;
    if (!motion_.moving()) {
      out.active = active;
      set(out, inverse_);
      return out;
    }
    // Each lane at its own time, and only within the motion's time range (as Embree
    // shows a moving instance: from start until, not at, end).
    constexpr int W = simd::width<Arch>;
    alignas(64) float m[12][W];
    alignas(64) float there[W];
    for (int i = 0; i < W; ++i) {
      const float time = simd::lane(world.time, i);
      const bool in_range = simd::lane(active, i) && time >= motion_.start() && time < motion_.end();
      there[i] = in_range ? 1.f : 0.f;
      const Affine3f inv = in_range ? motion_.at(time).inverse() : Affine3f{};
      const Vec3f cols[4] = {inv.vx, inv.vy, inv.vz, inv.p};
      for (int c = 0; c < 4; ++c) m[3 * c][i] = cols[c].x, m[3 * c + 1][i] = cols[c].y, m[3 * c + 2][i] = cols[c].z;
    }
    const auto column = [&](int c) {
      return Vec3<F>{simd::load<Arch>(m[3 * c]), simd::load<Arch>(m[3 * c + 1]), simd::load<Arch>(m[3 * c + 2])};
    };
    out.active = active & (simd::load<Arch>(there) > F(0.f));
    apply(out, column(0), column(1), column(2), column(3));
    return out;
  }

private:
  template <class Arch>
  static void set(VolumeRay<Arch>& out, const Affine3f& inv) {
    using F = simd::Float<Arch>;
    apply(out, Vec3<F>(inv.vx), Vec3<F>(inv.vy), Vec3<F>(inv.vz), Vec3<F>(inv.p));
  }
  template <class Arch, class V>
  static void apply(VolumeRay<Arch>& out, const V& vx, const V& vy, const V& vz, const V& p) {
    const V& o = out.world->org;
    const V& d = out.world->dir;
    out.ray.org = vx * o.x + vy * o.y + vz * o.z + p;
    out.ray.dir = vx * d.x + vy * d.y + vz * d.z;
    out.to_object[0] = vx, out.to_object[1] = vy, out.to_object[2] = vz;
  }

  MotionTransform motion_;
  bool direct_ = true;
  Affine3f inverse_;
};

}  // namespace sciray
