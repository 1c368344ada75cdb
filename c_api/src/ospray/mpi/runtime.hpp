#pragma once
// MPI's lifetime for the MPI devices: initialized by the first device that needs it
// unless the application did, finalized at the end by whoever initialized it.
#include <mpi.h>

namespace sciray::ospray::mpi_runtime {

struct Use {
  bool finalize;     ///< this process's devices initialized MPI and finalize it
  int thread_level;  ///< what MPI provides
};

/// Initializes MPI with MPI_THREAD_MULTIPLE if the application has not, or takes the
/// application's level; throws below MPI_THREAD_SERIALIZED (the devices call MPI from
/// the frame's thread and the application's).
Use initialize();

}  // namespace sciray::ospray::mpi_runtime
