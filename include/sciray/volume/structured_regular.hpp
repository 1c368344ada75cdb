#pragma once
// StructuredRegular<Voxel, Layout> (OSPRay's `structuredRegular`): a regular grid of
// scalar voxels (uint8, int16, uint16, float, double) with `gridOrigin`, `gridSpacing`,
// vertex- or cell-centred values, and nearest, trilinear or tricubic filtering.
//
// Layouts:
//  - LinearLayout: the caller's array, x fastest, read in place (zero-copy);
//  - BrickedLayout: the paper's two-level bricking (8³-voxel bricks in 4³-brick
//    superbricks), a copy whose neighbourhoods share cache lines and pages.
// Both address voxels with 64-bit indices, so volumes over 2^32 voxels and 4 GiB work.
// A packet's positions are turned into cells in registers; the eight corner values are
// loaded lane by lane (a 64-bit gather) and interpolated in registers again, except in
// linear uint8 and float volumes of fewer than 2^31 voxels, whose corners packets load
// with the hardware's gathers of 32-bit offsets.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <type_traits>
#include <vector>

#include "sciray/error.hpp"
#include "sciray/math/box.hpp"
#include "sciray/math/vec.hpp"
#include "sciray/simd/packet.hpp"
#include "sciray/volume/macrocells.hpp"

namespace sciray {

/// Nearest voxel, trilinear, or tricubic B-spline (smooth, C², reproduces linear fields
/// exactly; it approximates rather than interpolates the voxels, as OSPRay's cubic filter).
enum class VolumeFilter { nearest, linear, cubic };

template <class Voxel>
concept VoxelType = std::is_same_v<Voxel, std::uint8_t> || std::is_same_v<Voxel, std::int16_t> ||
                    std::is_same_v<Voxel, std::uint16_t> || std::is_same_v<Voxel, float> ||
                    std::is_same_v<Voxel, double>;

using VolumeDims = std::array<std::int64_t, 3>;

/// The caller's voxels, x fastest then y then z; kept alive by `owner` if given.
template <VoxelType Voxel>
class LinearLayout {
public:
  LinearLayout(const Voxel* data, VolumeDims dims, std::shared_ptr<const void> owner = {})
      : data_(data), dims_(dims), owner_(std::move(owner)) {
    // Offsets of every voxel, plus the few bytes of a misaligned start (gather_bytes), fit an int32.
    gathers_ = gatherable_voxels && dims[0] * dims[1] * dims[2] < (std::int64_t{1} << 31) - 4;
  }
  /// Voxel types whose packets cell_packet gathers.
  static constexpr bool gatherable_voxels = std::is_same_v<Voxel, std::uint8_t> || std::is_same_v<Voxel, float>;

  const VolumeDims& dims() const { return dims_; }
  float at(std::int64_t x, std::int64_t y, std::int64_t z) const {
    return static_cast<float>(data_[(z * dims_[1] + y) * dims_[0] + x]);
  }
  /// The 8 corners of cell (x, y, z), in the order x fastest.
  void cell(std::int64_t x, std::int64_t y, std::int64_t z, float out[8]) const {
    const std::int64_t row = dims_[0], slice = dims_[0] * dims_[1];
    const Voxel* p = data_ + z * slice + y * row + x;
    out[0] = static_cast<float>(p[0]), out[1] = static_cast<float>(p[1]);
    out[2] = static_cast<float>(p[row]), out[3] = static_cast<float>(p[row + 1]);
    out[4] = static_cast<float>(p[slice]), out[5] = static_cast<float>(p[slice + 1]);
    out[6] = static_cast<float>(p[slice + row]), out[7] = static_cast<float>(p[slice + row + 1]);
  }
  std::size_t owned_bytes() const { return 0; }

