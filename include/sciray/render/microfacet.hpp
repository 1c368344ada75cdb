#pragma once
// The scalar building blocks of the path tracer's BSDFs (render/bsdf_lobes.hpp): Fresnel
// terms, a thin dielectric sheet, the GGX microfacet distribution with its directional
// albedo (for OSPRay's energy compensation), and the Charlie sheen distribution.
//
// References: Walter et al. 2007, "Microfacet Models for Refraction through Rough Surfaces"
// (GGX, rough refraction); Heitz 2014, "Understanding the Masking-Shadowing Function in
// Microfacet-Based BRDFs" (height-correlated Smith G2); Heitz 2018, "Sampling the GGX
// Distribution of Visible Normals"; Kulla & Conty 2017, "Revisiting Physically Based
// Shading at Imageworks" (energy compensation, average Fresnel); Conty Estevez & Kulla
// 2017, "Production Friendly Microfacet Sheen BRDF" (Charlie sheen, its Lambda fit);
// Schlick 1994 (Fresnel approximation); Pharr et al., PBRT 4th ed. (complex Fresnel).
#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <limits>
#include <numbers>
#include <optional>
#include <utility>

#include "sciray/math/vec.hpp"

namespace sciray::bsdf_detail {

inline constexpr float pi = std::numbers::pi_v<float>;
/// GGX alpha (roughness²) below which a lobe is a perfect mirror or refraction: the peak of
/// D, 1/(pi alpha²), would outgrow what float resolves around the half vector.
inline constexpr float min_alpha = 1e-4f;
/// Relative index of refraction closer to 1 than this refracts as a delta lobe: the rough
/// refraction lobe collapses onto -wo and its half vector becomes ill-defined.
inline constexpr float min_eta_contrast = 1e-3f;
/// Principled's transmissionDepth below which light is absorbed as over this depth (0 is
/// allowed: all but channels of transmissionColor 1 are absorbed at once, as OSPRay's).
inline constexpr float min_depth = 1e-5f;
/// Smallest cosine between the shading normal and wo; an interpolated normal that faces
/// away from wo is bent towards it until it sees wo at this angle.
inline constexpr float min_cos = 1e-4f;

inline float mean(const Vec3f& c) { return (c.x + c.y + c.z) * (1.f / 3.f); }
inline float max_component(const Vec3f& c) { return std::max(c.x, std::max(c.y, c.z)); }
inline Vec3f clamp01(const Vec3f& c) {
  return {std::clamp(c.x, 0.f, 1.f), std::clamp(c.y, 0.f, 1.f), std::clamp(c.z, 0.f, 1.f)};
}
inline Vec3f lerp(const Vec3f& a, const Vec3f& b, float t) { return a + (b - a) * t; }
inline Vec3f pow(const Vec3f& c, float e) { return {std::pow(c.x, e), std::pow(c.y, e), std::pow(c.z, e)}; }
inline bool finite_non_negative(const Vec3f& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z) && v.x >= 0.f && v.y >= 0.f && v.z >= 0.f;
}

/// An orthonormal frame around the shading normal; local z is the normal.
struct Frame {
  Vec3f t, b, n;
  Frame() = default;
  explicit Frame(const Vec3f& normal) : t(perpendicular(normal)), b(cross(normal, t)), n(normal) {}
  /// With local x along `tangent` made perpendicular to the normal (as OSPRay's shading
  /// frame takes dP/ds); any tangent where that is 0 or parallel to the normal.
  Frame(const Vec3f& normal, const Vec3f& tangent) : Frame(normal) {
    const Vec3f in_plane = tangent - normal * dot(tangent, normal);
    const float l = length(in_plane);
    if (!(l > 1e-6f * length(tangent)) || !std::isfinite(l)) return;
    t = in_plane / l, b = cross(normal, t);
  }
  /// This frame with its tangent turned about the normal by `radians` (towards b).
  Frame turned(float radians) const {
    Frame f = *this;
    f.t = t * std::cos(radians) + b * std::sin(radians);
    f.b = cross(n, f.t);
    return f;
  }
  Vec3f to_local(const Vec3f& v) const { return {dot(v, t), dot(v, b), dot(v, n)}; }
  Vec3f to_world(const Vec3f& v) const { return t * v.x + b * v.y + n * v.z; }
};

