#pragma once
// What every renderer shares: the parameters OSPRay's renderers have in common, the
// world's materials and lights, and the step from a packet of hits to per-lane surface
// data. Rays travel in packets (one Embree call per packet); shading then runs lane by
// lane, because lanes of one packet see different materials and lights and a masked
// packet would pay for all of them in every lane.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "sciray/accel/trace.hpp"
#include "sciray/error.hpp"
#include "sciray/math/affine.hpp"
#include "sciray/math/vec.hpp"
#include "sciray/render/light.hpp"
#include "sciray/render/material.hpp"
#include "sciray/render/sample.hpp"
#include "sciray/render/texture.hpp"
#include "sciray/volume/volumetric_model.hpp"

namespace sciray {

/// OSPRay's parameters common to all renderers, plus the world's lights and the material
/// list that geometries index (Group::add).
struct RendererParams {
  /// Entry i shades the geometries added with material i (Group::add); the material's
  /// colour multiplies the geometry's.
  std::vector<Material> materials;
  std::vector<Light> lights = default_lights();
  std::vector<MovingLight> moving_lights;  ///< lights of moving instances, placed at each ray's time
  Vec3f background_color{0.f, 0.f, 0.f};  ///< backgroundColor (rgb)
  float background_alpha = 0.f;           ///< backgroundColor (alpha)
  std::shared_ptr<const Texture2D> backplate;  ///< map_backplate: screen-space background image
  std::shared_ptr<const Texture2D> backplate_alpha;  ///< its alpha (as grey); null: opaque
  /// map_maxDepth: how far camera rays reach, per pixel (its first channel at the pixel
  /// centre's screen position): surfaces and volumes beyond are not seen, as behind a
  /// rasterized image's depth buffer that the frame is composited with.
  std::shared_ptr<const Texture2D> max_depth;
  int max_path_length = 20;   ///< maxPathLength: surfaces a ray may pass through or bounce off
  float min_contribution = 0.001f;  ///< minContribution: paths carrying less are stopped
  float volume_sampling_rate = 1.f;  ///< volumeSamplingRate: samples per cell
  bool empty_space_skipping = true;
  bool volume_preintegration = false;    ///< see VolumeIntegration::preintegration
  bool volume_adaptive_sampling = false;  ///< see VolumeIntegration::adaptive_sampling
  bool volume_exact = false;              ///< see VolumeIntegration::exact
};

/// The background at screen position (x, y): the backplate (clamped at its edges), else
/// the background colour; with its alpha (a backplate's, 1 for formats without alpha).
inline Vec3f background_at(const RendererParams& p, float x, float y) {
  return p.backplate ? p.backplate->sample_clamped(x, y) : p.background_color;
}
inline float background_alpha_at(const RendererParams& p, float x, float y) {
  if (!p.backplate) return p.background_alpha;
  return p.backplate_alpha ? p.backplate_alpha->sample_clamped(x, y).x : 1.f;
}

/// Throws an Error naming what is wrong with `p` for a world whose geometries need
/// `materials_needed` materials.
inline void validate(const RendererParams& p, std::uint32_t materials_needed, const std::string& renderer) {
  if (materials_needed > p.materials.size())
    throw Error(renderer + " renderer: a geometry uses material " + std::to_string(materials_needed - 1) +
                " but only " + std::to_string(p.materials.size()) + " materials were given");
  for (std::size_t i = 0; i < p.materials.size(); ++i) try {
      validate(p.materials[i]);
    } catch (const Error& e) {
      throw Error(renderer + " renderer: material " + std::to_string(i) + ": " + e.what());
    }
  for (std::size_t i = 0; i < p.lights.size(); ++i) try {
      validate(p.lights[i]);
    } catch (const Error& e) {
      throw Error(renderer + " renderer: light " + std::to_string(i) + ": " + e.what());
    }
  for (std::size_t i = 0; i < p.moving_lights.size(); ++i) try {
      validate(p.moving_lights[i].light);
    } catch (const Error& e) {
      throw Error(renderer + " renderer: moving light " + std::to_string(i) + ": " + e.what());
    }
  if (p.max_path_length < 0) throw Error(renderer + " renderer: parameter 'maxPathLength' must not be negative");
  if (!(p.min_contribution >= 0.f)) throw Error(renderer + " renderer: parameter 'minContribution' must not be negative");
  if (!(p.volume_sampling_rate > 0.f) || !std::isfinite(p.volume_sampling_rate))
    throw Error(renderer + " renderer: parameter 'volumeSamplingRate' must be positive and finite, got " +
                std::to_string(p.volume_sampling_rate));
}

/// One lane's surface hit, in world space.
struct SurfacePoint {
  Vec3f p;       ///< hit position
  Vec3f n;       ///< unit shading normal, facing the incoming ray
  Vec3f ng;      ///< unit geometric normal, facing the incoming ray
  bool front;    ///< the ray hit the side the geometric normal points to
  Vec3f color;   ///< the geometry's colour, (1,1,1) where it has none
  float alpha;   ///< the colour's alpha: opacity, with the material's
  bool has_color;
  std::uint32_t material;  ///< index into RendererParams::materials
  TexCoord<float> uv;      ///< texture coordinates, for the material's maps (textured())
  /// Position's derivatives along the texture coordinates, which orient normal maps
  /// (mapped_normal); filled only for materials with one (for_each_surface).
  Vec3f dpds{1.f, 0.f, 0.f}, dpdt{0.f, 1.f, 0.f};
  float t = 0.f;        ///< distance along the ray that found it
  float epsilon = 0.f;  ///< the geometry's own precision (SurfaceSample::epsilon)
};

namespace detail {

template <class Arch>
int first_lane(const simd::Mask<Arch>& mask) {
  for (int i = 0; i < simd::width<Arch>; ++i)
    if (simd::lane(mask, i)) return i;
  return 0;
}

/// Calls f(lanes, inst_id, geom_id) once for each (instance, geometry) that the lanes of
/// `mask` hit, with the lanes that hit it: a packet usually hits one or a few.
template <class Arch, class F>
void for_each_hit_group(const accel::Hit<Arch>& hit, const simd::Mask<Arch>& mask, F&& f) {
  using Fl = simd::Float<Arch>;
  using M = simd::Mask<Arch>;
  M remaining = mask & hit.hit;
  while (simd::any(remaining)) {
    const int lane0 = first_lane<Arch>(remaining);
    const std::int32_t geom_id = simd::lane(hit.geom_id, lane0), inst_id = simd::lane(hit.inst_id, lane0);
    const M lanes = remaining & (simd::to_float(hit.geom_id) == Fl(static_cast<float>(geom_id))) &
                    (simd::to_float(hit.inst_id) == Fl(static_cast<float>(inst_id)));
    f(lanes, static_cast<std::uint32_t>(inst_id), static_cast<std::uint32_t>(geom_id));
    remaining = remaining & !lanes;
  }
}

/// The materials per primitive of geometry `geom` of instance `inst` (as a hit reports
/// them), or null where it has one material for all.
template <class WorldT>
const std::vector<std::uint32_t>* primitive_materials(const WorldT& world, std::uint32_t inst, std::uint32_t geom) {
  if constexpr (requires { world.primitive_materials_of(inst, geom); })
    return world.primitive_materials_of(inst, geom);
  else
    return nullptr;
}

/// Entry `prim` of a list of materials per primitive (the last for ids beyond it).
inline std::uint32_t primitive_material(const std::vector<std::uint32_t>& materials, std::int32_t prim) {
  return materials[std::min(static_cast<std::size_t>(std::max(prim, 0)), materials.size() - 1)];
}

/// Calls f(lanes, material) for the `lanes` of one (instance, geometry) group of `hit`
/// by material: once, unless the geometry has a material per primitive.
template <class Arch, class WorldT, class F>
void for_each_material(const WorldT& world, std::uint32_t inst, std::uint32_t geom, const accel::Hit<Arch>& hit,
                       const simd::Mask<Arch>& lanes, F&& f) {
  constexpr int W = simd::width<Arch>;
  const std::vector<std::uint32_t>* per_primitive = primitive_materials(world, inst, geom);
  if (!per_primitive) return f(lanes, world.material_of(inst, geom));
  alignas(64) std::int32_t prim[W];
  alignas(64) float material[W];  // exact: indices stay far below 2^24
  simd::store<Arch>(prim, hit.prim_id);
  for (int i = 0; i < W; ++i)
    material[i] = simd::lane(lanes, i) ? static_cast<float>(primitive_material(*per_primitive, prim[i])) : -1.f;
  const simd::Float<Arch> materials = simd::load<Arch>(material);
  simd::Mask<Arch> remaining = lanes;
  while (simd::any(remaining)) {
    const float m = material[first_lane<Arch>(remaining)];
    const simd::Mask<Arch> same = remaining & (materials == simd::Float<Arch>(m));
    f(same, static_cast<std::uint32_t>(m));
    remaining = remaining & !same;
  }
}

/// The derivatives of position along the texture coordinates at the hits of `lanes` on
/// `geometry`, in world space: a mesh's (TriangleMesh::texture_derivatives), or as OSPRay
/// (1, 0, 0) and (0, 1, 0) in the geometry's own space for others.
template <class Arch, class Geometry>
std::array<Vec3<simd::Float<Arch>>, 2> texture_derivatives(const Geometry& geometry, const accel::Hit<Arch>& hit,
                                                           const simd::Mask<Arch>& lanes,
                                                           const MotionTransform* placement,
                                                           const simd::Float<Arch>& time) {
  using Fl = simd::Float<Arch>;
  std::array<Vec3<Fl>, 2> d{Vec3<Fl>{Fl(1.f), Fl(0.f), Fl(0.f)}, Vec3<Fl>{Fl(0.f), Fl(1.f), Fl(0.f)}};
  if constexpr (requires { geometry.template texture_derivatives<Arch>(hit, lanes); })
    d = geometry.template texture_derivatives<Arch>(hit, lanes);
  if (!placement) return d;
  constexpr int W = simd::width<Arch>;
  alignas(64) float out[6][W];
  for (int i = 0; i < W; ++i) {
    const Affine3f x = placement->at(simd::lane(time, i));
    for (int k = 0; k < 2; ++k) {
      const Vec3<Fl>& v = d[static_cast<std::size_t>(k)];
      const Vec3f placed = x.vector({simd::lane(v.x, i), simd::lane(v.y, i), simd::lane(v.z, i)});
      out[3 * k][i] = placed.x, out[3 * k + 1][i] = placed.y, out[3 * k + 2][i] = placed.z;
    }
  }
  for (int k = 0; k < 2; ++k)
    d[static_cast<std::size_t>(k)] = {simd::load<Arch>(out[3 * k]), simd::load<Arch>(out[3 * k + 1]),
                                      simd::load<Arch>(out[3 * k + 2])};
  return d;
}

/// Calls f(lane, SurfacePoint) for every lane of `mask` that `hit` hit, resolving each
/// (instance, geometry) group of lanes once, as a packet. `normal_mapped` (per material
/// index): whose surfaces need SurfacePoint::dpds and dpdt.
template <class Arch, class WorldT, class F>
void for_each_surface(const WorldT& world, const Ray<simd::Float<Arch>>& ray, const accel::Hit<Arch>& hit,
                      const simd::Mask<Arch>& mask, F&& f, const std::vector<bool>* normal_mapped = nullptr) {
  using Fl = simd::Float<Arch>;
  for_each_hit_group<Arch>(hit, mask, [&](const simd::Mask<Arch>& lanes, std::uint32_t inst, std::uint32_t geom) {
    const std::vector<std::uint32_t>* per_primitive = primitive_materials(world, inst, geom);
    const std::uint32_t material = world.material_of(inst, geom);
    const auto lane_material = [&](int i) {
      return per_primitive ? primitive_material(*per_primitive, simd::lane(hit.prim_id, i)) : material;
    };
    bool derivatives = false;
    for (int i = 0; normal_mapped && i < simd::width<Arch>; ++i)
      if (simd::lane(lanes, i) && lane_material(i) != no_material) derivatives |= (*normal_mapped)[lane_material(i)];
    world.visit_hit(inst, geom, [&](const auto& geometry, const MotionTransform* placement) {
      auto surface = geometry.template surface<Arch>(hit, lanes);
      std::array<Vec3<Fl>, 2> d;
      if (derivatives) d = texture_derivatives<Arch>(geometry, hit, lanes, placement, ray.time);
      Vec3<Fl> ng = hit.ng;
      if (placement)
        surface.normal = placement->normal(surface.normal, ray.time), ng = placement->normal(ng, ray.time);
      for (int i = 0; i < simd::width<Arch>; ++i) {
        if (!simd::lane(lanes, i)) continue;
        const Vec3f dir{simd::lane(ray.dir.x, i), simd::lane(ray.dir.y, i), simd::lane(ray.dir.z, i)};
        const float t = simd::lane(hit.t, i);
        SurfacePoint s;
        s.p = Vec3f{simd::lane(ray.org.x, i), simd::lane(ray.org.y, i), simd::lane(ray.org.z, i)} + dir * t;
        s.t = t * length(dir);
        s.epsilon = simd::lane(surface.epsilon, i);
        Vec3f g{simd::lane(ng.x, i), simd::lane(ng.y, i), simd::lane(ng.z, i)};
        Vec3f n{simd::lane(surface.normal.x, i), simd::lane(surface.normal.y, i), simd::lane(surface.normal.z, i)};
        const float gl = length(g), nl = length(n);
        g = gl > 0.f && std::isfinite(gl) ? g / gl : -dir;
        n = nl > 0.f && std::isfinite(nl) ? n / nl : g;
        s.front = dot(g, dir) < 0.f;
        if (!s.front) g = -g;
        if (dot(n, g) < 0.f) n = -n;  // the shading normal on the geometric normal's side, as OSPRay
        s.n = n, s.ng = g;
        s.has_color = simd::lane(surface.has_color, i);
        s.color = s.has_color ? Vec3f{simd::lane(surface.color.x, i), simd::lane(surface.color.y, i),
                                      simd::lane(surface.color.z, i)}
                              : splat(1.f);
        s.alpha = s.has_color ? simd::lane(surface.alpha, i) : 1.f;
        s.material = lane_material(i);
        s.uv = {simd::lane(surface.uv.u, i), simd::lane(surface.uv.v, i)};
        if (derivatives) {
          s.dpds = {simd::lane(d[0].x, i), simd::lane(d[0].y, i), simd::lane(d[0].z, i)};
          s.dpdt = {simd::lane(d[1].x, i), simd::lane(d[1].y, i), simd::lane(d[1].z, i)};
        }
        f(i, s);
      }
    });
  });
}

/// Records the surface hits of `hit` as a packet's first hit in `out` (t, and the ids the
/// id channels show); lanes that missed get inf and -1.
template <class Arch, class WorldT>
void record_first_hit(const WorldT& world, const accel::Hit<Arch>& hit, PixelSample<Arch>& out) {
  using Fl = simd::Float<Arch>;
  using I = simd::Int<Arch>;
  out.t = simd::select(hit.hit, hit.t, Fl(std::numeric_limits<float>::infinity()));
  out.prim_id = simd::select(hit.hit, hit.prim_id, I(-1));
  bool user_ids = false;
  if constexpr (requires { world.user_ids(); }) user_ids = world.user_ids();
  if (!user_ids) {
    out.geom_id = simd::select(hit.hit, hit.geom_id, I(-1));
    // Instances are numbered from 0 as the world added them; -1 for direct geometry.
    const I first_instance(static_cast<std::int32_t>(world.geometry_count()));
    const auto instanced = hit.hit & (simd::to_float(hit.inst_id) != Fl(static_cast<float>(RTC_INVALID_GEOMETRY_ID)));
    out.inst_id = simd::select(instanced, hit.inst_id - first_instance, I(-1));
    return;
  }
  out.geom_id = I(-1), out.inst_id = I(-1);
  if constexpr (requires { world.user_ids(); })
    for_each_hit_group<Arch>(hit, hit.hit, [&](const simd::Mask<Arch>& lanes, std::uint32_t inst, std::uint32_t geom) {
      const auto [object, instance] = world.channel_ids(inst, geom);
      out.geom_id = simd::select(lanes, I(object), out.geom_id);
      out.inst_id = simd::select(lanes, I(instance), out.inst_id);
    });
}

/// Where each lane's camera ray meets the first volume sample OSPRay's scivis makes its
/// hit (VolumeSample::hit_t; at depth 0: in front of any surface), and which placed
/// volume that is; -1 where none.
template <class Arch>
struct VolumeEntry {
  simd::Float<Arch> t = simd::Float<Arch>(std::numeric_limits<float>::infinity());
  simd::Int<Arch> volume = simd::Int<Arch>(-1);
};

/// Makes the volumes that `entry` found the first hit of their lanes in `out`, as OSPRay
/// records them: t of that sample, primitive 0, the volume's ids.
template <class Arch, class WorldT>
void record_volume_entry(const WorldT& world, const VolumeEntry<Arch>& entry, PixelSample<Arch>& out) {
  using I = simd::Int<Arch>;
  const auto seen = simd::to_float(entry.volume) >= simd::Float<Arch>(0.f);
  if (!simd::any(seen)) return;
  alignas(64) std::int32_t ids[2][simd::width<Arch>];
  simd::store<Arch>(ids[0], out.geom_id);
  simd::store<Arch>(ids[1], out.inst_id);
  for (int i = 0; i < simd::width<Arch>; ++i) {
    const std::int32_t volume = simd::lane(entry.volume, i);
    if (volume < 0) continue;
    const auto [object, instance] = world.volume_ids(static_cast<std::size_t>(volume));
    ids[0][i] = object, ids[1][i] = instance;
  }
  out.t = simd::select(seen, entry.t, out.t);
  out.prim_id = simd::select(seen, I(0), out.prim_id);
  out.geom_id = simd::load<Arch>(ids[0]);
  out.inst_id = simd::load<Arch>(ids[1]);
}

/// How far a secondary ray starts off the surface it leaves, along the geometric normal,
/// given `magnitude`, the larger of the hit's largest coordinate and its distance along
/// the ray that found it (one float or a packet): about 8 ulps of it (0x1.fp-21), twice
/// what OSPRay 3.1 takes (2^-21, 4 ulps: measured, that offset reproduces its lit pixels on
/// a mesh floor and on spheres 2·10⁵ radii away). A geometry that knows its own precision (a
/// sphere: its roots are refined, so only the rounding of org + t·dir is left, about an
/// ulp of that magnitude) starts at its own epsilon or an ulp or two (0x1p-23), whichever is
/// larger: a shadow ray pushed 8 ulps out from a sphere seen from 2·10⁵ radii away starts
/// 18 % of the radius off and moves shadow edges; 0x1p-23 keeps them within a pixel of the
/// exact edge, and a quarter of it lets spheres shadow themselves.
template <class F>
F offset_for(const F& magnitude, const F& geometry_epsilon) {
  return simd::select(geometry_epsilon > F(0.f), simd::max(F(0x1p-23f) * magnitude, geometry_epsilon),
                      F(0x1.fp-21f) * magnitude);
}

/// offset_for of the hit `p`, found `t` along its ray.
inline float ray_offset(const Vec3f& p, float t, float geometry_epsilon) {
  return offset_for(std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z), t}), geometry_epsilon);
}

