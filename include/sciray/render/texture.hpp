#pragma once
// A 2D texture of linear RGB texels (OSPRay `texture2d`), sampled bilinearly (or nearest).
// Environment maps read it with the u axis wrapping and the v axis clamped (sample),
// backplates clamped on both axes (sample_clamped, as OSPRay 3.1's runtime shows them);
// materials' maps read it by its wrap mode per axis (sample_tiled): OSPRay's `wrapMode`,
// repeat by default, or mirrored repeat, or clamped to the edge.
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

  /// u wraps, v is clamped: environment maps.
  Vec3f sample(float u, float v) const { return lookup<Wrapping::environment>(u, v); }
  /// Both axes clamped: backplates.
  Vec3f sample_clamped(float u, float v) const { return lookup<Wrapping::clamped>(u, v); }
  /// Each axis by its wrap mode: material maps.
  Vec3f sample_tiled(float u, float v) const { return lookup<Wrapping::tiled>(u, v); }
  /// The wrap modes of u and v for sample_tiled (both repeat unless set).
  void set_wrap(TextureWrap u, TextureWrap v) { wrap_u_ = u, wrap_v_ = v; }

  std::size_t bytes() const { return texels_.size() * sizeof(Vec3f); }

private:
  enum class Wrapping { environment, clamped, tiled };
  template <Wrapping How>
  Vec3f lookup(float u, float v) const {
    if (!std::isfinite(u) || !std::isfinite(v)) return splat(0.f);
    const TextureWrap mode_u = How == Wrapping::tiled     ? wrap_u_
                               : How == Wrapping::clamped ? TextureWrap::clamp_to_edge
                                                          : TextureWrap::repeat;
    const TextureWrap mode_v = How == Wrapping::tiled ? wrap_v_ : TextureWrap::clamp_to_edge;
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
    // Clamped: every t beyond [-1, 2] reads the edge texel as -1 or 2 do, and a far one
    // would overflow the texel index.
    return std::clamp(t, -1.f, 2.f);
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
  /// This transform after `first`.
  TexCoordTransform operator*(const TexCoordTransform& first) const {
    const auto linear = [&](const TexCoord<float>& v) -> TexCoord<float> {
      return {vx.u * v.u + vy.u * v.v, vx.v * v.u + vy.v * v.v};
    };
    return {linear(first.vx), linear(first.vy), (*this)(first.p)};
  }
  bool finite() const {
    return std::isfinite(vx.u) && std::isfinite(vx.v) && std::isfinite(vy.u) && std::isfinite(vy.v) &&
           std::isfinite(p.u) && std::isfinite(p.v);
  }

  static TexCoordTransform translate(TexCoord<float> by) { return {{1.f, 0.f}, {0.f, 1.f}, by}; }
  static TexCoordTransform scale(TexCoord<float> by) { return {{by.u, 0.f}, {0.f, by.v}, {0.f, 0.f}}; }
  /// Counterclockwise by `radians`.
  static TexCoordTransform rotate(float radians) {
    const float c = std::cos(radians), s = std::sin(radians);
    return {{c, s}, {-s, c}, {0.f, 0.f}};
  }
  /// `linear` about the texture's centre (0.5, 0.5).
  static TexCoordTransform about_centre(const TexCoordTransform& linear) {
    return translate({0.5f, 0.5f}) * linear * translate({-0.5f, -0.5f});
  }

  /// OSPRay's `<map>.rotation` (degrees), `.scale` and `.translation` composed as OSPRay 3
  /// composes them: the texture turns counterclockwise and grows about its centre
  /// (0.5, 0.5), then moves towards +u, +v. The transform maps surface coordinates into
  /// the texture, so each step is the inverse, and the rotation applies to them first.
  static TexCoordTransform of_texture(float rotation_degrees, TexCoord<float> scale, TexCoord<float> translation) {
    return translate({-translation.u, -translation.v}) * about_centre(TexCoordTransform::scale({1.f / scale.u, 1.f / scale.v})) *
           about_centre(rotate(-rotation_degrees * 3.14159265358979f / 180.f));
  }

  /// How a normal map's tangent-space normals turn with this transform: the inverse (the
  /// transpose) of the rotation closest to its linear part, a reflection kept (OSPRay's
  /// `orthogonal().transposed()`), so that normals follow the texture as it turns on the
  /// surface. In 2D the closest rotation has a closed form: the angle atan2(c - b, a + d)
  /// of the matrix [a b; c d].
  TexCoordTransform normal_rotation() const {
    TexCoord<float> x = vx;
    const bool mirrored = vx.u * vy.v - vy.u * vx.v < 0.f;
    if (mirrored) x = {-x.u, -x.v};
    const float angle = std::atan2(x.v - vy.u, x.u + vy.v);
    TexCoordTransform r = rotate(angle);
    if (mirrored) r.vx = {-r.vx.u, -r.vx.v};
    return {{r.vx.u, r.vy.u}, {r.vx.v, r.vy.v}, {0.f, 0.f}};  // transposed
  }
};

