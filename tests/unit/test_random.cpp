// The pixel sample streams: stratified across a pixel's samples in every draw, and draws
// independent of each other.
#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <numbers>
#include <vector>

#include "sciray/math/random.hpp"
#include "sciray/math/random_lanes.hpp"

namespace {

using sciray::PixelRandom;

/// Draw `draw` (1-based) of samples first .. first + count - 1 of `pixel`.
std::vector<PixelRandom::Pair> draws_of(std::uint32_t pixel, int draw, std::uint32_t first, std::uint32_t count) {
  std::vector<PixelRandom::Pair> out;
  for (std::uint32_t s = first; s < first + count; ++s) {
    PixelRandom rng(pixel, s);
    PixelRandom::Pair p{};
    for (int d = 0; d < draw; ++d) p = rng.next_2d();
    out.push_back(p);
  }
  return out;
}

/// Whether the points put exactly one point in each cell of every (2^a x 2^b) grid with
/// a + b = log2(points): the (0,m,2)-net property.
bool is_net(const std::vector<PixelRandom::Pair>& points) {
  const int m = static_cast<int>(std::log2(static_cast<double>(points.size())));
  for (int a = 0; a <= m; ++a) {
    const int nx = 1 << a, ny = 1 << (m - a);
    std::vector<int> cells(points.size(), 0);
    for (const auto& p : points) {
      const int x = static_cast<int>(p.u * static_cast<float>(nx)), y = static_cast<int>(p.v * static_cast<float>(ny));
      if (++cells[static_cast<std::size_t>(y * nx + x)] > 1) return false;
    }
  }
  return true;
}

}  // namespace

TEST_CASE("Sobol's second dimension from its direction numbers", "[random]") {
  // v0 = 1/2, v(k+1) = vk xor vk/2: the definition, one index bit at a time.
  const auto by_direction_numbers = [](std::uint32_t index) {
    std::uint32_t x = 0, direction = 0x80000000U;
    for (; index; index >>= 1, direction ^= direction >> 1)
      if (index & 1U) x ^= direction;
    return x;
  };
  for (std::uint32_t index : {0u, 1u, 2u, 3u, 5u, 16u, 255u, 1000u, 65535u, 0x12345678u, 0xffffffffu}) {
    CAPTURE(index);
    CHECK(sciray::reverse_bits(sciray::sobol_second_reversed(index)) == by_direction_numbers(index));
    CHECK(sciray::reverse_bits(sciray::sobol_first_reversed(index)) == sciray::reverse_bits(index));
  }
  CHECK(sciray::reverse_bits(1u) == 0x80000000U);
  CHECK(sciray::reverse_bits(0x12345678U) == 0x1e6a2c48U);
}

TEST_CASE("every aligned block of 2^k samples of a pixel is a (0,k,2)-net in every draw", "[random]") {
  for (std::uint32_t pixel : {0u, 1u, 77u, 65535u, 1u << 20})
    for (int draw = 1; draw <= 12; ++draw) {
      CAPTURE(pixel, draw);
      CHECK(is_net(draws_of(pixel, draw, 0, 16)));
      CHECK(is_net(draws_of(pixel, draw, 16, 16)));
      CHECK(is_net(draws_of(pixel, draw, 256, 64)));
      CHECK(is_net(draws_of(pixel, draw, 0, 1024)));
    }
}

TEST_CASE("a pixel's draws converge on a smooth integral far faster than random numbers", "[random]") {
  // ∫∫ sin(πu) sin(πv) du dv = 4/π² over 64 samples: random numbers err by about
  // 0.31/8 = 0.039 (RMS over pixels); a scrambled (0,2)-net by far less.
  const double exact = 4.0 / (std::numbers::pi * std::numbers::pi);
  double squared_error = 0.0;
  const int pixels = 200;
  for (int pixel = 0; pixel < pixels; ++pixel) {
    double sum = 0.0;
    for (const auto& p : draws_of(static_cast<std::uint32_t>(pixel), 3, 0, 64))
      sum += std::sin(std::numbers::pi * p.u) * std::sin(std::numbers::pi * p.v);
    squared_error += (sum / 64.0 - exact) * (sum / 64.0 - exact);
  }
  CHECK(std::sqrt(squared_error / pixels) < 0.004);
}

TEST_CASE("different draws of one pixel are independent of each other", "[random]") {
  // Within one pixel, over 4096 samples: the product of two draws' coordinates averages
  // 1/4 and a quadrant of one draw's u against another's v holds a quarter of the samples.
  // Draws that were functions of each other (a shifted copy) miss both by far.
  for (std::uint32_t pixel : {3u, 4u, 1000u})
    for (auto [a, b] : {std::pair{1, 2}, std::pair{1, 5}, std::pair{4, 9}}) {
      CAPTURE(pixel, a, b);
      const auto first = draws_of(pixel, a, 0, 4096), second = draws_of(pixel, b, 0, 4096);
      double product = 0.0;
      int quadrant = 0;
      for (std::size_t i = 0; i < first.size(); ++i) {
        product += static_cast<double>(first[i].u) * second[i].v;
        quadrant += first[i].u < 0.5f && second[i].v < 0.5f;
      }
      CHECK(product / 4096.0 == Approx(0.25).margin(0.01));
      CHECK(quadrant / 4096.0 == Approx(0.25).margin(0.02));
    }
}

