#pragma once
// Lattices of n³ cubes cut into unstructured cells, with a field's values at the vertices:
// the unstructured volumes of the tests and benchmarks.
#include <cstdint>
#include <vector>

#include "sciray/math/vec.hpp"
#include "sciray/volume/unstructured.hpp"

namespace sciray::testing {

/// n³ cubes between the lattice points position(x, y, z) (integers 0..n each), each cut
/// into cells of `type` over its corners in VTK's hexahedron order: 1 hexahedron, 2 wedges,
/// 3 pyramids (apex at corner 6) or 6 tetrahedra (around the diagonal 0-6); field(p) at
/// every vertex p.
template <class Position, class Field>
UnstructuredData cell_lattice(CellType type, int n, Position&& position, Field&& field) {
  UnstructuredData d;
  const auto at = [n](int x, int y, int z) { return static_cast<std::uint64_t>((z * (n + 1) + y) * (n + 1) + x); };
  for (int z = 0; z <= n; ++z)
    for (int y = 0; y <= n; ++y)
      for (int x = 0; x <= n; ++x) {
        d.positions.push_back(position(x, y, z));
        d.vertex_values.push_back(field(d.positions.back()));
      }
  std::vector<std::vector<int>> cuts;
  switch (type) {
    case CellType::hexahedron: cuts = {{0, 1, 2, 3, 4, 5, 6, 7}}; break;
    case CellType::wedge: cuts = {{0, 1, 3, 4, 5, 7}, {1, 2, 3, 5, 6, 7}}; break;
    case CellType::pyramid: cuts = {{0, 1, 5, 4, 6}, {0, 4, 7, 3, 6}, {0, 3, 2, 1, 6}}; break;
    case CellType::tetrahedron: cuts = {{0, 1, 2, 6}, {0, 2, 3, 6}, {0, 3, 7, 6}, {0, 7, 4, 6}, {0, 4, 5, 6}, {0, 5, 1, 6}}; break;
  }
  for (int z = 0; z < n; ++z)
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) {
        const std::uint64_t corner[8] = {at(x, y, z),     at(x + 1, y, z),     at(x + 1, y + 1, z),     at(x, y + 1, z),
                                         at(x, y, z + 1), at(x + 1, y, z + 1), at(x + 1, y + 1, z + 1), at(x, y + 1, z + 1)};
        for (const auto& cut : cuts) {
          d.cell_index.push_back(d.index.size());
          d.cell_type.push_back(static_cast<std::uint8_t>(type));
          for (int k : cut) d.index.push_back(corner[k]);
        }
      }
  return d;
}

/// n³ unit cubes (corners at integer points), each cut into 6 tetrahedra around its diagonal.
template <class Field>
UnstructuredData tetrahedral_lattice(int n, Field&& field) {
  const auto integer_point = [](int x, int y, int z) {
    return Vec3f{static_cast<float>(x), static_cast<float>(y), static_cast<float>(z)};
  };
  return cell_lattice(CellType::tetrahedron, n, integer_point, field);
}

}  // namespace sciray::testing
