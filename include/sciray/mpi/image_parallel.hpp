#pragma once
// Image-parallel rendering over MPI (OSPRay's mpiOffload): one rank owns the frame
// buffer and hands out its tiles; the other ranks render them with the normal engine
// into staging frame buffers (render_tiles) and send back the frame's samples, which the
// owner accumulates as if it had rendered them (FrameBuffer::accumulate_tile). Every
// sample's position depends only on its pixel and the tile's frame count, both the
// owner's, so the image is the one a single process renders for any number of ranks, any
// tile order and any accumulated frame.
//
// Tiles go out on request, a task queue: a rank asks for a batch, renders it, and sends
// it back with its next request, so fast ranks take more tiles (dynamic load balancing);
// batches start large (half of what is left over the ranks: guided self-scheduling) and
// shrink to the rank's own size (four tiles a thread) towards the end.
// With Scheduling::dynamic off, each rank gets one fixed share (every n-th tile).
// The owner waits for answers at most Scheduling::timeout_seconds since the last one:
// a rank that died or never took part ends the frame with an error, not a hang.
#include <mpi.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <deque>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <thread>
#include <vector>

#include "sciray/error.hpp"
#include "sciray/frame/framebuffer.hpp"
#include "sciray/frame/render_frame.hpp"
#include "sciray/mpi/wire.hpp"

namespace sciray::mpi {

/// Throws an Error naming `what` unless `code` is MPI_SUCCESS.
inline void check(int code, const char* what) {
  if (code == MPI_SUCCESS) return;
  char text[MPI_MAX_ERROR_STRING];
  int length = 0;
  MPI_Error_string(code, text, &length);
  throw Error(std::string("mpi: ") + what + " failed: " + std::string(text, static_cast<std::size_t>(length)));
}

/// A duplicate of a communicator, freed with this object (unless MPI is finalized by
/// then), so that the layer's messages never meet the application's.
class Communicator {
public:
  explicit Communicator(MPI_Comm comm) {
    check(MPI_Comm_dup(comm, &comm_), "MPI_Comm_dup");
    check(MPI_Comm_rank(comm_, &rank_), "MPI_Comm_rank");
    check(MPI_Comm_size(comm_, &size_), "MPI_Comm_size");
  }
  ~Communicator() {
    int finalized = 0;
    MPI_Finalized(&finalized);
    if (!finalized) MPI_Comm_free(&comm_);
  }
  Communicator(const Communicator&) = delete;
  Communicator& operator=(const Communicator&) = delete;

