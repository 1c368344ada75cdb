#pragma once
// Clipping geometry (OSPRay's `clippingGeometry`): volumes whose inside removes every
// surface of the world. A clipping sphere, box, closed mesh or round curve (the inside of
// its tube, geometry/curve_solid.hpp) clips its inside; a plane
// a·x + b·y + c·z + d = 0 clips the half-space behind its normal (a, b, c), the side where
// a·x + b·y + c·z + d < 0; `invert` clips the other side instead (OSPRay's
// invertNormals). A point inside any clipping volume is clipped.
//
// The test runs on each candidate hit, through Embree's context filter, so the nearest
// surviving hit is found by the same traversal: the clipped surface is simply not there,
// and what lies behind it shows. Spheres, boxes and planes are tested analytically; a
// closed mesh by the parity of the crossings of a ray from the point to infinity; a curve
// by the segments whose bounds hold the point (an Embree point query over them, one user
// geometry per curve set), each tested analytically.
//
// Clipping geometry placed by a moving instance (OSPRay's `motion.*`) clips where the
// instance is at each ray's time: it is kept in its own space with its placement, and
// a point is carried there by the placement's inverse at that time.
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "sciray/accel/embree.hpp"
#include "sciray/accel/trace.hpp"
#include "sciray/error.hpp"
#include "sciray/geometry/curve_solid.hpp"
#include "sciray/geometry/curves.hpp"
#include "sciray/geometry/mesh_data.hpp"
#include "sciray/geometry/subdivision.hpp"
#include "sciray/geometry/triangle_mesh.hpp"
#include "sciray/math/box.hpp"
#include "sciray/math/motion.hpp"

namespace sciray {

class Clipping {
public:
  /// Closed meshes and subdivision surfaces are counted in one 64-bit parity word.
  static constexpr std::size_t max_meshes = 64;
  /// Curve sets are told apart in one 64-bit word too.
  static constexpr std::size_t max_curve_sets = 64;

  void add_sphere(const Vec3f& center, float radius, bool invert = false) {
    if (!std::isfinite(center.x + center.y + center.z) || !(radius > 0.f) || !std::isfinite(radius))
      throw Error("clipping sphere " + std::to_string(spheres_.size()) + ": needs a finite centre and a positive radius");
    spheres_.push_back({center, radius, invert});
  }
  void add_box(const Box3f& box, bool invert = false) {
    for (int k = 0; k < 3; ++k)
      if (!std::isfinite(box.lower[k]) || !std::isfinite(box.upper[k]) || box.lower[k] > box.upper[k])
        throw Error("clipping box " + std::to_string(boxes_.size()) + ": is not a finite box with lower <= upper");
    boxes_.push_back({box, invert});
  }
  void add_plane(const Vec3f& normal, float d, bool invert = false) {
    if (!std::isfinite(normal.x + normal.y + normal.z + d) || (normal.x == 0 && normal.y == 0 && normal.z == 0))
      throw Error("clipping plane " + std::to_string(planes_.size()) + ": needs finite coefficients and a non-zero normal");
    planes_.push_back({normal, d, invert});
  }
  /// A closed, consistently oriented triangle or quad mesh; its inside is clipped.
  void add_mesh(std::shared_ptr<const MeshData> mesh, bool invert = false) {
    if (meshes_.size() + subdivisions_.size() == max_meshes)
      throw Error("clipping: at most " + std::to_string(max_meshes) +
                  " clipping meshes are supported (subdivision surfaces count as meshes)");
    TriangleMesh(mesh).validate();
    meshes_.push_back({std::move(mesh), invert});
    mesh_scene_.reset();
  }

  /// A closed subdivision surface (every edge shared by two faces); its inside is
  /// clipped. Shares max_meshes with the meshes.
  void add_subdivision(std::shared_ptr<const SubdivisionData> surface, bool invert = false) {
    if (meshes_.size() + subdivisions_.size() == max_meshes)
      throw Error("clipping: at most " + std::to_string(max_meshes) +
                  " clipping meshes are supported (subdivision surfaces count as meshes)");
    Subdivision(surface).validate();
    std::unordered_map<std::uint64_t, int> faces_of_edge;
    std::size_t first = 0;
    for (std::uint32_t size : surface->face_sizes) {
      for (std::uint32_t k = 0; k < size; ++k) {
        const std::uint32_t a = surface->indices[first + k], b = surface->indices[first + (k + 1) % size];
        ++faces_of_edge[std::uint64_t{std::min(a, b)} << 32 | std::max(a, b)];
      }
      first += size;
    }
    for (const auto& [edge, faces] : faces_of_edge)
      if (faces != 2)
        throw Error("clipping: only a closed subdivision surface can clip, but the edge between vertices " +
                    std::to_string(edge >> 32) + " and " + std::to_string(edge & 0xffffffffu) + " belongs to " +
                    std::to_string(faces) + " face" + (faces == 1 ? "" : "s"));
    subdivisions_.push_back({Subdivision(std::move(surface)), invert});
    mesh_scene_.reset();
  }

