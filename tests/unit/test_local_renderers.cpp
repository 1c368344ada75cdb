// The local renderers against closed forms: scivis's hard shadows, ambient occlusion,
// transparency (colour and alpha) and sphere lights, and the ao renderer's eye light and
// occlusion distance. Frames go through the compiled shim for the best ISA, as in
// test_renderers.cpp.
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

#include "sciray/shim/engine.hpp"
#include "sciray/testing/scenes.hpp"
#include "support/render_stats.hpp"
#include "support/render_scenes.hpp"

using namespace sciray;
using namespace sciray::test_support;

// ---- scivis against closed forms --------------------------------------------------

TEST_CASE("scivis: a distant light's hard shadow is where the sphere blocks it, and only with shadows", "[renderers]") {
  TestWorld scene;
  scene.world.add(TriangleMesh(quads({square(10.f, 0.f)})), 0);
  const Vec3f centre{0.f, 0.f, 1.f};
  constexpr float radius = 0.5f;
  scene.world.add(spheres({{centre, radius}}), 0);
  scene.world.commit();
  const Vec3f kd{0.6f, 0.5f, 0.4f};
  SciVisParams params;
  params.materials = {ObjMaterial{.kd = kd}};
  AmbientLight ambient;
  ambient.intensity = 0.25f;
  DistantLight sun;
  sun.direction = {1.f, 0.f, -1.f};  // travelling: the shadow falls towards +x
  params.lights = {ambient, sun};
  constexpr int size = 64;
  const OrthographicCamera camera = top_view(0.6f, 0.f, 5.f, 4.f);
  const float pixel = 4.f / size;
  const Vec3f to_sun = normalize(-sun.direction);
  const float cos_sun = to_sun.z;  // the floor's normal is +z

  for (const bool shadows : {true, false}) {
    INFO("shadows " << shadows);
    params.shadows = shadows;
    const Image image = render(scene.world, params, camera, size, size, 1, point_sampled());
    int shadowed = 0, lit = 0, wrong = 0;
    for (int y = 0; y < size; ++y)
      for (int x = 0; x < size; ++x) {
        const Vec3f p = floor_point(camera, x, y, size, size);
        if (p.x * p.x + p.y * p.y < (radius + 2 * pixel) * (radius + 2 * pixel)) continue;  // the camera sees the sphere
        // Closest approach to the sphere's centre of the ray from p towards the sun.
        const Vec3f to_centre = centre - p;
        const float along = dot(to_centre, to_sun);
        const float miss = length(to_centre - to_sun * along);
        const bool in_shadow = along > 0.f && miss < radius - 2 * pixel;
        const bool in_light = along <= 0.f || miss > radius + 2 * pixel;
        if (!in_shadow && !in_light) continue;  // the shadow's edge
        (in_shadow ? shadowed : lit)++;
        // OSPRay's Lambertian kd/π: irradiance cos * intensity reflects cos * intensity / π.
        const float direct = shadows && in_shadow ? 0.f : cos_sun * sun.intensity / std::numbers::pi_v<float>;
        for (int c = 0; c < 3; ++c) wrong += std::abs(image.at(x, y, c) - kd[c] * (ambient.intensity + direct)) > 1e-4;
      }
    CHECK(shadowed > 100);
    CHECK(lit > 2000);
    CHECK(wrong == 0);
  }
}

TEST_CASE("scivis: ambient occlusion leaves an open plane at kd * ambient and blacks out a closed box", "[renderers]") {
  const Vec3f kd{0.6f, 0.5f, 0.4f};
  SciVisParams params;
  params.materials = {ObjMaterial{.kd = kd}};
  AmbientLight ambient;
  params.lights = {ambient};
  constexpr int size = 32;
  const auto all_pixels_are = [&](const Image& image, Vec3f expected, double tolerance) {
    double worst = 0;
    for (std::size_t p = 0; p < image.pixels(); ++p)
      for (int c = 0; c < 3; ++c) worst = std::max(worst, std::abs(image.rgb[3 * p + c] - expected[c]));
    INFO("largest difference " << worst);
    return worst <= tolerance;
  };

  SECTION("an open plane: every AO ray escapes") {
    TestWorld scene;
    scene.world.add(TriangleMesh(quads({square(10.f, 0.f)})), 0);
    scene.world.commit();
    params.ao_samples = 8;
    CHECK(all_pixels_are(render(scene.world, params, top_view(0.f, 0.f, 2.f, 4.f), size, size, 2), kd, 1e-5));
  }
  SECTION("the floor of a closed box: every AO ray hits a wall") {
    TestWorld scene;
    scene.world.add(TriangleMesh(closed_box({-1.f, -1.f, -1.f}, {1.f, 1.f, 1.f})), 0);
    scene.world.commit();
    const OrthographicCamera inside = top_view(0.f, 0.f, 0.9f, 1.6f);
    params.ao_samples = 4;
    CHECK(all_pixels_are(render(scene.world, params, inside, size, size, 2), {0.f, 0.f, 0.f}, 1e-6));
    params.ao_samples = 0;  // no AO: ambient light reaches everything
    CHECK(all_pixels_are(render(scene.world, params, inside, size, size, 1), kd, 1e-5));
  }
}

