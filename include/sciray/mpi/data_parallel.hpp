#pragma once
// Data-parallel rendering over MPI (OSPRay's mpiDistributed): every rank renders the
// regions of the world it owns into fragment images (distributed/region_renderer.hpp),
// and the frame is composited sort-last by direct send with band ownership: rank r owns
// the r-th of P bands of image rows; every rank sends each owner its fragments of that
// band in one all-to-all; each owner blends its band front to back in region order
// (distributed/fragments.hpp); the frame's owner gathers the bands and accumulates them.
// Each rank sends and receives (P-1)/P of its fragment images, the bytes binary swap
// moves, in one round instead of log2 P (docs/distributed.md has the model). Fragment
// layers a band does not see (no ray of the band meets the region) are not sent.
//
// Every exchange is non-blocking and waited for at most `timeout_seconds`: a rank that
// does not take part in a frame (mismatched collective calls, a dead rank) ends the
// frame with an error naming what did not complete, not a deadlock.
#include <mpi.h>
#include <tbb/parallel_for.h>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <span>
#include <string>
#include <thread>
#include <vector>

#include "sciray/distributed/fragments.hpp"
#include "sciray/frame/framebuffer.hpp"
#include "sciray/math/box.hpp"
#include "sciray/mpi/image_parallel.hpp"

namespace sciray::mpi {

/// What one composited frame moved on this rank.
struct CompositeTraffic {
  std::uint64_t bytes_sent = 0, bytes_received = 0;
};

class DataParallel {
public:
  explicit DataParallel(MPI_Comm comm, int owner = 0,
                        double timeout_seconds = scheduling_from_environment().timeout_seconds)
      : comm_(comm), owner_(owner), timeout_(timeout_seconds) {}

  bool owns_frames() const { return comm_.rank() == owner_; }
  int rank() const { return comm_.rank(); }
  int ranks() const { return comm_.size(); }
  MPI_Comm communicator() const { return comm_.get(); }

  /// The frame index of every tile, the owner's (`fb` there, ignored elsewhere), for the
  /// regions' samples to follow the owner's accumulation (collective).
  std::vector<std::uint32_t> tile_frames(const FrameBuffer* fb, int tile_count) {
    std::vector<std::uint32_t> frames(static_cast<std::size_t>(tile_count), 0);
    if (owns_frames()) {
      if (!fb || fb->tile_count() != tile_count) throw Error("mpi: the frame's owner needs its frame buffer");
      for (int tile = 0; tile < tile_count; ++tile) frames[static_cast<std::size_t>(tile)] = fb->tile_frames(tile);
    }
    MPI_Request request;
    check(MPI_Ibcast(frames.data(), tile_count, MPI_UINT32_T, owner_, comm_.get(), &request), "MPI_Ibcast");
    wait(request, "sharing the frame's tile counts");
    return frames;
  }

  /// Every rank's regions, by rank (collective).
  std::vector<std::vector<Box3f>> all_regions(std::span<const Box3f> mine) {
    static_assert(sizeof(Box3f) == 6 * sizeof(float));
    const int count = static_cast<int>(6 * mine.size());
    std::vector<int> counts(static_cast<std::size_t>(comm_.size())), offsets(static_cast<std::size_t>(comm_.size()));
    MPI_Request request;
    check(MPI_Iallgather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, comm_.get(), &request), "MPI_Iallgather");
    wait(request, "sharing the ranks' regions");
    int total = 0;
    for (int r = 0; r < comm_.size(); ++r)
      offsets[static_cast<std::size_t>(r)] = total, total += counts[static_cast<std::size_t>(r)];
    std::vector<float> boxes(static_cast<std::size_t>(total));
    check(MPI_Iallgatherv(mine.data(), count, MPI_FLOAT, boxes.data(), counts.data(), offsets.data(), MPI_FLOAT,
                          comm_.get(), &request),
          "MPI_Iallgatherv");
    wait(request, "sharing the ranks' regions");
    std::vector<std::vector<Box3f>> all(static_cast<std::size_t>(comm_.size()));
    for (int r = 0; r < comm_.size(); ++r)
      for (int at = offsets[static_cast<std::size_t>(r)];
           at < offsets[static_cast<std::size_t>(r)] + counts[static_cast<std::size_t>(r)]; at += 6) {
        const float* b = &boxes[static_cast<std::size_t>(at)];
        all[static_cast<std::size_t>(r)].push_back({{b[0], b[1], b[2]}, {b[3], b[4], b[5]}});
      }
    return all;
  }

