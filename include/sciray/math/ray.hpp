#pragma once
#include <limits>

#include "sciray/math/vec.hpp"

namespace sciray {

/// The largest ray origin or direction coordinate Embree traces (its FLT_LARGE): its
/// traversal asserts on a larger or non-finite one.
inline constexpr float max_ray_coordinate = 1.844e18f;

/// One ray (T = float) or a packet of W rays (T = Float<Arch>); `dir` is unit length
/// for camera rays, so hit distances are Euclidean.
template <class T>
struct Ray {
  Vec3<T> org;
  Vec3<T> dir;
  T tnear = T(0.f);
  T tfar = T(std::numeric_limits<float>::infinity());
  /// When within the frame's shutter the ray samples the scene, for what moves (Embree's
  /// ray time, in the time units of OSPRay's `shutter`); secondary rays keep their camera
  /// ray's time.
  T time = T(0.f);
};

}  // namespace sciray