TEST_CASE("scivis: transparent surfaces composite over what lies behind them analytically", "[renderers]") {
  const Vec3f kd{0.8f, 0.6f, 0.4f}, tf{0.2f, 0.4f, 0.6f};
  constexpr float d = 0.5f;
  const Vec3f pass = splat(1.f - d) + tf * d;  // what the surface lets through
  SciVisParams params;
  params.materials = {ObjMaterial{.kd = kd, .d = d, .tf = tf}, ObjMaterial{.kd = {0.3f, 0.7f, 0.2f}}};
  params.background_color = {0.1f, 0.5f, 0.9f};
  constexpr int size = 16;
  const OrthographicCamera camera = top_view(0.f, 0.f, 2.f, 4.f);
  const auto check_all = [&](const Image& image, Vec3f expected) {
    int wrong = 0;
    for (std::size_t p = 0; p < image.pixels(); ++p)
      for (int c = 0; c < 3; ++c) wrong += std::abs(image.rgb[3 * p + c] - expected[c]) > 1e-3;
    INFO("pixel 0: " << image.rgb[0] << " " << image.rgb[1] << " " << image.rgb[2] << ", expected " << expected.x
                     << " " << expected.y << " " << expected.z);
    CHECK(wrong == 0);
  };

  SECTION("over the background, under ambient light") {
    TestWorld scene;
    scene.world.add(TriangleMesh(quads({square(5.f, 0.f)})), 0);
    scene.world.commit();
    AmbientLight ambient;
    params.lights = {ambient};
    check_all(render(scene.world, params, camera, size, size), kd * d + pass * params.background_color);
  }
  SECTION("over an opaque floor, with the sun's shadow through it tinted by the filter") {
    TestWorld scene;
    scene.world.add(TriangleMesh(quads({square(5.f, 0.f)})), 0);
    scene.world.add(TriangleMesh(quads({square(5.f, -1.f)})), 1);
    scene.world.commit();
    AmbientLight ambient;
    ambient.intensity = 0.2f;
    DistantLight sun;  // straight down
    sun.direction = {0.f, 0.f, -1.f};
    params.lights = {ambient, sun};
    params.shadows = true;
    const Vec3f floor_kd = std::get<ObjMaterial>(params.materials[1]).kd;
    check_all(render(scene.world, params, camera, size, size),
              kd * d * (0.2f + 1.f / std::numbers::pi_v<float>) +
                  pass * floor_kd * (splat(0.2f) + pass / std::numbers::pi_v<float>));
  }
  SECTION("alpha is 1 minus what passes, also beside lanes of the same packet that go on through the surface") {
    TestWorld scene;
    scene.world.add(TriangleMesh(quads({square(5.f, 0.f)})), 0);
    kernels().commit(scene.world);
    // The quad's edge x = 5 crosses the view at pixel column 10.8, inside a packet.
    const OrthographicCamera across_edge = top_view(4.3f, 0.f, 2.f, 4.f);
    FrameBuffer fb(size, size, ColorFormat::rgba32f);
    kernels().render(scene.world, params, across_edge, fb, nullptr, FrameSettings{});
    const float behind_surface = 1.f - (pass.x + pass.y + pass.z) / 3.f;
    int wrong = 0;
    for (int y = 0; y < size; ++y)
      for (int x = 0; x < size; ++x) {
        const float alpha = fb.color32f()[4 * (y * size + x) + 3];
        if (x <= 9) wrong += std::abs(alpha - behind_surface) > 1e-5f;
        if (x >= 11) wrong += alpha != 0.f;
      }
    CHECK(wrong == 0);
  }
}

TEST_CASE("scivis: a sphere light with a radius is sampled at its centre, as in OSPRay: a hard shadow, and "
          "kd/pi * cos * radiance * solid angle where lit",
          "[renderers]") {
  TestWorld scene;
  scene.world.add(TriangleMesh(quads({square(8.f, 0.f)})), 0);
  const Vec3f centre{0.f, 0.f, 1.f};
  constexpr float radius = 0.5f;
  scene.world.add(spheres({{centre, radius}}), 0);
  scene.world.commit();
  constexpr float kd = 0.8f;
  SphereLight lamp;
  lamp.position = {-3.f, 0.f, 3.f};
  lamp.radius = 0.5f;
  lamp.intensity = 10.f;
  SciVisParams params;
  params.materials = {ObjMaterial{.kd = splat(kd)}};
  params.lights = {lamp};  // no ambient light: the shadow is black
  constexpr int size = 64;
  const OrthographicCamera camera = top_view(1.5f, 0.f, 5.f, 3.f);  // the shadow falls around x = 1.5
  const float pixel = 3.f / size;

  FrameSettings settings = point_sampled();
  settings.pixel_samples = 4;  // one light sample point however many pixel samples
  for (const bool shadows : {true, false}) {
    INFO("shadows " << shadows);
    params.shadows = shadows;
    const Image image = render(scene.world, params, camera, size, size, 1, settings);
    int shadowed = 0, lit = 0, wrong = 0;
    for (int y = 0; y < size; ++y)
      for (int x = 0; x < size; ++x) {
        const Vec3f p = floor_point(camera, x, y, size, size);
        if (p.x * p.x + p.y * p.y < (radius + 2 * pixel) * (radius + 2 * pixel)) continue;  // the sphere's image
        const Vec3f to_lamp = lamp.position - p;
        const float dist = length(to_lamp);
        const Vec3f w = to_lamp / dist;
        // The ray to the lamp's centre passes the sphere's centre at distance `miss`.
        const float miss = length((centre - p) - w * dot(centre - p, w));
        if (std::abs(miss - radius) < 2 * pixel) continue;  // the shadow's edge
        const bool in_shadow = shadows && miss < radius;
        const float cos_max = std::sqrt(1.f - lamp.radius * lamp.radius / (dist * dist));
        constexpr float fpi = std::numbers::pi_v<float>;
        const float solid_angle = 2 * fpi * (1 - cos_max), radiance = lamp.intensity / (fpi * lamp.radius * lamp.radius);
        const float expected = in_shadow ? 0.f : kd / fpi * w.z * radiance * solid_angle;
        (in_shadow ? shadowed : lit)++;
        wrong += std::abs(image.at(x, y, 1) - expected) > 1e-4f * (1.f + expected);
      }
    CHECK(lit > 1000);
    if (shadows) CHECK(shadowed > 30);
    CHECK(wrong == 0);
  }
}

