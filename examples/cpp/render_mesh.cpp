// The smallest complete use of the header-only engine: load a PLY mesh, frame it, render
// a few accumulated frames with the scivis renderer for the architecture this file is
// compiled for, write a PNG.
//   render_mesh MESH.ply OUT.png
#include <iostream>

#include <sciray/sciray.hpp>

int main(int argc, char** argv) {
  if (argc != 3) {
    std::cerr << "usage: render_mesh MESH.ply OUT.png\n";
    return 2;
  }
  try {
    sciray::accel::Device device;
    sciray::World<sciray::TriangleMesh> world(device);  // meshes only: nothing else is compiled
    world.add(sciray::TriangleMesh(sciray::io::read_ply(argv[1])));
    world.commit();

    using Arch = xsimd::default_arch;  // the widest ISA enabled by this file's compiler flags
    const sciray::SciVis<Arch, decltype(world)> renderer(world, sciray::SciVisParams{});
    const auto camera = sciray::prepare(sciray::frame_bounds(world.bounds(), 4.f / 3.f));
    sciray::FrameBuffer fb(640, 480, sciray::ColorFormat::srgba);
    for (int frame = 0; frame < 8; ++frame) sciray::render_frame<Arch>(renderer, camera, fb);
    sciray::io::write_color(fb, argv[2]);
  } catch (const sciray::Error& e) {
    std::cerr << "render_mesh: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
