// Structured volumes: sampling every voxel type and layout against analytic fields,
// transfer functions, and the ray marcher against closed-form integrals on every ISA.
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>
#include <vector>

#include "sciray/io/frame_io.hpp"
#include "sciray/io/volume.hpp"
#include "sciray/shim/engine.hpp"
#include "sciray/testing/scenes.hpp"
#include "support/isas.hpp"

using namespace sciray;
using sciray::test_support::supported_isas;

namespace {

/// f(x, y, z) = 3 + 2x + y/2 + 5z on voxel indices, rounded to the voxel type.
template <class Voxel>
std::shared_ptr<std::vector<Voxel>> linear_field(const VolumeDims& d) {
  auto voxels = std::make_shared<std::vector<Voxel>>();
  for (std::int64_t z = 0; z < d[2]; ++z)
    for (std::int64_t y = 0; y < d[1]; ++y)
      for (std::int64_t x = 0; x < d[0]; ++x) voxels->push_back(static_cast<Voxel>(3 + 2 * x + y / 2.0 + 5 * z));
  return voxels;
}

double field(double x, double y, double z) {
  return 3 + 2 * x + y / 2 + 5 * z;
}

template <class Voxel, template <class> class Layout>
StructuredRegular<Voxel, Layout> make_volume(const std::shared_ptr<std::vector<Voxel>>& voxels, const VolumeDims& d,
                                             const VolumeGrid& grid) {
  if constexpr (std::is_same_v<Layout<Voxel>, LinearLayout<Voxel>>)
    return {LinearLayout<Voxel>(voxels->data(), d, voxels), grid};
  else
    return {BrickedLayout<Voxel>(voxels->data(), d), grid};
}

template <class Voxel, template <class> class Layout>
void check_trilinear_sampling() {
  const VolumeDims d{37, 20, 11};  // not a multiple of the bricks, to cross their edges
  const auto voxels = linear_field<Voxel>(d);
  const VolumeGrid grid{{-1.f, 2.f, 0.5f}, {0.5f, 2.f, 1.f}, false};
  const auto volume = make_volume<Voxel, Layout>(voxels, d, grid);
  using A = xsimd::default_arch;
  constexpr int W = simd::width<A>;
  for (int i = 0; i < 400; ++i) {
    alignas(64) float px[W], py[W], pz[W];
    double expected[W];
    for (int k = 0; k < W; ++k) {
      // Voxel coordinates with an integer y (the field's y/2 rounds for integer voxels).
      const double x = 36 * testing::hash_uniform(3 * (W * i + k)),
                   y = std::floor(19 * testing::hash_uniform(3 * (W * i + k) + 1));
      const double z = 10 * testing::hash_uniform(3 * (W * i + k) + 2);
      px[k] = static_cast<float>(-1 + 0.5 * x), py[k] = static_cast<float>(2 + 2 * y),
      pz[k] = static_cast<float>(0.5 + z);
      expected[k] = std::is_integral_v<Voxel> ? field(x, 2 * std::floor(y / 2), z) : field(x, y, z);
    }
    const Vec3<simd::Float<A>> p{simd::load<A>(px), simd::load<A>(py), simd::load<A>(pz)};
    const auto packet = volume.template sample<A>(p);
    for (int k = 0; k < W; ++k) {
      const float scalar = volume.template sample<simd::scalar>(Vec3f{px[k], py[k], pz[k]});
      REQUIRE(simd::lane(packet, k) == Approx(scalar).epsilon(1e-6));  // FMA contraction may differ
      REQUIRE(scalar == Approx(expected[k]).epsilon(1e-5));
    }
  }
}

}  // namespace

TEST_CASE("trilinear samples of a linear field are exact, for every voxel type and layout", "[volume]") {
  check_trilinear_sampling<float, LinearLayout>();
  check_trilinear_sampling<double, LinearLayout>();
  check_trilinear_sampling<std::uint8_t, LinearLayout>();
  check_trilinear_sampling<std::int16_t, LinearLayout>();
  check_trilinear_sampling<std::uint16_t, LinearLayout>();
  check_trilinear_sampling<float, BrickedLayout>();
  check_trilinear_sampling<std::uint8_t, BrickedLayout>();
  check_trilinear_sampling<std::int16_t, BrickedLayout>();
}

TEST_CASE("packets gather uint8 corners from a misaligned array up to its last voxel as lane-by-lane loads do",
          "[volume][simd]") {
  const VolumeDims d{5, 4, 3};
  for (std::size_t start = 0; start < 4; ++start) {
    // The voxels at every alignment, the last one at the very end of the allocation.
    std::vector<std::uint8_t> storage(start + 60);
    for (std::size_t i = 0; i < 60; ++i) storage[start + i] = static_cast<std::uint8_t>(251 - 4 * i);
    const StructuredRegular<std::uint8_t> volume(LinearLayout<std::uint8_t>(storage.data() + start, d), VolumeGrid{});
    REQUIRE(volume.layout().gathers_cells());
    using A = xsimd::default_arch;
    constexpr int W = simd::width<A>;
    for (int i = 0; i < 64; ++i) {
      alignas(64) float p[3][W];
      for (int k = 0; k < W; ++k)
        for (int a = 0; a < 3; ++a)  // up to and past the far corner, where the last cell is read
          p[a][k] = static_cast<float>(d[a]) * static_cast<float>(testing::hash_uniform(3 * (W * i + k) + a));
      const auto packet = volume.template sample<A>({simd::load<A>(p[0]), simd::load<A>(p[1]), simd::load<A>(p[2])});
      for (int k = 0; k < W; ++k) {
        INFO("start " << start << ", position " << p[0][k] << " " << p[1][k] << " " << p[2][k]);
        CHECK(simd::lane(packet, k) == Approx(volume.template sample<simd::scalar>(Vec3f{p[0][k], p[1][k], p[2][k]}))
                                           .epsilon(1e-6));
      }
    }
  }
}

