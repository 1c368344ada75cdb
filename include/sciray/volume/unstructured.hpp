#pragma once
// Unstructured (OSPRay's `unstructured`): a volume of tetrahedra, hexahedra, wedges and
// pyramids that share vertices, with values at the vertices (interpolated inside each
// cell) or one value per cell, as finite-element and CFD codes write them (VTK's
// unstructured grid; cell types and vertex orders are VTK's).
//
// A sample finds its cell through a bounding volume hierarchy over the cells' boxes, whose
// nodes also hold the range of values beneath them, and interpolates exactly in the cell:
// barycentric coordinates in a tetrahedron, and in the other cells the inverse of their
// isoparametric map (trilinear for hexahedra, linear × bilinear for wedges and pyramids),
// found by Newton's method, which is exact for cells whose faces are not planar too.
// Outside every cell a sample is `background` (NaN by default: transparent). Cells that
// span no volume are refused; cells whose map folds (distorted elements) are kept.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <string>
#include <vector>

#include "sciray/error.hpp"
#include "sciray/math/box.hpp"
#include "sciray/math/vec.hpp"
#include "sciray/simd/packet.hpp"
#include "sciray/volume/lane_by_lane.hpp"
#include "sciray/volume/macrocells.hpp"

namespace sciray {

/// OSPRay's (and VTK's) cell type codes.
enum class CellType : std::uint8_t { tetrahedron = 10, hexahedron = 12, wedge = 13, pyramid = 14 };

/// How many vertices a cell of type `type` has; 0 for a code that is not a cell type.
inline int cell_vertex_count(std::uint8_t type) {
  switch (static_cast<CellType>(type)) {
    case CellType::tetrahedron: return 4;
    case CellType::hexahedron: return 8;
    case CellType::wedge: return 6;
    case CellType::pyramid: return 5;
  }
  return 0;
}

/// An unstructured volume as OSPRay's parameters describe it.
struct UnstructuredData {
  std::vector<Vec3f> positions;            ///< vertex.position
  std::vector<float> vertex_values;        ///< vertex.data, one per vertex (or cell_values)
  std::vector<float> cell_values;          ///< cell.data, one per cell
  std::vector<std::uint64_t> index;        ///< index: the vertices of every cell, one cell after another
  std::vector<std::uint64_t> cell_index;   ///< cell.index: where each cell's vertices start in `index`
  std::vector<std::uint8_t> cell_type;     ///< cell.type: a CellType code per cell
  float background = std::numeric_limits<float>::quiet_NaN();  ///< the value outside every cell
};

/// Replaces `cell_values` by vertex values, each vertex the mean of the cells around it
/// (ParaView's "cell data to point data"): what isosurfaces of cell data are drawn from.
inline void average_cell_values_to_vertices(UnstructuredData& d) {
  if (d.cell_values.empty()) return;
  if (d.cell_index.size() != d.cell_values.size() || d.cell_type.size() != d.cell_values.size())
    throw Error("unstructured volume: 'cell.data' has " + std::to_string(d.cell_values.size()) + " values but there are " +
                std::to_string(d.cell_index.size()) + " cells");
  std::vector<double> sum(d.positions.size(), 0.);
  std::vector<std::uint32_t> count(d.positions.size(), 0);
  for (std::size_t c = 0; c < d.cell_values.size(); ++c)
    for (int k = 0; k < cell_vertex_count(d.cell_type[c]); ++k) {
      const std::uint64_t at = d.cell_index[c] + static_cast<std::uint64_t>(k);
      if (at >= d.index.size() || d.index[at] >= d.positions.size()) continue;  // the constructor names it
      sum[d.index[at]] += d.cell_values[c];
      ++count[d.index[at]];
    }
  d.vertex_values.resize(d.positions.size());
  for (std::size_t v = 0; v < d.positions.size(); ++v)
    d.vertex_values[v] = count[v] > 0 ? static_cast<float>(sum[v] / count[v]) : 0.f;
  d.cell_values = {};
}

class Unstructured {
public:
  explicit Unstructured(UnstructuredData data) : d_(std::move(data)), cells_(d_.cell_index.size()) {
    validate();
    narrow_indices();
    build_hierarchy();
  }

