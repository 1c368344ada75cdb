// Camera rays: directions and origins against the OSPRay definitions, packets against
// single rays, and clear errors for impossible parameters.
#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>

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
