/* Compile-time check of sciray's OSPRay 3 C headers from C99: every function of ospray.h
   and ospray_util.h is assigned to a pointer of the type OSPRay documents (so a missing
   or misdeclared function fails to compile under -Werror), every enumeration type is
   used, and a few documented enumerator values are pinned. */

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
  OSPSubdivisionMode subdivisionMode;
  OSPAMRMethod amrMethod;
  OSPPixelFilterType pixelFilter;
  OSPIntensityQuantity intensityQuantity;
  OSPShutterType shutterType;
  OSPBounds bounds;
  OSPPickResult pick;
} sciray_enums = {OSP_LOG_WARNING,
                  OSP_DEVICE_VERSION_MAJOR,
                  OSP_VEC3F,
                  OSP_TEXTURE_SRGBA,
                  OSP_TEXTURE_FILTER_NEAREST,
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
                  OSP_SUBDIVISION_PIN_CORNERS,
                  OSP_AMR_OCTANT,
                  OSP_PIXELFILTER_GAUSS,
                  OSP_INTENSITY_QUANTITY_RADIANCE,
                  OSP_SHUTTER_ROLLING_DOWN,
                  {{0.0f, 0.0f, 0.0f}, {1.0f, 1.0f, 1.0f}},
                  {0, {0.0f, 0.0f, 0.0f}, NULL, NULL, 0}};

/* Values OSPRay documents and binaries depend on (a negative array size fails). */
#define SCIRAY_PIN(name, condition) typedef char sciray_pin_##name[(condition) ? 1 : -1];
SCIRAY_PIN(bool, OSP_BOOL == 250)
SCIRAY_PIN(string, OSP_STRING == 1500)
SCIRAY_PIN(object, OSP_OBJECT == 0x8000000)
SCIRAY_PIN(data, OSP_DATA == OSP_OBJECT + 100 && OSP_CAMERA == OSP_DATA + 1 && OSP_WORLD == OSP_DATA + 16)
SCIRAY_PIN(uchar, OSP_UCHAR == 2500 && OSP_VEC4UC == 2503)
SCIRAY_PIN(uint, OSP_UINT == 4500 && OSP_VEC3UI == 4502)
SCIRAY_PIN(ulong, OSP_ULONG == 5550)
SCIRAY_PIN(float, OSP_FLOAT == 6000 && OSP_VEC3F == 6002 && OSP_VEC4F == 6003)
SCIRAY_PIN(affine, OSP_LINEAR2F == 12000 && OSP_AFFINE3F == 12003)
SCIRAY_PIN(unknown, OSP_UNKNOWN == 9999999)
SCIRAY_PIN(fb_format, OSP_FB_NONE == 0 && OSP_FB_SRGBA == 2 && OSP_FB_RGBA32F == 3)
SCIRAY_PIN(fb_channel, OSP_FB_COLOR == 1 && OSP_FB_DEPTH == 2 && OSP_FB_ACCUM == 4 && OSP_FB_ALBEDO == 32)
SCIRAY_PIN(sync, OSP_FRAME_FINISHED == 30 && OSP_TASK_FINISHED == 100000)
SCIRAY_PIN(texture, OSP_TEXTURE_R16 == 14 && OSP_TEXTURE_FORMAT_INVALID == 255)
SCIRAY_PIN(error, OSP_NO_ERROR == 0 && OSP_VERSION_MISMATCH == 6)

int sciray_header_check(void);

/* The number of functions checked (every entry is non-null, so this also uses the table). */
int sciray_header_check(void) {
  int count = 0;
  size_t i;
  for (i = 0; i < sizeof sciray_functions / sizeof sciray_functions[0]; ++i)
    if (sciray_functions[i].address && sciray_functions[i].name) ++count;
  return count + (sciray_enums.dataType == OSP_VEC3F ? 0 : -1000);
}
