#pragma once
// OSPRay's pixel filters (the renderer parameter `pixelFilter`), applied by filter
// importance sampling (Ernst et al. 2006): every camera sample lands at an offset from
// the pixel centre drawn with the filter's density, so the plain average of a pixel's
// samples is its filtered value. No per-sample weights, no splatting into neighbours:
// accumulation, the variance estimate and adaptive tiles stay per pixel.
//
// The filters are separable, profile(x) * profile(y), with OSPRay's widths:
//   point           every sample at the pixel centre (aliased)
//   box             uniform over the pixel (width 1)
//   gauss           Gaussian of standard deviation 0.5 px, truncated smoothly at 1.5 px
//                   (its value there subtracted) — OSPRay's default
//   mitchell        Mitchell-Netravali with B = C = 1/3 over 4 px; a density cannot be
//                   negative, so its negative lobes are clipped (sampled as max(f, 0))
//   blackman_harris 4-term Blackman-Harris window over 3 px
#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "sciray/error.hpp"
#include "sciray/simd/packet.hpp"

namespace sciray {

/// Values as OSPRay's OSPPixelFilterType.
enum class PixelFilter : int { point = 0, box = 1, gauss = 2, mitchell = 3, blackman_harris = 4 };

inline PixelFilter pixel_filter_from_int(int value) {
  if (value < 0 || value > 4)
    throw Error("'pixelFilter' must be OSP_PIXELFILTER_POINT (0), _BOX (1), _GAUSS (2), _MITCHELL (3) or "
                "_BLACKMAN_HARRIS (4), got " + std::to_string(value));
  return static_cast<PixelFilter>(value);
}

/// Half the support of the filter in pixels.
inline float filter_radius(PixelFilter filter) {
  switch (filter) {
    case PixelFilter::point: return 0.f;
    case PixelFilter::box: return 0.5f;
    case PixelFilter::gauss: return 1.5f;
    case PixelFilter::mitchell: return 2.f;
    case PixelFilter::blackman_harris: return 1.5f;
  }
  return 0.f;
}

/// The 1D profile of `filter` at `x` pixels from the centre (unnormalized; 0 outside
/// the radius; Mitchell's negative lobes included). Not defined for `point`.
inline float filter_profile(PixelFilter filter, float x) {
  const float r = filter_radius(filter);
  const float ax = std::abs(x);
  if (ax > r) return 0.f;
  switch (filter) {
    case PixelFilter::point: return 0.f;
    case PixelFilter::box: return 1.f;
    case PixelFilter::gauss: {
      constexpr float inv_two_sigma2 = 1.f / (2.f * 0.5f * 0.5f);
      return std::exp(-x * x * inv_two_sigma2) - std::exp(-r * r * inv_two_sigma2);
    }
    case PixelFilter::mitchell: {
      constexpr float b = 1.f / 3.f, c = 1.f / 3.f;
      const float x2 = ax * ax, x3 = x2 * ax;
      if (ax < 1.f)
        return ((12.f - 9.f * b - 6.f * c) * x3 + (-18.f + 12.f * b + 6.f * c) * x2 + (6.f - 2.f * b)) / 6.f;
      return ((-b - 6.f * c) * x3 + (6.f * b + 30.f * c) * x2 + (-12.f * b - 48.f * c) * ax + (8.f * b + 24.f * c)) /
             6.f;
    }
    case PixelFilter::blackman_harris: {
      const float t = 2.f * std::numbers::pi_v<float> * (x / (2.f * r) + 0.5f);
      return 0.35875f - 0.48829f * std::cos(t) + 0.14128f * std::cos(2.f * t) - 0.01168f * std::cos(3.f * t);
    }
  }
  return 0.f;
}

/// Offset from the pixel centre, in pixels.
struct FilterOffset {
  float x, y;
};

/// Maps uniform [0,1)^2 samples to offsets distributed as the filter, through a table
/// of the inverse of the profile's cumulative distribution. The table is symmetric, so
/// u = 0.5 maps exactly to the centre and low-discrepancy inputs stay stratified.
class FilterSampler {
public:
  explicit FilterSampler(PixelFilter filter) : filter_(filter) {
    if (filter == PixelFilter::point || filter == PixelFilter::box) return;
    // Cumulative distribution of max(profile, 0) over [-r, r] by the midpoint rule on a
    // fine grid; the density is piecewise constant per cell, so its inverse is
    // piecewise linear and exact at the cell boundaries.
    constexpr int cells = 8192;
    const float r = filter_radius(filter);
    const double cell = 2.0 * r / cells;
    std::vector<double> cdf(cells + 1, 0.0);
    for (int i = 0; i < cells; ++i) {
      const double x = -r + (i + 0.5) * cell;
      cdf[i + 1] = cdf[i] + std::max(0.0, static_cast<double>(filter_profile(filter, static_cast<float>(x))));
    }
    int i = 0;
    for (int k = 0; k <= table_size / 2; ++k) {
      const double target = cdf[cells] * k / table_size;
      while (i < cells - 1 && cdf[i + 1] < target) ++i;
      const double in_cell = cdf[i + 1] > cdf[i] ? (target - cdf[i]) / (cdf[i + 1] - cdf[i]) : 0.0;
      inverse_[k] = static_cast<float>(-r + (i + std::clamp(in_cell, 0.0, 1.0)) * cell);
    }
    inverse_[table_size / 2] = 0.f;
    for (int k = 0; k < table_size / 2; ++k) inverse_[table_size - k] = -inverse_[k];
  }

  PixelFilter filter() const { return filter_; }

  FilterOffset sample(float u, float v) const {
    switch (filter_) {
      case PixelFilter::point: return {0.f, 0.f};
      case PixelFilter::box: return {u - 0.5f, v - 0.5f};
      default: return {invert(u), invert(v)};
    }
  }
  /// sample() for a packet of (u, v): offsets in `x`, `y`.
  template <class Arch>
  void sample(const simd::Float<Arch>& u, const simd::Float<Arch>& v, simd::Float<Arch>& x,
              simd::Float<Arch>& y) const {
    using F = simd::Float<Arch>;
    switch (filter_) {
      case PixelFilter::point: x = y = F(0.f); return;
      case PixelFilter::box: x = u - F(0.5f), y = v - F(0.5f); return;
      default: x = invert<Arch>(u), y = invert<Arch>(v);
    }
  }

  /// The sampler of `filter`, built once.
  static const FilterSampler& of(PixelFilter filter) {
    static const std::array<FilterSampler, 5> samplers{
        FilterSampler(PixelFilter::point), FilterSampler(PixelFilter::box), FilterSampler(PixelFilter::gauss),
        FilterSampler(PixelFilter::mitchell), FilterSampler(PixelFilter::blackman_harris)};
    return samplers[static_cast<std::size_t>(filter)];
  }

private:
  static constexpr int table_size = 1024;  // even, so that u = 0.5 is an entry

  float invert(float u) const { return invert<simd::scalar>(u); }
  template <class Arch>
  simd::Float<Arch> invert(const simd::Float<Arch>& u) const {
    using F = simd::Float<Arch>;
    const F t = simd::min(simd::max(u, F(0.f)), F(1.f)) * F(static_cast<float>(table_size));
    const simd::Int<Arch> k = simd::to_int(simd::min(t, F(static_cast<float>(table_size - 1))));
    const F f = t - simd::to_float(k);
    const F below = simd::gather<Arch>(inverse_.data(), k), above = simd::gather<Arch>(inverse_.data() + 1, k);
    return below + f * (above - below);
  }

  PixelFilter filter_;
  std::array<float, table_size + 1> inverse_{};
};

}  // namespace sciray
