#pragma once
#include "sciray/math/vec.hpp"

namespace sciray {

/// A renderer's result for a packet of primary rays.
template <class Arch>
struct PixelSample {
  using F = simd::Float<Arch>;
  Vec3<F> color;  ///< linear RGB
  F alpha;
  F t;  ///< distance to the first hit along the unit ray direction (inf if none)
};

}  // namespace sciray