// ---- Fresnel --------------------------------------------------------------------------

/// Unpolarised reflectance of a smooth dielectric interface for light arriving at
/// cos_i > 0, eta = n(far side) / n(near side). cos_t receives the cosine of the refracted
/// direction; total internal reflection (and cos_i <= 0) gives 1.
inline float fresnel_dielectric(float cos_i, float eta, float& cos_t) {
  cos_t = 0.f;
  if (!(cos_i > 0.f)) return 1.f;
  cos_i = std::min(cos_i, 1.f);
  const float sin2_t = (1.f - cos_i * cos_i) / (eta * eta);
  if (sin2_t >= 1.f) return 1.f;
  cos_t = std::sqrt(1.f - sin2_t);
  const float r_s = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
  const float r_p = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
  return 0.5f * (r_s * r_s + r_p * r_p);
}
inline float fresnel_dielectric(float cos_i, float eta) {
  float cos_t;
  return fresnel_dielectric(cos_i, eta, cos_t);
}

/// Unpolarised reflectance of a conductor of complex index eta + i k (PBRT's FrComplex).
/// The denominators cannot vanish for cos_i > 0, eta > 0, k >= 0.
inline float fresnel_conductor(float cos_i, float eta, float k) {
  using Complex = std::complex<float>;
  cos_i = std::clamp(cos_i, 1e-6f, 1.f);
  const Complex n(eta, k);
  const Complex cos_t = std::sqrt(Complex(1.f) - (1.f - cos_i * cos_i) / (n * n));
  const Complex r_parallel = (n * cos_i - cos_t) / (n * cos_i + cos_t);
  const Complex r_perpendicular = (cos_i - n * cos_t) / (cos_i + n * cos_t);
  return 0.5f * (std::norm(r_parallel) + std::norm(r_perpendicular));
}

/// Schlick's curve from the reflectance at normal incidence to the one at grazing
/// incidence (OSPRay's alloy: colour to edge colour).
inline Vec3f fresnel_schlick(const Vec3f& normal, const Vec3f& grazing, float cos_i) {
  const float m = std::clamp(1.f - cos_i, 0.f, 1.f);
  return normal + (grazing - normal) * (m * m * m * m * m);
}

/// Cosine-weighted average of a dielectric interface's reflectance, 2 ∫ F(μ) μ dμ, for
/// eta = n(far side) / n(near side): Kulla & Conty's fit (entering, eta >= 1, and leaving).
inline float fresnel_dielectric_average(float eta) {
  if (eta >= 1.f) return (eta - 1.f) / (4.08567f + 1.00071f * eta);
  return 0.997118f + eta * (0.1014f + eta * (-0.965241f - 0.130607f * eta));
}

/// The reflectance a lobe carries, evaluated at the cosine between wo and the (micro)normal.
struct Fresnel {
  enum class Kind { one, dielectric, conductor, schlick };
  Kind kind = Kind::one;
  float eta = 1.f;    ///< dielectric: n(inside) / n(side of wo)
  float scale = 1.f;  ///< dielectric: the specular weight of its reflectance
  Vec3f c0{}, c1{};   ///< conductor: eta and k; schlick: reflectance at normal and grazing incidence

  Vec3f operator()(float cos_i) const {
    switch (kind) {
      case Kind::dielectric: return splat(scale * fresnel_dielectric(cos_i, eta));
      case Kind::conductor:
        return {fresnel_conductor(cos_i, c0.x, c1.x), fresnel_conductor(cos_i, c0.y, c1.y),
                fresnel_conductor(cos_i, c0.z, c1.z)};
      case Kind::schlick: return fresnel_schlick(c0, c1, cos_i);
      case Kind::one: break;
    }
    return splat(1.f);
  }
  /// Cosine-weighted average over incidence, 2 ∫ F(μ) μ dμ, where OSPRay compensates a
  /// microfacet lobe of this Fresnel for multiple scattering: Schlick's, r + (g - r)/21
  /// (2 ∫ (1 - μ)^5 μ dμ = 1/21); 0 (no compensation, as OSPRay's conductors of given
  /// eta and k) for the others.
  Vec3f average() const { return kind == Kind::schlick ? c0 + (c1 - c0) * (1.f / 21.f) : Vec3f{0.f, 0.f, 0.f}; }
  /// What a dielectric interface refracts: 1 - scale·F, and 0 past the critical angle.
  float transmit(float cos_i) const {
    const float f = fresnel_dielectric(cos_i, eta);
    return f < 1.f ? 1.f - scale * f : 0.f;
  }
};

