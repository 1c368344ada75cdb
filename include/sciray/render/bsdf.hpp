#pragma once
// Physically based BSDFs for every material type of material.hpp, one shading point at a
// time in scalar float, for the path tracer.
//
// Conventions: wo points from the surface to where the path came from (-ray.dir), wi to
// where the light comes from; both unit. eval() gives f·|cos θi| and the solid-angle pdf
// with which sample() draws wi; sample() gives the throughput weight f·|cos θi| / pdf.
//
// A material is a short list of lobes, built for one wo (make_bsdf). sample() picks a lobe
// with a probability proportional to an estimate of its albedo for wo, draws a direction
// from it and, if the lobe is not a delta lobe, weights that direction by the whole
// mixture: the sum of every non-delta lobe's f over the sum of their probability-weighted
// pdfs (one-sample MIS, Veach 1997), which is exactly what eval() reports. Delta lobes
// (mirror, smooth refraction, straight pass-through) are invisible to eval(); their pdf is
// the probability of picking them.
//
// Layers (principled): sheen over clear coat over the base. A layer passes on what it does
// not reflect: what lies below is scaled by (1 - reflectance) of the layer for wo and for
// wi, so a stack never reflects more than it receives (as OSPRay does). Light bouncing
// between layers and multiple scattering between microfacets are ignored, so rough
// materials are somewhat darker than a full simulation.
//
// Refraction does not scale radiance by 1/eta² (neither does OSPRay): the weights are
// those of importance transport, so a path that enters and leaves a glass body keeps its
// throughput.
//
// References: Walter et al. 2007, "Microfacet Models for Refraction through Rough Surfaces"
// (GGX, rough refraction); Heitz 2014, "Understanding the Masking-Shadowing Function in
// Microfacet-Based BRDFs" (height-correlated Smith G2); Heitz 2018, "Sampling the GGX
// Distribution of Visible Normals"; Conty Estevez & Kulla 2017, "Production Friendly
// Microfacet Sheen BRDF" (Charlie sheen, its Lambda fit); Lafortune & Willems 1994
// (energy-normalised Phong); Schlick 1994 (Fresnel approximation); Pharr et al., PBRT 4th
// ed. (complex Fresnel).
#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <limits>
#include <numbers>
#include <optional>
#include <variant>

#include "sciray/math/vec.hpp"
#include "sciray/render/material.hpp"

