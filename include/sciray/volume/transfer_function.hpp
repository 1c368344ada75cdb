#pragma once
// OSPRay's `piecewiseLinear` transfer function: `color` (RGB) and `opacity` tables, each
// spread evenly over `value` = [lo, hi] (they may differ in length), interpolated
// linearly; values outside the range take the end entries.
#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "sciray/error.hpp"
#include "sciray/math/vec.hpp"
#include "sciray/simd/packet.hpp"

namespace sciray {

class TransferFunction {
public:
  TransferFunction(std::vector<Vec3f> colors, std::vector<float> opacities, std::array<float, 2> value_range)
      : colors_(std::move(colors)), opacities_(std::move(opacities)), range_(value_range) {
    if (colors_.empty()) throw Error("transferFunction: 'color' is missing or empty");
    if (opacities_.empty()) throw Error("transferFunction: 'opacity' is missing or empty");
    if (!std::isfinite(range_[0]) || !std::isfinite(range_[1]) || !(range_[0] < range_[1]))
      throw Error("transferFunction: 'value' must be a finite range with lo < hi, got [" + std::to_string(range_[0]) +
                  ", " + std::to_string(range_[1]) + "]");
    for (std::size_t i = 0; i < colors_.size(); ++i)
      for (int k = 0; k < 3; ++k)
        if (!std::isfinite(colors_[i][k]) || colors_[i][k] < 0.f)
          throw Error("transferFunction: 'color' " + std::to_string(i) + " must be finite and not negative");
    for (std::size_t i = 0; i < opacities_.size(); ++i)
      if (!std::isfinite(opacities_[i]) || opacities_[i] < 0.f)
        throw Error("transferFunction: 'opacity' " + std::to_string(i) + " must be finite and not negative");
    // Planar tables for gathers; a repeated last entry saves a bounds check.
    for (int k = 0; k < 3; ++k) {
      for (const Vec3f& c : colors_) color_planes_[k].push_back(c[k]);
      color_planes_[k].push_back(color_planes_[k].back());
    }
    opacity_table_ = opacities_;
    opacity_table_.push_back(opacity_table_.back());
  }

  const std::array<float, 2>& value_range() const { return range_; }
  const std::vector<Vec3f>& colors() const { return colors_; }
  const std::vector<float>& opacities() const { return opacities_; }

  template <class Arch>
  simd::Float<Arch> opacity(const simd::Float<Arch>& value) const {
    return lookup<Arch>(opacity_table_, value);
  }
  template <class Arch>
  Vec3<simd::Float<Arch>> color(const simd::Float<Arch>& value) const {
    return {lookup<Arch>(color_planes_[0], value), lookup<Arch>(color_planes_[1], value),
            lookup<Arch>(color_planes_[2], value)};
  }

  /// The largest opacity over values in [lo, hi]: at an end or at a node between them,
  /// since opacity is piecewise linear. Empty-space skipping asks this per macrocell.
  float max_opacity(float lo, float hi) const {
    float best = std::max(opacity<simd::scalar>(lo), opacity<simd::scalar>(hi));
    const float n = static_cast<float>(opacities_.size() - 1);
    for (std::size_t i = 0; i < opacities_.size(); ++i) {
      const float at = range_[0] + (range_[1] - range_[0]) * (n > 0 ? static_cast<float>(i) / n : 0.f);
      if (at > lo && at < hi) best = std::max(best, opacities_[i]);
    }
    return best;
  }

private:
  template <class Arch>
  simd::Float<Arch> lookup(const std::vector<float>& table, const simd::Float<Arch>& value) const {
    using F = simd::Float<Arch>;
    const float last = static_cast<float>(table.size() - 2);  // the real last entry
    const F x = simd::min(simd::max((value - F(range_[0])) * F(last / (range_[1] - range_[0])), F(0.f)), F(last));
    const auto i = simd::to_int(x);  // truncates: floor, as x >= 0
    const F w = x - simd::to_float(i);
    const F a = simd::gather<Arch>(table.data(), i), b = simd::gather<Arch>(table.data(), i + decltype(i)(1));
    return simd::fma(b - a, w, a);
  }

  std::vector<Vec3f> colors_;
  std::vector<float> opacities_;
  std::array<float, 2> range_;
  std::array<std::vector<float>, 3> color_planes_;
  std::vector<float> opacity_table_;
};

}  // namespace sciray
