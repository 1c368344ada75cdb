#pragma once
// Catmull-Clark subdivision surfaces (OSPRay's `subdivision`), tessellated and
// intersected by Embree (RTC_GEOMETRY_TYPE_SUBDIVISION). Shading asks Embree for the
// limit surface at the hit: its derivatives give a smooth normal, and colours and
// texture coordinates are interpolated over the same patches (vertex attributes per
// control vertex, or per face corner through a second topology).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <type_traits>

#include "sciray/accel/embree.hpp"
#include "sciray/accel/trace.hpp"
#include "sciray/error.hpp"
#include "sciray/geometry/data.hpp"
#include "sciray/geometry/surface.hpp"
#include "sciray/math/box.hpp"

namespace sciray {

/// How the surface treats its boundary, with Embree's (and OSPRay's) values.
enum class SubdivisionMode : std::uint8_t {
  no_boundary = RTC_SUBDIVISION_MODE_NO_BOUNDARY,          ///< boundary faces are dropped
  smooth_boundary = RTC_SUBDIVISION_MODE_SMOOTH_BOUNDARY,  ///< the boundary is a smooth B-spline
  pin_corners = RTC_SUBDIVISION_MODE_PIN_CORNERS,          ///< as smooth, corners (valence 2) stay put
  pin_boundary = RTC_SUBDIVISION_MODE_PIN_BOUNDARY,        ///< the boundary is the cage's polyline
  pin_all = RTC_SUBDIVISION_MODE_PIN_ALL,                  ///< no smoothing: the cage's faces
};

/// A subdivision surface's control cage and attributes, owned and padded for Embree.
struct SubdivisionData {
  PaddedVector<float> positions;             ///< 3 floats per control vertex
  PaddedVector<std::uint32_t> indices;       ///< the faces' vertices, face after face
  PaddedVector<std::uint32_t> face_sizes;    ///< vertices per face (at least 3)
  PaddedVector<std::uint32_t> edge_creases;  ///< 2 vertex indices per creased edge
  PaddedVector<float> edge_crease_weights;   ///< one per creased edge; infinity is sharp
  PaddedVector<std::uint32_t> vertex_creases;
  PaddedVector<float> vertex_crease_weights;
  /// RGBA per control vertex, or per face corner (one per `indices` entry) where
  /// `face_varying_colors`; empty for none.
  PaddedVector<float> colors;
  bool face_varying_colors = false;
  PaddedVector<float> texcoords;  ///< (u, v) per control vertex or, likewise, face corner
  bool face_varying_texcoords = false;
  PaddedVector<float> edge_levels;  ///< tessellation level per `indices` entry (its edge to the next), or empty
  float level = 5.f;                ///< tessellation level of every edge without edge_levels
  SubdivisionMode mode = SubdivisionMode::smooth_boundary;

  std::size_t vertex_count() const { return positions.size() / 3; }
  std::size_t face_count() const { return face_sizes.size(); }
};

class Subdivision {
public:
  explicit Subdivision(SubdivisionData data) : Subdivision(std::make_shared<const SubdivisionData>(std::move(data))) {}
  explicit Subdivision(std::shared_ptr<const SubdivisionData> data)
      : data_(std::move(data)), translucent_(translucent(data_->colors)) {}

  const SubdivisionData& data() const { return *data_; }
  const std::shared_ptr<const SubdivisionData>& shared_data() const { return data_; }
  std::size_t owned_bytes() const {
    const SubdivisionData& d = *data_;
    return (d.positions.size() + d.edge_crease_weights.size() + d.vertex_crease_weights.size() + d.colors.size() +
            d.texcoords.size() + d.edge_levels.size() + face_colors_.size()) *
               sizeof(float) +
           (d.indices.size() + d.face_sizes.size() + d.edge_creases.size() + d.vertex_creases.size()) *
               sizeof(std::uint32_t);
  }

