// sciray's OSPRay C++ wrapper: Device. Devices have their own reference counting in the C
// API (ospDeviceRetain/Release), so this wrapper is not a ManagedObject, but it owns its
// handle the same way: copies retain, destruction releases, moves transfer.
#pragma once

#include <string>
#include <utility>

#include "../ospray.h"
#include "Traits.h"

namespace ospray {
namespace cpp {

class Device {
public:
  // A new device of the given type ("cpu"); commit it and make it current to use it.
  Device(const std::string& deviceType = "cpu") : ospHandle(ospNewDevice(deviceType.c_str())) {}
  // Adopts an existing handle (without retaining it).
  Device(OSPDevice existing) : ospHandle(existing) {}
  ~Device() { ospDeviceRelease(ospHandle); }

  Device(const Device& other) : ospHandle(other.ospHandle) { ospDeviceRetain(ospHandle); }
  Device(Device&& other) : ospHandle(other.ospHandle) { other.ospHandle = nullptr; }

  Device& operator=(const Device& other) {
    ospDeviceRetain(other.ospHandle);  // before the release: self-assignment keeps the device
    ospDeviceRelease(ospHandle);
    ospHandle = other.ospHandle;
    return *this;
  }
  Device& operator=(Device&& other) {
    if (this != &other) {
      ospDeviceRelease(ospHandle);
      ospHandle = other.ospHandle;
      other.ospHandle = nullptr;
    }
    return *this;
  }

  // Callbacks are plain functions (or lambdas without captures) of OSPErrorCallback's and
  // OSPStatusCallback's signatures; their user pointer is NULL.
  template <typename FCN_T>
  void setErrorCallback(FCN_T&& callback) {
    ospDeviceSetErrorCallback(ospHandle, std::forward<FCN_T>(callback), nullptr);
  }
  template <typename FCN_T>
  void setStatusCallback(FCN_T&& callback) {
    ospDeviceSetStatusCallback(ospHandle, std::forward<FCN_T>(callback), nullptr);
  }

  template <typename T>
  void setParam(const std::string& name, const T& value) const {
    static_assert(OSPTypeFor<T>::value != OSP_UNKNOWN, "Device::setParam: this type has no OSPDataType");
    ospDeviceSetParam(ospHandle, name.c_str(), OSPTypeFor<T>::value, &value);
  }
  void setParam(const std::string& name, const char* value) const {
    ospDeviceSetParam(ospHandle, name.c_str(), OSP_STRING, value);
  }
  void setParam(const std::string& name, const std::string& value) const {
    ospDeviceSetParam(ospHandle, name.c_str(), OSP_STRING, value.c_str());
  }
  void setParam(const std::string& name, OSPDataType paramType, const void* memory) const {
    ospDeviceSetParam(ospHandle, name.c_str(), paramType, memory);
  }
  void removeParam(const std::string& name) const { ospDeviceRemoveParam(ospHandle, name.c_str()); }

  void commit() const { ospDeviceCommit(ospHandle); }
  void setCurrent() const { ospSetCurrentDevice(ospHandle); }
  // The current device (ospGetCurrentDevice hands out a reference of its own).
  static Device current() { return Device(ospGetCurrentDevice()); }

  OSPDevice handle() const { return ospHandle; }

private:
  OSPDevice ospHandle;
};

}  // namespace cpp

OSPTYPEFOR_SPECIALIZATION(cpp::Device, OSP_DEVICE)

}  // namespace ospray
