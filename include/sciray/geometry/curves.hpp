#pragma once
// Curves (OSPRay's `curve`): streamlines, bonds, fibres. Embree intersects them exactly
// on its x,y,z,r control points; sciray maps OSPRay's `type` and `basis` onto Embree's
// curve kinds and blends per-vertex colours with the hit segment's basis.
//   round linear    = tubes with rounded joints (streamlines, bonds)
//   disjoint linear = cones per segment with no joints
//   flat            = ribbons that face the ray; ribbon = oriented by `vertex.normal`
//   bezier, b-spline, Catmull-Rom, Hermite (with `vertex.tangent`) = smooth tubes
#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <string>

#include "sciray/accel/embree.hpp"
#include "sciray/accel/trace.hpp"
#include "sciray/error.hpp"
#include "sciray/geometry/data.hpp"
#include "sciray/geometry/surface.hpp"
#include "sciray/math/box.hpp"

namespace sciray {

enum class CurveType { round, flat, ribbon, disjoint };  // OSPRay's order
enum class CurveBasis { linear, bezier, bspline, hermite, catmull_rom };

/// The owned form of a curve set. Segment s uses control points index[s] .. index[s] +
/// (1 for linear and Hermite, 3 for the cubic bases).
struct CurveData {
  PaddedVector<float> position_radius;  ///< x,y,z,r per vertex
  PaddedVector<std::uint32_t> indices;  ///< first vertex of each segment
  PaddedVector<float> colors;           ///< r,g,b,a per vertex, or empty
  PaddedVector<float> tangents;         ///< x,y,z,r per vertex, Hermite only
  PaddedVector<float> normals;          ///< x,y,z per vertex, ribbons only
  CurveType type = CurveType::round;
  CurveBasis basis = CurveBasis::linear;

  std::size_t vertex_count() const { return position_radius.size() / 4; }
};

class Curves {
public:
  explicit Curves(CurveData data) : Curves(std::make_shared<const CurveData>(std::move(data))) {}
  explicit Curves(std::shared_ptr<const CurveData> data)
      : data_(std::move(data)), translucent_(translucent(data_->colors)) {}

  const CurveData& data() const { return *data_; }
  /// Whether a vertex colour has alpha below 1.
  bool translucent_colors() const { return translucent_; }
  std::size_t segment_count() const { return data_->indices.size(); }

  std::size_t owned_bytes() const {
    const CurveData& d = *data_;
    return (d.position_radius.size() + d.colors.size() + d.tangents.size() + d.normals.size()) * sizeof(float) +
           d.indices.size() * sizeof(std::uint32_t);
  }

