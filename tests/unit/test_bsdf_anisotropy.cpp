// Principled's anisotropic GGX (OSPRay's anisotropy and rotation): anisotropy 0 is the
// isotropic lobe, the lobe stretches along the tangent, rotation turns the tangent, the
// stretched distribution keeps Heitz's identities (unit projected area, visible normals
// projecting to cos θo) and its sampling pdf integrates to what sample() draws, and a
// white anisotropic conductor creates no energy. Out-of-range values are named.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <string>

#include "sciray/error.hpp"
#include "sciray/math/random.hpp"
#include "sciray/render/bsdf.hpp"
#include "support/bsdf_checks.hpp"

using namespace sciray;
using namespace sciray_test;

namespace {

/// A principled metal of white colour (Schlick Fresnel 1 everywhere).
PrincipledMaterial white_metal(float roughness, float anisotropy, float rotation = 0.f) {
  PrincipledMaterial m;
  m.base_color = {1.f, 1.f, 1.f};
  m.metallic = 1.f, m.roughness = roughness, m.anisotropy = anisotropy, m.rotation = rotation;
  return m;
}

/// A flat shading point whose tangent (dP/ds) is `tangent`.
ShadingPoint with_tangent(const Vec3f& tangent) {
  ShadingPoint sp = flat();
  sp.tangent = tangent;
  return sp;
}

/// ∫ eval(wi).pdf over the sphere.
double pdf_integral(const Material& m, const ShadingPoint& sp, const Vec3f& wo) {
  Pcg32 rng(5, 3);
  return sphere_integral(400, rng, [&](const Vec3f& wi) { return eval(m, sp, wo, wi).pdf; });
}

}  // namespace

TEST_CASE("Anisotropy 0 is the isotropic lobe whatever the tangent and rotation", "[bsdf][anisotropy]") {
  for (const float angle : {0.f, 40.f, 75.f}) {
    const Vec3f wo = at_angle(angle);
    PrincipledMaterial glass = white_metal(0.4f, 0.f, 0.3f);
    glass.metallic = 0.f, glass.transmission = 1.f, glass.ior = 1.5f;
    for (const PrincipledMaterial& m : {white_metal(0.4f, 0.f, 0.3f), glass}) {
      Pcg32 rng(3, 1);
      for (int k = 0; k < 200; ++k) {
        const Vec3f wi = normalize(Vec3f{2.f * rng.next_float() - 1.f, 2.f * rng.next_float() - 1.f,
                                         2.f * rng.next_float() - 1.f});
        const BsdfValue plain = eval(m, flat(), wo, wi), turned = eval(m, with_tangent({0.3f, 0.8f, 0.2f}), wo, wi);
        INFO("at " << angle << " degrees, wi " << wi.x << " " << wi.y << " " << wi.z);
        CHECK(turned.pdf == Approx(plain.pdf).epsilon(1e-4).margin(1e-6));
        CHECK(turned.f_cos.x == Approx(plain.f_cos.x).epsilon(1e-4).margin(1e-6));
      }
    }
  }
  // The stretched alpha of anisotropy 0 is the isotropic one, exactly.
  const bsdf_detail::GgxAlpha alpha = bsdf_detail::anisotropic_alpha(0.3f, 0.f);
  CHECK(alpha.x == 0.3f);
  CHECK(alpha.y == 0.3f);
}

TEST_CASE("Anisotropic GGX stretches along the tangent and rotation turns it", "[bsdf][anisotropy]") {
  // OSPRay's aspect sqrt(1 - 0.9 a): alpha / aspect along the tangent, alpha * aspect across.
  const bsdf_detail::GgxAlpha alpha = bsdf_detail::anisotropic_alpha(0.25f, 1.f);
  CHECK(alpha.x == Approx(0.25f / std::sqrt(0.1f)));
  CHECK(alpha.y == Approx(0.25f * std::sqrt(0.1f)));
  // Seen from the normal, the highlight is wider along the tangent (x) than across it (y).
  const Vec3f wo{0.f, 0.f, 1.f};
  const Material m = white_metal(0.5f, 0.8f);
  const auto lobe_at = [&](const ShadingPoint& sp, const Vec3f& off) { return eval(m, sp, wo, normalize(wo + off)).f_cos.x; };
  const ShadingPoint along_x = with_tangent({1.f, 0.f, 0.f});
  CHECK(lobe_at(along_x, {0.3f, 0.f, 0.f}) > 2.f * lobe_at(along_x, {0.f, 0.3f, 0.f}));
  // rotation 0.25 turns the tangent by a quarter turn: a tangent along y, unturned, is the same.
  const Material turned = white_metal(0.5f, 0.8f, 0.25f);
  const ShadingPoint along_y = with_tangent({0.f, 1.f, 0.f});
  for (const float angle : {20.f, 60.f}) {
    const Vec3f w = at_angle(angle, 0.3f);
    Pcg32 rng(9, 2);
    for (int k = 0; k < 100; ++k) {
      const Vec3f wi = normalize(Vec3f{2.f * rng.next_float() - 1.f, 2.f * rng.next_float() - 1.f, rng.next_float()});
      CHECK(eval(turned, along_x, w, wi).f_cos.x == Approx(eval(m, along_y, w, wi).f_cos.x).epsilon(1e-3).margin(1e-6));
    }
  }
}

