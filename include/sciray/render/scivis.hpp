#pragma once
// The `scivis` and `ao` renderers: fast, OpenGL-like local shading for visualization,
// with the depth cues of ray tracing where asked for.
//
// scivis: kd (times the geometry's colour) lit by every light: ambient lights scaled by
// the unoccluded fraction of `aoSamples` cosine-weighted rays within `aoDistance`;
// other lights with OSPRay's normalized BRDF — Lambertian kd/π plus Blinn-Phong `ks` of
// exponent 4 `ns` — so that a white surface facing a distant light of irradiance 1 shows
// 1/π, as in OSPRay and the path tracer; each light is sampled once, where OSPRay's scivis
// samples it (the centre of a disk, sphere or cone, a quad light's centre),
// so shadows are hard when `shadows` is set — soft shadows are the path tracer's; with
// them, as in OSPRay, a light adds nothing where its unshadowed contribution is not above
// `minContribution`. Surfaces with opacity `d` < 1 or a transmissive filter `tf` let
// the ray continue, up to `maxPathLength` surfaces; shadows are tinted by them too.
// Volumes are integrated on the same rays, between surfaces. Both see the shutter's
// middle instant through the lens centre, as OSPRay's (LocalRendererParams).
//
// ao: OSPRay's ao renderer, an eye light: kd times |n·ω| (the surface as lit from the
// camera), dimmed by occlusion as `aoIntensity` says — times 1 - aoIntensity + aoIntensity
// times the unoccluded fraction of `aoSamples` rays (no dimming without samples); other
// lights play no part. Volumes as scivis's (unlit); surfaces let 1 - d through, untinted
// (OSPRay's ao has no tf), and block AO rays whatever their opacity (measured with OSPRay
// 3.1's runtime: a kd 0 / tf 0.8 sheet shows black; a floor under a sheet of d 0.3 is as
// occluded as under an opaque one).
//
// Shading runs on packets: the lanes of a packet that hit one geometry share a material,
// and the directional and ambient lights are the same for every lane. A material with
// texture maps is resolved lane by lane at each hit's texture coordinates (textured());
// materials without maps take the packet-wide values, as cheaply as before.
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <type_traits>

#include "sciray/math/random_lanes.hpp"
#include "sciray/render/common.hpp"

namespace sciray {

/// What scivis and ao share. Their camera rays see the shutter's middle instant through
/// the lens centre, as OSPRay's do (motion blur and depth of field are the path tracer's),
/// unless `sample_lens_and_shutter` is set.
struct LocalRendererParams : RendererParams {
  bool sample_lens_and_shutter = false;
  /// Whether the geometry colours' alpha is opacity (as OSPRay's scivis and ao read it;
  /// its data-parallel mpiRaycast takes opacity from the material's `d` alone).
  bool color_alpha_is_opacity = true;
};

struct SciVisParams : LocalRendererParams {
  bool shadows = false;
  /// visibleLights: camera rays (and rays through transparent surfaces) see the lights
  /// with size and `visible` set, as OSPRay's scivis; the hdri light is the background.
  bool visible_lights = false;
  int ao_samples = 0;                   ///< aoSamples
  float ao_distance = 1e20f;            ///< aoDistance
};

struct AOParams : LocalRendererParams {
  AOParams() { lights.clear(); }
  int ao_samples = 1;
  float ao_distance = 1e20f;
  float ao_intensity = 1.f;  ///< aoIntensity
  /// Whether a surface of opacity d adds d times its colour (ao's over operator), or, as
  /// OSPRay's data-parallel mpiRaycast does, its whole colour; either way 1 - d of what lies
  /// behind shows through.
  bool opacity_weights_color = true;
};

namespace detail {

template <class Arch>
simd::Float<Arch> pow(const simd::Float<Arch>& x, const simd::Float<Arch>& e) {
  if constexpr (std::is_same_v<Arch, simd::scalar>)
    return std::pow(x, e);
  else
    return xsimd::pow(x, e);
}

template <class Arch>
simd::Float<Arch> exp(const simd::Float<Arch>& x) {
  if constexpr (std::is_same_v<Arch, simd::scalar>)
    return std::exp(x);
  else
    return xsimd::exp(x);
}

/// Whether `m` has a map that changes its opacity or what passes it (obj map_d or map_kd's
/// alpha; principled map_opacity, map_baseColor's alpha, map_transmission or
/// map_transmissionColor).
inline bool opacity_mapped(const Material& m) {
  if (const auto* obj = std::get_if<ObjMaterial>(&m)) return obj->map_d || obj->map_kd.alpha;
  if (const auto* principled = std::get_if<PrincipledMaterial>(&m))
    return principled->map_opacity || principled->map_base_color.alpha || principled->map_transmission ||
           principled->map_transmission_color;
  return false;
}

/// Local shading shared by scivis and ao; `Params` picks which.
template <class Arch, class WorldT, class Params>
class LocalRenderer {
public:
  using F = simd::Float<Arch>;
  using I = simd::Int<Arch>;
  using M = simd::Mask<Arch>;
  static constexpr int W = simd::width<Arch>;
  static constexpr bool is_ao = std::is_same_v<Params, AOParams>;

