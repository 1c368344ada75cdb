// OSPRay C API: frame buffer channels (normal, albedo, ids), the tonemapper image
// operation, and the cameras' depth of field, stereo and panoramic projection, through
// the same calls an OSPRay application makes.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include <ospray/ospray.h>
#include <ospray/ospray_util.h>

#include "sciray/frame/image_ops.hpp"
#include "support/api_fixture.hpp"
#include "support/c_api_scenes.hpp"

namespace {

using sciray_test::ApiFixture;

/// Spheres of radius 1 (one geometry, one model, one instance), ambient light, scivis,
/// and a camera of the given type at (0, 0, -5) looking down +z (its right is -x).
struct SphereScene {
  OSPGeometry geometry = ospNewGeometry("sphere");
  OSPGeometricModel model;
  OSPGroup group = ospNewGroup();
  OSPInstance instance = ospNewInstance(group);
  OSPWorld world = ospNewWorld();
  OSPCamera camera;
  OSPRenderer renderer = ospNewRenderer("scivis");
  OSPLight light = ospNewLight("ambient");

  SphereScene(const std::vector<float>& centers, const char* camera_type) : camera(ospNewCamera(camera_type)) {
    OSPData positions = ospNewSharedData1D(centers.data(), OSP_VEC3F, centers.size() / 3);
    ospSetObject(geometry, "sphere.position", positions);
    ospRelease(positions);
    ospSetFloat(geometry, "radius", 1.f);
    ospCommit(geometry);
    model = ospNewGeometricModel(geometry);
    ospCommit(model);
    ospSetObjectAsData(group, "geometry", OSP_GEOMETRIC_MODEL, model);
    ospCommit(group);
    ospCommit(instance);
    ospSetObjectAsData(world, "instance", OSP_INSTANCE, instance);
    ospCommit(light);
    ospSetObjectAsData(world, "light", OSP_LIGHT, light);
    ospCommit(world);
    ospSetVec3f(camera, "position", 0.f, 0.f, -5.f);
    ospSetVec3f(camera, "direction", 0.f, 0.f, 1.f);
    ospCommit(camera);
    ospSetVec4f(renderer, "backgroundColor", 0.1f, 0.2f, 0.3f, 1.f);
    ospCommit(renderer);
  }
  SphereScene(const SphereScene&) = delete;
  SphereScene& operator=(const SphereScene&) = delete;
  ~SphereScene() {
    for (OSPObject o :
         std::initializer_list<OSPObject>{geometry, model, group, instance, world, camera, renderer, light})
      ospRelease(o);
  }

  /// The pick at screen position (x, y), its handles released.
  OSPPickResult pick(float x, float y) const {
    OSPFrameBuffer fb = ospNewFrameBuffer(8, 8);
    OSPPickResult result;
    ospPick(&result, fb, renderer, camera, world, x, y);
    ospRelease(fb);
    if (result.hasHit) {
      ospRelease(result.instance);
      ospRelease(result.model);
    }
    return result;
  }

  /// `frames` frames into an RGBA32F frame buffer with accumulation: colour, first row
  /// at the bottom.
  std::vector<float> render(int w, int h, int frames = 1) const {
    OSPFrameBuffer fb = ospNewFrameBuffer(w, h, OSP_FB_RGBA32F, OSP_FB_COLOR | OSP_FB_ACCUM);
    for (int f = 0; f < frames; ++f) ospRenderFrameBlocking(fb, renderer, camera, world);
    const auto* p = static_cast<const float*>(ospMapFrameBuffer(fb, OSP_FB_COLOR));
    std::vector<float> out(p, p + 4 * w * h);
    ospUnmapFrameBuffer(p, fb);
    ospRelease(fb);
    return out;
  }
};

template <class T>
std::vector<T> map_channel(OSPFrameBuffer fb, OSPFrameBufferChannel channel, std::size_t count) {
  const auto* p = static_cast<const T*>(ospMapFrameBuffer(fb, channel));
  REQUIRE(p != nullptr);
  std::vector<T> out(p, p + count);
  ospUnmapFrameBuffer(p, fb);
  return out;
}

}  // namespace

