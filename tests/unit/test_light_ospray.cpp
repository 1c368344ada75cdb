// OSPRay's light features: intensity quantities, ring spots, cylinder lights,
// photometric tables, placement by instances, and the sunSky light.
#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>
#include <random>

#include "sciray/render/light.hpp"
#include "sciray/render/sky.hpp"

using namespace sciray;

namespace {

constexpr double pi = std::numbers::pi;

/// Irradiance at p on a surface with normal n, by sampling the light (unoccluded).
double irradiance(const Light& light, Vec3f p, Vec3f n, int samples = 200'000) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(0.f, 1.f);
  double sum = 0.0;
  for (int i = 0; i < samples; ++i) {
    const auto s = sample(light, p, n, u(rng), u(rng));
    if (s) sum += std::max(0.f, dot(s->dir, n)) * s->weight.x;
  }
  return sum / samples;
}

/// Sample and eval agree on pdf and radiance for `light` seen from p (to `tolerance`:
/// grazing directions amplify rounding).
void check_sample_eval(const Light& light, Vec3f p, Vec3f n, double tolerance = 3e-3) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(0.f, 1.f);
  int checked = 0;
  for (int i = 0; i < 300; ++i) {
    const auto s = sample(light, p, n, u(rng), u(rng));
    if (!s) continue;
    const LightEval e = eval(light, p, n, s->dir, std::numeric_limits<float>::infinity());
    REQUIRE(e.pdf == Approx(s->pdf).epsilon(tolerance));
    for (int c = 0; c < 3; ++c) REQUIRE(e.radiance[c] / e.pdf == Approx(s->weight[c]).epsilon(tolerance));
    ++checked;
  }
  CHECK(checked > 100);
}

TEST_CASE("intensityQuantity converts as OSPRay documents it", "[light]") {
  const Vec3f p{0.f, 0.f, 0.f}, up{0.f, 1.f, 0.f};
  SECTION("a sphere's power P gives P / (4 pi d^2), as a point and with a radius") {
    SphereLight point;
    point.position = {0.f, 4.f, 0.f};
    point.intensity = 100.f;
    point.quantity = IntensityQuantity::power;
    const double expected = 100.0 / (4.0 * pi * 16.0);
    CHECK(irradiance(point, p, up, 10) == Approx(expected).epsilon(1e-5));
    SphereLight ball = point;
    ball.radius = 0.5f;
    CHECK(irradiance(ball, p, up) == Approx(expected).epsilon(5e-3));
  }
  SECTION("a sphere's radiance L gives pi L sin^2(alpha); a point has no radiance") {
    SphereLight ball;
    ball.position = {0.f, 4.f, 0.f};
    ball.radius = 1.f;
    ball.intensity = 2.f;
    ball.quantity = IntensityQuantity::radiance;
    CHECK(irradiance(ball, p, up) == Approx(pi * 2.0 / 16.0).epsilon(5e-3));
    ball.radius = 0.f;
    CHECK(irradiance(ball, p, up, 10) == 0.0);
  }
  SECTION("a quad's intensity I is radiance I / area, its power P radiance P / (pi area)") {
    QuadLight l;
    l.position = {-1.f, 1.f, -1.f};
    l.edge1 = {2.f, 0.f, 0.f};
    l.edge2 = {0.f, 0.f, 2.f};
    l.intensity = 8.f;
    const double radiance_lit = irradiance(l, p, up);
    l.quantity = IntensityQuantity::intensity;
    CHECK(irradiance(l, p, up) == Approx(radiance_lit / 4.0).epsilon(1e-6));
    l.quantity = IntensityQuantity::power;
    CHECK(irradiance(l, p, up) == Approx(radiance_lit / (4.0 * pi)).epsilon(1e-6));
  }
  SECTION("a point spot's power spreads over the cosine-weighted cap of its opening") {
    SpotLight l;
    l.position = {0.f, 2.f, 0.f};
    l.direction = {0.f, -1.f, 0.f};
    l.opening_angle = 60.f;
    l.penumbra_angle = 0.f;
    l.intensity = 10.f;
    l.quantity = IntensityQuantity::power;
    const double cos_half = std::cos(pi / 6.0);
    CHECK(irradiance(l, p, up, 10) == Approx(10.0 / (pi * (1.0 - cos_half * cos_half)) / 4.0).epsilon(1e-5));
  }
  SECTION("ambient irradiance E is radiance E / pi; a distant light's radiance covers its disk") {
    AmbientLight a;
    a.intensity = 2.f;
    a.quantity = IntensityQuantity::irradiance;
    CHECK(emitted(a).x == Approx(2.0 / pi));
    DistantLight d;
    d.angular_diameter = 2.f;
    d.quantity = IntensityQuantity::radiance;
    CHECK(emitted(d).x == Approx(2.0 * pi * (1.0 - std::cos(pi / 180.0))));
  }
  SECTION("quantities a light does not take are named") {
    SphereLight s;
    s.quantity = IntensityQuantity::scale;
    CHECK_THROWS_WITH(validate(s), Catch::Contains("intensityQuantity") && Catch::Contains("without"));
    DistantLight d;
    d.quantity = IntensityQuantity::power;
    CHECK_THROWS_WITH(validate(d), Catch::Contains("intensityQuantity"));
  }
}

