/* sciray's implementation of the OSPRay 3 C API: the functions, handle types and
   structures OSPRay documents, implemented by libsciray_ospray. Usable from C99 and C++.
   See docs/c-api.md for what is supported. */
#pragma once

#include <stddef.h>
#include <stdint.h>

#include "OSPEnums.h"

#define OSPRAY_VERSION_MAJOR 3
#define OSPRAY_VERSION_MINOR 2
#define OSPRAY_VERSION_PATCH 0
#define OSPRAY_SCIRAY 1 /* this OSPRay API is provided by sciray */

#if defined(_WIN32)
#define OSPRAY_INTERFACE __declspec(dllimport)
#else
#define OSPRAY_INTERFACE __attribute__((visibility("default")))
#endif

#ifdef __cplusplus
#define OSP_DEFAULT_VAL(a) = a
#else
#define OSP_DEFAULT_VAL(a)
#endif

/* Handles. In C++ each object kind is its own type (all convert to OSPObject); in C they
   are one type, as C has no inheritance. */
#ifdef __cplusplus
namespace osp {
struct Device;
struct ManagedObject {};
struct Camera : ManagedObject {};
struct Data : ManagedObject {};
struct FrameBuffer : ManagedObject {};
struct Future : ManagedObject {};
struct GeometricModel : ManagedObject {};
struct Geometry : ManagedObject {};
struct Group : ManagedObject {};
struct ImageOperation : ManagedObject {};
struct Instance : ManagedObject {};
struct Light : ManagedObject {};
struct Material : ManagedObject {};
struct Renderer : ManagedObject {};
struct Texture : ManagedObject {};
struct TransferFunction : ManagedObject {};
struct Volume : ManagedObject {};
struct VolumetricModel : ManagedObject {};
struct World : ManagedObject {};
}  // namespace osp
typedef osp::Device *OSPDevice;
typedef osp::ManagedObject *OSPObject;
typedef osp::Camera *OSPCamera;
typedef osp::Data *OSPData;
typedef osp::FrameBuffer *OSPFrameBuffer;
typedef osp::Future *OSPFuture;
typedef osp::GeometricModel *OSPGeometricModel;
typedef osp::Geometry *OSPGeometry;
typedef osp::Group *OSPGroup;
typedef osp::ImageOperation *OSPImageOperation;
typedef osp::Instance *OSPInstance;
typedef osp::Light *OSPLight;
typedef osp::Material *OSPMaterial;
typedef osp::Renderer *OSPRenderer;
typedef osp::Texture *OSPTexture;
typedef osp::TransferFunction *OSPTransferFunction;
typedef osp::Volume *OSPVolume;
typedef osp::VolumetricModel *OSPVolumetricModel;
typedef osp::World *OSPWorld;
#else
typedef void *OSPDevice;
typedef void _OSPManagedObject;
typedef _OSPManagedObject *OSPManagedObject, *OSPObject, *OSPCamera, *OSPData, *OSPFrameBuffer, *OSPFuture,
    *OSPGeometricModel, *OSPGeometry, *OSPGroup, *OSPImageOperation, *OSPInstance, *OSPLight, *OSPMaterial,
    *OSPRenderer, *OSPTexture, *OSPTransferFunction, *OSPVolume, *OSPVolumetricModel, *OSPWorld;
#endif

