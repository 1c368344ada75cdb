#pragma once
// Physically based BSDFs for every material type of material.hpp, one shading point at a
// time in scalar float, for the path tracer.
//
// Conventions: wo points from the surface to where the path came from (-ray.dir), wi to
// where the light comes from; both unit. eval() gives f·|cos θi| and the solid-angle pdf
// with which sample() draws wi; sample() gives the throughput weight f·|cos θi| / pdf.
//
// A material is a short list of lobes (render/bsdf_lobes.hpp), built for one wo
// (make_bsdf). sample() picks a lobe with a probability proportional to an estimate of its
// albedo for wo, draws a direction from it and, if the lobe is not a delta lobe, weights
// that direction by the whole mixture: the sum of every non-delta lobe's f over the sum of
// their probability-weighted pdfs (one-sample MIS, Veach 1997), which is exactly what
// eval() reports. Delta lobes (mirror, smooth refraction, straight pass-through) are
// invisible to eval(); their pdf is the probability of picking them.
//
// Layers (principled, and the paints of render/bsdf_paint.hpp) follow OSPRay's: see
// render/bsdf_lobes.hpp. Light bouncing between a layer and anything but a diffuse
// substrate is ignored. As OSPRay's, GGX lobes of Schlick Fresnel (alloy, principled's
// metal, the paints' flakes), rough glass, rough coats and principled's rough specular
// layer get the energy of multiple scattering between microfacets back; conductors of
// given eta and k do not (neither do OSPRay's).
//
// A mix (MixMaterial) is not one list of lobes but its two parts' BSDFs, each with its own
// layers, weighted by 1 - factor and factor, as OSPRay's MultiBSDF: eval() sums them so
// weighted; sample() picks a part in that proportion and weights a non-delta direction by
// the whole mix.
//
// Shading normals (interpolated, or tilted by a normal map) are followed as OSPRay 3.1's
// are, as measured with its runtime: a surface seen from below its shading normal (but
// from above the geometric surface) keeps that normal, and only the lobes that do not
// depend on wo scatter (Lambert's, the straight pass-through; OSPRay's other BSDFs give
// nothing for such a view); a normal that sees wo at a grazing angle bends towards it. A
// non-delta lobe's direction on the reflected side of the shading normal but below the
// geometric surface is a reflection all the same: the path tracer sends it off wo's side,
// so it meets the surface again and scatters anew (the shading normal's white furnace
// holds). eval() takes light only from the side of the geometric surface that the shading
// normal agrees with: nothing reaches wo through the surface.
//
// Refraction does not scale radiance by 1/eta² (neither does OSPRay): the weights are
// those of importance transport, so a path that enters and leaves a glass body keeps its
// throughput.
//
// References: see render/microfacet.hpp; Lafortune & Willems 1994 (energy-normalised Phong).
#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <utility>
#include <variant>

#include "sciray/math/vec.hpp"
#include "sciray/render/bsdf_lobes.hpp"
#include "sciray/render/bsdf_paint.hpp"
#include "sciray/render/material.hpp"

