#pragma once
// Emissive geometry as lights (OSPRay's geometry lights): the path tracer samples every
// primitive whose material emits (luminous, principled with emissiveColor) by area, so
// that small emitters converge by next-event estimation instead of by the rare BSDF
// sample that hits them.
//
// One distribution covers all emitting primitives of the world, direct and instanced:
// a primitive is picked with probability proportional to its area (at the start of its
// motion) times its material's emission, then a point on it uniformly by area. `pdf_area`
// answers for any hit how likely `sample` was to pick that point, so the path tracer can
// weigh the light sample against the BSDF sample that finds the same point (multiple
// importance sampling). Triangle and quad meshes (deforming ones at the ray's time) and
// spheres are sampled; other geometry (curves, boxes, planes, discs, isosurfaces) still
// emits where paths hit it, at full weight, as before.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <optional>
#include <unordered_map>
#include <vector>

#include "sciray/geometry/spheres.hpp"
#include "sciray/geometry/triangle_mesh.hpp"
#include "sciray/math/motion.hpp"
#include "sciray/render/common.hpp"
#include "sciray/render/material.hpp"

namespace sciray {

/// How strongly `m` emits, before textures and geometry colours: the largest component
/// of luminous color * intensity or of principled emissiveColor, a mix's parts' weighted by
/// its factor; 0 for the rest.
inline float emission_strength(const Material& m) {
  const auto peak = [](const Vec3f& c) { return std::max({c.x, c.y, c.z}); };
  if (const auto* luminous = std::get_if<LuminousMaterial>(&m)) return peak(luminous->color) * luminous->intensity;
  if (const auto* principled = std::get_if<PrincipledMaterial>(&m)) return peak(principled->emissive_color);
  if (const auto* mix = std::get_if<MixMaterial>(&m)) {
    // Called before the renderer validates its materials: a missing part emits nothing.
    const auto part = [&](const std::shared_ptr<const MixPart>& p) { return p ? emission_strength(p->material) : 0.f; };
    return part(mix->material1) * (1.f - mix->factor) + part(mix->material2) * mix->factor;
  }
  return 0.f;
}

/// A point on an emitting primitive, described as Embree would report a hit there.
struct EmitterSample {
  std::uint32_t inst_id, geom_id, prim_id;  ///< inst_id RTC_INVALID_GEOMETRY_ID for direct geometry
  float u, v;                               ///< Embree's hit coordinates of the point
  Vec3f p;                                  ///< world position
  Vec3f ng_object;                          ///< geometric normal in the geometry's own space
  float pdf_area;                           ///< per unit of world area
};

template <class WorldT>
class GeometryLights {
public:
  GeometryLights() = default;

  /// Collects the emitting primitives of `world` shaded with `materials`.
  GeometryLights(const WorldT& world, const std::vector<Material>& materials) {
    const auto collect = [&](const auto& group, std::uint32_t inst_id, const MotionTransform* placement) {
      for (std::uint32_t id = 0; id < group.geometry_count(); ++id) {
        const std::uint32_t material = group.material(id);
        const std::vector<std::uint32_t>* per_primitive = group.primitive_materials(id);
        const auto strength = [&](std::uint32_t prim) {
          const std::uint32_t m = per_primitive ? detail::primitive_material(*per_primitive, static_cast<std::int32_t>(prim))
                                                : material;
          return m < materials.size() ? emission_strength(materials[m]) : 0.f;
        };
        if (!per_primitive && strength(0) <= 0.f) continue;
        group.visit(id, [&](const auto& geometry) { add(geometry, inst_id, id, placement, strength); });
      }
    };
    collect(world, RTC_INVALID_GEOMETRY_ID, nullptr);
    const auto first_instance = static_cast<std::uint32_t>(world.geometry_count());
    for (std::uint32_t i = 0; i < world.instance_count(); ++i)
      collect(world.instance_group(i), first_instance + i, &world.instance_motion(i));
    if (total_ > 0.)
      for (float& c : cdf_) c = static_cast<float>(c / total_);
    for (Emitter& e : emitters_)
      for (float& w : e.probability) w = static_cast<float>(w / total_);
  }

  bool empty() const { return picks_.empty(); }

