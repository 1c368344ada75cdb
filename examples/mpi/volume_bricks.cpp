// Data-parallel volume rendering through OSPRay's C API (the mpiDistributed device): each
// of the job's P ranks keeps one brick of a volume (with one layer of ghost voxels from
// its neighbours), makes a world of it whose `region` is the part of the volume it owns,
// and renders collectively with the mpiRaycast renderer; rank 0 gets the composited image.
//
//   mpirun -n 4 volume_bricks VOLUME.raw OUT.png [--frames N] [--isosurface VALUE]
//                         [--rgba OUT.rgba] [--compare REFERENCE.rgba MAX_RMSE]
//   volume_bricks VOLUME.raw OUT.png --unsplit ...   (the whole volume on the local device)
//
// --isosurface shows the bricks' isosurface at VALUE (surfaces) instead of the volume.
// --rgba writes rank 0's image as RGBA32F; --compare fails (exit 1) when the image's
// RMSE against such a file is above MAX_RMSE, the way the tests check that 2, 3 and 4
// bricks composite to the unsplit image.
#include "sciray/distributed/volume_bricks.hpp"

#include <mpi.h>
#include <ospray/ospray.h>
#include <ospray/ospray_util.h>
#include <stb/stb_image_write.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include "sciray/io/volume.hpp"
#include "sciray/math/color.hpp"