namespace sciray {

/// The local frame at a shading point, seen from the incoming ray.
struct ShadingPoint {
  Vec3f n;   ///< unit shading normal on the side of wo (interpolated: dot(n, wo) may still be <= 0)
  Vec3f ng;  ///< unit geometric normal on the side of wo (dot(ng, wo) > 0)
  bool entering = true;  ///< the ray arrived at the front face: eta is outside -> inside; false: leaving the medium
  Vec3f color{1.f, 1.f, 1.f};  ///< the geometry's own colour; multiplies the material's base colour
  float alpha = 1.f;           ///< the colour's alpha, which multiplies the material's opacity (as OSPRay)
};

struct BsdfSample {
  Vec3f wi;          ///< sampled direction towards the light, unit
  Vec3f weight;      ///< f * |cos(n, wi)| / pdf
  float pdf;         ///< solid-angle pdf of wi; for delta lobes the probability of choosing that lobe
  bool delta;        ///< a specular (Dirac) lobe: not evaluable by eval(), no MIS
  bool transmitted;  ///< wi is on the other side of the surface than wo (relative to ng)
};

struct BsdfValue {
  Vec3f f_cos{0.f, 0.f, 0.f};  ///< f(wo, wi) * |cos(n, wi)| (non-delta lobes only)
  float pdf = 0.f;             ///< the solid-angle pdf with which sample() produces wi
};

namespace bsdf_detail {

inline constexpr float pi = std::numbers::pi_v<float>;
/// GGX alpha (roughness²) below which a lobe is a perfect mirror or refraction: the peak of
/// D, 1/(pi alpha²), would outgrow what float resolves around the half vector.
inline constexpr float min_alpha = 1e-4f;
/// Relative index of refraction closer to 1 than this refracts as a delta lobe: the rough
/// refraction lobe collapses onto -wo and its half vector becomes ill-defined.
inline constexpr float min_eta_contrast = 1e-3f;
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

/// Isotropic GGX normal distribution, written with the tangential part so that tiny alpha
/// does not cancel catastrophically.
inline float ggx_d(const Vec3f& h, float alpha) {
  if (!(h.z > 0.f)) return 0.f;
  const float a2 = alpha * alpha;
  const float t = (h.x * h.x + h.y * h.y) / a2 + h.z * h.z;
  return 1.f / (pi * a2 * t * t);
}
/// Smith's Lambda for GGX; infinite for a direction in the tangent plane.
inline float ggx_lambda(const Vec3f& w, float alpha) {
  const float z2 = w.z * w.z;
  if (!(z2 > 0.f)) return std::numeric_limits<float>::infinity();
  const float tan2 = std::max(0.f, 1.f - z2) / z2;
  return 0.5f * (std::sqrt(1.f + alpha * alpha * tan2) - 1.f);
}
inline float ggx_g1(const Vec3f& w, float alpha) { return 1.f / (1.f + ggx_lambda(w, alpha)); }
/// Height-correlated masking-shadowing (Heitz 2014, eq. 99; used for transmission too).
inline float ggx_g2(const Vec3f& wo, const Vec3f& wi, float alpha) {
  return 1.f / (1.f + ggx_lambda(wo, alpha) + ggx_lambda(wi, alpha));
}
/// A microfacet normal drawn from the normals visible from wo (wo.z > 0), with density
/// G1(wo) max(0, wo·h) D(h) / wo.z (Heitz 2018, listing 1).
inline Vec3f sample_ggx_visible_normal(const Vec3f& wo, float alpha, float u1, float u2) {
  const Vec3f v = normalize(Vec3f{alpha * wo.x, alpha * wo.y, wo.z});  // to the hemisphere configuration
  const float len2 = v.x * v.x + v.y * v.y;
  const Vec3f t1 = len2 > 0.f ? Vec3f{-v.y, v.x, 0.f} / std::sqrt(len2) : Vec3f{1.f, 0.f, 0.f};
  const Vec3f t2 = cross(v, t1);
  const float r = std::sqrt(u1), phi = 2.f * pi * u2;
  const float p1 = r * std::cos(phi);
  const float s = 0.5f * (1.f + v.z);
  const float p2 = (1.f - s) * std::sqrt(std::max(0.f, 1.f - p1 * p1)) + s * r * std::sin(phi);
  const Vec3f nh = t1 * p1 + t2 * p2 + v * std::sqrt(std::max(0.f, 1.f - p1 * p1 - p2 * p2));
  return normalize(Vec3f{alpha * nh.x, alpha * nh.y, std::max(nh.z, 0.f)});
}

inline Vec3f reflect(const Vec3f& wo, const Vec3f& h) { return h * (2.f * dot(wo, h)) - wo; }
/// wo refracted through the (micro)normal h (wo·h > 0) into the side of relative index eta.
inline std::optional<Vec3f> refract(const Vec3f& wo, const Vec3f& h, float eta) {
  const float c = dot(wo, h);
  const float sin2_t = std::max(0.f, 1.f - c * c) / (eta * eta);
  if (!(c > 0.f) || sin2_t >= 1.f) return std::nullopt;
  return wo * (-1.f / eta) + h * (c / eta - std::sqrt(1.f - sin2_t));
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
  const float x = std::clamp(roughness, 0.f, 1.f) * cells;
  const float y = std::cbrt(std::clamp(cos_o, 0.f, 1.f)) * cells;
  const int i = std::min(static_cast<int>(x), cells - 1), j = std::min(static_cast<int>(y), cells - 1);
  const float fx = x - static_cast<float>(i), fy = y - static_cast<float>(j);
  const auto at = [&](int di, int dj) { return table[(i + di) * (cells + 1) + j + dj]; };
  return (1.f - fx) * ((1.f - fy) * at(0, 0) + fy * at(0, 1)) + fx * ((1.f - fy) * at(1, 0) + fy * at(1, 1));
}

// ---- Lobes ------------------------------------------------------------------------------

enum class LobeKind {
  lambert,      ///< tint/pi, cosine-weighted sampling
  phong,        ///< tint (n+2)/(2 pi) cos^n around the mirror direction, n = shape
  sheen,        ///< tint · Charlie sheen normalised to albedo <= 1, uniform hemisphere sampling
  ggx_reflect,  ///< tint · F · D G2 / (4 cos_o cos_i), alpha = shape, visible normal sampling
  ggx_refract,  ///< tint · (1 - F) through GGX microfacets, alpha = shape
  mirror,       ///< delta: tint · F(cos_o) in the mirror direction
  refract,      ///< delta: tint · (1 - F(cos_o)) in the refracted direction
  straight,     ///< delta: tint, wi = -wo
};
inline bool is_delta(LobeKind kind) { return kind >= LobeKind::mirror; }

/// Layers of the principled stack above a lobe, each scaling it by what it lets through.
enum Layer : unsigned { below_sheen = 1u, below_coat = 2u, below_specular = 4u };

struct Lobe {
  LobeKind kind{};
  Vec3f tint;
  Fresnel fresnel;
  float shape = 0.f;  ///< GGX alpha, Phong exponent or sheen roughness
  unsigned layers = 0u;
  float probability = 0.f;  ///< of sample() choosing it
};

/// The lobes of one material at one shading point, for one wo.
struct Bsdf {
  Frame frame;
  Vec3f wo;  ///< local
  std::array<Lobe, 8> lobes{};  // the most a principled material needs
  int count = 0;
  // The principled stack's layers, which scale the lobes below them.
  float sheen_cover = 0.f;  ///< sheen weight · max channel of the sheen colour
  float sheen_roughness = 0.f;
  float coat = 0.f, coat_eta = 1.f, coat_thickness = 0.f;
  Vec3f coat_color{1.f, 1.f, 1.f};
  float specular = 0.f, specular_eta = 1.f;  ///< the dielectric interface over the diffuse lobe

