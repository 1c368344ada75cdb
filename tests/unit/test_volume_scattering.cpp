// Volumes as participating media in the path tracer: the Henyey–Greenstein phase
// function, delta tracking and ratio tracking against closed forms and against the
// deterministic ray marcher on real data, and whole renders against analytic single
// scattering, a volumetric white furnace and the three light-sampling strategies.
#include <catch2/catch.hpp>

#include <cmath>
#include <memory>
#include <numbers>
#include <vector>

#include "sciray/io/volume.hpp"
#include "sciray/render/phase.hpp"
#include "sciray/shim/engine.hpp"
#include "support/render_stats.hpp"

using namespace sciray;
using namespace sciray::test_support;

namespace {

constexpr double pi = std::numbers::pi;

/// A volume of constant value 1 over the box [0, size] (2³ vertex-centred voxels).
std::shared_ptr<const StructuredRegular<float>> constant_box(Vec3f size) {
  auto voxels = std::make_shared<std::vector<float>>(8, 1.f);
  return std::make_shared<const StructuredRegular<float>>(LinearLayout<float>(voxels->data(), {2, 2, 2}, voxels),
                                                          VolumeGrid{{0.f, 0.f, 0.f}, size});
}

/// A transfer function giving every value `color` and extinction `sigma` (at densityScale 1).
TransferFunction constant_tf(Vec3f color, float sigma) { return TransferFunction({color}, {sigma}, {0.f, 2.f}); }

std::shared_ptr<const StructuredRegular<std::uint8_t>> neghip() {
  static const io::VolumeFile file = io::read_volume(SCIRAY_DATA_DIR "/volumes/neghip_66x66x66_uint8.raw");
  return std::make_shared<const StructuredRegular<std::uint8_t>>(
      LinearLayout<std::uint8_t>(reinterpret_cast<const std::uint8_t*>(file.voxels->data()), file.dims, file.voxels),
      file.grid);
}

/// A stream of independent uniform numbers for the scalar trackers.
struct Uniforms {
  Pcg32 rng{12345u, 678u};
  long calls = 0;
  float operator()() {
    ++calls;
    return rng.next_float();
  }
};

Ray<float> ray_along_z(float x, float y) {
  Ray<float> r;
  r.org = {x, y, -1.f};
  r.dir = {0.f, 0.f, 1.f};
  r.tnear = 0.f;
  r.tfar = std::numeric_limits<float>::infinity();
  return r;
}

OrthographicCamera looking_down(Vec3f at, float height) {
  OrthographicCamera c;
  c.position = at;
  c.direction = {0.f, 0.f, -1.f};
  c.height = height;
  return c;
}

}  // namespace

TEST_CASE("Henyey-Greenstein: the density integrates to one, sampling follows it, its mean cosine is g",
          "[volume][scattering]") {
  for (float g : {-0.7f, 0.f, 0.3f, 0.9f}) {
    INFO("g = " << g);
    // ∫ p dω = 2π ∫ p(μ) dμ, by the midpoint rule on 200000 intervals.
    double integral = 0, mean_cos = 0;
    const int n = 200000;
    for (int k = 0; k < n; ++k) {
      const double mu = -1 + (k + 0.5) * 2.0 / n;
      const double p = henyey_greenstein(static_cast<float>(mu), g);
      integral += 2 * pi * p * 2.0 / n;
      mean_cos += 2 * pi * p * mu * 2.0 / n;
    }
    CHECK(integral == Approx(1.0).epsilon(1e-3));
    CHECK(mean_cos == Approx(g).margin(1e-3));

    // Sampled directions: unit, mean cosine g, and a histogram of cos θ that matches the
    // density within 4 standard errors per bin.
    const Vec3f dir = normalize(Vec3f{0.3f, -0.5f, 0.8f});
    Pcg32 rng(7u, 11u);
    const int samples = 400000, bins = 20;
    std::vector<int> histogram(bins, 0);
    double sum_cos = 0;
    for (int s = 0; s < samples; ++s) {
      const Vec3f w = sample_henyey_greenstein(dir, g, rng.next_float(), rng.next_float());
      REQUIRE(length(w) == Approx(1.f).margin(1e-5));
      const float c = dot(w, dir);
      sum_cos += c;
      ++histogram[std::min(bins - 1, static_cast<int>((c + 1.f) * 0.5f * bins))];
    }
    CHECK(sum_cos / samples == Approx(g).margin(0.01));
    for (int b = 0; b < bins; ++b) {
      double expected = 0;  // the bin's probability, by quadrature
      for (int k = 0; k < 100; ++k) {
        const double mu = -1 + (b + (k + 0.5) / 100) * 2.0 / bins;
        expected += 2 * pi * henyey_greenstein(static_cast<float>(mu), g) * 2.0 / bins / 100;
      }
      const double observed = static_cast<double>(histogram[b]) / samples;
      CHECK(std::abs(observed - expected) <= 4 * std::sqrt(expected * (1 - expected) / samples) + 1e-4);
    }
  }
}

