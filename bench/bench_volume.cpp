// Volumes: the sampler's throughput per ISA (scalar against W = 4/8/16, linear against
// bricked layout) on a 256³ float volume, and whole frames of the real volumes in the
// same run: scivis ray marching with and without empty-space skipping, and the path
// tracer scattering in them (delta tracking, up to 8 bounces).
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "sciray/io/volume.hpp"
#include "sciray/shim/engine.hpp"
#include "sciray/testing/scenes.hpp"

namespace {

constexpr std::int64_t sampler_size = 256;

/// A smooth 256³ field (a sum of sines), its random sample positions, in both layouts.
struct SamplerData {
  std::shared_ptr<std::vector<float>> voxels = std::make_shared<std::vector<float>>();
  std::unique_ptr<sciray::StructuredRegular<float>> linear;
  std::unique_ptr<sciray::StructuredRegular<float, sciray::BrickedLayout>> bricked;
  std::vector<sciray::Vec3f> positions;
  std::vector<float> out;

  SamplerData() {
    const sciray::VolumeDims d{sampler_size, sampler_size, sampler_size};
    voxels->reserve(static_cast<std::size_t>(d[0] * d[1] * d[2]));
    for (std::int64_t z = 0; z < d[2]; ++z)
      for (std::int64_t y = 0; y < d[1]; ++y)
        for (std::int64_t x = 0; x < d[0]; ++x)
          voxels->push_back(std::sin(0.05f * x) + std::sin(0.07f * y) * std::cos(0.03f * z));
    linear = std::make_unique<sciray::StructuredRegular<float>>(sciray::LinearLayout<float>(voxels->data(), d, voxels),
                                                                 sciray::VolumeGrid{});
    bricked = std::make_unique<sciray::StructuredRegular<float, sciray::BrickedLayout>>(
        sciray::BrickedLayout<float>(voxels->data(), d), sciray::VolumeGrid{});
    for (std::uint64_t i = 0; i < 1 << 20; ++i)
      positions.push_back(sciray::Vec3f{sciray::testing::hash_uniform(3 * i), sciray::testing::hash_uniform(3 * i + 1),
                                        sciray::testing::hash_uniform(3 * i + 2)} *
                          static_cast<float>(sampler_size - 1));
    out.resize(positions.size());
  }
};

SamplerData& sampler_data() {
  static SamplerData data;
  return data;
}

void sample(benchmark::State& state, sciray::simd::Isa isa, bool bricked) {
  SamplerData& data = sampler_data();
  const auto& kernels = sciray::shim::kernels(isa);
  for (auto _ : state) {
    if (bricked)
      kernels.sample_bricked_volume(*data.bricked, data.positions, data.out);
    else
      kernels.sample_volume(*data.linear, data.positions, data.out);
    benchmark::DoNotOptimize(data.out.data());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(data.positions.size()));
}

enum class VolumeRenderer { skipping, every_sample, pathtracer };

/// A real volume rendered at 512² with its default transfer function (the tool's).
void volume_frame(benchmark::State& state, sciray::simd::Isa isa, const std::string& name, VolumeRenderer renderer) {
  static std::string loaded;
  static std::unique_ptr<sciray::accel::Device> device;
  static std::unique_ptr<sciray::shim::EngineWorld> world;
  static sciray::io::VolumeFile file;
  if (loaded != name) {
    world.reset();
    device = std::make_unique<sciray::accel::Device>();
    world = std::make_unique<sciray::shim::EngineWorld>(*device);
    file = sciray::io::read_volume(std::string(SCIRAY_DATA_DIR) + "/volumes/" + name);
    const auto* voxels = reinterpret_cast<const std::uint8_t*>(file.voxels->data());
    auto volume = std::make_shared<const sciray::StructuredRegular<std::uint8_t>>(
        sciray::LinearLayout<std::uint8_t>(voxels, file.dims, file.voxels), file.grid);
    std::vector<sciray::Vec3f> colors;
    for (int i = 0; i < 8; ++i) colors.push_back(sciray::testing::colormap(i / 7.f));
    world->add_volume(sciray::VolumetricModel(volume, sciray::TransferFunction(colors, {0.f, 1.f}, {0.f, 255.f}),
                                              4.f / length(volume->bounds().size())));
    loaded = name;
  }
  const auto& kernels = sciray::shim::kernels(isa);
  kernels.commit(*world);
  sciray::shim::RendererConfig config;
  if (renderer == VolumeRenderer::pathtracer) {
    sciray::PathTracerParams params;
    params.max_path_length = 8;
    config = params;
  } else {
    sciray::SciVisParams params;
    params.empty_space_skipping = renderer == VolumeRenderer::skipping;
    config = params;
  }
  sciray::FrameBuffer fb(512, 512, sciray::ColorFormat::srgba, sciray::channel_color | sciray::channel_accum);
  const sciray::Camera camera = sciray::frame_bounds(world->bounds(), 1.f);
  for (auto _ : state) kernels.render(*world, config, camera, fb, nullptr, sciray::FrameSettings{});
  state.SetItemsProcessed(state.iterations() * 512 * 512);
}

const bool registered = [] {
  for (auto isa : sciray::simd::all_isas) {
    if (!sciray::simd::cpu_supports(isa)) continue;
    const std::string isa_name(sciray::simd::isa_name(isa));
    for (bool bricked : {false, true})
      benchmark::RegisterBenchmark(("volume/sample/" + isa_name + (bricked ? "/bricked" : "/linear")).c_str(), sample,
                                   isa, bricked)
          ->Unit(benchmark::kMillisecond)
          ->MeasureProcessCPUTime();
  }
  for (const char* name : {"embryo_256x256x256_uint8.raw", "neghip_66x66x66_uint8.raw"})
    for (auto isa : sciray::simd::all_isas) {
      if (!sciray::simd::cpu_supports(isa)) continue;
      for (const auto& [renderer, label] : {std::pair{VolumeRenderer::skipping, "/skipping"},
                                            std::pair{VolumeRenderer::every_sample, "/every_sample"},
                                            std::pair{VolumeRenderer::pathtracer, "/pathtracer_pl8"}})
        benchmark::RegisterBenchmark(("frame/volume/" + std::string(sciray::simd::isa_name(isa)) + "/" +
                                      std::string(name).substr(0, std::string(name).find('_')) + label)
                                         .c_str(),
                                     volume_frame, isa, std::string(name), renderer)
            ->Unit(benchmark::kMillisecond)
            ->MeasureProcessCPUTime();
    }
  return true;
}();

}  // namespace