TEST_CASE("frame buffer: normal, albedo and id channels map as OSPRay lays them out", "[c_api][frame]") {
  ApiFixture api;
  SphereScene scene({0.f, 0.f, 0.f}, "perspective");
  constexpr int size = 32;
  const std::uint32_t all = OSP_FB_COLOR | OSP_FB_DEPTH | OSP_FB_ACCUM | OSP_FB_VARIANCE | OSP_FB_NORMAL |
                            OSP_FB_ALBEDO | OSP_FB_ID_PRIMITIVE | OSP_FB_ID_OBJECT | OSP_FB_ID_INSTANCE;
  OSPFrameBuffer fb = ospNewFrameBuffer(size, size, OSP_FB_RGBA32F, all);
  CHECK(!api.messages.any_status_containing("channel"));  // every channel is supported
  for (int f = 0; f < 3; ++f) ospRenderFrameBlocking(fb, scene.renderer, scene.camera, scene.world);
  const std::size_t centre = (size / 2) * size + size / 2, corner = 0;

  const auto normal = map_channel<float>(fb, OSP_FB_NORMAL, 3 * size * size);  // float3 per pixel
  // Facing the camera; the pixel and its jittered samples lie up to ~2 pixels (0.2 of the
  // radius) off the sphere's centre.
  CHECK(normal[3 * centre + 0] == Approx(0.f).margin(0.2));
  CHECK(normal[3 * centre + 1] == Approx(0.f).margin(0.2));
  CHECK(normal[3 * centre + 2] < -0.95f);
  CHECK(normal[3 * corner + 2] == 0.f);
  const auto albedo = map_channel<float>(fb, OSP_FB_ALBEDO, 3 * size * size);
  CHECK(albedo[3 * centre] == Approx(0.8f).margin(0.01));  // the default grey
  CHECK(albedo[3 * corner + 2] == Approx(0.3f));           // the background where nothing is hit
  const auto primitive = map_channel<std::uint32_t>(fb, OSP_FB_ID_PRIMITIVE, size * size);
  const auto object = map_channel<std::uint32_t>(fb, OSP_FB_ID_OBJECT, size * size);
  const auto instance = map_channel<std::uint32_t>(fb, OSP_FB_ID_INSTANCE, size * size);
  CHECK(primitive[centre] == 0u);
  CHECK(object[centre] == 0u);
  CHECK(instance[centre] == 0u);
  CHECK(primitive[corner] == 0xFFFFFFFFu);
  CHECK(object[corner] == 0xFFFFFFFFu);
  CHECK(instance[corner] == 0xFFFFFFFFu);
  const auto depth = map_channel<float>(fb, OSP_FB_DEPTH, size * size);
  CHECK(depth[centre] == Approx(4.f).epsilon(0.01));
  CHECK(std::isfinite(ospGetVariance(fb)));
  CHECK(api.messages.errors.empty());

  CHECK(ospMapFrameBuffer(fb, OSP_FB_VARIANCE) == nullptr);
  api.expect_error("OSP_FB_VARIANCE cannot be mapped");
  CHECK(ospMapFrameBuffer(fb, OSP_FB_ACCUM) == nullptr);
  api.expect_error("OSP_FB_ACCUM cannot be mapped");
  ospRelease(fb);

  OSPFrameBuffer plain = ospNewFrameBuffer(4, 4, OSP_FB_RGBA8, OSP_FB_COLOR | (1u << 12));
  CHECK(api.messages.any_status_containing("channel bits 4096"));
  for (const auto& [channel, name] :
       {std::pair{OSP_FB_NORMAL, "OSP_FB_NORMAL"}, {OSP_FB_ALBEDO, "OSP_FB_ALBEDO"},
        {OSP_FB_ID_PRIMITIVE, "OSP_FB_ID_PRIMITIVE"}, {OSP_FB_ID_OBJECT, "OSP_FB_ID_OBJECT"},
        {OSP_FB_ID_INSTANCE, "OSP_FB_ID_INSTANCE"}}) {
    CHECK(ospMapFrameBuffer(plain, channel) == nullptr);
    api.expect_error(std::string("cannot map ") + name + ": it was not created with it");
  }
  ospRelease(plain);
}

