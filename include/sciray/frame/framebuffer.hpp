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
#include "sciray/math/vec.hpp"
#include "sciray/simd/packet.hpp"

namespace sciray {

enum class ColorFormat { none, rgba8, srgba, rgba32f };

/// Channel flags beyond colour.
enum Channel : unsigned {
  channel_color = 1u << 0,
  channel_depth = 1u << 1,  ///< Euclidean distance from the camera and projected depth
  channel_accum = 1u << 2,  ///< average successive frames
  channel_variance = 1u << 3,  ///< estimate the error of the average (needs accum)
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
    // Pixels are addressed with 32-bit lane indices.
    if (width <= 0 || height <= 0 ||
        static_cast<std::size_t>(width) * static_cast<std::size_t>(height) > std::size_t{INT32_MAX})
      throw Error("framebuffer: size " + std::to_string(width) + "x" + std::to_string(height) +
                  " must be positive with fewer than 2^31 pixels");
    if (format == ColorFormat::none) channels_ &= ~unsigned(channel_color);
    const std::size_t n = pixel_count();
    if (channels_ & channel_accum) accum_.assign(4 * n, 0.f);
    if (!(channels_ & channel_accum)) channels_ &= ~unsigned(channel_variance);
    if (channels_ & channel_variance) odd_luminance_.assign(n, 0.f);
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

  /// Stores a packet of samples of the frame being rendered (frame index
  /// accumulated_frames()); lane i goes to pixel `pixel[i]`, or nowhere if it is
  /// negative. Each pixel is written by one thread per frame, so no synchronisation is
  /// needed and results do not depend on the thread count.
  template <class Arch>
  void write_packet(const std::int32_t* pixel, const Vec3<simd::Float<Arch>>& color, const simd::Float<Arch>& alpha,
                    const simd::Float<Arch>& depth, const simd::Float<Arch>& depth_projected) {
    using F = simd::Float<Arch>;
    constexpr int W = simd::width<Arch>;
    alignas(64) float rgba[4][W];
    simd::store<Arch>(rgba[0], color.x);
    simd::store<Arch>(rgba[1], color.y);
    simd::store<Arch>(rgba[2], color.z);
    simd::store<Arch>(rgba[3], alpha);
    if (has(channel_depth)) {
      alignas(64) float t[W], tz[W];
      simd::store<Arch>(t, depth);
      simd::store<Arch>(tz, depth_projected);
      for (int i = 0; i < W; ++i)
        if (pixel[i] >= 0) depth_[pixel[i]] = t[i], depth_projected_[pixel[i]] = tz[i];
    }
    if (has(channel_accum)) {
      const float inv = 1.f / static_cast<float>(frames_ + 1);
      const bool odd_frame = frames_ % 2 == 1;
      for (int i = 0; i < W; ++i) {
        if (pixel[i] < 0) continue;
        if (!odd_luminance_.empty()) {
          float& odd = odd_luminance_[static_cast<std::size_t>(pixel[i])];
          if (frames_ == 0) odd = 0.f;
          if (odd_frame) odd += luminance(rgba[0][i], rgba[1][i], rgba[2][i]);
        }
        float* acc = &accum_[4 * static_cast<std::size_t>(pixel[i])];
        for (int c = 0; c < 4; ++c) {
          acc[c] = frames_ == 0 ? rgba[c][i] : acc[c] + rgba[c][i];
          rgba[c][i] = acc[c] * inv;
        }
      }
    }
    if (format_ == ColorFormat::rgba32f) {
      for (int i = 0; i < W; ++i)
        if (pixel[i] >= 0)
          for (int c = 0; c < 4; ++c) color32_[4 * static_cast<std::size_t>(pixel[i]) + c] = rgba[c][i];
      return;
    }
    if (format_ == ColorFormat::none) return;
    // 8-bit formats: quantize all lanes at once, then look up / store per pixel. Alpha
    // stays linear; colour is sRGB-encoded through a table for SRGBA.
    const bool srgb = format_ == ColorFormat::srgba;
    const F scale(srgb ? 65535.f : 255.f);
    alignas(64) std::int32_t q[4][W];
    for (int c = 0; c < 4; ++c) {
      const F v = simd::load<Arch>(rgba[c]);
      // max/min order maps NaN to 0, and the +0.5 with truncation rounds to nearest.
      const F clamped = simd::min(simd::max(v, F(0.f)), F(1.f));
      simd::store<Arch>(q[c], simd::to_int(clamped * (c == 3 ? F(255.f) : scale) + F(0.5f)));
    }
    const auto& table = detail::srgb_table();
    for (int i = 0; i < W; ++i) {
      if (pixel[i] < 0) continue;
      std::uint8_t* out = &color8_[4 * static_cast<std::size_t>(pixel[i])];
      for (int c = 0; c < 3; ++c) out[c] = srgb ? table[static_cast<std::size_t>(q[c][i])] : static_cast<std::uint8_t>(q[c][i]);
      out[3] = static_cast<std::uint8_t>(q[3][i]);
    }
  }

  /// An estimate of the error left in the accumulated colour: the mean absolute luminance
  /// difference between the average of all frames and the average of the odd frames,
  /// which for independent frames shrinks as 1/sqrt(frames). Infinite before two frames
  /// or without a variance channel (as OSPRay reports).
  float variance() const {
    if (odd_luminance_.empty() || frames_ < 2) return std::numeric_limits<float>::infinity();
    const float odd_frames = static_cast<float>(frames_ / 2);
    double sum = 0.0;
    for (std::size_t p = 0; p < odd_luminance_.size(); ++p) {
      const float* acc = &accum_[4 * p];
      const float mean = luminance(acc[0], acc[1], acc[2]) / static_cast<float>(frames_);
      sum += std::abs(mean - odd_luminance_[p] / odd_frames);
    }
    return static_cast<float>(sum / static_cast<double>(odd_luminance_.size()));
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
    return color8_.size() + sizeof(float) * (color32_.size() + depth_.size() + depth_projected_.size() +
                                             accum_.size() + odd_luminance_.size());
  }

private:
  int width_, height_;
  ColorFormat format_;
  unsigned channels_;
  std::uint32_t frames_ = 0;
  static float luminance(float r, float g, float b) { return 0.2126f * r + 0.7152f * g + 0.0722f * b; }

  std::vector<float> accum_;
  std::vector<float> odd_luminance_;  // sum over odd frames, for the variance estimate
  std::vector<std::uint8_t> color8_;
  std::vector<float> color32_;
  std::vector<float> depth_;
  std::vector<float> depth_projected_;
};

}  // namespace sciray
