// AMR volumes (volume/amr.hpp): the dual-cell interpolant against analytic fields and a
// brute-force oracle, the finest block winning, the background, gradients, conservative
// macrocell ranges, packets, bad input named, and the ray marcher's closed-form opacity.
#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "sciray/volume/amr.hpp"
#include "sciray/volume/volumetric_model.hpp"

using namespace sciray;

namespace {

const Vec3f origin{1.f, -2.f, 0.5f}, spacing{0.5f, 0.25f, 1.f};

/// Object position of AMR position a.
Vec3f object(const Vec3f& a) {
  return origin + spacing * a;
}

float linear(const Vec3f& p) {
  return 1.f + 2.f * p.x + 3.f * p.y + 4.f * p.z;
}

/// Three levels (widths 1, 0.5, 0.25) over AMR space [0, 8]^3: level 0 as two blocks (x below
/// and above 4), level 1 over [2, 6]^3, level 2 over [2.5, 3.5]^3. Cell values f(level, object
/// position of the cell centre).
template <class F>
AmrData three_levels(F f) {
  AmrData d;
  d.cell_width = {1.f, 0.5f, 0.25f};
  d.grid_origin = origin, d.grid_spacing = spacing;
  const auto add = [&](AmrBox box, int level) {
    const float w = d.cell_width[static_cast<std::size_t>(level)];
    std::vector<float> values;
    for (int z = box.lower[2]; z <= box.upper[2]; ++z)
      for (int y = box.lower[1]; y <= box.upper[1]; ++y)
        for (int x = box.lower[0]; x <= box.upper[0]; ++x)
          values.push_back(f(level, object(Vec3f{x + 0.5f, y + 0.5f, z + 0.5f} * w)));
    d.block_bounds.push_back(box), d.block_level.push_back(level), d.block_data.push_back(std::move(values));
  };
  add({{0, 0, 0}, {3, 7, 7}}, 0);
  add({{4, 0, 0}, {7, 7, 7}}, 0);
  add({{4, 4, 4}, {11, 11, 11}}, 1);
  add({{10, 10, 10}, {13, 13, 13}}, 2);
  return d;
}
float linear_field(int, const Vec3f& p) {
  return linear(p);
}
float noise_field(int level, const Vec3f& p) {
  return std::sin(7.1f * p.x + 3.3f * level) * std::cos(5.3f * p.y) + 0.5f * std::sin(11.7f * p.z);
}

/// The same semantics without the tree or the fast path: every block scanned.
float oracle(const AmrData& d, const Vec3f& p) {
  struct B {
    std::array<float, 3> lo, hi;
    float w;
    int level;
    const AmrBox* box;
    const std::vector<float>* v;
  };
  std::vector<B> blocks;
  std::array<float, 3> lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
  float finest = INFINITY;
  for (std::size_t b = 0; b < d.block_bounds.size(); ++b) {
    B x{{},
        {},
        d.cell_width[static_cast<std::size_t>(d.block_level[b])],
        d.block_level[b],
        &d.block_bounds[b],
        &d.block_data[b]};
    for (int k = 0; k < 3; ++k) {
      x.lo[k] = static_cast<float>(double(x.box->lower[k]) * x.w);
      x.hi[k] = static_cast<float>((double(x.box->upper[k]) + 1) * x.w);
      lo[k] = std::min(lo[k], x.lo[k]), hi[k] = std::max(hi[k], x.hi[k]);
    }
    finest = std::min(finest, x.w);
    blocks.push_back(x);
  }
  const Vec3f bl = object({lo[0], lo[1], lo[2]}), bu = object({hi[0], hi[1], hi[2]});
  for (int k = 0; k < 3; ++k)
    if (!(p[k] >= bl[k] && p[k] <= bu[k])) return d.background;
  const Vec3f local = (p - origin) * Vec3f{1.f / spacing.x, 1.f / spacing.y, 1.f / spacing.z};
  const auto clamp = [&](float x, int k) { return std::clamp(x, lo[k], std::nextafter(hi[k], -INFINITY)); };
  const auto covering = [&](const std::array<float, 3>& q, float min_width) {
    const B* best = nullptr;
    for (const B& b : blocks)
      if (b.w >= min_width && q[0] >= b.lo[0] && q[0] < b.hi[0] && q[1] >= b.lo[1] && q[1] < b.hi[1] &&
          q[2] >= b.lo[2] && q[2] < b.hi[2] && (!best || b.level > best->level))
        best = &b;
    return best;
  };
  const std::array<float, 3> a{clamp(local.x, 0), clamp(local.y, 1), clamp(local.z, 2)};
  const float w = d.method == AmrMethod::finest ? finest : covering(a, 0.f)->w;
  float weight[3], corner[2][3], v[8];
  for (int k = 0; k < 3; ++k) {
    const float s = (a[k] - 0.5f * w) / w, f = std::floor(s);
    weight[k] = s - f;
    corner[0][k] = clamp(f * w + 0.5f * w, k), corner[1][k] = clamp(f * w + 0.5f * w + w, k);
  }
  for (int i = 0; i < 8; ++i) {
    const std::array<float, 3> q{corner[i & 1][0], corner[(i >> 1) & 1][1], corner[i >> 2][2]};
    const B& b = *covering(q, w);
    std::size_t at = 0;
    for (int k = 2; k >= 0; --k)
      at = at * (b.box->upper[k] - b.box->lower[k] + 1) + std::size_t((q[k] - b.lo[k]) / b.w);
    v[i] = (*b.v)[at];
  }
  const auto lerp = [](float x, float y, float t) { return x + (y - x) * t; };
  return lerp(lerp(lerp(v[0], v[1], weight[0]), lerp(v[2], v[3], weight[0]), weight[1]),
              lerp(lerp(v[4], v[5], weight[0]), lerp(v[6], v[7], weight[0]), weight[1]), weight[2]);
}

/// n deterministic AMR positions in [lo, hi]^3.
std::vector<Vec3f> points(int n, float lo, float hi, unsigned seed = 7) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(lo, hi);
  std::vector<Vec3f> out;
  for (int i = 0; i < n; ++i) out.push_back({u(rng), u(rng), u(rng)});
  return out;
}

