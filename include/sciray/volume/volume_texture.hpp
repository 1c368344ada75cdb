#pragma once
// VolumeTexture: a volume seen through a transfer function as a 3D texture (OSPRay's
// `volume` texture, as an obj material's `map_kd`). A surface point, in its geometry's own
// space, is moved by the texture's transform (OSPRay's affine3f `map_kd.transform`) to
// where the volume is sampled. The volume's voxel type and layout are erased behind a
// sampling function, so one type serves every StructuredRegular.
#include <memory>

#include "sciray/error.hpp"
#include "sciray/math/affine.hpp"
#include "sciray/math/box.hpp"
#include "sciray/volume/transfer_function.hpp"

namespace sciray {

class VolumeTexture {
public:
  template <class Volume>
  VolumeTexture(std::shared_ptr<const Volume> volume, TransferFunction transfer_function, Affine3f transform = {})
      : tf_(std::move(transfer_function)), transform_(transform) {
    if (!volume) throw Error("volume texture: the volume is missing");
    bounds_ = volume->bounds();
    sample_ = [](const void* v, const Vec3f& p) {
      return static_cast<const Volume*>(v)->template sample<simd::scalar>(p);
    };
    volume_ = std::move(volume);
  }

  const TransferFunction& transfer_function() const { return tf_; }
  std::size_t owned_bytes() const { return (tf_.colors().size() * 6 + tf_.opacities().size() * 2) * sizeof(float); }

  /// The volume's value at the surface point `p`, the border's beyond the volume.
  float value(const Vec3f& p) const { return sample_(volume_.get(), transform_.point(p)); }

  /// The transfer function's colour and opacity of the volume's value at the surface
  /// points `p` of `lanes`; both 0 where the point falls outside the volume, as OSPRay's
  /// TextureVolume (an obj material then shows nothing there: the opacity is 0).
  template <class Arch>
  void lookup(const Vec3<simd::Float<Arch>>& p, const simd::Mask<Arch>& lanes, Vec3<simd::Float<Arch>>& color,
              simd::Float<Arch>& opacity) const {
    using F = simd::Float<Arch>;
    constexpr int W = simd::width<Arch>;
    alignas(64) float values[W], covered[W];
    for (int i = 0; i < W; ++i) {
      values[i] = 0.f, covered[i] = 0.f;
      if (!simd::lane(lanes, i)) continue;
      const Vec3f at = transform_.point({simd::lane(p.x, i), simd::lane(p.y, i), simd::lane(p.z, i)});
      if (at.x < bounds_.lower.x || at.y < bounds_.lower.y || at.z < bounds_.lower.z || at.x > bounds_.upper.x ||
          at.y > bounds_.upper.y || at.z > bounds_.upper.z)
        continue;
      values[i] = sample_(volume_.get(), at);
      covered[i] = 1.f;
    }
    const F v = simd::load<Arch>(values), in = simd::load<Arch>(covered);
    color = tf_.template color<Arch>(v) * in;
    opacity = tf_.template opacity<Arch>(v) * in;
  }

private:
  std::shared_ptr<const void> volume_;
  float (*sample_)(const void*, const Vec3f&) = nullptr;
  Box3f bounds_;
  TransferFunction tf_;
  Affine3f transform_;
};

}  // namespace sciray