TEST_CASE("image operations: the tonemapper maps the frame buffer's colour", "[c_api][frame][tonemapper]") {
  ApiFixture api;
  SphereScene scene({0.f, 0.f, 0.f}, "perspective");
  constexpr int size = 16;
  OSPImageOperation tonemapper = ospNewImageOperation("tonemapper");
  ospSetFloat(tonemapper, "exposure", 3.f);
  ospSetBool(tonemapper, "acesColor", false);
  ospCommit(tonemapper);
  OSPFrameBuffer fb = ospNewFrameBuffer(size, size, OSP_FB_RGBA32F, OSP_FB_COLOR | OSP_FB_ACCUM);
  ospRenderFrameBlocking(fb, scene.renderer, scene.camera, scene.world);
  const auto plain = map_channel<float>(fb, OSP_FB_COLOR, 4 * size * size);
  ospSetObjectAsData(fb, "imageOperation", OSP_IMAGE_OPERATION, tonemapper);
  ospCommit(fb);  // the accumulated frame is tone mapped at once
  sciray::TonemapperParams expected_params;
  expected_params.exposure = 3.f;
  expected_params.aces_color = false;
  const sciray::Tonemapper expected(expected_params);
  const auto mapped = map_channel<float>(fb, OSP_FB_COLOR, 4 * size * size);
  for (std::size_t p = 0; p < size * size; ++p) {
    const sciray::Vec3f rgb = expected(sciray::Vec3f{plain[4 * p], plain[4 * p + 1], plain[4 * p + 2]});
    REQUIRE(mapped[4 * p] == Approx(rgb.x).margin(1e-5));
    REQUIRE(mapped[4 * p + 2] == Approx(rgb.z).margin(1e-5));
    REQUIRE(mapped[4 * p + 3] == plain[4 * p + 3]);  // alpha untouched
  }
  ospRenderFrameBlocking(fb, scene.renderer, scene.camera, scene.world);  // frames keep being mapped
  CHECK(map_channel<float>(fb, OSP_FB_COLOR, 4)[0] != plain[0]);
  ospRemoveParam(fb, "imageOperation");
  ospCommit(fb);
  CHECK(map_channel<float>(fb, OSP_FB_COLOR, 4)[0] == Approx(plain[0]).margin(1e-4));
  CHECK(api.messages.errors.empty());

  // What cannot work is named.
  CHECK(ospNewImageOperation("denoiser") == nullptr);
  api.expect_error("unknown image operation type 'denoiser' (sciray supports: tonemapper, debug)");
  ospSetFloat(tonemapper, "contrast", -1.f);
  ospCommit(tonemapper);
  api.expect_error("ospCommit: tonemapper: 'contrast' must be positive");
  // An uncommitted operation has its defaults, as in OSPRay (its parameters are unseen).
  OSPImageOperation uncommitted = ospNewImageOperation("tonemapper");
  ospSetFloat(uncommitted, "exposure", 100.f);
  ospSetObjectAsData(fb, "imageOperation", OSP_IMAGE_OPERATION, uncommitted);
  ospCommit(fb);
  CHECK(api.messages.errors.empty());
  const sciray::Vec3f by_default = sciray::Tonemapper{}(sciray::Vec3f{plain[0], plain[1], plain[2]});
  CHECK(map_channel<float>(fb, OSP_FB_COLOR, 4)[0] == Approx(by_default.x).margin(1e-5));
  ospSetObject(fb, "imageOperation", scene.camera);
  ospCommit(fb);
  api.expect_error("parameter 'imageOperation' must be an OSPImageOperation, got OSPCamera");
  ospRelease(uncommitted);
  ospRelease(tonemapper);
  ospRelease(fb);
}

