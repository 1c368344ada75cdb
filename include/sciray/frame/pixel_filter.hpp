#pragma once
// OSPRay's pixel filters (the renderer parameter `pixelFilter`), applied by filter
// importance sampling (Ernst et al. 2006): every camera sample lands at an offset from
// the pixel centre drawn with the filter's density, so the plain average of a pixel's
// samples is its filtered value. No per-sample weights, no splatting into neighbours:
// accumulation, the variance estimate and adaptive tiles stay per pixel.
//
// Sampled as OSPRay samples them, so that images agree with OSPRay's sample for sample:
// the filter is tabulated at the centres of 5 bins per pixel over its width (2D, radial)
// and drawn from that piecewise-constant table, a row by v, then a column in it by u.
//   point           every sample at the pixel centre (aliased)
//   box             uniform over the pixel (width 1)
//   gauss           Gaussian of standard deviation 0.5 px over a width of 3 px — OSPRay's default
//   mitchell        Mitchell-Netravali with B = C = 1/3 over 4 px; a density cannot be
//                   negative, so its negative lobes are clipped (sampled as max(f, 0))
//   blackman_harris 4-term Blackman-Harris window over 3 px
//
// The sample points themselves (pixel_sample_point) are OSPRay's too: for scivis and ao,
// sample n of a frame's accumulation lies at the same place in every pixel; the path
// tracer, as OSPRay's, draws each pixel's from a sequence of its own (path_film_point).
#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <string>
#include <string_view>
#include <vector>

#include "sciray/error.hpp"
#include "sciray/math/random.hpp"