  LocalRenderer(const WorldT& world, const Params& params)
      : world_(&world),
        params_(params),
        camera_volumes_(volume_integration(world, params)),
        light_volumes_(volume_integration(world, params, 0.25f)),
        ao_volumes_(volume_integration(world, params, 0.1f)) {
    validate(params_, world.materials_needed(), is_ao ? "ao" : "scivis");
    if (params_.ao_samples < 0) throw Error(std::string(is_ao ? "ao" : "scivis") + " renderer: parameter 'aoSamples' must not be negative");
    if (!(params_.ao_distance > 0.f)) throw Error(std::string(is_ao ? "ao" : "scivis") + " renderer: parameter 'aoDistance' must be positive");
    for (const Material& m : params_.materials) {
      surfaces_.push_back(obj_view(m));
      luminous_.push_back(std::holds_alternative<LuminousMaterial>(m));
      textured_.push_back(has_maps(m));
      normal_mapped_.push_back(has_normal_map(m));
      opacity_mapped_.push_back(opacity_mapped(m));
      const ObjMaterial& o = surfaces_.back();
      if (o.d < 1.f || o.tf.x > 0.f || o.tf.y > 0.f || o.tf.z > 0.f || opacity_mapped_.back()) any_transparent_ = true;
    }
    // Colours with alpha below 1 are translucent too.
    if constexpr (requires { world.translucent_colors(); }) any_transparent_ = any_transparent_ || world.translucent_colors();
    const auto add_light = [&](const DirectLight& d) {
      const Light& l = d.kind();
      if (const auto* h = std::get_if<HdriLight>(&l); h && h->visible && !environment_) environment_ = d;
      if (const auto* a = std::get_if<AmbientLight>(&l)) {
        ambient_ = ambient_ + emitted(l);  // the same wherever an instance places it
        if (a->visible) visible_ambient_ = visible_ambient_ + emitted(l);
      } else
        direct_lights_.push_back(d);
    };
    for (const Light& l : params_.lights) add_light({&l, nullptr});
    for (const MovingLight& m : params_.moving_lights) add_light({nullptr, &m});
    // Only AO rays draw random numbers: every light is sampled at one fixed point.
    needs_random_ = params_.ao_samples > 0;
    const Box3f b = world.bounds();
    scene_size_ = b.empty() ? 1.f : length(b.size());
  }

  // Holds pointers into its own copy of the lights.
  LocalRenderer(const LocalRenderer&) = delete;
  LocalRenderer& operator=(const LocalRenderer&) = delete;

