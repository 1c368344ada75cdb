#pragma once
// Vdb (OSPRay's `vdb`, Open VKL's): a sparse volume in a tree of fixed shape, as OpenVDB
// stores them (Museth 2013). Index space is cut into a root of 64³ level-1 slots of 4096³
// voxels, each of 32³ level-2 slots of 128³ voxels, each of 16³ level-3 slots of 8³
// voxels (Open VKL's default configuration, which OSPRay requires). The input is a list
// of nodes: a tile (one value over its whole slot) on level 1, 2 or 3, or a dense leaf of
// 8³ voxels on level 3 (z fastest, then y, then x: Open VKL's VKL_FORMAT_DENSE_ZYX).
//
// Values as Open VKL's sampler reads them (VdbSampler_traverseAndSample.ih):
//  - voxel (i, j, k) is the value of the node that covers it; 0 where no node does but it
//    lies in the domain, from the root's origin (the nodes' lowest corner rounded down to
//    4096) to the nodes' highest corner; `background` beyond (NaN by default);
//  - nearest: voxel floor(x); trilinear: voxel i sits at index i (not at i + 0.5), so a
//    sample reads voxels floor(x) and floor(x) + 1 of whichever nodes hold them, and
//    within the top voxel layer it reads the background (NaN: transparent there).
// Object space is indexToObject · index space; outside the nodes' box a sample is
// `background`. The tree is kept sparse: a hash table from (level, slot) to the node.
#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "sciray/error.hpp"
#include "sciray/math/affine.hpp"
#include "sciray/math/box.hpp"
#include "sciray/math/vec.hpp"
#include "sciray/simd/packet.hpp"
#include "sciray/volume/lane_by_lane.hpp"
#include "sciray/volume/macrocells.hpp"
#include "sciray/volume/structured_regular.hpp"  // VolumeFilter

namespace sciray {

/// OSPRay's OSPVolumeFormat (Open VKL's VKLFormat).
enum class VdbFormat : std::uint32_t { tile = 0, dense_zyx = 1 };

/// A vdb volume as OSPRay's parameters describe it: node.* arrays of one entry per node.
struct VdbData {
  std::vector<std::uint32_t> level;                 ///< node.level: 1 to 3 (dense nodes: 3)
  std::vector<std::array<std::int32_t, 3>> origin;  ///< node.origin: the lowest voxel, in index space
  /// node.format (VdbFormat codes). OSPRay deduces it from node.data (one value: a tile,
  /// else dense) and ignores what was set; left empty, it is deduced so here too.
  std::vector<std::uint32_t> format;
  std::vector<std::vector<float>> data;         ///< node.data: per node 1 value (tile) or 512 (dense)
  std::vector<float> packed_dense;              ///< nodesPackedDense: every dense node's 512 values, in node order
  std::vector<float> packed_tile;               ///< nodesPackedTile: every tile's value, in node order
  std::vector<std::uint32_t> temporal_format;   ///< node.temporalFormat: only 0 (constant) is supported
  bool temporal_arrays = false;                 ///< node.temporally* set: refused (no motion blur)
  Affine3f index_to_object;                     ///< indexToObject
  VolumeFilter filter = VolumeFilter::linear;   ///< filter: nearest or linear
  std::optional<VolumeFilter> gradient_filter;  ///< gradientFilter: `filter` if not set
  float background = std::numeric_limits<float>::quiet_NaN();  ///< the value beyond the domain
};

class Vdb {
public:
  static constexpr std::uint32_t leaf_level = 3;
  /// log2 of a level's voxels per axis: a level-l node spans 2^span_log(l) voxels.
  static constexpr int span_log(int level) { return level == 3 ? 3 : level == 2 ? 7 : level == 1 ? 12 : 18; }
  static constexpr std::int64_t root_span = std::int64_t{1} << 18;

  explicit Vdb(VdbData data) : background_(data.background) {
    validate(data);
    build(data);
  }

