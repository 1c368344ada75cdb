// sciray's OSPRay C++ wrapper: World, the instances and lights a frame renders.
#pragma once

#include "Instance.h"

namespace ospray {
namespace cpp {

// Constructing a World without arguments makes a new world.
class World : public ManagedObject<OSPWorld, OSP_WORLD> {
public:
  World() : ManagedObject(ospNewWorld()) {}
  World(OSPWorld existing) : ManagedObject(existing) {}
};
SCIRAY_OSP_CPP_CHECK_LAYOUT(World, OSPWorld);

}  // namespace cpp

OSPTYPEFOR_SPECIALIZATION(cpp::World, OSP_WORLD)

}  // namespace ospray
