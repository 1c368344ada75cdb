#pragma once
// Low-discrepancy sample positions: the same for a pixel and frame on any thread, so
// that images do not depend on how tiles are scheduled.
#include <cstdint>

namespace sciray {

/// Sub-pixel offset in [0,1)^2 for accumulation frame `frame`: the R2 sequence
/// (Roberts 2018, additive recurrence on the plastic number) started at the pixel
/// centre. Frame 0 is the centre; averaging frames converges to the box-filtered pixel.
/// Unlike Halton's base-2 axis, its even and odd frames are equally distributed, which
/// the frame buffer's variance estimate relies on.
struct PixelOffset {
  float x, y;
};
inline PixelOffset pixel_offset(std::uint32_t frame) {
  constexpr double a1 = 0.7548776662466927;  // 1 / plastic number
  constexpr double a2 = 0.5698402909980532;  // 1 / plastic number^2
  const auto wrap = [](double v) { return static_cast<float>(v - static_cast<double>(static_cast<std::uint64_t>(v))); };
  return {wrap(0.5 + a1 * frame), wrap(0.5 + a2 * frame)};
}

}  // namespace sciray
