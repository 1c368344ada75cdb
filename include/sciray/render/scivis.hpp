#pragma once
// The `scivis` renderer, first cut: OpenGL-like local shading of the first hit with
// per-vertex or per-face colours, (interpolated) normals, one directional light and
// ambient light, two-sided as visualization data is rarely closed; volumes of a
// VolumeWorld integrated in front of that hit and composited over it. Later issues add
// shadows, ambient occlusion and transparency.
#include <cmath>
#include <limits>

#include "sciray/accel/trace.hpp"
#include "sciray/math/affine.hpp"
#include "sciray/math/vec.hpp"
#include "sciray/render/sample.hpp"
#include "sciray/volume/volumetric_model.hpp"

namespace sciray {

struct SciVisParams {
  Vec3f background_color{0.f, 0.f, 0.f};
  float background_alpha = 0.f;
  Vec3f default_color{0.8f, 0.8f, 0.8f};  ///< where the geometry has no colours
  Vec3f ambient_color{1.f, 1.f, 1.f};
  float ambient_intensity = 0.2f;
  Vec3f light_direction{0.f, 0.f, -1.f};  ///< the direction the light travels (OSPRay 'distant')
  Vec3f light_color{1.f, 1.f, 1.f};
  float light_intensity = 0.8f;
  float volume_sampling_rate = 1.f;   ///< OSPRay's volumeSamplingRate: samples per cell
  bool empty_space_skipping = true;
  bool volume_gradient_shading = false;
  bool volume_preintegration = false;  ///< see VolumeIntegration::preintegration
  bool volume_adaptive_sampling = false;  ///< see VolumeIntegration::adaptive_sampling
};

template <class Arch, class WorldT>
class SciVis {
public:
  using F = simd::Float<Arch>;
  using M = simd::Mask<Arch>;

  SciVis(const WorldT& world, const SciVisParams& params)
      : world_(&world), params_(params), to_light_(-normalize(params.light_direction)) {}

  PixelSample<Arch> render(const Ray<F>& ray, const M& active, const SampleIndex<Arch>& = {}) const {
    const auto hit = accel::intersect<Arch>(world_->scene(), ray, active, true, world_->hit_filter());
    PixelSample<Arch> out;
    out.color = Vec3<F>(params_.background_color);
    out.alpha = F(params_.background_alpha);
    out.t = simd::select(hit.hit, hit.t, F(std::numeric_limits<float>::infinity()));
    if (simd::any(hit.hit)) shade_surfaces(ray, hit, out);
    if constexpr (requires { world_->volume_count(); })
      if (world_->volume_count()) composite_volumes(ray, active, out);
    return out;
  }

private:
  void shade_surfaces(const Ray<F>& ray, const accel::Hit<Arch>& hit, PixelSample<Arch>& out) const {

    // A packet usually hits one geometry; shade each (instance, geometry)'s lanes together.
    M remaining = hit.hit;
    while (simd::any(remaining)) {
      const int lane = first_lane(remaining);
      const std::int32_t geom_id = simd::lane(hit.geom_id, lane), inst_id = simd::lane(hit.inst_id, lane);
      const M lanes = remaining & (simd::to_float(hit.geom_id) == F(static_cast<float>(geom_id))) &
                      (simd::to_float(hit.inst_id) == F(static_cast<float>(inst_id)));
      world_->visit_hit(static_cast<std::uint32_t>(inst_id), static_cast<std::uint32_t>(geom_id),
                        [&](const auto& geometry, const Affine3f* transform) {
                          auto surface = geometry.template surface<Arch>(hit, lanes);
                          // Instanced hits come back in the group's space.
                          if (transform) surface.normal = normalize(transform->normal(surface.normal));
                          out.color = select(lanes, shade(ray, surface), out.color);
                        });
      out.alpha = simd::select(lanes, F(1.f), out.alpha);
      remaining = remaining & !lanes;
    }
  }

  /// Volumes in front of the surface hit (or the background), composited over it. Each
  /// volume is integrated on its own, so overlapping volumes are composited in the order
  /// they were added rather than interleaved.
  void composite_volumes(const Ray<F>& ray, const M& active, PixelSample<Arch>& out) const {
    VolumeIntegration how;
    how.sampling_rate = params_.volume_sampling_rate;
    how.empty_space_skipping = params_.empty_space_skipping;
    how.gradient_shading = params_.volume_gradient_shading;
    how.to_light = to_light_;
    how.clipping = world_->clipping();
    how.preintegration = params_.volume_preintegration;
    how.adaptive_sampling = params_.volume_adaptive_sampling;
    world_->for_each_volume([&](const auto& model) {
      const VolumeSample<Arch> v = model.template integrate<Arch>(ray, active, out.t, how);
      out.color = v.color + out.color * (F(1.f) - v.alpha);
      out.alpha = v.alpha + out.alpha * (F(1.f) - v.alpha);
    });
  }

  template <class Surface>
  Vec3<F> shade(const Ray<F>& ray, const Surface& s) const {
    // Face the normal towards the viewer: both sides of a surface are lit.
    const F facing = dot(s.normal, ray.dir);
    const Vec3<F> n = select(facing > F(0.f), -s.normal, s.normal);
    const F diffuse = simd::max(F(0.f), dot(n, Vec3<F>(to_light_)));
    const Vec3<F> albedo = select(s.has_color, s.color, Vec3<F>(params_.default_color));
    const Vec3<F> light = Vec3<F>(params_.ambient_color * params_.ambient_intensity) +
                          Vec3<F>(params_.light_color * params_.light_intensity) * diffuse;
    return albedo * light;
  }

  static int first_lane(const M& mask) {
    for (int i = 0; i < simd::width<Arch>; ++i)
      if (simd::lane(mask, i)) return i;
    return 0;
  }

  const WorldT* world_;
  SciVisParams params_;
  Vec3f to_light_;
};

}  // namespace sciray
