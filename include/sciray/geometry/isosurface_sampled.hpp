#pragma once
// The isosurface of a volume without cells of its own to solve in (particles, AMR, VDB,
// spherical grids; geometry/isosurface.hpp): Embree sees one primitive per macrocell whose
// value range holds an isovalue, and inside it a ray samples the volume every quarter of a
// typical cell and bisects, on the volume itself, the first step whose ends straddle an
// isovalue. A surface that enters and leaves between two samples (a shell thinner than a
// quarter cell along the ray) is missed; the grids and unstructured cells are solved
// exactly instead (isosurface_grid.hpp, isosurface_unstructured.hpp).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <vector>

#include "sciray/geometry/isosurface_field.hpp"
#include "sciray/volume/macrocells.hpp"

namespace sciray {

template <class Volume>
class SampledIsosurface final : public IsosurfaceField {
public:
  static constexpr std::int64_t macrocell_cells = 8;
  static constexpr float steps_per_cell = 4.f;

  SampledIsosurface(std::shared_ptr<const Volume> volume, const std::vector<float>& isovalues)
      : volume_(std::move(volume)), isovalues_(isovalues), grid_(volume_->macrocell_grid(macrocell_cells)) {
    std::vector<float> ranges = grid_.empty_ranges();
    volume_->widen_macrocell_ranges(grid_, macrocell_cells, ranges);
    for (std::size_t i = 0; i < grid_.count(); ++i)
      for (float iso : isovalues_)
        if (iso >= ranges[2 * i] && iso <= ranges[2 * i + 1]) {
          active_.push_back(static_cast<std::uint32_t>(i));
          break;
        }
    const Vec3f& cell = volume_->cell_size();
    step_ = std::min({cell.x, cell.y, cell.z}) / steps_per_cell;
  }

  std::size_t primitive_count() const override { return active_.size(); }
  std::size_t owned_bytes() const override { return active_.size() * sizeof(std::uint32_t); }
  Box3f primitive_bounds(std::uint32_t prim) const override {
    const std::int64_t i = active_[prim], nx = grid_.counts[0], ny = grid_.counts[1];
    const Vec3f corner{static_cast<float>(i % nx), static_cast<float>(i / nx % ny), static_cast<float>(i / (nx * ny))};
    const Vec3f lower = grid_.lower + corner * grid_.size;
    return {lower, lower + grid_.size};
  }

  PrimitiveHit<simd::scalar> first_crossing(const Ray<float>& ray, std::uint32_t prim) const override {
    PrimitiveHit<simd::scalar> none{false, std::numeric_limits<float>::infinity(), {}};
    const Box3f box = primitive_bounds(prim);
    float t0 = ray.tnear, t1 = ray.tfar;
    for (int k = 0; k < 3; ++k) {
      const float a = (box.lower[k] - ray.org[k]) / ray.dir[k], b = (box.upper[k] - ray.org[k]) / ray.dir[k];
      t0 = std::max(t0, std::min(a, b)), t1 = std::min(t1, std::max(a, b));
    }
    if (!(t0 <= t1)) return none;
    // Steps in t of a quarter cell, on a grid shared by every macrocell along the ray so
    // that neighbours see the same samples.
    const float dt = step_ / std::sqrt(dot(ray.dir, ray.dir));
    const auto value = [&](double t) { return volume_->sample(ray.org + ray.dir * static_cast<float>(t)); };
    double ta = std::floor(t0 / dt) * dt;
    float fa = value(std::max<double>(ta, t0));
    ta = std::max<double>(ta, t0);
    for (double tb = std::floor(t0 / dt) * dt + dt; ta < t1; tb += dt) {
      tb = std::min<double>(tb, t1);
      const float fb = value(tb);
      // The nearest crossing of any isovalue in this step.
      PrimitiveHit<simd::scalar> hit = none;
      for (std::size_t i = 0; i < isovalues_.size(); ++i) {
        const float iso = isovalues_[i];
        if (!(fa == fa && fb == fb) || (fa < iso) == (fb < iso)) continue;
        double lo = ta, hi = tb;
        for (int it = 0; it < 40 && hi - lo > 0; ++it) {
          const double mid = 0.5 * (lo + hi);
          if ((value(mid) < iso) == (fa < iso))
            lo = mid;
          else
            hi = mid;
        }
        if (static_cast<float>(hi) < hit.t) hit.hit = true, hit.t = static_cast<float>(hi), hit.u = static_cast<float>(i);
      }
      if (hit.hit) {
        hit.ng = volume_->template gradient<simd::scalar>(ray.org + ray.dir * hit.t);
        if (!(dot(hit.ng, hit.ng) > 0.f)) hit.ng = -ray.dir;
        return hit;
      }
      ta = tb, fa = fb;
    }
    return none;
  }

private:
  std::shared_ptr<const Volume> volume_;
  std::vector<float> isovalues_;
  MacrocellGrid grid_;
  std::vector<std::uint32_t> active_;  ///< macrocells whose range holds an isovalue
  float step_;
};

}  // namespace sciray
