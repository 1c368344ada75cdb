// 100,000 accumulated frames keep their running mean: the sums are doubles, so the mean
// of a long progressive render does not drift as a float sum would once it has grown.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>

#include "sciray/frame/framebuffer.hpp"
#include "sciray/shim/engine.hpp"

using namespace sciray;

TEST_CASE("accumulation: the mean of 100,000 frames equals their exact mean", "[frame][stability][long]") {
  FrameBuffer fb(1, 1, ColorFormat::rgba32f, channel_color | channel_accum);
  constexpr int frames = 100'000;
  double exact = 0.0;
  float float_sum = 0.f;  // what a float accumulation would hold
  for (int k = 0; k < frames; ++k) {
    // A period-10 pattern of values that no float holds exactly.
    const float v = 0.1f + 0.07f * static_cast<float>((7 * k) % 10);
    exact += v;
    float_sum += v;
    PixelSample<simd::scalar> s;
    s.color = {v, v, v};
    s.alpha = 1.f;
    s.t = 1.f;
    std::int32_t pixel = 0;
    fb.write_packet<simd::scalar>(&pixel, s, 1.f);
    fb.finish_tile(0);
    fb.finish_frame();
  }
  exact /= frames;
  const double float_mean = static_cast<double>(float_sum) / frames;
  INFO("exact mean " << exact << ", float sum's mean " << float_mean);
  CHECK(std::abs(float_mean - exact) > 1e-5);  // the failure this guards against
  CHECK(fb.accumulated_frames() == frames);
  CHECK(std::abs(static_cast<double>(fb.color32f()[0]) - exact) < 1e-6);
}

TEST_CASE("accumulation: a path-traced white furnace stays at its closed form over 100,000 frames",
          "[render][pathtracer][stability][long]") {
  // A convex diffuse sphere of albedo a in uniform ambient light L sends a * L to the
  // camera: every bounce leaves to the light. Cosine-sampled, each path carries exactly
  // that, so the mean of any number of frames must be a * L to float precision.
  accel::Device device;
  shim::EngineWorld world(device);
  SphereData sphere;
  sphere.positions = {0.f, 0.f, 0.f};
  sphere.radius = 1.f;
  world.add(Spheres(std::move(sphere)), 0);
  const auto& kernels = shim::kernels(simd::best_supported_isa());
  kernels.commit(world);
  PathTracerParams params;
  ObjMaterial diffuse;
  diffuse.kd = {0.3f, 0.5f, 0.7f};
  params.materials = {diffuse};
  AmbientLight ambient;
  ambient.intensity = 0.8f;
  params.lights = {ambient};
  PerspectiveCamera camera;
  camera.position = {0.f, 0.f, 5.f};
  camera.direction = {0.f, 0.f, -1.f};
  camera.fovy = 1.f;  // the one pixel sees the sphere only
  FrameBuffer fb(1, 1, ColorFormat::rgba32f, channel_color | channel_accum);
  for (int k = 0; k < 100'000; ++k) kernels.render(world, params, camera, fb, nullptr, {});
  CHECK(fb.accumulated_frames() == 100'000);
  CHECK(fb.color32f()[0] == Approx(0.3f * 0.8f).epsilon(1e-5));
  CHECK(fb.color32f()[1] == Approx(0.5f * 0.8f).epsilon(1e-5));
  CHECK(fb.color32f()[2] == Approx(0.7f * 0.8f).epsilon(1e-5));
}
