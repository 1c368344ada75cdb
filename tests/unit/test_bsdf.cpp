// BSDFs: white furnace, energy conservation, sample/eval agreement, pdf normalisation,
// reciprocity, dielectric Fresnel and total internal reflection, no NaN anywhere.
#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "sciray/math/random.hpp"
#include "sciray/render/bsdf.hpp"
#include "support/bsdf_checks.hpp"

using namespace sciray;
using namespace sciray_test;

namespace {

constexpr float grazing_angles[] = {0.f, 30.f, 60.f, 75.f, 85.f};

PrincipledMaterial principled(float roughness) {
  PrincipledMaterial p;
  p.base_color = {1.f, 1.f, 1.f};
  p.roughness = roughness;
  p.ior = 1.5f;  // a specular interface (OSPRay's default, 1, has none)
  return p;
}

struct NamedMaterial {
  std::string name;
  Material material;
  bool entering = true;
};

/// Every material type with parameter sets at the corners of their ranges.
std::vector<NamedMaterial> material_corners() {
  std::vector<NamedMaterial> all;
  const auto add = [&](std::string name, Material m, bool entering = true) {
    all.push_back({std::move(name), std::move(m), entering});
  };
  add("obj kd 1", ObjMaterial{{1.f, 1.f, 1.f}, {0.f, 0.f, 0.f}, 10.f, 1.f, {0.f, 0.f, 0.f}});
  add("obj kd+ks", ObjMaterial{{0.5f, 0.5f, 0.5f}, {0.5f, 0.5f, 0.5f}, 20.f, 1.f, {0.f, 0.f, 0.f}});
  add("obj ks 1 ns 0", ObjMaterial{{0.f, 0.f, 0.f}, {1.f, 1.f, 1.f}, 0.f, 1.f, {0.f, 0.f, 0.f}});
  add("obj ks 1 ns 1000", ObjMaterial{{0.f, 0.f, 0.f}, {1.f, 1.f, 1.f}, 1000.f, 1.f, {0.f, 0.f, 0.f}});
  add("obj everything 1", ObjMaterial{{1.f, 1.f, 1.f}, {1.f, 1.f, 1.f}, 5.f, 0.5f, {1.f, 1.f, 1.f}});
  for (const float r : {0.f, 0.05f, 0.5f, 1.f}) {
    const std::string at = " roughness " + std::to_string(r).substr(0, 4);
    add("principled dielectric" + at, principled(r));
    auto metal = principled(r);
    metal.metallic = 1.f;
    add("principled metal" + at, metal);
    auto glass = principled(r);
    glass.transmission = 1.f;
    add("principled transmission" + at, glass);
    add("principled transmission from inside" + at, glass, false);
    glass.thin = true;
    add("principled thin transmission" + at, glass);
    auto coated = principled(r);
    coated.coat = 1.f;
    coated.coat_roughness = r;
    add("principled coat" + at, coated);
    coated.metallic = 1.f;
    add("principled coat over metal" + at, coated);
    auto cloth = principled(r);
    cloth.sheen = 1.f;
    cloth.sheen_roughness = r;
    add("principled sheen" + at, cloth);
    cloth.metallic = 1.f;
    add("principled sheen over metal" + at, cloth);
    auto mix = principled(r);
    mix.metallic = 0.5f, mix.transmission = 0.5f, mix.coat = 1.f, mix.sheen = 1.f, mix.opacity = 0.7f;
    add("principled everything" + at, mix);
    add("metal" + at, MetalMaterial{{1.5f, 0.98f, 0.6f}, {7.6f, 6.6f, 5.4f}, r});
    add("metal k 0" + at, MetalMaterial{{0.2f, 1.f, 3.f}, {0.f, 0.f, 0.f}, r});
    add("alloy" + at, AlloyMaterial{{1.f, 1.f, 1.f}, {1.f, 1.f, 1.f}, r});
  }
  add("glass", GlassMaterial{});
  add("glass from inside", GlassMaterial{}, false);
  add("glass eta 1", GlassMaterial{1.f, {1.f, 1.f, 1.f}, 1.f});
  add("thinGlass", ThinGlassMaterial{});
  add("thinGlass absorbing", ThinGlassMaterial{1.5f, {0.2f, 0.5f, 0.9f}, 0.5f, 1.f});
  add("luminous transparent", LuminousMaterial{{1.f, 1.f, 1.f}, 3.f, 0.6f});
  // OSPRay's velvet adds its two lobes unnormalised: white only where their colours sum to 1.
  add("velvet", VelvetMaterial{{0.5f, 0.5f, 0.5f}, 0.f, {0.5f, 0.5f, 0.5f}, 0.f});
  add("velvet backscattering", VelvetMaterial{{0.7f, 0.7f, 0.7f}, 3.f, {0.3f, 0.3f, 0.3f}, 20.f});
  for (const float amount : {0.f, 0.3f, 1.f})
    for (const float spread : {0.f, 0.5f, 1.f})
      add("metallicPaint amount " + std::to_string(amount).substr(0, 3) + " spread " + std::to_string(spread).substr(0, 3),
          MetallicPaintMaterial{{1.f, 1.f, 1.f}, amount, {1.f, 1.f, 1.f}, spread, 1.5f});
  for (const float roughness : {0.f, 0.5f, 1.f}) {
    const std::string at = " roughness " + std::to_string(roughness).substr(0, 3);
    CarPaintMaterial paint;
    paint.base_color = {1.f, 1.f, 1.f}, paint.roughness = roughness, paint.coat_roughness = roughness;
    add("carPaint" + at, paint);
    paint.flake_density = 1.f, paint.flake_roughness = roughness, paint.flake_color = Vec3f{1.f, 1.f, 1.f};
    add("carPaint all flakes" + at, paint);
    paint.flake_density = 0.5f, paint.flake_color.reset(), paint.flipflop_falloff = 0.f;
    add("carPaint aluminium flakes, flipflop" + at, paint);
    add("plastic" + at, PlasticMaterial{{1.f, 1.f, 1.f}, 1.4f, roughness});
    auto backlit = principled(roughness);
    backlit.thin = true, backlit.backlight = 1.f, backlit.transmission = 0.3f;
    add("principled backlight" + at, backlit);
  }
  return all;
}

}  // namespace