  /// A set of round (or disjoint) curves, Curves::validate's rules; the inside of its
  /// tube is clipped. Flat curves and ribbons enclose nothing: an error.
  void add_curves(std::shared_ptr<const CurveData> curves, bool invert = false) {
    const std::string which = "clipping curves " + std::to_string(curve_sets_.size());
    if (curve_sets_.size() == max_curve_sets)
      throw Error("clipping: at most " + std::to_string(max_curve_sets) + " clipping curve sets are supported");
    try {
      Curves(curves).validate();
      curve_sets_.push_back({curve_solids(*curves), invert});
    } catch (const Error& e) {
      throw Error(which + ": " + e.what());
    }
    curve_scene_.reset();
  }

  /// Clipping geometry `local`, in its own space, placed by `placement` (every key
  /// invertible): at each ray's time it clips where the placement puts it then, and a
  /// moving placement only from its start until (not at) its end, as Embree shows a
  /// moving instance. Under a non-uniform scale a sphere clips as the ellipsoid it
  /// becomes.
  void add_placed(std::shared_ptr<Clipping> local, MotionTransform placement) {
    const std::string what = "clipping placement " + std::to_string(placed_.size());
    if (!local) throw Error(what + ": its clipping geometry is null");
    for (std::size_t k = 0; k < placement.key_count(); ++k) {
      const float det = placement.key(k).determinant();
      if (det == 0.f || !std::isfinite(det))
        throw Error(what + ": its transform is singular or not finite" +
                    (placement.moving() ? " at key " + std::to_string(k) : std::string()));
    }
    const Affine3f inverse = placement.moving() ? Affine3f{} : placement.key(0).inverse();
    placed_.push_back({std::move(local), std::move(placement), inverse});
  }

  bool empty() const {
    if (!(spheres_.empty() && boxes_.empty() && planes_.empty() && meshes_.empty() && subdivisions_.empty() &&
          curve_sets_.empty()))
      return false;
    return std::all_of(placed_.begin(), placed_.end(), [](const Placed& part) { return part.local->empty(); });
  }

  /// Builds the BVHs the closed-mesh and curve tests query; call before rendering.
  void commit(const accel::Device& device) {
    commit_curves(device);
    for (Placed& part : placed_) part.local->commit(device);
    mesh_scene_.reset();
    if (meshes_.empty() && subdivisions_.empty()) return;
    accel::Scene scene(device);
    rtcSetSceneFlags(scene.get(), RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION | RTC_SCENE_FLAG_ROBUST);
    const auto attach = [&](RTCGeometry g, std::size_t id) {
      rtcAttachGeometryByID(scene.get(), g, static_cast<unsigned>(id));
      rtcReleaseGeometry(g);
      device.check("clipping mesh");
    };
    for (std::size_t i = 0; i < meshes_.size(); ++i)
      attach(TriangleMesh(meshes_[i].mesh).create_embree_geometry<simd::scalar>(device), i);
    // Subdivision surfaces take the ids (and parity bits) after the meshes.
    for (std::size_t i = 0; i < subdivisions_.size(); ++i)
      attach(subdivisions_[i].surface.create_embree_geometry<simd::scalar>(device), meshes_.size() + i);
    scene.commit();
    mesh_scene_.emplace(std::move(scene));
  }

  /// Whether the point `p` lies in a clipped region for rays at `time` (placed clipping
  /// geometry may move).
  bool clipped(const Vec3f& p, float time) const {
    for (const auto& s : spheres_) {
      const Vec3f d = p - s.center;
      if ((dot(d, d) < s.radius * s.radius) != s.invert) return true;
    }
    for (const auto& b : boxes_) {
      const bool inside = p.x > b.box.lower.x && p.x < b.box.upper.x && p.y > b.box.lower.y &&
                          p.y < b.box.upper.y && p.z > b.box.lower.z && p.z < b.box.upper.z;
      if (inside != b.invert) return true;
    }
    for (const auto& plane : planes_)
      if ((dot(plane.normal, p) + plane.d < 0.f) != plane.invert) return true;
    if (!meshes_.empty() || !subdivisions_.empty()) {
      const std::uint64_t inside = inside_meshes(p);
      for (std::size_t i = 0; i < meshes_.size(); ++i)
        if (((inside >> i) & 1) != meshes_[i].invert) return true;
      for (std::size_t i = 0; i < subdivisions_.size(); ++i)
        if (((inside >> (meshes_.size() + i)) & 1) != subdivisions_[i].invert) return true;
    }
    if (!curve_sets_.empty()) {
      const std::uint64_t inside = inside_curves(p);
      for (std::size_t i = 0; i < curve_sets_.size(); ++i)
        if (((inside >> i) & 1) != curve_sets_[i].invert) return true;
    }
    for (const Placed& part : placed_) {
      const MotionTransform& m = part.placement;
      if (!m.moving()) {
        if (part.local->clipped(part.inverse.point(p), time)) return true;
      } else if (time >= m.start() && time < m.end() && part.local->clipped(m.at(time).inverse().point(p), time)) {
        return true;
      }
    }
    return false;
  }

private:
  struct Sphere {
    Vec3f center;
    float radius;
    bool invert;
  };
  struct BoxClip {
    Box3f box;
    bool invert;
  };
  struct Plane {
    Vec3f normal;
    float d;
    bool invert;
  };
  struct Mesh {
    std::shared_ptr<const MeshData> mesh;
    bool invert;
  };