TEST_CASE("delta tracking: collisions in a constant medium are exponential", "[volume][scattering]") {
  // σ = 1.5 over the unit cube, crossed along z: no collision with probability exp(-1.5),
  // and the depth of a collision, given one, has mean 1/σ - L/(exp(σL) - 1).
  const VolumetricModel<StructuredRegular<float>> model(constant_box({1.f, 1.f, 1.f}), constant_tf({0.5f, 1.f, 2.f}, 1.5f));
  CHECK(model.majorant() == Approx(1.5f));
  Uniforms uniform;
  const int n = 200000;
  int escaped = 0;
  double depth_sum = 0;
  for (int i = 0; i < n; ++i) {
    const auto c = model.sample_collision<simd::scalar>(ray_along_z(0.5f, 0.5f), true, 1e30f, nullptr, uniform);
    if (!c.hit) {
      ++escaped;
      continue;
    }
    REQUIRE(c.t >= 1.f);
    REQUIRE(c.t < 2.f);
    REQUIRE(c.albedo.x == 0.5f);  // the colour, at most 1
    REQUIRE(c.albedo.z == 1.f);
    depth_sum += c.t - 1.0;
  }
  const double p = std::exp(-1.5);
  CHECK(std::abs(static_cast<double>(escaped) / n - p) <= 4 * std::sqrt(p * (1 - p) / n));
  CHECK(depth_sum / (n - escaped) == Approx(1 / 1.5 - 1 / (std::exp(1.5) - 1)).epsilon(0.01));

  // Directions with components of -0 (whose inverse is -inf) cross the macrocells as fast:
  // two numbers a tentative collision, about 1.5 collisions a ray, not a crawl.
  Ray<float> minus_zero = ray_along_z(0.5f, 0.5f);
  minus_zero.dir = {-0.f, -0.f, 1.f};
  uniform.calls = 0;
  escaped = 0;
  for (int i = 0; i < 10000; ++i)
    escaped += model.sample_collision<simd::scalar>(minus_zero, true, 1e30f, nullptr, uniform).hit ? 0 : 1;
  CHECK(std::abs(escaped / 10000.0 - p) <= 4 * std::sqrt(p * (1 - p) / 10000));
  CHECK(uniform.calls < 5 * 10000);

  // t_end (a surface) ends the tracking: nothing collides behind it.
  for (int i = 0; i < 1000; ++i) {
    const auto c = model.sample_collision<simd::scalar>(ray_along_z(0.5f, 0.5f), true, 1.25f, nullptr, uniform);
    REQUIRE((!c.hit || c.t < 1.25f));
  }
}

