#pragma once
// The lobes of OSPRay's cloth, paint and plastic materials (velvet, metallicPaint,
// carPaint, plastic) and carPaint's flakes, for render/bsdf.hpp's make_bsdf. Parameters are
// read as OSPRay's materials read them: clamped where OSPRay clamps, roughness squared to
// GGX alpha (at least 1e-3, as OSPRay's), a coat index below 1 inverted.
//
// carPaint's flakes: the hit point, in cells of 1/flakeScale world units, finds the
// nearest of the cells' jittered feature points (Worley's cellular noise, as OSPRay's,
// after Apodaca & Gritz 1999, "Advanced RenderMan", pp. 255-261); that cell holds a flake
// with probability flakeDensity, its normal drawn from a Beckmann distribution of
// roughness flakeSpread. The cell hash and random numbers are sciray's own, so single
// flakes lie elsewhere than in OSPRay's images; their density and normals are distributed
// alike.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>

#include "sciray/math/vec.hpp"
#include "sciray/render/bsdf_lobes.hpp"
#include "sciray/render/material.hpp"

namespace sciray::bsdf_detail {

/// Below this OSPRay's paints take a weight, density or roughness as 0.
inline constexpr float paint_epsilon = 1e-5f;

/// GGX alpha of a paint's roughness, as OSPRay's microfacets: squared, at least 1e-3.
inline float paint_alpha(float roughness) { return std::max(roughness * roughness, 1e-3f); }

/// Random numbers of one flake cell: a hash of its integer coordinates, then a linear
/// congruential stream, each output finalised by MurmurHash3's mixer.
class CellRandom {
public:
  CellRandom(std::int64_t x, std::int64_t y, std::int64_t z)
      : state_(mix(static_cast<std::uint32_t>(x) * 0x8da6b343u ^ static_cast<std::uint32_t>(y) * 0xd8163841u ^
                   static_cast<std::uint32_t>(z) * 0xcb1ab31fu)) {}
  float next() {
    state_ = state_ * 747796405u + 2891336453u;
    return static_cast<float>(mix(state_) >> 8) * 0x1p-24f;
  }

private:
  static std::uint32_t mix(std::uint32_t h) {
    h ^= h >> 16, h *= 0x85ebca6bu, h ^= h >> 13, h *= 0xc2b2ae35u, h ^= h >> 16;
    return h;
  }
  std::uint32_t state_;
};

/// The normal of the flake at world point p, in a frame whose z is the surface normal;
/// nullopt where no flake is (see the header).
inline std::optional<Vec3f> flake_normal(const Vec3f& p, float scale, float density, float spread, float jitter) {
  if (!(density > 0.f) || !(spread > 0.f)) return std::nullopt;
  const Vec3f q = p * scale;
  // Cells are addressed by 64-bit integers: far from the origin they wrap, never overflow.
  constexpr float reach = 1e18f;
  if (!(std::abs(q.x) < reach && std::abs(q.y) < reach && std::abs(q.z) < reach)) return std::nullopt;
  const std::int64_t cx = static_cast<std::int64_t>(std::floor(q.x)), cy = static_cast<std::int64_t>(std::floor(q.y)),
                     cz = static_cast<std::int64_t>(std::floor(q.z));
  float nearest = std::numeric_limits<float>::infinity();
  std::int64_t best[3] = {cx, cy, cz};
  for (int i = -1; i <= 1; ++i)
    for (int j = -1; j <= 1; ++j)
      for (int k = -1; k <= 1; ++k) {
        CellRandom random(cx + i, cy + j, cz + k);
        const Vec3f centre{static_cast<float>(cx + i) + 0.5f, static_cast<float>(cy + j) + 0.5f,
                           static_cast<float>(cz + k) + 0.5f};
        const Vec3f feature = centre + Vec3f{random.next() - 0.5f, random.next() - 0.5f, random.next() - 0.5f} * jitter;
        const Vec3f d = feature - q;
        if (const float d2 = dot(d, d); d2 < nearest) nearest = d2, best[0] = cx + i, best[1] = cy + j, best[2] = cz + k;
      }
  CellRandom random(best[0], best[1], best[2]);
  random.next(), random.next(), random.next();  // the feature point's
  if (!(random.next() < density)) return std::nullopt;
  // A Beckmann normal: tan²θ = -alpha² ln(1 - u1), φ = 2π u2.
  const float alpha = paint_alpha(spread), u1 = random.next(), u2 = random.next();
  const float tan2 = -alpha * alpha * std::log1p(-u1);
  const float cos_t = 1.f / std::sqrt(1.f + tan2), sin_t = std::sqrt(std::max(0.f, 1.f - cos_t * cos_t));
  const float phi = 2.f * pi * u2;
  return Vec3f{sin_t * std::cos(phi), sin_t * std::sin(phi), cos_t};
}

inline void build(Bsdf& b, const VelvetMaterial& m, const ShadingPoint&) {
  const float sin_o = std::sqrt(std::max(0.f, 1.f - b.wo().z * b.wo().z));
  b.add(LobeKind::minnaert, m.reflectance, mean(m.reflectance), {}, m.back_scattering);
  b.add(LobeKind::velvety, m.horizon_scattering_color,
        mean(m.horizon_scattering_color) * std::pow(sin_o, m.horizon_scattering_fall_off), {},
        m.horizon_scattering_fall_off);
}

/// A clear coat of weight `coat`, index `ior` and `roughness` (below paint_epsilon:
/// smooth) over the lobes added after it with `below_coat`; absorbing towards `color` over
/// `thickness`. The layers they lie under.
inline unsigned add_coat(Bsdf& b, float coat, float ior, const Vec3f& color, float thickness, float roughness = 0.f) {
  const bool smooth = roughness < paint_epsilon;
  const float alpha = smooth ? 0.f : paint_alpha(roughness);
  b.coat = DielectricLayer(coat, ior, alpha, b.wo().z);
  b.coat_color = color, b.coat_thickness = thickness;
  const Fresnel fresnel{Fresnel::Kind::dielectric, ior, coat};
  b.add(smooth ? LobeKind::mirror : LobeKind::ggx_reflect, splat(1.f), b.coat.reflected_o, fresnel, alpha, 0u, 0, 0.f,
        b.coat.ms_scale);
  return below_coat;
}

inline void build(Bsdf& b, const MetallicPaintMaterial& m, const ShadingPoint& sp) {
  const float cos_o = b.wo().z;
  // OSPRay's layer takes eta and 1/eta alike.
  const unsigned under = add_coat(b, 1.f, m.eta >= 1.f ? m.eta : 1.f / m.eta, splat(1.f), 1.f);
  const float outer = b.outer(under);
  const Vec3f color = m.base_color * sp.color * (1.f - m.flake_amount);
  b.add(LobeKind::lambert, color, outer * mean(color), {}, 0.f, under);
  if (m.flake_amount > 0.f) {
    const Fresnel flakes{Fresnel::Kind::schlick, 1.f, 1.f, m.flake_color * m.flake_amount, splat(m.flake_amount)};
    b.add(LobeKind::ggx_reflect, splat(1.f), outer * mean(flakes(cos_o)), flakes, paint_alpha(m.flake_spread), under);
  }
}

inline void build(Bsdf& b, const CarPaintMaterial& m, const ShadingPoint& sp) {
  const Vec3f wo = b.frames[0].to_world(b.wo());
  // Flakes lie along the coat's normal, the shading frame.
  std::optional<Vec3f> flake;
  if (const float density = std::clamp(m.flake_density, 0.f, 1.f); density > paint_epsilon)
    if (const auto local = flake_normal(sp.p, std::max(m.flake_scale, 0.f), density, std::max(m.flake_spread, 0.f),
                                        std::clamp(m.flake_jitter, 0.f, 1.f)))
      flake = normalize(b.frames[0].to_world(*local));

  unsigned under = 0u;
  const float coat = std::clamp(m.coat, 0.f, 1.f);
  const float ior = std::clamp(m.coat_ior < 1.f ? 1.f / m.coat_ior : m.coat_ior, 1.f, 3.f);
  if (coat > paint_epsilon && ior - 1.f > paint_epsilon) {
    Vec3f color = clamp01(m.coat_color);
    // Pearlescent flakes: the coat over them turns to flipflopColor towards grazing views.
    if (const float falloff = std::clamp(m.flipflop_falloff, 0.f, 1.f); flake && falloff < 1.f - paint_epsilon) {
      const float toward = std::pow(1.f - std::max(dot(wo, *flake), 0.f), 1.f / (1.f - falloff));
      color = lerp(color, clamp01(m.flipflop_color), toward);
    }
    under = add_coat(b, coat, ior, color, std::max(m.coat_thickness, 0.f), std::max(m.coat_roughness, 0.f));
  }
  const float outer = b.outer(under);

  if (flake) {
    // Where a flake is, the base is not; a flake seen from behind reflects nothing.
    const int frame = b.add_frame(*flake, wo);
    if (!(b.wos[frame].z > 0.f)) return;
    // As OSPRay's: aluminium's eta and k, or Schlick from flakeColor to white.
    const Fresnel fresnel =
        m.flake_color
            ? Fresnel{Fresnel::Kind::schlick, 1.f, 1.f, clamp01(*m.flake_color), splat(1.f)}
            : Fresnel{Fresnel::Kind::conductor, 1.f, 1.f, {1.69700277f, 0.879832864f, 0.5301736f},
                      {9.30200672f, 6.27604008f, 4.89433956f}};
    const float roughness = std::max(m.flake_roughness, 0.f);
    b.add(roughness < paint_epsilon ? LobeKind::mirror : LobeKind::ggx_reflect, splat(1.f),
          outer * mean(fresnel(b.wos[frame].z)), fresnel, paint_alpha(roughness), under, frame);
    return;
  }
  // The base, tilted by map_normal where the coat has a normal of its own.
  const int frame = sp.coat_n ? b.add_frame(facing(sp.n, wo, sp.ng), wo) : 0;
  const Vec3f base = clamp01(m.base_color * sp.color);
  const float roughness = std::max(m.roughness, 0.f);
  b.add(roughness < paint_epsilon ? LobeKind::lambert : LobeKind::oren_nayar, base, outer * mean(base), {}, roughness,
        under, frame);
}

inline void build(Bsdf& b, const PlasticMaterial& m, const ShadingPoint&) {
  // OSPRay's plastic is smooth at roughness 0 exactly; its layer takes eta and 1/eta alike.
  const float ior = m.eta >= 1.f ? m.eta : 1.f / m.eta;
  const unsigned under =
      add_coat(b, 1.f, ior, splat(1.f), 1.f, m.roughness > 0.f ? std::max(m.roughness, paint_epsilon) : 0.f);
  b.add(LobeKind::lambert, m.pigment_color, b.outer(under) * mean(m.pigment_color), {}, 0.f, under);
}

}  // namespace sciray::bsdf_detail
