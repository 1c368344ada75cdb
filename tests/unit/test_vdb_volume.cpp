// VDB volumes (volume/vdb.hpp): Open VKL's voxel placement and lookup, leaves and tiles
// on every level, both forms of node data, indexToObject, conservative macrocell ranges,
// packets, bad nodes named, and the integral through a constant block.
#include <catch2/catch.hpp>
#include <cmath>
#include <functional>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "sciray/volume/vdb.hpp"
#include "sciray/volume/volumetric_model.hpp"

using namespace sciray;

namespace {

using Field = std::function<float(float, float, float)>;

float linear(float i, float j, float k) {
  return 1.f + 2.f * i + 3.f * j + 0.5f * k;
}

/// A dense leaf at `o` holding f at each voxel, in Open VKL's order: z fastest, x slowest.
std::vector<float> leaf(const std::array<std::int32_t, 3>& o, const Field& f) {
  std::vector<float> v(512);
  for (int x = 0; x < 8; ++x)
    for (int y = 0; y < 8; ++y)
      for (int z = 0; z < 8; ++z)
        v[static_cast<std::size_t>(x * 64 + y * 8 + z)] =
            f(static_cast<float>(o[0] + x), static_cast<float>(o[1] + y), static_cast<float>(o[2] + z));
  return v;
}

void add_leaf(VdbData& d, const std::array<std::int32_t, 3>& o, const Field& f) {
  d.level.push_back(3), d.origin.push_back(o), d.data.push_back(leaf(o, f));
}
void add_tile(VdbData& d, std::uint32_t level, const std::array<std::int32_t, 3>& o, float value) {
  d.level.push_back(level), d.origin.push_back(o), d.data.push_back({value});
}

/// n³ leaves from the origin holding f: index box [0, 8n]³.
VdbData cube(int n, const Field& f) {
  VdbData d;
  for (int x = 0; x < n; ++x)
    for (int y = 0; y < n; ++y)
      for (int z = 0; z < n; ++z) add_leaf(d, {8 * x, 8 * y, 8 * z}, f);
  return d;
}

Vec3f random_point(std::mt19937& rng, const Vec3f& lo, const Vec3f& hi) {
  std::uniform_real_distribution<float> u(0.f, 1.f);
  return {lo.x + (hi.x - lo.x) * u(rng), lo.y + (hi.y - lo.y) * u(rng), lo.z + (hi.z - lo.z) * u(rng)};
}

bool same(float a, float b) {
  return (std::isnan(a) && std::isnan(b)) || a == b;
}

std::string error_of(VdbData d) {
  try {
    Vdb v(std::move(d));
  } catch (const Error& e) {
    return e.what();
  }
  return "no error";
}

}  // namespace

TEST_CASE("vdb: trilinear reproduces a linear field across leaves, voxel i sits at index i", "[volume][vdb]") {
  const Vdb v(cube(2, linear));
  CHECK(v.node_count() == 8);
  CHECK(v.bounds().lower == Vec3f{0, 0, 0});
  CHECK(v.bounds().upper == Vec3f{16, 16, 16});
  CHECK(v.cell_size() == Vec3f{1, 1, 1});
  CHECK(v.value_range() == std::array<float, 2>{linear(0, 0, 0), linear(15, 15, 15)});
  CHECK(v.voxel(9, 3, 14) == linear(9, 3, 14));  // z fastest in each leaf
  CHECK(v.sample({9.f, 3.f, 14.f}) == linear(9, 3, 14));
  std::mt19937 rng(1);
  double worst = 0, worst_gradient = 0;
  for (int i = 0; i < 3000; ++i) {
    // Up to 15: beyond, trilinear reads the top voxel layer's neighbours outside the domain.
    Vec3f p = random_point(rng, {0, 0, 0}, {15, 15, 15});
    if (i % 3 == 0) p.x = 7.f + 0.001f * static_cast<float>(i % 1000);  // across the leaves' faces
    worst = std::max(worst, static_cast<double>(std::abs(v.sample(p) - linear(p.x, p.y, p.z))));
    const Vec3f g = v.gradient(p);
    worst_gradient = std::max({worst_gradient, std::abs(g.x - 2.0), std::abs(g.y - 3.0), std::abs(g.z - 0.5)});
  }
  CHECK(worst < 1e-4);  // values up to 84: float rounding
  CHECK(worst_gradient < 1e-4);
  // The top voxel layer interpolates towards the background beyond the domain (NaN by default).
  CHECK(std::isnan(v.sample({15.5f, 4.f, 4.f})));
  CHECK(v.gradient({15.5f, 4.f, 4.f}) == Vec3f{0, 0, 0});
  CHECK(std::isnan(v.sample({-0.01f, 4.f, 4.f})));
  CHECK(std::isnan(v.sample({4.f, 16.5f, 4.f})));
  VdbData d = cube(2, linear);
  d.background = -1.f;
  const Vdb with_background(d);
  CHECK(with_background.sample({15.5f, 4.25f, 4.f}) == Approx(0.5f * linear(15, 4.25f, 4) - 0.5f));
  CHECK(with_background.sample({20.f, 4.f, 4.f}) == -1.f);
  // Nearest: voxel floor(x) (Open VKL's constant cells), and no gradient unless gradientFilter is linear.
  d.filter = VolumeFilter::nearest;
  const Vdb nearest(d);
  CHECK(nearest.sample({9.7f, 3.2f, 14.9f}) == linear(9, 3, 14));
  CHECK(nearest.sample({8.f, 0.f, 15.99f}) == linear(8, 0, 15));
  CHECK(nearest.gradient({9.7f, 3.2f, 14.9f}) == Vec3f{0, 0, 0});
  d.gradient_filter = VolumeFilter::linear;
  const Vec3f g = Vdb(d).gradient({9.7f, 3.2f, 14.1f});
  CHECK(g.x == Approx(2.f));
  CHECK(g.y == Approx(3.f));
  CHECK(g.z == Approx(0.5f));
}

