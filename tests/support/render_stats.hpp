#pragma once
// Rendering through the compiled shim for the best ISA into RGBA32F frame buffers that
// accumulate, and the statistics the renderer tests take of the images: a frame's own
// image is the difference of the accumulation before and after it, so statistics come
// from independent batches of samples.
#include <algorithm>
#include <cmath>
#include <numeric>
#include <vector>

#include "sciray/shim/engine.hpp"

namespace sciray::test_support {

inline const shim::IsaKernels& kernels() { return shim::kernels(shim::select_isa()); }

/// A world with the device it lives on (neither may move once built).
struct TestWorld {
  accel::Device device;
  shim::EngineWorld world{device};
};

/// Linear RGB, one pixel after another in the frame buffer's order (bottom row first).
struct Image {
  int width = 0, height = 0;
  std::vector<double> rgb;

  double at(int x, int y, int c) const { return rgb[3 * (static_cast<std::size_t>(y) * width + x) + c]; }
  double luminance(std::size_t p) const { return 0.2126 * rgb[3 * p] + 0.7152 * rgb[3 * p + 1] + 0.0722 * rgb[3 * p + 2]; }
  double mean_luminance() const {
    double sum = 0;
    for (std::size_t p = 0; p < pixels(); ++p) sum += luminance(p);
    return sum / static_cast<double>(pixels());
  }
  std::size_t pixels() const { return static_cast<std::size_t>(width) * height; }
};

/// Renders `frames` frames after `skip` frames (whose samples are then used by no
/// returned image) and returns each frame's own image.
inline std::vector<Image> render_frames(const shim::EngineWorld& world, const shim::RendererConfig& config,
                                 const Camera& camera, int width, int height, int frames,
                                 const FrameSettings& settings = {}, int skip = 0) {
  FrameBuffer fb(width, height, ColorFormat::rgba32f, channel_color | channel_accum);
  const auto& k = kernels();
  for (int f = 0; f < skip; ++f) k.render(world, config, camera, fb, nullptr, settings);
  std::vector<double> before = fb.accum();
  if (before.empty()) before.assign(4 * fb.pixel_count(), 0.f);
  if (skip == 0) std::fill(before.begin(), before.end(), 0.f);
  std::vector<Image> images;
  for (int f = 0; f < frames; ++f) {
    k.render(world, config, camera, fb, nullptr, settings);
    Image image{width, height, std::vector<double>(3 * fb.pixel_count())};
    const std::vector<double>& after = fb.accum();
    for (std::size_t p = 0; p < fb.pixel_count(); ++p)
      for (int c = 0; c < 3; ++c)
        image.rgb[3 * p + c] = static_cast<double>(after[4 * p + c]) - static_cast<double>(before[4 * p + c]);
    before = after;
    images.push_back(std::move(image));
  }
  return images;
}

inline Image average(const std::vector<Image>& images, std::size_t first = 0, std::size_t count = 0) {
  if (count == 0) count = images.size() - first;
  Image out{images[first].width, images[first].height, std::vector<double>(images[first].rgb.size(), 0.0)};
  for (std::size_t i = first; i < first + count; ++i)
    for (std::size_t k = 0; k < out.rgb.size(); ++k) out.rgb[k] += images[i].rgb[k];
  for (double& v : out.rgb) v /= static_cast<double>(count);
  return out;
}

inline Image render(const shim::EngineWorld& world, const shim::RendererConfig& config, const Camera& camera, int width,
             int height, int frames = 1, const FrameSettings& settings = {}, int skip = 0) {
  return average(render_frames(world, config, camera, width, height, frames, settings, skip));
}

/// Mean and standard error of the mean of independent values.
struct Stats {
  double mean, stderr_;
};
inline Stats stats(const std::vector<double>& values) {
  const double n = static_cast<double>(values.size());
  const double mean = std::accumulate(values.begin(), values.end(), 0.0) / n;
  double ss = 0;
  for (double v : values) ss += (v - mean) * (v - mean);
  return {mean, std::sqrt(ss / (n - 1) / n)};
}

/// Mean luminance of each batch, the batches' mean and its standard error.
inline Stats luminance_stats(const std::vector<Image>& batches) {
  std::vector<double> means;
  for (const Image& b : batches) means.push_back(b.mean_luminance());
  return stats(means);
}

/// RMSE over the colour channels of the pixels with x in [x0, x1) of a and x + dx of b.
inline double rmse(const Image& a, const Image& b, int x0 = 0, int x1 = -1, int dx = 0) {
  if (x1 < 0) x1 = a.width;
  double sum = 0;
  std::size_t n = 0;
  for (int y = 0; y < a.height; ++y)
    for (int x = x0; x < x1; ++x)
      for (int c = 0; c < 3; ++c) {
        const double d = a.at(x, y, c) - b.at(x + dx, y, c);
        sum += d * d, ++n;
      }
  return std::sqrt(sum / static_cast<double>(n));
}

/// Least-squares slope of log(error) over log(spp).
inline double loglog_slope(const std::vector<double>& spp, const std::vector<double>& error) {
  const std::size_t n = spp.size();
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double x = std::log(spp[i]), y = std::log(error[i]);
    sx += x, sy += y, sxx += x * x, sxy += x * y;
  }
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

}  // namespace sciray::test_support
