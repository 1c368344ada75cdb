#pragma once
// Surfaces that scatter by Lambert's lobe alone (obj with kd only, and geometry without a
// material), shaded for a packet of paths at once: the path tracer gathers the paths at
// such surfaces into a LambertPacket, draws their light samples and next directions here
// over the lanes, and writes the results back to its paths.
//
// Every function gives what bsdf.hpp's general eval() and sample() and light.hpp's
// sample() give for these surfaces, from the same random numbers: images do not change
// (tests/unit/test_renderers.cpp renders a box both ways).
#include <array>
#include <limits>
#include <optional>
#include <variant>

#include "sciray/math/random_lanes.hpp"
#include "sciray/render/bsdf.hpp"
#include "sciray/render/light.hpp"

namespace sciray {

/// The energy-conserving kd of a material that is Lambert's lobe alone (obj with kd only:
/// no ks, no transmission filter, opaque, no maps), or none.
inline std::optional<Vec3f> lambert_kd(const Material& material) {
  const auto* obj = std::get_if<ObjMaterial>(&material);
  if (!obj || has_maps(material) || obj->d != 1.f) return std::nullopt;
  const ObjMaterial m = energy_conserving(*obj);
  if (bsdf_detail::max_component(m.ks) > 0.f || bsdf_detail::max_component(m.tf) > 0.f) return std::nullopt;
  return m.kd;
}

/// A Lambert surface seen from wo, as make_bsdf() finds it: its colour (kd times the
/// geometry's), the normal of its shading frame, and whether wo sees its lobe at all.
struct LambertSurface {
  Vec3f tint, frame_normal;
  bool scatters = false;
};

/// The Lambert surface at `sp` seen from wo for a material of Lambert's `kd`; none where
/// the geometry's alpha cuts it out or a coat has a normal of its own.
inline std::optional<LambertSurface> lambert_surface(const Vec3f& kd, const ShadingPoint& sp, const Vec3f& wo) {
  if (sp.alpha != 1.f || sp.coat_n) return std::nullopt;
  LambertSurface s;
  s.tint = kd * sp.color;
  const bool from_below = dot(sp.n, wo) <= 0.f;
  s.frame_normal = from_below ? sp.n : bsdf_detail::facing(sp.n, wo, sp.ng);
  s.scatters = dot(wo, sp.ng) > 0.f && (from_below || dot(s.frame_normal, wo) > 0.f) &&
               bsdf_detail::max_component(s.tint) > 0.f;
  return s;
}

/// Lambert's f·cos and pdf towards wi (eval()): light from below the geometric surface
/// `ng`, or the shading frame, does not reach wo.
inline BsdfValue lambert_value(const LambertSurface& s, const Vec3f& ng, const Vec3f& wi) {
  BsdfValue f;
  const float cos_i = dot(s.frame_normal, wi);
  if (!s.scatters || dot(wi, ng) < 0.f || !(cos_i > 0.f)) return f;
  f.pdf = cos_i / bsdf_detail::pi;
  f.f_cos = s.tint * f.pdf;
  return f;
}

/// A packet of paths at Lambert surfaces (`lanes`), gathered once a bounce for their
/// light samples and their next directions.
template <class Arch>
struct LambertPacket {
  simd::Mask<Arch> lanes, scatters;
  Vec3<simd::Float<Arch>> at, shading_normal, frame_normal, ng, tint, throughput;
  simd::Float<Arch> offset;  ///< how far rays leaving start off the surface
  std::array<PixelRandom*, simd::width<Arch>> rngs;  ///< each path's own generator
};

/// The next directions of a packet: the same draws as sample() (u_lobe, then the
/// direction), cosine-weighted about each frame normal, of weight f·cos / pdf = the
/// tint, leaving off the surface on wo's side. Lanes that do not scatter are absorbed.
template <class Arch>
struct LambertDirections {
  simd::Mask<Arch> scattered;
  Vec3<simd::Float<Arch>> dir, throughput, org;
  simd::Float<Arch> pdf;
};
template <class Arch>
LambertDirections<Arch> sample_lambert_directions(const LambertPacket<Arch>& packet) {
  using F = simd::Float<Arch>;
  const Vec3<F>& n = packet.frame_normal;
  PixelRandomLanes<Arch>::next_2d_of(packet.rngs, packet.lanes);  // u_lobe: there is one lobe to pick
  const auto [u1, u2] = PixelRandomLanes<Arch>::next_2d_of(packet.rngs, packet.lanes);
  LambertDirections<Arch> out;
  out.dir = normalize(detail::sample_cosine(n, u1, u2));
  const F cos_i = dot(n, out.dir);
  out.scattered = packet.scatters & (cos_i > F(0.f));
  out.pdf = cos_i / F(bsdf_detail::pi);
  out.org = packet.at + packet.ng * packet.offset;
  out.throughput = packet.throughput * packet.tint;
  return out;
}

/// One light's samples for a packet: the same draw and sample as light.hpp's sample() for
/// ambient light (about the shading normal), a point distant light and a quad light
/// without an intensity table, weighed by lambert_value() and, with `mis`, the power
/// heuristic; none (nothing drawn) for the other kinds, which go lane by lane.
template <class Arch>
struct LambertLightSamples {
  simd::Mask<Arch> sampled;
  Vec3<simd::Float<Arch>> contribution, dir;
  simd::Float<Arch> reach;  ///< how far the shadow ray goes
};
template <class Arch>
std::optional<LambertLightSamples<Arch>> sample_light_lambert(const Light& light, const LambertPacket<Arch>& packet,
                                                              bool mis) {
  using F = simd::Float<Arch>;
  using M = simd::Mask<Arch>;
  constexpr float inf = std::numeric_limits<float>::infinity();
  const auto* ambient = std::get_if<AmbientLight>(&light);
  const auto* distant = std::get_if<DistantLight>(&light);
  const auto* quad = std::get_if<QuadLight>(&light);
  if (!ambient && !(distant && distant->angular_diameter <= 0.f) && !(quad && !quad->distribution)) return std::nullopt;
  const Vec3<F>&at = packet.at, &n = packet.shading_normal;
  const auto [u1, u2] = PixelRandomLanes<Arch>::next_2d_of(packet.rngs, packet.lanes);
  const Vec3<F> emission(emitted(light));
  LambertLightSamples<Arch> out;
  Vec3<F> weight;
  F pdf;
  out.reach = F(inf);
  M sampled = packet.lanes;
  if (ambient) {
    out.dir = detail::sample_cosine(n, u1, u2);
    pdf = dot(out.dir, n) / F(detail::pi);
    sampled = sampled & (pdf > F(0.f));
    weight = emission / pdf;
  } else if (distant) {
    out.dir = Vec3<F>(-normalize(distant->direction));
    pdf = F(inf);
    weight = emission;
  } else {
    const Vec3<F> q = Vec3<F>(quad->position) + Vec3<F>(quad->edge1) * u1 + Vec3<F>(quad->edge2) * u2;
    const Vec3f normal_area = cross(quad->edge1, quad->edge2);
    const float area = length(normal_area);
    const Vec3<F> d = q - at;
    const F dist2 = dot(d, d), dist = simd::sqrt(dist2);
    out.dir = d / dist;
    const F cos_light = -dot(out.dir, Vec3<F>(normal_area)) / F(area);
    sampled = sampled & (dist > F(0.f)) & (cos_light > F(0.f));  // not the back of the quad
    pdf = dist2 / (cos_light * F(area));
    weight = emission / pdf;
    out.reach = dist * F(1.f - 1e-4f);
  }
  const F cos_i = dot(packet.frame_normal, out.dir);
  const F f_pdf = cos_i / F(bsdf_detail::pi);
  const Vec3<F> f_cos = packet.tint * f_pdf;
  out.sampled = sampled & packet.scatters & (dot(out.dir, packet.ng) >= F(0.f)) & (cos_i > F(0.f)) &
                (simd::max(f_cos.x, simd::max(f_cos.y, f_cos.z)) > F(0.f));
  F w(1.f);
  if (mis && !distant) {
    const F a2 = pdf * pdf, b2 = f_pdf * f_pdf;
    w = simd::select(a2 + b2 > F(0.f), a2 / (a2 + b2), F(0.f));
  }
  out.contribution = packet.throughput * f_cos * weight * w;
  return out;
}

}  // namespace sciray