namespace {

constexpr int width = 320, height = 240;
int errors = 0;

void on_error(void*, OSPError code, const char* message) {
  ++errors;
  std::fprintf(stderr, "OSPRay error %d: %s\n", static_cast<int>(code), message);
}

/// This rank's brick of the volume: its voxels as float, grid and region.
struct Brick {
  std::vector<float> voxels;
  sciray::VolumeDims dims;
  sciray::VolumeGrid grid;
  sciray::Box3f region;
};

/// `ghost_layers`: 1 for sampling (trilinear), 2 for gradients by central differences
/// (isosurface normals), which read a voxel further.
Brick brick_of(const sciray::io::VolumeFile& file, int rank, int ranks, int ghost_layers) {
  if (file.kind != sciray::io::VoxelKind::uint8) throw sciray::Error("volume_bricks reads uint8 volumes");
  const std::span voxels(reinterpret_cast<const std::uint8_t*>(file.voxels->data()), file.voxels->size());
  const auto bricks = sciray::distributed::split_volume(voxels, file.dims, file.grid,
                                                        sciray::distributed::brick_grid(ranks), ghost_layers);
  const auto& mine = bricks[static_cast<std::size_t>(rank)];
  return {std::vector<float>(mine.voxels->begin(), mine.voxels->end()), mine.dims, mine.grid, mine.region};
}

OSPWorld make_world(const Brick& brick, bool distributed, std::optional<float> isovalue) {
  OSPVolume volume = ospNewVolume("structuredRegular");
  OSPData data = ospNewSharedData3D(brick.voxels.data(), OSP_FLOAT, static_cast<uint64_t>(brick.dims[0]),
                                    static_cast<uint64_t>(brick.dims[1]), static_cast<uint64_t>(brick.dims[2]));
  ospSetObject(volume, "data", data);
  ospRelease(data);
  ospSetVec3f(volume, "gridOrigin", brick.grid.origin.x, brick.grid.origin.y, brick.grid.origin.z);
  ospSetVec3f(volume, "gridSpacing", brick.grid.spacing.x, brick.grid.spacing.y, brick.grid.spacing.z);
  ospCommit(volume);

  // The protein's shells: low values faint blue, high ones opaque orange.
  const float colors[] = {0.1f, 0.2f, 0.8f, 0.9f, 0.9f, 0.9f, 1.0f, 0.5f, 0.1f};
  const float opacities[] = {0.f, 0.05f, 0.f, 0.6f, 1.f};
  OSPTransferFunction tf = ospNewTransferFunction("piecewiseLinear");
  data = ospNewSharedData1D(colors, OSP_VEC3F, 3);
  ospSetObject(tf, "color", data);
  ospRelease(data);
  data = ospNewSharedData1D(opacities, OSP_FLOAT, 5);
  ospSetObject(tf, "opacity", data);
  ospRelease(data);
  ospSetVec2f(tf, "value", 0.f, 255.f);
  ospCommit(tf);

  OSPVolumetricModel model = ospNewVolumetricModel(volume);
  ospSetObject(model, "transferFunction", tf);
  ospSetFloat(model, "densityScale", 0.3f);
  ospCommit(model);
  ospRelease(tf);

  OSPGroup group = ospNewGroup();
  if (isovalue) {
    OSPGeometry surface = ospNewGeometry("isosurface");
    ospSetObject(surface, "volume", volume);
    ospSetFloat(surface, "isovalue", *isovalue);
    ospCommit(surface);
    OSPGeometricModel surface_model = ospNewGeometricModel(surface);
    ospSetVec4f(surface_model, "color", 1.f, 0.7f, 0.3f, 1.f);
    ospCommit(surface_model);
    ospSetObjectAsData(group, "geometry", OSP_GEOMETRIC_MODEL, surface_model);
    ospRelease(surface_model);
    ospRelease(surface);
  } else {
    ospSetObjectAsData(group, "volume", OSP_VOLUMETRIC_MODEL, model);
  }
  ospCommit(group);
  ospRelease(model);
  ospRelease(volume);
  OSPInstance instance = ospNewInstance(group);
  ospCommit(instance);
  ospRelease(group);

  OSPWorld world = ospNewWorld();
  ospSetObjectAsData(world, "instance", OSP_INSTANCE, instance);
  ospRelease(instance);
  // Shared, not copied: it must outlive the commit below.
  const sciray::Box3f& r = brick.region;
  const float region[6] = {r.lower.x, r.lower.y, r.lower.z, r.upper.x, r.upper.y, r.upper.z};
  if (distributed) {
    data = ospNewSharedData1D(region, OSP_BOX3F, 1);
    ospSetObject(world, "region", data);
    ospRelease(data);
  }
  ospCommit(world);
  return world;
}

double rmse(const float* image, const std::string& reference_file) {
  std::vector<float> reference(4 * static_cast<std::size_t>(width) * height);
  std::ifstream in(reference_file, std::ios::binary);
  if (!in.read(reinterpret_cast<char*>(reference.data()), static_cast<std::streamsize>(reference.size() * 4)))
    throw sciray::Error(reference_file + ": not a " + std::to_string(width) + "x" + std::to_string(height) +
                        " RGBA32F image");
  double sum = 0.0;
  for (std::size_t i = 0; i < reference.size(); ++i) sum += std::pow(double(image[i]) - reference[i], 2);
  return std::sqrt(sum / static_cast<double>(reference.size()));
}

}  // namespace