TEST_CASE("ratio and delta tracking agree with the ray marcher's transmittance on real data",
          "[volume][scattering][accuracy]") {
  // neghip (66³ uint8) with an opacity ramp: the deterministic marcher at 16 samples a cell
  // is the reference. Ratio tracking's mean and delta tracking's escape rate must match it.
  const VolumetricModel<StructuredRegular<std::uint8_t>> model(neghip(), TransferFunction({{1, 1, 1}}, {0.f, 0.08f}, {0.f, 255.f}));
  VolumeIntegration how;
  how.sampling_rate = 16.f;
  for (const Vec3f at : {Vec3f{20.f, 30.f, 0.f}, Vec3f{45.f, 25.f, 0.f}, Vec3f{33.f, 20.f, 0.f}, Vec3f{30.f, 45.f, 0.f}}) {
    Ray<float> ray = ray_along_z(at.x, at.y);
    const float reference = 1.f - model.integrate<simd::scalar>(ray, true, 1e30f, how).alpha;
    INFO("ray at (" << at.x << ", " << at.y << "): transmittance " << reference);
    REQUIRE(reference > 0.05f);
    REQUIRE(reference < 0.95f);
    Uniforms uniform;
    const int n = 40000;
    double sum = 0, sum2 = 0;
    int escaped = 0;
    for (int i = 0; i < n; ++i) {
      const double t = model.transmittance<simd::scalar>(ray, true, 1e30f, nullptr, uniform);
      REQUIRE(t >= 0.0);
      sum += t, sum2 += t * t;
      escaped += model.sample_collision<simd::scalar>(ray, true, 1e30f, nullptr, uniform).hit ? 0 : 1;
    }
    const double mean = sum / n, se = std::sqrt((sum2 / n - mean * mean) / n);
    CHECK(std::abs(mean - reference) <= 4 * se + 2e-3);
    const double rate = static_cast<double>(escaped) / n;
    CHECK(std::abs(rate - reference) <= 4 * std::sqrt(reference * (1 - reference) / n) + 2e-3);
  }
}

TEST_CASE("pathtracer: an absorbing slab passes exp(-tau) of the background", "[volume][scattering][renderers]") {
  // Albedo 0: every collision ends the path, so a pixel is the background times the
  // probability of crossing the slab, exp(-σL), with σ = 1.2 and L = 1.5.
  TestWorld w;
  w.world.add_volume(VolumetricModel<StructuredRegular<float>>(constant_box({4.f, 4.f, 1.5f}), constant_tf({0, 0, 0}, 1.2f)));
  w.world.commit();
  PathTracerParams params;
  params.lights = {};
  params.background_color = {1.f, 1.f, 1.f};
  const auto batches = render_frames(w.world, params, looking_down({2.f, 2.f, 5.f}, 2.f), 64, 64, 32);
  const Stats s = luminance_stats(batches);
  INFO("mean " << s.mean << " +- " << s.stderr_);
  CHECK(std::abs(s.mean - std::exp(-1.2 * 1.5)) <= 4 * s.stderr_);
  CHECK(s.mean == Approx(std::exp(-1.2 * 1.5)).epsilon(0.01));
}

TEST_CASE("pathtracer: single scattering in a slab matches the closed form for each anisotropy",
          "[volume][scattering][renderers]") {
  // A wide slab of thickness h = 0.5, σ = 2 and albedo 1 seen from above, lit by a distant
  // light of irradiance E arriving at angle acos(μ) from the vertical. With maxPathLength 1
  // light scatters once, so a pixel is
  //   E p(cos θ) ∫ σ exp(-σ s) exp(-σ s / μ) ds over s in [0, h]
  //   = E p(cos θ) (1 - exp(-σ h (1 + 1/μ))) / (1 + 1/μ),
  // where θ is the angle between the light's direction of travel and the way to the camera.
  const float sigma = 2.f, h = 0.5f, E = 3.f;
  const Vec3f travel = normalize(Vec3f{0.6f, 0.f, -0.8f});  // μ = 0.8
  const double mu = 0.8;
  for (float g : {0.f, 0.6f, -0.6f}) {
    INFO("anisotropy " << g);
    TestWorld w;
    w.world.add_volume(VolumetricModel<StructuredRegular<float>>(constant_box({20.f, 20.f, h}),
                                                                 constant_tf({1, 1, 1}, sigma), 1.f, g));
    w.world.commit();
    PathTracerParams params;
    DistantLight sun;
    sun.direction = travel;
    sun.intensity = E;
    params.lights = {sun};
    params.max_path_length = 1;
    const auto batches = render_frames(w.world, params, looking_down({10.f, 10.f, 2.f}, 1.f), 128, 128, 64);
    const Stats s = luminance_stats(batches);
    const double expected = E * henyey_greenstein(dot(travel, Vec3f{0.f, 0.f, 1.f}), g) *
                            (1 - std::exp(-sigma * h * (1 + 1 / mu))) / (1 + 1 / mu);
    INFO("mean " << s.mean << " +- " << s.stderr_ << ", expected " << expected);
    CHECK(std::abs(s.mean - expected) <= 4 * s.stderr_);
    CHECK(s.mean == Approx(expected).epsilon(0.01));
  }
}

