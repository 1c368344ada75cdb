#pragma once
// StructuredSpherical (OSPRay's / Open VKL's `structuredSpherical`): a regular grid in
// spherical coordinates (radius r, inclination θ from +z, azimuth φ from +x towards +y:
// the ISO convention), values at the vertices, r fastest, interpolated trilinearly in
// (r, θ, φ) index space, as planetary and stellar simulations write their shells.
//
// A point p maps to r = |p|, θ = acos(z / r) in [0°, 180°] (computed as atan2(ρ, z)),
// φ = atan2(y, x) in [0°, 360°) (Open VKL's SharedStructuredVolume.ih), and from there to
// index coordinates through `gridOrigin` and `gridSpacing` (angles in degrees; a negative
// spacing runs the grid backwards, as Open VKL allows). Outside [0, dimensions - 1] a
// sample is `background` (NaN by default: transparent). As in Open VKL, φ does not wrap: a
// grid that stops short of 360° leaves a wedge of background rather than joining its last
// vertices to its first.
//
// Unlike Open VKL, points within a ten-thousandth of a cell of the grid's ends count as
// inside (and read the end cell), so that float rounding in atan2 opens no seam of
// background along the poles and the 0°/360° meridian of a full sphere; and the centre
// (r = 0, where Open VKL's θ is acos(0/0)) takes θ = 0.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <string>
#include <type_traits>
#include <vector>

#include "sciray/error.hpp"
#include "sciray/math/box.hpp"
#include "sciray/math/vec.hpp"
#include "sciray/simd/packet.hpp"
#include "sciray/volume/macrocells.hpp"

namespace sciray {

/// A structured spherical volume as OSPRay's parameters describe it.
struct StructuredSphericalData {
  std::array<std::int64_t, 3> dimensions{0, 0, 0};  ///< the vertices along (r, θ, φ): `data`'s numItems
  std::vector<float> values;                        ///< data: one value per vertex, r fastest, then θ, then φ
  Vec3f grid_origin{0.f, 0.f, 0.f};                 ///< gridOrigin: (r, θ°, φ°) of vertex (0, 0, 0)
  Vec3f grid_spacing{1.f, 1.f, 1.f};                ///< gridSpacing: (Δr, Δθ°, Δφ°) between vertices
  float background = std::numeric_limits<float>::quiet_NaN();  ///< the value outside the grid
};

class StructuredSpherical {
public:
  explicit StructuredSpherical(StructuredSphericalData data) : d_(std::move(data)) {
    validate();
    prepare();
  }

  const std::array<std::int64_t, 3>& dims() const { return d_.dimensions; }
  const StructuredSphericalData& data() const { return d_; }
  Box3f bounds() const { return bounds_; }
  std::size_t owned_bytes() const {
    return d_.values.size() * sizeof(float) + (theta_cells_.size() + phi_cells_.size()) * sizeof(AngleCell);
  }
  /// The smallest and largest vertex value (the interpolant stays between them).
  std::array<float, 2> value_range() const { return range_; }

  /// A typical cell's extent, the same along every axis: the smallest of the radial
  /// spacing and the two angular spacings' arcs at the middle radius (and, for φ, the
  /// middle inclination).
  const Vec3f& cell_size() const { return cell_size_; }

  /// Macrocells of about n typical cells a side over bounds(), at most 128 a side.
  MacrocellGrid macrocell_grid(std::int64_t n) const { return MacrocellGrid::over(bounds(), cell_size_.x, n); }
  /// Widens the ranges of `m` by every spherical cell's corner values over the macrocells
  /// its Cartesian box overlaps. The box is exact (r, sin θ, cos θ, sin φ, cos φ each take
  /// their extremes over the cell independently: at its ends, or where an angle passes a
  /// multiple of 90°), then padded for float rounding and the grid's end tolerance. A
  /// finite background widens every macrocell (almost all reach outside the grid).
  void widen_macrocell_ranges(const MacrocellGrid& m, std::int64_t, std::vector<float>& ranges) const {
    const auto& d = d_.dimensions;
    for (std::int64_t k = 0; k + 1 < d[2]; ++k)
      for (std::int64_t j = 0; j + 1 < d[1]; ++j)
        for (std::int64_t i = 0; i + 1 < d[0]; ++i) {
          float v[8];
          corners(i, j, k, v);
          const auto [lo, hi] = std::minmax_element(v, v + 8);
          m.widen(cell_box(i, j, k), *lo, *hi, ranges);
        }
    if (!std::isnan(d_.background))
      for (std::size_t c = 0; c < m.count(); ++c) {
        ranges[2 * c] = std::min(ranges[2 * c], d_.background);
        ranges[2 * c + 1] = std::max(ranges[2 * c + 1], d_.background);
      }
  }

