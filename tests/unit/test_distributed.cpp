// Data-parallel rendering in one process: a world split into regions (replicated surfaces
// clipped by region, as OSPRay's data-parallel tests do, and a volume cut into bricks with
// ghost voxels), each region rendered into a fragment image through the compiled shim and
// the fragments composited, against the unsplit world rendered as a normal frame.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <random>
#include <vector>

#include "sciray/distributed/fragments.hpp"
#include "sciray/distributed/mpi_raycast.hpp"
#include "sciray/distributed/volume_bricks.hpp"
#include "sciray/io/volume.hpp"
#include "sciray/shim/engine.hpp"
#include "sciray/testing/scenes.hpp"
#include "support/render_scenes.hpp"
#include "support/render_stats.hpp"

using namespace sciray;
using namespace sciray::test_support;
using distributed::Background;
using distributed::FragmentImage;

namespace {

constexpr float inf = std::numeric_limits<float>::infinity();

struct Difference {
  double rmse = 0, max_abs = 0;
};

/// Over RGBA, pixel by pixel.
Difference difference(const std::vector<float>& a, const std::vector<float>& b) {
  REQUIRE(a.size() == b.size());
  Difference d;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const double e = static_cast<double>(a[i]) - static_cast<double>(b[i]);
    d.rmse += e * e, d.max_abs = std::max(d.max_abs, std::abs(e));
  }
  d.rmse = std::sqrt(d.rmse / static_cast<double>(a.size()));
  return d;
}

/// The unsplit world as a normal frame: RGBA32F with the renderer's background.
std::vector<float> render_whole(const shim::EngineWorld& world, const shim::RendererConfig& config,
                                const Camera& camera, int width, int height, const FrameSettings& settings = {}) {
  FrameBuffer fb(width, height, ColorFormat::rgba32f, channel_color | channel_depth);
  kernels().render(world, config, camera, fb, nullptr, settings);
  return fb.color32f();
}

/// Region i of `regions` rendered from `*worlds[i]` into a fragment, all composited over
/// `background`.
std::vector<float> render_split(const std::vector<const shim::EngineWorld*>& worlds, const std::vector<Box3f>& regions,
                                const shim::RendererConfig& config, const Camera& camera, int width, int height,
                                const Background& background, const FrameSettings& settings = {}) {
  std::vector<FragmentImage> fragments;
  for (std::size_t i = 0; i < regions.size(); ++i) {
    FragmentImage fragment(width, height);
    kernels().render_region(*worlds[i], config, camera, regions[i], settings, {}, fragment);
    fragments.push_back(std::move(fragment));
  }
  std::vector<float> rgba;
  distributed::composite(fragments, background, rgba);
  return rgba;
}

/// OSPRay's data-parallel test regions: the bounds cut into a grid, outer faces pushed out
/// a little so that geometry touching the bounds is not clipped on them.
std::vector<Box3f> padded_regions(Box3f bounds, const distributed::BrickGrid& grid) {
  const Vec3f pad = bounds.size() * 1e-3f;
  std::vector<Box3f> boxes = distributed::split_box(bounds, grid);
  const auto push = [](float v, float outer, float by) { return v == outer ? outer + by : v; };
  for (Box3f& b : boxes) {
    b.lower = {push(b.lower.x, bounds.lower.x, -pad.x), push(b.lower.y, bounds.lower.y, -pad.y),
               push(b.lower.z, bounds.lower.z, -pad.z)};
    b.upper = {push(b.upper.x, bounds.upper.x, pad.x), push(b.upper.y, bounds.upper.y, pad.y),
               push(b.upper.z, bounds.upper.z, pad.z)};
  }
  return boxes;
}

PerspectiveCamera looking_at(const Box3f& bounds, Vec3f from_direction, float fovy = 40.f) {
  PerspectiveCamera camera;
  const Vec3f centre = bounds.center();
  camera.position = centre + normalize(from_direction) * (1.6f * length(bounds.size()));
  camera.direction = centre - camera.position;
  camera.up = {0.f, 1.f, 0.f};
  camera.fovy = fovy;
  return camera;
}

