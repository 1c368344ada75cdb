/* Compile-time check of sciray's OSPRay 3 C headers from C99 against OSPRay 3.2's: each of
   the 77 functions of ospray.h and ospray_util.h is assigned to a pointer of OSPRay's type
   (so a missing or misdeclared function fails to compile under -Werror), every enumeration
   type is used, and every enumerator is pinned to OSPRay's value (a negative array size
   fails). */

#include <ospray/ospray.h>
#include <ospray/ospray_util.h>

#if !defined(OSPRAY_VERSION_MAJOR) || OSPRAY_VERSION_MAJOR != 3 || !defined(OSPRAY_VERSION_MINOR)
#error "ospray.h must declare OSPRay 3's version macros"
#endif

/* X(return type, name, parameter types) for every function in both headers. */
#define SCIRAY_OSPRAY_FUNCTIONS(X)                                                                        \
  /* devices */                                                                                           \
  X(OSPError, ospInit, (int *, const char **))                                                            \
  X(void, ospShutdown, (void))                                                                            \
  X(OSPDevice, ospNewDevice, (const char *))                                                              \
  X(void, ospSetCurrentDevice, (OSPDevice))                                                               \
  X(OSPDevice, ospGetCurrentDevice, (void))                                                               \
  X(int64_t, ospDeviceGetProperty, (OSPDevice, OSPDeviceProperty))                                        \
  X(void, ospDeviceSetParam, (OSPDevice, const char *, OSPDataType, const void *))                        \
  X(void, ospDeviceRemoveParam, (OSPDevice, const char *))                                                \
  X(void, ospDeviceSetStatusCallback, (OSPDevice, OSPStatusCallback, void *))                             \
  X(void, ospDeviceSetErrorCallback, (OSPDevice, OSPErrorCallback, void *))                               \
  X(OSPError, ospDeviceGetLastErrorCode, (OSPDevice))                                                     \
  X(const char *, ospDeviceGetLastErrorMsg, (OSPDevice))                                                  \
  X(void, ospDeviceCommit, (OSPDevice))                                                                   \
  X(void, ospDeviceRelease, (OSPDevice))                                                                  \
  X(void, ospDeviceRetain, (OSPDevice))                                                                   \
  X(OSPError, ospLoadModule, (const char *))                                                              \
  /* data arrays */                                                                                       \
  X(OSPData, ospNewSharedData,                                                                            \
    (const void *, OSPDataType, uint64_t, int64_t, uint64_t, int64_t, uint64_t, int64_t,                  \
     OSPDeleterCallback, const void *))                                                                   \
  X(OSPData, ospNewData, (OSPDataType, uint64_t, uint64_t, uint64_t))                                     \
  X(void, ospCopyData, (const OSPData, OSPData, uint64_t, uint64_t, uint64_t))                            \
  /* objects */                                                                                           \
  X(OSPLight, ospNewLight, (const char *))                                                                \
  X(OSPCamera, ospNewCamera, (const char *))                                                              \
  X(OSPGeometry, ospNewGeometry, (const char *))                                                          \
  X(OSPVolume, ospNewVolume, (const char *))                                                              \
  X(OSPGeometricModel, ospNewGeometricModel, (OSPGeometry))                                               \
  X(OSPVolumetricModel, ospNewVolumetricModel, (OSPVolume))                                               \
  X(OSPMaterial, ospNewMaterial, (const char *))                                                          \
  X(OSPTransferFunction, ospNewTransferFunction, (const char *))                                          \
  X(OSPTexture, ospNewTexture, (const char *))                                                            \
  X(OSPGroup, ospNewGroup, (void))                                                                        \
  X(OSPInstance, ospNewInstance, (OSPGroup))                                                              \
  X(OSPWorld, ospNewWorld, (void))                                                                        \
  X(OSPBounds, ospGetBounds, (OSPObject))                                                                 \
  /* parameters and lifetime */                                                                           \
  X(void, ospSetParam, (OSPObject, const char *, OSPDataType, const void *))                              \
  X(void, ospRemoveParam, (OSPObject, const char *))                                                      \
  X(void, ospCommit, (OSPObject))                                                                         \
  X(void, ospRelease, (OSPObject))                                                                        \
  X(void, ospRetain, (OSPObject))                                                                         \
  /* frame buffers */                                                                                     \
  X(OSPFrameBuffer, ospNewFrameBuffer, (int, int, OSPFrameBufferFormat, uint32_t))                        \
  X(OSPImageOperation, ospNewImageOperation, (const char *))                                              \
  X(const void *, ospMapFrameBuffer, (OSPFrameBuffer, OSPFrameBufferChannel))                             \
  X(void, ospUnmapFrameBuffer, (const void *, OSPFrameBuffer))                                            \
  X(float, ospGetVariance, (OSPFrameBuffer))                                                              \
  X(void, ospResetAccumulation, (OSPFrameBuffer))                                                         \
  /* rendering */                                                                                         \
  X(OSPRenderer, ospNewRenderer, (const char *))                                                          \
  X(OSPFuture, ospRenderFrame, (OSPFrameBuffer, OSPRenderer, OSPCamera, OSPWorld))                        \
  X(int, ospIsReady, (OSPFuture, OSPSyncEvent))                                                           \
  X(void, ospWait, (OSPFuture, OSPSyncEvent))                                                             \
  X(void, ospCancel, (OSPFuture))                                                                         \
  X(float, ospGetProgress, (OSPFuture))                                                                   \
  X(float, ospGetTaskDuration, (OSPFuture))                                                               \
  X(void, ospPick, (OSPPickResult *, OSPFrameBuffer, OSPRenderer, OSPCamera, OSPWorld, float, float))     \
  /* ospray_util.h: data arrays */                                                                        \
  X(OSPData, ospNewSharedData1D, (const void *, OSPDataType, uint64_t))                                   \
  X(OSPData, ospNewAssignedData1D, (const void *, OSPDataType, uint64_t, OSPDeleterCallback, const void *)) \
  X(OSPData, ospNewSharedData1DStride, (const void *, OSPDataType, uint64_t, int64_t))                    \
  X(OSPData, ospNewSharedData2D, (const void *, OSPDataType, uint64_t, uint64_t))                         \
  X(OSPData, ospNewSharedData2DStride, (const void *, OSPDataType, uint64_t, int64_t, uint64_t, int64_t)) \
  X(OSPData, ospNewSharedData3D, (const void *, OSPDataType, uint64_t, uint64_t, uint64_t))               \
  X(OSPData, ospNewData1D, (OSPDataType, uint64_t))                                                       \
  X(OSPData, ospNewData2D, (OSPDataType, uint64_t, uint64_t))                                             \
  X(void, ospCopyData1D, (const OSPData, OSPData, uint64_t))                                              \
  X(void, ospCopyData2D, (const OSPData, OSPData, uint64_t, uint64_t))                                    \
  /* ospray_util.h: typed parameters */                                                                   \
  X(void, ospSetString, (OSPObject, const char *, const char *))                                          \
  X(void, ospSetObject, (OSPObject, const char *, OSPObject))                                             \
  X(void, ospSetBool, (OSPObject, const char *, int))                                                     \
  X(void, ospSetFloat, (OSPObject, const char *, float))                                                  \
  X(void, ospSetInt, (OSPObject, const char *, int))                                                      \
  X(void, ospSetUInt, (OSPObject, const char *, unsigned int))                                            \
  X(void, ospSetBox1f, (OSPObject, const char *, float, float))                                           \
  X(void, ospSetLinear2f, (OSPObject, const char *, float, float, float, float))                          \
  X(void, ospSetVec2f, (OSPObject, const char *, float, float))                                           \
  X(void, ospSetVec3f, (OSPObject, const char *, float, float, float))                                    \
  X(void, ospSetVec4f, (OSPObject, const char *, float, float, float, float))                             \
  X(void, ospSetVec2i, (OSPObject, const char *, int, int))                                               \
  X(void, ospSetVec3i, (OSPObject, const char *, int, int, int))                                          \
  X(void, ospSetVec4i, (OSPObject, const char *, int, int, int, int))                                     \
  X(void, ospSetObjectAsData, (OSPObject, const char *, OSPDataType, OSPObject))                          \
  /* ospray_util.h: rendering */                                                                          \
  X(float, ospRenderFrameBlocking, (OSPFrameBuffer, OSPRenderer, OSPCamera, OSPWorld))

