// sciray's OSPRay C++ wrapper: Group, models (geometric, volumetric, clipping) placed together.
#pragma once

#include "ManagedObject.h"

namespace ospray {
namespace cpp {

// Unlike the typed objects, constructing a Group without arguments makes a new group.
class Group : public ManagedObject<OSPGroup, OSP_GROUP> {
public:
  Group() : ManagedObject(ospNewGroup()) {}
  Group(OSPGroup existing) : ManagedObject(existing) {}
};
SCIRAY_OSP_CPP_CHECK_LAYOUT(Group, OSPGroup);

}  // namespace cpp

OSPTYPEFOR_SPECIALIZATION(cpp::Group, OSP_GROUP)

}  // namespace ospray
