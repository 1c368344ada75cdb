#pragma once
// The lobes the path tracer's BSDFs are made of (render/bsdf.hpp builds them per
// material): their kinds, evaluation and sampling in a local frame whose z is the normal,
// and the container of one shading point's lobes with the dielectric layers over them.
//
// Layers (principled, carPaint, metallicPaint, plastic): sheen over clear coat over the
// base, and principled's specular interface over its diffuse part. As OSPRay's layers
// (after Weidlich & Wilkie 2007), a dielectric layer of weight w reflects w·F and what lies
// below it is scaled by what the layer lets through towards wo and wi, 1 - Ro and 1 - Ri,
// refraction ignored: by (1 - Ro)(1 - Ri) / (1 - R_avg) over a purely diffuse substrate,
// which gives back the light bounced between layer and substrate (Kelemen & Szirmay-Kalos
// 2001), else by min(1 - Ro, 1 - Ri) (Kulla & Conty 2017). A smooth layer reflects R = w·F;
// a rough one (OSPRay's microfacet layer) R = w·(R_ggx + s·(1 - E)), R_ggx its GGX
// reflection albedo, E a white GGX lobe's albedo and s = layer_multiple_scattering_scale:
// its reflection lobe gives back s·(1 - E) of what its microfacets scatter more than once
// (Kulla & Conty's lobe, not weighted by w, as OSPRay's). A coloured coat absorbs along
// the refracted paths through its thickness (their mean for transmitted light). The sheen
// layer passes 1 - its albedo, for wo and for reflected wi.
//
// Lobes of velvet (Minnaert, "velvety"), carPaint (Oren–Nayar) and principled's backlight
// (diffuse transmission) are OSPRay's: Minnaert 1941 as OSPRay writes it; Fujii 2012,
// "A tiny improvement of Oren-Nayar reflectance model".
#include <algorithm>
#include <array>
#include <cmath>
#include <optional>

#include "sciray/geometry/surface.hpp"
#include "sciray/math/vec.hpp"
#include "sciray/render/microfacet.hpp"

