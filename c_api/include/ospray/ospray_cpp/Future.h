// sciray's OSPRay C++ wrapper: Future, an asynchronous frame (FrameBuffer::renderFrame).
// Dropping the last reference to a running frame's future waits for the frame to finish.
#pragma once

#include "ManagedObject.h"

namespace ospray {
namespace cpp {

class Future : public ManagedObject<OSPFuture, OSP_FUTURE> {
public:
  Future(OSPFuture existing = nullptr) : ManagedObject(existing) {}

  bool isReady(OSPSyncEvent event = OSP_TASK_FINISHED) const { return ospIsReady(ospObject, event) != 0; }
  void wait(OSPSyncEvent event = OSP_TASK_FINISHED) const { ospWait(ospObject, event); }
  void cancel() const { ospCancel(ospObject); }
  // The fraction of the frame done, in [0, 1].
  float progress() const { return ospGetProgress(ospObject); }
  // Seconds the frame took (0 while it runs).
  float duration() const { return ospGetTaskDuration(ospObject); }
};
SCIRAY_OSP_CPP_CHECK_LAYOUT(Future, OSPFuture);

}  // namespace cpp

OSPTYPEFOR_SPECIALIZATION(cpp::Future, OSP_FUTURE)

}  // namespace ospray
