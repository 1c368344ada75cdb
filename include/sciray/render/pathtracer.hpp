#pragma once
// The `pathtracer` renderer: unbiased Monte Carlo light transport with the materials of
// render/bsdf.hpp and the lights of render/light.hpp.
//
// At every surface the path estimates direct light twice, by sampling each light and by
// sampling the BSDF, and weighs the two with the power heuristic (multiple importance
// sampling, Veach 1997), so that small bright lights and sharp highlights both converge.
// Paths end by Russian roulette after `roulettePathLength` bounces, at `maxPathLength`,
// or when the BSDF absorbs them; `maxContribution` clamps fireflies (biased, off by
// default). The paths of a tile travel as a stream: after every bounce the live ones are
// packed into full packets again (render_stream).
//
// Emissive geometry (luminous, principled emissiveColor) is a light too: meshes and
// spheres, direct or instanced, moving or deforming, are sampled by area
// (render/geometry_light.hpp) and weighed against BSDF sampling like every other light
// with size; emitters of other types are found by BSDF sampling alone.
//
// Shadow rays pass surfaces that let light straight through (cut-out opacity, obj's
// transmission filter, thin glass, luminous transparency: bsdf.hpp's transparency()),
// filtered by them, as OSPRay's transparent shadows; so point and distant lights shine
// through them. A path that passes such a surface straight on keeps the vertex before it
// for multiple importance sampling (as OSPRay's): the light it then finds is weighed
// against light sampling from that vertex, whose shadow ray came through the same surface,
// and is not counted twice. Refracting surfaces stop shadow rays: light through glass
// arrives only along BSDF-sampled paths (caustics from lights with size and from the
// environment, none from point lights).
//
// Volumes are participating media (volume/volumetric_model.hpp): a path collides with
// them where delta tracking says, loses the part its albedo (the transfer function's
// colour) does not scatter, and leaves in a direction drawn from the Henyey–Greenstein
// phase function; next-event estimation weighs lights by the phase function and by the
// transmittance that ratio tracking estimates along the shadow ray. Volumes do not emit.
// As in OSPRay, a camera path's first collision with a volume is its first hit: alpha 1,
// depth and ids (primitive 0, the volume's object and instance ids) are there.
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <span>
#include <vector>

#include "sciray/math/random.hpp"
#include "sciray/render/bsdf.hpp"
#include "sciray/render/common.hpp"
#include "sciray/render/geometry_light.hpp"
#include "sciray/render/lambert_lanes.hpp"
#include "sciray/render/phase.hpp"

namespace sciray {

/// Which estimators of direct light a path uses: both weighed by multiple importance
/// sampling (the default), or one alone (for tests and charts: each alone is unbiased
/// too, but noisier where the other is good; delta lights need light sampling and
/// mirrors need BSDF sampling).
enum class LightSampling { mis, lights_only, bsdf_only };

struct PathTracerParams : RendererParams {
  int roulette_path_length = 5;  ///< roulettePathLength: bounces before Russian roulette starts
  float max_contribution = std::numeric_limits<float>::infinity();  ///< maxContribution
  LightSampling light_sampling = LightSampling::mis;
  /// geometryLights: emissive geometry is sampled as a light (else found by BSDF sampling only)
  bool geometry_lights = true;
  /// lightSamples: lights sampled per path vertex, each picked uniformly at random (as
  /// OSPRay 3.1 picks them); negative, or at least the number of lights: each light once;
  /// 0: none. Emissive geometry has its own sample per vertex either way.
  int light_samples = -1;
  /// backgroundRefraction: the background (colour or backplate) is seen through
  /// refracting surfaces — paths of specular transmissions only — as OSPRay's; else only
  /// along paths that kept their direction (camera rays, and through transparency).
  bool background_refraction = false;
};

template <class Arch, class WorldT>
class PathTracer {
public:
  using F = simd::Float<Arch>;
  using I = simd::Int<Arch>;
  using M = simd::Mask<Arch>;
  static constexpr int W = simd::width<Arch>;

  PathTracer(const WorldT& world, const PathTracerParams& params)
      : world_(&world),
        params_(params),
        geometry_lights_(params.light_sampling == LightSampling::bsdf_only || !params.geometry_lights ||
                                 params.light_samples == 0
                             ? GeometryLights<WorldT>()
                             : GeometryLights<WorldT>(world, params.materials)) {
    validate(params_, world.materials_needed(), "pathtracer");
    if (params_.roulette_path_length < 0)
      throw Error("pathtracer renderer: parameter 'roulettePathLength' must not be negative");
    if (!(params_.max_contribution > 0.f)) throw Error("pathtracer renderer: parameter 'maxContribution' must be positive");
    // No light samples (as OSPRay's lightSamples 0): lights are found by BSDF sampling only.
    if (params_.light_samples == 0) params_.light_sampling = LightSampling::bsdf_only;
    for (const Material& m : params_.materials) {
      textured_ = textured_ || has_maps(m);
      lambert_kd_.push_back(lambert_kd(m));
      normal_mapped_.push_back(has_normal_map(m));
      anisotropic_.push_back(is_anisotropic(m));
      derivatives_needed_.push_back(normal_mapped_.back() || anisotropic_.back());
      transparent_shadows_ = transparent_shadows_ || may_pass_straight(m);
    }
    // Colours' alpha cuts out any surface (and a surface without material is obj's).
    if constexpr (requires { world.translucent_colors(); })
      transparent_shadows_ = transparent_shadows_ || world.translucent_colors();
  }

  /// Each pixel's film positions come from a sequence of its own (render_frame), as in
  /// OSPRay's path tracer; scivis and ao keep OSPRay's points, the same in every pixel.
  bool jitters_film_per_pixel() const { return true; }
  /// A pixel's ids come from its nearest hit among the frame's samples (render_frame), as
  /// OSPRay's path tracer keeps them; scivis and ao keep the last sample's.
  bool ids_from_nearest_sample() const { return true; }