/// A texture as a material parameter's map (OSPRay's `map_kd` etc.): the texture tiles
/// the surface's texture coordinates after `transform`. Empty where the parameter has none.
struct TextureMap {
  std::shared_ptr<const Texture2D> texture;
  TexCoordTransform transform;
  /// The texture's alpha channel as grey texels, where its format has one and the map reads
  /// it: OSPRay multiplies the opacity of obj and principled materials by the alpha of their
  /// map_kd and map_baseColor. Null otherwise, which costs a map nothing per hit.
  std::shared_ptr<const Texture2D> alpha;

  explicit operator bool() const { return texture != nullptr; }
  /// The texture's colour at surface coordinates uv; scalar maps read its first channel.
  Vec3f at(const TexCoord<float>& uv) const {
    const TexCoord<float> t = transform(uv);
    return texture->sample_tiled(t.u, t.v);
  }
  /// The alpha at surface coordinates uv; call only where `alpha` is set.
  float alpha_at(const TexCoord<float>& uv) const {
    const TexCoord<float> t = transform(uv);
    return alpha->sample_tiled(t.u, t.v).x;
  }
};

/// A normal map (OSPRay's obj `map_bump`, principled `map_normal`): its texels hold
/// tangent-space normals n encoded as (n + 1) / 2 (see normal_map_texel), x along the
/// surface's dP/ds, y along dP/dt, z along the shading normal. Empty where the material
/// has none.
struct NormalMap {
  TextureMap map;

  explicit operator bool() const { return bool(map); }
  /// The tangent-space normal at surface coordinates uv, x and y times `scale` (principled's
  /// `normal`) and turned with the map's transform; not normalized, as OSPRay's.
  Vec3f at(const TexCoord<float>& uv, float scale = 1.f) const {
    const Vec3f e = map.at(uv);
    const TexCoord<float> xy = map.transform.normal_rotation()({(2.f * e.x - 1.f) * scale, (2.f * e.y - 1.f) * scale});
    return {xy.u, xy.v, 2.f * e.z - 1.f};
  }
  /// The shading normal `n` (unit, on the viewer's side) tilted by the map in the frame of
  /// the surface's texture derivatives dpds, dpdt (OSPRay's makeShadingFrame); n itself
  /// where that frame degenerates.
  Vec3f perturb(const Vec3f& n, const Vec3f& dpds, const Vec3f& dpdt, const TexCoord<float>& uv,
                float scale = 1.f) const {
    const Vec3f local = at(uv, scale);
    const float ls = length(dpds), lt = length(dpdt);
    if (!(ls > 0.f) || !(lt > 0.f)) return n;
    const Vec3f tilted = dpds * (local.x / ls) + dpdt * (local.y / lt) + n * local.z;
    const float l = length(tilted);
    return l > 0.f && std::isfinite(l) ? tilted / l : n;
  }
};

/// A normal map's texels from raw channel values in [0, 1] (before any sRGB decoding,
/// which OSPRay ignores for normals): OSPRay decodes v * scale - 1, with scale 255/127
/// for 8-bit and 65535/32767 for 16-bit channels (so that 127 and 32767 are 0) and 2 for
/// floating point ones; stored here as (v * scale) / 2, so that NormalMap::at's 2e - 1
/// gives the same.
inline Vec3f normal_map_texel(const Vec3f& raw, float scale) { return raw * (0.5f * scale); }

}  // namespace sciray