TEST_CASE("volumes are shaded with the trilinear interpolant's own gradient, as Open VKL's (OSPRay's gradient shading)",
          "[volume]") {
  // Values 0, 1, 2, 1, 0 along z (OSPRay's Transparency scene's volume across its depth),
  // spacing 0.1 on a vertex-centred grid: the interpolant rises at 10 per unit up to the
  // middle voxel and falls after it. Its own derivative holds that up to the kink and at
  // the faces; central differences of one spacing flatten it near both (1/4 of it at
  // voxel coordinate 1.75, 5/8 at 0.25, where the clamp cuts them). OSPRay 3.1's scivis,
  // sampling that scene's volume 20 times a voxel, shades as this gradient does: its
  // middle rows show 0.655 (this gradient: 0.656; forward differences: 0.639) and its
  // rows 1.2 voxels above the bottom face 0.612 (this gradient: 0.614; central
  // differences: 0.526), measured with its runtime.
  const VolumeDims d{2, 2, 5};
  auto voxels = std::make_shared<std::vector<float>>();
  for (const float v : {0.f, 1.f, 2.f, 1.f, 0.f})
    for (int k = 0; k < 4; ++k) voxels->push_back(v);
  const VolumeGrid grid{{0.f, 0.f, 0.f}, {0.1f, 0.1f, 0.1f}, false};
  const StructuredRegular<float> volume({voxels->data(), d, voxels}, grid);
  const auto gradient_at = [&](float voxel_z) { return volume.shading_gradient<simd::scalar>(Vec3f{0.05f, 0.05f, 0.1f * voxel_z}); };
  for (const float z : {0.f, 0.25f, 1.f, 1.75f, 1.999f}) {
    INFO("voxel z " << z);
    CHECK(gradient_at(z).z == Approx(10.f).epsilon(1e-4));
    CHECK(gradient_at(z).x == 0.f);
  }
  for (const float z : {2.001f, 2.5f, 3.75f, 4.f}) {
    INFO("voxel z " << z);
    CHECK(gradient_at(z).z == Approx(-10.f).epsilon(1e-4));
  }
  // gradient() (isosurface normals, smooth across cells) keeps central differences.
  CHECK(volume.gradient<simd::scalar>(Vec3f{0.05f, 0.05f, 0.175f}).z == Approx(2.5f).epsilon(1e-4));
  // Outside the grid the clamped field is flat along the axes it left.
  CHECK(volume.shading_gradient<simd::scalar>(Vec3f{0.05f, 0.05f, -0.1f}).z == 0.f);
  CHECK(volume.shading_gradient<simd::scalar>(Vec3f{0.05f, 0.05f, 0.6f}).z == 0.f);
  // Packets agree with single lanes.
  using A = xsimd::default_arch;
  constexpr int W = simd::width<A>;
  alignas(64) float pz[W];
  for (int k = 0; k < W; ++k) pz[k] = 0.4f * (static_cast<float>(k) + 0.5f) / W;
  const auto packet = volume.shading_gradient<A>(Vec3<simd::Float<A>>{simd::Float<A>(0.05f), simd::Float<A>(0.05f), simd::load<A>(pz)});
  for (int k = 0; k < W; ++k) CHECK(simd::lane(packet.z, k) == volume.shading_gradient<simd::scalar>(Vec3f{0.05f, 0.05f, pz[k]}).z);
}

TEST_CASE("nearest filtering and cell-centred grids", "[volume]") {
  const VolumeDims d{4, 4, 4};
  const auto voxels = linear_field<float>(d);
  StructuredRegular<float> vertex({voxels->data(), d, voxels}, {{0, 0, 0}, {1, 1, 1}, false}, VolumeFilter::nearest);
  CHECK(vertex.sample<simd::scalar>(Vec3f{1.4f, 2.f, 0.6f}) == float(field(1, 2, 1)));
  CHECK(vertex.bounds().upper.x == 3.f);
  StructuredRegular<float> cells({voxels->data(), d, voxels}, {{0, 0, 0}, {1, 1, 1}, true});
  // Cell-centred: voxel i sits at i + ½, and the grid covers whole cells.
  CHECK(cells.sample<simd::scalar>(Vec3f{1.5f, 2.5f, 3.5f}) == Approx(field(1, 2, 3)));
  CHECK(cells.bounds().upper.x == 4.f);
}