  std::size_t node_count() const { return nodes_.size(); }
  Box3f bounds() const { return bounds_; }
  std::size_t owned_bytes() const {
    return voxels_.size() * sizeof(float) + table_.size() * sizeof(Entry) + nodes_.size() * sizeof(Node);
  }
  /// The smallest and largest value the nodes hold.
  std::array<float, 2> value_range() const { return range_; }
  /// A voxel's shortest edge in object space, along every axis.
  const Vec3f& cell_size() const { return cell_size_; }
  const Affine3f& index_to_object() const { return to_object_; }
  VolumeFilter filter() const { return filter_; }

  /// Macrocells of about n voxels a side over the volume's box, at most 128 a side.
  MacrocellGrid macrocell_grid(std::int64_t n) const { return MacrocellGrid::over(bounds(), cell_size_.x, n); }
  /// Widens the ranges of `m` by every value a sample can read, over the index boxes of
  /// the samples that read it, a voxel wider on each side (trilinear reads voxels up to
  /// one below; one more for rounding): each node's values, 0 over the domain's gaps, the
  /// background over the top voxel layers (not NaN: it is transparent).
  void widen_macrocell_ranges(const MacrocellGrid& m, std::int64_t, std::vector<float>& ranges) const {
    const auto widen = [&](const std::array<std::int64_t, 3>& lo, const std::array<std::int64_t, 3>& hi, float a,
                           float b) {
      Box3f box;
      box.extend(Vec3f{static_cast<float>(lo[0] - 1), static_cast<float>(lo[1] - 1), static_cast<float>(lo[2] - 1)});
      box.extend(Vec3f{static_cast<float>(hi[0] + 1), static_cast<float>(hi[1] + 1), static_cast<float>(hi[2] + 1)});
      m.widen(to_object_.transform(box), a, b, ranges);
    };
    for (const Node& n : nodes_) {
      const std::int64_t span = std::int64_t{1} << span_log(n.level);
      widen({n.origin[0], n.origin[1], n.origin[2]}, {n.origin[0] + span, n.origin[1] + span, n.origin[2] + span}, n.lo,
            n.hi);
    }
    for_each_gap([&](const std::array<std::int64_t, 3>& lo, const std::array<std::int64_t, 3>& hi) {
      widen({lo[0] + root_[0], lo[1] + root_[1], lo[2] + root_[2]},
            {hi[0] + root_[0], hi[1] + root_[1], hi[2] + root_[2]}, 0.f, 0.f);
    });
    if (std::isnan(background_)) return;
    for (int k = 0; k < 3; ++k) {
      std::array<std::int64_t, 3> lo = lower_;
      lo[static_cast<std::size_t>(k)] = upper_[static_cast<std::size_t>(k)] - 1;
      widen(lo, upper_, background_, background_);
    }
  }

  /// The value at index (x, y, z) as Open VKL's voxel lookup returns it.
  float voxel(std::int64_t x, std::int64_t y, std::int64_t z) const {
    Cache cache;
    return voxel(x - root_[0], y - root_[1], z - root_[2], cache);
  }

private:
  struct Entry;
  /// The leaf slot of the last lookup and the node that covers it (null: a gap): the
  /// corners of a trilinear cell, and neighbouring lanes, are usually in the same one.
  struct Cache {
    std::uint64_t slot = ~std::uint64_t{0};
    const Entry* entry = nullptr;
  };
  float sample(const Vec3f& p, Cache& cache) const {
    const Vec3f g = to_index_.point(p);
    if (!inside(g)) return background_;
    const Vec3f f{std::floor(g.x), std::floor(g.y), std::floor(g.z)};
    const auto x = static_cast<std::int64_t>(f.x), y = static_cast<std::int64_t>(f.y),
               z = static_cast<std::int64_t>(f.z);
    if (filter_ == VolumeFilter::nearest) return voxel(x - root_[0], y - root_[1], z - root_[2], cache);
    float c[8];
    corners(x, y, z, c, cache);
    const float wx = g.x - f.x, wy = g.y - f.y, wz = g.z - f.z;
    const auto lerp = [](float a, float b, float t) { return a + (b - a) * t; };
    return lerp(lerp(lerp(c[0], c[1], wx), lerp(c[2], c[3], wx), wy),
                lerp(lerp(c[4], c[5], wx), lerp(c[6], c[7], wx), wy), wz);
  }

public:
  /// The filtered value at object position p; `background` outside the nodes' box.
  float sample(const Vec3f& p) const {
    Cache cache;
    return sample(p, cache);
  }
  /// Lane by lane through the scalar sample (the tree is irregular), so packets and
  /// single rays see the same values bit for bit; neighbouring lanes share a leaf lookup.
  template <class Arch>
  simd::Float<Arch> sample(const Vec3<simd::Float<Arch>>& p) const {
    Cache cache;
    return scalar_per_lane<Arch>(p, [&](const Vec3f& q) { return sample(q, cache); });
  }

