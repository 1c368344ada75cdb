// Camera rays: directions and origins against the OSPRay definitions, packets against
// single rays, and clear errors for impossible parameters.
#include <catch2/catch.hpp>

#include <cmath>
#include <memory>
#include <numbers>
#include <utility>
#include <vector>

#include "sciray/frame/pixel_filter.hpp"
#include "sciray/math/sequence.hpp"
#include "sciray/render/camera.hpp"

using namespace sciray;

TEST_CASE("perspective camera rays", "[camera]") {
  PerspectiveCamera c;
  c.position = {1.f, 2.f, 3.f};
  c.direction = {0.f, 0.f, -2.f};
  c.up = {0.f, 1.f, 0.f};
  c.fovy = 90.f;
  c.aspect = 2.f;
  const auto cam = prepare(c);

  const Ray<float> centre = cam.generate(0.5f, 0.5f);
  CHECK(centre.org == c.position);
  CHECK(centre.dir.x == Approx(0.f).margin(1e-6));
  CHECK(centre.dir.y == Approx(0.f).margin(1e-6));
  CHECK(centre.dir.z == Approx(-1.f));

  // With fovy 90 the top edge of the image is 45 degrees up; the right edge is at
  // atan(aspect * tan(45 deg)) sideways.
  const Ray<float> top = cam.generate(0.5f, 1.f);
  CHECK(std::atan2(top.dir.y, -top.dir.z) == Approx(std::numbers::pi / 4));
  const Ray<float> right = cam.generate(1.f, 0.5f);
  CHECK(right.dir.x > 0.f);
  CHECK(std::atan2(right.dir.x, -right.dir.z) == Approx(std::atan(2.0)));
  CHECK(length(cam.generate(0.1f, 0.9f).dir) == Approx(1.f));

  // Projected depth of a point straight ahead equals its distance; off-axis it is shorter.
  CHECK(cam.projected_depth(centre, 5.f) == Approx(5.f));
  CHECK(cam.projected_depth(top, 5.f) == Approx(5.f * std::cos(std::numbers::pi / 4)));
}

TEST_CASE("packet camera rays equal single rays", "[camera][simd]") {
  using A = xsimd::sse2;
  using F = simd::Float<A>;
  PerspectiveCamera c;
  c.position = {0.f, 1.f, 5.f};
  c.direction = {0.1f, -0.2f, -1.f};
  c.fovy = 35.f;
  c.aspect = 1.5f;
  const auto cam = prepare(c);
  const F sx{0.f, 0.25f, 0.6f, 1.f}, sy{1.f, 0.1f, 0.5f, 0.f};
  const Ray<F> packet = cam.generate(sx, sy);
  for (int i = 0; i < simd::width<A>; ++i) {
    const Ray<float> single = cam.generate(simd::lane(sx, i), simd::lane(sy, i));
    CHECK(simd::lane(packet.dir.x, i) == Approx(single.dir.x));
    CHECK(simd::lane(packet.dir.y, i) == Approx(single.dir.y));
    CHECK(simd::lane(packet.dir.z, i) == Approx(single.dir.z));
  }
}

TEST_CASE("orthographic camera rays", "[camera]") {
  OrthographicCamera c;
  c.position = {0.f, 0.f, 10.f};
  c.direction = {0.f, 0.f, -1.f};
  c.height = 4.f;
  c.aspect = 0.5f;
  const auto cam = prepare(c);
  const Ray<float> corner = cam.generate(0.f, 0.f);
  CHECK(corner.org.x == Approx(-1.f));
  CHECK(corner.org.y == Approx(-2.f));
  CHECK(corner.org.z == Approx(10.f));
  CHECK(corner.dir == Vec3f{0.f, 0.f, -1.f});
  const Ray<float> top_right = cam.generate(1.f, 1.f);
  CHECK(top_right.org.x == Approx(1.f));
  CHECK(top_right.org.y == Approx(2.f));
  CHECK(cam.projected_depth(corner, 3.f) == 3.f);
}