  /// One packet of camera rays: a stream of one packet.
  PixelSample<Arch> render(const Ray<F>& camera_ray, const M& active, const SampleIndex<Arch>& index = {}) const {
    const CameraPacket<Arch> packet{camera_ray, active, index};
    PixelSample<Arch> out;
    render_stream(std::span<const CameraPacket<Arch>>(&packet, 1), std::span<PixelSample<Arch>>(&out, 1));
    return out;
  }

  /// The paths of all `packets` (a tile's sample, from render_frame) as one stream: after
  /// every bounce the live paths are packed into full packets again, so the lanes of
  /// paths that ended (escaped, absorbed, stopped by roulette) carry other paths' rays.
  /// Each path's numbers and shading are its own, so an image does not depend on how
  /// paths share packets.
  void render_stream(std::span<const CameraPacket<Arch>> packets, std::span<PixelSample<Arch>> results) const {
    constexpr float inf = std::numeric_limits<float>::infinity();
    const std::size_t count = packets.size() * W;
    // Reused by each thread's streams: a Material is 1.6 kB, so the textured copies are
    // there only where some material has maps.
    thread_local std::vector<Path> paths;
    thread_local std::vector<Material> textured_storage;
    paths.assign(count, Path{});
    if (textured_ && textured_storage.size() < count) textured_storage.resize(count);
    std::vector<std::uint32_t> live;
    live.reserve(count);
    for (std::size_t k = 0; k < packets.size(); ++k) {
      const CameraPacket<Arch>& c = packets[k];
      const F reach = detail::max_depth<Arch>(params_, c.active, c.index);
      for (int i = 0; i < W; ++i) {
        Path& p = paths[k * W + static_cast<std::size_t>(i)];
        if (!simd::lane(c.active, i)) continue;
        p.rng = PixelRandom(static_cast<std::uint32_t>(simd::lane(c.index.pixel, i)), c.index.sample);
        if (textured_) p.textured_material = &textured_storage[k * W + static_cast<std::size_t>(i)];
        p.alive = true;
        p.org = {simd::lane(c.ray.org.x, i), simd::lane(c.ray.org.y, i), simd::lane(c.ray.org.z, i)};
        p.dir = {simd::lane(c.ray.dir.x, i), simd::lane(c.ray.dir.y, i), simd::lane(c.ray.dir.z, i)};
        p.time = simd::lane(c.ray.time, i);
        p.tnear = simd::lane(c.ray.tnear, i);
        p.tfar = simd::lane(reach, i);
        p.screen_x = simd::lane(c.index.screen_x, i), p.screen_y = simd::lane(c.index.screen_y, i);
        live.push_back(static_cast<std::uint32_t>(k * W + static_cast<std::size_t>(i)));
      }
    }
    Path dead[W];  // the lanes of a last, partly filled packet
    for (int depth = 0; depth <= params_.max_path_length && !live.empty(); ++depth) {
      for (std::size_t first = 0; first < live.size(); first += W) {
        PathLanes lanes;
        for (int i = 0; i < W; ++i)
          lanes.lane[i] = first + i < live.size() ? &paths[live[first + i]] : &dead[i];
        bounce(lanes, depth);
      }
      std::erase_if(live, [&](std::uint32_t i) { return !paths[i].alive; });
    }

    for (std::size_t k = 0; k < packets.size(); ++k) {
      alignas(64) float lanes[11][W];
      alignas(64) std::int32_t ids[3][W];
      for (int i = 0; i < W; ++i) {
        const Path& p = paths[k * W + static_cast<std::size_t>(i)];
        const float c[11] = {p.radiance.x, p.radiance.y, p.radiance.z, p.alpha, p.first_t,
                             p.first_normal.x, p.first_normal.y, p.first_normal.z,
                             p.first_albedo.x, p.first_albedo.y, p.first_albedo.z};
        for (int j = 0; j < 11; ++j) lanes[j][i] = c[j];
        for (int j = 0; j < 3; ++j) ids[j][i] = p.first_ids[j];
      }
      PixelSample<Arch>& out = results[k];
      out.color = {simd::load<Arch>(lanes[0]), simd::load<Arch>(lanes[1]), simd::load<Arch>(lanes[2])};
      out.alpha = simd::load<Arch>(lanes[3]);
      out.t = simd::load<Arch>(lanes[4]);
      out.normal = {simd::load<Arch>(lanes[5]), simd::load<Arch>(lanes[6]), simd::load<Arch>(lanes[7])};
      out.albedo = {simd::load<Arch>(lanes[8]), simd::load<Arch>(lanes[9]), simd::load<Arch>(lanes[10])};
      out.albedo = select(out.t < F(inf), out.albedo, Vec3<F>(params_.background_color));
      out.prim_id = simd::load<Arch>(ids[0]);
      out.geom_id = simd::load<Arch>(ids[1]);
      out.inst_id = simd::load<Arch>(ids[2]);
    }
  }

private:
  struct Path {
    PixelRandom rng;
    bool alive = false;
    Vec3f org, dir;
    float time = 0.f;  // the camera ray's: where lights of moving instances are
    float tnear = 0.f, tfar = 0.f;  // the camera ray's near clip and reach (map_maxDepth)
    float screen_x = 0.5f, screen_y = 0.5f;  // the camera sample's, for the background
    // The background is seen along straight paths (or, with backgroundRefraction, paths of
    // specular transmissions only).
    bool straight = true, specular_transmissions = true;
    Vec3f throughput{1.f, 1.f, 1.f};
    Vec3f radiance{0.f, 0.f, 0.f};
    float alpha = 0.f;
    ShadingPoint sp;
    Vec3f p;
    float offset = 0.f;  // how far rays leaving p start off the surface (detail::ray_offset)
    // The last vertex that chose the ray's direction (not passed straight through): its
    // sampling's pdf, whether it was a delta lobe, its normal and position.
    float previous_pdf = 0.f;
    bool previous_delta = true;  // the camera ray: lights it sees count fully
    Vec3f previous_normal{0.f, 0.f, 1.f};
    Vec3f vertex;
    bool passed_straight = false;  // the ray starts on a surface passed straight through since that vertex
    std::uint32_t medium = no_material;  // the material whose interior the path is in
    Material* textured_material = nullptr;  // where its material with maps resolved goes, if any has maps
    const Material* material = nullptr;  // the material at the path's current surface
    std::optional<LambertSurface> lambert;  // at a surface of Lambert's lobe alone: what it is
    // The first hit's channels: distance, normal, albedo, and primitive, object, instance ids.
    float first_t = std::numeric_limits<float>::infinity();
    Vec3f first_normal{0.f, 0.f, 0.f}, first_albedo{0.f, 0.f, 0.f};
    std::int32_t first_ids[3] = {-1, -1, -1};
  };

