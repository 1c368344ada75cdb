// Implicit isosurfaces: exact ray–trilinear intersection against analytic surfaces, and
// the thin shell that sampling misses (tests/stability case, docs/accuracy.md).
#include <catch2/catch.hpp>

#include <cmath>
#include <memory>
#include <vector>

#include "sciray/shim/engine.hpp"
#include "sciray/testing/scenes.hpp"
#include "support/isas.hpp"
#include "support/trace.hpp"

using namespace sciray;
using sciray::test_support::supported_isas;
using sciray::test_support::trace_geometry;

namespace {

template <class F>
std::shared_ptr<const StructuredRegular<float>> volume_of(const VolumeDims& d, const VolumeGrid& grid, F&& f) {
  auto voxels = std::make_shared<std::vector<float>>();
  for (std::int64_t z = 0; z < d[2]; ++z)
    for (std::int64_t y = 0; y < d[1]; ++y)
      for (std::int64_t x = 0; x < d[0]; ++x) voxels->push_back(f(x, y, z));
  return std::make_shared<const StructuredRegular<float>>(LinearLayout<float>(voxels->data(), d, voxels), grid);
}

}  // namespace

TEST_CASE("the isosurface of a linear field is its exact plane", "[isosurface][simd]") {
  // f = x + 2y + 3z in world units on a 20x20x20 grid of spacing 0.1: trilinear
  // interpolation reproduces it, so f = 3 is the plane x + 2y + 3z = 3 exactly.
  const VolumeGrid grid{{0.f, 0.f, 0.f}, {0.1f, 0.1f, 0.1f}, false};
  const auto volume = volume_of({20, 20, 20}, grid, [](auto x, auto y, auto z) {
    return 0.1f * static_cast<float>(x + 2 * y + 3 * z);
  });
  std::vector<Ray<float>> rays;
  for (std::size_t i = 0; i < 500; ++i) {
    const Vec3f target{1.9f * testing::hash_uniform(3 * i), 1.9f * testing::hash_uniform(3 * i + 1), 0.f};
    rays.push_back({target + Vec3f{0.f, 0.f, -3.f}, {0.f, 0.f, 1.f}});
  }
  for (auto isa : supported_isas()) {
    INFO(simd::isa_name(isa));
    const auto got = trace_geometry(isa, Isosurface(volume, {3.f}), rays);
    for (std::size_t i = 0; i < rays.size(); ++i) {
      const Vec3f o = rays[i].org;
      const float z = (3.f - o.x - 2.f * o.y) / 3.f;  // where the ray meets the plane
      if (z < 0.f || z > 1.9f) {
        CHECK(got[i].prim_id == -1);
        continue;
      }
      REQUIRE(got[i].prim_id >= 0);
      CHECK(got[i].t == Approx(z + 3.f).margin(1e-5));
    }
  }
}

TEST_CASE("a shell thinner than a sampling step is found exactly and missed by sampling", "[isosurface][stability]") {
  // One voxel of value 1 in a field of 0: where the interpolant exceeds 0.5 is a small
  // blob inside the 8 cells around it (at most half a cell from the voxel along an axis).
  const VolumeGrid grid;
  const auto volume = volume_of({9, 9, 9}, grid, [](auto x, auto y, auto z) { return x == 4 && y == 4 && z == 4 ? 1.f : 0.f; });
  std::vector<Ray<float>> rays;
  for (int j = 0; j < 24; ++j)
    for (int i = 0; i < 24; ++i)  // parallel rays over the blob, offset from the voxel grid
      rays.push_back({{3.52f + i * 0.04f, 3.53f + j * 0.04f, -2.3f}, {0.f, 0.f, 1.f}});
  const auto exact = trace_geometry(shim::select_isa(), Isosurface(volume, {0.5f}), rays);
  std::size_t crossing = 0, found = 0, sampled = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    // Whether the ray really crosses 0.5: the maximum along it, finely sampled.
    float peak = 0.f;
    for (float t = 0.f; t < 12.f; t += 1e-3f) peak = std::max(peak, volume->sample<simd::scalar>(rays[i].org + rays[i].dir * t));
    if (peak <= 0.5f) {
      CHECK(exact[i].prim_id == -1);
      continue;
    }
    ++crossing;
    if (exact[i].prim_id >= 0) {
      ++found;
      // The hit lies on the surface.
      CHECK(volume->sample<simd::scalar>(rays[i].org + rays[i].dir * exact[i].t) == Approx(0.5f).margin(1e-4));
    }
    // Sampling at one sample per cell (volumeSamplingRate 1) where the ray marcher puts
    // them, in the middle of each step from where the ray enters the grid (z = 0).
    bool above = false;
    for (float t = 2.8f; t < 11.3f; t += 1.f) above = above || volume->sample<simd::scalar>(rays[i].org + rays[i].dir * t) > 0.5f;
    sampled += above;
  }
  INFO(crossing << " rays cross the shell; exact finds " << found << ", sampling at one sample a cell " << sampled);
  REQUIRE(crossing > 50);
  CHECK(found == crossing);
  CHECK(sampled < crossing / 2);
}

