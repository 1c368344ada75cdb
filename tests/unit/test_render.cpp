// Whole frames through the compiled shim: every ISA against the scalar reference path,
// a stored reference image, determinism across thread counts, accumulation and depth.
//
// References are regenerated with
//   SCIRAY_UPDATE_REFERENCES=1 ./build/tests/sciray_tests "[reference]"
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <numeric>
#include <random>

#include <tbb/task_arena.h>

#include "sciray/io/frame_io.hpp"
#include "sciray/io/ply.hpp"
#include "sciray/shim/engine.hpp"
#include "sciray/testing/image_compare.hpp"
#include "sciray/testing/scenes.hpp"

using namespace sciray;

namespace {

std::vector<simd::Isa> supported_packet_isas() {
  std::vector<simd::Isa> isas;
  for (auto isa : simd::all_isas)
    if (isa != simd::Isa::scalar && simd::cpu_supports(isa)) isas.push_back(isa);
  return isas;
}

struct BunnyScene {
  accel::Device device;
  shim::EngineWorld world{device};
  PerspectiveCamera camera;
  SciVisParams params;

  BunnyScene() {
    world.add(TriangleMesh(io::read_ply(SCIRAY_DATA_DIR "/meshes/bunny.ply")));
    world.commit();
    camera = frame_bounds(world.bounds(), 1.f, 30.f, {0.f, -0.2f, -1.f});
    params.background_color = {0.1f, 0.1f, 0.12f};
    params.background_alpha = 1.f;
    params.lights = default_lights({0.5f, -0.7f, -0.6f});
  }
};

FrameBuffer render(const BunnyScene& scene, simd::Isa isa, int size, ColorFormat format = ColorFormat::srgba,
                   int frames = 1) {
  FrameBuffer fb(size, size, format);
  for (int f = 0; f < frames; ++f) shim::kernels(isa).render_scivis(scene.world, scene.params, scene.camera, fb, nullptr);
  return fb;
}

/// Random rays from around the bounds towards points inside them (seeded).
std::vector<Ray<float>> random_rays(const Box3f& bounds, std::size_t count) {
  std::mt19937 rng(42);
  std::uniform_real_distribution<float> unit(0.f, 1.f);
  const auto inside = [&] {
    return bounds.lower + bounds.size() * Vec3f{unit(rng), unit(rng), unit(rng)};
  };
  std::vector<Ray<float>> rays(count);
  for (auto& r : rays) {
    const Vec3f target = inside();
    const Vec3f dir = normalize(Vec3f{unit(rng) - 0.5f, unit(rng) - 0.5f, unit(rng) - 0.5f});
    r.org = target - dir * length(bounds.size());
    r.dir = dir;
  }
  return rays;
}

}  // namespace

TEST_CASE("every ISA finds the hits the scalar path finds", "[render][simd]") {
  const BunnyScene scene;
  const auto rays = random_rays(scene.world.bounds(), 20'000);
  std::vector<shim::TraceResult> reference(rays.size()), packet(rays.size());
  shim::kernels(simd::Isa::scalar).trace(scene.world, rays, reference);
  std::size_t hits = 0;
  for (const auto& r : reference) hits += r.geom_id >= 0;
  REQUIRE(hits > rays.size() / 10);

  for (auto isa : supported_packet_isas()) {
    INFO("ISA " << simd::isa_name(isa));
    shim::kernels(isa).trace(scene.world, rays, packet);
    // Embree's packet and single-ray kernels use the same watertight test, so hits must
    // agree exactly in which primitive they find and to float rounding in distance.
    std::size_t mismatches = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
      if (packet[i].prim_id != reference[i].prim_id || packet[i].geom_id != reference[i].geom_id) {
        ++mismatches;
        continue;
      }
      if (reference[i].geom_id >= 0) {
        REQUIRE(packet[i].t == Approx(reference[i].t).epsilon(1e-5));
        REQUIRE(packet[i].u == Approx(reference[i].u).margin(1e-4));
        REQUIRE(packet[i].v == Approx(reference[i].v).margin(1e-4));
      }
    }
    CHECK(mismatches == 0);
  }
}

TEST_CASE("every ISA renders the scalar path's image", "[render][simd]") {
  const BunnyScene scene;
  const auto reference = io::color_image(render(scene, simd::Isa::scalar, 96, ColorFormat::rgba32f));
  for (auto isa : supported_packet_isas()) {
    const auto image = io::color_image(render(scene, isa, 96, ColorFormat::rgba32f));
    const auto diff = testing::compare_images(image, reference, 1e-3);
    INFO("ISA " << simd::isa_name(isa) << ": " << testing::describe(diff));
    // Only float rounding differs (FMA contraction, normalization order).
    CHECK(diff.max_abs < 1e-3);
    CHECK(diff.differing_pixels == 0);
  }
}

