#pragma once
// A 2D texture of linear RGB texels (OSPRay `texture2d`), sampled bilinearly (or nearest).
// Environment maps and backplates read it with the u axis wrapping and the v axis clamped
// (sample); materials' maps tile it, both axes wrapping (sample_tiled), as OSPRay's maps.
#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "sciray/error.hpp"
#include "sciray/geometry/surface.hpp"
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

  /// u wraps, v is clamped: environment maps and backplates.
  Vec3f sample(float u, float v) const { return lookup<false>(u, v); }
  /// Both axes wrap: material maps (OSPRay's repeat wrap mode).
  Vec3f sample_tiled(float u, float v) const { return lookup<true>(u, v); }

  std::size_t bytes() const { return texels_.size() * sizeof(Vec3f); }

private:
  template <bool WrapV>
  Vec3f lookup(float u, float v) const {
    if (!std::isfinite(u) || !std::isfinite(v)) return splat(0.f);
    // Tiling is periodic: reduce first, so that large coordinates keep their precision.
    if constexpr (WrapV) u -= std::floor(u), v -= std::floor(v);
    const float x = u * static_cast<float>(width_) - 0.5f, y = v * static_cast<float>(height_) - 0.5f;
    const auto row = [&](int at) { return WrapV ? wrap(at, height_) : std::clamp(at, 0, height_ - 1); };
    if (nearest_)
      return texel(wrap(static_cast<int>(std::floor(x + 0.5f)), width_), row(static_cast<int>(std::floor(y + 0.5f))));
    const float fx = std::floor(x), fy = std::floor(y);
    const float ax = x - fx, ay = y - fy;
    const int x0 = wrap(static_cast<int>(fx), width_), x1 = wrap(static_cast<int>(fx) + 1, width_);
    const int y0 = row(static_cast<int>(fy)), y1 = row(static_cast<int>(fy) + 1);
    return (texel(x0, y0) * (1.f - ax) + texel(x1, y0) * ax) * (1.f - ay) +
           (texel(x0, y1) * (1.f - ax) + texel(x1, y1) * ax) * ay;
  }
  static int wrap(int x, int n) { return ((x % n) + n) % n; }

  int width_, height_;
  bool nearest_;
  std::vector<Vec3f> texels_;
};

/// OSPRay's affine2f for texture coordinates: uv' = vx u + vy v + p.
struct TexCoordTransform {
  TexCoord<float> vx{1.f, 0.f}, vy{0.f, 1.f}, p{0.f, 0.f};

  TexCoord<float> operator()(const TexCoord<float>& uv) const {
    return {vx.u * uv.u + vy.u * uv.v + p.u, vx.v * uv.u + vy.v * uv.v + p.v};
  }
  bool finite() const {
    return std::isfinite(vx.u) && std::isfinite(vx.v) && std::isfinite(vy.u) && std::isfinite(vy.v) &&
           std::isfinite(p.u) && std::isfinite(p.v);
  }

  /// OSPRay's `<map>.rotation` (degrees, counterclockwise), `.scale` (enlarges) and
  /// `.translation` (moves towards +u, +v) of the texture about its centre (0.5, 0.5),
  /// applied in that order; the transform maps surface coordinates into the texture, so
  /// it is their inverse.
  static TexCoordTransform of_texture(float rotation_degrees, TexCoord<float> scale, TexCoord<float> translation) {
    const float a = -rotation_degrees * 3.14159265358979f / 180.f, c = std::cos(a), s = std::sin(a);
    // uv' = 0.5 + R(-a) S^-1 (uv - translation - 0.5)
    TexCoordTransform t;
    t.vx = {c / scale.u, s / scale.u};
    t.vy = {-s / scale.v, c / scale.v};
    const TexCoord<float> shift{-translation.u - 0.5f, -translation.v - 0.5f};
    t.p = {t.vx.u * shift.u + t.vy.u * shift.v + 0.5f, t.vx.v * shift.u + t.vy.v * shift.v + 0.5f};
    return t;
  }
};

/// A texture as a material parameter's map (OSPRay's `map_kd` etc.): the texture tiles
/// the surface's texture coordinates after `transform`. Empty where the parameter has none.
struct TextureMap {
  std::shared_ptr<const Texture2D> texture;
  TexCoordTransform transform;

  explicit operator bool() const { return texture != nullptr; }
  /// The texture's colour at surface coordinates uv; scalar maps read its first channel.
  Vec3f at(const TexCoord<float>& uv) const {
    const TexCoord<float> t = transform(uv);
    return texture->sample_tiled(t.u, t.v);
  }
};

}  // namespace sciray
