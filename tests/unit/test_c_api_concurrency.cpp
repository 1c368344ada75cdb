// The C API from several application threads (docs/c-api.md, "Threads"): frames of one
// world into different frame buffers at once, commits racing frames (a frame renders the
// state committed before its ospRenderFrame, never a mix), ospCancel racing completion,
// and releasing objects while frames that use them run. The TSan build runs these too
// (scripts/sanitize.sh).
#include <catch2/catch.hpp>

#include <array>
#include <atomic>
#include <chrono>
#include <cstring>
#include <thread>
#include <vector>

#include <ospray/ospray.h>
#include <ospray/ospray_util.h>

#include "support/api_fixture.hpp"
#include "support/c_api_scenes.hpp"

namespace {

constexpr int width = 48, height = 36;

OSPGeometry two_spheres() {
  OSPGeometry spheres = ospNewGeometry("sphere");
  const float centers[] = {-0.6f, 0.f, 0.f, 0.7f, 0.2f, 0.f};
  OSPData data = ospNewSharedData1D(centers, OSP_VEC3F, 2);
  OSPData copy = ospNewData1D(OSP_VEC3F, 2);
  ospCopyData1D(data, copy, 0);
  ospSetObject(spheres, "sphere.position", copy);
  ospSetFloat(spheres, "radius", 0.5f);
  ospRelease(data);
  ospRelease(copy);
  ospCommit(spheres);
  return spheres;
}

/// Two spheres in an instance whose transform the tests move, seen by a camera they move.
struct Scene : sciray_test::GeometryScene {
  Scene() : GeometryScene(two_spheres()) {}

  void place_camera(float x) { look_from(x, 0.f, -5.f); }
  void move_instance(float dx) {
    const float xfm[12] = {1, 0, 0, 0, 1, 0, 0, 0, 1, dx, 0, 0};
    ospSetParam(instance, "transform", OSP_AFFINE3F, xfm);
    ospCommit(instance);
    ospCommit(world);
  }
};

/// A frame buffer of colour only (no accumulation): every frame stands alone.
OSPFrameBuffer new_frame_buffer() { return ospNewFrameBuffer(width, height, OSP_FB_RGBA32F, OSP_FB_COLOR); }

std::vector<float> render(OSPFrameBuffer fb, const Scene& scene) {
  ospRenderFrameBlocking(fb, scene.renderer, scene.camera, scene.world);
  const auto* pixels = static_cast<const float*>(ospMapFrameBuffer(fb, OSP_FB_COLOR));
  std::vector<float> image(pixels, pixels + 4 * width * height);
  ospUnmapFrameBuffer(pixels, fb);
  return image;
}

}  // namespace

TEST_CASE("C API threads: frames of one world into their own frame buffers at once", "[c_api][threads]") {
  sciray_test::ApiFixture api;
  Scene scene;
  OSPFrameBuffer reference_fb = new_frame_buffer();
  const std::vector<float> reference = render(reference_fb, scene);
  ospRelease(reference_fb);
  constexpr int threads = 4, frames_each = 6;
  std::atomic<int> mismatches{0};
  std::vector<std::thread> workers;
  for (int t = 0; t < threads; ++t)
    workers.emplace_back([&] {
      OSPFrameBuffer fb = new_frame_buffer();
      for (int f = 0; f < frames_each; ++f)
        if (render(fb, scene) != reference) ++mismatches;
      ospRelease(fb);
    });
  for (auto& w : workers) w.join();
  CHECK(mismatches == 0);
  CHECK(api.messages.errors.empty());
}

TEST_CASE("C API threads: a camera or an instance committed while frames run: old or new state, never a mix",
          "[c_api][threads]") {
  sciray_test::ApiFixture api;
  Scene scene;
  OSPFrameBuffer fb = new_frame_buffer();
  // The four states the other thread switches between.
  std::array<std::vector<float>, 4> states;
  for (int k = 0; k < 4; ++k) {
    scene.place_camera(k % 2 ? 0.4f : 0.f);
    scene.move_instance(k / 2 ? -0.3f : 0.f);
    states[static_cast<std::size_t>(k)] = render(fb, scene);
  }
  REQUIRE(states[0] != states[1]);
  REQUIRE(states[0] != states[2]);
  std::atomic<bool> done{false};
  std::thread committer([&] {
    for (int k = 0; !done; ++k) {
      scene.place_camera(k % 2 ? 0.4f : 0.f);
      scene.move_instance((k / 2) % 2 ? -0.3f : 0.f);
    }
  });
  int mixed = 0, seen_changes = 0;
  std::vector<float> last;
  for (int f = 0; f < 60; ++f) {
    const std::vector<float> image = render(fb, scene);
    bool known = false;
    for (const auto& state : states) known = known || image == state;
    if (!known) ++mixed;
    if (!last.empty() && image != last) ++seen_changes;
    last = image;
  }
  done = true;
  committer.join();
  ospRelease(fb);
  CHECK(mixed == 0);
  CHECK(seen_changes > 0);  // the commits did land between frames
  CHECK(api.messages.errors.empty());
}

TEST_CASE("C API threads: ospCancel racing a frame's completion, and releasing what a frame uses", "[c_api][threads]") {
  sciray_test::ApiFixture api;
  OSPFrameBuffer fb = ospNewFrameBuffer(256, 192, OSP_FB_SRGBA, OSP_FB_COLOR | OSP_FB_ACCUM);
  {
    Scene scene;
    ospSetInt(scene.renderer, "pixelSamples", 4);
    ospCommit(scene.renderer);
    for (int k = 0; k < 40; ++k) {
      OSPFuture future = ospRenderFrame(fb, scene.renderer, scene.camera, scene.world);
      // Cancel at different moments: at once, during the frame, after it may have ended.
      std::this_thread::sleep_for(std::chrono::microseconds(250 * (k % 8)));
      ospCancel(future);
      CHECK(ospIsReady(future, OSP_TASK_FINISHED) == 1);
      ospCancel(future);  // again, after completion: nothing happens
      const float progress = ospGetProgress(future);
      CHECK((progress >= 0.f && progress <= 1.f));
      ospRelease(future);
    }
  }
  // The objects of a frame released while it renders: the frame holds its own references.
  for (int k = 0; k < 8; ++k) {
    auto* scene = new Scene;
    OSPFuture future = ospRenderFrame(fb, scene->renderer, scene->camera, scene->world);
    delete scene;  // releases every handle the application held
    ospWait(future, OSP_TASK_FINISHED);
    CHECK(ospGetProgress(future) == 1.f);
    ospRelease(future);
  }
  const auto* pixels = static_cast<const std::uint8_t*>(ospMapFrameBuffer(fb, OSP_FB_COLOR));
  int covered = 0;
  for (int p = 0; p < 256 * 192; ++p) covered += pixels[4 * p + 3] > 0;  // alpha: a sphere was hit
  ospUnmapFrameBuffer(pixels, fb);
  CHECK(covered > 1000);  // the last frames, whose objects were released, rendered the spheres
  ospRelease(fb);
  CHECK(api.messages.errors.empty());
}
