#pragma once
// The frame buffer: a colour channel in the format the application asks for (RGBA8,
// SRGBA or RGBA32F), depth as Euclidean distance and as projected view depth, world-space
// normal and albedo, the ids of what each pixel shows, and an accumulation channel that
// averages successive frames. Rows are stored bottom-up, as OSPRay maps them (row 0 is
// the bottom of the image).
//
// Accumulation counts frames per tile of tile_size^2 pixels, so that adaptive rendering
// can stop sampling tiles whose estimated error is small enough while the others go on;
// every average is taken over its own tile's frames.
#include <algorithm>
#include <bit>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include <sys/sysinfo.h>

#include "sciray/error.hpp"
#include "sciray/frame/error_regions.hpp"
#include "sciray/frame/image_ops.hpp"
#include "sciray/math/color.hpp"
#include "sciray/math/vec.hpp"
#include "sciray/render/sample.hpp"
#include "sciray/simd/packet.hpp"

namespace sciray {

/// `srgba` encodes colour with the sRGB curve; `gamma22` as OSPRay's OSP_FB_SRGBA does,
/// linear^(1/2.2), which lifts dark tones (linear 0.001 is 11/255 against sRGB's 3/255).
enum class ColorFormat { none, rgba8, srgba, rgba32f, gamma22 };

/// Channel flags beyond colour, with OSPRay's OSPFrameBufferChannel bits.
enum Channel : unsigned {
  channel_color = 1u << 0,
  channel_depth = 1u << 1,  ///< Euclidean distance from the camera and projected depth
  channel_accum = 1u << 2,  ///< average successive frames
  channel_variance = 1u << 3,  ///< estimate the error of the average (needs accum)
  channel_normal = 1u << 4,  ///< world-space shading normal of the first hit (averaged like colour)
  channel_albedo = 1u << 5,  ///< albedo of the first hit (averaged like colour)
  channel_id_primitive = 1u << 6,  ///< primitive id of the first hit, first frame
  channel_id_object = 1u << 7,     ///< geometry id of the first hit, first frame
  channel_id_instance = 1u << 8,   ///< instance id of the first hit, first frame
};

/// How the variance channel estimates the error left in the accumulated colour.
enum class ErrorEstimate {
  /// sciray's: the expected absolute luminance error of a tile's average (see variance()).
  luminance,
  /// OSPRay 3.1's, which its `varianceThreshold` and ospGetVariance are in, over
  /// OSPRay's 64-pixel tiles (ospray_tile_size): after every second frame of such a tile,
  /// 64 times the mean over its pixels of the RGBA difference between the mean of all
  /// frames and the mean of the odd ones (frame 1, 3, ...), divided by
  /// sqrt(r + g + b + 1 - alpha) of the mean; tiles refined in regions (ErrorRegions),
  /// the frame's error what ErrorRegions::refine reports. Measured with OSPRay 3.1's
  /// runtime: a diagonal edge in a 64-pixel image after two frames gives 0.70711, as this
  /// formula over one 64-pixel tile does (over 16-pixel tiles it would be 2.26).
  ospray,
};

/// Pixels of one tile side: the unit of parallel rendering and of adaptive accumulation.
inline constexpr int tile_size = 16;
/// Pixels of one side of OSPRay's tiles, over which ErrorEstimate::ospray is taken.
inline constexpr int ospray_tile_size = 64;
inline constexpr int tiles_per_ospray_tile = ospray_tile_size / tile_size;

/// What an id channel holds where nothing was hit.
inline constexpr std::uint32_t no_id = 0xFFFFFFFFu;

namespace detail {
/// sRGB (or OSPRay's gamma 2.2) encoding through a table indexed by the linear value
/// quantized to 16 bits: a std::pow per channel would cost as much as tracing the ray.
/// The machine's memory and swap in bytes (the most any allocation could get).
inline std::size_t memory_and_swap_bytes() {
  struct sysinfo info {};
  if (sysinfo(&info) != 0) return std::numeric_limits<std::size_t>::max();
  return (static_cast<std::size_t>(info.totalram) + static_cast<std::size_t>(info.totalswap)) * info.mem_unit;
}

inline std::string gigabytes(std::size_t bytes) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f", static_cast<double>(bytes) / 1e9);
  return text;
}

inline const std::array<std::uint8_t, 65536>& encoding_table(ColorFormat format) {
  const auto make = [](auto encode) {
    std::array<std::uint8_t, 65536> t{};
    for (std::size_t i = 0; i < t.size(); ++i) t[i] = to_unorm8(encode(static_cast<float>(i) / 65535.f));
    return t;
  };
  static const auto srgb = make([](float v) { return linear_to_srgb(v); });
  static const auto gamma = make([](float v) { return std::pow(v, 1.f / 2.2f); });
  return format == ColorFormat::gamma22 ? gamma : srgb;
}
}  // namespace detail