/// Reflectance and transmittance of a thin dielectric sheet: two parallel interfaces of
/// reflectance scale·F each, and absorption to `color` per `depth` (thickness over
/// attenuation distance) along the refracted path inside; inter-reflections summed as a
/// geometric series. With color 1: r + t = 1.
struct SheetResponse {
  Vec3f r, t;
};
inline SheetResponse thin_sheet(float cos_i, float eta, float scale, const Vec3f& color, float depth) {
  float cos_t;
  const float f = fresnel_dielectric(cos_i, eta, cos_t);
  if (!(f < 1.f)) return {splat(scale), splat(0.f)};  // total internal reflection: nothing enters
  const float r = scale * f, t = 1.f - r;
  const Vec3f pass = pow(color, depth / std::max(cos_t, min_cos));  // one crossing of the sheet
  const auto reflected = [&](float a) { return r + t * t * r * a * a / (1.f - r * r * a * a); };
  const auto transmitted = [&](float a) { return t * t * a / (1.f - r * r * a * a); };
  return {{reflected(pass.x), reflected(pass.y), reflected(pass.z)},
          {transmitted(pass.x), transmitted(pass.y), transmitted(pass.z)}};
}

// ---- GGX (Walter et al. 2007; Heitz 2014, 2018), local frame with z the normal ---------

/// GGX alpha along the local x axis (the tangent) and y; isotropic where they are equal.
struct GgxAlpha {
  float x, y;
  GgxAlpha(float alpha) : x(alpha), y(alpha) {}  // implicit: an isotropic alpha is one
  GgxAlpha(float along, float across) : x(along), y(across) {}
};
/// OSPRay's anisotropic alpha (after Burley 2012, "Physically Based Shading at Disney"):
/// isotropic `alpha` stretched along the tangent and shrunk across it by the aspect
/// sqrt(1 - 0.9 anisotropy), their product kept.
inline GgxAlpha anisotropic_alpha(float alpha, float anisotropy) {
  if (!(anisotropy > 0.f)) return alpha;
  const float aspect = std::sqrt(1.f - 0.9f * std::min(anisotropy, 1.f));
  return {alpha / aspect, alpha * aspect};
}

/// GGX normal distribution, written with the tangential part so that tiny alpha does not
/// cancel catastrophically.
inline float ggx_d(const Vec3f& h, GgxAlpha alpha) {
  if (!(h.z > 0.f)) return 0.f;
  const float x = h.x / alpha.x, y = h.y / alpha.y;
  const float t = x * x + y * y + h.z * h.z;
  return 1.f / (pi * alpha.x * alpha.y * t * t);
}
/// Smith's Lambda for GGX; infinite for a direction in the tangent plane.
inline float ggx_lambda(const Vec3f& w, GgxAlpha alpha) {
  const float z2 = w.z * w.z;
  if (!(z2 > 0.f)) return std::numeric_limits<float>::infinity();
  // alpha² tan²θ, the alpha of w's azimuth (Heitz 2014, eq. 80).
  const float ax = alpha.x * w.x, ay = alpha.y * w.y;
  const float a2_tan2 = alpha.x == alpha.y ? alpha.x * alpha.x * std::max(0.f, 1.f - z2) / z2 : (ax * ax + ay * ay) / z2;
  return 0.5f * (std::sqrt(1.f + a2_tan2) - 1.f);
}
inline float ggx_g1(const Vec3f& w, GgxAlpha alpha) { return 1.f / (1.f + ggx_lambda(w, alpha)); }
/// Height-correlated masking-shadowing (Heitz 2014, eq. 99; used for transmission too).
inline float ggx_g2(const Vec3f& wo, const Vec3f& wi, GgxAlpha alpha) {
  return 1.f / (1.f + ggx_lambda(wo, alpha) + ggx_lambda(wi, alpha));
}
/// A microfacet normal drawn from the normals visible from wo (wo.z > 0), with density
/// G1(wo) max(0, wo·h) D(h) / wo.z (Heitz 2018, listing 1).
inline Vec3f sample_ggx_visible_normal(const Vec3f& wo, GgxAlpha alpha, float u1, float u2) {
  const Vec3f v = normalize(Vec3f{alpha.x * wo.x, alpha.y * wo.y, wo.z});  // to the hemisphere configuration
  const float len2 = v.x * v.x + v.y * v.y;
  const Vec3f t1 = len2 > 0.f ? Vec3f{-v.y, v.x, 0.f} / std::sqrt(len2) : Vec3f{1.f, 0.f, 0.f};
  const Vec3f t2 = cross(v, t1);
  const float r = std::sqrt(u1), phi = 2.f * pi * u2;
  const float p1 = r * std::cos(phi);
  const float s = 0.5f * (1.f + v.z);
  const float p2 = (1.f - s) * std::sqrt(std::max(0.f, 1.f - p1 * p1)) + s * r * std::sin(phi);
  const Vec3f nh = t1 * p1 + t2 * p2 + v * std::sqrt(std::max(0.f, 1.f - p1 * p1 - p2 * p2));
  return normalize(Vec3f{alpha.x * nh.x, alpha.y * nh.y, std::max(nh.z, 0.f)});
}

