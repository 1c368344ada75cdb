#pragma once
// Amr (OSPRay's `amr`): block-structured adaptive mesh refinement (Berger–Colella, Chombo),
// sampled as Open VKL samples it. Blocks of cell-centred values live on refinement levels;
// a block's `block.bounds` are its cells' indices, upper bound included, in its level's
// index space, and the level's `cellWidth` w maps cell i to [i·w, (i+1)·w) in AMR space,
// which object space is gridOrigin + gridSpacing · (AMR position). Finer blocks overlap
// coarser ones and win there.
//
// A sample finds the finest block that holds it through a k-d tree cut at the blocks' faces
// (each leaf lists the blocks that cover it, finest first) and interpolates trilinearly
// between the 8 cell centres of the "dual cell" of width w around it (Wald et al. 2017,
// "CPU Volume Rendering of Adaptive Mesh Refinement Data"): `current` takes w from that
// finest block, `finest` the finest level's everywhere. Each corner takes the cell that
// holds it in the finest block covering it that is not finer than w, so next to a coarser
// level the coarse cells fill in (values jump across level boundaries, as in Open VKL);
// corners past the domain's faces are clamped onto it. Outside the blocks' box a sample is
// `background`. The paper's continuous `octant` method is not implemented: it is refused.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <string>
#include <type_traits>
#include <vector>

#include "sciray/error.hpp"
#include "sciray/math/box.hpp"
#include "sciray/math/vec.hpp"
#include "sciray/simd/packet.hpp"
#include "sciray/volume/lane_by_lane.hpp"
#include "sciray/volume/macrocells.hpp"

namespace sciray {

/// OSPRay's OSPAMRMethod (Open VKL's VKLAMRMethod), with its values.
enum class AmrMethod : std::uint8_t { current = 0, finest = 1, octant = 2 };

/// OSPRay's box3i: a block's cells, lower and upper corners both included.
struct AmrBox {
  std::array<std::int32_t, 3> lower{}, upper{};
};
static_assert(sizeof(AmrBox) == 6 * sizeof(std::int32_t), "AmrBox is laid out as OSP_BOX3I");

/// An AMR volume as OSPRay's parameters describe it.
struct AmrData {
  std::vector<AmrBox> block_bounds;            ///< block.bounds: each block's cells in its level's index space
  std::vector<std::int32_t> block_level;       ///< block.level: each block's refinement level (0 = coarsest)
  std::vector<std::vector<float>> block_data;  ///< block.data: each block's cell values, x fastest
  std::vector<float> cell_width;               ///< cellWidth: each level's cell width in AMR space
  Vec3f grid_origin{0.f, 0.f, 0.f};            ///< gridOrigin
  Vec3f grid_spacing{1.f, 1.f, 1.f};           ///< gridSpacing: object units per AMR unit
  AmrMethod method = AmrMethod::current;       ///< method
  float background = std::numeric_limits<float>::quiet_NaN();  ///< the value outside the blocks
};

class Amr {
public:
  explicit Amr(AmrData data) : d_(std::move(data)) {
    validate();
    build_blocks();
    std::vector<std::uint32_t> all(blocks_.size());
    std::iota(all.begin(), all.end(), 0u);
    nodes_.push_back({});
    build_node(0, amr_box_, std::move(all));
    d_.block_bounds = {}, d_.block_level = {}, d_.block_data = {};  // copied into blocks_ and values_
  }

  std::size_t block_count() const { return blocks_.size(); }
  AmrMethod method() const { return d_.method; }
  Box3f bounds() const { return bounds_; }
  std::size_t owned_bytes() const {
    return values_.size() * sizeof(float) + blocks_.size() * sizeof(Block) + nodes_.size() * sizeof(Node) +
           leaf_blocks_.size() * sizeof(std::uint32_t) + d_.cell_width.size() * sizeof(float);
  }
  /// The smallest and largest value of any block (covered ones too: their cells fill the
  /// corners of coarser neighbours' dual cells).
  std::array<float, 2> value_range() const { return range_; }

  /// The finest level's cell in object units (its smallest side), along every axis: steps
  /// resolve the finest blocks, as OSPRay's steps there do.
  const Vec3f& cell_size() const { return cell_size_; }