  MPI_Comm get() const { return comm_; }
  int rank() const { return rank_; }
  int size() const { return size_; }

private:
  MPI_Comm comm_ = MPI_COMM_NULL;
  int rank_ = 0, size_ = 1;
};

struct Scheduling {
  bool dynamic = true;  ///< a task queue of tile batches; off: one fixed share per rank
  /// Tiles a rank asks for at once (0: four per thread it renders with).
  int batch_tiles = 0;
  /// How long the owner waits for the next answer from any rank before it gives up.
  double timeout_seconds = 300.;
};

/// The environment's choices over `defaults`: SCIRAY_MPI_STATIC_TILES=1 turns the task
/// queue off (OSPRay's static load balancer), SCIRAY_MPI_TIMEOUT sets the timeout in seconds.
inline Scheduling scheduling_from_environment(Scheduling defaults = {}) {
  if (const char* s = std::getenv("SCIRAY_MPI_STATIC_TILES"); s && *s) defaults.dynamic = std::string(s) == "0";
  if (const char* s = std::getenv("SCIRAY_MPI_TIMEOUT"); s && *s) {
    char* end = nullptr;
    const double seconds = std::strtod(s, &end);
    if (*end != '\0' || !(seconds > 0.))
      throw Error(std::string("SCIRAY_MPI_TIMEOUT must be a positive number of seconds, got '") + s + "'");
    defaults.timeout_seconds = seconds;
  }
  return defaults;
}

/// Accumulates a packed tile into a frame buffer (FrameBuffer::accumulate_tile). Pass the
/// one compiled with the renderers' flags where they differ from the caller's (the C API's
/// per-ISA kernels): the running means of normal and albedo round as they were compiled,
/// and the same image on every number of ranks needs the same rounding.
using AccumulateTile = void (*)(FrameBuffer& fb, int tile, const float* packed);
inline void accumulate_tile(FrameBuffer& fb, int tile, const float* packed) {
  fb.accumulate_tile<xsimd::default_arch>(tile, packed);
}

/// What one frame moved: per rank, the tiles it rendered and the bytes it sent the owner.
struct FrameTraffic {
  std::vector<std::uint32_t> tiles;
  std::vector<std::uint64_t> bytes;
};

/// A message the frame's owner received for a frame it has not started: a rank that
/// finished its share of frame f may already ask for tiles of frame f + 1 while the
/// owner still serves f. It waits here for serve_frame of its frame.
struct EarlyMessage {
  int rank;
  int tag;
  std::vector<std::byte> bytes;
};

namespace detail {
enum Tag : int { tag_result = 1, tag_error = 2, tag_work = 3 };

/// The frame's staging buffer: the owner's size and channels, RGBA32F, no accumulation.
inline unsigned staging_channels(unsigned channels) {
  return (channels & ~unsigned(channel_accum | channel_variance)) | channel_color;
}

inline void send(const Writer& message, int rank, int tag, MPI_Comm comm) {
  check(MPI_Send(message.data(), static_cast<int>(message.size()), MPI_BYTE, rank, tag, comm),
        "sending a tile message");
}
}  // namespace detail

/// The owner's side of frame `frame_id` on `comm` (the caller's rank owns it): hands the
/// tiles of `fb` that need rendering (all, or those above settings.variance_threshold)
/// to the other ranks, accumulates what they send, and finishes the frame. Cancelling
/// through `control` stops handing out tiles and leaves the accumulation reset, as
/// render_frame does; an error from any rank does the same and is thrown, naming the rank.
/// Where ranks start the next frame without waiting for the owner (ImageParallel), pass
/// the same `early` list to every frame: requests for later frames wait there.
inline FrameTraffic serve_frame(MPI_Comm comm, std::uint32_t frame_id, FrameBuffer& fb, const FrameSettings& settings,
                                const Scheduling& scheduling = {}, FrameControl* control = nullptr,
                                AccumulateTile accumulate = accumulate_tile,
                                std::deque<EarlyMessage>* early = nullptr) {
  int ranks = 0, self = 0;
  check(MPI_Comm_size(comm, &ranks), "MPI_Comm_size");
  check(MPI_Comm_rank(comm, &self), "MPI_Comm_rank");
  if (ranks < 2) throw Error("mpi: image-parallel rendering needs at least one rank besides the frame's owner");

  std::deque<TileWork> queue;
  for (int tile = 0; tile < fb.tile_count(); ++tile)
    if (!fb.tile_converged(tile, settings.variance_threshold)) queue.push_back({tile, fb.tile_frames(tile)});
  const auto total_tiles = static_cast<std::uint32_t>(queue.size());
  if (control) control->tiles_done = 0, control->tile_count = total_tiles;
  // The static shares: rank r's are every (ranks - 1)-th queued tile from its own.
  std::vector<std::vector<TileWork>> fixed_share(static_cast<std::size_t>(ranks));
  if (!scheduling.dynamic)
    for (std::size_t i = 0; i < queue.size(); ++i) {
      int rank = static_cast<int>(i % static_cast<std::size_t>(ranks - 1));
      fixed_share[static_cast<std::size_t>(rank >= self ? rank + 1 : rank)].push_back(queue[i]);
    }

  FrameTraffic traffic{std::vector<std::uint32_t>(static_cast<std::size_t>(ranks), 0),
                       std::vector<std::uint64_t>(static_cast<std::size_t>(ranks), 0)};
  std::vector<std::vector<TileWork>> in_flight(static_cast<std::size_t>(ranks));
  std::vector<bool> finished(static_cast<std::size_t>(ranks), false);
  finished[static_cast<std::size_t>(self)] = true;
  int open = ranks - 1;
  std::string failure;
  std::uint32_t accumulated = 0;
  std::vector<std::byte> buffer;
  const auto timeout = std::chrono::duration<double>(scheduling.timeout_seconds);
  auto deadline = std::chrono::steady_clock::now() + timeout;

  // The frame a message belongs to, against this one (wrapping frame ids compare by difference).
  const auto frames_ahead = [&](const std::vector<std::byte>& bytes) {
    return static_cast<std::int32_t>(Reader(bytes).get<std::uint32_t>() - frame_id);
  };
  while (open > 0) {
    int rank = 0, tag = 0;
    const auto waiting = early ? std::find_if(early->begin(), early->end(),
                                              [&](const EarlyMessage& m) { return frames_ahead(m.bytes) <= 0; })
                               : std::deque<EarlyMessage>::iterator{};
    if (early && waiting != early->end()) {
      rank = waiting->rank, tag = waiting->tag;
      buffer = std::move(waiting->bytes);
      early->erase(waiting);
    } else {
      int arrived = 0;
      MPI_Status status;
      check(MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, comm, &arrived, &status), "MPI_Iprobe");
      if (!arrived) {
        if (std::chrono::steady_clock::now() > deadline) {
          std::string silent;
          for (int r = 0; r < ranks; ++r)
            if (!finished[static_cast<std::size_t>(r)]) silent += (silent.empty() ? "" : ", ") + std::to_string(r);
          fb.reset_accumulation();
          throw Error("mpi: frame " + std::to_string(frame_id) + ": no answer from rank(s) " + silent + " within " +
                      std::to_string(scheduling.timeout_seconds) +
                      " s (a rank died, never started, or is not rendering this frame)");
        }
        std::this_thread::sleep_for(std::chrono::microseconds(50));
        continue;
      }
      int size = 0;
      check(MPI_Get_count(&status, MPI_BYTE, &size), "MPI_Get_count");
      buffer.resize(static_cast<std::size_t>(size));
      check(MPI_Recv(buffer.data(), size, MPI_BYTE, status.MPI_SOURCE, status.MPI_TAG, comm, MPI_STATUS_IGNORE),
            "receiving a tile message");
      deadline = std::chrono::steady_clock::now() + timeout;
      rank = status.MPI_SOURCE, tag = status.MPI_TAG;
    }
    const auto r = static_cast<std::size_t>(rank);
    const auto answer = [&](std::uint32_t frame, std::span<const TileWork> work) {
      Writer reply;
      reply.put(frame);
      reply.put_span(work);
      detail::send(reply, rank, detail::tag_work, comm);
    };
    if (const std::int32_t ahead = frames_ahead(buffer); ahead != 0) {
      if (ahead > 0 && early) {
        early->push_back({rank, tag, std::move(buffer)});
      } else if (ahead > 0) {
        fb.reset_accumulation();
        throw Error("mpi: frame " + std::to_string(frame_id) + ": rank " + std::to_string(rank) +
                    " asked for tiles of a later frame before this one ended");
      } else if (tag == detail::tag_result) {  // from a frame that timed out: let that rank move on
        answer(frame_id + static_cast<std::uint32_t>(ahead), {});
      }
      continue;
    }
    if (finished[r]) continue;
    Reader message(buffer);
    message.get<std::uint32_t>();
    traffic.bytes[r] += static_cast<std::uint64_t>(buffer.size());
    if (tag == detail::tag_error) {
      if (failure.empty()) failure = "rank " + std::to_string(rank) + ": " + message.get_string();
      finished[r] = true, --open;
      continue;
    }
    const auto batch_wanted = message.get<std::int32_t>();
    const auto tiles = message.get_vector<std::int32_t>();
    const auto packed = message.get_vector<float>();
    // The batch must be the one this rank was given, every tile packed whole.
    const auto packed_per_pixel = static_cast<std::size_t>(fb.packed_floats());
    std::size_t expected = 0;
    bool matches = tiles.size() == in_flight[r].size();
    for (std::size_t i = 0; matches && i < tiles.size(); ++i) {
      matches = tiles[i] == in_flight[r][i].tile;
      if (matches) expected += fb.tile_pixels(tiles[i]) * packed_per_pixel;
    }
    if (!matches || expected != packed.size()) {
      fb.reset_accumulation();
      throw Error("mpi: frame " + std::to_string(frame_id) + ": rank " + std::to_string(rank) +
                  " sent tiles it was not given, or not whole");
    }
    // The rank's next batch goes out first: it renders while this one is accumulated.
    const bool cancelled = control && control->cancel.load();
    in_flight[r].clear();
    if (!cancelled && failure.empty()) {
      if (scheduling.dynamic) {
        // Guided self-scheduling: large batches while much is left (few round trips),
        // down to the rank's own batch size at the end (balance).
        const std::size_t guided = queue.size() / (2 * static_cast<std::size_t>(ranks - 1));
        const auto take = std::min(queue.size(), std::max(guided, static_cast<std::size_t>(std::max(batch_wanted, 1))));
        in_flight[r].assign(queue.begin(), queue.begin() + static_cast<std::ptrdiff_t>(take));
        queue.erase(queue.begin(), queue.begin() + static_cast<std::ptrdiff_t>(take));
      } else {
        in_flight[r] = std::move(fixed_share[r]);
        fixed_share[r].clear();
      }
    }
    answer(frame_id, in_flight[r]);
    if (in_flight[r].empty()) finished[r] = true, --open;
    if (!cancelled && failure.empty()) {
      // Tiles are independent: the owner's threads accumulate them together.
      std::vector<std::size_t> offsets(tiles.size() + 1, 0);
      for (std::size_t i = 0; i < tiles.size(); ++i)
        offsets[i + 1] = offsets[i] + fb.tile_pixels(tiles[i]) * packed_per_pixel;
      tbb::parallel_for(std::size_t{0}, tiles.size(),
                        [&](std::size_t i) { accumulate(fb, tiles[i], packed.data() + offsets[i]); });
    }
    accumulated += static_cast<std::uint32_t>(tiles.size());
    traffic.tiles[r] += static_cast<std::uint32_t>(tiles.size());
    if (control) control->tiles_done = accumulated;
  }
  if (control && control->cancel.load()) {
    fb.reset_accumulation();
    return traffic;
  }
  if (!failure.empty()) {
    fb.reset_accumulation();
    throw Error("mpi: frame " + std::to_string(frame_id) + ": " + failure);
  }
  if (accumulated != total_tiles) {
    fb.reset_accumulation();
    throw Error("mpi: frame " + std::to_string(frame_id) + ": " + std::to_string(total_tiles - accumulated) +
                " tiles were not rendered");
  }
  if (total_tiles > 0) fb.finish_frame(settings.variance_threshold);
  return traffic;
}

