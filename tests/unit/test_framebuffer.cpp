// Frame buffer formats, accumulation arithmetic and limits, through the scalar path.
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

#include "sciray/frame/framebuffer.hpp"

using namespace sciray;

namespace {
void write(FrameBuffer& fb, std::int32_t pixel, Vec3f color, float alpha, float depth = 1.f) {
  fb.write_packet<simd::scalar>(&pixel, color, alpha, depth, depth);
}
}  // namespace

TEST_CASE("colour formats encode as documented", "[frame]") {
  FrameBuffer linear(2, 1, ColorFormat::rgba8, channel_color);
  FrameBuffer srgb(2, 1, ColorFormat::srgba, channel_color);
  FrameBuffer floats(2, 1, ColorFormat::rgba32f, channel_color);
  for (FrameBuffer* fb : {&linear, &srgb, &floats}) {
    write(*fb, 0, {0.5f, 0.214041f, 2.f}, 0.5f);
    write(*fb, 1, {std::nanf(""), -1.f, 0.f}, 1.f);
    fb->finish_frame();
  }
  CHECK(linear.color8()[0] == 128);
  CHECK(linear.color8()[1] == 55);
  CHECK(linear.color8()[2] == 255);  // clamped
  CHECK(linear.color8()[3] == 128);
  // The sRGB table quantizes linear values to 16 bits first: within 1 of exact encoding.
  CHECK(std::abs(srgb.color8()[0] - to_unorm8(linear_to_srgb(0.5f))) <= 1);
  CHECK(std::abs(srgb.color8()[1] - 128) <= 1);  // sRGB(0.214) = 0.5
  CHECK(srgb.color8()[3] == 128);  // alpha stays linear
  CHECK(srgb.color8()[4] == 0);    // NaN and negative become 0
  CHECK(srgb.color8()[5] == 0);
  CHECK(floats.color32f()[0] == 0.5f);
  CHECK(floats.color32f()[2] == 2.f);  // float output keeps the range
  CHECK(linear.depth().empty());
}

TEST_CASE("accumulation is the running mean of frames", "[frame]") {
  FrameBuffer fb(1, 1, ColorFormat::rgba32f);
  const float samples[] = {0.2f, 0.6f, 0.1f, 0.9f};
  float sum = 0.f;
  for (int f = 0; f < 4; ++f) {
    CHECK(fb.accumulated_frames() == static_cast<std::uint32_t>(f));
    write(fb, 0, {samples[f], 0.f, 0.f}, 1.f, 10.f + f);
    fb.finish_frame();
    sum += samples[f];
    CHECK(fb.color32f()[0] == Approx(sum / (f + 1)));
    CHECK(fb.depth()[0] == 10.f + f);  // depth is the latest frame's
  }
  fb.reset_accumulation();
  write(fb, 0, {0.3f, 0.f, 0.f}, 1.f);
  fb.finish_frame();
  CHECK(fb.color32f()[0] == 0.3f);
  CHECK(fb.accumulated_frames() == 1);
}

TEST_CASE("without an accum channel every frame replaces the last", "[frame]") {
  FrameBuffer fb(1, 1, ColorFormat::rgba32f, channel_color);
  write(fb, 0, {0.2f, 0.f, 0.f}, 1.f);
  fb.finish_frame();
  write(fb, 0, {0.6f, 0.f, 0.f}, 1.f);
  fb.finish_frame();
  CHECK(fb.color32f()[0] == 0.6f);
  CHECK(fb.accum().empty());
}

TEST_CASE("lanes with a negative pixel index write nothing", "[frame]") {
  FrameBuffer fb(1, 1, ColorFormat::rgba8);
  write(fb, -1, {1.f, 1.f, 1.f}, 1.f);
  CHECK(fb.color8()[0] == 0);
  CHECK(std::isinf(fb.depth()[0]));
}

TEST_CASE("frame buffer sizes are checked", "[frame][errors]") {
  CHECK_THROWS_WITH(FrameBuffer(0, 10), Catch::Contains("size 0x10"));
  CHECK_THROWS_WITH(FrameBuffer(65536, 65536), Catch::Contains("fewer than 2^31 pixels"));
  CHECK(FrameBuffer(3, 5).memory_bytes() == 15 * (4 + 4 * 4 + 4 + 4));
}
