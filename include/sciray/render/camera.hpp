#pragma once
// Cameras as OSPRay defines them: screen coordinates (sx, sy) in [0,1]^2 with (0,0) at
// the bottom-left of the image map to rays. `prepare` validates the parameters once per
// frame and precomputes the image-plane basis, so that ray generation is a few FMAs per
// lane.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <variant>

#include "sciray/error.hpp"
#include "sciray/math/box.hpp"
#include "sciray/math/ray.hpp"

namespace sciray {

struct PerspectiveCamera {
  Vec3f position{0.f, 0.f, 0.f};
  Vec3f direction{0.f, 0.f, -1.f};
  Vec3f up{0.f, 1.f, 0.f};
  float fovy = 60.f;   ///< full vertical field of view, degrees
  float aspect = 1.f;  ///< width / height
};

struct OrthographicCamera {
  Vec3f position{0.f, 0.f, 0.f};
  Vec3f direction{0.f, 0.f, -1.f};
  Vec3f up{0.f, 1.f, 0.f};
  float height = 1.f;  ///< world-space height of the view
  float aspect = 1.f;
};

using Camera = std::variant<PerspectiveCamera, OrthographicCamera>;

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

}  // namespace detail

/// A perspective camera ready to generate rays.
struct PreparedPerspective {
  Vec3f position, forward, dir_00, du, dv;

  template <class T>
  Ray<T> generate(const T& sx, const T& sy) const {
    Ray<T> ray;
    ray.org = Vec3<T>(position);
    ray.dir = normalize(Vec3<T>(dir_00) + Vec3<T>(du) * sx + Vec3<T>(dv) * sy);
    return ray;
  }
  /// Distance along the view axis of a point at Euclidean distance t along `dir`.
  template <class T>
  T projected_depth(const Ray<T>& ray, const T& t) const {
    return t * dot(ray.dir, Vec3<T>(forward));
  }
};

struct PreparedOrthographic {
  Vec3f forward, org_00, du, dv;

  template <class T>
  Ray<T> generate(const T& sx, const T& sy) const {
    Ray<T> ray;
    ray.org = Vec3<T>(org_00) + Vec3<T>(du) * sx + Vec3<T>(dv) * sy;
    ray.dir = Vec3<T>(forward);
    return ray;
  }
  template <class T>
  T projected_depth(const Ray<T>&, const T& t) const {
    return t;
  }
};

inline PreparedPerspective prepare(const PerspectiveCamera& c) {
  if (!(c.fovy > 0.f && c.fovy < 180.f))
    throw Error("perspective camera: 'fovy' must be in (0, 180) degrees, got " + std::to_string(c.fovy));
  const auto basis = detail::view_basis("perspective", c.position, c.direction, c.up, c.aspect);
  const float half_height = std::tan(0.5f * c.fovy * std::numbers::pi_v<float> / 180.f);
  const Vec3f dv = basis.up * (2.f * half_height);
  const Vec3f du = basis.right * (2.f * half_height * c.aspect);
  return {c.position, basis.forward, basis.forward - 0.5f * du - 0.5f * dv, du, dv};
}

inline PreparedOrthographic prepare(const OrthographicCamera& c) {
  if (!(c.height > 0.f) || !std::isfinite(c.height))
    throw Error("orthographic camera: 'height' must be positive");
  const auto basis = detail::view_basis("orthographic", c.position, c.direction, c.up, c.aspect);
  const Vec3f dv = basis.up * c.height;
  const Vec3f du = basis.right * (c.height * c.aspect);
  return {basis.forward, c.position - 0.5f * du - 0.5f * dv, du, dv};
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
