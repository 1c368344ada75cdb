#pragma once
// The isosurface of a structured regular volume (geometry/isosurface.hpp), intersected
// exactly: along a ray inside one cell the trilinear interpolant is a cubic in t. Its
// extrema (roots of the derivative) cut the cell's t-interval into pieces on which it is
// monotone; the first piece whose ends straddle the isovalue holds the first crossing,
// found by bisection to float resolution (Marmitt, Kleer, Wald, Friedrich, Slusallek,
// "Fast and accurate ray-voxel intersection techniques for iso-surface ray tracing", VMV
// 2004).
//
// Embree sees one primitive per macrocell (8³ cells) whose value range contains an
// isovalue; inside it the ray walks the cells (3D DDA) and solves only in cells whose
// corner range contains one. The volume's voxel type is erased behind a cell loader, so
// one GridIsosurface type serves every StructuredRegular.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "sciray/error.hpp"
#include "sciray/geometry/isosurface_field.hpp"
#include "sciray/volume/structured_regular.hpp"

namespace sciray {

class GridIsosurface final : public IsosurfaceField {
public:
  static constexpr std::int64_t macrocell_cells = 8;

  template <class Volume>
  GridIsosurface(std::shared_ptr<const Volume> volume, const std::vector<float>& isovalues)
      : volume_(volume), isovalues_(isovalues), dims_(volume->dims()), grid_(volume->grid()) {
    load_cell_ = [](const void* v, std::int64_t x, std::int64_t y, std::int64_t z, float out[8]) {
      static_cast<const Volume*>(v)->layout().cell(x, y, z, out);
    };
    gradient_ = [](const void* v, const Vec3f& p) { return static_cast<const Volume*>(v)->template gradient<simd::scalar>(p); };
    find_active_macrocells();
  }

  std::size_t primitive_count() const override { return active_.size(); }
  std::size_t owned_bytes() const override { return active_.size() * sizeof(std::uint32_t); }
  Box3f primitive_bounds(std::uint32_t prim) const override {
    const auto [lo, hi] = macrocell_cells_range(active_[prim]);
    return {world(lo), world(hi)};
  }

  /// The first crossing for one ray: walk the macrocell's cells in ray order.
  PrimitiveHit<simd::scalar> first_crossing(const Ray<float>& ray, std::uint32_t prim) const override {
    PrimitiveHit<simd::scalar> none{false, std::numeric_limits<float>::infinity(), {}};
    const auto [lo, hi] = macrocell_cells_range(active_[prim]);
    // The ray in voxel coordinates (voxel i at i).
    const Vec3f shift = grid_.cell_centered ? Vec3f{0.5f, 0.5f, 0.5f} : Vec3f{0.f, 0.f, 0.f};
    const Vec3f inv_spacing{1.f / grid_.spacing.x, 1.f / grid_.spacing.y, 1.f / grid_.spacing.z};
    const Vec3f o = (ray.org - grid_.origin) * inv_spacing - shift, d = ray.dir * inv_spacing;
    float t0 = ray.tnear, t1 = ray.tfar;
    for (int k = 0; k < 3; ++k) {
      const float a = (lo[k] - o[k]) / d[k], b = (hi[k] - o[k]) / d[k];
      t0 = std::max(t0, std::min(a, b)), t1 = std::min(t1, std::max(a, b));
    }
    if (!(t0 <= t1)) return none;
    // 3D DDA over the cells, starting in the one containing the entry point.
    std::int64_t cell[3];
    float next[3], delta[3];
    int step[3];
    const Vec3f entry = o + d * t0;
    for (int k = 0; k < 3; ++k) {
      // Clamped as a float before the conversion: the entry of a ray along a cell face, or
      // far out, may be NaN or beyond any integer.
      const float first = std::floor(entry[k]);
      cell[k] = first >= hi[k] - 1.f ? static_cast<std::int64_t>(hi[k]) - 1
                : first > lo[k]        ? static_cast<std::int64_t>(first)
                                       : static_cast<std::int64_t>(lo[k]);
      step[k] = d[k] >= 0.f ? 1 : -1;
      const float boundary = static_cast<float>(cell[k] + (step[k] > 0 ? 1 : 0));
      next[k] = d[k] != 0.f ? (boundary - o[k]) / d[k] : std::numeric_limits<float>::infinity();
      delta[k] = d[k] != 0.f ? std::fabs(1.f / d[k]) : std::numeric_limits<float>::infinity();
    }
    float t_cell = t0;
    while (t_cell <= t1) {
      const int axis = next[0] < next[1] ? (next[0] < next[2] ? 0 : 2) : (next[1] < next[2] ? 1 : 2);
      const float t_exit = std::min(next[axis], t1);
      float c[8];
      load_cell_(volume_.get(), cell[0], cell[1], cell[2], c);
      const float cmin = *std::min_element(c, c + 8), cmax = *std::max_element(c, c + 8);
      float best = std::numeric_limits<float>::infinity();
      std::size_t best_iso = 0;
      for (std::size_t k = 0; k < isovalues_.size(); ++k) {
        const float iso = isovalues_[k];
        if (!(iso >= cmin && iso <= cmax)) continue;
        if (const float t = solve_cell(c, iso, o, d, cell, t_cell, t_exit); t < best) best = t, best_iso = k;
      }
      if (best < std::numeric_limits<float>::infinity()) {
        PrimitiveHit<simd::scalar> h;
        h.hit = true;
        h.t = best;
        h.u = static_cast<float>(best_iso);
        // The normal: the gradient by central differences, which unlike the cell's own
        // trilinear gradient is continuous across cells (no faceting).
        h.ng = gradient_(volume_.get(), ray.org + ray.dir * best);
        if (!(dot(h.ng, h.ng) > 0.f)) {
          const Vec3f p = o + d * best;
          h.ng = cell_gradient(c, {p.x - cell[0], p.y - cell[1], p.z - cell[2]}) * inv_spacing;
        }
        if (!(dot(h.ng, h.ng) > 0.f)) h.ng = -ray.dir;
        return h;
      }
      cell[axis] += step[axis];
      if (cell[axis] < static_cast<std::int64_t>(lo[axis]) || cell[axis] >= static_cast<std::int64_t>(hi[axis])) break;
      t_cell = next[axis];
      next[axis] += delta[axis];
    }
    return none;
  }


private:
  /// Cells [lo, hi) of macrocell `index` in voxel coordinates.
  std::pair<Vec3f, Vec3f> macrocell_cells_range(std::uint32_t index) const {
    const std::int64_t mx = index % cells_[0], my = (index / cells_[0]) % cells_[1], mz = index / (cells_[0] * cells_[1]);
    const std::int64_t m[3] = {mx, my, mz};
    std::array<float, 3> lo, hi;
    for (int k = 0; k < 3; ++k) {
      lo[k] = static_cast<float>(m[k] * macrocell_cells);
      hi[k] = static_cast<float>(std::min((m[k] + 1) * macrocell_cells, dims_[k] - 1));
    }
    return {{lo[0], lo[1], lo[2]}, {hi[0], hi[1], hi[2]}};
  }

