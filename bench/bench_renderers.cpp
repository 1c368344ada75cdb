// What shadows, ambient occlusion and path tracing cost: whole frames of every renderer
// configuration on standard scenes, per ISA, as pixel samples per CPU second, with the
// primary-ray baseline (scivis without shadows or AO: one camera ray and local shading a
// sample) measured in the same run on the same scene and ISA. The figure of merit is the
// baseline's rate over each configuration's (bench/ratio.py: "cost x primary").
//
// Names: renderer/<isa>/<scene>/<config>, so --benchmark_filter=renderer/avx512/ picks one
// ISA. Configurations: scivis (the baseline), scivis_shadows, scivis_ao4 (aoSamples 4),
// ao1, ao4 (the ao renderer, aoSamples 1 and 4), pathtracer_pl8 (maxPathLength 8). All
// use OSPRay's default aoDistance (1e20: AO rays are unbounded) and one sample per pixel
// per frame.
#include <benchmark/benchmark.h>

#include <exception>
#include <memory>
#include <string>
#include <tuple>

#include "sciray/geometry/molecule.hpp"
#include "sciray/shim/engine.hpp"
#include "sciray/testing/scenes.hpp"

namespace {

constexpr int image_size = 1024;

struct Scene {
  sciray::accel::Device device;
  sciray::shim::EngineWorld world{device};
  sciray::Camera camera;
  std::vector<sciray::Light> lights;
};

/// Builds scene `name` ("molecule_3GQP": the 3GQP protein, ball and stick, from the
/// shared data; otherwise a standard scene) with the lights every renderer gets: the
/// scene's own plus an ambient light of 0.2 (Cornell box), or the tool's default (ambient
/// 0.2 and a distant light of 0.8 from the upper left behind the viewer).
std::unique_ptr<Scene> build(const std::string& name, sciray::simd::Isa isa) {
  auto scene = std::make_unique<Scene>();
  sciray::testing::StandardScene standard;
  if (name == "molecule_3GQP") {
    auto molecule =
        sciray::molecule_geometry(sciray::io::read_pdb(std::string(SCIRAY_DATA_DIR) + "/molecules/3GQP.pdb"),
                                  sciray::MoleculeStyle::ball_and_stick);
    standard.spheres = std::move(molecule.atoms);
    standard.curves = std::move(molecule.bonds);
  } else {
    standard = sciray::testing::standard_scene(name, SCIRAY_DATA_DIR);
  }
  if (standard.mesh) scene->world.add(sciray::TriangleMesh(std::move(*standard.mesh)));
  if (standard.spheres) scene->world.add(sciray::Spheres(std::move(*standard.spheres)));
  if (standard.curves) scene->world.add(sciray::Curves(std::move(*standard.curves)));
  sciray::shim::kernels(isa).commit(scene->world);
  const sciray::PerspectiveCamera view =
      standard.camera ? *standard.camera : sciray::frame_bounds(scene->world.bounds(), 1.f);
  scene->camera = view;
  if (!standard.lights.empty()) {
    scene->lights = standard.lights;
    sciray::AmbientLight ambient;
    ambient.intensity = 0.2f;
    scene->lights.push_back(ambient);
  } else {
    const sciray::Vec3f forward = normalize(view.direction), right = normalize(cross(forward, view.up));
    const sciray::Vec3f up = cross(right, forward);
    scene->lights = sciray::default_lights(normalize(forward + right * 0.5f - up * 0.7f));
  }
  return scene;
}

/// One scene at a time (spheres' own intersector is compiled per ISA, so each ISA commits
/// its own world); benchmarks are registered grouped by (scene, ISA).
const Scene& scene_for(const std::string& name, sciray::simd::Isa isa) {
  static std::pair<std::string, sciray::simd::Isa> cached_key;
  static std::unique_ptr<Scene> cached;
  if (!cached || cached_key != std::pair{name, isa}) {
    cached.reset();
    cached = build(name, isa);
    cached_key = {name, isa};
  }
  return *cached;
}

enum class Config { scivis, scivis_shadows, scivis_ao4, ao1, ao4, pathtracer_pl8 };

constexpr std::pair<Config, const char*> configs[] = {{Config::scivis, "scivis"},
                                                      {Config::scivis_shadows, "scivis_shadows"},
                                                      {Config::scivis_ao4, "scivis_ao4"},
                                                      {Config::ao1, "ao1"},
                                                      {Config::ao4, "ao4"},
                                                      {Config::pathtracer_pl8, "pathtracer_pl8"}};

sciray::shim::RendererConfig renderer_config(Config config, const std::vector<sciray::Light>& lights) {
  switch (config) {
    case Config::scivis:
    case Config::scivis_shadows:
    case Config::scivis_ao4: {
      sciray::SciVisParams p;
      p.lights = lights;
      p.shadows = config == Config::scivis_shadows;
      p.ao_samples = config == Config::scivis_ao4 ? 4 : 0;
      return p;
    }
    case Config::ao1:
    case Config::ao4: {
      sciray::AOParams p;
      p.ao_samples = config == Config::ao1 ? 1 : 4;
      return p;
    }
    case Config::pathtracer_pl8: {
      sciray::PathTracerParams p;
      p.lights = lights;
      p.max_path_length = 8;
      return p;
    }
  }
  return sciray::SciVisParams{};
}

void renderer_frame(benchmark::State& state, std::string scene_name, sciray::simd::Isa isa, Config config) {
  const Scene* found = nullptr;
  try {
    found = &scene_for(scene_name, isa);
  } catch (const std::exception& e) {  // e.g. the shared data is not there
    state.SkipWithError(e.what());
    return;
  }
  const Scene& scene = *found;
  const auto& kernels = sciray::shim::kernels(isa);
  const sciray::shim::RendererConfig renderer = renderer_config(config, scene.lights);
  sciray::FrameBuffer fb(image_size, image_size, sciray::ColorFormat::rgba32f,
                         sciray::channel_color | sciray::channel_accum);
  for (auto _ : state) kernels.render(scene.world, renderer, scene.camera, fb, nullptr, sciray::FrameSettings{});
  const auto samples = static_cast<double>(state.iterations()) * image_size * image_size;
  state.SetItemsProcessed(static_cast<std::int64_t>(samples));
  state.counters["samples_per_second"] = benchmark::Counter(samples, benchmark::Counter::kIsRate);
}

const bool registered = [] {
  for (const char* scene : {"torus_1M", "spheres_1M", "cornell_box", "molecule_3GQP"})
    for (auto isa : sciray::simd::all_isas) {
      if (!sciray::simd::cpu_supports(isa)) continue;
      for (const auto& [config, config_name] : configs)
        benchmark::RegisterBenchmark(
            ("renderer/" + std::string(sciray::simd::isa_name(isa)) + "/" + scene + "/" + config_name).c_str(),
            renderer_frame, std::string(scene), isa, config)
            ->Unit(benchmark::kMillisecond)
            ->MeasureProcessCPUTime();
    }
  return true;
}();

}  // namespace