TEST_CASE("image operations: debug sets red to 1 after the tonemapper, as OSPRay's", "[c_api][frame]") {
  ApiFixture api;
  SphereScene scene({0.f, 0.f, 0.f}, "perspective");
  constexpr int size = 16;
  OSPImageOperation tonemapper = ospNewImageOperation("tonemapper"), debug = ospNewImageOperation("debug");
  ospCommit(tonemapper);
  ospCommit(debug);
  OSPFrameBuffer fb = ospNewFrameBuffer(size, size, OSP_FB_RGBA32F, OSP_FB_COLOR | OSP_FB_ACCUM);
  ospRenderFrameBlocking(fb, scene.renderer, scene.camera, scene.world);
  const auto plain = map_channel<float>(fb, OSP_FB_COLOR, 4 * size * size);
  const OSPImageOperation both[] = {tonemapper, debug};
  OSPData list = ospNewSharedData1D(both, OSP_IMAGE_OPERATION, 2);
  ospSetObject(fb, "imageOperation", list);
  ospCommit(fb);
  const sciray::Tonemapper expected;
  const auto marked = map_channel<float>(fb, OSP_FB_COLOR, 4 * size * size);
  for (std::size_t p = 0; p < size * size; ++p) {
    const sciray::Vec3f rgb = expected(sciray::Vec3f{plain[4 * p], plain[4 * p + 1], plain[4 * p + 2]});
    REQUIRE(marked[4 * p] == 1.f);
    REQUIRE(marked[4 * p + 1] == Approx(rgb.y).margin(1e-5));
    REQUIRE(marked[4 * p + 3] == plain[4 * p + 3]);
  }
  CHECK(api.messages.errors.empty());
  ospRelease(list);
  ospRelease(tonemapper);
  ospRelease(debug);
  ospRelease(fb);
}

TEST_CASE("cameras: depth of field, stereo eyes and the panoramic camera through the C API", "[c_api][camera]") {
  ApiFixture api;
  SECTION("panoramic: the centre looks along direction, the edges behind, the whole sphere around") {
    // Spheres ahead (+z), to the camera's right (-x) and behind (-z), seen from the origin.
    SphereScene scene({0.f, 0.f, 5.f, -5.f, 0.f, 0.f, 0.f, 0.f, -5.f}, "panoramic");
    ospSetVec3f(scene.camera, "position", 0.f, 0.f, 0.f);
    ospCommit(scene.camera);
    const OSPPickResult ahead = scene.pick(0.5f, 0.5f), right = scene.pick(0.75f, 0.5f), behind = scene.pick(0.f, 0.5f);
    REQUIRE(ahead.hasHit == 1);
    REQUIRE(right.hasHit == 1);
    REQUIRE(behind.hasHit == 1);
    CHECK(ahead.primID == 0);
    CHECK(ahead.worldPosition[2] == Approx(4.f));
    CHECK(right.primID == 1);
    CHECK(right.worldPosition[0] == Approx(-4.f));
    CHECK(behind.primID == 2);
    CHECK(scene.pick(0.5f, 0.99f).hasHit == 0);  // straight up
    const auto image = scene.render(64, 32);
    CHECK(image[4 * (16 * 64 + 32)] != image[4 * (31 * 64 + 32)]);  // a sphere ahead, sky above
  }
  SECTION("stereo: side by side, the eyes converge at focusDistance") {
    SphereScene scene({0.f, 0.f, 0.f}, "perspective");
    ospSetInt(scene.camera, "stereoMode", OSP_STEREO_SIDE_BY_SIDE);
    ospSetFloat(scene.camera, "interpupillaryDistance", 1.f);
    ospSetFloat(scene.camera, "focusDistance", 5.f);
    ospCommit(scene.camera);
    // The left eye sits at x = +0.5 (the camera's right is -x) and looks at the origin.
    const OSPPickResult left = scene.pick(0.25f, 0.5f), right = scene.pick(0.75f, 0.5f);
    REQUIRE(left.hasHit == 1);
    REQUIRE(right.hasHit == 1);
    CHECK(left.worldPosition[0] > 0.05f);
    CHECK(right.worldPosition[0] == Approx(-left.worldPosition[0]));
    CHECK(right.worldPosition[2] == Approx(left.worldPosition[2]));
  }
  SECTION("depth of field: the pick looks through the lens centre; out-of-focus edges blur in the path tracer, "
          "scivis sees through the lens centre as OSPRay's") {
    SphereScene scene({0.f, 0.f, 0.f}, "perspective");
    ospSetFloat(scene.camera, "fovy", 40.f);
    ospCommit(scene.camera);
    const auto scivis_sharp = scene.render(32, 32, 8);
    ospRelease(scene.renderer);
    scene.renderer = ospNewRenderer("pathtracer");
    ospSetVec4f(scene.renderer, "backgroundColor", 0.1f, 0.2f, 0.3f, 1.f);
    ospCommit(scene.renderer);
    const auto sharp = scene.render(32, 32, 8);
    ospSetFloat(scene.camera, "apertureRadius", 0.4f);
    ospSetFloat(scene.camera, "focusDistance", 2.f);
    ospCommit(scene.camera);
    const OSPPickResult centre = scene.pick(0.5f, 0.5f);
    REQUIRE(centre.hasHit == 1);
    CHECK(centre.worldPosition[2] == Approx(-1.f));
    const auto blurred = scene.render(32, 32, 8);
    ospRelease(scene.renderer);
    scene.renderer = ospNewRenderer("scivis");
    ospSetVec4f(scene.renderer, "backgroundColor", 0.1f, 0.2f, 0.3f, 1.f);
    ospCommit(scene.renderer);
    CHECK(scene.render(32, 32, 8) == scivis_sharp);
    // Along the middle row, the silhouette spreads over more pixels between the
    // background and the sphere's shade.
    const auto mixed = [](const std::vector<float>& image) {
      const float background = image[4 * (16 * 32)], inside = image[4 * (16 * 32 + 16)];
      int count = 0;
      for (int x = 0; x < 32; ++x) {
        const float v = image[4 * (16 * 32 + x)];
        count += std::abs(v - background) > 0.02f && std::abs(v - inside) > 0.02f;
      }
      return count;
    };
    CHECK(mixed(blurred) > mixed(sharp) + 2);
  }
  CHECK(api.messages.errors.empty());

  SECTION("parameters that cannot work are named") {
    OSPCamera camera = ospNewCamera("perspective");
    ospSetFloat(camera, "apertureRadius", -1.f);
    ospCommit(camera);
    api.expect_error("perspective camera: 'apertureRadius'");
    ospRemoveParam(camera, "apertureRadius");
    ospSetFloat(camera, "focusDistance", 0.f);
    ospCommit(camera);
    api.expect_error("perspective camera: 'focusDistance' must be positive");
    ospRemoveParam(camera, "focusDistance");
    ospSetInt(camera, "stereoMode", 9);
    ospCommit(camera);
    api.expect_error("perspective camera: 'stereoMode' must be OSP_STEREO_NONE (0)");
    ospRelease(camera);
    CHECK(ospNewCamera("fisheye") == nullptr);
    api.expect_error("sciray supports: perspective, orthographic, panoramic");
  }
}