  std::size_t cell_count() const { return cells_; }
  Box3f bounds() const { return nodes_.front().box; }
  std::size_t owned_bytes() const {
    return d_.positions.size() * sizeof(Vec3f) + (d_.vertex_values.size() + d_.cell_values.size()) * sizeof(float) +
           (d_.index.size() + d_.cell_index.size()) * sizeof(std::uint64_t) +
           (index32_.size() + cell_index32_.size()) * sizeof(std::uint32_t) + d_.cell_type.size() +
           nodes_.size() * sizeof(Node) + order_.size() * sizeof(std::uint32_t);
  }
  /// How many cells fold over themselves (their map's Jacobian changes sign): they are
  /// sampled where Newton's method finds a preimage, one of several inside the fold.
  std::size_t folded_cells() const { return folded_; }
  /// The smallest and largest value inside the cells.
  std::array<float, 2> value_range() const { return {nodes_.front().lo, nodes_.front().hi}; }

  /// A typical cell's extent (the median over cells of their boxes' mean side), the same
  /// along every axis: what sampling rates are relative to.
  const Vec3f& cell_size() const { return cell_size_; }

  /// Macrocells of about n typical cells a side over the volume's box, at most 128 a side.
  MacrocellGrid macrocell_grid(std::int64_t n) const { return MacrocellGrid::over(bounds(), cell_size_.x, n); }
  /// Widens the ranges of `m` by every cell's values over the macrocells its box overlaps
  /// (inside a cell the interpolant stays within its vertices' values).
  void widen_macrocell_ranges(const MacrocellGrid& m, std::int64_t, std::vector<float>& ranges) const {
    for (std::uint32_t c = 0; c < cell_count(); ++c) {
      const auto [lo, hi] = cell_range(c);
      m.widen(cell_box(c), lo, hi, ranges);
    }
  }

  /// The value at p: interpolated in the cell that holds it, else the background.
  float sample(const Vec3f& p) const {
    std::uint32_t cell;
    return sample(p, cell);
  }
  template <class Arch>
  simd::Float<Arch> sample(const Vec3<simd::Float<Arch>>& p) const {
    return scalar_per_lane<Arch>(p, [this](const Vec3f& q) { return sample(q); });
  }

  /// sample() along the rays of one packet: each lane first tries the cell of its last
  /// sample, where a ray's next sample usually is, before searching the hierarchy.
  template <class Arch>
  class Sampler {
  public:
    explicit Sampler(const Unstructured& volume) : volume_(&volume) { last_.fill(no_cell); }
    simd::Float<Arch> operator()(const Vec3<simd::Float<Arch>>& p) {
      constexpr int W = simd::width<Arch>;
      alignas(64) float out[W];
      for (int i = 0; i < W; ++i) {
        const Vec3f q{simd::lane(p.x, i), simd::lane(p.y, i), simd::lane(p.z, i)};
        std::uint32_t& last = last_[static_cast<std::size_t>(i)];
        float r, s, t;
        if (last != no_cell && volume_->parameters(last, q, r, s, t)) {
          out[i] = volume_->interpolate(last, shape(static_cast<CellType>(volume_->d_.cell_type[last]), r, s, t));
          continue;
        }
        out[i] = volume_->sample(q, last);
      }
      if constexpr (std::is_same_v<Arch, simd::scalar>)
        return out[0];
      else
        return simd::load<Arch>(out);
    }

  private:
    const Unstructured* volume_;
    std::array<std::uint32_t, simd::width<Arch>> last_;
  };
  template <class Arch>
  Sampler<Arch> sampler() const {
    return Sampler<Arch>(*this);
  }

