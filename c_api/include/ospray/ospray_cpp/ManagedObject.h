// sciray's OSPRay C++ wrapper: ManagedObject, the base of every object wrapper. It holds
// one reference to an OSPRay handle: copies retain, destruction releases, moves transfer.
// The handle is its only member, so a wrapper has the handle's size and layout; that is
// what lets setParam and Data pass a wrapper's address where OSPRay expects a handle's.
#pragma once

#include <cstring>
#include <string>
#include <type_traits>

#include "../ospray.h"
#include "Traits.h"

namespace ospray {
namespace cpp {

template <typename HANDLE_T = OSPObject, OSPDataType TYPE = OSP_OBJECT>
class ManagedObject {
  static_assert(std::is_same<HANDLE_T, OSPObject>::value ||
                    std::is_base_of<osp::ManagedObject, typename std::remove_pointer<HANDLE_T>::type>::value,
                "ManagedObject wraps OSPObject or one of the OSP* handle types");

public:
  static constexpr OSPDataType type = TYPE;

  // Adopts `object`: the wrapper owns the reference it was given (it does not retain).
  ManagedObject(HANDLE_T object = nullptr) : ospObject(object) {}
  ~ManagedObject() { ospRelease(ospObject); }

  ManagedObject(const ManagedObject& other) : ospObject(other.ospObject) {
    if (ospObject) ospRetain(ospObject);
  }
  ManagedObject(ManagedObject&& other) : ospObject(other.ospObject) { other.ospObject = nullptr; }

  ManagedObject& operator=(const ManagedObject& other) {
    // Retain before releasing, so that assigning an object to itself keeps it alive.
    if (other.ospObject) ospRetain(other.ospObject);
    ospRelease(ospObject);
    ospObject = other.ospObject;
    return *this;
  }
  ManagedObject& operator=(ManagedObject&& other) {
    if (this != &other) {
      ospRelease(ospObject);
      ospObject = other.ospObject;
      other.ospObject = nullptr;
    }
    return *this;
  }

  template <typename T>
  void setParam(const std::string& name, const T& value) const {
    static_assert(OSPTypeFor<T>::value != OSP_UNKNOWN,
                  "setParam: this type has no OSPDataType; vector, box and matrix types need an "
                  "OSPTypeFor specialization (include ospray/ospray_cpp/ext/glm.h or ext/rkcommon.h, "
                  "or use OSPTYPEFOR_SPECIALIZATION)");
    ospSetParam(ospObject, name.c_str(), OSPTypeFor<T>::value, &value);
  }
  void setParam(const std::string& name, const char* value) const {
    ospSetParam(ospObject, name.c_str(), OSP_STRING, value);
  }
  void setParam(const std::string& name, const std::string& value) const {
    ospSetParam(ospObject, name.c_str(), OSP_STRING, value.c_str());
  }
  // The escape hatch: the caller names the type of what `memory` points to.
  void setParam(const std::string& name, OSPDataType paramType, const void* memory) const {
    ospSetParam(ospObject, name.c_str(), paramType, memory);
  }

  void removeParam(const std::string& name) const { ospRemoveParam(ospObject, name.c_str()); }

  // The object's bounds (of a committed world, instance, group, model, geometry or volume)
  // as the application's box type, which must be six floats: lower then upper corner.
  template <typename BOX3F_T>
  BOX3F_T getBounds() const {
    static_assert(OSPTypeFor<BOX3F_T>::value == OSP_BOX3F,
                  "getBounds: the box type must be declared OSP_BOX3F with OSPTYPEFOR_SPECIALIZATION");
    static_assert(sizeof(BOX3F_T) == sizeof(OSPBounds), "getBounds: a box3f is six floats");
    const OSPBounds bounds = ospGetBounds(ospObject);
    BOX3F_T box;
    std::memcpy(static_cast<void*>(&box), &bounds, sizeof(bounds));
    return box;
  }

  void commit() const { ospCommit(ospObject); }

  HANDLE_T handle() const { return ospObject; }

  // Whether the wrapper holds an object (a failed factory yields NULL).
  operator bool() const { return ospObject != nullptr; }

protected:
  HANDLE_T ospObject;
};

// Every wrapper adds behaviour, never data: it must stay laid out as its handle.
#define SCIRAY_OSP_CPP_CHECK_LAYOUT(wrapper, handle_type)                                          \
  static_assert(sizeof(wrapper) == sizeof(handle_type) && std::is_standard_layout<wrapper>::value, \
                #wrapper " must be laid out as its handle: it is passed where OSPRay expects one")

}  // namespace cpp
}  // namespace ospray
