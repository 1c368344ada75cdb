// Particle volumes (volume/particle.hpp): the field and its gradient against the sum of
// Gaussians written out here, the support cut-off and the clamp, conservative macrocell
// ranges, packets equal to the scalar path, bad input named, and the alpha of a ray
// through a particle against the Gaussian's line integral.
#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include "sciray/volume/particle.hpp"
#include "sciray/volume/volumetric_model.hpp"

using namespace sciray;

namespace {

/// A uniform number in [0, 1) from a counter (splitmix64).
double uniform(std::uint64_t counter) {
  std::uint64_t z = counter * 0x9E3779B97F4A7C15ull + 0x632BE59BD9B4E019ull;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return static_cast<double>((z ^ (z >> 31)) >> 11) * 0x1p-53;
}

/// The field as the header's comment defines it, in double, its gradient and the sums of
/// the terms' magnitudes (which float rounding is relative to).
double field(const ParticleData& d, const Vec3f& x, std::array<double, 3>* gradient = nullptr,
             std::array<double, 2>* magnitude = nullptr) {
  double sum = 0;
  if (gradient) *gradient = {0, 0, 0};
  if (magnitude) *magnitude = {0, 0};
  for (std::size_t i = 0; i < d.positions.size(); ++i) {
    const double dx = x.x - d.positions[i].x, dy = x.y - d.positions[i].y, dz = x.z - d.positions[i].z;
    const double d2 = dx * dx + dy * dy + dz * dz, r = d.radii[i];
    if (std::sqrt(d2) > d.radius_support_factor * r) continue;
    const double k = (d.weights.empty() ? 1.0 : d.weights[i]) * std::exp(-d2 / (2 * r * r));
    sum += k;
    if (magnitude)
      *magnitude = {(*magnitude)[0] + std::abs(k), (*magnitude)[1] + std::abs(k) * std::sqrt(d2) / (r * r)};
    if (gradient)
      *gradient = {(*gradient)[0] - dx / (r * r) * k, (*gradient)[1] - dy / (r * r) * k,
                   (*gradient)[2] - dz / (r * r) * k};
  }
  return d.clamp_max_cumulative_value > 0 ? std::min(sum, static_cast<double>(d.clamp_max_cumulative_value)) : sum;
}

/// A point uniform in `box`, drawn with counters from `seed`.
Vec3f point_in(const Box3f& box, std::uint64_t seed) {
  const auto at = [&](int k) {
    return box.lower[k] +
           static_cast<float>(uniform(3 * seed + static_cast<std::uint64_t>(k))) * (box.upper[k] - box.lower[k]);
  };
  return {at(0), at(1), at(2)};
}

/// `count` particles in the unit cube with radii in [0.03, 0.09] and weights in [lo, hi].
ParticleData cloud(int count, float lo, float hi, std::uint64_t seed) {
  ParticleData d;
  for (int i = 0; i < count; ++i) {
    const std::uint64_t s = seed + 5 * static_cast<std::uint64_t>(i);
    d.positions.push_back(point_in(Box3f{{0, 0, 0}, {1, 1, 1}}, s));
    d.radii.push_back(0.03f + 0.06f * static_cast<float>(uniform(1000003 + s)));
    d.weights.push_back(lo + (hi - lo) * static_cast<float>(uniform(2000003 + s)));
  }
  return d;
}

void check_against_field(const Particles& volume, const ParticleData& d, int points, std::uint64_t seed) {
  const Box3f box = volume.bounds();
  double worst_value = 0, worst_gradient = 0;
  for (int i = 0; i < points; ++i) {
    const Vec3f p = point_in(box, seed + static_cast<std::uint64_t>(i));
    std::array<double, 3> g;
    std::array<double, 2> scale;
    const double expected = field(d, p, &g, &scale);
    worst_value = std::max(worst_value, std::abs(volume.sample(p) - expected) / std::max(scale[0], 1.0));
    const Vec3f got = volume.gradient<simd::scalar>(p);
    worst_gradient =
        std::max(worst_gradient, std::max({std::abs(got.x - g[0]), std::abs(got.y - g[1]), std::abs(got.z - g[2])}) /
                                     std::max(scale[1], 1.0));
  }
  CHECK(worst_value < 1e-6);  // relative to the sum of the terms' magnitudes: float rounding
  CHECK(worst_gradient < 1e-6);
}

}  // namespace

