#pragma once
// The isosurface of an unstructured volume (geometry/isosurface.hpp), intersected in each
// cell with the cell's own interpolant.
//
// Embree sees one primitive per cell whose vertex values straddle an isovalue. Where a
// ray crosses a tetrahedron is exact (its four face planes), and its linear interpolant
// crosses an isovalue at one t in closed form. Hexahedra, wedges and pyramids are bounded
// by bilinear faces (triangles are degenerate ones): the ray's crossings of them, from a
// quadratic each, cut it into the spans inside the cell, and in each span the cell's
// interpolant along the ray is solved as the grid's cells are (first_crossing_of_cubic:
// exact where the cell is a parallelepiped, and bisected on the interpolant itself
// elsewhere). Neighbouring cells share their faces' exact crossings, so the surface has no
// cracks between them.
//
// Normals are smooth: each vertex holds the volume-weighted mean gradient of the cells
// around it, and a hit interpolates its cell's vertex gradients with the cell's weights
// (as Phong shading interpolates a mesh's vertex normals); a cell's own gradient would
// show every cell as a facet.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "sciray/error.hpp"
#include "sciray/geometry/isosurface_field.hpp"
#include "sciray/volume/unstructured.hpp"

namespace sciray {

class UnstructuredIsosurface final : public IsosurfaceField {
public:
  UnstructuredIsosurface(std::shared_ptr<const Unstructured> volume, const std::vector<float>& isovalues)
      : volume_(std::move(volume)), isovalues_(isovalues) {
    if (volume_->cell_valued())
      throw Error("isosurface: the unstructured volume has 'cell.data', constant in each cell, which has no "
                  "isosurface; give it 'vertex.data'");
    const auto cells = static_cast<std::uint32_t>(volume_->cell_count());
    for (std::uint32_t c = 0; c < cells; ++c) {
      const auto [lo, hi] = volume_->cell_range(c);
      for (float iso : isovalues_)
        if (iso >= lo && iso <= hi) {
          active_.push_back(c);
          break;
        }
    }
    average_vertex_gradients();
  }

  std::size_t primitive_count() const override { return active_.size(); }
  std::size_t owned_bytes() const override {
    return active_.size() * sizeof(std::uint32_t) + vertex_gradients_.size() * sizeof(Vec3f);
  }
  Box3f primitive_bounds(std::uint32_t prim) const override { return volume_->cell_box(active_[prim]); }

  PrimitiveHit<simd::scalar> first_crossing(const Ray<float>& ray, std::uint32_t prim) const override {
    const std::uint32_t cell = active_[prim];
    float best = std::numeric_limits<float>::infinity();
    std::size_t best_iso = 0;
    const auto consider = [&](std::size_t iso, float t) {
      if (t < best) best = t, best_iso = iso;
    };
    if (volume_->type(cell) == CellType::tetrahedron)
      tetrahedron_crossing(ray, cell, consider);
    else
      curved_cell_crossing(ray, cell, consider);
    PrimitiveHit<simd::scalar> hit{false, std::numeric_limits<float>::infinity(), {}};
    if (!(best < std::numeric_limits<float>::infinity())) return hit;
    hit.hit = true;
    hit.t = best;
    hit.u = static_cast<float>(best_iso);
    hit.ng = normal(cell, ray.org + ray.dir * best, ray.dir);
    return hit;
  }

private:
  /// The tetrahedron's span along the ray, and the linear interpolant's crossings of
  /// each isovalue in it.
  template <class Consider>
  void tetrahedron_crossing(const Ray<float>& ray, std::uint32_t cell, Consider&& consider) const {
    float t_in, t_out;
    if (!volume_->tetrahedron_span(cell, ray.org, ray.dir, t_in, t_out)) return;
    t_in = std::max(t_in, ray.tnear), t_out = std::min(t_out, ray.tfar);
    if (!(t_in <= t_out)) return;
    const float f_in = volume_->value_in_cell(cell, ray.org + ray.dir * t_in);
    const float f_out = volume_->value_in_cell(cell, ray.org + ray.dir * t_out);
    for (std::size_t i = 0; i < isovalues_.size(); ++i) {
      const float iso = isovalues_[i];
      if ((f_in - iso) * (f_out - iso) > 0.f || f_in == f_out) continue;
      consider(i, t_in + (iso - f_in) / (f_out - f_in) * (t_out - t_in));
    }
  }

