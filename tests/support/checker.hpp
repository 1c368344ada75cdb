#pragma once
// A checkerboard texture and its analytic colour, for tests of texture maps.
#include <cmath>
#include <memory>
#include <utility>
#include <vector>

#include "sciray/math/vec.hpp"
#include "sciray/render/texture.hpp"

namespace sciray::test_support {

/// An n x n checkerboard of colours a (where the cell's x + y is even) and b.
inline std::shared_ptr<const Texture2D> checker(int n, Vec3f a, Vec3f b) {
  std::vector<Vec3f> texels;
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) texels.push_back((x + y) % 2 == 0 ? a : b);
  return std::make_shared<const Texture2D>(n, n, std::move(texels), /*nearest=*/true);
}

/// The checker's colour at (u, v) in [0, 1)^2, analytically.
inline Vec3f checker_at(float u, float v, int n, Vec3f a, Vec3f b) {
  const int x = static_cast<int>(std::floor(u * n)), y = static_cast<int>(std::floor(v * n));
  return (x + y) % 2 == 0 ? a : b;
}

}  // namespace sciray::test_support