  /// The gradient by central differences a tenth of a typical cell apart; components
  /// where a neighbour lies outside every cell are 0.
  template <class Arch>
  Vec3<simd::Float<Arch>> gradient(const Vec3<simd::Float<Arch>>& p) const {
    using F = simd::Float<Arch>;
    const float h = 0.1f * cell_size_.x;
    const auto difference = [&](const Vec3f& axis) {
      const F a = sample<Arch>(p + Vec3<F>(axis * h)), b = sample<Arch>(p - Vec3<F>(axis * h));
      const F g = (a - b) * F(0.5f / h);
      return simd::select(g == g, g, F(0.f));  // NaN outside the cells
    };
    return {difference({1.f, 0.f, 0.f}), difference({0.f, 1.f, 0.f}), difference({0.f, 0.f, 1.f})};
  }
  template <class Arch>
  Vec3<simd::Float<Arch>> shading_gradient(const Vec3<simd::Float<Arch>>& p) const {
    return gradient<Arch>(p);
  }

  // ---- One cell at a time (isosurfaces and the exact integrator use them) ----

  CellType type(std::uint32_t cell) const { return static_cast<CellType>(d_.cell_type[cell]); }
  /// Vertex k of `cell` (an index into the positions).
  std::uint64_t vertex(std::uint32_t cell, int k) const {
    const std::uint64_t at = (cell_index32_.empty() ? d_.cell_index[cell] : cell_index32_[cell]) + static_cast<std::uint64_t>(k);
    return index32_.empty() ? d_.index[at] : index32_[at];
  }

  int vertices(std::uint32_t cell) const { return cell_vertex_count(d_.cell_type[cell]); }

  std::size_t vertex_count() const { return d_.positions.size(); }
  const Vec3f& position(std::uint64_t vertex) const { return d_.positions[vertex]; }
  /// Whether values are given per cell (constant in each) rather than per vertex.
  bool cell_valued() const { return !d_.cell_values.empty(); }
  float vertex_value(std::uint64_t vertex) const { return d_.vertex_values[vertex]; }
  Box3f cell_box(std::uint32_t cell) const {
    Box3f box;
    for (int k = 0; k < vertices(cell); ++k) box.extend(d_.positions[vertex(cell, k)]);
    return box;
  }
  std::array<float, 2> cell_range(std::uint32_t cell) const {
    if (!d_.cell_values.empty()) return {d_.cell_values[cell], d_.cell_values[cell]};
    std::array<float, 2> r{std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity()};
    for (int k = 0; k < vertices(cell); ++k) {
      const float v = d_.vertex_values[vertex(cell, k)];
      r[0] = std::min(r[0], v), r[1] = std::max(r[1], v);
    }
    return r;
  }
  float interpolate(std::uint32_t cell, const std::array<float, 8>& weights) const {
    if (!d_.cell_values.empty()) return d_.cell_values[cell];
    float v = 0.f;
    for (int k = 0; k < vertices(cell); ++k) v += weights[static_cast<std::size_t>(k)] * d_.vertex_values[vertex(cell, k)];
    return v;
  }