  /// The interpolated value at p, or the background outside the grid.
  float sample(const Vec3f& p) const {
    float f[3];
    std::int64_t at;
    if (!locate(to_index<float>(p), at, f)) return d_.background;
    float v[8];
    corners(at, v);
    return trilinear<float>(v, f[0], f[1], f[2]);
  }
  /// sample() for a packet: the coordinate transform in registers, the corners lane by
  /// lane, the interpolation in registers again.
  template <class Arch>
  simd::Float<Arch> sample(const Vec3<simd::Float<Arch>>& p) const {
    if constexpr (std::is_same_v<Arch, simd::scalar>) {
      return sample(p);
    } else {
      using F = simd::Float<Arch>;
      constexpr int W = simd::width<Arch>;
      const Vec3<F> c = to_index<F>(p);
      alignas(64) float cx[W], cy[W], cz[W], fr[3][W], v[8][W], outside[W];
      simd::store<Arch>(cx, c.x), simd::store<Arch>(cy, c.y), simd::store<Arch>(cz, c.z);
      for (int l = 0; l < W; ++l) {
        float f[3], corner[8];
        std::int64_t at;
        const bool inside = locate({cx[l], cy[l], cz[l]}, at, f);
        outside[l] = inside ? 0.f : 1.f;
        if (inside)
          corners(at, corner);
        else
          std::fill(corner, corner + 8, 0.f), f[0] = f[1] = f[2] = 0.f;
        for (int k = 0; k < 3; ++k) fr[k][l] = f[k];
        for (int k = 0; k < 8; ++k) v[k][l] = corner[k];
      }
      F corner[8];
      for (int k = 0; k < 8; ++k) corner[k] = simd::load<Arch>(v[k]);
      const F value = trilinear<F>(corner, simd::load<Arch>(fr[0]), simd::load<Arch>(fr[1]), simd::load<Arch>(fr[2]));
      return simd::select(simd::load<Arch>(outside) != F(0.f), F(d_.background), value);
    }
  }

  /// The gradient of the interpolant, analytic: its derivatives in index space through
  /// the chain rule, ∇v = v_r ∇r + v_θ ∇θ + v_φ ∇φ with ∇r = p/r, ∇θ = (xz/ρ, yz/ρ, -ρ)/r²,
  /// ∇φ = (-y, x, 0)/ρ² (ρ² = x² + y²). On the z axis and at the centre, where θ or φ has
  /// no derivative, central differences a tenth of a cell apart (0 where a neighbour lies
  /// outside the grid). 0 outside the grid.
  template <class Arch>
  Vec3<simd::Float<Arch>> gradient(const Vec3<simd::Float<Arch>>& p) const {
    if constexpr (std::is_same_v<Arch, simd::scalar>) {
      return gradient_at(p);
    } else {
      constexpr int W = simd::width<Arch>;
      alignas(64) float out[3][W];
      for (int l = 0; l < W; ++l) {
        const Vec3f g = gradient_at({simd::lane(p.x, l), simd::lane(p.y, l), simd::lane(p.z, l)});
        out[0][l] = g.x, out[1][l] = g.y, out[2][l] = g.z;
      }
      return {simd::load<Arch>(out[0]), simd::load<Arch>(out[1]), simd::load<Arch>(out[2])};
    }
  }
  template <class Arch>
  Vec3<simd::Float<Arch>> shading_gradient(const Vec3<simd::Float<Arch>>& p) const {
    return gradient<Arch>(p);
  }