TEST_CASE("a spot light with an inner radius is a ring", "[light]") {
  SpotLight ring;
  ring.position = {0.f, 1.f, 0.f};
  ring.direction = {0.f, -1.f, 0.f};
  ring.penumbra_angle = 0.f;
  ring.radius = 0.8f;
  ring.inner_radius = 0.5f;
  ring.intensity = 3.f;
  ring.quantity = IntensityQuantity::radiance;
  REQUIRE_NOTHROW(validate(ring));
  // On the axis, h below a Lambertian annulus of radiance L: pi L (R^2/(R^2+h^2) - r^2/(r^2+h^2)).
  const double h = 1.0, big = 0.64, small = 0.25;
  const double expected = pi * 3.0 * (big / (big + h * h) - small / (small + h * h));
  CHECK(irradiance(ring, {0.f, 0.f, 0.f}, {0.f, 1.f, 0.f}) == Approx(expected).epsilon(5e-3));
  check_sample_eval(ring, {0.3f, 0.f, 0.1f}, {0.f, 1.f, 0.f});
  // Sample (0, 0), where scivis samples it, is on the inner edge along c0.
  ring.c0 = Vec3f{1.f, 0.f, 0.f};
  const auto s = sample(ring, {0.f, 0.f, 0.f}, {0.f, 1.f, 0.f}, 0.f, 0.f);
  REQUIRE(s);
  const Vec3f at = s->dir * s->dist;
  CHECK(at.x == Approx(0.5f));
  CHECK(at.y == Approx(1.f));
  CHECK(at.z == Approx(0.f).margin(1e-6));
  ring.inner_radius = 0.8f;
  CHECK_THROWS_WITH(validate(ring), Catch::Contains("innerRadius"));
}

/// The irradiance at p (normal n) from the side of cylinder light c, by the midpoint rule
/// over the side: L cos_p cos_light / d^2 dA over the part that faces p.
double side_irradiance(const CylinderLight& c, Vec3f p, Vec3f n) {
  const Vec3f d = c.position1 - c.position0;
  const double length = sciray::length(d);
  const Vec3f axis = d / static_cast<float>(length), e1 = perpendicular(axis), e2 = cross(axis, e1);
  const int nz = 600, nphi = 1200;
  const double dz = length / nz, dphi = 2.0 * pi / nphi;
  double integral = 0.0;
  for (int i = 0; i < nz; ++i)
    for (int j = 0; j < nphi; ++j) {
      const double z = (i + 0.5) * dz, phi = (j + 0.5) * dphi;
      const Vec3f normal = e1 * static_cast<float>(std::cos(phi)) + e2 * static_cast<float>(std::sin(phi));
      const Vec3f q = c.position0 + axis * static_cast<float>(z) + normal * c.radius;
      const Vec3f to = q - p;
      const double d2 = dot(to, to);
      const Vec3f w = to / static_cast<float>(std::sqrt(d2));
      const double cos_p = dot(w, n), cos_l = -dot(w, normal);
      if (cos_p > 0 && cos_l > 0) integral += c.intensity * cos_p * cos_l / d2 * c.radius * dphi * dz;
    }
  return integral;
}

}  // namespace