/// Renders a batch of tiles into the staging frame buffer (render_tiles with the frame's
/// renderer, camera and settings).
using RenderShare = std::function<void(std::span<const TileWork> share, FrameBuffer& staging)>;

/// A rendering rank's side of frame `frame_id`: asks `owner` for tiles until it has none
/// left, renders them into `staging` (the owner's size and depth, normal, albedo and id
/// channels, RGBA32F, no accumulation) and sends them back. An exception while rendering
/// is sent to the owner, who reports it.
inline void work_frame(MPI_Comm comm, int owner, std::uint32_t frame_id, FrameBuffer& staging,
                       const RenderShare& render_share, int batch_tiles) {
  Writer message;
  message.put(frame_id);
  message.put<std::int32_t>(batch_tiles);
  message.put_span(std::span<const std::int32_t>());
  message.put_span(std::span<const float>());
  std::vector<std::byte> buffer;
  std::vector<std::int32_t> tiles;
  std::vector<float> packed;
  for (;;) {
    detail::send(message, owner, detail::tag_result, comm);
    MPI_Status status;
    check(MPI_Probe(owner, detail::tag_work, comm, &status), "MPI_Probe");
    int size = 0;
    check(MPI_Get_count(&status, MPI_BYTE, &size), "MPI_Get_count");
    buffer.resize(static_cast<std::size_t>(size));
    check(MPI_Recv(buffer.data(), size, MPI_BYTE, owner, detail::tag_work, comm, MPI_STATUS_IGNORE), "receiving tiles");
    Reader reply(buffer);
    if (reply.get<std::uint32_t>() != frame_id) continue;  // an answer to an abandoned frame
    const auto share = reply.get_vector<TileWork>();
    if (share.empty()) return;
    tiles.clear(), packed.clear();
    try {
      render_share(share, staging);
      for (const TileWork& work : share) {
        tiles.push_back(work.tile);
        staging.pack_tile(work.tile, packed);
      }
    } catch (const std::exception& e) {
      Writer failure;
      failure.put(frame_id);
      failure.put_string(e.what());
      detail::send(failure, owner, detail::tag_error, comm);
      return;
    }
    message.clear();
    message.put(frame_id);
    message.put<std::int32_t>(batch_tiles);
    message.put_span(std::span<const std::int32_t>(tiles));
    message.put_span(std::span<const float>(packed));
  }
}