  /// The paths that fill a packet's lanes (indexed as an array of paths).
  struct PathLanes {
    std::array<Path*, W> lane;
    Path& operator[](int i) const { return *lane[static_cast<std::size_t>(i)]; }
  };

  /// Where a path scatters next: off a surface, or inside a volume.
  struct Vertex {
    enum class Kind : std::uint8_t { none, surface, medium };
    Kind kind = Kind::none;
    SurfacePoint surface;        // kind surface
    Vec3f albedo;                // kind medium: the part of the light scattered
    float anisotropy = 0.f;      // kind medium: Henyey–Greenstein g
    std::size_t volume = 0;      // kind medium: the placed volume collided with
  };

  /// One bounce of the paths in `path`'s lanes: their rays traced as a packet, light
  /// found along them, a light sample at each vertex and the next direction drawn.
  void bounce(const PathLanes& path, int depth) const {
    constexpr float inf = std::numeric_limits<float>::infinity();
    // The paths' rays as a packet (bounce rays start off the surface: tnear 0).
    alignas(64) float lanes[10][W];
    bool any_alive = false;
    for (int i = 0; i < W; ++i) {
      const Path& p = path[i];
      any_alive |= p.alive;
      const float v[10] = {p.org.x, p.org.y, p.org.z, p.dir.x, p.dir.y, p.dir.z, p.alive ? 1.f : 0.f,
                           depth == 0 ? p.tnear : 0.f, depth == 0 ? p.tfar : inf, p.time};
      for (int c = 0; c < 10; ++c) lanes[c][i] = v[c];
    }
    if (!any_alive) return;
    Ray<F> ray;
    ray.org = {simd::load<Arch>(lanes[0]), simd::load<Arch>(lanes[1]), simd::load<Arch>(lanes[2])};
    ray.dir = {simd::load<Arch>(lanes[3]), simd::load<Arch>(lanes[4]), simd::load<Arch>(lanes[5])};
    ray.tnear = simd::load<Arch>(lanes[7]);  // the camera's near clip
    ray.tfar = simd::load<Arch>(lanes[8]);
    ray.time = simd::load<Arch>(lanes[9]);
    const M live = simd::load<Arch>(lanes[6]) > F(0.f);
    const auto hit = accel::intersect<Arch>(world_->scene(), ray, live, depth == 0, world_->hit_filter());
    F t_event = simd::select(hit.hit, hit.t, F(inf));

    // A collision with a volume before the surface replaces the surface as the next vertex.
    Vertex vertex[W];
    M in_medium(false);
    if constexpr (requires { world_->volume_count(); })
      if (world_->volume_count()) in_medium = collide_with_volumes(path, ray, live, t_event, vertex);
    detail::for_each_surface<Arch>(
        *world_, ray, hit, live & !in_medium,
        [&](int i, const SurfacePoint& s) {
          vertex[i].kind = Vertex::Kind::surface;
          vertex[i].surface = s;
        },
        &derivatives_needed_);

    // Light found by the BSDF-sampled ray (or seen by the camera), and emission.
    for (int i = 0; i < W; ++i) {
      Path& p = path[i];
      if (!p.alive) continue;
      Vertex& v = vertex[i];
      const float t = v.kind == Vertex::Kind::none ? inf : simd::lane(t_event, i);
      add_lights_along(p, t, depth);
      if (v.kind == Vertex::Kind::none) {
        if (params_.background_refraction ? p.specular_transmissions : p.straight) {
          const float x = p.screen_x, y = p.screen_y;
          p.radiance = p.radiance + p.throughput * background_at(params_, x, y);
          // As OSPRay: what the surfaces passed let through is the background's share.
          const float through = std::clamp(
              0.212671f * p.throughput.x + 0.715160f * p.throughput.y + 0.072169f * p.throughput.z, 0.f, 1.f);
          p.alpha = 1.f - through + through * background_alpha_at(params_, x, y);
        }
        p.alive = false;
        continue;
      }
      if (p.medium != no_material) p.throughput = p.throughput * medium_transmittance(params_.materials[p.medium], t);
      if (depth == params_.max_path_length) p.alive = false;
      if (v.kind == Vertex::Kind::medium) {
        p.p = p.org + p.dir * t;
        p.throughput = p.throughput * v.albedo;
        if (depth == 0) {
          p.alpha = 1.f;
          p.first_t = t;
          p.first_albedo = v.albedo;
          if constexpr (requires { world_->volume_count(); }) {
            const auto [object, instance] = world_->volume_ids(v.volume);
            p.first_ids[0] = 0, p.first_ids[1] = object, p.first_ids[2] = instance;
          }
        }
        continue;
      }
      const SurfacePoint& s = v.surface;
      p.sp = shading_point(s);
      p.p = s.p;
      p.offset = detail::ray_offset(s.p, s.t, s.epsilon);
      p.material = p.textured_material ? &textured(material(s), s.uv, *p.textured_material) : &material(s);
      const Material& m = *p.material;
      set_lambert(p, s);
      // A refracting material's side is the path's, as OSPRay tracks media: it enters
      // unless it is inside this material already, whichever way the surface is wound.
      if (has_medium(m)) p.sp.entering = p.medium != s.material;
      if (const Vec3f e = emitted(m, p.sp, -p.dir); std::max({e.x, e.y, e.z}) > 0.f)
        add(p, p.throughput * e * emission_weight(p, hit, i, s.ng, p.time), depth);
      if (depth == 0) {
        p.alpha = 1.f;
        p.first_t = t;
        p.first_normal = s.n;
        p.first_albedo = albedo(m, p.sp);
        p.first_ids[0] = simd::lane(hit.prim_id, i);
        const auto [object, instance] =
            world_->channel_ids(static_cast<std::uint32_t>(simd::lane(hit.inst_id, i)),
                                static_cast<std::uint32_t>(simd::lane(hit.geom_id, i)));
        p.first_ids[1] = object, p.first_ids[2] = instance;
      }
    }

    // The paths at Lambert surfaces: their light samples and next directions go as packets.
    alignas(64) float lambert_lane[W];
    for (int i = 0; i < W; ++i)
      lambert_lane[i] = path[i].alive && vertex[i].kind == Vertex::Kind::surface && path[i].lambert ? 1.f : 0.f;
    const M lambert_lanes = simd::load<Arch>(lambert_lane) > F(0.f);

    std::optional<LambertPacket<Arch>> lambert;
    if (simd::any(lambert_lanes)) lambert = gather_lambert(path, lambert_lanes);

    sample_lights(path, vertex, lambert, ray.time);
    sample_geometry_lights(path, vertex, ray.time);

    // Continue each path by sampling its BSDF or phase function.
    if (lambert) sample_lambert(path, *lambert);
    for (int i = 0; i < W; ++i) {
      Path& p = path[i];
      const Vertex& v = vertex[i];
      if (!p.alive || v.kind == Vertex::Kind::none) continue;
      if (lambert_lane[i] > 0.f) {
        // sampled above
      } else if (!sample_direction(p, v)) {
        p.alive = false;
        continue;
      }
      // Russian roulette: continue with the probability the path's throughput suggests.
      if (depth + 1 >= params_.roulette_path_length) {
        const float survive = std::min(0.95f, std::max({p.throughput.x, p.throughput.y, p.throughput.z}));
        if (!(p.rng.next_1d() < survive)) {
          p.alive = false;
          continue;
        }
        p.throughput = p.throughput / survive;
      }
      if (!(std::max({p.throughput.x, p.throughput.y, p.throughput.z}) > 0.f)) p.alive = false;
    }
  }

