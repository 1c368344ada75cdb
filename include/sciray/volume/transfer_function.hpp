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
    build_prefix_integrals();
  }

  const std::array<float, 2>& value_range() const { return range_; }
  const std::vector<Vec3f>& colors() const { return colors_; }
  const std::vector<float>& opacities() const { return opacities_; }

  /// A value that is not a number (outside an unstructured volume's cells) is transparent.
  template <class Arch>
  simd::Float<Arch> opacity(const simd::Float<Arch>& value) const {
    using F = simd::Float<Arch>;
    return simd::select(value == value, lookup<Arch>(opacity_table_, value), F(0.f));
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

  /// Pre-integration (Engel, Kraus, Ertl 2001, with 1D prefix integrals): the mean
  /// opacity and the opacity-weighted mean colour over values from `a` to `b`, which is
  /// what a step sees if the value varies linearly along it. Exact for the opacity of such
  /// a step however narrow the transfer function's features; colour ignores attenuation
  /// within the step.
  template <class Arch>
  void segment(const simd::Float<Arch>& a, const simd::Float<Arch>& b, simd::Float<Arch>& mean_opacity,
               Vec3<simd::Float<Arch>>& mean_color) const {
    using F = simd::Float<Arch>;
    const F mid = (a + b) * F(0.5f);
    const F span = b - a;
    // Below this the difference of prefix integrals cancels: use the midpoint instead.
    const auto narrow = simd::abs(span) <= F(1e-4f * (range_[1] - range_[0]));
    const F inv_span = F(1.f) / simd::select(narrow, F(1.f), span);
    const auto mean_of = [&](const std::vector<float>& table) {
      return (prefix<Arch>(table, b) - prefix<Arch>(table, a)) * inv_span;
    };
    const F sigma = mean_of(prefix_opacity_);
    const Vec3<F> weighted{mean_of(prefix_color_[0]), mean_of(prefix_color_[1]), mean_of(prefix_color_[2])};
    const F point_sigma = opacity<Arch>(mid);
    const Vec3<F> point_color = color<Arch>(mid);
    mean_opacity = simd::select(narrow, point_sigma, simd::max(sigma, F(0.f)));
    const auto has_weight = (!narrow) & (sigma > F(1e-12f));
    const F inv_sigma = F(1.f) / simd::select(has_weight, sigma, F(1.f));
    mean_color = select(has_weight, weighted * inv_sigma, point_color);
  }

private:
  static constexpr int prefix_bins = 4096;

  /// ∫ opacity and ∫ colour·opacity from the range's start, tabulated over the range
  /// (trapezoids on a grid fine against the tables' own spacing).
  void build_prefix_integrals() {
    const float width = (range_[1] - range_[0]) / prefix_bins;
    prefix_opacity_.assign(prefix_bins + 2, 0.f);
    for (auto& table : prefix_color_) table.assign(prefix_bins + 2, 0.f);
    double sum = 0, sum_color[3] = {0, 0, 0};
    const auto at = [&](int i) { return range_[0] + width * static_cast<float>(i); };
    for (int i = 1; i <= prefix_bins; ++i) {
      const float v0 = at(i - 1), v1 = at(i);
      const float s0 = opacity<simd::scalar>(v0), s1 = opacity<simd::scalar>(v1);
      const Vec3f c0 = color<simd::scalar>(v0), c1 = color<simd::scalar>(v1);
      sum += 0.5 * (s0 + s1) * width;
      for (int k = 0; k < 3; ++k) sum_color[k] += 0.5 * (c0[k] * s0 + c1[k] * s1) * width;
      prefix_opacity_[i] = static_cast<float>(sum);
      for (int k = 0; k < 3; ++k) prefix_color_[k][i] = static_cast<float>(sum_color[k]);
    }
    prefix_opacity_[prefix_bins + 1] = prefix_opacity_[prefix_bins];
    for (auto& table : prefix_color_) table[prefix_bins + 1] = table[prefix_bins];
  }

  /// A prefix integral at `value`; outside the range the end entries' integrand continues.
  template <class Arch>
  simd::Float<Arch> prefix(const std::vector<float>& table, const simd::Float<Arch>& value) const {
    using F = simd::Float<Arch>;
    const float lo = range_[0], hi = range_[1];
    const F scale(static_cast<float>(prefix_bins) / (hi - lo));
    const F x = simd::min(simd::max((value - F(lo)) * scale, F(0.f)), F(static_cast<float>(prefix_bins)));
    const auto i = simd::to_int(x);
    const F w = x - simd::to_float(i);
    const F a = simd::gather<Arch>(table.data(), i), b = simd::gather<Arch>(table.data(), i + decltype(i)(1));
    const F inside = simd::fma(b - a, w, a);
    // Beyond the ends the integrand is the end value's (opacity, colour·opacity).
    const float slope_lo = (table[1] - table[0]) * (prefix_bins / (hi - lo));
    const float slope_hi = (table[prefix_bins] - table[prefix_bins - 1]) * (prefix_bins / (hi - lo));
    const F below = simd::min(value - F(lo), F(0.f)) * F(slope_lo);
    const F above = simd::max(value - F(hi), F(0.f)) * F(slope_hi);
    return inside + below + above;
  }

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
  std::vector<float> prefix_opacity_;
  std::array<std::vector<float>, 3> prefix_color_;
};

}  // namespace sciray