TEST_CASE("particle: one particle is a Gaussian cut off at radiusSupportFactor radii", "[volume][particle]") {
  ParticleData d;
  d.positions = {{1.f, 2.f, 3.f}};
  d.radii = {0.5f};
  d.weights = {2.f};
  const Particles volume(d);
  CHECK(volume.particle_count() == 1);
  CHECK(volume.bounds().lower == Vec3f{-0.5f, 0.5f, 1.5f});  // ± 3 radii
  CHECK(volume.bounds().upper == Vec3f{2.5f, 3.5f, 4.5f});
  CHECK(volume.cell_size() == Vec3f{0.5f, 0.5f, 0.5f});
  CHECK(volume.value_range() == std::array<float, 2>{0.f, 2.f});
  CHECK(volume.owned_bytes() > 0);
  CHECK(volume.sample({1.f, 2.f, 3.f}) == 2.f);
  // One radius away: 2 e^(-1/2), gradient (-1/r)·value along the offset.
  CHECK(volume.sample({1.5f, 2.f, 3.f}) == Approx(2.0 * std::exp(-0.5)).epsilon(1e-6));
  CHECK(volume.gradient<simd::scalar>({1.f, 2.5f, 3.f}).y == Approx(-2.0 * 2.0 * std::exp(-0.5)).epsilon(1e-6));
  CHECK(volume.gradient<simd::scalar>({1.f, 2.f, 3.f}) == Vec3f{0.f, 0.f, 0.f});
  // The cut-off: 2 e^(-4.5) just inside 3 radii, 0 just beyond (inside the box, not NaN).
  CHECK(volume.sample({1.f, 2.f, 4.49f}) == Approx(2.0 * std::exp(-0.5 * 2.98 * 2.98)).epsilon(1e-5));
  CHECK(volume.sample({1.f, 2.f, 4.4999f}) > 0.02f);
  CHECK(volume.sample({2.1f, 3.1f, 3.f}) == 0.f);  // a box corner region, 1.56 from the centre
  CHECK(volume.gradient<simd::scalar>({2.1f, 3.1f, 3.f}) == Vec3f{0.f, 0.f, 0.f});
  // Outside the box: the background.
  CHECK(std::isnan(volume.sample({1.f, 2.f, 4.51f})));
  CHECK(std::isnan(volume.sample({-0.6f, 2.f, 3.f})));
  d.background = -1.f;
  CHECK(Particles(d).sample({1.f, 2.f, 4.51f}) == -1.f);
  check_against_field(volume, d, 3000, 1);
  // A smaller support: one radius.
  d.radius_support_factor = 1.f;
  const Particles narrow(d);
  CHECK(narrow.bounds().upper == Vec3f{1.5f, 2.5f, 3.5f});
  CHECK(narrow.sample({1.f, 2.f, 3.49f}) == Approx(2.0 * std::exp(-0.5 * 0.98 * 0.98)).epsilon(1e-5));
  CHECK(narrow.sample({1.3f, 2.f, 3.45f}) == 0.f);
  check_against_field(narrow, d, 3000, 2);
  // No weights: 1 each.
  d.weights.clear();
  CHECK(Particles(d).sample({1.f, 2.f, 3.f}) == 1.f);
}

TEST_CASE("particle: overlapping particles sum, the value range is found between them", "[volume][particle]") {
  ParticleData d;
  d.positions = {{0.f, 0.f, 0.f}, {1.5f, 0.f, 0.f}, {0.7f, 0.9f, 0.f}};
  d.radii = {1.f, 0.7f, 0.4f};
  d.weights = {1.f, -0.5f, 0.6f};
  const Particles volume(d);
  check_against_field(volume, d, 5000, 3);
  // The extrema by brute force on a fine lattice of the z = 0 plane (every particle lies in it).
  double lo = 0, hi = 0;
  for (int i = 0; i <= 600; ++i)
    for (int j = 0; j <= 600; ++j) {
      const double v =
          field(d, {-3.f + 6.6f * static_cast<float>(i) / 600.f, -3.f + 6.f * static_cast<float>(j) / 600.f, 0.f});
      lo = std::min(lo, v), hi = std::max(hi, v);
    }
  INFO("lattice [" << lo << ", " << hi << "], estimated [" << volume.value_range()[0] << ", " << volume.value_range()[1]
                   << "]");
  CHECK(volume.value_range()[0] == Approx(lo).margin(1e-3));
  CHECK(volume.value_range()[1] == Approx(hi).margin(1e-3));
  CHECK(volume.value_range()[1] > 1.f);  // the maximum lies between particles 0 and 2, not at a centre
}