  /// Colours per face (RGBA; OSPRay's per-primitive model colours), which replace the
  /// surface's own colours; empty to keep them.
  void set_face_colors(PaddedVector<float> colors) {
    face_colors_ = std::move(colors);
    translucent_ = translucent(face_colors_.empty() ? data_->colors : face_colors_);
  }
  /// Drops the surface's own colours (a model's single colour, given as material colour, replaces them).
  void ignore_own_colors() {
    own_colors_ = false;
    translucent_ = translucent(face_colors_);
  }
  /// Multiplies the colours, or is the colour where there are none (OSPRay's `kd`).
  void set_material_color(const Vec3f& color) { material_color_ = color; }
  bool translucent_colors() const { return translucent_; }

  /// Checks the cage, creases and attributes; throws an Error naming the first problem.
  void validate() const {
    const SubdivisionData& d = *data_;
    const std::size_t vertices = d.vertex_count();
    if (d.positions.empty() || d.positions.size() % 3 != 0)
      throw Error("subdivision: 'vertex.position' is missing or empty");
    if (d.indices.empty()) throw Error("subdivision: 'index' is missing or empty");
    for (std::size_t i = 0; i < vertices; ++i) {
      const float* p = &d.positions[3 * i];
      if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
        throw Error("subdivision: 'vertex.position' " + std::to_string(i) + " is not finite (" + std::to_string(p[0]) +
                    ", " + std::to_string(p[1]) + ", " + std::to_string(p[2]) + ")");
    }
    std::size_t corners = 0;
    for (std::size_t f = 0; f < d.face_sizes.size(); ++f) {
      if (d.face_sizes[f] < 3)
        throw Error("subdivision: 'face' " + std::to_string(f) + " has " + std::to_string(d.face_sizes[f]) +
                    " vertices; a face needs at least 3");
      corners += d.face_sizes[f];
    }
    if (corners != d.indices.size())
      throw Error("subdivision: the 'face' sizes add up to " + std::to_string(corners) + " vertices but 'index' has " +
                  std::to_string(d.indices.size()));
    for (std::size_t i = 0; i < d.indices.size(); ++i)
      if (d.indices[i] >= vertices)
        throw Error("subdivision: 'index' " + std::to_string(i) + " refers to vertex " + std::to_string(d.indices[i]) +
                    " but 'vertex.position' has " + std::to_string(vertices));
    check_creases("edgeCrease", d.edge_creases, 2, d.edge_crease_weights, vertices);
    check_creases("vertexCrease", d.vertex_creases, 1, d.vertex_crease_weights, vertices);
    check_attribute(d.face_varying_colors ? "color" : "vertex.color", d.colors, 4, d.face_varying_colors);
    check_attribute(d.face_varying_texcoords ? "texcoord" : "vertex.texcoord", d.texcoords, 2,
                    d.face_varying_texcoords);
    if (!(d.level > 0.f) || !std::isfinite(d.level))
      throw Error("subdivision: 'level' must be finite and positive, got " + std::to_string(d.level));
    if (!d.edge_levels.empty()) {
      if (d.edge_levels.size() != d.indices.size())
        throw Error("subdivision: 'index.level' has " + std::to_string(d.edge_levels.size()) +
                    " elements but 'index' has " + std::to_string(d.indices.size()));
      for (std::size_t i = 0; i < d.edge_levels.size(); ++i)
        if (!(d.edge_levels[i] > 0.f) || !std::isfinite(d.edge_levels[i]))
          throw Error("subdivision: 'index.level' " + std::to_string(i) + " must be finite and positive");
    }
    if (static_cast<unsigned>(d.mode) > RTC_SUBDIVISION_MODE_PIN_ALL)
      throw Error("subdivision: 'mode' has unknown value " + std::to_string(static_cast<unsigned>(d.mode)));
    if (!face_colors_.empty() && face_colors_.size() != 4 * d.face_count())
      throw Error("subdivision: " + std::to_string(face_colors_.size() / 4) + " face colours for " +
                  std::to_string(d.face_count()) + " faces");
  }