TEST_CASE("camera parameters that cannot work are named", "[camera][errors]") {
  PerspectiveCamera c;
  c.fovy = 180.f;
  CHECK_THROWS_WITH(prepare(c), Catch::Contains("'fovy'"));
  c.fovy = 60.f;
  c.up = {0.f, 0.f, 1.f};
  CHECK_THROWS_WITH(prepare(c), Catch::Contains("'up' is parallel to 'direction'"));
  c.up = {0.f, 1.f, 0.f};
  c.direction = {0.f, 0.f, 0.f};
  CHECK_THROWS_WITH(prepare(c), Catch::Contains("'direction'"));
  c.direction = {0.f, 0.f, -1.f};
  c.position = {std::nanf(""), 0.f, 0.f};
  CHECK_THROWS_WITH(prepare(c), Catch::Contains("'position'"));
  c.position = {};
  c.aspect = 0.f;
  CHECK_THROWS_WITH(prepare(c), Catch::Contains("'aspect'"));
  OrthographicCamera o;
  o.height = -1.f;
  CHECK_THROWS_WITH(prepare(o), Catch::Contains("'height'"));
}

TEST_CASE("frame_bounds sees the whole box", "[camera]") {
  Box3f box;
  box.extend(Vec3f{-1.f, -2.f, -0.5f});
  box.extend(Vec3f{3.f, 1.f, 0.5f});
  for (float aspect : {0.5f, 1.f, 2.f}) {
    const auto cam = prepare(frame_bounds(box, aspect));
    // Every corner projects inside the image.
    for (int k = 0; k < 8; ++k) {
      const Vec3f p{k & 1 ? box.upper.x : box.lower.x, k & 2 ? box.upper.y : box.lower.y,
                    k & 4 ? box.upper.z : box.lower.z};
      const Vec3f d = p - cam.position;
      const float along = dot(d, cam.forward);
      REQUIRE(along > 0.f);
      const float sx = dot(d, cam.du) / (along * dot(cam.du, cam.du)) + 0.5f;
      const float sy = dot(d, cam.dv) / (along * dot(cam.dv, cam.dv)) + 0.5f;
      CHECK(sx >= 0.f);
      CHECK(sx <= 1.f);
      CHECK(sy >= 0.f);
      CHECK(sy <= 1.f);
    }
  }
  CHECK_THROWS_WITH(frame_bounds(Box3f{}, 1.f), Catch::Contains("empty"));
}

namespace {
/// Where `ray` meets the plane at distance `depth` along the unit view axis `forward` from `eye`.
Vec3f on_plane(const Ray<float>& ray, const Vec3f& eye, const Vec3f& forward, float depth) {
  const float t = (depth - dot(ray.org - eye, forward)) / dot(ray.dir, forward);
  return ray.org + ray.dir * t;
}
void check_near(const Vec3f& a, const Vec3f& b, float margin) {
  CHECK(a.x == Approx(b.x).margin(margin));
  CHECK(a.y == Approx(b.y).margin(margin));
  CHECK(a.z == Approx(b.z).margin(margin));
}
}  // namespace