namespace sciray {

/// The local frame at a shading point, seen from the incoming ray.
struct ShadingPoint {
  Vec3f n;   ///< unit shading normal on the side of wo (interpolated: dot(n, wo) may still be <= 0)
  Vec3f ng;  ///< unit geometric normal on the side of wo (dot(ng, wo) > 0)
  bool entering = true;  ///< the ray arrived at the front face: eta is outside -> inside; false: leaving the medium
  Vec3f color{1.f, 1.f, 1.f};  ///< the geometry's own colour; multiplies the material's base colour
  float alpha = 1.f;           ///< the colour's alpha, which multiplies the material's opacity (as OSPRay)
  Vec3f p{0.f, 0.f, 0.f};      ///< the hit point in world space (where carPaint's flakes are)
  /// The normal of a coat that does not share n (carPaint's: see mapped_coat_normal), on
  /// the side of wo as n; none: the coat's normal is n.
  std::optional<Vec3f> coat_n{};
  /// The surface's texture coordinates, where a mix reads its factor map and its parts' maps.
  TexCoord<float> uv{0.f, 0.f};
  /// Where the material is anisotropic: the direction of its tangent, dP/ds (not yet
  /// perpendicular to n, not unit); zero: any tangent.
  Vec3f tangent{0.f, 0.f, 0.f};
};

struct BsdfSample {
  Vec3f wi;          ///< sampled direction towards the light, unit
  Vec3f weight;      ///< f * |cos(n, wi)| / pdf
  float pdf;         ///< solid-angle pdf of wi; for delta lobes the probability of choosing that lobe
  bool delta;        ///< a specular (Dirac) lobe: not evaluable by eval(), no MIS
  /// The lobe sent wi to the other side of the surface than wo: through the geometric
  /// surface for a delta lobe, through the shading one for others. A reflection that the
  /// shading normal sends below the geometric surface is not transmitted: it leaves on
  /// wo's side and meets the surface again (as OSPRay's).
  bool transmitted;
  bool straight = false;  ///< the straight pass-through (wi = -wo), where shadow rays pass too (transparency())
};

struct BsdfValue {
  Vec3f f_cos{0.f, 0.f, 0.f};  ///< f(wo, wi) * |cos(n, wi)| (non-delta lobes only)
  float pdf = 0.f;             ///< the solid-angle pdf with which sample() produces wi
};

namespace bsdf_detail {

enum class LobeKind {
  lambert,               ///< tint/pi, cosine-weighted sampling
  lambert_transmission,  ///< tint/pi on the far side (wi.z < 0), cosine-weighted sampling there
  oren_nayar,            ///< tint (1 + σ s/t) / (pi + (pi/2 - 2/3) σ), σ = shape (Fujii's form, as OSPRay)
  minnaert,              ///< tint/pi · max(0, wo·wi)^shape, cosine-weighted sampling
  velvety,               ///< tint/pi · sin(θo)^shape, cosine-weighted sampling
  phong,                 ///< tint (n+2)/(2 pi) cos^n around the mirror direction, n = shape
  sheen,                 ///< tint · Charlie sheen normalised to albedo <= 1, uniform hemisphere sampling
  ggx_reflect,           ///< tint · F · D G2 / (4 cos_o cos_i) (+ multiple scattering for Schlick F), alpha = shape
  ggx_refract,           ///< tint · (1 - F) through GGX microfacets, alpha = shape
  dielectric_ms,         ///< tint · what a rough interface (alpha = shape, fresnel.eta) scatters more than once
  mirror,                ///< delta: tint · F(cos_o) in the mirror direction
  refract,               ///< delta: tint · (1 - F(cos_o)) in the refracted direction
  straight,              ///< delta: tint, wi = -wo
};
inline bool is_delta(LobeKind kind) { return kind >= LobeKind::mirror; }
inline bool is_diffuse(LobeKind kind) {
  return kind == LobeKind::lambert || kind == LobeKind::lambert_transmission || kind == LobeKind::oren_nayar;
}
/// Scatters the same whatever wo: Lambert's lobes and the straight pass-through.
inline bool is_view_independent(LobeKind kind) {
  return kind == LobeKind::lambert || kind == LobeKind::lambert_transmission || kind == LobeKind::straight;
}

/// Layers of a stack above a lobe, each scaling it by what it lets through.
enum Layer : unsigned { below_sheen = 1u, below_coat = 2u, below_specular = 4u };

struct Lobe {
  LobeKind kind{};
  Vec3f tint;
  Fresnel fresnel;
  float shape = 0.f;  ///< GGX alpha, Phong exponent, sheen roughness, Oren–Nayar σ, Minnaert or velvety exponent
  unsigned layers = 0u;
  float probability = 0.f;  ///< of sample() choosing it
  int frame = 0;            ///< Bsdf::frames index: 0, the shading frame; others tilted (a normal map, a flake)
  float anisotropy = 0.f;   ///< GGX lobes: stretches alpha along the frame's tangent (anisotropic_alpha)
  /// A rough dielectric layer's reflection: the share of a white GGX lobe's lost energy it
  /// gives back (layer_multiple_scattering_scale), relative to tint.
  float layer_ms = 0.f;

  /// A GGX lobe's alpha along the frame's tangent and bitangent.
  GgxAlpha alpha() const { return anisotropic_alpha(shape, anisotropy); }
};

/// A dielectric layer over the lobes below it (OSPRay's DielectricLayer and
/// MicrofacetDielectricLayer): weight, relative index eta >= 1 from outside, GGX alpha
/// (0: smooth), and what it reflects towards wo and on average, set for one wo.
struct DielectricLayer {
  float weight = 0.f, eta = 1.f, alpha = 0.f;
  float ms_scale = 0.f;     ///< rough: layer_multiple_scattering_scale of its average Fresnel
  float reflected_o = 0.f;  ///< reflected(cos θo)
  float average = 0.f;      ///< 2 ∫ reflected(μ) μ dμ