  /// The control cage's bounds, which hold the limit surface (every limit point is a
  /// convex combination of control vertices; creases keep it so).
  Box3f bounds() const {
    const SubdivisionData& d = *data_;
    Box3f box;
    for (std::uint32_t v : d.indices)
      box.extend(Vec3f{d.positions[3 * v], d.positions[3 * v + 1], d.positions[3 * v + 2]});
    return box;
  }

  /// A committed Embree subdivision geometry reading this surface's arrays in place
  /// (positions and texture coordinates copied, see below). It is kept for shading
  /// (rtcInterpolate): surface() needs the geometry it was hit on.
  template <class Arch>
  RTCGeometry create_embree_geometry(const accel::Device& device) const {
    const SubdivisionData& d = *data_;
    accel::GeometryHandle handle(device, RTC_GEOMETRY_TYPE_SUBDIVISION);
    RTCGeometry g = handle.get();
    const auto share = [&](RTCBufferType type, unsigned slot, RTCFormat format, const auto& array, unsigned per_item) {
      using T = typename std::decay_t<decltype(array)>::value_type;
      rtcSetSharedGeometryBuffer(g, type, slot, format, array.data(), 0, per_item * sizeof(T), array.size() / per_item);
    };
    // Embree reads each control point (and attribute) with a 4-float load and checks
    // that every lane is finite: positions and texture coordinates are copied to 16-byte
    // elements with zeros after them, where the shared arrays would expose the bytes
    // after their last element.
    const auto copy_padded = [&](RTCBufferType type, unsigned slot, RTCFormat format, const PaddedVector<float>& from,
                                 std::size_t components) {
      const std::size_t count = from.size() / components;
      auto* to = static_cast<float*>(rtcSetNewGeometryBuffer(g, type, slot, format, 4 * sizeof(float), count));
      if (!to) return;
      for (std::size_t i = 0; i < count; ++i)
        for (std::size_t c = 0; c < 4; ++c) to[4 * i + c] = c < components ? from[components * i + c] : 0.f;
    };
    copy_padded(RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, d.positions, 3);
    share(RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT, d.indices, 1);
    share(RTC_BUFFER_TYPE_FACE, 0, RTC_FORMAT_UINT, d.face_sizes, 1);
    const auto mode = static_cast<RTCSubdivisionMode>(d.mode);
    rtcSetGeometrySubdivisionMode(g, 0, mode);
    if (!d.edge_creases.empty()) {
      share(RTC_BUFFER_TYPE_EDGE_CREASE_INDEX, 0, RTC_FORMAT_UINT2, d.edge_creases, 2);
      share(RTC_BUFFER_TYPE_EDGE_CREASE_WEIGHT, 0, RTC_FORMAT_FLOAT, d.edge_crease_weights, 1);
    }
    if (!d.vertex_creases.empty()) {
      share(RTC_BUFFER_TYPE_VERTEX_CREASE_INDEX, 0, RTC_FORMAT_UINT, d.vertex_creases, 1);
      share(RTC_BUFFER_TYPE_VERTEX_CREASE_WEIGHT, 0, RTC_FORMAT_FLOAT, d.vertex_crease_weights, 1);
    }
    // Face-varying attributes index their values by face corner: a second topology
    // whose index is the corner's own number, subdivided in the same mode.
    const bool face_varying =
        (!d.colors.empty() && d.face_varying_colors) || (!d.texcoords.empty() && d.face_varying_texcoords);
    if (face_varying) {
      rtcSetGeometryTopologyCount(g, 2);
      auto* corner = static_cast<std::uint32_t*>(rtcSetNewGeometryBuffer(
          g, RTC_BUFFER_TYPE_INDEX, face_varying_topology, RTC_FORMAT_UINT, sizeof(std::uint32_t), d.indices.size()));
      if (corner)
        for (std::size_t i = 0; i < d.indices.size(); ++i) corner[i] = static_cast<std::uint32_t>(i);
      rtcSetGeometrySubdivisionMode(g, face_varying_topology, mode);
    }
    if (!d.colors.empty() || !d.texcoords.empty()) rtcSetGeometryVertexAttributeCount(g, d.texcoords.empty() ? 1 : 2);
    if (!d.colors.empty()) {
      share(RTC_BUFFER_TYPE_VERTEX_ATTRIBUTE, color_slot, RTC_FORMAT_FLOAT4, d.colors, 4);
      if (d.face_varying_colors) rtcSetGeometryVertexAttributeTopology(g, color_slot, face_varying_topology);
    }
    if (!d.texcoords.empty()) {
      copy_padded(RTC_BUFFER_TYPE_VERTEX_ATTRIBUTE, texcoord_slot, RTC_FORMAT_FLOAT2, d.texcoords, 2);
      if (d.face_varying_texcoords) rtcSetGeometryVertexAttributeTopology(g, texcoord_slot, face_varying_topology);
    }
    if (d.edge_levels.empty())
      rtcSetGeometryTessellationRate(g, d.level);
    else
      share(RTC_BUFFER_TYPE_LEVEL, 0, RTC_FORMAT_FLOAT, d.edge_levels, 1);
    device.check("subdivision: setting its buffers");
    RTCGeometry committed = handle.commit(device, "subdivision");
    rtcRetainGeometry(committed);
    embree_ = std::shared_ptr<RTCGeometryTy>(committed, [](RTCGeometry h) { rtcReleaseGeometry(h); });
    return committed;
  }