TEST_CASE("the cubic filter reproduces linear fields and smooths steps", "[volume]") {
  const VolumeDims d{12, 10, 9};
  const auto voxels = linear_field<float>(d);
  const StructuredRegular<float> volume({voxels->data(), d, voxels}, VolumeGrid{}, VolumeFilter::cubic);
  using A = xsimd::default_arch;
  constexpr int W = simd::width<A>;
  for (int i = 0; i < 100; ++i) {
    alignas(64) float px[W], py[W], pz[W];
    for (int k = 0; k < W; ++k) {
      // Away from the border, where clamped indices would bend the field.
      px[k] = 1.f + 9.f * testing::hash_uniform(3 * (W * i + k)), py[k] = 1.f + 7.f * testing::hash_uniform(3 * (W * i + k) + 1);
      pz[k] = 1.f + 6.f * testing::hash_uniform(3 * (W * i + k) + 2);
    }
    const auto packet = volume.sample<A>({simd::load<A>(px), simd::load<A>(py), simd::load<A>(pz)});
    for (int k = 0; k < W; ++k)
      REQUIRE(simd::lane(packet, k) == Approx(field(px[k], py[k], pz[k])).epsilon(1e-5));
  }
  // A step between two voxels: the B-spline rises smoothly through it (and never overshoots).
  auto step = std::make_shared<std::vector<float>>();
  for (int z = 0; z < 4; ++z)
    for (int y = 0; y < 4; ++y)
      for (int x = 0; x < 8; ++x) step->push_back(x < 4 ? 0.f : 1.f);
  const StructuredRegular<float> edge({step->data(), {8, 4, 4}, step}, VolumeGrid{}, VolumeFilter::cubic);
  float last = -1.f;
  for (float x = 1.f; x <= 6.f; x += 0.25f) {
    const float v = edge.sample<simd::scalar>(Vec3f{x, 1.5f, 1.5f});
    CHECK(v >= last - 1e-6f);  // monotone up to rounding on the plateau
    CHECK(v >= 0.f);
    CHECK(v <= 1.f + 1e-6f);
    last = v;
  }
  CHECK(edge.sample<simd::scalar>(Vec3f{3.5f, 1.5f, 1.5f}) == Approx(0.5f));
}

TEST_CASE("transfer functions interpolate and bound their opacity", "[volume][tf]") {
  const TransferFunction tf({{0, 0, 1}, {1, 0, 0}}, {0.f, 1.f, 0.f}, {10.f, 20.f});
  CHECK(tf.opacity<simd::scalar>(15.f) == Approx(1.f));
  CHECK(tf.opacity<simd::scalar>(12.5f) == Approx(0.5f));
  CHECK(tf.opacity<simd::scalar>(5.f) == 0.f);  // below the range: the first entry
  CHECK(tf.color<simd::scalar>(17.5f).x == Approx(0.75f));
  CHECK(tf.max_opacity(11.f, 19.f) == Approx(1.f));  // the peak between the ends
  CHECK(tf.max_opacity(10.f, 11.f) == Approx(0.2f));
  CHECK_THROWS_WITH(TransferFunction({{0, 0, 1}}, {}, {0.f, 1.f}), Catch::Contains("'opacity' is missing"));
  CHECK_THROWS_WITH(TransferFunction({{0, 0, 1}}, {1.f}, {1.f, 1.f}), Catch::Contains("lo < hi"));
  CHECK_THROWS_WITH(TransferFunction({{0, 0, 1}}, {-1.f}, {0.f, 1.f}), Catch::Contains("'opacity' 0"));
}

namespace {

/// Renders `world` with scivis looking down -z... along +z through x, y in [0, 1].
FrameBuffer render_volume(simd::Isa isa, shim::EngineWorld& world, SciVisParams params = {}, int size = 16) {
  shim::kernels(isa).commit(world);
  OrthographicCamera camera;
  camera.position = {0.5f, 0.5f, -5.f};
  camera.direction = {0.f, 0.f, 1.f};
  camera.height = 1.f;
  FrameBuffer fb(size, size, ColorFormat::rgba32f);
  shim::kernels(isa).render_scivis(world, params, camera, fb, nullptr);
  return fb;
}

}  // namespace

TEST_CASE("the ray marcher integrates extinction exactly for linear fields", "[volume][render][simd]") {
  // A unit cube whose value grows linearly with z from 0 to 1, a transfer function whose
  // opacity is the value: σ(z) = densityScale·z, so ∫σ = densityScale/2 along z and the
  // opacity is 1 − exp(−densityScale/2) whatever the sampling rate (the midpoint rule is
  // exact for linear integrands). White emission: colour = opacity.
  const VolumeDims d{5, 5, 9};
  auto voxels = std::make_shared<std::vector<float>>();
  for (std::int64_t z = 0; z < d[2]; ++z)
    for (int k = 0; k < 25; ++k) voxels->push_back(static_cast<float>(z) / 8.f);
  const auto volume =
      std::make_shared<StructuredRegular<float>>(LinearLayout<float>(voxels->data(), d, voxels),
                                                 StructuredRegular<float>::Grid{{0, 0, 0}, {0.25f, 0.25f, 0.125f}});
  // Any partition of the ray into steps integrates a linear extinction exactly, so
  // adaptive step lengths must hold to the same closed form.
  for (auto isa : supported_isas())
    for (float rate : {0.25f, 1.f, 3.7f})
      for (bool adaptive : {false, true}) {
        INFO(simd::isa_name(isa) << " at " << rate << " samples a cell" << (adaptive ? ", adaptive" : ""));
        accel::Device device;
        shim::EngineWorld world(device);
        world.add_volume(VolumetricModel<StructuredRegular<float>>(
            volume, TransferFunction({{1, 1, 1}}, {0.f, 1.f}, {0.f, 1.f}), 3.f));
        SciVisParams params;
        params.volume_sampling_rate = rate;
        params.volume_adaptive_sampling = adaptive;
        const FrameBuffer fb = render_volume(isa, world, params);
        const float expected = 1.f - std::exp(-1.5f);
        for (int pixel = 0; pixel < 256; ++pixel) {
          REQUIRE(fb.color32f()[4 * pixel + 3] == Approx(expected).epsilon(1e-5));
          REQUIRE(fb.color32f()[4 * pixel] == Approx(expected).epsilon(1e-5));
        }
      }
}