TEST_CASE("depth of field: every lens point of a screen point meets one focal-plane point", "[camera][dof]") {
  PerspectiveCamera c;
  c.position = {1.f, -2.f, 3.f};
  c.direction = {0.3f, 0.1f, -1.f};
  c.fovy = 50.f;
  c.aspect = 1.5f;
  c.aperture_radius = 0.2f;
  c.focus_distance = 7.f;
  const auto cam = prepare(c);
  const Vec3f forward = normalize(c.direction);
  for (const auto& [sx, sy] : {std::pair{0.5f, 0.5f}, {0.1f, 0.9f}, {0.95f, 0.2f}}) {
    const Ray<float> pinhole = cam.generate(sx, sy);  // lens centre
    CHECK(pinhole.org == c.position);
    const Vec3f focus = on_plane(pinhole, c.position, forward, c.focus_distance);
    for (const auto& [u, v] : {std::pair{0.f, 0.f}, {0.99f, 0.5f}, {0.3f, 0.8f}, {0.5f, 0.01f}}) {
      const Ray<float> ray = cam.generate(sx, sy, u, v);
      CHECK(length(ray.dir) == Approx(1.f));
      const Vec3f lens = ray.org - c.position;
      CHECK(dot(lens, forward) == Approx(0.f).margin(1e-6));  // the lens lies across the view axis
      CHECK(length(lens) <= c.aperture_radius * 1.0001f);
      check_near(on_plane(ray, c.position, forward, c.focus_distance), focus, 1e-4f);
    }
  }
  // Corners of the lens square reach the rim of the disc; other depths blur.
  CHECK(length(cam.generate(0.5f, 0.5f, 0.f, 0.f).org - c.position) == Approx(c.aperture_radius));
  const Vec3f near_a = on_plane(cam.generate(0.5f, 0.5f, 0.f, 0.5f), c.position, forward, 2.f);
  const Vec3f near_b = on_plane(cam.generate(0.5f, 0.5f, 0.99f, 0.5f), c.position, forward, 2.f);
  CHECK(length(near_a - near_b) > 0.1f);
}

TEST_CASE("stereo: eyes IPD/2 to either side along the right axis, looking parallel (as OSPRay)", "[camera][stereo]") {
  PerspectiveCamera c;
  c.position = {0.f, 1.f, 5.f};
  c.direction = {0.f, 0.f, -1.f};
  c.fovy = 60.f;
  c.aspect = 2.f;
  c.focus_distance = 4.f;
  c.interpupillary_distance = 0.07f;
  const Vec3f right{1.f, 0.f, 0.f};
  PerspectiveCamera mono = c;

  c.stereo_mode = StereoMode::left;
  const Ray<float> left = prepare(c).generate(0.5f, 0.5f);
  c.stereo_mode = StereoMode::right;
  const Ray<float> right_eye = prepare(c).generate(0.5f, 0.5f);
  check_near(left.org, c.position - right * 0.035f, 1e-6f);
  check_near(right_eye.org, c.position + right * 0.035f, 1e-6f);
  // Every screen point's ray of either eye is the mono camera's, moved sideways: points
  // far away land on the same pixel for both eyes, near ones shift (parallax).
  for (const auto& [sx, sy] : {std::pair{0.5f, 0.5f}, {0.1f, 0.8f}, {0.9f, 0.05f}}) {
    const Ray<float> m = prepare(mono).generate(sx, sy);
    c.stereo_mode = StereoMode::left;
    check_near(prepare(c).generate(sx, sy).dir, m.dir, 1e-6f);
    c.stereo_mode = StereoMode::right;
    check_near(prepare(c).generate(sx, sy).dir, m.dir, 1e-6f);
  }

  // Side by side: the left half is the left eye, each half a whole view of half the
  // aspect; top/bottom: the top half is the left eye.
  c.stereo_mode = StereoMode::side_by_side;
  const auto sbs = prepare(c);
  check_near(sbs.generate(0.25f, 0.5f).org, left.org, 1e-6f);
  check_near(sbs.generate(0.75f, 0.5f).org, right_eye.org, 1e-6f);
  check_near(sbs.generate(0.25f, 0.5f).dir, left.dir, 1e-6f);
  c.stereo_mode = StereoMode::left;
  c.aspect = 1.f;
  check_near(sbs.generate(0.05f, 0.9f).dir, prepare(c).generate(0.1f, 0.9f).dir, 1e-5f);
  c.aspect = 2.f;
  c.stereo_mode = StereoMode::top_bottom;
  const auto tb = prepare(c);
  check_near(tb.generate(0.5f, 0.75f).org, left.org, 1e-6f);
  check_near(tb.generate(0.5f, 0.25f).org, right_eye.org, 1e-6f);
}

