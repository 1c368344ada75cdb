#pragma once
// Low-discrepancy sample positions: the same for a pixel and sample on any thread, so
// that images do not depend on how tiles are scheduled.
#include <cstdint>

namespace sciray {

namespace detail {
/// Kronecker sequences in 32-bit fixed point: start + i * step wraps modulo 1 for free,
/// and a step rounded to 2^-32 keeps the sequence's structure over any practical count.
constexpr std::uint32_t fixed_step(double step) { return static_cast<std::uint32_t>(step * 4294967296.0 + 0.5); }
inline float fixed_to_unit(std::uint32_t v) { return static_cast<float>(v >> 8) * 0x1p-24f; }
inline constexpr std::uint32_t r2_x = fixed_step(0.7548776662466927);    // 1 / plastic number
inline constexpr std::uint32_t r2_y = fixed_step(0.5698402909980532);    // 1 / plastic number^2
inline constexpr std::uint32_t r4_3 = fixed_step(0.6287067210378086);    // 1 / g^3, g the root of x^5 = x + 1
inline constexpr std::uint32_t r4_4 = fixed_step(0.5385972572236101);    // 1 / g^4
inline constexpr std::uint32_t half = 0x80000000u;
/// lowbias32 (Wellons): a cheap, well mixed 32-bit hash.
inline std::uint32_t mix32(std::uint32_t x) {
  x ^= x >> 16;
  x *= 0x7feb352dU;
  x ^= x >> 15;
  x *= 0x846ca68bU;
  x ^= x >> 16;
  return x;
}
}  // namespace detail

/// Sub-pixel offset in [0,1)^2 for sample `i`: the R2 sequence (Roberts 2018, additive
/// recurrence on the plastic number) started at the pixel centre. Sample 0 is the
/// centre. Unlike Halton's base-2 axis, its even and odd samples are equally
/// distributed, which the frame buffer's variance estimate relies on.
struct PixelOffset {
  float x, y;
};
inline PixelOffset pixel_offset(std::uint32_t i) {
  return {detail::fixed_to_unit(detail::half + i * detail::r2_x), detail::fixed_to_unit(detail::half + i * detail::r2_y)};
}

/// The camera's part of one pixel sample, each in [0,1): where on the film (fed to the
/// pixel filter) and where on the lens.
struct CameraSample {
  float film_x, film_y, lens_u, lens_v;
};

/// The camera samples of one pixel. The film position is pixel_offset(sample) rotated
/// by a per-pixel shift (Cranley-Patterson), so neighbouring pixels do not share one
/// sub-pixel pattern; sample 0 stays at the centre, so single-sample images are
/// centre-sampled. The lens position is the second pair of the 4D Kronecker sequence
/// R4 (Roberts 2018, on the root of x^5 = x + 1), shifted per pixel too. Film and lens
/// use rationally independent steps: were both pairs one 2D sequence under two shifts,
/// lens and film would differ by a constant per pixel and depth of field would average
/// a single line of the (film, lens) square instead of all of it.
class CameraSequence {
public:
  CameraSequence() = default;
  explicit CameraSequence(std::uint32_t pixel) {
    // Four independent hashes (not a chain of them), so that they run in parallel.
    constexpr std::uint32_t salt[4] = {0x5bd1e995U, 0x27d4eb2fU, 0x165667b1U, 0x9e3779b9U};
    for (int k = 0; k < 4; ++k) shift_[k] = detail::mix32(pixel ^ salt[k]);
  }
  CameraSample operator()(std::uint32_t sample) const {
    const bool centre = sample == 0;
    return {centre ? 0.5f : detail::fixed_to_unit(detail::half + sample * detail::r2_x + shift_[0]),
            centre ? 0.5f : detail::fixed_to_unit(detail::half + sample * detail::r2_y + shift_[1]),
            detail::fixed_to_unit(shift_[2] + sample * detail::r4_3),
            detail::fixed_to_unit(shift_[3] + sample * detail::r4_4)};
  }

private:
  std::uint32_t shift_[4] = {};
};

/// Camera sample `sample` of pixel `pixel`.
inline CameraSample camera_sample(std::uint32_t pixel, std::uint32_t sample) { return CameraSequence(pixel)(sample); }

}  // namespace sciray