TEST_CASE("White furnace: white Lambertian materials reflect exactly what they receive", "[bsdf]") {
  PrincipledMaterial diffuse_only = principled(0.f);
  diffuse_only.specular = 0.f;  // no interface over the diffuse lobe
  for (const Material& m : {Material{ObjMaterial{{1.f, 1.f, 1.f}, {0.f, 0.f, 0.f}, 10.f, 1.f, {0.f, 0.f, 0.f}}},
                            Material{diffuse_only}}) {
    for (const float angle : {0.f, 30.f, 60.f, 80.f, 89.f}) {
      INFO(type_name(m) << " at " << angle << " degrees");
      const Vec3f wo = at_angle(angle);
      const Estimate sampled = sampled_albedo(m, flat(), wo, 20000, 1);
      // Independently: integrate eval by cosine-weighted hemisphere sampling.
      Pcg32 rng(2, 3);
      double integral = 0.;
      constexpr int n = 20000;
      for (int i = 0; i < n; ++i) {
        const float r = std::sqrt(rng.next_float()), phi = 2.f * pi * rng.next_float();
        const Vec3f wi{r * std::cos(phi), r * std::sin(phi), std::sqrt(std::max(0.f, 1.f - r * r))};
        if (wi.z <= 0.f) continue;
        integral += eval(m, flat(), wo, wi).f_cos.x / (wi.z / pi);
      }
      for (int c = 0; c < 3; ++c) CHECK(sampled.mean[c] == Approx(1.).epsilon(1e-3));
      CHECK(integral / n == Approx(1.).epsilon(1e-3));
    }
  }
}