  /// The spans of the ray inside a cell with bilinear faces, and in each the first
  /// crossing of each isovalue.
  template <class Consider>
  void curved_cell_crossing(const Ray<float>& ray, std::uint32_t cell, Consider&& consider) const {
    // The ray's stretch in the cell's box, cut at its crossings of the cell's faces.
    const Box3f box = volume_->cell_box(cell);
    float t0 = ray.tnear, t1 = ray.tfar;
    for (int k = 0; k < 3; ++k) {
      const float a = (box.lower[k] - ray.org[k]) / ray.dir[k], b = (box.upper[k] - ray.org[k]) / ray.dir[k];
      if (a == a && b == b) t0 = std::max(t0, std::min(a, b)), t1 = std::min(t1, std::max(a, b));
    }
    if (!(t0 < t1)) return;
    std::array<float, 2 * 6 + 2> cuts;  // at most two crossings per face, and the stretch's ends
    int n = 0;
    cuts[static_cast<std::size_t>(n++)] = t0;
    cuts[static_cast<std::size_t>(n++)] = t1;
    for (const auto& face : faces(volume_->type(cell))) {
      if (face[0] < 0) break;
      std::array<Vec3f, 4> q;
      for (int k = 0; k < 4; ++k)
        q[static_cast<std::size_t>(k)] = volume_->position(volume_->vertex(cell, face[static_cast<std::size_t>(k)]));
      patch_crossings(ray, q, [&](float t) {
        if (t > t0 && t < t1) cuts[static_cast<std::size_t>(n++)] = t;
      });
    }
    std::sort(cuts.begin(), cuts.begin() + n);
    for (int k = 0; k + 1 < n; ++k) {
      const float ta = cuts[static_cast<std::size_t>(k)], tb = cuts[static_cast<std::size_t>(k + 1)];
      if (!(tb > ta) || !std::isfinite(tb - ta)) continue;
      float r, s, t;
      if (!volume_->parameters(cell, ray.org + ray.dir * (0.5f * (ta + tb)), r, s, t)) continue;
      for (std::size_t i = 0; i < isovalues_.size(); ++i) {
        const float iso = isovalues_[i];
        consider(i, first_crossing_of_cubic(
                        [&](double at) { return static_cast<double>(volume_->value_in_cell(cell, ray.org + ray.dir * static_cast<float>(at))) - iso; },
                        ta, tb));
      }
    }
  }

  /// A cell's faces as bilinear patches (corners in cyclic order; a triangle repeats its
  /// last corner), VTK's vertex numbering; {-1, ...} ends the list.
  static const std::array<std::array<int, 4>, 6>& faces(CellType type) {
    static const std::array<std::array<int, 4>, 6> hexahedron{
        {{0, 4, 7, 3}, {1, 2, 6, 5}, {0, 1, 5, 4}, {3, 7, 6, 2}, {0, 3, 2, 1}, {4, 5, 6, 7}}};
    static const std::array<std::array<int, 4>, 6> wedge{
        {{0, 1, 2, 2}, {3, 5, 4, 4}, {0, 3, 4, 1}, {1, 4, 5, 2}, {2, 5, 3, 0}, {-1, 0, 0, 0}}};
    static const std::array<std::array<int, 4>, 6> pyramid{
        {{0, 3, 2, 1}, {0, 1, 4, 4}, {1, 2, 4, 4}, {2, 3, 4, 4}, {3, 0, 4, 4}, {-1, 0, 0, 0}}};
    return type == CellType::hexahedron ? hexahedron : type == CellType::wedge ? wedge : pyramid;
  }

