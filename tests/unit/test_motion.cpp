// Motion blur and camera placement in whole frames: keyed transforms interpolate as
// Embree does, an instance moving across the shutter blurs into a streak whose value in
// each pixel is the fraction of the shutter it covers the pixel, a rolling shutter shears
// a moving edge row by row, and a camera `transform` or image region changes nothing but
// where the camera looks.
#include <catch2/catch.hpp>

#include <cmath>
#include <memory>
#include <numbers>
#include <vector>

#include "sciray/shim/engine.hpp"
#include "support/render_stats.hpp"

using namespace sciray;
using namespace sciray::test_support;

namespace {

/// A rotation by `degrees` about +z, as a unit quaternion.
Quaternion about_z(float degrees) {
  const float half = 0.5f * degrees * std::numbers::pi_v<float> / 180.f;
  return {std::cos(half), 0.f, 0.f, std::sin(half)};
}

/// The rectangle [x0, x1] x [y0, y1] at z = 0, facing +z.
TriangleMesh rectangle(float x0, float x1, float y0, float y1) {
  MeshData mesh;
  mesh.positions = {x0, y0, 0.f, x1, y0, 0.f, x1, y1, 0.f, x0, y1, 0.f};
  mesh.indices = {0, 1, 2, 0, 2, 3};
  return TriangleMesh(std::move(mesh));
}

/// Looking straight down -z at the square [-2, 2]^2 of the plane z = 0.
OrthographicCamera top_view() {
  OrthographicCamera c;
  c.position = {0.f, 0.f, 5.f};
  c.direction = {0.f, 0.f, -1.f};
  c.height = 4.f;
  return c;
}

/// Flat white under ambient light: a pixel's value is how much of it the geometry covers
/// over the shutter (scivis made to sample it: OSPRay's sees only the middle instant).
SciVisParams coverage_shading() {
  SciVisParams params;
  params.sample_lens_and_shutter = true;
  params.materials = {ObjMaterial{.kd = {1.f, 1.f, 1.f}}};
  params.lights = {AmbientLight{}};
  return params;
}

FrameSettings centre_samples(int samples) {
  FrameSettings s;
  s.pixel_filter = PixelFilter::point;  // every sample at the pixel centre: only time varies
  s.pixel_samples = samples;
  return s;
}

}  // namespace

TEST_CASE("motion transforms interpolate their keys exactly as Embree places instances", "[motion]") {
  accel::Device device;
  accel::Scene empty(device);
  empty.commit();
  const auto check = [&](const MotionTransform& motion) {
    accel::GeometryHandle instance(device, RTC_GEOMETRY_TYPE_INSTANCE);
    rtcSetGeometryInstancedScene(instance.get(), empty.get());
    accel::set_transform(instance.get(), motion);
    rtcCommitGeometry(instance.get());
    for (float time : {-0.5f, -0.2f, 0.f, 0.3f, 0.5f, 0.77f, 1.f, 1.5f}) {
      INFO("time " << time);
      float embree[12];
      rtcGetGeometryTransform(instance.get(), time, RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, embree);
      const Affine3f m = motion.at(time);
      const float ours[12] = {m.vx.x, m.vx.y, m.vx.z, m.vy.x, m.vy.y, m.vy.z, m.vz.x, m.vz.y, m.vz.z, m.p.x, m.p.y, m.p.z};
      for (int k = 0; k < 12; ++k) CHECK(ours[k] == Approx(embree[k]).margin(1e-5));
    }
  };
  const Affine3f shear{{1.f, 0.2f, 0.f}, {0.f, 2.f, 0.f}, {0.3f, 0.f, 0.5f}, {1.f, 2.f, 3.f}};
  check(MotionTransform({Affine3f{}, shear, Affine3f::translate({-1.f, 0.f, 4.f})}, -0.5f, 1.5f));
  QuaternionDecomposition a, b, c;
  a.rotation = about_z(10.f), a.shift = {0.f, -4.f, 0.f}, a.translation = {0.f, 4.f, 0.f};
  b.rotation = about_z(100.f), b.scale = {1.f, 2.f, 0.5f}, b.skew = {0.1f, 0.f, 0.2f}, b.translation = {1.f, 0.f, 0.f};
  c.rotation = Quaternion{0.5f, 0.5f, 0.5f, 0.5f};
  check(MotionTransform({a, b, c}, -0.5f, 1.5f));

  // Quaternions turn on the arc: halfway from 0 to 90 degrees is a 45-degree rotation,
  // not the shrunken average of the two matrices.
  QuaternionDecomposition from, to;
  to.rotation = about_z(90.f);
  const Affine3f half = MotionTransform({from, to}, 0.f, 1.f).at(0.5f);
  CHECK(half.vx.x == Approx(std::sqrt(0.5f)));
  CHECK(half.vx.y == Approx(std::sqrt(0.5f)));
  CHECK(length(half.vy) == Approx(1.f));
}