TEST_CASE("No material reflects and transmits more than it receives", "[bsdf]") {
  double worst_excess = -1.;
  std::string worst;
  std::uint64_t seed = 10;
  for (const NamedMaterial& nm : material_corners()) {
    for (const float angle : grazing_angles) {
      const Estimate e = sampled_albedo(nm.material, flat(nm.entering), at_angle(angle), 4000, ++seed);
      for (int c = 0; c < 3; ++c) {
        INFO(nm.name << " at " << angle << " degrees, channel " << c << ": albedo " << e.mean[c] << " +- "
                     << e.standard_error[c]);
        CHECK(e.mean[c] <= 1. + 3. * e.standard_error[c] + 1e-5);
        if (e.mean[c] - 1. > worst_excess) {
          worst_excess = e.mean[c] - 1.;
          worst = nm.name + " at " + std::to_string(angle) + " degrees: " + std::to_string(e.mean[c]) + " +- " +
                  std::to_string(e.standard_error[c]);
        }
      }
    }
  }
  WARN("highest albedo: " << worst);
}

TEST_CASE("sample() reports the pdf and weight eval() gives for its direction", "[bsdf]") {
  PrincipledMaterial layered = principled(0.5f);
  layered.coat = 1.f, layered.coat_roughness = 0.f, layered.sheen = 0.5f, layered.metallic = 0.3f;
  layered.transmission = 0.4f;
  PrincipledMaterial rough_glass = principled(0.3f);
  rough_glass.transmission = 1.f;
  const std::vector<NamedMaterial> materials = {
      {"obj phong + cut-out", ObjMaterial{{0.4f, 0.2f, 0.1f}, {0.3f, 0.5f, 0.2f}, 30.f, 0.7f, {0.2f, 0.2f, 0.2f}}},
      {"principled layered", layered},
      {"principled rough glass", rough_glass},
      {"principled rough glass from inside", rough_glass, false},
      {"metal", MetalMaterial{{0.2f, 0.9f, 1.1f}, {3.f, 2.5f, 2.f}, 0.4f}},
      {"alloy", AlloyMaterial{{0.9f, 0.6f, 0.3f}, {1.f, 1.f, 1.f}, 0.05f}}};
  ShadingPoint tilted = flat();  // an interpolated normal 20 degrees off the geometric one
  tilted.n = at_angle(20.f, 2.f);
  for (const NamedMaterial& nm : materials) {
    Pcg32 rng(5, 5);
    int non_delta = 0;
    for (ShadingPoint sp : {flat(), tilted})
      for (const float angle : grazing_angles) {
        sp.entering = nm.entering;
        const Vec3f wo = at_angle(angle);
        for (int i = 0; i < 500; ++i) {
          const auto s = sample(nm.material, sp, wo, rng.next_float(), rng.next_float(), rng.next_float());
          if (!s || s->delta) continue;
          ++non_delta;
          // Where the shading normal sends wi through the geometric surface the other way,
          // wi meets the surface again: eval() takes no light from there, and the sample
          // is weighed on the shading normal's side.
          const BsdfValue v = bsdf_detail::eval_towards(nm.material, sp, wo, s->wi, s->transmitted);
          INFO(nm.name << " at " << angle << " degrees, shading normal z " << sp.n.z);
          if ((dot(s->wi, sp.ng) < 0.f) == s->transmitted) REQUIRE(eval(nm.material, sp, wo, s->wi).pdf == v.pdf);
          else REQUIRE(eval(nm.material, sp, wo, s->wi).pdf == 0.f);
          REQUIRE(v.pdf == Approx(s->pdf).epsilon(1e-3));
          for (int c = 0; c < 3; ++c) REQUIRE(v.f_cos[c] / v.pdf == Approx(s->weight[c]).epsilon(1e-3).margin(1e-6));
        }
      }
    INFO(nm.name);
    CHECK(non_delta > 1000);
  }
}