bool inside(const Vec3f& a, float lo, float hi) {
  return a.x >= lo && a.x < hi && a.y >= lo && a.y < hi && a.z >= lo && a.z < hi;
}

}  // namespace

TEST_CASE("amr: the box, the value range and the finest cell", "[volume][amr]") {
  const Amr amr(three_levels(linear_field));
  CHECK(amr.block_count() == 4);
  CHECK(amr.bounds().lower == origin);
  CHECK(amr.bounds().upper == object({8.f, 8.f, 8.f}));
  CHECK(amr.value_range()[0] == Approx(linear(object({0.5f, 0.5f, 0.5f}))));
  CHECK(amr.value_range()[1] == Approx(linear(object({7.5f, 7.5f, 7.5f}))));
  CHECK(amr.cell_size() == Vec3f{0.0625f, 0.0625f, 0.0625f});  // width 0.25 × the smallest spacing
  CHECK(amr.owned_bytes() >= (2 * 4 * 8 * 8 + 8 * 8 * 8 + 4 * 4 * 4) * sizeof(float));
}

TEST_CASE("amr: each level reproduces a linear field exactly away from its edges", "[volume][amr]") {
  for (AmrMethod method : {AmrMethod::current, AmrMethod::finest}) {
    AmrData d = three_levels(linear_field);
    d.method = method;
    const Amr amr(d);
    int checked = 0;
    for (const Vec3f& a : method == AmrMethod::current ? points(4000, 0.f, 8.f) : points(2000, 2.6f, 3.4f)) {
      // current: a dual cell of the finest level at a, whose corners all lie in that level's
      // blocks (the coarse corners skip finer blocks); finest: one of width 0.25 inside level 2.
      const bool exact = method == AmrMethod::current
                             ? (inside(a, 2.65f, 3.35f) || (inside(a, 2.3f, 5.7f) && !inside(a, 2.5f, 3.5f)) ||
                                (inside(a, 0.5f, 7.5f) && !inside(a, 2.f, 6.f)))
                             : inside(a, 2.65f, 3.35f);
      if (!exact) continue;
      ++checked;
      INFO("AMR position (" << a.x << ", " << a.y << ", " << a.z << ")");
      REQUIRE(amr.sample(object(a)) == Approx(linear(object(a))).margin(2e-5f * 40));
      const Vec3f g = amr.gradient(object(a));
      REQUIRE(g.x == Approx(2.f).margin(1e-3));
      REQUIRE(g.y == Approx(3.f).margin(1e-3));
      REQUIRE(g.z == Approx(4.f).margin(1e-3));
    }
    CHECK(checked > 1000);
  }
}

