// Structured spherical volumes (volume/structured_spherical.hpp): fields linear in r, θ, φ
// reproduced exactly, the trilinear interpolant in index space, analytic gradients, the
// shell's box, conservative macrocells, packets equal to scalars, bad input named, and a
// ray's opacity through a constant shell against its closed form.
#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include "sciray/volume/structured_spherical.hpp"
#include "sciray/volume/volumetric_model.hpp"

using namespace sciray;

namespace {

constexpr double degrees = 180.0 / std::numbers::pi;

/// Deterministic uniform numbers in [0, 1) (splitmix64).
double uniform(std::uint64_t n) {
  std::uint64_t z = n * 0x9e3779b97f4a7c15ull + 0x632be59bd9b4e019ull;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return static_cast<double>((z ^ (z >> 31)) >> 11) * 0x1.0p-53;
}
Vec3f random_point(std::uint64_t n, float half) {
  const auto c = [&](int k) { return static_cast<float>((2 * uniform(3 * n + k) - 1) * half); };
  return {c(0), c(1), c(2)};
}

/// (r, θ°, φ°) of p in double, φ in [0, 360).
std::array<double, 3> spherical(const Vec3f& p) {
  const double x = p.x, y = p.y, z = p.z, rho = std::hypot(x, y);
  double phi = std::atan2(y, x) * degrees;
  if (phi < 0) phi += 360;
  return {std::hypot(rho, z), std::atan2(rho, z) * degrees, phi};
}

/// A grid whose vertex (i, j, k) holds f(r, θ°, φ°, i, j, k).
template <class F>
StructuredSphericalData grid(std::array<std::int64_t, 3> dims, Vec3f origin, Vec3f spacing, F&& f) {
  StructuredSphericalData d;
  d.dimensions = dims, d.grid_origin = origin, d.grid_spacing = spacing;
  for (std::int64_t k = 0; k < dims[2]; ++k)
    for (std::int64_t j = 0; j < dims[1]; ++j)
      for (std::int64_t i = 0; i < dims[0]; ++i)
        d.values.push_back(static_cast<float>(
            f(origin.x + i * spacing.x, origin.y + j * spacing.y, origin.z + k * spacing.z, i, j, k)));
  return d;
}
/// A shell r in [0.5, 2] over the full sphere: 0.25 radially, 15° in both angles.
template <class F>
StructuredSphericalData shell(F&& f) {
  return grid({7, 13, 25}, {0.5f, 0.f, 0.f}, {0.25f, 15.f, 15.f}, f);
}
float random_value(double, double, double, std::int64_t i, std::int64_t j, std::int64_t k) {
  return static_cast<float>(uniform(static_cast<std::uint64_t>((k * 100 + j) * 100 + i) + 7777));
}

/// The trilinear interpolant of `d` at p in index space, in double (NaN outside).
double reference(const StructuredSphericalData& d, const Vec3f& p) {
  const auto s = spherical(p);
  double c[3];
  std::int64_t at[3];
  for (int k = 0; k < 3; ++k) {
    const double index = (s[k] - d.grid_origin[k]) / d.grid_spacing[k];
    if (index < 0 || index > d.dimensions[k] - 1) return std::nan("");
    at[k] = std::min<std::int64_t>(static_cast<std::int64_t>(index), d.dimensions[k] - 2);
    c[k] = index - static_cast<double>(at[k]);
  }
  double sum = 0;
  for (int n = 0; n < 8; ++n) {
    const std::int64_t i = at[0] + (n & 1), j = at[1] + (n >> 1 & 1), k = at[2] + (n >> 2);
    const double w = (n & 1 ? c[0] : 1 - c[0]) * (n >> 1 & 1 ? c[1] : 1 - c[1]) * (n >> 2 ? c[2] : 1 - c[2]);
    sum += w * d.values[static_cast<std::size_t>((k * d.dimensions[1] + j) * d.dimensions[0] + i)];
  }
  return sum;
}

template <class Arch>
void check_packets_match_scalar(const StructuredSpherical& v) {
  constexpr int W = simd::width<Arch>;
  for (int n = 0; n < 64; ++n) {
    alignas(64) float p[3][W];
    for (int l = 0; l < W; ++l) {
      Vec3f q = random_point(static_cast<std::uint64_t>(W * n + l), 2.3f);
      if (l == 0) q = {0.f, 0.f, 1.2f * static_cast<float>(n % 3) - 1.2f};  // the axis, the centre
      p[0][l] = q.x, p[1][l] = q.y, p[2][l] = q.z;
    }
    const Vec3<simd::Float<Arch>> packet{simd::load<Arch>(p[0]), simd::load<Arch>(p[1]), simd::load<Arch>(p[2])};
    const auto values = v.sample<Arch>(packet);
    const auto gradients = v.gradient<Arch>(packet);
    for (int l = 0; l < W; ++l) {
      const Vec3f q{p[0][l], p[1][l], p[2][l]};
      INFO("lane " << l << " at " << q.x << " " << q.y << " " << q.z);
      const float scalar = v.sample(q);
      if (std::isnan(scalar))
        REQUIRE(std::isnan(simd::lane(values, l)));
      else
        REQUIRE(simd::lane(values, l) == Approx(scalar).margin(1e-5));
      const Vec3f g = v.gradient<simd::scalar>(q);
      REQUIRE(simd::lane(gradients.x, l) == Approx(g.x).margin(1e-3));
      REQUIRE(simd::lane(gradients.y, l) == Approx(g.y).margin(1e-3));
      REQUIRE(simd::lane(gradients.z, l) == Approx(g.z).margin(1e-3));
    }
  }
}

}  // namespace

