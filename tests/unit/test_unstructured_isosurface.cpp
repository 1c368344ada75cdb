// Isosurfaces of unstructured volumes (geometry/isosurface_unstructured.hpp): exact
// crossings in every cell type, no cracks between distorted cells, smooth normals.
#include <catch2/catch.hpp>

#include <cmath>
#include <memory>
#include <vector>

#include "sciray/shim/engine.hpp"
#include "sciray/testing/cell_lattice.hpp"
#include "sciray/testing/scenes.hpp"
#include "support/isas.hpp"
#include "support/trace.hpp"

using namespace sciray;
using sciray::test_support::supported_isas;
using sciray::test_support::trace_geometry;

namespace {

/// [0, 1]³ cut into n³ cubes, each into cells of `type` (1 hexahedron, 2 wedges, 3 pyramids
/// or 6 tetrahedra, as tests/unit/test_unstructured.cpp cuts the unit cube), its inner
/// vertices moved by up to `jitter` of a cube (faces of hexahedra and wedges no longer
/// plane), values f = x + 2y + 3z at the vertices. Pyramids stay undistorted: a cube's
/// pyramids meet the next cube's on a quad one side and two triangles the other, which
/// only coincide while the quad is plane.
std::shared_ptr<const Unstructured> linear_mesh(CellType type, int n, float jitter) {
  const auto jittered = [&](int x, int y, int z) {
    Vec3f p{static_cast<float>(x) / n, static_cast<float>(y) / n, static_cast<float>(z) / n};
    if (type != CellType::pyramid && x > 0 && x < n && y > 0 && y < n && z > 0 && z < n) {
      const std::size_t h = 3 * static_cast<std::size_t>((z * (n + 1) + y) * (n + 1) + x);
      p = p + Vec3f{testing::hash_uniform(h) - 0.5f, testing::hash_uniform(h + 1) - 0.5f,
                    testing::hash_uniform(h + 2) - 0.5f} *
                  (2.f * jitter / static_cast<float>(n));
    }
    return p;
  };
  return std::make_shared<const Unstructured>(
      testing::cell_lattice(type, n, jittered, [](const Vec3f& p) { return p.x + 2 * p.y + 3 * p.z; }));
}

const CellType all_types[] = {CellType::tetrahedron, CellType::hexahedron, CellType::wedge, CellType::pyramid};

}  // namespace

TEST_CASE("the isosurface of a linear field on distorted cells is its exact plane, without cracks",
          "[isosurface][unstructured][simd]") {
  // Every cell type reproduces a linear field however its vertices lie, so f = 3 is the
  // plane x + 2y + 3z = 3: each ray up +z meets it at z = (3 − x − 2y) / 3. A ray lost at
  // a face two cells share would show as a miss.
  std::vector<Ray<float>> rays;
  for (std::size_t i = 0; i < 400; ++i) {
    const Vec3f target{0.02f + 0.96f * testing::hash_uniform(3 * i), 0.02f + 0.96f * testing::hash_uniform(3 * i + 1), 0.f};
    rays.push_back({target + Vec3f{0.f, 0.f, -3.f}, {0.f, 0.f, 1.f}});
  }
  for (const CellType type : all_types) {
    INFO("cell type " << static_cast<int>(type));
    const auto volume = linear_mesh(type, 4, 0.2f);
    for (auto isa : supported_isas()) {
      INFO(simd::isa_name(isa));
      const auto got = trace_geometry(isa, Isosurface(volume, {3.f}), rays);
      int misses = 0, wrong = 0;
      for (std::size_t i = 0; i < rays.size(); ++i) {
        const float z = (3.f - rays[i].org.x - 2.f * rays[i].org.y) / 3.f;
        if (z < 0.f || z > 1.f) continue;
        misses += got[i].prim_id < 0;
        wrong += got[i].prim_id >= 0 && std::abs(got[i].t - (z + 3.f)) > 2e-4f;
      }
      CHECK(misses == 0);
      CHECK(wrong == 0);
    }
  }
}

TEST_CASE("unstructured isosurface normals are the field's gradient, and every isovalue is found",
          "[isosurface][unstructured]") {
  const Vec3f gradient = normalize(Vec3f{1.f, 2.f, 3.f});
  for (const CellType type : all_types) {
    INFO("cell type " << static_cast<int>(type));
    const auto volume = linear_mesh(type, 3, 0.15f);
    const Isosurface surface(volume, {3.f, 1.5f});
    // The nearest crossing over all primitives, as Embree would report it.
    for (std::size_t i = 0; i < 50; ++i) {
      const Ray<float> ray{{0.1f + 0.8f * testing::hash_uniform(2 * i), 0.1f + 0.8f * testing::hash_uniform(2 * i + 1), -1.f},
                           {0.f, 0.f, 1.f}};
      PrimitiveHit<simd::scalar> best{false, INFINITY, {}};
      for (std::uint32_t p = 0; p < surface.primitive_count(); ++p)
        if (const auto h = surface.intersect_primitive<simd::scalar>(ray, p); h.hit && h.t < best.t) best = h;
      // f = 1.5 comes first along +z wherever it lies inside the cube.
      const float z15 = (1.5f - ray.org.x - 2.f * ray.org.y) / 3.f;
      const float z3 = (3.f - ray.org.x - 2.f * ray.org.y) / 3.f;
      const float expected = z15 >= 0.f ? z15 : z3;
      INFO("ray at " << ray.org.x << ", " << ray.org.y);
      REQUIRE(best.hit);
      CHECK(best.t == Approx(expected + 1.f).margin(2e-4));
      CHECK(best.u == (z15 >= 0.f ? 1.f : 0.f));
      CHECK(dot(normalize(best.ng), gradient) == Approx(1.f).margin(1e-4));
    }
  }
}

TEST_CASE("an unstructured isosurface with values per cell is refused", "[isosurface][unstructured][errors]") {
  UnstructuredData d;
  d.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  d.index = {0, 1, 2, 3};
  d.cell_index = {0};
  d.cell_type = {static_cast<std::uint8_t>(CellType::tetrahedron)};
  d.cell_values = {1.f};
  const auto volume = std::make_shared<const Unstructured>(std::move(d));
  REQUIRE_THROWS_WITH(Isosurface(volume, {0.5f}), Catch::Contains("'cell.data', constant in each cell"));
}