  /// How far past the grid's ends (in cells) a point still counts as inside.
  static constexpr float end_tolerance = 1e-4f;

private:
  /// The ranges of sin and cos over one angular cell.
  struct AngleCell {
    float sin_lo, sin_hi, cos_lo, cos_hi;
  };
  struct Interval {
    float lo, hi;
  };
  static Interval times(Interval a, Interval b) {
    const float p[4] = {a.lo * b.lo, a.lo * b.hi, a.hi * b.lo, a.hi * b.hi};
    return {std::min({p[0], p[1], p[2], p[3]}), std::max({p[0], p[1], p[2], p[3]})};
  }

  // ---- Coordinates ----

  template <class F>
  static F atan2_of(const F& y, const F& x) {
    if constexpr (std::is_same_v<F, float>)
      return std::atan2(y, x);
    else
      return xsimd::atan2(y, x);
  }

  // GCC 12 warns that _mm512_sqrt_ps's _mm512_undefined_ps() is uninitialised when
  // inlined here at -O1 (GCC bug 105593, fixed in GCC 13): a false alarm.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wuninitialized"
#endif
  /// Continuous index coordinates (vertex i at i) of object-space points.
  template <class F>
  Vec3<F> to_index(const Vec3<F>& p) const {
    const F rho = simd::sqrt(p.x * p.x + p.y * p.y), r = simd::sqrt(rho * rho + p.z * p.z);
    // θ = atan2(ρ, z) equals Open VKL's acos(z / r) but keeps its precision near the poles
    // (where acos of a rounded z / r loses half the digits) and is 0 at the centre.
    // atan2(0, 0) is 0 in libm but NaN in xsimd: the centre and the axis take θ = φ = 0.
    const F theta = simd::select(r > F(0.f), atan2_of(rho, p.z), F(0.f));
    const F atan = simd::select(rho > F(0.f), atan2_of(p.y, p.x), F(0.f));  // (-π, π]
    // The grid's convention is [0, 2π).
    const F phi = simd::select(atan < F(0.f), atan + F(2.f * std::numbers::pi_v<float>), atan);
    return {(r - F(origin_.x)) * F(inv_spacing_.x), (theta - F(origin_.y)) * F(inv_spacing_.y),
            (phi - F(origin_.z)) * F(inv_spacing_.z)};
  }
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif

  /// The flat index of the cell holding index coordinates c and the fractions within it;
  /// false outside the grid (NaN coordinates included).
  bool locate(const Vec3f& c, std::int64_t& at, float f[3]) const {
    const auto& d = d_.dimensions;
    std::int64_t i[3];
    for (int k = 0; k < 3; ++k) {
      const float last = static_cast<float>(d[k] - 1);
      if (!(c[k] >= -end_tolerance && c[k] <= last + end_tolerance)) return false;
      const float clamped = std::clamp(c[k], 0.f, last);
      // The cell's lower vertex, one short of the last so the cell exists.
      i[k] = std::min<std::int64_t>(static_cast<std::int64_t>(clamped), d[k] - 2);
      f[k] = clamped - static_cast<float>(i[k]);
    }
    at = (i[2] * d[1] + i[1]) * d[0] + i[0];
    return true;
  }
  /// The values at the 8 vertices of the cell whose lower vertex has flat index `at`,
  /// r fastest (corner (a, b, c) at a + 2b + 4c).
  void corners(std::int64_t at, float v[8]) const {
    const auto& d = d_.dimensions;
    const std::int64_t row = d[0], slice = d[0] * d[1];
    const float* p = d_.values.data() + at;
    v[0] = p[0], v[1] = p[1], v[2] = p[row], v[3] = p[row + 1];
    v[4] = p[slice], v[5] = p[slice + 1], v[6] = p[slice + row], v[7] = p[slice + row + 1];
  }
  void corners(std::int64_t i, std::int64_t j, std::int64_t k, float v[8]) const {
    corners((k * d_.dimensions[1] + j) * d_.dimensions[0] + i, v);
  }
  template <class F>
  static F trilinear(const F v[8], const F& fr, const F& ft, const F& fp) {
    const auto lerp = [](const F& a, const F& b, const F& t) { return simd::fma(b - a, t, a); };
    return lerp(lerp(lerp(v[0], v[1], fr), lerp(v[2], v[3], fr), ft),
                lerp(lerp(v[4], v[5], fr), lerp(v[6], v[7], fr), ft), fp);
  }

