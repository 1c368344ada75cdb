#pragma once
// Triangle and quad meshes (OSPRay's `mesh`). The mesh reads its arrays through views,
// so it either owns them (from a loader's MeshData) or shares the caller's memory with
// no copy; Embree reads the same memory. `validate` runs once at commit and names the
// first bad value, so the per-ray code can trust every index.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "sciray/accel/embree.hpp"
#include "sciray/accel/trace.hpp"
#include "sciray/error.hpp"
#include "sciray/geometry/data.hpp"
#include "sciray/geometry/mesh_data.hpp"
#include "sciray/geometry/surface.hpp"
#include "sciray/math/box.hpp"

namespace sciray {

class TriangleMesh {
public:
  /// Arrays of a mesh the caller owns and keeps alive while sciray uses it. Embree reads
  /// up to 16 bytes past the last position and index element (embree_buffer_padding).
  struct SharedArrays {
    StridedView<float> positions;          ///< 3 floats per vertex
    StridedView<std::uint32_t> indices;    ///< vertices_per_face per face
    unsigned vertices_per_face = 3;
    StridedView<float> normals;            ///< 3 floats per vertex, optional
    StridedView<float> vertex_colors;      ///< 4 floats per vertex, optional
    StridedView<float> face_colors;        ///< 4 floats per face, optional
    StridedView<float> texcoords;          ///< 2 floats (u, v) per vertex, optional
    /// A deforming mesh: 3 floats per vertex at each of at least two time steps spaced
    /// evenly over [time_start, time_end], which Embree interpolates linearly at each
    /// ray's time; empty for a rigid mesh (`positions` alone).
    std::vector<StridedView<float>> motion_positions;
    /// A deforming mesh's normals (3 floats per vertex) at each of its time steps,
    /// interpolated at each ray's time as the positions are; empty for normals that do
    /// not change (`normals`, if any).
    std::vector<StridedView<float>> motion_normals;
    float time_start = 0.f, time_end = 1.f;
  };

  /// Takes ownership of loaded data (no copy: the vectors move into the mesh).
  explicit TriangleMesh(MeshData data) : TriangleMesh(std::make_shared<const MeshData>(std::move(data))) {}

  /// Shares ownership of data with other meshes (several instances of one geometry).
  explicit TriangleMesh(std::shared_ptr<const MeshData> owned) {
    const MeshData& d = *owned;
    arrays_.vertices_per_face = d.vertices_per_face;
    arrays_.positions = {d.positions.data(), d.vertex_count(), 3 * sizeof(float)};
    arrays_.indices = {d.indices.data(), d.vertices_per_face ? d.indices.size() / d.vertices_per_face : 0,
                       d.vertices_per_face * sizeof(std::uint32_t)};
    if (!d.normals.empty()) arrays_.normals = {d.normals.data(), d.normals.size() / 3, 3 * sizeof(float)};
    if (!d.vertex_colors.empty())
      arrays_.vertex_colors = {d.vertex_colors.data(), d.vertex_colors.size() / 4, 4 * sizeof(float)};
    if (!d.face_colors.empty())
      arrays_.face_colors = {d.face_colors.data(), d.face_colors.size() / 4, 4 * sizeof(float)};
    if (!d.texcoords.empty()) arrays_.texcoords = {d.texcoords.data(), d.texcoords.size() / 2, 2 * sizeof(float)};
    owned_bytes_ = (d.positions.size() + d.normals.size() + d.vertex_colors.size() + d.face_colors.size() +
                    d.texcoords.size()) *
                       sizeof(float) +
                   d.indices.size() * sizeof(std::uint32_t);
    for (const auto& step : d.motion_positions) {
      arrays_.motion_positions.push_back({step.data(), step.size() / 3, 3 * sizeof(float)});
      owned_bytes_ += step.size() * sizeof(float);
    }
    for (const auto& step : d.motion_normals) {
      arrays_.motion_normals.push_back({step.data(), step.size() / 3, 3 * sizeof(float)});
      owned_bytes_ += step.size() * sizeof(float);
    }
    arrays_.time_start = d.time_start, arrays_.time_end = d.time_end;
    keep_alive_ = std::move(owned);
    note_translucency();
  }

