#pragma once
// `sciray render --mpi`, run under mpirun: every rank loads the same scene, and each frame
// is rendered image-parallel (sciray/mpi/image_parallel.hpp): rank 0 hands out the tiles,
// accumulates them and writes the outputs; the other ranks render tiles. Built with MPI
// only (SCIRAY_TOOL_MPI).
#include <mpi.h>

#include <memory>

#include "sciray/mpi/image_parallel.hpp"
#include "sciray/shim/engine.hpp"

namespace sciray_tool {

class MpiFrames {
public:
  MpiFrames() {
    int initialized = 0, level = 0;
    MPI_Initialized(&initialized);
    if (!initialized) sciray::mpi::check(MPI_Init_thread(nullptr, nullptr, MPI_THREAD_SERIALIZED, &level), "MPI_Init");
    frames_ = std::make_unique<sciray::mpi::ImageParallel>(MPI_COMM_WORLD);
    if (frames_->ranks() < 2)
      throw sciray::Error("--mpi: run under mpirun with 2 or more ranks (rank 0 accumulates, the others render)");
  }
  ~MpiFrames() {
    frames_.reset();  // its communicator goes before MPI does
    MPI_Finalize();
  }
  MpiFrames(const MpiFrames&) = delete;
  MpiFrames& operator=(const MpiFrames&) = delete;

  /// Rank 0 writes the outputs.
  bool writes_outputs() const { return frames_->owns_frames(); }
  int ranks() const { return frames_->ranks(); }

  /// Whether to render another frame: rank 0's `wanted`, for every rank.
  bool another_frame(bool wanted) {
    int go = wanted ? 1 : 0;
    sciray::mpi::check(MPI_Bcast(&go, 1, MPI_INT, 0, frames_->communicator()), "MPI_Bcast");
    return go != 0;
  }

  /// One frame of `world` into rank 0's `fb` (collective; run inside the tool's arena,
  /// whose threads set the ranks' batches).
  void render(const sciray::shim::IsaKernels& kernels, const sciray::shim::EngineWorld& world,
              const sciray::shim::RendererConfig& config, const sciray::Camera& camera, sciray::FrameBuffer& fb,
              const sciray::FrameSettings& settings) {
    frames_->render_frame(
        fb, settings,
        [&](std::span<const sciray::TileWork> share, sciray::FrameBuffer& staged) {
          kernels.render_tiles(world, config, camera, staged, share, nullptr, settings);
        },
        kernels.accumulate_tile);
  }

private:
  std::unique_ptr<sciray::mpi::ImageParallel> frames_;
};

}  // namespace sciray_tool