TEST_CASE("several isovalues: the nearest surface wins", "[isosurface]") {
  // f = distance from the centre, in voxels: nested spheres for isovalues 3 and 6.
  const auto volume = volume_of({21, 21, 21}, VolumeGrid{}, [](auto x, auto y, auto z) {
    return std::sqrt(static_cast<float>((x - 10) * (x - 10) + (y - 10) * (y - 10) + (z - 10) * (z - 10)));
  });
  const std::vector<Ray<float>> rays{{{10.f, 10.f, -5.f}, {0.f, 0.f, 1.f}}, {{10.f, 14.5f, -5.f}, {0.f, 0.f, 1.f}}};
  const auto got = trace_geometry(shim::select_isa(), Isosurface(volume, {3.f, 6.f}), rays);
  CHECK(got[0].t == Approx(5.f + 4.f).margin(0.05));   // the outer sphere, radius 6, at z = 4
  CHECK(got[1].t == Approx(5.f + 10.f - std::sqrt(36.f - 4.5f * 4.5f)).margin(0.1));
  CHECK_THROWS_WITH(Isosurface(volume, {}), Catch::Contains("'isovalue' is missing"));
  CHECK_THROWS_WITH(Isosurface(volume, {std::nanf("")}), Catch::Contains("'isovalue' 0 is not finite"));
}

TEST_CASE("a colour per isovalue shows on that isovalue's shell", "[isosurface][render]") {
  // Nested spheres of radius 3 and 6 about the centre of a 21³ distance field, seen along
  // +z through their centre under a white ambient light of 1 (no material): the pixels
  // show the colour of the shell they hit, exactly.
  const auto volume = volume_of({21, 21, 21}, VolumeGrid{}, [](auto x, auto y, auto z) {
    return std::sqrt(static_cast<float>((x - 10) * (x - 10) + (y - 10) * (y - 10) + (z - 10) * (z - 10)));
  });
  const Vec3f red{1.f, 0.f, 0.f}, blue{0.f, 0.f, 1.f};
  const auto centre_colour = [&](std::vector<float> isovalues, std::vector<float> rgba) {
    accel::Device device;
    shim::EngineWorld world(device);
    Isosurface shells(volume, std::move(isovalues));
    shells.set_colors(std::move(rgba));
    world.add(std::move(shells));
    const auto& kernels = shim::kernels(shim::select_isa());
    kernels.commit(world);
    OrthographicCamera camera;
    camera.position = {10.f, 10.f, -5.f};
    camera.direction = {0.f, 0.f, 1.f};
    camera.height = 1.f;
    SciVisParams params;
    params.lights = {AmbientLight{}};
    FrameBuffer fb(4, 4, ColorFormat::rgba32f);
    kernels.render_scivis(world, params, camera, fb, nullptr);
    const float* p = fb.color32f().data() + 4 * (4 * 2 + 2);
    return Vec3f{p[0], p[1], p[2]};
  };
  // The outer shell (isovalue 6) is hit first, whichever index it has.
  CHECK(centre_colour({3.f, 6.f}, {1, 0, 0, 1, 0, 0, 1, 1}) == blue);
  CHECK(centre_colour({6.f, 3.f}, {1, 0, 0, 1, 0, 0, 1, 1}) == red);
  // A transparent outer shell lets the inner one's colour through.
  CHECK(centre_colour({3.f, 6.f}, {1, 0, 0, 1, 0, 0, 1, 0}) == red);
  CHECK_THROWS_WITH(Isosurface(volume, {3.f, 6.f, 9.f}).set_colors({1, 0, 0, 1, 0, 0, 1, 1}),
                    Catch::Contains("2 colours for 3 isovalues"));
}