  /// Shares the caller's arrays (zero-copy).
  static TriangleMesh shared(const SharedArrays& arrays) { return TriangleMesh(arrays); }

  const SharedArrays& arrays() const { return arrays_; }
  unsigned vertices_per_face() const { return arrays_.vertices_per_face; }
  std::size_t vertex_count() const { return arrays_.positions.count; }
  /// Whether the mesh deforms over time (motion_positions).
  bool deforming() const { return !arrays_.motion_positions.empty(); }
  /// Whether rays at `time` see the mesh: always a rigid one, a deforming one within its
  /// time range (as for moving instances, math/motion.hpp).
  bool present_at(float time) const {
    return !deforming() || (time >= arrays_.time_start && time <= arrays_.time_end);
  }
  /// Vertex `i` at `time` (within the time range), interpolated between time steps as
  /// Embree does.
  Vec3f position(std::size_t i, float time) const {
    const auto at = [&](const StridedView<float>& view) {
      const float* p = view.element(i);
      return Vec3f{p[0], p[1], p[2]};
    };
    if (!deforming()) return at(arrays_.positions);
    const auto& steps = arrays_.motion_positions;
    const float span = arrays_.time_end - arrays_.time_start;
    const float x = span > 0.f ? std::clamp((time - arrays_.time_start) / span, 0.f, 1.f) *
                                     static_cast<float>(steps.size() - 1)
                               : 0.f;
    const std::size_t k = std::min(static_cast<std::size_t>(x), steps.size() - 2);
    const float f = x - static_cast<float>(k);
    return at(steps[k]) * (1.f - f) + at(steps[k + 1]) * f;
  }
  std::size_t face_count() const { return arrays_.indices.count; }
  /// Triangles the mesh represents: a quad counts two unless it repeats its last index.
  std::size_t triangle_count() const {
    if (arrays_.vertices_per_face == 3) return face_count();
    std::size_t triangles = 0;
    for (std::size_t f = 0; f < face_count(); ++f) {
      const std::uint32_t* q = arrays_.indices.element(f);
      triangles += q[2] == q[3] ? 1 : 2;
    }
    return triangles;
  }
  /// A material colour (OSPRay's `kd`): multiplies the vertex or face colours, or is the
  /// colour where the mesh has none.
  void set_material_color(const Vec3f& color) { material_color_ = color; }
  /// Whether the colours it shows (vertex colours, else face colours) have alpha below 1.
  bool translucent_colors() const { return translucent_; }

  /// Bytes of mesh data sciray owns (0 for shared arrays, which the caller owns).
  std::size_t owned_bytes() const { return owned_bytes_; }

