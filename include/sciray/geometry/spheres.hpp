#pragma once
// Spheres (OSPRay's `sphere`): atoms, particles, glyphs, rendered exactly rather than
// tessellated. One type, two intersectors behind it:
//  - `embree`: Embree's native point geometry (needs a copied x,y,z,r buffer);
//  - `sciray`: sciray's own packet intersector (geometry/sphere_intersect.hpp) as Embree
//    user geometry, reading the caller's arrays in place.
// Both are measured in bench/ (docs/performance.md); `sciray` is the default there.
// OSPRay's `type`: spheres, discs facing the ray, or discs oriented by `sphere.normal`.
// A volume texture (OSPRay's `volume` texture as an obj `map_kd`) colours spheres by the
// volume's value at each hit point: centre + radius · the unit geometric normal, in the
// spheres' own space (the hit carries no position; a sphere's normal tells it).
#include <cmath>
#include <cstdint>
#include <memory>
#include <string>

#include "sciray/accel/embree.hpp"
#include "sciray/accel/trace.hpp"
#include "sciray/accel/user_geometry.hpp"
#include "sciray/error.hpp"
#include "sciray/geometry/data.hpp"
#include "sciray/geometry/sphere_intersect.hpp"
#include "sciray/geometry/surface.hpp"
#include "sciray/math/box.hpp"
#include "sciray/volume/volume_texture.hpp"

namespace sciray {

enum class SphereType { sphere, disc, oriented_disc };
enum class SphereIntersector { sciray, embree };

/// The owned form of a set of spheres, as loaders and generators produce it.
struct SphereData {
  PaddedVector<float> positions;  ///< x,y,z per sphere
  PaddedVector<float> radii;      ///< one per sphere, or empty for `radius`
  float radius = 0.01f;           ///< OSPRay's default
  PaddedVector<float> colors;     ///< r,g,b,a per sphere, or empty
  PaddedVector<float> normals;    ///< x,y,z per sphere, for oriented discs
  PaddedVector<float> texcoords;  ///< u,v per sphere, or empty

  std::size_t count() const { return positions.size() / 3; }
};

class Spheres {
public:
  /// Arrays the caller owns and keeps alive while sciray uses them.
  struct SharedArrays {
    StridedView<float> positions;  ///< 3 floats per sphere
    StridedView<float> radii;      ///< 1 float per sphere, optional
    float radius = 0.01f;
    StridedView<float> colors;     ///< 4 floats per sphere, optional
    StridedView<float> normals;    ///< 3 floats per sphere, for oriented discs
    StridedView<float> texcoords;  ///< 2 floats (u, v) per sphere, optional
  };

  explicit Spheres(SphereData data) : Spheres(std::make_shared<const SphereData>(std::move(data))) {}

  explicit Spheres(std::shared_ptr<const SphereData> owned) {
    const SphereData& d = *owned;
    arrays_.positions = {d.positions.data(), d.count(), 3 * sizeof(float)};
    if (!d.radii.empty()) arrays_.radii = {d.radii.data(), d.radii.size(), sizeof(float)};
    arrays_.radius = d.radius;
    if (!d.colors.empty()) arrays_.colors = {d.colors.data(), d.colors.size() / 4, 4 * sizeof(float)};
    if (!d.normals.empty()) arrays_.normals = {d.normals.data(), d.normals.size() / 3, 3 * sizeof(float)};
    if (!d.texcoords.empty()) arrays_.texcoords = {d.texcoords.data(), d.texcoords.size() / 2, 2 * sizeof(float)};
    owned_bytes_ =
        (d.positions.size() + d.radii.size() + d.colors.size() + d.normals.size() + d.texcoords.size()) * sizeof(float);
    keep_alive_ = std::move(owned);
    translucent_ = translucent(arrays_.colors);
  }

  static Spheres shared(const SharedArrays& arrays) {
    Spheres spheres;
    spheres.arrays_ = arrays;
    spheres.translucent_ = translucent(arrays.colors);
    return spheres;
  }

  /// Whether a colour has alpha below 1 (a volume texture's may be: it is 0 beyond the
  /// volume).
  bool translucent_colors() const { return translucent_ || volume_texture_; }

  /// Colours the spheres by `texture` at their hit points, times their own colours.
  Spheres& set_volume_texture(std::shared_ptr<const VolumeTexture> texture) {
    return volume_texture_ = std::move(texture), *this;
  }
  const std::shared_ptr<const VolumeTexture>& volume_texture() const { return volume_texture_; }

  Spheres& set_type(SphereType type) { return type_ = type, *this; }
  Spheres& set_intersector(SphereIntersector intersector) { return intersector_ = intersector, *this; }
  SphereType type() const { return type_; }
  SphereIntersector intersector() const { return intersector_; }
  std::size_t count() const { return arrays_.positions.count; }
  const SharedArrays& arrays() const { return arrays_; }

  /// Bytes sciray owns: the arrays it was given (0 when shared), plus for the native
  /// intersector the x,y,z,r copy Embree needs (counted by Embree's memory monitor).
  std::size_t owned_bytes() const { return owned_bytes_; }

