// sciray's OSPRay C++ wrapper: Material, made by type name or adopting an existing OSPMaterial.
#pragma once

#include "ManagedObject.h"

namespace ospray {
namespace cpp {

class Material : public ManagedObject<OSPMaterial, OSP_MATERIAL> {
public:
  Material(const std::string& typeName) : ManagedObject(ospNewMaterial(typeName.c_str())) {}
  Material(OSPMaterial existing = nullptr) : ManagedObject(existing) {}
};
SCIRAY_OSP_CPP_CHECK_LAYOUT(Material, OSPMaterial);

}  // namespace cpp

OSPTYPEFOR_SPECIALIZATION(cpp::Material, OSP_MATERIAL)

}  // namespace ospray
