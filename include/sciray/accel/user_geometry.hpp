#pragma once
// Embree user geometry over sciray's own packet intersectors. A geometry type G provides
//   template <class Arch> PrimitiveHit<Arch> intersect_primitive(const Ray<Float<Arch>>&, std::uint32_t prim) const;
//   Box3f primitive_bounds(std::uint32_t prim) const;
// and Embree calls back here for each candidate primitive. Embree passes the packet it was
// asked to trace (N = 4/8/16 from rtcIntersect4/8/16, 1 from rtcIntersect1): when N is the
// width of Arch the whole packet is intersected in registers, otherwise lane by lane with
// the scalar instantiation. The callbacks are instantiated for the Arch the world was
// committed with, so each ISA's translation unit registers its own compiled code.
#include <cstdint>
#include <limits>

#include <embree3/rtcore.h>

#include "sciray/accel/embree.hpp"
#include "sciray/geometry/sphere_intersect.hpp"

namespace sciray::accel {

namespace user_detail {

// Offsets, in units of N, of the fields of Embree's SoA ray and hit packets.
enum RayField { org_x, org_y, org_z, tnear, dir_x, dir_y, dir_z, time, tfar };
enum HitField { ng_x = 12, ng_y, ng_z, u, v, prim_id, geom_id, inst_id };

template <class Arch, class G, bool Occlusion>
void packet_callback(const G& geometry, float* rays, const int* valid, std::uint32_t prim, unsigned geom,
                     const RTCIntersectContext* context) {
  using F = simd::Float<Arch>;
  using I = simd::Int<Arch>;
  constexpr int W = simd::width<Arch>;
  const auto field = [&](int k) { return rays + k * W; };
  Ray<F> ray;
  ray.org = {F::load_unaligned(field(org_x)), F::load_unaligned(field(org_y)), F::load_unaligned(field(org_z))};
  ray.dir = {F::load_unaligned(field(dir_x)), F::load_unaligned(field(dir_y)), F::load_unaligned(field(dir_z))};
  ray.tnear = F::load_unaligned(field(tnear));
  ray.tfar = F::load_unaligned(field(tfar));
  // Embree marks valid lanes -1: compare as numbers, since the bit pattern is a NaN.
  const auto active = simd::to_float(I::load_unaligned(valid)) != F(0.f);
  const PrimitiveHit<Arch> hit = geometry.template intersect_primitive<Arch>(ray, prim);
  const auto accept = active & hit.hit;
  if (!simd::any(accept)) return;
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
    store_int(prim_id, static_cast<std::int32_t>(prim));
    store_int(geom_id, static_cast<std::int32_t>(geom));
    store_int(inst_id, static_cast<std::int32_t>(context->instID[0]));
  }
}

template <class G, bool Occlusion>
void lane_callback(const G& geometry, float* rays, const int* valid, unsigned N, std::uint32_t prim, unsigned geom,
                   const RTCIntersectContext* context) {
  const auto field = [&](int k, unsigned i) -> float& { return rays[k * N + i]; };
  for (unsigned i = 0; i < N; ++i) {
    if (!valid[i]) continue;
    Ray<float> ray;
    ray.org = {field(org_x, i), field(org_y, i), field(org_z, i)};
    ray.dir = {field(dir_x, i), field(dir_y, i), field(dir_z, i)};
    ray.tnear = field(tnear, i);
    ray.tfar = field(tfar, i);
    const PrimitiveHit<simd::scalar> hit = geometry.template intersect_primitive<simd::scalar>(ray, prim);
    if (!hit.hit) continue;
    if constexpr (Occlusion) {
      field(tfar, i) = -std::numeric_limits<float>::infinity();
    } else {
      field(tfar, i) = hit.t;
      field(ng_x, i) = hit.ng.x, field(ng_y, i) = hit.ng.y, field(ng_z, i) = hit.ng.z;
      field(u, i) = hit.u, field(v, i) = hit.v;
      reinterpret_cast<unsigned&>(field(prim_id, i)) = prim;
      reinterpret_cast<unsigned&>(field(geom_id, i)) = geom;
      reinterpret_cast<unsigned&>(field(inst_id, i)) = context->instID[0];
    }
  }
}

template <class Arch, class G>
void intersect(const RTCIntersectFunctionNArguments* args) {
  const G& geometry = *static_cast<const G*>(args->geometryUserPtr);
  auto* rays = reinterpret_cast<float*>(args->rayhit);
  if constexpr (!std::is_same_v<Arch, simd::scalar>)
    if (args->N == simd::width<Arch>)
      return packet_callback<Arch, G, false>(geometry, rays, args->valid, args->primID, args->geomID, args->context);
  lane_callback<G, false>(geometry, rays, args->valid, args->N, args->primID, args->geomID, args->context);
}

template <class Arch, class G>
void occluded(const RTCOccludedFunctionNArguments* args) {
  const G& geometry = *static_cast<const G*>(args->geometryUserPtr);
  auto* rays = reinterpret_cast<float*>(args->ray);
  if constexpr (!std::is_same_v<Arch, simd::scalar>)
    if (args->N == simd::width<Arch>)
      return packet_callback<Arch, G, true>(geometry, rays, args->valid, args->primID, args->geomID, args->context);
  lane_callback<G, true>(geometry, rays, args->valid, args->N, args->primID, args->geomID, args->context);
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
  rtcCommitGeometry(g);
  device.check("user geometry: rtcCommitGeometry");
  rtcRetainGeometry(g);
  return g;
}

}  // namespace sciray::accel