class FrameBuffer {
public:
  FrameBuffer(int width, int height, ColorFormat format = ColorFormat::srgba,
              unsigned channels = channel_color | channel_depth | channel_accum,
              ErrorEstimate estimate = ErrorEstimate::luminance)
      : width_(width), height_(height), format_(format), channels_(channels) {
    // Pixels are addressed with 32-bit lane indices.
    if (width <= 0 || height <= 0 ||
        static_cast<std::size_t>(width) * static_cast<std::size_t>(height) > std::size_t{INT32_MAX})
      throw Error("framebuffer: size " + std::to_string(width) + "x" + std::to_string(height) +
                  " must be positive with fewer than 2^31 pixels");
    if (format == ColorFormat::none) channels_ &= ~unsigned(channel_color);
    if (!(channels_ & channel_accum)) channels_ &= ~unsigned(channel_variance);
    const std::size_t n = pixel_count();
    // Refused by name rather than left to the allocator, which may promise the memory and
    // let the kernel kill the process once the channels are filled.
    if (const std::size_t needed = n * bytes_per_pixel(format, channels_, estimate);
        needed > detail::memory_and_swap_bytes())
      throw Error("framebuffer: " + std::to_string(width) + "x" + std::to_string(height) + " with these channels needs " +
                  detail::gigabytes(needed) + " GB, more than this machine's " +
                  detail::gigabytes(detail::memory_and_swap_bytes()) + " GB of memory and swap");
    tiles_x_ = (width + tile_size - 1) / tile_size;
    int log2_width = 0;  // ceil(log2(width))
    while ((std::uint64_t{1} << log2_width) < static_cast<std::uint64_t>(width)) ++log2_width;
    row_shift_ = 31 + log2_width;
    const auto w = static_cast<std::uint64_t>(width);
    row_magic_ = ((std::uint64_t{1} << row_shift_) + w - 1) / w;
    const int tiles_y = (height + tile_size - 1) / tile_size;
    const auto tiles = static_cast<std::size_t>(tiles_x_) * static_cast<std::size_t>(tiles_y);
    tile_frames_.assign(tiles, 0);
    tile_error_.assign(tiles, std::numeric_limits<float>::infinity());
    if (channels_ & channel_accum) accum_.assign(4 * n, 0.f);
    if (channels_ & channel_variance) {
      if (estimate == ErrorEstimate::ospray) {
        odd_rgba_.assign(4 * n, 0.f);
        blocks_x_ = (width + ospray_tile_size - 1) / ospray_tile_size;
        const int blocks_y = (height + ospray_tile_size - 1) / ospray_tile_size;
        const auto blocks = static_cast<std::size_t>(blocks_x_) * static_cast<std::size_t>(blocks_y);
        block_error_.assign(blocks, std::numeric_limits<float>::infinity());
        block_frames_.assign(blocks, 0);
        regions_.reset(blocks_x_, blocks_y);
      } else {
        odd_luminance_.assign(n, 0.f);
      }
    }
    if (format == ColorFormat::rgba8 || format == ColorFormat::srgba || format == ColorFormat::gamma22)
      color8_.assign(4 * n, 0);
    if (format == ColorFormat::rgba32f) color32_.assign(4 * n, 0.f);
    if (channels_ & channel_depth) {
      depth_.assign(n, std::numeric_limits<float>::infinity());
      depth_projected_.assign(n, std::numeric_limits<float>::infinity());
    }
    if (channels_ & channel_normal) normal_.assign(3 * n, 0.f);
    if (channels_ & channel_albedo) albedo_.assign(3 * n, 0.f);
    if (channels_ & channel_id_primitive) primitive_id_.assign(n, no_id);
    if (channels_ & channel_id_object) object_id_.assign(n, no_id);
    if (channels_ & channel_id_instance) instance_id_.assign(n, no_id);
    if (format == ColorFormat::srgba || format == ColorFormat::gamma22) detail::encoding_table(format);
  }

  /// Bytes a pixel takes in the channels and format given.
  static std::size_t bytes_per_pixel(ColorFormat format, unsigned channels, ErrorEstimate estimate) {
    std::size_t bytes = format == ColorFormat::rgba32f ? 16 : format == ColorFormat::none ? 0 : 4;
    if (channels & channel_accum) bytes += 4 * sizeof(double);
    if (channels & channel_variance) bytes += (estimate == ErrorEstimate::ospray ? 4 : 1) * sizeof(double);
    if (channels & channel_depth) bytes += 2 * sizeof(float);
    if (channels & channel_normal) bytes += 3 * sizeof(float);
    if (channels & channel_albedo) bytes += 3 * sizeof(float);
    for (Channel id : {channel_id_primitive, channel_id_object, channel_id_instance})
      if (channels & id) bytes += sizeof(std::uint32_t);
    return bytes;
  }

