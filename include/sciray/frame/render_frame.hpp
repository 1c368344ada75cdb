#pragma once
// One frame: the image is cut into tiles that oneTBB renders in parallel; inside a
// tile the camera generates one packet per stamp of W pixels (4x1, 4x2, 4x4 for
// W = 4, 8, 16), the renderer traces and shades it, and the frame buffer accumulates
// it. Every pixel's sample position depends only on the pixel and the frame index, so
// the image is the same for any number of threads.
#include <algorithm>
#include <atomic>
#include <concepts>
#include <cstdint>
#include <variant>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "sciray/frame/framebuffer.hpp"
#include "sciray/math/sequence.hpp"
#include "sciray/render/camera.hpp"
#include "sciray/render/sample.hpp"

namespace sciray {

inline constexpr int tile_size = 16;

/// Lets another thread follow and stop a frame: `tiles_done` counts finished tiles of
/// `tile_count`; setting `cancel` makes the remaining tiles return at once. A cancelled
/// frame leaves the accumulation reset, as some pixels lack its sample.
struct FrameControl {
  std::atomic<bool> cancel{false};
  std::atomic<std::uint32_t> tiles_done{0};
  std::atomic<std::uint32_t> tile_count{0};

  float progress() const {
    const std::uint32_t total = tile_count.load();
    return total == 0 ? 0.f : static_cast<float>(tiles_done.load()) / static_cast<float>(total);
  }
};

/// Pixels of a stamp: 4 wide, W/4 high (one pixel for the scalar path).
template <class Arch>
struct Stamp {
  static constexpr int width = simd::width<Arch> >= 4 ? 4 : 1;
  static constexpr int height = simd::width<Arch> / width;
};

/// What render_frame needs of a renderer: a packet of camera rays (with the lanes that
/// are inside the image) in, colour, alpha and hit distance out.
template <class R, class Arch>
concept PacketRenderer = requires(const R& renderer, const Ray<simd::Float<Arch>>& ray, const simd::Mask<Arch>& active,
                                  const SampleIndex<Arch>& index) {
  { renderer.render(ray, active, index) } -> std::same_as<PixelSample<Arch>>;
};

/// Renders one frame of `renderer` into `fb`, accumulating if the frame buffer does.
/// Run it inside a tbb::task_arena to bound the threads.
template <class Arch, class Renderer, class PreparedCamera>
  requires PacketRenderer<Renderer, Arch>
void render_frame(const Renderer& renderer, const PreparedCamera& camera, FrameBuffer& fb,
                  FrameControl* control = nullptr) {
  using F = simd::Float<Arch>;
  using M = simd::Mask<Arch>;
  using S = Stamp<Arch>;
  static_assert(tile_size % S::width == 0 && tile_size % S::height == 0);

  const int width = fb.width(), height = fb.height();
  const int tiles_x = (width + tile_size - 1) / tile_size;
  const int tiles_y = (height + tile_size - 1) / tile_size;
  if (control) control->tiles_done = 0, control->tile_count = static_cast<std::uint32_t>(tiles_x * tiles_y);
  const PixelOffset offset = pixel_offset(fb.accumulated_frames());
  const float inv_width = 1.f / static_cast<float>(width), inv_height = 1.f / static_cast<float>(height);

  // Lane i of a stamp covers pixel (i % stamp width, i / stamp width).
  const F lane = simd::lane_index<Arch>();
  F lane_dy;
  if constexpr (S::width == 1)
    lane_dy = F(0.f);
  else
    lane_dy = xsimd::floor(lane * F(1.f / S::width));
  const F lane_dx = lane - lane_dy * F(static_cast<float>(S::width));

  tbb::parallel_for(tbb::blocked_range<int>(0, tiles_x * tiles_y), [&](const tbb::blocked_range<int>& range) {
    alignas(64) std::int32_t pixel[simd::width<Arch>];
    for (int tile = range.begin(); tile != range.end(); ++tile) {
      if (control && control->cancel.load(std::memory_order_relaxed)) return;
      const int tile_x0 = (tile % tiles_x) * tile_size, tile_y0 = (tile / tiles_x) * tile_size;
      for (int y0 = tile_y0; y0 < std::min(tile_y0 + tile_size, height); y0 += S::height) {
        for (int x0 = tile_x0; x0 < std::min(tile_x0 + tile_size, width); x0 += S::width) {
          const F px = F(static_cast<float>(x0)) + lane_dx;
          const F py = F(static_cast<float>(y0)) + lane_dy;
          const M active = (px < F(static_cast<float>(width))) & (py < F(static_cast<float>(height)));
          for (int i = 0; i < simd::width<Arch>; ++i) {
            const int x = x0 + i % S::width, y = y0 + i / S::width;
            pixel[i] = x < width && y < height ? y * width + x : -1;
          }
          const auto ray = camera.generate((px + F(offset.x)) * F(inv_width), (py + F(offset.y)) * F(inv_height));
          const PixelSample<Arch> sample =
              renderer.render(ray, active, SampleIndex<Arch>{simd::load<Arch>(pixel), fb.accumulated_frames()});
          fb.write_packet<Arch>(pixel, sample.color, sample.alpha, sample.t, camera.projected_depth(ray, sample.t));
        }
      }
      if (control) control->tiles_done.fetch_add(1, std::memory_order_relaxed);
    }
  });
  if (control && control->cancel.load())
    fb.reset_accumulation();
  else
    fb.finish_frame();
}

/// render_frame for a Camera variant: the camera type is resolved once per frame.
template <class Arch, class Renderer>
void render_frame(const Renderer& renderer, const Camera& camera, FrameBuffer& fb, FrameControl* control = nullptr) {
  std::visit([&](const auto& c) { render_frame<Arch>(renderer, prepare(c), fb, control); }, camera);
}

}  // namespace sciray