  Vec3f gradient_at(const Vec3f& p) const {
    const Vec3f zero{0.f, 0.f, 0.f};
    float f[3];
    std::int64_t at;
    if (!locate(to_index<float>(p), at, f)) return zero;
    const float rho2 = p.x * p.x + p.y * p.y, r2 = rho2 + p.z * p.z;
    if (!(rho2 > 1e-12f * r2) || !(r2 > 0.f)) return central_differences(p);
    float v[8];
    corners(at, v);
    const float er = 1.f - f[0], et = 1.f - f[1], ep = 1.f - f[2];
    // The interpolant's derivatives along the index axes, then per unit of r, θ, φ.
    const float dr = (et * ep * (v[1] - v[0]) + f[1] * ep * (v[3] - v[2]) + et * f[2] * (v[5] - v[4]) +
                      f[1] * f[2] * (v[7] - v[6])) *
                     inv_spacing_.x;
    const float dt = (er * ep * (v[2] - v[0]) + f[0] * ep * (v[3] - v[1]) + er * f[2] * (v[6] - v[4]) +
                      f[0] * f[2] * (v[7] - v[5])) *
                     inv_spacing_.y;
    const float dp = (er * et * (v[4] - v[0]) + f[0] * et * (v[5] - v[1]) + er * f[1] * (v[6] - v[2]) +
                      f[0] * f[1] * (v[7] - v[3])) *
                     inv_spacing_.z;
    const float r = std::sqrt(r2), rho = std::sqrt(rho2);
    const Vec3f grad_r = p / r;
    const Vec3f grad_theta = Vec3f{p.x * p.z / rho, p.y * p.z / rho, -rho} / r2;
    const Vec3f grad_phi = Vec3f{-p.y, p.x, 0.f} / rho2;
    return grad_r * dr + grad_theta * dt + grad_phi * dp;
  }
  Vec3f central_differences(const Vec3f& p) const {
    const float h = 0.1f * cell_size_.x;
    const auto difference = [&](const Vec3f& axis) {
      const float g = (sample(p + axis * h) - sample(p - axis * h)) * (0.5f / h);
      return g == g ? g : 0.f;
    };
    return {difference({1.f, 0.f, 0.f}), difference({0.f, 1.f, 0.f}), difference({0.f, 0.f, 1.f})};
  }

  // ---- Geometry of the cells ----

