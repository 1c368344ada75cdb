// sciray's OSPRay C++ wrapper: ImageOperation, made by type name or adopting an existing OSPImageOperation.
#pragma once

#include "ManagedObject.h"

namespace ospray {
namespace cpp {

class ImageOperation : public ManagedObject<OSPImageOperation, OSP_IMAGE_OPERATION> {
public:
  ImageOperation(const std::string& typeName) : ManagedObject(ospNewImageOperation(typeName.c_str())) {}
  ImageOperation(OSPImageOperation existing = nullptr) : ManagedObject(existing) {}
};
SCIRAY_OSP_CPP_CHECK_LAYOUT(ImageOperation, OSPImageOperation);

}  // namespace cpp

OSPTYPEFOR_SPECIALIZATION(cpp::ImageOperation, OSP_IMAGE_OPERATION)

}  // namespace ospray