TEST_CASE("the bunny matches its stored reference image", "[render][reference]") {
  const BunnyScene scene;
  const std::string reference_path = SCIRAY_REFERENCE_DIR "/bunny_scivis.png";
  const auto fb = render(scene, shim::select_isa(), 200);
  if (std::getenv("SCIRAY_UPDATE_REFERENCES")) io::write_color(fb, reference_path);
  const auto diff = testing::compare_images(io::color_image(fb), io::read_png(reference_path), 2.5 / 255);
  INFO(testing::describe(diff));
  // Stated tolerance: references may come from another ISA or Embree build, so allow
  // rounding-level noise but no region that is wrong: RMSE <= 0.5% of full scale, no 8x8
  // block off by more than 2%.
  CHECK(diff.rmse <= 0.005);
  CHECK(diff.local_mean_error_max <= 0.02);
}

TEST_CASE("images do not depend on the number of threads", "[render][determinism]") {
  const BunnyScene scene;
  const auto isa = shim::select_isa();
  const auto render_with = [&](int threads) {
    tbb::task_arena arena(threads);
    std::vector<float> pixels;
    arena.execute([&] { pixels = render(scene, isa, 97, ColorFormat::rgba32f, 3).color32f(); });
    return pixels;
  };
  const auto one = render_with(1);
  CHECK(one == render_with(2));
  CHECK(one == render_with(7));
}

TEST_CASE("accumulation averages jittered frames into anti-aliased coverage", "[render][frame]") {
  BunnyScene scene;
  scene.params.background_alpha = 0.f;  // alpha is then the pixel's coverage
  const auto& kernels = shim::kernels(shim::select_isa());
  FrameBuffer fb(64, 64, ColorFormat::rgba32f);
  const auto alphas = [&] {
    std::vector<float> a(fb.pixel_count());
    for (std::size_t p = 0; p < a.size(); ++p) a[p] = fb.color32f()[4 * p + 3];
    return a;
  };
  kernels.render_scivis(scene.world, scene.params, scene.camera, fb, nullptr);
  const std::vector<float> first_colors = fb.color32f();
  const auto one_frame = alphas();
  for (int f = 1; f < 16; ++f) kernels.render_scivis(scene.world, scene.params, scene.camera, fb, nullptr);
  CHECK(fb.accumulated_frames() == 16);
  const auto sixteen_frames = alphas();

  const auto partial = [](const std::vector<float>& a) {
    return std::count_if(a.begin(), a.end(), [](float v) { return v > 0.f && v < 1.f; });
  };
  CHECK(partial(one_frame) == 0);
  CHECK(partial(sixteen_frames) > 50);  // the silhouette is now anti-aliased
  const auto coverage = [](const std::vector<float>& a) { return std::accumulate(a.begin(), a.end(), 0.0); };
  CHECK(coverage(sixteen_frames) == Approx(coverage(one_frame)).epsilon(0.02));
  for (std::size_t i = 0; i < fb.accum().size(); ++i)
    REQUIRE(fb.color32f()[i] == Approx(fb.accum()[i] / 16.f).epsilon(1e-6));

  // After a reset the next frame is frame 0 again.
  fb.reset_accumulation();
  kernels.render_scivis(scene.world, scene.params, scene.camera, fb, nullptr);
  CHECK(fb.color32f() == first_colors);
}

TEST_CASE("depth channels hold Euclidean and projected distance", "[render][frame]") {
  accel::Device device;
  shim::EngineWorld world(device);
  MeshData plane;
  plane.positions = {-10, -10, 0, 10, -10, 0, 10, 10, 0, -10, 10, 0};
  plane.vertices_per_face = 4;
  plane.indices = {0, 1, 2, 3};
  world.add(TriangleMesh(std::move(plane)));
  world.commit();
  PerspectiveCamera camera;
  camera.position = {0.f, 0.f, 5.f};
  camera.fovy = 60.f;
  FrameBuffer fb(33, 33, ColorFormat::rgba8);
  shim::kernels(shim::select_isa()).render_scivis(world, SciVisParams{}, camera, fb, nullptr);
  const auto prepared = prepare(camera);
  for (int y : {0, 16, 32})
    for (int x : {0, 7, 16, 32}) {
      const std::size_t p = static_cast<std::size_t>(y) * 33 + x;
      const Ray<float> ray = prepared.generate((x + 0.5f) / 33.f, (y + 0.5f) / 33.f);
      CHECK(fb.depth_projected()[p] == Approx(5.f).epsilon(1e-5));
      CHECK(fb.depth()[p] == Approx(5.f / -ray.dir.z).epsilon(1e-5));
    }
}
