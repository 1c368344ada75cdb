#pragma once
// Axis-aligned boxes (OSPRay's `box`) and planes (OSPRay's `plane`), each intersected by
// sciray's own packet code as Embree user geometry: a box is six faces for the price of
// one slab test, a plane needs no tessellation at all.
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "sciray/accel/trace.hpp"
#include "sciray/accel/user_geometry.hpp"
#include "sciray/error.hpp"
#include "sciray/geometry/data.hpp"
#include "sciray/geometry/surface.hpp"
#include "sciray/math/box.hpp"

namespace sciray {

namespace box_detail {

/// Per-primitive colours (r,g,b,a), gathered for the lanes of one geometry.
template <class Arch>
SurfaceSample<Arch> colored_surface(const std::vector<float>& colors, const accel::Hit<Arch>& hit,
                                    const simd::Mask<Arch>& lanes) {
  using I = simd::Int<Arch>;
  SurfaceSample<Arch> s;
  s.normal = normalize(hit.ng);
  s.has_color = lanes;
  if (colors.empty()) {
    s.has_color = simd::Mask<Arch>(false);
    return s;
  }
  const I at = simd::select(lanes, hit.prim_id, I(0)) * I(4);
  s.color = {simd::gather<Arch>(colors.data(), at), simd::gather<Arch>(colors.data(), at + I(1)),
             simd::gather<Arch>(colors.data(), at + I(2))};
  s.alpha = simd::gather<Arch>(colors.data(), at + I(3));
  return s;
}

inline void check_colors(const char* type, const std::vector<float>& colors, std::size_t count) {
  if (colors.empty()) return;
  if (colors.size() != 4 * count)
    throw Error(std::string(type) + ": 'color' has " + std::to_string(colors.size() / 4) +
                " elements but there are " + std::to_string(count) + " primitives");
  for (std::size_t i = 0; i < colors.size(); ++i)
    if (!std::isfinite(colors[i])) throw Error(std::string(type) + ": 'color' " + std::to_string(i / 4) + " is not finite");
}

}  // namespace box_detail

class Boxes {
public:
  /// `boxes`: one Box3f per primitive; `colors`: r,g,b,a per box, or empty.
  explicit Boxes(std::vector<Box3f> boxes, std::vector<float> colors = {})
      : data_(std::make_shared<const Data>(Data{std::move(boxes), std::move(colors)})),
        translucent_(translucent(data_->colors)) {}

  std::size_t count() const { return data_->boxes.size(); }
  std::size_t owned_bytes() const { return count() * sizeof(Box3f) + data_->colors.size() * sizeof(float); }

  void validate() const {
    if (data_->boxes.empty()) throw Error("box: 'box' is missing or empty");
    for (std::size_t i = 0; i < count(); ++i) {
      const Box3f& b = data_->boxes[i];
      for (int k = 0; k < 3; ++k)
        if (!std::isfinite(b.lower[k]) || !std::isfinite(b.upper[k]) || b.lower[k] > b.upper[k])
          throw Error("box: 'box' " + std::to_string(i) + " is not a finite box with lower <= upper");
    }
    box_detail::check_colors("box", data_->colors, count());
  }

  Box3f bounds() const {
    Box3f box;
    for (const Box3f& b : data_->boxes) box.extend(b);
    return box;
  }
  Box3f primitive_bounds(std::uint32_t i) const { return data_->boxes[i]; }

  template <class Arch>
  RTCGeometry create_embree_geometry(const accel::Device& device) const {
    return accel::create_user_geometry<Arch>(device, *this, count());
  }

  /// Slab test; a ray starting inside a box hits its exit face.
  template <class Arch>
  PrimitiveHit<Arch> intersect_primitive(const Ray<simd::Float<Arch>>& ray, std::uint32_t i) const {
    using F = simd::Float<Arch>;
    const Box3f& b = data_->boxes[i];
    const Vec3<F> inv{F(1.f) / ray.dir.x, F(1.f) / ray.dir.y, F(1.f) / ray.dir.z};
    const Vec3<F> t0 = (Vec3<F>(b.lower) - ray.org) * inv, t1 = (Vec3<F>(b.upper) - ray.org) * inv;
    const Vec3<F> near = min(t0, t1), far = max(t0, t1);
    const F t_enter = simd::max(simd::max(near.x, near.y), near.z);
    const F t_exit = simd::min(simd::min(far.x, far.y), far.z);
    const auto enter_ok = (t_enter > ray.tnear) & (t_enter < ray.tfar);
    const auto exit_ok = (t_exit > ray.tnear) & (t_exit < ray.tfar);
    PrimitiveHit<Arch> hit;
    hit.hit = (t_enter <= t_exit) & (enter_ok | exit_ok);
    hit.t = simd::select(enter_ok, t_enter, t_exit);
    // The face is the slab whose plane the hit lies on; its normal opposes the ray on entry.
    const F sign = simd::select(enter_ok, F(-1.f), F(1.f));
    const auto face_x = hit.t == simd::select(enter_ok, near.x, far.x);
    const auto face_y = (!face_x) & (hit.t == simd::select(enter_ok, near.y, far.y));
    const auto face_z = (!face_x) & (!face_y);
    const auto along = [&](const F& d, const auto& face) {
      return simd::select(face, simd::select(d >= F(0.f), sign, -sign), F(0.f));
    };
    hit.ng = {along(ray.dir.x, face_x), along(ray.dir.y, face_y), along(ray.dir.z, face_z)};
    return hit;
  }