TEST_CASE("structuredSpherical: fields linear in r, in θ and in φ are reproduced at random points",
          "[volume][spherical]") {
  const StructuredSpherical radius(shell([](double r, double, double, auto...) { return r; }));
  const StructuredSpherical theta(shell([](double, double t, double, auto...) { return t; }));
  const StructuredSpherical phi(shell([](double, double, double f, auto...) { return f; }));
  int inside = 0;
  for (std::uint64_t n = 0; n < 4000; ++n) {
    const Vec3f p = random_point(n, 2.2f);
    const auto s = spherical(p);
    INFO("p = " << p.x << " " << p.y << " " << p.z << ", r " << s[0]);
    if (s[0] < 0.5 - 1e-4 || s[0] > 2 + 1e-4) {
      REQUIRE(std::isnan(radius.sample(p)));
      continue;
    }
    if (s[0] < 0.5 + 1e-4 || s[0] > 2 - 1e-4) continue;  // too close to the shell's faces to call
    ++inside;
    REQUIRE(radius.sample(p) == Approx(s[0]).margin(2e-6));
    REQUIRE(theta.sample(p) == Approx(s[1]).margin(2e-4));
    if (s[2] > 1e-3 && s[2] < 360 - 1e-3) REQUIRE(phi.sample(p) == Approx(s[2]).margin(4e-4));
  }
  CHECK(inside > 1000);
  // The poles, the 0°/360° meridian and the faces of the shell are inside, not seams.
  CHECK(theta.sample({0.f, 0.f, 1.5f}) == 0.f);
  CHECK(theta.sample({0.f, 0.f, -1.5f}) == Approx(180.f));
  CHECK(phi.sample({1.5f, -1e-7f, 0.f}) == Approx(360.f));
  CHECK(radius.sample({0.f, 2.f, 0.f}) == Approx(2.f));
  CHECK(radius.sample({0.f, 0.f, -0.5f}) == Approx(0.5f));
  CHECK(radius.value_range() == std::array<float, 2>{0.5f, 2.f});
  CHECK(theta.value_range() == std::array<float, 2>{0.f, 180.f});
}