TEST_CASE("particle: clampMaxCumulativeValue clamps the sum, estimateValueRanges off takes [Σ negative weights, clamp]",
          "[volume][particle]") {
  ParticleData d;
  d.positions = {{0.f, 0.f, 0.f}, {0.2f, 0.f, 0.f}, {0.f, 0.3f, 0.f}};
  d.radii = {0.5f, 0.5f, 0.5f};
  d.clamp_max_cumulative_value = 2.f;
  const Particles volume(d);
  CHECK(volume.sample({0.f, 0.f, 0.f}) == 2.f);  // 2.76 unclamped
  CHECK(volume.sample({0.1f, 1.2f, 0.f}) == Approx(field(d, {0.1f, 1.2f, 0.f})).epsilon(1e-6));
  CHECK(field(d, {0.1f, 1.2f, 0.f}) < 2.0);
  check_against_field(volume, d, 3000, 4);
  CHECK(volume.value_range() == std::array<float, 2>{0.f, 2.f});
  // The gradient stays the kernels' (as Open VKL's), also where the sum is clamped.
  std::array<double, 3> g;
  d.clamp_max_cumulative_value = 0.f;
  field(d, {0.1f, 0.1f, 0.f}, &g);
  CHECK(volume.gradient<simd::scalar>({0.1f, 0.1f, 0.f}).x == Approx(g[0]).epsilon(1e-5));
  d.clamp_max_cumulative_value = 1.5f;
  d.estimate_value_ranges = false;
  CHECK(Particles(d).value_range() == std::array<float, 2>{0.f, 1.5f});
  d.weights = {1.f, -0.25f, -0.5f};
  CHECK(Particles(d).value_range() == std::array<float, 2>{-0.75f, 1.5f});
}

TEST_CASE("particle: macrocell ranges hold every sample", "[volume][particle]") {
  for (const float clamp : {0.f, 1.2f})
    for (const std::int64_t n : {1, 3, 8}) {
      INFO("clamp " << clamp << ", macrocells of " << n << " radii");
      ParticleData d = cloud(400, -0.5f, 1.5f, 77);
      d.clamp_max_cumulative_value = clamp;
      const Particles volume(d);
      const MacrocellGrid m = volume.macrocell_grid(n);
      std::vector<float> ranges = m.empty_ranges();
      volume.widen_macrocell_ranges(m, n, ranges);
      std::size_t outside = 0, tight = 0;
      for (std::int64_t z = 0; z < m.counts[2]; ++z)
        for (std::int64_t y = 0; y < m.counts[1]; ++y)
          for (std::int64_t x = 0; x < m.counts[0]; ++x) {
            const std::size_t i = m.index(x, y, z);
            const Vec3f lower =
                m.lower + Vec3f{static_cast<float>(x), static_cast<float>(y), static_cast<float>(z)} * m.size;
            const Box3f cell{lower, lower + m.size};
            float seen_hi = -INFINITY;
            for (int s = 0; s < 24; ++s) {
              const float v = volume.sample(point_in(cell, 100000 * i + static_cast<std::size_t>(s)));
              outside += !(v >= ranges[2 * i] && v <= ranges[2 * i + 1]);
              seen_hi = std::max(seen_hi, v);
            }
            tight += ranges[2 * i + 1] - seen_hi < 0.5f;
          }
      CHECK(outside == 0);
      if (n == 1) CHECK(tight > m.count() / 2);  // small macrocells: ranges near the values they hold
    }
}

