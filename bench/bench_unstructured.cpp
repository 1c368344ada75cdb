// Unstructured volumes: whole scivis frames of a 1M-tetrahedron volume per ISA, against
// the same field resampled to a structured float grid of equal memory in the same run
// (bench/ratio.py prints the tetrahedra's speed as a multiple of the grid's).
//
// The volume: a lattice of 55³ cubes, each cut into 6 tetrahedra (998,250 cells), of the
// smooth field sin(0.3 x) + sin(0.4 y) cos(0.2 z) at the vertices; the grid samples the
// same field at the spacing that gives it the unstructured volume's bytes.
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "sciray/shim/engine.hpp"
#include "sciray/testing/scenes.hpp"
#include "sciray/testing/cell_lattice.hpp"

namespace {

constexpr int lattice = 55;

float field(const sciray::Vec3f& p) { return std::sin(0.3f * p.x) + std::sin(0.4f * p.y) * std::cos(0.2f * p.z); }

std::shared_ptr<const sciray::Unstructured> tetrahedra() {
  return std::make_shared<const sciray::Unstructured>(sciray::testing::tetrahedral_lattice(lattice, field));
}

/// Adds `model` to `world` (out of line: inlined into Scenes' constructor, g++ 12 warns
/// of an uninitialized MotionTransform that is not).
template <class Volume>
[[gnu::noinline]] void add_model(sciray::shim::EngineWorld& world, sciray::VolumetricModel<Volume> model) {
  world.add_volume(std::move(model));
}

/// The two worlds (unstructured, and the grid of equal memory), built once.
struct Scenes {
  sciray::accel::Device device;
  sciray::shim::EngineWorld unstructured{device}, grid{device};
  std::shared_ptr<std::vector<float>> voxels = std::make_shared<std::vector<float>>();
  std::size_t unstructured_bytes = 0, grid_side = 0;

  Scenes() {
    const auto volume = tetrahedra();
    unstructured_bytes = volume->owned_bytes();
    std::vector<sciray::Vec3f> colors;
    for (int i = 0; i < 8; ++i) colors.push_back(sciray::testing::colormap(i / 7.f));
    const sciray::TransferFunction tf(colors, {0.f, 0.2f, 1.f}, {-2.f, 2.f});
    const float density = 4.f / (std::sqrt(3.f) * lattice);
    add_model(unstructured, sciray::VolumetricModel(volume, tf, density));
    grid_side = static_cast<std::size_t>(std::cbrt(static_cast<double>(unstructured_bytes) / sizeof(float)));
    const float spacing = static_cast<float>(lattice) / static_cast<float>(grid_side - 1);
    for (std::size_t z = 0; z < grid_side; ++z)
      for (std::size_t y = 0; y < grid_side; ++y)
        for (std::size_t x = 0; x < grid_side; ++x)
          voxels->push_back(field(sciray::Vec3f{static_cast<float>(x), static_cast<float>(y), static_cast<float>(z)} * spacing));
    const auto n = static_cast<std::int64_t>(grid_side);
    sciray::VolumeGrid g;
    g.spacing = {spacing, spacing, spacing};
    add_model(grid, sciray::VolumetricModel(std::make_shared<const sciray::StructuredRegular<float>>(
                                                sciray::LinearLayout<float>(voxels->data(), {n, n, n}, voxels), g),
                                            tf, density));
  }
};

Scenes& scenes() {
  static Scenes s;
  return s;
}

void frame(benchmark::State& state, sciray::simd::Isa isa, bool unstructured, bool exact) {
  Scenes& s = scenes();
  sciray::shim::EngineWorld& world = unstructured ? s.unstructured : s.grid;
  const auto& kernels = sciray::shim::kernels(isa);
  kernels.commit(world);
  sciray::FrameBuffer fb(512, 512, sciray::ColorFormat::srgba, sciray::channel_color | sciray::channel_accum);
  const sciray::Camera camera = sciray::frame_bounds(world.bounds(), 1.f);
  sciray::SciVisParams params;
  params.volume_exact = exact;
  for (auto _ : state) kernels.render(world, params, camera, fb, nullptr, sciray::FrameSettings{});
  state.SetItemsProcessed(state.iterations() * 512 * 512);
  state.counters["volume_bytes"] = static_cast<double>(unstructured ? s.unstructured_bytes : s.voxels->size() * sizeof(float));
  if (unstructured) state.counters["bytes_per_cell"] = static_cast<double>(s.unstructured_bytes) / (6.0 * lattice * lattice * lattice);
}

const bool registered = [] {
  for (auto isa : sciray::simd::all_isas) {
    if (!sciray::simd::cpu_supports(isa)) continue;
    const std::string isa_name(sciray::simd::isa_name(isa));
    benchmark::RegisterBenchmark(("frame/unstructured/" + isa_name + "/tetrahedra_1M").c_str(), frame, isa, true, false)
        ->Unit(benchmark::kMillisecond)
        ->MeasureProcessCPUTime();
    benchmark::RegisterBenchmark(("frame/unstructured/" + isa_name + "/tetrahedra_1M_exact").c_str(), frame, isa, true,
                                 true)
        ->Unit(benchmark::kMillisecond)
        ->MeasureProcessCPUTime();
    benchmark::RegisterBenchmark(("frame/unstructured/" + isa_name + "/grid_of_equal_memory").c_str(), frame, isa, false,
                                 false)
        ->Unit(benchmark::kMillisecond)
        ->MeasureProcessCPUTime();
  }
  return true;
}();

}  // namespace
