#pragma once
// Exact emission–absorption through a tetrahedral mesh (VolumeIntegration::exact): inside
// a tetrahedron the value is linear along a ray, so the ray's integral through each cell
// needs no samples. The transfer function is piecewise linear in the value, so cutting a
// cell's segment at the values of its nodes leaves pieces where extinction σ and colour
// c are both linear in the distance x. On such a piece of length ℓ the optical depth
// τ(x) = σa x + (σb − σa) x² / 2ℓ is a quadratic, and since dτ/dx = σ,
//   ∫ c σ e^−τ dx = ca (1 − e^−τ(ℓ)) + (cb − ca)/ℓ · (∫ e^−τ dx − ℓ e^−τ(ℓ)),
// leaving only ∫ e^−τ dx, a smooth positive integrand: closed form where σ is constant,
// else 8-point Gauss–Legendre on parts of optical depth at most 1/2 (an error far below
// float rounding). The segments of a ray are the cells it crosses, found through the
// volume's hierarchy and taken in depth order; between cells (a mesh with holes, or
// outside it) the background value is integrated as a constant.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "sciray/math/vec.hpp"
#include "sciray/volume/transfer_function.hpp"
#include "sciray/volume/unstructured.hpp"

namespace sciray {

/// Front-to-back accumulation of one ray's premultiplied colour and transmittance.
struct ExactAccumulator {
  Vec3f color{0.f, 0.f, 0.f};
  double transmittance = 1.;
  bool stopped = false;  ///< the transmittance reached the caller's stop
};

namespace exact_detail {

/// ∫₀^ℓ exp(−(a x + b x²)) dx for a, b with a x + b x² ≥ 0 on [0, ℓ].
inline double integral_of_transmittance(double a, double b, double length) {
  const double depth = a * length + b * length * length;
  if (std::abs(b * length * length) <= 1e-12 * std::max(1., depth)) {
    if (std::abs(a * length) < 1e-8) return length * (1. - 0.5 * a * length);
    return -std::expm1(-a * length) / a;
  }
  static constexpr std::array<double, 8> node{-0.9602898564975363, -0.7966664774136267, -0.5255324099163290,
                                              -0.1834346424956498, 0.1834346424956498,  0.5255324099163290,
                                              0.7966664774136267,  0.9602898564975363};
  static constexpr std::array<double, 8> weight{0.1012285362903763, 0.2223810344533745, 0.3137066458778873,
                                                0.3626837833783620, 0.3626837833783620, 0.3137066458778873,
                                                0.2223810344533745, 0.1012285362903763};
  const int parts = static_cast<int>(std::clamp(std::ceil(2. * depth), 1., 256.));
  const double h = length / parts;
  double sum = 0.;
  for (int p = 0; p < parts; ++p) {
    const double mid = (p + 0.5) * h;
    for (std::size_t k = 0; k < node.size(); ++k) {
      const double x = mid + 0.5 * h * node[k];
      sum += weight[k] * std::exp(-(a * x + b * x * x));
    }
  }
  return 0.5 * h * sum;
}

/// The cut values of one segment, reused per thread.
inline std::vector<double>& cut_buffer() {
  thread_local std::vector<double> cuts;
  return cuts;
}

}  // namespace exact_detail

/// Adds a segment of `length` (in ray t) along which the value goes linearly from v0 to
/// v1 to `acc`, through `tf` with extinction opacity × density per unit of t. Where the
/// transmittance reaches `stop_below` the integral ends exactly there (`acc.stopped`), as
/// the marcher's early ray termination ends it in the limit of small steps.
inline void integrate_linear_segment(const TransferFunction& tf, float density, double length, float v0, float v1,
                                     ExactAccumulator& acc, double stop_below = 0.) {
  if (acc.stopped || !(length > 0.) || !(v0 == v0) || !(v1 == v1)) return;  // NaN: outside the cells, transparent
  // The values where the transfer function has nodes, strictly between v0 and v1.
  const auto [lo, hi] = tf.value_range();
  std::vector<double>& cuts = exact_detail::cut_buffer();
  cuts.clear();
  cuts.push_back(0.);
  if (v0 != v1) {
    for (const std::size_t nodes : {tf.opacities().size(), tf.colors().size()})
      for (std::size_t i = 0; i < nodes; ++i) {
        const double at = nodes > 1 ? lo + (hi - lo) * static_cast<double>(i) / static_cast<double>(nodes - 1) : lo;
        const double s = (at - v0) / (static_cast<double>(v1) - v0);
        if (s > 0. && s < 1.) cuts.push_back(s);
      }
    std::sort(cuts.begin(), cuts.end());
  }
  cuts.push_back(1.);
  const auto value_at = [&](double s) { return static_cast<float>(v0 + (static_cast<double>(v1) - v0) * s); };
  for (std::size_t k = 0; k + 1 < cuts.size() && !acc.stopped; ++k) {
    double piece = (cuts[k + 1] - cuts[k]) * length;
    if (!(piece > 0.)) continue;
    const float va = value_at(cuts[k]), vb = value_at(cuts[k + 1]);
    const double sa = static_cast<double>(tf.opacity<simd::scalar>(va)) * density;
    double sb = static_cast<double>(tf.opacity<simd::scalar>(vb)) * density;
    const Vec3f ca = tf.color<simd::scalar>(va);
    Vec3f cb = tf.color<simd::scalar>(vb);
    const double a = sa;
    double b = (sb - sa) / (2. * piece);
    double depth = 0.5 * (sa + sb) * piece;
    if (acc.transmittance * std::exp(-depth) <= stop_below) {
      // Where a x + b x² reaches the depth left: the piece ends there, σ and c cut with it.
      const double left = std::log(acc.transmittance / stop_below);
      const double x = 2. * left / (a + std::sqrt(std::max(a * a + 4. * b * left, 0.)));
      if (x < piece) {
        const double f = x / piece;
        sb = sa + (sb - sa) * f, cb = ca + (cb - ca) * static_cast<float>(f);
        piece = x, depth = left;
      }
      acc.stopped = true;
    }
    const double leaving = std::exp(-depth);
    const double absorbed = -std::expm1(-depth);
    const double slope_term = exact_detail::integral_of_transmittance(a, b, piece) / piece - leaving;
    const Vec3f emitted = ca * static_cast<float>(absorbed) + (cb - ca) * static_cast<float>(slope_term);
    acc.color = acc.color + emitted * static_cast<float>(acc.transmittance);
    acc.transmittance *= leaving;
  }
}

/// One cell's stretch of a ray: where it enters and leaves, and the values there.
struct CellSegment {
  float t0, t1, v0, v1;
};

/// The exact integral along one ray (object space; t in the units the caller's rays use)
/// from t0 to t1 through a volume of tetrahedra, ending where the transmittance reaches
/// `stop_below`. `hit_t` becomes the middle of the first cell segment after which more
/// than `hit_opacity` is absorbed (infinity if none).
inline ExactAccumulator integrate_tetrahedra(const Unstructured& volume, const TransferFunction& tf, float density,
                                             const Vec3f& org, const Vec3f& dir, float t0, float t1, double stop_below,
                                             float hit_opacity, float& hit_t) {
  thread_local std::vector<CellSegment> segments;
  segments.clear();
  volume.cells_along(org, dir, t0, t1, [&](std::uint32_t cell) {
    float ta, tb;
    if (!volume.tetrahedron_span(cell, org, dir, ta, tb)) return;
    ta = std::max(ta, t0), tb = std::min(tb, t1);
    if (!(ta < tb)) return;
    segments.push_back({ta, tb, volume.value_in_cell(cell, org + dir * ta), volume.value_in_cell(cell, org + dir * tb)});
  });
  std::sort(segments.begin(), segments.end(), [](const CellSegment& a, const CellSegment& b) { return a.t0 < b.t0; });
  ExactAccumulator acc;
  hit_t = std::numeric_limits<float>::infinity();
  const float background = volume.background();
  float cursor = t0;
  const auto add = [&](float ta, float tb, float va, float vb) {
    integrate_linear_segment(tf, density, static_cast<double>(tb) - ta, va, vb, acc, stop_below);
    if (hit_t == std::numeric_limits<float>::infinity() && 1. - acc.transmittance > hit_opacity) hit_t = 0.5f * (ta + tb);
  };
  for (const CellSegment& s : segments) {
    if (acc.stopped) break;
    if (s.t1 <= cursor) continue;
    if (s.t0 > cursor) add(cursor, s.t0, background, background);  // a gap: NaN (transparent) unless set
    // What a cell before it covered already (a ray in a face two cells share crosses both)
    // is not counted twice.
    const float start = std::max(s.t0, cursor);
    add(start, s.t1, s.v0 + (s.v1 - s.v0) * ((start - s.t0) / (s.t1 - s.t0)), s.v1);
    cursor = s.t1;
  }
  if (cursor < t1) add(cursor, t1, background, background);
  return acc;
}

}  // namespace sciray
