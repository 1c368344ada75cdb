// sciray's OSPRay C++ wrapper: Instance, a group placed in the world by a transform.
#pragma once

#include "Group.h"

namespace ospray {
namespace cpp {

class Instance : public ManagedObject<OSPInstance, OSP_INSTANCE> {
public:
  Instance(const Group& group) : Instance(group.handle()) {}
  Instance(OSPGroup group) : ManagedObject(ospNewInstance(group)) {}
  Instance(OSPInstance existing = nullptr) : ManagedObject(existing) {}
};
SCIRAY_OSP_CPP_CHECK_LAYOUT(Instance, OSPInstance);

}  // namespace cpp

OSPTYPEFOR_SPECIALIZATION(cpp::Instance, OSP_INSTANCE)

}  // namespace ospray