TEST_CASE("panoramic camera: equirectangular over the whole sphere", "[camera][panoramic]") {
  PanoramicCamera c;
  c.position = {1.f, 2.f, 3.f};
  c.direction = {0.f, 0.f, -1.f};
  c.up = {0.f, 1.f, 0.f};
  const auto cam = prepare(c);
  const Vec3f forward{0.f, 0.f, -1.f}, right{1.f, 0.f, 0.f}, up{0.f, 1.f, 0.f};
  check_near(cam.generate(0.5f, 0.5f).dir, forward, 1e-6f);
  check_near(cam.generate(0.75f, 0.5f).dir, right, 1e-6f);
  check_near(cam.generate(0.25f, 0.5f).dir, -right, 1e-6f);
  check_near(cam.generate(0.f, 0.5f).dir, -forward, 1e-6f);
  check_near(cam.generate(1.f, 0.5f).dir, -forward, 1e-6f);
  check_near(cam.generate(0.3f, 1.f).dir, up, 1e-6f);
  check_near(cam.generate(0.8f, 0.f).dir, -up, 1e-6f);
  check_near(cam.generate(0.5f, 0.75f).dir, normalize(forward + up), 1e-6f);
  CHECK(cam.generate(0.2f, 0.3f).org == c.position);
  // Onto: every direction is the ray of the screen point its longitude and latitude give.
  for (const Vec3f d : {Vec3f{0.3f, -0.5f, 0.8f}, Vec3f{-0.9f, 0.1f, 0.2f}, Vec3f{0.f, 0.2f, 1.f},
                        Vec3f{0.01f, -1.f, 0.f}}) {
    const Vec3f n = normalize(d);
    const float sx = 0.5f + std::atan2(dot(n, right), dot(n, forward)) / (2.f * std::numbers::pi_v<float>);
    const float sy = 0.5f + std::asin(dot(n, up)) / std::numbers::pi_v<float>;
    check_near(cam.generate(sx, sy).dir, n, 1e-5f);
  }

  // Omni-directional stereo: each eye IPD/2 to the side of the ray's horizontal heading.
  c.stereo_mode = StereoMode::side_by_side;
  c.interpupillary_distance = 0.06f;
  const auto stereo = prepare(c);
  check_near(stereo.generate(0.25f, 0.5f).org, c.position - right * 0.03f, 1e-6f);  // left eye, looking ahead
  check_near(stereo.generate(0.75f, 0.5f).org, c.position + right * 0.03f, 1e-6f);  // right eye, looking ahead
  const Ray<float> left_looking_right = stereo.generate(0.375f, 0.5f);
  check_near(left_looking_right.dir, right, 1e-6f);
  check_near(left_looking_right.org, c.position + forward * 0.03f, 1e-6f);
  CHECK(dot(stereo.generate(0.1f, 0.7f).org - c.position, stereo.generate(0.1f, 0.7f).dir) == Approx(0.f).margin(1e-6));
}

TEST_CASE("orthographic cameras ignore the lens sample, packets with lens and stereo equal single rays",
          "[camera][simd]") {
  OrthographicCamera o;
  const auto ortho = prepare(o);
  check_near(ortho.generate(0.2f, 0.7f, 0.f, 0.9f).org, ortho.generate(0.2f, 0.7f).org, 0.f);

  using A = xsimd::sse2;
  using F = simd::Float<A>;
  PerspectiveCamera c;
  c.aperture_radius = 0.1f;
  c.focus_distance = 3.f;
  c.stereo_mode = StereoMode::side_by_side;
  PanoramicCamera p;
  p.stereo_mode = StereoMode::top_bottom;
  const F sx{0.f, 0.3f, 0.6f, 1.f}, sy{1.f, 0.1f, 0.5f, 0.7f}, u{0.1f, 0.5f, 0.9f, 0.3f}, v{0.7f, 0.5f, 0.2f, 0.f};
  const auto check_packet = [&](const auto& cam) {
    const Ray<F> packet = cam.generate(sx, sy, u, v);
    for (int i = 0; i < simd::width<A>; ++i) {
      const Ray<float> single = cam.generate(simd::lane(sx, i), simd::lane(sy, i), simd::lane(u, i), simd::lane(v, i));
      CHECK(simd::lane(packet.org.x, i) == Approx(single.org.x).margin(1e-6));
      CHECK(simd::lane(packet.org.z, i) == Approx(single.org.z).margin(1e-6));
      CHECK(simd::lane(packet.dir.x, i) == Approx(single.dir.x).margin(1e-5));
      CHECK(simd::lane(packet.dir.y, i) == Approx(single.dir.y).margin(1e-5));
    }
  };
  check_packet(prepare(c));
  check_packet(prepare(p));
}

