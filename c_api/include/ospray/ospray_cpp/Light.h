// sciray's OSPRay C++ wrapper: Light, made by type name or adopting an existing OSPLight.
#pragma once

#include "ManagedObject.h"

namespace ospray {
namespace cpp {

class Light : public ManagedObject<OSPLight, OSP_LIGHT> {
public:
  Light(const std::string& typeName) : ManagedObject(ospNewLight(typeName.c_str())) {}
  Light(OSPLight existing = nullptr) : ManagedObject(existing) {}
};
SCIRAY_OSP_CPP_CHECK_LAYOUT(Light, OSPLight);

}  // namespace cpp

OSPTYPEFOR_SPECIALIZATION(cpp::Light, OSP_LIGHT)

}  // namespace ospray