  /// Composites the fragment images of every rank (this rank's `layers`, one per region
  /// it owns, each width x height, possibly none) over `background` (collective). The
  /// owner's `fb` (colour, optionally depth, accumulation and variance) accumulates
  /// the frame with `accumulate`; the other ranks pass null.
  CompositeTraffic composite_frame(std::span<const distributed::FragmentImage> layers, int width, int height,
                                   const distributed::Background& background, FrameBuffer* fb,
                                   AccumulateTile accumulate = accumulate_tile) {
    for (const auto& layer : layers)
      if (layer.width != width || layer.height != height)
        throw Error("mpi: a fragment image of " + std::to_string(layer.width) + "x" + std::to_string(layer.height) +
                    " in a frame of " + std::to_string(width) + "x" + std::to_string(height));
    if (owns_frames()) check_frame_buffer(fb, width, height);
    const auto band = [&](int r) {
      const auto rows = static_cast<std::size_t>(height);
      const std::size_t first = rows * static_cast<std::size_t>(r) / static_cast<std::size_t>(comm_.size());
      const std::size_t last = rows * static_cast<std::size_t>(r + 1) / static_cast<std::size_t>(comm_.size());
      return std::pair{first * static_cast<std::size_t>(width), (last - first) * static_cast<std::size_t>(width)};
    };

    // Each owner's band of every layer that sees it: rgba, key, depth. (The buffers are
    // kept from frame to frame: fresh pages cost more than the compositing.)
    std::vector<float>& outgoing = outgoing_;
    outgoing.clear();
    std::vector<int> send_counts(static_cast<std::size_t>(comm_.size())),
        send_offsets(static_cast<std::size_t>(comm_.size()));
    for (int r = 0; r < comm_.size(); ++r) {
      const auto [first, count] = band(r);
      send_offsets[static_cast<std::size_t>(r)] = static_cast<int>(outgoing.size());
      for (const auto& layer : layers) {
        bool seen = false;
        for (std::size_t p = first; p < first + count && !seen; ++p) seen = std::isfinite(layer.key[p]);
        if (!seen) continue;
        outgoing.insert(outgoing.end(), layer.rgba.begin() + static_cast<std::ptrdiff_t>(4 * first),
                        layer.rgba.begin() + static_cast<std::ptrdiff_t>(4 * (first + count)));
        outgoing.insert(outgoing.end(), layer.key.begin() + static_cast<std::ptrdiff_t>(first),
                        layer.key.begin() + static_cast<std::ptrdiff_t>(first + count));
        outgoing.insert(outgoing.end(), layer.depth.begin() + static_cast<std::ptrdiff_t>(first),
                        layer.depth.begin() + static_cast<std::ptrdiff_t>(first + count));
      }
      send_counts[static_cast<std::size_t>(r)] =
          static_cast<int>(outgoing.size()) - send_offsets[static_cast<std::size_t>(r)];
    }
    std::vector<int> receive_counts(static_cast<std::size_t>(comm_.size())),
        receive_offsets(static_cast<std::size_t>(comm_.size()));
    MPI_Request request;
    check(MPI_Ialltoall(send_counts.data(), 1, MPI_INT, receive_counts.data(), 1, MPI_INT, comm_.get(), &request),
          "MPI_Ialltoall");
    wait(request, "exchanging fragment counts");
    int total = 0;
    for (int r = 0; r < comm_.size(); ++r)
      receive_offsets[static_cast<std::size_t>(r)] = total, total += receive_counts[static_cast<std::size_t>(r)];
    std::vector<float>& incoming = incoming_;
    incoming.resize(static_cast<std::size_t>(total));
    check(MPI_Ialltoallv(outgoing.data(), send_counts.data(), send_offsets.data(), MPI_FLOAT, incoming.data(),
                         receive_counts.data(), receive_offsets.data(), MPI_FLOAT, comm_.get(), &request),
          "MPI_Ialltoallv");
    wait(request, "exchanging fragments");

    // This rank's band, composited.
    const auto [first, count] = band(comm_.rank());
    std::vector<distributed::FragmentView> views;
    const std::size_t per_layer = 6 * count;
    for (std::size_t at = 0; per_layer > 0 && at + per_layer <= incoming.size(); at += per_layer) {
      const std::span<const float> layer(incoming.data() + at, per_layer);
      views.emplace_back(layer.subspan(0, 4 * count), layer.subspan(4 * count, count), layer.subspan(5 * count, count));
    }
    std::vector<float>& composited = composited_;  // rgba, then depth
    composited.resize(5 * count);
    distributed::composite(views, background, std::span(composited).subspan(0, 4 * count),
                           std::span(composited).subspan(4 * count, count));

    // The bands to the frame's owner.
    std::vector<int> band_counts(static_cast<std::size_t>(comm_.size())),
        band_offsets(static_cast<std::size_t>(comm_.size()));
    for (int r = 0; r < comm_.size(); ++r) {
      band_counts[static_cast<std::size_t>(r)] = static_cast<int>(5 * band(r).second);
      band_offsets[static_cast<std::size_t>(r)] = static_cast<int>(5 * band(r).first);
    }
    std::vector<float>& bands = bands_;
    bands.resize(owns_frames() ? 5 * static_cast<std::size_t>(width) * static_cast<std::size_t>(height) : 0);
    check(MPI_Igatherv(composited.data(), static_cast<int>(composited.size()), MPI_FLOAT, bands.data(),
                       band_counts.data(), band_offsets.data(), MPI_FLOAT, owner_, comm_.get(), &request),
          "MPI_Igatherv");
    wait(request, "gathering the composited bands");

    CompositeTraffic traffic;
    for (int r = 0; r < comm_.size(); ++r) {
      if (r == comm_.rank()) continue;
      const auto at = static_cast<std::size_t>(r);
      traffic.bytes_sent += sizeof(float) * static_cast<std::uint64_t>(send_counts[at]);
      traffic.bytes_received += sizeof(float) * static_cast<std::uint64_t>(receive_counts[at]);
    }
    if (!owns_frames()) {
      traffic.bytes_sent += sizeof(float) * composited.size();
      return traffic;
    }
    accumulate_bands(bands, width, band, *fb, accumulate);
    return traffic;
  }

private:
  /// The owner's frame buffer holds what compositing produces: colour (and its
  /// accumulation and variance) and depth, the frame's size.
  static void check_frame_buffer(const FrameBuffer* fb, int width, int height) {
    if (!fb) throw Error("mpi: the frame's owner needs its frame buffer");
    if (fb->width() != width || fb->height() != height)
      throw Error("mpi: the frame buffer is " + std::to_string(fb->width()) + "x" + std::to_string(fb->height()) +
                  ", the frame " + std::to_string(width) + "x" + std::to_string(height));
    for (Channel c : {channel_normal, channel_albedo, channel_id_primitive, channel_id_object, channel_id_instance})
      if (fb->has(c))
        throw Error(
            "mpi: data-parallel frames composite colour and depth only; the frame buffer asks for normal, "
            "albedo or id channels");
  }

