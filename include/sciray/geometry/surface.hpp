#pragma once
#include "sciray/math/vec.hpp"

namespace sciray {

/// Texture coordinates (OSPRay's vec2f `texcoord`), of one lane (T = float) or a packet.
template <class T>
struct TexCoord {
  T u, v;
};

/// What a renderer needs to shade a packet of hits on a surface.
template <class Arch>
struct SurfaceSample {
  using F = simd::Float<Arch>;
  Vec3<F> normal;  ///< unit shading normal (not yet facing the ray)
  Vec3<F> color;   ///< base colour (linear RGB)
  simd::Mask<Arch> has_color;  ///< whether the geometry supplied the colour
  /// Interpolated texture coordinates; (0, 0) on geometry without them, as in OSPRay.
  TexCoord<F> uv{F(0.f), F(0.f)};
};

}  // namespace sciray
