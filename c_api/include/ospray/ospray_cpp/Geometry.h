// sciray's OSPRay C++ wrapper: Geometry, made by type name or adopting an existing OSPGeometry.
#pragma once

#include "ManagedObject.h"

namespace ospray {
namespace cpp {

class Geometry : public ManagedObject<OSPGeometry, OSP_GEOMETRY> {
public:
  Geometry(const std::string& typeName) : ManagedObject(ospNewGeometry(typeName.c_str())) {}
  Geometry(OSPGeometry existing = nullptr) : ManagedObject(existing) {}
};
SCIRAY_OSP_CPP_CHECK_LAYOUT(Geometry, OSPGeometry);

}  // namespace cpp

OSPTYPEFOR_SPECIALIZATION(cpp::Geometry, OSP_GEOMETRY)

}  // namespace ospray