  /// The weights of a cell's vertices at parametric (r, s, t) (VTK's shape functions).
  static std::array<float, 8> shape(CellType type, float r, float s, float t) {
    switch (type) {
      case CellType::hexahedron:
        return {(1 - r) * (1 - s) * (1 - t), r * (1 - s) * (1 - t), r * s * (1 - t), (1 - r) * s * (1 - t),
                (1 - r) * (1 - s) * t,       r * (1 - s) * t,       r * s * t,       (1 - r) * s * t};
      case CellType::wedge:
        return {(1 - r - s) * (1 - t), r * (1 - t), s * (1 - t), (1 - r - s) * t, r * t, s * t, 0.f, 0.f};
      case CellType::pyramid:
        return {(1 - r) * (1 - s) * (1 - t), r * (1 - s) * (1 - t), r * s * (1 - t), (1 - r) * s * (1 - t), t, 0.f, 0.f,
                0.f};
      case CellType::tetrahedron: return {1 - r - s - t, r, s, t, 0.f, 0.f, 0.f, 0.f};
    }
    return {};
  }
  /// The parametric coordinates of p in `cell` (a tetrahedron's affine map inverted
  /// directly, the others' by Newton's method from the cell's centre); false where p
  /// lies outside it.
  bool parameters(std::uint32_t cell, const Vec3f& p, float& r, float& s, float& t) const {
    const auto type = static_cast<CellType>(d_.cell_type[cell]);
    if (type == CellType::tetrahedron) {
      // The affine map's inverse by Cramer's rule, straight from the edges.
      const Vec3f& v0 = d_.positions[vertex(cell, 0)];
      const Vec3f e1 = d_.positions[vertex(cell, 1)] - v0, e2 = d_.positions[vertex(cell, 2)] - v0,
                  e3 = d_.positions[vertex(cell, 3)] - v0, q = p - v0;
      const Vec3f n23 = cross(e2, e3);
      const float det = dot(e1, n23);
      r = dot(q, n23) / det, s = dot(e1, cross(q, e3)) / det, t = dot(e1, cross(e2, q)) / det;
      return inside_parameters(type, r, s, t);
    }
    r = s = type == CellType::wedge ? 1.f / 3.f : 0.5f;
    t = type == CellType::pyramid ? 0.2f : 0.5f;
    for (int i = 0; i < 16; ++i) {
      Vec3f x, j[3];
      map(cell, r, s, t, x, j);
      const Vec3f residual = p - x;
      const float det = dot(j[0], cross(j[1], j[2]));
      if (!(std::abs(det) > 0.f)) return false;
      // Cramer's rule for j · delta = residual.
      const float dr = dot(residual, cross(j[1], j[2])) / det;
      const float ds = dot(j[0], cross(residual, j[2])) / det;
      const float dt = dot(j[0], cross(j[1], residual)) / det;
      r += dr, s += ds, t += dt;
      if (std::abs(dr) + std::abs(ds) + std::abs(dt) < 1e-6f) break;
      if (std::abs(r) + std::abs(s) + std::abs(t) > 100.f) return false;  // diverging: far outside
    }
    return inside_parameters(type, r, s, t);
  }

  /// The cell's interpolant at p (extended past its faces where p lies just outside;
  /// its value where values are per cell).
  float value_in_cell(std::uint32_t cell, const Vec3f& p) const {
    if (cell_valued()) return d_.cell_values[cell];
    float r, s, t;
    parameters(cell, p, r, s, t);
    return interpolate(cell, shape(type(cell), r, s, t));
  }
  /// Where the ray org + t·dir is inside tetrahedron `cell`, from its four face planes;
  /// false where it misses.
  bool tetrahedron_span(std::uint32_t cell, const Vec3f& org, const Vec3f& dir, float& t_in, float& t_out) const {
    std::array<Vec3f, 4> v;
    for (int k = 0; k < 4; ++k) v[static_cast<std::size_t>(k)] = position(vertex(cell, k));
    t_in = -std::numeric_limits<float>::infinity(), t_out = std::numeric_limits<float>::infinity();
    for (std::size_t k = 0; k < 4; ++k) {
      // The face opposite vertex k; points p inside have dot(n, p − a) <= 0.
      const Vec3f& a = v[(k + 1) % 4];
      Vec3f n = cross(v[(k + 2) % 4] - a, v[(k + 3) % 4] - a);
      if (dot(n, v[k] - a) > 0.f) n = -n;
      const float denom = dot(n, dir), num = dot(n, a - org);
      if (denom > 0.f)
        t_out = std::min(t_out, num / denom);
      else if (denom < 0.f)
        t_in = std::max(t_in, num / denom);
      else if (num < 0.f)
        return false;  // parallel to the face and outside it
    }
    return t_in <= t_out;
  }
  /// Whether every cell is a tetrahedron (what exact integration needs).
  bool tetrahedral() const { return tetrahedra_ == cell_count(); }
  /// The value outside every cell (NaN: transparent).
  float background() const { return d_.background; }

