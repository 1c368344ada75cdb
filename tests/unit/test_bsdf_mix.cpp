// The mix material (OSPRay's `mix`): two BSDFs weighted by 1 - factor and factor, a
// factor map read at the surface's texture coordinates, emission by the plain factor, and
// the errors that name a bad mix.
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "sciray/math/random.hpp"
#include "sciray/render/bsdf.hpp"
#include "support/bsdf_checks.hpp"

using namespace sciray;
using namespace sciray_test;

namespace {

ObjMaterial lambert(const Vec3f& kd) {
  ObjMaterial m;
  m.kd = kd;
  return m;
}

MixMaterial mix(Material a, Material b, float factor) {
  MixMaterial m;
  m.material1 = mix_part(std::move(a));
  m.material2 = mix_part(std::move(b));
  m.factor = factor;
  return m;
}

/// A 2×2 checkerboard of nearest texels: 1 where u and v fall in different halves, else 0.
TextureMap checkerboard() {
  TextureMap map;
  map.texture = std::make_shared<const Texture2D>(
      2, 2, std::vector<Vec3f>{splat(0.f), splat(1.f), splat(1.f), splat(0.f)}, true);
  return map;
}

ShadingPoint at_uv(float u, float v) {
  ShadingPoint sp = flat();
  sp.uv = {u, v};
  return sp;
}

}  // namespace

TEST_CASE("A mix of two Lambertian obj materials is the obj material of the mixed kd", "[bsdf][mix]") {
  // Analytic: (1 - f)·kd1/π + f·kd2/π is the Lambertian of kd = (1 - f)·kd1 + f·kd2, so
  // every sample weighs exactly that kd and eval agrees with that obj's everywhere.
  const Vec3f kd1{0.9f, 0.2f, 0.1f}, kd2{0.1f, 0.5f, 0.8f};
  for (const float f : {0.f, 0.3f, 0.5f, 1.f}) {
    const Material mixed = mix(lambert(kd1), lambert(kd2), f);
    const Vec3f kd = kd1 * (1.f - f) + kd2 * f;
    const Material expected = lambert(kd);
    Pcg32 rng(3, 1);
    for (const float angle : {0.f, 40.f, 80.f}) {
      const Vec3f wo = at_angle(angle);
      for (int i = 0; i < 200; ++i) {
        INFO("factor " << f << " at " << angle << " degrees");
        const auto s = sample(mixed, flat(), wo, rng.next_float(), rng.next_float(), rng.next_float());
        REQUIRE(s);
        CHECK_FALSE(s->delta);
        for (int c = 0; c < 3; ++c) CHECK(s->weight[c] == Approx(kd[c]).epsilon(1e-5));
        const BsdfValue got = eval(mixed, flat(), wo, s->wi), want = eval(expected, flat(), wo, s->wi);
        CHECK(got.pdf == Approx(want.pdf).epsilon(1e-5));
        for (int c = 0; c < 3; ++c) CHECK(got.f_cos[c] == Approx(want.f_cos[c]).epsilon(1e-5));
      }
    }
    const Vec3f a = albedo(mixed, flat());
    for (int c = 0; c < 3; ++c) CHECK(a[c] == Approx(kd[c]).epsilon(1e-6));
  }
}

TEST_CASE("A nested mix weighs its parts by the products of the factors", "[bsdf][mix]") {
  const Vec3f red{1.f, 0.f, 0.f}, green{0.f, 1.f, 0.f}, blue{0.f, 0.f, 1.f};
  const Material nested = mix(mix(lambert(red), lambert(green), 0.5f), lambert(blue), 0.5f);
  const Vec3f wi = at_angle(30.f, 2.f);
  const BsdfValue v = eval(nested, flat(), at_angle(20.f), wi);
  const float lambert_cos = wi.z / pi;  // Lambertian f·cos for kd 1
  CHECK(v.f_cos.x == Approx(0.25f * lambert_cos));
  CHECK(v.f_cos.y == Approx(0.25f * lambert_cos));
  CHECK(v.f_cos.z == Approx(0.5f * lambert_cos));
  CHECK(v.pdf == Approx(lambert_cos));
}