TEST_CASE("vdb: tiles on every level, 0 in the domain's gaps, trilinear across node kinds", "[volume][vdb]") {
  VdbData d;
  add_leaf(d, {120, 0, 0}, linear);
  add_tile(d, 2, {128, 0, 0}, 5.f);   // 128³ voxels
  add_tile(d, 1, {4096, 0, 0}, 3.f);  // 4096³ voxels
  add_tile(d, 3, {0, 0, 0}, 2.f);     // a constant leaf
  const Vdb v(d);
  CHECK(v.bounds().lower == Vec3f{0, 0, 0});
  CHECK(v.bounds().upper == Vec3f{8192, 4096, 4096});
  CHECK(v.value_range() == std::array<float, 2>{2.f, linear(127, 7, 7)});
  CHECK(v.sample({3.f, 4.f, 5.f}) == 2.f);
  CHECK(v.sample({200.f, 50.f, 50.f}) == 5.f);
  CHECK(v.sample({5000.f, 1000.f, 3000.f}) == 3.f);
  CHECK(v.sample({60.f, 60.f, 60.f}) == 0.f);  // no node: Open VKL's empty voxels
  CHECK(v.sample({1000.f, 2000.f, 3000.f}) == 0.f);
  CHECK(std::isnan(v.voxel(0, 0, 4096)));  // beyond the nodes' top corner: the background
  // A sample between two nodes reads both: a leaf and a tile, a gap and a tile, a tile and a tile.
  CHECK(v.sample({127.5f, 2.f, 3.f}) == Approx(0.5f * linear(127, 2, 3) + 2.5f));
  CHECK(v.sample({127.25f, 100.f, 100.f}) == Approx(1.25f));
  CHECK(v.sample({4095.5f, 64.f, 64.f}) == Approx(1.5f));
  CHECK(v.sample({7.5f, 0.f, 0.f}) == Approx(1.f));
  // Open VKL's domain starts at the root's origin, the nodes' corner rounded down to 4096.
  VdbData one;
  add_leaf(one, {16, 0, 0}, linear);
  CHECK(Vdb(one).voxel(15, 0, 0) == 0.f);
  CHECK(std::isnan(Vdb(one).voxel(24, 0, 0)));
  CHECK(std::isnan(Vdb(one).sample({15.5f, 1.f, 1.f})));  // but samples outside the nodes' box are the background
}

