#pragma once
// A 2D texture of linear RGB texels (OSPRay `texture2d`), sampled bilinearly (or nearest).
// Environment maps and backplates read it with the u axis wrapping and the v axis clamped
// (sample); materials' maps read it by its wrap mode per axis (sample_tiled): OSPRay's
// `wrapMode`, repeat by default, or mirrored repeat, or clamped to the edge.
#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "sciray/error.hpp"
#include "sciray/geometry/surface.hpp"
#include "sciray/math/vec.hpp"

namespace sciray {

/// How a material map continues beyond [0, 1): values as OSPRay's OSPTextureWrapMode.
enum class TextureWrap : int { repeat = 0, mirrored_repeat = 1, clamp_to_edge = 2 };

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
  /// Each axis by its wrap mode: material maps.
  Vec3f sample_tiled(float u, float v) const { return lookup<true>(u, v); }
  /// The wrap modes of u and v for sample_tiled (both repeat unless set).
  void set_wrap(TextureWrap u, TextureWrap v) { wrap_u_ = u, wrap_v_ = v; }

  std::size_t bytes() const { return texels_.size() * sizeof(Vec3f); }

private:
  /// `Tiled`: by the wrap modes; else u repeats and v is clamped.
  template <bool Tiled>
  Vec3f lookup(float u, float v) const {
    if (!std::isfinite(u) || !std::isfinite(v)) return splat(0.f);
    const TextureWrap mode_u = Tiled ? wrap_u_ : TextureWrap::repeat;
    const TextureWrap mode_v = Tiled ? wrap_v_ : TextureWrap::clamp_to_edge;
    // Repeats are periodic: reduce first (by one period, two when mirrored), so that
    // large coordinates keep their precision.
    u = reduce(u, mode_u), v = reduce(v, mode_v);
    const float x = u * static_cast<float>(width_) - 0.5f, y = v * static_cast<float>(height_) - 0.5f;
    const auto column = [&](int at) { return index(at, width_, mode_u); };
    const auto row = [&](int at) { return index(at, height_, mode_v); };
    if (nearest_)
      return texel(column(static_cast<int>(std::floor(x + 0.5f))), row(static_cast<int>(std::floor(y + 0.5f))));
    const float fx = std::floor(x), fy = std::floor(y);
    const float ax = x - fx, ay = y - fy;
    const int x0 = column(static_cast<int>(fx)), x1 = column(static_cast<int>(fx) + 1);
    const int y0 = row(static_cast<int>(fy)), y1 = row(static_cast<int>(fy) + 1);
    return (texel(x0, y0) * (1.f - ax) + texel(x1, y0) * ax) * (1.f - ay) +
           (texel(x0, y1) * (1.f - ax) + texel(x1, y1) * ax) * ay;
  }
  static float reduce(float t, TextureWrap mode) {
    if (mode == TextureWrap::repeat) return t - std::floor(t);
    if (mode == TextureWrap::mirrored_repeat) return t - 2.f * std::floor(0.5f * t);
    return t;
  }
  /// The texel index of `at` on an axis of `n` texels.
  static int index(int at, int n, TextureWrap mode) {
    switch (mode) {
      case TextureWrap::repeat: return ((at % n) + n) % n;
      case TextureWrap::mirrored_repeat: {
        const int m = ((at % (2 * n)) + 2 * n) % (2 * n);
        return m < n ? m : 2 * n - 1 - m;
      }
      case TextureWrap::clamp_to_edge: break;
    }
    return std::clamp(at, 0, n - 1);
  }

  int width_, height_;
  bool nearest_;
  TextureWrap wrap_u_ = TextureWrap::repeat, wrap_v_ = TextureWrap::repeat;
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
