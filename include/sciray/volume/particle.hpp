#pragma once
// Particles (OSPRay's `particle` volume, which is Open VKL's): a field of Gaussian radial
// basis functions, one per particle (molecular dynamics, SPH, N-body output), as Open VKL
// evaluates it (openvkl/devices/cpu/volume/particle/):
//
//   v(x) = Σ_i w_i exp(−|x − p_i|² / (2 r_i²))   over the particles with |x − p_i| ≤ f r_i,
//
// r_i is the Gaussian's standard deviation and f is `radiusSupportFactor`: the kernel is
// cut off at f standard deviations, not tapered, so v jumps by w_i e^(−f²/2) there. Where
// `clampMaxCumulativeValue` c > 0 the value is min(v, c). (Open VKL clamps its running
// sum leaf by leaf and stops once it reaches c: the same unless weights are negative,
// where its result depends on its traversal order and this one does not.) The domain is
// the union of the support spheres' boxes: inside it, away from every particle, a sample
// is 0; outside it a sample is `background` (NaN by default: transparent).
//
// A sample finds its particles through a bounding volume hierarchy over the support
// boxes (leaves of at most 4 particles, stored in leaf order). Macrocell ranges bound each
// kernel over the macrocell by its values at the macrocell's nearest and farthest points
// (the kernel falls with distance), summed: conservative, and tight where particles are
// sparse. The gradient is analytic: the sum of the kernels' gradients.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <sstream>
#include <string>
#include <vector>

#include "sciray/error.hpp"
#include "sciray/math/box.hpp"
#include "sciray/math/vec.hpp"
#include "sciray/simd/packet.hpp"
#include "sciray/volume/lane_by_lane.hpp"
#include "sciray/volume/macrocells.hpp"

namespace sciray {

/// A particle volume as OSPRay's parameters describe it.
struct ParticleData {
  std::vector<Vec3f> positions;            ///< particle.position
  std::vector<float> radii;                ///< particle.radius: each kernel's standard deviation
  std::vector<float> weights;              ///< particle.weight: each kernel's height (empty: 1 each)
  float radius_support_factor = 3.f;       ///< radiusSupportFactor: the cut-off, in radii
  float clamp_max_cumulative_value = 0.f;  ///< clampMaxCumulativeValue: > 0 clamps the sum
  /// estimateValueRanges: value_range() estimated from the field (true), or taken as
  /// [Σ negative weights (0 if none), clampMaxCumulativeValue] (false, which needs a clamp).
  bool estimate_value_ranges = true;
  float background = std::numeric_limits<float>::quiet_NaN();  ///< the value outside bounds()
};

class Particles {
public:
  explicit Particles(ParticleData data)
      : factor_(data.radius_support_factor), clamp_(data.clamp_max_cumulative_value), background_(data.background) {
    validate(data);
    build_hierarchy(data);
    range_ = data.estimate_value_ranges ? estimated_range() : assumed_range(data);
  }

  std::size_t particle_count() const { return particles_.size(); }
  Box3f bounds() const { return nodes_.front().box; }
  std::size_t owned_bytes() const { return particles_.size() * sizeof(Particle) + nodes_.size() * sizeof(Node); }
  /// The smallest and largest value inside bounds(). Estimated (estimateValueRanges, the
  /// default): 0 (the box's corners lie outside every support) and the values found by
  /// climbing the field from every particle's centre towards its weight's sign; each end
  /// is a value the field takes, so the range is never too wide, and it holds every
  /// local extremum that a climb reaches. Else [Σ negative weights (0 if none), c], where
  /// Open VKL assumes [0, c].
  std::array<float, 2> value_range() const { return range_; }

  /// The median particle radius on every axis: Open VKL's nominal step in a particle leaf
  /// is its smallest radius, which OSPRay divides by the sampling rate.
  const Vec3f& cell_size() const { return cell_size_; }

  /// Macrocells of about n typical cells a side over the volume's box, at most 128 a side.
  MacrocellGrid macrocell_grid(std::int64_t n) const { return MacrocellGrid::over(bounds(), cell_size_.x, n); }

