/* An OSPRay program for the mpiOffload tests: renders four frames of a path-traced scene
   (noisy, so the variance estimate and adaptive accumulation have work to do) into a frame
   buffer with every channel, and writes each frame's variance and every channel of the last
   frame, as bytes, to OUTPUT. Run once on one process and once under mpirun with
   --osp:device=mpiOffload: the two files must be identical.

     offload_frames [--osp:...] OUTPUT

   Exits non-zero if OSPRay reported an error. */
#include <stdio.h>
#include <string.h>

#include <ospray/ospray.h>
#include <ospray/ospray_util.h>

enum { WIDTH = 150, HEIGHT = 100, FRAMES = 4 };

static int errors = 0;

static void on_error(void *user, OSPError code, const char *details) {
  (void)user;
  ++errors;
  fprintf(stderr, "OSPRay error %d: %s\n", (int)code, details);
}

/* Sets an array on an object and drops our reference to it. */
static void set_array(OSPObject object, const char *id, OSPData data) {
  ospSetObject(object, id, data);
  ospRelease(data);
}

static void write_channel(FILE *out, OSPFrameBuffer fb, OSPFrameBufferChannel channel, size_t bytes) {
  const void *mapped = ospMapFrameBuffer(fb, channel);
  if (!mapped) return;
  fwrite(mapped, 1, bytes, out);
  ospUnmapFrameBuffer(mapped, fb);
}

int main(int argc, char **argv) {
  const float spheres[][4] = {{-1.2f, 0.5f, 0.f, 0.5f}, {0.f, 0.7f, 0.3f, 0.7f}, {1.3f, 0.4f, -0.2f, 0.4f}};
  const float floor_vertices[][3] = {{-4.f, 0.f, -4.f}, {4.f, 0.f, -4.f}, {4.f, 0.f, 4.f}, {-4.f, 0.f, 4.f}};
  const unsigned floor_quad[4] = {0, 1, 2, 3};
  OSPGeometry ball, floor_mesh;
  OSPGeometricModel models[2];
  OSPMaterial material;
  OSPGroup group;
  OSPInstance instance;
  OSPLight light;
  OSPWorld world;
  OSPCamera camera;
  OSPRenderer renderer;
  OSPFrameBuffer fb;
  OSPDevice device;
  FILE *out;
  int frame;
  const size_t pixels = (size_t)WIDTH * HEIGHT;

  if (ospInit(&argc, (const char **)argv) != OSP_NO_ERROR || argc < 2) {
    fprintf(stderr, "usage: offload_frames [--osp:...] OUTPUT\n");
    return 2;
  }
  device = ospGetCurrentDevice();
  ospDeviceSetErrorCallback(device, on_error, NULL);
  ospDeviceRelease(device);

  ball = ospNewGeometry("sphere");
  /* Strided arrays: the workers get them compacted. */
  set_array(ball, "sphere.position", ospNewSharedData(spheres, OSP_VEC3F, 3, sizeof spheres[0], 1, 0, 1, 0, NULL, NULL));
  set_array(ball, "sphere.radius", ospNewSharedData(&spheres[0][3], OSP_FLOAT, 3, sizeof spheres[0], 1, 0, 1, 0, NULL, NULL));
  ospCommit(ball);
  floor_mesh = ospNewGeometry("mesh");
  set_array(floor_mesh, "vertex.position", ospNewSharedData1D(floor_vertices, OSP_VEC3F, 4));
  set_array(floor_mesh, "index", ospNewSharedData1D(floor_quad, OSP_VEC4UI, 1));
  ospCommit(floor_mesh);

  material = ospNewMaterial("principled");
  ospSetVec3f(material, "baseColor", 0.8f, 0.5f, 0.3f);
  ospSetFloat(material, "roughness", 0.3f);
  ospCommit(material);
  models[0] = ospNewGeometricModel(ball);
  ospSetObject(models[0], "material", material);
  ospCommit(models[0]);
  models[1] = ospNewGeometricModel(floor_mesh);
  ospCommit(models[1]);
  group = ospNewGroup();
  set_array(group, "geometry", ospNewSharedData1D(models, OSP_GEOMETRIC_MODEL, 2));
  ospCommit(group);
  instance = ospNewInstance(group);
  ospCommit(instance);

  light = ospNewLight("sunSky");
  ospCommit(light);
  world = ospNewWorld();
  ospSetObjectAsData(world, "instance", OSP_INSTANCE, instance);
  ospSetObjectAsData(world, "light", OSP_LIGHT, light);
  ospCommit(world);

  camera = ospNewCamera("perspective");
  ospSetVec3f(camera, "position", 0.f, 1.5f, 4.f);
  ospSetVec3f(camera, "direction", 0.f, -0.3f, -1.f);
  ospSetFloat(camera, "aspect", (float)WIDTH / HEIGHT);
  ospCommit(camera);

  renderer = ospNewRenderer("pathtracer");
  ospSetInt(renderer, "pixelSamples", 2);
  ospSetFloat(renderer, "varianceThreshold", 0.05f);
  ospCommit(renderer);

  fb = ospNewFrameBuffer(WIDTH, HEIGHT, OSP_FB_RGBA32F,
                         OSP_FB_COLOR | OSP_FB_DEPTH | OSP_FB_ACCUM | OSP_FB_VARIANCE | OSP_FB_NORMAL | OSP_FB_ALBEDO |
                             OSP_FB_ID_PRIMITIVE | OSP_FB_ID_OBJECT | OSP_FB_ID_INSTANCE);
  ospCommit(fb);

  out = fopen(argv[1], "wb");
  if (!out) {
    fprintf(stderr, "cannot write %s\n", argv[1]);
    return 2;
  }
  for (frame = 0; frame < FRAMES; ++frame) {
    const float variance = ospRenderFrameBlocking(fb, renderer, camera, world);
    fwrite(&variance, sizeof variance, 1, out);
    printf("frame %d: variance %g\n", frame + 1, (double)variance);
  }
  write_channel(out, fb, OSP_FB_COLOR, 16 * pixels);
  write_channel(out, fb, OSP_FB_DEPTH, 4 * pixels);
  write_channel(out, fb, OSP_FB_NORMAL, 12 * pixels);
  write_channel(out, fb, OSP_FB_ALBEDO, 12 * pixels);
  write_channel(out, fb, OSP_FB_ID_PRIMITIVE, 4 * pixels);
  write_channel(out, fb, OSP_FB_ID_OBJECT, 4 * pixels);
  write_channel(out, fb, OSP_FB_ID_INSTANCE, 4 * pixels);
  fclose(out);

  ospRelease(fb);
  ospRelease(renderer);
  ospRelease(camera);
  ospRelease(world);
  ospRelease(light);
  ospRelease(instance);
  ospRelease(group);
  ospRelease(models[0]);
  ospRelease(models[1]);
  ospRelease(material);
  ospRelease(floor_mesh);
  ospRelease(ball);
  ospShutdown();
  return errors ? 1 : 0;
}
