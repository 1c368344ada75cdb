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
//
// writes /tmp/pt_<frames>.pfm per checkpoint and prints one JSON object:
//   {"isa": ..., "threads": ..., "width": ..., "height": ..., "spp": ...,
//    "checkpoints": [{"frames": F, "wall_s": ..., "cpu_s": ..., "file": ...}, ...]}
// where wall_s and cpu_s are the render calls' wall-clock and process CPU seconds summed
// over frames 1..F (image writing is not counted).
#include <tbb/info.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <exception>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "sciray/io/frame_io.hpp"
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
  std::vector<int> checkpoints{1};
  std::string out = "sweep_";
};

double cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
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

int run(const Options& o) {
  const sciray::simd::Isa isa = sciray::shim::select_isa(o.isa);
  const auto& kernels = sciray::shim::kernels(isa);
  const int threads = o.threads > 0 ? o.threads : tbb::info::default_concurrency();
  sciray::testing::StandardScene standard = sciray::testing::standard_scene(o.scene, SCIRAY_DATA_DIR);
  sciray::accel::Device device;
  sciray::shim::EngineWorld world(device);
  // A scene's material (if it has one) shades all its geometry.
  std::vector<sciray::Material> materials;
  if (standard.material) materials.push_back(*standard.material);
  const std::uint32_t material = materials.empty() ? sciray::no_material : 0;
  if (standard.mesh) world.add(sciray::TriangleMesh(std::move(*standard.mesh)), material);
  if (standard.spheres) world.add(sciray::Spheres(std::move(*standard.spheres)), material);
  if (standard.curves) world.add(sciray::Curves(std::move(*standard.curves)), material);
  kernels.commit(world);
  const float aspect = static_cast<float>(o.width) / static_cast<float>(o.height);
  sciray::PerspectiveCamera camera = standard.camera ? *standard.camera : sciray::frame_bounds(world.bounds(), aspect);
  camera.aspect = aspect;
  std::vector<sciray::Light> lights = standard.lights.empty() ? sciray::default_lights() : standard.lights;
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
