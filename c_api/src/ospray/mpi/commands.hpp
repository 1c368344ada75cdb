#pragma once
// The calls the mpiOffload device forwards from the application's rank to its workers.
// The application's rank keeps a full replica of the scene (so that errors, bounds and
// picks answer at once, as on one process) and records each call that changed state
// after it succeeded there; the records are batched and sent when a frame starts, and
// every worker replays them in order through the same API. Data arrays travel once,
// compacted, when created (and again when the application commits one it shares, the
// way to tell OSPRay its memory changed). Handles travel as the application rank's values;
// each worker maps them to its own objects.
#include <ospray/ospray.h>

#include <cstdint>
#include <functional>
#include <mutex>
#include <span>
#include <string>
#include <unordered_map>
#include <vector>

#include "sciray/mpi/wire.hpp"

namespace sciray::ospray {
class Data;
}

namespace sciray::ospray::offload {

class CommandLog {
public:
  /// ospNew<Kind>(type) returned `handle` (kind OSP_GROUP or OSP_WORLD: no type).
  void new_object(OSPDataType kind, const std::string& type, const void* handle);
  /// ospNewGeometricModel, ospNewVolumetricModel, ospNewInstance of `content` (may be NULL).
  void new_holder(OSPDataType kind, const void* handle, const void* content);
  void new_frame_buffer(const void* handle, int width, int height, OSPFrameBufferFormat format, std::uint32_t channels);
  /// ospNewData / ospNewSharedData: the array's elements, compacted.
  void new_data(const void* handle, const Data& data);
  /// The application committed a shared array: its elements may have changed.
  void update_data(const void* handle, const Data& data);
  void copy_data(const void* source, const void* destination, std::uint64_t i1, std::uint64_t i2, std::uint64_t i3);
  void set_param(const void* handle, const char* id, OSPDataType type, const void* value);
  void remove_param(const void* handle, const char* id);
  void commit(const void* handle);
  void release(const void* handle);
  void retain(const void* handle);
  void render_frame(const void* fb, const void* renderer, const void* camera, const void* world,
                    std::uint32_t frame_id);
  void shutdown();

  /// The batch recorded since the last take (the log is left empty).
  std::vector<std::byte> take();

private:
  std::mutex mutex_;
  mpi::Writer out_;
  /// A hash of the elements last sent of each shared array: a commit that changed
  /// nothing sends nothing again.
  std::unordered_map<const void*, std::uint64_t> sent_elements_;
};

/// A worker's side: replays batches through the API onto the current (local) device.
class Replayer {
public:
  /// Renders a frame with the worker's handles; the frame's id pairs it with the owner's.
  using RenderFrame = std::function<void(OSPFrameBuffer, OSPRenderer, OSPCamera, OSPWorld, std::uint32_t)>;

  /// Replays one batch; false once it held `shutdown`.
  bool replay(std::span<const std::byte> batch, const RenderFrame& render_frame);

private:
  OSPObject local(std::uint64_t handle) const;
  void add(std::uint64_t handle, OSPObject object);
  /// Elements as the worker's array holds them: object handles translated.
  std::vector<std::byte> local_elements(OSPDataType type, std::vector<std::byte> elements) const;

  std::unordered_map<std::uint64_t, OSPObject> handles_;
  /// The memory of each array the worker created (shared with it until its deleter runs).
  std::unordered_map<std::uint64_t, std::vector<std::byte>*> array_memory_;
};

}  // namespace sciray::ospray::offload
