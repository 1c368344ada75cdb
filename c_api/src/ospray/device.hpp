#pragma once
// OSPDevice: parameters (numThreads, logLevel, warnAsError, isa), the error and status
// callbacks with their user pointers, the last error, and the thread arena and ISA
// kernels every frame of this device runs with.
#include <atomic>
#include <memory>
#include <string>

#include <tbb/task_arena.h>

#include "object.hpp"
#include "sciray/shim/engine.hpp"

namespace sciray::ospray {

class Device {
public:
  Device();

  void set_param(const std::string& id, OSPDataType type, const void* mem);
  void remove_param(const std::string& id);
  void commit();

  void retain() { ++refs_; }
  bool release() { return --refs_ == 0; }

  void set_error_callback(OSPErrorCallback cb, void* user) { error_cb_ = cb, error_user_ = user; }
  void set_status_callback(OSPStatusCallback cb, void* user) { status_cb_ = cb, status_user_ = user; }

  /// Records and reports an error through the callback (stderr if none is set).
  void error(OSPError code, const std::string& message);
  /// Reports a warning through the status callback, or as an error with warnAsError.
  void warn(const std::string& message);
  void status(OSPLogLevel level, const std::string& message);
  /// Whether messages of `level` reach the status callback.
  bool logs(OSPLogLevel level) const { return status_cb_ && static_cast<int>(level) >= committed_.log_level; }

  OSPError last_error_code() const { return last_error_; }
  const char* last_error_message() const { return last_message_.c_str(); }

  tbb::task_arena& arena() { return *arena_; }
  const shim::IsaKernels& kernels() const { return *kernels_; }
  int threads() const { return threads_; }

private:
  struct Params {
    int num_threads = 0;
    int log_level = OSP_LOG_WARNING;
    bool warn_as_error = false;
    std::string isa;
  };

  std::atomic<int> refs_{1};
  Params staged_, committed_;
  OSPErrorCallback error_cb_ = nullptr;
  void* error_user_ = nullptr;
  OSPStatusCallback status_cb_ = nullptr;
  void* status_user_ = nullptr;
  OSPError last_error_ = OSP_NO_ERROR;
  std::string last_message_;
  int threads_ = 0;
  std::unique_ptr<tbb::task_arena> arena_;
  const shim::IsaKernels* kernels_ = nullptr;
};

}  // namespace sciray::ospray