TEST_CASE("empty-space skipping changes the work, not the image", "[volume][render]") {
  // A 64³ volume that is zero except for a ball of value 1: most macrocells are empty.
  const VolumeDims d{64, 64, 64};
  auto voxels = std::make_shared<std::vector<std::uint8_t>>();
  for (std::int64_t z = 0; z < 64; ++z)
    for (std::int64_t y = 0; y < 64; ++y)
      for (std::int64_t x = 0; x < 64; ++x)
        voxels->push_back((x - 40) * (x - 40) + (y - 30) * (y - 30) + (z - 34) * (z - 34) < 100 ? 200 : 0);
  const auto volume = std::make_shared<StructuredRegular<std::uint8_t>>(
      LinearLayout<std::uint8_t>(voxels->data(), d, voxels),
      StructuredRegular<std::uint8_t>::Grid{{0, 0, 0}, {1.f / 63, 1.f / 63, 1.f / 63}});
  accel::Device device;
  shim::EngineWorld world(device);
  world.add_volume(VolumetricModel<StructuredRegular<std::uint8_t>>(
      volume, TransferFunction({{1, 0.5f, 0}, {0, 0.5f, 1}}, {0.f, 0.f, 40.f}, {0.f, 255.f})));
  for (auto isa : supported_isas()) {
    INFO(simd::isa_name(isa));
    SciVisParams skip, no_skip;
    no_skip.empty_space_skipping = false;
    const auto a = render_volume(isa, world, skip, 48), b = render_volume(isa, world, no_skip, 48);
    // The same sample positions up to the rounding of t + n·dt against n additions of dt.
    float total = 0, worst = 0;
    for (std::size_t i = 0; i < a.color32f().size(); ++i)
      worst = std::max(worst, std::fabs(a.color32f()[i] - b.color32f()[i]));
    for (std::size_t i = 3; i < a.color32f().size(); i += 4) total += a.color32f()[i];
    CHECK(worst < 1e-4f);
    CHECK(total > 10.f);  // the ball shows
  }
}

TEST_CASE("a surface inside a volume ends the integration and shows through", "[volume][render]") {
  // A constant volume of σ = 2 over the unit cube, a sphere of radius 0.25 at its centre.
  const VolumeDims d{2, 2, 2};
  auto voxels = std::make_shared<std::vector<float>>(8, 1.f);
  const auto volume = std::make_shared<StructuredRegular<float>>(LinearLayout<float>(voxels->data(), d, voxels),
                                                                 StructuredRegular<float>::Grid{});
  accel::Device device;
  shim::EngineWorld world(device);
  world.add_volume(VolumetricModel<StructuredRegular<float>>(volume, TransferFunction({{0, 0, 1}}, {2.f}, {0.f, 2.f})));
  SphereData ball;
  ball.positions = {0.5f, 0.5f, 0.5f};
  ball.radius = 0.25f;
  world.add(Spheres(ball));
  SciVisParams params;
  params.lights = {AmbientLight{}};  // the sphere shows its albedo
  params.volume_sampling_rate = 8.f;
  for (auto isa : supported_isas()) {
    INFO(simd::isa_name(isa));
    const auto fb = render_volume(isa, world, params, 16);
    // Centre pixel (7.5 + 0.5 offset hits the middle): volume from z = 0 to the sphere at
    // z = 0.25, then the sphere (grey 0.8) behind it.
    const std::size_t centre = 4 * (8 * 16 + 8);
    const float x = 0.5f + 0.5f / 16, y = x;
    const float depth = 0.5f - std::sqrt(0.25f * 0.25f - (x - 0.5f) * (x - 0.5f) - (y - 0.5f) * (y - 0.5f));
    const float alpha = 1.f - std::exp(-2.f * depth);
    CHECK(fb.color32f()[centre + 2] == Approx(alpha + (1 - alpha) * 0.8f).epsilon(1e-4));  // blue
    CHECK(fb.color32f()[centre + 0] == Approx((1 - alpha) * 0.8f).epsilon(1e-4));          // red: the sphere only
    CHECK(fb.color32f()[centre + 3] == Approx(1.f));
    // A corner pixel misses the sphere: the whole unit depth of volume.
    CHECK(fb.color32f()[3] == Approx(1.f - std::exp(-2.f)).epsilon(1e-4));
  }
}

TEST_CASE("volume input is checked", "[volume][errors]") {
  auto voxels = std::make_shared<std::vector<float>>(8, 1.f);
  using Volume = StructuredRegular<float>;
  CHECK_THROWS_WITH(Volume(LinearLayout<float>(voxels->data(), {1, 2, 4}), {}), Catch::Contains("at least 2"));
  CHECK_THROWS_WITH(Volume(LinearLayout<float>(voxels->data(), {2, 2, 2}), {{0, 0, 0}, {1, 0, 1}}),
                    Catch::Contains("'gridSpacing' must be positive"));
  (*voxels)[5] = std::nanf("");
  const auto with_nan =
      std::make_shared<Volume>(LinearLayout<float>(voxels->data(), {2, 2, 2}, voxels), Volume::Grid{});
  CHECK_THROWS_WITH(VolumetricModel<Volume>(with_nan, TransferFunction({{1, 1, 1}}, {1.f}, {0.f, 1.f})),
                    Catch::Contains("voxel (1, 0, 1) is not finite"));
}