TEST_CASE("amr: everywhere the interpolant is the dual cell's, with coarse cells at level edges", "[volume][amr]") {
  for (AmrMethod method : {AmrMethod::current, AmrMethod::finest}) {
    AmrData d = three_levels(noise_field);
    d.method = method;
    const Amr amr(d);
    double worst = 0;
    for (const Vec3f& a : points(20000, -0.3f, 8.3f, 11)) {
      const float got = amr.sample(object(a)), want = oracle(d, object(a));
      REQUIRE(std::isnan(got) == std::isnan(want));
      if (!std::isnan(want)) worst = std::max(worst, double(std::abs(got - want)));
    }
    CHECK(worst < 1e-6);
    // At the cell centres of the finest block over them, a sample is that cell's value.
    if (method == AmrMethod::current)
      for (const Vec3f& a : {Vec3f{2.875f, 3.125f, 2.625f}, Vec3f{4.75f, 5.25f, 2.25f}, Vec3f{0.5f, 6.5f, 7.5f}}) {
        const int level = inside(a, 2.5f, 3.5f) ? 2 : inside(a, 2.f, 6.f) ? 1 : 0;
        CHECK(amr.sample(object(a)) == Approx(noise_field(level, object(a))).margin(1e-6));
      }
  }
}

TEST_CASE("amr: the finest block wins where blocks overlap", "[volume][amr]") {
  // Level l holds 2^l everywhere: a dual cell of one level reads only that level's blocks.
  const Amr amr(three_levels([](int level, const Vec3f&) { return float(1 << level); }));
  CHECK(amr.value_range() == std::array<float, 2>{1.f, 4.f});
  for (const Vec3f& a : points(3000, 0.f, 8.f, 3)) {
    const float expected = inside(a, 2.5f, 3.5f) ? 4.f : inside(a, 2.f, 6.f) ? 2.f : 1.f;
    // Near a finer block's faces the dual cell reaches the coarser level's cells.
    if (inside(a, 2.65f, 3.35f) || (inside(a, 2.3f, 5.7f) && !inside(a, 2.5f, 3.5f)) || !inside(a, 2.f, 6.f))
      REQUIRE(amr.sample(object(a)) == expected);
  }
}

TEST_CASE("amr: outside the box a sample is the background, inside its faces the edge cells extend", "[volume][amr]") {
  AmrData d = three_levels(linear_field);
  const Amr nan_outside(d);
  const Box3f box = nan_outside.bounds();
  CHECK(std::isnan(nan_outside.sample(box.upper + Vec3f{1e-3f, 0.f, 0.f})));
  CHECK(std::isnan(nan_outside.sample(box.lower - Vec3f{0.f, 0.f, 1e-3f})));
  CHECK(nan_outside.gradient(box.lower - Vec3f{1.f, 1.f, 1.f}) == Vec3f{0.f, 0.f, 0.f});
  // Within half a cell of the x = 0 face the corners clamp onto the first cell: constant in x.
  const Vec3f a{0.2f, 4.1f, 0.8f};
  CHECK(nan_outside.sample(object(a)) == Approx(linear(object({0.5f, 4.1f, 0.8f}))).epsilon(1e-5));
  CHECK(nan_outside.gradient(object(a)).x == 0.f);
  CHECK(nan_outside.gradient(object(a)).y == Approx(3.f).epsilon(1e-4));
  CHECK(nan_outside.sample(box.lower) == Approx(linear(object({0.5f, 0.5f, 0.5f}))).epsilon(1e-5));
  CHECK(nan_outside.sample(box.upper) == Approx(linear(object({7.5f, 7.5f, 7.5f}))).epsilon(1e-5));
  d.background = -3.f;
  CHECK(Amr(d).sample(box.upper + Vec3f{0.f, 1e-3f, 0.f}) == -3.f);
}

TEST_CASE("amr: packets sample and differentiate as the scalar path does", "[volume][amr][simd]") {
  const Amr amr(three_levels(noise_field));
  const auto check = [&]<class Arch>(Arch) {
    using F = simd::Float<Arch>;
    constexpr int W = simd::width<Arch>;
    const auto ps = points(64 * W, -0.5f, 8.5f, 5);
    for (std::size_t i = 0; i + W <= ps.size(); i += W) {
      alignas(64) float x[W], y[W], z[W];
      for (int k = 0; k < W; ++k) {
        const Vec3f p = object(ps[i + static_cast<std::size_t>(k)]);
        x[k] = p.x, y[k] = p.y, z[k] = p.z;
      }
      const Vec3<F> p{simd::load<Arch>(x), simd::load<Arch>(y), simd::load<Arch>(z)};
      const F v = amr.sample<Arch>(p);
      const Vec3<F> g = amr.gradient<Arch>(p);
      for (int k = 0; k < W; ++k) {
        const Vec3f q{x[k], y[k], z[k]};
        const float s = amr.sample(q);
        REQUIRE((std::isnan(s) ? std::isnan(simd::lane(v, k)) : simd::lane(v, k) == s));
        REQUIRE(Vec3f{simd::lane(g.x, k), simd::lane(g.y, k), simd::lane(g.z, k)} == amr.gradient(q));
      }
    }
  };
  check(simd::scalar{});
#if XSIMD_WITH_AVX512BW
  check(xsimd::avx512bw{});
#endif
}