/// How far each active lane's camera ray reaches: map_maxDepth at its pixel centre
/// (OSPRay's Renderer_getMaxDepth), infinity without the map.
template <class Arch>
simd::Float<Arch> max_depth(const RendererParams& params, const simd::Mask<Arch>& active,
                            const SampleIndex<Arch>& index) {
  constexpr float inf = std::numeric_limits<float>::infinity();
  if (!params.max_depth) return simd::Float<Arch>(inf);
  alignas(64) float depth[simd::width<Arch>];
  for (int i = 0; i < simd::width<Arch>; ++i)
    depth[i] = simd::lane(active, i)
                   ? params.max_depth->sample(simd::lane(index.center_x, i), simd::lane(index.center_y, i)).x
                   : inf;
  return simd::load<Arch>(depth);
}

/// How volumes of `world` are integrated under the renderer's parameters, at
/// `rate_scale` times its sampling rate (OSPRay's shadow and AO rays sample coarser).
template <class WorldT>
VolumeIntegration volume_integration(const WorldT& world, const RendererParams& params, float rate_scale = 1.f) {
  VolumeIntegration how;
  how.sampling_rate = params.volume_sampling_rate * rate_scale;
  how.empty_space_skipping = params.empty_space_skipping;
  if constexpr (requires { world.clipping(); }) how.clipping = world.clipping();
  how.preintegration = params.volume_preintegration;
  how.adaptive_sampling = params.volume_adaptive_sampling;
  how.exact = params.volume_exact;
  how.hit_opacity = params.min_contribution;
  return how;
}