inline Vec3f reflect(const Vec3f& wo, const Vec3f& h) { return h * (2.f * dot(wo, h)) - wo; }
/// wo refracted through the (micro)normal h (wo·h > 0) into the side of relative index eta.
inline std::optional<Vec3f> refract(const Vec3f& wo, const Vec3f& h, float eta) {
  const float c = dot(wo, h);
  const float sin2_t = std::max(0.f, 1.f - c * c) / (eta * eta);
  if (!(c > 0.f) || sin2_t >= 1.f) return std::nullopt;
  return wo * (-1.f / eta) + h * (c / eta - std::sqrt(1.f - sin2_t));
}

/// A table over roughness (√alpha) and cbrt(cos θo) in [0, 1]², `cells` intervals each,
/// bilinearly interpolated (the albedos change fastest at grazing angles).
template <int cells>
float interpolate_table(const float* table, float roughness, float cos_o) {
  const float x = std::clamp(roughness, 0.f, 1.f) * cells;
  const float y = std::cbrt(std::clamp(cos_o, 0.f, 1.f)) * cells;
  const int i = std::min(static_cast<int>(x), cells - 1), j = std::min(static_cast<int>(y), cells - 1);
  const float fx = x - static_cast<float>(i), fy = y - static_cast<float>(j);
  const auto at = [&](int di, int dj) { return table[(i + di) * (cells + 1) + j + dj]; };
  return (1.f - fx) * ((1.f - fy) * at(0, 0) + fy * at(0, 1)) + fx * ((1.f - fy) * at(1, 0) + fy * at(1, 1));
}

/// Directional albedo E(θo) of a white GGX reflection lobe (F = 1, single scattering), and
/// in the extra row its cosine-weighted average over θo: tabulated on first use, each entry
/// the mean of G2/G1 over a stratified grid of visible normals (exact in expectation).
struct GgxAlbedoTable {
  static constexpr int cells = 32, strata = 32;
  std::array<float, (cells + 1) * (cells + 1)> albedo{};
  std::array<float, cells + 1> average{};

  GgxAlbedoTable() {
    for (int i = 0; i <= cells; ++i) {
      const float roughness = static_cast<float>(i) / cells, alpha = roughness * roughness;
      double weighted = 0.;
      for (int j = 0; j <= cells; ++j) {
        const float s = static_cast<float>(j) / cells;
        const float c_o = std::max(s * s * s, min_cos);
        const Vec3f wo{std::sqrt(1.f - c_o * c_o), 0.f, c_o};
        const float g1 = ggx_g1(wo, alpha);
        double sum = 0.;
        for (int a = 0; a < strata; ++a)
          for (int b = 0; b < strata; ++b) {
            const float u1 = (static_cast<float>(a) + 0.5f) / strata, u2 = (static_cast<float>(b) + 0.5f) / strata;
            const Vec3f wi = reflect(wo, sample_ggx_visible_normal(wo, alpha, u1, u2));
            if (wi.z > 0.f) sum += ggx_g2(wo, wi, alpha) / g1;
          }
        const float e = static_cast<float>(sum / (strata * strata));
        albedo[i * (cells + 1) + j] = e;
        // 2 ∫ E(μ) μ dμ with μ = s³, dμ = 3 s² ds: Simpson's rule over s (cells is even).
        const double simpson = j == 0 || j == cells ? 1. : (j % 2 ? 4. : 2.);
        weighted += simpson * e * 6. * s * s * s * s * s / (3. * cells);
      }
      average[i] = static_cast<float>(weighted);
    }
  }
  static const GgxAlbedoTable& get() {
    static const GgxAlbedoTable table;
    return table;
  }
};

