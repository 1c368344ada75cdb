// Uses the engine from headers alone, for the architecture this file is compiled for.
#include <sciray/sciray.hpp>

int main() {
  sciray::accel::Device device;
  sciray::World<sciray::TriangleMesh> world(device);
  world.add(sciray::TriangleMesh(sciray::testing::wavy_torus(2000)));
  world.commit();
  const auto camera = sciray::prepare(sciray::frame_bounds(world.bounds(), 1.f));
  const sciray::SciVis<xsimd::default_arch, decltype(world)> renderer(world, {});
  sciray::FrameBuffer fb(32, 32);
  sciray::render_frame<xsimd::default_arch>(renderer, camera, fb);
  // The torus fills the middle of the view.
  return fb.depth()[16 * 32 + 16] < 1e30f ? 0 : 1;
}