TEST_CASE("seen from below its shading normal, only the lobes that ignore wo scatter, about that normal", "[bsdf]") {
  // A shading normal tilted 60 degrees, seen from 75 degrees the other side of the
  // geometric one: OSPRay's Lambert ignores wo and keeps the normal (its runtime shows a
  // tilted Lambertian quad alike from every side), and its other BSDFs give nothing.
  ShadingPoint sp = flat();
  sp.n = at_angle(60.f, 0.f);
  const Vec3f wo = at_angle(75.f, pi);
  REQUIRE(dot(sp.n, wo) < 0.f);
  const ObjMaterial obj{{0.6f, 0.6f, 0.6f}, {0.3f, 0.3f, 0.3f}, 20.f, 1.f, {0.f, 0.f, 0.f}};
  // Light along the geometric normal meets the shading normal at 60 degrees; the Phong
  // lobe adds nothing, and Lambert's is the only pdf.
  const BsdfValue up = eval(obj, sp, wo, sp.ng);
  CHECK(up.f_cos.x == Approx(0.6f / pi * 0.5f).epsilon(1e-5));
  CHECK(up.pdf == Approx(0.5f / pi).epsilon(1e-5));
  // Samples are cosine-weighted about the shading normal, weight kd; the share below the
  // geometric surface, (1 - cos 60) / 2, are reflections that meet the surface again.
  Pcg32 rng(8, 1);
  int below = 0;
  const int n = 20000;
  for (int i = 0; i < n; ++i) {
    const auto s = sample(obj, sp, wo, rng.next_float(), rng.next_float(), rng.next_float());
    REQUIRE(s);
    REQUIRE_FALSE(s->transmitted);
    REQUIRE(s->weight.x == Approx(0.6f).epsilon(1e-4));
    below += dot(s->wi, sp.ng) < 0.f;
  }
  CHECK(static_cast<float>(below) / n == Approx(0.25f).margin(0.01f));
  // A diffuse base under principled's specular layer, whose Fresnel needs wo above the
  // normal, scatters nothing (OSPRay's dielectric layer neither).
  CHECK_FALSE(sample(principled(0.f), sp, wo, 0.5f, 0.5f, 0.5f));
  CHECK(eval(principled(0.f), sp, wo, sp.ng).pdf == 0.f);
}

TEST_CASE("eval's pdf integrates over the sphere to the probability of a non-delta sample", "[bsdf]") {
  PrincipledMaterial plastic = principled(0.5f);
  PrincipledMaterial rough_glass = principled(0.7f);
  rough_glass.transmission = 1.f;
  PrincipledMaterial cloth = principled(0.6f);
  cloth.sheen = 1.f, cloth.sheen_roughness = 0.5f, cloth.opacity = 0.6f;
  const std::vector<NamedMaterial> materials = {
      {"obj phong", ObjMaterial{{0.5f, 0.5f, 0.5f}, {0.5f, 0.5f, 0.5f}, 20.f, 1.f, {0.f, 0.f, 0.f}}},
      {"obj half cut out", ObjMaterial{{0.8f, 0.8f, 0.8f}, {0.f, 0.f, 0.f}, 20.f, 0.5f, {0.f, 0.f, 0.f}}},
      {"principled plastic", plastic},
      {"principled rough glass", rough_glass},
      {"principled rough glass from inside", rough_glass, false},
      {"principled sheen, cut out", cloth},
      {"metal", MetalMaterial{{1.5f, 0.98f, 0.6f}, {7.6f, 6.6f, 5.4f}, 0.6f}},
      {"alloy", AlloyMaterial{{0.9f, 0.9f, 0.9f}, {1.f, 1.f, 1.f}, 1.f}}};
  for (const NamedMaterial& nm : materials) {
    for (const float angle : {10.f, 60.f}) {
      const Vec3f wo = at_angle(angle);
      Pcg32 rng(11, 1);
      const double integral = sphere_integral(
          256, rng, [&](const Vec3f& wi) { return eval(nm.material, flat(nm.entering), wo, wi).pdf; });
      constexpr int n = 20000;
      int non_delta = 0;
      for (int i = 0; i < n; ++i) {
        const auto s = sample(nm.material, flat(nm.entering), wo, rng.next_float(), rng.next_float(), rng.next_float());
        non_delta += s && !s->delta;
      }
      INFO(nm.name << " at " << angle << " degrees: integral " << integral << ", non-delta fraction "
                   << double(non_delta) / n);
      CHECK(integral == Approx(double(non_delta) / n).epsilon(0.03));
      CHECK(integral > 0.3);
    }
  }
}

