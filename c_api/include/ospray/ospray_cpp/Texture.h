// sciray's OSPRay C++ wrapper: Texture, made by type name or adopting an existing OSPTexture.
#pragma once

#include "ManagedObject.h"

namespace ospray {
namespace cpp {

class Texture : public ManagedObject<OSPTexture, OSP_TEXTURE> {
public:
  Texture(const std::string& typeName) : ManagedObject(ospNewTexture(typeName.c_str())) {}
  Texture(OSPTexture existing = nullptr) : ManagedObject(existing) {}
};
SCIRAY_OSP_CPP_CHECK_LAYOUT(Texture, OSPTexture);

}  // namespace cpp

OSPTYPEFOR_SPECIALIZATION(cpp::Texture, OSP_TEXTURE)

}  // namespace ospray
