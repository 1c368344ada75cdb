// Image files (PNG, PFM) and the image-difference metrics that every image test relies on.
#include <catch2/catch.hpp>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "sciray/io/image.hpp"
#include "sciray/testing/image_compare.hpp"

using sciray::Error;
using sciray::io::Image;
namespace io = sciray::io;
namespace testing = sciray::testing;

namespace {

std::filesystem::path scratch(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / "sciray_image_test";
  std::filesystem::create_directories(dir);
  return dir / name;
}

void write_bytes(const std::filesystem::path& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  REQUIRE(out);
}

std::string read_bytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

Image constant_image(int width, int height, int channels, float value) {
  return {width, height, channels,
          std::vector<float>(static_cast<std::size_t>(width) * height * channels, value)};
}

/// Every value distinct, so a swapped row, column or channel shows up.
Image ramp_image(int width, int height, int channels) {
  Image image = constant_image(width, height, channels, 0.f);
  for (std::size_t i = 0; i < image.pixels.size(); ++i) image.pixels[i] = 0.25f * static_cast<float>(i) - 3.f;
  return image;
}

}  // namespace

TEST_CASE("PNG round trip is exact for 8-bit data", "[image][png]") {
  for (int channels : {1, 3, 4}) {
    const int width = 7, height = 5;  // odd width: no row padding assumptions
    std::vector<std::uint8_t> bytes(static_cast<std::size_t>(width) * height * channels);
    for (std::size_t i = 0; i < bytes.size(); ++i) bytes[i] = static_cast<std::uint8_t>(i * 37 % 256);
    const auto path = scratch("round_trip_" + std::to_string(channels) + ".png");
    io::write_png(path, width, height, channels, bytes.data());

    const Image image = io::read_png(path);
    REQUIRE(image.width == width);
    REQUIRE(image.height == height);
    REQUIRE(image.channels == channels);
    REQUIRE(image.pixels.size() == bytes.size());
    for (std::size_t i = 0; i < bytes.size(); ++i)
      REQUIRE(image.pixels[i] * 255.f == static_cast<float>(bytes[i]));

    // write_image quantizes k/255 back to k, so the float path is exact too.
    const auto again = scratch("round_trip_again_" + std::to_string(channels) + ".png");
    io::write_image(again, image);
    CHECK(io::read_image(again).pixels == image.pixels);
  }
}

TEST_CASE("PNG writing clamps out-of-range values", "[image][png]") {
  const Image image{3, 1, 1, {-0.5f, 0.5f, 1.5f}};
  const auto path = scratch("clamped.png");
  io::write_image(path, image);
  CHECK(io::read_png(path).pixels == std::vector<float>{0.f, 128.f / 255.f, 1.f});
}

TEST_CASE("PFM round trip is exact for floats", "[image][pfm]") {
  for (int channels : {1, 3}) {
    Image image = ramp_image(5, 4, channels);
    image.pixels[1] = std::numeric_limits<float>::infinity();  // depth images store inf for misses
    image.pixels[2] = 1e-38f;
    const auto path = scratch("round_trip_" + std::to_string(channels) + ".pfm");
    io::write_image(path, image);
    const Image back = io::read_image(path);
    CHECK(back.width == image.width);
    CHECK(back.height == image.height);
    CHECK(back.channels == channels);
    CHECK(back.pixels == image.pixels);
  }
}

TEST_CASE("PFM drops alpha: RGBA is written as RGB", "[image][pfm]") {
  const Image rgba = ramp_image(3, 2, 4);
  const auto path = scratch("rgba.pfm");
  io::write_pfm(path, rgba);
  const Image rgb = io::read_pfm(path);
  REQUIRE(rgb.channels == 3);
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 3; ++x)
      for (int c = 0; c < 3; ++c) CHECK(rgb.at(x, y, c) == rgba.at(x, y, c));
}

TEST_CASE("PFM stores the bottom row first, Image keeps the top row first", "[image][pfm]") {
  const int width = 2, height = 3;
  Image gradient = constant_image(width, height, 1, 0.f);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      gradient.pixels[static_cast<std::size_t>(y) * width + x] = static_cast<float>(y);
  const auto path = scratch("gradient.pfm");
  io::write_pfm(path, gradient);

  const std::string header = "Pf\n2 3\n-1.0\n";
  const std::string file = read_bytes(path);
  REQUIRE(file.substr(0, header.size()) == header);
  REQUIRE(file.size() == header.size() + width * height * sizeof(float));
  float first_in_file;
  std::memcpy(&first_in_file, file.data() + header.size(), sizeof(float));
  CHECK(first_in_file == height - 1);  // the bottom row

  const Image back = io::read_pfm(path);
  CHECK(back.at(0, 0, 0) == 0.f);  // the top row
  CHECK(back.at(1, height - 1, 0) == height - 1);
}

