#pragma once
#include <cstdint>

#include "sciray/math/ray.hpp"
#include "sciray/math/vec.hpp"

namespace sciray {

/// Where a packet of camera samples comes from: each lane's pixel (linear index into the
/// frame buffer, -1 outside the image) and which sample of that pixel it is
/// (frame * pixelSamples + s). Renderers seed their random numbers from these two, so an
/// image depends only on them, never on which thread rendered which tile.
template <class Arch>
struct SampleIndex {
  simd::Int<Arch> pixel;
  std::uint32_t sample = 0;
  /// Where the camera sample lies on the screen, [0,1]^2 from the bottom left (for
  /// screen-space backgrounds).
  simd::Float<Arch> screen_x = simd::Float<Arch>(0.5f), screen_y = simd::Float<Arch>(0.5f);
  /// The screen position of the lane's pixel centre: per-pixel maps (map_maxDepth) are
  /// read there, the same for every sample of the pixel.
  simd::Float<Arch> center_x = simd::Float<Arch>(0.5f), center_y = simd::Float<Arch>(0.5f);
  /// Whether the frame buffer keeps depth or ids: where it does not, renderers skip
  /// finding what volumes would put there.
  bool first_hit_channels = true;
};

/// A renderer's result for a packet of camera rays, one value per frame buffer channel.
template <class Arch>
struct PixelSample {
  using F = simd::Float<Arch>;
  using I = simd::Int<Arch>;
  Vec3<F> color{F(0.f), F(0.f), F(0.f)};  ///< linear RGB
  F alpha = F(0.f);
  F t = F(0.f);  ///< distance to the first hit along the unit ray direction (inf if none)
  Vec3<F> normal{F(0.f), F(0.f), F(0.f)};  ///< world-space shading normal of the first hit, facing the camera
  Vec3<F> albedo{F(0.f), F(0.f), F(0.f)};  ///< the first hit's material albedo (background colour where none)
  I prim_id = I(-1);  ///< primitive, geometry and instance of the first hit; -1 where none
  I geom_id = I(-1);
  I inst_id = I(-1);
};

/// One packet of camera samples as a renderer gets it: the rays, the lanes inside the
/// image and where the samples come from.
template <class Arch>
struct CameraPacket {
  Ray<simd::Float<Arch>> ray;
  simd::Mask<Arch> active;
  SampleIndex<Arch> index;
};

}  // namespace sciray
