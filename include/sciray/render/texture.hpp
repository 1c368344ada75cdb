#pragma once
// A 2D texture of linear RGB texels (OSPRay `texture2d`), sampled bilinearly with the
// u axis wrapping and the v axis clamped, as latitude-longitude environment maps and
// backplates want.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "sciray/error.hpp"
#include "sciray/math/vec.hpp"

namespace sciray {

class Texture2D {
public:
  /// `texels`: width * height RGB triples, row 0 at v = 0 (the bottom, as OSPRay).
  Texture2D(int width, int height, std::vector<Vec3f> texels, bool nearest = false)
      : width_(width), height_(height), nearest_(nearest), texels_(std::move(texels)) {
    if (width <= 0 || height <= 0) throw Error("texture2d: size must be positive");
    if (texels_.size() != static_cast<std::size_t>(width) * static_cast<std::size_t>(height))
      throw Error("texture2d: " + std::to_string(texels_.size()) + " texels for a " + std::to_string(width) + "x" +
                  std::to_string(height) + " texture");
    for (std::size_t i = 0; i < texels_.size(); ++i) {
      const Vec3f& t = texels_[i];
      if (!(std::isfinite(t.x) && std::isfinite(t.y) && std::isfinite(t.z)) || t.x < 0.f || t.y < 0.f || t.z < 0.f)
        throw Error("texture2d: texel " + std::to_string(i) + " is negative or not finite");
    }
  }

  int width() const { return width_; }
  int height() const { return height_; }
  const Vec3f& texel(int x, int y) const { return texels_[static_cast<std::size_t>(y) * width_ + x]; }

  Vec3f sample(float u, float v) const {
    if (!std::isfinite(u) || !std::isfinite(v)) return splat(0.f);
    const float x = u * static_cast<float>(width_) - 0.5f, y = v * static_cast<float>(height_) - 0.5f;
    if (nearest_) return texel(wrap(static_cast<int>(std::floor(x + 0.5f))), clamp_y(static_cast<int>(std::floor(y + 0.5f))));
    const float fx = std::floor(x), fy = std::floor(y);
    const float ax = x - fx, ay = y - fy;
    const int x0 = wrap(static_cast<int>(fx)), x1 = wrap(static_cast<int>(fx) + 1);
    const int y0 = clamp_y(static_cast<int>(fy)), y1 = clamp_y(static_cast<int>(fy) + 1);
    return (texel(x0, y0) * (1.f - ax) + texel(x1, y0) * ax) * (1.f - ay) +
           (texel(x0, y1) * (1.f - ax) + texel(x1, y1) * ax) * ay;
  }

  std::size_t bytes() const { return texels_.size() * sizeof(Vec3f); }

private:
  int wrap(int x) const { return ((x % width_) + width_) % width_; }
  int clamp_y(int y) const { return std::clamp(y, 0, height_ - 1); }

  int width_, height_;
  bool nearest_;
  std::vector<Vec3f> texels_;
};

}  // namespace sciray
