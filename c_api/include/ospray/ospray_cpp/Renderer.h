// sciray's OSPRay C++ wrapper: Renderer, made by type name or adopting an existing OSPRenderer.
#pragma once

#include "ManagedObject.h"

namespace ospray {
namespace cpp {

class Renderer : public ManagedObject<OSPRenderer, OSP_RENDERER> {
public:
  Renderer(const std::string& typeName) : ManagedObject(ospNewRenderer(typeName.c_str())) {}
  Renderer(OSPRenderer existing = nullptr) : ManagedObject(existing) {}
};
SCIRAY_OSP_CPP_CHECK_LAYOUT(Renderer, OSPRenderer);

}  // namespace cpp

OSPTYPEFOR_SPECIALIZATION(cpp::Renderer, OSP_RENDERER)

}  // namespace ospray