TEST_CASE("vdb: indexToObject scales, rotates and translates, gradients follow", "[volume][vdb]") {
  VdbData d = cube(2, linear);
  d.index_to_object = {{0.5f, 0, 0}, {0, 0.5f, 0}, {0, 0, 0.5f}, {1, 2, 3}};
  const Vdb scaled(d);
  CHECK(scaled.bounds().lower == Vec3f{1, 2, 3});
  CHECK(scaled.bounds().upper == Vec3f{9, 10, 11});
  CHECK(scaled.cell_size() == Vec3f{0.5f, 0.5f, 0.5f});
  // Rotated by 90° about z with x stretched: object p = (5 - j, 2 i, k), so the field is
  // 1 + p.y + 3 (5 - p.x) + 0.5 p.z, of gradient (-3, 1, 0.5).
  d.index_to_object = {{0, 2, 0}, {-1, 0, 0}, {0, 0, 1}, {5, 0, 0}};
  const Vdb rotated(d);
  CHECK(rotated.bounds().lower == Vec3f{-11, 0, 0});
  CHECK(rotated.bounds().upper == Vec3f{5, 32, 16});
  CHECK(rotated.cell_size() == Vec3f{1, 1, 1});
  std::mt19937 rng(2);
  for (int i = 0; i < 500; ++i) {
    const Vec3f q = random_point(rng, {0, 0, 0}, {15, 15, 15});
    REQUIRE(scaled.sample(Vec3f{1, 2, 3} + q * 0.5f) == Approx(linear(q.x, q.y, q.z)).epsilon(1e-5));
    const Vec3f gs = scaled.gradient(Vec3f{1, 2, 3} + q * 0.5f);
    REQUIRE((gs.x == Approx(4.f) && gs.y == Approx(6.f) && gs.z == Approx(1.f)));
    const Vec3f p{5.f - q.y, 2.f * q.x, q.z};
    REQUIRE(rotated.sample(p) == Approx(linear(q.x, q.y, q.z)).epsilon(1e-5));
    const Vec3f gr = rotated.gradient(p);
    REQUIRE((gr.x == Approx(-3.f) && gr.y == Approx(1.f) && gr.z == Approx(0.5f)));
  }
}

namespace {

float hashed(float i, float j, float k) {
  const std::uint32_t h = static_cast<std::uint32_t>(i) * 73856093u ^ static_cast<std::uint32_t>(j) * 19349663u ^
                          static_cast<std::uint32_t>(k) * 83492791u;
  return static_cast<float>((h * 2654435761u) >> 8) * 0x1p-24f * 10.f - 3.f;  // in [-3, 7)
}

/// A level-2 tile of 7 and some leaves of hashed values beside it, gaps between them.
VdbData mixed() {
  VdbData d;
  add_tile(d, 2, {0, 0, 0}, 7.f);
  for (int a = 0; a < 4; ++a)
    for (int b = 0; b < 3; ++b)
      for (int c = 0; c < 2; ++c)
        if ((a + 2 * b + c) % 3 != 0) add_leaf(d, {128 + 8 * a, 8 * b, 8 * c}, hashed);
  add_tile(d, 3, {152, 120, 120}, -1.f);
  return d;
}

}  // namespace

TEST_CASE("vdb: packed node data (nodesPackedDense, nodesPackedTile) is the same volume", "[volume][vdb]") {
  const VdbData d = mixed();
  VdbData packed = d;
  packed.data.clear();
  for (std::size_t i = 0; i < d.level.size(); ++i) {
    const bool tile = d.data[i].size() == 1;
    packed.format.push_back(tile ? 0u : 1u);
    auto& into = tile ? packed.packed_tile : packed.packed_dense;
    into.insert(into.end(), d.data[i].begin(), d.data[i].end());
  }
  const Vdb a(d), b(packed);
  CHECK(a.owned_bytes() == b.owned_bytes());
  std::mt19937 rng(3);
  for (int i = 0; i < 2000; ++i) {
    const Vec3f p = random_point(rng, {-1, -1, -1}, {161, 129, 129});
    REQUIRE(same(a.sample(p), b.sample(p)));
  }
}

TEST_CASE("vdb: macrocell ranges bound every sample, and stay tight inside nodes and gaps", "[volume][vdb]") {
  VdbData d = mixed();
  d.background = -2.f;  // read in the top voxel layers
  d.index_to_object = {{0.25f, 0, 0}, {0, 0.25f, 0}, {0, 0, 0.25f}, {-3, 1, 2}};
  const Vdb v(d);
  const MacrocellGrid m = v.macrocell_grid(8);
  CHECK(m.counts == std::array<std::int64_t, 3>{20, 16, 16});
  std::vector<float> ranges = m.empty_ranges();
  v.widen_macrocell_ranges(m, 8, ranges);
  std::mt19937 rng(4);
  std::size_t checked = 0;
  for (std::int64_t z = 0; z < m.counts[2]; ++z)
    for (std::int64_t y = 0; y < m.counts[1]; ++y)
      for (std::int64_t x = 0; x < m.counts[0]; ++x) {
        const std::size_t i = m.index(x, y, z);
        const Vec3f lo = m.lower + Vec3f{static_cast<float>(x), static_cast<float>(y), static_cast<float>(z)} * m.size;
        for (int s = 0; s < 24; ++s) {
          const float value = v.sample(random_point(rng, lo, lo + m.size));
          if (std::isnan(value)) continue;
          INFO("macrocell (" << x << ", " << y << ", " << z << ") value " << value);
          REQUIRE(value >= ranges[2 * i]);
          REQUIRE(value <= ranges[2 * i + 1]);
          ++checked;
        }
      }
  CHECK(checked == 24 * m.count());  // a finite background: no NaN anywhere in the box
  // Macrocells of 8 voxels: (3, 3, 3) lies inside the tile, (17, 8, 8) in the gap beside it.
  CHECK(ranges[2 * m.index(3, 3, 3)] == 7.f);
  CHECK(ranges[2 * m.index(3, 3, 3) + 1] == 7.f);
  CHECK(ranges[2 * m.index(17, 8, 8)] == 0.f);
  CHECK(ranges[2 * m.index(17, 8, 8) + 1] == 0.f);
  CHECK(ranges[2 * m.index(19, 15, 15)] == -2.f);  // the top corner: the background
}

