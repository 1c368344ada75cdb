// The renderers' convergence, for bench/charts.py: renders a standard scene with one
// renderer configuration frame after frame into an accumulating RGBA32F frame buffer and
// writes the accumulated image at chosen frame counts (checkpoints), with the render time
// spent up to each. The `sciray` tool renders one image per run and has no switch for the
// path tracer's light sampling; this does one run per curve and has.
//
//   sciray_render_sweep --renderer pathtracer --light-sampling mis --checkpoints 1,2,4,8
//       --out /tmp/pt_ [--scene cornell_box] [--size 128x128] [--isa auto] [--threads 0]
//       [--spp 1] [--shadows] [--ao-samples N] [--ao-distance D] [--ambient I]
//       [--max-path-length N]
//       [--volume FILE.raw [--albedo A] [--extinction S] [--anisotropy G]]
//       [--sphere-light X,Y,Z,RADIUS,INTENSITY]
//
// --volume renders a real volume (io::read_volume) instead of --scene, as a participating
// medium: a grey transfer function of colour (single-scattering albedo) A whose opacity
// rises linearly from 0 to S over the value range (densityScale 1, so S is the densest
// extinction per world unit), Henyey–Greenstein anisotropy G, seen along +y from in front
// of the volume. --sphere-light replaces the scene's lights with a sphere light (radiant
// intensity INTENSITY); --ambient adds to either.
//
// writes /tmp/pt_<frames>.pfm per checkpoint and prints one JSON object:
//   {"isa": ..., "threads": ..., "width": ..., "height": ..., "spp": ...,
//    "checkpoints": [{"frames": F, "wall_s": ..., "cpu_s": ..., "file": ...}, ...]}
// where wall_s and cpu_s are the render calls' wall-clock and process CPU seconds summed
// over frames 1..F (image writing is not counted).
#include <tbb/info.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <ctime>
#include <exception>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "sciray/io/frame_io.hpp"
#include "sciray/io/volume.hpp"
#include "sciray/shim/engine.hpp"
#include "sciray/testing/scenes.hpp"

namespace {

struct Options {
  std::string scene = "cornell_box";
  int width = 128, height = 128;
  std::string isa = "auto";
  int threads = 0;
  std::string renderer = "pathtracer";
  std::string light_sampling = "mis";
  int spp = 1;
  bool shadows = false;
  int ao_samples = -1;  // -1: the renderer's default
  float ao_distance = 1e20f;
  float ambient = 0.f;  // > 0: add an ambient light of this intensity to the scene's lights
  int max_path_length = 20;
  std::string volume;  // a volume file instead of `scene`
  float albedo = 0.8f, extinction = 0.15f, anisotropy = 0.f;
  std::vector<float> sphere_light;  // x, y, z, radius, intensity
  std::vector<int> checkpoints{1};
  std::string out = "sweep_";
};

double cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

std::vector<float> parse_floats(const std::string& arg, const std::string& text, std::size_t count) {
  std::vector<float> values;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) values.push_back(std::stof(item));
  if (values.size() != count)
    throw sciray::Error(arg + ": expected " + std::to_string(count) + " comma-separated numbers, got '" + text + "'");
  return values;
}