TEST_CASE("an instance moving across the shutter blurs into a streak covering each pixel for its share of the shutter",
          "[motion][render]") {
  constexpr int size = 64;
  constexpr float pixel = 4.f / size, x0 = -1.5f, travel = 2.f, width = 1.f;
  // The keys span [0, 1] or only [0, 0.5], where the square also travels twice as fast
  // and is gone for the second half of the shutter.
  for (const float key_end : {1.f, 0.5f}) {
    INFO("keys over [0, " << key_end << "]");
    TestWorld scene;
    auto group = std::make_shared<shim::EngineWorld::GroupType>(scene.device);
    group->add(rectangle(0.f, width, -0.5f, 0.5f), 0);
    scene.world.add_instance(group, MotionTransform({Affine3f::translate({x0, 0.f, 0.f}),
                                                     Affine3f::translate({x0 + travel, 0.f, 0.f})},
                                                    0.f, key_end));
    scene.world.commit();
    OrthographicCamera camera = top_view();
    camera.shutter_open = camera.shutter_close = 0.f;  // the first key alone: full coverage
    const double full = render(scene.world, coverage_shading(), camera, size, size, 1, centre_samples(1))
                            .at(size / 2 - 16, size / 2, 0);  // x = -1, inside [x0, x0 + width]
    REQUIRE(full > 0.1);
    camera.shutter_close = 1.f;
    const Image image = render(scene.world, coverage_shading(), camera, size, size, 1, centre_samples(64));

    int streaked = 0, checked = 0;
    for (int y = size / 2 - 6; y < size / 2 + 6; ++y)  // rows well inside the square's height
      for (int x = 0; x < size; ++x) {
        const float centre = -2.f + (static_cast<float>(x) + 0.5f) * pixel;
        // The fraction of the shutter during which [left(t), left(t) + width] covers the centre.
        constexpr int steps = 20000;
        int covered = 0;
        for (int s = 0; s < steps; ++s) {
          const float t = (static_cast<float>(s) + 0.5f) / steps;
          if (t > key_end) break;
          const float left = x0 + travel * t / key_end;
          covered += left <= centre && centre <= left + width;
        }
        const double expected = static_cast<double>(covered) / steps;
        INFO("pixel (" << x << ", " << y << ") at x = " << centre);
        CHECK(image.at(x, y, 0) / full == Approx(expected).margin(0.05));
        streaked += expected > 0.05 && expected < 0.95;
        ++checked;
      }
    CHECK(streaked > checked / 2);  // the streak is most of the row, not a sharp square
  }
}

TEST_CASE("scivis and ao render the shutter's middle instant, as OSPRay's: a moving square stays sharp",
          "[motion][render]") {
  constexpr int size = 64;
  constexpr float pixel = 4.f / size, x0 = -1.5f, travel = 2.f, width = 1.f;
  TestWorld scene;
  auto group = std::make_shared<shim::EngineWorld::GroupType>(scene.device);
  group->add(rectangle(0.f, width, -0.5f, 0.5f), 0);
  scene.world.add_instance(group, MotionTransform({Affine3f::translate({x0, 0.f, 0.f}),
                                                   Affine3f::translate({x0 + travel, 0.f, 0.f})},
                                                  0.f, 1.f));
  scene.world.commit();
  OrthographicCamera camera = top_view();
  camera.shutter_open = 0.f, camera.shutter_close = 1.f;
  SciVisParams scivis = coverage_shading();
  scivis.sample_lens_and_shutter = false;
  AOParams ao;
  ao.materials = scivis.materials;
  ao.ao_samples = 0;
  const Image scivis_image = render(scene.world, scivis, camera, size, size, 1, centre_samples(16));
  const Image ao_image = render(scene.world, ao, camera, size, size, 1, centre_samples(16));
  // At time 0.5 the square spans [x0 + travel / 2, x0 + travel / 2 + width] = [-0.5, 0.5].
  const float left = x0 + 0.5f * travel;
  for (const Image* image : {&scivis_image, &ao_image}) {
    const double inside = image->at(size / 2, size / 2, 0);
    REQUIRE(inside > 0.1);
    for (int x = 0; x < size; ++x) {
      const float centre = -2.f + (static_cast<float>(x) + 0.5f) * pixel;
      const bool covered = left <= centre && centre <= left + width;
      INFO("pixel x = " << x << " at " << centre);
      CHECK(image->at(x, size / 2, 0) / inside == Approx(covered ? 1.0 : 0.0).margin(1e-4));
    }
  }
}

