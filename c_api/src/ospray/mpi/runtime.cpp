#include "runtime.hpp"

#include <string>

#include "sciray/mpi/image_parallel.hpp"

namespace sciray::ospray::mpi_runtime {

Use initialize() {
  int initialized = 0, level = 0;
  mpi::check(MPI_Initialized(&initialized), "MPI_Initialized");
  if (!initialized)
    mpi::check(MPI_Init_thread(nullptr, nullptr, MPI_THREAD_MULTIPLE, &level), "MPI_Init_thread");
  else
    mpi::check(MPI_Query_thread(&level), "MPI_Query_thread");
  if (level < MPI_THREAD_SERIALIZED)
    throw Error(std::string("MPI runs at thread level ") +
                (level == MPI_THREAD_SINGLE ? "MPI_THREAD_SINGLE" : "MPI_THREAD_FUNNELED") +
                "; sciray's MPI devices call MPI from the frame's thread and the application's and need "
                "MPI_THREAD_SERIALIZED (frames then finish inside ospRenderFrame) or MPI_THREAD_MULTIPLE "
                "(MPI_Init_thread)");
  return {!initialized, level};
}

}  // namespace sciray::ospray::mpi_runtime