TEST_CASE("structuredSpherical: values interpolate trilinearly in (r, θ, φ) index space, r fastest",
          "[volume][spherical]") {
  // A random field, and a grid that runs backwards along every axis.
  const StructuredSphericalData d = shell(random_value);
  const StructuredSpherical v(d);
  const StructuredSphericalData backwards =
      grid({7, 13, 25}, {2.f, 180.f, 360.f}, {-0.25f, -15.f, -15.f}, random_value);
  const StructuredSpherical w(backwards);
  for (std::uint64_t n = 0; n < 3000; ++n) {
    const Vec3f p = random_point(n + 9000, 2.2f);
    const auto s = spherical(p);
    if (std::abs(s[0] - 0.5) < 1e-4 || std::abs(s[0] - 2) < 1e-4 || s[2] < 1e-3 || s[2] > 360 - 1e-3) continue;
    INFO("p = " << p.x << " " << p.y << " " << p.z);
    const double expected = reference(d, p);
    if (std::isnan(expected)) {
      REQUIRE(std::isnan(v.sample(p)));
      REQUIRE(std::isnan(w.sample(p)));
    } else {
      REQUIRE(v.sample(p) == Approx(expected).margin(1e-4));
      REQUIRE(w.sample(p) == Approx(reference(backwards, p)).margin(1e-4));
    }
  }
  CHECK(v.sample({0.75f, 0.f, 0.f}) == d.values[1 + 7 * 6]);  // vertex (1, 6, 0): r 0.75, θ 90°, φ 0°
}

TEST_CASE("structuredSpherical: outside the grid a sample is the background, φ does not wrap", "[volume][spherical]") {
  // r in [1, 2], θ in [0°, 60°], φ in [0°, 270°].
  StructuredSphericalData d = grid({5, 5, 10}, {1.f, 0.f, 0.f}, {0.25f, 15.f, 30.f}, [](auto...) { return 3.0; });
  const StructuredSpherical v(d);
  const auto at = [](double r, double theta, double phi) {
    const double t = theta / degrees, f = phi / degrees;
    return Vec3f{static_cast<float>(r * std::sin(t) * std::cos(f)), static_cast<float>(r * std::sin(t) * std::sin(f)),
                 static_cast<float>(r * std::cos(t))};
  };
  CHECK(v.sample({0.f, 0.f, 1.5f}) == 3.f);
  CHECK(v.sample(at(1.5, 45, 200)) == 3.f);
  CHECK(std::isnan(v.sample(at(0.5, 45, 200))));  // inside the hollow
  CHECK(std::isnan(v.sample(at(2.5, 45, 200))));  // beyond the outer face
  CHECK(std::isnan(v.sample(at(1.5, 90, 200))));  // past the cone
  CHECK(std::isnan(v.sample(at(1.5, 45, 315))));  // past 270°: no wrap to 0°
  CHECK(v.sample(at(1.5, 45, 5)) == 3.f);
  d.background = -1.f;
  CHECK(StructuredSpherical(d).sample({1.5f, 0.f, 0.f}) == -1.f);
  // A sphere from the centre: r = 0 is inside (θ taken as 0 there).
  const StructuredSpherical ball(
      grid({3, 3, 3}, {0.f, 0.f, 0.f}, {1.f, 90.f, 180.f}, [](double r, auto...) { return r; }));
  CHECK(ball.sample({0.f, 0.f, 0.f}) == 0.f);
  CHECK(v.owned_bytes() >= d.values.size() * sizeof(float));
}

