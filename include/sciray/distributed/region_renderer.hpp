#pragma once
// Rendering one region of a data-parallel world into a fragment image (fragments.hpp),
// as OSPRay's distributed renderers do on each rank: every camera ray is clipped to
// [t_enter, t_exit] of the region's box, so surfaces hit outside it are not seen and
// volumes are integrated over the interval only; the region adds no background (the
// compositor puts it behind all regions). Secondary rays (AO, shadows) are not clipped:
// they see whatever data the rank holds, as OSPRay's do.
//
// The frame itself is render_frame's, so samples fall where a normal frame puts them
// (the same per-pixel sequence, pixel filter and renderer seeds): a region holding the
// whole world renders the normal image.
#include <algorithm>
#include <cstdint>
#include <limits>
#include <span>
#include <string>
#include <type_traits>
#include <variant>
#include <vector>

#include "sciray/distributed/fragments.hpp"
#include "sciray/frame/framebuffer.hpp"
#include "sciray/frame/render_frame.hpp"
#include "sciray/math/box.hpp"
#include "sciray/render/common.hpp"

namespace sciray::distributed {

/// A renderer's parameters for rendering a region: no background colour, backplate or
/// lights seen by camera rays (visibleLights, visible hdri and ambient lights), which
/// would otherwise show in every region a ray passes; the compositor adds the background.
template <class Params>
Params region_params(Params params) {
  static_assert(std::is_base_of_v<RendererParams, Params>);
  params.background_color = {0.f, 0.f, 0.f};
  params.background_alpha = 0.f;
  params.backplate.reset();
  params.backplate_alpha.reset();
  if constexpr (requires { params.visible_lights; }) params.visible_lights = false;
  for (Light& light : params.lights) std::visit([](auto& l) { l.visible = false; }, light);
  for (MovingLight& moving : params.moving_lights) std::visit([](auto& l) { l.visible = false; }, moving.light);
  return params;
}

/// Where each lane's ray enters and leaves `box` within [tnear, tfar]: enter > exit
/// where it misses.
template <class Arch>
std::pair<simd::Float<Arch>, simd::Float<Arch>> box_interval(const Box3f& box, const Ray<simd::Float<Arch>>& ray) {
  using F = simd::Float<Arch>;
  const Vec3<F> inv{F(1.f) / ray.dir.x, F(1.f) / ray.dir.y, F(1.f) / ray.dir.z};
  const Vec3<F> t0 = (Vec3<F>(box.lower) - ray.org) * inv, t1 = (Vec3<F>(box.upper) - ray.org) * inv;
  const Vec3<F> near = min(t0, t1), far = max(t0, t1);
  return {simd::max(simd::max(simd::max(near.x, near.y), near.z), ray.tnear),
          simd::min(simd::min(simd::min(far.x, far.y), far.z), ray.tfar)};
}

/// A PacketRenderer that renders only what lies inside `region`: the camera rays are
/// clipped to the region's box before `inner` (built with region_params) traces them.
/// It records each pixel's sort key — the smallest t_enter of its samples' rays — in
/// `keys` (one float a pixel, +inf to start): a tile's pixels are rendered by one
/// thread, so the writes never race.
template <class Arch, class Inner>
class RegionRenderer {
public:
  using F = simd::Float<Arch>;
  using M = simd::Mask<Arch>;

  RegionRenderer(const Inner& inner, const Box3f& region, float* keys) : inner_(&inner), region_(region), keys_(keys) {}

  PixelSample<Arch> render(const Ray<F>& ray, const M& active, const SampleIndex<Arch>& index) const {
    const auto [enter, exit] = box_interval<Arch>(region_, ray);
    const M inside = active & (enter <= exit);
    record_keys(index, active, simd::select(inside, enter, F(std::numeric_limits<float>::infinity())));
    if (!simd::any(inside)) {
      PixelSample<Arch> nothing;
      nothing.t = F(std::numeric_limits<float>::infinity());
      return nothing;
    }
    Ray<F> clipped = ray;
    clipped.tnear = simd::select(inside, enter, ray.tnear);
    clipped.tfar = simd::select(inside, exit, ray.tfar);
    return inner_->render(clipped, inside, index);
  }

  // What render_frame asks of a renderer, passed on.
  bool samples_lens_and_shutter() const {
    if constexpr (requires { inner_->samples_lens_and_shutter(); }) return inner_->samples_lens_and_shutter();
    return true;
  }
  bool jitters_film_per_pixel() const {
    if constexpr (requires { inner_->jitters_film_per_pixel(); }) return inner_->jitters_film_per_pixel();
    return false;
  }
  bool ids_from_nearest_sample() const {
    if constexpr (requires { inner_->ids_from_nearest_sample(); }) return inner_->ids_from_nearest_sample();
    return false;
  }

private:
  void record_keys(const SampleIndex<Arch>& index, const M& active, const F& enter) const {
    for (int i = 0; i < simd::width<Arch>; ++i) {
      const std::int32_t pixel = simd::lane(index.pixel, i);
      if (pixel < 0 || !simd::lane(active, i)) continue;
      float& key = keys_[pixel];
      key = std::min(key, simd::lane(enter, i));
    }
  }

  const Inner* inner_;
  Box3f region_;
  float* keys_;
};

/// Renders what `renderer` (built with region_params) sees inside `region` into a
/// fragment image of width x height: premultiplied RGBA averaged over the frame's
/// samples, each pixel's sort key, and the depth channel's first-hit distance.
/// `tile_frames` holds each tile's frame index in an accumulation (render_tiles; empty:
/// the first frame), so that fragments of later frames sample where the normal frame does.
template <class Arch, class Renderer, class CameraT>
FragmentImage render_region(const Renderer& renderer, const CameraT& camera, const Box3f& region, int width,
                            int height, const FrameSettings& settings = {},
                            std::span<const std::uint32_t> tile_frames = {}) {
  FragmentImage out(width, height);
  FrameBuffer fb(width, height, ColorFormat::rgba32f, channel_color | channel_depth);
  if (!tile_frames.empty() && tile_frames.size() != static_cast<std::size_t>(fb.tile_count()))
    throw Error("render_region: " + std::to_string(tile_frames.size()) + " tile frame counts for " +
                std::to_string(fb.tile_count()) + " tiles");
  std::vector<TileWork> every_tile(static_cast<std::size_t>(fb.tile_count()));
  for (int tile = 0; tile < fb.tile_count(); ++tile)
    every_tile[static_cast<std::size_t>(tile)] = {tile, tile_frames.empty() ? 0u : tile_frames[static_cast<std::size_t>(tile)]};
  const RegionRenderer<Arch, Renderer> clipped(renderer, region, out.key.data());
  render_tiles<Arch>(clipped, camera, fb, every_tile, nullptr, settings);
  out.rgba = fb.color32f();
  out.depth = fb.depth();
  return out;
}

}  // namespace sciray::distributed
