#pragma once
// Cameras as OSPRay defines them: screen coordinates (sx, sy) in [0,1]^2 with (0,0) at
// the bottom-left of the image, and a lens sample in [0,1)^2, map to rays. `prepare`
// validates the parameters once per frame and precomputes the image-plane basis, so
// that ray generation is a few FMAs per lane.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <variant>

#include "sciray/error.hpp"
#include "sciray/math/box.hpp"
#include "sciray/math/ray.hpp"

namespace sciray {

/// OSPRay's OSPStereoMode: which eye(s) a camera renders. Side by side puts the left eye
/// in the left half of the image, top/bottom puts it in the top half.
enum class StereoMode : int { none = 0, left = 1, right = 2, side_by_side = 3, top_bottom = 4 };

inline StereoMode stereo_mode_from_int(const std::string& camera_type, int value) {
  if (value < 0 || value > 4)
    throw Error(camera_type + " camera: 'stereoMode' must be OSP_STEREO_NONE (0), _LEFT (1), _RIGHT (2), "
                "_SIDE_BY_SIDE (3) or _TOP_BOTTOM (4), got " + std::to_string(value));
  return static_cast<StereoMode>(value);
}

struct PerspectiveCamera {
  Vec3f position{0.f, 0.f, 0.f};
  Vec3f direction{0.f, 0.f, -1.f};
  Vec3f up{0.f, 1.f, 0.f};
  float fovy = 60.f;   ///< full vertical field of view of one eye, degrees
  float aspect = 1.f;  ///< width / height of the whole image
  float aperture_radius = 0.f;  ///< apertureRadius: 0 is a pinhole
  float focus_distance = 1.f;   ///< focusDistance: depth along `direction` that stays sharp, where stereo eyes converge
  StereoMode stereo_mode = StereoMode::none;
  float interpupillary_distance = 0.0635f;  ///< interpupillaryDistance
};

struct OrthographicCamera {
  Vec3f position{0.f, 0.f, 0.f};
  Vec3f direction{0.f, 0.f, -1.f};
  Vec3f up{0.f, 1.f, 0.f};
  float height = 1.f;  ///< world-space height of the view
  float aspect = 1.f;
};

/// OSPRay's `panoramic` camera: the full sphere of directions around `position` as an
/// equirectangular image, 360 degrees across and 180 degrees up; the image centre looks
/// along `direction`, its top along `up`. Stereo is omni-directional: each ray starts
/// IPD/2 to the side of `position`, perpendicular to the ray's horizontal heading.
struct PanoramicCamera {
  Vec3f position{0.f, 0.f, 0.f};
  Vec3f direction{0.f, 0.f, -1.f};
  Vec3f up{0.f, 1.f, 0.f};
  StereoMode stereo_mode = StereoMode::none;
  float interpupillary_distance = 0.0635f;
};

using Camera = std::variant<PerspectiveCamera, OrthographicCamera, PanoramicCamera>;

namespace detail {

inline bool finite(const Vec3f& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

/// Orthonormal view basis; names the bad parameter of `camera_type` when there is none.
struct ViewBasis {
  Vec3f forward, right, up;
};
inline ViewBasis view_basis(const char* camera_type, const Vec3f& position, const Vec3f& direction,
                            const Vec3f& up, float aspect) {
  const std::string type(camera_type);
  if (!finite(position)) throw Error(type + " camera: 'position' is not finite");
  if (!finite(direction) || length(direction) == 0.f)
    throw Error(type + " camera: 'direction' must be a finite non-zero vector");
  if (!finite(up) || length(up) == 0.f) throw Error(type + " camera: 'up' must be a finite non-zero vector");
  if (!(aspect > 0.f) || !std::isfinite(aspect)) throw Error(type + " camera: 'aspect' must be positive");
  const Vec3f forward = normalize(direction);
  const Vec3f right_unnormalized = cross(forward, up);
  if (length(right_unnormalized) < 1e-6f * length(up))
    throw Error(type + " camera: 'up' is parallel to 'direction'");
  const Vec3f right = normalize(right_unnormalized);
  return {forward, right, cross(right, forward)};
}

inline void check_stereo(const std::string& type, StereoMode mode, float interpupillary_distance) {
  stereo_mode_from_int(type, static_cast<int>(mode));  // throws for a value outside the enum
  if (mode != StereoMode::none && !(interpupillary_distance >= 0.f && std::isfinite(interpupillary_distance)))
    throw Error(type + " camera: 'interpupillaryDistance' must be finite and not negative");
}

/// The eye of a stereo image at screen point (sx, sy): the screen point within that
/// eye's view and the eye's side, -1 for the left and +1 for the right (0 without
/// stereo).
template <class T>
struct EyeView {
  T sx, sy, side;
};
template <class T>
EyeView<T> eye_view(StereoMode mode, const T& sx, const T& sy) {
  switch (mode) {
    case StereoMode::none: return {sx, sy, T(0.f)};
    case StereoMode::left: return {sx, sy, T(-1.f)};
    case StereoMode::right: return {sx, sy, T(1.f)};
    case StereoMode::side_by_side: {
      const auto left = sx < T(0.5f);
      return {simd::select(left, sx * T(2.f), sx * T(2.f) - T(1.f)), sy, simd::select(left, T(-1.f), T(1.f))};
    }
    case StereoMode::top_bottom: {
      const auto left = sy >= T(0.5f);
      return {sx, simd::select(left, sy * T(2.f) - T(1.f), sy * T(2.f)), simd::select(left, T(-1.f), T(1.f))};
    }
  }
  return {sx, sy, T(0.f)};
}

/// Concentric map of [0,1)^2 onto the unit disc (Shirley and Chiu 1997): strata stay
/// compact, and (0.5, 0.5) maps to the centre.
template <class T>
void concentric_disc(const T& u, const T& v, T& x, T& y) {
  using std::cos, std::sin;
  const T a = T(2.f) * u - T(1.f), b = T(2.f) * v - T(1.f);
  const auto wide = simd::abs(a) > simd::abs(b);
  const T r = simd::select(wide, a, b);
  const T other = simd::select(wide, b, a);
  const T ratio = simd::select(r == T(0.f), T(0.f), other / simd::select(r == T(0.f), T(1.f), r));
  constexpr float quarter_pi = std::numbers::pi_v<float> / 4.f;
  const T phi = simd::select(wide, T(quarter_pi) * ratio, T(2.f * quarter_pi) - T(quarter_pi) * ratio);
  x = r * cos(phi);
  y = r * sin(phi);
}

}  // namespace detail

/// A perspective camera ready to generate rays. Every ray of screen point (sx, sy)
/// passes through the point of the focal plane (at `focus_distance` along the view
/// axis) that the pinhole ray of that point meets, whatever its lens sample and eye:
/// the lens (a disc of `aperture_radius` around the eye) blurs what lies off that plane,
/// and the two eyes' views converge on it.
struct PreparedPerspective {
  Vec3f position, forward, dir_00, du, dv;
  Vec3f lens_du, lens_dv;  ///< right and up, scaled by the aperture radius
  Vec3f eye_offset;        ///< from `position` to the right eye (IPD/2 along right)
  float focus_distance;
  StereoMode stereo;

