#pragma once
// Cameras as OSPRay defines them: screen coordinates (sx, sy) in [0,1]^2 with (0,0) at
// the bottom-left of the image, a lens sample in [0,1)^2 and a time sample in [0,1) map
// to rays. `prepare` validates the parameters once per frame and precomputes the
// image-plane basis, so that ray generation is a few FMAs per lane; a camera that moves
// while the shutter is open rebuilds its basis per lane at the ray's time.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <numbers>
#include <string>
#include <tuple>
#include <utility>
#include <variant>

#include "sciray/error.hpp"
#include "sciray/math/box.hpp"
#include "sciray/math/motion.hpp"
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

/// OSPRay's OSPShutterType: a global shutter exposes the whole image over the shutter
/// interval; a rolling one exposes it column by column (right: left column first; left:
/// right column first) or row by row (down: top row first; up: bottom row first), each
/// for `rolling_shutter_duration`.
enum class ShutterType : int { global = 0, rolling_right = 1, rolling_left = 2, rolling_down = 3, rolling_up = 4 };

inline ShutterType shutter_type_from_int(const std::string& camera_type, int value) {
  if (value < 0 || value > 4)
    throw Error(camera_type + " camera: 'shutterType' must be OSP_SHUTTER_GLOBAL (0), _ROLLING_RIGHT (1), "
                "_ROLLING_LEFT (2), _ROLLING_DOWN (3) or _ROLLING_UP (4), got " + std::to_string(value));
  return static_cast<ShutterType>(value);
}

/// The part of the image plane the image shows, in screen coordinates ([0,1]^2 is the
/// whole view; OSPRay's imageStart and imageEnd): crops, tiles of a display wall, shifted
/// sensors; a start beyond the end mirrors that axis.
struct ImageRegion {
  float start_x = 0.f, start_y = 0.f, end_x = 1.f, end_y = 1.f;
};

/// What every camera has besides its projection: placement, clipping, image region and
/// shutter (OSPRay's common camera parameters).
struct CameraCommon {
  Vec3f position{0.f, 0.f, 0.f};
  Vec3f direction{0.f, 0.f, -1.f};
  Vec3f up{0.f, 1.f, 0.f};
  /// motion.*: places position, direction and up at each ray's time (keys over the
  /// motion's time range); null for a camera that stays where they say.
  std::shared_ptr<const MotionTransform> motion;
  float near_clip = 0.f;  ///< nearClip: camera rays start this far from their origin
  ImageRegion image_region;
  /// shutter: the times rays sample, in [0,1]; open == close is one instant.
  float shutter_open = 0.5f, shutter_close = 0.5f;
  ShutterType shutter_type = ShutterType::global;
  /// rollingShutterDuration: how long each row or column of a rolling shutter is
  /// exposed, in [0, close - open].
  float rolling_shutter_duration = 0.f;
};

struct PerspectiveCamera : CameraCommon {
  float fovy = 60.f;   ///< full vertical field of view of one eye, degrees
  float aspect = 1.f;  ///< width / height of the whole image
  float aperture_radius = 0.f;  ///< apertureRadius: 0 is a pinhole
  float focus_distance = 1.f;   ///< focusDistance: depth along `direction` that stays sharp
  /// architectural: the image plane stays parallel to `up` (vertical lines stay parallel)
  /// instead of across `direction`.
  bool architectural = false;
  StereoMode stereo_mode = StereoMode::none;
  float interpupillary_distance = 0.0635f;  ///< interpupillaryDistance
};

struct OrthographicCamera : CameraCommon {
  float height = 1.f;  ///< world-space height of the view
  float aspect = 1.f;
};