  void validate() const {
    const CurveData& d = *data_;
    if (d.position_radius.empty()) throw Error("curve: 'vertex.position_radius' is missing or empty");
    if (d.position_radius.size() % 4) throw Error("curve: 'vertex.position_radius' must hold 4 floats per vertex");
    if (d.indices.empty()) throw Error("curve: 'index' is missing or empty");
    const std::size_t n = d.vertex_count();
    for (std::size_t i = 0; i < n; ++i) {
      const float* p = &d.position_radius[4 * i];
      if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]) || !std::isfinite(p[3]))
        throw Error("curve: 'vertex.position_radius' " + std::to_string(i) + " is not finite");
      if (p[3] < 0.f)
        throw Error("curve: 'vertex.position_radius' " + std::to_string(i) + " has a negative radius " +
                    std::to_string(p[3]));
    }
    const std::uint32_t span = points_per_segment() - 1;
    for (std::size_t s = 0; s < d.indices.size(); ++s)
      if (std::uint64_t{d.indices[s]} + span >= n)
        throw Error("curve: 'index' " + std::to_string(s) + " starts a segment at vertex " +
                    std::to_string(d.indices[s]) + " that needs vertex " + std::to_string(d.indices[s] + span) +
                    " but 'vertex.position_radius' has " + std::to_string(n));
    check_per_vertex("vertex.color", d.colors, 4);
    if (d.basis == CurveBasis::hermite) {
      if (d.tangents.empty()) throw Error("curve: basis 'hermite' needs 'vertex.tangent'");
      check_per_vertex("vertex.tangent", d.tangents, 4);
    }
    if (d.type == CurveType::ribbon) {
      if (d.basis == CurveBasis::linear) throw Error("curve: type 'ribbon' needs a cubic basis, not 'linear'");
      if (d.normals.empty()) throw Error("curve: type 'ribbon' needs 'vertex.normal'");
      check_per_vertex("vertex.normal", d.normals, 3);
    }
    if (d.type == CurveType::disjoint && d.basis != CurveBasis::linear)
      throw Error("curve: type 'disjoint' is only defined for basis 'linear'");
  }

  /// The control points' boxes grown by their radii (the cubic curves stay inside their
  /// control polygon, except Catmull-Rom and Hermite which overshoot a little; Embree's
  /// own bounds are exact, this is for framing).
  Box3f bounds() const {
    Box3f box;
    const CurveData& d = *data_;
    for (std::size_t i = 0; i < d.vertex_count(); ++i) {
      const float* p = &d.position_radius[4 * i];
      box.extend(Vec3f{p[0] - p[3], p[1] - p[3], p[2] - p[3]});
      box.extend(Vec3f{p[0] + p[3], p[1] + p[3], p[2] + p[3]});
    }
    return box;
  }

  template <class Arch>
  RTCGeometry create_embree_geometry(const accel::Device& device) const {
    const CurveData& d = *data_;
    accel::GeometryHandle geometry(device, embree_type());
    rtcSetSharedGeometryBuffer(geometry.get(), RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4,
                               d.position_radius.data(), 0, 4 * sizeof(float), d.vertex_count());
    rtcSetSharedGeometryBuffer(geometry.get(), RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT, d.indices.data(), 0,
                               sizeof(std::uint32_t), d.indices.size());
    if (d.basis == CurveBasis::hermite)
      rtcSetSharedGeometryBuffer(geometry.get(), RTC_BUFFER_TYPE_TANGENT, 0, RTC_FORMAT_FLOAT4, d.tangents.data(),
                                 0, 4 * sizeof(float), d.vertex_count());
    if (d.type == CurveType::ribbon)
      rtcSetSharedGeometryBuffer(geometry.get(), RTC_BUFFER_TYPE_NORMAL, 0, RTC_FORMAT_FLOAT3, d.normals.data(), 0,
                                 3 * sizeof(float), d.vertex_count());
    device.check("curve: rtcSetSharedGeometryBuffer");
    return geometry.commit(device, "curve");
  }

  template <class Arch>
  SurfaceSample<Arch> surface(const accel::Hit<Arch>& hit, const simd::Mask<Arch>& lanes) const {
    using F = simd::Float<Arch>;
    using I = simd::Int<Arch>;
    const CurveData& d = *data_;
    SurfaceSample<Arch> s;
    s.normal = normalize(hit.ng);
    s.has_color = lanes;
    if (d.colors.empty()) {
      s.has_color = simd::Mask<Arch>(false);
      return s;
    }
    // The colour is the segment's curve over its vertex colours, as OSPRay weighs them.
    const I first = simd::gather<Arch>(reinterpret_cast<const std::int32_t*>(d.indices.data()),
                                       simd::select(lanes, hit.prim_id, I(0)));
    const std::array<F, 4> weight = colour_weights(simd::min(simd::max(hit.u, F(0.f)), F(1.f)));
    const float* c = d.colors.data();
    const auto blend = [&](int k) {
      F sum(0.f);
      for (std::uint32_t p = 0; p < points_per_segment(); ++p)
        sum += weight[p] * simd::gather<Arch>(c, (first + I(static_cast<std::int32_t>(p))) * I(4) + I(k));
      return sum;
    };
    s.color = {blend(0), blend(1), blend(2)};
    // Catmull-Rom weights overshoot between their points; alpha is an opacity all the same.
    s.alpha = simd::min(simd::max(blend(3), F(0.f)), F(1.f));
    return s;
  }