TEST_CASE("amr: macrocell ranges bound every sample inside them", "[volume][amr]") {
  for (AmrMethod method : {AmrMethod::current, AmrMethod::finest})
    for (std::int64_t n : {3, 8}) {
      AmrData d = three_levels(noise_field);
      d.method = method;
      const Amr amr(d);
      const MacrocellGrid m = amr.macrocell_grid(n);
      std::vector<float> ranges = m.empty_ranges();
      amr.widen_macrocell_ranges(m, n, ranges);
      std::mt19937 rng(13);
      std::uniform_real_distribution<float> u(0.f, 1.f);
      std::size_t narrower = 0;
      for (std::int64_t z = 0; z < m.counts[2]; ++z)
        for (std::int64_t y = 0; y < m.counts[1]; ++y)
          for (std::int64_t x = 0; x < m.counts[0]; ++x) {
            const std::size_t i = m.index(x, y, z);
            narrower += ranges[2 * i + 1] - ranges[2 * i] < amr.value_range()[1] - amr.value_range()[0];
            for (int s = 0; s < 24; ++s) {
              const Vec3f p = m.lower + m.size * Vec3f{float(x) + u(rng), float(y) + u(rng), float(z) + u(rng)};
              const float v = amr.sample(p);
              INFO("macrocell " << x << " " << y << " " << z << ", value " << v);
              REQUIRE(v >= ranges[2 * i]);
              REQUIRE(v <= ranges[2 * i + 1]);
            }
          }
      CHECK(narrower > m.count() / 2);  // and they are not all the whole range
    }
}

TEST_CASE("amr: where only finer blocks cover a corner, the sample's own block fills it", "[volume][amr]") {
  // Level 0 holds 1 over x < 4 only, level 1 holds 2 over x >= 4 (it nests in no level-0
  // block: Open VKL reads past its list there). AMR x = 3.9: the width-1 dual cell's corner
  // at 4.5 has no block of width >= 1, so it takes the sample's own nearest cell: 1. At 4.1
  // the width-0.5 dual cell spans the level-0 centre 3.75 and the level-1 centre 4.25.
  AmrData d;
  d.cell_width = {1.f, 0.5f};
  d.block_bounds = {{{0, 0, 0}, {3, 7, 7}}, {{8, 0, 0}, {15, 15, 15}}};
  d.block_level = {0, 1};
  d.block_data = {std::vector<float>(4 * 8 * 8, 1.f), std::vector<float>(8 * 16 * 16, 2.f)};
  const Amr amr(d);
  CHECK(amr.sample({3.9f, 4.f, 4.f}) == 1.f);
  CHECK(amr.sample({4.1f, 4.f, 4.f}) == Approx(1.7f).epsilon(1e-6));
  CHECK(amr.gradient(Vec3f{4.1f, 4.f, 4.f}).x == Approx(2.f).epsilon(1e-6));  // (2 - 1) / 0.5
  const MacrocellGrid m = amr.macrocell_grid(1);
  std::vector<float> ranges = m.empty_ranges();
  amr.widen_macrocell_ranges(m, 1, ranges);
  for (const Vec3f& p : points(20000, 0.f, 8.f, 17)) {
    const float v = amr.sample(p);
    const auto c = [&](int k) {
      return std::min<std::int64_t>(std::int64_t((p[k] - m.lower[k]) / m.size[k]), m.counts[k] - 1);
    };
    const std::size_t i = m.index(c(0), c(1), c(2));
    REQUIRE(v >= ranges[2 * i]);
    REQUIRE(v <= ranges[2 * i + 1]);
  }
}