TEST_CASE("neighbouring pixels draw different points", "[random]") {
  const auto a = draws_of(10, 1, 0, 1), b = draws_of(11, 1, 0, 1);
  CHECK((a[0].u != b[0].u || a[0].v != b[0].v));
  // The first sample of many pixels is uniform over [0,1)^2: a 4x4 histogram of 4096 pixels.
  std::vector<int> cells(16, 0);
  for (std::uint32_t pixel = 0; pixel < 4096; ++pixel) {
    const auto p = draws_of(pixel, 1, 0, 1)[0];
    ++cells[static_cast<std::size_t>(static_cast<int>(p.v * 4.f) * 4 + static_cast<int>(p.u * 4.f))];
  }
  for (int c : cells) CHECK(std::abs(c - 256) < 64);
}

TEMPLATE_TEST_CASE("a packet of generators draws, lane by lane, what each pixel's own generator draws", "[random][simd]",
                   xsimd::default_arch, sciray::simd::scalar) {
  using Arch = TestType;
  constexpr int W = sciray::simd::width<Arch>;
  alignas(64) std::int32_t pixels[W];
  alignas(64) float active[W];
  for (const std::uint32_t sample : {0u, 1u, 37u, 1u << 20}) {
    for (int i = 0; i < W; ++i) pixels[i] = 1000 * i + 7 * static_cast<int>(sample), active[i] = 1.f;
    sciray::PixelRandomLanes<Arch> lanes(sciray::simd::load<Arch>(pixels), sample);
    std::vector<PixelRandom> own;
    for (int i = 0; i < W; ++i) own.emplace_back(static_cast<std::uint32_t>(pixels[i]), sample);
    for (int draw = 0; draw < 6; ++draw) {
      // Lanes sit out some draws: those draw nothing and keep their place in the sequence.
      for (int i = 0; i < W; ++i) active[i] = (draw + i) % 3 == 0 ? 0.f : 1.f;
      const auto drawing = sciray::simd::load<Arch>(active) > sciray::simd::Float<Arch>(0.f);
      const auto [u, v] = lanes.next_2d(drawing);
      for (int i = 0; i < W; ++i) {
        if (active[i] == 0.f) continue;
        INFO("sample " << sample << ", draw " << draw << ", lane " << i);
        const PixelRandom::Pair expected = own[static_cast<std::size_t>(i)].next_2d();
        CHECK(sciray::simd::lane(u, i) == expected.u);
        CHECK(sciray::simd::lane(v, i) == expected.v);
      }
    }
  }
}

TEMPLATE_TEST_CASE("a packet of paths' own generators draws, lane by lane, what each would alone", "[random][simd]",
                   xsimd::default_arch, sciray::simd::scalar) {
  using Arch = TestType;
  constexpr int W = sciray::simd::width<Arch>;
  // Generators of different pixels and samples, each already some draws into its sequence.
  std::vector<PixelRandom> paths, alone;
  for (int i = 0; i < W; ++i) {
    paths.emplace_back(static_cast<std::uint32_t>(31 * i + 5), static_cast<std::uint32_t>(i % 3));
    for (int d = 0; d < i % 4; ++d) paths.back().next_2d();
    alone.push_back(paths.back());
  }
  std::array<PixelRandom*, W> lanes;
  for (int i = 0; i < W; ++i) lanes[static_cast<std::size_t>(i)] = &paths[static_cast<std::size_t>(i)];
  alignas(64) float active[W];
  for (int draw = 0; draw < 6; ++draw) {
    for (int i = 0; i < W; ++i) active[i] = (draw + i) % 3 == 0 ? 0.f : 1.f;
    const auto drawing = sciray::simd::load<Arch>(active) > sciray::simd::Float<Arch>(0.f);
    const auto [u, v] = sciray::PixelRandomLanes<Arch>::next_2d_of(lanes, drawing);
    for (int i = 0; i < W; ++i) {
      if (active[i] == 0.f) continue;
      INFO("draw " << draw << ", lane " << i);
      const PixelRandom::Pair expected = alone[static_cast<std::size_t>(i)].next_2d();
      CHECK(sciray::simd::lane(u, i) == expected.u);
      CHECK(sciray::simd::lane(v, i) == expected.v);
    }
  }
  // Lanes that sat out draws kept their place: their next draws are still each one's own.
  for (int i = 0; i < W; ++i)
    CHECK(paths[static_cast<std::size_t>(i)].next_2d().u == alone[static_cast<std::size_t>(i)].next_2d().u);
}