/// Composites the samples of volumes that do not overlap along any lane (`along[k]`
/// gave `samples[k]`), each lane in the order it enters them.
template <class Arch, class AlongT>
void composite_in_depth_order(const std::vector<AlongT>& along, const std::vector<VolumeSample<Arch>>& samples,
                              Vec3<simd::Float<Arch>>& color, Vec3<simd::Float<Arch>>& transmittance) {
  constexpr int W = simd::width<Arch>;
  alignas(64) float out[6][W];
  std::vector<std::pair<float, std::size_t>> order;
  for (int i = 0; i < W; ++i) {
    order.clear();
    for (std::size_t k = 0; k < samples.size(); ++k)
      if (simd::lane(samples[k].alpha, i) > 0.f) order.emplace_back(simd::lane(along[k].enter, i), k);
    std::sort(order.begin(), order.end());
    Vec3f c{simd::lane(color.x, i), simd::lane(color.y, i), simd::lane(color.z, i)};
    Vec3f t{simd::lane(transmittance.x, i), simd::lane(transmittance.y, i), simd::lane(transmittance.z, i)};
    for (const auto& [enter, k] : order) {
      const VolumeSample<Arch>& v = samples[k];
      c = c + t * Vec3f{simd::lane(v.color.x, i), simd::lane(v.color.y, i), simd::lane(v.color.z, i)};
      t = t * (1.f - simd::lane(v.alpha, i));
    }
    const float values[6] = {c.x, c.y, c.z, t.x, t.y, t.z};
    for (int k = 0; k < 6; ++k) out[k][i] = values[k];
  }
  color = {simd::load<Arch>(out[0]), simd::load<Arch>(out[1]), simd::load<Arch>(out[2])};
  transmittance = {simd::load<Arch>(out[3]), simd::load<Arch>(out[4]), simd::load<Arch>(out[5])};
}