  /// The limit surface's normal, colour and texture coordinates at the hits of `lanes`
  /// (all on this surface), from Embree one lane at a time.
  template <class Arch>
  SurfaceSample<Arch> surface(const accel::Hit<Arch>& hit, const simd::Mask<Arch>& lanes) const {
    using F = simd::Float<Arch>;
    constexpr int W = simd::width<Arch>;
    const SubdivisionData& d = *data_;
    if (!embree_) throw Error("subdivision: shaded before its Embree geometry was created");
    const bool vertex_colors = own_colors_ && face_colors_.empty() && !d.colors.empty();
    float normal[3][W] = {}, color[4][W] = {}, uv[2][W] = {};
    for (int i = 0; i < W; ++i) {
      if (!simd::lane(lanes, i)) continue;
      const auto prim = static_cast<unsigned>(simd::lane(hit.prim_id, i));
      const float u = simd::lane(hit.u, i), v = simd::lane(hit.v, i);
      float du[3], dv[3];
      interpolate(prim, u, v, RTC_BUFFER_TYPE_VERTEX, 0, nullptr, du, dv, 3);
      const Vec3f n = cross(Vec3f{du[0], du[1], du[2]}, Vec3f{dv[0], dv[1], dv[2]});
      const Vec3f ng{simd::lane(hit.ng.x, i), simd::lane(hit.ng.y, i), simd::lane(hit.ng.z, i)};
      // Derivatives can vanish at extraordinary vertices: the tessellation's normal then.
      const Vec3f shading = dot(n, n) > 0.f && std::isfinite(dot(n, n)) ? n : ng;
      normal[0][i] = shading.x, normal[1][i] = shading.y, normal[2][i] = shading.z;
      if (vertex_colors) {
        float c[4];
        interpolate(prim, u, v, RTC_BUFFER_TYPE_VERTEX_ATTRIBUTE, color_slot, c, nullptr, nullptr, 4);
        for (int k = 0; k < 4; ++k) color[k][i] = c[k];
      } else if (!face_colors_.empty()) {
        for (int k = 0; k < 4; ++k) color[k][i] = face_colors_[4 * prim + static_cast<unsigned>(k)];
      }
      if (!d.texcoords.empty()) {
        float t[2];
        interpolate(prim, u, v, RTC_BUFFER_TYPE_VERTEX_ATTRIBUTE, texcoord_slot, t, nullptr, nullptr, 2);
        uv[0][i] = t[0], uv[1][i] = t[1];
      }
    }
    SurfaceSample<Arch> s;
    s.normal = normalize(Vec3<F>{load<Arch>(normal[0]), load<Arch>(normal[1]), load<Arch>(normal[2])});
    if (!d.texcoords.empty()) s.uv = {load<Arch>(uv[0]), load<Arch>(uv[1])};
    s.has_color = lanes;
    if (vertex_colors || !face_colors_.empty()) {
      s.color = {load<Arch>(color[0]), load<Arch>(color[1]), load<Arch>(color[2])};
      if (translucent_) s.alpha = load<Arch>(color[3]);
      if (material_color_) s.color = s.color * Vec3<F>(*material_color_);
    } else if (material_color_) {
      s.color = Vec3<F>(*material_color_);
    } else {
      s.has_color = simd::Mask<Arch>(false);
    }
    return s;
  }

private:
  static constexpr unsigned face_varying_topology = 1;
  static constexpr unsigned color_slot = 0, texcoord_slot = 1;  // as OSPRay's

