#pragma once
// Low-discrepancy sample positions: the same for a pixel and frame on any thread, so
// that images do not depend on how tiles are scheduled.
#include <cstdint>

namespace sciray {

/// Radical inverse of `index` in `base` (the van der Corput / Halton sequence).
inline float radical_inverse(std::uint32_t index, std::uint32_t base) {
  const float inv_base = 1.f / static_cast<float>(base);
  float inv_base_n = 1.f, result = 0.f;
  while (index > 0) {
    inv_base_n *= inv_base;
    result += static_cast<float>(index % base) * inv_base_n;
    index /= base;
  }
  return result;
}

/// Sub-pixel offset in [0,1)^2 for accumulation frame `frame`: frame 0 is the pixel
/// centre, later frames follow the (2,3) Halton sequence so that averaging frames
/// converges to the box-filtered pixel.
struct PixelOffset {
  float x, y;
};
inline PixelOffset pixel_offset(std::uint32_t frame) {
  if (frame == 0) return {0.5f, 0.5f};
  return {radical_inverse(frame, 2), radical_inverse(frame, 3)};
}

}  // namespace sciray