  int width() const { return width_; }
  int height() const { return height_; }
  std::size_t pixel_count() const { return static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_); }
  ColorFormat format() const { return format_; }
  bool has(Channel c) const { return (channels_ & c) != 0; }

  // ---- tiles ------------------------------------------------------------------------
  int tiles_x() const { return tiles_x_; }
  int tile_count() const { return static_cast<int>(tile_frames_.size()); }
  int tile_of(std::int32_t pixel) const {
    // Division by the width as a multiply and shift (Granlund and Montgomery 1994, exact
    // for numerators below 2^31): two integer divisions per lane would cost a third of a
    // trivial frame.
    const auto row = static_cast<std::int32_t>((static_cast<std::uint64_t>(pixel) * row_magic_) >> row_shift_);
    const std::int32_t column = pixel - row * width_;
    return (row / tile_size) * tiles_x_ + column / tile_size;
  }
  /// Frames averaged into the tile so far (the index of its next frame); stays 0
  /// without accumulation.
  std::uint32_t tile_frames(int tile) const { return tile_frames_[static_cast<std::size_t>(tile)]; }
  /// The tile's share of variance(): its pixels' mean estimated error; infinite before
  /// two frames or without a variance channel.
  float tile_error(int tile) const { return tile_error_[static_cast<std::size_t>(tile)]; }
  /// Whether adaptive rendering may skip the tile: its estimated error is at most
  /// `threshold` (> 0; 0 turns adaptivity off).
  bool tile_converged(int tile, float threshold) const { return threshold > 0.f && tile_error(tile) <= threshold; }

  /// Frames rendered since the last reset (the most any tile has).
  std::uint32_t accumulated_frames() const { return frames_; }
  void reset_accumulation() {
    frames_ = 0;
    std::fill(tile_frames_.begin(), tile_frames_.end(), 0u);
    std::fill(tile_error_.begin(), tile_error_.end(), std::numeric_limits<float>::infinity());
    frame_error_ = std::numeric_limits<float>::infinity();
    if (!odd_rgba_.empty()) {
      std::fill(block_error_.begin(), block_error_.end(), std::numeric_limits<float>::infinity());
      std::fill(block_frames_.begin(), block_frames_.end(), 0u);
      regions_.reset(blocks_x_, static_cast<int>(block_error_.size()) / blocks_x_);
    }
  }

  /// Called once every packet of a tile's frame is written: counts the frame for the
  /// tile and updates its error estimate. Tiles are independent, so threads may finish
  /// different tiles at once.
  void finish_tile(int tile) {
    if (!has(channel_accum)) return;
    const std::uint32_t frames = ++tile_frames_[static_cast<std::size_t>(tile)];
    if (!odd_luminance_.empty() && frames >= 2)
      tile_error_[static_cast<std::size_t>(tile)] = estimate_tile_error(tile, frames);
  }
  /// Called once the frame is done (after finish_tile of every tile it rendered), with
  /// the frame's variance threshold (0 without adaptive rendering).
  void finish_frame(float variance_threshold = 0.f) {
    frames_ = has(channel_accum) ? frames_ + 1 : 1;
    if (!odd_rgba_.empty()) estimate_ospray_errors(variance_threshold);
  }

  /// Stores a packet of the renderer's samples (averaged over the frame's samples per
  /// pixel) of the frame being rendered; lane i goes to pixel `pixel[i]`, or nowhere if
  /// it is negative. Depth is `sample.t`, the projected depth comes from the camera.
  /// Each pixel is written by one thread per frame, so no synchronisation is needed and
  /// results do not depend on the thread count.
  template <class Arch>
  void write_packet(const std::int32_t* pixel, const PixelSample<Arch>& sample,
                    const simd::Float<Arch>& depth_projected) {
    constexpr int W = simd::width<Arch>;
    // Frames of each lane's tile before this one (a stamp lies in one tile, but lanes
    // are looked up one by one so that any packet works); only averaged channels and ids
    // need them, and without accumulation every tile stays at 0 frames.
    alignas(64) std::uint32_t before[W] = {};
    if (averages())
      for (int i = 0; i < W; ++i) before[i] = pixel[i] >= 0 ? tile_frames(tile_of(pixel[i])) : 0;
    write_lanes<Arch>(pixel, sample, depth_projected, before);
  }
  /// write_packet() for a packet whose pixels all lie in one tile, which has
  /// `tile_frames_before` frames so far (its tile_frames()): no per-lane tile lookup.
  template <class Arch>
  void write_packet(const std::int32_t* pixel, const PixelSample<Arch>& sample,
                    const simd::Float<Arch>& depth_projected, std::uint32_t tile_frames_before) {
    alignas(64) std::uint32_t before[simd::width<Arch>];
    std::fill_n(before, simd::width<Arch>, tile_frames_before);
    write_lanes<Arch>(pixel, sample, depth_projected, before);
  }

  // ---- frames rendered elsewhere ------------------------------------------------------
  // A frame split among renderers (ranks of an MPI job) is rendered into staging frame
  // buffers (render_tiles: RGBA32F, the same other channels, no accumulation), whose
  // tiles are packed, sent and accumulated by the frame's owner as if it had rendered them.

  /// Floats per pixel of a packed tile: RGBA, then where this frame buffer has them the
  /// distance and projected depth, normal, albedo and each id channel (as bits).
  int packed_floats() const {
    return 4 + (has(channel_depth) ? 2 : 0) + (has(channel_normal) ? 3 : 0) + (has(channel_albedo) ? 3 : 0) +
           (has(channel_id_primitive) ? 1 : 0) + (has(channel_id_object) ? 1 : 0) + (has(channel_id_instance) ? 1 : 0);
  }
  /// Pixels of `tile` (fewer than tile_size^2 at the right and top edges).
  std::size_t tile_pixels(int tile) const {
    const int x0 = (tile % tiles_x_) * tile_size, y0 = (tile / tiles_x_) * tile_size;
    return static_cast<std::size_t>(std::min(tile_size, width_ - x0)) *
           static_cast<std::size_t>(std::min(tile_size, height_ - y0));
  }
  /// Appends the frame samples this staging frame buffer holds for `tile` to `out`,
  /// packed_floats() per pixel, row by row.
  void pack_tile(int tile, std::vector<float>& out) const {
    if (has(channel_accum) || format_ != ColorFormat::rgba32f)
      throw Error("framebuffer: only a staging frame buffer (RGBA32F, no accumulation) packs tiles");
    for_each_tile_pixel(tile, [&](std::size_t p) {
      out.insert(out.end(), &color32_[4 * p], &color32_[4 * p] + 4);
      if (has(channel_depth)) out.push_back(depth_[p]), out.push_back(depth_projected_[p]);
      if (has(channel_normal)) out.insert(out.end(), &normal_[3 * p], &normal_[3 * p] + 3);
      if (has(channel_albedo)) out.insert(out.end(), &albedo_[3 * p], &albedo_[3 * p] + 3);
      for (const auto* ids : {&primitive_id_, &object_id_, &instance_id_})
        if (!ids->empty()) out.push_back(std::bit_cast<float>((*ids)[p]));
    });
  }
  /// Writes a tile's frame samples, packed by a staging frame buffer with the same
  /// depth, normal, albedo and id channels, as render_frame writes its own (averaging
  /// them into the accumulation, Arch's width of pixels at a time), and counts the frame
  /// for the tile. `packed` holds packed_floats() * tile_pixels(tile) values.
  template <class Arch = simd::scalar>
  void accumulate_tile(int tile, const float* packed) {
    if (tile < 0 || tile >= tile_count())
      throw Error("framebuffer: tile " + std::to_string(tile) + " is outside the " + std::to_string(tile_count()) +
                  " tiles");
    constexpr int W = simd::width<Arch>;
    using F = simd::Float<Arch>;
    alignas(64) std::int32_t pixel[W];
    alignas(64) float lanes[13][W] = {};  // rgba, t, projected t, normal, albedo
    alignas(64) std::int32_t id_lanes[3][W] = {};
    alignas(64) std::uint32_t before[W];
    std::fill_n(before, W, tile_frames(tile));
    const int floats = packed_floats();
    const int ids = static_cast<int>(!primitive_id_.empty()) + static_cast<int>(!object_id_.empty()) +
                    static_cast<int>(!instance_id_.empty());
    const int values = floats - ids;
    int filled = 0;
    const auto flush = [&] {
      for (int i = filled; i < W; ++i) pixel[i] = -1;
      const auto load = [&](int k) { return simd::load<Arch>(lanes[k]); };
      PixelSample<Arch> sample;
      sample.color = {load(0), load(1), load(2)};
      sample.alpha = load(3);
      int k = 4;
      F projected(0.f);
      if (has(channel_depth)) sample.t = load(k), projected = load(k + 1), k += 2;
      if (has(channel_normal)) sample.normal = {load(k), load(k + 1), load(k + 2)}, k += 3;
      if (has(channel_albedo)) sample.albedo = {load(k), load(k + 1), load(k + 2)}, k += 3;
      int next_id = 0;
      for (auto [channel, id] : {std::pair{&primitive_id_, &sample.prim_id}, std::pair{&object_id_, &sample.geom_id},
                                 std::pair{&instance_id_, &sample.inst_id}})
        if (!channel->empty()) *id = simd::load<Arch>(id_lanes[next_id++]);
      write_lanes<Arch>(pixel, sample, projected, before);
      filled = 0;
    };
    for_each_tile_pixel(tile, [&](std::size_t p) {
      pixel[filled] = static_cast<std::int32_t>(p);
      for (int k = 0; k < values; ++k) lanes[k][filled] = packed[k];
      for (int k = 0; k < ids; ++k) id_lanes[k][filled] = std::bit_cast<std::int32_t>(packed[values + k]);
      packed += floats;
      if (++filled == W) flush();
    });
    if (filled) flush();
    finish_tile(tile);
  }

  /// The image operations applied, in order, to the colour output (not to the
  /// accumulation). Outputs already written are redone from the accumulation where
  /// there is one; otherwise the next frame shows the change.
  void set_image_operations(std::vector<ImageOperation> operations) {
    image_operations_ = std::move(operations);
    if (!has(channel_accum) || frames_ == 0) return;
    for (std::size_t p = 0; p < pixel_count(); ++p) {
      const auto pixel = static_cast<std::int32_t>(p);
      const std::uint32_t frames = tile_frames(tile_of(pixel));
      if (frames == 0) continue;
      float rgba[4][1];
      for (int c = 0; c < 4; ++c) rgba[c][0] = static_cast<float>(accum_[4 * p + c] / frames);
      output_color<simd::scalar>(&pixel, rgba);
    }
  }
  const std::vector<ImageOperation>& image_operations() const { return image_operations_; }

  /// An estimate of the error left in the accumulated colour: the mean over pixels of
  /// the expected absolute luminance error of their average (tiles weighted by their
  /// pixels). Per pixel it compares the means of two halves of the frames, which for
  /// independent frames differ by sqrt(frames^2 / (half0 * half1)) times the error of the
  /// whole average: the estimate is unbiased for all frame counts. The halves are split
  /// by the parity of the number of ones in the frame's index (Thue-Morse), not as even
  /// and odd frames: the pixel sample points are OSPRay's Halton points, the same in
  /// every pixel, and every other one lies in the same half of the pixel, so even and
  /// odd frames differ at every edge however many there are; each Thue-Morse half is
  /// stratified on its own (their difference falls as 1/frames, as the error does). Infinite while any
  /// tile has fewer than two frames, or without a variance channel (as OSPRay reports).
  /// With ErrorEstimate::ospray, the frame's error as OSPRay's ospGetVariance reports it.
  float variance() const {
    if (!odd_rgba_.empty()) return frame_error_;
    if (odd_luminance_.empty() || frames_ < 2) return std::numeric_limits<float>::infinity();
    double sum = 0.0;
    for (int tile = 0; tile < tile_count(); ++tile) {
      if (!std::isfinite(tile_error(tile))) return std::numeric_limits<float>::infinity();
      sum += static_cast<double>(tile_error(tile)) * static_cast<double>(tile_pixels(tile));
    }
    return static_cast<float>(sum / static_cast<double>(pixel_count()));
  }

  /// RGBA8 or SRGBA bytes, bottom row first. Empty for other formats.
  const std::vector<std::uint8_t>& color8() const { return color8_; }
  /// RGBA32F values, bottom row first. Empty for other formats.
  const std::vector<float>& color32f() const { return color32_; }
  /// Euclidean distance from the camera to the hit (inf where nothing was hit).
  const std::vector<float>& depth() const { return depth_; }
  /// Distance along the camera's view direction (as a z-buffer holds).
  const std::vector<float>& depth_projected() const { return depth_projected_; }
  /// Sum of the frames' RGBA (divide by the pixel's tile_frames).
  const std::vector<double>& accum() const { return accum_; }
  /// Average world-space normal, xyz per pixel (zero where nothing was hit).
  const std::vector<float>& normal() const { return normal_; }
  /// Average albedo, rgb per pixel.
  const std::vector<float>& albedo() const { return albedo_; }
  /// Ids of the first hit in the first frame since the last reset (no_id where nothing
  /// was hit): OSPRay writes them only while a tile has no frames, so accumulating frames
  /// (whose samples lie elsewhere in the pixel) leave them as they are; without
  /// accumulation every frame is a first frame.
  const std::vector<std::uint32_t>& primitive_id() const { return primitive_id_; }
  const std::vector<std::uint32_t>& object_id() const { return object_id_; }
  const std::vector<std::uint32_t>& instance_id() const { return instance_id_; }

  /// Bytes of all channels.
  std::size_t memory_bytes() const {
    return color8_.size() +
           sizeof(float) * (color32_.size() + depth_.size() + depth_projected_.size() + normal_.size() + albedo_.size()) +
           sizeof(double) * (accum_.size() + odd_luminance_.size() + odd_rgba_.size()) +
           sizeof(std::uint32_t) * (primitive_id_.size() + object_id_.size() + instance_id_.size());
  }

