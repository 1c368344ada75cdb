// The C++ face of image-parallel rendering: sciray::mpi::ImageParallel renders, on every
// rank of the job, frames of a scene every rank builds; rank 0's frame buffer must hold,
// byte for byte, what render_frame gives on rank 0 alone (4 accumulated frames, AO).
//   mpirun -n 3 image_parallel_cpp        exit status 0 when equal
#include <mpi.h>

#include <cstdio>

#include "sciray/frame/render_frame.hpp"
#include "sciray/mpi/image_parallel.hpp"
#include "sciray/render/scivis.hpp"
#include "sciray/scene/world.hpp"
#include "support/render_scenes.hpp"

int main(int argc, char** argv) {
  int level = 0, rank = 0;
  MPI_Init_thread(&argc, &argv, MPI_THREAD_SERIALIZED, &level);
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  int status = 0;
  {
    using Arch = xsimd::default_arch;
    using namespace sciray;
    accel::Device device;
    World<Spheres> world(device);
    world.add(test_support::spheres({{{0.f, 0.f, 0.f}, 1.f}, {{1.2f, 0.3f, 0.5f}, 0.6f}, {{-1.f, -0.8f, 0.4f}, 0.4f}}));
    world.commit();
    SciVisParams params;
    params.ao_samples = 2;
    const SciVis<Arch, decltype(world)> renderer(world, params);
    const auto camera = prepare(frame_bounds(world.bounds(), 1.f));
    const unsigned channels = channel_color | channel_depth | channel_accum | channel_variance;
    FrameBuffer fb(100, 70, ColorFormat::srgba, channels);
    mpi::ImageParallel frames(MPI_COMM_WORLD);
    for (int f = 0; f < 4; ++f) frames.render_frame<Arch>(renderer, camera, fb);
    if (frames.owns_frames()) {
      FrameBuffer alone(100, 70, ColorFormat::srgba, channels);
      for (int f = 0; f < 4; ++f) render_frame<Arch>(renderer, camera, alone);
      const bool same = fb.color8() == alone.color8() && fb.depth() == alone.depth() &&
                        fb.variance() == alone.variance();
      std::printf("%s\n", same ? "same as one process" : "DIFFERS from one process");
      status = same ? 0 : 1;
    }
  }
  MPI_Finalize();
  return status;
}