  PixelSample<Arch> render(const Ray<F>& camera_ray, const M& active, const SampleIndex<Arch>& index = {}) const {
    // Seeded only where random numbers are drawn.
    std::optional<PixelRandomLanes<Arch>> generators;
    if (needs_random_) generators.emplace(index.pixel, index.sample);
    PixelRandomLanes<Arch>* rng = generators ? &*generators : nullptr;
    const F inf(std::numeric_limits<float>::infinity());

    PixelSample<Arch> out;
    out.t = inf;
    Vec3<F> color(splat(0.f)), transmittance(splat(1.f));
    Ray<F> ray = camera_ray;
    ray.tfar = simd::min(ray.tfar, max_depth<Arch>(params_, active, index));
    M live = active;
    M first_surface(false);  // the lanes whose first hit is a surface: they have an albedo
    for (int depth = 0; simd::any(live); ++depth) {
      const auto hit = accel::intersect<Arch>(world_->scene(), ray, live, depth == 0, world_->hit_filter());
      const F t_end = simd::select(hit.hit, hit.t, inf);
      // scivis's camera rays make the first visible volume sample their first hit (depth
      // and ids), in front of the surface; OSPRay's ao gives volumes none.
      VolumeEntry<Arch> entry;
      if constexpr (is_ao) {
        composite_volumes<Arch>(*world_, camera_volumes_, ray, live, t_end, color,
                                transmittance);  // unlit, as OSPRay's ao
      } else {
        composite_volumes<Arch>(
            *world_, camera_volumes_, ray, live, t_end, color, transmittance,
            [&](const Vec3<F>& p, const Vec3<F>& n, const Vec3<F>& c, const M& lanes) {
              return lit_volume_sample(p, n, c, ray.time, lanes, rng);
            },
            depth == 0 && index.first_hit_channels ? &entry : nullptr);
      }
      if constexpr (!is_ao)
        if (params_.visible_lights) add_visible_lights(ray, live, t_end, transmittance, color);
      const M surfaces = live & hit.hit;
      if (depth == 0) {
        first_surface = surfaces;
        record_first_hit<Arch>(*world_, hit, out);
        if constexpr (!is_ao)
          if constexpr (requires { world_->volume_count(); }) record_volume_entry<Arch>(*world_, entry, out);
      }
      Vec3<F> pass(splat(0.f));
      if (simd::any(surfaces)) shade_surfaces(ray, hit, surfaces, rng, color, transmittance, pass, out, depth == 0);
      // Lanes that missed see the background; lanes that hit continue through what the
      // surface lets pass, while that is worth tracing. Lanes done earlier keep their
      // transmittance: it is their alpha.
      const M missed = live & !hit.hit;
      if (simd::any(missed))
        color = color + select(missed, transmittance * background(ray, missed, index), Vec3<F>(splat(0.f)));
      transmittance = select(surfaces, transmittance * pass, transmittance);
      const F left = simd::max(simd::max(transmittance.x, transmittance.y), transmittance.z);
      live = surfaces & (left > F(params_.min_contribution)) & M(depth + 1 < params_.max_path_length);
      const M stopped = surfaces & !live;
      // A stopped path sees nothing more: what it could still pass becomes opaque.
      transmittance = select(stopped, Vec3<F>(splat(0.f)), transmittance);
      ray.tnear = simd::select(live, hit.t + simd::max(hit.t * F(1e-5f), F(1e-6f * scene_size_)), ray.tnear);
    }
    out.color = color;
    const F transmitted = (transmittance.x + transmittance.y + transmittance.z) * F(1.f / 3.f);
    F background_alpha(params_.background_alpha);
    if (params_.backplate) {
      alignas(64) float alpha[W];
      for (int i = 0; i < W; ++i)
        alpha[i] = background_alpha_at(params_, simd::lane(index.screen_x, i), simd::lane(index.screen_y, i));
      background_alpha = simd::load<Arch>(alpha);
    }
    out.alpha = F(1.f) - transmitted * (F(1.f) - background_alpha);
    out.albedo = select(first_surface, out.albedo, Vec3<F>(params_.background_color));
    return out;
  }

  /// Whether camera rays sample the lens and the shutter (render_frame asks).
  bool samples_lens_and_shutter() const { return params_.sample_lens_and_shutter; }

private:
  /// A light sampled at every hit: one of the world's, or a moving instance's, placed at
  /// each lane's time.
  struct DirectLight {
    const Light* fixed = nullptr;
    const MovingLight* moving = nullptr;
    explicit operator bool() const { return fixed || moving; }
    /// The light as given: its type and parameters other than placement.
    const Light& kind() const { return fixed ? *fixed : moving->light; }
    template <class Fn>
    void with(float time, Fn&& f) const {
      if (fixed) return f(*fixed);
      f(moving->at(time));
    }
  };

