#pragma once
// Packet traversal: a packet of W rays maps onto Embree's rtcIntersect4/8/16 and
// rtcOccluded4/8/16 (SoA structures filled straight from the lane registers); the
// scalar path uses rtcIntersect1 / rtcOccluded1.
#include <cstdint>
#include <type_traits>

#include <embree3/rtcore.h>

#include "sciray/math/ray.hpp"

namespace sciray::accel {

/// What a packet of rays hit. Lanes with `hit` false hold no meaningful hit data.
template <class Arch>
struct Hit {
  using F = simd::Float<Arch>;
  using I = simd::Int<Arch>;
  simd::Mask<Arch> hit;
  F t;             ///< distance along the ray
  F u, v;          ///< Embree's barycentrics of the hit primitive
  Vec3<F> ng;      ///< unnormalized geometric normal
  I prim_id;       ///< primitive index (0 where no hit)
  I geom_id;       ///< Embree geometry id (RTC_INVALID_GEOMETRY_ID where no hit)
  I inst_id;       ///< top-level id of the instance hit, RTC_INVALID_GEOMETRY_ID for direct geometry
  F time = F(0.f);  ///< the ray's time, at which a deforming mesh interpolates its normals
};

namespace detail {

template <int W>
struct EmbreePacket;
template <>
struct EmbreePacket<4> {
  using RayHit = RTCRayHit4;
  using Ray = RTCRay4;
  static void intersect(const int* valid, RTCScene s, RTCIntersectContext* c, RayHit* r) {
    rtcIntersect4(valid, s, c, r);
  }
  static void occluded(const int* valid, RTCScene s, RTCIntersectContext* c, Ray* r) {
    rtcOccluded4(valid, s, c, r);
  }
};
template <>
struct EmbreePacket<8> {
  using RayHit = RTCRayHit8;
  using Ray = RTCRay8;
  static void intersect(const int* valid, RTCScene s, RTCIntersectContext* c, RayHit* r) {
    rtcIntersect8(valid, s, c, r);
  }
  static void occluded(const int* valid, RTCScene s, RTCIntersectContext* c, Ray* r) {
    rtcOccluded8(valid, s, c, r);
  }
};
template <>
struct EmbreePacket<16> {
  using RayHit = RTCRayHit16;
  using Ray = RTCRay16;
  static void intersect(const int* valid, RTCScene s, RTCIntersectContext* c, RayHit* r) {
    rtcIntersect16(valid, s, c, r);
  }
  static void occluded(const int* valid, RTCScene s, RTCIntersectContext* c, Ray* r) {
    rtcOccluded16(valid, s, c, r);
  }
};

template <class Arch, class EmbreeRay>
void store_ray(EmbreeRay& out, const Ray<simd::Float<Arch>>& ray) {
  ray.org.x.store_aligned(out.org_x);
  ray.org.y.store_aligned(out.org_y);
  ray.org.z.store_aligned(out.org_z);
  ray.dir.x.store_aligned(out.dir_x);
  ray.dir.y.store_aligned(out.dir_y);
  ray.dir.z.store_aligned(out.dir_z);
  ray.tnear.store_aligned(out.tnear);
  ray.tfar.store_aligned(out.tfar);
  ray.time.store_aligned(out.time);
  constexpr int W = simd::width<Arch>;
  for (int i = 0; i < W; ++i) {
    out.mask[i] = ~0u;
    out.id[i] = static_cast<unsigned>(i);
    out.flags[i] = 0;
  }
}

}  // namespace detail

/// The lanes Embree can trace: origin and direction within ±max_ray_coordinate (NaN is
/// not) and tnear, tfar not NaN. intersect and occluded treat the others as missing
/// everything: a camera placed, or a path bounced, beyond that range.
template <class Arch>
simd::Mask<Arch> traceable(const Ray<simd::Float<Arch>>& ray) {
  using F = simd::Float<Arch>;
  const F limit(max_ray_coordinate);
  const auto within = [&](const F& x) -> simd::Mask<Arch> { return simd::abs(x) <= limit; };
  const simd::Mask<Arch> origin = within(ray.org.x) && within(ray.org.y) && within(ray.org.z);
  const simd::Mask<Arch> direction = within(ray.dir.x) && within(ray.dir.y) && within(ray.dir.z);
  const simd::Mask<Arch> interval = (ray.tnear == ray.tnear) && (ray.tfar == ray.tfar);
  return origin && direction && interval;
}

/// An extra test every candidate hit must pass before it counts (clipping): Embree's
/// context filter function, and what it reads. Scenes traced with one must have been
/// built with RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION.
struct HitFilter {
  RTCFilterFunctionN function = nullptr;
  const void* data = nullptr;