  /// The coordinates of vertex `index` along `axis`, in radians for the angles.
  double vertex(int axis, std::int64_t index) const {
    return origin_d_[axis] + static_cast<double>(index) * spacing_d_[axis];
  }
  /// sin and cos over the angles between a and b (radians, either order), exactly: at
  /// the ends, or ±1 where a multiple of π/2 lies between them.
  static AngleCell angle_cell(double a, double b) {
    if (a > b) std::swap(a, b);
    AngleCell c{
        static_cast<float>(std::min(std::sin(a), std::sin(b))), static_cast<float>(std::max(std::sin(a), std::sin(b))),
        static_cast<float>(std::min(std::cos(a), std::cos(b))), static_cast<float>(std::max(std::cos(a), std::cos(b)))};
    constexpr double quarter = std::numbers::pi / 2;
    for (int q = static_cast<int>(std::ceil(a / quarter)); q * quarter <= b; ++q) switch (((q % 4) + 4) % 4) {
        case 0: c.cos_hi = 1.f; break;
        case 1: c.sin_hi = 1.f; break;
        case 2: c.cos_lo = -1.f; break;
        case 3: c.sin_lo = -1.f; break;
      }
    return c;
  }
  /// The Cartesian box of the region r in [r0, r1], angles in `theta` × `phi`, padded.
  Box3f box_of(Interval r, const AngleCell& theta, const AngleCell& phi) const {
    const Interval sin_t{theta.sin_lo, theta.sin_hi};
    const Interval x = times(r, times(sin_t, {phi.cos_lo, phi.cos_hi}));
    const Interval y = times(r, times(sin_t, {phi.sin_lo, phi.sin_hi}));
    const Interval z = times(r, {theta.cos_lo, theta.cos_hi});
    return {{x.lo - pad_, y.lo - pad_, z.lo - pad_}, {x.hi + pad_, y.hi + pad_, z.hi + pad_}};
  }
  Box3f cell_box(std::int64_t i, std::int64_t j, std::int64_t k) const {
    const float a = static_cast<float>(vertex(0, i)), b = static_cast<float>(vertex(0, i + 1));
    return box_of({std::min(a, b), std::max(a, b)}, theta_cells_[static_cast<std::size_t>(j)],
                  phi_cells_[static_cast<std::size_t>(k)]);
  }

  // ---- Construction ----

  void validate() {
    const auto fail = [](const std::string& what) { throw Error("structuredSpherical volume: " + what); };
    const auto& d = d_.dimensions;
    const std::string dims = std::to_string(d[0]) + "x" + std::to_string(d[1]) + "x" + std::to_string(d[2]);
    if (d_.values.empty()) fail("'data' is missing or empty");
    if (d[0] < 2 || d[1] < 2 || d[2] < 2)
      fail("'dimensions' must be at least 2 along each of r, theta and phi, got " + dims);
    if (static_cast<double>(d[0]) * static_cast<double>(d[1]) * static_cast<double>(d[2]) > 9e18)
      fail("'dimensions' " + dims + " has too many vertices");
    const auto expected = static_cast<std::size_t>(d[0] * d[1] * d[2]);
    if (d_.values.size() != expected)
      fail("'data' has " + std::to_string(d_.values.size()) + " values but 'dimensions' " + dims + " needs " +
           std::to_string(expected));
    const char* axes[3] = {"radius", "inclination", "azimuth"};
    for (int k = 0; k < 3; ++k) {
      if (!std::isfinite(d_.grid_origin[k])) fail(std::string("'gridOrigin' ") + axes[k] + " is not finite");
      if (!std::isfinite(d_.grid_spacing[k]) || d_.grid_spacing[k] == 0.f)
        fail(std::string("'gridSpacing' ") + axes[k] + " must be finite and not 0, got " +
             std::to_string(d_.grid_spacing[k]));
    }
    // Open VKL's limits on the vertices (a negative spacing runs backwards), with a little
    // slack for spacings such as 180/11 that float rounding carries just past the end.
    const float limits[3][2] = {{0.f, std::numeric_limits<float>::infinity()}, {0.f, 180.f}, {0.f, 360.f}};
    const char* units[3] = {"", " degrees", " degrees"};
    for (int k = 0; k < 3; ++k) {
      const double first = d_.grid_origin[k], last = first + static_cast<double>(d[k] - 1) * d_.grid_spacing[k];
      const double lo = std::min(first, last), hi = std::max(first, last);
      const double slack = 1e-6 * (hi - lo) + (k == 0 ? 0.0 : 1e-4);
      if (lo < limits[k][0] - slack || hi > limits[k][1] + slack)
        fail(std::string("the ") + axes[k] + " grid ('gridOrigin' + [0, 'dimensions' - 1] x 'gridSpacing') spans [" +
             std::to_string(lo) + ", " + std::to_string(hi) + "]" + units[k] + ", outside [0, " +
             (k == 0   ? std::string("infinity)")
              : k == 1 ? std::string("180]")
                       : std::string("360]")));
    }
    for (std::size_t n = 0; n < d_.values.size(); ++n)
      if (!std::isfinite(d_.values[n])) {
        const auto i = static_cast<std::int64_t>(n);
        fail("'data' " + std::to_string(n) + " (vertex " + std::to_string(i % d[0]) + ", " +
             std::to_string(i / d[0] % d[1]) + ", " + std::to_string(i / (d[0] * d[1])) +
             " along r, theta, phi) is not finite");
      }
  }