TEST_CASE("lens and stereo parameters that cannot work are named", "[camera][errors]") {
  PerspectiveCamera c;
  c.aperture_radius = -0.1f;
  CHECK_THROWS_WITH(prepare(c), Catch::Contains("'apertureRadius'"));
  c.aperture_radius = 0.1f;
  c.focus_distance = 0.f;
  CHECK_THROWS_WITH(prepare(c), Catch::Contains("'focusDistance'"));
  c.focus_distance = 1.f;
  c.stereo_mode = static_cast<StereoMode>(7);
  CHECK_THROWS_WITH(prepare(c), Catch::Contains("'stereoMode'") && Catch::Contains("got 7"));
  c.stereo_mode = StereoMode::left;
  c.interpupillary_distance = -1.f;
  CHECK_THROWS_WITH(prepare(c), Catch::Contains("'interpupillaryDistance'"));
  PanoramicCamera p;
  p.up = p.direction;
  CHECK_THROWS_WITH(prepare(p), Catch::Contains("panoramic camera: 'up' is parallel"));
  CHECK_THROWS_WITH(stereo_mode_from_int("panoramic", -1), Catch::Contains("panoramic camera: 'stereoMode'"));
}

TEST_CASE("lens samples: stratified per pixel, decorrelated between pixels, the same in packets",
          "[camera][sampling]") {
  CHECK(camera_sample(1, 5).lens_u != camera_sample(2, 5).lens_u);  // pixels are decorrelated
  // Packets of pixels give each lane its own pixel's samples.
  using A = xsimd::sse2;
  const CameraSequence<A> packet(simd::Int<A>{3, 70, 9000, -1});
  for (std::uint32_t sample : {0u, 1u, 77u}) {
    const CameraSamples<simd::Float<A>> lanes = packet(sample);
    const std::uint32_t pixels[4] = {3, 70, 9000, 0xFFFFFFFFu};
    for (int i = 0; i < 4; ++i) {
      const CameraSample single = camera_sample(pixels[i], sample);
      CHECK(simd::lane(lanes.lens_u, i) == single.lens_u);
      CHECK(simd::lane(lanes.lens_v, i) == single.lens_v);
    }
  }
  // 1024 samples of one pixel: each quarter of each lens dimension gets a quarter of them
  // (within 6; independent random samples would miss by 14 on average), and the lens is
  // uncorrelated with the film's sample points.
  int quarters[2][4] = {};
  double film_lens = 0.0;
  for (std::uint32_t i = 0; i < 1024; ++i) {
    const CameraSample s = camera_sample(99, i);
    const float dims[2] = {s.lens_u, s.lens_v};
    for (int d = 0; d < 2; ++d) {
      REQUIRE(dims[d] >= 0.f);
      REQUIRE(dims[d] < 1.f);
      ++quarters[d][static_cast<int>(dims[d] * 4)];
    }
    film_lens += (pixel_sample_point(i)[0] - 0.5) * (s.lens_u - 0.5) * 12.0;  // correlation of two uniform variables
  }
  for (int d = 0; d < 2; ++d)
    for (int q = 0; q < 4; ++q) CHECK(std::abs(quarters[d][q] - 256) <= 6);
  CHECK(std::abs(film_lens / 1024) < 0.05);
}

