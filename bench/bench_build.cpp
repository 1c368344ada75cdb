// BVH build of a triangle mesh: the engine's commit (validation, Embree geometry over the
// mesh's arrays, scene build) against raw Embree building the same arrays with the same
// scene flags in the same run. Wall time (the build runs on TBB's threads).
// The figure of merit is the raw build's time over the engine's (bench/ratio.py).
#include <map>
#include <memory>

#include <benchmark/benchmark.h>
#include <embree3/rtcore.h>

#include "sciray/shim/engine.hpp"
#include "sciray/testing/scenes.hpp"

namespace {

/// The plain torus of about `triangles` triangles, generated once per process.
const sciray::MeshData& torus(std::size_t triangles) {
  static std::map<std::size_t, std::unique_ptr<sciray::MeshData>> cache;
  auto& mesh = cache[triangles];
  if (!mesh) {
    mesh = std::make_unique<sciray::MeshData>(sciray::testing::wavy_torus(triangles));
    mesh->normals.clear(), mesh->vertex_colors.clear();
  }
  return *mesh;
}

void engine_build(benchmark::State& state, std::size_t triangles) {
  const sciray::MeshData& mesh = torus(triangles);
  sciray::accel::Device device;
  for (auto _ : state) {
    sciray::shim::EngineWorld world(device);
    sciray::TriangleMesh::SharedArrays arrays;  // the mesh read in place, as the raw build reads it
    arrays.positions = {mesh.positions.data(), mesh.vertex_count(), 3 * sizeof(float)};
    arrays.indices = {mesh.indices.data(), mesh.face_count(), 3 * sizeof(std::uint32_t)};
    world.add(sciray::TriangleMesh::shared(arrays));
    world.commit();
    benchmark::DoNotOptimize(world.scene());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(mesh.face_count()));
}

void raw_embree_build(benchmark::State& state, std::size_t triangles) {
  const sciray::MeshData& mesh = torus(triangles);
  RTCDevice device = rtcNewDevice(nullptr);
  for (auto _ : state) {
    RTCScene scene = rtcNewScene(device);
    rtcSetSceneFlags(scene, RTC_SCENE_FLAG_ROBUST);  // as the engine's scenes
    RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    rtcSetSharedGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, mesh.positions.data(), 0,
                               3 * sizeof(float), mesh.vertex_count());
    rtcSetSharedGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, mesh.indices.data(), 0,
                               3 * sizeof(std::uint32_t), mesh.face_count());
    rtcCommitGeometry(geometry);
    rtcAttachGeometry(scene, geometry);
    rtcReleaseGeometry(geometry);
    rtcCommitScene(scene);
    benchmark::DoNotOptimize(scene);
    rtcReleaseScene(scene);
  }
  rtcReleaseDevice(device);
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(mesh.face_count()));
}

const bool registered = [] {
  for (const auto& [name, triangles] : {std::pair{"torus_1M", std::size_t{1'000'000}}, {"torus_5M", 5'000'000}}) {
    benchmark::RegisterBenchmark((std::string("build/raw_embree/") + name).c_str(), raw_embree_build, triangles)
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime();
    benchmark::RegisterBenchmark((std::string("build/sciray/") + name).c_str(), engine_build, triangles)
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime();
  }
  return true;
}();

}  // namespace
