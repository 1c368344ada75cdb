// Lights: every light's sample and eval agree, and Monte Carlo estimates of irradiance
// from sampling match closed forms.
#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>
#include <random>

#include "sciray/render/light.hpp"

using namespace sciray;

namespace {

constexpr float pi = std::numbers::pi_v<float>;

/// Irradiance at p on a surface with normal n, by sampling the light (unoccluded).
double irradiance(const Light& light, Vec3f p, Vec3f n, int samples = 200'000) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(0.f, 1.f);
  double sum = 0.0;
  for (int i = 0; i < samples; ++i) {
    const auto s = sample(light, p, n, u(rng), u(rng));
    if (!s) continue;
    sum += std::max(0.f, dot(s->dir, n)) * s->weight.x;
  }
  return sum / samples;
}

}  // namespace

TEST_CASE("sampled lights report the pdf and radiance eval finds in the same direction", "[light]") {
  std::vector<std::pair<std::string, Light>> lights;
  DistantLight sun;
  sun.direction = {0.2f, -1.f, 0.1f};
  sun.angular_diameter = 5.f;
  lights.emplace_back("distant", sun);
  SphereLight sphere;
  sphere.position = {0.f, 3.f, 0.f};
  sphere.radius = 0.5f;
  lights.emplace_back("sphere", sphere);
  SpotLight spot;
  spot.position = {0.f, 2.f, 0.f};
  spot.direction = {0.f, -1.f, 0.f};
  spot.opening_angle = 90.f;
  spot.radius = 0.3f;
  lights.emplace_back("spot", spot);
  QuadLight quad;
  quad.position = {-0.5f, 2.f, -0.5f};
  quad.edge1 = {1.f, 0.f, 0.f};
  quad.edge2 = {0.f, 0.f, 1.f};  // edge1 x edge2 points down, towards p
  lights.emplace_back("quad", quad);
  lights.emplace_back("ambient", AmbientLight{});
  std::vector<Vec3f> texels(16 * 8);
  for (std::size_t i = 0; i < texels.size(); ++i) texels[i] = splat(0.1f + static_cast<float>(i % 7));
  lights.emplace_back("hdri", HdriLight(std::make_shared<Texture2D>(16, 8, texels)));

  const Vec3f p{0.1f, 0.f, 0.2f}, n{0.f, 1.f, 0.f};
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(0.f, 1.f);
  for (const auto& [name, light] : lights) {
    INFO(name);
    REQUIRE_NOTHROW(validate(light));
    int checked = 0;
    for (int i = 0; i < 200; ++i) {
      const auto s = sample(light, p, n, u(rng), u(rng));
      if (!s) continue;
      const LightEval e = eval(light, p, n, s->dir, std::numeric_limits<float>::infinity());
      REQUIRE(e.pdf == Approx(s->pdf).epsilon(2e-3));
      for (int c = 0; c < 3; ++c) REQUIRE(e.radiance[c] / e.pdf == Approx(s->weight[c]).epsilon(2e-3));
      ++checked;
    }
    CHECK(checked > 100);
  }
}

TEST_CASE("irradiance estimated by sampling lights matches closed forms", "[light]") {
  const Vec3f p{0.f, 0.f, 0.f}, n{0.f, 1.f, 0.f};
  SECTION("point light: I cos / d^2") {
    SphereLight l;
    l.position = {1.f, 2.f, 0.f};
    l.intensity = 3.f;
    CHECK(irradiance(l, p, n, 10) == Approx(3.0 * (2.0 / std::sqrt(5.0)) / 5.0).epsilon(1e-5));
  }
  SECTION("sphere light overhead: pi L sin^2(alpha), with L = I / (pi r^2)") {
    SphereLight l;
    l.position = {0.f, 4.f, 0.f};
    l.radius = 1.f;
    l.intensity = 2.f;
    const double radiance = 2.0 / (pi * 1.0), sin2 = 1.0 / 16.0;
    CHECK(irradiance(l, p, n) == Approx(pi * radiance * sin2).epsilon(5e-3));
  }
  SECTION("unit square one unit above: L * form factor") {
    QuadLight l;
    l.position = {-0.5f, 1.f, -0.5f};
    l.edge1 = {1.f, 0.f, 0.f};
    l.edge2 = {0.f, 0.f, 1.f};  // edge1 x edge2 points down
    l.intensity = 1.f;
    // Irradiance from a square of side a at height h, centred above: 4 L (a'/sqrt(1+a'^2))
    // atan(a'/sqrt(1+a'^2)) with a' = a / (2h) (the corner-point rectangle formula, four times).
    const double x = 0.5, y = 0.5;
    const double corner = (x / std::sqrt(1 + x * x)) * std::atan(y / std::sqrt(1 + x * x)) +
                          (y / std::sqrt(1 + y * y)) * std::atan(x / std::sqrt(1 + y * y));
    CHECK(irradiance(l, p, n) == Approx(4.0 * corner / 2.0).epsilon(5e-3));
  }
  SECTION("the back of a quad light is dark") {
    QuadLight l;
    l.position = {-0.5f, 1.f, -0.5f};
    l.edge1 = {0.f, 0.f, 1.f};
    l.edge2 = {1.f, 0.f, 0.f};  // edge1 x edge2 points up, away from p
    CHECK(irradiance(l, p, n, 1000) == 0.0);
  }
  SECTION("ambient and a constant environment map: pi L") {
    AmbientLight a;
    a.intensity = 0.7f;
    CHECK(irradiance(a, p, n) == Approx(pi * 0.7).epsilon(1e-3));
    HdriLight h(std::make_shared<Texture2D>(32, 16, std::vector<Vec3f>(32 * 16, splat(0.7f))));
    CHECK(irradiance(h, p, n) == Approx(pi * 0.7).epsilon(1e-2));
    // A NaN direction (from a ray gone wrong) has no density, rather than a NaN one.
    CHECK(h.pdf({std::nanf(""), 0.f, 0.f}) == 0.f);
  }
  SECTION("a distant light's irradiance does not depend on its angular size") {
    DistantLight sharp, soft;
    sharp.direction = soft.direction = {0.f, -1.f, 0.f};
    soft.angular_diameter = 10.f;
    // Over a small disk the cosine varies little: within 0.2 %.
    CHECK(irradiance(soft, p, n) == Approx(irradiance(sharp, p, n, 10)).epsilon(2e-3));
  }
}

