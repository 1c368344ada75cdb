#pragma once
// Writing a frame buffer's channels to files: colour to PNG (8-bit formats) or PFM
// (float), depth to PFM. Frame buffers are bottom-up; image files are top-down.
#include <filesystem>
#include <string>

#include "sciray/frame/framebuffer.hpp"
#include "sciray/io/image.hpp"

namespace sciray::io {

/// The colour channel as a top-down RGBA float image (values as stored: sRGB-encoded
/// for SRGBA, linear otherwise).
inline Image color_image(const FrameBuffer& fb) {
  Image image{fb.width(), fb.height(), 4, std::vector<float>(4 * fb.pixel_count())};
  for (int y = 0; y < fb.height(); ++y) {
    const std::size_t src = 4 * static_cast<std::size_t>(fb.height() - 1 - y) * fb.width();
    const std::size_t dst = 4 * static_cast<std::size_t>(y) * fb.width();
    for (std::size_t i = 0; i < 4 * static_cast<std::size_t>(fb.width()); ++i)
      image.pixels[dst + i] = fb.format() == ColorFormat::rgba32f ? fb.color32f()[src + i]
                                                                   : static_cast<float>(fb.color8()[src + i]) / 255.f;
  }
  return image;
}

/// Writes the colour channel: .png needs an 8-bit format, .pfm a float one.
inline void write_color(const FrameBuffer& fb, const std::filesystem::path& path) {
  const std::string ext = path.extension().string();
  if (ext == ".png") {
    if (fb.format() != ColorFormat::rgba8 && fb.format() != ColorFormat::srgba && fb.format() != ColorFormat::gamma22)
      throw Error("write_color: " + path.string() + ": PNG needs an RGBA8 or SRGBA frame buffer");
    std::vector<std::uint8_t> rows(fb.color8().size());
    const std::size_t row_bytes = 4 * static_cast<std::size_t>(fb.width());
    for (int y = 0; y < fb.height(); ++y)
      std::copy_n(fb.color8().begin() + static_cast<std::ptrdiff_t>((fb.height() - 1 - y) * row_bytes), row_bytes,
                  rows.begin() + static_cast<std::ptrdiff_t>(y * row_bytes));
    write_png(path, fb.width(), fb.height(), 4, rows.data());
  } else if (ext == ".pfm") {
    if (fb.format() != ColorFormat::rgba32f)
      throw Error("write_color: " + path.string() + ": PFM needs an RGBA32F frame buffer");
    write_pfm(path, color_image(fb));
  } else {
    throw Error("write_color: " + path.string() + ": unknown image extension (expected .png or .pfm)");
  }
}

/// Writes the Euclidean depth channel as a one-channel PFM (inf where nothing was hit).
inline void write_depth(const FrameBuffer& fb, const std::filesystem::path& path) {
  if (!fb.has(channel_depth)) throw Error("write_depth: the frame buffer has no depth channel");
  Image image{fb.width(), fb.height(), 1, std::vector<float>(fb.pixel_count())};
  for (int y = 0; y < fb.height(); ++y)
    std::copy_n(fb.depth().begin() + static_cast<std::ptrdiff_t>(fb.height() - 1 - y) * fb.width(), fb.width(),
                image.pixels.begin() + static_cast<std::ptrdiff_t>(y) * fb.width());
  write_pfm(path, image);
}

}  // namespace sciray::io
