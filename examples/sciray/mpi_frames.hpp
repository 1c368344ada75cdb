#pragma once
// `sciray render --mpi`, run under mpirun: every rank loads the same scene, and each frame
// is rendered image-parallel (sciray/mpi/image_parallel.hpp): rank 0 hands out the tiles,
// accumulates them and writes the outputs; the other ranks render tiles. Built with MPI
// only (SCIRAY_TOOL_MPI).
#include <mpi.h>

#include <cstdint>

#include "sciray/mpi/image_parallel.hpp"
#include "sciray/shim/engine.hpp"

namespace sciray_tool {

class MpiFrames {
public:
  MpiFrames() {
    int initialized = 0, level = 0;
    MPI_Initialized(&initialized);
    if (!initialized) sciray::mpi::check(MPI_Init_thread(nullptr, nullptr, MPI_THREAD_SERIALIZED, &level), "MPI_Init");
    sciray::mpi::check(MPI_Comm_dup(MPI_COMM_WORLD, &comm_), "MPI_Comm_dup");
    MPI_Comm_rank(comm_, &rank_);
    MPI_Comm_size(comm_, &ranks_);
    if (ranks_ < 2)
      throw sciray::Error("--mpi: run under mpirun with 2 or more ranks (rank 0 accumulates, the others render)");
  }
  ~MpiFrames() {
    MPI_Comm_free(&comm_);
    MPI_Finalize();
  }
  MpiFrames(const MpiFrames&) = delete;
  MpiFrames& operator=(const MpiFrames&) = delete;

  /// Rank 0 writes the outputs.
  bool writes_outputs() const { return rank_ == 0; }
  int ranks() const { return ranks_; }

  /// Whether to render another frame: rank 0's `wanted`, for every rank.
  bool another_frame(bool wanted) {
    int go = wanted ? 1 : 0;
    sciray::mpi::check(MPI_Bcast(&go, 1, MPI_INT, 0, comm_), "MPI_Bcast");
    return go != 0;
  }

  /// One frame of `world` into rank 0's `fb` (collective).
  void render(const sciray::shim::IsaKernels& kernels, const sciray::shim::EngineWorld& world,
              const sciray::shim::RendererConfig& config, const sciray::Camera& camera, sciray::FrameBuffer& fb,
              const sciray::FrameSettings& settings, int threads) {
    const std::uint32_t frame_id = next_frame_++;
    if (rank_ == 0) {
      sciray::mpi::serve_frame(comm_, frame_id, fb, settings, scheduling_, nullptr, kernels.accumulate_tile);
      return;
    }
    if (!staging_) {
      unsigned channels = 0;
      if (fb.has(sciray::channel_depth)) channels |= sciray::channel_depth;
      staging_.emplace(sciray::mpi::staging_for(fb.width(), fb.height(), channels));
    }
    sciray::mpi::work_frame(
        comm_, 0, frame_id, *staging_,
        [&](std::span<const sciray::TileWork> share, sciray::FrameBuffer& staged) {
          kernels.render_tiles(world, config, camera, staged, share, nullptr, settings);
        },
        4 * threads);
  }

private:
  MPI_Comm comm_ = MPI_COMM_NULL;
  int rank_ = 0, ranks_ = 1;
  sciray::mpi::Scheduling scheduling_ = sciray::mpi::scheduling_from_environment();
  std::uint32_t next_frame_ = 0;
  std::optional<sciray::FrameBuffer> staging_;
};

}  // namespace sciray_tool