/// OSPRay's `panoramic` camera: the full sphere of directions around `position` as an
/// equirectangular image, 360 degrees across and 180 degrees up; the image centre looks
/// along `direction`, its top along `up`. Stereo is omni-directional: each ray starts
/// IPD/2 to the side of `position`, perpendicular to the ray and `up` (less towards the
/// poles).
struct PanoramicCamera : CameraCommon {
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
inline ViewBasis view_basis(const std::string& type, const Vec3f& position, const Vec3f& direction, const Vec3f& up,
                            float aspect) {
  if (!finite(position)) throw Error(type + " camera: 'position' is not finite");
  if (const float farthest = std::max({std::abs(position.x), std::abs(position.y), std::abs(position.z)});
      farthest > max_ray_coordinate) {
    char value[32];
    std::snprintf(value, sizeof value, "%g", static_cast<double>(farthest));
    throw Error(type + " camera: 'position' has a coordinate of magnitude " + value +
                ", beyond 1.8e18, farther out than rays can start");
  }
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

/// A camera's frame (a struct of Vec3 fields listed by fields()) for each lane: the
/// static one broadcast, or frame_at(time) of each lane's time for a moving camera.
/// Inlined, so that a static camera broadcasts only the fields a ray reads (a call
/// stored all eight and cost 4 % of a primary-ray frame).
template <template <class> class Frame, class T, class FrameAt>
[[gnu::always_inline]] inline Frame<Vec3<T>> frame_per_lane(const Frame<Vec3f>* fixed, const T& time, const FrameAt& frame_at) {
  Frame<Vec3<T>> out;
  if constexpr (std::is_same_v<T, float>) {
    out = fixed ? *fixed : frame_at(time);
  } else {
    constexpr int W = static_cast<int>(T::size);
    if (fixed) {
      std::apply([&](auto&... to) { std::apply([&](const auto&... from) { ((to = Vec3<T>(from)), ...); },
                                               fixed->fields()); },
                 out.fields());
      return out;
    }
    constexpr std::size_t K = std::tuple_size_v<decltype(out.fields())>;
    alignas(64) float lanes[K][3][W];
    for (int i = 0; i < W; ++i) {
      Frame<Vec3f> f = frame_at(simd::lane(time, i));
      std::size_t k = 0;
      std::apply([&](const auto&... v) { ((lanes[k][0][i] = v.x, lanes[k][1][i] = v.y, lanes[k][2][i] = v.z, ++k), ...); },
                 f.fields());
    }
    std::size_t k = 0;
    std::apply([&](auto&... v) {
      ((v = Vec3<T>{T::load_aligned(lanes[k][0]), T::load_aligned(lanes[k][1]), T::load_aligned(lanes[k][2])}, ++k),
       ...);
    }, out.fields());
  }
  return out;
}

/// What every prepared camera does before projecting: the eye's screen point into the
/// image region, the ray's time from the shutter, and (for a moving camera) its
/// placement at that time.
struct PreparedCommon {
  ImageRegion region;
  float near_clip = 0.f;
  /// The times of the first and last row or column (a rolling shutter), or of the
  /// shutter's open and close (a global one).
  float time_first = 0.5f, time_last = 0.5f;
  ShutterType shutter = ShutterType::global;
  float rolling_duration = 0.f;
  /// Set only where the camera moves while the shutter is open; position, direction and
  /// up are then in the motion's local space.
  std::shared_ptr<const MotionTransform> motion;
  Vec3f position, direction, up;

  template <class T>
  void map_region(T& sx, T& sy) const {
    sx = T(region.start_x) + sx * T(region.end_x - region.start_x);
    sy = T(region.start_y) + sy * T(region.end_y - region.start_y);
  }

  /// The time of a ray through image-plane point (sx, sy) with time sample `u` in [0,1).
  template <class T>
  T time(const T& sx, const T& sy, const T& u) const {
    if (shutter == ShutterType::global) return T(time_first) + u * T(time_last - time_first);
    const bool horizontal = shutter == ShutterType::rolling_right || shutter == ShutterType::rolling_left;
    const T& along = horizontal ? sx : sy;
    const T t = T(time_first) + along * T(time_last - time_first) + u * T(rolling_duration);
    return simd::min(simd::max(t, T(0.f)), T(1.f));
  }

  /// Whether rays' times depend on their time sample (not only on where they look).
  bool uses_time_sample() const {
    return shutter == ShutterType::global ? time_first != time_last : rolling_duration > 0.f;
  }

  /// position, direction and up placed at `time`.
  void placed_at(float time, Vec3f& p, Vec3f& d, Vec3f& u) const {
    const Affine3f m = motion->at(time);
    p = m.point(position), d = m.vector(direction), u = m.vector(up);
  }
};

/// Validates the common parameters of `c` and prepares them. `position`, `direction` and
/// `up` receive the camera's placement where it does not move while the shutter is open
/// (its motion, if any, at the shutter's opening); `check_view` validates one placement.
template <class CheckView>
PreparedCommon prepare_common(const std::string& type, const CameraCommon& c, Vec3f& position, Vec3f& direction,
                              Vec3f& up, const CheckView& check_view) {
  const auto fail = [&](const std::string& what) { throw Error(type + " camera: " + what); };
  if (!(c.near_clip >= 0.f) || !std::isfinite(c.near_clip))
    fail("'nearClip' must be finite and not negative, got " + std::to_string(c.near_clip));
  const ImageRegion& r = c.image_region;
  for (float v : {r.start_x, r.start_y, r.end_x, r.end_y})
    if (!std::isfinite(v)) fail("'imageStart' and 'imageEnd' must be finite");
  if (r.start_x == r.end_x || r.start_y == r.end_y)
    fail("'imageStart' and 'imageEnd' must differ in x and in y (the image region is empty)");
  if (!(c.shutter_open >= 0.f && c.shutter_open <= c.shutter_close && c.shutter_close <= 1.f))
    fail("'shutter' must satisfy 0 <= lower <= upper <= 1, got [" + std::to_string(c.shutter_open) + ", " +
         std::to_string(c.shutter_close) + "]");
  shutter_type_from_int(type, static_cast<int>(c.shutter_type));  // throws for a value outside the enum
  if (!(c.rolling_shutter_duration >= 0.f && c.rolling_shutter_duration <= c.shutter_close - c.shutter_open))
    fail("'rollingShutterDuration' must be in [0, shutter upper - lower] = [0, " +
         std::to_string(c.shutter_close - c.shutter_open) + "], got " + std::to_string(c.rolling_shutter_duration));

  PreparedCommon out;
  out.region = r;
  out.near_clip = c.near_clip;
  out.shutter = c.shutter_type;
  out.time_first = c.shutter_open, out.time_last = c.shutter_close;
  if (c.shutter_type != ShutterType::global) {
    // The last row or column opens `duration` before the shutter closes.
    out.rolling_duration = c.rolling_shutter_duration;
    out.time_last -= c.rolling_shutter_duration;
    if (c.shutter_type == ShutterType::rolling_left || c.shutter_type == ShutterType::rolling_down)
      std::swap(out.time_first, out.time_last);
  }
  position = c.position, direction = c.direction, up = c.up;
  check_view(position, direction, up);
  if (!c.motion) return out;
  const MotionTransform& motion = *c.motion;
  for (std::size_t k = 0; k < motion.key_count(); ++k) {
    const Affine3f m = motion.key(k);
    try {
      check_view(m.point(c.position), m.vector(c.direction), m.vector(c.up));
    } catch (const Error& e) {
      fail("'motion.transform' key " + std::to_string(k) + " places the camera where " + e.what());
    }
  }
  if (motion.moving() && c.shutter_open != c.shutter_close) {
    out.motion = c.motion;
    out.position = c.position, out.direction = c.direction, out.up = c.up;
  } else {
    const Affine3f m = motion.at(c.shutter_open);
    position = m.point(c.position), direction = m.vector(c.direction), up = m.vector(c.up);
  }
  return out;
}

/// A ray from `org` along the unit `dir`, starting `near_clip` out, at `time`.
template <class T>
Ray<T> camera_ray(const Vec3<T>& org, const Vec3<T>& dir, float near_clip, const T& time) {
  Ray<T> ray;
  ray.org = org;
  ray.dir = dir;
  ray.tnear = T(near_clip);
  ray.time = time;
  return ray;
}

}  // namespace detail

/// What a perspective camera's rays are built from: the eye position, the view axis, the
/// ray direction (unit length along the axis) through screen point (0, 0), the steps
/// across and up the screen, the lens's right and up scaled by the aperture radius, and
/// the right eye's offset from `position`.
template <class V>
struct PerspectiveFrame {
  V position, forward, dir_00, du, dv, lens_du, lens_dv, eye_offset;
  auto fields() { return std::tie(position, forward, dir_00, du, dv, lens_du, lens_dv, eye_offset); }
  auto fields() const { return std::tie(position, forward, dir_00, du, dv, lens_du, lens_dv, eye_offset); }
};

/// A perspective camera ready to generate rays. The lens (a disc of `aperture_radius`
/// around the eye) blurs what lies off the focal plane: every lens point's ray of a
/// screen point meets its pinhole ray at `focus_distance` along the view axis. Stereo
/// eyes sit IPD/2 to either side and look parallel, as in OSPRay.
struct PreparedPerspective : PerspectiveFrame<Vec3f> {
  float focus_distance;
  StereoMode stereo;
  bool has_lens;
  // For re-preparing the frame of a moving camera at each ray's time.
  float width, height, aperture_radius, half_ipd;
  bool architectural;
  detail::PreparedCommon common;

