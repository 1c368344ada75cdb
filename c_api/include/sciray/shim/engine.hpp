#pragma once
// The compiled side of sciray: the engine instantiated once per ISA (each in its own
// translation unit, compiled with that ISA's flags) behind a table of entry points, and
// the run-time choice of ISA. The command-line tool, the C API, tests and benchmarks
// reach the per-ISA code only through `kernels`.
#include <cstdint>
#include <span>
#include <string_view>
#include <variant>

#include "sciray/distributed/fragments.hpp"
#include "sciray/frame/framebuffer.hpp"
#include "sciray/math/box.hpp"
#include "sciray/frame/render_frame.hpp"
#include "sciray/geometry/boxes.hpp"
#include "sciray/geometry/curves.hpp"
#include "sciray/geometry/isosurface.hpp"
#include "sciray/geometry/slice.hpp"
#include "sciray/geometry/spheres.hpp"
#include "sciray/geometry/subdivision.hpp"
#include "sciray/geometry/triangle_mesh.hpp"
#include "sciray/render/camera.hpp"
#include "sciray/render/pathtracer.hpp"
#include "sciray/render/scivis.hpp"
#include "sciray/scene/volume_world.hpp"
#include "sciray/scene/world.hpp"
#include "sciray/volume/structured_regular.hpp"
#include "sciray/volume/amr.hpp"
#include "sciray/volume/particle.hpp"
#include "sciray/volume/structured_spherical.hpp"
#include "sciray/volume/unstructured.hpp"
#include "sciray/volume/vdb.hpp"
#include "sciray/simd/arch.hpp"

/// Marks what libsciray_ospray exports (it is built with hidden visibility).
#define SCIRAY_SHIM_API __attribute__((visibility("default")))

namespace sciray::shim {

/// The full set of geometry and volume types, as the C API and the tool need it: every
/// voxel type in the linear (shared) and bricked layouts, unstructured volumes, particles,
/// spherical grids, VDB trees and AMR blocks.
using EngineWorld =
    VolumeWorld<World<TriangleMesh, Spheres, Curves, Boxes, Planes, Isosurface, VolumeSlice, Subdivision>,
                StructuredRegular<std::uint8_t>, StructuredRegular<std::int16_t>, StructuredRegular<std::uint16_t>,
                StructuredRegular<float>, StructuredRegular<double>, StructuredRegular<std::uint8_t, BrickedLayout>,
                StructuredRegular<std::int16_t, BrickedLayout>, StructuredRegular<std::uint16_t, BrickedLayout>,
                StructuredRegular<float, BrickedLayout>, StructuredRegular<double, BrickedLayout>, Unstructured,
                Particles, StructuredSpherical, Vdb, Amr>;

/// One ray's closest hit, as the packet paths report it (for cross-ISA checks).
struct TraceResult {
  float t;  ///< inf where nothing was hit
  float u, v;
  std::int32_t prim_id;
  std::int32_t geom_id;  ///< -1 where nothing was hit
  std::int32_t inst_id;  ///< top-level id of the instance hit, -1 for direct geometry or no hit
};

/// Which renderer, with its parameters: OSPRay's `scivis`, `ao` and `pathtracer`.
using RendererConfig = std::variant<SciVisParams, AOParams, PathTracerParams>;

struct IsaKernels {
  simd::Isa isa;
  /// Builds the world's BVH with sciray's own intersectors compiled for this ISA.
  void (*commit)(EngineWorld& world);
  /// Renders one frame with the scivis renderer into `fb` (accumulating); `control`
  /// (optional) reports progress and cancels.
  void (*render_scivis)(const EngineWorld& world, const SciVisParams& params, const Camera& camera, FrameBuffer& fb,
                        FrameControl* control);
  /// Renders one frame with any renderer, taking samples per pixel, pixel filter and
  /// variance threshold from `settings`.
  void (*render)(const EngineWorld& world, const RendererConfig& renderer, const Camera& camera, FrameBuffer& fb,
                 FrameControl* control, const FrameSettings& settings);
  /// Renders a share of a frame (render_tiles): the tiles of `share` at their frame
  /// indices into the staging frame buffer `fb`, for a frame accumulated elsewhere.
  void (*render_tiles)(const EngineWorld& world, const RendererConfig& renderer, const Camera& camera, FrameBuffer& fb,
                       std::span<const TileWork> share, FrameControl* control, const FrameSettings& settings);
  /// FrameBuffer::accumulate_tile compiled for this ISA, for frames rendered elsewhere
  /// to round as frames rendered here.
  void (*accumulate_tile)(FrameBuffer& fb, int tile, const float* packed);
  /// Samples a float volume (linear or bricked layout) at `positions`, in packets of this
  /// ISA's width (for measuring the sampler; renderers sample inside their kernels).
  void (*sample_volume)(const StructuredRegular<float>& volume, std::span<const Vec3f> positions, std::span<float> out);
  void (*sample_bricked_volume)(const StructuredRegular<float, BrickedLayout>& volume, std::span<const Vec3f> positions,
                                std::span<float> out);
  /// The same for the other volume types (bench/bench_volume_types.cpp).
  void (*sample_unstructured)(const Unstructured& volume, std::span<const Vec3f> positions, std::span<float> out);
  void (*sample_particles)(const Particles& volume, std::span<const Vec3f> positions, std::span<float> out);
  void (*sample_spherical)(const StructuredSpherical& volume, std::span<const Vec3f> positions, std::span<float> out);
  void (*sample_vdb)(const Vdb& volume, std::span<const Vec3f> positions, std::span<float> out);
  void (*sample_amr)(const Amr& volume, std::span<const Vec3f> positions, std::span<float> out);
  /// Traces arbitrary rays in packets of this ISA's width.
  void (*trace)(const EngineWorld& world, std::span<const Ray<float>> rays, std::span<TraceResult> results);
  /// Renders what the scivis or ao renderer (OSPRay's mpiRaycast: distributed/mpi_raycast.hpp)
  /// sees of `world` inside `region` as one region's fragment of a data-parallel frame
  /// (distributed/region_renderer.hpp), `out`'s size; `tile_frames`: each tile's frame
  /// index in the accumulation. Throws for the path tracer.
  void (*render_region)(const EngineWorld& world, const RendererConfig& renderer, const Camera& camera,
                        const Box3f& region, const FrameSettings& settings, std::span<const std::uint32_t> tile_frames,
                        distributed::FragmentImage& out);
};

/// The entry points of `isa`; throws if this CPU cannot run it.
SCIRAY_SHIM_API const IsaKernels& kernels(simd::Isa isa);

/// The ISA to use: `request` ("auto", "avx512", "avx2", "sse4.2", "scalar"), or when it
/// is empty or "auto" the SCIRAY_ISA environment variable if set, else the best one.
SCIRAY_SHIM_API simd::Isa select_isa(std::string_view request = {});

}  // namespace sciray::shim