  /// Macrocells of about n finest cells a side over the volume's box, at most 128 a side.
  MacrocellGrid macrocell_grid(std::int64_t n) const { return MacrocellGrid::over(bounds(), cell_size_.x, n); }
  /// Widens the ranges of `m` by every cell of every block over the macrocells within one
  /// of its cells of it: a cell's value reaches samples at most one dual cell away, whose
  /// width is never above the cell's own (see corner_value).
  void widen_macrocell_ranges(const MacrocellGrid& m, std::int64_t, std::vector<float>& ranges) const {
    std::array<std::vector<std::array<std::int64_t, 2>>, 3> spans;
    for (const Block& b : blocks_) {
      for (int k = 0; k < 3; ++k) {
        spans[k].resize(static_cast<std::size_t>(b.dims[k]));
        const auto macrocell = [&](double amr) {
          const double object = static_cast<double>(d_.grid_origin[k]) + static_cast<double>(d_.grid_spacing[k]) * amr;
          const double c = (object - static_cast<double>(m.lower[k])) / static_cast<double>(m.size[k]);
          return c <= 0. ? std::int64_t{0} : std::min<std::int64_t>(static_cast<std::int64_t>(c), m.counts[k] - 1);
        };
        const double w = b.width, slack = 1e-3 * w;  // rounding of the marcher's own lookups
        for (std::int32_t i = 0; i < b.dims[k]; ++i)
          spans[k][static_cast<std::size_t>(i)] = {macrocell(b.lower[k] + (i - 1) * w - slack),
                                                   macrocell(b.lower[k] + (i + 2) * w + slack)};
      }
      const float* v = values_.data() + b.offset;
      for (const auto& [z0, z1] : spans[2])
        for (const auto& [y0, y1] : spans[1])
          for (const auto& [x0, x1] : spans[0]) {
            const float value = *v++;
            for (std::int64_t z = z0; z <= z1; ++z)
              for (std::int64_t y = y0; y <= y1; ++y)
                for (std::int64_t x = x0; x <= x1; ++x) {
                  const std::size_t i = m.index(x, y, z);
                  ranges[2 * i] = std::min(ranges[2 * i], value);
                  ranges[2 * i + 1] = std::max(ranges[2 * i + 1], value);
                }
          }
    }
  }

  /// The value at p: the dual cell's trilinear interpolant, else the background.
  float sample(const Vec3f& p) const {
    DualCell c;
    if (!dual_cell(p, c)) return d_.background;
    const auto lerp = [](float a, float b, float t) { return a + (b - a) * t; };
    const float* v = c.values.data();
    const float y0 = lerp(lerp(v[0], v[1], c.weights[0]), lerp(v[2], v[3], c.weights[0]), c.weights[1]);
    const float y1 = lerp(lerp(v[4], v[5], c.weights[0]), lerp(v[6], v[7], c.weights[0]), c.weights[1]);
    return lerp(y0, y1, c.weights[2]);
  }
  template <class Arch>
  simd::Float<Arch> sample(const Vec3<simd::Float<Arch>>& p) const {
    return scalar_per_lane<Arch>(p, [this](const Vec3f& q) { return sample(q); });
  }

