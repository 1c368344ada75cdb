// sciray's OSPRay C++ wrapper: Volume, made by type name or adopting an existing OSPVolume.
#pragma once

#include "ManagedObject.h"

namespace ospray {
namespace cpp {

class Volume : public ManagedObject<OSPVolume, OSP_VOLUME> {
public:
  Volume(const std::string& typeName) : ManagedObject(ospNewVolume(typeName.c_str())) {}
  Volume(OSPVolume existing = nullptr) : ManagedObject(existing) {}
};
SCIRAY_OSP_CPP_CHECK_LAYOUT(Volume, OSPVolume);

}  // namespace cpp

OSPTYPEFOR_SPECIALIZATION(cpp::Volume, OSP_VOLUME)

}  // namespace ospray