/// Spheres of the shared test scenes and a torus through them: both straddle every cut.
void add_surfaces(shim::EngineWorld& world) {
  world.add(Spheres(testing::random_spheres(60, 3)), 0);
  MeshData torus = testing::wavy_torus(4000);
  for (std::size_t i = 0; i < torus.positions.size(); i += 3) {
    torus.positions[i] = 0.5f + 0.4f * torus.positions[i];
    torus.positions[i + 1] = 0.5f + 0.4f * torus.positions[i + 1];
    torus.positions[i + 2] = 0.5f + 0.4f * torus.positions[i + 2];
  }
  world.add(TriangleMesh(std::move(torus)), 1);
}

struct VolumeScene {
  std::vector<std::uint8_t> voxels;
  VolumeDims dims;
  VolumeGrid grid;
};

/// A real volume: the negative potential of a high-potential iron protein, 66³ bytes.
VolumeScene neghip() {
  const io::VolumeFile file = io::read_volume(SCIRAY_DATA_DIR "/volumes/neghip_66x66x66_uint8.raw");
  REQUIRE(file.kind == io::VoxelKind::uint8);
  const auto* bytes = reinterpret_cast<const std::uint8_t*>(file.voxels->data());
  return {std::vector<std::uint8_t>(bytes, bytes + file.voxels->size()), file.dims, file.grid};
}

VolumetricModel<StructuredRegular<std::uint8_t>> neghip_model(std::shared_ptr<const StructuredRegular<std::uint8_t>> v,
                                                               float density_scale = 1.f) {
  // Blue where the potential is weak, orange where strong; opacity rising with it.
  return VolumetricModel<StructuredRegular<std::uint8_t>>(
      std::move(v), TransferFunction({{0.1f, 0.3f, 1.f}, {0.2f, 1.f, 0.6f}, {1.f, 0.5f, 0.1f}}, {0.f, 0.02f, 0.1f},
                                     {0.f, 255.f}),
      density_scale);
}

/// Renders the volume split into `grid` bricks (one world per brick, as ranks hold them)
/// with `ghost_layers`, composited.
std::vector<float> render_bricks(const VolumeScene& scene, const distributed::BrickGrid& grid, int ghost_layers,
                                 const shim::RendererConfig& config, const Camera& camera, int size,
                                 const Background& background) {
  const auto bricks = distributed::split_volume<std::uint8_t>(scene.voxels, scene.dims, scene.grid, grid, ghost_layers);
  std::vector<std::unique_ptr<TestWorld>> worlds;
  std::vector<const shim::EngineWorld*> world_of;
  std::vector<Box3f> regions;
  for (const auto& brick : bricks) {
    worlds.push_back(std::make_unique<TestWorld>());
    worlds.back()->world.add_volume(neghip_model(brick.volume()));
    kernels().commit(worlds.back()->world);
    world_of.push_back(&worlds.back()->world);
    regions.push_back(brick.region);
  }
  return render_split(world_of, regions, config, camera, size, size, background);
}

}  // namespace