namespace {
void check_rays_equal(const Ray<float>& a, const Ray<float>& b, float margin) {
  check_near(a.org, b.org, margin);
  check_near(a.dir, b.dir, margin);
  CHECK(a.tnear == Approx(b.tnear).margin(margin));
  CHECK(a.time == Approx(b.time).margin(margin));
}
/// A rotation by `degrees` about +y, then `translation`.
Affine3f turn_y(float degrees, Vec3f translation = {}) {
  const float a = degrees * std::numbers::pi_v<float> / 180.f;
  return {{std::cos(a), 0.f, -std::sin(a)}, {0.f, 1.f, 0.f}, {std::sin(a), 0.f, std::cos(a)}, translation};
}
}  // namespace

TEST_CASE("camera 'transform' places position, direction and up: the rays of the transformed camera",
          "[camera][transform]") {
  const Affine3f m = turn_y(30.f, {1.f, -2.f, 0.5f}) * Affine3f::scale(2.f);  // sizes stay: only vectors move
  const auto check_type = [&](auto camera) {
    camera.position = {0.3f, 0.1f, 2.f};
    camera.direction = {0.1f, -0.2f, -1.f};
    camera.up = {0.f, 1.f, 0.2f};
    auto moved = camera;
    moved.position = m.point(camera.position), moved.direction = m.vector(camera.direction);
    moved.up = m.vector(camera.up);
    camera.motion = std::make_shared<const MotionTransform>(m);
    const auto a = prepare(camera), b = prepare(moved);
    for (const auto& [sx, sy] : {std::pair{0.5f, 0.5f}, {0.f, 1.f}, {0.83f, 0.27f}})
      check_rays_equal(a.generate(sx, sy, 0.3f, 0.7f), b.generate(sx, sy, 0.3f, 0.7f), 0.f);
  };
  PerspectiveCamera p;
  p.aperture_radius = 0.1f;
  check_type(p);
  check_type(OrthographicCamera{});
  check_type(PanoramicCamera{});
}

TEST_CASE("moving camera: each ray is placed by the motion keys at its own time", "[camera][motion]") {
  // Two keys 2 apart along x, and a quarter turn about y: each ray sees the camera where
  // the linearly interpolated keys put it at the ray's time.
  auto slide = std::make_shared<const MotionTransform>(
      std::vector<Affine3f>{Affine3f{}, Affine3f::translate({2.f, 0.f, 0.f})}, 0.f, 1.f);
  auto turn = std::make_shared<const MotionTransform>(std::vector<Affine3f>{turn_y(0.f), turn_y(90.f)}, 0.f, 1.f);
  OrthographicCamera o;
  o.motion = slide;
  o.shutter_open = 0.f, o.shutter_close = 1.f;
  const auto ortho = prepare(o);
  CHECK(ortho.uses_time_sample());
  for (float u : {0.f, 0.25f, 0.9f}) {
    const Ray<float> ray = ortho.generate(0.5f, 0.5f, 0.5f, 0.5f, u);
    CHECK(ray.time == Approx(u));
    check_near(ray.org, {2.f * u, 0.f, 0.f}, 1e-6f);
  }
  PanoramicCamera p;
  p.motion = turn;
  p.shutter_open = 0.f, p.shutter_close = 1.f;
  // Halfway the matrices average to a scaled 45-degree turn; the camera is rebuilt from
  // the normalized direction, so the view turns 45 degrees.
  const float h = std::sqrt(0.5f);
  check_near(prepare(p).generate(0.5f, 0.5f, 0.5f, 0.5f, 0.5f).dir, {-h, 0.f, -h}, 1e-6f);
  check_near(prepare(p).generate(0.5f, 0.5f, 0.5f, 0.5f, 1.f).dir, {-1.f, 0.f, 0.f}, 1e-6f);
  // Packets place every lane at its own time.
  using A = xsimd::sse2;
  using F = simd::Float<A>;
  PerspectiveCamera c;
  c.motion = turn;
  c.shutter_open = 0.2f, c.shutter_close = 0.8f;
  c.stereo_mode = StereoMode::side_by_side;
  c.aperture_radius = 0.05f;
  const auto cam = prepare(c);
  const F sx{0.1f, 0.4f, 0.6f, 0.9f}, sy{0.9f, 0.2f, 0.5f, 0.3f}, u{0.f, 0.3f, 0.6f, 0.99f};
  const Ray<F> packet = cam.generate(sx, sy, u, u, u);
  for (int i = 0; i < 4; ++i) {
    const Ray<float> single = cam.generate(simd::lane(sx, i), simd::lane(sy, i), simd::lane(u, i), simd::lane(u, i),
                                           simd::lane(u, i));
    CHECK(simd::lane(packet.time, i) == Approx(0.2f + 0.6f * simd::lane(u, i)));
    check_near({simd::lane(packet.dir.x, i), simd::lane(packet.dir.y, i), simd::lane(packet.dir.z, i)}, single.dir,
               1e-5f);
    check_near({simd::lane(packet.org.x, i), simd::lane(packet.org.y, i), simd::lane(packet.org.z, i)}, single.org,
               1e-6f);
    CHECK(simd::lane(cam.projected_depth(packet, F(2.f)), i) == Approx(cam.projected_depth(single, 2.f)));
  }
  // Depth is measured along the view axis at the ray's own time: straight ahead it is
  // the distance, whenever the ray looks.
  c.stereo_mode = StereoMode::none;
  c.aperture_radius = 0.f;
  const auto pinhole = prepare(c);
  for (float time_u : {0.f, 0.5f, 1.f}) {
    const Ray<float> ahead = pinhole.generate(0.5f, 0.5f, 0.5f, 0.5f, time_u);
    CHECK(pinhole.projected_depth(ahead, 2.f) == Approx(2.f));
  }
}

