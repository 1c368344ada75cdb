// Uses the compiled shim's per-ISA kernels.
#include <sciray/shim/engine.hpp>
#include <sciray/testing/scenes.hpp>

int main() {
  sciray::accel::Device device;
  sciray::shim::EngineWorld world(device);
  world.add(sciray::TriangleMesh(sciray::testing::wavy_torus(2000)));
  world.commit();
  sciray::FrameBuffer fb(32, 32);
  sciray::shim::kernels(sciray::shim::select_isa())
      .render_scivis(world, {}, sciray::frame_bounds(world.bounds(), 1.f), fb, nullptr);
  return fb.depth()[16 * 32 + 16] < 1e30f ? 0 : 1;
}