TEST_CASE("composite blends fragments front to back by key, then the background", "[distributed]") {
  // Two pixels, two fragments of constant alpha: red at alpha 1/2 and green at alpha 1/4
  // (premultiplied). Pixel 0 has red in front, pixel 1 green; blue opaque background.
  const std::vector<float> red = {0.5f, 0.f, 0.f, 0.5f, 0.5f, 0.f, 0.f, 0.5f};
  const std::vector<float> green = {0.f, 0.25f, 0.f, 0.25f, 0.f, 0.25f, 0.f, 0.25f};
  const std::vector<float> red_key = {1.f, 2.f}, green_key = {2.f, 1.f};
  const std::vector<float> red_depth = {1.5f, 2.5f}, green_depth = {2.5f, inf};
  const std::vector<distributed::FragmentView> views = {{red, red_key, red_depth}, {green, green_key, green_depth}};
  std::vector<float> rgba(8), depth(2);
  distributed::composite(views, Background{{0.f, 0.f, 1.f}, 1.f}, rgba, depth);
  // Red over green over blue: (1/2, 0, 0) + 1/2·(0, 1/4, 0) + 1/2·3/4·(0, 0, 1), alpha 1.
  CHECK(rgba[0] == Approx(0.5f));
  CHECK(rgba[1] == Approx(0.125f));
  CHECK(rgba[2] == Approx(0.375f));
  CHECK(rgba[3] == Approx(1.f));
  // Green over red over blue: (0, 1/4, 0) + 3/4·(1/2, 0, 0) + 3/4·1/2·(0, 0, 1).
  CHECK(rgba[4] == Approx(0.375f));
  CHECK(rgba[5] == Approx(0.25f));
  CHECK(rgba[6] == Approx(0.375f));
  CHECK(rgba[7] == Approx(1.f));
  CHECK(depth[0] == 1.5f);
  CHECK(depth[1] == 2.5f);

  // A transparent background keeps the coverage as alpha: 1 − 1/2·3/4.
  distributed::composite(views, Background{{1.f, 1.f, 1.f}, 0.f}, rgba);
  CHECK(rgba[3] == Approx(0.625f));
  CHECK(rgba[0] == Approx(0.5f + 0.375f));

  // The views must describe the same pixels.
  const std::vector<float> short_key = {1.f};
  const std::vector<distributed::FragmentView> bad = {{red, short_key}};
  CHECK_THROWS_WITH(distributed::composite(bad, Background{}, rgba), Catch::Contains("fragment 0 has 8 colour floats and 1 keys for 2 pixels"));
}

TEST_CASE("a region holding the whole world renders the normal frame", "[distributed]") {
  // The same samples, seeds and clipping-free rays: the fragment over the background is the
  // normal image (AO rays included, which draw from the pixel's sequence).
  TestWorld scene;
  add_surfaces(scene.world);
  VolumeScene volume = neghip();
  volume.grid.spacing = Vec3f{1.f, 1.f, 1.f} / 65.f;
  scene.world.add_volume(neghip_model(std::make_shared<const StructuredRegular<std::uint8_t>>(
                                          LinearLayout<std::uint8_t>(volume.voxels.data(), volume.dims), volume.grid),
                                      40.f));
  kernels().commit(scene.world);
  AOParams params = distributed::mpi_raycast_params();
  params.ao_samples = 2;
  params.materials = {ObjMaterial{.kd = {0.9f, 0.9f, 0.9f}}, ObjMaterial{.kd = {1.f, 1.f, 1.f}, .d = 0.6f}};
  params.background_color = {1.f, 1.f, 1.f};
  const Box3f bounds = scene.world.bounds();
  const Camera camera = looking_at(bounds, {0.4f, 0.5f, 1.f});
  FrameSettings settings;
  settings.pixel_samples = 2;
  const int size = 64;
  const std::vector<float> whole = render_whole(scene.world, params, camera, size, size, settings);
  const std::vector<float> split = render_split({&scene.world}, padded_regions(bounds, {1, 1, 1}), params, camera, size,
                                                size, Background{{1.f, 1.f, 1.f}, 0.f}, settings);
  const Difference d = difference(whole, split);
  CHECK(d.max_abs < 1e-5);
}