TEST_CASE("amr: bad input is named", "[volume][amr][errors]") {
  const AmrData good = three_levels(linear_field);
  const auto fails = [](AmrData d, const std::string& what) {
    REQUIRE_THROWS_WITH(Amr(std::move(d)), Catch::Contains(what));
  };
  AmrData d = good;
  d.block_level.pop_back();
  fails(d, "amr volume: 'block.level' has 3 entries but 'block.bounds' has 4 blocks");
  d = good, d.block_data.push_back({});
  fails(d, "amr volume: 'block.data' has 5 arrays but 'block.bounds' has 4 blocks");
  d = good, d.block_bounds.clear(), d.block_level.clear(), d.block_data.clear();
  fails(d, "amr volume: 'block.bounds' is missing or empty");
  d = good, d.block_data[2].pop_back();
  fails(d, "amr volume: block 2 has 511 values in 'block.data' but its bounds hold 8 x 8 x 8 cells");
  d = good, d.block_level[1] = -1;
  fails(d, "amr volume: block 1 has 'block.level' -1, which is negative");
  d = good, d.block_level[3] = 3;
  fails(d, "amr volume: block 3 is on level 3 but 'cellWidth' has widths for 3 levels");
  d = good, d.block_bounds[0].upper[1] = -1;
  fails(d, "amr volume: block 0 has 'block.bounds' upper (3, -1, 7) below lower (0, 0, 0)");
  d = good, d.block_bounds[1].lower[0] = 3, d.block_data[1].resize(5 * 8 * 8);
  fails(d, "amr volume: blocks 0 and 1 overlap on level 0");
  d = good, d.block_bounds[0].upper[0] = 2, d.block_data[0].resize(3 * 8 * 8);
  fails(d,
        "amr volume: no block covers the region from (3.000000, 0.000000, 0.000000) to (4.000000, 2.000000, 3.500000)");
  d = good, d.cell_width = {1.f, 0.5f, 0.5f};
  fails(d, "amr volume: 'cellWidth' must shrink from level to level, but level 2's 0.500000 is not below level 1's");
  d = good, d.cell_width[0] = 0.f;
  fails(d, "amr volume: 'cellWidth' 0 is 0.000000; cell widths must be finite and positive");
  d = good, d.cell_width.clear();
  fails(d, "amr volume: 'cellWidth' is missing or empty");
  d = good, d.block_data[3][5] = NAN;
  fails(d, "amr volume: block 3 has a value that is not finite in 'block.data', at cell 5");
  d = good, d.grid_spacing.y = 0.f;
  fails(d, "amr volume: 'gridSpacing' must be finite and positive, got 0.000000 along axis 1");
  d = good, d.method = AmrMethod::octant;
  fails(d, "amr volume: 'method' OSP_AMR_OCTANT (2) is not implemented");
  d = good, d.method = static_cast<AmrMethod>(5);
  fails(d, "amr volume: 'method' 5 is none of OSP_AMR_CURRENT (0), OSP_AMR_FINEST (1), OSP_AMR_OCTANT (2)");
  // Holes inside finer levels are fine as long as a coarser level covers them.
  d = good, d.block_bounds.pop_back(), d.block_level.pop_back(), d.block_data.pop_back();
  CHECK(Amr(d).block_count() == 3);
}

TEST_CASE("amr: the ray marcher's opacity through a constant field is 1 - exp(-sigma L)", "[volume][amr][render]") {
  // Every level holds 1, so every dual cell interpolates 1; opacity(1) = 1 per unit, times densityScale.
  const auto volume = std::make_shared<const Amr>(three_levels([](int, const Vec3f&) { return 1.f; }));
  const float density = 0.3f;
  const VolumetricModel<Amr> model(volume, TransferFunction({{1, 1, 1}}, {0.f, 1.f}, {0.f, 1.f}), density);
  const Box3f box = volume->bounds();
  for (bool skipping : {true, false})
    for (float rate : {0.5f, 1.f, 4.f}) {
      VolumeIntegration how;
      how.sampling_rate = rate;
      how.empty_space_skipping = skipping;
      // Along x through the level-2 block: L = 8 × 0.5; along z beside it: L = 8 × 1.
      const Vec3f through = object({0.f, 3.f, 3.f}) - Vec3f{1.f, 0.f, 0.f}, beside = object({6.5f, 1.f, 0.f});
      const auto along_x = model.integrate<simd::scalar>(Ray<float>{through, {1.f, 0.f, 0.f}}, true, INFINITY, how);
      const auto along_z = model.integrate<simd::scalar>(Ray<float>{beside - Vec3f{0.f, 0.f, 2.f}, {0.f, 0.f, 1.f}},
                                                         true, INFINITY, how);
      INFO("rate " << rate << (skipping ? ", skipping" : ""));
      CHECK(along_x.alpha == Approx(1.f - std::exp(-density * (box.upper.x - box.lower.x))).epsilon(1e-5));
      CHECK(along_z.alpha == Approx(1.f - std::exp(-density * (box.upper.z - box.lower.z))).epsilon(1e-5));
      const auto miss = model.integrate<simd::scalar>(Ray<float>{box.upper + Vec3f{0.f, 1.f, 0.5f}, {1.f, 0.f, 0.f}},
                                                      true, INFINITY, how);
      CHECK(miss.alpha == 0.f);
    }
}