TEST_CASE("clipping geometry cuts volumes as it cuts surfaces", "[volume][clipping][render]") {
  // The constant σ = 2 unit cube, the half z < 0.5 clipped by a plane: half the depth.
  auto voxels = std::make_shared<std::vector<float>>(8, 1.f);
  const auto volume =
      std::make_shared<StructuredRegular<float>>(LinearLayout<float>(voxels->data(), {2, 2, 2}, voxels), VolumeGrid{});
  accel::Device device;
  shim::EngineWorld world(device);
  world.add_volume(VolumetricModel<StructuredRegular<float>>(volume, TransferFunction({{1, 1, 1}}, {2.f}, {0.f, 2.f})));
  auto clipping = std::make_shared<Clipping>();
  clipping->add_plane({0.f, 0.f, 1.f}, -0.5f);
  world.set_clipping(clipping);
  SciVisParams params;
  params.volume_sampling_rate = 10.f;  // steps of 0.1: the plane falls on a step boundary
  for (auto isa : supported_isas()) {
    INFO(simd::isa_name(isa));
    const auto fb = render_volume(isa, world, params, 8);
    for (int pixel = 0; pixel < 64; ++pixel)
      REQUIRE(fb.color32f()[4 * pixel + 3] == Approx(1.f - std::exp(-1.f)).epsilon(1e-4));
  }
}

TEST_CASE("pre-integration keeps a narrow transfer-function feature at coarse steps",
          "[volume][preintegration][simd]") {
  // The value rises linearly with z from 0 to 1 over the unit cube; the transfer function
  // is opaque only in a band of values 0.02 wide around 0.53, which steps of 0.125 in z
  // step over.
  const VolumeDims d{2, 2, 9};
  auto voxels = std::make_shared<std::vector<float>>();
  for (std::int64_t z = 0; z < d[2]; ++z)
    for (int k = 0; k < 4; ++k) voxels->push_back(static_cast<float>(z) / 8.f);
  const auto volume = std::make_shared<StructuredRegular<float>>(LinearLayout<float>(voxels->data(), d, voxels),
                                                                 VolumeGrid{{0, 0, 0}, {1.f, 1.f, 0.125f}});
  // 101 opacity entries over [0, 1]: 0 everywhere but a peak of 20 at 0.53 (entry 53).
  std::vector<float> opacity(101, 0.f);
  opacity[53] = 20.f;
  // Triangle of height 20 over [0.52, 0.54]: ∫σ dv = 0.2, and dv/dz = 1, so ∫σ dz = 0.2.
  const float expected = 1.f - std::exp(-0.2f);
  accel::Device device;
  shim::EngineWorld world(device);
  world.add_volume(
      VolumetricModel<StructuredRegular<float>>(volume, TransferFunction({{1, 1, 1}}, opacity, {0.f, 1.f})));
  for (auto isa : supported_isas()) {
    INFO(simd::isa_name(isa));
    SciVisParams midpoint, preintegrated;
    midpoint.volume_sampling_rate = preintegrated.volume_sampling_rate = 1.f;  // steps of 0.125 in z
    preintegrated.volume_preintegration = true;
    const float plain = render_volume(isa, world, midpoint, 4).color32f()[3];
    const float pre = render_volume(isa, world, preintegrated, 4).color32f()[3];
    INFO("midpoint " << plain << ", pre-integrated " << pre << ", exact " << expected);
    CHECK(std::fabs(plain - expected) > 0.5f * expected);  // the steps' midpoints miss the band
    CHECK(pre == Approx(expected).epsilon(2e-3));
  }
}