  /// The frame of the camera placed at `position`, looking along `direction` (which the
  /// caller validated).
  PerspectiveFrame<Vec3f> frame(const Vec3f& position, const Vec3f& direction, const Vec3f& up) const {
    const Vec3f forward = normalize(direction);
    const Vec3f right = normalize(cross(forward, up));
    const Vec3f screen_up = architectural ? normalize(up) : cross(right, forward);
    const Vec3f du = right * width, dv = screen_up * height;
    return {position,          forward, forward - 0.5f * du - 0.5f * dv, du, dv, right * aperture_radius,
            screen_up * aperture_radius, right * half_ipd};
  }

  /// The ray through screen point (sx, sy) in [0,1]^2 from lens point (lens_u, lens_v)
  /// in [0,1)^2 ((0.5, 0.5) is the lens centre) at time sample `time_u` in [0,1).
  template <class T>
  Ray<T> generate(const T& sx, const T& sy, const T& lens_u = T(0.5f), const T& lens_v = T(0.5f),
                  const T& time_u = T(0.5f)) const {
    detail::EyeView<T> eye = detail::eye_view(stereo, sx, sy);
    common.map_region(eye.sx, eye.sy);
    const T time = common.time(eye.sx, eye.sy, time_u);
    const PerspectiveFrame<Vec3<T>> f = frame_at<T>(time);
    // Unnormalized, with unit length along the view axis.
    const Vec3<T> pinhole = f.dir_00 + f.du * eye.sx + f.dv * eye.sy;
    if (!has_lens && stereo == StereoMode::none)
      return detail::camera_ray(f.position, normalize(pinhole), common.near_clip, time);
    T disc_x(0.f), disc_y(0.f);
    if (has_lens) detail::concentric_disc(lens_u, lens_v, disc_x, disc_y);
    const Vec3<T> lens = f.lens_du * disc_x + f.lens_dv * disc_y;
    return detail::camera_ray(f.position + f.eye_offset * eye.side + lens, normalize(pinhole * T(focus_distance) - lens),
                              common.near_clip, time);
  }
  /// Whether generate() reads its lens sample (a pinhole does not, so the frame loop
  /// need not draw one).
  bool uses_lens() const { return has_lens; }
  bool uses_time_sample() const { return common.uses_time_sample(); }
  /// Distance along the view axis of a point at Euclidean distance t along `dir` (the
  /// lens lies in a plane across that axis).
  template <class T>
  T projected_depth(const Ray<T>& ray, const T& t) const {
    return t * dot(ray.dir, frame_at<T>(ray.time).forward);
  }

private:
  template <class T>
  PerspectiveFrame<Vec3<T>> frame_at(const T& time) const {
    return detail::frame_per_lane<PerspectiveFrame>(common.motion ? nullptr : static_cast<const PerspectiveFrame<Vec3f>*>(this), time,
                                                    [&](float t) {
                                                      Vec3f p, d, u;
                                                      common.placed_at(t, p, d, u);
                                                      return frame(p, d, u);
                                                    });
  }
};

/// What an orthographic camera's rays are built from: their direction, the origin of
/// screen point (0, 0) and the steps across and up the screen.
template <class V>
struct OrthographicFrame {
  V forward, org_00, du, dv;
  auto fields() { return std::tie(forward, org_00, du, dv); }
  auto fields() const { return std::tie(forward, org_00, du, dv); }
};

/// An orthographic camera ready to generate rays; it has no lens, so the lens sample is
/// ignored.
struct PreparedOrthographic : OrthographicFrame<Vec3f> {
  float width, height;
  detail::PreparedCommon common;