  /// The ray's crossings of the bilinear patch (1−u)(1−v) q0 + u(1−v) q1 + uv q2 + (1−u)v q3,
  /// u, v in [0, 1]: in the two planes through the ray, the patch's equations are bilinear
  /// in u and v; eliminating u leaves a quadratic in v (in double).
  template <class Found>
  static void patch_crossings(const Ray<float>& ray, const std::array<Vec3f, 4>& q, Found&& found) {
    using D3 = std::array<double, 3>;
    const auto d3 = [](const Vec3f& a) { return D3{a.x, a.y, a.z}; };
    const auto sub = [](const D3& a, const D3& b) { return D3{a[0] - b[0], a[1] - b[1], a[2] - b[2]}; };
    const auto dotd = [](const D3& a, const D3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; };
    const auto crossd = [](const D3& a, const D3& b) {
      return D3{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
    };
    const D3 o = d3(ray.org), d = d3(ray.dir);
    const D3 q0 = d3(q[0]), q1 = d3(q[1]), q2 = d3(q[2]), q3 = d3(q[3]);
    const D3 b = sub(q1, q0), c = sub(q3, q0), e = sub(sub(q0, q1), sub(q3, q2)), a = sub(q0, o);
    // Two directions across the ray.
    const D3 helper = std::abs(d[0]) < 0.6 * std::sqrt(dotd(d, d)) ? D3{1, 0, 0} : D3{0, 1, 0};
    const D3 n1 = crossd(d, helper), n2 = crossd(d, n1);
    const double A1 = dotd(n1, e), B1 = dotd(n1, b), C1 = dotd(n1, c), D1 = dotd(n1, a);
    const double A2 = dotd(n2, e), B2 = dotd(n2, b), C2 = dotd(n2, c), D2 = dotd(n2, a);
    // Each: u (A v + B) = −(C v + D).
    const double qa = C1 * A2 - C2 * A1, qb = C1 * B2 + D1 * A2 - C2 * B1 - D2 * A1, qc = D1 * B2 - D2 * B1;
    double roots[2];
    int count = 0;
    const double scale = std::abs(qa) + std::abs(qb) + std::abs(qc);
    if (!(scale > 0)) return;
    if (std::abs(qa) <= 1e-12 * scale) {
      if (std::abs(qb) > 1e-12 * scale) roots[count++] = -qc / qb;
    } else {
      const double disc = qb * qb - 4 * qa * qc;
      if (disc < 0) return;
      const double r = -0.5 * (qb + std::copysign(std::sqrt(disc), qb));
      roots[count++] = r / qa;
      if (r != 0) roots[count++] = qc / r;
    }
    constexpr double tolerance = 1e-7;
    for (int i = 0; i < count; ++i) {
      const double v = roots[i];
      if (!(v >= -tolerance && v <= 1 + tolerance)) continue;
      const double den1 = A1 * v + B1, den2 = A2 * v + B2;
      const double u = std::abs(den1) >= std::abs(den2) ? -(C1 * v + D1) / den1 : -(C2 * v + D2) / den2;
      if (!(u >= -tolerance && u <= 1 + tolerance)) continue;
      const D3 p = {q0[0] + b[0] * u + c[0] * v + e[0] * u * v, q0[1] + b[1] * u + c[1] * v + e[1] * u * v,
                    q0[2] + b[2] * u + c[2] * v + e[2] * u * v};
      found(static_cast<float>(dotd(sub(p, o), d) / dotd(d, d)));
    }
  }

  Vec3f normal(std::uint32_t cell, const Vec3f& p, const Vec3f& dir) const {
    float r, s, t;
    volume_->parameters(cell, p, r, s, t);
    const auto weights = Unstructured::shape(volume_->type(cell), r, s, t);
    Vec3f g{0.f, 0.f, 0.f};
    for (int k = 0; k < volume_->vertices(cell); ++k)
      g = g + vertex_gradients_[volume_->vertex(cell, k)] * weights[static_cast<std::size_t>(k)];
    if (!(dot(g, g) > 0.f)) g = volume_->cell_gradient(cell, r, s, t);
    if (!(dot(g, g) > 0.f)) g = -dir;
    return g;
  }

  /// Each vertex's mean of its cells' gradients (at their centres), weighted by their volumes.
  void average_vertex_gradients() {
    const std::size_t vertex_count = volume_->vertex_count();
    vertex_gradients_.assign(vertex_count, Vec3f{0.f, 0.f, 0.f});
    std::vector<float> weight(vertex_count, 0.f);
    std::vector<bool> needed(vertex_count, false);
    for (std::uint32_t c : active_)
      for (int k = 0; k < volume_->vertices(c); ++k) needed[volume_->vertex(c, k)] = true;
    for (std::uint32_t c = 0; c < volume_->cell_count(); ++c) {
      bool touches = false;
      for (int k = 0; k < volume_->vertices(c) && !touches; ++k) touches = needed[volume_->vertex(c, k)];
      if (!touches) continue;
      const CellType type = volume_->type(c);
      const float r = type == CellType::tetrahedron ? 0.25f : type == CellType::wedge ? 1.f / 3.f : 0.5f;
      const float t = type == CellType::tetrahedron ? 0.25f : type == CellType::pyramid ? 0.2f : 0.5f;
      const Vec3f g = volume_->cell_gradient(c, r, r, t);
      const Box3f box = volume_->cell_box(c);
      const Vec3f e = box.upper - box.lower;
      const float w = e.x * e.y * e.z;  // about the cell's volume
      for (int k = 0; k < volume_->vertices(c); ++k) {
        const std::uint64_t v = volume_->vertex(c, k);
        vertex_gradients_[v] = vertex_gradients_[v] + g * w;
        weight[v] += w;
      }
    }
    for (std::size_t v = 0; v < vertex_count; ++v)
      if (weight[v] > 0.f) vertex_gradients_[v] = vertex_gradients_[v] / weight[v];
  }

  std::shared_ptr<const Unstructured> volume_;
  std::vector<float> isovalues_;
  std::vector<std::uint32_t> active_;   ///< cells that hold an isovalue
  std::vector<Vec3f> vertex_gradients_;  ///< mean gradient per vertex (0 where no active cell needs it)
};

}  // namespace sciray
