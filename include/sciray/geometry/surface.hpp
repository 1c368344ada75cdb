#pragma once
#include "sciray/math/vec.hpp"

namespace sciray {

/// What a renderer needs to shade a packet of hits on a surface.
template <class Arch>
struct SurfaceSample {
  using F = simd::Float<Arch>;
  Vec3<F> normal;  ///< unit shading normal (not yet facing the ray)
  Vec3<F> color;   ///< base colour (linear RGB)
  simd::Mask<Arch> has_color;  ///< whether the geometry supplied the colour
};

}  // namespace sciray
