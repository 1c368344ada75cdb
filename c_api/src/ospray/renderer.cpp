// OSPRay's renderers: scivis, ao, pathtracer and mpiRaycast.
#include "scene_common.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <type_traits>

#include "sciray/distributed/mpi_raycast.hpp"

namespace sciray::ospray {

void Renderer::on_commit() {
  const auto common = [&](auto params) {
    const auto background = get_color4("backgroundColor", {0.f, 0.f, 0.f, 0.f});
    params.background_color = {background[0], background[1], background[2]};
    params.background_alpha = background[3];
    params.max_path_length = get_int("maxPathLength", params.max_path_length);
    params.min_contribution = get_float("minContribution", params.min_contribution);
    params.volume_sampling_rate = get_float("volumeSamplingRate", params.volume_sampling_rate);
    // sciray's own: how volumes are integrated (VolumeIntegration).
    if (const Param* p = find("volumeIntegration")) {
      if (p->type != OSP_STRING)
        throw Error(name() + ": parameter 'volumeIntegration' must be a string, got " + type_name(p->type));
      if (p->string == "preintegrated")
        params.volume_preintegration = true;
      else if (p->string == "exact")
        params.volume_exact = true;
      else if (p->string != "sampled")
        throw Error(name() + ": parameter 'volumeIntegration' has unknown value '" + p->string +
                    "' (sampled, preintegrated, exact)");
    }
    if (auto* backplate = get_object<TextureObject>("map_backplate", OSP_TEXTURE, false)) {
      if (!backplate->committed() || !backplate->image())
        throw Error(name() + ": parameter 'map_backplate' must be a committed texture2d");
      params.backplate = backplate->image();
      params.backplate_alpha = backplate->alpha_image();
    }
    // Texels are finite and not negative (texture2d checks them): every depth is valid.
    if (auto* max_depth = get_object<TextureObject>("map_maxDepth", OSP_TEXTURE, false)) {
      if (!max_depth->committed() || !max_depth->image())
        throw Error(name() + ": parameter 'map_maxDepth' must be a committed texture2d");
      params.max_depth = max_depth->image();
    }
    return params;
  };
  shim::RendererConfig config;
  if (subtype() == "scivis") {
    SciVisParams p = common(SciVisParams{});
    p.shadows = get_bool("shadows", p.shadows);
    p.visible_lights = get_bool("visibleLights", p.visible_lights);
    p.ao_samples = get_int("aoSamples", p.ao_samples);
    p.ao_distance = get_float("aoDistance", p.ao_distance);
    config = p;
  } else if (subtype() == "ao" || subtype() == "mpiRaycast") {
    // mpiRaycast (OSPRay's data-parallel renderer) is ao with its own defaults.
    AOParams p = common(subtype() == "ao" ? AOParams{} : distributed::mpi_raycast_params());
    p.ao_samples = get_int("aoSamples", p.ao_samples);
    p.ao_distance = get_float("aoDistance", p.ao_distance);
    p.ao_intensity = get_float("aoIntensity", p.ao_intensity);
    config = p;
  } else {
    PathTracerParams p = common(PathTracerParams{});
    p.roulette_path_length = get_int("roulettePathLength", p.roulette_path_length);
    p.max_contribution = get_float("maxContribution", p.max_contribution);
    p.geometry_lights = get_bool("geometryLights", p.geometry_lights);
    p.light_samples = get_int("lightSamples", p.light_samples);
    p.background_refraction = get_bool("backgroundRefraction", p.background_refraction);
    config = p;
  }
  // What the renderers check of their parameters, checked now with no lights or materials.
  std::visit(
      [&](const auto& p) {
        validate(p, 0, subtype());  // names "<type> renderer: parameter ..."
        if constexpr (!std::is_same_v<std::decay_t<decltype(p)>, PathTracerParams>) {
          if (p.ao_samples < 0) throw Error(name() + ": parameter 'aoSamples' must not be negative");
          if (!(p.ao_distance > 0.f)) throw Error(name() + ": parameter 'aoDistance' must be positive");
        } else {
          if (p.roulette_path_length < 0) throw Error(name() + ": parameter 'roulettePathLength' must not be negative");
          if (!(p.max_contribution > 0.f)) throw Error(name() + ": parameter 'maxContribution' must be positive");
        }
      },
      config);
  std::vector<Ref<Material>> materials;
  if (const Data* list = get_data(*this, find("material"), "material", {OSP_MATERIAL}))
    for (std::size_t i = 0; i < list->size(); ++i) {
      auto* material = static_cast<Material*>(list->object(i));
      if (!material || !material->committed())
        throw Error(name() + ": parameter 'material' element " + std::to_string(i) + " is not a committed material");
      materials.emplace_back(material);
    }
  FrameSettings settings;
  settings.pixel_samples = get_int("pixelSamples", 1);
  settings.variance_threshold = get_float("varianceThreshold", 0.f);
  try {
    settings.pixel_filter = pixel_filter_from_int(get_int("pixelFilter", static_cast<int>(PixelFilter::gauss)));
    validate(settings);
  } catch (const Error& e) {
    throw Error(name() + ": parameter " + e.what());
  }
  config_ = std::move(config);
  settings_ = settings;
  materials_ = std::move(materials);
}

shim::RendererConfig Renderer::config(const BuiltWorld& world) const {
  shim::RendererConfig config = config_;
  std::visit(
      [&](auto& p) {
        p.lights = world.lights;
        p.moving_lights = world.moving_lights;
        p.materials = world.materials;
        // Models' indices into the renderer's `material` list; as OSPRay, an index
        // beyond it shows the default obj material.
        for (const BuiltWorld::RendererMaterial& r : world.renderer_materials) {
          if (r.index >= materials_.size()) continue;
          const Material& m = *materials_[r.index];
          const auto base = m.base_color();
          p.materials[r.entry] = r.tint && base ? m.with_base_color(*r.tint * *base) : m.material();
        }
      },
      config);
  return config;
}

}  // namespace sciray::ospray