/// E(θo) of a white GGX lobe of `alpha` (see GgxAlbedoTable).
inline float ggx_albedo(float cos_o, float alpha) {
  return interpolate_table<GgxAlbedoTable::cells>(GgxAlbedoTable::get().albedo.data(), std::sqrt(alpha), cos_o);
}
/// 2 ∫ E(μ) μ dμ of a white GGX lobe of `alpha`.
inline float ggx_average_albedo(float alpha) {
  const auto& average = GgxAlbedoTable::get().average;
  const float x = std::clamp(std::sqrt(alpha), 0.f, 1.f) * GgxAlbedoTable::cells;
  const int i = std::min(static_cast<int>(x), GgxAlbedoTable::cells - 1);
  return average[i] + (average[i + 1] - average[i]) * (x - static_cast<float>(i));
}

/// Directional albedo E(θo) of a rough dielectric interface of relative index eta =
/// n(far side) / n(near side) in [1/3, 3] (GGX reflection plus refraction, single
/// scattering, refracted radiance not scaled by 1/eta² as sciray's refraction), the part
/// of it reflected, and the cosine-weighted averages of both: tabulated on first use over ln(eta),
/// √alpha and cbrt(cos θo), each entry the mean of F G2/G1 (reflected) plus (1 - F) G2/G1
/// (refracted) over a stratified grid of visible normals.
struct GgxDielectricAlbedoTable {
  static constexpr int etas = 16, cells = 16, strata = 16;
  static constexpr float log_max_eta = 1.0986123f;  // ln 3: OSPRay clamps eta to [1/3, 3] too
  static constexpr int slice = (cells + 1) * (cells + 1);
  std::array<float, (etas + 1) * slice> albedo{}, reflected{};
  std::array<float, (etas + 1) * (cells + 1)> average{}, reflected_average{};

  static float eta_at(int k) { return std::exp(log_max_eta * (2.f * static_cast<float>(k) / etas - 1.f)); }
  GgxDielectricAlbedoTable() {
    for (int k = 0; k <= etas; ++k) {
      const float eta = eta_at(k);
      for (int i = 0; i <= cells; ++i) {
        const float roughness = static_cast<float>(i) / cells, alpha = std::max(roughness * roughness, 1e-4f);
        double weighted = 0., weighted_up = 0.;
        for (int j = 0; j <= cells; ++j) {
          const float s = static_cast<float>(j) / cells;
          const float c_o = std::max(s * s * s, min_cos);
          const Vec3f wo{std::sqrt(1.f - c_o * c_o), 0.f, c_o};
          const float g1 = ggx_g1(wo, alpha);
          double up = 0., through = 0.;
          for (int a = 0; a < strata; ++a)
            for (int b = 0; b < strata; ++b) {
              const float u1 = (static_cast<float>(a) + 0.5f) / strata, u2 = (static_cast<float>(b) + 0.5f) / strata;
              const Vec3f h = sample_ggx_visible_normal(wo, alpha, u1, u2);
              const float f = fresnel_dielectric(dot(wo, h), eta);
              if (const Vec3f wi = reflect(wo, h); wi.z > 0.f) up += f * ggx_g2(wo, wi, alpha) / g1;
              if (const auto wi = refract(wo, h, eta); wi && wi->z < 0.f) through += (1.f - f) * ggx_g2(wo, *wi, alpha) / g1;
            }
          const float e = static_cast<float>((up + through) / (strata * strata));
          albedo[k * slice + i * (cells + 1) + j] = e;
          reflected[k * slice + i * (cells + 1) + j] = static_cast<float>(up / (strata * strata));
          const double simpson = j == 0 || j == cells ? 1. : (j % 2 ? 4. : 2.);
          weighted += simpson * e * 6. * s * s * s * s * s / (3. * cells);
          weighted_up += simpson * (up / (strata * strata)) * 6. * s * s * s * s * s / (3. * cells);
        }
        average[k * (cells + 1) + i] = static_cast<float>(weighted);
        reflected_average[k * (cells + 1) + i] = static_cast<float>(weighted_up);
      }
    }
  }
  static const GgxDielectricAlbedoTable& get() {
    static const GgxDielectricAlbedoTable table;
    return table;
  }
  /// The eta slices around eta and the weight of the upper one.
  static std::pair<int, float> eta_cell(float eta) {
    const float x = std::clamp((std::log(eta) / log_max_eta + 1.f) * 0.5f, 0.f, 1.f) * etas;
    const int k = std::min(static_cast<int>(x), etas - 1);
    return {k, x - static_cast<float>(k)};
  }
};