  void prepare() {
    const auto& d = d_.dimensions;
    const double radians = std::numbers::pi / 180.0;
    for (int k = 0; k < 3; ++k) {
      const double scale = k == 0 ? 1.0 : radians;
      origin_d_[k] = d_.grid_origin[k] * scale;
      spacing_d_[k] = d_.grid_spacing[k] * scale;
    }
    origin_ = {static_cast<float>(origin_d_[0]), static_cast<float>(origin_d_[1]), static_cast<float>(origin_d_[2])};
    inv_spacing_ = {static_cast<float>(1.0 / spacing_d_[0]), static_cast<float>(1.0 / spacing_d_[1]),
                    static_cast<float>(1.0 / spacing_d_[2])};
    // A radius just below 0 by that slack is taken as 0 (no point lies there).
    const auto end = [&](int axis, bool upper) { return vertex(axis, upper ? d[axis] - 1 : 0); };
    const double r_lo = std::max(0.0, std::min(end(0, false), end(0, true)));
    const double r_hi = std::max(end(0, false), end(0, true));
    const double t_lo = std::min(end(1, false), end(1, true)), t_hi = std::max(end(1, false), end(1, true));
    const double p_lo = std::min(end(2, false), end(2, true)), p_hi = std::max(end(2, false), end(2, true));

    theta_cells_.resize(static_cast<std::size_t>(d[1] - 1));
    for (std::int64_t j = 0; j + 1 < d[1]; ++j)
      theta_cells_[static_cast<std::size_t>(j)] = angle_cell(vertex(1, j), vertex(1, j + 1));
    phi_cells_.resize(static_cast<std::size_t>(d[2] - 1));
    for (std::int64_t k = 0; k + 1 < d[2]; ++k)
      phi_cells_[static_cast<std::size_t>(k)] = angle_cell(vertex(2, k), vertex(2, k + 1));

    // Padding: the end tolerance (a ten-thousandth of a cell, radially and as an arc at
    // the outer radius) and float rounding of positions up to the outer radius.
    pad_ = static_cast<float>(
               1e-4 * (std::abs(spacing_d_[0]) + r_hi * (std::abs(spacing_d_[1]) + std::abs(spacing_d_[2]))) +
               4e-6 * r_hi) +
           std::numeric_limits<float>::min();
    bounds_ =
        box_of({static_cast<float>(r_lo), static_cast<float>(r_hi)}, angle_cell(t_lo, t_hi), angle_cell(p_lo, p_hi));

    range_ = {*std::min_element(d_.values.begin(), d_.values.end()),
              *std::max_element(d_.values.begin(), d_.values.end())};

    const double r_mid = 0.5 * (r_lo + r_hi);
    double typical = std::abs(spacing_d_[0]);
    for (const double arc :
         {r_mid * std::abs(spacing_d_[1]), r_mid * std::sin(0.5 * (t_lo + t_hi)) * std::abs(spacing_d_[2])})
      if (arc > 0.0) typical = std::min(typical, arc);
    const auto size = static_cast<float>(typical);
    cell_size_ = {size, size, size};
  }

  StructuredSphericalData d_;
  double origin_d_[3] = {0, 0, 0}, spacing_d_[3] = {1, 1, 1};  // angles in radians
  Vec3f origin_{0.f, 0.f, 0.f}, inv_spacing_{1.f, 1.f, 1.f};   // the same in float, for sampling
  std::vector<AngleCell> theta_cells_, phi_cells_;
  Box3f bounds_;
  float pad_ = 0.f;
  std::array<float, 2> range_{0.f, 0.f};
  Vec3f cell_size_{1.f, 1.f, 1.f};
};

}  // namespace sciray