  /// Widens every macrocell's range by the field's bounds over it: each kernel lies
  /// between its values at the macrocell's nearest and farthest points (0 where those
  /// leave its support), and the sum between the sums of those; a macrocell that no
  /// support reaches holds 0. The boxes are padded a little, and the sums widened by
  /// 1e-5 of their magnitude, so that float rounding in sample() cannot leave them.
  void widen_macrocell_ranges(const MacrocellGrid& m, std::int64_t, std::vector<float>& ranges) const {
    const std::size_t count = m.count();
    std::vector<float> lo(count, 0.f), hi(count, 0.f), magnitude(count, 0.f);
    const Box3f box = bounds();
    const float largest = std::max({std::fabs(box.lower.x), std::fabs(box.lower.y), std::fabs(box.lower.z),
                                    std::fabs(box.upper.x), std::fabs(box.upper.y), std::fabs(box.upper.z)});
    const float pad = 1e-3f * std::max({m.size.x, m.size.y, m.size.z}) + 1e-6f * largest;
    for (const Particle& q : particles_) {
      const float support = std::sqrt(q.support2);
      std::int64_t first[3], last[3];
      // Far from the origin the padding (1e-6 of the largest coordinate) over a thin axis's
      // small macrocells reaches beyond any integer: cell_along clamps it.
      for (int k = 0; k < 3; ++k)
        first[k] = m.cell_along(k, q.centre[k] - support - pad), last[k] = m.cell_along(k, q.centre[k] + support + pad);
      for (std::int64_t z = first[2]; z <= last[2]; ++z)
        for (std::int64_t y = first[1]; y <= last[1]; ++y)
          for (std::int64_t x = first[0]; x <= last[0]; ++x) {
            const std::int64_t at[3] = {x, y, z};
            float near2 = 0.f, far2 = 0.f;
            for (int k = 0; k < 3; ++k) {
              const float lower = m.lower[k] + static_cast<float>(at[k]) * m.size[k] - pad;
              const float upper = lower + m.size[k] + 2.f * pad;
              const float c = q.centre[k];
              const float gap = std::max({lower - c, 0.f, c - upper}), reach = std::max(c - lower, upper - c);
              near2 += gap * gap, far2 += reach * reach;
            }
            if (near2 > q.support2) continue;
            const float nearest = q.weight * std::exp(-near2 * q.inv_two_r2);
            const float farthest = far2 <= q.support2 ? q.weight * std::exp(-far2 * q.inv_two_r2) : 0.f;
            const std::size_t i = m.index(x, y, z);
            hi[i] += std::max(nearest, farthest), lo[i] += std::min(nearest, farthest);
            magnitude[i] += std::fabs(nearest);
          }
    }
    for (std::size_t i = 0; i < count; ++i) {
      const float margin = 1e-5f * magnitude[i];
      const float a = clamped(lo[i] - margin), b = clamped(hi[i] + margin);
      ranges[2 * i] = std::min(ranges[2 * i], a);
      ranges[2 * i + 1] = std::max(ranges[2 * i + 1], b);
    }
  }

  /// The value at p: the kernels' sum (clamped) inside bounds(), else the background.
  float sample(const Vec3f& p) const {
    if (!inside(bounds(), p)) return background_;
    float sum = 0.f;
    near(p, [&](const Particle& q, const Vec3f&, float d2) { sum += q.weight * std::exp(-d2 * q.inv_two_r2); });
    return clamped(sum);
  }
  template <class Arch>
  simd::Float<Arch> sample(const Vec3<simd::Float<Arch>>& p) const {
    return scalar_per_lane<Arch>(p, [this](const Vec3f& q) { return sample(q); });
  }

  /// The analytic gradient: Σ −(x − p_i)/r_i² · w_i exp(−|x − p_i|²/(2 r_i²)) over the
  /// supports that hold x (0 outside them all). As Open VKL's, it ignores the clamp: where
  /// the sum is clamped flat, shading still shows the particles' shape.
  Vec3f gradient(const Vec3f& p) const {
    Vec3f g{0.f, 0.f, 0.f};
    near(p, [&](const Particle& q, const Vec3f& d, float d2) {
      g += d * (-2.f * q.inv_two_r2 * q.weight * std::exp(-d2 * q.inv_two_r2));
    });
    return g;
  }
  template <class Arch>
  Vec3<simd::Float<Arch>> gradient(const Vec3<simd::Float<Arch>>& p) const {
    return vector_per_lane<Arch>(p, [this](const Vec3f& q) { return gradient(q); });
  }
  template <class Arch>
  Vec3<simd::Float<Arch>> shading_gradient(const Vec3<simd::Float<Arch>>& p) const {
    return gradient<Arch>(p);
  }

private:
  struct Particle {
    Vec3f centre;
    float weight;
    float support2;    // (radiusSupportFactor · r)²
    float inv_two_r2;  // 1 / (2 r²)
  };
  struct Node {
    Box3f box;            // the support boxes beneath
    std::uint32_t first;  // leaf: its first particle in particles_; inner: its left child (right follows)
    std::uint32_t count;  // particles in a leaf, 0 for an inner node
  };

