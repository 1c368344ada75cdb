#pragma once
// Affine transforms as OSPRay and Embree store them: the linear part's columns vx, vy,
// vz, then the translation p (12 floats, column major).
#include <cmath>

#include "sciray/math/box.hpp"
#include "sciray/math/vec.hpp"

namespace sciray {

struct Affine3f {
  Vec3f vx{1, 0, 0}, vy{0, 1, 0}, vz{0, 0, 1}, p{0, 0, 0};

  static Affine3f translate(const Vec3f& t) { return {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, t}; }
  static Affine3f scale(float s) { return {{s, 0, 0}, {0, s, 0}, {0, 0, s}, {0, 0, 0}}; }

  bool identity() const {
    return vx == Vec3f{1, 0, 0} && vy == Vec3f{0, 1, 0} && vz == Vec3f{0, 0, 1} && p == Vec3f{0, 0, 0};
  }
  float determinant() const { return dot(cross(vx, vy), vz); }
  Vec3f point(const Vec3f& x) const { return vx * x.x + vy * x.y + vz * x.z + p; }
  Vec3f vector(const Vec3f& x) const { return vx * x.x + vy * x.y + vz * x.z; }

  /// Transforms normals by the cofactor matrix (the inverse transpose times the
  /// determinant): right for any invertible transform, and for packets as for floats.
  template <class T>
  Vec3<T> normal(const Vec3<T>& n) const {
    return Vec3<T>(cross(vy, vz)) * n.x + Vec3<T>(cross(vz, vx)) * n.y + Vec3<T>(cross(vx, vy)) * n.z;
  }

  /// The inverse transform; the determinant must not be 0.
  Affine3f inverse() const {
    const float inv_det = 1.f / determinant();
    // The inverse's rows are the cofactor columns over the determinant.
    const Vec3f r0 = cross(vy, vz) * inv_det, r1 = cross(vz, vx) * inv_det, r2 = cross(vx, vy) * inv_det;
    Affine3f out{{r0.x, r1.x, r2.x}, {r0.y, r1.y, r2.y}, {r0.z, r1.z, r2.z}, {0.f, 0.f, 0.f}};
    out.p = -out.vector(p);
    return out;
  }

  Box3f transform(const Box3f& box) const {
    Box3f out;
    if (box.empty()) return out;
    for (int k = 0; k < 8; ++k)
      out.extend(point({k & 1 ? box.upper.x : box.lower.x, k & 2 ? box.upper.y : box.lower.y,
                        k & 4 ? box.upper.z : box.lower.z}));
    return out;
  }
};

inline Affine3f operator*(const Affine3f& a, const Affine3f& b) {
  return {a.vector(b.vx), a.vector(b.vy), a.vector(b.vz), a.point(b.p)};
}

}  // namespace sciray