  /// Checks every array and index; throws an Error naming the first problem.
  void validate() const {
    const auto& a = arrays_;
    if (a.vertices_per_face != 3 && a.vertices_per_face != 4)
      throw Error("mesh: 'index' must hold 3 (triangles) or 4 (quads) indices per face, got " +
                  std::to_string(a.vertices_per_face));
    if (a.positions.empty()) throw Error("mesh: 'vertex.position' is missing or empty");
    if (a.indices.empty()) throw Error("mesh: 'index' is missing or empty");
    check_stride("vertex.position", a.positions, 3 * sizeof(float));
    check_stride("index", a.indices, a.vertices_per_face * sizeof(std::uint32_t));
    // Shading gathers with 32-bit float offsets; larger arrays would wrap.
    const std::size_t max_floats = std::numeric_limits<std::int32_t>::max();
    if (a.positions.count * (a.positions.byte_stride / sizeof(float)) > max_floats ||
        a.indices.count * (a.indices.byte_stride / sizeof(std::uint32_t)) > max_floats)
      throw Error("mesh: more than 2^31 array elements; split the mesh into several geometries");
    for (std::size_t i = 0; i < a.positions.count; ++i) {
      const float* p = a.positions.element(i);
      if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
        throw Error("mesh: 'vertex.position' " + std::to_string(i) + " is not finite (" + std::to_string(p[0]) +
                    ", " + std::to_string(p[1]) + ", " + std::to_string(p[2]) + ")");
    }
    for (std::size_t f = 0; f < a.indices.count; ++f) {
      const std::uint32_t* face = a.indices.element(f);
      for (unsigned k = 0; k < a.vertices_per_face; ++k)
        if (face[k] >= a.positions.count)
          throw Error("mesh: 'index' of face " + std::to_string(f) + " refers to vertex " +
                      std::to_string(face[k]) + " but 'vertex.position' has " +
                      std::to_string(a.positions.count));
    }
    check_optional("vertex.normal", a.normals, a.positions.count, 3, "vertices");
    check_optional("vertex.color", a.vertex_colors, a.positions.count, 4, "vertices");
    check_optional("color", a.face_colors, a.indices.count, 4, "faces");
    check_optional("vertex.texcoord", a.texcoords, a.positions.count, 2, "vertices");
    if (!a.motion_positions.empty()) {
      if (a.motion_positions.size() < 2)
        throw Error("mesh: 'motion.vertex.position' needs at least two time steps, got 1");
      if (!(std::isfinite(a.time_start) && std::isfinite(a.time_end) && a.time_start <= a.time_end))
        throw Error("mesh: 'time' must be finite with lower <= upper, got [" + std::to_string(a.time_start) + ", " +
                    std::to_string(a.time_end) + "]");
      for (std::size_t k = 0; k < a.motion_positions.size(); ++k) {
        const std::string step = "motion.vertex.position[" + std::to_string(k) + "]";
        if (a.motion_positions[k].empty()) throw Error("mesh: '" + step + "' is empty");
        check_optional(step.c_str(), a.motion_positions[k], a.positions.count, 3, "vertices");
      }
    }
    if (!a.motion_normals.empty()) {
      if (a.motion_normals.size() != a.motion_positions.size())
        throw Error("mesh: 'motion.vertex.normal' has " + std::to_string(a.motion_normals.size()) +
                    " time steps but 'motion.vertex.position' has " + std::to_string(a.motion_positions.size()));
      for (std::size_t k = 0; k < a.motion_normals.size(); ++k) {
        const std::string step = "motion.vertex.normal[" + std::to_string(k) + "]";
        if (a.motion_normals[k].empty()) throw Error("mesh: '" + step + "' is empty");
        check_optional(step.c_str(), a.motion_normals[k], a.positions.count, 3, "vertices");
      }
    }
  }

  Box3f bounds() const {
    Box3f box;
    for (std::size_t i = 0; i < arrays_.positions.count; ++i) {
      const float* p = arrays_.positions.element(i);
      box.extend(Vec3f{p[0], p[1], p[2]});
    }
    for (const auto& step : arrays_.motion_positions)
      for (std::size_t i = 0; i < step.count; ++i) {
        const float* p = step.element(i);
        box.extend(Vec3f{p[0], p[1], p[2]});
      }
    return box;
  }

  /// A committed Embree triangle or quad geometry reading this mesh's arrays in place
  /// (Embree's own intersector: Arch plays no part).
  template <class Arch>
  RTCGeometry create_embree_geometry(const accel::Device& device) const {
    const bool quads = arrays_.vertices_per_face == 4;
    accel::GeometryHandle geometry(device, quads ? RTC_GEOMETRY_TYPE_QUAD : RTC_GEOMETRY_TYPE_TRIANGLE);
    if (deforming()) {
      const auto steps = static_cast<unsigned>(arrays_.motion_positions.size());
      rtcSetGeometryTimeStepCount(geometry.get(), steps);
      for (unsigned k = 0; k < steps; ++k) {
        const StridedView<float>& step = arrays_.motion_positions[k];
        rtcSetSharedGeometryBuffer(geometry.get(), RTC_BUFFER_TYPE_VERTEX, k, RTC_FORMAT_FLOAT3, step.base, 0,
                                   step.byte_stride, step.count);
      }
      rtcSetGeometryTimeRange(geometry.get(), arrays_.time_start, arrays_.time_end);
    } else {
      rtcSetSharedGeometryBuffer(geometry.get(), RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                 arrays_.positions.base, 0, arrays_.positions.byte_stride, arrays_.positions.count);
    }
    rtcSetSharedGeometryBuffer(geometry.get(), RTC_BUFFER_TYPE_INDEX, 0,
                               quads ? RTC_FORMAT_UINT4 : RTC_FORMAT_UINT3, arrays_.indices.base, 0,
                               arrays_.indices.byte_stride, arrays_.indices.count);
    device.check("mesh: rtcSetSharedGeometryBuffer");
    return geometry.commit(device, "mesh");
  }