TEST_CASE("Anisotropic GGX: eval's pdf integrates to the share of samples drawn", "[bsdf][anisotropy]") {
  // The stretched D must stay normalised against the stretched visible-normal sampler:
  // ∫ pdf over the sphere is the fraction of sample() calls that give a direction.
  PrincipledMaterial glass = white_metal(0.6f, 0.7f, 0.1f);
  glass.metallic = 0.f, glass.transmission = 1.f, glass.ior = 1.5f;
  for (const PrincipledMaterial& m : {white_metal(0.5f, 1.f, 0.1f), white_metal(0.7f, 0.5f), glass})
    for (const float angle : {10.f, 60.f}) {
      const Vec3f wo = at_angle(angle);
      const ShadingPoint sp = with_tangent({1.f, 0.5f, 0.f});
      const double integral = pdf_integral(m, sp, wo);
      Pcg32 rng(4, 4);
      constexpr int n = 40000;
      int drawn = 0;
      for (int i = 0; i < n; ++i) {
        const auto s = sample(m, sp, wo, rng.next_float(), rng.next_float(), rng.next_float());
        drawn += s && !s->delta;
      }
      INFO("transmission " << m.transmission << " at " << angle << " degrees: " << integral << " vs "
                           << double(drawn) / n);
      CHECK(integral == Approx(double(drawn) / n).epsilon(0.02));
    }
}

TEST_CASE("Anisotropic GGX: D projects to unit area and the visible normals to cos(theta_o)", "[bsdf][anisotropy]") {
  // Heitz 2014's identities, exact for any alpha: ∫ D(h) cos θh dω = 1 and, with Smith's
  // masking, ∫ G1(wo) max(0, wo·h) D(h) dω = cos θo for every wo, including azimuths
  // between the tangent and the bitangent. Integrated over the plane of slopes
  // (x, y) = (αx r cos φ, αy r sin φ), r = tan u, where dω = cos³θh dx dy, so
  // dω cos θh = cos⁴θh αx αy r dr dφ.
  using bsdf_detail::GgxAlpha;
  for (const GgxAlpha alpha : {bsdf_detail::anisotropic_alpha(0.25f, 1.f), bsdf_detail::anisotropic_alpha(0.6f, 0.5f),
                               GgxAlpha{0.8f, 0.15f}})
    for (const float angle : {0.f, 45.f, 80.f}) {
      const Vec3f wo = at_angle(angle, 0.7f);
      constexpr int n = 1500;
      double area = 0., visible = 0.;
      for (int i = 0; i < n; ++i) {
        const double u = (i + 0.5) * (pi / 2.) / n, r = std::tan(u), dr = (pi / 2.) / n / (std::cos(u) * std::cos(u));
        for (int j = 0; j < n; ++j) {
          const double phi = (j + 0.5) * 2. * pi / n;
          const double x = alpha.x * r * std::cos(phi), y = alpha.y * r * std::sin(phi);
          const Vec3f h = normalize(Vec3f{static_cast<float>(-x), static_cast<float>(-y), 1.f});
          const double cos4 = std::pow(double(h.z), 4.);
          const double d_omega_cos = alpha.x * alpha.y * r * dr * (2. * pi / n) * cos4;  // dω cos θh
          const double d = bsdf_detail::ggx_d(h, alpha);
          area += d * d_omega_cos;
          visible += bsdf_detail::ggx_g1(wo, alpha) * std::max(0.f, dot(wo, h)) * d * d_omega_cos / h.z;
        }
      }
      INFO("alpha " << alpha.x << " x " << alpha.y << " at " << angle << " degrees");
      CHECK(area == Approx(1.).epsilon(2e-3));
      CHECK(visible == Approx(wo.z).epsilon(3e-3));
    }
}

TEST_CASE("A white anisotropic GGX conductor reflects no more than it receives", "[bsdf][anisotropy]") {
  // F = 1: single scattering loses what the stretched microfacets shadow; OSPRay's
  // compensation, by the isotropic albedo of the lobe's roughness, gives back part of it
  // and must not create energy.
  for (const float roughness : {0.3f, 0.6f, 1.f})
    for (const float angle : {0.f, 45.f, 75.f}) {
      const Estimate e =
          sampled_albedo(white_metal(roughness, 1.f), with_tangent({1.f, 0.f, 0.f}), at_angle(angle), 40000, 6);
      INFO("roughness " << roughness << " at " << angle << " degrees: " << e.mean[0] << " +- " << e.standard_error[0]);
      CHECK(e.mean[0] <= 1. + 4. * e.standard_error[0]);
      CHECK(e.mean[0] > 0.5);
    }
}

TEST_CASE("Principled anisotropy and rotation out of [0, 1] are named", "[bsdf][anisotropy][errors]") {
  const auto message = [](const PrincipledMaterial& m) {
    try {
      validate(m);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  PrincipledMaterial m;
  m.anisotropy = 1.5f;
  CHECK(message(m) == "principled material: parameter 'anisotropy' must be in [0, 1]");
  m.anisotropy = 0.5f, m.rotation = -0.1f;
  CHECK(message(m) == "principled material: parameter 'rotation' must be in [0, 1]");
  m.rotation = 1.f;
  CHECK(message(m).empty());
}