TEST_CASE("surfaces split into 2, 3 and 4 regions composite to the unsplit image", "[distributed]") {
  // Replicated data clipped by regions, as OSPRay's data-parallel suite renders it, with the
  // mpiRaycast renderer: every surface point is shaded in exactly one region, with the
  // same AO rays (a pixel draws its AO directions from its own sequence), so opaque
  // surfaces composite to the unsplit frame exactly. Behind a transparent surface the
  // whole ray's generator has moved on where a region's starts afresh: the AO there is
  // another unbiased estimate, and the difference is AO noise with mean 0.
  TestWorld scene;
  add_surfaces(scene.world);
  kernels().commit(scene.world);
  const Box3f bounds = scene.world.bounds();
  const Camera camera = looking_at(bounds, {0.4f, 0.5f, 1.f});
  const int size = 96;
  for (const auto& [ao_samples, torus_opacity] : {std::pair{4, 1.f}, std::pair{0, 0.6f}, std::pair{4, 0.6f}}) {
    AOParams params = distributed::mpi_raycast_params();
    params.ao_samples = ao_samples;
    params.materials = {ObjMaterial{.kd = {0.9f, 0.9f, 0.9f}}, ObjMaterial{.kd = {1.f, 1.f, 1.f}, .d = torus_opacity}};
    params.background_color = {1.f, 1.f, 1.f};
    const std::vector<float> whole = render_whole(scene.world, params, camera, size, size);
    for (int ranks : {2, 3, 4}) {
      const auto regions = padded_regions(bounds, distributed::brick_grid(ranks));
      const std::vector<const shim::EngineWorld*> worlds(regions.size(), &scene.world);
      const std::vector<float> split =
          render_split(worlds, regions, params, camera, size, size, Background{{1.f, 1.f, 1.f}, 0.f});
      const Difference d = difference(whole, split);
      INFO(ranks << " regions, aoSamples " << ao_samples << ", torus d " << torus_opacity << ": RMSE " << d.rmse
                 << ", max " << d.max_abs);
      if (torus_opacity == 1.f) {
        CHECK(d.rmse == 0.0);
      } else if (ao_samples == 0) {
        // A transparent hit's continuation starts a rounding offset past it, a region's
        // continuation at its face: surfaces within that offset of a face (a few pixels).
        CHECK(d.rmse < 2e-5);
        CHECK(d.max_abs < 2e-3);
      } else {
        std::vector<double> differences;
        for (std::size_t i = 0; i < whole.size(); ++i)
          if (whole[i] != split[i]) differences.push_back(static_cast<double>(split[i]) - whole[i]);
        INFO(differences.size() << " channel values differ");
        REQUIRE(differences.size() > 20);
        const Stats s = stats(differences);
        CHECK(std::abs(s.mean) < 4 * s.stderr_);
        CHECK(d.rmse < 1e-3);
      }
    }
  }
}

TEST_CASE("a volume split into 2, 3 and 4 bricks with ghost voxels composites to the unsplit image", "[distributed]") {
  // Each brick's region is marched from where the ray enters it, its last step cut where
  // the ray leaves: the midpoint rule over another partition of the ray than the unsplit
  // march's, which differs by the quadrature error, O(step²). Measured on neghip (66³,
  // 96² pixels): RMSE 4–5e-4 at 1 sample a cell, 2–3e-5 at 4; the bounds are twice
  // that, and the difference must shrink with the step as a quadrature error does.
  // Without ghost voxels the bricks leave half a cell unsampled on each side of every
  // border: an order of magnitude more, whatever the step.
  const VolumeScene scene = neghip();
  TestWorld whole_world;
  whole_world.world.add_volume(neghip_model(std::make_shared<const StructuredRegular<std::uint8_t>>(
      LinearLayout<std::uint8_t>(scene.voxels.data(), scene.dims), scene.grid)));
  kernels().commit(whole_world.world);
  const Box3f bounds = whole_world.world.bounds();
  const Camera camera = looking_at(bounds, {0.5f, 0.35f, 1.f});
  const Background background{{1.f, 1.f, 1.f}, 0.f};
  const int size = 96;
  std::map<int, double> coarse;  // RMSE at 1 sample a cell, by bricks
  for (float rate : {1.f, 4.f}) {
    AOParams params = distributed::mpi_raycast_params();
    params.background_color = background.color;
    params.volume_sampling_rate = rate;
    const std::vector<float> whole = render_whole(whole_world.world, params, camera, size, size);
    for (int ranks : {2, 3, 4}) {
      const distributed::BrickGrid grid = distributed::brick_grid(ranks);
      const Difference ghosts = difference(whole, render_bricks(scene, grid, 1, params, camera, size, background));
      const Difference none = difference(whole, render_bricks(scene, grid, 0, params, camera, size, background));
      INFO(ranks << " bricks at " << rate << " samples a cell: RMSE " << ghosts.rmse << " (max " << ghosts.max_abs
                 << "), without ghosts " << none.rmse << " (max " << none.max_abs << ")");
      CHECK(ghosts.rmse < (rate == 1.f ? 1e-3 : 6e-5));
      CHECK(none.rmse > 8 * ghosts.rmse);
      if (rate == 1.f)
        coarse[ranks] = ghosts.rmse;
      else
        CHECK(ghosts.rmse < coarse[ranks] / 8);
    }
  }
}

