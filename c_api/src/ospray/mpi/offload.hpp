#pragma once
// The mpiOffload device (OSPRay's image-parallel mode): the application runs on rank 0,
// whose device records its calls (commands.hpp) and owns every frame buffer; the other
// ranks are workers that replay the calls and render the tiles rank 0 hands out
// (sciray/mpi/image_parallel.hpp). Built only with MPI (SCIRAY_MPI); without it,
// starting the device is an error that says so.
#include <functional>
#include <memory>

#include "../frame_objects.hpp"
#include "../scene_objects.hpp"
#include "commands.hpp"

namespace sciray::ospray {
class Device;
}

namespace sciray::ospray::offload {

/// The application rank's link to the workers.
class Session {
public:
  virtual ~Session() = default;
  CommandLog& log() { return log_; }

  /// Sends the recorded calls and the frame to the workers; returns the frame's task
  /// (for a Future), which hands out the tiles and accumulates them into `fb` with
  /// `kernels` (the workers' ISA, so that they round alike).
  virtual std::function<void(FrameControl&)> render_frame(Ref<FrameBufferObject> fb, Ref<Renderer> renderer,
                                                          Ref<CameraObject> camera, Ref<World> world,
                                                          const shim::IsaKernels& kernels) = 0;
  /// Whether frames may run on a thread of their own while the application goes on
  /// (MPI_THREAD_MULTIPLE); otherwise ospRenderFrame returns a finished frame.
  virtual bool frames_run_asynchronously() const = 0;

protected:
  CommandLog log_;
};

/// Initializes MPI if the application has not, and takes this process's role: rank 0
/// gets its session; any other rank becomes a worker, which makes `device` current
/// through `make_current`, replays and renders until the application shuts down, and
/// then ends the process.
std::unique_ptr<Session> start(Device& device, const std::function<void()>& make_current);

}  // namespace sciray::ospray::offload