  /// Whether cell_packet may be called: gatherable voxels, fewer than 2^31 of them.
  bool gathers_cells() const { return gathers_; }
  /// cell() for a packet of cells whose lower corners are (x, y, z), by hardware gathers.
  template <class Arch>
  std::array<simd::Float<Arch>, 8> cell_packet(const simd::Int<Arch>& x, const simd::Int<Arch>& y,
                                                const simd::Int<Arch>& z) const {
    using I = simd::Int<Arch>;
    const auto row = static_cast<std::int32_t>(dims_[0]), slice = static_cast<std::int32_t>(dims_[0] * dims_[1]);
    const I at = x + y * I(row) + z * I(slice);
    const std::int32_t step[8] = {0, 1, row, row + 1, slice, slice + 1, slice + row, slice + row + 1};
    std::array<simd::Float<Arch>, 8> out;
    for (int k = 0; k < 8; ++k) {
      if constexpr (std::is_same_v<Voxel, float>)
        out[k] = simd::gather<Arch>(data_, at + I(step[k]));
      else
        out[k] = simd::to_float(simd::gather_bytes<Arch>(data_, at + I(step[k])));
    }
    return out;
  }

private:
  const Voxel* data_;
  VolumeDims dims_;
  std::shared_ptr<const void> owner_;
  bool gathers_ = false;
};

/// Two-level bricking: voxel (x, y, z) lives in brick (x/8, y/8, z/8), which lives in
/// superbrick (x/32, y/32, z/32); superbricks are stored one after another, each holding
/// its 64 bricks of 512 voxels contiguously. A trilinear cell touches at most 8 bricks,
/// usually one.
template <VoxelType Voxel>
class BrickedLayout {
public:
  static constexpr std::int64_t brick = 8, bricks_per_super = 4, super = brick * bricks_per_super;

  /// Copies a linear (x fastest) array into bricks.
  BrickedLayout(const Voxel* linear, VolumeDims dims) : dims_(dims) {
    for (int k = 0; k < 3; ++k) supers_[k] = (dims[k] + super - 1) / super;
    voxels_.resize(static_cast<std::size_t>(supers_[0] * supers_[1] * supers_[2] * super * super * super));
    for (std::int64_t z = 0; z < dims[2]; ++z)
      for (std::int64_t y = 0; y < dims[1]; ++y)
        for (std::int64_t x = 0; x < dims[0]; ++x) voxels_[index(x, y, z)] = linear[(z * dims[1] + y) * dims[0] + x];
  }

  const VolumeDims& dims() const { return dims_; }
  float at(std::int64_t x, std::int64_t y, std::int64_t z) const { return static_cast<float>(voxels_[index(x, y, z)]); }
  void cell(std::int64_t x, std::int64_t y, std::int64_t z, float out[8]) const {
    if ((x & (brick - 1)) != brick - 1 && (y & (brick - 1)) != brick - 1 && (z & (brick - 1)) != brick - 1) {
      // The usual case: the cell lies inside one brick, whose voxels are x fastest.
      const Voxel* p = voxels_.data() + index(x, y, z);
      constexpr std::int64_t row = brick, slice = brick * brick;
      out[0] = static_cast<float>(p[0]), out[1] = static_cast<float>(p[1]);
      out[2] = static_cast<float>(p[row]), out[3] = static_cast<float>(p[row + 1]);
      out[4] = static_cast<float>(p[slice]), out[5] = static_cast<float>(p[slice + 1]);
      out[6] = static_cast<float>(p[slice + row]), out[7] = static_cast<float>(p[slice + row + 1]);
      return;
    }
    for (int k = 0; k < 8; ++k) out[k] = at(x + (k & 1), y + ((k >> 1) & 1), z + (k >> 2));
  }
  std::size_t owned_bytes() const { return voxels_.size() * sizeof(Voxel); }

private:
  // Indices are never negative: shifts and masks (the sizes are powers of two).
  std::size_t index(std::int64_t x, std::int64_t y, std::int64_t z) const {
    const std::int64_t superbrick = ((z >> 5) * supers_[1] + (y >> 5)) * supers_[0] + (x >> 5);
    const std::int64_t in_super = ((((z >> 3) & 3) << 2 | ((y >> 3) & 3)) << 2) | ((x >> 3) & 3);
    const std::int64_t in_brick = ((z & 7) << 6) | ((y & 7) << 3) | (x & 7);
    return static_cast<std::size_t>((superbrick << 15) | (in_super << 9) | in_brick);
  }
  static_assert(brick == 8 && bricks_per_super == 4, "index() spells out these sizes as shifts");

