#pragma once
// Tracing rays through a world with one ISA's kernels, as the per-ISA tests do.
#include <utility>
#include <vector>

#include "sciray/shim/engine.hpp"

namespace sciray::test_support {

/// Commits `world` with `isa`'s kernels (own intersectors compiled for it) and traces `rays`.
inline std::vector<shim::TraceResult> trace(simd::Isa isa, shim::EngineWorld& world, const std::vector<Ray<float>>& rays) {
  shim::kernels(isa).commit(world);
  std::vector<shim::TraceResult> results(rays.size());
  shim::kernels(isa).trace(world, rays, results);
  return results;
}

/// The same for a world holding only `geometry`.
template <class G>
std::vector<shim::TraceResult> trace_geometry(simd::Isa isa, G geometry, const std::vector<Ray<float>>& rays) {
  accel::Device device;
  shim::EngineWorld world(device);
  world.add(std::move(geometry));
  return trace(isa, world, rays);
}

}  // namespace sciray::test_support