  Vec3f world(const Vec3f& voxel) const {
    const Vec3f shift = grid_.cell_centered ? Vec3f{0.5f, 0.5f, 0.5f} : Vec3f{0.f, 0.f, 0.f};
    return grid_.origin + (voxel + shift) * grid_.spacing;
  }

  void find_active_macrocells() {
    for (int k = 0; k < 3; ++k) cells_[k] = std::max<std::int64_t>(1, (dims_[k] - 1 + macrocell_cells - 1) / macrocell_cells);
    float corners[8];
    for (std::int64_t mz = 0; mz < cells_[2]; ++mz)
      for (std::int64_t my = 0; my < cells_[1]; ++my)
        for (std::int64_t mx = 0; mx < cells_[0]; ++mx) {
          float lo = std::numeric_limits<float>::infinity(), hi = -lo;
          for (std::int64_t z = mz * macrocell_cells; z < std::min((mz + 1) * macrocell_cells, dims_[2] - 1); ++z)
            for (std::int64_t y = my * macrocell_cells; y < std::min((my + 1) * macrocell_cells, dims_[1] - 1); ++y)
              for (std::int64_t x = mx * macrocell_cells; x < std::min((mx + 1) * macrocell_cells, dims_[0] - 1); ++x) {
                load_cell_(volume_.get(), x, y, z, corners);
                for (float c : corners) {
                  if (!std::isfinite(c))
                    throw Error("isosurface: the volume has a non-finite voxel near (" + std::to_string(x) + ", " +
                                std::to_string(y) + ", " + std::to_string(z) + ")");
                  lo = std::min(lo, c), hi = std::max(hi, c);
                }
              }
          for (float iso : isovalues_)
            if (iso >= lo && iso <= hi) {
              active_.push_back(static_cast<std::uint32_t>((mz * cells_[1] + my) * cells_[0] + mx));
              break;
            }
        }
  }

  static float trilinear(const float c[8], float x, float y, float z) {
    const float x00 = c[0] + (c[1] - c[0]) * x, x10 = c[2] + (c[3] - c[2]) * x;
    const float x01 = c[4] + (c[5] - c[4]) * x, x11 = c[6] + (c[7] - c[6]) * x;
    const float y0 = x00 + (x10 - x00) * y, y1 = x01 + (x11 - x01) * y;
    return y0 + (y1 - y0) * z;
  }

  static Vec3f cell_gradient(const float c[8], const Vec3f& f) {
    const float x = f.x, y = f.y, z = f.z;
    return {(1 - y) * (1 - z) * (c[1] - c[0]) + y * (1 - z) * (c[3] - c[2]) + (1 - y) * z * (c[5] - c[4]) + y * z * (c[7] - c[6]),
            (1 - x) * (1 - z) * (c[2] - c[0]) + x * (1 - z) * (c[3] - c[1]) + (1 - x) * z * (c[6] - c[4]) + x * z * (c[7] - c[5]),
            (1 - x) * (1 - y) * (c[4] - c[0]) + x * (1 - y) * (c[5] - c[1]) + (1 - x) * y * (c[6] - c[2]) + x * y * (c[7] - c[3])};
  }

  /// The first t in [ta, tb] where the cell's interpolant crosses `iso`, or infinity.
  static float solve_cell(const float c[8], float iso, const Vec3f& o, const Vec3f& d, const std::int64_t cell[3],
                          float ta, float tb) {
    // Cell-local coordinates are offsets from the cell's corner: keep them small.
    const Vec3f base{static_cast<float>(cell[0]), static_cast<float>(cell[1]), static_cast<float>(cell[2])};
    return first_crossing_of_cubic(
        [&](double t) {
          const Vec3f p = o + d * static_cast<float>(t) - base;
          return static_cast<double>(trilinear(c, p.x, p.y, p.z)) - iso;
        },
        ta, tb);
  }

  std::shared_ptr<const void> volume_;
  std::vector<float> isovalues_;
  VolumeDims dims_;
  VolumeGrid grid_;
  void (*load_cell_)(const void*, std::int64_t, std::int64_t, std::int64_t, float*) = nullptr;
  Vec3f (*gradient_)(const void*, const Vec3f&) = nullptr;
  std::array<std::int64_t, 3> cells_{};
  std::vector<std::uint32_t> active_;
};

}  // namespace sciray
