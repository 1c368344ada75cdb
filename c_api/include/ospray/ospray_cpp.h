// sciray's OSPRay C++ wrapper: header-only classes over the OSPRay 3 C API (ospray.h), with
// the names, signatures and semantics of OSPRay's own ospray_cpp. One include for all of it.
// Vector types of glm or rkcommon become parameter and data types with ext/glm.h or
// ext/rkcommon.h. See docs/c-api.md for what differs from OSPRay's.
#pragma once

#include "ospray_cpp/Camera.h"
#include "ospray_cpp/Data.h"
#include "ospray_cpp/Device.h"
#include "ospray_cpp/FrameBuffer.h"
#include "ospray_cpp/Future.h"
#include "ospray_cpp/GeometricModel.h"
#include "ospray_cpp/Geometry.h"
#include "ospray_cpp/Group.h"
#include "ospray_cpp/ImageOperation.h"
#include "ospray_cpp/Instance.h"
#include "ospray_cpp/Light.h"
#include "ospray_cpp/ManagedObject.h"
#include "ospray_cpp/Material.h"
#include "ospray_cpp/Renderer.h"
#include "ospray_cpp/Texture.h"
#include "ospray_cpp/Traits.h"
#include "ospray_cpp/TransferFunction.h"
#include "ospray_cpp/Volume.h"
#include "ospray_cpp/VolumetricModel.h"
#include "ospray_cpp/World.h"
