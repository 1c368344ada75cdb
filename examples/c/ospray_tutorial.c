/* A tour of sciray's OSPRay 3 C API from plain C99: builds a small coloured scene (a
   floor and a pyramid), renders it with progressive accumulation, writes a PNG, and
   queries the world's bounds and what the centre pixel sees.

     ospray_tutorial [--osp:...] [output.png]

   Exits non-zero if OSPRay reported any error. */

#include <stdint.h>
#include <stdio.h>

#include <ospray/ospray.h>
#include <ospray/ospray_util.h>
#include <stb/stb_image_write.h>

enum { WIDTH = 480, HEIGHT = 320 };

static void on_error(void *userData, OSPError code, const char *details) {
  int *errors = (int *)userData;
  ++*errors;
  fprintf(stderr, "OSPRay error %d: %s\n", (int)code, details ? details : "(no details)");
}

static void on_status(void *userData, const char *message) {
  (void)userData;
  fprintf(stderr, "OSPRay: %s", message ? message : "");
}

int main(int argc, char **argv) {
  int errors = 0;
  const char *output;
  OSPDevice device;

  /* Geometry, shared with OSPRay: it must outlive every object that uses it. */
  const float positions[][3] = {
      /* floor */
      {-3.0f, 0.0f, -3.0f}, {3.0f, 0.0f, -3.0f}, {3.0f, 0.0f, 3.0f}, {-3.0f, 0.0f, 3.0f},
      /* pyramid: base corners, then apex */
      {-1.0f, 0.0f, -1.0f}, {1.0f, 0.0f, -1.0f}, {1.0f, 0.0f, 1.0f}, {-1.0f, 0.0f, 1.0f},
      {0.0f, 1.5f, 0.0f}};
  const float colors[][4] = {
      {0.8f, 0.8f, 0.8f, 1.0f}, {0.8f, 0.8f, 0.8f, 1.0f}, {0.8f, 0.8f, 0.8f, 1.0f},
      {0.8f, 0.8f, 0.8f, 1.0f}, {0.9f, 0.1f, 0.1f, 1.0f}, {0.1f, 0.9f, 0.1f, 1.0f},
      {0.1f, 0.2f, 0.9f, 1.0f}, {0.9f, 0.8f, 0.1f, 1.0f}, {1.0f, 1.0f, 1.0f, 1.0f}};
  const uint32_t triangles[][3] = {
      {0, 1, 2}, {0, 2, 3},                        /* floor quad as two triangles */
      {4, 5, 8}, {5, 6, 8}, {6, 7, 8}, {7, 4, 8}}; /* pyramid sides */
  const uint64_t vertexCount = sizeof positions / sizeof positions[0];
  const uint64_t triangleCount = sizeof triangles / sizeof triangles[0];
  /* Instance placement: a 3x3 linear part (columns) followed by a translation. */
  const float transform[12] = {1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0};

  OSPGeometry mesh;
  OSPData data;
  OSPMaterial material;
  OSPGeometricModel model;
  OSPGroup group;
  OSPInstance instance;
  OSPLight lights[2];
  OSPWorld world;
  OSPCamera camera;
  OSPRenderer renderer;
  OSPFrameBuffer framebuffer;
  OSPFuture future;
  OSPBounds bounds;
  OSPPickResult pick;
  const unsigned char *pixels;
  const float *depth;
  int frame;

  /* ospInit consumes the --osp:... arguments, so argv[1] is ours afterwards. */
  if (ospInit(&argc, (const char **)argv) != OSP_NO_ERROR) {
    fprintf(stderr, "ospInit failed\n");
    return 1;
  }
  output = argc > 1 ? argv[1] : "ospray_tutorial.png";

  device = ospGetCurrentDevice(); /* a new reference: released below */
  ospDeviceSetErrorCallback(device, on_error, &errors);
  ospDeviceSetStatusCallback(device, on_status, NULL);
  ospDeviceRelease(device);

  /* Triangle mesh with per-vertex colours. */
  mesh = ospNewGeometry("mesh");
  data = ospNewSharedData1D(positions, OSP_VEC3F, vertexCount);
  ospCommit(data);
  ospSetObject(mesh, "vertex.position", data);
  ospRelease(data);
  data = ospNewSharedData1D(colors, OSP_VEC4F, vertexCount);
  ospCommit(data);
  ospSetObject(mesh, "vertex.color", data);
  ospRelease(data);
  data = ospNewSharedData1D(triangles, OSP_VEC3UI, triangleCount);
  ospCommit(data);
  ospSetObject(mesh, "index", data);
  ospRelease(data);
  ospCommit(mesh);

  /* The model gives the geometry its appearance; objects hold references to what is
     set on them, so our own handles can go once they are set. */
  material = ospNewMaterial("obj");
  ospSetVec3f(material, "kd", 0.8f, 0.8f, 0.8f);
  ospCommit(material);
  model = ospNewGeometricModel(mesh);
  ospSetObject(model, "material", material);
  ospCommit(model);
  ospRelease(mesh);
  ospRelease(material);

  group = ospNewGroup();
  ospSetObjectAsData(group, "geometry", OSP_GEOMETRIC_MODEL, model);
  ospCommit(group);

  instance = ospNewInstance(group);
  ospSetParam(instance, "transform", OSP_AFFINE3F, transform);
  ospCommit(instance);
  ospRelease(group);

  lights[0] = ospNewLight("distant");
  ospSetVec3f(lights[0], "direction", -0.5f, -1.0f, -0.7f);
  ospSetVec3f(lights[0], "color", 1.0f, 0.95f, 0.9f);
  ospSetFloat(lights[0], "intensity", 2.0f);
  ospCommit(lights[0]);
  lights[1] = ospNewLight("ambient");
  ospSetFloat(lights[1], "intensity", 0.4f);
  ospCommit(lights[1]);

  world = ospNewWorld();
  ospSetObjectAsData(world, "instance", OSP_INSTANCE, instance);
  data = ospNewSharedData1D(lights, OSP_LIGHT, 2);
  ospCommit(data);
  ospSetObject(world, "light", data);
  ospRelease(data);
  ospCommit(world);
  ospRelease(instance);
  ospRelease(lights[0]);
  ospRelease(lights[1]);

  camera = ospNewCamera("perspective");
  ospSetVec3f(camera, "position", 0.0f, 1.8f, 5.0f);
  ospSetVec3f(camera, "direction", 0.0f, -1.2f, -5.0f);
  ospSetVec3f(camera, "up", 0.0f, 1.0f, 0.0f);
  ospSetFloat(camera, "aspect", (float)WIDTH / (float)HEIGHT);
  ospSetFloat(camera, "fovy", 45.0f);
  ospCommit(camera);

  renderer = ospNewRenderer("scivis");
  ospSetVec4f(renderer, "backgroundColor", 0.15f, 0.17f, 0.22f, 1.0f);
  ospSetInt(renderer, "pixelSamples", 1);
  ospSetBool(renderer, "shadows", 1);
  ospCommit(renderer);

  framebuffer = ospNewFrameBuffer(WIDTH, HEIGHT, OSP_FB_SRGBA, OSP_FB_COLOR | OSP_FB_ACCUM | OSP_FB_DEPTH);
  ospCommit(framebuffer);
  ospResetAccumulation(framebuffer);

  /* Progressive refinement: each frame adds samples to the accumulation buffer. */
  for (frame = 1; frame <= 4; ++frame) {
    const float variance = ospRenderFrameBlocking(framebuffer, renderer, camera, world);
    printf("frame %d rendered, variance %g\n", frame, (double)variance);
  }

  /* The asynchronous form: start a frame, wait for it, then ask how it went. */
  future = ospRenderFrame(framebuffer, renderer, camera, world);
  ospWait(future, OSP_TASK_FINISHED);
  printf("frame 5: ready %d, progress %.2f, %.4f s\n", ospIsReady(future, OSP_TASK_FINISHED),
         (double)ospGetProgress(future), (double)ospGetTaskDuration(future));
  ospRelease(future);

  /* OSPRay maps the bottom row first; PNG stores the top row first. */
  pixels = (const unsigned char *)ospMapFrameBuffer(framebuffer, OSP_FB_COLOR);
  if (pixels) {
    stbi_flip_vertically_on_write(1);
    if (stbi_write_png(output, WIDTH, HEIGHT, 4, pixels, 4 * WIDTH))
      printf("wrote %s\n", output);
    else {
      fprintf(stderr, "could not write %s\n", output);
      ++errors;
    }
    ospUnmapFrameBuffer(pixels, framebuffer);
  }

  depth = (const float *)ospMapFrameBuffer(framebuffer, OSP_FB_DEPTH);
  if (depth) {
    printf("depth at the centre pixel: %g\n", (double)depth[(HEIGHT / 2) * WIDTH + WIDTH / 2]);
    ospUnmapFrameBuffer(depth, framebuffer);
  }

  bounds = ospGetBounds(world);
  printf("world bounds: (%g, %g, %g) - (%g, %g, %g)\n", (double)bounds.lower[0], (double)bounds.lower[1],
         (double)bounds.lower[2], (double)bounds.upper[0], (double)bounds.upper[1], (double)bounds.upper[2]);

  ospPick(&pick, framebuffer, renderer, camera, world, 0.5f, 0.5f);
  if (pick.hasHit) {
    printf("centre pixel sees primitive %u at (%g, %g, %g)%s\n", (unsigned)pick.primID,
           (double)pick.worldPosition[0], (double)pick.worldPosition[1], (double)pick.worldPosition[2],
           pick.model == model ? " on the mesh's model" : "");
  } else {
    printf("centre pixel sees the background\n");
  }
  /* The handles a pick returns are new references. */
  if (pick.instance) ospRelease(pick.instance);
  if (pick.model) ospRelease(pick.model);

  ospRelease(model);
  ospRelease(framebuffer);
  ospRelease(renderer);
  ospRelease(camera);
  ospRelease(world);
  ospShutdown();

  if (errors) fprintf(stderr, "%d OSPRay error(s) reported\n", errors);
  return errors ? 1 : 0;
}
