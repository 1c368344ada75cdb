#pragma once
// Low-discrepancy sample positions: the same for a pixel and sample on any thread, so
// that images do not depend on how tiles are scheduled.
#include <cstdint>
#include <type_traits>

#include "sciray/simd/packet.hpp"

namespace sciray {

namespace detail {
/// Kronecker sequences in 32-bit fixed point: start + i * step wraps modulo 1 for free,
/// and a step rounded to 2^-32 keeps the sequence's structure over any practical count.
constexpr std::uint32_t fixed_step(double step) { return static_cast<std::uint32_t>(step * 4294967296.0 + 0.5); }
// g is the root of x^5 = x + 1
inline constexpr std::uint32_t r4_3 = fixed_step(0.6287067210378086);    // 1 / g^3
inline constexpr std::uint32_t r4_4 = fixed_step(0.5385972572236101);    // 1 / g^4
inline constexpr std::uint32_t golden = fixed_step(0.6180339887498949);  // 1 / golden ratio

/// Unsigned lanes: uint32 for the scalar path, a batch of them for packets.
template <class Arch>
using UInt = std::conditional_t<std::is_same_v<Arch, simd::scalar>, std::uint32_t, xsimd::batch<std::uint32_t, Arch>>;

/// [0,1) from the top 24 bits of fixed-point values.
template <class Arch>
simd::Float<Arch> fixed_to_unit(const UInt<Arch>& v) {
  if constexpr (std::is_same_v<Arch, simd::scalar>)
    return static_cast<float>(v >> 8) * 0x1p-24f;
  else
    return xsimd::to_float(xsimd::bitwise_cast<simd::Int<Arch>>(v >> 8)) * simd::Float<Arch>(0x1p-24f);
}

/// lowbias32 (Wellons): a cheap, well mixed 32-bit hash, per lane.
template <class U>
U mix32(U x) {
  x ^= x >> 16;
  x *= U(0x7feb352dU);
  x ^= x >> 15;
  x *= U(0x846ca68bU);
  x ^= x >> 16;
  return x;
}
}  // namespace detail

/// Where on the lens a pixel sample passes (T = float for one, a packet for W), in
/// [0,1)^2. (Where on the film is OSPRay's sample point, the same in every pixel for
/// scivis and ao, path_film_point for the path tracer: both in frame/pixel_filter.hpp.)
template <class T>
struct CameraSamples {
  T lens_u, lens_v;
};

using CameraSample = CameraSamples<float>;

/// The lens samples of one pixel per lane: the second pair of the 4D Kronecker sequence
/// R4 (Roberts 2018, on the root of x^5 = x + 1), rotated by a per-pixel shift
/// (Cranley-Patterson), so that neighbouring pixels do not share one lens pattern. Its
/// steps are rationally independent of the film's Halton and Sobol points, so depth of
/// field averages the whole (film, lens) square, not a line of it.
template <class Arch>
class CameraSequence {
public:
  using U = detail::UInt<Arch>;
  using F = simd::Float<Arch>;

  /// `pixel`: each lane's pixel index (any value for lanes outside the image).
  explicit CameraSequence(const simd::Int<Arch>& pixel) {
    U p;
    if constexpr (std::is_same_v<Arch, simd::scalar>)
      p = static_cast<std::uint32_t>(pixel);
    else
      p = xsimd::bitwise_cast<U>(pixel);
    // Independent hashes (not a chain of them), so that they run in parallel.
    constexpr std::uint32_t salt[2] = {0x165667b1U, 0x9e3779b9U};
    for (int k = 0; k < 2; ++k) shift_[k] = detail::mix32(p ^ U(salt[k]));
  }

  CameraSamples<F> operator()(std::uint32_t sample) const {
    CameraSamples<F> s;
    s.lens_u = detail::fixed_to_unit<Arch>(U(sample * detail::r4_3) + shift_[0]);
    s.lens_v = detail::fixed_to_unit<Arch>(U(sample * detail::r4_4) + shift_[1]);
    return s;
  }

private:
  U shift_[2];
};

/// The shutter time sample in [0,1) of sample `sample` of each lane's pixel: the
/// golden-ratio sequence (stratified over any run of samples), shifted by a hash of the
/// pixel of its own, so that it is unrelated to the lens position.
template <class Arch>
simd::Float<Arch> time_sample(const simd::Int<Arch>& pixel, std::uint32_t sample) {
  using U = detail::UInt<Arch>;
  U p;
  if constexpr (std::is_same_v<Arch, simd::scalar>)
    p = static_cast<std::uint32_t>(pixel);
  else
    p = xsimd::bitwise_cast<U>(pixel);
  return detail::fixed_to_unit<Arch>(U(sample * detail::golden) + detail::mix32(p ^ U(0x2c1b3c6dU)));
}

/// Camera sample `sample` of pixel `pixel`.
inline CameraSample camera_sample(std::uint32_t pixel, std::uint32_t sample) {
  return CameraSequence<simd::scalar>(static_cast<std::int32_t>(pixel))(sample);
}

}  // namespace sciray