  /// Interpolated normal, colour and texture coordinates at the hits of lanes `lanes`
  /// (all hitting this mesh).
  template <class Arch>
  SurfaceSample<Arch> surface(const accel::Hit<Arch>& hit, const simd::Mask<Arch>& lanes) const {
    using F = simd::Float<Arch>;
    using I = simd::Int<Arch>;
    const auto& a = arrays_;
    // Lanes outside `lanes` may carry another geometry's primitive ids: read face 0.
    const I prim = simd::select(lanes, hit.prim_id, I(0));
    // A mesh of positions alone interpolates nothing: its hits read no vertex indices.
    Corners<Arch> corners;
    if (!a.texcoords.empty() || !a.motion_normals.empty() || !a.normals.empty() || !a.vertex_colors.empty()) {
      const auto* index = reinterpret_cast<const std::int32_t*>(a.indices.base);
      const I face = prim * I(static_cast<std::int32_t>(a.indices.byte_stride / sizeof(std::uint32_t)));
      const I i0 = simd::gather<Arch>(index, face), i1 = simd::gather<Arch>(index, face + I(1)),
              i2 = simd::gather<Arch>(index, face + I(2));
      // Triangles interpolate with barycentrics; quads, as in OSPRay, bilinearly in the
      // (u, v) Embree reports over the unit square: (v0, v1, v2, v3) at its corners
      // (0,0), (1,0), (1,1), (0,1).
      corners = {{i0, i1, i2, i0}, {F(1.f) - hit.u - hit.v, hit.u, hit.v, F(0.f)}, 3};
      if (a.vertices_per_face == 4) {
        corners.index[3] = simd::gather<Arch>(index, face + I(3));
        const F u = hit.u, v = hit.v;
        corners.weight = {(F(1.f) - u) * (F(1.f) - v), u * (F(1.f) - v), u * v, (F(1.f) - u) * v};
        corners.count = 4;
      }
    }
    SurfaceSample<Arch> s;
    if (!a.texcoords.empty()) {
      const auto uv = interpolate<Arch, 2>(a.texcoords, corners);
      s.uv = {uv[0], uv[1]};
    } else {
      s.uv = {hit.u, hit.v};  // as OSPRay: the hit's own coordinates (a quad's spans [0, 1]^2)
    }
    if (!a.motion_normals.empty()) {
      // Over the face in each of the time steps around the ray's time, then between them
      // (OSPRay's order: both are linear, so either order gives the same normal).
      s.normal = normalize(at_time<Arch>(a.motion_normals, hit.time, lanes, [&](const StridedView<float>& step) {
        const auto n = interpolate<Arch, 3>(step, corners);
        return Vec3<F>{n[0], n[1], n[2]};
      }));
    } else if (!a.normals.empty()) {
      const auto n = interpolate<Arch, 3>(a.normals, corners);
      s.normal = normalize(Vec3<F>{n[0], n[1], n[2]});
    } else {
      s.normal = normalize(hit.ng);
    }
    s.has_color = lanes;
    if (!a.vertex_colors.empty()) {
      const auto c = interpolate<Arch, 4>(a.vertex_colors, corners);
      s.color = {c[0], c[1], c[2]};
      if (translucent_) s.alpha = c[3];
    } else if (!a.face_colors.empty()) {
      const auto* colors = a.face_colors.data();
      const I at = prim * I(static_cast<std::int32_t>(a.face_colors.byte_stride / sizeof(float)));
      s.color = {simd::gather<Arch>(colors, at), simd::gather<Arch>(colors, at + I(1)),
                 simd::gather<Arch>(colors, at + I(2))};
      if (translucent_) s.alpha = simd::gather<Arch>(colors, at + I(3));
    } else if (material_color_) {
      s.color = Vec3<F>(*material_color_);
      return s;
    } else {
      s.has_color = simd::Mask<Arch>(false);
      return s;
    }
    if (material_color_) s.color = s.color * Vec3<F>(*material_color_);
    return s;
  }

