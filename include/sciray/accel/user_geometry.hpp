#pragma once
// Embree user geometry over sciray's own packet intersectors. A geometry type G provides
//   template <class Arch> PrimitiveHit<Arch> intersect_primitive(const Ray<Float<Arch>>&, std::uint32_t prim) const;
//   Box3f primitive_bounds(std::uint32_t prim) const;
// and Embree calls back here for each candidate primitive. Embree passes the packet it was
// asked to trace (N = 4/8/16 from rtcIntersect4/8/16, 1 from rtcIntersect1): when N is the
// width of Arch the whole packet is intersected in registers, otherwise lane by lane with
// the scalar instantiation. The callbacks are instantiated for the Arch the world was
// committed with, so each ISA's translation unit registers its own compiled code.
// When the query carries a context filter (clipping), each candidate hit is put to it
// before it counts, as Embree does for its own primitives.
#include <cstdint>
#include <limits>

#include <embree3/rtcore.h>

#include "sciray/accel/embree.hpp"
#include "sciray/accel/trace.hpp"
#include "sciray/geometry/sphere_intersect.hpp"

namespace sciray::accel {

namespace user_detail {

// Offsets, in units of N, of the fields of Embree's SoA ray and hit packets.
enum RayField { org_x, org_y, org_z, tnear, dir_x, dir_y, dir_z, time, tfar };
enum HitField { ng_x = 12, ng_y, ng_z, u, v, prim_id, geom_id, inst_id };

// Embree's intersect and occluded callbacks differ only in the name of the ray argument.
inline float* rays_of(const RTCIntersectFunctionNArguments* args) { return reinterpret_cast<float*>(args->rayhit); }
inline float* rays_of(const RTCOccludedFunctionNArguments* args) { return reinterpret_cast<float*>(args->ray); }

/// Asks the context filter (clipping), if the query has one, which candidate hits count:
/// clears `valid[i]` for the rejected ones. Embree's contract is followed: the filter sees
/// the candidate's distance in the ray's tfar and its data in a separate hit packet.
template <bool Occlusion, class Args>
void run_context_filter(const Args* args, int* valid, const float* t, const float* ng, const float* uv,
                        std::uint32_t prim) {
  const unsigned N = args->N;
  float* rays = rays_of(args);
  alignas(64) float hit_storage[(7 + RTC_MAX_INSTANCE_LEVEL_COUNT) * 16];
  auto* hit = reinterpret_cast<RTCHitN*>(hit_storage);
  alignas(64) float saved_tfar[16];
  bool saved[16] = {};
  for (unsigned i = 0; i < N; ++i) {
    if (!valid[i]) continue;
    saved[i] = true;
    saved_tfar[i] = rays[tfar * N + i];
    rays[tfar * N + i] = t[i];
    RTCHitN_Ng_x(hit, N, i) = ng[i], RTCHitN_Ng_y(hit, N, i) = ng[N + i], RTCHitN_Ng_z(hit, N, i) = ng[2 * N + i];
    RTCHitN_u(hit, N, i) = uv[i], RTCHitN_v(hit, N, i) = uv[N + i];
    RTCHitN_primID(hit, N, i) = prim;
    RTCHitN_geomID(hit, N, i) = args->geomID;
    for (unsigned l = 0; l < RTC_MAX_INSTANCE_LEVEL_COUNT; ++l) RTCHitN_instID(hit, N, i, l) = args->context->instID[l];
  }
  RTCFilterFunctionNArguments filter{valid, args->geometryUserPtr, args->context,
                                     reinterpret_cast<RTCRayN*>(rays), hit, N};
  if constexpr (Occlusion)
    rtcFilterOcclusion(args, &filter);
  else
    rtcFilterIntersection(args, &filter);
  // The caller writes the accepted hits; until then every lane keeps its old tfar.
  for (unsigned i = 0; i < N; ++i)
    if (saved[i]) rays[tfar * N + i] = saved_tfar[i];
}

template <class Arch, class G, bool Occlusion, class Args>
void packet_callback(const G& geometry, const Args* args) {
  using F = simd::Float<Arch>;
  using I = simd::Int<Arch>;
  constexpr int W = simd::width<Arch>;
  float* rays = rays_of(args);
  const auto field = [&](int k) { return rays + k * W; };
  Ray<F> ray;
  ray.org = {F::load_unaligned(field(org_x)), F::load_unaligned(field(org_y)), F::load_unaligned(field(org_z))};
  ray.dir = {F::load_unaligned(field(dir_x)), F::load_unaligned(field(dir_y)), F::load_unaligned(field(dir_z))};
  ray.tnear = F::load_unaligned(field(tnear));
  ray.tfar = F::load_unaligned(field(tfar));
  // Embree marks valid lanes -1: compare as numbers, since the bit pattern is a NaN.
  const auto active = simd::to_float(I::load_unaligned(args->valid)) != F(0.f);
  PrimitiveHit<Arch> hit = geometry.template intersect_primitive<Arch>(ray, args->primID);
  auto accept = active & hit.hit;
  if (!simd::any(accept)) return;
  if (args->context->filter) {
    // A rejected (clipped) hit may hide a later one on the same primitive, as the far
    // side of a sphere or box: look again beyond it. Convex primitives have two.
    auto pending = accept;
    accept = simd::Mask<Arch>(false);
    PrimitiveHit<Arch> kept = hit;
    for (int round = 0; round < 2 && simd::any(pending); ++round) {
      alignas(64) std::int32_t valid[W];
      alignas(64) float t[W], ng[3 * W], uv[2 * W];
      simd::valid_lanes(pending).store_aligned(valid);
      hit.t.store_aligned(t);
      hit.ng.x.store_aligned(ng), hit.ng.y.store_aligned(ng + W), hit.ng.z.store_aligned(ng + 2 * W);
      hit.u.store_aligned(uv), hit.v.store_aligned(uv + W);
      run_context_filter<Occlusion>(args, valid, t, ng, uv, args->primID);
      const auto passed = pending & (simd::to_float(I::load_aligned(valid)) != F(0.f));
      kept.t = simd::select(passed, hit.t, kept.t);
      kept.ng = select(passed, hit.ng, kept.ng);
      kept.u = simd::select(passed, hit.u, kept.u), kept.v = simd::select(passed, hit.v, kept.v);
      accept = accept | passed;
      const auto rejected = pending & !passed;
      ray.tnear = simd::select(rejected, hit.t, ray.tnear);
      hit = geometry.template intersect_primitive<Arch>(ray, args->primID);
      pending = rejected & hit.hit;
    }
    if (!simd::any(accept)) return;
    hit = kept;
  }
  if constexpr (Occlusion) {
    simd::select(accept, F(-std::numeric_limits<float>::infinity()), ray.tfar).store_unaligned(field(tfar));
  } else {
    const auto store_float = [&](int k, const F& value) {
      simd::select(accept, value, F::load_unaligned(field(k))).store_unaligned(field(k));
    };
    const auto store_int = [&](int k, std::int32_t value) {
      auto* at = reinterpret_cast<std::int32_t*>(field(k));
      simd::select(accept, I(value), I::load_unaligned(at)).store_unaligned(at);
    };
    store_float(tfar, hit.t);
    store_float(ng_x, hit.ng.x), store_float(ng_y, hit.ng.y), store_float(ng_z, hit.ng.z);
    store_float(u, hit.u), store_float(v, hit.v);
    store_int(prim_id, static_cast<std::int32_t>(args->primID));
    store_int(geom_id, static_cast<std::int32_t>(args->geomID));
    store_int(inst_id, static_cast<std::int32_t>(args->context->instID[0]));
  }
}

template <class G, bool Occlusion, class Args>
void lane_callback(const G& geometry, const Args* args) {
  const unsigned N = args->N;
  float* rays = rays_of(args);
  const auto field = [&](int k, unsigned i) -> float& { return rays[k * N + i]; };
  for (unsigned i = 0; i < N; ++i) {
    if (!args->valid[i]) continue;
    Ray<float> ray;
    ray.org = {field(org_x, i), field(org_y, i), field(org_z, i)};
    ray.dir = {field(dir_x, i), field(dir_y, i), field(dir_z, i)};
    ray.tnear = field(tnear, i);
    ray.tfar = field(tfar, i);
    PrimitiveHit<simd::scalar> hit = geometry.template intersect_primitive<simd::scalar>(ray, args->primID);
    // As in the packet path: past a rejected hit, the primitive's next one (two at most).
    for (int round = 0; hit.hit && args->context->filter; ++round) {
      int valid[16] = {};  // one lane at a time, in Embree's N-wide layout
      float t[16], ng[3 * 16], uv[2 * 16];
      valid[i] = -1, t[i] = hit.t;
      ng[i] = hit.ng.x, ng[N + i] = hit.ng.y, ng[2 * N + i] = hit.ng.z;
      uv[i] = hit.u, uv[N + i] = hit.v;
      run_context_filter<Occlusion>(args, valid, t, ng, uv, args->primID);
      if (valid[i]) break;
      ray.tnear = hit.t;
      hit = round == 0 ? geometry.template intersect_primitive<simd::scalar>(ray, args->primID)
                       : PrimitiveHit<simd::scalar>{false, 0.f, {}};
    }
    if (!hit.hit) continue;
    if constexpr (Occlusion) {
      field(tfar, i) = -std::numeric_limits<float>::infinity();
    } else {
      field(tfar, i) = hit.t;
      field(ng_x, i) = hit.ng.x, field(ng_y, i) = hit.ng.y, field(ng_z, i) = hit.ng.z;
      field(u, i) = hit.u, field(v, i) = hit.v;
      reinterpret_cast<unsigned&>(field(prim_id, i)) = args->primID;
      reinterpret_cast<unsigned&>(field(geom_id, i)) = args->geomID;
      reinterpret_cast<unsigned&>(field(inst_id, i)) = args->context->instID[0];
    }
  }
}

template <class Arch, class G>
void intersect(const RTCIntersectFunctionNArguments* args) {
  const G& geometry = *static_cast<const G*>(args->geometryUserPtr);
  if constexpr (!std::is_same_v<Arch, simd::scalar>)
    if (args->N == simd::width<Arch>) return packet_callback<Arch, G, false>(geometry, args);
  lane_callback<G, false>(geometry, args);
}

template <class Arch, class G>
void occluded(const RTCOccludedFunctionNArguments* args) {
  const G& geometry = *static_cast<const G*>(args->geometryUserPtr);
  if constexpr (!std::is_same_v<Arch, simd::scalar>)
    if (args->N == simd::width<Arch>) return packet_callback<Arch, G, true>(geometry, args);
  lane_callback<G, true>(geometry, args);
}

template <class G>
void bounds(const RTCBoundsFunctionArguments* args) {
  const G& geometry = *static_cast<const G*>(args->geometryUserPtr);
  const Box3f box = geometry.primitive_bounds(args->primID);
  *args->bounds_o = {box.lower.x, box.lower.y, box.lower.z, 0.f, box.upper.x, box.upper.y, box.upper.z, 0.f};
}

}  // namespace user_detail

/// A committed Embree user geometry of `count` primitives that calls `geometry`'s own
/// intersector, compiled for Arch. `geometry` must outlive the Embree scene.
template <class Arch, class G>
RTCGeometry create_user_geometry(const Device& device, const G& geometry, std::size_t count) {
  GeometryHandle handle(device, RTC_GEOMETRY_TYPE_USER);
  RTCGeometry g = handle.get();
  rtcSetGeometryUserPrimitiveCount(g, static_cast<unsigned>(count));
  rtcSetGeometryUserData(g, const_cast<G*>(&geometry));
  rtcSetGeometryBoundsFunction(g, &user_detail::bounds<G>, nullptr);
  rtcSetGeometryIntersectFunction(g, &user_detail::intersect<Arch, G>);
  rtcSetGeometryOccludedFunction(g, &user_detail::occluded<Arch, G>);
  return handle.commit(device, "user geometry");
}

}  // namespace sciray::accel