// ---- the ao renderer -------------------------------------------------------------

TEST_CASE("ao: an eye light, kd times the cosine to the camera, a ceiling dims it by aoIntensity only within aoDistance", "[renderers]") {
  const Vec3f kd{0.6f, 0.5f, 0.4f};
  AOParams params;
  params.materials = {ObjMaterial{.kd = kd}};
  params.ao_intensity = 0.7f;
  constexpr int size = 32;
  const auto channel_means = [](const Image& image) {
    std::array<double, 3> m{};
    for (std::size_t p = 0; p < image.pixels(); ++p)
      for (int c = 0; c < 3; ++c) m[c] += image.rgb[3 * p + c] / static_cast<double>(image.pixels());
    return m;
  };
  const auto largest_difference = [](const Image& image, Vec3f expected) {
    double worst = 0;
    for (std::size_t p = 0; p < image.pixels(); ++p)
      for (int c = 0; c < 3; ++c) worst = std::max(worst, std::abs(image.rgb[3 * p + c] - expected[c]));
    return worst;
  };

  SECTION("an open plane") {
    TestWorld scene;
    scene.world.add(TriangleMesh(quads({square(10.f, 0.f)})), 0);
    scene.world.commit();
    params.ao_samples = 4;
    CHECK(largest_difference(render(scene.world, params, top_view(0.f, 0.f, 2.f, 4.f), size, size, 2), kd) < 1e-5);
    // Seen 60 degrees off its normal, the plane shows kd cos 60.
    OrthographicCamera oblique = top_view(0.f, 0.f, 0.f, 2.f);
    oblique.direction = {0.f, std::sin(std::numbers::pi_v<float> / 3.f), -0.5f};
    oblique.position = -oblique.direction * 4.f;
    oblique.up = {0.f, 0.f, 1.f};
    CHECK(largest_difference(render(scene.world, params, oblique, size, size, 2), kd * 0.5f) < 1e-5);
  }
  SECTION("a floor under a large ceiling one unit above it") {
    TestWorld scene;
    scene.world.add(TriangleMesh(quads({square(50.f, 0.f), square(50.f, 1.f)})), 0);
    scene.world.commit();
    const OrthographicCamera between_them = top_view(0.f, 0.f, 0.5f, 2.f);
    params.ao_samples = 4;
    params.ao_distance = 0.5f;  // shorter than the gap: nothing occludes
    CHECK(largest_difference(render(scene.world, params, between_them, size, size, 2), kd) < 1e-5);
    params.ao_distance = 1e20f;  // the ceiling hides all but rays within atan(1/50) of the horizon
    // Fully occluded, what is left is 1 - aoIntensity of the eye light.
    const auto closed = channel_means(render(scene.world, params, between_them, size, size, 2));
    CHECK(std::abs(closed[0] - kd.x * (1.f - params.ao_intensity)) < 0.002);
    // Within 2 units only rays steeper than 60 degrees from the normal reach the ceiling:
    // cosine-weighted, the fraction that escapes is 1 - cos^2(60) ... = sin^2 = 1/4.
    params.ao_distance = 2.f;
    params.ao_samples = 16;
    std::vector<double> batch_means;
    for (const Image& b : render_frames(scene.world, params, between_them, size, size, 8)) {
      batch_means.push_back((channel_means(b)[0] / kd.x - (1.f - params.ao_intensity)) / params.ao_intensity);
    }
    const Stats visible = stats(batch_means);
    std::printf("[renderers] ao within 2 units under a ceiling at 1: visible fraction %.5f +- %.5f (closed form 0.25)\n",
                visible.mean, visible.stderr_);
    CHECK(std::abs(visible.mean - 0.25) < std::max(0.0025, 4 * visible.stderr_));
  }
}

