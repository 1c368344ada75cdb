#pragma once
// The mpiDistributed device (OSPRay's data-parallel mode): every rank creates its own
// world from its own data, with the world parameter `region` (box3f[]) bounding what it
// owns, and calls ospRenderFrame collectively; each rank renders its regions into
// fragments, which are composited sort-last (sciray/mpi/data_parallel.hpp) into rank 0's
// frame buffer. Built only with MPI (SCIRAY_MPI).
#include <memory>

#include "../frame_objects.hpp"
#include "../scene_objects.hpp"

namespace sciray::ospray {
class Device;
}

namespace sciray::ospray::distributed {

class Session {
public:
  virtual ~Session() = default;
  /// Renders this rank's regions of `world` and composites the frame with every other
  /// rank's (collective; rank 0's `fb` gets the image). `built` is this rank's world.
  virtual void render_frame(FrameBufferObject& fb, const Renderer& renderer, const CameraObject& camera,
                            const World& world, const BuiltWorld& built, Device& device) = 0;
};

/// Initializes MPI if the application has not and joins the job's ranks.
std::unique_ptr<Session> start();

}  // namespace sciray::ospray::distributed