TEST_CASE("structuredSpherical: bounds are the sector's box", "[volume][spherical]") {
  const auto box_of = [](Vec3f origin, Vec3f spacing, std::array<std::int64_t, 3> dims) {
    return StructuredSpherical(grid(dims, origin, spacing, [](auto...) { return 0.0; })).bounds();
  };
  const auto check_box = [](const Box3f& b, Vec3f lower, Vec3f upper) {
    for (int k = 0; k < 3; ++k) {
      CHECK(b.lower[k] <= lower[k]);  // conservative, and tight to 1e-3
      CHECK(b.lower[k] == Approx(lower[k]).margin(1e-3));
      CHECK(b.upper[k] >= upper[k]);
      CHECK(b.upper[k] == Approx(upper[k]).margin(1e-3));
    }
  };
  check_box(box_of({0.f, 0.f, 0.f}, {0.5f, 15.f, 15.f}, {5, 13, 25}), {-2.f, -2.f, -2.f}, {2.f, 2.f, 2.f});
  check_box(box_of({0.f, 0.f, 0.f}, {0.5f, 15.f, 15.f}, {5, 7, 25}), {-2.f, -2.f, 0.f}, {2.f, 2.f, 2.f});  // θ ≤ 90°
  const float c = 2.f * std::sqrt(0.5f);
  // r in [1, 2], θ in [45°, 135°], φ in [0°, 90°] (and the same backwards).
  check_box(box_of({1.f, 45.f, 0.f}, {0.25f, 15.f, 15.f}, {5, 7, 7}), {0.f, 0.f, -c}, {2.f, 2.f, c});
  check_box(box_of({2.f, 135.f, 90.f}, {-0.25f, -15.f, -15.f}, {5, 7, 7}), {0.f, 0.f, -c}, {2.f, 2.f, c});
  // r in [1, 2], θ in [30°, 60°], φ in [120°, 150°]: the extremes at the sector's corners.
  const double t0 = 30 / degrees, t1 = 60 / degrees, f0 = 120 / degrees, f1 = 150 / degrees;
  check_box(box_of({1.f, 30.f, 120.f}, {0.5f, 15.f, 15.f}, {3, 3, 3}),
            {static_cast<float>(2 * std::sin(t1) * std::cos(f1)), static_cast<float>(1 * std::sin(t0) * std::sin(f1)),
             static_cast<float>(1 * std::cos(t1))},
            {static_cast<float>(1 * std::sin(t0) * std::cos(f0)), static_cast<float>(2 * std::sin(t1) * std::sin(f0)),
             static_cast<float>(2 * std::cos(t0))});
}

TEST_CASE("structuredSpherical: macrocell ranges hold every sample inside them", "[volume][spherical]") {
  for (float background : {std::nanf(""), -5.f}) {
    for (const auto& d : {shell(random_value), grid({6, 5, 7}, {1.f, 20.f, 40.f}, {0.2f, 25.f, 40.f}, random_value)}) {
      StructuredSphericalData data = d;
      data.background = background;
      const StructuredSpherical v(data);
      const MacrocellGrid m = v.macrocell_grid(2);
      REQUIRE(m.count() > 8);
      std::vector<float> ranges = m.empty_ranges();
      v.widen_macrocell_ranges(m, 2, ranges);
      int values = 0;
      for (std::int64_t z = 0; z < m.counts[2]; ++z)
        for (std::int64_t y = 0; y < m.counts[1]; ++y)
          for (std::int64_t x = 0; x < m.counts[0]; ++x) {
            const std::size_t i = m.index(x, y, z);
            for (std::uint64_t n = 0; n < 60; ++n) {
              const auto u = [&](int k) { return static_cast<float>(uniform(3 * (i * 60 + n) + k)); };
              const Vec3f p{m.lower.x + (static_cast<float>(x) + u(0)) * m.size.x,
                            m.lower.y + (static_cast<float>(y) + u(1)) * m.size.y,
                            m.lower.z + (static_cast<float>(z) + u(2)) * m.size.z};
              const float value = v.sample(p);
              if (std::isnan(value)) continue;
              ++values;
              INFO("macrocell " << x << " " << y << " " << z << ", value " << value << " in [" << ranges[2 * i] << ", "
                                << ranges[2 * i + 1] << "]");
              // Within the range up to a float rounding of the interpolation.
              REQUIRE(value >= ranges[2 * i] - 1e-6f);
              REQUIRE(value <= ranges[2 * i + 1] + 1e-6f);
            }
          }
      CHECK(values > 1000);
    }
  }
}

