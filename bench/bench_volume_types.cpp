// Samples per second of every volume type per ISA, the scalar path in the same run (bench/
// ratio.py prints each ISA's speed over it): the same 2^18 random positions in each
// volume's box, each type at a size its users meet.
//  - structuredRegular: 128³ float voxels (the grid's throughput, for scale);
//  - unstructured: a lattice of 30³ cubes, 6 tetrahedra each (162,000 cells);
//  - particle: 100,000 Gaussians of radius 0.01 in the unit cube (support 3 radii);
//  - structuredSpherical: 64 radii × 64 inclinations × 128 azimuths;
//  - vdb: the dense 8³ leaves of every other 8³ block of a 256³ domain (half of it);
//  - amr: a 64³ level-0 block with a 64³ level-1 block refining its middle.
// Each samples the smooth field sin(0.3 x) + sin(0.4 y) cos(0.2 z) of its own coordinates.
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "sciray/shim/engine.hpp"
#include "sciray/testing/scenes.hpp"
#include "sciray/testing/cell_lattice.hpp"

namespace {

float field(float x, float y, float z) { return std::sin(0.3f * x) + std::sin(0.4f * y) * std::cos(0.2f * z); }

std::shared_ptr<const sciray::StructuredRegular<float>> grid() {
  constexpr std::int64_t n = 128;
  auto voxels = std::make_shared<std::vector<float>>();
  for (std::int64_t z = 0; z < n; ++z)
    for (std::int64_t y = 0; y < n; ++y)
      for (std::int64_t x = 0; x < n; ++x) voxels->push_back(field(x, y, z));
  return std::make_shared<const sciray::StructuredRegular<float>>(
      sciray::LinearLayout<float>(voxels->data(), {n, n, n}, voxels), sciray::VolumeGrid{});
}

std::shared_ptr<const sciray::Unstructured> tetrahedra() {
  return std::make_shared<const sciray::Unstructured>(
      sciray::testing::tetrahedral_lattice(30, [](const sciray::Vec3f& p) { return field(p.x, p.y, p.z); }));
}

std::shared_ptr<const sciray::Particles> particles() {
  sciray::ParticleData d;
  for (std::uint64_t i = 0; i < 100000; ++i) {
    const sciray::Vec3f p{sciray::testing::hash_uniform(3 * i), sciray::testing::hash_uniform(3 * i + 1),
                          sciray::testing::hash_uniform(3 * i + 2)};
    d.positions.push_back(p);
    d.radii.push_back(0.01f);
    d.weights.push_back(field(30.f * p.x, 30.f * p.y, 30.f * p.z));
  }
  return std::make_shared<const sciray::Particles>(std::move(d));
}

std::shared_ptr<const sciray::StructuredSpherical> spherical() {
  sciray::StructuredSphericalData d;
  d.dimensions = {64, 64, 128};
  d.grid_origin = {1.f, 0.f, 0.f};
  d.grid_spacing = {1.f / 63.f, 180.f / 63.f, 360.f / 127.f};
  for (std::int64_t k = 0; k < 128; ++k)
    for (std::int64_t j = 0; j < 64; ++j)
      for (std::int64_t i = 0; i < 64; ++i) d.values.push_back(field(i, j, k));
  return std::make_shared<const sciray::StructuredSpherical>(std::move(d));
}

std::shared_ptr<const sciray::Vdb> vdb() {
  sciray::VdbData d;
  for (int bz = 0; bz < 32; ++bz)
    for (int by = 0; by < 32; ++by)
      for (int bx = 0; bx < 32; ++bx) {
        if ((bx + by + bz) % 2) continue;
        d.level.push_back(3);
        d.origin.push_back({8 * bx, 8 * by, 8 * bz});
        std::vector<float> leaf;
        for (int x = 0; x < 8; ++x)  // z fastest
          for (int y = 0; y < 8; ++y)
            for (int z = 0; z < 8; ++z) leaf.push_back(field(8 * bx + x, 8 * by + y, 8 * bz + z));
        d.data.push_back(std::move(leaf));
      }
  return std::make_shared<const sciray::Vdb>(std::move(d));
}

std::shared_ptr<const sciray::Amr> amr() {
  sciray::AmrData d;
  d.cell_width = {1.f, 0.5f};
  d.block_bounds = {{{0, 0, 0}, {63, 63, 63}}, {{32, 32, 32}, {95, 95, 95}}};
  d.block_level = {0, 1};
  for (int level = 0; level < 2; ++level) {
    const auto& b = d.block_bounds[static_cast<std::size_t>(level)];
    const float w = d.cell_width[static_cast<std::size_t>(level)];
    std::vector<float> cells;
    for (int z = b.lower[2]; z <= b.upper[2]; ++z)
      for (int y = b.lower[1]; y <= b.upper[1]; ++y)
        for (int x = b.lower[0]; x <= b.upper[0]; ++x) cells.push_back(field((x + 0.5f) * w, (y + 0.5f) * w, (z + 0.5f) * w));
    d.block_data.push_back(std::move(cells));
  }
  return std::make_shared<const sciray::Amr>(std::move(d));
}

/// 2^18 random positions in `box`.
std::vector<sciray::Vec3f> positions_in(const sciray::Box3f& box) {
  std::vector<sciray::Vec3f> out;
  for (std::uint64_t i = 0; i < 1 << 18; ++i)
    out.push_back(box.lower + sciray::Vec3f{sciray::testing::hash_uniform(3 * i), sciray::testing::hash_uniform(3 * i + 1),
                                            sciray::testing::hash_uniform(3 * i + 2)} *
                                  (box.upper - box.lower));
  return out;
}

/// Samples of `volume` through `kernel` (an ISA's sample entry for its type), per second.
template <class Volume, class Kernel>
void samples(benchmark::State& state, std::shared_ptr<const Volume> (*make)(), Kernel kernel) {
  static const std::shared_ptr<const Volume> volume = make();
  static const std::vector<sciray::Vec3f> positions = positions_in(volume->bounds());
  std::vector<float> out(positions.size());
  for (auto _ : state) {
    kernel(*volume, positions, out);
    benchmark::DoNotOptimize(out.data());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(positions.size()));
}

const bool registered = [] {
  for (auto isa : sciray::simd::all_isas) {
    if (!sciray::simd::cpu_supports(isa)) continue;
    const auto& k = sciray::shim::kernels(isa);
    const std::string suffix = "/" + std::string(sciray::simd::isa_name(isa));
    const auto add = [&](const std::string& type, auto make, auto kernel) {
      benchmark::RegisterBenchmark(("samples/" + type + suffix).c_str(),
                                   [make, kernel](benchmark::State& s) { samples(s, make, kernel); })
          ->Unit(benchmark::kMillisecond)
          ->MeasureProcessCPUTime();
    };
    add("structuredRegular", &grid, k.sample_volume);
    add("unstructured", &tetrahedra, k.sample_unstructured);
    add("particle", &particles, k.sample_particles);
    add("structuredSpherical", &spherical, k.sample_spherical);
    add("vdb", &vdb, k.sample_vdb);
    add("amr", &amr, k.sample_amr);
  }
  return true;
}();

}  // namespace
