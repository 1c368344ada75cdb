// Isosurfaces of the volume types without cells to solve in (geometry/isosurface_sampled.hpp):
// analytic surfaces of spherical, vdb and amr fields found to bisection's precision.
#include <catch2/catch.hpp>

#include <cmath>
#include <memory>
#include <vector>

#include "sciray/geometry/isosurface.hpp"
#include "sciray/testing/scenes.hpp"
#include "sciray/volume/amr.hpp"
#include "sciray/volume/structured_spherical.hpp"
#include "sciray/volume/vdb.hpp"

using namespace sciray;

namespace {

/// The nearest crossing over all of `surface`'s primitives, as Embree would report it.
PrimitiveHit<simd::scalar> first_hit(const Isosurface& surface, const Ray<float>& ray) {
  PrimitiveHit<simd::scalar> best{false, INFINITY, {}};
  for (std::uint32_t p = 0; p < surface.primitive_count(); ++p)
    if (const auto h = surface.intersect_primitive<simd::scalar>(ray, p); h.hit && h.t < best.t) best = h;
  return best;
}

/// 40 rays up +z from z = −5 at random (x, y) in [lo, hi]².
std::vector<Ray<float>> rays_up(float lo, float hi) {
  std::vector<Ray<float>> rays;
  for (std::size_t i = 0; i < 40; ++i)
    rays.push_back({{lo + (hi - lo) * testing::hash_uniform(2 * i), lo + (hi - lo) * testing::hash_uniform(2 * i + 1), -5.f},
                    {0.f, 0.f, 1.f}});
  return rays;
}

}  // namespace

TEST_CASE("sampled isosurfaces: a sphere in a spherical grid, planes in vdb and amr fields", "[isosurface][volume]") {
  SECTION("structuredSpherical: the field r is 1.5 on the sphere of radius 1.5") {
    StructuredSphericalData d;
    d.dimensions = {3, 13, 25};
    d.grid_origin = {1.f, 0.f, 0.f};
    d.grid_spacing = {0.5f, 15.f, 15.f};
    for (int k = 0; k < 25; ++k)
      for (int j = 0; j < 13; ++j)
        for (int i = 0; i < 3; ++i) d.values.push_back(1.f + 0.5f * static_cast<float>(i));
    const Isosurface surface(std::make_shared<const StructuredSpherical>(std::move(d)), {1.5f});
    for (const auto& ray : rays_up(-1.f, 1.f)) {
      const float rho2 = ray.org.x * ray.org.x + ray.org.y * ray.org.y;
      const auto hit = first_hit(surface, ray);
      REQUIRE(hit.hit);
      CHECK(hit.t == Approx(5.f - std::sqrt(2.25f - rho2)).margin(1e-4));
      CHECK(dot(normalize(hit.ng), normalize(ray.org + ray.dir * hit.t)) == Approx(1.f).margin(1e-3));
    }
  }
  SECTION("vdb: a field linear in the index across two leaves is a plane") {
    VdbData d;
    for (int leaf = 0; leaf < 2; ++leaf) {
      d.level.push_back(3);
      d.origin.push_back({0, 0, 8 * leaf});
      std::vector<float> values;
      for (int x = 0; x < 8; ++x)  // z fastest
        for (int y = 0; y < 8; ++y)
          for (int z = 0; z < 8; ++z) values.push_back(static_cast<float>(x + 2 * y + (8 * leaf + z)));
      d.data.push_back(std::move(values));
    }
    const Isosurface surface(std::make_shared<const Vdb>(std::move(d)), {12.f});
    for (const auto& ray : rays_up(0.5f, 6.5f)) {
      const float z = 12.f - ray.org.x - 2.f * ray.org.y;  // where x + 2y + z = 12
      const auto hit = first_hit(surface, ray);
      if (z < 0.f || z > 15.f) continue;
      REQUIRE(hit.hit);
      CHECK(hit.t == Approx(z + 5.f).margin(1e-4));
    }
  }
  SECTION("amr: a linear field over two levels is a plane") {
    AmrData d;
    d.cell_width = {1.f, 0.5f};
    d.block_bounds = {{{0, 0, 0}, {7, 7, 7}}, {{4, 4, 4}, {11, 11, 11}}};
    d.block_level = {0, 1};
    for (int level = 0; level < 2; ++level) {
      const auto& b = d.block_bounds[static_cast<std::size_t>(level)];
      const float w = d.cell_width[static_cast<std::size_t>(level)];
      std::vector<float> cells;
      for (int z = b.lower[2]; z <= b.upper[2]; ++z)
        for (int y = b.lower[1]; y <= b.upper[1]; ++y)
          for (int x = b.lower[0]; x <= b.upper[0]; ++x) cells.push_back(((x + 0.5f) + (y + 0.5f) + 2 * (z + 0.5f)) * w);
      d.block_data.push_back(std::move(cells));
    }
    const Isosurface surface(std::make_shared<const Amr>(std::move(d)), {8.f});
    for (const auto& ray : rays_up(0.6f, 7.4f)) {
      const float z = (8.f - ray.org.x - ray.org.y) / 2.f;  // where x + y + 2z = 8
      if (z < 0.6f || z > 7.4f) continue;  // the dual cells' clamped edge half a cell wide
      const auto hit = first_hit(surface, ray);
      REQUIRE(hit.hit);
      CHECK(hit.t == Approx(z + 5.f).margin(1e-4));
    }
  }
}