  /// Adds a lobe unless it is black. `estimate`, its albedo for wo (exact for a delta
  /// lobe, roughly for others), sets how often sample() picks it; a non-delta lobe keeps a
  /// small share when its estimate is 0, as it may still reflect towards other wi.
  void add(LobeKind kind, const Vec3f& tint, float estimate, const Fresnel& fresnel = {}, float shape = 0.f,
           unsigned layers = 0u) {
    if (!(max_component(tint) > 0.f) || (is_delta(kind) && !(estimate > 0.f))) return;
    lobes[count++] = {kind, tint, fresnel, shape, layers, std::max(estimate, 1e-3f * max_component(tint))};
  }
  void normalize_probabilities() {
    float total = 0.f;
    for (int i = 0; i < count; ++i) total += lobes[i].probability;
    for (int i = 0; i < count; ++i) lobes[i].probability /= total;
  }

  /// What the layers above a lobe let through, for wo and (when `with_wi`: reflection)
  /// for wi at cos_i > 0 too; transmitted light crosses the layers on the side of wo only.
  Vec3f layer_transmittance(unsigned layers, float cos_i, bool with_wi) const {
    const float cos_o = wo.z;
    float through = 1.f;
    Vec3f absorbed = splat(1.f);
    if (layers & below_sheen) {
      const float albedo_o = sheen_albedo(cos_o, sheen_roughness);
      const float albedo = with_wi ? std::max(albedo_o, sheen_albedo(cos_i, sheen_roughness)) : albedo_o;
      through *= 1.f - sheen_cover * std::min(albedo, 1.f);
    }
    if (layers & below_coat) {
      float cos_t;
      through *= 1.f - coat * fresnel_dielectric(cos_o, coat_eta, cos_t);
      float path = 1.f / std::max(cos_t, min_cos);
      if (with_wi) {
        through *= 1.f - coat * fresnel_dielectric(cos_i, coat_eta, cos_t);
        path += 1.f / std::max(cos_t, min_cos);
      }
      absorbed = lerp(splat(1.f), pow(coat_color, coat_thickness * path), coat);
    }
    if (layers & below_specular) {
      through *= 1.f - specular * fresnel_dielectric(cos_o, specular_eta);
      if (with_wi) through *= 1.f - specular * fresnel_dielectric(cos_i, specular_eta);
    }
    return absorbed * through;
  }
  /// The same for wo alone, averaged over the channels: the lobe-choice estimate.
  float outer(unsigned layers) const { return mean(layer_transmittance(layers, 0.f, false)); }
};

// ---- Material -> lobes ------------------------------------------------------------------

inline void build(Bsdf& b, const ObjMaterial& material, const ShadingPoint& sp) {
  const ObjMaterial m = energy_conserving(material);
  const Vec3f kd = m.kd * sp.color, ks = m.ks, tf = m.tf;
  const float d = m.d * sp.alpha;
  b.add(LobeKind::lambert, kd * d, d * mean(kd));
  b.add(LobeKind::phong, ks * d, d * mean(ks), {}, m.ns);
  const Vec3f through = splat(1.f - d) + tf * d;  // cut-out opacity plus the transmissive filter
  b.add(LobeKind::straight, through, mean(through));
}

/// Whether a dielectric Fresnel term is not identically 0 (index contrast, specular weight).
inline bool reflects(const Fresnel& dielectric) { return dielectric.scale > 0.f && dielectric.eta != 1.f; }

/// A bare dielectric interface of relative index `eta` from wo's side to the other: GGX (or
/// smooth) reflection and refraction, weighted by `weight`.
inline void add_interface(Bsdf& b, float eta, float specular, float alpha, float weight) {
  const Fresnel fresnel{Fresnel::Kind::dielectric, eta, specular};
  if (reflects(fresnel))
    b.add(alpha >= min_alpha ? LobeKind::ggx_reflect : LobeKind::mirror, splat(weight),
          weight * fresnel(b.wo.z).x, fresnel, alpha);
  const bool rough = alpha >= min_alpha && std::abs(eta - 1.f) >= min_eta_contrast;
  b.add(rough ? LobeKind::ggx_refract : LobeKind::refract, splat(weight), weight * fresnel.transmit(b.wo.z), fresnel,
        alpha);
}

inline void build(Bsdf& b, const PrincipledMaterial& m, const ShadingPoint& sp) {
  const float cos_o = b.wo.z;
  const float opacity = m.opacity * sp.alpha;
  b.add(LobeKind::straight, splat(1.f - opacity), 1.f - opacity);  // cut-out
  const float alpha = m.roughness * m.roughness;
  const LobeKind reflection = alpha >= min_alpha ? LobeKind::ggx_reflect : LobeKind::mirror;
  const float dielectric = 1.f - m.metallic;

  if (!sp.entering && !m.thin && m.transmission > 0.f) {
    // From inside the body only its interface is met.
    add_interface(b, 1.f / m.ior, m.specular, alpha, opacity);
    return;
  }
  const Vec3f base = clamp01(m.base_color * sp.color);
  unsigned under = 0u;  // the layers over the base
  if (m.sheen > 0.f) {
    const Vec3f color = clamp01(lerp(splat(1.f), base, m.sheen_tint) * m.sheen_color);
    b.sheen_cover = m.sheen * max_component(color);
    b.sheen_roughness = m.sheen_roughness;
    b.add(LobeKind::sheen, color * (opacity * m.sheen),
          opacity * m.sheen * mean(color) * std::min(sheen_albedo(cos_o, m.sheen_roughness), 1.f), {},
          m.sheen_roughness);
    under |= below_sheen;
  }
  if (m.coat > 0.f) {
    b.coat = m.coat, b.coat_eta = m.coat_ior, b.coat_thickness = m.coat_thickness;
    b.coat_color = clamp01(m.coat_color);
    const Fresnel fresnel{Fresnel::Kind::dielectric, m.coat_ior, 1.f};
    const float coat_alpha = m.coat_roughness * m.coat_roughness;
    if (reflects(fresnel))
      b.add(coat_alpha >= min_alpha ? LobeKind::ggx_reflect : LobeKind::mirror, splat(opacity * m.coat),
            b.outer(under) * opacity * m.coat * fresnel(cos_o).x, fresnel, coat_alpha, under);
    under |= below_coat;
  }
  const float outer = b.outer(under);

  if (dielectric > 0.f) {
    b.specular = m.specular, b.specular_eta = m.ior;
    const Fresnel specular{Fresnel::Kind::dielectric, m.ior, m.specular};
    const float transmission = m.transmission;
    // The interface reflects alike over the diffuse and over the transmissive part, except
    // for a thin sheet, whose second face reflects too.
    const float plain_reflection = m.thin ? 1.f - transmission : 1.f;
    if (reflects(specular))
      b.add(reflection, splat(opacity * dielectric * plain_reflection),
            outer * opacity * dielectric * plain_reflection * specular(cos_o).x, specular, alpha, under);
    const Vec3f diffuse = base * (opacity * dielectric * (1.f - transmission) * m.diffuse);
    b.add(LobeKind::lambert, diffuse, b.outer(under | below_specular) * mean(diffuse), {}, 0.f,
          under | below_specular);
    if (transmission > 0.f) {
      const float weight = opacity * dielectric * transmission;
      if (m.thin) {
        // Thin: no bending, like thinGlass; reflection and transmission of the whole sheet
        // at the macroscopic angle (reflection keeps its GGX shape).
        const SheetResponse sheet = thin_sheet(cos_o, m.ior, m.specular, clamp01(m.transmission_color),
                                               m.thickness / m.transmission_depth);
        b.add(reflection, sheet.r * weight, outer * weight * mean(sheet.r), {}, alpha, under);
        b.add(LobeKind::straight, sheet.t * weight, outer * weight * mean(sheet.t), {}, 0.f, under);
      } else {
        const bool rough = alpha >= min_alpha && std::abs(m.ior - 1.f) >= min_eta_contrast;
        b.add(rough ? LobeKind::ggx_refract : LobeKind::refract, splat(weight),
              outer * weight * specular.transmit(cos_o), specular, alpha, under);
      }
    }
  }
  if (m.metallic > 0.f) {
    const Fresnel metal{Fresnel::Kind::schlick, 1.f, 1.f, base, clamp01(m.edge_color)};
    b.add(reflection, splat(opacity * m.metallic), outer * opacity * m.metallic * mean(metal(cos_o)), metal, alpha,
          under);
  }
}

inline void build(Bsdf& b, const GlassMaterial& m, const ShadingPoint& sp) {
  add_interface(b, sp.entering ? m.eta : 1.f / m.eta, 1.f, 0.f, 1.f);
}

inline void build(Bsdf& b, const ThinGlassMaterial& m, const ShadingPoint& sp) {
  // The geometry's colour tints the sheet as attenuationColor does (OSPRay's thinGlass).
  const SheetResponse sheet = thin_sheet(b.wo.z, m.eta, 1.f, clamp01(m.attenuation_color * sp.color),
                                         m.thickness / m.attenuation_distance);
  b.add(LobeKind::mirror, sheet.r, mean(sheet.r));
  b.add(LobeKind::straight, sheet.t, mean(sheet.t));
}

inline void build(Bsdf& b, const MetalMaterial& m, const ShadingPoint&) {
  const float alpha = m.roughness * m.roughness;
  b.add(alpha >= min_alpha ? LobeKind::ggx_reflect : LobeKind::mirror, splat(1.f), 1.f,
        {Fresnel::Kind::conductor, 1.f, 1.f, m.eta, m.k}, alpha);
}

inline void build(Bsdf& b, const AlloyMaterial& m, const ShadingPoint& sp) {
  const float alpha = m.roughness * m.roughness;
  b.add(alpha >= min_alpha ? LobeKind::ggx_reflect : LobeKind::mirror, splat(1.f), 1.f,
        {Fresnel::Kind::schlick, 1.f, 1.f, clamp01(m.color * sp.color), clamp01(m.edge_color)}, alpha);
}

inline void build(Bsdf& b, const LuminousMaterial& m, const ShadingPoint&) {
  b.add(LobeKind::straight, splat(m.transparency), m.transparency);
}

/// The lobes of `material` for wo; none when wo is not above the geometric surface.
inline Bsdf make_bsdf(const Material& material, const ShadingPoint& sp, const Vec3f& wo) {
  Bsdf b;
  if (!(dot(wo, sp.ng) > 0.f)) return b;
  Vec3f n = sp.n;
  const float cos_o = dot(n, wo);
  if (!(cos_o >= min_cos)) {
    n = n + wo * (min_cos - cos_o);
    const float len = length(n);
    n = len > 1e-6f ? n / len : sp.ng;  // also catches a NaN normal
  }
  b.frame = Frame(n);
  b.wo = b.frame.to_local(wo);
  if (!(b.wo.z > 0.f)) return b;
  std::visit([&](const auto& m) { build(b, m, sp); }, material);
  b.normalize_probabilities();
  return b;
}

// ---- Per-lobe sampling and evaluation, local frame --------------------------------------

struct LobeValue {
  Vec3f f_cos{0.f, 0.f, 0.f};
  float pdf = 0.f;
};

inline LobeValue eval_lobe(const Lobe& lobe, const Vec3f& wo, const Vec3f& wi) {
  switch (lobe.kind) {
    case LobeKind::lambert:
      if (!(wi.z > 0.f)) return {};
      return {lobe.tint * (wi.z / pi), wi.z / pi};
    case LobeKind::phong: {
      const float c = dot(wi, Vec3f{-wo.x, -wo.y, wo.z});  // cosine to the mirror direction
      if (!(wi.z > 0.f) || !(c > 0.f)) return {};
      const float n = lobe.shape, lobe_c = std::pow(c, n);
      return {lobe.tint * ((n + 2.f) / (2.f * pi) * lobe_c * wi.z), (n + 1.f) / (2.f * pi) * lobe_c};
    }
    case LobeKind::sheen: {
      if (!(wi.z > 0.f)) return {};
      const float roughness = lobe.shape;
      const float albedo = std::max({1.f, sheen_albedo(wo.z, roughness), sheen_albedo(wi.z, roughness)});
      return {lobe.tint * (charlie_f_cos(wo, wi, sheen_r(roughness)) / albedo), 1.f / (2.f * pi)};
    }
    case LobeKind::ggx_reflect: {
      if (!(wi.z > 0.f)) return {};
      const float alpha = lobe.shape;
      const Vec3f h = normalize(wo + wi);
      const float d = ggx_d(h, alpha);
      const float f_cos = d * ggx_g2(wo, wi, alpha) / (4.f * wo.z);
      return {lobe.tint * lobe.fresnel(dot(wo, h)) * f_cos, ggx_g1(wo, alpha) * d / (4.f * wo.z)};
    }
    case LobeKind::ggx_refract: {
      if (!(wi.z < 0.f)) return {};
      const float alpha = lobe.shape, eta = lobe.fresnel.eta;
      Vec3f h = normalize(wo + wi * eta);  // the generalised half vector, up to its sign
      if (h.z < 0.f) h = -h;
      const float cos_oh = dot(wo, h), cos_ih = dot(wi, h);
      if (!(cos_oh > 0.f && cos_ih < 0.f)) return {};
      const float denom = cos_oh + eta * cos_ih;  // |wo + eta wi| >= |eta - 1|: never 0 here
      const float jacobian = eta * eta * -cos_ih / (denom * denom);  // dh/dwi
      const float d_visible = ggx_d(h, alpha) * cos_oh / wo.z;      // D(h) wo·h / cos_o
      const float f_cos = lobe.fresnel.transmit(cos_oh) * d_visible * ggx_g2(wo, wi, alpha) * jacobian;
      return {lobe.tint * f_cos, ggx_g1(wo, alpha) * d_visible * jacobian};
    }
    case LobeKind::mirror:
    case LobeKind::refract:
    case LobeKind::straight: break;
  }
  return {};
}

/// A direction from a non-delta lobe; nullopt where the lobe's sampler leaves the
/// hemisphere it covers.
inline std::optional<Vec3f> sample_lobe(const Lobe& lobe, const Vec3f& wo, float u1, float u2) {
  const float phi = 2.f * pi * u2;
  switch (lobe.kind) {
    case LobeKind::lambert: {
      const float r = std::sqrt(u1);
      return Vec3f{r * std::cos(phi), r * std::sin(phi), std::sqrt(std::max(0.f, 1.f - u1))};
    }
    case LobeKind::sheen: {
      const float r = std::sqrt(std::max(0.f, 1.f - u1 * u1));
      return Vec3f{r * std::cos(phi), r * std::sin(phi), u1};
    }
    case LobeKind::phong: {
      const Vec3f mirror{-wo.x, -wo.y, wo.z};
      const float cos_a = std::pow(u1, 1.f / (lobe.shape + 1.f)), sin_a = std::sqrt(std::max(0.f, 1.f - cos_a * cos_a));
      const Vec3f t = perpendicular(mirror), b = cross(mirror, t);
      const Vec3f wi = t * (sin_a * std::cos(phi)) + b * (sin_a * std::sin(phi)) + mirror * cos_a;
      if (!(wi.z > 0.f)) return std::nullopt;
      return wi;
    }
    case LobeKind::ggx_reflect: {
      const Vec3f wi = reflect(wo, sample_ggx_visible_normal(wo, lobe.shape, u1, u2));
      if (!(wi.z > 0.f)) return std::nullopt;
      return wi;
    }
    case LobeKind::ggx_refract: {
      const auto wi = refract(wo, sample_ggx_visible_normal(wo, lobe.shape, u1, u2), lobe.fresnel.eta);
      if (!wi || !(wi->z < 0.f)) return std::nullopt;
      return wi;
    }
    case LobeKind::mirror:
    case LobeKind::refract:
    case LobeKind::straight: break;
  }
  return std::nullopt;
}

struct DeltaDirection {
  Vec3f wi;  ///< local
  Vec3f value;
};
inline std::optional<DeltaDirection> sample_delta(const Lobe& lobe, const Vec3f& wo) {
  switch (lobe.kind) {
    case LobeKind::mirror: return DeltaDirection{{-wo.x, -wo.y, wo.z}, lobe.tint * lobe.fresnel(wo.z)};
    case LobeKind::refract: {
      const auto wi = refract(wo, {0.f, 0.f, 1.f}, lobe.fresnel.eta);
      if (!wi) return std::nullopt;
      return DeltaDirection{*wi, lobe.tint * lobe.fresnel.transmit(wo.z)};
    }
    case LobeKind::straight: return DeltaDirection{-wo, lobe.tint};
    default: return std::nullopt;
  }
}

/// The non-delta mixture at wi (world space).
inline BsdfValue evaluate(const Bsdf& b, const ShadingPoint& sp, const Vec3f& wi_world) {
  const Vec3f wi = b.frame.to_local(wi_world);
  const bool transmitted = dot(wi_world, sp.ng) < 0.f;
  // The shading normal must agree with the geometric one about the side of wi (also
  // rejects NaN).
  if (!(transmitted ? wi.z < 0.f : wi.z > 0.f)) return {};
  BsdfValue result;
  for (int i = 0; i < b.count; ++i) {
    const Lobe& lobe = b.lobes[i];
    if (is_delta(lobe.kind)) continue;
    const LobeValue v = eval_lobe(lobe, b.wo, wi);
    if (!(v.pdf > 0.f)) continue;
    result.f_cos += v.f_cos * b.layer_transmittance(lobe.layers, std::abs(wi.z), !transmitted);
    result.pdf += lobe.probability * v.pdf;
  }
  if (!finite_non_negative(result.f_cos) || !std::isfinite(result.pdf)) return {};
  return result;
}

}  // namespace bsdf_detail

/// f(wo, wi)·|cos θi| of the non-delta lobes and the pdf with which sample() draws wi.
inline BsdfValue eval(const Material& m, const ShadingPoint& sp, const Vec3f& wo, const Vec3f& wi) {
  const bsdf_detail::Bsdf b = bsdf_detail::make_bsdf(m, sp, wo);
  return b.count > 0 ? bsdf_detail::evaluate(b, sp, wi) : BsdfValue{};
}

/// Draws wi: u_lobe picks the lobe, (u1, u2) the direction. nullopt: the path is absorbed.
inline std::optional<BsdfSample> sample(const Material& m, const ShadingPoint& sp, const Vec3f& wo, float u_lobe,
                                        float u1, float u2) {
  using namespace bsdf_detail;
  const Bsdf b = make_bsdf(m, sp, wo);
  if (b.count == 0) return std::nullopt;
  int chosen = 0;
  for (float cdf = b.lobes[0].probability; chosen < b.count - 1 && !(u_lobe < cdf);)
    cdf += b.lobes[++chosen].probability;
  const Lobe& lobe = b.lobes[chosen];

  if (is_delta(lobe.kind)) {
    const auto d = sample_delta(lobe, b.wo);
    if (!d) return std::nullopt;
    const bool transmitted = d->wi.z < 0.f;
    const Vec3f wi = lobe.kind == LobeKind::straight ? -wo : normalize(b.frame.to_world(d->wi));
    if ((dot(wi, sp.ng) < 0.f) != transmitted) return std::nullopt;  // bent to the wrong side by the shading normal
    const Vec3f weight = d->value * b.layer_transmittance(lobe.layers, std::abs(d->wi.z), !transmitted) /
                         lobe.probability;
    if (!finite_non_negative(weight) || !(max_component(weight) > 0.f)) return std::nullopt;
    return BsdfSample{wi, weight, lobe.probability, true, transmitted};
  }
  const auto wi_local = sample_lobe(lobe, b.wo, u1, u2);
  if (!wi_local) return std::nullopt;
  const Vec3f wi = normalize(b.frame.to_world(*wi_local));
  const BsdfValue v = evaluate(b, sp, wi);  // the mixture, exactly as eval() reports it
  if (!(v.pdf > 0.f)) return std::nullopt;
  const Vec3f weight = v.f_cos / v.pdf;
  if (!finite_non_negative(weight) || !(max_component(weight) > 0.f)) return std::nullopt;
  return BsdfSample{wi, weight, v.pdf, false, dot(wi, sp.ng) < 0.f};
}

/// Radiance emitted towards wo: luminous color·intensity (both faces), principled emissiveColor.
inline Vec3f emitted(const Material& m, const ShadingPoint& sp, const Vec3f& /*wo*/) {
  if (const auto* luminous = std::get_if<LuminousMaterial>(&m)) return luminous->color * sp.color * luminous->intensity;
  if (const auto* principled = std::get_if<PrincipledMaterial>(&m)) return principled->emissive_color;
  return splat(0.f);
}

/// A colour for the frame buffer's albedo channel (a denoiser's guide), in [0, 1].
inline Vec3f albedo(const Material& material, const ShadingPoint& sp) {
  using bsdf_detail::clamp01;
  return std::visit(
      [&](const auto& m) -> Vec3f {
        using M = std::decay_t<decltype(m)>;
        if constexpr (std::is_same_v<M, ObjMaterial>) {
          return clamp01(m.kd * sp.color);
        } else if constexpr (std::is_same_v<M, PrincipledMaterial>) {
          const float transmissive = (1.f - m.metallic) * m.transmission;
          return bsdf_detail::lerp(clamp01(m.base_color * sp.color), clamp01(m.transmission_color), transmissive);
        } else if constexpr (std::is_same_v<M, MetalMaterial>) {
          using bsdf_detail::fresnel_conductor;
          return {fresnel_conductor(1.f, m.eta.x, m.k.x), fresnel_conductor(1.f, m.eta.y, m.k.y),
                  fresnel_conductor(1.f, m.eta.z, m.k.z)};
        } else if constexpr (std::is_same_v<M, AlloyMaterial>) {
          return clamp01(m.color * sp.color);
        } else if constexpr (std::is_same_v<M, LuminousMaterial>) {
          return clamp01(m.color * sp.color);
        } else {
          return splat(1.f);  // glass, thinGlass
        }
      },
      material);
}

/// Beer-Lambert transmittance over `distance` inside the material's medium; (1,1,1) for
/// materials without one.
inline Vec3f medium_transmittance(const Material& m, float distance) {
  if (!(distance > 0.f)) return splat(1.f);
  if (const auto* glass = std::get_if<GlassMaterial>(&m))
    return bsdf_detail::pow(bsdf_detail::clamp01(glass->attenuation_color), distance / glass->attenuation_distance);
  if (const auto* p = std::get_if<PrincipledMaterial>(&m); p && p->transmission > 0.f && !p->thin)
    return bsdf_detail::pow(bsdf_detail::clamp01(p->transmission_color), distance / p->transmission_depth);
  return splat(1.f);
}

/// Whether the material has an interior medium that refracts (the path tracer tracks when
/// a path is inside): glass, and principled with transmission > 0 and !thin.
inline bool has_medium(const Material& m) {
  if (std::holds_alternative<GlassMaterial>(m)) return true;
  const auto* p = std::get_if<PrincipledMaterial>(&m);
  return p && p->transmission > 0.f && !p->thin;
}

}  // namespace sciray