private:
  std::uint32_t points_per_segment() const {
    const CurveBasis b = data_->basis;
    return b == CurveBasis::linear || b == CurveBasis::hermite ? 2 : 4;
  }

  /// Each control point's weight in a segment's colour at parameter u: the basis functions
  /// of the cubic curves (a B-spline's colour at u is the B-spline of its vertex colours);
  /// linear and Hermite segments blend their two ends.
  template <class F>
  std::array<F, 4> colour_weights(const F& u) const {
    const F s = F(1.f) - u, u2 = u * u, s2 = s * s, u3 = u2 * u, s3 = s2 * s;
    switch (data_->basis) {
      case CurveBasis::bspline:
        return {s3 * F(1.f / 6.f), (F(3.f) * u3 - F(6.f) * u2 + F(4.f)) * F(1.f / 6.f),
                (F(3.f) * s3 - F(6.f) * s2 + F(4.f)) * F(1.f / 6.f), u3 * F(1.f / 6.f)};
      case CurveBasis::catmull_rom:
        return {F(-0.5f) * s2 * u, (F(3.f) * u3 - F(5.f) * u2 + F(2.f)) * F(0.5f),
                (F(3.f) * s3 - F(5.f) * s2 + F(2.f)) * F(0.5f), F(-0.5f) * u2 * s};
      case CurveBasis::bezier: return {s3, F(3.f) * s2 * u, F(3.f) * s * u2, u3};
      default: return {s, u, F(0.f), F(0.f)};
    }
  }

  RTCGeometryType embree_type() const {
    const CurveData& d = *data_;
    if (d.type == CurveType::disjoint) return RTC_GEOMETRY_TYPE_CONE_LINEAR_CURVE;
    // Rows: basis; columns: round, flat, ribbon.
    static constexpr RTCGeometryType kinds[5][3] = {
        {RTC_GEOMETRY_TYPE_ROUND_LINEAR_CURVE, RTC_GEOMETRY_TYPE_FLAT_LINEAR_CURVE, RTC_GEOMETRY_TYPE_FLAT_LINEAR_CURVE},
        {RTC_GEOMETRY_TYPE_ROUND_BEZIER_CURVE, RTC_GEOMETRY_TYPE_FLAT_BEZIER_CURVE,
         RTC_GEOMETRY_TYPE_NORMAL_ORIENTED_BEZIER_CURVE},
        {RTC_GEOMETRY_TYPE_ROUND_BSPLINE_CURVE, RTC_GEOMETRY_TYPE_FLAT_BSPLINE_CURVE,
         RTC_GEOMETRY_TYPE_NORMAL_ORIENTED_BSPLINE_CURVE},
        {RTC_GEOMETRY_TYPE_ROUND_HERMITE_CURVE, RTC_GEOMETRY_TYPE_FLAT_HERMITE_CURVE,
         RTC_GEOMETRY_TYPE_NORMAL_ORIENTED_HERMITE_CURVE},
        {RTC_GEOMETRY_TYPE_ROUND_CATMULL_ROM_CURVE, RTC_GEOMETRY_TYPE_FLAT_CATMULL_ROM_CURVE,
         RTC_GEOMETRY_TYPE_NORMAL_ORIENTED_CATMULL_ROM_CURVE}};
    return kinds[static_cast<int>(d.basis)][static_cast<int>(d.type)];
  }

  void check_per_vertex(const char* name, const PaddedVector<float>& values, std::size_t components) const {
    if (values.empty()) return;
    if (values.size() != components * data_->vertex_count())
      throw Error(std::string("curve: '") + name + "' has " + std::to_string(values.size() / components) +
                  " elements but there are " + std::to_string(data_->vertex_count()) + " vertices");
    for (std::size_t i = 0; i < values.size(); ++i)
      if (!std::isfinite(values[i]))
        throw Error(std::string("curve: '") + name + "' " + std::to_string(i / components) + " is not finite");
  }

  std::shared_ptr<const CurveData> data_;
  bool translucent_;
};

}  // namespace sciray