  VolumeDims dims_;
  std::array<std::int64_t, 3> supers_{};
  std::vector<Voxel> voxels_;
};

/// Where a regular grid's voxels sit in the world.
struct VolumeGrid {
  Vec3f origin{0.f, 0.f, 0.f};   ///< OSPRay's gridOrigin
  Vec3f spacing{1.f, 1.f, 1.f};  ///< OSPRay's gridSpacing
  bool cell_centered = false;    ///< values at cell centres rather than at vertices
};

template <VoxelType Voxel, template <class> class Layout = LinearLayout>
class StructuredRegular {
public:
  using voxel_type = Voxel;

  using Grid = VolumeGrid;

  StructuredRegular(Layout<Voxel> layout, const Grid& grid, VolumeFilter filter = VolumeFilter::linear)
      : layout_(std::move(layout)), grid_(grid), filter_(filter) {
    const VolumeDims& d = layout_.dims();
    for (int k = 0; k < 3; ++k)
      if (d[k] < 2) throw Error("structuredRegular: 'dimensions' must be at least 2 in every direction, got " +
                                std::to_string(d[0]) + "x" + std::to_string(d[1]) + "x" + std::to_string(d[2]));
    for (int k = 0; k < 3; ++k) {
      if (!(grid.spacing[k] > 0.f) || !std::isfinite(grid.spacing[k]))
        throw Error("structuredRegular: 'gridSpacing' must be positive and finite");
      if (!std::isfinite(grid.origin[k])) throw Error("structuredRegular: 'gridOrigin' must be finite");
    }
    inv_spacing_ = {1.f / grid.spacing.x, 1.f / grid.spacing.y, 1.f / grid.spacing.z};
  }

  const VolumeDims& dims() const { return layout_.dims(); }
  const Grid& grid() const { return grid_; }
  const Layout<Voxel>& layout() const { return layout_; }
  VolumeFilter filter() const { return filter_; }
  void set_filter(VolumeFilter filter) { filter_ = filter; }
  std::size_t owned_bytes() const { return layout_.owned_bytes(); }

  /// The region the values cover: vertex-centred data spans dims-1 cells, cell-centred
  /// data whole cells.
  Box3f bounds() const {
    const float extra = grid_.cell_centered ? 0.f : -1.f;
    const VolumeDims& d = dims();
    const Vec3f size{(static_cast<float>(d[0]) + extra) * grid_.spacing.x,
                     (static_cast<float>(d[1]) + extra) * grid_.spacing.y,
                     (static_cast<float>(d[2]) + extra) * grid_.spacing.z};
    return {grid_.origin, grid_.origin + size};
  }

  /// The voxel value at index (x, y, z).
  float voxel(std::int64_t x, std::int64_t y, std::int64_t z) const { return layout_.at(x, y, z); }

  /// The extent of one cell along each axis: what sampling rates are relative to.
  const Vec3f& cell_size() const { return grid_.spacing; }