TEST_CASE("Reflection-only BRDFs are reciprocal", "[bsdf]") {
  const std::vector<NamedMaterial> materials = {
      {"obj", ObjMaterial{{0.3f, 0.2f, 0.1f}, {0.6f, 0.5f, 0.4f}, 30.f, 1.f, {0.f, 0.f, 0.f}}},
      {"metal rough", MetalMaterial{{1.5f, 0.98f, 0.6f}, {7.6f, 6.6f, 5.4f}, 0.7f}},
      {"metal glossy", MetalMaterial{{0.2f, 0.9f, 1.1f}, {3.f, 2.5f, 2.f}, 0.3f}},
      {"alloy", AlloyMaterial{{0.9f, 0.6f, 0.3f}, {1.f, 0.9f, 0.8f}, 0.5f}}};
  Pcg32 rng(3, 9);
  for (const NamedMaterial& nm : materials) {
    int compared = 0;
    for (int i = 0; i < 2000; ++i) {
      const Vec3f a = at_angle(85.f * rng.next_float(), 2.f * pi * rng.next_float());
      const Vec3f b = at_angle(85.f * rng.next_float(), 2.f * pi * rng.next_float());
      const Vec3f f_ab = eval(nm.material, flat(), a, b).f_cos / b.z;
      const Vec3f f_ba = eval(nm.material, flat(), b, a).f_cos / a.z;
      if (f_ab.x < 1e-4f) continue;
      ++compared;
      INFO(nm.name);
      for (int c = 0; c < 3; ++c) REQUIRE(f_ab[c] == Approx(f_ba[c]).epsilon(1e-3));
    }
    CHECK(compared > 500);
  }
}

TEST_CASE("Glass reflects by Fresnel and totally inside past the critical angle", "[bsdf]") {
  const Material glass = GlassMaterial{1.5f, {1.f, 1.f, 1.f}, 1.f};
  Pcg32 rng(21, 2);
  constexpr int n = 200000;
  int reflected = 0;
  double reflected_weight = 0., transmitted_weight = 0.;
  for (int i = 0; i < n; ++i) {
    const auto s = sample(glass, flat(), {0.f, 0.f, 1.f}, rng.next_float(), rng.next_float(), rng.next_float());
    REQUIRE(s);
    REQUIRE(s->delta);
    if (s->transmitted) {
      CHECK(s->wi.z == Approx(-1.f));
      transmitted_weight += s->weight.x;
    } else {
      ++reflected;
      CHECK(s->pdf == Approx(0.04f).epsilon(1e-4));
      reflected_weight += s->weight.x;
    }
  }
  const double frequency = double(reflected) / n;
  CHECK(std::abs(frequency - 0.04) < 4. * std::sqrt(0.04 * 0.96 / n));
  CHECK(reflected_weight / n == Approx(0.04).epsilon(0.03));
  CHECK((reflected_weight + transmitted_weight) / n == Approx(1.).epsilon(1e-6));

  // From inside, past asin(1/1.5) = 41.8 degrees, every sample reflects with weight 1.
  for (const float angle : {42.f, 60.f, 85.f, 89.9f}) {
    const Vec3f wo = at_angle(angle);
    for (int i = 0; i < 1000; ++i) {
      const auto s = sample(glass, flat(false), wo, rng.next_float(), rng.next_float(), rng.next_float());
      REQUIRE(s);
      CHECK_FALSE(s->transmitted);
      CHECK(s->weight.x == Approx(1.f));
      CHECK(s->wi.z == Approx(wo.z));
    }
  }
  // Just inside the critical angle from inside, light still gets out.
  int escaped = 0;
  for (int i = 0; i < 1000; ++i)
    escaped += sample(glass, flat(false), at_angle(40.f), rng.next_float(), 0.5f, 0.5f)->transmitted;
  CHECK(escaped > 0);
}