TEST_CASE("renderer frame settings: pixelSamples, pixelFilter and varianceThreshold", "[c_api][frame]") {
  ApiFixture api;
  SphereScene scene({0.f, 0.f, 0.f}, "perspective");
  constexpr int size = 48;
  const auto frames = [&](int count, std::uint32_t channels = OSP_FB_COLOR | OSP_FB_ACCUM) {
    OSPFrameBuffer fb = ospNewFrameBuffer(size, size, OSP_FB_RGBA32F, channels);
    for (int f = 0; f < count; ++f) ospRenderFrameBlocking(fb, scene.renderer, scene.camera, scene.world);
    auto image = map_channel<float>(fb, OSP_FB_COLOR, 4 * size * size);
    ospRelease(fb);
    return image;
  };
  // One frame of 4 samples per pixel averages the samples 4 one-sample frames take.
  const auto four_frames = frames(4);
  ospSetInt(scene.renderer, "pixelSamples", 4);
  ospCommit(scene.renderer);
  const auto one_frame = frames(1);
  for (std::size_t i = 0; i < one_frame.size(); ++i) REQUIRE(one_frame[i] == Approx(four_frames[i]).margin(1e-5));
  ospSetInt(scene.renderer, "pixelSamples", 1);
  ospCommit(scene.renderer);
  CHECK(one_frame != frames(1));  // one sample at each pixel centre

  // The point filter puts every sample at the pixel centre: more frames change nothing.
  ospSetInt(scene.renderer, "pixelFilter", OSP_PIXELFILTER_POINT);
  ospCommit(scene.renderer);
  CHECK(frames(4) == frames(1));
  ospRemoveParam(scene.renderer, "pixelFilter");

  // With a variance channel and a generous varianceThreshold (in OSPRay's units, see
  // below), every tile converges after two frames and a third leaves the image as it
  // was; without one the third refines it.
  const std::uint32_t variance = OSP_FB_COLOR | OSP_FB_ACCUM | OSP_FB_VARIANCE;
  ospSetFloat(scene.renderer, "varianceThreshold", 1000.f);
  ospCommit(scene.renderer);
  CHECK(frames(3, variance) == frames(2, variance));
  ospSetFloat(scene.renderer, "varianceThreshold", 0.f);
  ospCommit(scene.renderer);
  CHECK(frames(3, variance) != frames(2, variance));
  CHECK(api.messages.errors.empty());

  ospSetInt(scene.renderer, "pixelSamples", 0);
  ospCommit(scene.renderer);
  api.expect_error("'pixelSamples' must be at least 1");
  ospSetInt(scene.renderer, "pixelSamples", 1);
  ospSetInt(scene.renderer, "pixelFilter", 7);
  ospCommit(scene.renderer);
  api.expect_error("'pixelFilter' must be OSP_PIXELFILTER_POINT (0)");
}

