#pragma once
#include <limits>

#include "sciray/math/vec.hpp"

namespace sciray {

struct Box3f {
  Vec3f lower{std::numeric_limits<float>::infinity(), std::numeric_limits<float>::infinity(),
              std::numeric_limits<float>::infinity()};
  Vec3f upper{-std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity(),
              -std::numeric_limits<float>::infinity()};

  bool empty() const { return lower.x > upper.x || lower.y > upper.y || lower.z > upper.z; }
  void extend(const Vec3f& p) {
    lower = min(lower, p);
    upper = max(upper, p);
  }
  void extend(const Box3f& b) {
    lower = min(lower, b.lower);
    upper = max(upper, b.upper);
  }
  Vec3f center() const { return (lower + upper) * 0.5f; }
  Vec3f size() const { return upper - lower; }
};

}  // namespace sciray
