// sciray's OSPRay C++ wrapper: Camera, made by type name or adopting an existing OSPCamera.
#pragma once

#include "ManagedObject.h"

namespace ospray {
namespace cpp {

class Camera : public ManagedObject<OSPCamera, OSP_CAMERA> {
public:
  Camera(const std::string& typeName) : ManagedObject(ospNewCamera(typeName.c_str())) {}
  Camera(OSPCamera existing = nullptr) : ManagedObject(existing) {}
};
SCIRAY_OSP_CPP_CHECK_LAYOUT(Camera, OSPCamera);

}  // namespace cpp

OSPTYPEFOR_SPECIALIZATION(cpp::Camera, OSP_CAMERA)

}  // namespace ospray
