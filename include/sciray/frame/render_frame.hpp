#pragma once
// One frame: the image is cut into tiles that oneTBB renders in parallel; inside a
// tile the camera generates one packet per stamp of W pixels (4x1, 4x2, 4x4 for
// W = 4, 8, 16) and sample, the renderer traces and shades it (a stream renderer takes
// the packets of all stamps at once), and the frame buffer accumulates the frame's average. Every sample's position on the film and the lens
// depends only on its pixel and sample index, so the image is the same for any number
// of threads.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <concepts>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <variant>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "sciray/frame/framebuffer.hpp"
#include "sciray/frame/pixel_filter.hpp"
#include "sciray/math/sequence.hpp"
#include "sciray/render/camera.hpp"
#include "sciray/render/sample.hpp"

namespace sciray {

/// How a frame samples its pixels (OSPRay's renderer parameters of the same names).
struct FrameSettings {
  int pixel_samples = 1;  ///< pixelSamples: samples per pixel per frame, averaged in the frame
  PixelFilter pixel_filter = PixelFilter::gauss;  ///< pixelFilter
  /// varianceThreshold: with a variance channel, tiles whose estimated error is at most
  /// this are not rendered again (0: every tile, every frame).
  float variance_threshold = 0.f;
};

inline void validate(const FrameSettings& s) {
  if (s.pixel_samples < 1)
    throw Error("frame settings: 'pixelSamples' must be at least 1, got " + std::to_string(s.pixel_samples));
  pixel_filter_from_int(static_cast<int>(s.pixel_filter));  // throws for a value outside the enum
  if (!(s.variance_threshold >= 0.f) || !std::isfinite(s.variance_threshold))
    throw Error("frame settings: 'varianceThreshold' must be finite and not negative, got " +
                std::to_string(s.variance_threshold));
}

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

/// A renderer that takes all camera packets of a tile's sample at once (the path tracer,
/// which regroups their paths after every bounce); results come one per packet.
template <class R, class Arch>
concept StreamRenderer = requires(const R& renderer, std::span<const CameraPacket<Arch>> packets,
                                  std::span<PixelSample<Arch>> results) {
  renderer.render_stream(packets, results);
};

/// What render_frame needs of a camera: prepare()'s result, generating packets of rays
/// from screen points, lens samples and shutter time samples. (Camera descriptions go
/// through the Camera overload, which prepares them.)
template <class C, class Arch>
concept PreparedCamera = requires(const C& camera, const simd::Float<Arch>& s, const Ray<simd::Float<Arch>>& ray) {
  { camera.generate(s, s, s, s, s) } -> std::same_as<Ray<simd::Float<Arch>>>;
  { camera.projected_depth(ray, s) } -> std::same_as<simd::Float<Arch>>;
};

/// One tile of a share of a frame: its index and the frames it had before this one,
/// which place its samples in each pixel's sequence (FrameBuffer::tile_frames).
struct TileWork {
  std::int32_t tile;
  std::uint32_t frames_before;
};

namespace detail {
template <class Arch, class Renderer, class CameraT>
std::uint32_t render_tiles(const Renderer& renderer, const CameraT& camera, FrameBuffer& fb, FrameControl* control,
                           const FrameSettings& settings, const std::span<const TileWork>* share);
}  // namespace detail

/// Renders one frame of `renderer` into `fb`, accumulating if the frame buffer does:
/// `settings.pixel_samples` samples per pixel (sample index frame * pixel_samples + s,
/// the frame counted per tile), each at the offset the pixel filter gives OSPRay's
/// sample point of that index, and at the lens position of the pixel's camera sequence. Colour, alpha, normal and
/// albedo are averaged over the frame's samples; depth comes from the nearest hit among
/// them, ids (as OSPRay's) from the frame's last sample, or from its nearest hit for a
/// renderer whose ids_from_nearest_sample() says so (the path tracer). Tiles the frame buffer reports converged below
/// `settings.variance_threshold` are skipped. Returns the number of tiles rendered.
/// Run it inside a tbb::task_arena to bound the threads.
template <class Arch, class Renderer, class CameraT>
  requires PacketRenderer<Renderer, Arch> && PreparedCamera<CameraT, Arch>
std::uint32_t render_frame(const Renderer& renderer, const CameraT& camera, FrameBuffer& fb,
                           FrameControl* control = nullptr, const FrameSettings& settings = {}) {
  return detail::render_tiles<Arch>(renderer, camera, fb, control, settings, nullptr);
}

/// Renders a share of a frame: the tiles of `share`, each at its own frame index, into
/// `fb`, which stages the frame's samples (it must not accumulate: whoever owns the
/// frame accumulates them, see FrameBuffer::accumulate_tile). The samples are those
/// render_frame would take for the tiles of a frame buffer with those frame counts, so
/// a frame split among renderers in any way is the same frame. Returns the tiles rendered.
template <class Arch, class Renderer, class CameraT>
  requires PacketRenderer<Renderer, Arch> && PreparedCamera<CameraT, Arch>
std::uint32_t render_tiles(const Renderer& renderer, const CameraT& camera, FrameBuffer& fb,
                           std::span<const TileWork> share, FrameControl* control = nullptr,
                           const FrameSettings& settings = {}) {
  if (fb.has(channel_accum))
    throw Error("render_tiles: the frame buffer stages a share of a frame and must not accumulate");
  for (const TileWork& work : share)
    if (work.tile < 0 || work.tile >= fb.tile_count())
      throw Error("render_tiles: tile " + std::to_string(work.tile) + " is outside the frame buffer's " +
                  std::to_string(fb.tile_count()) + " tiles");
  return detail::render_tiles<Arch>(renderer, camera, fb, control, settings, &share);
}

namespace detail {
/// render_frame over every tile of `fb` (`share` null), or render_tiles over `share`.
template <class Arch, class Renderer, class CameraT>
std::uint32_t render_tiles(const Renderer& renderer, const CameraT& camera, FrameBuffer& fb, FrameControl* control,
                           const FrameSettings& settings, const std::span<const TileWork>* share) {
  using F = simd::Float<Arch>;
  using M = simd::Mask<Arch>;
  using S = Stamp<Arch>;
  constexpr int W = simd::width<Arch>;
  static_assert(tile_size % S::width == 0 && tile_size % S::height == 0);
  validate(settings);

  const int width = fb.width(), height = fb.height();
  const int tile_count = share ? static_cast<int>(share->size()) : fb.tile_count();
  if (control) control->tiles_done = 0, control->tile_count = static_cast<std::uint32_t>(tile_count);
  const float inv_width = 1.f / static_cast<float>(width), inv_height = 1.f / static_cast<float>(height);
  const auto samples = static_cast<std::uint32_t>(settings.pixel_samples);
  const F inv_samples(1.f / static_cast<float>(samples));
  const FilterSampler& filter = FilterSampler::of(settings.pixel_filter);
  std::atomic<std::uint32_t> tiles_rendered{0};

  // Lane i of a stamp covers pixel (i % stamp width, i / stamp width).
  const F lane = simd::lane_index<Arch>();
  F lane_dy;
  if constexpr (S::width == 1)
    lane_dy = F(0.f);
  else
    lane_dy = xsimd::floor(lane * F(1.f / S::width));
  const F lane_dx = lane - lane_dy * F(static_cast<float>(S::width));
  // Lane i's pixel relative to the stamp's first, for stamps wholly inside the image.
  alignas(64) std::int32_t lane_offset[W];
  for (int i = 0; i < W; ++i) lane_offset[i] = (i / S::width) * width + i % S::width;
  const simd::Int<Arch> lane_offsets = simd::load<Arch>(lane_offset);
  // The pixel offsets are the same in every pixel (OSPRay's sample points): only the lens
  // (if the camera has one) needs the per-pixel sequence.
  bool uses_lens = true;
  if constexpr (requires { camera.uses_lens(); }) uses_lens = camera.uses_lens();
  bool uses_time = false;
  if constexpr (requires { camera.uses_time_sample(); }) uses_time = camera.uses_time_sample();
  // Renderers that see one instant through the lens centre (scivis and ao, as OSPRay's).
  if constexpr (requires { renderer.samples_lens_and_shutter(); })
    if (!renderer.samples_lens_and_shutter()) uses_lens = uses_time = false;
  // The path tracer, as OSPRay's, places each pixel's samples on a sequence of its own.
  bool film_per_pixel = false;
  if constexpr (requires { renderer.jitters_film_per_pixel(); }) film_per_pixel = renderer.jitters_film_per_pixel();
  // Which of a pixel's samples its ids come from: OSPRay's path tracer keeps the nearest
  // hit's, its other renderers the last sample's, hit or not.
  bool ids_from_nearest = false;
  if constexpr (requires { renderer.ids_from_nearest_sample(); }) ids_from_nearest = renderer.ids_from_nearest_sample();

  const bool first_hit_channels = fb.has(channel_depth) || fb.has(channel_id_primitive) ||
                                  fb.has(channel_id_object) || fb.has(channel_id_instance);
  // A tile's stamps: the pixels of each and its frame, summed over the samples.
  struct StampFrame {
    alignas(64) std::int32_t pixel[W];
    M active;
    simd::Int<Arch> pixels;
    F pixel_x, pixel_y;
    std::optional<CameraSequence<Arch>> sequence;
    PixelSample<Arch> frame;
    F projected;
  };
  constexpr int max_stamps = (tile_size / S::width) * (tile_size / S::height);
  tbb::parallel_for(tbb::blocked_range<int>(0, tile_count), [&](const tbb::blocked_range<int>& range) {
    alignas(64) float inside[W];
    std::vector<StampFrame> stamps(max_stamps);
    std::vector<CameraPacket<Arch>> packets(max_stamps);
    std::vector<PixelSample<Arch>> results(max_stamps);
    for (int work = range.begin(); work != range.end(); ++work) {
      if (control && control->cancel.load(std::memory_order_relaxed)) return;
      const int tile = share ? (*share)[static_cast<std::size_t>(work)].tile : work;
      if (share || !fb.tile_converged(tile, settings.variance_threshold)) {
        const std::uint32_t tile_frames =
            share ? (*share)[static_cast<std::size_t>(work)].frames_before : fb.tile_frames(tile);
        const std::uint32_t first_sample = tile_frames * samples;
        const int tile_x0 = (tile % fb.tiles_x()) * tile_size, tile_y0 = (tile / fb.tiles_x()) * tile_size;
        std::size_t stamp_count = 0;
        for (int y0 = tile_y0; y0 < std::min(tile_y0 + tile_size, height); y0 += S::height) {
          for (int x0 = tile_x0; x0 < std::min(tile_x0 + tile_size, width); x0 += S::width) {
            StampFrame& stamp = stamps[stamp_count++];
            if (x0 + S::width <= width && y0 + S::height <= height) {
              stamp.pixels = simd::Int<Arch>(y0 * width + x0) + lane_offsets;
              simd::store<Arch>(stamp.pixel, stamp.pixels);
              stamp.active = M(true);
            } else {
              for (int i = 0; i < W; ++i) {
                const int x = x0 + i % S::width, y = y0 + i / S::width;
                stamp.pixel[i] = x < width && y < height ? y * width + x : -1;
                inside[i] = stamp.pixel[i] >= 0 ? 1.f : 0.f;
              }
              stamp.active = simd::load<Arch>(inside) > F(0.f);
              stamp.pixels = simd::load<Arch>(stamp.pixel);
            }
            stamp.pixel_x = F(static_cast<float>(x0) + 0.5f) + lane_dx;
            stamp.pixel_y = F(static_cast<float>(y0) + 0.5f) + lane_dy;
            stamp.sequence.reset();
            if (uses_lens) stamp.sequence.emplace(stamp.pixels);
          }
        }
        // Sample s of every stamp of the tile, rendered together (a stream renderer
        // regroups their paths), then summed into the stamps' frames.
        for (std::uint32_t s = 0; s < samples; ++s) {
          const std::uint32_t sample_index = first_sample + s;
          for (std::size_t k = 0; k < stamp_count; ++k) {
            const StampFrame& stamp = stamps[k];
            CameraSamples<F> cs{F(0.5f), F(0.5f)};
            if (uses_lens) cs = (*stamp.sequence)(sample_index);
            F offset_x, offset_y;
            if (film_per_pixel) {
              alignas(64) float ox[W], oy[W];
              for (int i = 0; i < W; ++i) {
                const auto [u, v] = path_film_point(static_cast<std::uint32_t>(stamp.pixel[i]), sample_index);
                const FilterOffset o = filter.sample(u, v);
                ox[i] = o.x, oy[i] = o.y;
              }
              offset_x = simd::load<Arch>(ox), offset_y = simd::load<Arch>(oy);
            } else {
              const auto [u, v] = pixel_sample_point(sample_index);
              const FilterOffset offset = filter.sample(u, v);
              offset_x = F(offset.x), offset_y = F(offset.y);
            }
            const F screen_x = (stamp.pixel_x + offset_x) * F(inv_width);
            const F screen_y = (stamp.pixel_y + offset_y) * F(inv_height);
            const F time_u = uses_time ? time_sample<Arch>(stamp.pixels, sample_index) : F(0.5f);
            packets[k] = {camera.generate(screen_x, screen_y, cs.lens_u, cs.lens_v, time_u), stamp.active,
                          SampleIndex<Arch>{stamp.pixels, sample_index, screen_x, screen_y,
                                            stamp.pixel_x * F(inv_width), stamp.pixel_y * F(inv_height),
                                            first_hit_channels}};
          }
          if constexpr (StreamRenderer<Renderer, Arch>) {
            renderer.render_stream(std::span<const CameraPacket<Arch>>(packets.data(), stamp_count),
                                   std::span<PixelSample<Arch>>(results.data(), stamp_count));
          } else {
            for (std::size_t k = 0; k < stamp_count; ++k)
              results[k] = renderer.render(packets[k].ray, packets[k].active, packets[k].index);
          }
          for (std::size_t k = 0; k < stamp_count; ++k) {
            StampFrame& stamp = stamps[k];
            const PixelSample<Arch>& one = results[k];
            const F projected = camera.projected_depth(packets[k].ray, one.t);
            if (s == 0) {
              stamp.frame = one;
              stamp.projected = projected;
              continue;
            }
            PixelSample<Arch>& frame = stamp.frame;
            frame.color += one.color;
            frame.alpha = frame.alpha + one.alpha;
            frame.normal += one.normal;
            frame.albedo += one.albedo;
            const M nearer = one.t < frame.t;
            frame.t = simd::select(nearer, one.t, frame.t);
            stamp.projected = simd::select(nearer, projected, stamp.projected);
            const M takes_ids = ids_from_nearest ? nearer : M(true);
            frame.prim_id = simd::select(takes_ids, one.prim_id, frame.prim_id);
            frame.geom_id = simd::select(takes_ids, one.geom_id, frame.geom_id);
            frame.inst_id = simd::select(takes_ids, one.inst_id, frame.inst_id);
          }
        }
        for (std::size_t k = 0; k < stamp_count; ++k) {
          PixelSample<Arch>& frame = stamps[k].frame;
          if (samples > 1) {
            frame.color = frame.color * inv_samples;
            frame.alpha = frame.alpha * inv_samples;
            frame.normal = frame.normal * inv_samples;
            frame.albedo = frame.albedo * inv_samples;
          }
          // A share's frame buffer stages this frame alone: each value is the frame's.
          fb.write_packet<Arch>(stamps[k].pixel, frame, stamps[k].projected, share ? 0u : tile_frames);
        }
        fb.finish_tile(tile);
        tiles_rendered.fetch_add(1, std::memory_order_relaxed);
      }
      if (control) control->tiles_done.fetch_add(1, std::memory_order_relaxed);
    }
  });
  if (share) return tiles_rendered.load();  // the frame's owner finishes it
  if (control && control->cancel.load())
    fb.reset_accumulation();
  else if (tiles_rendered.load() > 0)  // a frame that found every tile converged adds nothing
    fb.finish_frame(settings.variance_threshold);
  return tiles_rendered.load();
}
}  // namespace detail

/// render_frame for a Camera variant: the camera type is resolved once per frame.
template <class Arch, class Renderer>
std::uint32_t render_frame(const Renderer& renderer, const Camera& camera, FrameBuffer& fb,
                           FrameControl* control = nullptr, const FrameSettings& settings = {}) {
  return std::visit([&](const auto& c) { return render_frame<Arch>(renderer, prepare(c), fb, control, settings); },
                    camera);
}

/// render_tiles for a Camera variant.
template <class Arch, class Renderer>
std::uint32_t render_tiles(const Renderer& renderer, const Camera& camera, FrameBuffer& fb,
                           std::span<const TileWork> share, FrameControl* control = nullptr,
                           const FrameSettings& settings = {}) {
  return std::visit(
      [&](const auto& c) { return render_tiles<Arch>(renderer, prepare(c), fb, share, control, settings); }, camera);
}

/// What render_until achieved: frames rendered by the call and the frame buffer's
/// estimated error (FrameBuffer::variance) after them.
struct RenderUntilResult {
  std::uint32_t frames;
  float estimated_error;
};

/// Renders frames into `fb` until its estimated error is at most `target_error`, or
/// `max_frames` frames were rendered, or every tile is converged below
/// `settings.variance_threshold` (nothing is left to render), or `control` cancels (the
/// cancelled frame is not counted).
/// The frame buffer needs a variance channel. Set `settings.variance_threshold` (to
/// `target_error`, say) to spend the frames on the tiles that still need them.
template <class Arch, class Renderer, class CameraT>
RenderUntilResult render_until(const Renderer& renderer, const CameraT& camera, FrameBuffer& fb, float target_error,
                               std::uint32_t max_frames, const FrameSettings& settings = {},
                               FrameControl* control = nullptr) {
  if (!fb.has(channel_variance))
    throw Error("render_until: the frame buffer has no variance channel (it needs accum and variance) to estimate "
                "its error");
  if (!(target_error >= 0.f)) throw Error("render_until: the target error must not be negative or NaN");
  RenderUntilResult result{0, fb.variance()};
  while (result.frames < max_frames && !(result.estimated_error <= target_error)) {
    const std::uint32_t tiles = render_frame<Arch>(renderer, camera, fb, control, settings);
    if (tiles == 0 || (control && control->cancel.load())) break;
    ++result.frames;
    result.estimated_error = fb.variance();
  }
  return result;
}

}  // namespace sciray
