#pragma once
// RAII over Embree's device and scene. Embree reports errors through a callback; the
// device records the message and `check` turns it into a sciray::Error naming the
// operation, so no Embree failure passes silently. A memory monitor counts the bytes
// Embree holds (BVH and its own buffers) for the memory figures sciray reports. Instances
// get their (possibly moving) transforms from set_transform.
#include <array>
#include <atomic>
#include <memory>
#include <mutex>
#include <string>
#include <string_view>
#include <utility>

#include <sys/types.h>

#include <embree3/rtcore.h>

#include "sciray/error.hpp"
#include "sciray/math/box.hpp"
#include "sciray/math/motion.hpp"

namespace sciray::accel {

class Device {
public:
  /// `config` is Embree's device configuration string (e.g. "threads=4"); empty for
  /// defaults. Embree runs its builds on the TBB arena of the calling thread.
  explicit Device(const std::string& config = {}) : state_(std::make_unique<State>()) {
    device_ = rtcNewDevice(config.empty() ? nullptr : config.c_str());
    if (!device_) throw Error("embree: cannot create device (config '" + config + "')");
    rtcSetDeviceErrorFunction(device_, &Device::on_error, state_.get());
    rtcSetDeviceMemoryMonitorFunction(device_, &Device::on_memory, state_.get());
  }
  ~Device() {
    if (device_) rtcReleaseDevice(device_);
  }
  Device(const Device&) = delete;
  Device& operator=(const Device&) = delete;

  RTCDevice get() const { return device_; }

  /// Throws if Embree reported an error since the last check.
  void check(std::string_view operation) const {
    if (rtcGetDeviceError(device_) == RTC_ERROR_NONE) return;
    std::string message;
    {
      std::lock_guard lock(state_->mutex);
      message = std::move(state_->last_error);
      state_->last_error.clear();
    }
    throw Error("embree: " + std::string(operation) + " failed: " + message);
  }

  /// Bytes Embree currently holds for all scenes of this device.
  std::int64_t bytes_in_use() const { return state_->bytes.load(std::memory_order_relaxed); }

  /// How far the BVH build in progress on this device is, in [0, 1] (Embree's progress
  /// monitor; each scene's build, a group's and the top level's, goes from 0 to 1 in turn).
  double build_progress() const { return state_->build_progress.load(std::memory_order_relaxed); }

  /// Reports `scene`'s builds through build_progress().
  void watch_builds(RTCScene scene) const {
    rtcSetSceneProgressMonitorFunction(scene, &Device::on_build_progress, state_.get());
  }

private:
  struct State {
    std::atomic<std::int64_t> bytes{0};
    std::atomic<double> build_progress{0.0};
    std::mutex mutex;
    std::string last_error;
  };

  static void on_error(void* user, RTCError, const char* message) {
    auto* state = static_cast<State*>(user);
    std::lock_guard lock(state->mutex);
    state->last_error = message ? message : "unknown error";
  }
  static bool on_build_progress(void* user, double fraction) {
    static_cast<State*>(user)->build_progress.store(fraction, std::memory_order_relaxed);
    return true;  // never cancels the build
  }
  static bool on_memory(void* user, ssize_t bytes, bool) {
    static_cast<State*>(user)->bytes.fetch_add(bytes, std::memory_order_relaxed);
    return true;
  }

  RTCDevice device_ = nullptr;
  std::unique_ptr<State> state_;  // stable address for Embree's callbacks
};

class Scene {
public:
  explicit Scene(const Device& device) : device_(&device), scene_(rtcNewScene(device.get())) {
    device.check("rtcNewScene");
    device.watch_builds(scene_);
  }
  ~Scene() {
    if (scene_) rtcReleaseScene(scene_);
  }
  Scene(Scene&& other) noexcept : device_(other.device_), scene_(std::exchange(other.scene_, nullptr)) {}
  Scene& operator=(Scene&& other) noexcept {
    std::swap(device_, other.device_);
    std::swap(scene_, other.scene_);
    return *this;
  }
  Scene(const Scene&) = delete;
  Scene& operator=(const Scene&) = delete;

  RTCScene get() const { return scene_; }
  const Device& device() const { return *device_; }

  /// Attaches a committed geometry; the scene keeps its own reference.
  unsigned attach(RTCGeometry geometry) {
    const unsigned id = rtcAttachGeometry(scene_, geometry);
    device_->check("rtcAttachGeometry");
    return id;
  }

  void commit() {
    rtcCommitScene(scene_);
    device_->check("rtcCommitScene");
  }

  Box3f bounds() const {
    RTCBounds b;
    rtcGetSceneBounds(scene_, &b);
    Box3f box;
    if (b.lower_x <= b.upper_x) box = {{b.lower_x, b.lower_y, b.lower_z}, {b.upper_x, b.upper_y, b.upper_z}};
    return box;
  }

private:
  const Device* device_;
  RTCScene scene_;
};

/// Owns one reference to an Embree geometry until it is attached to a scene.
class GeometryHandle {
public:
  GeometryHandle(const Device& device, RTCGeometryType type) : geometry_(rtcNewGeometry(device.get(), type)) {
    device.check("rtcNewGeometry");
  }
  ~GeometryHandle() {
    if (geometry_) rtcReleaseGeometry(geometry_);
  }
  GeometryHandle(const GeometryHandle&) = delete;
  GeometryHandle& operator=(const GeometryHandle&) = delete;
  RTCGeometry get() const { return geometry_; }

  /// Commits the geometry and hands its reference to the caller (to attach and release).
  RTCGeometry commit(const Device& device, std::string_view what) {
    rtcCommitGeometry(geometry_);
    device.check(std::string(what) + ": rtcCommitGeometry");
    return std::exchange(geometry_, nullptr);
  }

private:
  RTCGeometry geometry_;
};

/// Sets an instance geometry's transform: one matrix, or the keys over their time range
/// (Embree interpolates them itself, as MotionTransform::at does).
inline void set_transform(RTCGeometry geometry, const MotionTransform& motion) {
  const auto columns = [](const Affine3f& m) {
    return std::array<float, 12>{m.vx.x, m.vx.y, m.vx.z, m.vy.x, m.vy.y, m.vy.z,
                                 m.vz.x, m.vz.y, m.vz.z, m.p.x,  m.p.y,  m.p.z};
  };
  const auto keys = static_cast<unsigned>(motion.key_count());
  rtcSetGeometryTimeStepCount(geometry, keys);
  for (unsigned k = 0; k < keys; ++k) {
    if (motion.quaternion()) {
      const QuaternionDecomposition& d = motion.decompositions()[k];
      RTCQuaternionDecomposition q;
      rtcInitQuaternionDecomposition(&q);
      rtcQuaternionDecompositionSetScale(&q, d.scale.x, d.scale.y, d.scale.z);
      rtcQuaternionDecompositionSetSkew(&q, d.skew.x, d.skew.y, d.skew.z);
      rtcQuaternionDecompositionSetShift(&q, d.shift.x, d.shift.y, d.shift.z);
      rtcQuaternionDecompositionSetQuaternion(&q, d.rotation.r, d.rotation.i, d.rotation.j, d.rotation.k);
      rtcQuaternionDecompositionSetTranslation(&q, d.translation.x, d.translation.y, d.translation.z);
      rtcSetGeometryTransformQuaternion(geometry, k, &q);
    } else {
      const auto m = columns(motion.matrices()[k]);
      rtcSetGeometryTransform(geometry, k, RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, m.data());
    }
  }
  if (motion.moving()) rtcSetGeometryTimeRange(geometry, motion.start(), motion.end());
}

}  // namespace sciray::accel