/* Implicit conversion to the expected pointer type: a mismatch is a diagnostic. */
#define SCIRAY_TYPED_POINTER(ret, name, params) static ret(*const sciray_check_##name) params = name;
SCIRAY_OSPRAY_FUNCTIONS(SCIRAY_TYPED_POINTER)

typedef void (*sciray_function)(void);
#define SCIRAY_TABLE_ENTRY(ret, name, params) {#name, (sciray_function)sciray_check_##name},
static const struct {
  const char *name;
  sciray_function address;
} sciray_functions[] = {SCIRAY_OSPRAY_FUNCTIONS(SCIRAY_TABLE_ENTRY)};

/* One object of every enumeration and structure type. */
static const struct {
  OSPLogLevel logLevel;
  OSPDeviceProperty deviceProperty;
  OSPDataType dataType;
  OSPTextureFormat textureFormat;
  OSPTextureFilter textureFilter;
  OSPTextureWrapMode textureWrapMode;
  OSPError error;
  OSPFrameBufferFormat frameBufferFormat;
  OSPFrameBufferChannel frameBufferChannel;
  OSPSyncEvent syncEvent;
  OSPUnstructuredCellType cellType;
  OSPStereoMode stereoMode;
  OSPCurveType curveType;
  OSPCurveBasis curveBasis;
  OSPSphereType sphereType;
  OSPVolumeFilter volumeFilter;
  OSPVolumeFormat volumeFormat;
  OSPSubdivisionMode subdivisionMode;
  OSPAMRMethod amrMethod;
  OSPPixelFilterType pixelFilter;
  OSPIntensityQuantity intensityQuantity;
  OSPShutterType shutterType;
  OSPDenoiserQuality denoiserQuality;
  OSPBounds bounds;
  OSPPickResult pick;
} sciray_enums = {OSP_LOG_WARNING,
                  OSP_DEVICE_VERSION_MAJOR,
                  OSP_VEC3F,
                  OSP_TEXTURE_SRGBA,
                  OSP_TEXTURE_FILTER_NEAREST,
                  OSP_TEXTURE_WRAP_CLAMP_TO_EDGE,
                  OSP_INVALID_ARGUMENT,
                  OSP_FB_SRGBA,
                  OSP_FB_DEPTH,
                  OSP_FRAME_FINISHED,
                  OSP_HEXAHEDRON,
                  OSP_STEREO_SIDE_BY_SIDE,
                  OSP_RIBBON,
                  OSP_CATMULL_ROM,
                  OSP_ORIENTED_DISC,
                  OSP_VOLUME_FILTER_LINEAR,
                  OSP_VOLUME_FORMAT_DENSE_ZYX,
                  OSP_SUBDIVISION_PIN_CORNERS,
                  OSP_AMR_OCTANT,
                  OSP_PIXELFILTER_GAUSS,
                  OSP_INTENSITY_QUANTITY_RADIANCE,
                  OSP_SHUTTER_ROLLING_DOWN,
                  OSP_DENOISER_QUALITY_HIGH,
                  {{0.0f, 0.0f, 0.0f}, {1.0f, 1.0f, 1.0f}},
                  {0, {0.0f, 0.0f, 0.0f}, NULL, NULL, 0}};

