// sciray's OSPRay C++ wrapper: compile-time OSPDataType inference. setParam and the
// Data constructors name no types; OSPTypeFor<T> says what T is on the C side.
// Applications teach it their own types with OSPTYPEFOR_SPECIALIZATION (see ext/).
#pragma once

#include <cstdint>

#include "../ospray.h"

namespace ospray {

// Unknown types stay OSP_UNKNOWN, which setParam and Data refuse at compile time.
template <typename T>
struct OSPTypeFor {
  static constexpr OSPDataType value = OSP_UNKNOWN;
};

// Expands to a complete specialization (callers may add a ';' of their own, as with OSPRay).
#define OSPTYPEFOR_SPECIALIZATION(type, osp_type)  \
  template <>                                      \
  struct OSPTypeFor<type> {                        \
    static constexpr OSPDataType value = osp_type; \
  };

// Before C++17 a static constexpr member that is bound to a reference needs one
// out-of-line definition in the program; this macro writes it.
#define OSPTYPEFOR_DEFINITION(type) constexpr OSPDataType OSPTypeFor<type>::value

namespace cpp_detail {
// An enum travels as its own bytes: OSPRay's enums are 32-bit except the one-byte
// OSPUnstructuredCellType, and sciray's OSPEnums.h gives some of them one byte, so the
// type follows the size rather than a fixed OSP_UINT that would read past a one-byte value.
template <typename E>
constexpr OSPDataType enumType() {
  static_assert(sizeof(E) == 1 || sizeof(E) == 4, "OSPRay enums are 8 or 32 bits wide");
  return sizeof(E) == 1 ? OSP_UCHAR : OSP_UINT;
}
}  // namespace cpp_detail

OSPTYPEFOR_SPECIALIZATION(void*, OSP_VOID_PTR)
OSPTYPEFOR_SPECIALIZATION(char*, OSP_STRING)
OSPTYPEFOR_SPECIALIZATION(const char*, OSP_STRING)
OSPTYPEFOR_SPECIALIZATION(const char[], OSP_STRING)
OSPTYPEFOR_SPECIALIZATION(bool, OSP_BOOL)
OSPTYPEFOR_SPECIALIZATION(char, OSP_CHAR)
OSPTYPEFOR_SPECIALIZATION(unsigned char, OSP_UCHAR)
OSPTYPEFOR_SPECIALIZATION(short, OSP_SHORT)
OSPTYPEFOR_SPECIALIZATION(unsigned short, OSP_USHORT)
OSPTYPEFOR_SPECIALIZATION(int, OSP_INT)
OSPTYPEFOR_SPECIALIZATION(unsigned int, OSP_UINT)
OSPTYPEFOR_SPECIALIZATION(long, OSP_LONG)
OSPTYPEFOR_SPECIALIZATION(unsigned long, OSP_ULONG)
OSPTYPEFOR_SPECIALIZATION(long long, OSP_LONG)
OSPTYPEFOR_SPECIALIZATION(unsigned long long, OSP_ULONG)
OSPTYPEFOR_SPECIALIZATION(float, OSP_FLOAT)
OSPTYPEFOR_SPECIALIZATION(double, OSP_DOUBLE)

OSPTYPEFOR_SPECIALIZATION(OSPObject, OSP_OBJECT)
OSPTYPEFOR_SPECIALIZATION(OSPCamera, OSP_CAMERA)
OSPTYPEFOR_SPECIALIZATION(OSPData, OSP_DATA)
OSPTYPEFOR_SPECIALIZATION(OSPFrameBuffer, OSP_FRAMEBUFFER)
OSPTYPEFOR_SPECIALIZATION(OSPFuture, OSP_FUTURE)
OSPTYPEFOR_SPECIALIZATION(OSPGeometricModel, OSP_GEOMETRIC_MODEL)
OSPTYPEFOR_SPECIALIZATION(OSPGeometry, OSP_GEOMETRY)
OSPTYPEFOR_SPECIALIZATION(OSPGroup, OSP_GROUP)
OSPTYPEFOR_SPECIALIZATION(OSPImageOperation, OSP_IMAGE_OPERATION)
OSPTYPEFOR_SPECIALIZATION(OSPInstance, OSP_INSTANCE)
OSPTYPEFOR_SPECIALIZATION(OSPLight, OSP_LIGHT)
OSPTYPEFOR_SPECIALIZATION(OSPMaterial, OSP_MATERIAL)
OSPTYPEFOR_SPECIALIZATION(OSPRenderer, OSP_RENDERER)
OSPTYPEFOR_SPECIALIZATION(OSPTexture, OSP_TEXTURE)
OSPTYPEFOR_SPECIALIZATION(OSPTransferFunction, OSP_TRANSFER_FUNCTION)
OSPTYPEFOR_SPECIALIZATION(OSPVolume, OSP_VOLUME)
OSPTYPEFOR_SPECIALIZATION(OSPVolumetricModel, OSP_VOLUMETRIC_MODEL)
OSPTYPEFOR_SPECIALIZATION(OSPWorld, OSP_WORLD)

OSPTYPEFOR_SPECIALIZATION(OSPLogLevel, cpp_detail::enumType<OSPLogLevel>())
OSPTYPEFOR_SPECIALIZATION(OSPDeviceProperty, cpp_detail::enumType<OSPDeviceProperty>())
OSPTYPEFOR_SPECIALIZATION(OSPDataType, cpp_detail::enumType<OSPDataType>())
OSPTYPEFOR_SPECIALIZATION(OSPTextureFormat, cpp_detail::enumType<OSPTextureFormat>())
OSPTYPEFOR_SPECIALIZATION(OSPTextureFilter, cpp_detail::enumType<OSPTextureFilter>())
OSPTYPEFOR_SPECIALIZATION(OSPTextureWrapMode, cpp_detail::enumType<OSPTextureWrapMode>())
OSPTYPEFOR_SPECIALIZATION(OSPError, cpp_detail::enumType<OSPError>())
OSPTYPEFOR_SPECIALIZATION(OSPFrameBufferFormat, cpp_detail::enumType<OSPFrameBufferFormat>())
OSPTYPEFOR_SPECIALIZATION(OSPFrameBufferChannel, cpp_detail::enumType<OSPFrameBufferChannel>())
OSPTYPEFOR_SPECIALIZATION(OSPSyncEvent, cpp_detail::enumType<OSPSyncEvent>())
OSPTYPEFOR_SPECIALIZATION(OSPUnstructuredCellType, cpp_detail::enumType<OSPUnstructuredCellType>())
OSPTYPEFOR_SPECIALIZATION(OSPStereoMode, cpp_detail::enumType<OSPStereoMode>())
OSPTYPEFOR_SPECIALIZATION(OSPShutterType, cpp_detail::enumType<OSPShutterType>())
OSPTYPEFOR_SPECIALIZATION(OSPCurveType, cpp_detail::enumType<OSPCurveType>())
OSPTYPEFOR_SPECIALIZATION(OSPCurveBasis, cpp_detail::enumType<OSPCurveBasis>())
OSPTYPEFOR_SPECIALIZATION(OSPSubdivisionMode, cpp_detail::enumType<OSPSubdivisionMode>())
OSPTYPEFOR_SPECIALIZATION(OSPAMRMethod, cpp_detail::enumType<OSPAMRMethod>())
OSPTYPEFOR_SPECIALIZATION(OSPVolumeFilter, cpp_detail::enumType<OSPVolumeFilter>())
OSPTYPEFOR_SPECIALIZATION(OSPPixelFilterType, cpp_detail::enumType<OSPPixelFilterType>())
OSPTYPEFOR_SPECIALIZATION(OSPIntensityQuantity, cpp_detail::enumType<OSPIntensityQuantity>())
OSPTYPEFOR_SPECIALIZATION(OSPSphereType, cpp_detail::enumType<OSPSphereType>())

// The scalar type of each component of a vector or box OSPDataType (void for the others).
template <OSPDataType TYPE>
struct OSPVecElementOf {
  using type = void;
};

#define OSPVECELEMENTOF_SPECIALIZATION(osp_type, element_type) \
  template <>                                                  \
  struct OSPVecElementOf<osp_type> {                           \
    using type = element_type;                                 \
  };

// The number of components of a vector or box OSPDataType (1 for scalars).
template <OSPDataType TYPE>
struct OSPDimensionalityOf {
  static constexpr int value = 1;
};

#define OSPDIMENSIONALITYOF_SPECIALIZATION(osp_type, components) \
  template <>                                                    \
  struct OSPDimensionalityOf<osp_type> {                         \
    static constexpr int value = components;                     \
  };

#define OSPDIMENSIONALITYOF_DEFINITION(osp_type) constexpr int OSPDimensionalityOf<osp_type>::value

// One family of vector types (OSP_VEC2x.. OSP_VEC4x, consecutive values) over one scalar.
#define SCIRAY_OSP_VEC_FAMILY(vec2_type, vec3_type, vec4_type, element_type) \
  OSPVECELEMENTOF_SPECIALIZATION(vec2_type, element_type)                    \
  OSPVECELEMENTOF_SPECIALIZATION(vec3_type, element_type)                    \
  OSPVECELEMENTOF_SPECIALIZATION(vec4_type, element_type)                    \
  OSPDIMENSIONALITYOF_SPECIALIZATION(vec2_type, 2)                           \
  OSPDIMENSIONALITYOF_SPECIALIZATION(vec3_type, 3)                           \
  OSPDIMENSIONALITYOF_SPECIALIZATION(vec4_type, 4)

OSPVECELEMENTOF_SPECIALIZATION(OSP_UCHAR, unsigned char)
OSPVECELEMENTOF_SPECIALIZATION(OSP_INT, std::int32_t)
OSPVECELEMENTOF_SPECIALIZATION(OSP_UINT, std::uint32_t)
OSPVECELEMENTOF_SPECIALIZATION(OSP_LONG, std::int64_t)
OSPVECELEMENTOF_SPECIALIZATION(OSP_ULONG, std::uint64_t)
OSPVECELEMENTOF_SPECIALIZATION(OSP_FLOAT, float)
SCIRAY_OSP_VEC_FAMILY(OSP_VEC2C, OSP_VEC3C, OSP_VEC4C, char)
SCIRAY_OSP_VEC_FAMILY(OSP_VEC2UC, OSP_VEC3UC, OSP_VEC4UC, unsigned char)
SCIRAY_OSP_VEC_FAMILY(OSP_VEC2S, OSP_VEC3S, OSP_VEC4S, short)
SCIRAY_OSP_VEC_FAMILY(OSP_VEC2US, OSP_VEC3US, OSP_VEC4US, unsigned short)
SCIRAY_OSP_VEC_FAMILY(OSP_VEC2I, OSP_VEC3I, OSP_VEC4I, std::int32_t)
SCIRAY_OSP_VEC_FAMILY(OSP_VEC2UI, OSP_VEC3UI, OSP_VEC4UI, std::uint32_t)
SCIRAY_OSP_VEC_FAMILY(OSP_VEC2L, OSP_VEC3L, OSP_VEC4L, std::int64_t)
SCIRAY_OSP_VEC_FAMILY(OSP_VEC2UL, OSP_VEC3UL, OSP_VEC4UL, std::uint64_t)
SCIRAY_OSP_VEC_FAMILY(OSP_VEC2F, OSP_VEC3F, OSP_VEC4F, float)
SCIRAY_OSP_VEC_FAMILY(OSP_VEC2D, OSP_VEC3D, OSP_VEC4D, double)
// Half-precision vectors have components but no C++ scalar type to name.
OSPDIMENSIONALITYOF_SPECIALIZATION(OSP_VEC2H, 2)
OSPDIMENSIONALITYOF_SPECIALIZATION(OSP_VEC3H, 3)
OSPDIMENSIONALITYOF_SPECIALIZATION(OSP_VEC4H, 4)
// A box's dimensionality is that of its corners.
OSPVECELEMENTOF_SPECIALIZATION(OSP_BOX1I, std::int32_t)
OSPVECELEMENTOF_SPECIALIZATION(OSP_BOX2I, std::int32_t)
OSPVECELEMENTOF_SPECIALIZATION(OSP_BOX3I, std::int32_t)
OSPVECELEMENTOF_SPECIALIZATION(OSP_BOX4I, std::int32_t)
OSPVECELEMENTOF_SPECIALIZATION(OSP_BOX1F, float)
OSPVECELEMENTOF_SPECIALIZATION(OSP_BOX2F, float)
OSPVECELEMENTOF_SPECIALIZATION(OSP_BOX3F, float)
OSPVECELEMENTOF_SPECIALIZATION(OSP_BOX4F, float)
OSPDIMENSIONALITYOF_SPECIALIZATION(OSP_BOX2I, 2)
OSPDIMENSIONALITYOF_SPECIALIZATION(OSP_BOX3I, 3)
OSPDIMENSIONALITYOF_SPECIALIZATION(OSP_BOX4I, 4)
OSPDIMENSIONALITYOF_SPECIALIZATION(OSP_BOX2F, 2)
OSPDIMENSIONALITYOF_SPECIALIZATION(OSP_BOX3F, 3)
OSPDIMENSIONALITYOF_SPECIALIZATION(OSP_BOX4F, 4)

#undef SCIRAY_OSP_VEC_FAMILY

}  // namespace ospray