  /// Open VKL's gradient: with a linear gradientFilter the trilinear interpolant's own
  /// derivative in the cell around p, carried to object space by the transpose of the
  /// object-to-index map; 0 with nearest (a piecewise constant field), outside the box
  /// and where a corner is NaN (the background).
  Vec3f gradient(const Vec3f& p) const {
    Cache cache;
    const Vec3f g = to_index_.point(p);
    if (gradient_filter_ == VolumeFilter::nearest || !inside(g)) return {0.f, 0.f, 0.f};
    const Vec3f f{std::floor(g.x), std::floor(g.y), std::floor(g.z)};
    float v[8];  // corner (dx, dy, dz) at dx + 2 dy + 4 dz
    corners(static_cast<std::int64_t>(f.x), static_cast<std::int64_t>(f.y), static_cast<std::int64_t>(f.z), v, cache);
    const float fx = g.x - f.x, fy = g.y - f.y, fz = g.z - f.z, ex = 1.f - fx, ey = 1.f - fy, ez = 1.f - fz;
    const Vec3f d{
        ey * ez * (v[1] - v[0]) + fy * ez * (v[3] - v[2]) + ey * fz * (v[5] - v[4]) + fy * fz * (v[7] - v[6]),
        ex * ez * (v[2] - v[0]) + fx * ez * (v[3] - v[1]) + ex * fz * (v[6] - v[4]) + fx * fz * (v[7] - v[5]),
        ex * ey * (v[4] - v[0]) + fx * ey * (v[5] - v[1]) + ex * fy * (v[6] - v[2]) + fx * fy * (v[7] - v[3])};
    const Vec3f out{dot(to_index_.vx, d), dot(to_index_.vy, d), dot(to_index_.vz, d)};
    return out.x == out.x && out.y == out.y && out.z == out.z ? out : Vec3f{0.f, 0.f, 0.f};
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
  struct Node {
    std::array<std::int64_t, 3> origin;  // index space
    std::uint32_t level;
    float lo, hi;  // the values it holds
  };
  /// A slot of the tree that holds a node: its values start at voxels_[first]; `mask`
  /// is 511 for a dense leaf (voxel (x, y, z) at x·64 + y·8 + z) and 0 for a tile.
  struct Entry {
    std::uint64_t key = empty_key;
    std::uint64_t first = 0;
    std::uint32_t mask = 0;
    std::uint32_t node = 0;
  };
  static constexpr std::uint64_t empty_key = ~std::uint64_t{0};

  /// The slot on `level` that holds offset (ox, oy, oz) from the root's origin: offsets
  /// are below 2^18, so 20 bits an axis hold them.
  static std::uint64_t key(std::uint32_t level, std::int64_t ox, std::int64_t oy, std::int64_t oz) {
    const int s = span_log(static_cast<int>(level));
    return std::uint64_t{level} << 60 | static_cast<std::uint64_t>(ox >> s) << 40 |
           static_cast<std::uint64_t>(oy >> s) << 20 | static_cast<std::uint64_t>(oz >> s);
  }
  static std::uint32_t local(std::int64_t ox, std::int64_t oy, std::int64_t oz) {
    return static_cast<std::uint32_t>((ox & 7) << 6 | (oy & 7) << 3 | (oz & 7));
  }
  const Entry* find(std::uint64_t k) const {
    for (std::size_t i = (k * 0x9E3779B97F4A7C15ull) >> shift_;; i = (i + 1) & (table_.size() - 1)) {
      if (table_[i].key == k) return &table_[i];
      if (table_[i].key == empty_key) return nullptr;
    }
  }
  /// The node that covers offset (ox, oy, oz), from the leaves up; null in a gap.
  const Entry* find_block(std::int64_t ox, std::int64_t oy, std::int64_t oz) const {
    for (std::uint32_t level = leaf_level; level >= 1; --level)
      if (has_level_[level])
        if (const Entry* e = find(key(level, ox, oy, oz))) return e;
    return nullptr;
  }
  const Entry* find_block(std::int64_t ox, std::int64_t oy, std::int64_t oz, Cache& cache) const {
    const std::uint64_t slot = key(leaf_level, ox, oy, oz);
    if (slot != cache.slot) cache = {slot, find_block(ox, oy, oz)};
    return cache.entry;
  }
  /// voxel() at offsets from the root's origin.
  float voxel(std::int64_t ox, std::int64_t oy, std::int64_t oz, Cache& cache) const {
    if (!in_domain(ox, oy, oz)) return background_;
    const Entry* e = find_block(ox, oy, oz, cache);
    return e ? voxels_[e->first + (local(ox, oy, oz) & e->mask)] : 0.f;
  }
  bool in_domain(std::int64_t ox, std::int64_t oy, std::int64_t oz) const {
    return ox >= 0 && oy >= 0 && oz >= 0 && ox < active_[0] && oy < active_[1] && oz < active_[2];
  }
  bool inside(const Vec3f& g) const {
    return g.x >= index_box_.lower.x && g.y >= index_box_.lower.y && g.z >= index_box_.lower.z &&
           g.x <= index_box_.upper.x && g.y <= index_box_.upper.y && g.z <= index_box_.upper.z;
  }
  /// The 8 voxels from (x, y, z) to (x + 1, y + 1, z + 1), corner (dx, dy, dz) at
  /// dx + 2 dy + 4 dz: one lookup where they share a leaf slot, else one per slot.
  void corners(std::int64_t x, std::int64_t y, std::int64_t z, float c[8], Cache& cache) const {
    const std::int64_t ox = x - root_[0], oy = y - root_[1], oz = z - root_[2];
    if ((ox & 7) != 7 && (oy & 7) != 7 && (oz & 7) != 7 && in_domain(ox, oy, oz) && in_domain(ox + 1, oy + 1, oz + 1)) {
      const Entry* e = find_block(ox, oy, oz, cache);
      if (!e) {
        std::fill(c, c + 8, 0.f);
      } else if (e->mask == 0) {
        std::fill(c, c + 8, voxels_[e->first]);
      } else {
        const float* v = voxels_.data() + e->first + local(ox, oy, oz);
        c[0] = v[0], c[1] = v[64], c[2] = v[8], c[3] = v[72], c[4] = v[1], c[5] = v[65], c[6] = v[9], c[7] = v[73];
      }
      return;
    }
    // Across a slot's face: corners in the lane's slot use its cache, the others share one.
    Cache other;
    for (int k = 0; k < 8; ++k) {
      const std::int64_t vx = ox + (k & 1), vy = oy + ((k >> 1) & 1), vz = oz + (k >> 2);
      c[k] = voxel(vx, vy, vz, key(leaf_level, vx, vy, vz) == cache.slot ? cache : other);
    }
  }

  /// Calls gap(lo, hi) for boxes of voxels (offsets from the root's origin, hi
  /// exclusive) that together make up the voxels between the nodes' lowest and highest
  /// corners that no node covers (runs along z of empty slots of the tree).
  template <class Gap>
  void for_each_gap(Gap&& gap) const {
    // Which slots hold something (a node, or a node below them): per inner node, a bit
    // per child slot, x slowest; the root's at level 0.
    std::unordered_map<std::uint64_t, std::vector<std::uint64_t>> occupied;
    const auto bitmap = [&](std::uint32_t level, const std::array<std::int64_t, 3>& o) -> std::vector<std::uint64_t>& {
      auto& bits = occupied[level == 0 ? 0 : key(level, o[0], o[1], o[2])];
      if (bits.empty())
        bits.resize(
            std::size_t{1} << (3 * (span_log(static_cast<int>(level)) - span_log(static_cast<int>(level) + 1)) - 6));
      return bits;
    };
    for (const Node& n : nodes_) {
      const std::array<std::int64_t, 3> o{n.origin[0] - root_[0], n.origin[1] - root_[1], n.origin[2] - root_[2]};
      for (std::uint32_t level = n.level; level >= 1; --level) {
        const int s = span_log(static_cast<int>(level)), per_axis = span_log(static_cast<int>(level) - 1) - s;
        const std::int64_t mask = (std::int64_t{1} << per_axis) - 1;
        const auto bit = static_cast<std::size_t>(
            (((o[0] >> s) & mask) << per_axis | ((o[1] >> s) & mask)) << per_axis | ((o[2] >> s) & mask));
        bitmap(level - 1, o)[bit >> 6] |= std::uint64_t{1} << (bit & 63);
      }
    }
    const std::array<std::int64_t, 3> lo{lower_[0] - root_[0], lower_[1] - root_[1], lower_[2] - root_[2]};
    const std::array<std::int64_t, 3> hi{upper_[0] - root_[0], upper_[1] - root_[1], upper_[2] - root_[2]};
    visit_gaps(0, {0, 0, 0}, occupied, lo, hi, gap);
  }
  template <class Gap>
  void visit_gaps(std::uint32_t level, const std::array<std::int64_t, 3>& origin,
                  const std::unordered_map<std::uint64_t, std::vector<std::uint64_t>>& occupied,
                  const std::array<std::int64_t, 3>& lo, const std::array<std::int64_t, 3>& hi, Gap& gap) const {
    const std::vector<std::uint64_t>& bits = occupied.at(level == 0 ? 0 : key(level, origin[0], origin[1], origin[2]));
    const int s = span_log(static_cast<int>(level) + 1), per_axis = span_log(static_cast<int>(level)) - s;
    const std::int64_t child = std::int64_t{1} << s, n = std::int64_t{1} << per_axis;
    std::array<std::int64_t, 3> first, last;  // the children that meet [lo, hi)
    for (std::size_t k = 0; k < 3; ++k) {
      first[k] = std::max<std::int64_t>(0, (lo[k] - origin[k]) / child);
      last[k] = std::min<std::int64_t>(n - 1, (hi[k] - 1 - origin[k]) / child);
    }
    // A z-row of children is n bits (16, 32 or 64) of one word. Rows of the same empty
    // children, one after another along y, make one box per run along z.
    const auto ones = [](std::int64_t count) {
      return count >= 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << count) - 1;
    };
    const std::uint64_t in_range = ones(last[2] - first[2] + 1) << first[2];
    const auto emit = [&](std::int64_t i, std::int64_t j0, std::int64_t j1, std::uint64_t empty) {
      while (empty) {
        const int k0 = std::countr_zero(empty), length = std::countr_one(empty >> k0);
        empty &= ~(ones(length) << k0);
        const std::array<std::int64_t, 3> a{origin[0] + i * child, origin[1] + j0 * child, origin[2] + k0 * child};
        gap(std::array<std::int64_t, 3>{std::max(a[0], lo[0]), std::max(a[1], lo[1]), std::max(a[2], lo[2])},
            std::array<std::int64_t, 3>{std::min(a[0] + child, hi[0]), std::min(origin[1] + j1 * child, hi[1]),
                                        std::min(a[2] + length * child, hi[2])});
      }
    };
    for (std::int64_t i = first[0]; i <= last[0]; ++i) {
      std::uint64_t open = 0;  // the empty children of the rows from open_from on
      std::int64_t open_from = first[1];
      for (std::int64_t j = first[1]; j <= last[1] + 1; ++j) {
        std::uint64_t empty = 0;
        if (j <= last[1]) {
          const auto at = static_cast<std::size_t>((i * n + j) * n);
          const std::uint64_t row = (bits[at >> 6] >> (at & 63)) & ones(n) & in_range;
          empty = ~row & in_range;
          for (std::uint64_t full = level + 1 < leaf_level ? row : 0; full; full &= full - 1) {
            const std::array<std::int64_t, 3> c{origin[0] + i * child, origin[1] + j * child,
                                                origin[2] + std::countr_zero(full) * child};
            if (occupied.count(key(level + 1, c[0], c[1], c[2]))) visit_gaps(level + 1, c, occupied, lo, hi, gap);
          }
        }
        if (j > last[1] || empty != open) {
          emit(i, open_from, j, open);
          open = empty, open_from = j;
        }
      }
    }
  }