TEST_CASE("bricks with one ghost layer sample their region as the whole volume does", "[distributed]") {
  // An analytic field with structure in every direction, vertex- and cell-centred, cut
  // 3x2x2; points drawn in each brick's region (faces included) sample the same there.
  const VolumeDims dims{23, 17, 12};
  std::vector<float> voxels;
  for (std::int64_t z = 0; z < dims[2]; ++z)
    for (std::int64_t y = 0; y < dims[1]; ++y)
      for (std::int64_t x = 0; x < dims[0]; ++x)
        voxels.push_back(std::sin(0.7f * static_cast<float>(x)) * std::cos(0.9f * static_cast<float>(y)) +
                         0.1f * static_cast<float>(z * z));
  std::mt19937 rng(7);
  for (bool cell_centered : {false, true})
    for (VolumeFilter filter : {VolumeFilter::linear, VolumeFilter::cubic}) {
      const int ghosts = filter == VolumeFilter::cubic ? 2 : 1;
      INFO((cell_centered ? "cell" : "vertex") << "-centred, " << (filter == VolumeFilter::cubic ? "cubic" : "linear"));
      const VolumeGrid grid{{-1.f, 0.5f, 2.f}, {0.3f, 0.25f, 0.4f}, cell_centered};
      const StructuredRegular<float> whole(LinearLayout<float>(voxels.data(), dims), grid, filter);
      const auto bricks = distributed::split_volume<float>(voxels, dims, grid, {3, 2, 2}, ghosts);
      REQUIRE(bricks.size() == 12);
      Box3f covered;
      double worst = 0, worst_without = 0;
      const auto without_ghosts = distributed::split_volume<float>(voxels, dims, grid, {3, 2, 2}, 0);
      for (std::size_t b = 0; b < bricks.size(); ++b) {
        const auto& brick = bricks[b];
        covered.extend(brick.region);
        const auto volume = brick.volume(filter), bare = without_ghosts[b].volume(filter);
        std::uniform_real_distribution<float> u(0.f, 1.f);
        for (int i = 0; i < 400; ++i) {
          // A quarter of the points on a face of the region.
          const auto along = [&](int k) {
            const float f = i % 4 == 0 && k == i / 4 % 3 ? static_cast<float>(i / 12 % 2) : u(rng);
            return brick.region.lower[k] + f * brick.region.size()[k];
          };
          const Vec3f p{along(0), along(1), along(2)};
          const float expected = whole.sample<simd::scalar>(p);
          worst = std::max(worst, static_cast<double>(std::abs(volume->sample<simd::scalar>(p) - expected)));
          worst_without = std::max(worst_without, static_cast<double>(std::abs(bare->sample<simd::scalar>(p) - expected)));
        }
      }
      CHECK(worst < 1e-4);
      CHECK(worst_without > 0.05);
      // The regions tile the volume's bounds.
      CHECK(covered.lower.x == whole.bounds().lower.x);
      CHECK(covered.upper.x == whole.bounds().upper.x);
      CHECK(covered.upper.y == whole.bounds().upper.y);
      CHECK(covered.upper.z == whole.bounds().upper.z);
    }
}