TEST_CASE("a volume over 4 GiB and 2^32 voxels is addressed right", "[volume][large]") {
  // 2048 × 2048 × 1030 uint8 voxels (4.32 GB) generated on the fly, value (x + 3y + 7z)
  // mod 251; samples beyond voxel 2^32 (z ≥ 1024) must read what the formula says.
  const VolumeDims d{2048, 2048, 1030};
  const auto value = [](std::int64_t x, std::int64_t y, std::int64_t z) { return (x + 3 * y + 7 * z) % 251; };
  auto voxels = std::make_shared<std::vector<std::uint8_t>>();
  voxels->resize(static_cast<std::size_t>(d[0] * d[1] * d[2]));
  REQUIRE(voxels->size() > (std::size_t{1} << 32));
  std::vector<std::uint8_t> period(251 + 2048);  // one row starting anywhere in the period
  for (std::size_t i = 0; i < period.size(); ++i) period[i] = static_cast<std::uint8_t>(i % 251);
  for (std::int64_t z = 0; z < d[2]; ++z)
    for (std::int64_t y = 0; y < d[1]; ++y)
      std::copy_n(period.begin() + value(0, y, z), d[0], voxels->begin() + (z * d[1] + y) * d[0]);
  const StructuredRegular<std::uint8_t> volume(LinearLayout<std::uint8_t>(voxels->data(), d, voxels), VolumeGrid{});
  using A = xsimd::default_arch;
  constexpr int W = simd::width<A>;
  for (int i = 0; i < 64; ++i) {
    alignas(64) float px[W], py[W], pz[W];
    double expected[W];
    for (int k = 0; k < W; ++k) {
      // A point inside a cell of the last slabs whose corners do not wrap around 251.
      std::int64_t x, y, z;
      std::uint64_t n = 97 * (W * i + k);
      do {
        x = static_cast<std::int64_t>(2046 * testing::hash_uniform(n++)),
        y = static_cast<std::int64_t>(2046 * testing::hash_uniform(n++));
        z = 1024 + static_cast<std::int64_t>(5 * testing::hash_uniform(n++));
      } while (value(x, y, z) > 251 - 12);  // +1 in x, +3 in y, +7 in z stays below 251
      const double fx = testing::hash_uniform(n++), fy = testing::hash_uniform(n++), fz = testing::hash_uniform(n++);
      px[k] = static_cast<float>(x + fx), py[k] = static_cast<float>(y + fy), pz[k] = static_cast<float>(z + fz);
      // The field is linear inside such a cell: its value at the (float-rounded) point.
      expected[k] = value(x, y, z) + (px[k] - x) + 3 * (py[k] - y) + 7 * (pz[k] - z);
    }
    const auto packet = volume.sample<A>({simd::load<A>(px), simd::load<A>(py), simd::load<A>(pz)});
    for (int k = 0; k < W; ++k) {
      REQUIRE(simd::lane(packet, k) == Approx(expected[k]).margin(1e-3));
      REQUIRE(volume.sample<simd::scalar>(Vec3f{px[k], py[k], pz[k]}) == Approx(expected[k]).margin(1e-3));
    }
  }
  // The very last voxel, 4.32e9 bytes in.
  CHECK(volume.voxel(2047, 2047, 1029) == static_cast<float>(value(2047, 2047, 1029)));
}

TEST_CASE("the ray marcher converges to a double-precision reference integral on real data", "[volume][accuracy]") {
  // neghip (66³ uint8) through a ramp transfer function; the reference integrates the same
  // emission–absorption model in double precision with steps of 1/1000 of a cell.
  const io::VolumeFile file = io::read_volume(SCIRAY_DATA_DIR "/volumes/neghip_66x66x66_uint8.raw");
  const auto* voxels = reinterpret_cast<const std::uint8_t*>(file.voxels->data());
  const auto volume = std::make_shared<const StructuredRegular<std::uint8_t>>(
      LinearLayout<std::uint8_t>(voxels, file.dims, file.voxels), file.grid);
  const TransferFunction tf({{0.2f, 0.3f, 1.f}, {1.f, 0.8f, 0.2f}}, {0.f, 0.05f}, {0.f, 255.f});
  const VolumetricModel<StructuredRegular<std::uint8_t>> model(volume, tf, 1.f);
  const auto n = file.dims[0];
  const auto voxel = [&](std::int64_t x, std::int64_t y, std::int64_t z) {
    return static_cast<double>(voxels[(z * n + y) * n + x]);
  };
  const auto sample = [&](double x, double y, double z) {  // trilinear, in double
    const auto cell = [&](double v) { return std::min<std::int64_t>(static_cast<std::int64_t>(v), n - 2); };
    const std::int64_t i = cell(x), j = cell(y), k = cell(z);
    const double fx = x - i, fy = y - j, fz = z - k;
    double sum = 0;
    for (int c = 0; c < 8; ++c)
      sum += voxel(i + (c & 1), j + ((c >> 1) & 1), k + (c >> 2)) * ((c & 1) ? fx : 1 - fx) *
             ((c >> 1 & 1) ? fy : 1 - fy) * ((c >> 2) ? fz : 1 - fz);
    return sum;
  };
  const auto reference = [&](double y, double z) {  // a ray along +x through (·, y, z)
    double alpha = 0, red = 0;
    const double dt = 1e-3;
    for (double t = 0.5 * dt; t < 65; t += dt) {
      const double v = sample(t, y, z) / 255;
      const double sigma = 0.05 * v;  // the ramp from 0 to 0.05
      const double a = 1 - std::exp(-sigma * dt);
      red += (1 - alpha) * a * (0.2 + 0.8 * v);
      alpha += (1 - alpha) * a;
    }
    return std::pair{alpha, red};
  };
  VolumeIntegration how;
  double worst_coarse = 0, worst_fine = 0;
  for (int r = 0; r < 12; ++r) {
    const double y = 10 + 45 * testing::hash_uniform(2 * r), z = 10 + 45 * testing::hash_uniform(2 * r + 1);
    const auto [alpha, red] = reference(y, z);
    const Ray<float> ray{{-1.f, static_cast<float>(y), static_cast<float>(z)}, {1.f, 0.f, 0.f}};
    for (float rate : {1.f, 8.f}) {
      how.sampling_rate = rate;
      const auto got = model.integrate<simd::scalar>(ray, true, INFINITY, how);
      double& worst = rate == 1.f ? worst_coarse : worst_fine;
      worst = std::max({worst, std::fabs(got.alpha - alpha), std::fabs(got.color.x - red)});
    }
  }
  INFO("worst error at 1 sample a cell " << worst_coarse << ", at 8: " << worst_fine);
  CHECK(worst_fine < 1e-3);
  CHECK(worst_fine < worst_coarse);
}