  /// The gradient of a cell's interpolant at parametric (r, s, t): the parametric
  /// gradient through the inverse transpose of the map's Jacobian (0 with cell values).
  Vec3f cell_gradient(std::uint32_t cell, float r, float s, float t) const {
    if (cell_valued()) return {0.f, 0.f, 0.f};
    Vec3f x, j[3];
    map(cell, r, s, t, x, j);
    const auto dn = shape_derivatives(type(cell), r, s, t);
    float df[3] = {0.f, 0.f, 0.f};
    for (int k = 0; k < vertices(cell); ++k)
      for (int a = 0; a < 3; ++a) df[a] += dn[static_cast<std::size_t>(a)][static_cast<std::size_t>(k)] * vertex_value(vertex(cell, k));
    // g with j[a] · g = df[a]: g = (df0 (j1 × j2) + df1 (j2 × j0) + df2 (j0 × j1)) / det.
    const float det = dot(j[0], cross(j[1], j[2]));
    if (!(std::abs(det) > 0.f)) return {0.f, 0.f, 0.f};
    return (cross(j[1], j[2]) * df[0] + cross(j[2], j[0]) * df[1] + cross(j[0], j[1]) * df[2]) / det;
  }

  /// The hierarchy's nodes that a segment of a ray crosses, nearest first, call
  /// visit(cell) for each of their cells (a cell may hold the segment or not).
  template <class Visit>
  void cells_along(const Vec3f& org, const Vec3f& dir, float t0, float t1, Visit&& visit) const {
    const Vec3f inv{1.f / dir.x, 1.f / dir.y, 1.f / dir.z};
    const auto enter = [&](const Box3f& b, float& t) {
      const Vec3f a = (b.lower - org) * inv, c = (b.upper - org) * inv;
      const float near = std::max({std::min(a.x, c.x), std::min(a.y, c.y), std::min(a.z, c.z), t0});
      const float far = std::min({std::max(a.x, c.x), std::max(a.y, c.y), std::max(a.z, c.z), t1});
      t = near;
      return near <= far;
    };
    std::uint32_t stack[64];
    int top = 0;
    float t;
    if (!enter(nodes_.front().box, t)) return;
    stack[top++] = 0;
    while (top > 0) {
      const Node& node = nodes_[stack[--top]];
      if (node.count > 0) {
        for (std::uint32_t k = 0; k < node.count; ++k) visit(order_[node.first + k]);
        continue;
      }
      float ta, tb;
      const bool a = enter(nodes_[node.first].box, ta), b = enter(nodes_[node.first + 1].box, tb);
      // The nearer child is popped first.
      if (a && b) {
        stack[top++] = ta <= tb ? node.first + 1 : node.first;
        stack[top++] = ta <= tb ? node.first : node.first + 1;
      } else if (a || b) {
        stack[top++] = a ? node.first : node.first + 1;
      }
    }
  }

private:
  struct Node {
    Box3f box;
    float lo, hi;         // the values beneath
    std::uint32_t first;  // leaf: the first of its cells in order_; inner: its left child (right follows)
    std::uint32_t count;  // cells in a leaf, 0 for an inner node
  };

  static constexpr std::uint32_t no_cell = 0xffffffffu;

  /// sample(p), and in `cell` the cell that holds p (no_cell where none does).
  float sample(const Vec3f& p, std::uint32_t& cell) const {
    float value = d_.background;
    cell = no_cell;
    locate(p, [&](std::uint32_t found, const std::array<float, 8>& weights) {
      value = interpolate(found, weights);
      cell = found;
    });
    return value;
  }

  /// Indices in 32 bits where they fit (vertices, and entries of `index`, below 2^32):
  /// 20 bytes less a tetrahedron.
  void narrow_indices() {
    constexpr std::uint64_t fits = std::numeric_limits<std::uint32_t>::max();
    if (d_.positions.size() <= fits) {
      index32_.assign(d_.index.begin(), d_.index.end());
      d_.index = {};
    }
    if (index32_.size() + d_.index.size() <= fits) {
      cell_index32_.assign(d_.cell_index.begin(), d_.cell_index.end());
      d_.cell_index = {};
    }
  }

  // ---- Shape functions: parametric (r, s, t) to the weights of the vertices (VTK's) ----