TEST_CASE("particle: many particles are found through the hierarchy", "[volume][particle]") {
  const ParticleData d = cloud(2000, 0.5f, 1.5f, 5);
  const Particles volume(d);
  CHECK(volume.particle_count() == 2000);
  check_against_field(volume, d, 3000, 6);
  // Positive weights: climbing from every centre finds the largest value of many samples.
  float seen = 0.f;
  for (int i = 0; i < 20000; ++i)
    seen = std::max(seen, volume.sample(point_in(volume.bounds(), 900000 + static_cast<std::uint64_t>(i))));
  CHECK(volume.value_range()[0] == 0.f);
  CHECK(volume.value_range()[1] >= seen);
}

namespace {

template <class Arch>
void check_packets(const Particles& volume, std::uint64_t seed) {
  using F = simd::Float<Arch>;
  constexpr int W = simd::width<Arch>;
  Box3f around = volume.bounds();
  around.lower = around.lower - splat(0.1f), around.upper = around.upper + splat(0.1f);  // some lanes outside
  for (int packet = 0; packet < 200; ++packet) {
    alignas(64) float x[W], y[W], z[W];
    for (int i = 0; i < W; ++i) {
      const Vec3f p = point_in(around, seed + static_cast<std::uint64_t>(W * packet + i));
      x[i] = p.x, y[i] = p.y, z[i] = p.z;
    }
    const Vec3<F> p{simd::load<Arch>(x), simd::load<Arch>(y), simd::load<Arch>(z)};
    const F v = volume.sample<Arch>(p);
    const Vec3<F> g = volume.gradient<Arch>(p), s = volume.shading_gradient<Arch>(p);
    for (int i = 0; i < W; ++i) {
      const Vec3f q{x[i], y[i], z[i]};
      const float expected = volume.sample(q);
      REQUIRE((simd::lane(v, i) == expected || (std::isnan(simd::lane(v, i)) && std::isnan(expected))));
      const Vec3f eg = volume.gradient(q);
      REQUIRE((Vec3f{simd::lane(g.x, i), simd::lane(g.y, i), simd::lane(g.z, i)} == eg));
      REQUIRE((Vec3f{simd::lane(s.x, i), simd::lane(s.y, i), simd::lane(s.z, i)} == eg));
    }
  }
}

}  // namespace

TEST_CASE("particle: packet samples and gradients equal the scalar ones", "[volume][particle][simd]") {
  const Particles volume(cloud(300, -0.5f, 1.5f, 11));
  check_packets<simd::scalar>(volume, 1);
#if XSIMD_WITH_SSE2
  check_packets<xsimd::sse2>(volume, 2);
#endif
#if XSIMD_WITH_AVX512BW
  check_packets<xsimd::avx512bw>(volume, 3);
#endif
}

TEST_CASE("particle: bad input is named", "[volume][particle][errors]") {
  ParticleData good;
  good.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  good.radii = {0.5f, 0.5f, 0.5f};
  good.weights = {1.f, 2.f, 3.f};
  const auto fails = [](const ParticleData& d, const std::string& message) {
    REQUIRE_THROWS_WITH(Particles(d), Catch::Contains(message));
    REQUIRE_THROWS_WITH(Particles(d), Catch::StartsWith("particle volume: "));
  };
  ParticleData d = good;
  d.positions.clear();
  fails(d, "'particle.position' is missing or empty");
  d = good;
  d.radii.pop_back();
  fails(d, "'particle.radius' has 2 values but 'particle.position' has 3 particles");
  d = good;
  d.weights = {1.f, 2.f, 3.f, 4.f};
  fails(d, "'particle.weight' has 4 values but 'particle.position' has 3 particles");
  d = good;
  d.positions[1].y = NAN;
  fails(d, "'particle.position' 1 is not finite");
  d = good;
  d.positions[2].z = INFINITY;
  fails(d, "'particle.position' 2 is not finite");
  d = good;
  d.radii[2] = 0.f;
  fails(d, "'particle.radius' 2 must be finite and greater than 0, got 0");
  d.radii[2] = -1.f;
  fails(d, "'particle.radius' 2 must be finite and greater than 0, got -1");
  d.radii[2] = NAN;
  fails(d, "'particle.radius' 2 must be finite and greater than 0, got nan");
  d = good;
  d.radii[1] = 1e-30f;
  fails(d, "'particle.radius' 1 is 1e-30: with 'radiusSupportFactor' 3 its kernel is out of float range");
  d = good;
  d.weights[0] = INFINITY;
  fails(d, "'particle.weight' 0 is not finite");
  d = good;
  d.radius_support_factor = 0.f;
  fails(d, "'radiusSupportFactor' must be finite and greater than 0, got 0");
  d.radius_support_factor = -2.f;
  fails(d, "'radiusSupportFactor' must be finite and greater than 0, got -2");
  d = good;
  d.clamp_max_cumulative_value = NAN;
  fails(d, "'clampMaxCumulativeValue' is not a number");
  d = good;
  d.estimate_value_ranges = false;
  fails(d, "'estimateValueRanges' is false, which needs 'clampMaxCumulativeValue' greater than 0, got 0");
}

