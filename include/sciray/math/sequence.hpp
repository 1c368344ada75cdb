#pragma once
// Low-discrepancy sample positions: the same for a pixel and sample on any thread, so
// that images do not depend on how tiles are scheduled.
#include <cstdint>

namespace sciray {

/// Sub-pixel offset in [0,1)^2 for sample `i`: the R2 sequence (Roberts 2018, additive
/// recurrence on the plastic number) started at the pixel centre. Sample 0 is the
/// centre. Unlike Halton's base-2 axis, its even and odd samples are equally
/// distributed, which the frame buffer's variance estimate relies on.
struct PixelOffset {
  float x, y;
};
inline PixelOffset pixel_offset(std::uint32_t i) {
  constexpr double a1 = 0.7548776662466927;  // 1 / plastic number
  constexpr double a2 = 0.5698402909980532;  // 1 / plastic number^2
  const auto wrap = [](double v) { return static_cast<float>(v - static_cast<double>(static_cast<std::uint64_t>(v))); };
  return {wrap(0.5 + a1 * i), wrap(0.5 + a2 * i)};
}

/// The camera's part of one pixel sample, each in [0,1): where on the film (fed to the
/// pixel filter) and where on the lens.
struct CameraSample {
  float film_x, film_y, lens_u, lens_v;
};

/// Camera sample `sample` of pixel `pixel`. The film position is pixel_offset(sample)
/// rotated by a per-pixel shift (Cranley-Patterson), so neighbouring pixels do not share
/// one sub-pixel pattern; sample 0 stays at the centre, so single-sample images are
/// centre-sampled. The lens position is the second pair of the 4D Kronecker sequence
/// R4 (Roberts 2018, on the root of x^5 = x + 1), shifted per pixel too. Film and lens
/// use rationally independent steps: were both pairs one 2D sequence under two shifts,
/// lens and film would differ by a constant per pixel and depth of field would average
/// a single line of the (film, lens) square instead of all of it.
inline CameraSample camera_sample(std::uint32_t pixel, std::uint32_t sample) {
  const auto hash = [](std::uint32_t x) {  // lowbias32 (Wellons)
    x ^= x >> 16;
    x *= 0x7feb352dU;
    x ^= x >> 15;
    x *= 0x846ca68bU;
    x ^= x >> 16;
    return x;
  };
  const auto unit = [](std::uint32_t bits) { return static_cast<double>(bits >> 8) * 0x1p-24; };
  const auto wrap = [](double v) {
    const float f = static_cast<float>(v - static_cast<double>(static_cast<std::uint64_t>(v)));
    return f < 1.f ? f : 0x1.fffffep-1f;
  };
  const std::uint32_t h0 = hash(pixel ^ 0x5bd1e995U), h1 = hash(h0), h2 = hash(h1), h3 = hash(h2);
  constexpr double r4_3 = 0.6287067210378086;  // 1 / g^3, g the root of x^5 = x + 1
  constexpr double r4_4 = 0.5385972572236101;  // 1 / g^4
  CameraSample s{0.5f, 0.5f, wrap(unit(h2) + r4_3 * sample), wrap(unit(h3) + r4_4 * sample)};
  if (sample != 0) {
    const PixelOffset film = pixel_offset(sample);
    s.film_x = wrap(film.x + unit(h0));
    s.film_y = wrap(film.y + unit(h1));
  }
  return s;
}

}  // namespace sciray
