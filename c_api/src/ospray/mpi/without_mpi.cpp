// The MPI devices in a build without MPI: choosing one says how to get them.
#include "distributed.hpp"
#include "offload.hpp"

namespace sciray::ospray {
namespace {
[[noreturn]] void without_mpi() {
  throw Error(
      "this sciray was built without MPI: the mpiOffload and mpiDistributed devices need OpenMPI at configure "
      "time (Debian: libopenmpi-dev openmpi-bin; CMake option SCIRAY_MPI)");
}
}  // namespace

std::unique_ptr<offload::Session> offload::start(Device&, const std::function<void()>&) {
  without_mpi();
}
std::unique_ptr<distributed::Session> distributed::start() {
  without_mpi();
}

}  // namespace sciray::ospray