TEST_CASE("shutter: a global one spans its interval, rolling ones sweep columns or rows", "[camera][shutter]") {
  OrthographicCamera c;
  c.shutter_open = 0.2f, c.shutter_close = 0.6f;
  const auto time = [&](float sx, float sy, float u) { return prepare(c).generate(sx, sy, 0.5f, 0.5f, u).time; };
  CHECK(time(0.f, 0.f, 0.f) == Approx(0.2f));
  CHECK(time(1.f, 0.3f, 0.5f) == Approx(0.4f));
  CHECK(prepare(c).uses_time_sample());
  c.shutter_open = c.shutter_close = 0.7f;  // one instant: the time sample is not needed
  CHECK(time(0.3f, 0.3f, 0.9f) == Approx(0.7f));
  CHECK_FALSE(prepare(c).uses_time_sample());

  // Each row or column opens in turn, for rollingShutterDuration: the last one opens
  // that long before the shutter closes.
  c.shutter_open = 0.f, c.shutter_close = 1.f;
  c.rolling_shutter_duration = 0.2f;
  c.shutter_type = ShutterType::rolling_right;  // left column first
  CHECK(time(0.f, 0.5f, 0.f) == Approx(0.f));
  CHECK(time(0.5f, 0.9f, 0.5f) == Approx(0.5f));
  CHECK(time(1.f, 0.1f, 1.f) == Approx(1.f));
  c.shutter_type = ShutterType::rolling_left;  // right column first
  CHECK(time(1.f, 0.5f, 0.f) == Approx(0.f));
  CHECK(time(0.f, 0.5f, 0.f) == Approx(0.8f));
  c.shutter_type = ShutterType::rolling_down;  // top row first
  CHECK(time(0.3f, 1.f, 0.f) == Approx(0.f));
  CHECK(time(0.3f, 0.f, 0.5f) == Approx(0.9f));
  c.shutter_type = ShutterType::rolling_up;  // bottom row first
  CHECK(time(0.3f, 0.f, 0.f) == Approx(0.f));
  CHECK(time(0.3f, 0.25f, 1.f) == Approx(0.4f));
  CHECK(prepare(c).uses_time_sample());
  c.rolling_shutter_duration = 0.f;  // each row is one instant
  CHECK_FALSE(prepare(c).uses_time_sample());
  CHECK(time(0.3f, 0.25f, 0.9f) == Approx(0.25f));

  // With stereo, each eye's view rolls on its own.
  PerspectiveCamera s;
  s.stereo_mode = StereoMode::top_bottom;
  s.shutter_open = 0.f, s.shutter_close = 1.f;
  s.shutter_type = ShutterType::rolling_down;
  CHECK(prepare(s).generate(0.5f, 1.f).time == Approx(0.f));    // top of the left eye
  CHECK(prepare(s).generate(0.5f, 0.4999f).time == Approx(0.f).margin(1e-3));  // top of the right eye
  CHECK(prepare(s).generate(0.5f, 0.25f).time == Approx(0.5f));
}

