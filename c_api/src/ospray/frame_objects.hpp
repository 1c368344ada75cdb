#pragma once
// OSPFrameBuffer, OSPImageOperation and OSPFuture: a sciray frame buffer the application
// maps, the image operations it applies to its colour, and a frame rendered on a thread
// of its own that can be waited on, polled and cancelled.
#include <chrono>
#include <condition_variable>
#include <functional>
#include <thread>

#include "object.hpp"
#include "sciray/frame/framebuffer.hpp"
#include "sciray/frame/image_ops.hpp"
#include "sciray/frame/render_frame.hpp"

namespace sciray::ospray {

/// OSPRay's `tonemapper` image operation (exposure, contrast, shoulder, midIn, midOut,
/// hdrMax, acesColor) and its `debug` one (red set to 1); a frame buffer takes their
/// parameters at the frame buffer's commit. Uncommitted, an operation has its defaults
/// (OSPRay's test suite hands over a `debug` operation it never commits).
class ImageOperationObject : public Object {
public:
  explicit ImageOperationObject(const std::string& type)
      : Object(OSP_IMAGE_OPERATION, type),
        operation_(type == "debug" ? ImageOperation{DebugMark{}} : ImageOperation{Tonemapper{}}) {}
  const ImageOperation& operation() const { return operation_; }

protected:
  void on_commit() override;

private:
  ImageOperation operation_;
};

class FrameBufferObject : public Object {
public:
  FrameBufferObject(int width, int height, OSPFrameBufferFormat format, std::uint32_t channels);

  sciray::FrameBuffer& frame() { return frame_; }
  std::uint32_t channels() const { return channels_; }
  /// Serializes rendering into and mapping of this frame buffer.
  std::mutex& mutex() { return mutex_; }

  const void* map(OSPFrameBufferChannel channel);
  void unmap(const void* mapped);

protected:
  /// Reads `imageOperation` (an OSPData of committed OSPImageOperation) and hands the
  /// operations to the frame buffer, which redoes its colour output with them.
  void on_commit() override;

private:
  sciray::FrameBuffer frame_;
  std::uint32_t channels_;
  std::mutex mutex_;
  std::multiset<const void*> mapped_;
};

class Future : public Object {
public:
  /// Starts `task` on its own thread; it receives the frame control for progress and cancel.
  explicit Future(std::function<void(FrameControl&)> task);
  ~Future() override;

  bool ready() const;
  void wait();
  void cancel() { control_.cancel = true; }
  /// 1 once a frame completed; a cancelled frame stays at the fraction it reached.
  float progress() const { return ready() && !control_.cancel ? 1.f : control_.progress(); }
  float duration_seconds() const;

private:
  FrameControl control_;
  mutable std::mutex mutex_;
  std::condition_variable done_signal_;
  bool done_ = false;
  std::chrono::steady_clock::time_point start_, end_;
  std::thread thread_;
};

}  // namespace sciray::ospray
