#pragma once
// Random numbers for renderers, seeded per pixel and per sample so that images do not
// depend on thread scheduling.
//
// A pixel's 2D draws are low-discrepancy across its samples: draw j of sample i is the
// two-dimensional Sobol (0,2)-sequence at a shuffled index, Owen-scrambled (Burley 2020,
// "Practical Hash-based Owen Scrambling"), with the shuffle and the scrambles seeded by a
// hash of (pixel, j). Every 2^k consecutive samples of one pixel then put exactly one
// point in each of the 2^k strata of any elementary-interval shape in each draw, and
// different draws are shuffled independently (padding), so a light sample and a BSDF
// sample are not functions of each other. (A Kronecker sequence in many dimensions,
// used before, steps its first dimensions by nearly 1: 16 samples covered two thirds of
// [0, 1).) Draws that must not take a low-discrepancy slot come from a PCG32 stream.
#include <cstdint>
#include <type_traits>

namespace sciray {

/// What the integer mixing below is written over: std::uint32_t, or a packet of them
/// (math/random_lanes.hpp), so that every lane draws what the scalar generator draws.
/// Never a signed integer, whose right shifts would smear the sign.
template <class U>
concept Uint32Lanes = std::is_same_v<U, std::uint32_t> || !std::is_integral_v<U>;

/// 32-bit integer hash (Wellons' lowbias32): cheap and well mixed.
template <Uint32Lanes U>
constexpr U hash32(U x) {
  x ^= x >> 16;
  x *= U(0x7feb352dU);
  x ^= x >> 15;
  x *= U(0x846ca68bU);
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

template <Uint32Lanes U>
constexpr U reverse_bits(U x) {
  if constexpr (std::is_integral_v<U>) {
    x = __builtin_bswap32(x);
  } else {
    x = (x << 16) | (x >> 16);
    x = ((x & U(0x00ff00ffU)) << 8) | ((x >> 8) & U(0x00ff00ffU));
  }
  x = ((x & U(0x0f0f0f0fU)) << 4) | ((x >> 4) & U(0x0f0f0f0fU));
  x = ((x & U(0x33333333U)) << 2) | ((x >> 2) & U(0x33333333U));
  x = ((x & U(0x55555555U)) << 1) | ((x >> 1) & U(0x55555555U));
  return x;
}

/// Laine and Karras's hash: a random permutation of 32-bit numbers in which bit b depends
/// only on bits 0..b. Applied to a fraction's bits in reverse order it is Owen scrambling
/// in base 2: each bit from the top flips depending only on the bits above it, so every
/// dyadic interval maps onto one of the same size (Burley 2020).
template <Uint32Lanes U>
constexpr U laine_karras_permutation(U x, U seed) {
  x += seed;
  x ^= x * U(0x6c50b47cU);
  x ^= x * U(0xb82f1e52U);
  x ^= x * U(0xc7afe638U);
  x ^= x * U(0x8d22f6e6U);
  return x;
}

/// The two dimensions of Sobol's (0,2)-sequence at `index` as 32-bit fractions with their
/// bits reversed (bit 0 the coarsest), the form Owen scrambling works on. The first is
/// `index` itself (the radical inverse, reversed); the second's direction numbers are the
/// rows of Pascal's triangle mod 2, so its bit j is the parity of the index bits k whose
/// binary digits include j's (Lucas's theorem): a superset sum over the five bit
/// positions of j, five shift-and-xor steps.
template <Uint32Lanes U>
constexpr U sobol_first_reversed(U index) {
  return index;
}
template <Uint32Lanes U>
constexpr U sobol_second_reversed(U index) {
  index ^= (index >> 1) & U(0x55555555U);
  index ^= (index >> 2) & U(0x33333333U);
  index ^= (index >> 4) & U(0x0f0f0f0fU);
  index ^= (index >> 8) & U(0x00ff00ffU);
  index ^= (index >> 16) & U(0x0000ffffU);
  return index;
}

/// The sample stream of one pixel sample: 2D draws stratified across the pixel's samples.
template <class Arch>
class PixelRandomLanes;

class PixelRandom {
public:
  PixelRandom() : PixelRandom(0, 0) {}
  PixelRandom(std::uint32_t pixel, std::uint32_t sample)
      : pixel_seed_(hash32(pixel ^ 0x632be5abU)),
        sample_reversed_(reverse_bits(sample)),
        pcg_((static_cast<std::uint64_t>(hash32(sample ^ hash32(pixel))) << 32) | hash32(sample * 0x9e3779b9U + pixel),
             pixel) {}

  struct Pair {
    float u, v;
  };

  /// The next 2D sample in [0,1)^2.
  Pair next_2d() {
    const std::uint32_t seed = hash32(pixel_seed_ + 0x9e3779b9U * ++draws_);
    // Each draw visits the pixel's samples in an order of its own (padding): the sample
    // index Owen-scrambled, which keeps every aligned block of 2^k samples a (0,k,2)-net.
    const std::uint32_t index = reverse_bits(laine_karras_permutation(sample_reversed_, seed));
    const auto coordinate = [](std::uint32_t reversed, std::uint32_t scramble) {
      return unit_float(reverse_bits(laine_karras_permutation(reversed, scramble)));
    };
    return {coordinate(sobol_first_reversed(index), seed * 0xa511e9b3U + 0x63d83595U),
            coordinate(sobol_second_reversed(index), seed * 0x63d83595U + 0xa511e9b3U)};
  }
  float next_1d() { return next_2d().u; }

  /// A number in [0,1) that takes no low-discrepancy draw: for samplers that draw a
  /// varying count of numbers (delta tracking), which would otherwise shift every later
  /// draw onto another sample's sequence.
  float next_independent() { return pcg_.next_float(); }

private:
  template <class Arch>
  friend class PixelRandomLanes;  // draws for a packet of generators at once
  std::uint32_t pixel_seed_, sample_reversed_;
  std::uint32_t draws_ = 0;
  Pcg32 pcg_;
};

}  // namespace sciray