  DielectricLayer() = default;
  DielectricLayer(float weight_, float eta_, float alpha_, float cos_o) : weight(weight_), eta(eta_), alpha(alpha_) {
    const float f_average = fresnel_dielectric_average(eta);
    if (rough()) {
      ms_scale = layer_multiple_scattering_scale(f_average, alpha);
      // OSPRay's reflection albedo table is of light arriving from outside (eta <= 1 in its terms).
      average = weight * (ggx_dielectric_average_reflectance(eta, alpha) + ms_scale * (1.f - ggx_average_albedo(alpha)));
    } else {
      average = weight * f_average;
    }
    reflected_o = reflected(cos_o);
  }
  bool rough() const { return alpha > 0.f; }
  /// What the layer reflects of light arriving at cosine c to its normal.
  float reflected(float c) const {
    if (!rough()) return weight * fresnel_dielectric(c, eta);
    return weight * (ggx_dielectric_reflectance(c, eta, alpha) + ms_scale * (1.f - ggx_albedo(c, alpha)));
  }
};

/// `n` bent towards wo until it sees wo at min_cos at least (an interpolated or mapped
/// normal may face away from it); the geometric normal where that fails (NaN).
inline Vec3f facing(const Vec3f& n, const Vec3f& wo, const Vec3f& ng) {
  const float cos_o = dot(n, wo);
  if (cos_o >= min_cos) return n;
  const Vec3f bent = n + wo * (min_cos - cos_o);
  const float len = length(bent);
  return len > 1e-6f ? bent / len : ng;
}

/// The lobes of one material at one shading point, for one wo.
struct Bsdf {
  static constexpr int max_frames = 3;
  std::array<Frame, max_frames> frames{};  ///< [0]: the shading frame, which layers and the side test use
  std::array<Vec3f, max_frames> wos{};     ///< wo in each frame (wos[0].z > 0 unless seen from below)
  int frame_count = 1;
  std::array<Lobe, 8> lobes{};  // the most a principled material needs
  int count = 0;
  // The layers, which scale the lobes below them.
  float sheen_cover = 0.f;  ///< sheen weight · max channel of the sheen colour
  float sheen_roughness = 0.f;
  DielectricLayer coat;
  float coat_thickness = 0.f;
  Vec3f coat_color{1.f, 1.f, 1.f};
  DielectricLayer specular;  ///< the dielectric interface over principled's diffuse lobes
  /// Principled's coat lies over a mix of its base's parts, which OSPRay's layer never takes
  /// for a purely diffuse substrate (as measured with its runtime: a smooth coat over a
  /// white diffuse base reflects 0.948 seen from the normal, not 0.998 as carPaint's).
  bool coat_over_mix = false;
  bool coat_over_diffuse = false, specular_over_diffuse = false;  ///< set by finish()

  const Vec3f& wo() const { return wos[0]; }
  /// Adds a frame of unit normal `normal` in which wo (world) is `wo`; its index.
  int add_frame(const Vec3f& normal, const Vec3f& wo_world) {
    frames[frame_count] = Frame(normal);
    wos[frame_count] = frames[frame_count].to_local(wo_world);
    return frame_count++;
  }

  /// Adds a lobe unless it is black. `estimate`, its albedo for wo (exact for a delta
  /// lobe, roughly for others), sets how often sample() picks it; a non-delta lobe keeps a
  /// small share when its estimate is 0, as it may still reflect towards other wi.
  void add(LobeKind kind, const Vec3f& tint, float estimate, const Fresnel& fresnel = {}, float shape = 0.f,
           unsigned layers = 0u, int frame = 0, float anisotropy = 0.f, float layer_ms = 0.f) {
    if (!(max_component(tint) > 0.f) || (is_delta(kind) && !(estimate > 0.f))) return;
    const float probability = std::max(estimate, 1e-3f * max_component(tint));
    lobes[count++] = {kind, tint, fresnel, shape, layers, probability, frame, anisotropy, layer_ms};
  }
  /// Turns the shading frame's tangent about its normal by `radians` (principled's rotation).
  void turn_tangent(float radians) {
    const Vec3f wo_world = frames[0].to_world(wos[0]);
    frames[0] = frames[0].turned(radians);
    wos[0] = frames[0].to_local(wo_world);
  }
  /// Keeps only the lobes that do not depend on wo, with no layer (whose Fresnel does)
  /// over them: those that scatter a view from below the shading normal.
  void keep_view_independent() {
    int kept = 0;
    for (int i = 0; i < count; ++i)
      if (is_view_independent(lobes[i].kind) && lobes[i].layers == 0u) lobes[kept++] = lobes[i];
    count = kept;
  }
  /// Once every lobe is in: the probabilities sum to 1, and each layer knows whether what
  /// lies below it is purely diffuse.
  void finish() {
    float total = 0.f;
    coat_over_diffuse = !coat_over_mix, specular_over_diffuse = true;
    for (int i = 0; i < count; ++i) {
      total += lobes[i].probability;
      if (!is_diffuse(lobes[i].kind)) {
        if (lobes[i].layers & below_coat) coat_over_diffuse = false;
        if (lobes[i].layers & below_specular) specular_over_diffuse = false;
      }
    }
    for (int i = 0; i < count; ++i) lobes[i].probability /= total;
  }