  /// Writes the gathered image (band r: its pixels' rgba, then their depths) into `fb`
  /// tile by tile, and finishes the frame.
  template <class Band>
  void accumulate_bands(const std::vector<float>& bands, int width, const Band& band, FrameBuffer& fb,
                        AccumulateTile accumulate) const {
    const auto row_width = static_cast<std::size_t>(width);
    std::vector<int> band_of_row(static_cast<std::size_t>(fb.height()));
    for (int r = 0; r < comm_.size(); ++r) {
      const auto [first, count] = band(r);
      for (std::size_t row = first / row_width; row < (first + count) / row_width; ++row) band_of_row[row] = r;
    }
    // Tiles are independent: the owner's threads pack and accumulate them together.
    tbb::parallel_for(0, fb.tile_count(), [&](int tile) {
      std::vector<float> packed;
      packed.reserve(fb.tile_pixels(tile) * static_cast<std::size_t>(fb.packed_floats()));
      const int x0 = (tile % fb.tiles_x()) * tile_size, y0 = (tile / fb.tiles_x()) * tile_size;
      for (int y = y0; y < std::min(y0 + tile_size, fb.height()); ++y) {
        const auto [first, count] = band(band_of_row[static_cast<std::size_t>(y)]);
        const float* rgba = bands.data() + 5 * first;
        const float* depth = rgba + 4 * count;
        for (int x = x0; x < std::min(x0 + tile_size, width); ++x) {
          const std::size_t at = static_cast<std::size_t>(y) * row_width + static_cast<std::size_t>(x) - first;
          packed.insert(packed.end(), rgba + 4 * at, rgba + 4 * at + 4);
          // The distance to the first hit; the projected depth is not composited (set the same).
          if (fb.has(channel_depth)) packed.insert(packed.end(), {depth[at], depth[at]});
        }
      }
      accumulate(fb, tile, packed.data());
    });
    fb.finish_frame();
  }

  void wait(MPI_Request& request, const char* what) const {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_);
    for (;;) {
      int done = 0;
      check(MPI_Test(&request, &done, MPI_STATUS_IGNORE), what);
      if (done) return;
      if (std::chrono::steady_clock::now() > deadline)
        throw Error(std::string("mpi: ") + what + " did not complete within " + std::to_string(timeout_) +
                    " s: every rank must render each frame (a rank skipped it, died, or is behind)");
      std::this_thread::sleep_for(std::chrono::microseconds(50));
    }
  }

  Communicator comm_;
  int owner_;
  double timeout_;
  std::vector<float> outgoing_, incoming_, composited_, bands_;
};

}  // namespace sciray::mpi