  template <class Arch>
  static simd::Float<Arch> load(const float* p) {
    if constexpr (simd::width<Arch> == 1)
      return p[0];
    else
      return simd::load<Arch>(p);
  }

  void interpolate(unsigned prim, float u, float v, RTCBufferType buffer, unsigned slot, float* value, float* du,
                   float* dv, unsigned count) const {
    RTCInterpolateArguments args{};
    args.geometry = embree_.get();
    args.primID = prim;
    args.u = u, args.v = v;
    args.bufferType = buffer;
    args.bufferSlot = slot;
    args.P = value, args.dPdu = du, args.dPdv = dv;
    args.valueCount = count;
    rtcInterpolate(&args);
  }

  static void check_creases(const std::string& name, const PaddedVector<std::uint32_t>& indices, std::size_t per_crease,
                            const PaddedVector<float>& weights, std::size_t vertices) {
    if (indices.size() / per_crease != weights.size())
      throw Error("subdivision: '" + name + ".index' has " + std::to_string(indices.size() / per_crease) +
                  " elements but '" + name + ".weight' has " + std::to_string(weights.size()));
    for (std::size_t i = 0; i < indices.size(); ++i)
      if (indices[i] >= vertices)
        throw Error("subdivision: '" + name + ".index' " + std::to_string(i / per_crease) + " refers to vertex " +
                    std::to_string(indices[i]) + " but 'vertex.position' has " + std::to_string(vertices));
    for (std::size_t i = 0; i < weights.size(); ++i)
      if (!(weights[i] >= 0.f))  // infinity is allowed: an infinitely sharp crease
        throw Error("subdivision: '" + name + ".weight' " + std::to_string(i) + " must not be negative or NaN, got " +
                    std::to_string(weights[i]));
  }

  void check_attribute(const char* name, const PaddedVector<float>& values, std::size_t components,
                       bool face_varying) const {
    if (values.empty()) return;
    const SubdivisionData& d = *data_;
    const std::size_t expected = face_varying ? d.indices.size() : d.vertex_count();
    if (values.size() != components * expected)
      throw Error(std::string("subdivision: '") + name + "' has " + std::to_string(values.size() / components) +
                  " elements but there are " + std::to_string(expected) +
                  (face_varying ? " face corners" : " vertices"));
    for (std::size_t i = 0; i < values.size(); ++i)
      if (!std::isfinite(values[i]))
        throw Error(std::string("subdivision: '") + name + "' " + std::to_string(i / components) + " is not finite");
  }

  std::shared_ptr<const SubdivisionData> data_;
  PaddedVector<float> face_colors_;
  bool own_colors_ = true;
  std::optional<Vec3f> material_color_;
  bool translucent_;
  /// The geometry last created for a scene. Copies share it, which is harmless: every
  /// geometry of the same data interpolates alike.
  mutable std::shared_ptr<RTCGeometryTy> embree_;
};

}  // namespace sciray
