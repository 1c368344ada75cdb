#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>

namespace sciray {

/// IEC 61966-2-1 sRGB transfer function for a linear value in [0,1].
inline float linear_to_srgb(float linear) {
  const float c = std::clamp(linear, 0.f, 1.f);
  return c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1.f / 2.4f) - 0.055f;
}

inline float srgb_to_linear(float encoded) {
  const float c = std::clamp(encoded, 0.f, 1.f);
  return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

/// Quantizes [0,1] to 8 bits, rounding to nearest (NaN maps to 0).
inline std::uint8_t to_unorm8(float v) {
  const float c = v > 0.f ? (v < 1.f ? v : 1.f) : 0.f;
  return static_cast<std::uint8_t>(c * 255.f + 0.5f);
}

}  // namespace sciray
