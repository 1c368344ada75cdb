// sciray's OSPRay C++ wrapper: GeometricModel, a geometry's appearance (material, colours).
#pragma once

#include "Geometry.h"
#include "Material.h"

namespace ospray {
namespace cpp {

class GeometricModel : public ManagedObject<OSPGeometricModel, OSP_GEOMETRIC_MODEL> {
public:
  GeometricModel(const Geometry& geometry) : GeometricModel(geometry.handle()) {}
  GeometricModel(OSPGeometry geometry) : ManagedObject(ospNewGeometricModel(geometry)) {}
  GeometricModel(OSPGeometricModel existing = nullptr) : ManagedObject(existing) {}
};
SCIRAY_OSP_CPP_CHECK_LAYOUT(GeometricModel, OSPGeometricModel);

}  // namespace cpp

OSPTYPEFOR_SPECIALIZATION(cpp::GeometricModel, OSP_GEOMETRIC_MODEL)

}  // namespace ospray