TEST_CASE("Smooth lobes are delta lobes with their exact reflectance", "[bsdf]") {
  const Vec3f normal{0.f, 0.f, 1.f};
  // Conductor at normal incidence: ((eta-1)² + k²) / ((eta+1)² + k²).
  const MetalMaterial metal{{1.5f, 0.98f, 0.6f}, {7.6f, 6.6f, 5.4f}, 0.f};
  const auto s = sample(metal, flat(), normal, 0.5f, 0.5f, 0.5f);
  REQUIRE(s);
  CHECK(s->delta);
  CHECK(s->wi.z == Approx(1.f));
  for (int c = 0; c < 3; ++c) {
    const float eta = metal.eta[c], k = metal.k[c];
    CHECK(s->weight[c] == Approx(((eta - 1) * (eta - 1) + k * k) / ((eta + 1) * (eta + 1) + k * k)).epsilon(1e-5));
  }
  CHECK(albedo(metal, flat()).x == Approx(s->weight.x).epsilon(1e-6));
  CHECK(eval(metal, flat(), normal, normal).f_cos == Vec3f{0.f, 0.f, 0.f});

  // A clear thin sheet: R = 2r/(1+r) with r = 0.04, the rest passes straight through.
  Pcg32 rng(4, 4);
  double reflected = 0., transmitted = 0.;
  constexpr int n = 20000;
  for (int i = 0; i < n; ++i) {
    const auto t = sample(ThinGlassMaterial{}, flat(), normal, rng.next_float(), 0.5f, 0.5f);
    REQUIRE(t);
    (t->transmitted ? transmitted : reflected) += t->weight.x;
    if (t->transmitted) CHECK(t->wi.z == -1.f);
  }
  CHECK((reflected + transmitted) / n == Approx(1.).epsilon(1e-6));
  CHECK(reflected / n == Approx(2. * 0.04 / 1.04).epsilon(0.05));

  // The geometry's colour absorbs as attenuationColor does (OSPRay's thinGlass multiplies
  // them): a red sheet under white attenuation passes what a white one under red does,
  // and less green and blue than red.
  ShadingPoint red = flat();
  red.color = {1.f, 0.3f, 0.3f};
  const auto coloured = bsdf_detail::make_bsdf(ThinGlassMaterial{}, red, normal);
  const auto attenuated = bsdf_detail::make_bsdf(ThinGlassMaterial{1.5f, {1.f, 0.3f, 0.3f}, 1.f, 1.f}, flat(), normal);
  const auto straight = [](const bsdf_detail::Bsdf& b) {
    for (int k = 0; k < b.count; ++k)
      if (b.lobes[k].kind == bsdf_detail::LobeKind::straight) return b.lobes[k].tint;
    return Vec3f{0.f, 0.f, 0.f};
  };
  for (int c = 0; c < 3; ++c) CHECK(straight(coloured)[c] == Approx(straight(attenuated)[c]).epsilon(1e-6));
  CHECK(straight(coloured).y < 0.5f * straight(coloured).x);
}

TEST_CASE("No NaN or Inf at grazing angles, below the surface or with degenerate parameters", "[bsdf]") {
  std::vector<NamedMaterial> materials = material_corners();
  PrincipledMaterial degenerate = principled(1.f);
  degenerate.ior = 1.f, degenerate.coat = 1.f, degenerate.coat_ior = 1.f, degenerate.coat_thickness = 0.f;
  degenerate.transmission = 1.f, degenerate.transmission_color = {0.f, 0.f, 0.f}, degenerate.sheen = 1.f;
  degenerate.sheen_roughness = 0.f;
  materials.push_back({"principled ior 1", degenerate});
  degenerate.thin = true, degenerate.thickness = 0.f, degenerate.roughness = 0.f;
  materials.push_back({"principled thin, thickness 0", degenerate});
  materials.push_back({"glass eta 1 inside", GlassMaterial{1.f, {0.f, 0.f, 0.f}, 1.f}, false});
  materials.push_back({"thinGlass black", ThinGlassMaterial{1.f, {0.f, 0.f, 0.f}, 1.f, 0.f}});
  materials.push_back({"metal eta 1", MetalMaterial{{1.f, 1.f, 1.f}, {0.f, 0.f, 0.f}, 1.f}});
  materials.push_back({"obj ns 1e6", ObjMaterial{{0.f, 0.f, 0.f}, {1.f, 1.f, 1.f}, 1e6f, 1.f, {0.f, 0.f, 0.f}}});

  // Geometry: flat, and a shading normal tilted 60 degrees away from the geometric one.
  ShadingPoint tilted = flat();
  tilted.n = at_angle(60.f, 0.f);
  const Vec3f grazing_wo[] = {at_angle(89.99f), at_angle(90.f), at_angle(89.f, 3.14159f), at_angle(95.f),
                              at_angle(180.f), at_angle(30.f)};
  const float corners[] = {0.f, 0.5f, 0x1.fffffep-1f};
  Pcg32 rng(8, 8);
  for (const NamedMaterial& nm : materials) {
    for (ShadingPoint sp : {flat(nm.entering), tilted}) {
      sp.entering = nm.entering;
      for (const Vec3f& wo : grazing_wo) {
        INFO(nm.name << ", wo " << wo.x << " " << wo.y << " " << wo.z << ", n " << sp.n.z);
        const bool above = dot(wo, sp.ng) > 0.f;
        for (const float u : corners)
          for (const float u1 : corners)
            for (const float u2 : corners) {
              const auto s = sample(nm.material, sp, wo, u, u1, u2);
              if (!s) continue;
              REQUIRE(above);
              REQUIRE(finite(s->weight));
              REQUIRE(s->weight.x >= 0.f);
              REQUIRE(std::isfinite(s->pdf));
              REQUIRE(s->pdf > 0.f);
              REQUIRE(length(s->wi) == Approx(1.f).epsilon(1e-4));
              // A delta lobe's side is the geometric surface's; another's the shading
              // normal's, on which eval_towards() finds the direction.
              if (s->delta) REQUIRE((dot(s->wi, sp.ng) < 0.f) == s->transmitted);
              else REQUIRE(bsdf_detail::eval_towards(nm.material, sp, wo, s->wi, s->transmitted).pdf > 0.f);
            }
        for (int i = 0; i < 50; ++i) {
          const Vec3f wi = at_angle(180.f * rng.next_float(), 2.f * pi * rng.next_float());
          const BsdfValue v = eval(nm.material, sp, wo, wi);
          REQUIRE(finite(v.f_cos));
          REQUIRE(std::isfinite(v.pdf));
          if (!above) REQUIRE(v.pdf == 0.f);
        }
        REQUIRE(finite(emitted(nm.material, sp, wo)));
        REQUIRE(finite(albedo(nm.material, sp)));
      }
    }
  }
}