std::vector<int> parse_ints(const std::string& text) {
  std::vector<int> values;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) values.push_back(std::stoi(item));
  if (values.empty() || !std::is_sorted(values.begin(), values.end()) || values.front() < 1)
    throw sciray::Error("--checkpoints: expected increasing frame counts >= 1, got '" + text + "'");
  return values;
}

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const auto value = [&]() -> std::string {
      if (i + 1 >= argc) throw sciray::Error(arg + " needs a value");
      return argv[++i];
    };
    if (arg == "--scene")
      o.scene = value();
    else if (arg == "--size") {
      const std::string s = value();
      if (std::sscanf(s.c_str(), "%dx%d", &o.width, &o.height) != 2 || o.width <= 0 || o.height <= 0)
        throw sciray::Error("--size: expected WxH, got '" + s + "'");
    } else if (arg == "--isa")
      o.isa = value();
    else if (arg == "--threads")
      o.threads = std::stoi(value());
    else if (arg == "--renderer")
      o.renderer = value();
    else if (arg == "--light-sampling")
      o.light_sampling = value();
    else if (arg == "--spp")
      o.spp = std::stoi(value());
    else if (arg == "--shadows")
      o.shadows = true;
    else if (arg == "--ao-samples")
      o.ao_samples = std::stoi(value());
    else if (arg == "--ao-distance")
      o.ao_distance = std::stof(value());
    else if (arg == "--ambient")
      o.ambient = std::stof(value());
    else if (arg == "--max-path-length")
      o.max_path_length = std::stoi(value());
    else if (arg == "--volume")
      o.volume = value();
    else if (arg == "--albedo")
      o.albedo = std::stof(value());
    else if (arg == "--extinction")
      o.extinction = std::stof(value());
    else if (arg == "--anisotropy")
      o.anisotropy = std::stof(value());
    else if (arg == "--sphere-light")
      o.sphere_light = parse_floats(arg, value(), 5);
    else if (arg == "--checkpoints")
      o.checkpoints = parse_ints(value());
    else if (arg == "--out")
      o.out = value();
    else
      throw sciray::Error("unknown argument '" + arg + "' (see the comment at the top of bench/render_sweep.cpp)");
  }
  return o;
}

/// The renderer of `o` with `lights` (not for ao) and the scene's `materials`.
sciray::shim::RendererConfig renderer_config(const Options& o, const std::vector<sciray::Light>& lights,
                                             const std::vector<sciray::Material>& materials) {
  const auto common = [&](auto params) {
    params.lights = lights;
    params.materials = materials;
    params.max_path_length = o.max_path_length;
    return params;
  };
  if (o.renderer == "scivis") {
    auto p = common(sciray::SciVisParams{});
    p.shadows = o.shadows;
    if (o.ao_samples >= 0) p.ao_samples = o.ao_samples;
    p.ao_distance = o.ao_distance;
    return p;
  }
  if (o.renderer == "ao") {
    sciray::AOParams p;  // no lights: ambient occlusion alone
    p.materials = materials;
    p.max_path_length = o.max_path_length;
    if (o.ao_samples >= 0) p.ao_samples = o.ao_samples;
    p.ao_distance = o.ao_distance;
    return p;
  }
  if (o.renderer == "pathtracer") {
    auto p = common(sciray::PathTracerParams{});
    if (o.light_sampling == "mis")
      p.light_sampling = sciray::LightSampling::mis;
    else if (o.light_sampling == "lights_only")
      p.light_sampling = sciray::LightSampling::lights_only;
    else if (o.light_sampling == "bsdf_only")
      p.light_sampling = sciray::LightSampling::bsdf_only;
    else
      throw sciray::Error("--light-sampling: expected mis, lights_only or bsdf_only, got '" + o.light_sampling + "'");
    return p;
  }
  throw sciray::Error("--renderer: expected scivis, ao or pathtracer, got '" + o.renderer + "'");
}

/// Adds the volume file of `o` to `world` as a scattering medium (see the top comment).
void add_volume(sciray::shim::EngineWorld& world, const sciray::io::VolumeFile& file, const Options& o) {
  const auto add = [&](auto voxel_tag) {
    using Voxel = decltype(voxel_tag);
    auto volume = std::make_shared<const sciray::StructuredRegular<Voxel>>(
        sciray::LinearLayout<Voxel>(reinterpret_cast<const Voxel*>(file.voxels->data()), file.dims, file.voxels),
        file.grid);
    const std::array<float, 2> range = file.range ? *file.range : volume->value_range();
    world.add_volume(sciray::VolumetricModel(
        volume, sciray::TransferFunction({{o.albedo, o.albedo, o.albedo}}, {0.f, o.extinction}, range), 1.f,
        o.anisotropy));
  };
  switch (file.kind) {
    case sciray::io::VoxelKind::uint8: add(std::uint8_t{}); break;
    case sciray::io::VoxelKind::int16: add(std::int16_t{}); break;
    case sciray::io::VoxelKind::uint16: add(std::uint16_t{}); break;
    case sciray::io::VoxelKind::float32: add(float{}); break;
    case sciray::io::VoxelKind::float64: add(double{}); break;
  }
}

