#pragma once
// What an Isosurface (geometry/isosurface.hpp) intersects, whatever the volume type: a set
// of primitives (boxes that Embree sees, each holding part of the surfaces) and the first
// crossing of one ray inside one of them. Each volume type has its own: the exact cell
// solvers of grids (isosurface_grid.hpp) and of unstructured cells
// (isosurface_unstructured.hpp).
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <utility>

#include "sciray/geometry/sphere_intersect.hpp"
#include "sciray/math/box.hpp"
#include "sciray/math/ray.hpp"

namespace sciray {

class IsosurfaceField {
public:
  virtual ~IsosurfaceField() = default;
  virtual std::size_t primitive_count() const = 0;
  virtual Box3f primitive_bounds(std::uint32_t prim) const = 0;
  /// The first crossing of any isovalue inside primitive `prim` within [tnear, tfar]: its
  /// t, its (unnormalised) normal, and in u the index of the isovalue.
  virtual PrimitiveHit<simd::scalar> first_crossing(const Ray<float>& ray, std::uint32_t prim) const = 0;
  virtual std::size_t owned_bytes() const = 0;
};

/// The first t in [ta, tb] where f(t) (a cell's interpolant along a ray, minus the
/// isovalue) crosses 0, or infinity. f is taken for a cubic through four samples to find
/// its extrema, which cut [ta, tb] into pieces where it is monotone; the first piece whose
/// ends straddle 0 is bisected on f itself to float resolution. Exact for interpolants
/// that are cubic along rays (trilinear cells of grids and of parallelepipeds).
template <class F>
float first_crossing_of_cubic(F&& f, float ta, float tb) {
  // The cubic's coefficients from four samples (exact for a cubic), for its extrema.
  const double h = static_cast<double>(tb) - ta;
  const double f0 = f(ta), f1 = f(ta + h / 3), f2 = f(ta + 2 * h / 3), f3 = f(tb);
  // In s = (t − ta)/h: f = a s³ + b s² + c s + f0 through s = 0, ⅓, ⅔, 1.
  const double a = (-f0 + 3 * f1 - 3 * f2 + f3) * 4.5, b = (2 * f0 - 5 * f1 + 4 * f2 - f3) * 4.5,
               cc = (-11 * f0 + 18 * f1 - 9 * f2 + 2 * f3) * 0.5;
  // Split [0, 1] at the derivative's roots 3a s² + 2b s + c = 0.
  double cuts[4] = {0, 1, 1, 1};
  int n = 1;
  const double qa = 3 * a, qb = 2 * b, disc = qb * qb - 4 * qa * cc;
  if (std::fabs(qa) > 1e-12 && disc > 0) {
    const double r = std::sqrt(disc), q = -0.5 * (qb + std::copysign(r, qb));
    double s1 = q / qa, s2 = q != 0 ? cc / q : 1;
    if (s1 > s2) std::swap(s1, s2);
    if (s1 > 0 && s1 < 1) cuts[n++] = s1;
    if (s2 > 0 && s2 < 1) cuts[n++] = s2;
  } else if (std::fabs(qa) <= 1e-12 && std::fabs(qb) > 1e-12) {
    const double s = -cc / qb;
    if (s > 0 && s < 1) cuts[n++] = s;
  }
  cuts[n++] = 1;
  for (int i = 0; i + 1 < n; ++i) {
    double lo = ta + cuts[i] * h, hi = ta + cuts[i + 1] * h;
    double flo = f(lo), fhi = f(hi);
    if (flo == 0) return static_cast<float>(lo);
    if ((flo < 0) == (fhi < 0) && fhi != 0) continue;
    for (int it = 0; it < 40 && hi - lo > 0; ++it) {  // bisection: monotone here
      const double mid = 0.5 * (lo + hi);
      const double fm = f(mid);
      if ((fm < 0) == (flo < 0) && fm != 0)
        lo = mid, flo = fm;
      else
        hi = mid;
    }
    return static_cast<float>(hi);
  }
  return std::numeric_limits<float>::infinity();
}

}  // namespace sciray