TEST_CASE("a bright spot in an environment map is sampled in proportion to its radiance", "[light]") {
  std::vector<Vec3f> texels(64 * 32, splat(0.01f));
  texels[20 * 64 + 40] = splat(1000.f);  // one bright texel above the horizon
  const HdriLight h(std::make_shared<Texture2D>(64, 32, texels, true));
  const Light light = h;
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(0.f, 1.f);
  int towards_spot = 0;
  const int n = 20'000;
  for (int i = 0; i < n; ++i) {
    const auto s = sample(light, {0.f, 0.f, 0.f}, {0.f, 1.f, 0.f}, u(rng), u(rng));
    REQUIRE(s);
    if (h.lookup(s->dir).x > 100.f) ++towards_spot;
  }
  CHECK(towards_spot > n * 9 / 10);
}

TEST_CASE("an environment map is laid out as OSPRay 3.1 lays it out", "[light]") {
  // Measured with OSPRay 3.1's runtime (a 31x15 map of distinct texels, nearest filter,
  // seen by scivis and pathtracer cameras): with up +y and direction +z the view along +x
  // shows u = 0.25, along -x u = 0.75, along +z the centre, along -z the seam (u = 0 or
  // 1), up v = 1; with up +z and direction -y the view along +x shows u = 0.25 again
  // (u = 0.75 lies towards direction x up).
  constexpr int w = 8, h = 4;
  std::vector<Vec3f> texels;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) texels.push_back({static_cast<float>(x), static_cast<float>(y), 0.f});
  const auto map = std::make_shared<Texture2D>(w, h, texels, true);
  const auto texel = [](const HdriLight& l, Vec3f dir) {
    const Vec3f t = l.lookup(normalize(dir));
    return std::pair<int, int>{static_cast<int>(t.x), static_cast<int>(t.y)};
  };
  const HdriLight standard(map);
  CHECK(texel(standard, {1.f, 0.1f, 0.1f}) == std::pair{2, 2});      // u ~ 0.27
  CHECK(texel(standard, {-1.f, 0.1f, 0.1f}) == std::pair{5, 2});     // u ~ 0.73
  CHECK(texel(standard, {-0.1f, 0.1f, 1.f}) == std::pair{4, 2});     // u ~ 0.52
  CHECK(texel(standard, {0.1f, 0.1f, -1.f}) == std::pair{0, 2});     // u ~ 0.02
  CHECK(texel(standard, {0.1f, 1.f, 0.2f}).second == 3);             // up: v ~ 0.9
  const HdriLight turned(map, {0.f, 0.f, 1.f}, {0.f, -1.f, 0.f});
  CHECK(texel(turned, {1.f, 0.05f, 0.1f}) == std::pair{1, 2});       // u ~ 0.24
  CHECK(texel(turned, {-1.f, 0.05f, 0.1f}) == std::pair{6, 2});      // u ~ 0.76
  // Importance sampling walks the same layout: a sample's direction shows the texel it was drawn from.
  std::vector<Vec3f> spot(w * h, splat(0.f));
  spot[1 * w + 2] = splat(1.f);  // column 2, row 1: below the horizon, towards +x
  const HdriLight lit(std::make_shared<Texture2D>(w, h, spot, true));
  const auto s = lit.sample(0.5f, 0.5f);
  CHECK(s.w.x > 0.5f);
  CHECK(s.w.y < 0.f);
  CHECK(lit.lookup(s.w).x == 1.f);
}

TEST_CASE("bad light parameters are named", "[light]") {
  QuadLight degenerate;
  degenerate.edge2 = degenerate.edge1;
  CHECK_THROWS_WITH(validate(degenerate), Catch::Contains("'edge1'"));
  SphereLight negative;
  negative.radius = -1.f;
  CHECK_THROWS_WITH(validate(negative), Catch::Contains("'radius'"));
  DistantLight nan_direction;
  nan_direction.direction = {std::nanf(""), 0.f, 0.f};
  CHECK_THROWS_WITH(validate(nan_direction), Catch::Contains("'direction'"));
  CHECK_THROWS_WITH(HdriLight(nullptr), Catch::Contains("'map'"));
  CHECK_THROWS_WITH(Texture2D(2, 2, std::vector<Vec3f>(3)), Catch::Contains("3 texels"));
}