  /// The derivatives of shape() by r, s and t.
  static std::array<std::array<float, 8>, 3> shape_derivatives(CellType type, float r, float s, float t) {
    switch (type) {
      case CellType::hexahedron:
        return {{{-(1 - s) * (1 - t), (1 - s) * (1 - t), s * (1 - t), -s * (1 - t), -(1 - s) * t, (1 - s) * t, s * t, -s * t},
                 {-(1 - r) * (1 - t), -r * (1 - t), r * (1 - t), (1 - r) * (1 - t), -(1 - r) * t, -r * t, r * t, (1 - r) * t},
                 {-(1 - r) * (1 - s), -r * (1 - s), -r * s, -(1 - r) * s, (1 - r) * (1 - s), r * (1 - s), r * s, (1 - r) * s}}};
      case CellType::wedge:
        return {{{-(1 - t), 1 - t, 0.f, -t, t, 0.f, 0.f, 0.f},
                 {-(1 - t), 0.f, 1 - t, -t, 0.f, t, 0.f, 0.f},
                 {-(1 - r - s), -r, -s, 1 - r - s, r, s, 0.f, 0.f}}};
      case CellType::pyramid:
        return {{{-(1 - s) * (1 - t), (1 - s) * (1 - t), s * (1 - t), -s * (1 - t), 0.f, 0.f, 0.f, 0.f},
                 {-(1 - r) * (1 - t), -r * (1 - t), r * (1 - t), (1 - r) * (1 - t), 0.f, 0.f, 0.f, 0.f},
                 {-(1 - r) * (1 - s), -r * (1 - s), -r * s, -(1 - r) * s, 1.f, 0.f, 0.f, 0.f}}};
      case CellType::tetrahedron:
        return {{{-1.f, 1.f, 0.f, 0.f, 0.f, 0.f, 0.f, 0.f}, {-1.f, 0.f, 1.f, 0.f, 0.f, 0.f, 0.f, 0.f},
                 {-1.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 0.f}}};
    }
    return {};
  }
  static bool inside_parameters(CellType type, float r, float s, float t) {
    constexpr float e = 1e-4f;
    const bool unit_t = t >= -e && t <= 1 + e;
    switch (type) {
      case CellType::hexahedron:
      case CellType::pyramid: return r >= -e && r <= 1 + e && s >= -e && s <= 1 + e && unit_t;
      case CellType::wedge: return r >= -e && s >= -e && r + s <= 1 + e && unit_t;
      case CellType::tetrahedron: return r >= -e && s >= -e && t >= -e && r + s + t <= 1 + e;
    }
    return false;
  }

  /// The map's Jacobian (columns: d/dr, d/ds, d/dt) at (r, s, t) and the mapped point.
  void map(std::uint32_t cell, float r, float s, float t, Vec3f& x, Vec3f jacobian[3]) const {
    const auto type = static_cast<CellType>(d_.cell_type[cell]);
    const auto n = shape(type, r, s, t);
    const auto dn = shape_derivatives(type, r, s, t);
    x = {0.f, 0.f, 0.f};
    jacobian[0] = jacobian[1] = jacobian[2] = Vec3f{0.f, 0.f, 0.f};
    for (int k = 0; k < vertices(cell); ++k) {
      const Vec3f& v = d_.positions[vertex(cell, k)];
      x = x + v * n[static_cast<std::size_t>(k)];
      for (int a = 0; a < 3; ++a) jacobian[a] = jacobian[a] + v * dn[static_cast<std::size_t>(a)][static_cast<std::size_t>(k)];
    }
  }

  /// Calls found(cell, weights) for the first cell that holds p, if any.
  template <class Found>
  void locate(const Vec3f& p, Found&& found) const {
    std::uint32_t stack[64];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const Node& node = nodes_[stack[--top]];
      const Box3f& b = node.box;
      if (!(p.x >= b.lower.x && p.x <= b.upper.x && p.y >= b.lower.y && p.y <= b.upper.y && p.z >= b.lower.z &&
            p.z <= b.upper.z))
        continue;
      if (node.count == 0) {
        stack[top++] = node.first + 1;
        stack[top++] = node.first;
        continue;
      }
      for (std::uint32_t k = 0; k < node.count; ++k) {
        const std::uint32_t cell = order_[node.first + k];
        float r, s, t;
        if (!parameters(cell, p, r, s, t)) continue;
        found(cell, shape(static_cast<CellType>(d_.cell_type[cell]), r, s, t));
        return;
      }
    }
  }