int main(int argc, char** argv) {
  // The application initializes MPI (the device then uses it as it is).
  int thread_level = 0, rank = 0, ranks = 1;
  MPI_Init_thread(&argc, &argv, MPI_THREAD_MULTIPLE, &thread_level);
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &ranks);
  std::vector<std::string> args(argv + 1, argv + argc);
  if (args.size() < 2) {
    std::cerr << "usage: volume_bricks VOLUME.raw OUT.png [--frames N] [--rgba OUT.rgba] "
                 "[--compare REFERENCE.rgba MAX_RMSE] [--isosurface VALUE] [--unsplit]\n";
    return 2;
  }
  int frames = 2;
  bool distributed = true;
  std::optional<float> isovalue;
  std::string rgba_out, compare_with;
  double max_rmse = 0.0;
  for (std::size_t i = 2; i < args.size(); ++i) {
    if (args[i] == "--frames" && i + 1 < args.size())
      frames = std::stoi(args[++i]);
    else if (args[i] == "--rgba" && i + 1 < args.size())
      rgba_out = args[++i];
    else if (args[i] == "--compare" && i + 2 < args.size())
      compare_with = args[++i], max_rmse = std::stod(args[++i]);
    else if (args[i] == "--isosurface" && i + 1 < args.size())
      isovalue = std::stof(args[++i]);
    else if (args[i] == "--unsplit")
      distributed = false;
    else
      return std::cerr << "volume_bricks: unknown argument " << args[i] << "\n", 2;
  }
  if (!distributed && ranks > 1) return std::cerr << "volume_bricks: --unsplit renders on one process\n", 2;

  ospLoadModule("mpi_distributed_cpu");
  OSPDevice device = ospNewDevice(distributed ? "mpiDistributed" : "cpu");
  ospDeviceSetErrorCallback(device, on_error, nullptr);
  ospDeviceCommit(device);
  ospSetCurrentDevice(device);
  ospDeviceRelease(device);

  int status = 0;
  try {
    const auto file = sciray::io::read_volume(args[0]);
    const Brick brick = brick_of(file, rank, ranks, isovalue ? 2 : 1);
    OSPWorld world = make_world(brick, distributed, isovalue);

    const sciray::Vec3f size =
        sciray::Vec3f{float(file.dims[0]), float(file.dims[1]), float(file.dims[2])} * file.grid.spacing;
    const sciray::Vec3f center = file.grid.origin + size * 0.5f;
    OSPCamera camera = ospNewCamera("perspective");
    // Oblique to every brick border.
    ospSetVec3f(camera, "position", center.x + 0.8f * size.x, center.y + 0.6f * size.y, center.z + 1.f * size.z);
    ospSetVec3f(camera, "direction", -0.8f * size.x, -0.6f * size.y, -1.f * size.z);
    ospSetVec3f(camera, "up", 0.f, 1.f, 0.f);
    ospSetFloat(camera, "aspect", float(width) / height);
    ospCommit(camera);

    OSPRenderer renderer = ospNewRenderer("mpiRaycast");
    ospSetVec4f(renderer, "backgroundColor", 0.05f, 0.05f, 0.08f, 1.f);
    ospCommit(renderer);

    OSPFrameBuffer fb = ospNewFrameBuffer(width, height, OSP_FB_RGBA32F, OSP_FB_COLOR | OSP_FB_ACCUM | OSP_FB_DEPTH);
    ospCommit(fb);
    for (int f = 0; f < frames; ++f) ospRenderFrameBlocking(fb, renderer, camera, world);

    if (rank == 0) {
      const auto* image = static_cast<const float*>(ospMapFrameBuffer(fb, OSP_FB_COLOR));
      if (image) {
        // sRGB bytes, top row first.
        std::vector<std::uint8_t> bytes(4 * static_cast<std::size_t>(width) * height);
        for (int y = 0; y < height; ++y)
          for (int x = 0; x < 4 * width; ++x) {
            const float v = image[4 * static_cast<std::size_t>(width) * (height - 1 - y) + x];
            bytes[4 * static_cast<std::size_t>(width) * y + x] =
                sciray::to_unorm8(x % 4 == 3 ? v : sciray::linear_to_srgb(v));
          }
        if (!stbi_write_png(args[1].c_str(), width, height, 4, bytes.data(), 4 * width))
          throw sciray::Error("could not write " + args[1]);
        if (!rgba_out.empty())
          std::ofstream(rgba_out, std::ios::binary)
              .write(reinterpret_cast<const char*>(image), static_cast<std::streamsize>(16) * width * height);
        if (!compare_with.empty()) {
          const double error = rmse(image, compare_with);
          std::printf("%d brick(s): RMSE %.6f against %s (at most %g)\n", ranks, error, compare_with.c_str(), max_rmse);
          if (!(error <= max_rmse)) status = 1;
        }
        ospUnmapFrameBuffer(image, fb);
      }
    }
    ospRelease(fb);
    ospRelease(renderer);
    ospRelease(camera);
    ospRelease(world);
  } catch (const std::exception& e) {
    std::cerr << "volume_bricks: " << e.what() << "\n";
    status = 1;
  }
  ospShutdown();
  MPI_Finalize();
  return errors ? 1 : status;
}