  /// The radiance of the visible lights with size that `ray` meets before `t_end`, and of
  /// the visible ambient lights where it meets nothing (OSPRay's: an ambient light lies at
  /// infinity), added to `color` under `transmittance`.
  void add_visible_lights(const Ray<F>& ray, const M& lanes, const F& t_end, const Vec3<F>& transmittance,
                          Vec3<F>& color) const {
    alignas(64) float rgb[3][W];
    bool any = false;
    for (int i = 0; i < W; ++i) {
      Vec3f sum{0.f, 0.f, 0.f};
      if (simd::lane(lanes, i) && std::isinf(simd::lane(t_end, i))) sum = visible_ambient_;
      if (simd::lane(lanes, i)) {
        const Vec3f org{simd::lane(ray.org.x, i), simd::lane(ray.org.y, i), simd::lane(ray.org.z, i)};
        const Vec3f dir = normalize(Vec3f{simd::lane(ray.dir.x, i), simd::lane(ray.dir.y, i), simd::lane(ray.dir.z, i)});
        for (const DirectLight& d : direct_lights_) {
          if (is_delta(d.kind()) || std::holds_alternative<HdriLight>(d.kind())) continue;
          if (!std::visit([](const auto& l) { return l.visible; }, d.kind())) continue;
          d.with(simd::lane(ray.time, i), [&](const Light& light) {
            sum = sum + eval(light, org, Vec3f{0.f, 0.f, 0.f}, dir, simd::lane(t_end, i)).radiance;
          });
        }
      }
      any = any || sum.x > 0.f || sum.y > 0.f || sum.z > 0.f;
      rgb[0][i] = sum.x, rgb[1][i] = sum.y, rgb[2][i] = sum.z;
    }
    if (any) color = color + transmittance * Vec3<F>{simd::load<Arch>(rgb[0]), simd::load<Arch>(rgb[1]), simd::load<Arch>(rgb[2])};
  }

  /// The background: `map_backplate` at the sample's screen position, else a visible
  /// `hdri` light's map in the ray's direction, else the background colour.
  Vec3<F> background(const Ray<F>& ray, const M& lanes, const SampleIndex<Arch>& index) const {
    if (!environment_ && !params_.backplate) return Vec3<F>(params_.background_color);
    alignas(64) float rgb[3][W];
    for (int i = 0; i < W; ++i) {
      Vec3f c = params_.background_color;
      if (simd::lane(lanes, i) && params_.backplate) {
        c = background_at(params_, simd::lane(index.screen_x, i), simd::lane(index.screen_y, i));
      } else if (simd::lane(lanes, i)) {
        const Vec3f dir{simd::lane(ray.dir.x, i), simd::lane(ray.dir.y, i), simd::lane(ray.dir.z, i)};
        environment_.with(simd::lane(ray.time, i), [&](const Light& l) {
          const auto& h = std::get<HdriLight>(l);
          c = h.lookup(normalize(dir)) * h.color * h.intensity;
        });
      }
      rgb[0][i] = c.x, rgb[1][i] = c.y, rgb[2][i] = c.z;
    }
    return {simd::load<Arch>(rgb[0]), simd::load<Arch>(rgb[1]), simd::load<Arch>(rgb[2])};
  }

  void shade_surfaces(const Ray<F>& ray, const accel::Hit<Arch>& hit, const M& surfaces, PixelRandomLanes<Arch>* rng,
                      Vec3<F>& color, const Vec3<F>& transmittance, Vec3<F>& pass, PixelSample<Arch>& out,
                      bool first) const {
    for_each_hit_group<Arch>(hit, surfaces, [&](const M& lanes, std::uint32_t inst, std::uint32_t geom) {
      world_->visit_hit(inst, geom, [&](const auto& geometry, const MotionTransform* placement) {
        auto surface = geometry.template surface<Arch>(hit, lanes);
        Vec3<F> ng = hit.ng;
        if (placement)
          surface.normal = normalize(placement->normal(surface.normal, ray.time)), ng = placement->normal(ng, ray.time);
        for_each_material<Arch>(*world_, inst, geom, hit, lanes, [&](const M& group, std::uint32_t material) {
          std::array<Vec3<F>, 2> derivatives;
          const bool mapped = material != no_material && normal_mapped_[material];
          if (mapped) derivatives = texture_derivatives<Arch>(geometry, hit, group, placement, ray.time);
          const Shaded shaded =
              shade(ray, hit.t, surface, normalize(ng), group, material, rng, mapped ? &derivatives : nullptr);
          color = color + select(group, transmittance * shaded.color, Vec3<F>(splat(0.f)));
          pass = select(group, shaded.pass, pass);
          if (first) {
            out.normal = select(group, shaded.normal, out.normal);
            out.albedo = select(group, shaded.albedo, out.albedo);
          }
        });
      });
    });
  }

  struct Shaded {
    Vec3<F> color, pass, normal, albedo;
  };

  /// The obj view of a material, lane by lane.
  struct ObjLanes {
    Vec3<F> kd, ks, tf;
    F ns, d;
  };