TEST_CASE("a cylinder light's irradiance matches integration over its side", "[light]") {
  CylinderLight c;
  c.position0 = {-1.f, 1.f, 0.f};
  c.position1 = {1.5f, 1.f, 0.f};
  c.radius = 0.2f;
  c.intensity = 2.f;
  const Vec3f n{0.f, 1.f, 0.f};
  SECTION("below it, near and far") {
    for (const Vec3f p : {Vec3f{0.3f, 0.f, 0.4f}, Vec3f{0.f, 0.7f, 0.1f}, Vec3f{0.5f, -3.f, 2.f}}) {
      CHECK(irradiance(c, p, n) == Approx(side_irradiance(c, p, n)).epsilon(5e-3));
      check_sample_eval(c, p, n, 1e-2);
    }
  }
  SECTION("past either end, where the caps hide part of the bounds") {
    for (const Vec3f p : {Vec3f{-1.6f, 0.5f, 0.2f}, Vec3f{2.5f, 0.2f, -0.3f}}) {
      const Vec3f facing = normalize(Vec3f{0.25f, 1.f, 0.f} - p);
      CHECK(irradiance(c, p, facing) == Approx(side_irradiance(c, p, facing)).epsilon(5e-3));
      check_sample_eval(c, p, facing, 1e-2);
    }
  }
  // Its intensity is radiance times the side's area over pi.
  CylinderLight by_intensity = c;
  by_intensity.quantity = IntensityQuantity::intensity;
  CHECK(emitted(by_intensity).x == Approx(2.0 * pi / (2.0 * pi * 0.2 * 2.5)));
  CHECK(!sample(c, {0.f, 1.1f, 0.f}, n, 0.3f, 0.4f));  // inside: the side faces away
}

TEST_CASE("scivis lights from a cylinder light's centre with radiance times its bounds' solid angle as OSPRay does", "[light]") {
  CylinderLight c;
  c.position0 = {-0.5f, 1.f, 0.f};
  c.position1 = {0.5f, 1.f, 0.f};
  c.radius = 0.2f;
  const Vec3f up{0.f, 1.f, 0.f};
  // OSPRay 3.1's scivis shows a white obj floor under this light at 0.1352 (measured
  // with its runtime): kd / pi times a weight of 0.4248 from straight above.
  const auto below = sample(c, {0.f, 0.f, 0.f}, up, 0.f, 0.f);
  REQUIRE(below);
  CHECK(below->dir.y == Approx(1.f));
  CHECK(below->dist == Approx(0.8f));
  CHECK(below->weight.x / pi == Approx(0.1352).epsilon(1e-3));
  // Off to the side along the axis it measured 0.0037 at x = -2.380 and nothing at
  // x = -2.678, where the way to the centre enters through a cap.
  const Vec3f p{-2.380f, 0.f, 0.f};
  const auto beside = sample(c, p, up, 0.f, 0.f);
  REQUIRE(beside);
  CHECK(beside->weight.x * dot(beside->dir, up) / pi == Approx(0.0037).epsilon(2e-2));
  CHECK(!sample(c, {-2.678f, 0.f, 0.f}, up, 0.f, 0.f));
}

