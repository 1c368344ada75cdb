#pragma once
// Cutting a structured regular volume into bricks for data-parallel rendering, each brick
// with the region of the world it is responsible for and ghost voxels around it, so that
// sampling inside its region gives what the whole volume gives there.
//
// The voxels are partitioned: along each axis, brick i owns voxels [a_i, a_(i+1)). Its
// region is the part of the world nearer its own voxels than any other brick's: in voxel
// coordinates (voxel v at v, which for cell-centred data sits half a spacing inside its
// cell) [a_i − ½, a_(i+1) − ½], and the volume's own bounds on outer faces. Trilinear
// filtering at a point of that region reads the voxels on either side of it, which reach
// one voxel past the owned ones on each inner face: one ghost layer makes the brick's
// samples there equal the whole volume's; without it a vertex-centred brick leaves a gap
// half a cell wide on each side of the border, and a cell-centred one clamps there.
// The cubic filter reads two voxels on each side: it needs two ghost layers.
#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "sciray/error.hpp"
#include "sciray/math/box.hpp"
#include "sciray/volume/structured_regular.hpp"

namespace sciray::distributed {

/// How many bricks along x, y and z.
using BrickGrid = std::array<int, 3>;

/// One brick of a split volume.
template <VoxelType Voxel>
struct VolumeBrick {
  std::array<int, 3> index{};  ///< position in the brick grid
  VolumeDims dims{};           ///< voxels, ghost layers included, x fastest
  VolumeGrid grid;             ///< the whole volume's spacing and centring; origin of its first voxel
  /// The part of the world the brick is responsible for (no ghosts): a data-parallel
  /// world's `region`. Neighbours' regions share faces exactly; together they are the
  /// whole volume's bounds.
  Box3f region;
  std::shared_ptr<std::vector<Voxel>> voxels;

