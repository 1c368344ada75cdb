/* Convenience functions of the OSPRay 3 API, built on ospray.h (implemented by
   libsciray_ospray). Usable from C99 and C++. */
#pragma once

#include "ospray.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Data arrays */
OSPRAY_INTERFACE OSPData ospNewSharedData1D(const void *sharedData, OSPDataType, uint64_t numItems);
/* Shared data whose deleter is called with userPtr and sharedData once the array is released. */
OSPRAY_INTERFACE OSPData ospNewAssignedData1D(const void *sharedData, OSPDataType, uint64_t numItems,
                                              OSPDeleterCallback, const void *userPtr);
OSPRAY_INTERFACE OSPData ospNewSharedData1DStride(const void *sharedData, OSPDataType, uint64_t numItems,
                                                  int64_t byteStride);
OSPRAY_INTERFACE OSPData ospNewSharedData2D(const void *sharedData, OSPDataType, uint64_t numItems1,
                                            uint64_t numItems2);
OSPRAY_INTERFACE OSPData ospNewSharedData2DStride(const void *sharedData, OSPDataType, uint64_t numItems1,
                                                  int64_t byteStride1, uint64_t numItems2, int64_t byteStride2);
OSPRAY_INTERFACE OSPData ospNewSharedData3D(const void *sharedData, OSPDataType, uint64_t numItems1,
                                            uint64_t numItems2, uint64_t numItems3);
OSPRAY_INTERFACE OSPData ospNewData1D(OSPDataType, uint64_t numItems);
OSPRAY_INTERFACE OSPData ospNewData2D(OSPDataType, uint64_t numItems1, uint64_t numItems2);
OSPRAY_INTERFACE void ospCopyData1D(const OSPData source, OSPData destination, uint64_t destinationIndex);
OSPRAY_INTERFACE void ospCopyData2D(const OSPData source, OSPData destination, uint64_t destinationIndex1,
                                    uint64_t destinationIndex2);

/* Typed parameters */
OSPRAY_INTERFACE void ospSetString(OSPObject, const char *id, const char *s);
OSPRAY_INTERFACE void ospSetObject(OSPObject, const char *id, OSPObject other);
OSPRAY_INTERFACE void ospSetBool(OSPObject, const char *id, int x);
OSPRAY_INTERFACE void ospSetFloat(OSPObject, const char *id, float x);
OSPRAY_INTERFACE void ospSetInt(OSPObject, const char *id, int x);
OSPRAY_INTERFACE void ospSetUInt(OSPObject, const char *id, unsigned int x);
/* A range [x, y] as box1f. */
OSPRAY_INTERFACE void ospSetBox1f(OSPObject, const char *id, float x, float y);
/* A 2x2 matrix as linear2f: columns (x, y) and (z, w). */
OSPRAY_INTERFACE void ospSetLinear2f(OSPObject, const char *id, float x, float y, float z, float w);
OSPRAY_INTERFACE void ospSetVec2f(OSPObject, const char *id, float x, float y);
OSPRAY_INTERFACE void ospSetVec3f(OSPObject, const char *id, float x, float y, float z);
OSPRAY_INTERFACE void ospSetVec4f(OSPObject, const char *id, float x, float y, float z, float w);
OSPRAY_INTERFACE void ospSetVec2i(OSPObject, const char *id, int x, int y);
OSPRAY_INTERFACE void ospSetVec3i(OSPObject, const char *id, int x, int y, int z);
OSPRAY_INTERFACE void ospSetVec4i(OSPObject, const char *id, int x, int y, int z, int w);
/* Wraps one object in a one-element data array of `type` and sets that. */
OSPRAY_INTERFACE void ospSetObjectAsData(OSPObject, const char *id, OSPDataType type, OSPObject obj);

/* Renders a frame and waits for it; returns the frame buffer's variance estimate. */
OSPRAY_INTERFACE float ospRenderFrameBlocking(OSPFrameBuffer, OSPRenderer, OSPCamera, OSPWorld);

#ifdef __cplusplus
}  // extern "C"
#endif