TEST_CASE("Emission, albedo channel and interior media", "[bsdf]") {
  ShadingPoint sp = flat();
  sp.color = {0.5f, 1.f, 1.f};
  const Vec3f wo{0.f, 0.f, 1.f};
  CHECK(emitted(LuminousMaterial{{1.f, 0.5f, 0.25f}, 4.f, 0.f}, sp, wo) == Vec3f{2.f, 2.f, 1.f});
  PrincipledMaterial glowing;
  glowing.emissive_color = {0.f, 3.f, 0.f};
  CHECK(emitted(glowing, sp, wo) == Vec3f{0.f, 3.f, 0.f});
  CHECK(emitted(ObjMaterial{}, sp, wo) == Vec3f{0.f, 0.f, 0.f});
  // A black, opaque luminous surface only emits.
  CHECK_FALSE(sample(LuminousMaterial{}, sp, wo, 0.5f, 0.5f, 0.5f));

  CHECK(albedo(ObjMaterial{}, sp) == Vec3f{0.4f, 0.8f, 0.8f});
  CHECK(albedo(GlassMaterial{}, sp) == Vec3f{1.f, 1.f, 1.f});
  CHECK(albedo(AlloyMaterial{}, sp) == Vec3f{0.45f, 0.9f, 0.9f});

  const GlassMaterial glass{1.5f, {0.25f, 0.5f, 1.f}, 2.f};
  CHECK(has_medium(glass));
  const Vec3f t = medium_transmittance(glass, 4.f);  // two attenuation distances
  CHECK(t.x == Approx(0.0625f));
  CHECK(t.y == Approx(0.25f));
  CHECK(t.z == Approx(1.f));
  PrincipledMaterial solid;
  solid.transmission = 1.f, solid.transmission_color = {0.5f, 0.5f, 0.5f}, solid.transmission_depth = 0.5f;
  CHECK(has_medium(solid));
  CHECK(medium_transmittance(solid, 1.f).x == Approx(0.25f));
  solid.thin = true;
  CHECK_FALSE(has_medium(solid));
  CHECK(medium_transmittance(solid, 1.f) == Vec3f{1.f, 1.f, 1.f});
  CHECK_FALSE(has_medium(ThinGlassMaterial{}));
  CHECK(medium_transmittance(ObjMaterial{}, 10.f) == Vec3f{1.f, 1.f, 1.f});
}