  /// `m` (the obj view of `material`) for every lane; with maps, resolved at each lane's
  /// texture coordinates `uv` (lanes outside `lanes` keep the plain values).
  ObjLanes obj_lanes(const ObjMaterial& m, std::uint32_t material, const TexCoord<F>& uv, const M& lanes) const {
    if (material == no_material || !textured_[material])
      return {Vec3<F>(m.kd), Vec3<F>(m.ks), Vec3<F>(m.tf), F(m.ns), F(m.d)};
    alignas(64) float v[11][W];
    Material storage;
    for (int i = 0; i < W; ++i) {
      const auto store = [&](const ObjMaterial& o) {
        const float values[11] = {o.kd.x, o.kd.y, o.kd.z, o.ks.x, o.ks.y, o.ks.z, o.tf.x, o.tf.y, o.tf.z, o.ns, o.d};
        for (int c = 0; c < 11; ++c) v[c][i] = values[c];
      };
      if (!simd::lane(lanes, i)) {
        store(m);
        continue;
      }
      const TexCoord<float> at{simd::lane(uv.u, i), simd::lane(uv.v, i)};
      store(obj_view(textured(params_.materials[material], at, storage)));
    }
    const auto load3 = [&](int c) {
      return Vec3<F>{simd::load<Arch>(v[c]), simd::load<Arch>(v[c + 1]), simd::load<Arch>(v[c + 2])};
    };
    return {load3(0), load3(3), load3(6), simd::load<Arch>(v[9]), simd::load<Arch>(v[10])};
  }

  /// The shading normals `n` of `lanes` as `material`'s normal map tilts them.
  static Vec3<F> mapped_normals(const Vec3<F>& n, const std::array<Vec3<F>, 2>& d, const TexCoord<F>& uv,
                                const M& lanes, const Material& material) {
    alignas(64) float out[3][W];
    for (int i = 0; i < W; ++i) {
      const auto lane = [&](const Vec3<F>& v) { return Vec3f{simd::lane(v.x, i), simd::lane(v.y, i), simd::lane(v.z, i)}; };
      Vec3f m = lane(n);
      if (simd::lane(lanes, i))
        m = mapped_normal(material, m, lane(d[0]), lane(d[1]), {simd::lane(uv.u, i), simd::lane(uv.v, i)});
      out[0][i] = m.x, out[1][i] = m.y, out[2][i] = m.z;
    }
    return {simd::load<Arch>(out[0]), simd::load<Arch>(out[1]), simd::load<Arch>(out[2])};
  }

  /// What a surface of opacity d and transmissive filter tf lets pass (ao: 1 - d alone).
  static Vec3<F> passing(const ObjLanes& o) {
    const F opaque = F(1.f) - o.d;
    if constexpr (is_ao) return Vec3<F>{opaque, opaque, opaque};
    return Vec3<F>{opaque, opaque, opaque} + o.tf * o.d;
  }

