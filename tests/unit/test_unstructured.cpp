// Unstructured volumes (volume/unstructured.hpp): exact interpolation in every cell type,
// point location through the hierarchy, the background outside, bad cells named.
#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "sciray/testing/cell_lattice.hpp"
#include "sciray/volume/unstructured.hpp"

using namespace sciray;

namespace {

/// The unit cube's corners in VTK's hexahedron order.
const std::vector<Vec3f> cube = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};

/// The unit cube cut into cells of one type: 1 hexahedron, 2 wedges, 3 pyramids (apex at
/// corner 6) or 6 tetrahedra (around the diagonal 0-6), values f at the vertices.
UnstructuredData cube_of(CellType type, float (*f)(const Vec3f&)) {
  UnstructuredData d;
  d.positions = cube;
  for (const Vec3f& p : cube) d.vertex_values.push_back(f(p));
  std::vector<std::vector<std::uint64_t>> cells;
  switch (type) {
    case CellType::hexahedron: cells = {{0, 1, 2, 3, 4, 5, 6, 7}}; break;
    case CellType::wedge: cells = {{0, 1, 3, 4, 5, 7}, {1, 2, 3, 5, 6, 7}}; break;
    case CellType::pyramid: cells = {{0, 1, 5, 4, 6}, {0, 4, 7, 3, 6}, {0, 3, 2, 1, 6}}; break;
    case CellType::tetrahedron:
      cells = {{0, 1, 2, 6}, {0, 2, 3, 6}, {0, 3, 7, 6}, {0, 7, 4, 6}, {0, 4, 5, 6}, {0, 5, 1, 6}};
      break;
  }
  for (const auto& c : cells) {
    d.cell_index.push_back(d.index.size());
    d.cell_type.push_back(static_cast<std::uint8_t>(type));
    d.index.insert(d.index.end(), c.begin(), c.end());
  }
  return d;
}

float linear(const Vec3f& p) { return 1.f + 2.f * p.x + 3.f * p.y + 4.f * p.z; }
float trilinear(const Vec3f& p) { return linear(p) + 5.f * p.x * p.y * p.z; }

/// The largest error of `volume` against f over a 9^3 lattice inside the unit cube.
double worst_error(const Unstructured& volume, float (*f)(const Vec3f&)) {
  double worst = 0;
  for (int i = 0; i < 9 * 9 * 9; ++i) {
    const Vec3f p{(i % 9 + 0.5f) / 9.f, (i / 9 % 9 + 0.5f) / 9.f, (i / 81 + 0.5f) / 9.f};
    worst = std::max(worst, static_cast<double>(std::abs(volume.sample(p) - f(p))));
  }
  return worst;
}

}  // namespace

TEST_CASE("unstructured: every cell type interpolates a linear field exactly", "[volume][unstructured]") {
  for (CellType type : {CellType::tetrahedron, CellType::hexahedron, CellType::wedge, CellType::pyramid}) {
    INFO("cell type " << static_cast<int>(type));
    const Unstructured volume(cube_of(type, linear));
    CHECK(worst_error(volume, linear) < 2e-5);  // values up to 10: float rounding
    CHECK(volume.value_range() == std::array<float, 2>{1.f, 10.f});
  }
}

TEST_CASE("unstructured: a hexahedron interpolates trilinearly, also with faces that are not planar",
          "[volume][unstructured]") {
  const Unstructured box(cube_of(CellType::hexahedron, trilinear));
  CHECK(worst_error(box, trilinear) < 2e-5);
  // Shear the cube by x' = x + 0.3 y z (its faces x = const twist): the value at the image
  // of p is still trilinear(p), found by inverting the map.
  UnstructuredData sheared = cube_of(CellType::hexahedron, trilinear);
  for (Vec3f& p : sheared.positions) p.x += 0.3f * p.y * p.z;
  const Unstructured twisted(std::move(sheared));
  for (const Vec3f p : {Vec3f{0.3f, 0.4f, 0.5f}, Vec3f{0.9f, 0.8f, 0.95f}, Vec3f{0.05f, 0.9f, 0.1f}})
    CHECK(twisted.sample({p.x + 0.3f * p.y * p.z, p.y, p.z}) == Approx(trilinear(p)).epsilon(1e-5));
}

