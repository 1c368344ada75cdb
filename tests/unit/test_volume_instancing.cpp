// Volumes placed by transforms (VolumeWorld::add_volume with a MotionTransform): marched
// in object space with the world ray's t, so a placed volume renders as the direct volume
// with the transformed grid, its optical depth grows with its world length (as OSPRay's),
// placements of one model share it and composite in each lane's depth order, and a
// moving placement is where each lane's time puts it.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>
#include <vector>

#include "sciray/shim/engine.hpp"
#include "support/isas.hpp"
#include "support/render_stats.hpp"

using namespace sciray;
using sciray::test_support::supported_isas;

namespace {

using FloatVolume = StructuredRegular<float>;
using Model = VolumetricModel<FloatVolume>;

/// A box of `cells` (5x5x9 voxels) from `origin`, whose value grows linearly with z from 0
/// to 1: σ = value is linear along any ray, which the midpoint rule integrates exactly
/// at any step, so placed and direct volumes agree whatever their steps.
std::shared_ptr<const FloatVolume> z_ramp(const Vec3f& origin, const Vec3f& size) {
  const VolumeDims d{5, 5, 9};
  auto voxels = std::make_shared<std::vector<float>>();
  for (std::int64_t z = 0; z < d[2]; ++z)
    for (int k = 0; k < 25; ++k) voxels->push_back(static_cast<float>(z) / 8.f);
  return std::make_shared<FloatVolume>(LinearLayout<float>(voxels->data(), d, voxels),
                                       FloatVolume::Grid{origin, {size.x / 4.f, size.y / 4.f, size.z / 8.f}});
}

/// The unit cube of constant value 1.
std::shared_ptr<const FloatVolume> unit_cube() {
  auto voxels = std::make_shared<std::vector<float>>(8, 1.f);
  return std::make_shared<FloatVolume>(LinearLayout<float>(voxels->data(), {2, 2, 2}, voxels), FloatVolume::Grid{});
}

/// White (or `color`) emission with opacity `sigma` times the value (in [0, 1]).
TransferFunction emission(float sigma, Vec3f color = {1.f, 1.f, 1.f}) {
  return TransferFunction({color}, {0.f, sigma}, {0.f, 1.f});
}

/// A 32x32 view down +z of the square [-1, 2]^2.
FrameBuffer render_down_z(simd::Isa isa, shim::EngineWorld& world, const shim::RendererConfig& renderer) {
  shim::kernels(isa).commit(world);
  OrthographicCamera camera;
  camera.position = {0.5f, 0.5f, -10.f};
  camera.direction = {0.f, 0.f, 1.f};
  camera.height = 3.f;
  FrameBuffer fb(32, 32, ColorFormat::rgba32f);
  FrameSettings settings;
  settings.pixel_filter = PixelFilter::point;
  shim::kernels(isa).render(world, renderer, camera, fb, nullptr, settings);
  return fb;
}

/// Rotation by 90 degrees about +z: (x, y) -> (-y, x).
Affine3f quarter_turn_z() { return {{0.f, 1.f, 0.f}, {-1.f, 0.f, 0.f}, {0.f, 0.f, 1.f}, {0.f, 0.f, 0.f}}; }

}  // namespace

TEST_CASE("a volume placed by a scale, rotation and translation renders as the direct volume with that grid",
          "[volume][instancing][render]") {
  // The unit ramp scaled by (1.5, 0.5, 2), turned a quarter about z and moved: world x in
  // [0.5, 1], y in [-0.5, 1], z in [0.3, 2.3], value (z - 0.3) / 2. The direct volume with
  // that grid (x and y swap sizes; the ramp does not vary across them) must match pixel
  // for pixel, to 1e-4 (the two march different steps; both integrate exactly).
  const Affine3f placement = Affine3f::translate({1.f, -0.5f, 0.3f}) * quarter_turn_z() *
                             Affine3f{{1.5f, 0.f, 0.f}, {0.f, 0.5f, 0.f}, {0.f, 0.f, 2.f}, {0.f, 0.f, 0.f}};
  for (const bool skipping : {true, false})
    for (const auto& [name, renderer] : {std::pair<const char*, shim::RendererConfig>{"scivis", SciVisParams{}},
                                         {"ao", AOParams{}}}) {
      accel::Device device;
      shim::EngineWorld placed(device), direct(device);
      placed.add_volume(Model(z_ramp({0.f, 0.f, 0.f}, {1.f, 1.f, 1.f}), emission(1.f)), MotionTransform(placement));
      direct.add_volume(Model(z_ramp({0.5f, -0.5f, 0.3f}, {0.5f, 1.5f, 2.f}), emission(1.f)));
      shim::RendererConfig config = renderer;
      std::visit([&](auto& p) { p.empty_space_skipping = skipping; }, config);
      CHECK(placed.bounds().lower.x == Approx(0.5f));
      CHECK(placed.bounds().upper.y == Approx(1.f));
      for (auto isa : supported_isas()) {
        INFO(simd::isa_name(isa) << " " << name << (skipping ? " with" : " without") << " empty-space skipping");
        const FrameBuffer a = render_down_z(isa, placed, config), b = render_down_z(isa, direct, config);
        int inside = 0;
        for (std::size_t i = 0; i < a.color32f().size(); ++i) REQUIRE(a.color32f()[i] == Approx(b.color32f()[i]).margin(1e-4));
        for (int pixel = 0; pixel < 32 * 32; ++pixel)
          if (a.color32f()[4 * pixel + 3] > 0.f) {
            // ∫σ = 2 (world length) × 1/2 (the mean value): twice the unit ramp's.
            REQUIRE(a.color32f()[4 * pixel + 3] == Approx(1.f - std::exp(-1.f)).epsilon(1e-4));
            ++inside;
          }
        CHECK(inside > 20);
      }
    }
}