  /// `derivatives`: the surface's dP/ds and dP/dt, for a material with a normal map.
  template <class Surface>
  Shaded shade(const Ray<F>& ray, const F& t, const Surface& s, const Vec3<F>& ng_raw, const M& lanes,
               std::uint32_t material, PixelRandomLanes<Arch>* rng, const std::array<Vec3<F>, 2>* derivatives = nullptr) const {
    static const ObjMaterial default_surface;
    const bool has_material = material != no_material;
    const ObjMaterial& m = has_material ? surfaces_[material] : default_surface;
    ObjLanes o = obj_lanes(m, material, s.uv, lanes);
    if (params_.color_alpha_is_opacity) o.d = o.d * s.alpha;
    // Both sides of a surface are lit: the geometric normal faces the viewer and, as in
    // OSPRay, the shading normal lies on its side.
    const Vec3<F> ng = select(dot(ng_raw, ray.dir) >= F(0.f), -ng_raw, ng_raw);
    Vec3<F> n = select(dot(s.normal, ng) < F(0.f), -s.normal, s.normal);
    if (derivatives) n = mapped_normals(n, *derivatives, s.uv, lanes, params_.materials[material]);
    // Without a material, a geometry shows its own colours (the default kd where none).
    const Vec3<F> geometry_color = select(s.has_color, s.color, Vec3<F>(has_material ? splat(1.f) : m.kd));
    const Vec3<F> kd = has_material ? geometry_color * o.kd : geometry_color;

    Shaded out;
    out.normal = n;
    out.albedo = kd;
    out.pass = passing(o);
    if (has_material && luminous_[material]) {
      out.color = kd * o.d;
      return out;
    }
    const Vec3<F> p = ray.org + ray.dir * t;
    const F offset = offset_for(magnitude_of(p, t, ray.dir), s.epsilon);
    const Vec3<F> org = p + ng * offset;

    if constexpr (is_ao) {
      F dimming(1.f);
      if (params_.ao_samples > 0 && params_.ao_intensity > 0.01f)  // OSPRay's cut-off
        dimming = F(1.f - params_.ao_intensity) +
                  F(params_.ao_intensity) * ambient_visibility(org, n, ray.time, lanes, rng);
      out.color = kd * (simd::abs(dot(n, normalize(ray.dir))) * dimming *
                        (params_.opacity_weights_color ? o.d : F(1.f)));
    } else {
      Vec3<F> lit = Vec3<F>(ambient_) * ambient_visibility(org, n, ray.time, lanes, rng);
      lit = lit * kd;
      const bool specular = m.ks.x > 0.f || m.ks.y > 0.f || m.ks.z > 0.f;
      // OSPRay's normalized BRDF: Lambertian kd/π, and ks with the Phong exponent ns as a
      // Blinn exponent 4 ns under its energy normalization.
      const Vec3<F> diffuse = kd * F(1.f / pi);
      const F shininess = o.ns * F(4.f);
      const Vec3<F> glossy = specular ? o.ks * ((shininess + F(2.f)) * F(1.f / (4.f * pi)) /
                                                (F(2.f) - exp<Arch>(shininess * F(-0.5f * std::numbers::ln2_v<float>))))
                                      : Vec3<F>(splat(0.f));
      for (const DirectLight& light : direct_lights_) {
        Vec3<F> wi, weight;
        F dist;
        if (!sample_light(light, p, n, ray.time, lanes, wi, weight, dist)) continue;
        const F cos_theta = dot(n, wi);
        // With shadows, light from below the geometric surface is blocked by the surface itself.
        M lit_lanes = lanes & (cos_theta > F(0.f));
        if (params_.shadows) lit_lanes = lit_lanes & (dot(ng, wi) > F(0.f));
        if (!simd::any(lit_lanes)) continue;
        Vec3<F> response = diffuse * cos_theta;
        if (specular) {
          const Vec3<F> h = normalize(wi - ray.dir);
          response = response + glossy * pow<Arch>(simd::max(dot(n, h), F(0.f)), shininess);
        }
        Vec3<F> arriving = weight;
        if (params_.shadows) {
          lit_lanes = lit_lanes & worth_a_shadow_ray(response * weight * o.d);
          if (!simd::any(lit_lanes)) continue;
          arriving = arriving * shadow_transmittance(org, wi, dist, ray.time, lit_lanes, light_volumes_);
        }
        lit = lit + select(lit_lanes, response * arriving, Vec3<F>(splat(0.f)));
      }
      out.color = lit * o.d;
    }
    return out;
  }

  /// A gradient-shaded volume sample of colour c at p lit as OSPRay's scivis lights it
  /// (a surface without material, normal n): c/π from every light on n's side (shadowed
  /// by surfaces with `shadows`) plus c times the ambient light (and its AO visibility).
  /// No two-sided lighting: n points out of the structure, and light behind it is not seen.
  Vec3<F> lit_volume_sample(const Vec3<F>& p, const Vec3<F>& n, const Vec3<F>& c, const F& time, const M& lanes,
                            PixelRandomLanes<Arch>* rng) const {
    Vec3<F> lit = c * Vec3<F>(ambient_) * ambient_visibility(p, n, time, lanes, rng);
    const Vec3<F> diffuse = c * F(1.f / pi);
    for (const DirectLight& light : direct_lights_) {
      Vec3<F> wi, weight;
      F dist;
      if (!sample_light(light, p, n, time, lanes, wi, weight, dist)) continue;
      const F cos_theta = dot(n, wi);
      M lit_lanes = lanes & (cos_theta > F(0.f));
      if (!simd::any(lit_lanes)) continue;
      Vec3<F> arriving = weight;
      if (params_.shadows) {
        lit_lanes = lit_lanes & worth_a_shadow_ray(diffuse * cos_theta * weight);
        if (!simd::any(lit_lanes)) continue;
        arriving = arriving * shadow_transmittance(p, wi, dist, time, lit_lanes, light_volumes_);
      }
      lit = lit + select(lit_lanes, diffuse * cos_theta * arriving, Vec3<F>(splat(0.f)));
    }
    return lit;
  }