  static bool inside(const Box3f& b, const Vec3f& p) {
    return p.x >= b.lower.x && p.x <= b.upper.x && p.y >= b.lower.y && p.y <= b.upper.y && p.z >= b.lower.z &&
           p.z <= b.upper.z;
  }
  float clamped(float v) const { return clamp_ > 0.f ? std::min(v, clamp_) : v; }

  /// Calls visit(particle, p − centre, |p − centre|²) for every particle whose support
  /// holds p (Open VKL's test: |p − centre| ≤ f r, the boundary included).
  template <class Visit>
  void near(const Vec3f& p, Visit&& visit) const {
    std::uint32_t stack[64];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const Node& node = nodes_[stack[--top]];
      if (!inside(node.box, p)) continue;
      if (node.count == 0) {
        stack[top++] = node.first + 1;
        stack[top++] = node.first;
        continue;
      }
      for (std::uint32_t k = node.first; k < node.first + node.count; ++k) {
        const Particle& q = particles_[k];
        const Vec3f d = p - q.centre;
        const float d2 = dot(d, d);
        if (d2 <= q.support2) visit(q, d, d2);
      }
    }
  }

  /// The unclamped sum at p and its gradient, in one walk.
  float field(const Vec3f& p, Vec3f& g) const {
    float sum = 0.f;
    g = {0.f, 0.f, 0.f};
    near(p, [&](const Particle& q, const Vec3f& d, float d2) {
      const float k = q.weight * std::exp(-d2 * q.inv_two_r2);
      sum += k;
      g += d * (-2.f * q.inv_two_r2 * k);
    });
    return sum;
  }

  /// estimateValueRanges: from every particle's centre, climb the field (descend, for a
  /// negative weight) by steps of r²/|w| times the gradient, which from near a lone
  /// particle's centre is the Newton step onto it, halving a step that does not improve;
  /// every value met extends the range.
  std::array<float, 2> estimated_range() const {
    float lo = 0.f, hi = 0.f;
    const auto record = [&](float v) { lo = std::min(lo, clamped(v)), hi = std::max(hi, clamped(v)); };
    for (const Particle& q : particles_) {
      const float toward = q.weight >= 0.f ? 1.f : -1.f;
      const float r2 = 0.5f / q.inv_two_r2;
      const float scale = q.weight != 0.f ? toward * r2 / std::fabs(q.weight) : 0.f;
      Vec3f x = q.centre, g;
      float v = field(x, g);
      record(v);
      for (int i = 0; i < 16; ++i) {
        Vec3f step = g * scale;
        if (!(dot(step, step) > 1e-8f * r2)) break;
        bool better = false;
        for (int halving = 0; halving < 4 && !better; ++halving, step = step * 0.5f) {
          Vec3f g_next;
          const float v_next = field(x + step, g_next);
          record(v_next);
          if (toward * v_next > toward * v) x = x + step, v = v_next, g = g_next, better = true;
        }
        if (!better) break;
      }
    }
    return {lo, hi};
  }
  std::array<float, 2> assumed_range(const ParticleData& d) const {
    float negative = 0.f;
    for (const float w : d.weights) negative += std::min(w, 0.f);
    return {negative, clamp_};
  }

  static std::string number(float v) {
    std::ostringstream s;
    s << v;
    return s.str();
  }