  /// The data of the filter that runs for `context` (the one given to intersect).
  static const void* data_of(const RTCIntersectContext* context);
};

namespace detail {

/// Embree's context with the data of a context filter behind it: a filter function
/// receives the RTCIntersectContext pointer and casts back to reach `filter_data`.
struct Context {
  RTCIntersectContext embree;
  const void* filter_data;
};
static_assert(std::is_standard_layout_v<Context>);

inline Context make_context(bool coherent, const HitFilter& filter) {
  Context context;
  rtcInitIntersectContext(&context.embree);
  context.embree.flags = coherent ? RTC_INTERSECT_CONTEXT_FLAG_COHERENT : RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
  context.embree.filter = filter.function;
  context.filter_data = filter.data;
  return context;
}

}  // namespace detail

inline const void* HitFilter::data_of(const RTCIntersectContext* context) {
  return reinterpret_cast<const detail::Context*>(context)->filter_data;
}

/// Closest hit for each active lane (none for a lane that is not traceable). `coherent`
/// tells Embree the rays are primary-like.
template <class Arch>
Hit<Arch> intersect(RTCScene scene, const Ray<simd::Float<Arch>>& ray, const simd::Mask<Arch>& requested,
                    bool coherent = true, const HitFilter& filter = {}) {
  using F = simd::Float<Arch>;
  using I = simd::Int<Arch>;
  const simd::Mask<Arch> active = requested && traceable<Arch>(ray);
  detail::Context context_storage = detail::make_context(coherent, filter);
  RTCIntersectContext& context = context_storage.embree;
  Hit<Arch> hit;
  if constexpr (std::is_same_v<Arch, simd::scalar>) {
    RTCRayHit rh;
    rh.ray = {ray.org.x, ray.org.y, ray.org.z, ray.tnear, ray.dir.x, ray.dir.y, ray.dir.z, ray.time, ray.tfar,
              ~0u, 0u, 0u};
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.primID = 0;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    if (active) rtcIntersect1(scene, &context, &rh);
    hit.hit = active && rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
    hit.t = rh.ray.tfar;
    hit.u = rh.hit.u;
    hit.v = rh.hit.v;
    hit.ng = {rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z};
    hit.prim_id = static_cast<std::int32_t>(rh.hit.primID);
    hit.geom_id = static_cast<std::int32_t>(rh.hit.geomID);
    hit.inst_id = static_cast<std::int32_t>(rh.hit.instID[0]);
    hit.time = ray.time;
  } else {
    using Packet = detail::EmbreePacket<simd::width<Arch>>;
    typename Packet::RayHit rh;
    detail::store_ray<Arch>(rh.ray, ray);
    I(static_cast<std::int32_t>(RTC_INVALID_GEOMETRY_ID)).store_aligned(reinterpret_cast<std::int32_t*>(rh.hit.geomID));
    I(static_cast<std::int32_t>(RTC_INVALID_GEOMETRY_ID))
        .store_aligned(reinterpret_cast<std::int32_t*>(rh.hit.instID[0]));
    I(0).store_aligned(reinterpret_cast<std::int32_t*>(rh.hit.primID));
    alignas(64) std::int32_t valid[simd::width<Arch>];
    simd::valid_lanes(active).store_aligned(valid);
    Packet::intersect(valid, scene, &context, &rh);
    hit.t = F::load_aligned(rh.ray.tfar);
    hit.hit = active & (hit.t < ray.tfar);
    hit.u = F::load_aligned(rh.hit.u);
    hit.v = F::load_aligned(rh.hit.v);
    hit.ng = {F::load_aligned(rh.hit.Ng_x), F::load_aligned(rh.hit.Ng_y), F::load_aligned(rh.hit.Ng_z)};
    hit.prim_id = I::load_aligned(reinterpret_cast<const std::int32_t*>(rh.hit.primID));
    hit.geom_id = I::load_aligned(reinterpret_cast<const std::int32_t*>(rh.hit.geomID));
    hit.inst_id = I::load_aligned(reinterpret_cast<const std::int32_t*>(rh.hit.instID[0]));
    hit.time = ray.time;
  }
  return hit;
}

/// Whether anything blocks each active lane between tnear and tfar (nothing, for a lane
/// that is not traceable).
template <class Arch>
simd::Mask<Arch> occluded(RTCScene scene, const Ray<simd::Float<Arch>>& ray, const simd::Mask<Arch>& requested,
                          bool coherent = false, const HitFilter& filter = {}) {
  using F = simd::Float<Arch>;
  const simd::Mask<Arch> active = requested && traceable<Arch>(ray);
  detail::Context context_storage = detail::make_context(coherent, filter);
  RTCIntersectContext& context = context_storage.embree;
  if constexpr (std::is_same_v<Arch, simd::scalar>) {
    RTCRay r{ray.org.x, ray.org.y, ray.org.z, ray.tnear, ray.dir.x, ray.dir.y, ray.dir.z, ray.time, ray.tfar,
             ~0u, 0u, 0u};
    if (!active) return false;
    rtcOccluded1(scene, &context, &r);
    return r.tfar < 0.f;  // Embree sets tfar to -inf on occlusion
  } else {
    using Packet = detail::EmbreePacket<simd::width<Arch>>;
    typename Packet::Ray r;
    detail::store_ray<Arch>(r, ray);
    alignas(64) std::int32_t valid[simd::width<Arch>];
    simd::valid_lanes(active).store_aligned(valid);
    Packet::occluded(valid, scene, &context, &r);
    return active & (F::load_aligned(r.tfar) < F(0.f));
  }
}

}  // namespace sciray::accel