TEST_CASE("a scaled constant slab absorbs per world unit, as OSPRay's volumes do", "[volume][instancing][render]") {
  // σ = 0.7 per unit of the (unit-length) camera ray's t: the unit cube stretched along
  // the view by s is s thick, whatever the sampling rate (OSPRay 3.1 measured alike).
  for (const float s : {0.5f, 1.f, 3.f})
    for (const float rate : {0.5f, 2.f}) {
      accel::Device device;
      shim::EngineWorld world(device);
      world.add_volume(Model(unit_cube(), emission(0.7f)),
                       MotionTransform(Affine3f{{1.f, 0.f, 0.f}, {0.f, 1.f, 0.f}, {0.f, 0.f, s}, {0.f, 0.f, 0.f}}));
      SciVisParams params;
      params.volume_sampling_rate = rate;
      for (auto isa : supported_isas()) {
        INFO(simd::isa_name(isa) << " scale " << s << " rate " << rate);
        const FrameBuffer fb = render_down_z(isa, world, params);
        const int centre = 4 * (16 * 32 + 16);  // x = 0.5 + 1.5/32, y likewise: inside the cube
        REQUIRE(fb.color32f()[centre + 3] == Approx(1.f - std::exp(-0.7f * s)).epsilon(1e-5));
      }
    }
}

TEST_CASE("placed volumes composite in each lane's depth order, placements share their model",
          "[volume][instancing][render]") {
  // A red σ = 2 cube behind a blue one, added first, then placed once more further
  // behind: each lane shows blue over red over red, a = 1 − exp(−2) each.
  accel::Device device;
  shim::EngineWorld world(device);
  const std::size_t red = world.add_volume(Model(unit_cube(), emission(2.f, {1.f, 0.f, 0.f})),
                                           MotionTransform(Affine3f::translate({0.f, 0.f, 2.f})));
  world.add_volume(Model(unit_cube(), emission(2.f, {0.f, 0.f, 1.f})));
  const std::size_t memory_two = world.memory_bytes();
  CHECK(world.place_volume(red, MotionTransform(Affine3f::translate({0.f, 0.f, 4.f}))) == 2);
  CHECK(world.volume_count() == 3);
  CHECK(world.memory_bytes() == memory_two);  // the model is shared, not copied
  const float a = 1.f - std::exp(-2.f);
  SciVisParams params;
  params.volume_sampling_rate = 4.f;
  for (auto isa : supported_isas()) {
    INFO(simd::isa_name(isa));
    const FrameBuffer fb = render_down_z(isa, world, params);
    const int centre = 4 * (16 * 32 + 16);
    CHECK(fb.color32f()[centre + 2] == Approx(a).epsilon(1e-4));
    CHECK(fb.color32f()[centre + 0] == Approx((1.f - a) * a * (2.f - a)).epsilon(1e-4));
    CHECK(fb.color32f()[centre + 3] == Approx(1.f - std::pow(1.f - a, 3.f)).epsilon(1e-4));
  }
}

