/* sciray_mpi_worker: a worker of the mpiOffload device for jobs that launch the
   application and the workers as different programs (MPMD), as OSPRay's ospray_mpi_worker:

     mpirun -n 1 APPLICATION --osp:device=mpiOffload : -n 2 sciray_mpi_worker [--osp:...]

   It takes the device's options (--osp:num-threads=N, --osp:isa=...), joins the job and
   serves the application until it shuts down; the device ends the process then. */
#include <stdio.h>
#include <stdlib.h>

#include <ospray/ospray.h>

int main(int argc, char **argv) {
  const char **args = malloc((size_t)(argc + 2) * sizeof *args);
  int count = argc + 1, i;
  if (!args) return 1;
  for (i = 0; i < argc; ++i) args[i] = argv[i];
  args[argc] = "--osp:device=mpiOffload";
  args[argc + 1] = NULL;
  /* On a worker's rank ospInit does not return. */
  if (ospInit(&count, args) == OSP_NO_ERROR)
    fprintf(stderr, "sciray_mpi_worker: this is the job's first rank, which must be the application\n");
  free(args);
  return 1;
}