TEST_CASE("A checkerboard map_factor alternates the mix's parts", "[bsdf][mix]") {
  MixMaterial checker = mix(lambert({1.f, 0.f, 0.f}), lambert({0.f, 0.f, 1.f}), 1.f);
  checker.map_factor = checkerboard();
  const Vec3f wo = at_angle(10.f), wi = at_angle(35.f, 1.f);
  const float lambert_cos = wi.z / pi;
  // Cells (u < ½, v < ½) and (u ≥ ½, v ≥ ½) hold 0 (material1, red); the others 1 (blue).
  const struct {
    float u, v;
    bool blue;
  } cells[] = {{0.25f, 0.25f, false}, {0.75f, 0.25f, true}, {0.25f, 0.75f, true}, {0.75f, 0.75f, false},
               {1.25f, 0.25f, false}, {1.75f, 0.25f, true}};  // the map tiles
  for (const auto& cell : cells) {
    INFO("uv (" << cell.u << ", " << cell.v << ")");
    const Vec3f f = eval(checker, at_uv(cell.u, cell.v), wo, wi).f_cos;
    CHECK(f.x == Approx(cell.blue ? 0.f : lambert_cos).margin(1e-6));
    CHECK(f.z == Approx(cell.blue ? lambert_cos : 0.f).margin(1e-6));
  }
  // The map multiplies factor: 0.4 in the cells of 1.
  checker.factor = 0.4f;
  const Vec3f f = eval(checker, at_uv(0.75f, 0.25f), wo, wi).f_cos;
  CHECK(f.x == Approx(0.6f * lambert_cos));
  CHECK(f.z == Approx(0.4f * lambert_cos));
}

TEST_CASE("A mix with a delta part samples what eval reports and loses no energy", "[bsdf][mix]") {
  // thinGlass of attenuationColor 1 reflects or transmits all it receives, and so does a
  // white Lambertian: any mix of the two keeps the furnace at 1.
  const Material obj_glass = mix(lambert(splat(1.f)), ThinGlassMaterial{}, 0.4f);
  PrincipledMaterial principled;
  principled.base_color = {0.0177f, 0.189f, 0.59f};
  CarPaintMaterial paint;
  paint.base_color = splat(0.5f), paint.flake_color = splat(0.8f), paint.flake_density = 1.f, paint.flake_scale = 1000.f;
  const Material layered = mix(paint, principled, 0.7f);
  for (const float angle : {0.f, 45.f, 80.f}) {
    INFO(angle << " degrees");
    const Estimate e = sampled_albedo(obj_glass, flat(), at_angle(angle), 20000, 9);
    for (int c = 0; c < 3; ++c) CHECK(e.mean[c] == Approx(1.).margin(3. * e.standard_error[c] + 1e-4));
  }
  Pcg32 rng(4, 4);
  int delta = 0, non_delta = 0;
  for (const Material* m : {&obj_glass, &layered})
    for (const float angle : {0.f, 45.f, 80.f})
      for (int i = 0; i < 1000; ++i) {
        const Vec3f wo = at_angle(angle);
        ShadingPoint sp = flat();
        sp.p = {rng.next_float(), rng.next_float(), 0.f};  // over carPaint's flakes
        const auto s = sample(*m, sp, wo, rng.next_float(), rng.next_float(), rng.next_float());
        if (!s) continue;
        if (s->delta) {
          ++delta;
          continue;
        }
        ++non_delta;
        const BsdfValue v = eval(*m, sp, wo, s->wi);
        REQUIRE(v.pdf == Approx(s->pdf).epsilon(1e-4));
        for (int c = 0; c < 3; ++c) REQUIRE(v.f_cos[c] / v.pdf == Approx(s->weight[c]).epsilon(1e-3).margin(1e-6));
      }
  CHECK(delta > 500);
  CHECK(non_delta > 2000);
}

TEST_CASE("A mix emits its parts' emission weighted by the plain factor", "[bsdf][mix]") {
  // As OSPRay's mix, whose emission is fixed at commit from `factor`: the map plays no part.
  LuminousMaterial light;
  light.intensity = 2.f;
  MixMaterial glowing = mix(lambert(splat(0.5f)), light, 0.25f);
  glowing.map_factor = checkerboard();
  for (const float u : {0.25f, 0.75f}) {
    const Vec3f e = emitted(glowing, at_uv(u, 0.25f), at_angle(0.f));
    for (int c = 0; c < 3; ++c) CHECK(e[c] == Approx(0.5f));
  }
}

TEST_CASE("A bad mix is refused by name", "[bsdf][mix][errors]") {
  const auto message = [](const Material& m) {
    try {
      validate(m);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  using Catch::Matchers::Contains;
  CHECK_THAT(message(mix(ObjMaterial{}, ObjMaterial{}, 1.5f)), Contains("'factor' must be in [0, 1]"));
  CHECK_THAT(message(mix(ObjMaterial{}, ObjMaterial{}, std::numeric_limits<float>::quiet_NaN())),
             Contains("'factor' must be in [0, 1]"));
  MixMaterial half = mix(ObjMaterial{}, ObjMaterial{}, 0.5f);
  half.material2.reset();
  CHECK_THAT(message(half), Contains("'material2' (the material it mixes) is missing"));
  ObjMaterial bad;
  bad.d = 2.f;
  CHECK_THAT(message(mix(ObjMaterial{}, bad, 0.5f)), Contains("'material2': obj material: parameter 'd'"));
  CHECK(message(mix(ObjMaterial{}, ThinGlassMaterial{}, 0.f)).empty());
}