TEST_CASE("vdb: packets sample and differentiate as the scalar path does", "[volume][vdb][simd]") {
  VdbData d = mixed();
  d.index_to_object = {{0, 2, 0}, {-1, 0, 0}, {0, 0, 1}, {5, 0, 0}};
  const Vdb v(d);
  std::mt19937 rng(5);
  const Box3f b = v.bounds();
  const auto check = [&]<class Arch>(Arch) {
    constexpr int W = simd::width<Arch>;
    for (int n = 0; n < 200; ++n) {
      alignas(64) float x[W], y[W], z[W];
      for (int i = 0; i < W; ++i) {
        const Vec3f p = random_point(rng, b.lower - Vec3f{1, 1, 1}, b.upper + Vec3f{1, 1, 1});
        x[i] = p.x, y[i] = p.y, z[i] = p.z;
      }
      const Vec3<simd::Float<Arch>> p{simd::load<Arch>(x), simd::load<Arch>(y), simd::load<Arch>(z)};
      const auto s = v.sample<Arch>(p);
      const auto g = v.gradient<Arch>(p);
      for (int i = 0; i < W; ++i) {
        const Vec3f q{x[i], y[i], z[i]};
        REQUIRE(same(simd::lane(s, i), v.sample(q)));
        const Vec3f gq = v.gradient(q);
        REQUIRE((simd::lane(g.x, i) == gq.x && simd::lane(g.y, i) == gq.y && simd::lane(g.z, i) == gq.z));
      }
    }
  };
  check(simd::scalar{});
#if XSIMD_WITH_AVX512BW  // built with AVX-512 enabled; every ISA's kernels: test_volume_type_packets.cpp
  check(xsimd::avx512bw{});
#endif
}