int run(const Options& o) {
  const sciray::simd::Isa isa = sciray::shim::select_isa(o.isa);
  const auto& kernels = sciray::shim::kernels(isa);
  const int threads = o.threads > 0 ? o.threads : tbb::info::default_concurrency();
  sciray::testing::StandardScene standard =
      o.volume.empty() ? sciray::testing::standard_scene(o.scene, SCIRAY_DATA_DIR) : sciray::testing::StandardScene{};
  sciray::accel::Device device;
  sciray::shim::EngineWorld world(device);
  if (!o.volume.empty()) add_volume(world, sciray::io::read_volume(o.volume), o);
  // A scene's material (if it has one) shades all its geometry.
  std::vector<sciray::Material> materials;
  if (standard.material) materials.push_back(*standard.material);
  const std::uint32_t material = materials.empty() ? sciray::no_material : 0;
  if (standard.mesh) world.add(sciray::TriangleMesh(std::move(*standard.mesh)), material);
  if (standard.spheres) world.add(sciray::Spheres(std::move(*standard.spheres)), material);
  if (standard.curves) world.add(sciray::Curves(std::move(*standard.curves)), material);
  kernels.commit(world);
  if (!o.volume.empty()) {
    // In front of the volume looking along +y, the box filling the height of a 40° view.
    const sciray::Box3f box = world.bounds();
    const sciray::Vec3f centre = 0.5f * (box.lower + box.upper), size = box.upper - box.lower;
    sciray::PerspectiveCamera front;
    front.position = centre - sciray::Vec3f{0.f, 1.42f * size.y, 0.f};
    front.direction = {0.f, 1.f, 0.f};
    front.up = {0.f, 0.f, 1.f};
    front.fovy = 40.f;
    standard.camera = front;
  }
  const float aspect = static_cast<float>(o.width) / static_cast<float>(o.height);
  sciray::PerspectiveCamera camera = standard.camera ? *standard.camera : sciray::frame_bounds(world.bounds(), aspect);
  camera.aspect = aspect;
  std::vector<sciray::Light> lights = standard.lights.empty() ? sciray::default_lights() : standard.lights;
  if (!o.sphere_light.empty()) {
    sciray::SphereLight lamp;
    lamp.position = {o.sphere_light[0], o.sphere_light[1], o.sphere_light[2]};
    lamp.radius = o.sphere_light[3];
    lamp.intensity = o.sphere_light[4];
    lights = {lamp};
  }
  if (o.ambient > 0.f) {
    sciray::AmbientLight ambient;
    ambient.intensity = o.ambient;
    lights.push_back(ambient);
  }
  const sciray::shim::RendererConfig config = renderer_config(o, lights, materials);
  const sciray::Camera view = camera;
  sciray::FrameSettings settings;
  settings.pixel_samples = o.spp;

  sciray::FrameBuffer fb(o.width, o.height, sciray::ColorFormat::rgba32f,
                         sciray::channel_color | sciray::channel_accum);
  std::ostringstream checkpoints;
  double wall = 0, cpu = 0;
  tbb::task_arena arena(threads);
  arena.execute([&] {
    std::size_t next = 0;
    for (int frame = 1; frame <= o.checkpoints.back(); ++frame) {
      const auto wall0 = std::chrono::steady_clock::now();
      const double cpu0 = cpu_seconds();
      kernels.render(world, config, view, fb, nullptr, settings);
      cpu += cpu_seconds() - cpu0;
      wall += std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
      if (frame == o.checkpoints[next]) {
        const std::string file = o.out + std::to_string(frame) + ".pfm";
        sciray::io::write_color(fb, file);
        checkpoints << (next ? ", " : "") << "{\"frames\": " << frame << ", \"wall_s\": " << wall
                    << ", \"cpu_s\": " << cpu << ", \"file\": \"" << file << "\"}";
        ++next;
      }
    }
  });
  std::cout << "{\"isa\": \"" << sciray::simd::isa_name(isa) << "\", \"threads\": " << threads
            << ", \"width\": " << o.width << ", \"height\": " << o.height << ", \"spp\": " << o.spp
            << ", \"checkpoints\": [" << checkpoints.str() << "]}\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(parse(argc, argv));
  } catch (const std::exception& e) {
    std::cerr << "sciray_render_sweep: error: " << e.what() << "\n";
    return 1;
  }
}