  void validate(const ParticleData& d) const {
    const auto fail = [](const std::string& what) { throw Error("particle volume: " + what); };
    const std::size_t n = d.positions.size();
    if (n == 0) fail("'particle.position' is missing or empty");
    if (d.radii.size() != n)
      fail("'particle.radius' has " + std::to_string(d.radii.size()) + " values but 'particle.position' has " +
           std::to_string(n) + " particles");
    if (!d.weights.empty() && d.weights.size() != n)
      fail("'particle.weight' has " + std::to_string(d.weights.size()) + " values but 'particle.position' has " +
           std::to_string(n) + " particles");
    if (n > std::numeric_limits<std::uint32_t>::max()) fail("more than 2^32 - 1 particles");
    if (!(std::isfinite(factor_) && factor_ > 0.f))
      fail("'radiusSupportFactor' must be finite and greater than 0, got " + number(factor_));
    if (std::isnan(clamp_)) fail("'clampMaxCumulativeValue' is not a number");
    if (!d.estimate_value_ranges && !(clamp_ > 0.f))
      fail("'estimateValueRanges' is false, which needs 'clampMaxCumulativeValue' greater than 0, got " +
           number(clamp_));
    Box3f supports;  // the volume's box, as build_hierarchy makes it
    for (std::size_t i = 0; i < n; ++i) {
      const std::string at = ' ' + std::to_string(i);
      const Vec3f& p = d.positions[i];
      if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
        fail("'particle.position'" + at + " is not finite");
      const float r = d.radii[i];
      // (Open VKL 2 leaves particles of radius <= 0 out of its hierarchy; here they are refused.)
      if (!(std::isfinite(r) && r > 0.f))
        fail("'particle.radius'" + at + " must be finite and greater than 0, got " + number(r));
      if (!d.weights.empty() && !std::isfinite(d.weights[i])) fail("'particle.weight'" + at + " is not finite");
      // The kernel needs 1/(2r²) and (f r)², and the support box p ± f r, as floats.
      const float support = r * factor_;
      const float reach = std::max({std::fabs(p.x), std::fabs(p.y), std::fabs(p.z)}) + support;
      if (!std::isfinite(reach) || !std::isfinite(support * support) || !std::isfinite(0.5f / (r * r)))
        fail("'particle.radius'" + at + " is " + number(r) + ": with 'radiusSupportFactor' " + number(factor_) +
             " its kernel is out of float range");
      supports.extend(Box3f{p - splat(support), p + splat(support)});
    }
    // The volume's box, and its macrocells, need its width as a float.
    for (int k = 0; k < 3; ++k)
      if (!std::isfinite(supports.upper[k] - supports.lower[k]))
        fail(std::string("the particles' supports span [") + number(supports.lower[k]) + ", " +
             number(supports.upper[k]) + "] along " + "xyz"[k] + ", wider than a float holds");
  }

  void build_hierarchy(const ParticleData& d) {
    const auto count = static_cast<std::uint32_t>(d.positions.size());
    std::vector<std::uint32_t> order(count);
    std::iota(order.begin(), order.end(), 0u);
    std::vector<float> radii = d.radii;
    std::nth_element(radii.begin(), radii.begin() + count / 2, radii.end());
    cell_size_ = {radii[count / 2], radii[count / 2], radii[count / 2]};
    nodes_.reserve(static_cast<std::size_t>(count) + 1);  // a leaf holds at least 2 particles unless it is the root
    nodes_.push_back({});
    build_node(0, 0, count, d, order, 0);
    particles_.reserve(count);
    for (const std::uint32_t i : order) {
      const float r = d.radii[i], support = r * factor_;
      particles_.push_back({d.positions[i], d.weights.empty() ? 1.f : d.weights[i], support * support, 0.5f / (r * r)});
    }
  }

  void build_node(std::uint32_t node, std::uint32_t first, std::uint32_t last, const ParticleData& d,
                  std::vector<std::uint32_t>& order, int depth) {
    Box3f box, centres;
    for (std::uint32_t i = first; i < last; ++i) {
      const Vec3f& p = d.positions[order[i]];
      const float support = d.radii[order[i]] * factor_;
      box.extend(Box3f{p - splat(support), p + splat(support)});
      centres.extend(p);
    }
    constexpr std::uint32_t leaf_particles = 4;
    // The walk's stack holds 64 entries: deeper than 60 levels the rest is one leaf.
    if (last - first <= leaf_particles || depth >= 60) {
      nodes_[node] = {box, first, last - first};
      return;
    }
    const Vec3f extent = centres.upper - centres.lower;
    const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : extent.y >= extent.z ? 1 : 2;
    const std::uint32_t middle = first + (last - first) / 2;
    std::nth_element(order.begin() + first, order.begin() + middle, order.begin() + last,
                     [&](std::uint32_t a, std::uint32_t b) { return d.positions[a][axis] < d.positions[b][axis]; });
    const auto left = static_cast<std::uint32_t>(nodes_.size());
    nodes_[node] = {box, left, 0};
    nodes_.push_back({});
    nodes_.push_back({});
    build_node(left, first, middle, d, order, depth + 1);
    build_node(left + 1, middle, last, d, order, depth + 1);
  }

  float factor_;
  float clamp_;
  float background_;
  std::vector<Particle> particles_;  ///< in leaf order
  std::vector<Node> nodes_;
  Vec3f cell_size_{1.f, 1.f, 1.f};
  std::array<float, 2> range_{0.f, 0.f};
};

}  // namespace sciray