TEST_CASE("brick grids, box splits and bad arguments", "[distributed]") {
  CHECK(distributed::brick_grid(1) == distributed::BrickGrid{1, 1, 1});
  CHECK(distributed::brick_grid(2) == distributed::BrickGrid{2, 1, 1});
  CHECK(distributed::brick_grid(3) == distributed::BrickGrid{3, 1, 1});
  CHECK(distributed::brick_grid(4) == distributed::BrickGrid{2, 2, 1});
  CHECK(distributed::brick_grid(8) == distributed::BrickGrid{2, 2, 2});
  CHECK(distributed::brick_grid(12) == distributed::BrickGrid{2, 2, 3});
  const auto boxes = distributed::split_box({{0.f, 0.f, 0.f}, {1.f, 3.f, 1.f}}, {1, 3, 1});
  REQUIRE(boxes.size() == 3);
  CHECK(boxes[0].upper.y == boxes[1].lower.y);
  CHECK(boxes[2].upper.y == 3.f);

  const std::vector<float> voxels(4 * 4 * 4, 1.f);
  CHECK_THROWS_WITH(distributed::split_volume<float>(voxels, {4, 4, 4}, {}, {3, 1, 1}),
                    Catch::Contains("every brick needs at least 2 voxels"));
  CHECK_THROWS_WITH(distributed::split_volume<float>(voxels, {4, 4, 5}, {}, {1, 1, 1}), Catch::Contains("64 voxels for dimensions 4x4x5"));

  TestWorld scene;
  scene.world.add(spheres({{{0.f, 0.f, 0.f}, 1.f}}));
  kernels().commit(scene.world);
  FragmentImage fragment(8, 8);
  CHECK_THROWS_WITH(kernels().render_region(scene.world, PathTracerParams{}, PerspectiveCamera{},
                                            {{-1.f, -1.f, -1.f}, {1.f, 1.f, 1.f}}, {}, {}, fragment),
                    Catch::Contains("path tracer cannot render a region"));
}

TEST_CASE("mpiRaycast adds a surface's whole colour and reads opacity from the material alone", "[distributed]") {
  // OSPRay's DistributedRaycast blends (colour, d) as out + (1 - out.a) * (colour, d), not
  // d * colour, and takes d from the material, not from the geometry colour's alpha. A quad
  // of kd 0.5, d 0.5 and colour alpha 0.25 seen straight on (|n.w| = 1) over black:
  // mpiRaycast 0.5 with alpha 0.5; ao 0.5 * (0.5 * 0.25) with alpha 0.125.
  TestWorld scene;
  MeshData quad = quads({square(2.f, 0.f)}, {{1.f, 1.f, 1.f}});
  quad.face_colors[3] = 0.25f;
  scene.world.add(TriangleMesh(std::move(quad)), 0);
  kernels().commit(scene.world);
  const Camera camera = top_view(0.f, 0.f, 1.f, 2.f);
  const auto centre = [&](AOParams params) {
    params.materials = {ObjMaterial{.kd = {0.5f, 0.5f, 0.5f}, .d = 0.5f}};
    FrameBuffer fb(4, 4, ColorFormat::rgba32f, channel_color);
    kernels().render(scene.world, params, camera, fb, nullptr, point_sampled());
    return std::pair{fb.color32f()[4 * 5], fb.color32f()[4 * 5 + 3]};
  };
  const auto [raycast, raycast_alpha] = centre(distributed::mpi_raycast_params());
  CHECK(raycast == Approx(0.5f).margin(1e-6));
  CHECK(raycast_alpha == Approx(0.5f).margin(1e-6));
  AOParams ao;
  ao.ao_samples = 0;
  const auto [plain, plain_alpha] = centre(ao);
  CHECK(plain == Approx(0.0625f).margin(1e-6));
  CHECK(plain_alpha == Approx(0.125f).margin(1e-6));
}