  /// The ray through screen point (sx, sy) in [0,1]^2 from lens point (lens_u, lens_v)
  /// in [0,1)^2; (0.5, 0.5) is the lens centre.
  template <class T>
  Ray<T> generate(const T& sx, const T& sy, const T& lens_u = T(0.5f), const T& lens_v = T(0.5f)) const {
    const detail::EyeView<T> eye = detail::eye_view(stereo, sx, sy);
    // Unnormalized, with unit length along the view axis.
    const Vec3<T> pinhole = Vec3<T>(dir_00) + Vec3<T>(du) * eye.sx + Vec3<T>(dv) * eye.sy;
    Ray<T> ray;
    if (lens_du == Vec3f{0.f, 0.f, 0.f} && stereo == StereoMode::none) {
      ray.org = Vec3<T>(position);
      ray.dir = normalize(pinhole);
      return ray;
    }
    T disc_x, disc_y;
    detail::concentric_disc(lens_u, lens_v, disc_x, disc_y);
    const Vec3<T> lens = Vec3<T>(eye_offset) * eye.side + Vec3<T>(lens_du) * disc_x + Vec3<T>(lens_dv) * disc_y;
    ray.org = Vec3<T>(position) + lens;
    ray.dir = normalize(pinhole * T(focus_distance) - lens);
    return ray;
  }
  /// Whether generate() reads its lens sample (a pinhole without stereo does not, so
  /// the frame loop need not draw one).
  bool uses_lens() const { return !(lens_du == Vec3f{0.f, 0.f, 0.f} && stereo == StereoMode::none); }
  /// Distance along the view axis of a point at Euclidean distance t along `dir` (the
  /// lens lies in a plane across that axis).
  template <class T>
  T projected_depth(const Ray<T>& ray, const T& t) const {
    return t * dot(ray.dir, Vec3<T>(forward));
  }
};

/// An orthographic camera ready to generate rays; it has no lens, so the lens sample is
/// ignored.
struct PreparedOrthographic {
  Vec3f forward, org_00, du, dv;