  static constexpr auto dense_code = static_cast<std::uint32_t>(VdbFormat::dense_zyx);
  static void fail(const std::string& what) { throw Error("vdb volume: " + what); }
  static std::string node_name(std::size_t i) { return "node " + std::to_string(i); }

  void validate(VdbData& d) {
    const std::size_t count = d.level.size();
    if (count == 0) fail("'node.level' is missing or empty (at least one node is needed)");
    const auto same_size = [&](std::size_t size, const char* name) {
      if (size != count)
        fail(std::string("'") + name + "' has " + std::to_string(size) + " entries but 'node.level' has " +
             std::to_string(count) + " nodes");
    };
    same_size(d.origin.size(), "node.origin");
    if (!d.format.empty()) same_size(d.format.size(), "node.format");
    if (!d.temporal_format.empty()) same_size(d.temporal_format.size(), "node.temporalFormat");
    const bool packed = !d.packed_dense.empty() || !d.packed_tile.empty();
    if (packed && !d.data.empty()) fail("give either 'node.data' or 'nodesPackedDense' / 'nodesPackedTile', not both");
    if (!packed && d.data.empty()) fail("'node.data' (or 'nodesPackedDense' / 'nodesPackedTile') is missing");
    if (packed && d.format.empty()) fail("'node.format' is needed with 'nodesPackedDense' / 'nodesPackedTile'");
    if (!packed) same_size(d.data.size(), "node.data");
    if (d.temporal_arrays)
      fail(
          "'node.temporallyStructuredNumTimesteps' / 'node.temporallyUnstructuredIndices' / "
          "'node.temporallyUnstructuredTimes' are not supported (no time-varying vdb volumes)");
    for (std::size_t i = 0; i < d.temporal_format.size(); ++i)
      if (d.temporal_format[i] != 0)
        fail(node_name(i) + " has 'node.temporalFormat' " + std::to_string(d.temporal_format[i]) +
             "; only constant data (0) is supported (no time-varying vdb volumes)");
    for (const auto& [f, name] :
         {std::pair{d.filter, "filter"}, std::pair{d.gradient_filter.value_or(d.filter), "gradientFilter"}})
      if (f != VolumeFilter::nearest && f != VolumeFilter::linear)
        fail(std::string("'") + name + "' cubic (Open VKL's tricubic) is not supported; use nearest or linear");
    const Affine3f& m = d.index_to_object;
    for (const Vec3f& c : {m.vx, m.vy, m.vz, m.p})
      if (!std::isfinite(c.x) || !std::isfinite(c.y) || !std::isfinite(c.z)) fail("'indexToObject' is not finite");
    if (!(std::abs(m.determinant()) > 0.f) || !std::isfinite(m.determinant()))
      fail("'indexToObject' is singular (determinant " + std::to_string(m.determinant()) + ")");

    if (d.format.empty())  // OSPRay's deduction from node.data
      for (const auto& values : d.data)
        d.format.push_back(static_cast<std::uint32_t>(values.size() == 1 ? VdbFormat::tile : VdbFormat::dense_zyx));
    std::size_t dense = 0, tiles = 0;
    for (std::size_t i = 0; i < count; ++i) {
      const std::uint32_t level = d.level[i], format = d.format[i];
      if (level < 1 || level > 3)
        fail(node_name(i) + " has 'node.level' " + std::to_string(level) + "; levels are 1 to 3 (3: the leaves)");
      if (format != static_cast<std::uint32_t>(VdbFormat::tile) && format != dense_code)
        fail(node_name(i) + " has 'node.format' " + std::to_string(format) +
             ", which is none of tile (0), dense zyx (1)");
      const bool is_dense = format == dense_code;
      if (is_dense && level != leaf_level)
        fail(node_name(i) + " is dense on level " + std::to_string(level) + ", but dense nodes exist only on level 3");
      const std::int64_t span = std::int64_t{1} << span_log(static_cast<int>(level));
      for (int k = 0; k < 3; ++k)
        if (d.origin[i][static_cast<std::size_t>(k)] % span != 0)
          fail(node_name(i) + " has 'node.origin' (" + std::to_string(d.origin[i][0]) + ", " +
               std::to_string(d.origin[i][1]) + ", " + std::to_string(d.origin[i][2]) +
               "), which is not a multiple of its level's span " + std::to_string(span));
      (is_dense ? dense : tiles)++;
      if (!packed) {
        const std::size_t want = is_dense ? 512 : 1;
        if (d.data[i].size() != want)
          fail(node_name(i) + " is " + (is_dense ? "dense" : "a tile") + ": its 'node.data' needs " +
               std::to_string(want) + (want == 1 ? " value" : " values") + ", got " + std::to_string(d.data[i].size()));
        for (std::size_t v = 0; v < want; ++v)
          if (!std::isfinite(d.data[i][v]))
            fail(node_name(i) + " 'node.data' value " + std::to_string(v) + " is not finite");
      }
    }
    if (packed) {
      if (d.packed_dense.size() != 512 * dense)
        fail("'nodesPackedDense' has " + std::to_string(d.packed_dense.size()) + " values but the " +
             std::to_string(dense) + " dense nodes need " + std::to_string(512 * dense));
      if (d.packed_tile.size() != tiles)
        fail("'nodesPackedTile' has " + std::to_string(d.packed_tile.size()) + " values but the " +
             std::to_string(tiles) + " tiles need " + std::to_string(tiles));
      for (const auto* values : {&d.packed_dense, &d.packed_tile})
        for (std::size_t v = 0; v < values->size(); ++v)
          if (!std::isfinite((*values)[v]))
            fail(std::string(values == &d.packed_dense ? "'nodesPackedDense'" : "'nodesPackedTile'") + " value " +
                 std::to_string(v) + " is not finite");
    }
  }