TEST_CASE("photometric tables shape the emission by angle", "[light]") {
  SpotLight spot;
  spot.position = {0.f, 1.f, 0.f};
  spot.direction = {0.f, -1.f, 0.f};
  spot.opening_angle = 360.f;
  spot.penumbra_angle = 0.f;
  spot.quantity = IntensityQuantity::scale;
  spot.distribution = IntensityDistribution({4.f, 2.f, 0.f}, 3);  // gamma 0, 90, 180 degrees
  REQUIRE_NOTHROW(validate(spot));
  const Vec3f n{0.f, 1.f, 0.f};
  // Straight below: the table's 4, no Lambertian cosine; at 45 degrees halfway to 2.
  CHECK(irradiance(spot, {0.f, 0.f, 0.f}, n, 10) == Approx(4.0));
  const double d2 = 2.0;
  CHECK(irradiance(spot, {1.f, 0.f, 0.f}, n, 10) == Approx(3.0 / d2 * std::sqrt(0.5)).epsilon(1e-5));
  // A second dimension in the azimuth from c0: C = 0 bright, C = 180 degrees dark.
  spot.distribution = IntensityDistribution({1.f, 1.f, 1.f, 0.f, 0.f, 0.f}, 3, 2);
  spot.c0 = Vec3f{1.f, 0.f, 0.f};
  CHECK(irradiance(spot, {0.5f, 0.f, 0.f}, n, 10) > 0.5);
  CHECK(irradiance(spot, {-0.5f, 0.f, 0.f}, n, 10) == Approx(0.0).margin(0.05));
  CHECK_THROWS(IntensityDistribution({1.f}, 1));
  // A NaN direction (from a ray gone wrong) gets no light, rather than NaN.
  const PhotometricFrame frame = photometric_frame({0.f, -1.f, 0.f}, {1.f, 0.f, 0.f});
  CHECK(spot.distribution(frame, std::nanf(""), {0.f, -1.f, 0.f}) == 0.f);
  CHECK(spot.distribution(frame, 1.f, {std::nanf(""), 0.f, 0.f}) == 0.f);
  spot.quantity = IntensityQuantity::power;
  CHECK_THROWS_WITH(validate(spot), Catch::Contains("with 'intensityDistribution'"));

  QuadLight quad;
  quad.position = {-0.05f, 1.f, -0.05f};
  quad.edge1 = {0.1f, 0.f, 0.f};
  quad.edge2 = {0.f, 0.f, 0.1f};
  quad.quantity = IntensityQuantity::scale;
  quad.distribution = IntensityDistribution({1.f, 1.f, 1.f}, 3);
  check_sample_eval(quad, {0.2f, 0.f, 0.1f}, n);
  // A uniform table makes the small quad an isotropic point of intensity 1 (both sides).
  CHECK(irradiance(quad, {0.f, 0.f, 0.f}, n, 20'000) == Approx(1.0).epsilon(5e-3));
  CHECK(irradiance(quad, {0.f, 2.f, 0.f}, {0.f, -1.f, 0.f}, 20'000) == Approx(1.0).epsilon(5e-3));
}

TEST_CASE("lights placed by an instance's transform move with it", "[light]") {
  const Affine3f xfm = Affine3f::translate({2.f, 0.f, 0.f}) * Affine3f{{0, 0, -1}, {0, 1, 0}, {1, 0, 0}, {0, 0, 0}};
  SpotLight spot;  // at the origin, shining along +x; the transform turns +x to -z, then moves it
  spot.direction = {1.f, 0.f, 0.f};
  spot.opening_angle = 90.f;
  const Light placed = transformed(spot, xfm);
  const auto& s = std::get<SpotLight>(placed);
  CHECK(s.position.x == Approx(2.f));
  CHECK(s.direction.z == Approx(-1.f));
  const Vec3f in_front{2.f, 0.f, -3.f}, behind{2.f, 0.f, 3.f};
  CHECK(irradiance(placed, in_front, {0.f, 0.f, 1.f}, 10) > 0.0);
  CHECK(irradiance(placed, behind, {0.f, 0.f, -1.f}, 10) == 0.0);
  // A scaled quad given as intensity keeps the radiance of its own size (as OSPRay).
  QuadLight q;
  q.quantity = IntensityQuantity::intensity;
  q.intensity = 5.f;
  CHECK(emitted(transformed(q, Affine3f::scale(3.f))).x == Approx(emitted(q).x));
}

TEST_CASE("the Hosek-Wilkie sky is positive, continuous and bright around the sun", "[light][sky]") {
  for (float turbidity : {1.f, 2.5f, 10.f})
    for (float elevation : {0.01f, 0.3f, 1.2f}) {
      INFO("turbidity " << turbidity << ", elevation " << elevation);
      const HosekWilkieSky sky(turbidity, 0.3f, elevation);
      const float sun_theta = 0.5f * static_cast<float>(pi) - elevation;
      Vec3f previous = sky.radiance(0.f, sun_theta);
      for (int i = 1; i <= 200; ++i) {
        const float theta = 0.5f * static_cast<float>(pi) * 0.999f * static_cast<float>(i) / 200.f;
        const Vec3f l = sky.radiance(theta, std::abs(theta - sun_theta));  // the sun's vertical plane
        for (int c = 0; c < 3; ++c) {
          REQUIRE(l[c] > 0.f);
          REQUIRE(std::abs(l[c] - previous[c]) < 0.25f * std::max(l[c], previous[c]));  // no jumps
        }
        previous = l;
      }
      // Towards the sun brighter than the opposite sky at the same height.
      const float theta = std::max(sun_theta, 0.3f);
      CHECK(sky.radiance(theta, std::abs(theta - sun_theta)).y > sky.radiance(theta, theta + sun_theta).y);
    }
  // A clear sky is blue overhead: more blue than red at the zenith with a high sun.
  const Vec3f zenith = HosekWilkieSky(2.f, 0.1f, 1.2f).radiance(0.f, 0.5f * static_cast<float>(pi) - 1.2f);
  CHECK(zenith.z > zenith.x);
}

TEST_CASE("sunSky is a sky map fading out below the horizon and a sun of 0.53 degrees", "[light][sky]") {
  SunSky params;
  params.up = {0.f, 1.f, 0.f};
  params.direction = {0.f, -0.5f, -1.f};  // the sun behind, at 26.6 degrees
  params.horizon_extension = 0.f;
  const auto [sky, sun] = sun_sky_lights(params);
  CHECK(sun.angular_diameter == 0.53f);
  CHECK(normalize(sun.direction).y == Approx(-0.5f / std::sqrt(1.25f)));
  CHECK(sky.lookup({0.f, 1.f, 0.f}).y > 0.f);
  CHECK(sky.lookup({0.f, -0.5f, 0.866f}).y == 0.f);  // below the horizon
  // Towards the sun the sky is brighter than opposite it.
  CHECK(sky.lookup(normalize(Vec3f{0.f, 0.6f, 1.f})).y > sky.lookup(normalize(Vec3f{0.f, 0.6f, -1.f})).y);
  // The sun outshines the sky: more irradiance on a surface facing it than from the sky.
  const Vec3f n = -normalize(sun.direction);
  CHECK(irradiance(sun, {0.f, 0.f, 0.f}, n, 1000) > irradiance(sky, {0.f, 0.f, 0.f}, n, 20'000));
  // A sun below the horizon stays on it, at its azimuth.
  params.direction = {0.f, 0.3f, -1.f};
  const auto [sky2, sun2] = sun_sky_lights(params);
  CHECK(normalize(sun2.direction).y == Approx(0.f).margin(1e-6));
  CHECK(normalize(sun2.direction).z == Approx(-1.f));
  params.turbidity = 0.5f;
  CHECK_THROWS_WITH(sun_sky_lights(params), Catch::Contains("turbidity"));
}

TEST_CASE("a sunSky's sun at the nadir sits on the horizon where OSPRay 3.1 puts it", "[light][sky]") {
  // A sun at the zenith or nadir has no azimuth of its own; OSPRay's runtime puts a nadir
  // sun of up (0,-1,0) on the horizon at +z, of up (0,0,1) at -x (the sun disc measured
  // in its path tracer's image), and the sky's glow with it.
  SunSky params;
  params.up = {0.f, -1.f, 0.f};
  params.direction = {0.f, -1.f, 0.f};  // travelling down: towards the sky's nadir
  const auto [sky, sun] = sun_sky_lights(params);
  CHECK(normalize(sun.direction).z == Approx(-1.f));  // it shines from +z
  const Vec3f above_horizon{0.f, -0.05f, 1.f};
  CHECK(sky.lookup(normalize(above_horizon)).x > 2.f * sky.lookup(normalize(Vec3f{0.f, -0.05f, -1.f})).x);
  params.up = {0.f, 0.f, 1.f};
  params.direction = {0.f, 0.f, 1.f};
  CHECK(normalize(sun_sky_lights(params).second.direction).x == Approx(1.f));  // it shines from -x
}
