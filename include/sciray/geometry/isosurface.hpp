#pragma once
// Isosurface (OSPRay's `isosurface` geometry): the surfaces where a volume's interpolant
// equals one of its isovalues, intersected exactly in each cell of grids and unstructured
// meshes rather than by sampling plus bisection, so shells thinner than any sampling step
// are not missed there. How depends on
// the volume (an IsosurfaceField): grids solve the trilinear cubic cell by cell along the
// ray (isosurface_grid.hpp), unstructured volumes their cells' own interpolants
// (isosurface_unstructured.hpp); the other types, which have no cells to solve in, are
// sampled finely and bisected (isosurface_sampled.hpp).
//
// A hit's u holds the index of the isovalue it lies on (OSPRay's primitive of an
// isosurface; the surface has no texture coordinates), so that each isovalue's shell can
// take its own colour.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <type_traits>
#include <vector>

#include "sciray/accel/trace.hpp"
#include "sciray/accel/user_geometry.hpp"
#include "sciray/error.hpp"
#include "sciray/geometry/isosurface_grid.hpp"
#include "sciray/geometry/isosurface_sampled.hpp"
#include "sciray/geometry/isosurface_unstructured.hpp"
#include "sciray/geometry/surface.hpp"

namespace sciray {

class Isosurface {
public:
  template <class Volume>
  Isosurface(std::shared_ptr<const Volume> volume, std::vector<float> isovalues) : isovalues_(std::move(isovalues)) {
    if (!volume) throw Error("isosurface: 'volume' is missing");
    if (isovalues_.empty()) throw Error("isosurface: 'isovalue' is missing or empty");
    for (std::size_t i = 0; i < isovalues_.size(); ++i)
      if (!std::isfinite(isovalues_[i])) throw Error("isosurface: 'isovalue' " + std::to_string(i) + " is not finite");
    if constexpr (std::is_same_v<Volume, Unstructured>)
      field_ = std::make_shared<const UnstructuredIsosurface>(volume, isovalues_);
    else if constexpr (requires { volume->layout(); })
      field_ = std::make_shared<const GridIsosurface>(volume, isovalues_);
    else
      field_ = std::make_shared<const SampledIsosurface<Volume>>(volume, isovalues_);
    bounds_ = volume->bounds();
  }

  /// RGBA colours (4 floats each): one per isovalue, or one for all, or none (the
  /// surfaces show their material's colour).
  void set_colors(std::vector<float> rgba) {
    if (rgba.size() == 4) {
      const std::array<float, 4> one{rgba[0], rgba[1], rgba[2], rgba[3]};
      for (std::size_t i = 1; i < isovalues_.size(); ++i) rgba.insert(rgba.end(), one.begin(), one.end());
    }
    if (!rgba.empty() && rgba.size() != 4 * isovalues_.size())
      throw Error("isosurface: " + std::to_string(rgba.size() / 4) + " colours for " +
                  std::to_string(isovalues_.size()) + " isovalues (give one for all, or one for each)");
    colors_ = std::move(rgba);
  }
  bool translucent_colors() const {
    for (std::size_t i = 3; i < colors_.size(); i += 4)
      if (colors_[i] < 1.f) return true;
    return false;
  }

  std::size_t owned_bytes() const { return field_->owned_bytes() + colors_.size() * sizeof(float); }
  void validate() const {}  // everything is checked at construction
  Box3f bounds() const { return bounds_; }
  std::size_t primitive_count() const { return field_->primitive_count(); }
  Box3f primitive_bounds(std::uint32_t prim) const { return field_->primitive_bounds(prim); }

  template <class Arch>
  RTCGeometry create_embree_geometry(const accel::Device& device) const {
    return accel::create_user_geometry<Arch>(device, *this, field_->primitive_count());
  }

  /// The first isovalue crossing inside primitive `prim`, lane by lane.
  template <class Arch>
  PrimitiveHit<Arch> intersect_primitive(const Ray<simd::Float<Arch>>& ray, std::uint32_t prim) const {
    if constexpr (std::is_same_v<Arch, simd::scalar>) {
      return field_->first_crossing(ray, prim);
    } else {
      using F = simd::Float<Arch>;
      constexpr int W = simd::width<Arch>;
      alignas(64) float hit[W], t[W], nx[W], ny[W], nz[W], iso[W];
      for (int i = 0; i < W; ++i) {
        const Ray<float> r{{simd::lane(ray.org.x, i), simd::lane(ray.org.y, i), simd::lane(ray.org.z, i)},
                           {simd::lane(ray.dir.x, i), simd::lane(ray.dir.y, i), simd::lane(ray.dir.z, i)},
                           simd::lane(ray.tnear, i), simd::lane(ray.tfar, i)};
        const PrimitiveHit<simd::scalar> h = field_->first_crossing(r, prim);
        hit[i] = h.hit ? 1.f : 0.f, t[i] = h.t, nx[i] = h.ng.x, ny[i] = h.ng.y, nz[i] = h.ng.z, iso[i] = h.u;
      }
      PrimitiveHit<Arch> out;
      out.hit = F::load_aligned(hit) != F(0.f);
      out.t = F::load_aligned(t);
      out.ng = {F::load_aligned(nx), F::load_aligned(ny), F::load_aligned(nz)};
      out.u = F::load_aligned(iso);
      return out;
    }
  }

  template <class Arch>
  SurfaceSample<Arch> surface(const accel::Hit<Arch>& hit, const simd::Mask<Arch>& lanes) const {
    SurfaceSample<Arch> s;
    s.normal = normalize(hit.ng);
    s.has_color = simd::Mask<Arch>(!colors_.empty());
    if (colors_.empty()) return s;
    // The colour of the isovalue each lane hit (u holds its index).
    constexpr int W = simd::width<Arch>;
    alignas(64) float rgba[4][W];
    for (int i = 0; i < W; ++i) {
      const auto iso = simd::lane(lanes, i) ? static_cast<std::size_t>(simd::lane(hit.u, i)) : 0;
      for (int c = 0; c < 4; ++c) rgba[c][i] = colors_[4 * std::min(iso, isovalues_.size() - 1) + c];
    }
    s.color = {simd::load<Arch>(rgba[0]), simd::load<Arch>(rgba[1]), simd::load<Arch>(rgba[2])};
    s.alpha = simd::load<Arch>(rgba[3]);
    return s;
  }

private:
  std::vector<float> isovalues_;
  std::shared_ptr<const IsosurfaceField> field_;
  Box3f bounds_;
  std::vector<float> colors_;  ///< RGBA per isovalue, or empty
};

}  // namespace sciray
