#pragma once
// PixelRandom for a packet of pixel samples: the same draws (lane i's equal to
// PixelRandom(pixel[i], sample)'s, bit for bit), computed for all lanes at once in SIMD
// integer arithmetic. Renderers that draw the same kind of number in every lane (the AO
// rays of scivis and ao) take it; per-lane paths (the path tracer) keep PixelRandom.
#include <cstdint>
#include <type_traits>
#include <utility>

#include "sciray/math/random.hpp"
#include "sciray/simd/packet.hpp"

namespace sciray {

template <class Arch>
class PixelRandomLanes {
public:
  using F = simd::Float<Arch>;
  using I = simd::Int<Arch>;
  using M = simd::Mask<Arch>;
  /// The lanes' unsigned view: logical shifts, as the scalar hashes use.
  using U = std::conditional_t<std::is_same_v<Arch, simd::scalar>, std::uint32_t, xsimd::batch<std::uint32_t, Arch>>;

  PixelRandomLanes(const I& pixel, std::uint32_t sample)
      : pixel_seed_(hash32(to_unsigned(pixel) ^ U(0x632be5abU))), sample_reversed_(reverse_bits(sample)), draws_(0U) {}

  /// The next 2D sample in [0,1)^2 of every lane; only the `active` lanes advance, as
  /// only the scalar generators of lanes that draw would.
  std::pair<F, F> next_2d(const M& active) {
    draws_ = draws_ + to_unsigned(simd::select(active, I(1), I(0)));
    const U seed = hash32(pixel_seed_ + U(0x9e3779b9U) * draws_);
    const U index = reverse_bits(laine_karras_permutation(U(sample_reversed_), seed));
    return {coordinate(sobol_first_reversed(index), seed * U(0xa511e9b3U) + U(0x63d83595U)),
            coordinate(sobol_second_reversed(index), seed * U(0x63d83595U) + U(0xa511e9b3U))};
  }

private:
  static U to_unsigned(const I& x) {
    if constexpr (std::is_same_v<Arch, simd::scalar>)
      return static_cast<std::uint32_t>(x);
    else
      return xsimd::bitwise_cast<U>(x);
  }
  /// PixelRandom's coordinate: the Owen-scrambled reversed fraction as a float in [0, 1).
  static F coordinate(const U& reversed, const U& scramble) {
    const U bits = reverse_bits(laine_karras_permutation(reversed, scramble)) >> 8;
    if constexpr (std::is_same_v<Arch, simd::scalar>)
      return static_cast<float>(bits) * 0x1p-24f;
    else
      return simd::to_float(xsimd::bitwise_cast<I>(bits)) * F(0x1p-24f);
  }

  U pixel_seed_;
  std::uint32_t sample_reversed_;
  U draws_;
};

}  // namespace sciray
