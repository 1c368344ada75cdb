#pragma once
// Images on disk: PNG through stb (Debian's libstb ships the implementation) and PFM
// for float data. An Image holds float channels with row 0 at the TOP, as files do.
#include <bit>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <stb/stb_image.h>
#include <stb/stb_image_write.h>

#include "sciray/error.hpp"

namespace sciray::io {

struct Image {
  int width = 0, height = 0, channels = 0;
  std::vector<float> pixels;  ///< row-major, top row first, channels interleaved

  float at(int x, int y, int c) const {
    return pixels[(static_cast<std::size_t>(y) * width + x) * channels + c];
  }
};

/// Throws unless the header agrees with the pixel data: writers and comparisons index by
/// the header, so a short pixel vector would otherwise be read past its end.
inline void check_image(const Image& image, const std::string& context) {
  if (image.width <= 0 || image.height <= 0 || image.channels < 1 || image.channels > 4)
    throw Error(context + ": bad image header " + std::to_string(image.width) + "x" +
                std::to_string(image.height) + "x" + std::to_string(image.channels) +
                " (need positive size and 1 to 4 channels)");
  const std::size_t expected = static_cast<std::size_t>(image.width) * image.height * image.channels;
  if (image.pixels.size() != expected)
    throw Error(context + ": image header " + std::to_string(image.width) + "x" +
                std::to_string(image.height) + "x" + std::to_string(image.channels) + " needs " +
                std::to_string(expected) + " values but there are " + std::to_string(image.pixels.size()));
}

inline void write_png(const std::filesystem::path& path, int width, int height, int channels,
                      const std::uint8_t* pixels_top_row_first) {
  if (!stbi_write_png(path.c_str(), width, height, channels, pixels_top_row_first, width * channels))
    throw Error("write_png: cannot write " + path.string());
}

inline Image read_png(const std::filesystem::path& path) {
  int width = 0, height = 0, channels = 0;
  stbi_uc* data = stbi_load(path.c_str(), &width, &height, &channels, 0);
  if (!data) throw Error("read_png: " + path.string() + ": " + stbi_failure_reason());
  Image image{width, height, channels,
              std::vector<float>(static_cast<std::size_t>(width) * height * channels)};
  for (std::size_t i = 0; i < image.pixels.size(); ++i) image.pixels[i] = static_cast<float>(data[i]) / 255.f;
  stbi_image_free(data);
  return image;
}

/// PFM: "PF" (RGB) or "Pf" (grey), little-endian (negative scale), bottom row first.
/// PFM has no alpha: RGBA is written as RGB and grey+alpha as grey.
inline void write_pfm(const std::filesystem::path& path, const Image& image) {
  check_image(image, "write_pfm: " + path.string());
  const int out_channels = image.channels <= 2 ? 1 : 3;
  std::ofstream out(path, std::ios::binary);
  if (!out) throw Error("write_pfm: cannot open " + path.string());
  out << (out_channels == 3 ? "PF" : "Pf") << "\n" << image.width << " " << image.height << "\n-1.0\n";
  std::vector<float> row(static_cast<std::size_t>(image.width) * out_channels);
  for (int y = image.height - 1; y >= 0; --y) {
    for (int x = 0; x < image.width; ++x)
      for (int c = 0; c < out_channels; ++c)
        row[static_cast<std::size_t>(x) * out_channels + c] = image.at(x, y, c);
    out.write(reinterpret_cast<const char*>(row.data()),
              static_cast<std::streamsize>(row.size() * sizeof(float)));
  }
  if (!out) throw Error("write_pfm: error writing " + path.string());
}

inline Image read_pfm(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error("read_pfm: cannot open " + path.string());
  std::string magic;
  int width = 0, height = 0;
  double scale = 0;
  in >> magic;
  if (magic != "PF" && magic != "Pf")
    throw Error("read_pfm: " + path.string() + ": not a PFM file (bad magic)");
  if (!(in >> width >> height) || width <= 0 || height <= 0 || width > (1 << 16) || height > (1 << 16))
    throw Error("read_pfm: " + path.string() + ": bad dimensions");
  if (!(in >> scale) || scale == 0) throw Error("read_pfm: " + path.string() + ": bad scale");
  in.get();  // the single whitespace byte before the data
  const int channels = magic == "PF" ? 3 : 1;
  const std::size_t row_floats = static_cast<std::size_t>(width) * channels;
  // Checked before allocating, so a corrupt header cannot ask for gigabytes.
  const std::size_t data_bytes = row_floats * height * sizeof(float);
  const auto data_start = in.tellg();
  in.seekg(0, std::ios::end);
  const auto available = static_cast<std::size_t>(in.tellg() - data_start);
  if (!in || available < data_bytes)
    throw Error("read_pfm: " + path.string() + ": truncated pixel data (" + std::to_string(width) + "x" +
                std::to_string(height) + "x" + std::to_string(channels) + " needs " +
                std::to_string(data_bytes) + " bytes, the file has " + std::to_string(available) + ")");
  in.seekg(data_start);
  Image image{width, height, channels, std::vector<float>(row_floats * height)};
  const bool swap = (scale > 0) != (std::endian::native == std::endian::big);
  for (int y = height - 1; y >= 0; --y) {
    float* row = image.pixels.data() + static_cast<std::size_t>(y) * row_floats;
    in.read(reinterpret_cast<char*>(row), static_cast<std::streamsize>(row_floats * sizeof(float)));
    if (!in) throw Error("read_pfm: " + path.string() + ": read error in the pixel data");
    if (swap)
      for (std::size_t i = 0; i < row_floats; ++i) {
        std::uint32_t bits;
        std::memcpy(&bits, &row[i], 4);
        bits = __builtin_bswap32(bits);
        std::memcpy(&row[i], &bits, 4);
      }
  }
  return image;
}

inline Image read_image(const std::filesystem::path& path) {
  const auto ext = path.extension();
  if (ext == ".png") return read_png(path);
  if (ext == ".pfm") return read_pfm(path);
  throw Error("read_image: " + path.string() + ": unknown extension (expected .png or .pfm)");
}

inline void write_image(const std::filesystem::path& path, const Image& image) {
  const auto ext = path.extension();
  if (ext == ".pfm") return write_pfm(path, image);
  if (ext != ".png")
    throw Error("write_image: " + path.string() + ": unknown extension (expected .png or .pfm)");
  check_image(image, "write_image: " + path.string());
  std::vector<std::uint8_t> bytes(image.pixels.size());
  for (std::size_t i = 0; i < bytes.size(); ++i) {
    const float v = image.pixels[i] > 0.f ? (image.pixels[i] < 1.f ? image.pixels[i] : 1.f) : 0.f;
    bytes[i] = static_cast<std::uint8_t>(v * 255.f + 0.5f);
  }
  write_png(path, image.width, image.height, image.channels, bytes.data());
}

}  // namespace sciray::io
