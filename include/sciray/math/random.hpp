#pragma once
// Random numbers for renderers, seeded per pixel and per sample so that images do not
// depend on thread scheduling.
//
// The first dimensions of a pixel's samples are low-discrepancy: dimension j of sample i
// is the 16-dimensional Kronecker sequence R16 (Roberts 2018: alpha_j = phi^-(j+1) with
// phi the root of x^17 = x + 1) at i, shifted by a per-pixel hash (Cranley-Patterson
// rotation), so successive samples of one pixel stratify well while neighbouring pixels
// decorrelate. One sequence in 16 dimensions, not one 2D sequence per pair: pairs of a
// 2D sequence shifted apart would be functions of each other, and an estimator that
// uses two of them (a light sample and a BSDF sample) would converge to the wrong value.
// Dimensions past the 16 come from a PCG32 stream seeded by a hash of (pixel, sample).
#include <array>
#include <cmath>
#include <cstdint>

namespace sciray {

/// 32-bit integer hash (Wellons' lowbias32): cheap and well mixed.
inline std::uint32_t hash32(std::uint32_t x) {
  x ^= x >> 16;
  x *= 0x7feb352dU;
  x ^= x >> 15;
  x *= 0x846ca68bU;
  x ^= x >> 16;
  return x;
}

/// [0,1) from the top 24 bits.
inline float unit_float(std::uint32_t bits) { return static_cast<float>(bits >> 8) * 0x1p-24f; }

/// PCG32 (O'Neill 2014): a small, statistically strong generator with selectable streams.
class Pcg32 {
public:
  Pcg32(std::uint64_t seed, std::uint64_t stream) : inc_((stream << 1u) | 1u) {
    next_uint();
    state_ += seed;
    next_uint();
  }
  std::uint32_t next_uint() {
    const std::uint64_t old = state_;
    state_ = old * 6364136223846793005ULL + inc_;
    const auto xorshifted = static_cast<std::uint32_t>(((old >> 18u) ^ old) >> 27u);
    const auto rot = static_cast<std::uint32_t>(old >> 59u);
    return (xorshifted >> rot) | (xorshifted << ((32u - rot) & 31u));
  }
  float next_float() { return unit_float(next_uint()); }

private:
  std::uint64_t state_ = 0;
  std::uint64_t inc_;
};

/// The sample stream of one pixel sample: 2D draws, the first `low_discrepancy_pairs`
/// of them stratified across the pixel's samples.
class PixelRandom {
public:
  static constexpr int low_discrepancy_pairs = 8;

  PixelRandom() : PixelRandom(0, 0) {}
  PixelRandom(std::uint32_t pixel, std::uint32_t sample)
      : pixel_(pixel),
        sample_(sample),
        pcg_((static_cast<std::uint64_t>(hash32(sample ^ hash32(pixel))) << 32) | hash32(sample * 0x9e3779b9U + pixel),
             pixel) {}

  struct Pair {
    float u, v;
  };

  /// The next 2D sample in [0,1)^2.
  Pair next_2d() {
    if (pair_ < low_discrepancy_pairs) {
      const auto& alpha = kronecker_alphas();
      const std::uint32_t h = hash32(pixel_ * 0x9e3779b9U ^ hash32(static_cast<std::uint32_t>(pair_) + 0x632be5abU));
      const double shift_u = unit_float(h), shift_v = unit_float(hash32(h));
      const int j = 2 * pair_++;
      // The fractional part of alpha * sample, exactly enough in double for 2^32 samples.
      return {wrap(shift_u + alpha[j] * sample_), wrap(shift_v + alpha[j + 1] * sample_)};
    }
    return {pcg_.next_float(), pcg_.next_float()};
  }
  float next_1d() { return next_2d().u; }

  /// A number in [0,1) that takes no low-discrepancy dimension: for samplers that draw a
  /// varying count of numbers (delta tracking), which would otherwise shift every later
  /// draw onto another sample's dimension.
  float next_independent() { return pcg_.next_float(); }

private:
  static const std::array<double, 2 * low_discrepancy_pairs>& kronecker_alphas() {
    static const auto alphas = [] {
      constexpr int d = 2 * low_discrepancy_pairs;
      double phi = 1.5;  // Newton's method on x^(d+1) - x - 1
      for (int k = 0; k < 64; ++k) phi -= (std::pow(phi, d + 1) - phi - 1.0) / ((d + 1) * std::pow(phi, d) - 1.0);
      std::array<double, d> a{};
      for (int j = 0; j < d; ++j) a[j] = std::fmod(std::pow(1.0 / phi, j + 1), 1.0);
      return a;
    }();
    return alphas;
  }
  static float wrap(double v) {
    const float f = static_cast<float>(v - static_cast<double>(static_cast<std::uint64_t>(v)));
    return f < 1.f ? f : 0x1.fffffep-1f;
  }
  std::uint32_t pixel_, sample_;
  int pair_ = 0;
  Pcg32 pcg_;
};

}  // namespace sciray