  /// The brick as a volume of the engine (sharing its voxels).
  std::shared_ptr<const StructuredRegular<Voxel>> volume(VolumeFilter filter = VolumeFilter::linear) const {
    return std::make_shared<const StructuredRegular<Voxel>>(LinearLayout<Voxel>(voxels->data(), dims, voxels), grid,
                                                            filter);
  }
};

/// The grid of bricks OSPRay's data-parallel tests give `count` ranks: count's smallest
/// factors dealt to x, y, z in turn (2: 2x1x1, 3: 3x1x1, 4: 2x2x1, 8: 2x2x2).
inline BrickGrid brick_grid(int count) {
  if (count < 1) throw Error("brick_grid: the count must be at least 1, got " + std::to_string(count));
  BrickGrid grid{1, 1, 1};
  int axis = 0;
  for (int f = 2; f * f <= count;) {
    if (count % f == 0) {
      grid[static_cast<std::size_t>(axis)] *= f, count /= f, axis = (axis + 1) % 3;
    } else {
      ++f;
    }
  }
  if (count > 1) grid[static_cast<std::size_t>(axis)] *= count;
  return grid;
}

/// `bounds` cut into the boxes of a grid, x fastest; neighbours share faces exactly.
inline std::vector<Box3f> split_box(const Box3f& bounds, const BrickGrid& grid) {
  for (int k = 0; k < 3; ++k)
    if (grid[static_cast<std::size_t>(k)] < 1)
      throw Error("split_box: the grid must have at least 1 box along each axis, got " + std::to_string(grid[0]) +
                  "x" + std::to_string(grid[1]) + "x" + std::to_string(grid[2]));
  std::array<std::vector<float>, 3> faces;
  for (int k = 0; k < 3; ++k) {
    const int n = grid[static_cast<std::size_t>(k)];
    for (int i = 0; i <= n; ++i)
      faces[static_cast<std::size_t>(k)].push_back(i == n ? bounds.upper[k]
                                                          : bounds.lower[k] + bounds.size()[k] * static_cast<float>(i) /
                                                                                  static_cast<float>(n));
  }
  std::vector<Box3f> boxes;
  for (int z = 0; z < grid[2]; ++z)
    for (int y = 0; y < grid[1]; ++y)
      for (int x = 0; x < grid[0]; ++x)
        boxes.push_back({{faces[0][x], faces[1][y], faces[2][z]}, {faces[0][x + 1], faces[1][y + 1], faces[2][z + 1]}});
  return boxes;
}

/// Cuts the volume of `voxels` (x fastest, `dims`, placed by `grid`) into `bricks`
/// (x fastest), each with `ghost_layers` voxels of its neighbours beyond every inner face
/// (1 for trilinear filtering, 2 for cubic; 0 only to see what ghosts are for).
template <VoxelType Voxel>
std::vector<VolumeBrick<Voxel>> split_volume(std::span<const Voxel> voxels, const VolumeDims& dims,
                                             const VolumeGrid& grid, const BrickGrid& bricks, int ghost_layers = 1) {
  const auto text = [](const auto& v) {
    return std::to_string(v[0]) + "x" + std::to_string(v[1]) + "x" + std::to_string(v[2]);
  };
  if (static_cast<std::int64_t>(voxels.size()) != dims[0] * dims[1] * dims[2])
    throw Error("split_volume: " + std::to_string(voxels.size()) + " voxels for dimensions " + text(dims));
  if (ghost_layers < 0) throw Error("split_volume: 'ghost_layers' must not be negative, got " + std::to_string(ghost_layers));
  for (int k = 0; k < 3; ++k) {
    const auto n = static_cast<std::int64_t>(bricks[static_cast<std::size_t>(k)]);
    // Each brick must remain a volume: at least 2 voxels along every axis.
    if (n < 1 || (dims[k] < 2 * n && n > 1) || dims[k] < 2)
      throw Error("split_volume: " + text(bricks) + " bricks of a " + text(dims) +
                  " volume: every brick needs at least 2 voxels of its own along each axis");
  }
  // Per axis: the first voxel each brick owns, and the faces between their regions (in
  // world units, computed once per face so that neighbours share them exactly).
  std::array<std::vector<std::int64_t>, 3> first;
  std::array<std::vector<float>, 3> faces;
  const float centring = grid.cell_centered ? 0.5f : 0.f;  // voxel v sits at origin + (v + centring)·spacing
  for (int k = 0; k < 3; ++k) {
    const auto n = static_cast<std::int64_t>(bricks[static_cast<std::size_t>(k)]);
    auto& a = first[static_cast<std::size_t>(k)];
    auto& f = faces[static_cast<std::size_t>(k)];
    for (std::int64_t i = 0; i <= n; ++i) a.push_back(i * dims[k] / n);
    const float outer_lower = grid.origin[k];
    const float outer_upper = grid.origin[k] + (static_cast<float>(dims[k]) - 1.f + 2.f * centring) * grid.spacing[k];
    for (std::int64_t i = 0; i <= n; ++i)
      f.push_back(i == 0   ? outer_lower
                  : i == n ? outer_upper
                           : grid.origin[k] + (static_cast<float>(a[i]) - 0.5f + centring) * grid.spacing[k]);
  }
  std::vector<VolumeBrick<Voxel>> out;
  for (int bz = 0; bz < bricks[2]; ++bz)
    for (int by = 0; by < bricks[1]; ++by)
      for (int bx = 0; bx < bricks[0]; ++bx) {
        const std::array<int, 3> b{bx, by, bz};
        VolumeBrick<Voxel> brick;
        brick.index = b;
        brick.grid = grid;
        std::array<std::int64_t, 3> lo{}, hi{};  // voxels copied: [lo, hi)
        std::array<float, 3> origin{}, lower{}, upper{};
        for (int k = 0; k < 3; ++k) {
          const auto i = static_cast<std::size_t>(b[static_cast<std::size_t>(k)]);
          const auto& a = first[static_cast<std::size_t>(k)];
          lo[k] = std::max<std::int64_t>(a[i] - ghost_layers, 0);
          hi[k] = std::min<std::int64_t>(a[i + 1] + ghost_layers, dims[k]);
          brick.dims[k] = hi[k] - lo[k];
          origin[k] = grid.origin[k] + static_cast<float>(lo[k]) * grid.spacing[k];
          lower[k] = faces[static_cast<std::size_t>(k)][i];
          upper[k] = faces[static_cast<std::size_t>(k)][i + 1];
        }
        brick.grid.origin = {origin[0], origin[1], origin[2]};
        brick.region = {{lower[0], lower[1], lower[2]}, {upper[0], upper[1], upper[2]}};
        brick.voxels = std::make_shared<std::vector<Voxel>>();
        brick.voxels->reserve(static_cast<std::size_t>(brick.dims[0] * brick.dims[1] * brick.dims[2]));
        for (std::int64_t z = lo[2]; z < hi[2]; ++z)
          for (std::int64_t y = lo[1]; y < hi[1]; ++y) {
            const auto row = voxels.begin() + (z * dims[1] + y) * dims[0];
            brick.voxels->insert(brick.voxels->end(), row + lo[0], row + hi[0]);
          }
        out.push_back(std::move(brick));
      }
  return out;
}

}  // namespace sciray::distributed