  /// A point on an emitter, chosen with `u_pick` and placed with (u1, v1), where the
  /// world is at `time`; none where the chosen emitter is absent then.
  std::optional<EmitterSample> sample(float u_pick, float u1, float u2, float time) const {
    if (empty()) return std::nullopt;
    const std::size_t k = std::min<std::size_t>(
        static_cast<std::size_t>(std::upper_bound(cdf_.begin(), cdf_.end(), u_pick) - cdf_.begin()), cdf_.size() - 1);
    const Emitter& e = emitters_[picks_[k].emitter];
    const std::uint32_t prim = picks_[k].prim;
    const std::optional<Affine3f> placement = placement_at(e, time);
    if (!placement) return std::nullopt;
    EmitterSample s{e.inst_id, e.geom_id, prim, 0.f, 0.f, {}, {}, 0.f};
    if (e.mesh) {
      if (!e.mesh->present_at(time)) return std::nullopt;
      const Face f = face(*e.mesh, prim, time, *placement);
      if (!(f.area > 0.f)) return std::nullopt;
      // A half by area (u1 reused, rescaled), then uniform barycentrics (c1, c2) on it.
      const bool first = f.corners == 3 || u1 * f.area < f.half_area[0];
      const float x = first ? (f.corners == 3 ? u1 : u1 * f.area / f.half_area[0])
                            : (u1 * f.area - f.half_area[0]) / f.half_area[1];
      const float r = std::sqrt(std::clamp(x, 0.f, 1.f)), c1 = 1.f - r, c2 = u2 * r;
      if (first) {
        // Triangle (v0, v1, v2), or the quad's half (v0, v1, v3): Embree's (u, v) are (c1, c2).
        s.p = f.world[0] * (1.f - c1 - c2) + f.world[1] * c1 + f.world[f.corners == 3 ? 2 : 3] * c2;
        s.u = c1, s.v = c2;
        s.ng_object = f.normal_object[0];
      } else {
        // The quad's half (v2, v3, v1), where Embree reports (1 - c1, 1 - c2).
        s.p = f.world[2] * (1.f - c1 - c2) + f.world[3] * c1 + f.world[1] * c2;
        s.u = 1.f - c1, s.v = 1.f - c2;
        s.ng_object = f.normal_object[1];
      }
      s.pdf_area = e.probability[prim] / f.area;
    } else {
      const auto [center, radius] = sphere(*e.spheres, prim);
      const float z = 1.f - 2.f * u1, ring = std::sqrt(std::max(0.f, 1.f - z * z)), phi = 2.f * std::numbers::pi_v<float> * u2;
      const Vec3f n{ring * std::cos(phi), ring * std::sin(phi), z};
      s.p = placement->point(center + n * radius);
      s.ng_object = n;
      const float area = sphere_area(radius, n, *placement);
      if (!(area > 0.f)) return std::nullopt;
      s.pdf_area = e.probability[prim] / area;
    }
    return s;
  }

  /// The density per unit world area with which `sample` picks the point a hit reports
  /// on primitive `prim_id` of (inst_id, geom_id), whose geometric normal is `ng_object`
  /// in the geometry's space, at `time`; 0 where that primitive is not sampled.
  float pdf_area(std::uint32_t inst_id, std::uint32_t geom_id, std::uint32_t prim_id, const Vec3f& ng_object,
                 float time) const {
    const auto found = index_.find(key(inst_id, geom_id));
    if (found == index_.end()) return 0.f;
    const Emitter& e = emitters_[found->second];
    if (prim_id >= e.probability.size() || !(e.probability[prim_id] > 0.f)) return 0.f;
    const std::optional<Affine3f> placement = placement_at(e, time);
    if (!placement) return 0.f;
    float area;
    if (e.mesh) {
      area = face(*e.mesh, prim_id, time, *placement).area;
    } else {
      const float l = length(ng_object);
      if (!(l > 0.f)) return 0.f;
      area = sphere_area(sphere(*e.spheres, prim_id).second, ng_object / l, *placement);
    }
    return area > 0.f ? e.probability[prim_id] / area : 0.f;
  }

private:
  struct Emitter {
    std::uint32_t inst_id = 0, geom_id = 0;
    const MotionTransform* placement = nullptr;  ///< null for direct geometry
    const TriangleMesh* mesh = nullptr;
    const Spheres* spheres = nullptr;
    std::vector<float> probability;  ///< per primitive: the chance `sample` picks it
  };
  struct Pick {
    std::uint32_t emitter, prim;
  };

  /// A mesh face placed in the world: its corners, area and its halves' normals in the
  /// mesh's space (a triangle has one half).
  struct Face {
    int corners;
    Vec3f world[4];
    Vec3f normal_object[2];
    float half_area[2];
    float area;
  };

  static std::uint64_t key(std::uint32_t inst_id, std::uint32_t geom_id) {
    return (static_cast<std::uint64_t>(inst_id) << 32) | geom_id;
  }