TEST_CASE("particle: a ray's alpha is 1 - exp(-∫σ) with ∫σ the Gaussian's line integral",
          "[volume][particle][render]") {
  // One particle of weight 0.8 and radius 0.5 at the origin, a transfer function whose
  // opacity is the value on [0, 1]: along a line at distance b from the centre,
  //   ∫σ = D w e^(-b²/2r²) r sqrt(2π) erf(h / (r sqrt 2)),  h = sqrt((3r)² - b²)
  // (the support is a sphere of 3 radii). A ray through the centre starts and ends its
  // steps on the support's ends (the midpoint rule's error is then tiny); one beside it
  // meets the cut-off's jump of D w e^(-4.5) mid-step, which costs at most half a step of
  // it at each end.
  ParticleData d;
  d.positions = {{0.f, 0.f, 0.f}};
  d.radii = {0.5f};
  d.weights = {0.8f};
  const auto volume = std::make_shared<Particles>(d);
  const float density = 1.5f;
  const VolumetricModel<Particles> model(volume, TransferFunction({{1, 1, 1}}, {0.f, 1.f}, {0.f, 1.f}), density);
  for (const float b : {0.f, 0.3f, 1.2f})
    for (const float rate : {2.f, 8.f})
      for (const bool skipping : {true, false}) {
        const double r = 0.5, h = std::sqrt(9 * r * r - b * b);
        const double depth = density * 0.8 * std::exp(-b * b / (2 * r * r)) * r * std::sqrt(2 * std::numbers::pi) *
                             std::erf(h / (r * std::sqrt(2.0)));
        const Ray<float> ray{{-4.f, b, 0.f}, {1.f, 0.f, 0.f}};
        VolumeIntegration how;
        how.sampling_rate = rate;
        how.empty_space_skipping = skipping;
        const auto got = model.integrate<simd::scalar>(ray, true, INFINITY, how);
        INFO("b " << b << ", rate " << rate << (skipping ? ", skipping" : ""));
        const double jump = density * 0.8 * std::exp(-4.5), step = r / rate;
        CHECK(got.alpha == Approx(1 - std::exp(-depth)).margin(b == 0.f ? 2e-4 : jump * step + 1e-4));
      }
  // Zero-valued space inside the box is not empty to a transfer function that shows 0:
  // between two particles far apart σ = D all along the box (and beyond 1 the opacity
  // table's end, 1), so alpha = 1 - exp(-D L) with empty-space skipping on.
  d.positions = {{0.f, 0.f, 0.f}, {4.f, 0.f, 0.f}};
  d.radii = {0.25f, 0.25f};
  d.weights = {1.f, 1.f};
  const VolumetricModel<Particles> flat(std::make_shared<Particles>(d),
                                        TransferFunction({{1, 1, 1}}, {1.f, 1.f}, {0.f, 1.f}), 0.2f);
  const auto got =
      flat.integrate<simd::scalar>(Ray<float>{{-2.f, 0.f, 0.f}, {1.f, 0.f, 0.f}}, true, INFINITY, VolumeIntegration{});
  CHECK(got.alpha == Approx(1 - std::exp(-0.2 * 5.5)).margin(1e-5));  // the box spans x in [-0.75, 4.75]
}