  void validate() const {
    const auto& a = arrays_;
    if (a.positions.empty()) throw Error("sphere: 'sphere.position' is missing or empty");
    if (volume_texture_ && type_ != SphereType::sphere)
      throw Error("sphere: a volume texture colours spheres only, not discs (a disc's hit does not tell its point)");
    check_array("sphere.position", a.positions, count(), 3);
    if (a.radii.empty()) {
      if (!(a.radius > 0.f) || !std::isfinite(a.radius))
        throw Error("sphere: 'radius' must be positive and finite, got " + std::to_string(a.radius));
    } else {
      check_array("sphere.radius", a.radii, count(), 1);
      for (std::size_t i = 0; i < a.radii.count; ++i)
        if (!(*a.radii.element(i) > 0.f))
          throw Error("sphere: 'sphere.radius' " + std::to_string(i) + " must be positive, got " +
                      std::to_string(*a.radii.element(i)));
    }
    if (!a.colors.empty()) check_array("color", a.colors, count(), 4);
    if (!a.texcoords.empty()) check_array("sphere.texcoord", a.texcoords, count(), 2);
    if (type_ == SphereType::oriented_disc) {
      if (a.normals.empty()) throw Error("sphere: type 'oriented disc' needs 'sphere.normal'");
      check_array("sphere.normal", a.normals, count(), 3);
      for (std::size_t i = 0; i < a.normals.count; ++i) {
        const float* n = a.normals.element(i);
        if (n[0] == 0.f && n[1] == 0.f && n[2] == 0.f)
          throw Error("sphere: 'sphere.normal' " + std::to_string(i) + " is zero");
      }
    }
  }

  Box3f bounds() const {
    Box3f box;
    for (std::size_t i = 0; i < count(); ++i) box.extend(primitive_bounds(static_cast<std::uint32_t>(i)));
    return box;
  }

  Box3f primitive_bounds(std::uint32_t i) const {
    const Vec3f c = center(i);
    const float r = radius(i);
    return {c - Vec3f{r, r, r}, c + Vec3f{r, r, r}};
  }

  template <class Arch>
  RTCGeometry create_embree_geometry(const accel::Device& device) const {
    if (intersector_ == SphereIntersector::sciray) return accel::create_user_geometry<Arch>(device, *this, count());
    const RTCGeometryType types[] = {RTC_GEOMETRY_TYPE_SPHERE_POINT, RTC_GEOMETRY_TYPE_DISC_POINT,
                                     RTC_GEOMETRY_TYPE_ORIENTED_DISC_POINT};
    accel::GeometryHandle geometry(device, types[static_cast<int>(type_)]);
    auto* xyzr = static_cast<float*>(rtcSetNewGeometryBuffer(geometry.get(), RTC_BUFFER_TYPE_VERTEX, 0,
                                                             RTC_FORMAT_FLOAT4, 4 * sizeof(float), count()));
    device.check("sphere: rtcSetNewGeometryBuffer");
    for (std::size_t i = 0; i < count(); ++i) {
      const Vec3f c = center(static_cast<std::uint32_t>(i));
      xyzr[4 * i] = c.x, xyzr[4 * i + 1] = c.y, xyzr[4 * i + 2] = c.z;
      xyzr[4 * i + 3] = radius(static_cast<std::uint32_t>(i));
    }
    if (type_ == SphereType::oriented_disc)
      rtcSetSharedGeometryBuffer(geometry.get(), RTC_BUFFER_TYPE_NORMAL, 0, RTC_FORMAT_FLOAT3,
                                 arrays_.normals.base, 0, arrays_.normals.byte_stride, count());
    return geometry.commit(device, "sphere");
  }

  /// The own intersector for one sphere (or disc) against a packet of rays.
  template <class Arch>
  PrimitiveHit<Arch> intersect_primitive(const Ray<simd::Float<Arch>>& ray, std::uint32_t i) const {
    using F = simd::Float<Arch>;
    const Vec3<F> c(center(i));
    const F r(radius(i));
    switch (type_) {
      case SphereType::sphere: return intersect_sphere<Arch>(ray, c, r);
      case SphereType::disc: {
        // A disc facing every ray stands for a round particle. A ray that leaves its surface
        // (for shadows or ambient occlusion) would meet the copy of it that faces the new
        // direction and shade the particle by itself: rays from inside the particle's
        // sphere pass it, as Embree's own ray-facing discs skip self-intersections.
        PrimitiveHit<Arch> hit = intersect_disc<Arch>(ray, c, r, -ray.dir);
        const Vec3<F> from_center = ray.org - c;
        hit.hit = hit.hit & (dot(from_center, from_center) > r * r);
        return hit;
      }
      case SphereType::oriented_disc: {
        const float* n = arrays_.normals.element(i);
        return intersect_disc<Arch>(ray, c, r, Vec3<F>(Vec3f{n[0], n[1], n[2]}));
      }
    }
    return {};
  }