  /// Macrocells of n³ cells in voxel coordinates (voxel i at i), which for cell-centred
  /// data start half a spacing inside the box.
  MacrocellGrid macrocell_grid(std::int64_t n) const {
    MacrocellGrid m;
    m.lower = grid_.cell_centered ? grid_.origin + grid_.spacing * 0.5f : grid_.origin;
    m.size = grid_.spacing * static_cast<float>(n);
    for (int k = 0; k < 3; ++k) m.counts[k] = std::max<std::int64_t>(1, (dims()[k] - 1 + n - 1) / n);
    return m;
  }
  /// Widens the ranges of macrocell_grid(n) by every voxel: each macrocell's range holds
  /// every voxel its samples can read (its cells, plus one more voxel on each side for
  /// the cubic filter's 4³ neighbourhood; every filter's sample lies within the range of
  /// the voxels it reads, as the weights are positive and sum to one).
  void widen_macrocell_ranges(const MacrocellGrid& m, std::int64_t n, std::vector<float>& ranges) const {
    const VolumeDims& d = dims();
    for (std::int64_t z = 0; z < d[2]; ++z)
      for (std::int64_t y = 0; y < d[1]; ++y)
        for (std::int64_t x = 0; x < d[0]; ++x) {
          const float v = voxel(x, y, z);
          if (!std::isfinite(v))
            throw Error("structuredRegular: voxel (" + std::to_string(x) + ", " + std::to_string(y) + ", " +
                        std::to_string(z) + ") is not finite");
          const std::int64_t at[3] = {x, y, z};
          std::int64_t lo[3], hi[3];
          for (int k = 0; k < 3; ++k) {
            lo[k] = std::clamp<std::int64_t>((at[k] - 2) / n, 0, m.counts[k] - 1);
            hi[k] = std::clamp<std::int64_t>((at[k] + 1) / n, 0, m.counts[k] - 1);
          }
          for (std::int64_t cz = lo[2]; cz <= hi[2]; ++cz)
            for (std::int64_t cy = lo[1]; cy <= hi[1]; ++cy)
              for (std::int64_t cx = lo[0]; cx <= hi[0]; ++cx) {
                const std::size_t i = m.index(cx, cy, cz);
                ranges[2 * i] = std::min(ranges[2 * i], v);
                ranges[2 * i + 1] = std::max(ranges[2 * i + 1], v);
              }
        }
  }

  /// Continuous voxel coordinates of a world position (voxel i at i).
  template <class F>
  Vec3<F> to_voxel(const Vec3<F>& p) const {
    Vec3<F> g = (p - Vec3<F>(grid_.origin)) * Vec3<F>(inv_spacing_);
    if (grid_.cell_centered) g = g - Vec3<F>(Vec3f{0.5f, 0.5f, 0.5f});
    return g;
  }

  /// The filtered value at world positions `p` (clamped to the grid at its border).
  template <class Arch>
  simd::Float<Arch> sample(const Vec3<simd::Float<Arch>>& p) const {
    using F = simd::Float<Arch>;
    const VolumeDims& d = dims();
    const Vec3<F> g = to_voxel(p);
    const auto clamp = [](const F& v, std::int64_t n) {
      return simd::min(simd::max(v, F(0.f)), F(static_cast<float>(n - 1)));
    };
    const Vec3<F> c{clamp(g.x, d[0]), clamp(g.y, d[1]), clamp(g.z, d[2])};
    const auto lerp = [](const F& a, const F& b, const F& t) { return simd::fma(b - a, t, a); };
    if constexpr (!std::is_same_v<Arch, simd::scalar> && requires { requires Layout<Voxel>::gatherable_voxels; }) {
      if (filter_ == VolumeFilter::linear && layout_.gathers_cells()) {
        using I = simd::Int<Arch>;
        // The cell's lower corner, kept one short of the last voxel so the cell exists.
        const auto lower = [](const F& v, std::int64_t n) {
          return xsimd::min(simd::to_int(v), I(static_cast<std::int32_t>(n - 2)));
        };
        const I x = lower(c.x, d[0]), y = lower(c.y, d[1]), z = lower(c.z, d[2]);
        const F wx = c.x - simd::to_float(x), wy = c.y - simd::to_float(y), wz = c.z - simd::to_float(z);
        const auto v = layout_.template cell_packet<Arch>(x, y, z);
        return lerp(lerp(lerp(v[0], v[1], wx), lerp(v[2], v[3], wx), wy),
                    lerp(lerp(v[4], v[5], wx), lerp(v[6], v[7], wx), wy), wz);
      }
    }
    constexpr int W = simd::width<Arch>;
    alignas(64) float cx[W], cy[W], cz[W];
    store<Arch>(cx, c.x), store<Arch>(cy, c.y), store<Arch>(cz, c.z);
    if (filter_ == VolumeFilter::nearest) {
      alignas(64) float v[W];
      for (int i = 0; i < W; ++i)
        v[i] = layout_.at(std::llround(cx[i]), std::llround(cy[i]), std::llround(cz[i]));
      return load<Arch>(v);
    }
    if (filter_ == VolumeFilter::cubic) {
      alignas(64) float v[W];
      for (int i = 0; i < W; ++i) v[i] = cubic(cx[i], cy[i], cz[i]);
      return load<Arch>(v);
    }
    // The cell's lower corner, kept one short of the last voxel so the cell exists.
    alignas(64) float corners[8][W], fx[W], fy[W], fz[W];
    for (int i = 0; i < W; ++i) {
      const std::int64_t x = std::min<std::int64_t>(static_cast<std::int64_t>(cx[i]), d[0] - 2);
      const std::int64_t y = std::min<std::int64_t>(static_cast<std::int64_t>(cy[i]), d[1] - 2);
      const std::int64_t z = std::min<std::int64_t>(static_cast<std::int64_t>(cz[i]), d[2] - 2);
      fx[i] = cx[i] - static_cast<float>(x), fy[i] = cy[i] - static_cast<float>(y), fz[i] = cz[i] - static_cast<float>(z);
      float cell[8];
      layout_.cell(x, y, z, cell);
      for (int k = 0; k < 8; ++k) corners[k][i] = cell[k];
    }
    const F wx = load<Arch>(fx), wy = load<Arch>(fy), wz = load<Arch>(fz);
    const F x00 = lerp(load<Arch>(corners[0]), load<Arch>(corners[1]), wx);
    const F x10 = lerp(load<Arch>(corners[2]), load<Arch>(corners[3]), wx);
    const F x01 = lerp(load<Arch>(corners[4]), load<Arch>(corners[5]), wx);
    const F x11 = lerp(load<Arch>(corners[6]), load<Arch>(corners[7]), wx);
    return lerp(lerp(x00, x10, wy), lerp(x01, x11, wy), wz);
  }