  /// With shadows, OSPRay's scivis neither traces a shadow ray for a light nor adds its
  /// light where the unshadowed contribution (BRDF times cosine times the light's sample,
  /// its luminance) is not above `minContribution`: the many faint lights of a large scene
  /// (say, one per instance of a group) add nothing there. Without shadows every light adds.
  M worth_a_shadow_ray(const Vec3<F>& contribution) const {
    const F luminance = F(0.212671f) * contribution.x + F(0.715160f) * contribution.y + F(0.072169f) * contribution.z;
    return luminance > F(params_.min_contribution);
  }

  /// Per-lane light samples (of a moving instance's light placed at each lane's time)
  /// gathered into packets; false where no lane gets light.
  bool sample_light(const DirectLight& light, const Vec3<F>& p, const Vec3<F>& n, const F& time, const M& lanes,
                    Vec3<F>& wi, Vec3<F>& weight, F& dist) const {
    if (const auto* d = light.fixed ? std::get_if<DistantLight>(light.fixed) : nullptr; d && d->angular_diameter <= 0.f) {
      wi = Vec3<F>(-normalize(d->direction));
      weight = Vec3<F>(emitted(*light.fixed));
      dist = F(std::numeric_limits<float>::infinity());
      return true;
    }
    alignas(64) float v[7][W];
    bool any = false;
    for (int i = 0; i < W; ++i) {
      v[6][i] = 0.f;
      for (int c = 0; c < 6; ++c) v[c][i] = 0.f;
      if (!simd::lane(lanes, i)) continue;
      const Vec3f pi{simd::lane(p.x, i), simd::lane(p.y, i), simd::lane(p.z, i)};
      const Vec3f ni{simd::lane(n.x, i), simd::lane(n.y, i), simd::lane(n.z, i)};
      // OSPRay 3.1's scivis sample point (measured with its runtime): a quad light's
      // centre; (0, 0), the centre of a disk, sphere or cone, for the others.
      const float at = std::holds_alternative<QuadLight>(light.kind()) ? 0.5f : 0.f;
      std::optional<LightSample> s;
      light.with(simd::lane(time, i), [&](const Light& placed) { s = sample(placed, pi, ni, at, at); });
      if (!s) continue;
      any = true;
      const float values[7] = {s->dir.x, s->dir.y, s->dir.z, s->weight.x, s->weight.y, s->weight.z, s->dist};
      for (int c = 0; c < 7; ++c) v[c][i] = values[c];
    }
    wi = {simd::load<Arch>(v[0]), simd::load<Arch>(v[1]), simd::load<Arch>(v[2])};
    weight = {simd::load<Arch>(v[3]), simd::load<Arch>(v[4]), simd::load<Arch>(v[5])};
    dist = simd::load<Arch>(v[6]);
    return any;
  }

  /// The magnitude that scales how far shadow and AO rays start off the surface (offset_for):
  /// the larger of the hit's largest coordinate and its distance along the ray — so that
  /// shadow edges and terminators land where OSPRay's do, also on objects far smaller
  /// than the scene.
  static F magnitude_of(const Vec3<F>& p, const F& t, const Vec3<F>& dir) {
    const auto largest = [](const Vec3<F>& v) {
      return simd::max(simd::max(simd::abs(v.x), simd::abs(v.y)), simd::abs(v.z));
    };
    return simd::max(largest(p), largest(dir) * t);
  }

  /// The fraction of `aoSamples` cosine-weighted rays around n that nothing blocks within
  /// aoDistance (1 without samples), at each lane's ray time.
  F ambient_visibility(const Vec3<F>& org, const Vec3<F>& n, const F& time, const M& lanes, PixelRandomLanes<Arch>* rng) const {
    if (params_.ao_samples == 0) return F(1.f);
    F visible(0.f);
    for (int k = 0; k < params_.ao_samples; ++k) {
      // Only the lanes shaded here draw: a pixel's AO rays then depend on its own hits,
      // not on what else its packet hit (nor on the packet's width or a region's clip).
      const auto [u1, u2] = rng->next_2d(lanes);
      const Vec3<F> dir = select(lanes, detail::sample_cosine(n, u1, u2), n);
      const Vec3<F> through = shadow_transmittance(org, dir, F(params_.ao_distance), time, lanes, ao_volumes_);
      visible = visible + (through.x + through.y + through.z) * F(1.f / 3.f);
    }
    return visible * F(1.f / static_cast<float>(params_.ao_samples));
  }