  /// The interpolant's own gradient in object space (analytic within the dual cell; 0 along
  /// an axis where the corners are clamped onto one cell, and outside the box).
  Vec3f gradient(const Vec3f& p) const {
    DualCell c;
    if (!dual_cell(p, c)) return {0.f, 0.f, 0.f};
    const auto& v = c.values;
    const auto& w = c.weights;
    // d/dw_k of the trilinear form: the differences along k, interpolated over the other two axes.
    const auto along = [&](int k) {
      const int step = 1 << k, a = (k + 1) % 3, b = (k + 2) % 3;
      float sum = 0.f;
      for (int i = 0; i < 8; ++i) {
        if (i & step) continue;
        const float wa = (i >> a) & 1 ? w[a] : 1.f - w[a], wb = (i >> b) & 1 ? w[b] : 1.f - w[b];
        sum += wa * wb * (v[i + step] - v[i]);
      }
      return sum;
    };
    return {along(0) / (c.width * d_.grid_spacing.x), along(1) / (c.width * d_.grid_spacing.y),
            along(2) / (c.width * d_.grid_spacing.z)};
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
  struct Block {
    std::array<float, 3> lower, upper;  // AMR space
    float width;
    std::int32_t level;
    std::array<std::int32_t, 3> dims;
    std::size_t offset;  // of its first value in values_
  };
  struct Node {
    float position = 0.f;     // inner: the split plane
    std::uint32_t index = 0;  // inner: the left child (the right one follows); leaf: its first entry in leaf_blocks_
    std::uint32_t count = 0;  // leaf: how many blocks cover it
    std::uint8_t axis = 3;    // 0, 1, 2 for an inner node, 3 for a leaf
  };
  struct DualCell {
    std::array<float, 8> values;  // the corners, x fastest
    std::array<float, 3> weights;
    float width;
  };

  float value(const Block& b, const std::array<float, 3>& q) const {
    std::size_t at = 0;
    for (int k = 2; k >= 0; --k) {
      const auto i = static_cast<std::int32_t>(std::floor((q[k] - b.lower[k]) / b.width));
      at = at * static_cast<std::size_t>(b.dims[k]) + static_cast<std::size_t>(std::clamp(i, 0, b.dims[k] - 1));
    }
    return values_[b.offset + at];
  }
  const Node& leaf_of(const std::array<float, 3>& q) const {
    const Node* n = &nodes_[0];
    while (n->axis < 3) n = &nodes_[n->index + (q[n->axis] >= n->position ? 1u : 0u)];
    return *n;
  }
  /// The value at dual-cell corner q of width w, as Open VKL's findDualCell finds it: the
  /// cell holding q in the finest block over q that is not finer than w. Where only finer
  /// blocks cover q (a level that does not nest in the one below, past whose list Open VKL
  /// reads), the nearest cell of the sample's own block `own`.
  float corner_value(const std::array<float, 3>& q, float w, const Block& own) const {
    const Node& leaf = leaf_of(q);
    for (std::uint32_t i = 0; i < leaf.count; ++i) {
      const Block& b = blocks_[leaf_blocks_[leaf.index + i]];
      if (b.width >= w) return value(b, q);
    }
    return value(own, q);
  }

  /// The dual cell around p; false outside the volume's box.
  bool dual_cell(const Vec3f& p, DualCell& c) const {
    if (!(p.x >= bounds_.lower.x && p.x <= bounds_.upper.x && p.y >= bounds_.lower.y && p.y <= bounds_.upper.y &&
          p.z >= bounds_.lower.z && p.z <= bounds_.upper.z))
      return false;
    const Vec3f local = (p - d_.grid_origin) * inv_spacing_;
    std::array<float, 3> a;
    for (int k = 0; k < 3; ++k) a[k] = std::clamp(local[k], amr_box_.lower[k], last_inside_[k]);
    const Node& leaf = leaf_of(a);
    const Block& own = blocks_[leaf_blocks_[leaf.index]];  // the finest block over p
    const float w = d_.method == AmrMethod::finest ? finest_width_ : own.width;
    std::array<std::array<float, 3>, 2> corner;  // the lower and upper corners' coordinates
    bool in_own = own.width == w;
    for (int k = 0; k < 3; ++k) {
      const float scaled = (a[k] - 0.5f * w) / w, first = std::floor(scaled);
      const float centre = first * w + 0.5f * w;
      c.weights[k] = scaled - first;
      corner[0][k] = std::clamp(centre, amr_box_.lower[k], last_inside_[k]);
      corner[1][k] = std::clamp(centre + w, amr_box_.lower[k], last_inside_[k]);
      in_own = in_own && corner[0][k] >= own.lower[k] && corner[1][k] < own.upper[k];
    }
    c.width = w;
    for (int i = 0; i < 8; ++i) {
      const std::array<float, 3> q{corner[i & 1][0], corner[(i >> 1) & 1][1], corner[i >> 2][2]};
      // Usually all 8 corners lie in the sample's own block, which is their answer there.
      c.values[static_cast<std::size_t>(i)] = in_own ? value(own, q) : corner_value(q, w, own);
    }
    return true;
  }

  void validate() {
    const auto fail = [](const std::string& what) { throw Error("amr volume: " + what); };
    const auto point = [](const std::array<std::int32_t, 3>& v) {
      return '(' + std::to_string(v[0]) + ", " + std::to_string(v[1]) + ", " + std::to_string(v[2]) + ')';
    };
    const std::size_t n = d_.block_bounds.size();
    if (n == 0) fail("'block.bounds' is missing or empty");
    if (d_.block_level.size() != n)
      fail("'block.level' has " + std::to_string(d_.block_level.size()) + " entries but 'block.bounds' has " +
           std::to_string(n) + " blocks");
    if (d_.block_data.size() != n)
      fail("'block.data' has " + std::to_string(d_.block_data.size()) + " arrays but 'block.bounds' has " +
           std::to_string(n) + " blocks");
    if (n >= std::numeric_limits<std::uint32_t>::max()) fail("more than 2^32 - 2 blocks");
    if (d_.cell_width.empty()) fail("'cellWidth' is missing or empty");
    for (std::size_t l = 0; l < d_.cell_width.size(); ++l) {
      const float w = d_.cell_width[l];
      if (!std::isfinite(w) || !(w > 0.f))
        fail("'cellWidth' " + std::to_string(l) + " is " + std::to_string(w) +
             "; cell widths must be finite and positive");
      if (l > 0 && !(w < d_.cell_width[l - 1]))
        fail("'cellWidth' must shrink from level to level, but level " + std::to_string(l) + "'s " + std::to_string(w) +
             " is not below level " + std::to_string(l - 1) + "'s " + std::to_string(d_.cell_width[l - 1]));
    }
    for (int k = 0; k < 3; ++k) {
      if (!std::isfinite(d_.grid_origin[k])) fail("'gridOrigin' is not finite");
      if (!std::isfinite(d_.grid_spacing[k]) || !(d_.grid_spacing[k] > 0.f))
        fail("'gridSpacing' must be finite and positive, got " + std::to_string(d_.grid_spacing[k]) + " along axis " +
             std::to_string(k));
    }
    if (d_.method == AmrMethod::octant)
      fail("'method' OSP_AMR_OCTANT (2) is not implemented; use OSP_AMR_CURRENT (0) or OSP_AMR_FINEST (1)");
    if (d_.method != AmrMethod::current && d_.method != AmrMethod::finest)
      fail("'method' " + std::to_string(static_cast<int>(d_.method)) +
           " is none of OSP_AMR_CURRENT (0), OSP_AMR_FINEST (1), OSP_AMR_OCTANT (2)");
    for (std::size_t b = 0; b < n; ++b) {
      const std::string block = "block " + std::to_string(b);
      const AmrBox& box = d_.block_bounds[b];
      const std::int32_t level = d_.block_level[b];
      if (level < 0) fail(block + " has 'block.level' " + std::to_string(level) + ", which is negative");
      if (static_cast<std::size_t>(level) >= d_.cell_width.size())
        fail(block + " is on level " + std::to_string(level) + " but 'cellWidth' has widths for " +
             std::to_string(d_.cell_width.size()) + " levels");
      std::array<std::int64_t, 3> dims;
      for (int k = 0; k < 3; ++k) {
        dims[static_cast<std::size_t>(k)] = std::int64_t{box.upper[k]} - box.lower[k] + 1;
        if (dims[static_cast<std::size_t>(k)] < 1)
          fail(block + " has 'block.bounds' upper " + point(box.upper) + " below lower " + point(box.lower));
      }
      const std::vector<float>& values = d_.block_data[b];
      if (static_cast<double>(dims[0]) * static_cast<double>(dims[1]) * static_cast<double>(dims[2]) !=
          static_cast<double>(values.size()))
        fail(block + " has " + std::to_string(values.size()) + " values in 'block.data' but its bounds hold " +
             std::to_string(dims[0]) + " x " + std::to_string(dims[1]) + " x " + std::to_string(dims[2]) + " cells");
      for (std::size_t i = 0; i < values.size(); ++i)
        if (!std::isfinite(values[i]))
          fail(block + " has a value that is not finite in 'block.data', at cell " + std::to_string(i));
    }
  }

  void build_blocks() {
    range_ = {std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity()};
    finest_width_ = std::numeric_limits<float>::infinity();
    std::size_t total = 0;
    for (const auto& v : d_.block_data) total += v.size();
    values_.reserve(total);
    for (std::size_t b = 0; b < d_.block_bounds.size(); ++b) {
      const AmrBox& box = d_.block_bounds[b];
      Block block;
      block.level = d_.block_level[b];
      block.width = d_.cell_width[static_cast<std::size_t>(block.level)];
      block.offset = values_.size();
      for (int k = 0; k < 3; ++k) {
        // In double and rounded once, so that faces of blocks on different levels agree where they should.
        block.lower[k] = static_cast<float>(static_cast<double>(box.lower[k]) * block.width);
        block.upper[k] = static_cast<float>((static_cast<double>(box.upper[k]) + 1.) * block.width);
        block.dims[k] = box.upper[k] - box.lower[k] + 1;
        set(amr_box_.lower, k, std::min(amr_box_.lower[k], block.lower[k]));
        set(amr_box_.upper, k, std::max(amr_box_.upper[k], block.upper[k]));
      }
      for (float v : d_.block_data[b]) range_[0] = std::min(range_[0], v), range_[1] = std::max(range_[1], v);
      values_.insert(values_.end(), d_.block_data[b].begin(), d_.block_data[b].end());
      d_.block_data[b] = {};
      finest_width_ = std::min(finest_width_, block.width);
      blocks_.push_back(block);
    }
    inv_spacing_ = {1.f / d_.grid_spacing.x, 1.f / d_.grid_spacing.y, 1.f / d_.grid_spacing.z};
    bounds_ = {d_.grid_origin + d_.grid_spacing * amr_box_.lower, d_.grid_origin + d_.grid_spacing * amr_box_.upper};
    for (int k = 0; k < 3; ++k)
      last_inside_[k] = std::nextafter(amr_box_.upper[k], -std::numeric_limits<float>::infinity());
    const float side = finest_width_ * std::min({d_.grid_spacing.x, d_.grid_spacing.y, d_.grid_spacing.z});
    cell_size_ = {side, side, side};
  }

  static void set(Vec3f& v, int k, float x) { (k == 0 ? v.x : k == 1 ? v.y : v.z) = x; }

  /// Cuts `region` (AMR space) at the face of one of `blocks` (those overlapping it) nearest
  /// its middle, along the widest axis that has one, until no face crosses a region: then
  /// every block listed covers all of it, and the finest of them is the answer there.
  void build_node(std::uint32_t node, const Box3f& region, std::vector<std::uint32_t> blocks) {
    int axis = -1;
    float position = 0.f;
    const Vec3f middle = region.center(), extent = region.size();
    for (int k = 0; k < 3; ++k) {
      bool found = false;
      float best = 0.f;
      for (std::uint32_t b : blocks)
        for (float face : {blocks_[b].lower[k], blocks_[b].upper[k]})
          if (face > region.lower[k] && face < region.upper[k] &&
              (!found || std::abs(face - middle[k]) < std::abs(best - middle[k])))
            best = face, found = true;
      if (found && (axis < 0 || extent[k] > extent[axis])) axis = k, position = best;
    }
    if (axis < 0) {
      make_leaf(node, region, std::move(blocks));
      return;
    }
    std::vector<std::uint32_t> left, right;
    for (std::uint32_t b : blocks) {
      if (blocks_[b].lower[axis] < position) left.push_back(b);
      if (blocks_[b].upper[axis] > position) right.push_back(b);
    }
    blocks = {};
    const auto child = static_cast<std::uint32_t>(nodes_.size());
    nodes_[node] = {position, child, 0, static_cast<std::uint8_t>(axis)};
    nodes_.push_back({});
    nodes_.push_back({});
    Box3f lower_half = region, upper_half = region;
    set(lower_half.upper, axis, position);
    set(upper_half.lower, axis, position);
    build_node(child, lower_half, std::move(left));
    build_node(child + 1, upper_half, std::move(right));
  }

  void make_leaf(std::uint32_t node, const Box3f& region, std::vector<std::uint32_t> blocks) {
    const auto fail = [](const std::string& what) { throw Error("amr volume: " + what); };
    const auto point = [](const Vec3f& v) {
      return '(' + std::to_string(v.x) + ", " + std::to_string(v.y) + ", " + std::to_string(v.z) + ')';
    };
    // Open VKL needs the blocks to cover their bounding box (level 0 usually does alone).
    if (blocks.empty())
      fail("no block covers the region from " + point(region.lower) + " to " + point(region.upper) +
           " (in AMR space, where a cell is 'cellWidth' wide) inside the blocks' bounding box");
    std::sort(blocks.begin(), blocks.end(), [&](std::uint32_t a, std::uint32_t b) {
      return blocks_[a].level != blocks_[b].level ? blocks_[a].level > blocks_[b].level : a < b;
    });
    for (std::size_t i = 1; i < blocks.size(); ++i)
      if (blocks_[blocks[i]].level == blocks_[blocks[i - 1]].level)
        fail("blocks " + std::to_string(blocks[i - 1]) + " and " + std::to_string(blocks[i]) + " overlap on level " +
             std::to_string(blocks_[blocks[i]].level) + ", around " + point(region.center()) + " in AMR space");
    nodes_[node] = {0.f, static_cast<std::uint32_t>(leaf_blocks_.size()), static_cast<std::uint32_t>(blocks.size()), 3};
    leaf_blocks_.insert(leaf_blocks_.end(), blocks.begin(), blocks.end());
  }

  AmrData d_;  // block arrays emptied once copied into blocks_ and values_
  std::vector<Block> blocks_;
  std::vector<float> values_;  // every block's values, one block after another
  std::vector<Node> nodes_;
  std::vector<std::uint32_t> leaf_blocks_;  // per leaf, the blocks covering it, finest first
  Box3f amr_box_;                           // the blocks' box in AMR space
  std::array<float, 3> last_inside_{};      // the largest AMR coordinates inside amr_box_
  Box3f bounds_;                            // amr_box_ in object space
  Vec3f inv_spacing_{1.f, 1.f, 1.f};
  Vec3f cell_size_{1.f, 1.f, 1.f};
  float finest_width_ = 1.f;
  std::array<float, 2> range_{};
};

}  // namespace sciray
