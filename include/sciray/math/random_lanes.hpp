#pragma once
// PixelRandom for a packet of pixel samples: the same draws (lane i's equal to
// PixelRandom(pixel[i], sample)'s, bit for bit), computed for all lanes at once in SIMD
// integer arithmetic. Renderers that draw the same kind of number in every lane (the AO
// rays of scivis and ao) take it; the path tracer keeps a PixelRandom per path and draws
// for a packet of them at once where the packet's paths draw alike.
#include <array>
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
    return draw(pixel_seed_, U(sample_reversed_), draws_);
  }

  /// next_2d() of W generators at once, lane i's from *rngs[i], bit for bit: only the
  /// `active` lanes' generators advance. For paths that keep a generator each (the path
  /// tracer) but draw the same kind of number in a packet.
  static std::pair<F, F> next_2d_of(const std::array<PixelRandom*, simd::width<Arch>>& rngs, const M& active) {
    constexpr int W = simd::width<Arch>;
    alignas(64) std::uint32_t pixel_seed[W], sample_reversed[W], draws[W];
    for (int i = 0; i < W; ++i) {
      PixelRandom& r = *rngs[static_cast<std::size_t>(i)];
      if (simd::lane(active, i)) ++r.draws_;
      pixel_seed[i] = r.pixel_seed_, sample_reversed[i] = r.sample_reversed_, draws[i] = r.draws_;
    }
    return draw(load(pixel_seed), load(sample_reversed), load(draws));
  }

private:
  /// PixelRandom::next_2d's numbers for the generators' state after the draw.
  static std::pair<F, F> draw(const U& pixel_seed, const U& sample_reversed, const U& draws) {
    const U seed = hash32(pixel_seed + U(0x9e3779b9U) * draws);
    const U index = reverse_bits(laine_karras_permutation(sample_reversed, seed));
    return {coordinate(sobol_first_reversed(index), seed * U(0xa511e9b3U) + U(0x63d83595U)),
            coordinate(sobol_second_reversed(index), seed * U(0x63d83595U) + U(0xa511e9b3U))};
  }
  static U load(const std::uint32_t* x) {
    if constexpr (std::is_same_v<Arch, simd::scalar>)
      return *x;
    else
      return U::load_aligned(x);
  }
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