/// An entry of one of GgxDielectricAlbedoTable's tables, interpolated.
inline float interpolate_dielectric(const std::array<float, (GgxDielectricAlbedoTable::etas + 1) *
                                                            GgxDielectricAlbedoTable::slice>& table,
                                    float cos_o, float eta, float alpha) {
  const auto [k, w] = GgxDielectricAlbedoTable::eta_cell(eta);
  const float r = std::sqrt(alpha);
  constexpr int cells = GgxDielectricAlbedoTable::cells, slice = GgxDielectricAlbedoTable::slice;
  return (1.f - w) * interpolate_table<cells>(table.data() + k * slice, r, cos_o) +
         w * interpolate_table<cells>(table.data() + (k + 1) * slice, r, cos_o);
}
/// E(θo) of a rough dielectric interface (see GgxDielectricAlbedoTable).
inline float ggx_dielectric_albedo(float cos_o, float eta, float alpha) {
  return interpolate_dielectric(GgxDielectricAlbedoTable::get().albedo, cos_o, eta, alpha);
}
/// The part of E(θo) a rough dielectric interface reflects.
inline float ggx_dielectric_reflectance(float cos_o, float eta, float alpha) {
  return interpolate_dielectric(GgxDielectricAlbedoTable::get().reflected, cos_o, eta, alpha);
}
/// An entry of one of GgxDielectricAlbedoTable's averages, interpolated.
inline float interpolate_dielectric_average(
    const std::array<float, (GgxDielectricAlbedoTable::etas + 1) * (GgxDielectricAlbedoTable::cells + 1)>& table,
    float eta, float alpha) {
  const auto [k, w] = GgxDielectricAlbedoTable::eta_cell(eta);
  constexpr int cells = GgxDielectricAlbedoTable::cells;
  const float x = std::clamp(std::sqrt(alpha), 0.f, 1.f) * cells;
  const int i = std::min(static_cast<int>(x), cells - 1);
  const float f = x - static_cast<float>(i);
  const auto at = [&](int kk, int ii) { return table[kk * (cells + 1) + ii]; };
  return (1.f - w) * ((1.f - f) * at(k, i) + f * at(k, i + 1)) + w * ((1.f - f) * at(k + 1, i) + f * at(k + 1, i + 1));
}
/// 2 ∫ E(μ) μ dμ of a rough dielectric interface.
inline float ggx_dielectric_average_albedo(float eta, float alpha) {
  return interpolate_dielectric_average(GgxDielectricAlbedoTable::get().average, eta, alpha);
}
/// 2 ∫ R(μ) μ dμ of the part R of E that a rough dielectric interface reflects.
inline float ggx_dielectric_average_reflectance(float eta, float alpha) {
  return interpolate_dielectric_average(GgxDielectricAlbedoTable::get().reflected_average, eta, alpha);
}