  void build(VdbData& d) {
    const std::size_t count = d.level.size();
    filter_ = d.filter;
    gradient_filter_ = d.gradient_filter.value_or(d.filter);
    to_object_ = d.index_to_object;
    to_index_ = to_object_.inverse();
    // The values, packed: dense leaves' 512 each, then the tiles' one each.
    const bool packed = d.data.empty();
    std::vector<std::uint64_t> first(count);
    if (packed) {
      voxels_ = std::move(d.packed_dense);
      std::size_t dense = 0, tile = voxels_.size();
      for (std::size_t i = 0; i < count; ++i) first[i] = d.format[i] == dense_code ? 512 * dense++ : tile++;
      voxels_.insert(voxels_.end(), d.packed_tile.begin(), d.packed_tile.end());
    } else {
      for (std::size_t i = 0; i < count; ++i) {
        first[i] = voxels_.size();
        voxels_.insert(voxels_.end(), d.data[i].begin(), d.data[i].end());
        d.data[i] = {};
      }
    }
    // The nodes' box, and the root's origin below it (Open VKL's computeRootOrigin).
    nodes_.resize(count);
    for (std::size_t k = 0; k < 3; ++k) lower_[k] = std::numeric_limits<std::int64_t>::max(), upper_[k] = -lower_[k];
    range_ = {std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity()};
    for (std::size_t i = 0; i < count; ++i) {
      Node& n = nodes_[i];
      n.level = d.level[i];
      const std::int64_t span = std::int64_t{1} << span_log(static_cast<int>(n.level));
      for (std::size_t k = 0; k < 3; ++k) {
        n.origin[k] = d.origin[i][k];
        lower_[k] = std::min(lower_[k], n.origin[k]), upper_[k] = std::max(upper_[k], n.origin[k] + span);
      }
      const auto values = voxels_.begin() + static_cast<std::ptrdiff_t>(first[i]);
      const auto [lo, hi] = std::minmax_element(values, values + (d.format[i] == dense_code ? 512 : 1));
      n.lo = *lo, n.hi = *hi;
      range_ = {std::min(range_[0], n.lo), std::max(range_[1], n.hi)};
    }
    constexpr std::int64_t level1 = std::int64_t{1} << 12;
    for (std::size_t k = 0; k < 3; ++k) {
      root_[k] = (lower_[k] >= 0 ? lower_[k] : lower_[k] - level1 + 1) / level1 * level1;
      active_[k] = upper_[k] - root_[k];
      if (active_[k] > root_span)
        fail("the nodes span " + std::string(1, "xyz"[k]) + " from " + std::to_string(lower_[k]) + " to " +
             std::to_string(upper_[k]) + ", more than one root node holds (262144 voxels from a multiple of 4096)");
    }
    // The table, filled top down so a node inside a tile above it is found as it goes in.
    std::size_t capacity = 16;
    while (capacity < 2 * count) capacity *= 2;
    table_.assign(capacity, Entry{});
    shift_ = 64 - static_cast<int>(std::countr_zero(capacity));
    for (std::uint32_t level = 1; level <= leaf_level; ++level)
      for (std::size_t i = 0; i < count; ++i) {
        const Node& n = nodes_[i];
        if (n.level != level) continue;
        const std::int64_t ox = n.origin[0] - root_[0], oy = n.origin[1] - root_[1], oz = n.origin[2] - root_[2];
        for (std::uint32_t above = 1; above < level; ++above)
          if (const Entry* e = has_level_[above] ? find(key(above, ox, oy, oz)) : nullptr)
            fail(node_name(i) + " lies inside " + node_name(e->node) + ", a tile on level " + std::to_string(above));
        const std::uint64_t k = key(level, ox, oy, oz);
        std::size_t at = (k * 0x9E3779B97F4A7C15ull) >> shift_;
        for (; table_[at].key != empty_key; at = (at + 1) & (capacity - 1))
          if (table_[at].key == k) fail(node_name(i) + " covers the same voxels as " + node_name(table_[at].node));
        table_[at] = {k, first[i], d.format[i] == dense_code ? 511u : 0u, static_cast<std::uint32_t>(i)};
        has_level_[level] = true;
      }
    index_box_.extend(
        Vec3f{static_cast<float>(lower_[0]), static_cast<float>(lower_[1]), static_cast<float>(lower_[2])});
    index_box_.extend(
        Vec3f{static_cast<float>(upper_[0]), static_cast<float>(upper_[1]), static_cast<float>(upper_[2])});
    bounds_ = to_object_.transform(index_box_);
    const float edge = std::sqrt(std::min(
        {dot(to_object_.vx, to_object_.vx), dot(to_object_.vy, to_object_.vy), dot(to_object_.vz, to_object_.vz)}));
    cell_size_ = {edge, edge, edge};
  }

  float background_;
  VolumeFilter filter_ = VolumeFilter::linear, gradient_filter_ = VolumeFilter::linear;
  Affine3f to_object_, to_index_;
  std::vector<float> voxels_;
  std::vector<Entry> table_;  // open addressing, linear probing, a power of two long
  int shift_ = 60;
  std::array<bool, 4> has_level_{};
  std::vector<Node> nodes_;
  std::array<std::int64_t, 3> lower_{}, upper_{}, root_{}, active_{};  // index space; active_: the domain's size
  Box3f index_box_, bounds_;
  std::array<float, 2> range_{};
  Vec3f cell_size_{1.f, 1.f, 1.f};
};

}  // namespace sciray