  /// Draws a path's next direction at its vertex from the phase function or the BSDF;
  /// false where the BSDF absorbs the path.
  bool sample_direction(Path& p, const Vertex& v) const {
    const float u_lobe = p.rng.next_1d();
    const auto u = p.rng.next_2d();
    if (v.kind == Vertex::Kind::medium) {
      // The phase function is its own pdf: the weight is 1.
      const Vec3f scattered = sample_henyey_greenstein(p.dir, v.anisotropy, u.u, u.v);
      p.previous_pdf = henyey_greenstein(dot(p.dir, scattered), v.anisotropy);
      p.org = p.p;
      p.dir = scattered;
      p.previous_delta = false;
      p.previous_normal = splat(0.f);
      p.vertex = p.p;
      p.passed_straight = false;
      p.straight = p.specular_transmissions = false;
      return true;
    }
    const Material& m = *p.material;
    const std::optional<BsdfSample> b = sample(m, p.sp, -p.dir, u_lobe, u.u, u.v);
    if (!b || !(b->pdf > 0.f)) return false;
    p.throughput = p.throughput * b->weight;
    p.straight = p.straight && b->wi == p.dir;
    p.specular_transmissions = p.specular_transmissions && b->delta && b->transmitted;
    // Straight through: light found beyond is weighed as from the vertex before.
    p.passed_straight = b->straight;
    if (!b->straight) {
      p.previous_pdf = b->pdf;
      p.previous_delta = b->delta;
      p.previous_normal = p.sp.n;
      p.vertex = p.p;
    }
    if (b->transmitted && has_medium(m)) p.medium = p.medium == v.surface.material ? no_material : v.surface.material;
    // A reflection leaves from wo's side even where the shading normal sent it below
    // the geometric surface: it meets the surface again (as OSPRay's, whose furnace holds).
    p.org = p.p + (b->transmitted ? -p.sp.ng : p.sp.ng) * p.offset;
    p.dir = b->wi;
    return true;
  }

  /// Whether a path at surface s scatters by Lambert's lobe alone, and as what
  /// (lambert_lanes.hpp), or not (p.lambert none).
  void set_lambert(Path& p, const SurfacePoint& s) const {
    static const Vec3f own_colors = *lambert_kd(ObjMaterial{{1.f, 1.f, 1.f}});
    static const Vec3f default_grey = *lambert_kd(ObjMaterial{});
    const std::optional<Vec3f> kd = s.material != no_material ? lambert_kd_[s.material]
                                    : s.has_color                ? own_colors
                                                                 : default_grey;
    p.lambert = kd ? lambert_surface(*kd, p.sp, -p.dir) : std::nullopt;
  }

  /// The paths at Lambert surfaces (`lanes`) as a packet, gathered once a bounce.
  static LambertPacket<Arch> gather_lambert(const PathLanes& path, const M& lanes) {
    alignas(64) float in[20][W];
    LambertPacket<Arch> packet;
    packet.lanes = lanes;
    for (int i = 0; i < W; ++i) {
      Path& p = path[i];
      packet.rngs[static_cast<std::size_t>(i)] = &p.rng;
      const bool lane = simd::lane(lanes, i);
      const LambertSurface surface = lane ? *p.lambert : LambertSurface{};
      // Idle lanes get a unit normal, so that their (unused) arithmetic stays finite.
      const Vec3f n = lane ? p.sp.n : Vec3f{0.f, 0.f, 1.f}, fn = lane ? surface.frame_normal : n, ng = lane ? p.sp.ng : n;
      const float c[20] = {p.p.x, p.p.y, p.p.z, n.x, n.y, n.z, fn.x, fn.y, fn.z, ng.x, ng.y, ng.z,
                           surface.tint.x, surface.tint.y, surface.tint.z,
                           p.throughput.x, p.throughput.y, p.throughput.z, lane ? p.offset : 0.f,
                           surface.scatters ? 1.f : 0.f};
      for (int k = 0; k < 20; ++k) in[k][i] = c[k];
    }
    const auto lane3 = [&](int k) {
      return Vec3<F>{simd::load<Arch>(in[k]), simd::load<Arch>(in[k + 1]), simd::load<Arch>(in[k + 2])};
    };
    packet.at = lane3(0), packet.shading_normal = lane3(3), packet.frame_normal = lane3(6), packet.ng = lane3(9);
    packet.tint = lane3(12), packet.throughput = lane3(15);
    packet.offset = simd::load<Arch>(in[18]);
    packet.scatters = lanes & (simd::load<Arch>(in[19]) > F(0.f));
    return packet;
  }

