#pragma once
// OSPDevice: parameters (numThreads, logLevel, warnAsError, isa), the error and status
// callbacks with their user pointers, the last error, and the thread arena and ISA
// kernels every frame of this device runs with. The MPI types add their session once
// committed: `mpiOffload` on the application's rank forwards its calls to the workers
// (mpi/offload.hpp), `mpiDistributed` composites every rank's frame (mpi/distributed.hpp).
#include <atomic>
#include <functional>
#include <memory>
#include <string>

#include <tbb/task_arena.h>

#include "object.hpp"
#include "sciray/shim/engine.hpp"

namespace sciray::ospray {

namespace offload {
class Session;
}
namespace distributed {
class Session;
}

/// The device types: `cpu` (also `default`), and with MPI `mpiOffload` (image-parallel,
/// the application on rank 0) and `mpiDistributed` (data-parallel: every rank renders
/// its own part of the world).
enum class DeviceType { cpu, mpi_offload, mpi_distributed };

class Device {
public:
  explicit Device(DeviceType type = DeviceType::cpu);
  ~Device();

  DeviceType type() const { return type_; }
  /// The mpiOffload session on the application's rank once the device is committed; null
  /// for the other types.
  offload::Session* offload() const { return offload_.get(); }
  /// The mpiDistributed session once the device is committed; null for the other types.
  distributed::Session* distributed() const { return distributed_.get(); }
  /// Starts an MPI device's session (at its first commit). An mpiOffload device's workers
  /// do not return: they make the device current, serve the application and end the process.
  void start_mpi(const std::function<void()>& make_current);

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

  DeviceType type_;
  std::unique_ptr<offload::Session> offload_;
  std::unique_ptr<distributed::Session> distributed_;
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
