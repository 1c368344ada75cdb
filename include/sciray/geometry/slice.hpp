#pragma once
// VolumeSlice: planes coloured by a volume through a transfer function, what OSPRay draws
// for a `plane` geometry whose obj material has a `volume` texture as its `map_kd`. The
// colour at a point of the plane is the transfer function's colour of the volume's
// (filtered) value there; the planes intersect as `Planes` do, bounds included.
//
// Where the plane was hit: shading sees the hit (t, u, v, normal, ids), not the ray. A
// plane is two-dimensional, so the intersector stores the hit's coordinates in an
// orthonormal frame of the plane as the hit's u and v (a user geometry's own surface
// parameterization, which Embree carries to the hit untouched), and shading rebuilds the
// point from them: p = origin + u·e1 + v·e2. The point is in the geometry's own space
// (Embree gives instanced user geometry the ray in the instance's space), where the volume
// is sampled, as OSPRay's volume texture samples at the local position. No renderer, hit
// or surface-sample change is needed, and every renderer shades slices.
//
// The volume is a VolumeTexture (one type for every StructuredRegular). Unlike OSPRay's
// volume texture, which shows nothing beyond the volume's bounds, samples outside the
// volume take the value at its border (StructuredRegular clamps), and opacity is not used
// (an opaque plane).
#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "sciray/accel/trace.hpp"
#include "sciray/accel/user_geometry.hpp"
#include "sciray/error.hpp"
#include "sciray/geometry/boxes.hpp"
#include "sciray/geometry/surface.hpp"
#include "sciray/math/affine.hpp"
#include "sciray/math/box.hpp"
#include "sciray/volume/transfer_function.hpp"
#include "sciray/volume/volume_texture.hpp"

namespace sciray {

class VolumeSlice {
public:
  /// `planes` and `bounds` (empty, or one box per plane) as for Planes; `colors`: r,g,b,a
  /// per plane multiplying the texture's colour (a model's colours times its material's
  /// kd), or empty. Validates the planes ("plane: ..." messages).
  VolumeSlice(std::vector<Planes::Plane> planes, std::vector<Box3f> bounds, VolumeTexture texture,
              std::vector<float> colors = {})
      : planes_(planes, std::move(bounds), std::move(colors)) {
    planes_.validate();
    auto data = std::make_shared<Data>(Data{std::move(texture), {}});
    data->frames.reserve(planes.size());
    for (std::size_t i = 0; i < planes.size(); ++i)
      data->frames.push_back(frame_of(planes[i], planes_.primitive_bounds(static_cast<std::uint32_t>(i))));
    data_ = std::move(data);
  }

  /// The texture of `volume` through `transfer_function`; `texture_transform` maps points
  /// of the planes to where the volume is sampled (OSPRay's affine3f `map_kd.transform`).
  template <class Volume>
  VolumeSlice(std::vector<Planes::Plane> planes, std::vector<Box3f> bounds, std::shared_ptr<const Volume> volume,
              TransferFunction transfer_function, std::vector<float> colors = {}, Affine3f texture_transform = {})
      : VolumeSlice(std::move(planes), std::move(bounds),
                    texture_of(std::move(volume), std::move(transfer_function), texture_transform),
                    std::move(colors)) {}

  std::size_t count() const { return planes_.count(); }
  std::size_t owned_bytes() const {
    return planes_.owned_bytes() + data_->frames.size() * sizeof(Frame) + data_->texture.owned_bytes();
  }
  void validate() const { planes_.validate(); }
  Box3f bounds() const { return planes_.bounds(); }
  Box3f primitive_bounds(std::uint32_t i) const { return planes_.primitive_bounds(i); }
  const TransferFunction& transfer_function() const { return data_->texture.transfer_function(); }

  template <class Arch>
  RTCGeometry create_embree_geometry(const accel::Device& device) const {
    return accel::create_user_geometry<Arch>(device, *this, count());
  }

  /// The plane's hit, with u and v the hit point's coordinates in the plane's frame.
  template <class Arch>
  PrimitiveHit<Arch> intersect_primitive(const Ray<simd::Float<Arch>>& ray, std::uint32_t i) const {
    using F = simd::Float<Arch>;
    PrimitiveHit<Arch> hit = planes_.template intersect_primitive<Arch>(ray, i);
    const Frame& f = data_->frames[i];
    const Vec3<F> x = ray.org + ray.dir * hit.t - Vec3<F>(f.origin);
    hit.u = dot(x, Vec3<F>(f.e1));
    hit.v = dot(x, Vec3<F>(f.e2));
    return hit;
  }

  /// The transfer function's colour of the volume's value at each lane's hit point (times
  /// the plane's colour, if any).
  template <class Arch>
  SurfaceSample<Arch> surface(const accel::Hit<Arch>& hit, const simd::Mask<Arch>& lanes) const {
    using F = simd::Float<Arch>;
    constexpr int W = simd::width<Arch>;
    SurfaceSample<Arch> s = planes_.template surface<Arch>(hit, lanes);  // normal, plane colours
    alignas(64) float values[W];
    for (int i = 0; i < W; ++i) {
      values[i] = 0.f;
      if (!simd::lane(lanes, i)) continue;
      const Frame& f = data_->frames[static_cast<std::size_t>(simd::lane(hit.prim_id, i))];
      const Vec3f p = f.origin + f.e1 * simd::lane(hit.u, i) + f.e2 * simd::lane(hit.v, i);
      values[i] = data_->texture.value(p);
    }
    const Vec3<F> color = data_->texture.transfer_function().template color<Arch>(simd::load<Arch>(values));
    s.color = select(s.has_color, s.color * color, color);
    s.has_color = lanes;
    return s;
  }

private:
  template <class Volume>
  static VolumeTexture texture_of(std::shared_ptr<const Volume> volume, TransferFunction tf,
                                  const Affine3f& transform) {
    if (!volume) throw Error("slice: the volume is missing");
    return VolumeTexture(std::move(volume), std::move(tf), transform);
  }

  /// A point of the plane and an orthonormal basis of its directions.
  struct Frame {
    Vec3f origin, e1, e2;
  };

  /// The frame's origin is the point of the plane nearest the centre of its bounds (or of
  /// the world's origin for an unbounded plane), so u and v stay small where it is seen.
  static Frame frame_of(const Planes::Plane& plane, const Box3f& bounds) {
    const Vec3f normal{plane.a, plane.b, plane.c};
    const Vec3f n = normalize(normal);
    const bool bounded = std::abs(bounds.upper.x) < Planes::unbounded;
    const Vec3f centre = bounded ? (bounds.lower + bounds.upper) * 0.5f : Vec3f{0.f, 0.f, 0.f};
    // centre − n (n·centre + d/|normal|): the nearest point of the plane.
    const Vec3f origin = centre - n * (dot(n, centre) + plane.d / length(normal));
    // Cross with the axis the normal is least along, for a well-conditioned e1.
    const Vec3f a{std::abs(n.x), std::abs(n.y), std::abs(n.z)};
    const Vec3f axis = a.x <= a.y && a.x <= a.z ? Vec3f{1.f, 0.f, 0.f}
                       : a.y <= a.z             ? Vec3f{0.f, 1.f, 0.f}
                                                : Vec3f{0.f, 0.f, 1.f};
    const Vec3f e1 = normalize(cross(n, axis));
    return {origin, e1, cross(n, e1)};
  }

  struct Data {
    VolumeTexture texture;
    std::vector<Frame> frames;
  };

  Planes planes_;
  std::shared_ptr<const Data> data_;
};

}  // namespace sciray