namespace {

/// The pixels of render_volume's 16x16 image at least two pixels inside the unit cube's
/// footprint, whose rays cross the whole cube wherever in the pixel they fall.
std::vector<int> inner_pixels() {
  std::vector<int> pixels;
  for (int y = 2; y < 14; ++y)
    for (int x = 2; x < 14; ++x) pixels.push_back(16 * y + x);
  return pixels;
}

/// The unit cube whose value grows linearly with z from 0 to 1 (5x5x9 voxels): its
/// gradient points along +z everywhere, also where central differences are cut at a face.
std::shared_ptr<const StructuredRegular<float>> z_ramp() {
  const VolumeDims d{5, 5, 9};
  auto voxels = std::make_shared<std::vector<float>>();
  for (std::int64_t z = 0; z < d[2]; ++z)
    for (int k = 0; k < 25; ++k) voxels->push_back(static_cast<float>(z) / 8.f);
  return std::make_shared<StructuredRegular<float>>(LinearLayout<float>(voxels->data(), d, voxels),
                                                    StructuredRegular<float>::Grid{{0, 0, 0}, {0.25f, 0.25f, 0.125f}});
}

}  // namespace

TEST_CASE("gradient shading lerps each sample from its colour to its colour lit on the gradient", "[volume][render]") {
  // Opacity = value on the z ramp: every ray along +z integrates to A = 1 − exp(−D/2)
  // (D the density scale), and a constant colour c shows as c·A. The normal is the
  // negated gradient, −z, facing the camera. Lit by an ambient light a and a distant
  // light of irradiance E arriving at cos θ = 0.6 to it (a surface without material:
  // c/π per unit irradiance), a fully shaded sample is c·(a + 0.6·E/π).
  const Vec3f c{0.2f, 0.6f, 1.f};
  const float a = 0.25f, irradiance = 1.5f, density = 3.f;
  const float opacity = 1.f - std::exp(-density / 2);
  AmbientLight ambient;
  ambient.intensity = a;
  DistantLight front;
  front.direction = {0.f, -0.8f, 0.6f};  // travels away from the camera, towards +z
  front.intensity = irradiance;
  DistantLight behind = front;
  behind.direction = {0.f, 0.f, -1.f};  // towards the camera: lights the far side only
  const auto check = [&](float scale, const std::vector<Light>& lights, float expected_light) {
    accel::Device device;
    shim::EngineWorld world(device);
    VolumetricModel<StructuredRegular<float>> model(z_ramp(), TransferFunction({c}, {0.f, 1.f}, {0.f, 1.f}), density);
    model.set_gradient_shading_scale(scale);
    world.add_volume(std::move(model));
    SciVisParams params;
    params.lights = lights;
    params.volume_sampling_rate = 2.f;
    const float light = 1.f + scale * (expected_light - 1.f);  // the lerp of the colour
    for (auto isa : supported_isas()) {
      INFO(simd::isa_name(isa) << " at scale " << scale);
      const FrameBuffer fb = render_volume(isa, world, params);
      for (const int pixel : inner_pixels()) {
        REQUIRE(fb.color32f()[4 * pixel + 3] == Approx(opacity).epsilon(1e-5));  // shading keeps the opacity
        for (int k = 0; k < 3; ++k) REQUIRE(fb.color32f()[4 * pixel + k] == Approx(c[k] * light * opacity).epsilon(1e-4));
      }
    }
  };
  const float lit = a + 0.6f * irradiance / std::numbers::pi_v<float>;
  check(0.f, {ambient, front}, lit);        // exactly the unshaded colour
  check(1.f, {ambient, front}, lit);        // exactly the lit colour
  check(0.5f, {ambient, front}, lit);       // half way
  check(1.f, {ambient, behind}, a);         // one-sided: light from behind the normal is not seen
  VolumetricModel<StructuredRegular<float>> model(z_ramp(), TransferFunction({c}, {1.f}, {0.f, 1.f}));
  CHECK_THROWS_WITH(model.set_gradient_shading_scale(1.5f), Catch::Contains("'gradientShadingScale' must be in [0, 1]"));
  CHECK_THROWS_WITH(model.set_gradient_shading_scale(std::nanf("")), Catch::Contains("must be in [0, 1]"));
}

