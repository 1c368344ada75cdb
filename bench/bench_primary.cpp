// Primary-ray throughput: the engine's whole frame loop (camera packets, Embree packet
// traversal, scivis shading, frame buffer) per ISA, against a minimal raw-Embree loop on
// the same rays in the same run (4x4 stamps through rtcIntersect16, same TBB threads).
// The figure of merit is engine rays/s divided by raw-Embree rays/s (bench/ratio.py).
#include <map>
#include <memory>

#include <benchmark/benchmark.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "sciray/frame/render_frame.hpp"
#include "sciray/shim/engine.hpp"
#include "sciray/testing/scenes.hpp"

namespace {

constexpr int image_size = 1024;

struct Scene {
  sciray::accel::Device device;
  sciray::shim::EngineWorld world{device};
  sciray::PerspectiveCamera camera;
};

/// The torus of about `triangles` triangles, built once per process; `plain` drops its
/// vertex normals and colours (shading then uses the geometric normal).
const Scene& torus(std::size_t triangles, bool plain) {
  static std::map<std::pair<std::size_t, bool>, std::unique_ptr<Scene>> cache;
  auto& scene = cache[{triangles, plain}];
  if (!scene) {
    scene = std::make_unique<Scene>();
    sciray::MeshData mesh = sciray::testing::wavy_torus(triangles);
    if (plain) mesh.normals.clear(), mesh.vertex_colors.clear();
    scene->world.add(sciray::TriangleMesh(std::move(mesh)));
    scene->world.commit();
    scene->camera = sciray::frame_bounds(scene->world.bounds(), 1.f);
  }
  return *scene;
}

void engine_frame(benchmark::State& state, sciray::simd::Isa isa, std::size_t triangles, bool plain) {
  const Scene& scene = torus(triangles, plain);
  const auto& kernels = sciray::shim::kernels(isa);
  sciray::FrameBuffer fb(image_size, image_size, state.range(0) ? sciray::ColorFormat::srgba : sciray::ColorFormat::none,
                         state.range(0) ? sciray::channel_color : 0u);
  for (auto _ : state) kernels.render_scivis(scene.world, sciray::SciVisParams{}, scene.camera, fb, nullptr);
  state.SetItemsProcessed(state.iterations() * image_size * image_size);
}

void raw_embree_frame(benchmark::State& state, std::size_t triangles) {
  const Scene& scene = torus(triangles, true);
  const auto camera = sciray::prepare(scene.camera);
  std::vector<float> depth(static_cast<std::size_t>(image_size) * image_size);
  constexpr int tile = sciray::tile_size, tiles = image_size / tile;
  for (auto _ : state) {
    tbb::parallel_for(tbb::blocked_range<int>(0, tiles * tiles), [&](const tbb::blocked_range<int>& range) {
      RTCIntersectContext context;
      rtcInitIntersectContext(&context);
      context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
      alignas(64) int valid[16];
      std::fill_n(valid, 16, -1);
      for (int t = range.begin(); t != range.end(); ++t) {
        const int tx = (t % tiles) * tile, ty = (t / tiles) * tile;
        for (int y0 = ty; y0 < ty + tile; y0 += 4)
          for (int x0 = tx; x0 < tx + tile; x0 += 4) {
            RTCRayHit16 rh;
            for (int i = 0; i < 16; ++i) {
              const int x = x0 + i % 4, y = y0 + i / 4;
              const auto ray = camera.generate((x + 0.5f) / image_size, (y + 0.5f) / image_size);
              rh.ray.org_x[i] = ray.org.x, rh.ray.org_y[i] = ray.org.y, rh.ray.org_z[i] = ray.org.z;
              rh.ray.dir_x[i] = ray.dir.x, rh.ray.dir_y[i] = ray.dir.y, rh.ray.dir_z[i] = ray.dir.z;
              rh.ray.tnear[i] = 0.f, rh.ray.tfar[i] = std::numeric_limits<float>::infinity();
              rh.ray.time[i] = 0.f, rh.ray.mask[i] = ~0u, rh.ray.flags[i] = 0;
              rh.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
            }
            rtcIntersect16(valid, scene.world.scene(), &context, &rh);
            for (int i = 0; i < 16; ++i)
              depth[static_cast<std::size_t>(y0 + i / 4) * image_size + x0 + i % 4] = rh.ray.tfar[i];
          }
      }
    });
    benchmark::DoNotOptimize(depth.data());
  }
  state.SetItemsProcessed(state.iterations() * image_size * image_size);
}

const bool registered = [] {
  for (const auto& [triangles, name] : {std::pair{std::size_t{1'000'000}, "torus_1M"}, {5'000'000, "torus_5M"}}) {
    benchmark::RegisterBenchmark((std::string("frame/raw_embree/intersect16/") + name).c_str(), raw_embree_frame,
                                 triangles)
        ->Unit(benchmark::kMillisecond)
        ->MeasureProcessCPUTime();
    for (auto isa : sciray::simd::all_isas) {
      if (!sciray::simd::cpu_supports(isa)) continue;
      for (bool plain : {true, false})
        benchmark::RegisterBenchmark(("frame/scivis/" + std::string(sciray::simd::isa_name(isa)) + "/" + name +
                                      (plain ? "_plain" : "_normals_colors"))
                                         .c_str(),
                                     engine_frame, isa, triangles, plain)
            ->ArgName("color")
            ->Arg(0)
            ->Arg(1)
            ->Unit(benchmark::kMillisecond)
            ->MeasureProcessCPUTime();
    }
  }
  return true;
}();

}  // namespace