/* Every enumerator at OSPRay 3.2's value. */
#define SCIRAY_PIN(name, value) typedef char sciray_pin_##name[(name) == (value) ? 1 : -1];
/* OSPLogLevel */
SCIRAY_PIN(OSP_LOG_DEBUG, 1)
SCIRAY_PIN(OSP_LOG_INFO, 2)
SCIRAY_PIN(OSP_LOG_WARNING, 3)
SCIRAY_PIN(OSP_LOG_ERROR, 4)
SCIRAY_PIN(OSP_LOG_NONE, 5)
/* OSPDeviceProperty */
SCIRAY_PIN(OSP_DEVICE_VERSION, 0)
SCIRAY_PIN(OSP_DEVICE_VERSION_MAJOR, 1)
SCIRAY_PIN(OSP_DEVICE_VERSION_MINOR, 2)
SCIRAY_PIN(OSP_DEVICE_VERSION_PATCH, 3)
SCIRAY_PIN(OSP_DEVICE_SO_VERSION, 4)
/* OSPDataType */
SCIRAY_PIN(OSP_DEVICE, 100)
SCIRAY_PIN(OSP_VOID_PTR, 200)
SCIRAY_PIN(OSP_BOOL, 250)
SCIRAY_PIN(OSP_OBJECT, 0x8000000)
SCIRAY_PIN(OSP_DATA, 0x8000000 + 100)
SCIRAY_PIN(OSP_CAMERA, 0x8000000 + 101)
SCIRAY_PIN(OSP_FRAMEBUFFER, 0x8000000 + 102)
SCIRAY_PIN(OSP_FUTURE, 0x8000000 + 103)
SCIRAY_PIN(OSP_GEOMETRIC_MODEL, 0x8000000 + 104)
SCIRAY_PIN(OSP_GEOMETRY, 0x8000000 + 105)
SCIRAY_PIN(OSP_GROUP, 0x8000000 + 106)
SCIRAY_PIN(OSP_IMAGE_OPERATION, 0x8000000 + 107)
SCIRAY_PIN(OSP_INSTANCE, 0x8000000 + 108)
SCIRAY_PIN(OSP_LIGHT, 0x8000000 + 109)
SCIRAY_PIN(OSP_MATERIAL, 0x8000000 + 110)
SCIRAY_PIN(OSP_RENDERER, 0x8000000 + 111)
SCIRAY_PIN(OSP_TEXTURE, 0x8000000 + 112)
SCIRAY_PIN(OSP_TRANSFER_FUNCTION, 0x8000000 + 113)
SCIRAY_PIN(OSP_VOLUME, 0x8000000 + 114)
SCIRAY_PIN(OSP_VOLUMETRIC_MODEL, 0x8000000 + 115)
SCIRAY_PIN(OSP_WORLD, 0x8000000 + 116)
SCIRAY_PIN(OSP_STRING, 1500)
SCIRAY_PIN(OSP_CHAR, 2000)
SCIRAY_PIN(OSP_VEC2C, 2001)
SCIRAY_PIN(OSP_VEC3C, 2002)
SCIRAY_PIN(OSP_VEC4C, 2003)
SCIRAY_PIN(OSP_UCHAR, 2500)
SCIRAY_PIN(OSP_VEC2UC, 2501)
SCIRAY_PIN(OSP_VEC3UC, 2502)
SCIRAY_PIN(OSP_VEC4UC, 2503)
SCIRAY_PIN(OSP_BYTE, 2500)
SCIRAY_PIN(OSP_RAW, 2500)
SCIRAY_PIN(OSP_SHORT, 3000)
SCIRAY_PIN(OSP_VEC2S, 3001)
SCIRAY_PIN(OSP_VEC3S, 3002)
SCIRAY_PIN(OSP_VEC4S, 3003)
SCIRAY_PIN(OSP_USHORT, 3500)
SCIRAY_PIN(OSP_VEC2US, 3501)
SCIRAY_PIN(OSP_VEC3US, 3502)
SCIRAY_PIN(OSP_VEC4US, 3503)
SCIRAY_PIN(OSP_INT, 4000)
SCIRAY_PIN(OSP_VEC2I, 4001)
SCIRAY_PIN(OSP_VEC3I, 4002)
SCIRAY_PIN(OSP_VEC4I, 4003)
SCIRAY_PIN(OSP_UINT, 4500)
SCIRAY_PIN(OSP_VEC2UI, 4501)
SCIRAY_PIN(OSP_VEC3UI, 4502)
SCIRAY_PIN(OSP_VEC4UI, 4503)
SCIRAY_PIN(OSP_LONG, 5000)
SCIRAY_PIN(OSP_VEC2L, 5001)
SCIRAY_PIN(OSP_VEC3L, 5002)
SCIRAY_PIN(OSP_VEC4L, 5003)
SCIRAY_PIN(OSP_ULONG, 5550)
SCIRAY_PIN(OSP_VEC2UL, 5551)
SCIRAY_PIN(OSP_VEC3UL, 5552)
SCIRAY_PIN(OSP_VEC4UL, 5553)
SCIRAY_PIN(OSP_HALF, 5800)
SCIRAY_PIN(OSP_VEC2H, 5801)
SCIRAY_PIN(OSP_VEC3H, 5802)
SCIRAY_PIN(OSP_VEC4H, 5803)
SCIRAY_PIN(OSP_FLOAT, 6000)
SCIRAY_PIN(OSP_VEC2F, 6001)
SCIRAY_PIN(OSP_VEC3F, 6002)
SCIRAY_PIN(OSP_VEC4F, 6003)
SCIRAY_PIN(OSP_DOUBLE, 7000)
SCIRAY_PIN(OSP_VEC2D, 7001)
SCIRAY_PIN(OSP_VEC3D, 7002)
SCIRAY_PIN(OSP_VEC4D, 7003)
SCIRAY_PIN(OSP_BOX1I, 8000)
SCIRAY_PIN(OSP_BOX2I, 8001)
SCIRAY_PIN(OSP_BOX3I, 8002)
SCIRAY_PIN(OSP_BOX4I, 8003)
SCIRAY_PIN(OSP_BOX1F, 10000)
SCIRAY_PIN(OSP_BOX2F, 10001)
SCIRAY_PIN(OSP_BOX3F, 10002)
SCIRAY_PIN(OSP_BOX4F, 10003)
SCIRAY_PIN(OSP_LINEAR2F, 12000)
SCIRAY_PIN(OSP_LINEAR3F, 12001)
SCIRAY_PIN(OSP_AFFINE2F, 12002)
SCIRAY_PIN(OSP_AFFINE3F, 12003)
SCIRAY_PIN(OSP_QUATF, 12004)
SCIRAY_PIN(OSP_UNKNOWN, 9999999)
/* OSPTextureFormat */
SCIRAY_PIN(OSP_TEXTURE_RGBA8, 0)
SCIRAY_PIN(OSP_TEXTURE_SRGBA, 1)
SCIRAY_PIN(OSP_TEXTURE_RGBA32F, 2)
SCIRAY_PIN(OSP_TEXTURE_RGB8, 3)
SCIRAY_PIN(OSP_TEXTURE_SRGB, 4)
SCIRAY_PIN(OSP_TEXTURE_RGB32F, 5)
SCIRAY_PIN(OSP_TEXTURE_R8, 6)
SCIRAY_PIN(OSP_TEXTURE_R32F, 7)
SCIRAY_PIN(OSP_TEXTURE_L8, 8)
SCIRAY_PIN(OSP_TEXTURE_RA8, 9)
SCIRAY_PIN(OSP_TEXTURE_LA8, 10)
SCIRAY_PIN(OSP_TEXTURE_RGBA16, 11)
SCIRAY_PIN(OSP_TEXTURE_RGB16, 12)
SCIRAY_PIN(OSP_TEXTURE_RA16, 13)
SCIRAY_PIN(OSP_TEXTURE_R16, 14)
SCIRAY_PIN(OSP_TEXTURE_RGBA16F, 15)
SCIRAY_PIN(OSP_TEXTURE_RGB16F, 16)
SCIRAY_PIN(OSP_TEXTURE_RA16F, 17)
SCIRAY_PIN(OSP_TEXTURE_R16F, 18)
SCIRAY_PIN(OSP_TEXTURE_RA32F, 19)
SCIRAY_PIN(OSP_TEXTURE_FORMAT_INVALID, 255)
/* OSPTextureFilter */
SCIRAY_PIN(OSP_TEXTURE_FILTER_LINEAR, 0)
SCIRAY_PIN(OSP_TEXTURE_FILTER_NEAREST, 1)
/* OSPTextureWrapMode */
SCIRAY_PIN(OSP_TEXTURE_WRAP_REPEAT, 0)
SCIRAY_PIN(OSP_TEXTURE_WRAP_MIRRORED_REPEAT, 1)
SCIRAY_PIN(OSP_TEXTURE_WRAP_CLAMP_TO_EDGE, 2)
/* OSPError */
SCIRAY_PIN(OSP_NO_ERROR, 0)
SCIRAY_PIN(OSP_UNKNOWN_ERROR, 1)
SCIRAY_PIN(OSP_INVALID_ARGUMENT, 2)
SCIRAY_PIN(OSP_INVALID_OPERATION, 3)
SCIRAY_PIN(OSP_OUT_OF_MEMORY, 4)
SCIRAY_PIN(OSP_UNSUPPORTED_CPU, 5)
SCIRAY_PIN(OSP_VERSION_MISMATCH, 6)
/* OSPFrameBufferFormat */
SCIRAY_PIN(OSP_FB_NONE, 0)
SCIRAY_PIN(OSP_FB_RGBA8, 1)
SCIRAY_PIN(OSP_FB_SRGBA, 2)
SCIRAY_PIN(OSP_FB_RGBA32F, 3)
/* OSPFrameBufferChannel */
SCIRAY_PIN(OSP_FB_COLOR, 1)
SCIRAY_PIN(OSP_FB_DEPTH, 2)
SCIRAY_PIN(OSP_FB_ACCUM, 4)
SCIRAY_PIN(OSP_FB_VARIANCE, 8)
SCIRAY_PIN(OSP_FB_NORMAL, 16)
SCIRAY_PIN(OSP_FB_ALBEDO, 32)
SCIRAY_PIN(OSP_FB_ID_PRIMITIVE, 64)
SCIRAY_PIN(OSP_FB_ID_OBJECT, 128)
SCIRAY_PIN(OSP_FB_ID_INSTANCE, 256)
/* OSPSyncEvent */
SCIRAY_PIN(OSP_NONE_FINISHED, 0)
SCIRAY_PIN(OSP_WORLD_RENDERED, 10)
SCIRAY_PIN(OSP_WORLD_COMMITTED, 20)
SCIRAY_PIN(OSP_FRAME_FINISHED, 30)
SCIRAY_PIN(OSP_TASK_FINISHED, 100000)
/* OSPUnstructuredCellType */
SCIRAY_PIN(OSP_TETRAHEDRON, 10)
SCIRAY_PIN(OSP_HEXAHEDRON, 12)
SCIRAY_PIN(OSP_WEDGE, 13)
SCIRAY_PIN(OSP_PYRAMID, 14)
SCIRAY_PIN(OSP_UNKNOWN_CELL_TYPE, 255)
/* OSPStereoMode */
SCIRAY_PIN(OSP_STEREO_NONE, 0)
SCIRAY_PIN(OSP_STEREO_LEFT, 1)
SCIRAY_PIN(OSP_STEREO_RIGHT, 2)
SCIRAY_PIN(OSP_STEREO_SIDE_BY_SIDE, 3)
SCIRAY_PIN(OSP_STEREO_TOP_BOTTOM, 4)
SCIRAY_PIN(OSP_STEREO_UNKNOWN, 255)
/* OSPShutterType */
SCIRAY_PIN(OSP_SHUTTER_GLOBAL, 0)
SCIRAY_PIN(OSP_SHUTTER_ROLLING_RIGHT, 1)
SCIRAY_PIN(OSP_SHUTTER_ROLLING_LEFT, 2)
SCIRAY_PIN(OSP_SHUTTER_ROLLING_DOWN, 3)
SCIRAY_PIN(OSP_SHUTTER_ROLLING_UP, 4)
SCIRAY_PIN(OSP_SHUTTER_UNKNOWN, 255)
/* OSPCurveType */
SCIRAY_PIN(OSP_ROUND, 0)
SCIRAY_PIN(OSP_FLAT, 1)
SCIRAY_PIN(OSP_RIBBON, 2)
SCIRAY_PIN(OSP_DISJOINT, 3)
SCIRAY_PIN(OSP_UNKNOWN_CURVE_TYPE, 255)
/* OSPSphereType */
SCIRAY_PIN(OSP_SPHERE, 50)
SCIRAY_PIN(OSP_DISC, 51)
SCIRAY_PIN(OSP_ORIENTED_DISC, 52)
SCIRAY_PIN(OSP_UNKNOWN_SPHERE_TYPE, 255)
/* OSPCurveBasis */
SCIRAY_PIN(OSP_LINEAR, 0)
SCIRAY_PIN(OSP_BEZIER, 1)
SCIRAY_PIN(OSP_BSPLINE, 2)
SCIRAY_PIN(OSP_HERMITE, 3)
SCIRAY_PIN(OSP_CATMULL_ROM, 4)
SCIRAY_PIN(OSP_UNKNOWN_CURVE_BASIS, 255)
/* OSPSubdivisionMode */
SCIRAY_PIN(OSP_SUBDIVISION_NO_BOUNDARY, 0)
SCIRAY_PIN(OSP_SUBDIVISION_SMOOTH_BOUNDARY, 1)
SCIRAY_PIN(OSP_SUBDIVISION_PIN_CORNERS, 2)
SCIRAY_PIN(OSP_SUBDIVISION_PIN_BOUNDARY, 3)
SCIRAY_PIN(OSP_SUBDIVISION_PIN_ALL, 4)
/* OSPAMRMethod */
SCIRAY_PIN(OSP_AMR_CURRENT, 0)
SCIRAY_PIN(OSP_AMR_FINEST, 1)
SCIRAY_PIN(OSP_AMR_OCTANT, 2)
/* OSPVolumeFilter */
SCIRAY_PIN(OSP_VOLUME_FILTER_NEAREST, 0)
SCIRAY_PIN(OSP_VOLUME_FILTER_LINEAR, 100)
SCIRAY_PIN(OSP_VOLUME_FILTER_CUBIC, 200)
/* OSPVolumeFormat */
SCIRAY_PIN(OSP_VOLUME_FORMAT_TILE, 0)
SCIRAY_PIN(OSP_VOLUME_FORMAT_DENSE_ZYX, 1)
/* OSPPixelFilterType */
SCIRAY_PIN(OSP_PIXELFILTER_POINT, 0)
SCIRAY_PIN(OSP_PIXELFILTER_BOX, 1)
SCIRAY_PIN(OSP_PIXELFILTER_GAUSS, 2)
SCIRAY_PIN(OSP_PIXELFILTER_MITCHELL, 3)
SCIRAY_PIN(OSP_PIXELFILTER_BLACKMAN_HARRIS, 4)
/* OSPIntensityQuantity */
SCIRAY_PIN(OSP_INTENSITY_QUANTITY_RADIANCE, 0)
SCIRAY_PIN(OSP_INTENSITY_QUANTITY_IRRADIANCE, 1)
SCIRAY_PIN(OSP_INTENSITY_QUANTITY_INTENSITY, 2)
SCIRAY_PIN(OSP_INTENSITY_QUANTITY_POWER, 3)
SCIRAY_PIN(OSP_INTENSITY_QUANTITY_SCALE, 4)
SCIRAY_PIN(OSP_INTENSITY_QUANTITY_UNKNOWN, 5)
/* OSPDenoiserQuality */
SCIRAY_PIN(OSP_DENOISER_QUALITY_LOW, 4)
SCIRAY_PIN(OSP_DENOISER_QUALITY_MEDIUM, 5)
SCIRAY_PIN(OSP_DENOISER_QUALITY_HIGH, 6)

int sciray_header_check(void);

/* The number of functions checked (every entry is non-null, so this also uses the table). */
int sciray_header_check(void) {
  int count = 0;
  size_t i;
  for (i = 0; i < sizeof sciray_functions / sizeof sciray_functions[0]; ++i)
    if (sciray_functions[i].address && sciray_functions[i].name) ++count;
  return count + (sciray_enums.dataType == OSP_VEC3F ? 0 : -1000);
}
