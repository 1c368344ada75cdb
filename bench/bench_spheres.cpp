// Spheres and curves: whole scivis frames (1024², 2 threads' CPU time) of random spheres
// with sciray's own packet intersector against Embree's native point geometry, per ISA,
// in the same run; and the ABC-flow streamlines. The figure of merit is the ratio
// own / native (bench/ratio.py --baseline native).
#include <memory>
#include <tuple>

#include <benchmark/benchmark.h>

#include "sciray/shim/engine.hpp"
#include "sciray/testing/scenes.hpp"

namespace {

constexpr int image_size = 1024;

struct Scene {
  sciray::accel::Device device;
  sciray::shim::EngineWorld world{device};
  sciray::PerspectiveCamera camera;
};

using Key = std::tuple<std::size_t, sciray::SphereIntersector, sciray::simd::Isa>;

/// The spheres scene for one (count, intersector, ISA): the own intersector's callbacks
/// are compiled per ISA, so each ISA commits its own world. One scene is kept at a time
/// (10M spheres take over 1 GB) and benchmarks are registered grouped by key.
const Scene& spheres(const Key& key) {
  static Key cached_key;
  static std::unique_ptr<Scene> cached;
  if (!cached || cached_key != key) {
    cached.reset();
    cached = std::make_unique<Scene>();
    const auto [count, intersector, isa] = key;
    cached->world.add(sciray::Spheres(sciray::testing::random_spheres(count)).set_intersector(intersector));
    sciray::shim::kernels(isa).commit(cached->world);
    cached->camera = sciray::frame_bounds(cached->world.bounds(), 1.f);
    cached_key = key;
  }
  return *cached;
}

void render(benchmark::State& state, const Scene& scene, sciray::simd::Isa isa) {
  const auto& kernels = sciray::shim::kernels(isa);
  sciray::FrameBuffer fb(image_size, image_size, sciray::ColorFormat::srgba, sciray::channel_color);
  for (auto _ : state) kernels.render_scivis(scene.world, sciray::SciVisParams{}, scene.camera, fb, nullptr);
  state.SetItemsProcessed(state.iterations() * image_size * image_size);
}

void spheres_frame(benchmark::State& state, Key key) {
  const Scene& scene = spheres(key);
  render(state, scene, std::get<2>(key));
  state.counters["bytes_per_primitive"] =
      static_cast<double>(scene.world.memory_bytes()) / static_cast<double>(std::get<0>(key));
}

void streamlines_frame(benchmark::State& state, sciray::simd::Isa isa) {
  static const std::unique_ptr<Scene> scene = [] {
    auto s = std::make_unique<Scene>();
    s->world.add(sciray::Curves(sciray::testing::streamlines(2'000, 500)));
    s->world.commit();
    s->camera = sciray::frame_bounds(s->world.bounds(), 1.f);
    return s;
  }();
  render(state, *scene, isa);
  state.counters["bytes_per_primitive"] = static_cast<double>(scene->world.memory_bytes()) / (2'000.0 * 499);
}

const bool registered = [] {
  using sciray::SphereIntersector;
  for (const auto& [count, name] : {std::pair{std::size_t{1'000'000}, "spheres_1M"}, {10'000'000, "spheres_10M"}})
    for (auto isa : sciray::simd::all_isas) {
      if (!sciray::simd::cpu_supports(isa)) continue;
      for (auto intersector : {SphereIntersector::embree, SphereIntersector::sciray})
        benchmark::RegisterBenchmark(("frame/spheres/" + std::string(sciray::simd::isa_name(isa)) + "/" +
                                      (intersector == SphereIntersector::sciray ? "own" : "native") + "/" + name)
                                         .c_str(),
                                     spheres_frame, Key{count, intersector, isa})
            ->Unit(benchmark::kMillisecond)
            ->MeasureProcessCPUTime();
    }
  for (auto isa : sciray::simd::all_isas)
    if (sciray::simd::cpu_supports(isa))
      benchmark::RegisterBenchmark(("frame/curves/" + std::string(sciray::simd::isa_name(isa)) + "/streamlines_1M")
                                       .c_str(),
                                   streamlines_frame, isa)
          ->Unit(benchmark::kMillisecond)
          ->MeasureProcessCPUTime();
  return true;
}();

}  // namespace