TEST_CASE("map_maxDepth ends camera rays: volumes are integrated and surfaces seen only up to it", "[volume][render]") {
  // The camera is at z = −5 looking along +z: a depth of 5.3 reaches 0.3 into the unit
  // cube. Left half of the image: depth 5.3; right half: 5.8.
  const auto depths = std::make_shared<const Texture2D>(2, 1, std::vector<Vec3f>{splat(5.3f), splat(5.8f)}, true);
  auto voxels = std::make_shared<std::vector<float>>(8, 1.f);
  const auto volume = std::make_shared<StructuredRegular<float>>(LinearLayout<float>(voxels->data(), {2, 2, 2}, voxels),
                                                                 StructuredRegular<float>::Grid{});
  SECTION("a constant volume of σ = 2 absorbs 1 − exp(−2·0.3) on the left, 1 − exp(−2·0.8) on the right") {
    accel::Device device;
    shim::EngineWorld world(device);
    world.add_volume(VolumetricModel<StructuredRegular<float>>(volume, TransferFunction({{1, 1, 1}}, {2.f}, {0.f, 2.f})));
    SciVisParams params;
    params.max_depth = depths;
    for (auto isa : supported_isas()) {
      INFO(simd::isa_name(isa));
      const FrameBuffer fb = render_volume(isa, world, params);
      for (const int pixel : inner_pixels()) {
        const float reach = pixel % 16 < 8 ? 0.3f : 0.8f;
        REQUIRE(fb.color32f()[4 * pixel + 3] == Approx(1.f - std::exp(-2.f * reach)).epsilon(1e-4));
      }
    }
  }
  SECTION("a plane at z = 0.5 (5.5 away) is hidden on the left and seen on the right, by every renderer") {
    accel::Device device;
    shim::EngineWorld world(device);
    world.add(Planes({{0.f, 0.f, 1.f, -0.5f}}, {}));
    SciVisParams scivis;
    scivis.lights = {AmbientLight{}};
    scivis.max_depth = depths;
    AOParams ao;
    ao.max_depth = depths;
    PathTracerParams pathtracer;
    pathtracer.lights = {AmbientLight{}};
    pathtracer.max_depth = depths;
    for (const shim::RendererConfig& renderer : std::vector<shim::RendererConfig>{scivis, ao, pathtracer}) {
      INFO("renderer " << renderer.index());
      const auto& kernels = shim::kernels(shim::select_isa());
      kernels.commit(world);
      OrthographicCamera camera;
      camera.position = {0.5f, 0.5f, -5.f};
      camera.direction = {0.f, 0.f, 1.f};
      camera.height = 1.f;
      FrameBuffer fb(16, 16, ColorFormat::rgba32f);
      kernels.render(world, renderer, camera, fb, nullptr, FrameSettings{});
      for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 16; ++x) {
          // The background is transparent black; the plane is opaque.
          REQUIRE(fb.color32f()[4 * (16 * y + x) + 3] == Approx(x < 8 ? 0.f : 1.f));
          if (x >= 8) REQUIRE(fb.color32f()[4 * (16 * y + x)] > 0.1f);
        }
    }
  }
}

TEST_CASE("overlapping volumes interleave their samples in depth", "[volume][render]") {
  // Two constant volumes of σ = 2 filling the unit cube, red and blue. Marched together,
  // step by step (4 a cell: n = 4 steps of h = 1/4), each step composites the red sample
  // then the blue one, each absorbing a = 1 − exp(−2h): red = a·ΣT, blue = (1 − a)·a·ΣT
  // over T_k = ((1 − a)²)^k. One after the other, red would be 1 − exp(−2) and cover most of the blue.
  auto voxels = std::make_shared<std::vector<float>>(8, 1.f);
  const auto volume = std::make_shared<StructuredRegular<float>>(LinearLayout<float>(voxels->data(), {2, 2, 2}, voxels),
                                                                 StructuredRegular<float>::Grid{});
  accel::Device device;
  shim::EngineWorld world(device);
  world.add_volume(VolumetricModel<StructuredRegular<float>>(volume, TransferFunction({{1, 0, 0}}, {2.f}, {0.f, 2.f})));
  world.add_volume(VolumetricModel<StructuredRegular<float>>(volume, TransferFunction({{0, 0, 1}}, {2.f}, {0.f, 2.f})));
  SciVisParams params;
  params.volume_sampling_rate = 4.f;
  const double a = 1 - std::exp(-2.0 / 4);
  double sum = 0, through = 1;
  for (int k = 0; k < 4; ++k) sum += through, through *= (1 - a) * (1 - a);
  for (auto isa : supported_isas()) {
    INFO(simd::isa_name(isa));
    const FrameBuffer fb = render_volume(isa, world, params);
    for (const int pixel : inner_pixels()) {
      REQUIRE(fb.color32f()[4 * pixel + 0] == Approx(a * sum).epsilon(1e-4));
      REQUIRE(fb.color32f()[4 * pixel + 2] == Approx((1 - a) * a * sum).epsilon(1e-4));
      REQUIRE(fb.color32f()[4 * pixel + 3] == Approx(1 - through).epsilon(1e-4));
    }
  }
}

TEST_CASE("scivis shadows pass through volumes, attenuated by their transmittance", "[volume][render]") {
  // A black cube of σ = 1 between the camera and the plane z = 2, lit by a distant light
  // of irradiance π from the camera's side: the plane (kd 0.8, so 0.8/π per unit
  // irradiance) is seen through the cube (e⁻¹) and lit through it (e⁻¹ again) with
  // shadows, and only seen through it without.
  auto voxels = std::make_shared<std::vector<float>>(8, 1.f);
  const auto volume = std::make_shared<StructuredRegular<float>>(LinearLayout<float>(voxels->data(), {2, 2, 2}, voxels),
                                                                 StructuredRegular<float>::Grid{});
  accel::Device device;
  shim::EngineWorld world(device);
  world.add_volume(VolumetricModel<StructuredRegular<float>>(volume, TransferFunction({{0, 0, 0}}, {1.f}, {0.f, 1.f})));
  world.add(Planes({{0.f, 0.f, 1.f, -2.f}}));
  DistantLight light;
  light.direction = {0.f, 0.f, 1.f};
  light.intensity = std::numbers::pi_v<float>;
  SciVisParams params;
  params.lights = {light};
  for (const bool shadows : {false, true}) {
    params.shadows = shadows;
    const float expected = 0.8f * std::exp(shadows ? -2.f : -1.f);
    for (auto isa : supported_isas()) {
      INFO(simd::isa_name(isa) << (shadows ? " with shadows" : ""));
      const FrameBuffer fb = render_volume(isa, world, params);
      for (const int pixel : inner_pixels()) REQUIRE(fb.color32f()[4 * pixel] == Approx(expected).epsilon(1e-4));
    }
  }
}