  /// The next directions of the Lambert packet's paths (sample_lambert_directions),
  /// written back to the paths.
  void sample_lambert(const PathLanes& path, const LambertPacket<Arch>& packet) const {
    const LambertDirections<Arch> d = sample_lambert_directions(packet);
    alignas(64) float out[10][W];
    const F values[10] = {d.dir.x,          d.dir.y, d.dir.z, d.throughput.x, d.throughput.y, d.throughput.z,
                          d.pdf,            d.org.x, d.org.y, d.org.z};
    for (int k = 0; k < 10; ++k) simd::store<Arch>(out[k], values[k]);
    for (int i = 0; i < W; ++i) {
      if (!simd::lane(packet.lanes, i)) continue;
      Path& p = path[i];
      if (!simd::lane(d.scattered, i)) {
        p.alive = false;
        continue;
      }
      const Vec3f dir{out[0][i], out[1][i], out[2][i]};
      p.throughput = {out[3][i], out[4][i], out[5][i]};
      p.straight = p.straight && dir == p.dir;
      p.specular_transmissions = p.passed_straight = p.previous_delta = false;
      p.previous_pdf = out[6][i];
      p.previous_normal = p.sp.n;
      p.vertex = p.p;
      p.org = {out[7][i], out[8][i], out[9][i]};
      p.dir = dir;
    }
  }

  /// Independent uniform numbers for the lanes of live paths (others get 0.5).
  F independent_uniforms(const PathLanes& path) const {
    alignas(64) float u[W];
    for (int i = 0; i < W; ++i) u[i] = path[i].alive ? path[i].rng.next_independent() : 0.5f;
    return simd::load<Arch>(u);
  }

  /// Delta tracking through every volume up to `t_end`: the nearest collision of each
  /// lane (independent media superpose, so the nearest of their collisions is the
  /// mixture's). Sets t_end to it and fills the lane's medium vertex.
  M collide_with_volumes(const PathLanes& path, const Ray<F>& ray, const M& live, F& t_end, Vertex* vertex) const {
    M collided(false);
    Vec3<F> albedo(splat(0.f));
    F anisotropy(0.f);
    I volume(0);
    for (const auto& along : world_->template volumes_along<Arch>(ray, live, t_end))
      world_->template with_volume<Arch>(along.volume, ray, live & (along.enter <= along.leave),
                                         [&](const auto& model, const auto& object_ray) {
        const auto c = model.template sample_collision<Arch>(object_ray, t_end, world_->clipping(),
                                                             [&] { return independent_uniforms(path); });
        collided = collided | c.hit;
        t_end = simd::select(c.hit, c.t, t_end);
        albedo = select(c.hit, c.albedo, albedo);
        anisotropy = simd::select(c.hit, F(model.anisotropy()), anisotropy);
        volume = simd::select(c.hit, I(static_cast<std::int32_t>(along.volume)), volume);
      });
    for (int i = 0; i < W; ++i) {
      if (!simd::lane(collided, i)) continue;
      vertex[i].kind = Vertex::Kind::medium;
      vertex[i].volume = static_cast<std::size_t>(simd::lane(volume, i));
      vertex[i].albedo = {simd::lane(albedo.x, i), simd::lane(albedo.y, i), simd::lane(albedo.z, i)};
      vertex[i].anisotropy = simd::lane(anisotropy, i);
    }
    return collided;
  }

  /// Transmittance through the volumes along the shadow rays of `lanes`, by ratio tracking.
  F volume_transmittance(const PathLanes& path, const Ray<F>& ray, const M& lanes) const {
    F transmittance(1.f);
    if constexpr (requires { world_->volume_count(); })
      world_->template for_each_volume_along<Arch>(ray, lanes, ray.tfar, [&](const auto& model, auto object_ray) {
        object_ray.active = object_ray.active & (transmittance > F(0.f));
        if (!simd::any(object_ray.active)) return;
        transmittance = transmittance * model.template transmittance<Arch>(object_ray, ray.tfar, world_->clipping(),
                                                                           [&] { return independent_uniforms(path); });
      });
    return transmittance;
  }

  /// A surface's material; without one, a white Lambertian that shows the geometry's
  /// colours as they are (0.8 grey where it has none), like scivis.
  const Material& material(const SurfacePoint& s) const {
    static const Material own_colors = ObjMaterial{{1.f, 1.f, 1.f}};
    static const Material default_grey = ObjMaterial{};
    if (s.material != no_material) return params_.materials[s.material];
    return s.has_color ? own_colors : default_grey;
  }

  /// Adds a contribution, clamped by maxContribution after the camera's first hit.
  void add(Path& p, Vec3f c, int depth) const {
    if (depth > 0) {
      const float peak = std::max({c.x, c.y, c.z});
      if (peak > params_.max_contribution) c = c * (params_.max_contribution / peak);
    }
    if (std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(c.z)) p.radiance = p.radiance + c;
  }

  static float power_heuristic(float a, float b) {
    if (!std::isfinite(a)) return 1.f;
    const float a2 = a * a, b2 = b * b;
    return a2 + b2 > 0.f ? a2 / (a2 + b2) : 0.f;
  }