TEST_CASE("imageStart and imageEnd show a region of the image plane, nearClip starts the rays", "[camera][region]") {
  PerspectiveCamera c;
  c.position = {0.f, 1.f, 3.f};
  c.fovy = 50.f;
  c.aspect = 1.5f;
  c.near_clip = 0.25f;
  PerspectiveCamera region = c;
  region.image_region = {0.25f, 0.5f, 0.75f, 1.f};
  for (const auto& [sx, sy] : {std::pair{0.f, 0.f}, {0.5f, 0.5f}, {1.f, 0.2f}}) {
    const Ray<float> ray = prepare(region).generate(sx, sy);
    check_rays_equal(ray, prepare(c).generate(0.25f + 0.5f * sx, 0.5f + 0.5f * sy), 1e-6f);
    CHECK(ray.tnear == 0.25f);
  }
  // A start beyond the end mirrors that axis.
  region.image_region = {1.f, 0.f, 0.f, 1.f};
  check_rays_equal(prepare(region).generate(0.1f, 0.3f), prepare(c).generate(0.9f, 0.3f), 1e-6f);
  PanoramicCamera p;
  p.image_region = {0.5f, 0.f, 1.f, 1.f};  // the right half of the panorama
  check_near(prepare(p).generate(0.5f, 0.5f).dir, {1.f, 0.f, 0.f}, 1e-6f);
}

TEST_CASE("shutter, region, clipping and motion parameters that cannot work are named", "[camera][errors]") {
  OrthographicCamera c;
  c.near_clip = -1.f;
  CHECK_THROWS_WITH(prepare(c), Catch::Contains("orthographic camera: 'nearClip'"));
  c.near_clip = 0.f;
  c.image_region = {0.5f, 0.f, 0.5f, 1.f};
  CHECK_THROWS_WITH(prepare(c), Catch::Contains("'imageStart' and 'imageEnd' must differ"));
  c.image_region = {0.f, std::nanf(""), 1.f, 1.f};
  CHECK_THROWS_WITH(prepare(c), Catch::Contains("finite"));
  c.image_region = {};
  c.shutter_open = 0.6f, c.shutter_close = 0.4f;
  CHECK_THROWS_WITH(prepare(c), Catch::Contains("'shutter' must satisfy 0 <= lower <= upper <= 1"));
  c.shutter_open = 0.f, c.shutter_close = 1.5f;
  CHECK_THROWS_WITH(prepare(c), Catch::Contains("'shutter'"));
  c.shutter_close = 0.5f;
  c.shutter_type = static_cast<ShutterType>(9);
  CHECK_THROWS_WITH(prepare(c), Catch::Contains("'shutterType'") && Catch::Contains("got 9"));
  c.shutter_type = ShutterType::rolling_up;
  c.rolling_shutter_duration = 0.6f;
  CHECK_THROWS_WITH(prepare(c), Catch::Contains("'rollingShutterDuration' must be in [0, shutter upper - lower]"));
  c.rolling_shutter_duration = 0.f;
  // A key that folds the view onto `up` leaves no image plane.
  c.motion = std::make_shared<const MotionTransform>(
      std::vector<Affine3f>{Affine3f{}, Affine3f{{1.f, 0.f, 0.f}, {0.f, 1.f, 0.f}, {0.f, 1.f, 0.f}, {}}}, 0.f, 1.f);
  CHECK_THROWS_WITH(prepare(c), Catch::Contains("'motion.transform' key 1") && Catch::Contains("'up' is parallel"));
}
