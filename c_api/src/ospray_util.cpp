// The OSPRay 3 utility functions (ospray_util.h), implemented only through the core
// API of ospray.h, as OSPRay's own utility library is.

#include <ospray/ospray_util.h>

extern "C" {

// Data arrays ------------------------------------------------------------------

OSPData ospNewSharedData1D(const void *sharedData, OSPDataType type, uint64_t numItems) {
  return ospNewSharedData(sharedData, type, numItems, 0, 1, 0, 1, 0);
}

OSPData ospNewAssignedData1D(const void *sharedData, OSPDataType type, uint64_t numItems, OSPDeleterCallback deleter,
                             const void *userPtr) {
  return ospNewSharedData(sharedData, type, numItems, 0, 1, 0, 1, 0, deleter, userPtr);
}

OSPData ospNewSharedData1DStride(const void *sharedData, OSPDataType type, uint64_t numItems,
                                 int64_t byteStride) {
  return ospNewSharedData(sharedData, type, numItems, byteStride, 1, 0, 1, 0);
}

OSPData ospNewSharedData2D(const void *sharedData, OSPDataType type, uint64_t numItems1,
                           uint64_t numItems2) {
  return ospNewSharedData(sharedData, type, numItems1, 0, numItems2, 0, 1, 0);
}

OSPData ospNewSharedData2DStride(const void *sharedData, OSPDataType type, uint64_t numItems1,
                                 int64_t byteStride1, uint64_t numItems2, int64_t byteStride2) {
  return ospNewSharedData(sharedData, type, numItems1, byteStride1, numItems2, byteStride2, 1, 0);
}

OSPData ospNewSharedData3D(const void *sharedData, OSPDataType type, uint64_t numItems1,
                           uint64_t numItems2, uint64_t numItems3) {
  return ospNewSharedData(sharedData, type, numItems1, 0, numItems2, 0, numItems3, 0);
}

OSPData ospNewData1D(OSPDataType type, uint64_t numItems) { return ospNewData(type, numItems, 1, 1); }

OSPData ospNewData2D(OSPDataType type, uint64_t numItems1, uint64_t numItems2) {
  return ospNewData(type, numItems1, numItems2, 1);
}

void ospCopyData1D(const OSPData source, OSPData destination, uint64_t destinationIndex) {
  ospCopyData(source, destination, destinationIndex, 0, 0);
}

void ospCopyData2D(const OSPData source, OSPData destination, uint64_t destinationIndex1,
                   uint64_t destinationIndex2) {
  ospCopyData(source, destination, destinationIndex1, destinationIndex2, 0);
}

// Typed parameters ---------------------------------------------------------------

// OSP_STRING takes the string pointer itself as `mem`, not its address.
void ospSetString(OSPObject o, const char *id, const char *s) { ospSetParam(o, id, OSP_STRING, s); }

// Handles are passed by address, like every other value.
void ospSetObject(OSPObject o, const char *id, OSPObject other) { ospSetParam(o, id, OSP_OBJECT, &other); }

// OSP_BOOL is read as a C++ bool, as OSPRay does.
void ospSetBool(OSPObject o, const char *id, int x) {
  const bool b = x != 0;
  ospSetParam(o, id, OSP_BOOL, &b);
}

void ospSetFloat(OSPObject o, const char *id, float x) { ospSetParam(o, id, OSP_FLOAT, &x); }

void ospSetInt(OSPObject o, const char *id, int x) {
  const int32_t v = x;
  ospSetParam(o, id, OSP_INT, &v);
}

void ospSetUInt(OSPObject o, const char *id, unsigned int x) {
  const uint32_t v = x;
  ospSetParam(o, id, OSP_UINT, &v);
}

void ospSetBox1f(OSPObject o, const char *id, float x, float y) {
  const float v[2] = {x, y};
  ospSetParam(o, id, OSP_BOX1F, v);
}

void ospSetLinear2f(OSPObject o, const char *id, float x, float y, float z, float w) {
  const float v[4] = {x, y, z, w};
  ospSetParam(o, id, OSP_LINEAR2F, v);
}

void ospSetVec2f(OSPObject o, const char *id, float x, float y) {
  const float v[2] = {x, y};
  ospSetParam(o, id, OSP_VEC2F, v);
}

void ospSetVec3f(OSPObject o, const char *id, float x, float y, float z) {
  const float v[3] = {x, y, z};
  ospSetParam(o, id, OSP_VEC3F, v);
}

void ospSetVec4f(OSPObject o, const char *id, float x, float y, float z, float w) {
  const float v[4] = {x, y, z, w};
  ospSetParam(o, id, OSP_VEC4F, v);
}

void ospSetVec2i(OSPObject o, const char *id, int x, int y) {
  const int32_t v[2] = {x, y};
  ospSetParam(o, id, OSP_VEC2I, v);
}

void ospSetVec3i(OSPObject o, const char *id, int x, int y, int z) {
  const int32_t v[3] = {x, y, z};
  ospSetParam(o, id, OSP_VEC3I, v);
}

void ospSetVec4i(OSPObject o, const char *id, int x, int y, int z, int w) {
  const int32_t v[4] = {x, y, z, w};
  ospSetParam(o, id, OSP_VEC4I, v);
}

// The handle is copied into an opaque array, so the data does not refer to this
// function's stack once it returns.
void ospSetObjectAsData(OSPObject o, const char *id, OSPDataType type, OSPObject obj) {
  OSPData shared = ospNewSharedData1D(&obj, type, 1);
  OSPData data = ospNewData1D(type, 1);
  ospCopyData1D(shared, data, 0);
  ospSetParam(o, id, OSP_DATA, &data);
  ospRelease(shared);
  ospRelease(data);
}

// Rendering ----------------------------------------------------------------------

float ospRenderFrameBlocking(OSPFrameBuffer fb, OSPRenderer renderer, OSPCamera camera, OSPWorld world) {
  OSPFuture future = ospRenderFrame(fb, renderer, camera, world);
  ospWait(future, OSP_TASK_FINISHED);
  ospRelease(future);
  return ospGetVariance(fb);
}

}  // extern "C"
