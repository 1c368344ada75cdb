#pragma once
// The engine's entry points for one architecture. Included only by the per-ISA
// translation units (and the scalar one), each compiled with its ISA's flags.
#include <algorithm>
#include <limits>

#include "sciray/accel/trace.hpp"
#include "sciray/distributed/region_renderer.hpp"
#include "sciray/frame/render_frame.hpp"
#include "sciray/shim/engine.hpp"

namespace sciray::shim {

template <class Arch>
void commit(EngineWorld& world) {
  world.template commit<Arch>();
}

template <class Arch>
void render_scivis(const EngineWorld& world, const SciVisParams& params, const Camera& camera, FrameBuffer& fb,
                   FrameControl* control) {
  const SciVis<Arch, EngineWorld> renderer(world, params);
  render_frame<Arch>(renderer, camera, fb, control);
}

template <class Arch>
void render(const EngineWorld& world, const RendererConfig& config, const Camera& camera, FrameBuffer& fb,
            FrameControl* control, const FrameSettings& settings) {
  std::visit(
      [&](const auto& params) {
        using P = std::decay_t<decltype(params)>;
        if constexpr (std::is_same_v<P, SciVisParams>)
          render_frame<Arch>(SciVis<Arch, EngineWorld>(world, params), camera, fb, control, settings);
        else if constexpr (std::is_same_v<P, AOParams>)
          render_frame<Arch>(AmbientOcclusion<Arch, EngineWorld>(world, params), camera, fb, control, settings);
        else
          render_frame<Arch>(PathTracer<Arch, EngineWorld>(world, params), camera, fb, control, settings);
      },
      config);
}

template <class Arch>
void render_tiles(const EngineWorld& world, const RendererConfig& config, const Camera& camera, FrameBuffer& fb,
                  std::span<const TileWork> share, FrameControl* control, const FrameSettings& settings) {
  std::visit(
      [&](const auto& params) {
        using P = std::decay_t<decltype(params)>;
        if constexpr (std::is_same_v<P, SciVisParams>)
          sciray::render_tiles<Arch>(SciVis<Arch, EngineWorld>(world, params), camera, fb, share, control, settings);
        else if constexpr (std::is_same_v<P, AOParams>)
          sciray::render_tiles<Arch>(AmbientOcclusion<Arch, EngineWorld>(world, params), camera, fb, share, control,
                                     settings);
        else
          sciray::render_tiles<Arch>(PathTracer<Arch, EngineWorld>(world, params), camera, fb, share, control,
                                     settings);
      },
      config);
}

template <class Arch>
void accumulate_tile(FrameBuffer& fb, int tile, const float* packed) {
  fb.template accumulate_tile<Arch>(tile, packed);
}

template <class Arch>
void render_region(const EngineWorld& world, const RendererConfig& config, const Camera& camera, const Box3f& region,
                   const FrameSettings& settings, std::span<const std::uint32_t> tile_frames,
                   distributed::FragmentImage& out) {
  std::visit(
      [&](const auto& params) {
        using P = std::decay_t<decltype(params)>;
        if constexpr (std::is_same_v<P, SciVisParams>)
          out = distributed::render_region<Arch>(SciVis<Arch, EngineWorld>(world, distributed::region_params(params)),
                                                 camera, region, out.width, out.height, settings, tile_frames);
        else if constexpr (std::is_same_v<P, AOParams>)
          out = distributed::render_region<Arch>(
              AmbientOcclusion<Arch, EngineWorld>(world, distributed::region_params(params)), camera, region,
              out.width, out.height, settings, tile_frames);
        else
          throw Error("render_region: the path tracer cannot render a region of a data-parallel world (its paths "
                      "leave the region); use scivis or ao (mpiRaycast)");
      },
      config);
}

template <class Arch>
void trace(const EngineWorld& world, std::span<const Ray<float>> rays, std::span<TraceResult> results) {
  using F = simd::Float<Arch>;
  constexpr int W = simd::width<Arch>;
  const float inf = std::numeric_limits<float>::infinity();
  for (std::size_t first = 0; first < rays.size(); first += W) {
    const int count = static_cast<int>(std::min<std::size_t>(W, rays.size() - first));
    alignas(64) float lanes[9][W];
    for (int i = 0; i < W; ++i) {
      const Ray<float>& r = rays[first + std::min(i, count - 1)];
      const float values[9] = {r.org.x, r.org.y, r.org.z, r.dir.x, r.dir.y, r.dir.z, r.tnear, r.tfar, r.time};
      for (int k = 0; k < 9; ++k) lanes[k][i] = values[k];
    }
    Ray<F> ray;
    ray.org = {simd::load<Arch>(lanes[0]), simd::load<Arch>(lanes[1]), simd::load<Arch>(lanes[2])};
    ray.dir = {simd::load<Arch>(lanes[3]), simd::load<Arch>(lanes[4]), simd::load<Arch>(lanes[5])};
    ray.tnear = simd::load<Arch>(lanes[6]);
    ray.tfar = simd::load<Arch>(lanes[7]);
    ray.time = simd::load<Arch>(lanes[8]);
    const F active_lanes = simd::lane_index<Arch>();
    const auto hit = accel::intersect<Arch>(world.scene(), ray, active_lanes < F(static_cast<float>(count)), false,
                                           world.hit_filter());
    for (int i = 0; i < count; ++i) {
      const bool lane_hit = simd::lane(hit.hit, i);
      results[first + i] = {lane_hit ? simd::lane(hit.t, i) : inf, simd::lane(hit.u, i), simd::lane(hit.v, i),
                            lane_hit ? simd::lane(hit.prim_id, i) : -1, lane_hit ? simd::lane(hit.geom_id, i) : -1,
                            lane_hit ? simd::lane(hit.inst_id, i) : -1};
    }
  }
}

template <class Arch, class Volume>
void sample_volume(const Volume& volume, std::span<const Vec3f> positions, std::span<float> out) {
  constexpr int W = simd::width<Arch>;
  for (std::size_t first = 0; first < positions.size(); first += W) {
    const int count = static_cast<int>(std::min<std::size_t>(W, positions.size() - first));
    alignas(64) float x[W], y[W], z[W], values[W];
    for (int i = 0; i < W; ++i) {
      const Vec3f& p = positions[first + std::min(i, count - 1)];
      x[i] = p.x, y[i] = p.y, z[i] = p.z;
    }
    const Vec3<simd::Float<Arch>> p{simd::load<Arch>(x), simd::load<Arch>(y), simd::load<Arch>(z)};
    simd::store<Arch>(values, volume.template sample<Arch>(p));
    std::copy_n(values, count, out.begin() + static_cast<std::ptrdiff_t>(first));
  }
}

template <class Arch>
IsaKernels make_kernels(simd::Isa isa) {
  return {isa,
          &commit<Arch>,
          &render_scivis<Arch>,
          &render<Arch>,
          &render_tiles<Arch>,
          &accumulate_tile<Arch>,
          &sample_volume<Arch, StructuredRegular<float>>,
          &sample_volume<Arch, StructuredRegular<float, BrickedLayout>>,
          &sample_volume<Arch, Unstructured>,
          &sample_volume<Arch, Particles>,
          &sample_volume<Arch, StructuredSpherical>,
          &sample_volume<Arch, Vdb>,
          &sample_volume<Arch, Amr>,
          &trace<Arch>,
          &render_region<Arch>};
}

}  // namespace sciray::shim

/// Defines the one exported symbol of an ISA's translation unit. Everything else in
/// that object is made local at link time (see c_api/CMakeLists.txt), so inline
/// functions compiled with wider instructions can never be picked for another ISA.
#define SCIRAY_DEFINE_ISA_KERNELS(function_name, arch, isa_value)                      \
  extern "C" const sciray::shim::IsaKernels* function_name() {                         \
    static const sciray::shim::IsaKernels kernels = sciray::shim::make_kernels<arch>(isa_value); \
    return &kernels;                                                                   \
  }