  /// The derivatives dP/ds and dP/dt of position along the texture coordinates at the
  /// hits of `lanes` (object space, one per face, a deforming one's at the hits' time),
  /// which orient normal maps: solved from
  /// a triangle's corners (a quad's first, second and last), as OSPRay does; where the
  /// mesh has no texture coordinates or they degenerate, the face's edges from its first
  /// corner to the second and to the last.
  template <class Arch>
  std::array<Vec3<simd::Float<Arch>>, 2> texture_derivatives(const accel::Hit<Arch>& hit,
                                                             const simd::Mask<Arch>& lanes) const {
    using F = simd::Float<Arch>;
    using I = simd::Int<Arch>;
    const auto& a = arrays_;
    const I prim = simd::select(lanes, hit.prim_id, I(0));
    const auto* index = reinterpret_cast<const std::int32_t*>(a.indices.base);
    const I face = prim * I(static_cast<std::int32_t>(a.indices.byte_stride / sizeof(std::uint32_t)));
    const I last = face + I(a.vertices_per_face == 4 ? 3 : 2);
    const std::array<I, 3> corner{simd::gather<Arch>(index, face), simd::gather<Arch>(index, face + I(1)),
                                  simd::gather<Arch>(index, last)};
    const auto read = [&](const StridedView<float>& view, const I& vertex, int k) {
      return simd::gather<Arch>(view.data(), vertex * I(static_cast<std::int32_t>(view.byte_stride / sizeof(float))) + I(k));
    };
    std::array<Vec3<F>, 3> p;
    for (int j = 0; j < 3; ++j) {
      const I& v = corner[static_cast<std::size_t>(j)];
      const auto position = [&](const StridedView<float>& step) {
        return Vec3<F>{read(step, v, 0), read(step, v, 1), read(step, v, 2)};
      };
      // A deforming mesh's corners where the ray met them.
      p[static_cast<std::size_t>(j)] =
          deforming() ? at_time<Arch>(a.motion_positions, hit.time, lanes, position) : position(a.positions);
    }
    Vec3<F> dpds = p[1] - p[0], dpdt = p[2] - p[0];
    if (a.texcoords.empty()) return {dpds, dpdt};
    const auto st = [&](int j, int k) { return read(a.texcoords, corner[static_cast<std::size_t>(j)], k); };
    // Edges towards the last corner, in texture space and in space.
    const F ds02 = st(0, 0) - st(2, 0), dt02 = st(0, 1) - st(2, 1);
    const F ds12 = st(1, 0) - st(2, 0), dt12 = st(1, 1) - st(2, 1);
    const Vec3<F> dp02 = p[0] - p[2], dp12 = p[1] - p[2];
    const F det = ds02 * dt12 - dt02 * ds12;
    const auto solvable = det != F(0.f);
    const F inv = F(1.f) / simd::select(solvable, det, F(1.f));
    dpds = select(solvable, (dp02 * dt12 - dp12 * dt02) * inv, dpds);
    dpdt = select(solvable, (dp12 * ds02 - dp02 * ds12) * inv, dpdt);
    return {dpds, dpdt};
  }

private:
  /// `read(step)` (a value per lane read from one time step's array) at each lane's
  /// time: linear between the two steps around it, as Embree interpolates positions
  /// (position() for one vertex). Lanes outside `lanes` get step 0's value.
  template <class Arch, class Read>
  Vec3<simd::Float<Arch>> at_time(const std::vector<StridedView<float>>& steps, const simd::Float<Arch>& time,
                                  const simd::Mask<Arch>& lanes, Read&& read) const {
    using F = simd::Float<Arch>;
    const float span = arrays_.time_end - arrays_.time_start;
    const auto last_segment = static_cast<float>(steps.size() - 2);
    const F x = span > 0.f ? simd::min(simd::max((time - F(arrays_.time_start)) / F(span), F(0.f)), F(1.f)) *
                                 F(static_cast<float>(steps.size() - 1))
                           : F(0.f);
    const F segment = simd::min(simd::to_float(simd::to_int(x)), F(last_segment));  // x >= 0: truncation floors
    const F f = x - segment;
    const Vec3<F> first = read(steps[0]);
    Vec3<F> out = first;
    // A packet's lanes may sit in different segments: each segment the packet touches once.
    for (std::size_t k = 0; k + 1 < steps.size(); ++k) {
      const simd::Mask<Arch> in_segment = lanes & (segment == F(static_cast<float>(k)));
      if (!simd::any(in_segment)) continue;
      const Vec3<F> a = k == 0 ? first : read(steps[k]), b = read(steps[k + 1]);
      out = select(in_segment, a * (F(1.f) - f) + b * f, out);
    }
    return out;
  }