  template <class Arch>
  SurfaceSample<Arch> surface(const accel::Hit<Arch>& hit, const simd::Mask<Arch>& lanes) const {
    using I = simd::Int<Arch>;
    SurfaceSample<Arch> s;
    s.normal = normalize(hit.ng);
    s.has_color = lanes;
    if (!arrays_.texcoords.empty()) {
      // One (u, v) per sphere, as OSPRay's sphere.texcoord.
      const I at = simd::select(lanes, hit.prim_id, I(0)) *
                   I(static_cast<std::int32_t>(arrays_.texcoords.byte_stride / sizeof(float)));
      s.uv = {simd::gather<Arch>(arrays_.texcoords.data(), at), simd::gather<Arch>(arrays_.texcoords.data(), at + I(1))};
    }
    // A big sphere's hit is as precise as its radius allows, not its position: about 8
    // ulps of the radius (OSPRay's sphere epsilon), which also keeps the ground-sized
    // sphere under a small scene free of self-shadowing.
    const I prim = simd::select(lanes, hit.prim_id, I(0));
    const simd::Float<Arch> radius =
        arrays_.radii.empty()
            ? simd::Float<Arch>(arrays_.radius)
            : simd::gather<Arch>(arrays_.radii.data(), prim * I(static_cast<std::int32_t>(arrays_.radii.byte_stride / sizeof(float))));
    s.epsilon = radius * simd::Float<Arch>(0x1.fp-21f);
    if (arrays_.colors.empty()) {
      s.has_color = simd::Mask<Arch>(false);
    } else {
      const I at = prim * I(static_cast<std::int32_t>(arrays_.colors.byte_stride / sizeof(float)));
      const float* colors = arrays_.colors.data();
      s.color = {simd::gather<Arch>(colors, at), simd::gather<Arch>(colors, at + I(1)),
                 simd::gather<Arch>(colors, at + I(2))};
      if (translucent_) s.alpha = simd::gather<Arch>(colors, at + I(3));
    }
    if (volume_texture_) apply_volume_texture<Arch>(hit, lanes, prim, radius, s);
    return s;
  }

private:
  /// Multiplies the texture's colour and opacity at each lane's hit point into `s`.
  template <class Arch>
  void apply_volume_texture(const accel::Hit<Arch>& hit, const simd::Mask<Arch>& lanes, const simd::Int<Arch>& prim,
                            const simd::Float<Arch>& radius, SurfaceSample<Arch>& s) const {
    using F = simd::Float<Arch>;
    using I = simd::Int<Arch>;
    const I at = prim * I(static_cast<std::int32_t>(arrays_.positions.byte_stride / sizeof(float)));
    const float* positions = arrays_.positions.data();
    const Vec3<F> centre{simd::gather<Arch>(positions, at), simd::gather<Arch>(positions, at + I(1)),
                         simd::gather<Arch>(positions, at + I(2))};
    const Vec3<F> p = centre + normalize(hit.ng) * radius;
    Vec3<F> color;
    F opacity;
    volume_texture_->template lookup<Arch>(p, lanes, color, opacity);
    s.color = select(s.has_color, s.color * color, color);
    s.alpha = s.alpha * opacity;
    s.has_color = lanes;
  }

  Spheres() = default;

  Vec3f center(std::uint32_t i) const {
    const float* p = arrays_.positions.element(i);
    return {p[0], p[1], p[2]};
  }
  float radius(std::uint32_t i) const { return arrays_.radii.empty() ? arrays_.radius : *arrays_.radii.element(i); }

  static void check_array(const char* name, const StridedView<float>& view, std::size_t expected,
                          std::size_t components) {
    if (view.byte_stride < components * sizeof(float) || view.byte_stride % sizeof(float) != 0)
      throw Error(std::string("sphere: '") + name + "' byte stride " + std::to_string(view.byte_stride) +
                  " must be a multiple of 4 and at least " + std::to_string(components * sizeof(float)));
    if (view.count != expected)
      throw Error(std::string("sphere: '") + name + "' has " + std::to_string(view.count) + " elements but there are " +
                  std::to_string(expected) + " spheres");
    // Shading gathers with 32-bit float offsets.
    if (view.count * (view.byte_stride / sizeof(float)) > static_cast<std::size_t>(INT32_MAX))
      throw Error(std::string("sphere: '") + name + "' has more than 2^31 floats; split the spheres");
    for (std::size_t i = 0; i < view.count; ++i)
      for (std::size_t c = 0; c < components; ++c)
        if (!std::isfinite(view.element(i)[c]))
          throw Error(std::string("sphere: '") + name + "' " + std::to_string(i) + " is not finite");
  }

  SharedArrays arrays_;
  bool translucent_ = false;
  SphereType type_ = SphereType::sphere;
  SphereIntersector intersector_ = SphereIntersector::sciray;
  std::size_t owned_bytes_ = 0;
  std::shared_ptr<const void> keep_alive_;
  std::shared_ptr<const VolumeTexture> volume_texture_;
};

}  // namespace sciray