  void validate() {
    const auto fail = [](const std::string& what) { throw Error("unstructured volume: " + what); };
    if (d_.positions.empty()) fail("'vertex.position' is missing or empty");
    if (d_.cell_index.empty()) fail("'cell.index' is missing or empty");
    if (d_.index.empty()) fail("'index' is missing or empty");
    if (d_.cell_type.size() != d_.cell_index.size())
      fail("'cell.type' has " + std::to_string(d_.cell_type.size()) + " entries but 'cell.index' has " +
           std::to_string(d_.cell_index.size()) + " cells");
    if (d_.vertex_values.empty() == d_.cell_values.empty())
      fail("exactly one of 'vertex.data' and 'cell.data' must be given");
    if (!d_.vertex_values.empty() && d_.vertex_values.size() != d_.positions.size())
      fail("'vertex.data' has " + std::to_string(d_.vertex_values.size()) + " values but 'vertex.position' has " +
           std::to_string(d_.positions.size()) + " vertices");
    if (!d_.cell_values.empty() && d_.cell_values.size() != d_.cell_index.size())
      fail("'cell.data' has " + std::to_string(d_.cell_values.size()) + " values but there are " +
           std::to_string(d_.cell_index.size()) + " cells");
    if (d_.cell_index.size() > std::numeric_limits<std::uint32_t>::max())
      fail("more than 2^32 - 1 cells");
    for (std::size_t v = 0; v < d_.positions.size(); ++v) {
      const Vec3f& p = d_.positions[v];
      if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
        fail("'vertex.position' " + std::to_string(v) + " is not finite");
    }
    for (const auto* values : {&d_.vertex_values, &d_.cell_values})
      for (std::size_t i = 0; i < values->size(); ++i)
        if (!std::isfinite((*values)[i]))
          fail(std::string(values == &d_.vertex_values ? "'vertex.data' " : "'cell.data' ") + std::to_string(i) +
               " is not finite");
    for (std::uint32_t c = 0; c < cell_count(); ++c) {
      const std::string cell = "cell " + std::to_string(c);
      const int n = vertices(c);
      if (n == 0)
        fail(cell + " has type " + std::to_string(d_.cell_type[c]) +
             ", which is none of tetrahedron (10), hexahedron (12), wedge (13), pyramid (14)");
      if (d_.cell_index[c] > d_.index.size() || d_.index.size() - d_.cell_index[c] < static_cast<std::uint64_t>(n))
        fail(cell + " starts at 'index' entry " + std::to_string(d_.cell_index[c]) + " and needs " + std::to_string(n) +
             " vertices, but 'index' has " + std::to_string(d_.index.size()) + " entries");
      for (int k = 0; k < n; ++k)
        if (vertex(c, k) >= d_.positions.size())
          fail(cell + " refers to vertex " + std::to_string(vertex(c, k)) + " but 'vertex.position' has " +
               std::to_string(d_.positions.size()));
      // The cell must span a volume: its map's Jacobian at the centre is not 0. A map
      // whose Jacobian changes sign over the cell folds it (distorted finite elements, as
      // in a crushed can's output): such cells are kept, and counted (folded_cells()).
      const auto type = static_cast<CellType>(d_.cell_type[c]);
      tetrahedra_ += type == CellType::tetrahedron;
      const Box3f box = cell_box(c);
      const Vec3f extent = box.upper - box.lower;
      const float scale = std::max({extent.x, extent.y, extent.z});
      const float tiny = 1e-9f * scale * scale * scale;
      const auto determinant = [&](float r, float s, float t) {
        Vec3f x, j[3];
        map(c, r, s, t, x, j);
        return dot(j[0], cross(j[1], j[2]));
      };
      const float centre = type == CellType::tetrahedron ? determinant(0.25f, 0.25f, 0.25f)
                           : type == CellType::wedge      ? determinant(1.f / 3.f, 1.f / 3.f, 0.5f)
                           : type == CellType::pyramid    ? determinant(0.5f, 0.5f, 0.2f)
                                                          : determinant(0.5f, 0.5f, 0.5f);
      if (!(std::abs(centre) > tiny)) fail(cell + " is degenerate (its vertices span no volume)");
      const float corners[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
      const float wedge_corners[6][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {0, 1, 1}};
      // A tetrahedron's Jacobian is constant; a pyramid's vanishes at its apex: its base corners, a little above.
      const int samples = type == CellType::hexahedron ? 8 : type == CellType::wedge ? 6 : type == CellType::pyramid ? 4 : 0;
      for (int k = 0; k < samples; ++k) {
        const float* q = type == CellType::wedge ? wedge_corners[k] : corners[k];
        if (determinant(q[0], q[1], type == CellType::pyramid ? 0.01f : q[2]) * centre < 0.f) {
          ++folded_;
          break;
        }
      }
    }
  }

  void build_hierarchy() {
    const std::uint32_t count = static_cast<std::uint32_t>(cell_count());
    order_.resize(count);
    std::iota(order_.begin(), order_.end(), 0u);
    std::vector<Box3f> boxes(count);
    std::vector<Vec3f> centres(count);
    std::vector<float> sides(count);
    for (std::uint32_t c = 0; c < count; ++c) {
      boxes[c] = cell_box(c);
      centres[c] = (boxes[c].lower + boxes[c].upper) * 0.5f;
      const Vec3f e = boxes[c].upper - boxes[c].lower;
      sides[c] = (e.x + e.y + e.z) / 3.f;
    }
    std::nth_element(sides.begin(), sides.begin() + count / 2, sides.end());
    const float typical = sides[count / 2] > 0.f ? sides[count / 2] : 1.f;
    cell_size_ = {typical, typical, typical};
    nodes_.reserve(2 * static_cast<std::size_t>(count));
    nodes_.push_back({});
    build_node(0, 0, count, boxes, centres, 0);
  }

  void build_node(std::uint32_t node, std::uint32_t first, std::uint32_t last, const std::vector<Box3f>& boxes,
                  const std::vector<Vec3f>& centres, int depth) {
    Box3f box, centre_box;
    float lo = std::numeric_limits<float>::infinity(), hi = -lo;
    for (std::uint32_t i = first; i < last; ++i) {
      box.extend(boxes[order_[i]]);
      centre_box.extend(centres[order_[i]]);
      const auto [a, b] = cell_range(order_[i]);
      lo = std::min(lo, a), hi = std::max(hi, b);
    }
    constexpr std::uint32_t leaf_cells = 4;
    // The traversal stack holds 64 entries: deeper than 60 levels the rest is one leaf.
    if (last - first <= leaf_cells || depth >= 60) {
      nodes_[node] = {box, lo, hi, first, last - first};
      return;
    }
    const Vec3f extent = centre_box.upper - centre_box.lower;
    const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : extent.y >= extent.z ? 1 : 2;
    const std::uint32_t middle = first + (last - first) / 2;
    std::nth_element(order_.begin() + first, order_.begin() + middle, order_.begin() + last,
                     [&](std::uint32_t a, std::uint32_t b) { return centres[a][axis] < centres[b][axis]; });
    const auto left = static_cast<std::uint32_t>(nodes_.size());
    nodes_[node] = {box, lo, hi, left, 0};
    nodes_.push_back({});
    nodes_.push_back({});
    build_node(left, first, middle, boxes, centres, depth + 1);
    build_node(left + 1, middle, last, boxes, centres, depth + 1);
  }

  UnstructuredData d_;  // index and cell_index emptied where narrow_indices() keeps them in 32 bits
  std::size_t cells_;
  std::vector<std::uint32_t> index32_, cell_index32_;
  std::vector<Node> nodes_;
  std::vector<std::uint32_t> order_;  ///< cell indices, grouped by leaf
  Vec3f cell_size_{1.f, 1.f, 1.f};
  std::size_t folded_ = 0;
  std::size_t tetrahedra_ = 0;
};

}  // namespace sciray