TEST_CASE("a rolling shutter shears a moving edge: each row sees it where it was when that row was exposed",
          "[motion][render]") {
  constexpr int size = 64;
  constexpr float pixel = 4.f / size, x0 = -1.5f, travel = 2.f;
  TestWorld scene;
  auto group = std::make_shared<shim::EngineWorld::GroupType>(scene.device);
  group->add(rectangle(0.f, 10.f, -10.f, 10.f), 0);  // a half-plane right of its left edge
  scene.world.add_instance(
      group, MotionTransform({Affine3f::translate({x0, 0.f, 0.f}), Affine3f::translate({x0 + travel, 0.f, 0.f})},
                             0.f, 1.f));
  scene.world.commit();
  OrthographicCamera camera = top_view();
  camera.shutter_open = 0.f, camera.shutter_close = 1.f;
  camera.shutter_type = ShutterType::rolling_down;  // the top row at time 0, the bottom one at 1
  const Image image = render(scene.world, coverage_shading(), camera, size, size, 1, centre_samples(1));
  int rows = 0;
  for (int y = 0; y < size; ++y) {
    const float time = 1.f - (static_cast<float>(y) + 0.5f) / size;
    const float edge = x0 + travel * time;
    // The first pixel centre right of the edge (rows where the edge is at a centre prove nothing).
    const float columns = (edge + 2.f) / pixel - 0.5f;
    if (std::abs(columns - std::round(columns)) < 1e-3f) continue;
    const int expected = static_cast<int>(std::ceil(columns));
    int first = size;
    for (int x = 0; x < size && first == size; ++x)
      if (image.at(x, y, 0) > 0.05) first = x;
    INFO("row " << y << ", edge at x = " << edge);
    CHECK(first == expected);
    ++rows;
  }
  CHECK(rows > size / 2);
}

TEST_CASE("a camera 'transform' renders the image of the camera it places", "[motion][render][camera]") {
  TestWorld scene;
  scene.world.add(rectangle(-3.f, 3.f, -3.f, 3.f), 0);
  SphereData ball;
  ball.positions = {0.3f, -0.2f, 0.6f};
  ball.radius = 0.6f;
  scene.world.add(Spheres(std::move(ball)), 0);
  scene.world.commit();
  SciVisParams params;
  params.materials = {ObjMaterial{.kd = {0.7f, 0.6f, 0.5f}}};
  params.shadows = true;
  params.ao_samples = 2;
  PerspectiveCamera camera;
  camera.position = {0.f, 0.f, 0.f};
  camera.direction = {0.f, 0.f, -1.f};
  camera.up = {0.f, 1.f, 0.f};
  camera.fovy = 40.f;
  // Up and back, looking down at the ball; the scale changes no size of the camera.
  const float a = 0.6f;
  const Affine3f m = Affine3f{{1.f, 0.f, 0.f}, {0.f, std::cos(a), std::sin(a)}, {0.f, -std::sin(a), std::cos(a)},
                              {0.f, -3.f, 5.f}} *
                     Affine3f::scale(3.f);
  PerspectiveCamera placed = camera;
  placed.position = m.point(camera.position), placed.direction = m.vector(camera.direction);
  placed.up = m.vector(camera.up);
  camera.motion = std::make_shared<const MotionTransform>(m);
  const Image by_transform = render(scene.world, params, camera, 48, 32, 1, centre_samples(4));
  const Image by_position = render(scene.world, params, placed, 48, 32, 1, centre_samples(4));
  CHECK(by_transform.rgb == by_position.rgb);
  double sum = 0;
  for (double v : by_transform.rgb) sum += v;
  CHECK(sum > 0.1 * static_cast<double>(by_transform.rgb.size()));  // it sees the scene, not the void
}

TEST_CASE("imageStart and imageEnd render exactly the matching crop of the full image", "[motion][render][camera]") {
  TestWorld scene;
  scene.world.add(rectangle(-3.f, 3.f, -3.f, 3.f), 0);
  SphereData balls;
  balls.positions = {0.3f, -0.2f, 0.6f, -0.8f, 0.7f, 0.3f};
  balls.radius = 0.4f;
  scene.world.add(Spheres(std::move(balls)), 0);
  scene.world.commit();
  SciVisParams params;
  params.materials = {ObjMaterial{.kd = {0.7f, 0.6f, 0.5f}}};
  params.shadows = true;
  PerspectiveCamera camera;
  camera.position = {0.f, -4.f, 3.f};
  camera.direction = {0.f, 4.f, -3.f};
  camera.up = {0.f, 0.f, 1.f};
  camera.aspect = 64.f / 48.f;
  const Image full = render(scene.world, params, camera, 64, 48, 1, centre_samples(1));
  // The right-hand upper quarter's central half: columns 16..47, rows 24..47.
  camera.image_region = {0.25f, 0.5f, 0.75f, 1.f};
  const Image crop = render(scene.world, params, camera, 32, 24, 1, centre_samples(1));
  int same = 0;
  for (int y = 0; y < 24; ++y)
    for (int x = 0; x < 32; ++x) {
      bool equal = true;
      for (int c = 0; c < 3; ++c) equal &= std::abs(crop.at(x, y, c) - full.at(16 + x, 24 + y, c)) <= 1e-4;
      same += equal;
    }
  // Rays through the same points differ in the last bit at most: only a ray grazing a
  // silhouette may land on the other side.
  CHECK(same >= 32 * 24 - 4);
}