private:
  /// Whether a write needs the frames already in each pixel's tile.
  bool averages() const { return !accum_.empty() || !normal_.empty() || !albedo_.empty(); }

  /// write_packet() with the frames before this one of each lane's tile.
  template <class Arch>
  void write_lanes(const std::int32_t* pixel, const PixelSample<Arch>& sample,
                   const simd::Float<Arch>& depth_projected, const std::uint32_t* before) {
    constexpr int W = simd::width<Arch>;
    alignas(64) float rgba[4][W];
    simd::store<Arch>(rgba[0], sample.color.x);
    simd::store<Arch>(rgba[1], sample.color.y);
    simd::store<Arch>(rgba[2], sample.color.z);
    simd::store<Arch>(rgba[3], sample.alpha);
    if (has(channel_depth)) {
      alignas(64) float t[W], tz[W];
      simd::store<Arch>(t, sample.t);
      simd::store<Arch>(tz, depth_projected);
      for (int i = 0; i < W; ++i)
        if (pixel[i] >= 0) depth_[pixel[i]] = t[i], depth_projected_[pixel[i]] = tz[i];
    }
    store_ids<Arch>(pixel, before, primitive_id_, sample.prim_id);
    store_ids<Arch>(pixel, before, object_id_, sample.geom_id);
    store_ids<Arch>(pixel, before, instance_id_, sample.inst_id);
    average_into<Arch>(pixel, before, normal_, sample.normal);
    average_into<Arch>(pixel, before, albedo_, sample.albedo);
    if (has(channel_accum)) {
      for (int i = 0; i < W; ++i) {
        if (pixel[i] < 0) continue;
        const auto p = static_cast<std::size_t>(pixel[i]);
        if (!odd_luminance_.empty()) {
          double& odd = odd_luminance_[p];
          if (before[i] == 0) odd = 0.f;
          if (in_second_half(before[i])) odd += luminance(rgba[0][i], rgba[1][i], rgba[2][i]);
        }
        if (!odd_rgba_.empty() && before[i] % 2 == 1)
          for (int c = 0; c < 4; ++c) odd_rgba_[4 * p + c] = (before[i] == 1 ? 0.f : odd_rgba_[4 * p + c]) + rgba[c][i];
        // Sums in double: a float sum rounds away more of each sample as it grows (the
        // mean of 100,000 frames drifts by about 6e-5 of its value, more after that).
        double* acc = &accum_[4 * p];
        const double frames = static_cast<double>(before[i]) + 1.0;
        for (int c = 0; c < 4; ++c) {
          acc[c] = before[i] == 0 ? rgba[c][i] : acc[c] + rgba[c][i];
          rgba[c][i] = static_cast<float>(acc[c] / frames);
        }
      }
    }
    output_color<Arch>(pixel, rgba);
  }

  template <class T>
  static T luminance(T r, T g, T b) {
    return T(0.2126) * r + T(0.7152) * g + T(0.0722) * b;
  }

  /// Calls visit(p) for the pixels of `tile`, row by row.
  template <class Visit>
  void for_each_tile_pixel(int tile, Visit&& visit) const {
    const int x0 = (tile % tiles_x_) * tile_size, y0 = (tile / tiles_x_) * tile_size;
    for (int y = y0; y < std::min(y0 + tile_size, height_); ++y)
      for (int x = x0; x < std::min(x0 + tile_size, width_); ++x)
        visit(static_cast<std::size_t>(y) * static_cast<std::size_t>(width_) + static_cast<std::size_t>(x));
  }

  /// Whether frame `frame` (0 for the first) counts in the second half of the estimate.
  static bool in_second_half(std::uint32_t frame) { return std::popcount(frame) % 2 == 1; }
  /// How many of the first `frames` frames are in the second half: of 0..frames-1, those
  /// with an odd number of ones (each pair 2k, 2k + 1 holds one).
  static std::uint32_t second_half_frames(std::uint32_t frames) {
    return frames / 2 + (frames % 2 == 1 ? static_cast<std::uint32_t>(std::popcount(frames - 1) % 2) : 0u);
  }

  /// Mean over the tile's pixels of |first-half mean - second-half mean| * sqrt(first *
  /// second) / frames.
  float estimate_tile_error(int tile, std::uint32_t frames) const {
    const double odd_frames = second_half_frames(frames), even_frames = frames - odd_frames;
    const double scale = std::sqrt(even_frames * odd_frames) / frames;
    const int x0 = (tile % tiles_x_) * tile_size, y0 = (tile / tiles_x_) * tile_size;
    double sum = 0.0;
    for (int y = y0; y < std::min(y0 + tile_size, height_); ++y)
      for (int x = x0; x < std::min(x0 + tile_size, width_); ++x) {
        const auto p = static_cast<std::size_t>(y) * static_cast<std::size_t>(width_) + static_cast<std::size_t>(x);
        const double* acc = &accum_[4 * p];
        const double odd = odd_luminance_[p];
        const double all = luminance(acc[0], acc[1], acc[2]);
        sum += std::abs((all - odd) / even_frames - odd / odd_frames);
      }
    return static_cast<float>(scale * sum / static_cast<double>(tile_pixels(tile)));
  }

  /// ErrorEstimate::ospray after a frame: the OSPRay tiles that have just reached an even
  /// number of frames get a new error (the others keep theirs, so it falls steadily),
  /// the regions are refined, and each of sciray's tiles takes its OSPRay tile's error.
  void estimate_ospray_errors(float threshold) {
    for (std::size_t block = 0; block < block_error_.size(); ++block) {
      const int bx = static_cast<int>(block) % blocks_x_, by = static_cast<int>(block) / blocks_x_;
      // Its tiles are rendered together (they share the error), so its first counts for all.
      const std::uint32_t frames = tile_frames((by * tiles_per_ospray_tile) * tiles_x_ + bx * tiles_per_ospray_tile);
      if (frames == block_frames_[block]) continue;
      block_frames_[block] = frames;
      if (frames >= 2 && frames % 2 == 0) block_error_[block] = estimate_relative_error(bx, by, frames);
    }
    frame_error_ = regions_.refine(block_error_, threshold);
    for (int tile = 0; tile < tile_count(); ++tile) {
      const int bx = (tile % tiles_x_) / tiles_per_ospray_tile, by = (tile / tiles_x_) / tiles_per_ospray_tile;
      tile_error_[static_cast<std::size_t>(tile)] = block_error_[static_cast<std::size_t>(by * blocks_x_ + bx)];
    }
  }
  /// ErrorEstimate::ospray's error of OSPRay tile (bx, by) after `frames` (even) frames.
  float estimate_relative_error(int bx, int by, std::uint32_t frames) const {
    const float all_scale = 1.f / static_cast<float>(frames), odd_scale = 2.f / static_cast<float>(frames);
    const int x0 = bx * ospray_tile_size, y0 = by * ospray_tile_size;
    const int x1 = std::min(x0 + ospray_tile_size, width_), y1 = std::min(y0 + ospray_tile_size, height_);
    double sum = 0.0;
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x) {
        const auto p = static_cast<std::size_t>(y) * static_cast<std::size_t>(width_) + static_cast<std::size_t>(x);
        float mean[4], difference = 0.f;
        for (int c = 0; c < 4; ++c) {
          mean[c] = static_cast<float>(accum_[4 * p + c]) * all_scale;
          difference += std::abs(mean[c] - static_cast<float>(odd_rgba_[4 * p + c]) * odd_scale);
        }
        const float brightness = mean[0] + mean[1] + mean[2] + 1.f - mean[3];  // bright alpha weighs more
        if (brightness > 0.f) sum += difference / std::sqrt(brightness);
      }
    return static_cast<float>(64.0 * sum / (static_cast<double>(x1 - x0) * static_cast<double>(y1 - y0)));
  }

  /// Writes the ids of the lanes whose tile has no frames yet (see primitive_id()).
  template <class Arch>
  static void store_ids(const std::int32_t* pixel, const std::uint32_t* before, std::vector<std::uint32_t>& channel,
                        const simd::Int<Arch>& ids) {
    if (channel.empty()) return;
    alignas(64) std::int32_t values[simd::width<Arch>];
    simd::store<Arch>(values, ids);
    for (int i = 0; i < simd::width<Arch>; ++i)
      if (pixel[i] >= 0 && before[i] == 0)
        channel[static_cast<std::size_t>(pixel[i])] = static_cast<std::uint32_t>(values[i]);
  }

  /// Running mean of a 3-vector channel over the tile's frames (the latest value without
  /// accumulation).
  template <class Arch>
  static void average_into(const std::int32_t* pixel, const std::uint32_t* before, std::vector<float>& channel,
                           const Vec3<simd::Float<Arch>>& value) {
    if (channel.empty()) return;
    constexpr int W = simd::width<Arch>;
    alignas(64) float v[3][W];
    simd::store<Arch>(v[0], value.x);
    simd::store<Arch>(v[1], value.y);
    simd::store<Arch>(v[2], value.z);
    for (int i = 0; i < W; ++i) {
      if (pixel[i] < 0) continue;
      float* out = &channel[3 * static_cast<std::size_t>(pixel[i])];
      const float weight = 1.f / static_cast<float>(before[i] + 1);
      for (int c = 0; c < 3; ++c) out[c] = before[i] == 0 ? v[c][i] : out[c] + (v[c][i] - out[c]) * weight;
    }
  }

  /// Writes averaged linear RGBA to the colour channel: image operations, then the
  /// output format.
  template <class Arch>
  void output_color(const std::int32_t* pixel, float (&rgba)[4][simd::width<Arch>]) {
    using F = simd::Float<Arch>;
    constexpr int W = simd::width<Arch>;
    if (format_ == ColorFormat::none) return;
    if (!image_operations_.empty()) {
      Vec3<F> rgb{simd::load<Arch>(rgba[0]), simd::load<Arch>(rgba[1]), simd::load<Arch>(rgba[2])};
      for (const ImageOperation& op : image_operations_) rgb = std::visit([&](const auto& o) { return o(rgb); }, op);
      simd::store<Arch>(rgba[0], rgb.x);
      simd::store<Arch>(rgba[1], rgb.y);
      simd::store<Arch>(rgba[2], rgb.z);
    }
    if (format_ == ColorFormat::rgba32f) {
      for (int i = 0; i < W; ++i)
        if (pixel[i] >= 0)
          for (int c = 0; c < 4; ++c) color32_[4 * static_cast<std::size_t>(pixel[i]) + c] = rgba[c][i];
      return;
    }
    // 8-bit formats: quantize, encode and pack all lanes at once, then one 4-byte store
    // per pixel. Alpha stays linear; colour is encoded through a table for SRGBA and
    // gamma 2.2, looked up by gathers.
    using I = simd::Int<Arch>;
    const bool srgb = format_ == ColorFormat::srgba || format_ == ColorFormat::gamma22;
    const F scale(srgb ? 65535.f : 255.f);
    const std::uint8_t* table = srgb ? detail::encoding_table(format_).data() : nullptr;
    I packed(0);
    for (int c = 0; c < 4; ++c) {
      const F v = simd::load<Arch>(rgba[c]);
      // max/min order maps NaN to 0, and the +0.5 with truncation rounds to nearest.
      const F clamped = simd::min(simd::max(v, F(0.f)), F(1.f));
      I q = simd::to_int(clamped * (c == 3 ? F(255.f) : scale) + F(0.5f));
      if (table && c < 3) q = simd::gather_bytes<Arch>(table, q);
      packed = packed | (q << (8 * c));
    }
    alignas(64) std::int32_t bytes[W];
    simd::store<Arch>(bytes, packed);
    // A stamp's row is a run of neighbouring pixels: one store each.
    for (int i = 0; i < W;) {
      if (pixel[i] < 0) {
        ++i;
        continue;
      }
      int end = i + 1;
      while (end < W && pixel[end] == pixel[end - 1] + 1) ++end;
      std::memcpy(&color8_[4 * static_cast<std::size_t>(pixel[i])], &bytes[i], 4 * static_cast<std::size_t>(end - i));
      i = end;
    }
  }

  int width_, height_;
  ColorFormat format_;
  unsigned channels_;
  int tiles_x_;
  std::uint64_t row_magic_;  // pixel / width = pixel * row_magic_ >> row_shift_
  int row_shift_;
  std::uint32_t frames_ = 0;
  std::vector<std::uint32_t> tile_frames_;
  std::vector<float> tile_error_;
  std::vector<ImageOperation> image_operations_;

  std::vector<double> accum_;  // sums of the frames' samples
  std::vector<double> odd_luminance_;  // sum over the second half's frames (in_second_half), for the estimate
  // ErrorEstimate::ospray: sums over the odd frames; per OSPRay tile, its error and the
  // frames it was taken at; the refinement's regions.
  std::vector<double> odd_rgba_;
  int blocks_x_ = 0;
  std::vector<float> block_error_;
  std::vector<std::uint32_t> block_frames_;
  ErrorRegions regions_;
  float frame_error_ = std::numeric_limits<float>::infinity();
  std::vector<std::uint8_t> color8_;
  std::vector<float> color32_;
  std::vector<float> depth_;
  std::vector<float> depth_projected_;
  std::vector<float> normal_;
  std::vector<float> albedo_;
  std::vector<std::uint32_t> primitive_id_, object_id_, instance_id_;
};

}  // namespace sciray