TEST_CASE("structuredSpherical: gradients are the analytic gradients of fields linear in r, θ and φ",
          "[volume][spherical]") {
  const StructuredSpherical radius(shell([](double r, auto...) { return r; }));
  const StructuredSpherical theta(shell([](double, double t, auto...) { return t; }));
  const StructuredSpherical phi(shell([](double, double, double f, auto...) { return f; }));
  for (std::uint64_t n = 0; n < 2000; ++n) {
    const Vec3f p = random_point(n + 40000, 2.f);
    const auto s = spherical(p);
    const double r = s[0], rho = std::hypot(p.x, p.y);
    if (r < 0.55 || r > 1.95 || rho < 0.05 || s[2] < 1 || s[2] > 359) continue;
    INFO("p = " << p.x << " " << p.y << " " << p.z);
    const Vec3f gr = radius.gradient<simd::scalar>(p);
    const Vec3f gt = theta.gradient<simd::scalar>(p);
    const Vec3f gp = phi.gradient<simd::scalar>(p);
    const double expected_r[3] = {p.x / r, p.y / r, p.z / r};
    const double expected_t[3] = {degrees * p.x * p.z / (r * r * rho), degrees * p.y * p.z / (r * r * rho),
                                  -degrees * rho / (r * r)};
    const double expected_p[3] = {-degrees * p.y / (rho * rho), degrees * p.x / (rho * rho), 0};
    for (int k = 0; k < 3; ++k) {
      REQUIRE(gr[k] == Approx(expected_r[k]).margin(1e-4));
      REQUIRE(gt[k] == Approx(expected_t[k]).epsilon(1e-4).margin(1e-2));
      REQUIRE(gp[k] == Approx(expected_p[k]).epsilon(1e-4).margin(1e-2));
    }
  }
  // On the axis, central differences: ∇r = ±z there.
  const Vec3f up = radius.gradient<simd::scalar>(Vec3f{0.f, 0.f, 1.3f});
  const Vec3f down = radius.gradient<simd::scalar>(Vec3f{0.f, 0.f, -1.3f});
  CHECK(up.z == Approx(1.f).epsilon(1e-3));
  CHECK(down.z == Approx(-1.f).epsilon(1e-3));
  CHECK(std::abs(up.x) + std::abs(up.y) < 1e-3f);
  const Vec3f outside = radius.gradient<simd::scalar>(Vec3f{0.1f, 0.f, 0.f});
  CHECK((outside.x == 0.f && outside.y == 0.f && outside.z == 0.f));
}

TEST_CASE("structuredSpherical: packets sample and differentiate as the scalar code does",
          "[volume][spherical][simd]") {
  const StructuredSpherical v(shell(random_value));
  check_packets_match_scalar<simd::scalar>(v);
  check_packets_match_scalar<xsimd::default_arch>(v);
#if XSIMD_WITH_AVX512BW
  check_packets_match_scalar<xsimd::avx512bw>(v);
#endif
}

TEST_CASE("structuredSpherical: bad input is named", "[volume][spherical][errors]") {
  const StructuredSphericalData good = shell(random_value);
  const auto throws = [](const StructuredSphericalData& d, const std::string& what) {
    CHECK_THROWS_WITH(StructuredSpherical(d),
                      Catch::Contains(what) && Catch::StartsWith("structuredSpherical volume: "));
  };
  StructuredSphericalData d = good;
  d.values.clear();
  throws(d, "'data' is missing or empty");
  d = good;
  d.dimensions = {7, 1, 25 * 13};
  throws(d, "'dimensions' must be at least 2 along each of r, theta and phi, got 7x1x325");
  d = good;
  d.dimensions = {1 << 21, 1 << 21, 1 << 21};
  throws(d, "'dimensions' 2097152x2097152x2097152 has too many vertices");
  d = good;
  d.values.pop_back();
  throws(d, "'data' has 2274 values but 'dimensions' 7x13x25 needs 2275");
  d = good;
  d.grid_origin.y = INFINITY;
  throws(d, "'gridOrigin' inclination is not finite");
  d = good;
  d.grid_spacing.z = 0.f;
  throws(d, "'gridSpacing' azimuth must be finite and not 0, got 0.000000");
  d = good;
  d.grid_spacing.x = std::nanf("");
  throws(d, "'gridSpacing' radius must be finite and not 0");
  d = good;
  d.grid_origin.x = -0.1f;
  throws(d,
         "the radius grid ('gridOrigin' + [0, 'dimensions' - 1] x 'gridSpacing') spans [-0.100000, 1.400000], "
         "outside [0, infinity)");
  d = good;
  d.grid_origin.y = 10.f;
  throws(d,
         "the inclination grid ('gridOrigin' + [0, 'dimensions' - 1] x 'gridSpacing') spans [10.000000, "
         "190.000000] degrees, outside [0, 180]");
  d = good;
  d.grid_spacing.z = -15.f;
  throws(d,
         "the azimuth grid ('gridOrigin' + [0, 'dimensions' - 1] x 'gridSpacing') spans [-360.000000, 0.000000] "
         "degrees, outside [0, 360]");
  d = good;
  d.values[7 * 13 * 2 + 7 * 3 + 4] = std::nanf("");
  throws(d, "'data' 207 (vertex 4, 3, 2 along r, theta, phi) is not finite");
  // Float rounding just past 180° (11 × float(180 / 11) = 180.0000019°) is accepted.
  CHECK_NOTHROW(
      StructuredSpherical(grid({3, 12, 3}, {1.f, 0.f, 0.f}, {1.f, 180.f / 11.f, 90.f}, [](auto...) { return 0.0; })));
}

