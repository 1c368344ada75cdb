#pragma once
// The packet path of volume types that find their cell, block or particles one point at a
// time (unstructured, particle, amr, vdb): the scalar function applied lane by lane.
#include <type_traits>

#include "sciray/math/vec.hpp"
#include "sciray/simd/packet.hpp"

namespace sciray {

/// f(point) for every lane of `p`; f returns a float.
template <class Arch, class F>
simd::Float<Arch> scalar_per_lane(const Vec3<simd::Float<Arch>>& p, F&& f) {
  if constexpr (std::is_same_v<Arch, simd::scalar>) {
    return f(p);
  } else {
    constexpr int W = simd::width<Arch>;
    alignas(64) float out[W];
    for (int i = 0; i < W; ++i) out[i] = f(Vec3f{simd::lane(p.x, i), simd::lane(p.y, i), simd::lane(p.z, i)});
    return simd::load<Arch>(out);
  }
}

/// f(point) for every lane of `p`; f returns a Vec3f.
template <class Arch, class F>
Vec3<simd::Float<Arch>> vector_per_lane(const Vec3<simd::Float<Arch>>& p, F&& f) {
  if constexpr (std::is_same_v<Arch, simd::scalar>) {
    return f(p);
  } else {
    constexpr int W = simd::width<Arch>;
    alignas(64) float x[W], y[W], z[W];
    for (int i = 0; i < W; ++i) {
      const Vec3f v = f(Vec3f{simd::lane(p.x, i), simd::lane(p.y, i), simd::lane(p.z, i)});
      x[i] = v.x, y[i] = v.y, z[i] = v.z;
    }
    return {simd::load<Arch>(x), simd::load<Arch>(y), simd::load<Arch>(z)};
  }
}

}  // namespace sciray
