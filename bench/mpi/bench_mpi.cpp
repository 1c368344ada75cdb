// What distributing a frame costs: run under MPI on P ranks,
//   mpirun -n P sciray_bench_mpi [--benchmark_...]
// Rank 0 runs Google Benchmark; the other ranks follow each iteration (rank 0 tells them
// what to do, and they wait for it without spinning).
//   mpi/image_parallel/<size>: one frame of the bunny, scivis with shadows, with its tiles
//     handed out to ranks 1..P-1 and accumulated on rank 0 (P >= 2), against
//   mpi/local/<size>: the same frame rendered on rank 0 alone, in the same run (the ratio
//     is the overhead; this machine has 2 cores, so P ranks share them: not a speedup).
//   mpi/composite/<size>: sort-last compositing of one full-screen fragment layer per rank
//     (direct send by bands, then the gather to rank 0), no rendering: the compositing cost.
// Counters: bytes each rank sent rank 0 per frame (image-parallel), bytes sent per rank
// (compositing).
#include <benchmark/benchmark.h>
#include <mpi.h>

#include <chrono>
#include <cstdint>
#include <memory>
#include <thread>

#include "sciray/mpi/data_parallel.hpp"
#include "sciray/mpi/image_parallel.hpp"
#include "sciray/shim/engine.hpp"
#include "sciray/testing/scenes.hpp"

namespace {

enum class Op : std::int32_t { stop, image_parallel, composite };
struct Command {
  Op op;
  std::int32_t size;
};

int rank = 0, ranks = 1;
// Made by every rank before the first command.
std::unique_ptr<sciray::mpi::ImageParallel> frames;
std::unique_ptr<sciray::mpi::DataParallel> compositor;

/// Rank 0's command to every rank; the others wait for it sleeping, not spinning, so that
/// rank 0's own measurements get the cores.
Command share(Command command) {
  MPI_Request request;
  sciray::mpi::check(MPI_Ibcast(&command, sizeof command, MPI_BYTE, 0, MPI_COMM_WORLD, &request), "MPI_Ibcast");
  for (int done = 0; !done;) {
    sciray::mpi::check(MPI_Test(&request, &done, MPI_STATUS_IGNORE), "MPI_Test");
    if (!done) std::this_thread::sleep_for(std::chrono::microseconds(200));
  }
  return command;
}

struct Scene {
  sciray::accel::Device device;
  sciray::shim::EngineWorld world{device};
  sciray::Camera camera;
  sciray::SciVisParams params;
  const sciray::shim::IsaKernels* kernels = nullptr;
};

Scene& scene() {
  static std::unique_ptr<Scene> built = [] {
    auto s = std::make_unique<Scene>();
    const auto standard = sciray::testing::standard_scene("bunny", SCIRAY_DATA_DIR);
    s->world.add(sciray::TriangleMesh(*standard.mesh));
    s->kernels = &sciray::shim::kernels(sciray::shim::select_isa());
    s->kernels->commit(s->world);
    const sciray::PerspectiveCamera view = sciray::frame_bounds(s->world.bounds(), 1.f);
    s->camera = view;
    s->params.lights = sciray::default_lights(normalize(view.direction));
    s->params.shadows = true;
    return s;
  }();
  return *built;
}

constexpr unsigned channels = sciray::channel_color | sciray::channel_depth | sciray::channel_accum;

/// One image-parallel frame on every rank (rank 0 owns it).
sciray::mpi::FrameTraffic image_parallel_frame(sciray::FrameBuffer& fb) {
  Scene& s = scene();
  return frames->render_frame(
      fb, {},
      [&](std::span<const sciray::TileWork> share, sciray::FrameBuffer& staged) {
        s.kernels->render_tiles(s.world, s.params, s.camera, staged, share, nullptr, {});
      },
      s.kernels->accumulate_tile);
}

/// One fragment layer covering the frame, as a rank's region would.
sciray::distributed::FragmentImage layer_of(int size) {
  sciray::distributed::FragmentImage layer(size, size);
  for (std::size_t p = 0; p < layer.pixel_count(); ++p) {
    for (int c = 0; c < 4; ++c) layer.rgba[4 * p + c] = 0.1f * static_cast<float>(rank + 1);
    layer.key[p] = static_cast<float>(rank);
    layer.depth[p] = static_cast<float>(rank) + 0.5f;
  }
  return layer;
}

void follow() {
  for (;;) {
    const Command command = share({});
    if (command.op == Op::stop) return;
    if (command.op == Op::image_parallel) {
      sciray::FrameBuffer fb(command.size, command.size, sciray::ColorFormat::srgba, channels);
      image_parallel_frame(fb);
    } else {
      const auto layer = layer_of(command.size);
      compositor->composite_frame(std::span(&layer, 1), command.size, command.size, {}, nullptr);
    }
  }
}

void local_frame(benchmark::State& state) {
  Scene& s = scene();
  const int size = static_cast<int>(state.range(0));
  sciray::FrameBuffer fb(size, size, sciray::ColorFormat::srgba, channels);
  for (auto _ : state) s.kernels->render(s.world, s.params, s.camera, fb, nullptr, {});
  state.counters["ranks"] = ranks;
}

void image_parallel(benchmark::State& state) {
  if (ranks < 2) return state.SkipWithError("needs 2 or more ranks (mpirun -n P)");
  const int size = static_cast<int>(state.range(0));
  sciray::FrameBuffer fb(size, size, sciray::ColorFormat::srgba, channels);
  double bytes = 0, frame_count = 0;
  for (auto _ : state) {
    share({Op::image_parallel, size});
    const auto traffic = image_parallel_frame(fb);
    for (const auto b : traffic.bytes) bytes += static_cast<double>(b);
    ++frame_count;
  }
  state.counters["ranks"] = ranks;
  state.counters["bytes_to_rank0_per_frame"] = bytes / frame_count;
  state.counters["bytes_per_pixel"] = bytes / frame_count / (double(size) * size);
}

void composite(benchmark::State& state) {
  const int size = static_cast<int>(state.range(0));
  sciray::FrameBuffer fb(size, size, sciray::ColorFormat::srgba, sciray::channel_color | sciray::channel_depth);
  const auto layer = layer_of(size);
  double sent = 0, frame_count = 0;
  for (auto _ : state) {
    share({Op::composite, size});
    sent += static_cast<double>(
        compositor->composite_frame(std::span(&layer, 1), size, size, {}, &fb, scene().kernels->accumulate_tile)
            .bytes_sent);
    ++frame_count;
  }
  state.counters["ranks"] = ranks;
  state.counters["bytes_sent_rank0_per_frame"] = sent / frame_count;
  state.SetItemsProcessed(state.iterations() * size * size);  // pixels composited per second
}

}  // namespace