TEST_CASE("a moving placement is where each lane's time puts it", "[volume][instancing][motion][render]") {
  // The unit cube moves from x = -1 to x = 1 over the shutter; a rolling shutter exposes
  // the rows top to bottom, so packets hold lanes of different times and each row shows
  // the cube's edge where it was then: its left edge at -1 + 2·time.
  constexpr int width = 64, height = 16;
  accel::Device device;
  shim::EngineWorld world(device);
  world.add_volume(Model(unit_cube(), emission(8.f)),
                   MotionTransform({Affine3f::translate({-1.f, 0.f, 0.f}), Affine3f::translate({1.f, 0.f, 0.f})}, 0.f,
                                   1.f));
  CHECK(world.bounds().lower.x == Approx(-1.f));
  CHECK(world.bounds().upper.x == Approx(2.f));
  for (const auto& [name, renderer] : {std::pair<const char*, shim::RendererConfig>{"scivis", SciVisParams{}},
                                       {"pathtracer", PathTracerParams{}}}) {
    for (auto isa : supported_isas()) {
      INFO(simd::isa_name(isa) << " " << name);
      shim::kernels(isa).commit(world);
      OrthographicCamera camera;
      camera.position = {0.5f, 0.5f, -10.f};
      camera.direction = {0.f, 0.f, 1.f};
      camera.height = 1.f;  // x in [-1.5, 2.5], y in [0, 1]
      camera.aspect = 4.f;
      camera.shutter_open = 0.f, camera.shutter_close = 1.f;
      camera.shutter_type = ShutterType::rolling_down;  // the top row at time 0, the bottom one at 1
      FrameBuffer fb(width, height, ColorFormat::rgba32f);
      FrameSettings settings;
      settings.pixel_filter = PixelFilter::point;
      shim::kernels(isa).render(world, renderer, camera, fb, nullptr, settings);
      for (int row = 0; row < height; ++row) {
        // The frame buffer's row 0 is the first one exposed.
        const float time = (static_cast<float>(row) + 0.5f) / height;
        const float edge = -1.f + 2.f * time;
        int first = -1, last = -1;
        for (int x = 0; x < width; ++x)
          if (fb.color32f()[4 * (row * width + x) + 3] > 0.5f) last = x, first = first < 0 ? x : first;
        INFO("row " << row << ": left edge at x = " << edge);
        const float pixel = 4.f / width;
        REQUIRE(first >= 0);
        CHECK(std::abs((-1.5f + (static_cast<float>(first) + 0.5f) * pixel) - edge) <= pixel);
        CHECK(last - first + 1 == Approx(1.f / pixel).margin(1.5));
      }
    }
  }
}

TEST_CASE("placements are checked: singular and non-finite transforms are named", "[volume][instancing][errors]") {
  accel::Device device;
  shim::EngineWorld world(device);
  const Affine3f flat{{1.f, 0.f, 0.f}, {0.f, 1.f, 0.f}, {0.f, 0.f, 0.f}, {0.f, 0.f, 0.f}};
  CHECK_THROWS_WITH(world.add_volume(Model(unit_cube(), emission(1.f)), MotionTransform(flat)),
                    "volume 0: its transform is singular or not finite");
  const std::size_t v = world.add_volume(Model(unit_cube(), emission(1.f)));
  CHECK_THROWS_WITH(world.place_volume(v, MotionTransform({Affine3f{}, flat}, 0.f, 1.f)),
                    "volume 1: its transform is singular or not finite at key 1");
  CHECK_THROWS_AS(world.place_volume(7, MotionTransform()), std::out_of_range);
  CHECK(world.volume_count() == 1);
}

TEST_CASE("scivis shadow rays pass through placed volumes", "[volume][instancing][render]") {
  // A black cube of σ = 1 squeezed to half its depth (z in [0.5, 1]) in front of the
  // plane z = 2, lit from the camera's side by a distant light of irradiance π: the plane
  // (0.8/π per unit irradiance) is seen through the slab (e^-0.5), and lit through it
  // (e^-0.5 again) with shadows.
  accel::Device device;
  shim::EngineWorld world(device);
  world.add_volume(Model(unit_cube(), emission(1.f, {0.f, 0.f, 0.f})),
                   MotionTransform(Affine3f::translate({0.f, 0.f, 0.5f}) *
                                   Affine3f{{1.f, 0.f, 0.f}, {0.f, 1.f, 0.f}, {0.f, 0.f, 0.5f}, {0.f, 0.f, 0.f}}));
  world.add(Planes({{0.f, 0.f, 1.f, -2.f}}));
  DistantLight light;
  light.direction = {0.f, 0.f, 1.f};
  light.intensity = std::numbers::pi_v<float>;
  SciVisParams params;
  params.lights = {light};
  for (const bool shadows : {false, true}) {
    params.shadows = shadows;
    for (auto isa : supported_isas()) {
      INFO(simd::isa_name(isa) << (shadows ? " with shadows" : ""));
      const FrameBuffer fb = render_down_z(isa, world, params);
      const int centre = 4 * (16 * 32 + 16);
      CHECK(fb.color32f()[centre] == Approx(0.8f * std::exp(shadows ? -1.f : -0.5f)).epsilon(1e-4));
    }
  }
}
