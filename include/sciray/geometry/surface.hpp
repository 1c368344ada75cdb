#pragma once
#include <cstddef>
#include <vector>

#include "sciray/geometry/data.hpp"
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
  /// The colour's alpha, which OSPRay's renderers take as opacity (times the material's).
  F alpha = F(1.f);
  /// The least distance secondary rays start off this surface at, where the geometry
  /// knows its own precision (OSPRay's per-geometry epsilon: spheres scale it by their
  /// radius); 0 where the hit position's magnitude decides alone.
  F epsilon = F(0.f);
  /// Interpolated texture coordinates; without them, as in OSPRay, a mesh's hit
  /// coordinates (u, v) and (0, 0) on other geometry.
  TexCoord<F> uv{F(0.f), F(0.f)};
};

/// Whether any of the RGBA `colors` (alpha fourth) is translucent: renderers then look
/// at the alpha of what shadow rays pass.
inline bool translucent(const StridedView<float>& colors) {
  for (std::size_t i = 0; i < colors.count; ++i)
    if (colors.element(i)[3] < 1.f) return true;
  return false;
}

template <class Allocator>
bool translucent(const std::vector<float, Allocator>& rgba) {
  return translucent(StridedView<float>(rgba.data(), rgba.size() / 4, 4 * sizeof(float)));
}

}  // namespace sciray
