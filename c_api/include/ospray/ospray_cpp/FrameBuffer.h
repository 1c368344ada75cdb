// sciray's OSPRay C++ wrapper: FrameBuffer, where frames are rendered, accumulated and read,
// and PickResult, what ospPick saw at a screen position.
#pragma once

#include <cstdint>

#include "Camera.h"
#include "Future.h"
#include "GeometricModel.h"
#include "Instance.h"
#include "Renderer.h"
#include "World.h"

namespace ospray {
namespace cpp {

// The instance and model own the references ospPick returned (both empty without a hit).
struct PickResult {
  bool hasHit{false};
  float worldPosition[3] = {0.f, 0.f, 0.f};
  Instance instance{static_cast<OSPInstance>(nullptr)};
  GeometricModel model{static_cast<OSPGeometricModel>(nullptr)};
  std::uint32_t primID{0};
};

class FrameBuffer : public ManagedObject<OSPFrameBuffer, OSP_FRAMEBUFFER> {
public:
  // An empty wrapper (no frame buffer is made): assign one later.
  FrameBuffer() = default;
  FrameBuffer(int size_x, int size_y, OSPFrameBufferFormat format = OSP_FB_SRGBA, int channels = OSP_FB_COLOR)
      : ManagedObject(ospNewFrameBuffer(size_x, size_y, format, static_cast<std::uint32_t>(channels))) {}
  FrameBuffer(OSPFrameBuffer existing) : ManagedObject(existing) {}

  void resetAccumulation() const { ospResetAccumulation(ospObject); }
  // OSPRay's older name for resetAccumulation.
  void clear() const { ospResetAccumulation(ospObject); }

  // Starts a frame and returns at once; the future tracks it.
  Future renderFrame(const Renderer& renderer, const Camera& camera, const World& world) const {
    return Future(ospRenderFrame(ospObject, renderer.handle(), camera.handle(), world.handle()));
  }

  // What is seen at normalized screen position (0,0) bottom-left to (1,1) top-right.
  PickResult pick(const Renderer& renderer, const Camera& camera, const World& world, float screenPos_x,
                  float screenPos_y) const {
    OSPPickResult picked{};
    ospPick(&picked, ospObject, renderer.handle(), camera.handle(), world.handle(), screenPos_x, screenPos_y);
    PickResult result;
    result.hasHit = picked.hasHit != 0;
    result.instance = Instance(picked.instance);
    result.model = GeometricModel(picked.model);
    if (result.hasHit) {
      for (int axis = 0; axis < 3; ++axis) result.worldPosition[axis] = picked.worldPosition[axis];
      result.primID = picked.primID;
    }
    return result;
  }

  // The channel's pixels, rows from the bottom of the image; read-only, unmap when done.
  void* map(OSPFrameBufferChannel channel) const { return const_cast<void*>(ospMapFrameBuffer(ospObject, channel)); }
  void unmap(void* mapped) const { ospUnmapFrameBuffer(mapped, ospObject); }

  float variance() const { return ospGetVariance(ospObject); }
};
SCIRAY_OSP_CPP_CHECK_LAYOUT(FrameBuffer, OSPFrameBuffer);

}  // namespace cpp

OSPTYPEFOR_SPECIALIZATION(cpp::FrameBuffer, OSP_FRAMEBUFFER)

}  // namespace ospray