TEST_CASE("vdb: bad nodes and parameters are named", "[volume][vdb][errors]") {
  const VdbData good = cube(1, linear);
  VdbData d;
  CHECK_THAT(error_of(d), Catch::Contains("vdb volume: 'node.level' is missing or empty"));
  d = good;
  add_tile(d, 3, {8, 0, 0}, 1.f);
  d.origin.pop_back();
  CHECK(error_of(d) == "vdb volume: 'node.origin' has 1 entries but 'node.level' has 2 nodes");
  d = good;
  d.level.push_back(3), d.origin.push_back({8, 0, 0});
  CHECK(error_of(d) == "vdb volume: 'node.data' has 1 entries but 'node.level' has 2 nodes");
  for (std::uint32_t level : {0u, 4u}) {
    d = good;
    add_tile(d, level, {8, 0, 0}, 1.f);
    CHECK(error_of(d) ==
          "vdb volume: node 1 has 'node.level' " + std::to_string(level) + "; levels are 1 to 3 (3: the leaves)");
  }
  d = good;
  d.format = {7};
  CHECK(error_of(d) == "vdb volume: node 0 has 'node.format' 7, which is none of tile (0), dense zyx (1)");
  d = good;
  d.level = {2};
  CHECK(error_of(d) == "vdb volume: node 0 is dense on level 2, but dense nodes exist only on level 3");
  d = good;
  add_tile(d, 3, {3, 0, 8}, 1.f);
  CHECK(error_of(d) == "vdb volume: node 1 has 'node.origin' (3, 0, 8), which is not a multiple of its level's span 8");
  d = good;
  add_tile(d, 2, {0, 64, 0}, 1.f);
  CHECK_THAT(error_of(d),
             Catch::Contains("node 1 has 'node.origin' (0, 64, 0), which is not a multiple of its level's span 128"));
  d = good;
  d.data[0].resize(100);
  CHECK(error_of(d) == "vdb volume: node 0 is dense: its 'node.data' needs 512 values, got 100");
  d = good;
  d.format = {0};
  CHECK(error_of(d) == "vdb volume: node 0 is a tile: its 'node.data' needs 1 value, got 512");
  d = good;
  d.data[0][5] = INFINITY;
  CHECK(error_of(d) == "vdb volume: node 0 'node.data' value 5 is not finite");
  d = good;
  d.index_to_object = {{1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {0, 0, 0}};
  CHECK_THAT(error_of(d), Catch::Contains("vdb volume: 'indexToObject' is singular"));
  d.index_to_object = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {NAN, 0, 0}};
  CHECK(error_of(d) == "vdb volume: 'indexToObject' is not finite");
  d = good;
  d.filter = VolumeFilter::cubic;
  CHECK_THAT(error_of(d), Catch::Contains("vdb volume: 'filter' cubic (Open VKL's tricubic) is not supported"));
  d = good;
  d.gradient_filter = VolumeFilter::cubic;
  CHECK_THAT(error_of(d), Catch::Contains("'gradientFilter' cubic"));
  d = good;
  d.packed_tile = {1.f};
  CHECK_THAT(error_of(d),
             Catch::Contains("give either 'node.data' or 'nodesPackedDense' / 'nodesPackedTile', not both"));
  d.data.clear();
  CHECK(error_of(d) == "vdb volume: 'node.format' is needed with 'nodesPackedDense' / 'nodesPackedTile'");
  d.packed_tile.clear();
  CHECK_THAT(error_of(d), Catch::Contains("'node.data' (or 'nodesPackedDense' / 'nodesPackedTile') is missing"));
  d.format = {1}, d.packed_dense.assign(500, 1.f);
  CHECK(error_of(d) == "vdb volume: 'nodesPackedDense' has 500 values but the 1 dense nodes need 512");
  d.packed_dense.resize(512), d.packed_tile = {1.f};
  CHECK(error_of(d) == "vdb volume: 'nodesPackedTile' has 1 values but the 0 tiles need 0");
  d = good;
  add_leaf(d, {0, 0, 0}, linear);
  CHECK(error_of(d) == "vdb volume: node 1 covers the same voxels as node 0");
  d = good;
  add_tile(d, 2, {0, 0, 0}, 1.f);
  CHECK(error_of(d) == "vdb volume: node 0 lies inside node 1, a tile on level 2");
  d = good;
  add_leaf(d, {300000, 0, 0}, linear);
  CHECK_THAT(error_of(d), Catch::Contains("the nodes span x from 0 to 300008, more than one root node holds"));
  d = good;
  d.temporal_format = {1};
  CHECK_THAT(error_of(d), Catch::Contains("node 0 has 'node.temporalFormat' 1; only constant data (0) is supported"));
  d = good;
  d.temporal_arrays = true;
  CHECK_THAT(error_of(d), Catch::Contains("are not supported (no time-varying vdb volumes)"));
}

TEST_CASE("vdb: a ray through a constant block absorbs 1 - exp(-sigma L)", "[volume][vdb][render]") {
  // A level-2 tile of 0.5 (128³ voxels) scaled to [0, 8]³; opacity = value: sigma =
  // 0.5 × densityScale 0.2 per unit.
  VdbData d;
  add_tile(d, 2, {0, 0, 0}, 0.5f);
  d.index_to_object = {{1.f / 16, 0, 0}, {0, 1.f / 16, 0}, {0, 0, 1.f / 16}, {0, 0, 0}};
  const auto alpha = [](VdbData data) {
    const VolumetricModel<Vdb> model(std::make_shared<const Vdb>(std::move(data)),
                                     TransferFunction({{1, 1, 1}}, {0.f, 1.f}, {0.f, 1.f}), 0.2f);
    const Ray<float> ray{{-1.f, 4.f, 4.f}, {1.f, 0.f, 0.f}};
    return model.integrate<simd::scalar>(ray, true, INFINITY, VolumeIntegration{}).alpha;
  };
  d.background = 0.5f;  // the top voxel layer reads 0.5 on both sides: L = 8
  CHECK(alpha(d) == Approx(1.0 - std::exp(-0.1 * 8)).margin(1e-5));
  // With the default NaN background the top layer is transparent: L = 127/16.
  d.background = NAN;
  CHECK(alpha(d) == Approx(1.0 - std::exp(-0.1 * 127 / 16)).margin(1e-5));
}