  /// Bit i set where `p` is inside mesh i: an odd number of crossings along a ray to
  /// infinity. The filter flips a mesh's bit at each crossing and rejects the hit, so the
  /// one traversal sees them all. The direction avoids the axes, along which the edges
  /// of axis-aligned meshes run.
  std::uint64_t inside_meshes(const Vec3f& p) const {
    if (!mesh_scene_) throw Error("clipping: commit() the clipping before rendering");
    std::uint64_t parity = 0;
    const auto count = [](const RTCFilterFunctionNArguments* args) {
      auto* bits = static_cast<std::uint64_t*>(const_cast<void*>(accel::HitFilter::data_of(args->context)));
      const unsigned geom = RTCHitN_geomID(args->hit, args->N, 0);
      *bits ^= std::uint64_t{1} << geom;
      args->valid[0] = 0;
    };
    Ray<float> ray{p, normalize(Vec3f{0.5773f, 0.5921f, 0.5622f})};
    accel::intersect<simd::scalar>(mesh_scene_->get(), ray, true, false, accel::HitFilter{count, &parity});
    return parity;
  }

  /// One user geometry per curve set, its primitives the segments: a point query visits
  /// the segments whose bounds hold the point (Embree's point queries skip its own curves).
  void commit_curves(const accel::Device& device) {
    curve_scene_.reset();
    if (curve_sets_.empty()) return;
    accel::Scene scene(device);
    for (std::size_t i = 0; i < curve_sets_.size(); ++i) {
      const std::vector<CurveSegmentSolid>& segments = curve_sets_[i].segments;
      accel::GeometryHandle geometry(device, RTC_GEOMETRY_TYPE_USER);
      rtcSetGeometryUserPrimitiveCount(geometry.get(), static_cast<unsigned>(segments.size()));
      rtcSetGeometryUserData(geometry.get(), const_cast<CurveSegmentSolid*>(segments.data()));
      rtcSetGeometryBoundsFunction(
          geometry.get(),
          [](const RTCBoundsFunctionArguments* args) {
            const Box3f& b = static_cast<const CurveSegmentSolid*>(args->geometryUserPtr)[args->primID].bounds();
            *args->bounds_o = {b.lower.x, b.lower.y, b.lower.z, 0.f, b.upper.x, b.upper.y, b.upper.z, 0.f};
          },
          nullptr);
      RTCGeometry committed = geometry.commit(device, "clipping curves");
      rtcAttachGeometryByID(scene.get(), committed, static_cast<unsigned>(i));
      rtcReleaseGeometry(committed);
      device.check("clipping curves");
    }
    scene.commit();
    curve_scene_.emplace(std::move(scene));
  }

  /// Bit i set where `p` is inside curve set i.
  std::uint64_t inside_curves(const Vec3f& p) const {
    if (!curve_scene_) throw Error("clipping: commit() the clipping before rendering");
    struct Query {
      const Clipping* clipping;
      Vec3f point;
      std::uint64_t inside;
    } query{this, p, 0};
    const auto visit = [](RTCPointQueryFunctionArguments* args) {
      auto& q = *static_cast<Query*>(args->userPtr);
      const std::uint64_t bit = std::uint64_t{1} << args->geomID;
      if (!(q.inside & bit) && q.clipping->curve_sets_[args->geomID].segments[args->primID].contains(q.point))
        q.inside |= bit;
      return false;  // the query's radius (0) stays
    };
    alignas(16) RTCPointQuery point{p.x, p.y, p.z, 0.f, 0.f};
    RTCPointQueryContext context;
    rtcInitPointQueryContext(&context);
    rtcPointQuery(curve_scene_->get(), &point, &context, visit, &query);
    return query.inside;
  }

  std::vector<Sphere> spheres_;
  std::vector<BoxClip> boxes_;
  std::vector<Plane> planes_;
  struct SubdivisionClip {
    Subdivision surface;
    bool invert;
  };

  struct CurveSet {
    std::vector<CurveSegmentSolid> segments;
    bool invert;
  };

  struct Placed {
    std::shared_ptr<Clipping> local;
    MotionTransform placement;
    Affine3f inverse;  ///< a static placement's, computed once
  };

  std::vector<Mesh> meshes_;
  std::vector<SubdivisionClip> subdivisions_;
  std::vector<Placed> placed_;
  std::optional<accel::Scene> mesh_scene_;
  std::vector<CurveSet> curve_sets_;
  std::optional<accel::Scene> curve_scene_;
};

}  // namespace sciray