namespace sciray {

/// Values as OSPRay's OSPPixelFilterType.
enum class PixelFilter : int { point = 0, box = 1, gauss = 2, mitchell = 3, blackman_harris = 4 };

inline PixelFilter pixel_filter_from_int(int value) {
  if (value < 0 || value > 4)
    throw Error("'pixelFilter' must be OSP_PIXELFILTER_POINT (0), _BOX (1), _GAUSS (2), _MITCHELL (3) or "
                "_BLACKMAN_HARRIS (4), got " + std::to_string(value));
  return static_cast<PixelFilter>(value);
}

/// The filters' names where a text picks one (the tool's --pixel-filter, the Python
/// module's pixelFilter), in the enum's order.
inline constexpr std::array<const char*, 5> pixel_filter_names = {"point", "box", "gauss", "mitchell",
                                                                  "blackman_harris"};

/// The filter named `name`; `what` names the setting in the error for any other name.
inline PixelFilter pixel_filter_named(std::string_view name, const std::string& what) {
  for (std::size_t k = 0; k < pixel_filter_names.size(); ++k)
    if (name == pixel_filter_names[k]) return static_cast<PixelFilter>(k);
  std::string names;
  for (std::size_t k = 0; k < pixel_filter_names.size(); ++k)
    names += std::string(k == 0 ? "" : k + 1 < pixel_filter_names.size() ? ", " : " or ") + pixel_filter_names[k];
  throw Error(what + ": expected " + names + ", got '" + std::string(name) + "'");
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

/// The radial profile of `filter` at `r` pixels from the centre, as OSPRay tabulates it
/// (unnormalized; Mitchell's negative lobes included). Not defined for point and box.
inline float filter_profile(PixelFilter filter, float r) {
  const float width = 2.f * filter_radius(filter);
  switch (filter) {
    case PixelFilter::gauss: {
      constexpr float sigma = 0.5f;
      return std::exp(-0.5f * r * r / (sigma * sigma));
    }
    case PixelFilter::mitchell: {
      constexpr float b = 1.f / 3.f, c = 1.f / 3.f;
      const float x = 4.f * r / width, x2 = x * x, x3 = x2 * x;
      if (x < 1.f) return ((12.f - 9.f * b - 6.f * c) * x3 + (-18.f + 12.f * b + 6.f * c) * x2 + (6.f - 2.f * b)) / 6.f;
      if (x < 2.f)
        return ((-b - 6.f * c) * x3 + (6.f * b + 30.f * c) * x2 + (-12.f * b - 48.f * c) * x + (8.f * b + 24.f * c)) /
               6.f;
      return 0.f;
    }
    case PixelFilter::blackman_harris: {
      const float t = 2.f * std::numbers::pi_v<float> * (r + 0.5f * width) / width;
      return 0.35875f - 0.48829f * std::cos(t) + 0.14128f * std::cos(2.f * t) - 0.01168f * std::cos(3.f * t);
    }
    default: return 0.f;
  }
}

/// Offset from the pixel centre, in pixels.
struct FilterOffset {
  float x, y;
};

/// Maps uniform [0,1)^2 samples to offsets distributed as the filter, through OSPRay's
/// table: ceil(width) * 5 bins a side, each holding max(profile, 0) at its centre.
class FilterSampler {
public:
  explicit FilterSampler(PixelFilter filter) : filter_(filter) {
    if (filter == PixelFilter::point || filter == PixelFilter::box) return;
    width_ = 2.f * filter_radius(filter);
    bins_ = static_cast<int>(std::ceil(width_)) * bins_per_pixel;
    const auto n = static_cast<std::size_t>(bins_);
    cdf_x_.resize(n * n);
    cdf_y_.resize(n);
    for (std::size_t y = 0; y < n; ++y) {
      const float fy = ((static_cast<float>(y) + 0.5f) / static_cast<float>(n) - 0.5f) * width_;
      for (std::size_t x = 0; x < n; ++x) {
        const float fx = ((static_cast<float>(x) + 0.5f) / static_cast<float>(n) - 0.5f) * width_;
        cdf_x_[y * n + x] = std::max(0.f, filter_profile(filter, std::sqrt(fx * fx + fy * fy)));
      }
      cdf_y_[y] = to_cdf(&cdf_x_[y * n], n);
    }
    to_cdf(cdf_y_.data(), n);
  }

  PixelFilter filter() const { return filter_; }

  FilterOffset sample(float u, float v) const {
    switch (filter_) {
      case PixelFilter::point: return {0.f, 0.f};
      case PixelFilter::box: return {u - 0.5f, v - 0.5f};
      default: {
        const auto n = static_cast<std::size_t>(bins_);
        const float row = invert(cdf_y_.data(), n, v);
        const float column = invert(&cdf_x_[static_cast<std::size_t>(row) * n], n, u);
        const float inv_bins = 1.f / static_cast<float>(bins_);
        return {(column * inv_bins - 0.5f) * width_, (row * inv_bins - 0.5f) * width_};
      }
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
  static constexpr int bins_per_pixel = 5;

  /// Turns `n` weights into their normalized running sum (uniform if all are 0); returns
  /// their sum.
  static float to_cdf(float* values, std::size_t n) {
    float sum = 0.f;
    for (std::size_t i = 0; i < n; ++i) sum += values[i], values[i] = sum;
    for (std::size_t i = 0; i < n; ++i)
      values[i] = sum > 0.f ? values[i] / sum : static_cast<float>(i + 1) / static_cast<float>(n);
    return sum;
  }

  /// The bin index plus the position within it where the cdf reaches s.
  static float invert(const float* cdf, std::size_t n, float s) {
    const std::size_t i = std::min<std::size_t>(
        static_cast<std::size_t>(std::upper_bound(cdf, cdf + n, s) - cdf), n - 1);
    const float before = i == 0 ? 0.f : cdf[i - 1];
    const float p = cdf[i] - before;
    return static_cast<float>(i) + (p > 0.f ? (s - before) / p : 0.f);
  }

  PixelFilter filter_;
  float width_ = 0.f;
  int bins_ = 0;
  std::vector<float> cdf_x_;  ///< per row, the cumulative distribution over its columns
  std::vector<float> cdf_y_;  ///< the cumulative distribution over the rows
};

/// Where sample `n` of pixel `pixel` lies for the path tracer, in [0,1)^2 before the
/// filter maps it: OSPRay's path tracer film point, Sobol's first two dimensions at index
/// n + 64, each rotated (Cranley-Patterson) by a shift hashed from the pixel index (its
/// MurmurHash3 mix and finalizer, then per dimension a Wang-style integer hash). With the
/// same points, edge pixels, and the ids they show, are OSPRay's (measured: the primitive
/// ids of a scene of spheres at 1 and 2 samples per pixel equal OSPRay 3.1's in all
/// 48x48 pixels).
inline std::array<float, 2> path_film_point(std::uint32_t pixel, std::uint32_t n) {
  std::uint32_t scramble = std::rotl(std::rotl(pixel * 0xcc9e2d51U, 15) * 0x1b873593U, 13) * 5U + 0xe6546b64U;
  scramble = (scramble ^ (scramble >> 16)) * 0x85ebca6bU;
  scramble = (scramble ^ (scramble >> 13)) * 0xc2b2ae35U;
  scramble ^= scramble >> 16;
  const auto rotated = [&](std::uint32_t point, std::uint32_t dimension) {
    std::uint32_t shift = (dimension ^ 61U) ^ scramble;
    shift += shift << 3;
    shift = (shift ^ (shift >> 4)) * 0x27d4eb2dU;
    const float x = static_cast<float>(point) * 0x1p-32f + static_cast<float>(shift) * 0x1p-32f;
    return x >= 1.f ? x - 1.f : x;
  };
  const std::uint32_t index = n + 64;
  return {rotated(reverse_bits(sobol_first_reversed(index)), 0), rotated(reverse_bits(sobol_second_reversed(index)), 1)};
}

/// Where sample `n` of a pixel lies in [0,1)^2, before the filter maps it to an offset:
/// OSPRay's Halton point n + 1 (base 2; base 3 rotated by 1/6), the same in every pixel.
/// Sample 0 is (1/2, 1/2), the centre under every filter.
inline std::array<float, 2> pixel_sample_point(std::uint32_t sample) {
  const std::uint32_t n = sample + 1;
  std::uint32_t reversed = (n << 16) | (n >> 16);
  reversed = ((reversed & 0x00ff00ffu) << 8) | ((reversed & 0xff00ff00u) >> 8);
  reversed = ((reversed & 0x0f0f0f0fu) << 4) | ((reversed & 0xf0f0f0f0u) >> 4);
  reversed = ((reversed & 0x33333333u) << 2) | ((reversed & 0xccccccccu) >> 2);
  reversed = ((reversed & 0x55555555u) << 1) | ((reversed & 0xaaaaaaaau) >> 1);
  const float u = static_cast<float>(reversed >> 9) * 0x1p-23f;
  // The base-3 radical inverse of n's 20 lowest digits, four groups of five at a time.
  const auto reverse5 = [](std::uint32_t digits) {
    std::uint32_t r = 0;
    for (int k = 0; k < 5; ++k) r = r * 3 + digits % 3, digits /= 3;
    return r;
  };
  const std::uint32_t ternary = reverse5(n % 243u) * 14348907u + reverse5((n / 243u) % 243u) * 59049u +
                                reverse5((n / 59049u) % 243u) * 243u + reverse5((n / 14348907u) % 243u);
  float v = static_cast<float>(ternary) * (1.f / static_cast<float>(3486784401u)) + 1.f / 6.f;
  if (v >= 1.f) v -= 1.f;
  return {u, v};
}

}  // namespace sciray