  template <class Arch>
  SurfaceSample<Arch> surface(const accel::Hit<Arch>& hit, const simd::Mask<Arch>& lanes) const {
    return box_detail::colored_surface<Arch>(data_->colors, hit, lanes);
  }
  /// Whether a colour has alpha below 1.
  bool translucent_colors() const { return translucent_; }

private:
  struct Data {
    std::vector<Box3f> boxes;
    std::vector<float> colors;
  };
  std::shared_ptr<const Data> data_;
  bool translucent_;
};

/// Planes a·x + b·y + c·z + d = 0, each optionally bounded by a box (OSPRay's
/// `plane.bounds`). An unbounded plane is given a bounding box of ±1e18 in Embree's BVH,
/// far beyond any scene float coordinates can resolve.
class Planes {
public:
  struct Plane {
    float a, b, c, d;
  };
  static constexpr float unbounded = 1e18f;

  /// `bounds`: empty, or one box per plane; `colors`: r,g,b,a per plane, or empty.
  explicit Planes(std::vector<Plane> planes, std::vector<Box3f> bounds = {}, std::vector<float> colors = {})
      : data_(std::make_shared<const Data>(Data{std::move(planes), std::move(bounds), std::move(colors)})),
        translucent_(translucent(data_->colors)) {}

  std::size_t count() const { return data_->planes.size(); }
  std::size_t owned_bytes() const {
    return count() * sizeof(Plane) + data_->bounds.size() * sizeof(Box3f) + data_->colors.size() * sizeof(float);
  }

  void validate() const {
    const Data& d = *data_;
    if (d.planes.empty()) throw Error("plane: 'plane.coefficients' is missing or empty");
    for (std::size_t i = 0; i < count(); ++i) {
      const Plane& p = d.planes[i];
      if (!std::isfinite(p.a) || !std::isfinite(p.b) || !std::isfinite(p.c) || !std::isfinite(p.d))
        throw Error("plane: 'plane.coefficients' " + std::to_string(i) + " is not finite");
      if (p.a == 0.f && p.b == 0.f && p.c == 0.f)
        throw Error("plane: 'plane.coefficients' " + std::to_string(i) + " has a zero normal (a, b, c)");
    }
    if (!d.bounds.empty() && d.bounds.size() != count())
      throw Error("plane: 'plane.bounds' has " + std::to_string(d.bounds.size()) + " elements but there are " +
                  std::to_string(count()) + " planes");
    for (std::size_t i = 0; i < d.bounds.size(); ++i)
      for (int k = 0; k < 3; ++k)
        if (!std::isfinite(d.bounds[i].lower[k]) || !std::isfinite(d.bounds[i].upper[k]) ||
            d.bounds[i].lower[k] > d.bounds[i].upper[k])
          throw Error("plane: 'plane.bounds' " + std::to_string(i) + " is not a finite box with lower <= upper");
    box_detail::check_colors("plane", d.colors, count());
  }

  /// Bounded planes' boxes; unbounded planes add nothing (they cannot be framed).
  Box3f bounds() const {
    Box3f box;
    for (const Box3f& b : data_->bounds) box.extend(b);
    return box;
  }
  Box3f primitive_bounds(std::uint32_t i) const {
    if (!data_->bounds.empty()) return data_->bounds[i];
    return {Vec3f{-unbounded, -unbounded, -unbounded}, Vec3f{unbounded, unbounded, unbounded}};
  }

  template <class Arch>
  RTCGeometry create_embree_geometry(const accel::Device& device) const {
    return accel::create_user_geometry<Arch>(device, *this, count());
  }

  template <class Arch>
  PrimitiveHit<Arch> intersect_primitive(const Ray<simd::Float<Arch>>& ray, std::uint32_t i) const {
    using F = simd::Float<Arch>;
    const Plane& p = data_->planes[i];
    const Vec3<F> n(Vec3f{p.a, p.b, p.c});
    const F t = -(dot(n, ray.org) + F(p.d)) / dot(n, ray.dir);
    PrimitiveHit<Arch> hit;
    hit.hit = (t > ray.tnear) & (t < ray.tfar);
    if (!data_->bounds.empty()) {
      const Box3f& b = data_->bounds[i];
      const Vec3<F> x = ray.org + ray.dir * t;
      // Points on an axis-aligned plane can round just outside the box's flat extent.
      const float slack = 1e-6f * std::max(1.f, length(b.size()));
      const auto inside = [&](const F& v, float lo, float hi) { return (v >= F(lo - slack)) & (v <= F(hi + slack)); };
      hit.hit = hit.hit & inside(x.x, b.lower.x, b.upper.x) & inside(x.y, b.lower.y, b.upper.y) &
                inside(x.z, b.lower.z, b.upper.z);
    }
    hit.t = t;
    hit.ng = n;
    return hit;
  }

  template <class Arch>
  SurfaceSample<Arch> surface(const accel::Hit<Arch>& hit, const simd::Mask<Arch>& lanes) const {
    return box_detail::colored_surface<Arch>(data_->colors, hit, lanes);
  }
  /// Whether a colour has alpha below 1.
  bool translucent_colors() const { return translucent_; }

private:
  struct Data {
    std::vector<Plane> planes;
    std::vector<Box3f> bounds;
    std::vector<float> colors;
  };
  std::shared_ptr<const Data> data_;
  bool translucent_;
};

}  // namespace sciray