TEST_CASE("PFM with a positive scale is big-endian and is byte-swapped", "[image][pfm]") {
  const std::vector<float> values{1.5f, -2.25f};
  std::string file = "Pf\n2 1\n1.0\n";
  for (float v : values) {
    std::uint32_t bits;
    std::memcpy(&bits, &v, sizeof bits);
    for (int shift = 24; shift >= 0; shift -= 8) file += static_cast<char>((bits >> shift) & 0xff);
  }
  const auto path = scratch("big_endian.pfm");
  write_bytes(path, file);
  CHECK(io::read_pfm(path).pixels == values);
}

TEST_CASE("bad image files are rejected with a message naming the problem", "[image][errors]") {
  const auto truncated = scratch("truncated.pfm");
  write_bytes(truncated, "PF\n4 4\n-1.0\n" + std::string(20, '\0'));
  CHECK_THROWS_AS(io::read_pfm(truncated), Error);
  CHECK_THROWS_WITH(io::read_pfm(truncated),
                    Catch::Contains("truncated") && Catch::Contains("truncated.pfm"));

  const auto text = scratch("not_an_image.png");
  write_bytes(text, "this is a text file, not an image\n");
  CHECK_THROWS_WITH(io::read_png(text),
                    Catch::Contains("not_an_image.png") && Catch::Contains("unknown image type"));
  CHECK_THROWS_WITH(io::read_pfm(text), Catch::Contains("bad magic"));

  const auto bad_dims = scratch("bad_dims.pfm");
  write_bytes(bad_dims, "PF\n-4 4\n-1.0\n");
  CHECK_THROWS_WITH(io::read_pfm(bad_dims), Catch::Contains("bad dimensions"));

  CHECK_THROWS_WITH(io::read_image(scratch("picture.bmp")), Catch::Contains("unknown extension"));
  CHECK_THROWS_WITH(io::read_pfm(scratch("missing.pfm")), Catch::Contains("cannot open"));
  // A header that promises more pixels than the vector holds must not be written.
  CHECK_THROWS_WITH(io::write_image(scratch("short.pfm"), Image{4, 4, 3, std::vector<float>(5)}),
                    Catch::Contains("needs 48 values but there are 5"));
}

TEST_CASE("compare_images: identical images", "[image][compare]") {
  const Image image = ramp_image(16, 16, 3);
  const auto diff = testing::compare_images(image, image);
  CHECK(diff.rmse == 0);
  CHECK(diff.psnr_db == std::numeric_limits<double>::infinity());
  CHECK(diff.max_abs == 0);
  CHECK(diff.local_mean_error_max == 0);
  CHECK(diff.differing_pixels == 0);
}

TEST_CASE("compare_images: constant offset of 0.1 is 20 dB", "[image][compare]") {
  const auto diff =
      testing::compare_images(constant_image(32, 24, 3, 0.6f), constant_image(32, 24, 3, 0.5f), 0.05);
  INFO(testing::describe(diff));
  CHECK(diff.rmse == Approx(0.1).epsilon(1e-5));
  CHECK(diff.psnr_db == Approx(20.0).epsilon(1e-5));
  CHECK(diff.mean_abs == Approx(0.1).epsilon(1e-5));
  CHECK(diff.max_abs == Approx(0.1).epsilon(1e-5));
  CHECK(diff.local_mean_error_max == Approx(0.1).epsilon(1e-5));
  CHECK(diff.differing_pixels == 32 * 24);
}

TEST_CASE("compare_images: one wrong 8x8 block hides in the RMSE but not in the local metric",
          "[image][compare]") {
  const Image reference = constant_image(256, 256, 3, 0.25f);
  Image test = reference;
  for (int y = 40; y < 48; ++y)  // block-aligned, so exactly one window sees all of it
    for (int x = 96; x < 104; ++x)
      for (int c = 0; c < 3; ++c) test.pixels[(static_cast<std::size_t>(y) * 256 + x) * 3 + c] += 0.5f;

  const auto diff = testing::compare_images(test, reference, 0.01);
  INFO(testing::describe(diff));
  CHECK(diff.rmse < 0.02);
  CHECK(diff.local_mean_error_max == Approx(0.5));
  CHECK(diff.differing_pixels == 64);

  const Image difference = testing::difference_image(test, reference);
  CHECK(difference.at(96, 40, 1) == Approx(0.5f));
  CHECK(difference.at(0, 0, 0) == 0.f);
}

TEST_CASE("compare_images: mismatched sizes throw naming both", "[image][compare]") {
  CHECK_THROWS_WITH(testing::compare_images(constant_image(8, 4, 3, 0.f), constant_image(4, 8, 3, 0.f)),
                    Catch::Contains("8x4x3") && Catch::Contains("4x8x3"));
  CHECK_THROWS_AS(testing::compare_images(constant_image(8, 8, 3, 0.f), constant_image(8, 8, 4, 0.f)), Error);
  CHECK_THROWS_AS(testing::difference_image(constant_image(8, 8, 1, 0.f), constant_image(8, 9, 1, 0.f)),
                  Error);
}
