#!/usr/bin/env python3
"""What composing only the types a scene needs saves: builds the same spheres program twice,
once as World<Spheres> with the headers it needs, once composing every geometry and
volume type the engine has (as the shim does), and reports compile time and binary size.

    /usr/bin/python3 bench/model_cost.py [--repeat 3]

Both are compiled with g++ -O2 -std=c++20 -march=native against include/, one at a time;
the time is the best of --repeat wall-clock runs, the size that of the stripped binary.
"""
import argparse
import os
import subprocess
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
INCLUDE = os.path.join(HERE, "..", "include")

MAIN = r"""
int main() {
  sciray::accel::Device device;
  WorldType world(device);
  sciray::SphereData spheres;
  for (int i = 0; i < 1000; ++i) {
    const float x = static_cast<float>(i % 10), y = static_cast<float>(i / 10 % 10), z = static_cast<float>(i / 100);
    spheres.positions.insert(spheres.positions.end(), {x, y, z});
  }
  spheres.radius = 0.4f;
  world.add(sciray::Spheres(std::move(spheres)));
  using Arch = xsimd::default_arch;
  world.template commit<Arch>();
  const sciray::SciVis<Arch, WorldType> renderer(world, sciray::SciVisParams{});
  sciray::FrameBuffer fb(64, 64, sciray::ColorFormat::srgba);
  sciray::render_frame<Arch>(renderer, sciray::prepare(sciray::frame_bounds(world.bounds(), 1.f)), fb);
  return fb.color8()[4 * (32 * 64 + 32) + 3] == 255 ? 0 : 1;
}
"""

PROGRAMS = {
    "World<Spheres>": """
#include <sciray/frame/render_frame.hpp>
#include <sciray/geometry/spheres.hpp>
#include <sciray/render/scivis.hpp>
#include <sciray/scene/world.hpp>
using WorldType = sciray::World<sciray::Spheres>;
""",
    "every type": """
#include <sciray/sciray.hpp>
using WorldType = sciray::VolumeWorld<
    sciray::World<sciray::TriangleMesh, sciray::Spheres, sciray::Curves, sciray::Boxes, sciray::Planes, sciray::Isosurface>,
    sciray::StructuredRegular<std::uint8_t>, sciray::StructuredRegular<std::int16_t>,
    sciray::StructuredRegular<std::uint16_t>, sciray::StructuredRegular<float>, sciray::StructuredRegular<double>,
    sciray::StructuredRegular<std::uint8_t, sciray::BrickedLayout>, sciray::StructuredRegular<float, sciray::BrickedLayout>>;
""",
}


def build(source, out):
    start = time.perf_counter()
    subprocess.run(["g++", "-O2", "-std=c++20", "-march=native", "-Wno-uninitialized", "-Wno-maybe-uninitialized",
                    "-I", INCLUDE, source, "-o", out, "-lembree3", "-ltbb", "-lstb", "-lz"], check=True)
    seconds = time.perf_counter() - start
    subprocess.run(["strip", out], check=True)
    subprocess.run([out], check=True)  # it renders: a sphere covers the centre pixel
    return seconds, os.path.getsize(out)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    print("| composition | compile time (s) | stripped binary (KiB) |")
    print("|---|---:|---:|")
    with tempfile.TemporaryDirectory() as tmp:
        for name, head in PROGRAMS.items():
            source = os.path.join(tmp, "program.cpp")
            with open(source, "w") as f:
                f.write(head + MAIN)
            runs = [build(source, os.path.join(tmp, "program")) for _ in range(args.repeat)]
            print(f"| {name} | {min(r[0] for r in runs):.1f} | {runs[0][1] / 1024:.0f} |")


if __name__ == "__main__":
    main()
