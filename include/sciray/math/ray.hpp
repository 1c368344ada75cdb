#pragma once
#include <limits>

#include "sciray/math/vec.hpp"

namespace sciray {

/// One ray (T = float) or a packet of W rays (T = Float<Arch>); `dir` is unit length
/// for camera rays, so hit distances are Euclidean.
template <class T>
struct Ray {
  Vec3<T> org;
  Vec3<T> dir;
  T tnear = T(0.f);
  T tfar = T(std::numeric_limits<float>::infinity());
};

}  // namespace sciray