  /// What the layers above a lobe let through towards wo and towards wi, whose cosine to
  /// the shading normal is cos_i (negative: transmitted).
  Vec3f layer_transmittance(unsigned layers, float cos_i) const {
    const float cos_o = wo().z, abs_i = std::abs(cos_i);
    const bool reflected = cos_i > 0.f;
    float through = 1.f;
    Vec3f absorbed = splat(1.f);
    if (layers & below_sheen) {
      const float albedo_o = sheen_albedo(cos_o, sheen_roughness);
      const float albedo = reflected ? std::max(albedo_o, sheen_albedo(abs_i, sheen_roughness)) : albedo_o;
      through *= 1.f - sheen_cover * std::min(albedo, 1.f);
    }
    if (layers & below_coat) {
      through *= dielectric_layer(coat, coat.reflected(abs_i), coat_over_diffuse);
      // The absorbing path runs along the directions refracted by the macroscopic surface.
      const float path = (1.f / refracted_cosine(cos_o, coat.eta) + 1.f / refracted_cosine(abs_i, coat.eta)) *
                         (reflected ? 1.f : 0.5f);
      absorbed = lerp(splat(1.f), pow(coat_color, coat_thickness * path), coat.weight);
    }
    if (layers & below_specular) through *= dielectric_layer(specular, specular.reflected(abs_i), specular_over_diffuse);
    return absorbed * through;
  }
  /// What the layers above a lobe let through towards wo, averaged over the channels: the
  /// lobe-choice estimate.
  float outer(unsigned layers) const {
    const float cos_o = wo().z;
    float through = 1.f;
    if (layers & below_sheen) through *= 1.f - sheen_cover * std::min(sheen_albedo(cos_o, sheen_roughness), 1.f);
    if (layers & below_coat) through *= 1.f - coat.reflected_o;
    if (layers & below_specular) through *= 1.f - specular.reflected_o;
    return through;
  }

private:
  static float dielectric_layer(const DielectricLayer& layer, float reflected_i, bool over_diffuse) {
    const float r_o = layer.reflected_o;
    if (over_diffuse) return (1.f - r_o) * (1.f - reflected_i) / std::max(1.f - layer.average, min_cos);
    return std::min(1.f - r_o, 1.f - reflected_i);
  }
  /// cos θ of a direction at cosine c refracted into a layer of index eta >= 1, at least min_cos.
  static float refracted_cosine(float c, float eta) {
    return std::max(std::sqrt(std::max(0.f, 1.f - (1.f - c * c) / (eta * eta))), min_cos);
  }
};

// ---- Per-lobe sampling and evaluation, local frame --------------------------------------

struct LobeValue {
  Vec3f f_cos{0.f, 0.f, 0.f};
  float pdf = 0.f;
};

/// Cosine-weighted direction on the hemisphere around +z.
inline Vec3f sample_cosine(float u1, float u2) {
  const float r = std::sqrt(u1), phi = 2.f * pi * u2;
  return Vec3f{r * std::cos(phi), r * std::sin(phi), std::sqrt(std::max(0.f, 1.f - u1))};
}

inline LobeValue eval_lobe(const Lobe& lobe, const Vec3f& wo, const Vec3f& wi) {
  switch (lobe.kind) {
    case LobeKind::lambert:
      if (!(wi.z > 0.f)) return {};
      return {lobe.tint * (wi.z / pi), wi.z / pi};
    case LobeKind::lambert_transmission:
      if (!(wi.z < 0.f)) return {};
      return {lobe.tint * (-wi.z / pi), -wi.z / pi};
    case LobeKind::oren_nayar: {
      if (!(wi.z > 0.f)) return {};
      const float sigma = lobe.shape, s = dot(wo, wi) - wo.z * wi.z;
      const float s_over_t = s > 0.f ? s / std::max(wo.z, wi.z) : s;
      return {lobe.tint * (wi.z * (1.f + sigma * s_over_t) / (pi + (pi / 2.f - 2.f / 3.f) * sigma)), wi.z / pi};
    }
    case LobeKind::minnaert: {
      const float c = dot(wo, wi);
      if (!(wi.z > 0.f)) return {};
      // Towards the back half-space (wo·wi <= 0) it reflects nothing, even with exponent 0
      // (OSPRay's, as measured with its runtime).
      const float back = c > 0.f ? std::pow(c, lobe.shape) : 0.f;
      return {lobe.tint * (back * wi.z / pi), wi.z / pi};
    }
    case LobeKind::velvety: {
      if (!(wi.z > 0.f)) return {};
      const float sin_o = std::sqrt(std::max(0.f, 1.f - wo.z * wo.z));
      return {lobe.tint * (std::pow(sin_o, lobe.shape) * wi.z / pi), wi.z / pi};
    }
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
      const GgxAlpha alpha = lobe.alpha();
      const Vec3f h = normalize(wo + wi);
      const float d = ggx_d(h, alpha);
      const float f_cos = d * ggx_g2(wo, wi, alpha) / (4.f * wo.z);
      Vec3f f = lobe.fresnel(dot(wo, h)) * f_cos;
      // Energy compensation by the isotropic albedo of the lobe's roughness (as OSPRay's).
      if (lobe.fresnel.kind == Fresnel::Kind::schlick)
        f += ggx_multiple_scattering(lobe.fresnel.average(), wo.z, wi.z, lobe.shape);
      else if (lobe.layer_ms > 0.f)
        f += splat(lobe.layer_ms * ggx_lost_energy(wo.z, wi.z, lobe.shape));
      return {lobe.tint * f, ggx_g1(wo, alpha) * d / (4.f * wo.z)};
    }
    case LobeKind::ggx_refract: {
      if (!(wi.z < 0.f)) return {};
      const GgxAlpha alpha = lobe.alpha();
      const float eta = lobe.fresnel.eta;
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
    case LobeKind::dielectric_ms: {
      if (!(wi.z != 0.f)) return {};
      const float eta = lobe.fresnel.eta, alpha = lobe.shape;
      float pdf;
      const float f_cos = dielectric_multiple_scattering(wo.z, eta, alpha).f_cos(wi.z, eta, alpha, &pdf);
      return {lobe.tint * f_cos, pdf};
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
    case LobeKind::lambert:
    case LobeKind::oren_nayar:
    case LobeKind::minnaert:
    case LobeKind::velvety: return sample_cosine(u1, u2);
    case LobeKind::lambert_transmission: return -sample_cosine(u1, u2);
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
      const Vec3f wi = reflect(wo, sample_ggx_visible_normal(wo, lobe.alpha(), u1, u2));
      if (!(wi.z > 0.f)) return std::nullopt;
      return wi;
    }
    case LobeKind::ggx_refract: {
      const auto wi = refract(wo, sample_ggx_visible_normal(wo, lobe.alpha(), u1, u2), lobe.fresnel.eta);
      if (!wi || !(wi->z < 0.f)) return std::nullopt;
      return wi;
    }
    case LobeKind::dielectric_ms: {
      // u1 picks the side by the reflected share, then serves the cosine lobe there.
      const float reflected = dielectric_multiple_scattering(wo.z, lobe.fresnel.eta, lobe.shape).reflected;
      if (u1 < reflected) return sample_cosine(u1 / reflected, u2);
      return -sample_cosine((u1 - reflected) / (1.f - reflected), u2);
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

}  // namespace bsdf_detail
}  // namespace sciray