TEST_CASE("ospGetVariance and varianceThreshold are in OSPRay's units, over its 64-pixel tiles", "[c_api][frame]") {
  // A white diagonal edge (x + 0.3 y = 0.0984) in a 64x64 orthographic view of the unit
  // square, scivis at one sample a pixel under an ambient light of intensity 1: the first
  // two frames sample each pixel at the same two points in OSPRay and sciray, so their
  // error estimates agree. Measured with OSPRay 3.1's runtime: 0.70711 after two frames,
  // the relative even/odd difference over one 64-pixel tile (2.26 if taken over 16-pixel
  // tiles); infinite after one.
  ApiFixture api;
  const float corners[] = {-10.f, -10.f, 0.f, 3.0984f, -10.f, 0.f, -2.9016f, 10.f, 0.f, -10.f, 10.f, 0.f};
  const std::uint32_t quad[] = {0, 1, 2, 3};
  OSPGeometry mesh = ospNewGeometry("mesh");
  sciray_test::set_array(mesh, "vertex.position", corners, OSP_VEC3F, 4);
  sciray_test::set_array(mesh, "index", quad, OSP_VEC4UI, 1);
  ospCommit(mesh);
  sciray_test::GeometryScene scene(mesh, true);
  OSPMaterial white = ospNewMaterial("obj");
  ospSetVec3f(white, "kd", 1.f, 1.f, 1.f);
  ospCommit(white);
  ospSetObjectAsData(scene.model, "material", OSP_MATERIAL, white);
  ospCommit(scene.model);
  ospSetFloat(scene.camera, "height", 1.f);
  ospSetFloat(scene.camera, "aspect", 1.f);
  ospCommit(scene.camera);
  ospSetVec4f(scene.renderer, "backgroundColor", 0.f, 0.f, 0.f, 0.f);
  ospSetInt(scene.renderer, "pixelSamples", 1);
  ospCommit(scene.renderer);
  OSPFrameBuffer fb = ospNewFrameBuffer(64, 64, OSP_FB_RGBA32F, OSP_FB_COLOR | OSP_FB_ACCUM | OSP_FB_VARIANCE);
  CHECK(std::isinf(ospRenderFrameBlocking(fb, scene.renderer, scene.camera, scene.world)));
  CHECK(ospRenderFrameBlocking(fb, scene.renderer, scene.camera, scene.world) == Approx(0.70711f).epsilon(1e-4));
  // The estimate changes only after every second frame, as OSPRay's.
  const float after_two = ospGetVariance(fb);
  CHECK(ospRenderFrameBlocking(fb, scene.renderer, scene.camera, scene.world) == after_two);
  CHECK(api.messages.errors.empty());
  ospRelease(white);
  ospRelease(fb);
}