  /// Lights the ray (org, dir) of path p reaches before distance t: lights with size in
  /// front of the surface, and lights at infinity where the ray escapes.
  void add_lights_along(Path& p, float t, int depth) const {
    constexpr float inf = std::numeric_limits<float>::infinity();
    const float picked = light_pick_probability();
    for (std::size_t k = 0; k < light_count(); ++k)
      with_light(k, p.time, [&](const Light& light) {
        // As OSPRay: an invisible light is not seen along a straight path (camera rays and
        // their straight transmissions through thinGlass and the like).
        if (p.straight && !std::visit([](const auto& l) { return l.visible; }, light)) return;
        if (is_delta(light)) return;
        LightEval e = eval(light, p.org, p.previous_normal, p.dir, t);
        if (!(e.pdf > 0.f) && !(std::max({e.radiance.x, e.radiance.y, e.radiance.z}) > 0.f)) return;
        // Light sampling at the vertex found it through the surfaces passed since: from there.
        if (p.passed_straight && !p.previous_delta) e.pdf = eval(light, p.vertex, p.previous_normal, p.dir, inf).pdf;
        // The camera sees lights directly; a bounce after a specular lobe had no light sample to share with.
        float w = p.previous_delta ? 1.f : power_heuristic(p.previous_pdf, e.pdf * picked);
        if (!p.previous_delta && params_.light_sampling != LightSampling::mis)
          w = params_.light_sampling == LightSampling::bsdf_only ? 1.f : 0.f;
        add(p, p.throughput * e.radiance * w, depth);
      });
  }

  std::size_t light_count() const { return params_.lights.size() + params_.moving_lights.size(); }
  /// Calls f with light k (the fixed lights, then those of moving instances) at `time`.
  template <class Fn>
  void with_light(std::size_t k, float time, Fn&& f) const {
    if (k < params_.lights.size()) return f(params_.lights[k]);
    f(params_.moving_lights[k - params_.lights.size()].at(time));
  }
  /// lightSamples below the number of lights: each light sample picks its light.
  bool picks_lights() const {
    return params_.light_samples > 0 && static_cast<std::size_t>(params_.light_samples) < light_count();
  }
  /// How often a vertex's light samples pick a given light, on average (lightSamples /
  /// lights; 1 when every light is sampled).
  float light_pick_probability() const {
    return picks_lights() ? static_cast<float>(params_.light_samples) / static_cast<float>(light_count()) : 1.f;
  }

  /// Next-event estimation: one sample of every light for every path at a vertex (or
  /// of lightSamples lights picked at random, each lane its own), the shadow rays of one
  /// round traced as a packet (at the camera rays' `time`, where lights of moving
  /// instances are placed) and attenuated by the volumes they cross.
  void sample_lights(const PathLanes& path, const Vertex* vertex, const std::optional<LambertPacket<Arch>>& lambert,
                     const F& time) const {
    // Without light sampling only BSDF-sampled rays find lights; delta lights then vanish.
    if (params_.light_sampling == LightSampling::bsdf_only || light_count() == 0) return;
    const bool pick = picks_lights();
    const float picked = light_pick_probability();
    const std::size_t rounds = pick ? static_cast<std::size_t>(params_.light_samples) : light_count();
    for (std::size_t round = 0; round < rounds; ++round) {
      Shadow shadow[W];
      // A round of one fixed light for every path: the Lambert lanes' samples as a packet.
      M packet(false);
      if (!pick && round < params_.lights.size() && lambert &&
          shadows_of_lambert_packet(params_.lights[round], *lambert, shadow))
        packet = lambert->lanes;
      for (int i = 0; i < W; ++i) {
        Path& p = path[i];
        const Vertex& v = vertex[i];
        if (!p.alive || v.kind == Vertex::Kind::none || simd::lane(packet, i)) continue;
        const std::size_t k =
            pick ? std::min(static_cast<std::size_t>(p.rng.next_1d() * static_cast<float>(light_count())), light_count() - 1)
                 : round;
        with_light(k, p.time, [&](const Light& light) {
          const bool medium = v.kind == Vertex::Kind::medium;
          const auto u = p.rng.next_2d();
          const std::optional<LightSample> ls = sample(light, p.p, medium ? splat(0.f) : p.sp.n, u.u, u.v);
          if (!ls) return;
          const BsdfValue f = scattering(p, v, ls->dir);
          if (!(std::max({f.f_cos.x, f.f_cos.y, f.f_cos.z}) > 0.f)) return;
          const float w = std::isfinite(ls->pdf) && params_.light_sampling == LightSampling::mis
                              ? power_heuristic(ls->pdf * picked, f.pdf)
                              : 1.f;
          shadow[i] = {p.throughput * f.f_cos * ls->weight * (w / picked), ls->dir,
                       std::isfinite(ls->dist) ? ls->dist * (1.f - 1e-4f) : std::numeric_limits<float>::infinity(),
                       std::nullopt};
        });
      }
      cast_shadow_rays(path, vertex, shadow, time);
    }
  }