  /// The vertices a hit interpolates between, and their weights.
  template <class Arch>
  struct Corners {
    std::array<simd::Int<Arch>, 4> index;
    std::array<simd::Float<Arch>, 4> weight;
    int count = 3;  ///< 3 for a triangle, 4 for a quad
  };

  template <class Arch, int N>
  static std::array<simd::Float<Arch>, N> interpolate(const StridedView<float>& view, const Corners<Arch>& c) {
    using I = simd::Int<Arch>;
    const I stride(static_cast<std::int32_t>(view.byte_stride / sizeof(float)));
    std::array<simd::Float<Arch>, N> out;
    for (int k = 0; k < N; ++k) out[k] = simd::Float<Arch>(0.f);
    for (int j = 0; j < c.count; ++j) {
      const I at = c.index[static_cast<std::size_t>(j)] * stride;
      for (int k = 0; k < N; ++k)
        out[k] = out[k] + c.weight[static_cast<std::size_t>(j)] * simd::gather<Arch>(view.data(), at + I(k));
    }
    return out;
  }

  explicit TriangleMesh(const SharedArrays& arrays) : arrays_(arrays) { note_translucency(); }

  void note_translucency() {
    translucent_ = translucent(arrays_.vertex_colors.empty() ? arrays_.face_colors : arrays_.vertex_colors);
  }

  template <class T>
  static void check_stride(const char* name, const StridedView<T>& view, std::size_t min_stride) {
    if (view.byte_stride < min_stride || view.byte_stride % sizeof(float) != 0)
      throw Error(std::string("mesh: '") + name + "' byte stride " + std::to_string(view.byte_stride) +
                  " must be a multiple of 4 and at least " + std::to_string(min_stride));
  }
  static void check_optional(const char* name, const StridedView<float>& view, std::size_t expected,
                             std::size_t components, const char* per) {
    if (view.empty()) return;
    check_stride(name, view, components * sizeof(float));
    if (view.count != expected)
      throw Error(std::string("mesh: '") + name + "' has " + std::to_string(view.count) + " elements but there are " +
                  std::to_string(expected) + " " + per);
    for (std::size_t i = 0; i < view.count; ++i)
      for (std::size_t c = 0; c < components; ++c)
        if (!std::isfinite(view.element(i)[c]))
          throw Error(std::string("mesh: '") + name + "' " + std::to_string(i) + " is not finite");
  }

  SharedArrays arrays_;
  std::size_t owned_bytes_ = 0;
  std::optional<Vec3f> material_color_;
  bool translucent_ = false;
  std::shared_ptr<const void> keep_alive_;
};

}  // namespace sciray