  /// What reaches `org` from `dist` away along `dir`: 0 where something opaque is in the
  /// way, otherwise the product of the transparent surfaces' filters and the volumes'
  /// transmittance (integrated as `volumes` says), as OSPRay's scivis shadows. `time`:
  /// the camera ray's, so that what moves casts its shadow where the camera saw it.
  Vec3<F> shadow_transmittance(const Vec3<F>& org, const Vec3<F>& dir, const F& dist, const F& time, const M& lanes,
                               const VolumeIntegration& volumes) const {
    Ray<F> ray;
    ray.org = org;
    ray.dir = dir;
    ray.tnear = F(0.f);
    ray.tfar = dist * F(1.f - 1e-5f);
    ray.time = time;
    Vec3<F> through = surface_transmittance(ray, lanes);
    const M lit = lanes & (simd::max(simd::max(through.x, through.y), through.z) > F(0.f));
    if constexpr (requires { world_->volume_count(); })
      if (world_->volume_count() && simd::any(lit))
        through = through * volume_transmittance<Arch>(*world_, volumes, ray, lit, ray.tfar);
    return through;
  }

  /// The surfaces' part of shadow_transmittance along `ray` (ao's AO rays: any surface blocks).
  Vec3<F> surface_transmittance(Ray<F> ray, const M& lanes) const {
    if (is_ao || !any_transparent_) {
      const M blocked = accel::occluded<Arch>(world_->scene(), ray, lanes, false, world_->hit_filter());
      return select(blocked, Vec3<F>(splat(0.f)), Vec3<F>(splat(1.f)));
    }
    Vec3<F> through(splat(1.f));
    M live = lanes;
    for (int depth = 0; simd::any(live) && depth <= params_.max_path_length; ++depth) {
      const auto hit = accel::intersect<Arch>(world_->scene(), ray, live, false, world_->hit_filter());
      const M blocked = live & hit.hit;
      for_each_hit_group<Arch>(hit, blocked, [&](const M& hits, std::uint32_t inst, std::uint32_t geom) {
        for_each_material<Arch>(*world_, inst, geom, hit, hits, [&](const M& group, std::uint32_t material) {
          static const ObjMaterial opaque_surface;
          const ObjMaterial& m = material == no_material ? opaque_surface : surfaces_[material];
          world_->visit_hit(inst, geom, [&](const auto& geometry, const MotionTransform*) {
            bool translucent = false;
            if constexpr (requires { geometry.translucent_colors(); }) translucent = geometry.translucent_colors();
            if (!translucent && (material == no_material || !opacity_mapped_[material])) {
              through = select(group, through * Vec3<F>(splat(1.f - m.d) + m.tf * m.d), through);
              return;
            }
            // A map cuts the surface out, and colours' alpha thins it, lane by lane: that
            // needs the hits' texture coordinates and colours.
            const auto surface = geometry.template surface<Arch>(hit, group);
            ObjLanes o = obj_lanes(m, material, surface.uv, group);
            o.d = o.d * surface.alpha;
            through = select(group, through * passing(o), through);
          });
        });
      });
      const F left = simd::max(simd::max(through.x, through.y), through.z);
      live = blocked & (left > F(params_.min_contribution));
      through = select(blocked & !live, Vec3<F>(splat(0.f)), through);
      ray.tnear = simd::select(live, hit.t + simd::max(hit.t * F(1e-5f), F(1e-6f * scene_size_)), ray.tnear);
    }
    return through;
  }

  const WorldT* world_;
  Params params_;
  /// Volumes along camera rays, and along shadow and AO rays (which, as OSPRay's, sample
  /// them at a quarter and a tenth of the rate).
  VolumeIntegration camera_volumes_, light_volumes_, ao_volumes_;
  std::vector<ObjMaterial> surfaces_;
  std::vector<bool> luminous_;
  std::vector<bool> textured_;        ///< per material: has maps
  std::vector<bool> normal_mapped_;   ///< per material: has a normal map
  std::vector<bool> opacity_mapped_;  ///< per material: a map changes its opacity
  bool any_transparent_ = false;
  bool needs_random_ = false;
  Vec3f ambient_{0.f, 0.f, 0.f};
  Vec3f visible_ambient_{0.f, 0.f, 0.f};  // of the ambient lights whose `visible` is set
  std::vector<DirectLight> direct_lights_;
  DirectLight environment_;  ///< the first visible hdri light: the background
  float scene_size_ = 1.f;
};

}  // namespace detail

template <class Arch, class WorldT>
using SciVis = detail::LocalRenderer<Arch, WorldT, SciVisParams>;

template <class Arch, class WorldT>
using AmbientOcclusion = detail::LocalRenderer<Arch, WorldT, AOParams>;

}  // namespace sciray