namespace sciray {

namespace bsdf_detail {

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
/// smooth) reflection and refraction, weighted by `weight`; rough, also what its
/// microfacets scatter more than once (as OSPRay's microfacet dielectric).
inline void add_interface(Bsdf& b, float eta, float specular, float alpha, float weight, float anisotropy = 0.f) {
  const Fresnel fresnel{Fresnel::Kind::dielectric, eta, specular};
  const float cos_o = b.wo().z;
  const bool rough = alpha >= min_alpha && std::abs(eta - 1.f) >= min_eta_contrast;
  if (!rough) {
    if (reflects(fresnel)) b.add(LobeKind::mirror, splat(weight), weight * fresnel(cos_o).x, fresnel, alpha);
    b.add(LobeKind::refract, splat(weight), weight * fresnel.transmit(cos_o), fresnel, alpha);
    return;
  }
  // Rough: the shares of the microfacets, not of the smooth interface, pick the lobes
  // (past the critical angle a smooth interface refracts nothing, a rough one much).
  const float albedo = ggx_dielectric_albedo(cos_o, eta, alpha), up = ggx_dielectric_reflectance(cos_o, eta, alpha);
  if (reflects(fresnel)) b.add(LobeKind::ggx_reflect, splat(weight), weight * up, fresnel, alpha, 0u, 0, anisotropy);
  b.add(LobeKind::ggx_refract, splat(weight), weight * std::max(albedo - up, 0.f), fresnel, alpha, 0u, 0, anisotropy);
  b.add(LobeKind::dielectric_ms, splat(weight), weight * (1.f - albedo), fresnel, alpha);
}

inline void build(Bsdf& b, const PrincipledMaterial& m, const ShadingPoint& sp) {
  const float cos_o = b.wo().z;
  const float opacity = m.opacity * sp.alpha;
  b.add(LobeKind::straight, splat(1.f - opacity), 1.f - opacity);  // cut-out
  const float alpha = m.roughness * m.roughness;
  const LobeKind reflection = alpha >= min_alpha ? LobeKind::ggx_reflect : LobeKind::mirror;
  const float dielectric = 1.f - m.metallic;
  // The base's microfacets (specular, glass, metal; not the coat's) stretch along the
  // tangent, turned by rotation (OSPRay's).
  const float anisotropy = m.anisotropy;
  if (anisotropy > 0.f && m.rotation > 0.f) b.turn_tangent(2.f * pi * m.rotation);

  if (!sp.entering && !m.thin && m.transmission > 0.f) {
    // From inside the body only its interface is met.
    add_interface(b, 1.f / m.ior, m.specular, alpha, opacity, anisotropy);
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
    const float coat_alpha = m.coat_roughness * m.coat_roughness;
    const bool rough_coat = coat_alpha >= min_alpha;
    b.coat = DielectricLayer(m.coat, m.coat_ior, rough_coat ? coat_alpha : 0.f, cos_o);
    b.coat_thickness = m.coat_thickness, b.coat_color = clamp01(m.coat_color), b.coat_over_mix = true;
    const Fresnel fresnel{Fresnel::Kind::dielectric, m.coat_ior, m.coat};
    if (reflects(fresnel))
      b.add(rough_coat ? LobeKind::ggx_reflect : LobeKind::mirror, splat(opacity),
            b.outer(under) * opacity * b.coat.reflected_o, fresnel, coat_alpha, under, 0, 0.f, b.coat.ms_scale);
    under |= below_coat;
  }
  const float outer = b.outer(under);

  if (dielectric > 0.f) {
    b.specular = DielectricLayer(m.specular, m.ior, reflection == LobeKind::ggx_reflect ? alpha : 0.f, cos_o);
    const Fresnel specular{Fresnel::Kind::dielectric, m.ior, m.specular};
    const float transmission = m.transmission;
    // The interface reflects alike over the diffuse and over the transmissive part, except
    // for a thin sheet, whose second face reflects too. Only over the diffuse part is it
    // OSPRay's layer, whose reflection gives back what its microfacets scatter more than
    // once (rough glass has its dielectric_ms lobe).
    const float plain_reflection = m.thin ? 1.f - transmission : 1.f;
    if (reflects(specular))
      b.add(reflection, splat(opacity * dielectric * plain_reflection),
            outer * opacity * dielectric * plain_reflection * b.specular.reflected_o, specular, alpha, under, 0,
            anisotropy, b.specular.ms_scale * (1.f - transmission) / plain_reflection);
    // The diffuse part, rough as Oren–Nayar, of which a thin sheet transmits backlight/2 (as
    // OSPRay's).
    const Vec3f diffuse = base * (opacity * dielectric * (1.f - transmission) * m.diffuse);
    const float backlit = m.thin ? 0.5f * std::clamp(m.backlight, 0.f, 2.f) : 0.f;
    const float diffuse_outer = b.outer(under | below_specular);
    b.add(m.roughness > 0.f ? LobeKind::oren_nayar : LobeKind::lambert, diffuse * (1.f - backlit),
          diffuse_outer * (1.f - backlit) * mean(diffuse), {}, m.roughness, under | below_specular);
    b.add(LobeKind::lambert_transmission, diffuse * backlit, diffuse_outer * backlit * mean(diffuse), {}, 0.f,
          under | below_specular);
    if (transmission > 0.f) {
      const float weight = opacity * dielectric * transmission;
      if (m.thin) {
        // Thin: no bending, like thinGlass; reflection and transmission of the whole sheet
        // at the macroscopic angle (reflection keeps its GGX shape).
        const SheetResponse sheet = thin_sheet(cos_o, m.ior, m.specular, clamp01(m.transmission_color),
                                               m.thickness / std::max(m.transmission_depth, min_depth));
        b.add(reflection, sheet.r * weight, outer * weight * mean(sheet.r), {}, alpha, under, 0, anisotropy);
        b.add(LobeKind::straight, sheet.t * weight, outer * weight * mean(sheet.t), {}, 0.f, under);
      } else {
        const bool rough = alpha >= min_alpha && std::abs(m.ior - 1.f) >= min_eta_contrast;
        const float albedo = rough ? ggx_dielectric_albedo(cos_o, m.ior, alpha) : 1.f;
        const float through = rough ? std::max(albedo - ggx_dielectric_reflectance(cos_o, m.ior, alpha), 0.f)
                                    : specular.transmit(cos_o);
        b.add(rough ? LobeKind::ggx_refract : LobeKind::refract, splat(weight), outer * weight * through, specular,
              alpha, under, 0, anisotropy);
        if (rough) b.add(LobeKind::dielectric_ms, splat(weight), outer * weight * (1.f - albedo), specular, alpha, under);
      }
    }
  }
  if (m.metallic > 0.f) {
    const Fresnel metal{Fresnel::Kind::schlick, 1.f, 1.f, base, clamp01(m.edge_color)};
    b.add(reflection, splat(opacity * m.metallic), outer * opacity * m.metallic * mean(metal(cos_o)), metal, alpha,
          under, 0, anisotropy);
  }
}

inline void build(Bsdf& b, const GlassMaterial& m, const ShadingPoint& sp) {
  add_interface(b, sp.entering ? m.eta : 1.f / m.eta, 1.f, 0.f, 1.f);
}

inline void build(Bsdf& b, const ThinGlassMaterial& m, const ShadingPoint& sp) {
  // The geometry's colour tints the sheet as attenuationColor does (OSPRay's thinGlass).
  const SheetResponse sheet = thin_sheet(b.wo().z, m.eta, 1.f, clamp01(m.attenuation_color * sp.color),
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
  // The shading frame is the outermost layer's: a coat with a normal of its own has it.
  const Vec3f n = sp.coat_n.value_or(sp.n);
  const bool from_below = dot(n, wo) <= 0.f;
  b.frames[0] = Frame(from_below ? n : facing(n, wo, sp.ng), sp.tangent);
  b.wos[0] = b.frames[0].to_local(wo);
  if (!from_below && !(b.wo().z > 0.f)) return b;
  std::visit(
      [&](const auto& m) {
        // eval() and sample() take a mix apart into its parts before they build lobes.
        if constexpr (!std::is_same_v<std::decay_t<decltype(m)>, MixMaterial>) build(b, m, sp);
      },
      material);
  if (from_below) b.keep_view_independent();
  b.finish();
  return b;
}

/// The non-delta mixture at wi (world space), of the lobes that scatter to the side of the
/// shading normal `transmitted` names.
inline BsdfValue evaluate(const Bsdf& b, const Vec3f& wi_world, bool transmitted) {
  std::array<Vec3f, Bsdf::max_frames> wi;
  for (int k = 0; k < b.frame_count; ++k) wi[k] = b.frames[k].to_local(wi_world);
  if (!(transmitted ? wi[0].z < 0.f : wi[0].z > 0.f)) return {};  // (also rejects NaN)
  BsdfValue result;
  for (int i = 0; i < b.count; ++i) {
    const Lobe& lobe = b.lobes[i];
    if (is_delta(lobe.kind)) continue;
    const LobeValue v = eval_lobe(lobe, b.wos[lobe.frame], wi[lobe.frame]);
    if (!(v.pdf > 0.f)) continue;
    result.f_cos += v.f_cos * b.layer_transmittance(lobe.layers, wi[0].z);
    result.pdf += lobe.probability * v.pdf;
  }
  if (!finite_non_negative(result.f_cos) || !std::isfinite(result.pdf)) return {};
  return result;
}

/// A mix's factor at the shading point: `factor` times its map's first channel, which is
/// clamped to [0, 1] (as OSPRay's).
inline float mix_factor(const MixMaterial& mix, const ShadingPoint& sp) {
  return mix.map_factor ? mix.factor * std::clamp(mix.map_factor.at(sp.uv).x, 0.f, 1.f) : mix.factor;
}

/// Calls f(part, weight) for each part of `mix` that has weight (1 - factor for material1,
/// factor for material2), the part's maps read at the shading point.
template <class Fn>
void for_each_mix_part(const MixMaterial& mix, const ShadingPoint& sp, Fn&& f) {
  const float factor = mix_factor(mix, sp);
  const std::pair<const MixPart*, float> parts[] = {{mix.material1.get(), 1.f - factor}, {mix.material2.get(), factor}};
  for (const auto& [part, weight] : parts) {
    if (!(weight > 0.f)) continue;
    Material storage;
    f(textured(part->material, sp.uv, storage), weight);
  }
}

/// eval() of the lobes that scatter to the side of the shading normal `transmitted` names.
inline BsdfValue eval_towards(const Material& m, const ShadingPoint& sp, const Vec3f& wo, const Vec3f& wi,
                              bool transmitted) {
  if (const auto* mix = std::get_if<MixMaterial>(&m)) {
    // The parts' weights sum to 1, so the weighted pdfs are the pdf of picking a part by
    // its weight and then sampling it.
    BsdfValue sum;
    for_each_mix_part(*mix, sp, [&](const Material& part, float weight) {
      const BsdfValue v = eval_towards(part, sp, wo, wi, transmitted);
      sum.f_cos += v.f_cos * weight;
      sum.pdf += v.pdf * weight;
    });
    return sum;
  }
  const Bsdf b = make_bsdf(m, sp, wo);
  return b.count > 0 ? evaluate(b, wi, transmitted) : BsdfValue{};
}

}  // namespace bsdf_detail

/// f(wo, wi)·|cos θi| of the non-delta lobes and the pdf with which sample() draws wi:
/// light from a side of the geometric surface that the shading normal disagrees about
/// does not reach wo.
inline BsdfValue eval(const Material& m, const ShadingPoint& sp, const Vec3f& wo, const Vec3f& wi) {
  return bsdf_detail::eval_towards(m, sp, wo, wi, dot(wi, sp.ng) < 0.f);
}

/// Draws wi: u_lobe picks the lobe, (u1, u2) the direction. nullopt: the path is absorbed.
inline std::optional<BsdfSample> sample(const Material& m, const ShadingPoint& sp, const Vec3f& wo, float u_lobe,
                                        float u1, float u2) {
  using namespace bsdf_detail;
  if (const auto* mix = std::get_if<MixMaterial>(&m)) {
    // u_lobe picks the part by its weight and, rescaled, the part's lobe.
    const float factor = mix_factor(*mix, sp);
    const bool second = !(u_lobe < 1.f - factor);
    const float picked = second ? factor : 1.f - factor;
    const float u_part = std::min((second ? u_lobe - (1.f - factor) : u_lobe) / picked, 0x1.fffffep-1f);
    Material storage;
    const Material& part = textured((second ? mix->material2 : mix->material1)->material, sp.uv, storage);
    std::optional<BsdfSample> s = sample(part, sp, wo, u_part, u1, u2);
    if (!s) return std::nullopt;
    // A delta direction only this part has: the pick's probability cancels the part's weight.
    if (s->delta) {
      s->pdf *= picked;
      return s;
    }
    const BsdfValue v = eval_towards(m, sp, wo, s->wi, s->transmitted);  // the whole mix, as eval() reports it
    if (!(v.pdf > 0.f)) return std::nullopt;
    s->weight = v.f_cos / v.pdf;
    s->pdf = v.pdf;
    if (!finite_non_negative(s->weight) || !(max_component(s->weight) > 0.f)) return std::nullopt;
    return s;
  }
  const Bsdf b = make_bsdf(m, sp, wo);
  if (b.count == 0) return std::nullopt;
  int chosen = 0;
  for (float cdf = b.lobes[0].probability; chosen < b.count - 1 && !(u_lobe < cdf);)
    cdf += b.lobes[++chosen].probability;
  const Lobe& lobe = b.lobes[chosen];

  const Frame& frame = b.frames[lobe.frame];
  if (is_delta(lobe.kind)) {
    const auto d = sample_delta(lobe, b.wos[lobe.frame]);
    if (!d) return std::nullopt;
    const bool straight = lobe.kind == LobeKind::straight;
    const bool transmitted = straight || d->wi.z < 0.f;
    const Vec3f wi = straight ? -wo : normalize(frame.to_world(d->wi));
    // Bent to the wrong side by the shading normal (or a flake's); straight on passes
    // through whatever the shading normal.
    const float cos_i = dot(wi, b.frames[0].n);
    if ((dot(wi, sp.ng) < 0.f) != transmitted || (!straight && (cos_i < 0.f) != transmitted)) return std::nullopt;
    const Vec3f weight = d->value * b.layer_transmittance(lobe.layers, cos_i) / lobe.probability;
    if (!finite_non_negative(weight) || !(max_component(weight) > 0.f)) return std::nullopt;
    return BsdfSample{wi, weight, lobe.probability, true, transmitted, lobe.kind == LobeKind::straight};
  }
  const auto wi_local = sample_lobe(lobe, b.wos[lobe.frame], u1, u2);
  if (!wi_local) return std::nullopt;
  const Vec3f wi = normalize(frame.to_world(*wi_local));
  // The side of the shading normal wi is on, not of the geometric surface: a reflection
  // below the latter meets the surface again.
  const bool transmitted = dot(wi, b.frames[0].n) < 0.f;
  const BsdfValue v = evaluate(b, wi, transmitted);  // the mixture, as eval() reports it on that side
  if (!(v.pdf > 0.f)) return std::nullopt;
  const Vec3f weight = v.f_cos / v.pdf;
  if (!finite_non_negative(weight) || !(max_component(weight) > 0.f)) return std::nullopt;
  return BsdfSample{wi, weight, v.pdf, false, transmitted};
}

/// What a shadow ray meeting the surface along -wo lets through: the weight of the
/// straight pass-through lobes (cut-out opacity, obj's filter tf, thin sheets, luminous
/// transparency; a mix's parts weighted), which is exactly what sample() carries straight
/// on, on average. So light sampled through the surface and light that BSDF sampling finds
/// past it are one estimator's two halves (as OSPRay's transparent shadows, whose
/// getTransparency gives the same filters). Refraction bends the light: it lets no shadow
/// ray through (OSPRay's glass passes 1 - Fresnel straight on, a shadow without caustic).
inline Vec3f transparency(const Material& m, const ShadingPoint& sp, const Vec3f& wo) {
  using namespace bsdf_detail;
  if (const auto* mix = std::get_if<MixMaterial>(&m)) {
    Vec3f sum{0.f, 0.f, 0.f};
    for_each_mix_part(*mix, sp, [&](const Material& part, float weight) { sum += transparency(part, sp, wo) * weight; });
    return sum;
  }
  const Bsdf b = make_bsdf(m, sp, wo);
  Vec3f through{0.f, 0.f, 0.f};
  for (int i = 0; i < b.count; ++i) {
    const Lobe& lobe = b.lobes[i];
    // As sample() takes the lobe: forward in its frame, and -wo behind the shading normal.
    if (lobe.kind != LobeKind::straight || !(b.wos[lobe.frame].z > 0.f)) continue;
    const Vec3f weight = lobe.tint * b.layer_transmittance(lobe.layers, -b.wo().z);
    if (finite_non_negative(weight)) through += weight;
  }
  return through;
}

/// Whether transparency() can let anything through the material (the geometry's colours'
/// alpha aside, which cuts out obj and principled surfaces too).
inline bool may_pass_straight(const Material& material) {
  return std::visit(
      [](const auto& m) -> bool {
        using M = std::decay_t<decltype(m)>;
        if constexpr (std::is_same_v<M, ObjMaterial>)
          return m.d < 1.f || bsdf_detail::max_component(m.tf) > 0.f || m.map_d || m.map_kd.alpha;
        else if constexpr (std::is_same_v<M, PrincipledMaterial>)
          return m.opacity < 1.f || m.map_opacity || m.map_base_color.alpha ||
                 (m.thin && (m.transmission > 0.f || m.map_transmission));
        else if constexpr (std::is_same_v<M, ThinGlassMaterial>)
          return true;
        else if constexpr (std::is_same_v<M, LuminousMaterial>)
          return m.transparency > 0.f;
        else if constexpr (std::is_same_v<M, MixMaterial>)
          return may_pass_straight(m.material1->material) || may_pass_straight(m.material2->material);
        else
          return false;
      },
      material);
}

/// Radiance emitted towards wo: luminous color·intensity (both faces), principled
/// emissiveColor, a mix's parts' weighted by its plain `factor` (OSPRay's: not by map_factor).
inline Vec3f emitted(const Material& m, const ShadingPoint& sp, const Vec3f& wo) {
  if (const auto* mix = std::get_if<MixMaterial>(&m)) {
    Material storage1, storage2;
    return emitted(textured(mix->material1->material, sp.uv, storage1), sp, wo) * (1.f - mix->factor) +
           emitted(textured(mix->material2->material, sp.uv, storage2), sp, wo) * mix->factor;
  }
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
        } else if constexpr (std::is_same_v<M, VelvetMaterial>) {
          return clamp01(m.reflectance + m.horizon_scattering_color);
        } else if constexpr (std::is_same_v<M, MetallicPaintMaterial> || std::is_same_v<M, CarPaintMaterial>) {
          return clamp01(m.base_color * sp.color);
        } else if constexpr (std::is_same_v<M, PlasticMaterial>) {
          return clamp01(m.pigment_color);
        } else if constexpr (std::is_same_v<M, MixMaterial>) {
          Vec3f sum{0.f, 0.f, 0.f};
          bsdf_detail::for_each_mix_part(m, sp, [&](const Material& part, float weight) {
            sum += albedo(part, sp) * weight;
          });
          return sum;
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
    return bsdf_detail::pow(bsdf_detail::clamp01(p->transmission_color),
                            distance / std::max(p->transmission_depth, bsdf_detail::min_depth));
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