/// A frame buffer's staging twin for work_frame.
inline FrameBuffer staging_for(int width, int height, unsigned channels) {
  return FrameBuffer(width, height, ColorFormat::rgba32f, detail::staging_channels(channels));
}

/// Image-parallel rendering of a scene every rank holds: each frame is a collective call
/// on the communicator, whose rank `owner` gets the image in its frame buffer and the
/// others render. The C++ face of what the mpiOffload device does through the C API.
class ImageParallel {
public:
  explicit ImageParallel(MPI_Comm comm, int owner = 0, Scheduling scheduling = scheduling_from_environment())
      : comm_(comm), owner_(owner), scheduling_(scheduling) {}

  bool owns_frames() const { return comm_.rank() == owner_; }
  int ranks() const { return comm_.size(); }
  MPI_Comm communicator() const { return comm_.get(); }

  /// Renders one frame (a collective call): the owner's `fb` accumulates it; the other
  /// ranks' `fb` (of the same size and channels) only gives the staging buffer's shape.
  /// Returns the traffic on the owner (empty elsewhere).
  template <class Arch, class Renderer, class CameraT>
  FrameTraffic render_frame(const Renderer& renderer, const CameraT& camera, FrameBuffer& fb,
                            const FrameSettings& settings = {}, FrameControl* control = nullptr) {
    return render_frame(
        fb, settings,
        [&](std::span<const TileWork> share, FrameBuffer& staging) {
          render_tiles<Arch>(renderer, camera, staging, share, nullptr, settings);
        },
        accumulate_tile, control);
  }

