// sciray's OSPRay C++ wrapper: VolumetricModel, a volume's appearance (transfer function, density).
#pragma once

#include "TransferFunction.h"
#include "Volume.h"

namespace ospray {
namespace cpp {

class VolumetricModel : public ManagedObject<OSPVolumetricModel, OSP_VOLUMETRIC_MODEL> {
public:
  VolumetricModel(const Volume& volume) : VolumetricModel(volume.handle()) {}
  VolumetricModel(OSPVolume volume) : ManagedObject(ospNewVolumetricModel(volume)) {}
  VolumetricModel(OSPVolumetricModel existing = nullptr) : ManagedObject(existing) {}
};
SCIRAY_OSP_CPP_CHECK_LAYOUT(VolumetricModel, OSPVolumetricModel);

}  // namespace cpp

OSPTYPEFOR_SPECIALIZATION(cpp::VolumetricModel, OSP_VOLUMETRIC_MODEL)

}  // namespace ospray