TEST_CASE("unstructured: outside every cell a sample is the background, cell values are constant per cell",
          "[volume][unstructured]") {
  UnstructuredData d = cube_of(CellType::tetrahedron, linear);
  const Unstructured nan_outside(d);
  CHECK(std::isnan(nan_outside.sample({1.5f, 0.5f, 0.5f})));
  CHECK(std::isnan(nan_outside.sample({0.5f, 0.5f, -0.01f})));
  d.background = -1.f;
  CHECK(Unstructured(d).sample({1.5f, 0.5f, 0.5f}) == -1.f);
  d.vertex_values.clear();
  d.cell_values = {1, 2, 3, 4, 5, 6};
  const Unstructured per_cell(d);
  // (0.9, 0.2, 0.1) lies in the first tetrahedron (0, 1, 2, 6): x is the largest coordinate, then y.
  CHECK(per_cell.sample({0.9f, 0.2f, 0.1f}) == 1.f);
  CHECK(per_cell.value_range() == std::array<float, 2>{1.f, 6.f});
}

TEST_CASE("unstructured: many cells are found through the hierarchy", "[volume][unstructured]") {
  // A 12^3 lattice of unit cubes, each as 6 tetrahedra: 10,368 cells of a linear field.
  constexpr int n = 12;
  UnstructuredData d = testing::tetrahedral_lattice(n, [](const Vec3f& p) { return linear(p * (1.f / n)); });
  const Unstructured volume(std::move(d));
  CHECK(volume.cell_count() == 6 * n * n * n);
  CHECK(volume.cell_size().x == 1.f);
  double worst = 0;
  for (int i = 0; i < 2000; ++i) {
    const Vec3f p{std::fmod(i * 0.6180339f, 1.f) * n, std::fmod(i * 0.4142135f, 1.f) * n, std::fmod(i * 0.7320508f, 1.f) * n};
    worst = std::max(worst, static_cast<double>(std::abs(volume.sample(p) - linear(p * (1.f / n)))));
  }
  CHECK(worst < 2e-5);
}

TEST_CASE("unstructured: bad cells are named", "[volume][unstructured][errors]") {
  const auto error_of = [](UnstructuredData d) {
    try {
      Unstructured v(std::move(d));
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const UnstructuredData good = cube_of(CellType::tetrahedron, linear);
  UnstructuredData d = good;
  d.index[5] = 99;
  CHECK(error_of(d) == "unstructured volume: cell 1 refers to vertex 99 but 'vertex.position' has 8");
  d = good;
  d.cell_type[2] = 11;
  CHECK(error_of(d) == "unstructured volume: cell 2 has type 11, which is none of tetrahedron (10), hexahedron (12), "
                       "wedge (13), pyramid (14)");
  d = good;
  d.cell_index[5] = 22;
  CHECK(error_of(d) == "unstructured volume: cell 5 starts at 'index' entry 22 and needs 4 vertices, but 'index' has "
                       "24 entries");
  d = good;
  d.positions[3] = d.positions[0];  // cells 1 and 2 collapse
  CHECK(error_of(d) == "unstructured volume: cell 1 is degenerate (its vertices span no volume)");
  d = cube_of(CellType::hexahedron, linear);
  for (std::uint64_t& i : d.index) i = 0;
  CHECK(error_of(d) == "unstructured volume: cell 0 is degenerate (its vertices span no volume)");
  // A bow tie (the top face folds over itself, as crushed elements do) is kept, and counted.
  d = cube_of(CellType::hexahedron, linear);
  std::swap(d.index[6], d.index[7]);
  CHECK(Unstructured(d).folded_cells() == 1);
  CHECK(Unstructured(cube_of(CellType::hexahedron, linear)).folded_cells() == 0);
  d = good;
  d.vertex_values[4] = std::nanf("");
  CHECK(error_of(d) == "unstructured volume: 'vertex.data' 4 is not finite");
  d = good;
  d.cell_values = {1.f};
  CHECK(error_of(d) == "unstructured volume: exactly one of 'vertex.data' and 'cell.data' must be given");
  d = good;
  d.cell_type.pop_back();
  CHECK(error_of(d) == "unstructured volume: 'cell.type' has 5 entries but 'cell.index' has 6 cells");
}