  /// render_frame for renderers reached another way (the shim's per-ISA render_tiles):
  /// the other ranks render their shares with `render_share`, the owner accumulates with
  /// `accumulate`.
  FrameTraffic render_frame(FrameBuffer& fb, const FrameSettings& settings, const RenderShare& render_share,
                            AccumulateTile accumulate = accumulate_tile, FrameControl* control = nullptr) {
    const std::uint32_t frame_id = next_frame_++;
    if (owns_frames())
      return serve_frame(comm_.get(), frame_id, fb, settings, scheduling_, control, accumulate, &early_);
    if (!staging_ || staging_->width() != fb.width() || staging_->height() != fb.height() ||
        staging_->packed_floats() != fb.packed_floats())
      staging_.emplace(staging_for(fb.width(), fb.height(), channels_of(fb)));
    const int batch =
        scheduling_.batch_tiles > 0 ? scheduling_.batch_tiles : 4 * tbb::this_task_arena::max_concurrency();
    work_frame(comm_.get(), owner_, frame_id, *staging_, render_share, batch);
    return {};
  }

private:
  static unsigned channels_of(const FrameBuffer& fb) {
    unsigned channels = 0;
    for (Channel c :
         {channel_depth, channel_normal, channel_albedo, channel_id_primitive, channel_id_object, channel_id_instance})
      if (fb.has(c)) channels |= c;
    return channels;
  }

  Communicator comm_;
  int owner_;
  Scheduling scheduling_;
  std::uint32_t next_frame_ = 0;
  std::optional<FrameBuffer> staging_;
  std::deque<EarlyMessage> early_;  ///< on the owner: requests for frames it has not started
};

}  // namespace sciray::mpi
