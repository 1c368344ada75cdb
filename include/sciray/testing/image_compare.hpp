#pragma once
// Image differences for image tests. A global RMSE dilutes a small wrong region, so
// there is also the largest mean error over small windows, in the style of OSPRay's
// regression tests: a test states a bound on both.
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "sciray/io/image.hpp"

namespace sciray::testing {

struct ImageDifference {
  double rmse = 0;                   ///< over all channel values
  double psnr_db = 0;                ///< peak 1.0; infinite for identical images
  double max_abs = 0;                ///< largest channel difference
  double mean_abs = 0;               ///< mean channel difference
  double local_mean_error_max = 0;   ///< largest mean per-pixel error over window x window blocks
  std::size_t differing_pixels = 0;  ///< pixels whose largest channel difference exceeds the threshold
};

inline void check_same_size(const io::Image& test, const io::Image& reference, const std::string& context) {
  io::check_image(test, context + ": test image");
  io::check_image(reference, context + ": reference image");
  if (test.width != reference.width || test.height != reference.height || test.channels != reference.channels)
    throw Error(context + ": image is " + std::to_string(test.width) + "x" + std::to_string(test.height) +
                "x" + std::to_string(test.channels) + " but the reference is " +
                std::to_string(reference.width) + "x" + std::to_string(reference.height) + "x" +
                std::to_string(reference.channels));
}

inline ImageDifference compare_images(const io::Image& test, const io::Image& reference,
                                      double pixel_threshold = 0.0, int window = 8) {
  check_same_size(test, reference, "compare_images");
  if (window < 1) throw Error("compare_images: window is " + std::to_string(window) + ", must be at least 1");
  ImageDifference d;
  const int w = test.width, h = test.height, c = test.channels;
  const int blocks_x = (w + window - 1) / window, blocks_y = (h + window - 1) / window;
  std::vector<double> block_sum(static_cast<std::size_t>(blocks_x) * blocks_y, 0.0);
  std::vector<int> block_count(block_sum.size(), 0);
  double squared = 0, absolute = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      double pixel_sum = 0, pixel_max = 0;
      for (int k = 0; k < c; ++k) {
        const double e = std::abs(static_cast<double>(test.at(x, y, k)) - reference.at(x, y, k));
        squared += e * e;
        absolute += e;
        pixel_sum += e;
        pixel_max = std::max(pixel_max, e);
      }
      d.max_abs = std::max(d.max_abs, pixel_max);
      d.differing_pixels += pixel_max > pixel_threshold;
      const std::size_t block = static_cast<std::size_t>(y / window) * blocks_x + x / window;
      block_sum[block] += pixel_sum / c;
      ++block_count[block];
    }
  const double n = static_cast<double>(test.pixels.size());
  d.rmse = std::sqrt(squared / n);
  d.mean_abs = absolute / n;
  d.psnr_db = d.rmse == 0 ? std::numeric_limits<double>::infinity() : -20.0 * std::log10(d.rmse);
  for (std::size_t b = 0; b < block_sum.size(); ++b)
    d.local_mean_error_max = std::max(d.local_mean_error_max, block_sum[b] / block_count[b]);
  return d;
}

inline io::Image difference_image(const io::Image& a, const io::Image& b) {
  check_same_size(a, b, "difference_image");
  io::Image diff = a;
  for (std::size_t i = 0; i < diff.pixels.size(); ++i) diff.pixels[i] = std::abs(a.pixels[i] - b.pixels[i]);
  return diff;
}

inline std::string describe(const ImageDifference& d) {
  std::ostringstream s;
  s << "rmse " << d.rmse << ", psnr " << d.psnr_db << " dB, max " << d.max_abs << ", mean " << d.mean_abs
    << ", worst window mean " << d.local_mean_error_max << ", " << d.differing_pixels
    << " pixels over threshold";
  return s.str();
}

}  // namespace sciray::testing