TEST_CASE("pathtracer: a white scattering volume vanishes in a uniform environment", "[volume][scattering][renderers]") {
  // The volumetric white furnace: neghip with albedo 1 under ambient light 1. However light scatters, none is lost or gained, so every pixel is 1: a
  // bias of more than 0.1 % means the trackers, the phase function or MIS lose energy.
  for (float g : {0.f, 0.7f, -0.4f}) {
    INFO("anisotropy " << g);
    TestWorld w;
    w.world.add_volume(VolumetricModel<StructuredRegular<std::uint8_t>>(
        neghip(), TransferFunction({{1, 1, 1}}, {0.f, 0.2f}, {0.f, 255.f}), 1.f, g));
    w.world.commit();
    PathTracerParams params;
    params.lights = {AmbientLight{}};  // seen by the camera too: the environment
    params.max_path_length = 1000;
    PerspectiveCamera camera;
    camera.position = {33.f, -60.f, 33.f};
    camera.direction = {0.f, 1.f, 0.f};
    camera.up = {0.f, 0.f, 1.f};
    camera.fovy = 40.f;
    const auto batches = render_frames(w.world, params, camera, 96, 96, 100);
    const Stats s = luminance_stats(batches);
    INFO("mean " << s.mean << " +- " << s.stderr_);
    CHECK(std::abs(s.mean - 1.0) <= 1e-3);
    CHECK(s.stderr_ < 4e-4);  // enough samples to see a bias of 0.1 %
  }
}

TEST_CASE("pathtracer: light sampling, phase sampling and MIS converge to the same volume image",
          "[volume][scattering][renderers]") {
  // neghip with albedo 0.8 and forward scattering, lit by a sphere light with size: the
  // three estimators of direct light must agree within their combined noise.
  TestWorld w;
  w.world.add_volume(VolumetricModel<StructuredRegular<std::uint8_t>>(
      neghip(), TransferFunction({{0.8f, 0.8f, 0.8f}}, {0.f, 0.15f}, {0.f, 255.f}), 1.f, 0.5f));
  w.world.commit();
  PathTracerParams params;
  SphereLight lamp;
  lamp.position = {80.f, -20.f, 70.f};
  lamp.radius = 35.f;
  lamp.intensity = 2e4f;
  params.lights = {lamp};
  params.max_path_length = 8;
  PerspectiveCamera camera;
  camera.position = {33.f, -60.f, 33.f};
  camera.direction = {0.f, 1.f, 0.f};
  camera.up = {0.f, 0.f, 1.f};
  camera.fovy = 40.f;
  std::vector<Stats> results;
  for (LightSampling strategy : {LightSampling::mis, LightSampling::lights_only, LightSampling::bsdf_only}) {
    params.light_sampling = strategy;
    results.push_back(luminance_stats(render_frames(w.world, params, camera, 32, 32, 64)));
  }
  INFO("MIS " << results[0].mean << " +- " << results[0].stderr_ << ", lights " << results[1].mean << " +- "
              << results[1].stderr_ << ", phase " << results[2].mean << " +- " << results[2].stderr_);
  REQUIRE(results[0].mean > 0.01);
  for (int k : {1, 2})
    CHECK(std::abs(results[k].mean - results[0].mean) <=
          4 * std::hypot(results[k].stderr_, results[0].stderr_));
  // MIS is never much noisier than the better of the two alone.
  CHECK(results[0].stderr_ <= 1.2 * std::min(results[1].stderr_, results[2].stderr_));
}

TEST_CASE("volumetric model: anisotropy outside [-1, 1] is refused by name", "[volume][scattering][errors]") {
  CHECK_THROWS_WITH((VolumetricModel<StructuredRegular<float>>(constant_box({1.f, 1.f, 1.f}), constant_tf({1, 1, 1}, 1.f),
                                                               1.f, 1.5f)),
                    "volumetric model: 'anisotropy' must be in [-1, 1], got 1.500000");
  VolumetricModel<StructuredRegular<float>> model(constant_box({1.f, 1.f, 1.f}), constant_tf({1, 1, 1}, 1.f));
  CHECK_THROWS_WITH(model.set_anisotropy(NAN), Catch::Contains("'anisotropy' must be in [-1, 1]"));
  CHECK(model.anisotropy() == 0.f);
}