  /// The emitter's placement at `time`; none where a moving instance is absent then.
  static std::optional<Affine3f> placement_at(const Emitter& e, float time) {
    if (!e.placement) return Affine3f{};
    const MotionTransform& m = *e.placement;
    if (m.moving() && !(time >= m.start() && time <= m.end())) return std::nullopt;
    return m.at(time);
  }

  static Face face(const TriangleMesh& mesh, std::uint32_t prim, float time, const Affine3f& placement) {
    Face f;
    f.corners = static_cast<int>(mesh.vertices_per_face());
    const std::uint32_t* index = mesh.arrays().indices.element(prim);
    Vec3f object[4];
    for (int c = 0; c < f.corners; ++c) {
      object[c] = mesh.position(index[c], time);
      f.world[c] = placement.point(object[c]);
    }
    // Embree's halves: (v0, v1, v2) or, for quads, (v0, v1, v3) and (v2, v3, v1).
    const int third = f.corners == 3 ? 2 : 3;
    f.normal_object[0] = cross(object[1] - object[0], object[third] - object[0]);
    f.half_area[0] = 0.5f * length(cross(f.world[1] - f.world[0], f.world[third] - f.world[0]));
    f.half_area[1] = 0.f;
    if (f.corners == 4) {
      f.normal_object[1] = cross(object[3] - object[2], object[1] - object[2]);
      f.half_area[1] = 0.5f * length(cross(f.world[3] - f.world[2], f.world[1] - f.world[2]));
    }
    f.area = f.half_area[0] + f.half_area[1];
    return f;
  }

  static std::pair<Vec3f, float> sphere(const Spheres& spheres, std::uint32_t prim) {
    const auto& a = spheres.arrays();
    const float* c = a.positions.element(prim);
    return {{c[0], c[1], c[2]}, a.radii.empty() ? a.radius : *a.radii.element(prim)};
  }

  /// A sphere's world area as the density of uniform object-space samples sees it at the
  /// point of unit object normal n: 4 pi r^2 times the placement's area scale there
  /// (the length of the cofactor times n).
  static float sphere_area(float radius, const Vec3f& n, const Affine3f& placement) {
    return 4.f * std::numbers::pi_v<float> * radius * radius * length(placement.normal(n));
  }

  template <class G, class Strength>
  void add(const G& geometry, std::uint32_t inst_id, std::uint32_t geom_id, const MotionTransform* placement,
           const Strength& strength) {
    Emitter e;
    e.inst_id = inst_id, e.geom_id = geom_id, e.placement = placement;
    std::size_t count = 0;
    if constexpr (std::is_same_v<G, TriangleMesh>) {
      e.mesh = &geometry, count = geometry.face_count();
    } else if constexpr (std::is_same_v<G, Spheres>) {
      if (geometry.type() != SphereType::sphere) return;
      e.spheres = &geometry, count = geometry.arrays().positions.count;
    } else {
      return;
    }
    const Affine3f start = placement ? placement->key(0) : Affine3f{};
    const float time = e.mesh && e.mesh->deforming() ? e.mesh->arrays().time_start : 0.f;
    e.probability.assign(count, 0.f);
    const auto emitter = static_cast<std::uint32_t>(emitters_.size());
    for (std::uint32_t prim = 0; prim < count; ++prim) {
      const float s = strength(prim);
      if (!(s > 0.f)) continue;
      float area;
      if (e.mesh) {
        area = face(*e.mesh, prim, time, start).area;
      } else {
        // The sphere's area under the placement's average scale.
        const float r = sphere(*e.spheres, prim).second;
        area = 4.f * std::numbers::pi_v<float> * r * r * std::pow(std::abs(start.determinant()), 2.f / 3.f);
      }
      const double w = static_cast<double>(area) * s;
      if (!(w > 0.) || !std::isfinite(w)) continue;
      e.probability[prim] = static_cast<float>(w);
      total_ += w;
      cdf_.push_back(static_cast<float>(total_));
      picks_.push_back({emitter, prim});
    }
    if (picks_.empty() || picks_.back().emitter != emitter) return;  // nothing of it emits
    index_.emplace(key(inst_id, geom_id), emitter);
    emitters_.push_back(std::move(e));
  }

  std::vector<Emitter> emitters_;
  std::unordered_map<std::uint64_t, std::uint32_t> index_;  ///< (inst_id, geom_id) -> emitter
  std::vector<Pick> picks_;                                 ///< every emitting primitive
  std::vector<float> cdf_;                                  ///< of picks_, normalized
  double total_ = 0.;
};

}  // namespace sciray