/// Volumes of `world` integrated along `ray` up to `t_end`, composited front to back into
/// `color` under `transmittance` (both updated). `shade` lights gradient-shaded samples
/// (VolumetricModel::integrate); without it no sample is lit. Each lane composites the
/// volumes in its own depth order: where the volumes the packet passes do not overlap
/// along any lane, each is integrated on its own and every lane composites them sorted by
/// where it enters them; where they overlap, they are marched together in slabs one step
/// of the finest long, each volume over the slab in turn, so that their samples
/// interleave in depth as OSPRay's do. `entry`, if given, gets the nearest volume hit in
/// front of `t_end` along each lane.
template <class Arch, class WorldT, class Shade = std::nullptr_t>
void composite_volumes(const WorldT& world, const VolumeIntegration& how, const Ray<simd::Float<Arch>>& ray,
                       const simd::Mask<Arch>& active, const simd::Float<Arch>& t_end,
                       Vec3<simd::Float<Arch>>& color, Vec3<simd::Float<Arch>>& transmittance,
                       const Shade& shade = nullptr, VolumeEntry<Arch>* entry = nullptr) {
  using Fl = simd::Float<Arch>;
  using Ml = simd::Mask<Arch>;
  if constexpr (requires { world.volume_count(); }) {
    if (!world.volume_count()) return;
    const auto along = world.template volumes_along<Arch>(ray, active, t_end);
    if (along.empty()) return;
    const auto composite = [&](const VolumeSample<Arch>& v) {
      color = color + transmittance * v.color;
      transmittance = transmittance * (Fl(1.f) - v.alpha);
    };
    const auto integrate = [&](const auto& a, const Ray<Fl>& segment, const Ml& lanes, const Fl& end) {
      VolumeSample<Arch> v{Vec3<Fl>(Vec3f{0.f, 0.f, 0.f}), Fl(0.f)};
      world.template with_volume<Arch>(a.volume, segment, lanes, [&](const auto& model, const auto& object_ray) {
        v = model.template integrate<Arch>(object_ray, end, how, shade);
      });
      if (entry) {
        const Ml nearer = lanes & (v.hit_t < simd::min(entry->t, t_end));
        entry->t = simd::select(nearer, v.hit_t, entry->t);
        entry->volume = simd::select(nearer, simd::Int<Arch>(static_cast<std::int32_t>(a.volume)), entry->volume);
      }
      return v;
    };
    bool overlap = false;
    for (std::size_t i = 0; i < along.size() && !overlap; ++i)
      for (std::size_t j = i + 1; j < along.size() && !overlap; ++j)
        overlap = simd::any(simd::max(along[i].enter, along[j].enter) < simd::min(along[i].leave, along[j].leave));
    if (!overlap) {
      if (along.size() == 1) return composite(integrate(along[0], ray, active, t_end));
      std::vector<VolumeSample<Arch>> samples;
      samples.reserve(along.size());
      for (const auto& a : along) samples.push_back(integrate(a, ray, active & (a.enter <= a.leave), t_end));
      composite_in_depth_order<Arch>(along, samples, color, transmittance);
      return;
    }
    // The slabs cover where the rays cross the volumes' boxes.
    Fl start(INFINITY), leave(-INFINITY);
    float slab = INFINITY;
    for (const auto& a : along) {
      start = simd::min(start, a.enter), leave = simd::max(leave, a.leave);
      slab = std::min(slab, a.step / how.sampling_rate);
    }
    Ml lanes = active & (start < leave);
    Ray<Fl> segment = ray;
    while (simd::any(lanes)) {
      segment.tnear = start;
      const Fl end = simd::min(start + Fl(slab), leave);
      for (const auto& a : along) {
        const Ml in_slab = lanes & (a.enter < end) & (start <= a.leave);
        if (simd::any(in_slab)) composite(integrate(a, segment, in_slab, end));
      }
      start = start + Fl(slab);
      // Early ray termination, as each volume's own march stops at opacity 0.99.
      const Fl left = simd::max(simd::max(transmittance.x, transmittance.y), transmittance.z);
      lanes = lanes & (start < leave) & (left > Fl(0.01f));
    }
  }
}

/// The volumes' transmittance along `ray` up to `t_end` (shadow and AO rays, the path
/// tracer's alpha): the product over the volumes, which needs no depth order.
template <class Arch, class WorldT>
simd::Float<Arch> volume_transmittance(const WorldT& world, const VolumeIntegration& how,
                                       const Ray<simd::Float<Arch>>& ray, const simd::Mask<Arch>& active,
                                       const simd::Float<Arch>& t_end) {
  using Fl = simd::Float<Arch>;
  Fl through(1.f);
  if constexpr (requires { world.volume_count(); })
    if (world.volume_count())
      world.template for_each_volume_along<Arch>(ray, active, t_end, [&](const auto& model, const auto& object_ray) {
        through = through * (Fl(1.f) - model.template integrate<Arch>(object_ray, t_end, how).alpha);
      });
  return through;
}

}  // namespace detail
}  // namespace sciray