#ifdef __cplusplus
extern "C" {
#endif

/* Devices ------------------------------------------------------------------ */

/* Creates the default device from command-line arguments ("--osp:..."), which it removes
   from argv, and makes it current. */
OSPRAY_INTERFACE OSPError ospInit(int *argc OSP_DEFAULT_VAL(NULL), const char **argv OSP_DEFAULT_VAL(NULL));
OSPRAY_INTERFACE void ospShutdown(void);
OSPRAY_INTERFACE OSPDevice ospNewDevice(const char *deviceType OSP_DEFAULT_VAL("cpu"));
OSPRAY_INTERFACE void ospSetCurrentDevice(OSPDevice);
OSPRAY_INTERFACE OSPDevice ospGetCurrentDevice(void);
OSPRAY_INTERFACE int64_t ospDeviceGetProperty(OSPDevice, OSPDeviceProperty);

OSPRAY_INTERFACE void ospDeviceSetParam(OSPDevice, const char *id, OSPDataType, const void *mem);
OSPRAY_INTERFACE void ospDeviceRemoveParam(OSPDevice, const char *id);

typedef void (*OSPStatusCallback)(void *userData, const char *messageText);
OSPRAY_INTERFACE void ospDeviceSetStatusCallback(OSPDevice, OSPStatusCallback, void *userData);

typedef void (*OSPErrorCallback)(void *userData, OSPError, const char *errorDetails);
OSPRAY_INTERFACE void ospDeviceSetErrorCallback(OSPDevice, OSPErrorCallback, void *userData);

OSPRAY_INTERFACE OSPError ospDeviceGetLastErrorCode(OSPDevice);
OSPRAY_INTERFACE const char *ospDeviceGetLastErrorMsg(OSPDevice);

OSPRAY_INTERFACE void ospDeviceCommit(OSPDevice);
OSPRAY_INTERFACE void ospDeviceRelease(OSPDevice);
OSPRAY_INTERFACE void ospDeviceRetain(OSPDevice);

/* Modules: sciray's types are built in; loading "cpu" succeeds, any other name fails. */
OSPRAY_INTERFACE OSPError ospLoadModule(const char *name);

/* Data arrays -------------------------------------------------------------- */

typedef void (*OSPDeleterCallback)(const void *userData, const void *sharedData);

OSPRAY_INTERFACE OSPData ospNewSharedData(const void *sharedData, OSPDataType, uint64_t numItems1,
                                          int64_t byteStride1 OSP_DEFAULT_VAL(0),
                                          uint64_t numItems2 OSP_DEFAULT_VAL(1),
                                          int64_t byteStride2 OSP_DEFAULT_VAL(0),
                                          uint64_t numItems3 OSP_DEFAULT_VAL(1),
                                          int64_t byteStride3 OSP_DEFAULT_VAL(0),
                                          OSPDeleterCallback OSP_DEFAULT_VAL(NULL),
                                          const void *userData OSP_DEFAULT_VAL(NULL));

OSPRAY_INTERFACE OSPData ospNewData(OSPDataType, uint64_t numItems1, uint64_t numItems2 OSP_DEFAULT_VAL(1),
                                    uint64_t numItems3 OSP_DEFAULT_VAL(1));

OSPRAY_INTERFACE void ospCopyData(const OSPData source, OSPData destination,
                                  uint64_t destinationIndex1 OSP_DEFAULT_VAL(0),
                                  uint64_t destinationIndex2 OSP_DEFAULT_VAL(0),
                                  uint64_t destinationIndex3 OSP_DEFAULT_VAL(0));

/* Objects ------------------------------------------------------------------ */

OSPRAY_INTERFACE OSPLight ospNewLight(const char *type);
OSPRAY_INTERFACE OSPCamera ospNewCamera(const char *type);
OSPRAY_INTERFACE OSPGeometry ospNewGeometry(const char *type);
OSPRAY_INTERFACE OSPVolume ospNewVolume(const char *type);
OSPRAY_INTERFACE OSPGeometricModel ospNewGeometricModel(OSPGeometry OSP_DEFAULT_VAL(NULL));
OSPRAY_INTERFACE OSPVolumetricModel ospNewVolumetricModel(OSPVolume OSP_DEFAULT_VAL(NULL));
OSPRAY_INTERFACE OSPMaterial ospNewMaterial(const char *materialType);
OSPRAY_INTERFACE OSPTransferFunction ospNewTransferFunction(const char *type);
OSPRAY_INTERFACE OSPTexture ospNewTexture(const char *type);
OSPRAY_INTERFACE OSPGroup ospNewGroup(void);
OSPRAY_INTERFACE OSPInstance ospNewInstance(OSPGroup OSP_DEFAULT_VAL(NULL));
OSPRAY_INTERFACE OSPWorld ospNewWorld(void);

typedef struct {
  float lower[3];
  float upper[3];
} OSPBounds;

/* Bounds of a committed world, instance, group, geometric model or geometry. */
OSPRAY_INTERFACE OSPBounds ospGetBounds(OSPObject);

/* Parameters and lifetime --------------------------------------------------- */

OSPRAY_INTERFACE void ospSetParam(OSPObject, const char *id, OSPDataType, const void *mem);
OSPRAY_INTERFACE void ospRemoveParam(OSPObject, const char *id);
OSPRAY_INTERFACE void ospCommit(OSPObject);
OSPRAY_INTERFACE void ospRelease(OSPObject);
OSPRAY_INTERFACE void ospRetain(OSPObject);

/* Frame buffers -------------------------------------------------------------- */

OSPRAY_INTERFACE OSPFrameBuffer ospNewFrameBuffer(int size_x, int size_y,
                                                  OSPFrameBufferFormat format OSP_DEFAULT_VAL(OSP_FB_SRGBA),
                                                  uint32_t frameBufferChannels OSP_DEFAULT_VAL(OSP_FB_COLOR));
OSPRAY_INTERFACE OSPImageOperation ospNewImageOperation(const char *type);
/* Read-only pointer to a channel; the first row is the bottom of the image. */
OSPRAY_INTERFACE const void *ospMapFrameBuffer(OSPFrameBuffer, OSPFrameBufferChannel OSP_DEFAULT_VAL(OSP_FB_COLOR));
OSPRAY_INTERFACE void ospUnmapFrameBuffer(const void *mapped, OSPFrameBuffer);
OSPRAY_INTERFACE float ospGetVariance(OSPFrameBuffer);
OSPRAY_INTERFACE void ospResetAccumulation(OSPFrameBuffer);

/* Rendering ----------------------------------------------------------------- */

OSPRAY_INTERFACE OSPRenderer ospNewRenderer(const char *type);
/* Starts rendering one frame asynchronously. */
OSPRAY_INTERFACE OSPFuture ospRenderFrame(OSPFrameBuffer, OSPRenderer, OSPCamera, OSPWorld);
OSPRAY_INTERFACE int ospIsReady(OSPFuture, OSPSyncEvent OSP_DEFAULT_VAL(OSP_TASK_FINISHED));
OSPRAY_INTERFACE void ospWait(OSPFuture, OSPSyncEvent OSP_DEFAULT_VAL(OSP_TASK_FINISHED));
OSPRAY_INTERFACE void ospCancel(OSPFuture);
OSPRAY_INTERFACE float ospGetProgress(OSPFuture);
/* Seconds the task took (0 while it runs). */
OSPRAY_INTERFACE float ospGetTaskDuration(OSPFuture);

typedef struct {
  int hasHit;
  float worldPosition[3];
  OSPInstance instance;
  OSPGeometricModel model;
  uint32_t primID;
} OSPPickResult;

/* What is seen at normalized screen position (0,0) bottom-left to (1,1) top-right.
   The instance and model handles returned are retained: release them. */
OSPRAY_INTERFACE void ospPick(OSPPickResult *result, OSPFrameBuffer, OSPRenderer, OSPCamera, OSPWorld,
                              float screenPos_x, float screenPos_y);

#ifdef __cplusplus
}  // extern "C"
#endif

