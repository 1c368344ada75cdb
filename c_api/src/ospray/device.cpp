#include "device.hpp"

#include <cstdio>

#include <tbb/info.h>

#include "mpi/distributed.hpp"
#include "mpi/offload.hpp"

namespace sciray::ospray {

Device::Device(DeviceType type) : type_(type) { commit(); }

Device::~Device() = default;

void Device::start_mpi(const std::function<void()>& make_current) {
  if (type_ == DeviceType::mpi_offload && !offload_) offload_ = offload::start(*this, make_current);
  if (type_ == DeviceType::mpi_distributed && !distributed_) distributed_ = distributed::start();
}

void Device::set_param(const std::string& id, OSPDataType type, const void* mem) {
  if (!mem) throw Error("device: parameter '" + id + "': value pointer is NULL");
  const auto as_int = [&]() -> int {
    if (type == OSP_INT || type == OSP_UINT) return *static_cast<const std::int32_t*>(mem);
    if (type == OSP_BOOL) return *static_cast<const bool*>(mem) ? 1 : 0;
    throw Error("device: parameter '" + id + "' must be an int, got " + type_name(type));
  };
  if (id == "numThreads") {
    staged_.num_threads = as_int();
    if (staged_.num_threads < 0) throw Error("device: parameter 'numThreads' must not be negative");
  } else if (id == "logLevel") {
    if (type == OSP_STRING) {
      const std::string level = static_cast<const char*>(mem);
      const char* names[] = {"debug", "info", "warning", "error", "none"};
      int found = 0;
      for (int i = 0; i < 5; ++i)
        if (level == names[i]) found = i + 1;
      if (!found) throw Error("device: parameter 'logLevel': unknown level '" + level + "'");
      staged_.log_level = found;
    } else {
      staged_.log_level = as_int();
    }
  } else if (id == "warnAsError") {
    staged_.warn_as_error = as_int() != 0;
  } else if (id == "debug") {
    if (as_int()) staged_.log_level = OSP_LOG_DEBUG, staged_.num_threads = 1;
  } else if (id == "isa") {
    if (type != OSP_STRING) throw Error("device: parameter 'isa' must be a string, got " + type_name(type));
    staged_.isa = static_cast<const char*>(mem);
  } else {
    warn("device: unknown parameter '" + id + "' ignored");
  }
}

void Device::remove_param(const std::string& id) {
  const Params defaults;
  if (id == "numThreads") staged_.num_threads = defaults.num_threads;
  if (id == "logLevel") staged_.log_level = defaults.log_level;
  if (id == "warnAsError") staged_.warn_as_error = defaults.warn_as_error;
  if (id == "isa") staged_.isa = defaults.isa;
}

void Device::commit() {
  // Resolve the ISA first: a request the CPU cannot run leaves the device as it was.
  const shim::IsaKernels& kernels = shim::kernels(shim::select_isa(staged_.isa));
  committed_ = staged_;
  kernels_ = &kernels;
  threads_ = committed_.num_threads > 0 ? committed_.num_threads : tbb::info::default_concurrency();
  arena_ = std::make_unique<tbb::task_arena>(threads_);
  status(OSP_LOG_INFO, "sciray device: ISA " + std::string(simd::isa_name(kernels.isa)) + ", " +
                           std::to_string(threads_) + " threads");
}

void Device::error(OSPError code, const std::string& message) {
  last_error_ = code;
  last_message_ = message;
  if (error_cb_)
    error_cb_(error_user_, code, message.c_str());
  else
    std::fprintf(stderr, "sciray: OSPRay API error: %s\n", message.c_str());
}

void Device::warn(const std::string& message) {
  if (committed_.warn_as_error)
    error(OSP_INVALID_OPERATION, message);
  else
    status(OSP_LOG_WARNING, message);
}

void Device::status(OSPLogLevel level, const std::string& message) {
  if (static_cast<int>(level) < committed_.log_level || !status_cb_) return;
  status_cb_(status_user_, (message + "\n").c_str());
}

}  // namespace sciray::ospray