int main(int argc, char** argv) {
  int level = 0;
  MPI_Init_thread(&argc, &argv, MPI_THREAD_SERIALIZED, &level);
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &ranks);
  scene();  // every rank holds the scene before the first frame
  frames = std::make_unique<sciray::mpi::ImageParallel>(MPI_COMM_WORLD, 0, sciray::mpi::Scheduling{.batch_tiles = 32});
  compositor = std::make_unique<sciray::mpi::DataParallel>(MPI_COMM_WORLD);
  if (rank != 0) {
    follow();
  } else {
    for (const int size : {256, 512, 1024}) {
      benchmark::RegisterBenchmark(("mpi/local/" + std::to_string(size)).c_str(), local_frame)
          ->Arg(size)
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime();
      benchmark::RegisterBenchmark(("mpi/image_parallel/" + std::to_string(size)).c_str(), image_parallel)
          ->Arg(size)
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime();
    }
    for (const int size : {256, 512, 1024, 2048})
      benchmark::RegisterBenchmark(("mpi/composite/" + std::to_string(size)).c_str(), composite)
          ->Arg(size)
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime();
    benchmark::Initialize(&argc, argv);
    benchmark::RunSpecifiedBenchmarks();
    share({Op::stop, 0});
  }
  frames.reset();
  compositor.reset();
  MPI_Finalize();
  return 0;
}