  /// The gradient of the filtered field by central differences of one voxel spacing:
  /// continuous across cells, so isosurface normals show no facets.
  template <class Arch>
  Vec3<simd::Float<Arch>> gradient(const Vec3<simd::Float<Arch>>& p) const {
    using F = simd::Float<Arch>;
    const Vec3f h = grid_.spacing;
    const auto along = [&](const Vec3f& step, float length) {
      return (sample<Arch>(p + Vec3<F>(step)) - sample<Arch>(p - Vec3<F>(step))) * F(0.5f / length);
    };
    return {along({h.x, 0.f, 0.f}, h.x), along({0.f, h.y, 0.f}, h.y), along({0.f, 0.f, h.z}, h.z)};
  }

  /// The smallest and largest voxel value.
  std::array<float, 2> value_range() const {
    std::array<float, 2> range{std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity()};
    const VolumeDims& d = dims();
    for (std::int64_t z = 0; z < d[2]; ++z)
      for (std::int64_t y = 0; y < d[1]; ++y)
        for (std::int64_t x = 0; x < d[0]; ++x) {
          const float v = layout_.at(x, y, z);
          range[0] = std::min(range[0], v), range[1] = std::max(range[1], v);
        }
    return range;
  }

  /// The gradient volumes are shaded with, as Open VKL's, which OSPRay's gradient shading
  /// uses. Trilinear: the interpolant's own derivative in the cell around p (exact for the
  /// field sampled; central differences flatten it near kinks and faces), 0 along an axis
  /// on which p lies outside the grid (where the clamped field is flat). The other
  /// filters: gradient().
  template <class Arch>
  Vec3<simd::Float<Arch>> shading_gradient(const Vec3<simd::Float<Arch>>& p) const {
    if (filter_ != VolumeFilter::linear) return gradient<Arch>(p);
    const VolumeDims& d = dims();
    const Vec3<simd::Float<Arch>> g = to_voxel(p);
    constexpr int W = simd::width<Arch>;
    alignas(64) float gx[W], gy[W], gz[W], out[3][W];
    store<Arch>(gx, g.x), store<Arch>(gy, g.y), store<Arch>(gz, g.z);
    for (int i = 0; i < W; ++i) {
      const float c[3] = {gx[i], gy[i], gz[i]};
      std::int64_t corner[3];
      float f[3];
      bool inside[3];
      for (int k = 0; k < 3; ++k) {
        const float last = static_cast<float>(d[k] - 1);
        inside[k] = c[k] >= 0.f && c[k] <= last;
        const float clamped = std::clamp(c[k], 0.f, last);
        // The cell's lower corner, kept one short of the last voxel so the cell exists.
        corner[k] = std::min<std::int64_t>(static_cast<std::int64_t>(clamped), d[k] - 2);
        f[k] = clamped - static_cast<float>(corner[k]);
      }
      float v[8];  // corner (dx, dy, dz) at dx + 2 dy + 4 dz
      layout_.cell(corner[0], corner[1], corner[2], v);
      const float ex = 1.f - f[0], ey = 1.f - f[1], ez = 1.f - f[2];
      const float dx = ey * ez * (v[1] - v[0]) + f[1] * ez * (v[3] - v[2]) + ey * f[2] * (v[5] - v[4]) +
                       f[1] * f[2] * (v[7] - v[6]);
      const float dy = ex * ez * (v[2] - v[0]) + f[0] * ez * (v[3] - v[1]) + ex * f[2] * (v[6] - v[4]) +
                       f[0] * f[2] * (v[7] - v[5]);
      const float dz = ex * ey * (v[4] - v[0]) + f[0] * ey * (v[5] - v[1]) + ex * f[1] * (v[6] - v[2]) +
                       f[0] * f[1] * (v[7] - v[3]);
      out[0][i] = inside[0] ? dx * inv_spacing_.x : 0.f;
      out[1][i] = inside[1] ? dy * inv_spacing_.y : 0.f;
      out[2][i] = inside[2] ? dz * inv_spacing_.z : 0.f;
    }
    return {load<Arch>(out[0]), load<Arch>(out[1]), load<Arch>(out[2])};
  }

private:
  /// The uniform cubic B-spline's four weights for a fraction f of a cell.
  static std::array<float, 4> bspline(float f) {
    const float f2 = f * f, f3 = f2 * f, g = 1.f - f;
    return {g * g * g / 6.f, (3.f * f3 - 6.f * f2 + 4.f) / 6.f, (-3.f * f3 + 3.f * f2 + 3.f * f + 1.f) / 6.f,
            f3 / 6.f};
  }