  /// Next-event estimation of emissive geometry: one point on an emitter for every path
  /// at a vertex, its emission read from the surface there as a hit would (the synthetic
  /// hits go through for_each_surface as a packet), weighed against BSDF sampling.
  void sample_geometry_lights(const PathLanes& path, const Vertex* vertex, const F& time) const {
    if (geometry_lights_.empty()) return;
    alignas(64) float lanes[12][W];  // ray origin and direction; hit t, u, v, ng
    alignas(64) std::int32_t ids[3][W];
    float pdf_area[W];
    for (int i = 0; i < W; ++i) {
      for (auto& c : lanes) c[i] = 0.f;
      lanes[3][i] = 1.f;  // a unit direction in unused lanes
      for (auto& c : ids) c[i] = -1;
      Path& p = path[i];
      if (!p.alive || vertex[i].kind == Vertex::Kind::none) continue;
      const float u_pick = p.rng.next_1d();
      const auto u = p.rng.next_2d();
      const std::optional<EmitterSample> e = geometry_lights_.sample(u_pick, u.u, u.v, simd::lane(time, i));
      if (!e) continue;
      const Vec3f d = e->p - p.p;
      const float dist = length(d);
      if (!(dist > 0.f)) continue;
      const Vec3f w = d / dist;
      const float c[12] = {p.p.x, p.p.y, p.p.z, w.x, w.y, w.z, dist, e->u, e->v, e->ng_object.x, e->ng_object.y, e->ng_object.z};
      for (int k = 0; k < 12; ++k) lanes[k][i] = c[k];
      ids[0][i] = static_cast<std::int32_t>(e->prim_id);
      ids[1][i] = static_cast<std::int32_t>(e->geom_id);
      ids[2][i] = static_cast<std::int32_t>(e->inst_id);
      pdf_area[i] = e->pdf_area;
    }
    Ray<F> ray;
    ray.org = {simd::load<Arch>(lanes[0]), simd::load<Arch>(lanes[1]), simd::load<Arch>(lanes[2])};
    ray.dir = {simd::load<Arch>(lanes[3]), simd::load<Arch>(lanes[4]), simd::load<Arch>(lanes[5])};
    ray.time = time;
    accel::Hit<Arch> hit;
    hit.prim_id = simd::load<Arch>(ids[0]), hit.geom_id = simd::load<Arch>(ids[1]), hit.inst_id = simd::load<Arch>(ids[2]);
    hit.t = simd::load<Arch>(lanes[6]), hit.u = simd::load<Arch>(lanes[7]), hit.v = simd::load<Arch>(lanes[8]);
    hit.time = time;
    hit.hit = hit.t > F(0.f);  // the lanes with a sample
    if (!simd::any(hit.hit)) return;
    hit.ng = {simd::load<Arch>(lanes[9]), simd::load<Arch>(lanes[10]), simd::load<Arch>(lanes[11])};
    Shadow shadow[W];
    detail::for_each_surface<Arch>(*world_, ray, hit, hit.hit, [&](int i, const SurfacePoint& s) {
      const Path& p = path[i];
      Material storage;
      const Material& m = textured(material(s), s.uv, storage);
      const Vec3f w{lanes[3][i], lanes[4][i], lanes[5][i]};
      const Vec3f radiance = emitted(m, {s.n, s.ng, s.front, s.color, s.alpha, s.p, std::nullopt, s.uv}, -w);
      const float dist = lanes[6][i], cos_light = std::abs(dot(w, s.ng));
      if (!(std::max({radiance.x, radiance.y, radiance.z}) > 0.f) || !(cos_light > 0.f)) return;
      const float light_pdf = pdf_area[i] * dist * dist / cos_light;  // per solid angle
      const BsdfValue f = scattering(p, vertex[i], w);
      if (!(std::max({f.f_cos.x, f.f_cos.y, f.f_cos.z}) > 0.f)) return;
      const float mis = params_.light_sampling == LightSampling::mis ? power_heuristic(light_pdf, f.pdf) : 1.f;
      // The shadow ray ends just off the emitter, on the side it leaves towards the path.
      const Vec3f end = s.p + s.ng * detail::ray_offset(s.p, dist, s.epsilon);
      shadow[i] = {p.throughput * f.f_cos * radiance * (mis / light_pdf), w, 0.f, end};
    });
    cast_shadow_rays(path, vertex, shadow, time);
  }

  /// The weight of emission a path finds on surface `hit` lane i (distance t, world
  /// geometric normal ng) against the chance that light sampling found it: 1 for the
  /// camera ray, after specular bounces and on emitters light sampling does not pick.
  float emission_weight(const Path& p, const accel::Hit<Arch>& hit, int i, const Vec3f& ng, float time) const {
    if (p.previous_delta || geometry_lights_.empty()) return 1.f;
    const Vec3f ng_object{simd::lane(hit.ng.x, i), simd::lane(hit.ng.y, i), simd::lane(hit.ng.z, i)};
    const float pdf_area = geometry_lights_.pdf_area(static_cast<std::uint32_t>(simd::lane(hit.inst_id, i)),
                                                     static_cast<std::uint32_t>(simd::lane(hit.geom_id, i)),
                                                     static_cast<std::uint32_t>(simd::lane(hit.prim_id, i)), ng_object, time);
    if (!(pdf_area > 0.f)) return 1.f;
    if (params_.light_sampling == LightSampling::lights_only) return 0.f;
    // The distance from the vertex that chose the direction (straight passes included).
    const float t = simd::lane(hit.t, i) + (p.passed_straight ? length(p.org - p.vertex) : 0.f);
    const float cos_light = std::abs(dot(p.dir, ng));
    return cos_light > 0.f ? power_heuristic(p.previous_pdf, pdf_area * t * t / cos_light) : 1.f;
  }

  /// What a path's vertex scatters towards wi: the phase function in a medium, the BSDF
  /// (times the cosine) on a surface.
  BsdfValue scattering(const Path& p, const Vertex& v, const Vec3f& wi) const {
    if (v.kind != Vertex::Kind::medium)
      return p.lambert ? lambert_value(*p.lambert, p.sp.ng, wi) : eval(*p.material, p.sp, -p.dir, wi);
    BsdfValue f;
    f.pdf = henyey_greenstein(dot(p.dir, wi), v.anisotropy);
    f.f_cos = splat(f.pdf);
    return f;
  }

  /// A light sample's contribution to one path, if nothing blocks the shadow ray of
  /// direction `dir` and length `reach`, or, to a point on a surface, the ray that ends
  /// at `end` (from wherever the ray starts off the path's surface: at grazing angles
  /// that offset moves the emitter's plane along the ray by more than any fixed margin).
  struct Shadow {
    Vec3f contribution{0.f, 0.f, 0.f};
    Vec3f dir{0.f, 0.f, 1.f};
    float reach = 0.f;
    std::optional<Vec3f> end;
  };

  /// Light `light`'s samples for the Lambert packet (sample_light_lambert) as the lanes'
  /// shadow rays; false (nothing drawn) for the kinds that go lane by lane.
  bool shadows_of_lambert_packet(const Light& light, const LambertPacket<Arch>& packet, Shadow* shadow) const {
    const auto samples = sample_light_lambert(light, packet, params_.light_sampling == LightSampling::mis);
    if (!samples) return false;
    alignas(64) float out[7][W];
    const F values[7] = {samples->contribution.x, samples->contribution.y, samples->contribution.z,
                         samples->dir.x,          samples->dir.y,          samples->dir.z,
                         samples->reach};
    for (int k = 0; k < 7; ++k) simd::store<Arch>(out[k], values[k]);
    for (int i = 0; i < W; ++i)
      if (simd::lane(samples->sampled, i))
        shadow[i] = {{out[0][i], out[1][i], out[2][i]}, {out[3][i], out[4][i], out[5][i]}, out[6][i], std::nullopt};
    return true;
  }

