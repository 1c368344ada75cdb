#pragma once
// The grid of macrocells that empty-space skipping and the path tracer's majorants cut a
// volume into (volume/volumetric_model.hpp): boxes of equal size from `lower`, `counts`
// of them along each axis, each holding the range of values a sample inside it can take.
// Each volume type lays the grid over its own cells and widens the ranges by its values
// (StructuredRegular: 8³ voxels; Unstructured: its cells' boxes).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "sciray/error.hpp"
#include "sciray/math/box.hpp"
#include "sciray/math/vec.hpp"

namespace sciray {

struct MacrocellGrid {
  Vec3f lower{0.f, 0.f, 0.f};  ///< where macrocell (0, 0, 0) starts
  Vec3f size{1.f, 1.f, 1.f};   ///< one macrocell's extent
  std::array<std::int64_t, 3> counts{1, 1, 1};

  /// Macrocells of about n cells of side `cell` a side over `box`, at most 128 a side: the
  /// grid of the volume types whose own cells are not a grid (StructuredRegular lays it
  /// over its voxels).
  static MacrocellGrid over(const Box3f& box, float cell, std::int64_t n) {
    MacrocellGrid m;
    m.lower = box.lower;
    for (int k = 0; k < 3; ++k) {
      const float extent = box.upper[k] - box.lower[k];
      // Clamped as a float: a tiny cell in a large box is beyond any integer (and NaN is 1).
      const float cells = std::ceil(extent / (static_cast<float>(n) * cell));
      m.counts[k] = cells >= 128.f ? 128 : cells > 1.f ? static_cast<std::int64_t>(cells) : 1;
      const float size = extent / static_cast<float>(m.counts[k]);
      (k == 0 ? m.size.x : k == 1 ? m.size.y : m.size.z) = size > 0.f ? size : 1.f;
    }
    return m;
  }

  std::size_t count() const {
    return static_cast<std::size_t>(counts[0]) * static_cast<std::size_t>(counts[1]) *
           static_cast<std::size_t>(counts[2]);
  }
  std::size_t index(std::int64_t x, std::int64_t y, std::int64_t z) const {
    return static_cast<std::size_t>((z * counts[1] + y) * counts[0] + x);
  }
  /// The macrocell along `axis` that holds coordinate `v`, clamped to the grid. Compared as
  /// a float before the conversion: v may lie beyond any integer's worth of macrocells, or be NaN.
  std::int64_t cell_along(int axis, float v) const {
    const float c = (v - lower[axis]) / size[axis];
    if (!(c > 0.f)) return 0;
    return c >= static_cast<float>(counts[axis] - 1) ? counts[axis] - 1 : static_cast<std::int64_t>(c);
  }
  /// Ranges (min, max per macrocell) that no value has widened yet.
  std::vector<float> empty_ranges() const {
    if (count() > static_cast<std::size_t>(INT32_MAX)) throw Error("volume: too many macrocells for 32-bit indices");
    std::vector<float> ranges(2 * count());
    for (std::size_t i = 0; i < count(); ++i)
      ranges[2 * i] = std::numeric_limits<float>::infinity(), ranges[2 * i + 1] = -std::numeric_limits<float>::infinity();
    return ranges;
  }
  /// Widens the range of every macrocell that `box` overlaps (clamped to the grid) by [lo, hi].
  void widen(const Box3f& box, float lo, float hi, std::vector<float>& ranges) const {
    std::int64_t first[3], last[3];
    for (int k = 0; k < 3; ++k)
      first[k] = cell_along(k, box.lower[k]), last[k] = cell_along(k, box.upper[k]);
    for (std::int64_t z = first[2]; z <= last[2]; ++z)
      for (std::int64_t y = first[1]; y <= last[1]; ++y)
        for (std::int64_t x = first[0]; x <= last[0]; ++x) {
          const std::size_t i = index(x, y, z);
          ranges[2 * i] = std::min(ranges[2 * i], lo);
          ranges[2 * i + 1] = std::max(ranges[2 * i + 1], hi);
        }
  }
};

}  // namespace sciray