  /// Tricubic B-spline at voxel coordinates (x, y, z): 4³ voxels around the cell, indices
  /// clamped at the border.
  float cubic(float x, float y, float z) const {
    const VolumeDims& d = dims();
    const std::int64_t ix = std::min<std::int64_t>(static_cast<std::int64_t>(x), d[0] - 2),
                       iy = std::min<std::int64_t>(static_cast<std::int64_t>(y), d[1] - 2),
                       iz = std::min<std::int64_t>(static_cast<std::int64_t>(z), d[2] - 2);
    const auto wx = bspline(x - static_cast<float>(ix)), wy = bspline(y - static_cast<float>(iy)),
               wz = bspline(z - static_cast<float>(iz));
    const auto clamp = [](std::int64_t i, std::int64_t n) { return std::clamp<std::int64_t>(i, 0, n - 1); };
    float sum = 0.f;
    for (int k = 0; k < 4; ++k) {
      const std::int64_t vz = clamp(iz + k - 1, d[2]);
      for (int j = 0; j < 4; ++j) {
        const std::int64_t vy = clamp(iy + j - 1, d[1]);
        float row = 0.f;
        for (int i = 0; i < 4; ++i) row += wx[i] * layout_.at(clamp(ix + i - 1, d[0]), vy, vz);
        sum += wz[k] * wy[j] * row;
      }
    }
    return sum;
  }

  template <class Arch>
  static simd::Float<Arch> load(const float* p) {
    return simd::load<Arch>(p);
  }
  template <class Arch>
  static void store(float* p, const simd::Float<Arch>& v) {
    simd::store<Arch>(p, v);
  }

  Layout<Voxel> layout_;
  Grid grid_;
  VolumeFilter filter_;
  Vec3f inv_spacing_;
};

}  // namespace sciray