/// The energy a rough dielectric interface loses to multiple scattering between its
/// microfacets, given back as cosine lobes on both sides (Kulla & Conty 2017, as OSPRay's
/// microfacet dielectric): of what is lost for wo, 1 - E(θo), the share `reflected` goes
/// back to wo's side, the rest through, each shaped by 1 - E of the direction it leaves by.
struct DielectricMultipleScattering {
  float reflected;  ///< the share reflected, from the average Fresnel and albedos of both sides
  float e_o;        ///< E(θo)
  /// f·cos θi towards wi (cos_i < 0: through) and the pdf of sampling the side, then the
  /// cosine lobe.
  float f_cos(float cos_i, float eta, float alpha, float* pdf) const {
    const bool through = cos_i < 0.f;
    const float side_eta = through ? 1.f / eta : eta, c = std::abs(cos_i);
    const float share = through ? 1.f - reflected : reflected;
    *pdf = share * c / pi;
    const float e_average = ggx_dielectric_average_albedo(side_eta, alpha);
    if (!(e_average < 1.f - 1e-4f)) return 0.f;
    return share * (1.f - e_o) * (1.f - ggx_dielectric_albedo(c, side_eta, alpha)) * c / (pi * (1.f - e_average));
  }
};
inline DielectricMultipleScattering dielectric_multiple_scattering(float cos_o, float eta, float alpha) {
  const float f_eta = fresnel_dielectric_average(eta), f_inverse = fresnel_dielectric_average(1.f / eta);
  const float e_eta = ggx_dielectric_average_albedo(eta, alpha), e_inverse = ggx_dielectric_average_albedo(1.f / eta, alpha);
  // OSPRay's split (Kulla & Conty's, without the 1/eta² of radiance): what is reflected
  // balances what crosses from either side.
  const float a = (1.f - f_eta) / std::max(1.f - e_inverse, 1e-4f), b = (1.f - f_inverse) / std::max(1.f - e_eta, 1e-4f);
  const float x = b / (a + b);
  return {std::clamp(1.f - x * (1.f - f_eta), 0.f, 1.f), ggx_dielectric_albedo(cos_o, eta, alpha)};
}

/// The shape of what a white GGX lobe loses to multiple scattering between its microfacets,
/// given back as a diffuse-like lobe (Kulla & Conty 2017): (1 - E(θo)) (1 - E(θi)) cos θi /
/// (π (1 - E_avg)), which integrates over wi to 1 - E(θo); 0 where the lobe loses nothing.
inline float ggx_lost_energy(float cos_o, float cos_i, float alpha) {
  const float e_average = ggx_average_albedo(alpha);
  if (!(e_average < 1.f - 1e-4f)) return 0.f;
  const float shape = (1.f - ggx_albedo(cos_o, alpha)) * (1.f - ggx_albedo(cos_i, alpha)) * cos_i / (pi * (1.f - e_average));
  return std::max(shape, 0.f);
}

/// f·cos θi of the energy a GGX reflection lobe of average Fresnel `f_average` loses to
/// multiple scattering between its microfacets (Kulla & Conty 2017, with Hill's
/// average-Fresnel scale, as OSPRay's microfacet conductor): F_avg² E_avg / (1 - F_avg (1 -
/// E_avg)) times ggx_lost_energy. With F = 1 the lobe and this term together reflect exactly
/// what they receive.
inline Vec3f ggx_multiple_scattering(const Vec3f& f_average, float cos_o, float cos_i, float alpha) {
  if (!(max_component(f_average) > 0.f)) return {0.f, 0.f, 0.f};
  const float e_average = ggx_average_albedo(alpha);
  const auto scale = [&](float f) { return f * f * e_average / (1.f - f * (1.f - e_average)); };
  return Vec3f{scale(f_average.x), scale(f_average.y), scale(f_average.z)} * ggx_lost_energy(cos_o, cos_i, alpha);
}

/// The share of ggx_lost_energy that a rough dielectric layer's reflection gives back, from
/// its average Fresnel: F_avg (1 - E_avg) / (1 - F_avg E_avg) (OSPRay's microfacet
/// dielectric layer, after Kulla & Conty 2017).
inline float layer_multiple_scattering_scale(float f_average, float alpha) {
  const float e_average = ggx_average_albedo(alpha);
  return f_average * (1.f - e_average) / (1.f - f_average * e_average);
}

// ---- Charlie sheen (Conty Estevez & Kulla 2017) ----------------------------------------------

