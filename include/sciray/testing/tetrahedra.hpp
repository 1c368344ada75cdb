#pragma once
// A lattice of n³ unit cubes, each cut into 6 tetrahedra around its diagonal, with a
// field's values at the vertices: the unstructured volume of the benchmarks.
#include <cstdint>

#include "sciray/math/vec.hpp"
#include "sciray/volume/unstructured.hpp"

namespace sciray::testing {

template <class Field>
UnstructuredData tetrahedral_lattice(int n, Field&& field) {
  UnstructuredData d;
  const auto at = [n](int x, int y, int z) { return static_cast<std::uint64_t>((z * (n + 1) + y) * (n + 1) + x); };
  for (int z = 0; z <= n; ++z)
    for (int y = 0; y <= n; ++y)
      for (int x = 0; x <= n; ++x) {
        d.positions.push_back({static_cast<float>(x), static_cast<float>(y), static_cast<float>(z)});
        d.vertex_values.push_back(field(d.positions.back()));
      }
  const int tets[6][4] = {{0, 1, 2, 6}, {0, 2, 3, 6}, {0, 3, 7, 6}, {0, 7, 4, 6}, {0, 4, 5, 6}, {0, 5, 1, 6}};
  for (int z = 0; z < n; ++z)
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) {
        const std::uint64_t corner[8] = {at(x, y, z),     at(x + 1, y, z),     at(x + 1, y + 1, z),     at(x, y + 1, z),
                                         at(x, y, z + 1), at(x + 1, y, z + 1), at(x + 1, y + 1, z + 1), at(x, y + 1, z + 1)};
        for (const auto& t : tets) {
          d.cell_index.push_back(d.index.size());
          d.cell_type.push_back(static_cast<std::uint8_t>(CellType::tetrahedron));
          for (int v : t) d.index.push_back(corner[v]);
        }
      }
  return d;
}

}  // namespace sciray::testing