  OrthographicFrame<Vec3f> frame(const Vec3f& position, const Vec3f& direction, const Vec3f& up) const {
    const Vec3f forward = normalize(direction);
    const Vec3f right = normalize(cross(forward, up));
    const Vec3f du = right * width, dv = cross(right, forward) * height;
    return {forward, position - 0.5f * du - 0.5f * dv, du, dv};
  }

  template <class T>
  Ray<T> generate(const T& sx, const T& sy, const T& = T(0.5f), const T& = T(0.5f), const T& time_u = T(0.5f)) const {
    T x = sx, y = sy;
    common.map_region(x, y);
    const T time = common.time(x, y, time_u);
    const OrthographicFrame<Vec3<T>> f = detail::frame_per_lane<OrthographicFrame>(
        common.motion ? nullptr : static_cast<const OrthographicFrame<Vec3f>*>(this), time, [&](float t) {
          Vec3f p, d, u;
          common.placed_at(t, p, d, u);
          return frame(p, d, u);
        });
    return detail::camera_ray(f.org_00 + f.du * x + f.dv * y, f.forward, common.near_clip, time);
  }
  bool uses_lens() const { return false; }
  bool uses_time_sample() const { return common.uses_time_sample(); }
  template <class T>
  T projected_depth(const Ray<T>&, const T& t) const {
    return t;
  }
};

/// What a panoramic camera's rays are built from: its position and orthonormal frame.
template <class V>
struct PanoramicFrame {
  V position, forward, right, up;
  auto fields() { return std::tie(position, forward, right, up); }
  auto fields() const { return std::tie(position, forward, right, up); }
};

/// A panoramic camera ready to generate rays: longitude 2 pi (sx - 1/2) to the right of
/// `forward`, latitude pi (sy - 1/2) up. It has no lens.
struct PreparedPanoramic : PanoramicFrame<Vec3f> {
  float half_ipd;
  StereoMode stereo;
  detail::PreparedCommon common;