TEST_CASE("structuredSpherical: a ray through a constant shell absorbs 1 - exp(-σ L) over its chord",
          "[volume][spherical][integral]") {
  // Value 1 for r in [1, 2] over the full sphere, background (transparent) inside; the
  // transfer function gives σ = 0.5 everywhere.
  const auto volume = std::make_shared<const StructuredSpherical>(
      grid({11, 19, 37}, {1.f, 0.f, 0.f}, {0.1f, 10.f, 10.f}, [](auto...) { return 1.0; }));
  const float sigma = 0.5f;
  const VolumetricModel<StructuredSpherical> model(volume, TransferFunction({{1, 1, 1}}, {sigma}, {0.f, 2.f}));
  VolumeIntegration how;
  how.sampling_rate = 32.f;  // a step of 0.1 / 32: the faces cut steps in at most 4 places
  for (const float h : {0.f, 0.3f, 0.7f, 0.95f, 1.2f, 1.7f, 1.95f}) {
    for (const bool skipping : {true, false}) {
      how.empty_space_skipping = skipping;
      // Along +x at distance h from the centre, in the plane tilted 30° about x.
      const Ray<float> ray{{-3.f, h * 0.8660254f, h * 0.5f}, {1.f, 0.f, 0.f}};
      const double chord = 2 * (std::sqrt(4.0 - h * h) - std::sqrt(std::max(0.0, 1.0 - h * h)));
      const double expected = 1 - std::exp(-sigma * chord);
      const auto got = model.integrate<simd::scalar>(ray, true, INFINITY, how);
      INFO("h " << h << ", chord " << chord << ", skipping " << skipping);
      CHECK(got.alpha == Approx(expected).margin(4e-3));
    }
  }
  // A packet of rays at distances 0.1, 0.2, ... from the centre, lit by gradient shading
  // (which reads the packet gradient), absorbs as each of its rays alone.
  // (AVX2 where built: GCC 12 at -O1 warns falsely in AVX-512's _mm512_min_ps, bug 105593.)
#if XSIMD_WITH_AVX2
  using A = xsimd::avx2;
#else
  using A = xsimd::default_arch;
#endif
  constexpr int W = simd::width<A>;
  VolumetricModel<StructuredSpherical> shaded(volume, TransferFunction({{1, 1, 1}}, {sigma}, {0.f, 2.f}));
  shaded.set_gradient_shading_scale(1.f);
  alignas(64) float y[W], z[W];
  for (int l = 0; l < W; ++l) y[l] = 0.1f * static_cast<float>(l + 1), z[l] = 0.05f;
  const Ray<simd::Float<A>> rays{{simd::Float<A>(-3.f), simd::load<A>(y), simd::load<A>(z)},
                                 {simd::Float<A>(1.f), simd::Float<A>(0.f), simd::Float<A>(0.f)}};
  const auto lit = [](const auto&, const auto&, const auto& color, const auto&) { return color; };
  const auto packet = shaded.integrate<A>(rays, simd::Mask<A>(true), simd::Float<A>(INFINITY), how, lit);
  for (int l = 0; l < W; ++l) {
    const Ray<float> ray{{-3.f, y[l], z[l]}, {1.f, 0.f, 0.f}};
    CHECK(simd::lane(packet.alpha, l) ==
          Approx(model.integrate<simd::scalar>(ray, true, INFINITY, how).alpha).margin(1e-5));
  }
}
