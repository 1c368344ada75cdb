/* What the MPI devices do when MPI or the ranks do not cooperate (tests/mpi/CMakeLists.txt
   runs each case under mpirun and checks what this prints):

     mpi_faults funneled   MPI at MPI_THREAD_FUNNELED: committing mpiDistributed is refused
     mpi_faults serialized MPI at MPI_THREAD_SERIALIZED: mpiOffload frames are finished when
                           ospRenderFrame returns (the application may call MPI right away)
     mpi_faults skip       mpiDistributed, rank 1 skips the frame rank 0 renders: rank 0's
                           frame ends with an error within SCIRAY_MPI_TIMEOUT, no deadlock
     mpi_faults overlap    mpiDistributed, both ranks claim the same region: an error
     mpi_faults multiple   MPI at MPI_THREAD_MULTIPLE: the application calls MPI while an
                           mpiOffload frame renders on its own thread

   Prints "error: MESSAGE" for each OSPRay error and "ready: N" for ospIsReady after the frame. */
#include <mpi.h>
#include <stdio.h>
#include <string.h>

#include <ospray/ospray.h>
#include <ospray/ospray_util.h>

static void on_error(void *user, OSPError code, const char *message) {
  (void)user;
  (void)code;
  printf("error: %s\n", message);
  fflush(stdout);
}

/* Makes a device of `type` current (mpiOffload's workers stay in here). */
static void use_device(const char *type) {
  OSPDevice device = ospNewDevice(type);
  ospDeviceSetErrorCallback(device, on_error, NULL);
  ospDeviceCommit(device);
  ospSetCurrentDevice(device);
  ospDeviceRelease(device);
}

/* A one-sphere world, framed, and a frame; each rank owns a slab of its own, or with
   `overlap` all own the same box. With `call_mpi`, the application calls MPI until the
   frame is done. */
static void render_one_frame(int rank, int overlap, int call_mpi) {
  const float center[3] = {0.f, 0.f, 0.f};
  const float region[6] = {-1.f, -1.f, -1.f, 1.f, 1.f, 1.f};
  float mine[6];
  OSPGeometry sphere = ospNewGeometry("sphere");
  OSPData data = ospNewSharedData1D(center, OSP_VEC3F, 1);
  OSPGeometricModel model;
  OSPGroup group;
  OSPInstance instance;
  OSPWorld world;
  OSPCamera camera;
  OSPRenderer renderer;
  OSPFrameBuffer fb;
  OSPFuture future;
  ospSetObject(sphere, "sphere.position", data);
  ospRelease(data);
  ospCommit(sphere);
  model = ospNewGeometricModel(sphere);
  ospCommit(model);
  group = ospNewGroup();
  ospSetObjectAsData(group, "geometry", OSP_GEOMETRIC_MODEL, model);
  ospCommit(group);
  instance = ospNewInstance(group);
  ospCommit(instance);
  world = ospNewWorld();
  ospSetObjectAsData(world, "instance", OSP_INSTANCE, instance);
  /* Shared, not copied: it must outlive the commit below. */
  memcpy(mine, region, sizeof mine);
  if (!overlap) mine[0] = -1.f + (float)rank, mine[3] = (float)rank;
  data = ospNewSharedData1D(mine, OSP_BOX3F, 1);
  ospSetObject(world, "region", data);
  ospRelease(data);
  ospCommit(world);
  camera = ospNewCamera("perspective");
  ospSetVec3f(camera, "position", 0.f, 0.f, 4.f);
  ospSetVec3f(camera, "direction", 0.f, 0.f, -1.f);
  ospCommit(camera);
  renderer = ospNewRenderer("mpiRaycast");
  ospCommit(renderer);
  fb = ospNewFrameBuffer(32, 32, OSP_FB_SRGBA, OSP_FB_COLOR);
  ospCommit(fb);
  future = ospRenderFrame(fb, renderer, camera, world);
  printf("ready: %d\n", future ? ospIsReady(future, OSP_TASK_FINISHED) : -1);
  if (call_mpi && future) {
    int calls = 0;
    while (!ospIsReady(future, OSP_TASK_FINISHED)) MPI_Barrier(MPI_COMM_SELF), ++calls;
    printf("frame done after %d MPI calls of the application\n", calls);
  }
  fflush(stdout);
  if (future) {
    ospWait(future, OSP_TASK_FINISHED);
    ospRelease(future);
  }
  ospRelease(fb);
  ospRelease(renderer);
  ospRelease(camera);
  ospRelease(world);
  ospRelease(instance);
  ospRelease(group);
  ospRelease(model);
  ospRelease(sphere);
}

int main(int argc, char **argv) {
  const char *mode = argc > 1 ? argv[1] : "";
  int level = 0, rank = 0;
  if (strcmp(mode, "funneled") == 0) {
    MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &level);
    use_device("mpiDistributed");
    ospShutdown();
  } else if (strcmp(mode, "serialized") == 0) {
    MPI_Init_thread(&argc, &argv, MPI_THREAD_SERIALIZED, &level);
    use_device("mpiOffload");
    render_one_frame(0, 0, 0);
    ospShutdown();
  } else if (strcmp(mode, "skip") == 0) {
    MPI_Init_thread(&argc, &argv, MPI_THREAD_MULTIPLE, &level);
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    use_device("mpiDistributed");
    if (rank == 0) render_one_frame(0, 0, 0);
    /* The frame rank 1 skipped is still pending on rank 0: end the job here. */
    MPI_Barrier(MPI_COMM_WORLD);
    if (rank == 0) MPI_Abort(MPI_COMM_WORLD, 0);
  } else if (strcmp(mode, "overlap") == 0) {
    MPI_Init_thread(&argc, &argv, MPI_THREAD_MULTIPLE, &level);
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    use_device("mpiDistributed");
    render_one_frame(rank, 1, 0);
    ospShutdown();
  } else if (strcmp(mode, "multiple") == 0) {
    MPI_Init_thread(&argc, &argv, MPI_THREAD_MULTIPLE, &level);
    use_device("mpiOffload");
    render_one_frame(0, 0, 1);
    ospShutdown();
  } else {
    fprintf(stderr, "usage: mpi_faults funneled|serialized|skip|overlap|multiple\n");
    return 2;
  }
  MPI_Finalize();
  return 0;
}
