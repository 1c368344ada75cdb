#pragma once
// The frame buffer: a colour channel in the format the application asks for (RGBA8,
// SRGBA or RGBA32F), depth as Euclidean distance and as projected view depth, and an
// accumulation channel that averages successive frames. Rows are stored bottom-up, as
// OSPRay maps them (row 0 is the bottom of the image).
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "sciray/error.hpp"
#include "sciray/math/color.hpp"

namespace sciray {

enum class ColorFormat { none, rgba8, srgba, rgba32f };

/// Channel flags beyond colour.
enum Channel : unsigned {
  channel_color = 1u << 0,
  channel_depth = 1u << 1,  ///< Euclidean distance from the camera and projected depth
  channel_accum = 1u << 2,  ///< average successive frames
};

namespace detail {
/// sRGB encoding through a table indexed by the linear value quantized to 16 bits:
/// a std::pow per channel would cost as much as tracing the ray.
inline const std::array<std::uint8_t, 65536>& srgb_table() {
  static const auto table = [] {
    std::array<std::uint8_t, 65536> t{};
    for (std::size_t i = 0; i < t.size(); ++i) t[i] = to_unorm8(linear_to_srgb(static_cast<float>(i) / 65535.f));
    return t;
  }();
  return table;
}
}  // namespace detail

class FrameBuffer {
public:
  FrameBuffer(int width, int height, ColorFormat format = ColorFormat::srgba,
              unsigned channels = channel_color | channel_depth | channel_accum)
      : width_(width), height_(height), format_(format), channels_(channels) {
    if (width <= 0 || height <= 0 || width > 65536 || height > 65536)
      throw Error("framebuffer: size " + std::to_string(width) + "x" + std::to_string(height) +
                  " must be positive and at most 65536x65536");
    if (format == ColorFormat::none) channels_ &= ~unsigned(channel_color);
    const std::size_t n = pixel_count();
    if (channels_ & channel_accum) accum_.assign(4 * n, 0.f);
    if (format == ColorFormat::rgba8 || format == ColorFormat::srgba) color8_.assign(4 * n, 0);
    if (format == ColorFormat::rgba32f) color32_.assign(4 * n, 0.f);
    if (channels_ & channel_depth) {
      depth_.assign(n, std::numeric_limits<float>::infinity());
      depth_projected_.assign(n, std::numeric_limits<float>::infinity());
    }
    if (format == ColorFormat::srgba) detail::srgb_table();
  }

  int width() const { return width_; }
  int height() const { return height_; }
  std::size_t pixel_count() const { return static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_); }
  ColorFormat format() const { return format_; }
  bool has(Channel c) const { return (channels_ & c) != 0; }

  /// Frames averaged into the colour so far (the next frame's index).
  std::uint32_t accumulated_frames() const { return frames_; }
  void reset_accumulation() { frames_ = 0; }

  /// Called by the renderer after every pixel of a frame is written.
  void finish_frame() { frames_ = has(channel_accum) ? frames_ + 1 : 1; }

  /// Stores one pixel's sample of the frame being rendered (frame index
  /// accumulated_frames()) and updates the colour channel. Each pixel is written by one
  /// thread per frame, so no synchronisation is needed and results do not depend on
  /// the thread count.
  void write_sample(std::size_t pixel, float r, float g, float b, float a, float depth, float depth_projected) {
    if (has(channel_accum)) {
      float* acc = &accum_[4 * pixel];
      if (frames_ == 0) {
        acc[0] = r, acc[1] = g, acc[2] = b, acc[3] = a;
      } else {
        acc[0] += r, acc[1] += g, acc[2] += b, acc[3] += a;
      }
      const float inv = 1.f / static_cast<float>(frames_ + 1);
      r = acc[0] * inv, g = acc[1] * inv, b = acc[2] * inv, a = acc[3] * inv;
    }
    if (has(channel_depth)) {
      depth_[pixel] = depth;
      depth_projected_[pixel] = depth_projected;
    }
    switch (format_) {
      case ColorFormat::rgba8: {
        std::uint8_t* c = &color8_[4 * pixel];
        c[0] = to_unorm8(r), c[1] = to_unorm8(g), c[2] = to_unorm8(b), c[3] = to_unorm8(a);
        break;
      }
      case ColorFormat::srgba: {
        const auto& table = detail::srgb_table();
        std::uint8_t* c = &color8_[4 * pixel];
        c[0] = table[quantize16(r)], c[1] = table[quantize16(g)], c[2] = table[quantize16(b)];
        c[3] = to_unorm8(a);  // alpha stays linear
        break;
      }
      case ColorFormat::rgba32f: {
        float* c = &color32_[4 * pixel];
        c[0] = r, c[1] = g, c[2] = b, c[3] = a;
        break;
      }
      case ColorFormat::none: break;
    }
  }

  /// RGBA8 or SRGBA bytes, bottom row first. Empty for other formats.
  const std::vector<std::uint8_t>& color8() const { return color8_; }
  /// RGBA32F values, bottom row first. Empty for other formats.
  const std::vector<float>& color32f() const { return color32_; }
  /// Euclidean distance from the camera to the hit (inf where nothing was hit).
  const std::vector<float>& depth() const { return depth_; }
  /// Distance along the camera's view direction (as a z-buffer holds).
  const std::vector<float>& depth_projected() const { return depth_projected_; }
  /// Sum of the frames' RGBA (divide by accumulated_frames()).
  const std::vector<float>& accum() const { return accum_; }

  /// Bytes of all channels.
  std::size_t memory_bytes() const {
    return color8_.size() + sizeof(float) * (color32_.size() + depth_.size() + depth_projected_.size() + accum_.size());
  }

private:
  static std::size_t quantize16(float linear) {
    const float c = linear > 0.f ? (linear < 1.f ? linear : 1.f) : 0.f;  // NaN maps to 0
    return static_cast<std::size_t>(c * 65535.f + 0.5f);
  }

  int width_, height_;
  ColorFormat format_;
  unsigned channels_;
  std::uint32_t frames_ = 0;
  std::vector<float> accum_;
  std::vector<std::uint8_t> color8_;
  std::vector<float> color32_;
  std::vector<float> depth_;
  std::vector<float> depth_projected_;
};

}  // namespace sciray