/// The fibre-cone exponent r of the sheen distribution; roughness is squared as for GGX
/// and kept off 0 where the distribution degenerates (OSPRay does the same).
inline float sheen_r(float roughness) { return std::max(roughness * roughness, 1e-3f); }
inline float charlie_d(float cos_h, float r) {
  const float sin_h = std::sqrt(std::max(0.f, 1.f - cos_h * cos_h));
  return (2.f + 1.f / r) * std::pow(sin_h, 1.f / r) / (2.f * pi);
}
/// The paper's fitted Lambda, its coefficients interpolated between r = 0 and r = 1.
inline float charlie_lambda(float cos_theta, float r) {
  const float w0 = (1.f - r) * (1.f - r), w1 = 1.f - w0;
  const float a = w0 * 25.3245f + w1 * 21.5473f, b = w0 * 3.32435f + w1 * 3.82987f;
  const float c = w0 * 0.16801f + w1 * 0.19823f, d = w0 * -1.27393f + w1 * -1.97760f;
  const float e = w0 * -4.85967f + w1 * -4.32054f;
  const auto l = [&](float x) { return a / (1.f + b * std::pow(x, c)) + d * x + e; };
  return cos_theta < 0.5f ? std::exp(l(cos_theta)) : std::exp(2.f * l(0.5f) - l(1.f - cos_theta));
}
/// f·cos θi of the unnormalised sheen lobe (height-correlated G2 from the fitted Lambdas).
inline float charlie_f_cos(float cos_h, float lambda_o, float lambda_i, float cos_o, float r) {
  return charlie_d(cos_h, r) / ((1.f + lambda_o + lambda_i) * 4.f * cos_o);
}
inline float charlie_f_cos(const Vec3f& wo, const Vec3f& wi, float r) {
  return charlie_f_cos(normalize(wo + wi).z, charlie_lambda(wo.z, r), charlie_lambda(wi.z, r), wo.z, r);
}
/// Directional albedo of the unnormalised sheen lobe, over sheen roughness and cbrt(cos θo)
/// (the albedo changes fastest at grazing angles), tabulated on first use by midpoint
/// quadrature, which errs high at the grazing peak, so the layer below is not over-weighted.
/// The lobe's fit of Lambda is not exactly D's, so it can exceed 1 at grazing angles; the
/// lobe is divided by it there.
inline float sheen_albedo(float cos_o, float roughness) {
  constexpr int cells = 32, quadrature = 48;
  static const std::array<float, (cells + 1) * (cells + 1)> table = [] {
    std::array<float, (cells + 1) * (cells + 1)> t{};
    std::array<float, quadrature> cos_phi{};
    for (int k = 0; k < quadrature; ++k) {
      const float phi = pi * (static_cast<float>(k) + 0.5f) / quadrature;  // the lobe is symmetric in phi
      cos_phi[k] = std::cos(phi);
    }
    std::array<float, quadrature> cos_i{}, sin_i{}, lambda_i{};
    for (int i = 0; i <= cells; ++i) {
      const float r = sheen_r(static_cast<float>(i) / cells);
      for (int q = 0; q < quadrature; ++q) {
        const float theta = 0.5f * pi * (static_cast<float>(q) + 0.5f) / quadrature;
        cos_i[q] = std::cos(theta), sin_i[q] = std::sin(theta), lambda_i[q] = charlie_lambda(cos_i[q], r);
      }
      for (int j = 0; j <= cells; ++j) {
        const float s = static_cast<float>(j) / cells;
        const float c_o = std::max(s * s * s, min_cos), s_o = std::sqrt(1.f - c_o * c_o);
        const float lambda_o = charlie_lambda(c_o, r);
        double sum = 0.;
        for (int q = 0; q < quadrature; ++q)
          for (int k = 0; k < quadrature; ++k) {
            // |wo + wi|² = 2 + 2 wo·wi
            const float cos_h =
                (c_o + cos_i[q]) / std::sqrt(2.f + 2.f * (s_o * sin_i[q] * cos_phi[k] + c_o * cos_i[q]));
            sum += charlie_f_cos(cos_h, lambda_o, lambda_i[q], c_o, r) * sin_i[q];
          }
        t[i * (cells + 1) + j] = static_cast<float>(sum * (0.5 * pi / quadrature) * (2. * pi / quadrature));
      }
    }
    return t;
  }();
  return interpolate_table<cells>(table.data(), roughness, cos_o);
}

}  // namespace sciray::bsdf_detail
