#include "offload.hpp"

#include <mpi.h>

#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <mutex>

#include "../device.hpp"
#include "runtime.hpp"
#include "sciray/mpi/image_parallel.hpp"

namespace sciray::ospray::offload {

namespace {

constexpr int application_rank = 0;

/// Sends a batch of commands from rank 0 to every worker (collective on `comm`).
void broadcast(MPI_Comm comm, std::vector<std::byte>& batch) {
  std::uint64_t size = batch.size();
  mpi::check(MPI_Bcast(&size, 1, MPI_UINT64_T, application_rank, comm), "broadcasting commands");
  batch.resize(size);
  constexpr std::uint64_t chunk = std::uint64_t{1} << 30;  // MPI counts are ints
  for (std::uint64_t at = 0; at < size; at += chunk)
    mpi::check(
        MPI_Bcast(batch.data() + at, static_cast<int>(std::min(chunk, size - at)), MPI_BYTE, application_rank, comm),
        "broadcasting commands");
}

class MpiSession final : public Session {
public:
  MpiSession(bool finalize, int thread_level, MPI_Comm commands, MPI_Comm tiles)
      : finalize_(finalize),
        thread_level_(thread_level),
        commands_(commands),
        tiles_(tiles),
        scheduling_(mpi::scheduling_from_environment()) {}

  ~MpiSession() override {
    // Workers leave their loop and end; a frame still running is waited for first.
    std::lock_guard lock(mpi_);
    log_.shutdown();
    std::vector<std::byte> batch = log_.take();
    try {
      broadcast(commands_, batch);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "sciray: mpiOffload: %s\n", e.what());
    }
    MPI_Comm_free(&commands_);
    MPI_Comm_free(&tiles_);
    if (finalize_) MPI_Finalize();
  }

  bool frames_run_asynchronously() const override { return thread_level_ == MPI_THREAD_MULTIPLE; }

  std::function<void(FrameControl&)> render_frame(Ref<FrameBufferObject> fb, Ref<Renderer> renderer,
                                                  Ref<CameraObject> camera, Ref<World> world,
                                                  const shim::IsaKernels& kernels) override {
    std::uint32_t frame_id;
    {
      // Frames go out one at a time: the previous one's tiles are all in first.
      std::lock_guard lock(mpi_);
      frame_id = next_frame_++;
      log_.render_frame(fb.get(), renderer.get(), camera.get(), world.get(), frame_id);
      std::vector<std::byte> batch = log_.take();
      broadcast(commands_, batch);
    }
    return [this, fb, renderer, frame_id, accumulate = kernels.accumulate_tile](FrameControl& control) {
      std::unique_lock lock(mpi_);
      serving_.wait(lock, [&] { return next_served_ == frame_id; });
      std::lock_guard frame_lock(fb->mutex());
      try {
        mpi::serve_frame(tiles_, frame_id, fb->frame(), renderer->frame_settings(), scheduling_, &control, accumulate);
      } catch (...) {
        ++next_served_;
        serving_.notify_all();
        throw;
      }
      ++next_served_;
      serving_.notify_all();
    };
  }

private:
  bool finalize_;
  int thread_level_;
  MPI_Comm commands_, tiles_;
  mpi::Scheduling scheduling_;
  std::mutex mpi_;  // one thread at a time calls MPI (MPI_THREAD_SERIALIZED suffices)
  std::condition_variable serving_;
  std::uint32_t next_frame_ = 0, next_served_ = 0;
};

/// A worker: replays the application's calls and renders the tiles it is given.
void run_worker(Device& device, MPI_Comm commands, MPI_Comm tiles, const mpi::Scheduling& scheduling) {
  Replayer replayer;
  std::map<const void*, FrameBuffer> staging;  // per frame buffer of the application
  const auto render = [&](OSPFrameBuffer fb_handle, OSPRenderer renderer_handle, OSPCamera camera_handle,
                          OSPWorld world_handle, std::uint32_t frame_id) {
    auto& fb = *static_cast<FrameBufferObject*>(reinterpret_cast<Object*>(fb_handle));
    auto& renderer = *static_cast<Renderer*>(reinterpret_cast<Object*>(renderer_handle));
    auto& camera = *static_cast<CameraObject*>(reinterpret_cast<Object*>(camera_handle));
    auto& world = *static_cast<World*>(reinterpret_cast<Object*>(world_handle));
    const FrameBuffer& shape = fb.frame();
    auto found = staging.find(fb_handle);
    if (found == staging.end() || found->second.width() != shape.width() || found->second.height() != shape.height() ||
        found->second.packed_floats() != shape.packed_floats()) {
      staging.erase(fb_handle);
      found = staging.emplace(fb_handle, mpi::staging_for(shape.width(), shape.height(), fb.channels())).first;
    }
    // The world is built on the first batch, so that its errors reach rank 0 as the frame's.
    std::shared_ptr<const BuiltWorld> built;
    const mpi::RenderShare render_share = [&](std::span<const TileWork> share, FrameBuffer& staged) {
      if (!built) {
        BuildLog log;
        built = world.built(device.kernels(), log);
      }
      built->kernels->render_tiles(*built->world, renderer.config(*built), camera.camera(), staged, share, nullptr,
                                   renderer.frame_settings());
    };
    const int batch = scheduling.batch_tiles > 0 ? scheduling.batch_tiles : 4 * device.threads();
    device.arena().execute(
        [&] { mpi::work_frame(tiles, application_rank, frame_id, found->second, render_share, batch); });
  };
  for (;;) {
    std::vector<std::byte> batch;
    broadcast(commands, batch);
    try {
      if (!replayer.replay(batch, render)) return;
    } catch (const std::exception& e) {
      std::fprintf(stderr, "sciray: mpiOffload worker: %s\n", e.what());
      MPI_Abort(MPI_COMM_WORLD, 1);
    }
  }
}

}  // namespace

std::unique_ptr<Session> start(Device& device, const std::function<void()>& make_current) {
  const auto [finalize, thread_level] = mpi_runtime::initialize();  // finalize: on rank 0
  int ranks = 0, rank = 0;
  mpi::check(MPI_Comm_size(MPI_COMM_WORLD, &ranks), "MPI_Comm_size");
  mpi::check(MPI_Comm_rank(MPI_COMM_WORLD, &rank), "MPI_Comm_rank");
  if (ranks < 2)
    throw Error(
        "mpiOffload: this job has 1 rank; the device needs the application's rank and at least one worker "
        "(mpirun -n 3 PROGRAM ..., or mpirun -n 1 PROGRAM : -n 2 sciray_mpi_worker)");
  MPI_Comm commands = MPI_COMM_NULL, tiles = MPI_COMM_NULL;
  mpi::check(MPI_Comm_dup(MPI_COMM_WORLD, &commands), "MPI_Comm_dup");
  mpi::check(MPI_Comm_dup(MPI_COMM_WORLD, &tiles), "MPI_Comm_dup");
  const mpi::Scheduling scheduling = mpi::scheduling_from_environment();
  if (rank == application_rank) return std::make_unique<MpiSession>(finalize, thread_level, commands, tiles);

  make_current();
  run_worker(device, commands, tiles, scheduling);
  // A worker never returns to the application (which would go on as if it were rank 0):
  // it ends MPI and the process here, whoever initialized MPI.
  MPI_Comm_free(&commands);
  MPI_Comm_free(&tiles);
  MPI_Finalize();
  std::exit(0);
}

}  // namespace sciray::ospray::offload
