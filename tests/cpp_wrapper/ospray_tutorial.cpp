// OSPRay's C++ tutorial (ospTutorial.cpp with glm), as a test: the same scene built with the
// C++ wrapper (<ospray/ospray_cpp.h>, glm types through ospray_cpp/ext/glm.h), rendered
// through sciray's shim, with the image, picks, bounds, futures and accumulation checked.
// Written in C++11, as OSPRay's wrapper is.
//
//   cpp_wrapper_tutorial [--osp:...] [accumulated.ppm]
//
// Exits non-zero if a check fails or OSPRay reported an unexpected error.

#include <ospray/ospray_cpp.h>
#include <ospray/ospray_cpp/ext/glm.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <initializer_list>
#include <vector>

namespace {

// An application's own box type, taught to the wrapper the way OSPRay documents.
struct Box3 {
  glm::vec3 lower, upper;
};

const int width = 64, height = 48;

int failures = 0;
int errors = 0;

#define CHECK(condition)                                                                 \
  do {                                                                                   \
    if (!(condition)) {                                                                  \
      std::fprintf(stderr, "%s:%d: check failed: %s\n", __FILE__, __LINE__, #condition); \
      ++failures;                                                                        \
    }                                                                                    \
  } while (0)

bool near(float a, float b, float tolerance) {
  return std::fabs(a - b) <= tolerance;
}

// The SRGBA pixel under normalized screen position (u, v), v up (as ospPick takes it).
const std::uint8_t* pixelAt(const std::uint8_t* image, float u, float v) {
  const int x = static_cast<int>(u * width), y = static_cast<int>(v * height);
  return image + 4 * (y * width + x);
}

void writePPM(const char* path, const std::uint8_t* image) {
  std::FILE* file = std::fopen(path, "wb");
  if (!file) {
    std::fprintf(stderr, "cannot write %s\n", path);
    ++failures;
    return;
  }
  std::fprintf(file, "P6\n%d %d\n255\n", width, height);
  for (int y = height - 1; y >= 0; --y)  // the frame buffer's first row is the bottom
    for (int x = 0; x < width; ++x) std::fwrite(image + 4 * (y * width + x), 1, 3, file);
  std::fclose(file);
}

}  // namespace

namespace ospray {
OSPTYPEFOR_SPECIALIZATION(Box3, OSP_BOX3F)
}

int main(int argc, const char** argv) {
  // The tutorial's two triangles, seen square-on from the origin along +z (so world +x is
  // to the left): in the image the first fills the lower right half of a square, the
  // second (leaning towards the camera) its upper left half.
  std::vector<glm::vec3> vertex = {glm::vec3(-1.f, -1.f, 3.f), glm::vec3(-1.f, 1.f, 3.f), glm::vec3(1.f, -1.f, 3.f),
                                   glm::vec3(0.1f, 0.1f, 0.3f)};
  std::vector<glm::vec4> color = {glm::vec4(0.9f, 0.5f, 0.5f, 1.f), glm::vec4(0.8f, 0.8f, 0.8f, 1.f),
                                  glm::vec4(0.8f, 0.8f, 0.8f, 1.f), glm::vec4(0.5f, 0.9f, 0.5f, 1.f)};
  std::vector<glm::uvec3> index = {glm::uvec3(0, 1, 2), glm::uvec3(1, 2, 3)};

  if (ospInit(&argc, argv) != OSP_NO_ERROR) return 1;
  const char* output = argc > 1 ? argv[1] : nullptr;

  {  // scoped, so that every wrapper has released its object before ospShutdown
    ospray::cpp::Device device = ospray::cpp::Device::current();
    device.setErrorCallback([](void*, OSPError code, const char* details) {
      ++errors;
      std::fprintf(stderr, "OSPRay error %d: %s\n", static_cast<int>(code), details);
    });
    device.setStatusCallback([](void*, const char* message) { std::fprintf(stderr, "OSPRay: %s", message); });

    // A failed factory leaves an empty wrapper and reports through the callback.
    {
      ospray::cpp::Geometry teapot("teapot");
      CHECK(!teapot);
      CHECK(errors == 1);
      errors = 0;
    }

    ospray::cpp::Camera camera("perspective");
    camera.setParam("aspect", width / static_cast<float>(height));
    camera.setParam("position", glm::vec3(0.f, 0.f, 0.f));
    camera.setParam("direction", glm::vec3(0.f, 0.f, 1.f));
    camera.setParam("up", glm::vec3(0.f, 1.f, 0.f));
    camera.setParam("fovy", 60.f);
    camera.setParam("stereoMode", OSP_STEREO_NONE);
    camera.commit();

    ospray::cpp::Geometry mesh("mesh");
    mesh.setParam("vertex.position", ospray::cpp::CopiedData(vertex));
    mesh.setParam("vertex.color", ospray::cpp::SharedData(color));  // `color` outlives the mesh
    mesh.setParam("index", ospray::cpp::CopiedData(index));
    mesh.commit();

    ospray::cpp::GeometricModel model(mesh);
    model.commit();

    ospray::cpp::Group group;
    group.setParam("geometry", ospray::cpp::CopiedData(model));
    group.commit();

    ospray::cpp::Instance instance(group);
    instance.commit();

    // A second placement of the same group, moved far to the right (out of view), with a
    // glm::mat4x3: the linear columns, then the translation.
    glm::mat4x3 moved(1.f);
    moved[3] = glm::vec3(10.f, 0.f, 0.f);
    ospray::cpp::Instance movedInstance(group);
    movedInstance.setParam("transform", moved);
    movedInstance.commit();

    ospray::cpp::World world;
    std::vector<ospray::cpp::Instance> instances = {instance, movedInstance};
    world.setParam("instance", ospray::cpp::CopiedData(instances));

    ospray::cpp::Light light("ambient");
    light.commit();
    world.setParam("light", ospray::cpp::CopiedData(light));
    world.commit();

    const Box3 bounds = world.getBounds<Box3>();
    CHECK(near(bounds.lower.x, -1.f, 1e-4f) && near(bounds.lower.y, -1.f, 1e-4f) && near(bounds.lower.z, 0.3f, 1e-4f));
    CHECK(near(bounds.upper.x, 11.f, 1e-4f) && near(bounds.upper.y, 1.f, 1e-4f) && near(bounds.upper.z, 3.f, 1e-4f));

    ospray::cpp::Renderer renderer("scivis");
    renderer.setParam("aoSamples", 1);
    renderer.setParam("backgroundColor", 1.f);  // white, transparent
    renderer.commit();

    ospray::cpp::FrameBuffer framebuffer(width, height, OSP_FB_SRGBA, OSP_FB_COLOR | OSP_FB_ACCUM);
    framebuffer.clear();

    // The tutorial drops the future: releasing it waits for the frame.
    framebuffer.renderFrame(renderer, camera, world);

    const std::uint8_t* image = static_cast<const std::uint8_t*>(framebuffer.map(OSP_FB_COLOR));
    const std::uint8_t* background = pixelAt(image, 0.1f, 0.5f);
    CHECK(background[0] == 255 && background[1] == 255 && background[2] == 255 && background[3] == 0);
    // Inside the triangles: opaque and not the background (one ambient occlusion sample
    // may darken a pixel, so colours are judged on the accumulated image below).
    const float insideFirst[2] = {0.68f, 0.25f}, insideSecond[2] = {0.31f, 0.75f};
    for (const float* inside : {insideFirst, insideSecond}) {
      const std::uint8_t* pixel = pixelAt(image, inside[0], inside[1]);
      CHECK(pixel[3] == 255 && !(pixel[0] == 255 && pixel[1] == 255 && pixel[2] == 255));
    }
    framebuffer.unmap(const_cast<std::uint8_t*>(image));

    // Picks name the wrapper's own objects: the handles are the ones created above.
    ospray::cpp::PickResult hit = framebuffer.pick(renderer, camera, world, 0.65f, 0.3f);
    CHECK(hit.hasHit);
    CHECK(hit.model.handle() == model.handle() && hit.instance.handle() == instance.handle());
    CHECK(hit.primID == 0);
    CHECK(near(hit.worldPosition[2], 3.f, 1e-3f) && hit.worldPosition[0] + hit.worldPosition[1] < 0.f);
    hit = framebuffer.pick(renderer, camera, world, 0.35f, 0.7f);
    CHECK(hit.hasHit && hit.primID == 1 && hit.model.handle() == model.handle());
    const ospray::cpp::PickResult miss = framebuffer.pick(renderer, camera, world, 0.1f, 0.5f);
    CHECK(!miss.hasHit && !miss.model && !miss.instance);

    // Ten more frames accumulate into a converged image, as in the tutorial.
    for (int frame = 0; frame < 10; ++frame) framebuffer.renderFrame(renderer, camera, world);
    image = static_cast<const std::uint8_t*>(framebuffer.map(OSP_FB_COLOR));
    // The vertex colours show: reddish near vertex 0 of the first triangle, greenish near
    // vertex 3 of the second.
    const std::uint8_t* first = pixelAt(image, insideFirst[0], insideFirst[1]);
    const std::uint8_t* second = pixelAt(image, insideSecond[0], insideSecond[1]);
    std::printf("accumulated: (%d, %d, %d) near vertex 0, (%d, %d, %d) near vertex 3\n", first[0], first[1], first[2],
                second[0], second[1], second[2]);
    CHECK(first[0] > first[1] + 20 && first[0] > first[2] + 20);
    CHECK(second[1] > second[0] + 20 && second[1] > second[2] + 20);
    if (output) writePPM(output, image);
    framebuffer.unmap(const_cast<std::uint8_t*>(image));

    // Progressive accumulation: the path tracer's estimated error falls as frames add up,
    // and resetting the accumulation forgets them.
    ospray::cpp::Renderer pathtracer("pathtracer");
    pathtracer.setParam("backgroundColor", glm::vec4(0.f));
    pathtracer.commit();
    ospray::cpp::FrameBuffer accumulating(width, height, OSP_FB_RGBA32F, OSP_FB_COLOR | OSP_FB_ACCUM | OSP_FB_VARIANCE);
    for (int frame = 0; frame < 4; ++frame) accumulating.renderFrame(pathtracer, camera, world).wait();
    const float fewFrames = accumulating.variance();
    for (int frame = 4; frame < 64; ++frame) accumulating.renderFrame(pathtracer, camera, world).wait();
    const float manyFrames = accumulating.variance();
    std::printf("estimated error: %g after 4 frames, %g after 64\n", fewFrames, manyFrames);
    CHECK(std::isfinite(fewFrames) && fewFrames > 0.f);
    CHECK(manyFrames < 0.5f * fewFrames);
    accumulating.resetAccumulation();
    CHECK(std::isinf(accumulating.variance()));

    // A future: waited on, it is ready, complete and timed.
    ospray::cpp::Future future = accumulating.renderFrame(pathtracer, camera, world);
    future.wait();
    CHECK(future.isReady());
    CHECK(future.progress() == 1.f);
    CHECK(future.duration() > 0.f);
    // Cancelled at once, a large frame ends; sciray stops it short of its end (OSPRay 3.1
    // may finish the frame, reporting it complete).
    ospray::cpp::FrameBuffer large(1024, 1024, OSP_FB_SRGBA, OSP_FB_COLOR);
    pathtracer.setParam("pixelSamples", 16);
    pathtracer.commit();
    ospray::cpp::Future cancelled = large.renderFrame(pathtracer, camera, world);
    cancelled.cancel();
    cancelled.wait();
    CHECK(cancelled.isReady());
#ifdef OSPRAY_SCIRAY
    CHECK(cancelled.progress() < 1.f);
#endif

    // Wrappers share their object: copies and moves keep one object alive, no leak (the
    // test runs under LeakSanitizer where available).
    ospray::cpp::GeometricModel copy = model;
    ospray::cpp::GeometricModel moved2(std::move(copy));
    CHECK(!copy && moved2.handle() == model.handle());
    const ospray::cpp::GeometricModel& same = moved2;
    moved2 = same;
    CHECK(moved2.handle() == model.handle());
  }

  ospShutdown();
  CHECK(errors == 0);
  if (failures) std::fprintf(stderr, "%d check(s) failed\n", failures);
  return failures ? 1 : 0;
}