  template <class T>
  Ray<T> generate(const T& sx, const T& sy, const T& = T(0.5f), const T& = T(0.5f)) const {
    Ray<T> ray;
    ray.org = Vec3<T>(org_00) + Vec3<T>(du) * sx + Vec3<T>(dv) * sy;
    ray.dir = Vec3<T>(forward);
    return ray;
  }
  bool uses_lens() const { return false; }
  template <class T>
  T projected_depth(const Ray<T>&, const T& t) const {
    return t;
  }
};

/// A panoramic camera ready to generate rays: longitude 2 pi (sx - 1/2) to the right of
/// `forward`, latitude pi (sy - 1/2) up. It has no lens.
struct PreparedPanoramic {
  Vec3f position, forward, right, up;
  float half_ipd;
  StereoMode stereo;

  template <class T>
  Ray<T> generate(const T& sx, const T& sy, const T& = T(0.5f), const T& = T(0.5f)) const {
    using std::cos, std::sin;
    const detail::EyeView<T> eye = detail::eye_view(stereo, sx, sy);
    constexpr float pi = std::numbers::pi_v<float>;
    const T longitude = T(2.f * pi) * (eye.sx - T(0.5f)), latitude = T(pi) * (eye.sy - T(0.5f));
    const T cos_lon = cos(longitude), sin_lon = sin(longitude);
    const T cos_lat = cos(latitude), sin_lat = sin(latitude);
    const Vec3<T> heading = Vec3<T>(forward) * cos_lon + Vec3<T>(right) * sin_lon;
    Ray<T> ray;
    ray.dir = heading * cos_lat + Vec3<T>(up) * sin_lat;
    // The eye sits to the side of the heading: (cos, -sin) turns it a quarter right.
    const Vec3<T> heading_right = Vec3<T>(right) * cos_lon - Vec3<T>(forward) * sin_lon;
    ray.org = Vec3<T>(position) + heading_right * (eye.side * T(half_ipd));
    return ray;
  }
  bool uses_lens() const { return false; }
  /// There is no view plane: depth is the distance.
  template <class T>
  T projected_depth(const Ray<T>&, const T& t) const {
    return t;
  }
};

inline PreparedPerspective prepare(const PerspectiveCamera& c) {
  if (!(c.fovy > 0.f && c.fovy < 180.f))
    throw Error("perspective camera: 'fovy' must be in (0, 180) degrees, got " + std::to_string(c.fovy));
  if (!(c.aperture_radius >= 0.f) || !std::isfinite(c.aperture_radius))
    throw Error("perspective camera: 'apertureRadius' must be finite and not negative, got " +
                std::to_string(c.aperture_radius));
  if (!(c.focus_distance > 0.f) || !std::isfinite(c.focus_distance))
    throw Error("perspective camera: 'focusDistance' must be positive, got " + std::to_string(c.focus_distance));
  detail::check_stereo("perspective", c.stereo_mode, c.interpupillary_distance);
  const auto basis = detail::view_basis("perspective", c.position, c.direction, c.up, c.aspect);
  // Each eye of a split image sees half of it, with the field of view of the whole.
  float eye_aspect = c.aspect;
  if (c.stereo_mode == StereoMode::side_by_side) eye_aspect *= 0.5f;
  if (c.stereo_mode == StereoMode::top_bottom) eye_aspect *= 2.f;
  const float half_height = std::tan(0.5f * c.fovy * std::numbers::pi_v<float> / 180.f);
  const Vec3f dv = basis.up * (2.f * half_height);
  const Vec3f du = basis.right * (2.f * half_height * eye_aspect);
  const bool stereo = c.stereo_mode != StereoMode::none;
  return {c.position,
          basis.forward,
          basis.forward - 0.5f * du - 0.5f * dv,
          du,
          dv,
          basis.right * c.aperture_radius,
          basis.up * c.aperture_radius,
          basis.right * (stereo ? 0.5f * c.interpupillary_distance : 0.f),
          c.focus_distance,
          c.stereo_mode};
}

inline PreparedOrthographic prepare(const OrthographicCamera& c) {
  if (!(c.height > 0.f) || !std::isfinite(c.height))
    throw Error("orthographic camera: 'height' must be positive");
  const auto basis = detail::view_basis("orthographic", c.position, c.direction, c.up, c.aspect);
  const Vec3f dv = basis.up * c.height;
  const Vec3f du = basis.right * (c.height * c.aspect);
  return {basis.forward, c.position - 0.5f * du - 0.5f * dv, du, dv};
}

inline PreparedPanoramic prepare(const PanoramicCamera& c) {
  detail::check_stereo("panoramic", c.stereo_mode, c.interpupillary_distance);
  const auto basis = detail::view_basis("panoramic", c.position, c.direction, c.up, 1.f);
  const float half_ipd = c.stereo_mode == StereoMode::none ? 0.f : 0.5f * c.interpupillary_distance;
  return {c.position, basis.forward, basis.right, basis.up, half_ipd, c.stereo_mode};
}

}  // namespace sciray

namespace sciray {

/// A perspective camera looking along `view_direction` that frames all of `bounds`
/// (its bounding sphere fits the smaller of the two fields of view).
inline PerspectiveCamera frame_bounds(const Box3f& bounds, float aspect, float fovy = 40.f,
                                      Vec3f view_direction = {-0.4f, -0.3f, -1.f}, Vec3f up = {0.f, 1.f, 0.f}) {
  if (bounds.empty()) throw Error("camera: cannot frame an empty scene");
  const Vec3f center = bounds.center();
  const float radius = std::max(0.5f * length(bounds.size()), 1e-20f);
  const float half_fov = 0.5f * fovy * std::numbers::pi_v<float> / 180.f;
  const float half_fov_min = aspect >= 1.f ? half_fov : std::atan(std::tan(half_fov) * aspect);
  const float distance = radius / std::sin(half_fov_min);
  PerspectiveCamera camera;
  camera.direction = normalize(view_direction);
  camera.position = center - camera.direction * distance;
  camera.up = up;
  camera.fovy = fovy;
  camera.aspect = aspect;
  return camera;
}

}  // namespace sciray