  /// Traces the shadow rays of the lanes with a contribution as a packet (off each
  /// surface on the side they leave) and adds what arrives, attenuated by volumes.
  void cast_shadow_rays(const PathLanes& path, const Vertex* vertex, const Shadow* shadow, const F& time) const {
    alignas(64) float ray_lanes[8][W];
    bool any = false;
    for (int i = 0; i < W; ++i) {
      const Shadow& s = shadow[i];
      const bool wanted = std::max({s.contribution.x, s.contribution.y, s.contribution.z}) > 0.f;
      any |= wanted;
      Vec3f org = path[i].p;
      if (wanted && vertex[i].kind == Vertex::Kind::surface) {
        const Vec3f& ng = path[i].sp.ng;
        const bool below = dot(s.dir, ng) < 0.f;  // transmission: leave from the other side
        org = org + (below ? -ng : ng) * path[i].offset;
      }
      Vec3f dir = s.dir;
      float reach = s.reach;
      if (s.end) {
        const Vec3f d = *s.end - org;
        reach = length(d);
        dir = reach > 0.f ? d / reach : s.dir;
      }
      const float c[8] = {org.x, org.y, org.z, dir.x, dir.y, dir.z, reach, wanted ? 1.f : 0.f};
      for (int k = 0; k < 8; ++k) ray_lanes[k][i] = wanted ? c[k] : 0.f;
    }
    if (!any) return;
    Ray<F> ray;
    ray.org = {simd::load<Arch>(ray_lanes[0]), simd::load<Arch>(ray_lanes[1]), simd::load<Arch>(ray_lanes[2])};
    ray.dir = {simd::load<Arch>(ray_lanes[3]), simd::load<Arch>(ray_lanes[4]), simd::load<Arch>(ray_lanes[5])};
    ray.tnear = F(0.f);
    ray.tfar = simd::load<Arch>(ray_lanes[6]);
    ray.time = time;
    const M cast = simd::load<Arch>(ray_lanes[7]) > F(0.f);
    Vec3f filter[W];
    for (Vec3f& f : filter) f = splat(1.f);
    const M unblocked = transparent_shadows_
                            ? pass_transparent_surfaces(ray, cast, filter)
                            : cast & !accel::occluded<Arch>(world_->scene(), ray, cast, false, world_->hit_filter());
    const F transmittance = volume_transmittance(path, ray, unblocked);
    for (int i = 0; i < W; ++i)
      if (simd::lane(unblocked, i)) add(path[i], shadow[i].contribution * filter[i] * simd::lane(transmittance, i), 1);
  }

  /// The lanes of `ray` that reach its end through surfaces that let light straight
  /// through, each such surface's transparency() multiplied into the lane's `filter`. As
  /// OSPRay's, a shadow ray passes fewer than maxPathLength surfaces.
  M pass_transparent_surfaces(Ray<F> ray, M live, Vec3f* filter) const {
    M reached(false);
    for (int passed = 0; simd::any(live); ++passed) {
      const auto hit = accel::intersect<Arch>(world_->scene(), ray, live, false, world_->hit_filter());
      reached = reached | (live & !hit.hit);
      if (passed + 1 >= params_.max_path_length) break;
      alignas(64) float onward[W], tnear[W];
      for (int i = 0; i < W; ++i) onward[i] = 0.f, tnear[i] = simd::lane(ray.tnear, i);
      detail::for_each_surface<Arch>(
          *world_, ray, hit, live & hit.hit,
          [&](int i, const SurfacePoint& s) {
            Material storage;
            const Vec3f wo{-simd::lane(ray.dir.x, i), -simd::lane(ray.dir.y, i), -simd::lane(ray.dir.z, i)};
            filter[i] = filter[i] * transparency(textured(material(s), s.uv, storage), shading_point(s), wo);
            if (!(std::max({filter[i].x, filter[i].y, filter[i].z}) > 0.f)) return;
            onward[i] = 1.f;
            tnear[i] = s.t + detail::ray_offset(s.p, s.t, s.epsilon);
          },
          &derivatives_needed_);
      live = simd::load<Arch>(onward) > F(0.f);
      ray.tnear = simd::load<Arch>(tnear);
    }
    return reached;
  }

  /// The BSDF's view of a surface hit: its normal (mapped where the material has a normal
  /// map), colour, side and, for anisotropic materials, tangent.
  ShadingPoint shading_point(const SurfacePoint& s) const {
    const bool mapped = s.material != no_material && normal_mapped_[s.material];
    const Vec3f n = mapped ? mapped_normal(material(s), s.n, s.dpds, s.dpdt, s.uv) : s.n;
    const auto coat_n = mapped ? mapped_coat_normal(material(s), s.n, s.dpds, s.dpdt, s.uv) : std::nullopt;
    ShadingPoint sp{n, s.ng, s.front, s.color, s.alpha, s.p, coat_n, s.uv};
    if (s.material != no_material && anisotropic_[s.material]) sp.tangent = s.dpds;
    return sp;
  }

  const WorldT* world_;
  PathTracerParams params_;
  GeometryLights<WorldT> geometry_lights_;  ///< emissive geometry, for light sampling
  std::vector<std::optional<Vec3f>> lambert_kd_;  ///< per material: lambert_kd()
  std::vector<bool> normal_mapped_;       ///< per material: has a normal map
  std::vector<bool> anisotropic_;         ///< per material: reflects anisotropically (is_anisotropic)
  std::vector<bool> derivatives_needed_;  ///< per material: either, so its hits need dP/ds and dP/dt
  bool transparent_shadows_ = false;      ///< some surface may let shadow rays through (transparency())
  bool textured_ = false;                 ///< some material has maps, read per hit (textured())
};

}  // namespace sciray