  PanoramicFrame<Vec3f> frame(const Vec3f& position, const Vec3f& direction, const Vec3f& up) const {
    const Vec3f forward = normalize(direction);
    const Vec3f right = normalize(cross(forward, up));
    return {position, forward, right, cross(right, forward)};
  }

  template <class T>
  Ray<T> generate(const T& sx, const T& sy, const T& = T(0.5f), const T& = T(0.5f), const T& time_u = T(0.5f)) const {
    using std::cos, std::sin;
    detail::EyeView<T> eye = detail::eye_view(stereo, sx, sy);
    common.map_region(eye.sx, eye.sy);
    const T time = common.time(eye.sx, eye.sy, time_u);
    const PanoramicFrame<Vec3<T>> f = detail::frame_per_lane<PanoramicFrame>(
        common.motion ? nullptr : static_cast<const PanoramicFrame<Vec3f>*>(this), time, [&](float t) {
          Vec3f p, d, u;
          common.placed_at(t, p, d, u);
          return frame(p, d, u);
        });
    constexpr float pi = std::numbers::pi_v<float>;
    const T longitude = T(2.f * pi) * (eye.sx - T(0.5f)), latitude = T(pi) * (eye.sy - T(0.5f));
    const T cos_lon = cos(longitude), sin_lon = sin(longitude);
    const T cos_lat = cos(latitude), sin_lat = sin(latitude);
    const Vec3<T> heading = f.forward * cos_lon + f.right * sin_lon;
    const Vec3<T> dir = heading * cos_lat + f.up * sin_lat;
    // The eye sits to the side of the ray, across it and `up` (dir x up): a quarter turn
    // right of the heading, shrinking with the cosine of the latitude.
    const Vec3<T> heading_right = f.right * cos_lon - f.forward * sin_lon;
    return detail::camera_ray(f.position + heading_right * (eye.side * cos_lat * T(half_ipd)), dir, common.near_clip,
                              time);
  }
  bool uses_lens() const { return false; }
  bool uses_time_sample() const { return common.uses_time_sample(); }
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
  PreparedPerspective out;
  Vec3f position, direction, up;
  out.common = detail::prepare_common("perspective", c, position, direction, up,
                                      [&](const Vec3f& p, const Vec3f& d, const Vec3f& u) {
                                        detail::view_basis("perspective", p, d, u, c.aspect);
                                      });
  // Each eye of a split image sees half of it, with the field of view of the whole.
  float eye_aspect = c.aspect;
  if (c.stereo_mode == StereoMode::side_by_side) eye_aspect *= 0.5f;
  if (c.stereo_mode == StereoMode::top_bottom) eye_aspect *= 2.f;
  out.height = 2.f * std::tan(0.5f * c.fovy * std::numbers::pi_v<float> / 180.f);
  out.width = out.height * eye_aspect;
  out.aperture_radius = c.aperture_radius;
  out.half_ipd = c.stereo_mode == StereoMode::none ? 0.f : 0.5f * c.interpupillary_distance;
  out.architectural = c.architectural;
  out.focus_distance = c.focus_distance;
  out.stereo = c.stereo_mode;
  out.has_lens = c.aperture_radius > 0.f;
  static_cast<PerspectiveFrame<Vec3f>&>(out) = out.frame(position, direction, up);
  return out;
}

inline PreparedOrthographic prepare(const OrthographicCamera& c) {
  if (!(c.height > 0.f) || !std::isfinite(c.height))
    throw Error("orthographic camera: 'height' must be positive");
  PreparedOrthographic out;
  Vec3f position, direction, up;
  out.common = detail::prepare_common("orthographic", c, position, direction, up,
                                      [&](const Vec3f& p, const Vec3f& d, const Vec3f& u) {
                                        detail::view_basis("orthographic", p, d, u, c.aspect);
                                      });
  out.height = c.height;
  out.width = c.height * c.aspect;
  static_cast<OrthographicFrame<Vec3f>&>(out) = out.frame(position, direction, up);
  return out;
}

inline PreparedPanoramic prepare(const PanoramicCamera& c) {
  detail::check_stereo("panoramic", c.stereo_mode, c.interpupillary_distance);
  PreparedPanoramic out;
  Vec3f position, direction, up;
  out.common = detail::prepare_common("panoramic", c, position, direction, up,
                                      [&](const Vec3f& p, const Vec3f& d, const Vec3f& u) {
                                        detail::view_basis("panoramic", p, d, u, 1.f);
                                      });
  out.half_ipd = c.stereo_mode == StereoMode::none ? 0.f : 0.5f * c.interpupillary_distance;
  out.stereo = c.stereo_mode;
  static_cast<PanoramicFrame<Vec3f>&>(out) = out.frame(position, direction, up);
  return out;
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
