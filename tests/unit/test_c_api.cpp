// OSPRay C API conformance: every function of ospray.h and ospray_util.h is called and
// its result checked, on real data; every bad-input case is reported through the error
// callback with the object and parameter named, and never crashes.
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include <ospray/ospray.h>
#include <ospray/ospray_util.h>

#include "sciray/io/ply.hpp"
#include "sciray/shim/engine.hpp"
#include "support/api_fixture.hpp"

extern "C" int sciray_header_check(void);

namespace {

using sciray_test::ApiFixture;
using sciray_test::Messages;

/// The bunny as an OSPRay scene: mesh, model with an obj material, group, instance,
/// world with an ambient and a distant light, a perspective camera, scivis.
struct BunnyScene {
  sciray::MeshData mesh = sciray::io::read_ply(SCIRAY_DATA_DIR "/meshes/bunny.ply");
  OSPGeometry geometry = ospNewGeometry("mesh");
  OSPMaterial material = ospNewMaterial("obj");
  OSPGeometricModel model = ospNewGeometricModel(geometry);
  OSPGroup group = ospNewGroup();
  OSPInstance instance = ospNewInstance(group);
  OSPWorld world = ospNewWorld();
  OSPCamera camera = ospNewCamera("perspective");
  OSPRenderer renderer = ospNewRenderer("scivis");
  OSPLight lights[2] = {ospNewLight("ambient"), ospNewLight("distant")};

  BunnyScene() {
    OSPData position = ospNewSharedData1D(mesh.positions.data(), OSP_VEC3F, mesh.vertex_count());
    OSPData index = ospNewSharedData1D(mesh.indices.data(), OSP_VEC3UI, mesh.face_count());
    ospSetObject(geometry, "vertex.position", position);
    ospSetObject(geometry, "index", index);
    ospRelease(position);
    ospRelease(index);
    ospCommit(geometry);
    ospSetVec3f(material, "kd", 0.9f, 0.6f, 0.3f);
    ospCommit(material);
    ospSetObject(model, "material", material);
    ospCommit(model);
    ospSetObjectAsData(group, "geometry", OSP_GEOMETRIC_MODEL, model);
    ospCommit(group);
    ospCommit(instance);
    ospSetObjectAsData(world, "instance", OSP_INSTANCE, instance);
    ospSetFloat(lights[0], "intensity", 0.3f);
    ospSetVec3f(lights[1], "direction", 0.5f, -0.7f, -0.6f);
    for (OSPLight l : lights) ospCommit(l);
    OSPData light_list = ospNewSharedData1D(lights, OSP_LIGHT, 2);
    ospSetObject(world, "light", light_list);
    ospRelease(light_list);
    ospCommit(world);
    const OSPBounds b = ospGetBounds(world);
    const float center[3] = {(b.lower[0] + b.upper[0]) / 2, (b.lower[1] + b.upper[1]) / 2,
                             (b.lower[2] + b.upper[2]) / 2};
    ospSetVec3f(camera, "position", center[0], center[1], center[2] + 0.35f);
    ospSetVec3f(camera, "direction", 0.f, 0.f, -1.f);
    ospSetFloat(camera, "fovy", 40.f);
    ospCommit(camera);
    ospSetVec4f(renderer, "backgroundColor", 0.1f, 0.1f, 0.12f, 1.f);
    ospCommit(renderer);
  }
  ~BunnyScene() {
    for (OSPObject o : std::initializer_list<OSPObject>{geometry, material, model, group, instance, world, camera,
                                                       renderer, lights[0], lights[1]})
      ospRelease(o);
  }
};

std::vector<std::uint8_t> render_rgba8(const BunnyScene& s, int w, int h) {
  OSPFrameBuffer fb = ospNewFrameBuffer(w, h, OSP_FB_SRGBA, OSP_FB_COLOR);
  ospRenderFrameBlocking(fb, s.renderer, s.camera, s.world);
  const auto* pixels = static_cast<const std::uint8_t*>(ospMapFrameBuffer(fb, OSP_FB_COLOR));
  std::vector<std::uint8_t> out(pixels, pixels + 4 * w * h);
  ospUnmapFrameBuffer(pixels, fb);
  ospRelease(fb);
  return out;
}

}  // namespace

TEST_CASE("the C headers declare every function (checked by a C99 translation unit)", "[c_api]") {
  CHECK(sciray_header_check() == 77);
}

TEST_CASE("ospInit parses and removes --osp: arguments; the device reports its version", "[c_api][device]") {
  int argc = 4;
  const char* argv[] = {"app", "--osp:num-threads=2", "scene.ply", "--osp:log-level=warning", nullptr};
  REQUIRE(ospInit(&argc, argv) == OSP_NO_ERROR);
  CHECK(argc == 2);
  CHECK(std::string(argv[1]) == "scene.ply");
  OSPDevice device = ospGetCurrentDevice();
  CHECK(ospDeviceGetProperty(device, OSP_DEVICE_VERSION_MAJOR) == 3);
  CHECK(ospDeviceGetProperty(device, OSP_DEVICE_VERSION) == 30200);
  CHECK(ospLoadModule("cpu") == OSP_NO_ERROR);
  ospDeviceRelease(device);

  int bad_argc = 2;
  const char* bad_argv[] = {"app", "--osp:frobnicate", nullptr};
  CHECK(ospInit(&bad_argc, bad_argv) == OSP_INVALID_ARGUMENT);
  ospShutdown();
}

TEST_CASE("device parameters, callbacks with user pointers and the last error", "[c_api][device][errors]") {
  ApiFixture api;
  OSPDevice d = ospNewDevice("cpu");
  Messages mine;
  ospDeviceSetErrorCallback(
      d, [](void* user, OSPError, const char* text) { static_cast<Messages*>(user)->errors.emplace_back(text); },
      &mine);
  ospSetCurrentDevice(d);
  ospDeviceSetParam(d, "isa", OSP_STRING, "avx9000");
  ospDeviceCommit(d);
  CHECK(mine.any_error_containing("unknown ISA 'avx9000'"));
  CHECK(ospDeviceGetLastErrorCode(d) == OSP_INVALID_ARGUMENT);
  CHECK_THAT(ospDeviceGetLastErrorMsg(d), Catch::Contains("avx9000"));
  ospDeviceSetParam(d, "isa", OSP_STRING, "scalar");
  const int threads = 1;
  ospDeviceSetParam(d, "numThreads", OSP_INT, &threads);
  ospDeviceRemoveParam(d, "numThreads");
  ospDeviceCommit(d);
  CHECK(mine.errors.size() == 1);
  CHECK(ospNewGeometry("teapot") == nullptr);
  CHECK(mine.any_error_containing("unknown geometry type 'teapot'"));
  ospDeviceRetain(d);
  ospDeviceRelease(d);
  ospDeviceRelease(d);
}

TEST_CASE("a scene built through the C API renders what the engine renders", "[c_api][render]") {
  ApiFixture api;
  BunnyScene scene;
  REQUIRE(api.messages.errors.empty());
  const auto image = render_rgba8(scene, 64, 48);
  // The centre sees the orange bunny, the bottom-left corner (first mapped row: OSPRay maps
  // bottom-up) the background.
  const auto pixel = [&](int x, int y) { return &image[4 * (y * 64 + x)]; };
  CHECK(pixel(32, 24)[0] > pixel(32, 24)[2]);
  CHECK(pixel(0, 0)[0] == pixel(63, 47)[0]);
  CHECK(pixel(0, 0)[3] == 255);

  // The same frame from the C++ engine directly: identical bytes.
  sciray::accel::Device device;
  sciray::shim::EngineWorld world(device);
  sciray::TriangleMesh mesh(scene.mesh);
  mesh.set_material_color({0.9f, 0.6f, 0.3f});
  world.add(std::move(mesh));
  world.commit();
  sciray::SciVisParams params;
  params.background_color = {0.1f, 0.1f, 0.12f};
  params.background_alpha = 1.f;
  params.lights = sciray::default_lights({0.5f, -0.7f, -0.6f});
  std::get<sciray::AmbientLight>(params.lights[0]).intensity = 0.3f;
  std::get<sciray::DistantLight>(params.lights[1]).intensity = 1.f;
  const auto b = world.bounds();
  sciray::PerspectiveCamera camera;
  camera.position = b.center() + sciray::Vec3f{0.f, 0.f, 0.35f};
  camera.direction = {0.f, 0.f, -1.f};
  camera.fovy = 40.f;
  camera.aspect = 1.f;  // OSPRay's default: the application did not set it
  sciray::FrameBuffer fb(64, 48, sciray::ColorFormat::gamma22, sciray::channel_color);  // OSP_FB_SRGBA
  sciray::shim::kernels(sciray::shim::select_isa()).render_scivis(world, params, camera, fb, nullptr);
  CHECK(fb.color8() == image);
}

TEST_CASE("OSPRay's promotions: a float or vec3f backgroundColor gets alpha 0", "[c_api][params]") {
  ApiFixture api;
  BunnyScene scene;
  OSPFrameBuffer fb = ospNewFrameBuffer(8, 8, OSP_FB_RGBA32F, OSP_FB_COLOR);
  const auto corner = [&] {
    ospRenderFrameBlocking(fb, scene.renderer, scene.camera, scene.world);
    const auto* p = static_cast<const float*>(ospMapFrameBuffer(fb, OSP_FB_COLOR));
    std::vector<float> rgba(p, p + 4);
    ospUnmapFrameBuffer(p, fb);
    return rgba;
  };
  ospSetFloat(scene.renderer, "backgroundColor", 0.5f);
  ospCommit(scene.renderer);
  CHECK(corner() == std::vector<float>{0.5f, 0.5f, 0.5f, 0.f});
  ospSetVec3f(scene.renderer, "backgroundColor", 0.1f, 0.2f, 0.3f);
  ospCommit(scene.renderer);
  CHECK(corner() == std::vector<float>{0.1f, 0.2f, 0.3f, 0.f});
  ospRemoveParam(scene.renderer, "backgroundColor");
  ospCommit(scene.renderer);
  CHECK(corner() == std::vector<float>{0.f, 0.f, 0.f, 0.f});
  ospRelease(fb);
  CHECK(api.messages.errors.empty());
}

TEST_CASE("commit semantics: parameters take effect at commit; an instance commit is enough", "[c_api][commit]") {
  ApiFixture api;
  BunnyScene scene;
  const auto before = render_rgba8(scene, 32, 32);
  ospSetVec3f(scene.camera, "position", 5.f, 5.f, 5.f);  // not committed: invisible
  CHECK(render_rgba8(scene, 32, 32) == before);
  ospCommit(scene.camera);
  CHECK(render_rgba8(scene, 32, 32) != before);

  const OSPBounds b0 = ospGetBounds(scene.world);
  const float shift[12] = {1, 0, 0, 0, 1, 0, 0, 0, 1, 10.f, 0, 0};
  ospSetParam(scene.instance, "transform", OSP_AFFINE3F, shift);
  ospCommit(scene.instance);  // no world commit
  const OSPBounds b1 = ospGetBounds(scene.world);
  CHECK(b1.lower[0] == Approx(b0.lower[0] + 10.f));
  OSPFrameBuffer fb = ospNewFrameBuffer(8, 8);
  OSPPickResult pick;
  ospSetVec3f(scene.camera, "position", b1.lower[0] + 0.08f, 0.1f, 1.f);
  ospCommit(scene.camera);
  ospPick(&pick, fb, scene.renderer, scene.camera, scene.world, 0.5f, 0.5f);
  CHECK(pick.hasHit == 1);
  CHECK(pick.worldPosition[0] > 9.f);  // the moved bunny is hit
  ospRelease(pick.instance);
  ospRelease(pick.model);
  ospRelease(fb);
  CHECK(api.messages.errors.empty());
}

TEST_CASE("futures: progress, waiting, cancelling, duration", "[c_api][future]") {
  ApiFixture api;
  BunnyScene scene;
  OSPFrameBuffer fb = ospNewFrameBuffer(1024, 1024, OSP_FB_RGBA32F, OSP_FB_COLOR | OSP_FB_ACCUM | OSP_FB_DEPTH);
  OSPFuture full = ospRenderFrame(fb, scene.renderer, scene.camera, scene.world);
  ospWait(full, OSP_TASK_FINISHED);
  CHECK(ospIsReady(full, OSP_TASK_FINISHED) == 1);
  CHECK(ospGetProgress(full) == 1.f);
  const float full_seconds = ospGetTaskDuration(full);
  CHECK(full_seconds > 0.f);
  ospRelease(full);

  OSPFuture cancelled = ospRenderFrame(fb, scene.renderer, scene.camera, scene.world);
  ospCancel(cancelled);  // returns once the frame has stopped
  CHECK(ospIsReady(cancelled) == 1);
  CHECK(ospGetProgress(cancelled) < 1.f);
  CHECK(ospGetTaskDuration(cancelled) < full_seconds);
  ospRelease(cancelled);

  // Depth maps as Euclidean distance; no variance channel, no estimate.
  const auto* depth = static_cast<const float*>(ospMapFrameBuffer(fb, OSP_FB_DEPTH));
  CHECK(depth[512 * 1024 + 512] == Approx(0.35).margin(0.1));
  ospUnmapFrameBuffer(depth, fb);
  CHECK(std::isinf(ospGetVariance(fb)));
  ospResetAccumulation(fb);
  ospRelease(fb);

  // With a variance channel the estimate appears after two frames and shrinks as the
  // frames' sample points (OSPRay's Halton points) average out the silhouettes: more
  // slowly than the error itself, which falls about as 1/frames (see the
  // [frame][variance] tests), so by a quarter from 4 to 64 frames at least.
  OSPFrameBuffer accumulating = ospNewFrameBuffer(96, 96, OSP_FB_SRGBA, OSP_FB_COLOR | OSP_FB_ACCUM | OSP_FB_VARIANCE);
  CHECK(std::isinf(ospRenderFrameBlocking(accumulating, scene.renderer, scene.camera, scene.world)));
  const float after_two = ospRenderFrameBlocking(accumulating, scene.renderer, scene.camera, scene.world);
  CHECK(std::isfinite(after_two));
  CHECK(after_two > 0.f);
  std::vector<float> estimates{after_two};
  for (int f = 2; f < 64; ++f) estimates.push_back(ospRenderFrameBlocking(accumulating, scene.renderer, scene.camera, scene.world));
  CHECK(estimates.back() < 0.75f * estimates[2]);
  ospResetAccumulation(accumulating);
  CHECK(std::isinf(ospGetVariance(accumulating)));
  ospRelease(accumulating);
  CHECK(api.messages.errors.empty());
}

TEST_CASE("ospPick reports the instance, model, primitive and position", "[c_api][pick]") {
  ApiFixture api;
  BunnyScene scene;
  OSPFrameBuffer fb = ospNewFrameBuffer(64, 64);
  OSPPickResult hit;
  ospPick(&hit, fb, scene.renderer, scene.camera, scene.world, 0.5f, 0.5f);
  REQUIRE(hit.hasHit == 1);
  CHECK(hit.instance == scene.instance);
  CHECK(hit.model == scene.model);
  CHECK(hit.primID < scene.mesh.face_count());
  const OSPBounds b = ospGetBounds(scene.world);
  for (int k = 0; k < 3; ++k) {
    CHECK(hit.worldPosition[k] >= b.lower[k] - 1e-4f);
    CHECK(hit.worldPosition[k] <= b.upper[k] + 1e-4f);
  }
  ospRelease(hit.instance);
  ospRelease(hit.model);
  OSPPickResult miss;
  ospPick(&miss, fb, scene.renderer, scene.camera, scene.world, 0.01f, 0.99f);
  CHECK(miss.hasHit == 0);
  CHECK(miss.instance == nullptr);
  ospRelease(fb);
}

TEST_CASE("data arrays: shared with strides, owned, copied, deleted when the last holder lets go", "[c_api][data]") {
  ApiFixture api;
  // A 2x3 array of vec3f inside a larger strided buffer: every second float triple.
  std::vector<float> buffer(6 * 2 * 3, 0.f);
  OSPData strided = ospNewSharedData2DStride(buffer.data(), OSP_VEC3F, 2, 24, 3, 48);
  OSPData owned = ospNewData2D(OSP_VEC3F, 4, 4);
  ospCopyData2D(strided, owned, 1, 1);
  CHECK(api.messages.errors.empty());
  ospCopyData2D(strided, owned, 3, 0);  // 3 + 2 > 4
  CHECK(api.messages.any_error_containing("overflows dimension 1 of size 4"));
  ospCopyData1D(owned, strided, 0);
  CHECK(api.messages.any_error_containing("destination made by ospNewData"));
  OSPData cube = ospNewSharedData3D(buffer.data(), OSP_FLOAT, 2, 3, 6);
  OSPData copy = ospNewData(OSP_FLOAT, 2, 3, 6);
  ospCopyData(cube, copy);
  for (OSPData d : {strided, owned, cube, copy}) ospRelease(d);

  // The deleter runs once the geometry that holds the array is gone too.
  static int deleted = 0;
  deleted = 0;
  const float triangle[9 + 4] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  OSPData positions = ospNewSharedData(triangle, OSP_VEC3F, 3, 0, 1, 0, 1, 0,
                                       [](const void*, const void*) { ++deleted; }, nullptr);
  OSPGeometry g = ospNewGeometry("mesh");
  ospSetObject(g, "vertex.position", positions);
  ospRelease(positions);
  CHECK(deleted == 0);
  ospRelease(g);
  CHECK(deleted == 1);
}

TEST_CASE("bad input is named through the error callback and never crashes", "[c_api][errors]") {
  ApiFixture api;
  OSPGeometry mesh = ospNewGeometry("mesh");
  ospSetFloat(mesh, "vertex.position", 1.f);
  ospCommit(mesh);
  api.expect_error("mesh geometry: parameter 'vertex.position' must be an OSPData array");

  const float vertices[3 * 3 + 4] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  const unsigned bad_index[3] = {0, 1, 7};
  OSPData good_positions = ospNewSharedData1D(vertices, OSP_VEC3F, 3);
  ospSetObject(mesh, "vertex.position", good_positions);
  ospSetBool(mesh, "quadSoup", true);
  ospCommit(mesh);
  api.expect_error("without 'index', 'vertex.position' must hold 4 vertices per quad ('quadSoup'), got 3");
  ospRemoveParam(mesh, "quadSoup");
  OSPData index = ospNewSharedData1D(bad_index, OSP_VEC3UI, 1);
  ospSetObject(mesh, "index", index);
  ospCommit(mesh);
  api.expect_error("'index' of face 0 refers to vertex 7 but 'vertex.position' has 3");
  ospRemoveParam(mesh, "index");
  const float nan_vertices[3 * 3 + 4] = {0, 0, 0, NAN, 0, 0, 0, 1, 0};
  OSPData nan_positions = ospNewSharedData1D(nan_vertices, OSP_VEC3F, 3);
  ospSetObject(mesh, "vertex.position", nan_positions);
  ospCommit(mesh);
  api.expect_error("'vertex.position' 1 is not finite");

  OSPCamera camera = ospNewCamera("perspective");
  ospSetVec3f(camera, "up", 0.f, 0.f, 1.f);  // parallel to the default direction
  ospCommit(camera);
  api.expect_error("'up' is parallel to 'direction'");
  ospSetInt(camera, "fovy", 200);
  ospCommit(camera);
  api.expect_error("'fovy'");
  ospSetString(camera, "position", "here");
  ospCommit(camera);
  api.expect_error("parameter 'position' must be a vec3f, got string");

  OSPGeometricModel model = ospNewGeometricModel(nullptr);
  ospCommit(model);
  api.expect_error("geometric model: required parameter 'geometry' (OSPGeometry) is missing");
  ospSetParam(model, "geometry", OSP_GEOMETRY, &camera);
  api.expect_error("parameter 'geometry' was set as OSPGeometry but the object is OSPCamera");

  OSPRenderer renderer = ospNewRenderer("scivis");
  ospSetInt(renderer, "frobnication", 3);
  ospCommit(renderer);
  bool warned = false;
  for (const auto& s : api.messages.status) warned |= s.find("'frobnication' is not used") != std::string::npos;
  CHECK(warned);

  ospCommit(nullptr);
  api.expect_error("object is NULL");
  OSPWorld world = ospNewWorld();
  ospRelease(world);
  ospCommit(world);  // use after release
  api.expect_error("not a live object");
  OSPFrameBuffer fb = ospNewFrameBuffer(4, 4, OSP_FB_RGBA8, OSP_FB_COLOR);
  CHECK(ospMapFrameBuffer(fb, OSP_FB_DEPTH) == nullptr);
  api.expect_error("cannot map OSP_FB_DEPTH");
  ospUnmapFrameBuffer(vertices, fb);
  api.expect_error("did not map");
  CHECK(ospRenderFrame(fb, renderer, camera, reinterpret_cast<OSPWorld>(camera)) == nullptr);
  api.expect_error("world must be OSPWorld but is OSPCamera");
  CHECK(ospNewFrameBuffer(0, 4) == nullptr);
  api.expect_error("size 0x4");
  CHECK(ospNewSharedData1D(nullptr, OSP_FLOAT, 3) == nullptr);
  api.expect_error("shared memory pointer is NULL");
  ospRelease(nullptr);  // a no-op, as in OSPRay
  CHECK(api.messages.errors.empty());
  for (OSPObject o :
       std::initializer_list<OSPObject>{mesh, index, good_positions, nan_positions, camera, model, renderer, fb})
    ospRelease(o);
}

TEST_CASE("the remaining entry points: strided vertices, typed setters, retain, unsupported types", "[c_api]") {
  ApiFixture api;
  BunnyScene scene;
  const auto reference = render_rgba8(scene, 48, 48);

  // The same vertices interleaved with a padding float: a strided shared array.
  std::vector<float> interleaved;
  for (std::size_t v = 0; v < scene.mesh.vertex_count(); ++v)
    interleaved.insert(interleaved.end(), {scene.mesh.positions[3 * v], scene.mesh.positions[3 * v + 1],
                                           scene.mesh.positions[3 * v + 2], -1.f});
  OSPData strided = ospNewSharedData1DStride(interleaved.data(), OSP_VEC3F, scene.mesh.vertex_count(), 16);
  ospSetObject(scene.geometry, "vertex.position", strided);
  ospRelease(strided);
  ospCommit(scene.geometry);
  CHECK(render_rgba8(scene, 48, 48) == reference);  // a geometry recommit reaches the world

  // Typed setters OSPRay's scivis does not use here are reported as unused, not errors.
  ospSetBool(scene.model, "invertNormals", 1);
  ospSetVec2f(scene.renderer, "sciray.test2f", 1.f, 2.f);
  ospSetVec2i(scene.renderer, "sciray.test2i", 1, 2);
  ospSetVec3i(scene.renderer, "sciray.test3i", 1, 2, 3);
  ospSetVec4i(scene.renderer, "sciray.test4i", 1, 2, 3, 4);
  ospCommit(scene.model);
  ospCommit(scene.renderer);
  int unused = 0;
  for (const auto& s : api.messages.status) unused += s.find("'sciray.test") != std::string::npos;
  CHECK(unused == 4);

  // Retain keeps an object alive past one release.
  static int deleted = 0;
  deleted = 0;
  const float values[4] = {1, 2, 3, 4};
  OSPData data = ospNewSharedData(values, OSP_FLOAT, 4, 0, 1, 0, 1, 0, [](const void*, const void*) { ++deleted; },
                                  nullptr);
  ospRetain(data);
  ospRelease(data);
  CHECK(deleted == 0);
  ospRelease(data);
  CHECK(deleted == 1);
  OSPData two_d = ospNewSharedData2D(values, OSP_FLOAT, 2, 2);
  OSPData one_d = ospNewData1D(OSP_FLOAT, 4);
  ospCopyData1D(two_d, one_d, 0);
  CHECK(api.messages.any_error_containing("overflows dimension 2 of size 1"));
  api.messages.errors.clear();
  ospRelease(two_d);
  ospRelease(one_d);

  // Types later issues bring are refused by name, not crashed on.
  CHECK(ospNewVolume("unstructured") == nullptr);
  CHECK(ospNewTransferFunction("piecewise_linear") == nullptr);  // OSPRay 1's name
  CHECK(ospNewTexture("checkerboard") == nullptr);
  CHECK(ospNewImageOperation("denoiser") == nullptr);
  CHECK(api.messages.any_error_containing("unknown texture type 'checkerboard' (sciray supports: volume, texture2d)"));
  CHECK(ospLoadModule("denoiser") == OSP_INVALID_ARGUMENT);
  CHECK(api.messages.any_error_containing("unknown volume type 'unstructured' (sciray supports: structuredRegular)"));
  CHECK(api.messages.any_error_containing(
      "unknown transfer function type 'piecewise_linear' (sciray supports: piecewiseLinear)"));
  CHECK(api.messages.any_error_containing("unknown image operation type 'denoiser'"));
  CHECK(api.messages.codes.back() == OSP_INVALID_ARGUMENT);
}

TEST_CASE("the device's isa parameter picks the kernels; every ISA renders the same frame", "[c_api][device]") {
  ApiFixture api;
  BunnyScene scene;
  const auto best = render_rgba8(scene, 40, 40);
  for (auto isa : sciray::simd::all_isas) {
    if (!sciray::simd::cpu_supports(isa)) continue;
    const std::string name(sciray::simd::isa_name(isa));
    ospDeviceSetParam(api.device, "isa", OSP_STRING, name.c_str());
    ospDeviceCommit(api.device);
    const auto image = render_rgba8(scene, 40, 40);
    int largest = 0;
    for (std::size_t i = 0; i < image.size(); ++i) largest = std::max(largest, std::abs(image[i] - best[i]));
    INFO("ISA " << name);
    CHECK(largest <= 1);  // float rounding only (see the engine's cross-ISA tests)
  }
  CHECK(api.messages.errors.empty());
}

// ---- sphere and curve geometry ----------------------------------------------------------

namespace {

/// One geometry in a scene lit by a white ambient light of intensity 1 only, so that a
/// pixel's colour is the surface's albedo. The camera looks down +z from z = -5; `ortho`
/// makes it orthographic (height 4). Owns the geometry it is given.
struct GeometryScene {
  OSPGeometry geometry;
  OSPGeometricModel model;
  OSPGroup group = ospNewGroup();
  OSPInstance instance = ospNewInstance(group);
  OSPWorld world = ospNewWorld();
  OSPCamera camera;
  OSPRenderer renderer = ospNewRenderer("scivis");
  OSPLight light = ospNewLight("ambient");

  explicit GeometryScene(OSPGeometry g, bool ortho = false)
      : geometry(g), model(ospNewGeometricModel(g)), camera(ospNewCamera(ortho ? "orthographic" : "perspective")) {
    ospCommit(model);
    ospSetObjectAsData(group, "geometry", OSP_GEOMETRIC_MODEL, model);
    ospCommit(group);
    ospCommit(instance);
    ospSetObjectAsData(world, "instance", OSP_INSTANCE, instance);
    ospCommit(light);
    ospSetObjectAsData(world, "light", OSP_LIGHT, light);
    ospCommit(world);
    look_from(0.f, 0.f, -5.f);
    if (ortho) ospSetFloat(camera, "height", 4.f);
    ospCommit(camera);
    ospCommit(renderer);
  }
  GeometryScene(const GeometryScene&) = delete;
  GeometryScene& operator=(const GeometryScene&) = delete;
  ~GeometryScene() {
    for (OSPObject o : std::initializer_list<OSPObject>{geometry, model, group, instance, world, camera, renderer, light})
      ospRelease(o);
  }

  /// Moves the camera to (x, y, z), still looking down +z.
  void look_from(float x, float y, float z) {
    ospSetVec3f(camera, "position", x, y, z);
    ospSetVec3f(camera, "direction", 0.f, 0.f, 1.f);
    ospCommit(camera);
  }

  /// The pick at screen position (x, y); releases the handles it returns after checking
  /// they are this scene's.
  OSPPickResult pick(float x, float y) const {
    OSPFrameBuffer fb = ospNewFrameBuffer(8, 8);
    OSPPickResult result;
    ospPick(&result, fb, renderer, camera, world, x, y);
    ospRelease(fb);
    if (result.hasHit) {
      CHECK(result.instance == instance);
      CHECK(result.model == model);
      ospRelease(result.instance);
      ospRelease(result.model);
    }
    return result;
  }

  /// An RGBA32F frame, first row at the bottom.
  std::vector<float> render(int w, int h) const {
    OSPFrameBuffer fb = ospNewFrameBuffer(w, h, OSP_FB_RGBA32F, OSP_FB_COLOR);
    ospRenderFrameBlocking(fb, renderer, camera, world);
    const auto* p = static_cast<const float*>(ospMapFrameBuffer(fb, OSP_FB_COLOR));
    std::vector<float> out(p, p + 4 * w * h);
    ospUnmapFrameBuffer(p, fb);
    ospRelease(fb);
    return out;
  }
};

/// Sets a 1D array parameter holding a copy of `values` (an object may read its arrays
/// again at any later commit, so the tests do not share their temporaries).
void set_array(OSPObject o, const char* id, const void* values, OSPDataType type, std::uint64_t n) {
  OSPData shared = ospNewSharedData1D(values, type, n);
  OSPData owned = ospNewData1D(type, n);
  ospCopyData1D(shared, owned, 0);
  ospSetObject(o, id, owned);
  ospRelease(shared);
  ospRelease(owned);
}

/// A committed sphere geometry with the given centres (x,y,z each) and one radius.
OSPGeometry new_spheres(const std::vector<float>& centers, float radius) {
  OSPGeometry g = ospNewGeometry("sphere");
  set_array(g, "sphere.position", centers.data(), OSP_VEC3F, centers.size() / 3);
  ospSetFloat(g, "radius", radius);
  ospCommit(g);
  return g;
}

/// A committed curve geometry of x,y,z,r control points and segment indices.
OSPGeometry new_curves(const std::vector<float>& position_radius, const std::vector<std::uint32_t>& index,
                       OSPCurveType type, OSPCurveBasis basis) {
  OSPGeometry g = ospNewGeometry("curve");
  set_array(g, "vertex.position_radius", position_radius.data(), OSP_VEC4F, position_radius.size() / 4);
  set_array(g, "index", index.data(), OSP_UINT, index.size());
  ospSetInt(g, "type", type);
  ospSetInt(g, "basis", basis);
  ospCommit(g);
  return g;
}

void check_position(const OSPPickResult& hit, float x, float y, float z, float tolerance = 1e-4f) {
  REQUIRE(hit.hasHit == 1);
  CHECK(hit.worldPosition[0] == Approx(x).margin(tolerance));
  CHECK(hit.worldPosition[1] == Approx(y).margin(tolerance));
  CHECK(hit.worldPosition[2] == Approx(z).margin(tolerance));
}

float max_abs_difference(const std::vector<float>& a, const std::vector<float>& b) {
  REQUIRE(a.size() == b.size());
  float largest = 0.f;
  for (std::size_t i = 0; i < a.size(); ++i) largest = std::max(largest, std::abs(a[i] - b[i]));
  return largest;
}

const char* const intersectors[] = {"sciray", "embree"};

}  // namespace

TEST_CASE("sphere: picks land on the analytic surface; bounds; both intersectors", "[c_api][sphere]") {
  ApiFixture api;
  for (const char* intersector : intersectors) {
    INFO("intersector " << intersector);
    GeometryScene scene(new_spheres({0.f, 0.f, 0.f}, 1.f));
    ospSetString(scene.geometry, "intersector", intersector);
    ospCommit(scene.geometry);
    // A unit sphere at the origin seen from z = -5: the centre ray meets it at z = -1.
    const OSPPickResult centre = scene.pick(0.5f, 0.5f);
    check_position(centre, 0.f, 0.f, -1.f);
    CHECK(centre.primID == 0);
    // Off the centre the hit is still on the unit sphere, on the camera's side.
    const OSPPickResult side = scene.pick(0.56f, 0.45f);
    REQUIRE(side.hasHit == 1);
    const float* p = side.worldPosition;
    CHECK(std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]) == Approx(1.f).margin(1e-4));
    CHECK(p[2] < 0.f);
    CHECK(scene.pick(0.05f, 0.05f).hasHit == 0);  // far outside the silhouette

    const OSPBounds b = ospGetBounds(scene.geometry);
    const OSPBounds w = ospGetBounds(scene.world);
    for (int k = 0; k < 3; ++k) {
      CHECK(b.lower[k] == Approx(-1.f));
      CHECK(b.upper[k] == Approx(1.f));
      CHECK(w.lower[k] == Approx(-1.f));
      CHECK(w.upper[k] == Approx(1.f));
    }
  }
  CHECK(api.messages.errors.empty());
}

TEST_CASE("sphere: per-sphere radii, model colours and material kd show up in the image", "[c_api][sphere]") {
  ApiFixture api;
  // Three spheres along x, seen orthographically down +z (screen x runs along -x then).
  const std::vector<float> centers = {-2.f, 0.f, 0.f, 0.f, 0.f, 0.f, 2.f, 0.f, 0.f};
  const float radii[3] = {0.4f, 0.6f, 0.8f};
  const float colors[3][4] = {{1.f, 0.f, 0.f, 1.f}, {0.f, 1.f, 0.f, 1.f}, {0.f, 0.f, 1.f, 1.f}};
  GeometryScene scene(new_spheres(centers, 0.1f), true);
  set_array(scene.geometry, "sphere.radius", radii, OSP_FLOAT, 3);
  ospCommit(scene.geometry);
  set_array(scene.model, "color", colors, OSP_VEC4F, 3);
  ospCommit(scene.model);
  ospSetFloat(scene.camera, "aspect", 2.f);
  ospCommit(scene.camera);

  constexpr int W = 128, H = 64;  // 8 x 4 world units: 1/16 per pixel
  const auto classify = [&](const std::vector<float>& image, const std::array<std::array<float, 3>, 3>& expected) {
    int checked = 0;
    for (int py = 0; py < H; ++py)
      for (int px = 0; px < W; ++px) {
        const float x = -((px + 0.5f) / W * 8.f - 4.f), y = (py + 0.5f) / H * 4.f - 2.f;
        const float* rgba = &image[4 * (py * W + px)];
        bool near_edge = false;
        int inside = -1;
        for (int s = 0; s < 3; ++s) {
          const float d = std::hypot(x - centers[3 * s], y);
          near_edge |= std::abs(d - radii[s]) < 0.02f;
          if (d < radii[s]) inside = s;
        }
        if (near_edge) continue;
        ++checked;
        INFO("pixel " << px << "," << py << " sphere " << inside);
        if (inside < 0) {
          CHECK(rgba[3] == 0.f);
        } else {
          CHECK(rgba[3] == 1.f);
          for (int c = 0; c < 3; ++c) CHECK(rgba[c] == Approx(expected[inside][c]).margin(1e-5));
        }
      }
    CHECK(checked > W * H * 9 / 10);
  };
  classify(scene.render(W, H), {{{1.f, 0.f, 0.f}, {0.f, 1.f, 0.f}, {0.f, 0.f, 1.f}}});

  // A material multiplies the model colours, as on meshes...
  OSPMaterial material = ospNewMaterial("obj");
  ospSetVec3f(material, "kd", 0.5f, 0.25f, 0.75f);
  ospCommit(material);
  ospSetObject(scene.model, "material", material);
  ospCommit(scene.model);
  classify(scene.render(W, H), {{{0.5f, 0.f, 0.f}, {0.f, 0.25f, 0.f}, {0.f, 0.f, 0.75f}}});
  // ... and is the colour of spheres without colours; a material commit reaches the world.
  ospRemoveParam(scene.model, "color");
  ospCommit(scene.model);
  ospSetVec3f(material, "kd", 0.2f, 0.4f, 0.6f);
  ospCommit(material);
  classify(scene.render(W, H), {{{0.2f, 0.4f, 0.6f}, {0.2f, 0.4f, 0.6f}, {0.2f, 0.4f, 0.6f}}});
  ospRelease(material);
  CHECK(api.messages.errors.empty());
}

TEST_CASE("sphere: the three types, spheres, discs facing the ray and oriented discs", "[c_api][sphere]") {
  ApiFixture api;
  const float tilted[3] = {0.f, 1.f, 1.f};  // the plane z = -y
  for (const char* intersector : intersectors) {
    INFO("intersector " << intersector);
    GeometryScene scene(new_spheres({0.f, 0.f, 0.f}, 1.f), true);
    ospSetString(scene.geometry, "intersector", intersector);
    ospCommit(scene.geometry);
    // Orthographic rays down +z through screen (0.5, 0.625) pass x = 0, y = 0.5.
    check_position(scene.pick(0.5f, 0.625f), 0.f, 0.5f, -std::sqrt(0.75f));

    ospSetInt(scene.geometry, "type", OSP_DISC);
    ospCommit(scene.geometry);
    check_position(scene.pick(0.5f, 0.625f), 0.f, 0.5f, 0.f);
    CHECK(scene.pick(0.5f, 0.76f).hasHit == 0);  // y = 1.04: outside the disc

    ospSetInt(scene.geometry, "type", OSP_ORIENTED_DISC);
    set_array(scene.geometry, "sphere.normal", tilted, OSP_VEC3F, 1);
    ospCommit(scene.geometry);
    check_position(scene.pick(0.5f, 0.625f), 0.f, 0.5f, -0.5f);
    // Along the tilt the disc is foreshortened: y = 0.75 lies |(0, 0.75, -0.75)| = 1.06 out.
    CHECK(scene.pick(0.5f, 0.6875f).hasHit == 0);
    CHECK(scene.pick(0.6875f, 0.5f).hasHit == 1);  // x = -0.75: inside
  }
  CHECK(api.messages.errors.empty());
}

TEST_CASE("sphere: the sciray and embree intersectors render the same image on every ISA", "[c_api][sphere]") {
  ApiFixture api;
  std::vector<float> centers, radii, normals, colors;
  for (int i = 0; i < 40; ++i) {
    const float a = 0.157f * static_cast<float>(i);  // once around
    centers.insert(centers.end(), {1.6f * std::cos(a), 1.6f * std::sin(a), 0.05f * static_cast<float>(i % 7)});
    radii.push_back(0.16f + 0.02f * static_cast<float>(i % 5));
    normals.insert(normals.end(), {std::sin(a), 0.3f, -1.f});
    colors.insert(colors.end(), {0.2f + 0.02f * static_cast<float>(i), 0.5f, 1.f - 0.02f * static_cast<float>(i), 1.f});
  }
  GeometryScene scene(new_spheres(centers, 0.1f));
  set_array(scene.geometry, "sphere.radius", radii.data(), OSP_FLOAT, radii.size());
  set_array(scene.geometry, "sphere.normal", normals.data(), OSP_VEC3F, radii.size());
  set_array(scene.model, "color", colors.data(), OSP_VEC4F, radii.size());
  ospCommit(scene.model);
  // A distant light as well, so that shading depends on the normals.
  OSPLight sun = ospNewLight("distant");
  ospSetVec3f(sun, "direction", 0.3f, -0.5f, 1.f);
  ospCommit(sun);
  OSPLight lights[2] = {scene.light, sun};
  OSPData light_list = ospNewSharedData1D(lights, OSP_LIGHT, 2);
  ospSetObject(scene.world, "light", light_list);
  ospRelease(light_list);
  ospCommit(scene.world);

  for (auto isa : sciray::simd::all_isas) {
    if (!sciray::simd::cpu_supports(isa)) continue;
    const std::string isa_name(sciray::simd::isa_name(isa));
    ospDeviceSetParam(api.device, "isa", OSP_STRING, isa_name.c_str());
    ospDeviceCommit(api.device);
    for (int type : {OSP_SPHERE, OSP_DISC, OSP_ORIENTED_DISC}) {
      INFO("ISA " << isa_name << ", sphere type " << type);
      std::vector<float> images[2];
      for (int k = 0; k < 2; ++k) {
        ospSetInt(scene.geometry, "type", type);
        ospSetString(scene.geometry, "intersector", intersectors[k]);
        ospCommit(scene.geometry);
        images[k] = scene.render(96, 96);
      }
      int covered = 0;
      for (std::size_t i = 3; i < images[0].size(); i += 4) covered += images[0][i] == 1.f;
      CHECK(covered > 600);
      CHECK(max_abs_difference(images[0], images[1]) < 1e-3f);
    }
  }
  ospRelease(sun);
  CHECK(api.messages.errors.empty());
}

TEST_CASE("sphere: transformed instances move centres and scale radii; strided arrays",
          "[c_api][sphere][instancing]") {
  ApiFixture api;
  // x, y, z, r interleaved: 'sphere.position' and 'sphere.radius' read the same buffer.
  const float interleaved[8] = {0.f, 0.f, 0.f, 1.f, 0.f, 10.f, 0.f, 0.5f};
  OSPGeometry g = ospNewGeometry("sphere");
  OSPData position = ospNewSharedData1DStride(interleaved, OSP_VEC3F, 2, 16);
  OSPData radius = ospNewSharedData1DStride(interleaved + 3, OSP_FLOAT, 2, 16);
  ospSetObject(g, "sphere.position", position);
  ospSetObject(g, "sphere.radius", radius);
  ospRelease(position);
  ospRelease(radius);
  ospCommit(g);
  GeometryScene scene(g);
  check_position(scene.pick(0.5f, 0.5f), 0.f, 0.f, -1.f);
  const OSPBounds b = ospGetBounds(scene.geometry);
  CHECK(b.upper[1] == Approx(10.5f));

  // Scale 2, then move by (1, 0, 0): the unit sphere becomes radius 2 around (1, 0, 0).
  const float xfm[12] = {2, 0, 0, 0, 2, 0, 0, 0, 2, 1, 0, 0};
  ospSetParam(scene.instance, "transform", OSP_AFFINE3F, xfm);
  ospCommit(scene.instance);
  scene.look_from(1.f, 0.f, -5.f);
  for (const char* intersector : intersectors) {
    ospSetString(scene.geometry, "intersector", intersector);
    ospCommit(scene.geometry);
    check_position(scene.pick(0.5f, 0.5f), 1.f, 0.f, -2.f);
  }
  const OSPBounds w = ospGetBounds(scene.world);
  CHECK(w.lower[0] == Approx(-1.f));
  CHECK(w.upper[0] == Approx(3.f));
  CHECK(w.upper[1] == Approx(21.f));
  CHECK(api.messages.errors.empty());
}

TEST_CASE("curve: a round linear tube picked at its centre; vertex.position with radius", "[c_api][curve]") {
  ApiFixture api;
  // A tube of radius 0.25 along x from -1 to 1, seen from z = -5.
  GeometryScene scene(new_curves({-1.f, 0.f, 0.f, 0.25f, 1.f, 0.f, 0.f, 0.25f}, {0}, OSP_ROUND, OSP_LINEAR));
  check_position(scene.pick(0.5f, 0.5f), 0.f, 0.f, -0.25f);
  CHECK(scene.pick(0.5f, 0.56f).hasHit == 0);  // above the tube
  const OSPBounds b = ospGetBounds(scene.geometry);
  CHECK(b.lower[0] == Approx(-1.25f));
  CHECK(b.upper[1] == Approx(0.25f));

  // OSPRay's other form: 'vertex.position' and one 'radius', round and linear by default.
  const float points[6] = {-1.f, 0.f, 0.f, 1.f, 0.f, 0.f};
  OSPGeometry g = ospNewGeometry("curve");
  set_array(g, "vertex.position", points, OSP_VEC3F, 2);
  const std::int32_t index[1] = {0};
  set_array(g, "index", index, OSP_INT, 1);
  ospSetFloat(g, "radius", 0.5f);
  ospCommit(g);
  GeometryScene constant(g);
  check_position(constant.pick(0.5f, 0.5f), 0.f, 0.f, -0.5f);

  // A transformed instance: scale 2 and move up by 1.
  const float xfm[12] = {2, 0, 0, 0, 2, 0, 0, 0, 2, 0, 1, 0};
  ospSetParam(constant.instance, "transform", OSP_AFFINE3F, xfm);
  ospCommit(constant.instance);
  constant.look_from(0.f, 1.f, -5.f);
  check_position(constant.pick(0.5f, 0.5f), 0.f, 1.f, -1.f);
  CHECK(api.messages.errors.empty());
}

TEST_CASE("curve: bezier, b-spline, Catmull-Rom, Hermite and ribbon curves render with vertex colours",
          "[c_api][curve]") {
  ApiFixture api;
  const std::vector<float> points = {-1.5f, -1.f, 0.f, 0.2f, -0.5f, 1.5f, 0.f, 0.2f,
                                     0.5f,  -1.5f, 0.f, 0.2f, 1.5f, 1.f, 0.f, 0.2f};
  const float colors[4][3] = {{1.f, 0.f, 0.f}, {1.f, 0.f, 0.f}, {0.f, 0.f, 1.f}, {0.f, 0.f, 1.f}};
  const float tangents[4][4] = {{1, 3, 0, 0}, {1, 3, 0, 0}, {1, 3, 0, 0}, {1, 3, 0, 0}};
  const float normals[4][3] = {{0, 0, -1}, {0, 0, -1}, {0, 0, -1}, {0, 0, -1}};
  struct Case {
    OSPCurveType type;
    OSPCurveBasis basis;
    std::vector<std::uint32_t> index;
  };
  const Case cases[] = {{OSP_ROUND, OSP_BEZIER, {0}},      {OSP_FLAT, OSP_BEZIER, {0}},
                        {OSP_RIBBON, OSP_BEZIER, {0}},     {OSP_ROUND, OSP_BSPLINE, {0}},
                        {OSP_ROUND, OSP_CATMULL_ROM, {0}}, {OSP_ROUND, OSP_HERMITE, {0, 1, 2}},
                        {OSP_DISJOINT, OSP_LINEAR, {0, 2}}};
  for (const Case& c : cases) {
    INFO("type " << static_cast<int>(c.type) << ", basis " << static_cast<int>(c.basis));
    OSPGeometry g = ospNewGeometry("curve");
    set_array(g, "vertex.position_radius", points.data(), OSP_VEC4F, 4);
    set_array(g, "index", c.index.data(), OSP_UINT, c.index.size());
    set_array(g, "vertex.color", colors, OSP_VEC3F, 4);
    set_array(g, "vertex.tangent", tangents, OSP_VEC4F, 4);
    set_array(g, "vertex.normal", normals, OSP_VEC3F, 4);
    ospSetInt(g, "type", c.type);
    ospSetInt(g, "basis", c.basis);
    ospCommit(g);
    GeometryScene scene(g);
    const auto image = scene.render(96, 96);
    int covered = 0;
    for (std::size_t i = 0; i < image.size(); i += 4) {
      if (image[i + 3] != 1.f) continue;
      ++covered;
      // Colours run between red and blue, never green.
      CHECK(image[i + 1] == Approx(0.f).margin(1e-5));
      CHECK(image[i] + image[i + 2] == Approx(1.f).margin(1e-3));
    }
    CHECK(covered > 100);
  }
  // Parameters a curve does not use are reported, as OSPRay would not read them either.
  int unused = 0;
  for (const auto& s : api.messages.status)
    unused += s.find("'vertex.tangent' is not used") != std::string::npos ||
              s.find("'vertex.normal' is not used") != std::string::npos;
  CHECK(unused > 0);
  CHECK(api.messages.errors.empty());
}

TEST_CASE("sphere and curve: bad input is named through the error callback", "[c_api][sphere][curve][errors]") {
  ApiFixture api;
  CHECK(ospNewGeometry("subdivision") == nullptr);
  api.expect_error("unknown geometry type 'subdivision' (sciray supports: mesh, sphere, curve, box, plane, isosurface)");

  const float three[9] = {0, 0, 0, 1, 0, 0, 2, 0, 0};
  const float nan_three[9] = {0, 0, 0, NAN, 0, 0, 2, 0, 0};
  const float two_radii[2] = {0.1f, 0.2f};
  const float bad_radii[3] = {0.1f, -0.2f, 0.3f};
  const float four[16] = {};
  OSPGeometry spheres = ospNewGeometry("sphere");
  ospCommit(spheres);
  api.expect_error("sphere geometry: required parameter 'sphere.position' (array of vec3f) is missing");
  set_array(spheres, "sphere.position", four, OSP_VEC4F, 4);
  ospCommit(spheres);
  api.expect_error("parameter 'sphere.position' must be an array of vec3f, got an array of vec4f");
  set_array(spheres, "sphere.position", three, OSP_VEC3F, 3);
  ospCommit(spheres);
  CHECK(api.messages.errors.empty());  // a good commit

  set_array(spheres, "sphere.radius", two_radii, OSP_FLOAT, 2);
  ospCommit(spheres);
  api.expect_error("'sphere.radius' has 2 elements but there are 3 spheres");
  set_array(spheres, "sphere.radius", bad_radii, OSP_FLOAT, 3);
  ospCommit(spheres);
  api.expect_error("'sphere.radius' 1 must be positive");
  ospRemoveParam(spheres, "sphere.radius");
  ospSetFloat(spheres, "radius", -1.f);
  ospCommit(spheres);
  api.expect_error("'radius' must be positive");
  ospRemoveParam(spheres, "radius");
  set_array(spheres, "sphere.position", nan_three, OSP_VEC3F, 3);
  ospCommit(spheres);
  api.expect_error("'sphere.position' 1 is not finite");
  set_array(spheres, "sphere.position", three, OSP_VEC3F, 3);
  ospSetInt(spheres, "type", OSP_ORIENTED_DISC);
  ospCommit(spheres);
  api.expect_error("type 'oriented disc' needs 'sphere.normal'");
  ospSetInt(spheres, "type", 2);  // OSPRay 2's OSP_ORIENTED_DISC; OSPRay 3's are 50, 51, 52
  ospCommit(spheres);
  api.expect_error("sphere geometry: parameter 'type' has unknown value 2 (OSP_SPHERE = 50, OSP_DISC = 51, "
               "OSP_ORIENTED_DISC = 52)");
  ospSetFloat(spheres, "type", 1.f);
  ospCommit(spheres);
  api.expect_error("parameter 'type' must be an integer, got float");
  ospRemoveParam(spheres, "type");
  ospSetString(spheres, "intersector", "optix");
  ospCommit(spheres);
  api.expect_error("parameter 'intersector' has unknown value 'optix' (sciray, embree)");
  ospRemoveParam(spheres, "intersector");
  const float texcoords[6] = {};
  set_array(spheres, "sphere.texcoord", texcoords, OSP_VEC2F, 3);
  ospCommit(spheres);
  CHECK(api.messages.errors.empty());
  // Read as the spheres' texture coordinates, not reported unused.
  bool warned = false;
  for (const auto& s : api.messages.status) warned |= s.find("'sphere.texcoord' is not used") != std::string::npos;
  CHECK_FALSE(warned);

  // Model colours: one for all, or one per sphere (more are ignored, as by OSPRay); one
  // for a whole curve, none per curve segment yet.
  OSPGeometricModel model = ospNewGeometricModel(spheres);
  set_array(model, "color", four, OSP_VEC4F, 2);
  ospCommit(model);
  api.expect_error("geometric model: parameter 'color' has 2 elements but there are 3 primitives (give one for all, "
                   "or one for each)");

  const float pr[8] = {0, 0, 0, 0.1f, 1, 0, 0, 0.1f};
  const std::uint32_t bad_index[1] = {1};
  const std::uint32_t index[1] = {0};
  OSPGeometry curve = ospNewGeometry("curve");
  set_array(curve, "index", index, OSP_UINT, 1);
  ospCommit(curve);
  api.expect_error("curve geometry: required parameter 'vertex.position_radius' (array of vec4f) is missing");
  set_array(curve, "vertex.position_radius", pr, OSP_VEC3F, 2);
  ospCommit(curve);
  api.expect_error("parameter 'vertex.position_radius' must be an array of vec4f, got an array of vec3f");
  set_array(curve, "vertex.position_radius", pr, OSP_VEC4F, 2);
  ospCommit(curve);
  api.expect_error("curve geometry: required parameter 'type' (OSPCurveType");
  ospSetInt(curve, "type", OSP_ROUND);
  ospCommit(curve);
  api.expect_error("curve geometry: required parameter 'basis' (OSPCurveBasis");
  ospSetInt(curve, "basis", OSP_LINEAR);
  ospSetInt(curve, "type", 7);
  ospCommit(curve);
  api.expect_error("curve geometry: parameter 'type' has unknown value 7 (OSP_ROUND = 0, OSP_FLAT = 1");
  ospSetInt(curve, "type", OSP_ROUND);
  ospSetInt(curve, "basis", 9);
  ospCommit(curve);
  api.expect_error("curve geometry: parameter 'basis' has unknown value 9 (OSP_LINEAR = 0");
  ospSetInt(curve, "basis", OSP_LINEAR);
  set_array(curve, "index", bad_index, OSP_UINT, 1);
  ospCommit(curve);
  api.expect_error("curve: 'index' 0 starts a segment at vertex 1 that needs vertex 2 but 'vertex.position_radius' has 2");
  set_array(curve, "index", index, OSP_VEC2UI, 1);
  ospCommit(curve);
  api.expect_error("parameter 'index' must be an array of uint or int, got an array of vec2ui");
  set_array(curve, "index", index, OSP_UINT, 1);
  ospSetInt(curve, "basis", OSP_HERMITE);
  ospCommit(curve);
  api.expect_error("basis 'hermite' needs 'vertex.tangent'");
  ospSetInt(curve, "basis", OSP_LINEAR);
  ospCommit(curve);
  CHECK(api.messages.errors.empty());  // a good commit

  OSPGeometricModel curve_model = ospNewGeometricModel(curve);
  set_array(curve_model, "color", four, OSP_VEC4F, 1);
  ospCommit(curve_model);
  CHECK(api.messages.errors.empty());
  set_array(curve_model, "color", four, OSP_VEC4F, 2);
  ospCommit(curve_model);
  api.expect_error("curve geometry takes one colour for all its primitives (per-primitive colours of curve geometry "
                   "are not supported yet)");

  // The constant-radius form: round linear only, its errors name 'vertex.position'.
  OSPGeometry tube = ospNewGeometry("curve");
  set_array(tube, "index", index, OSP_UINT, 1);
  set_array(tube, "vertex.position", nan_three, OSP_VEC3F, 3);
  ospCommit(tube);
  api.expect_error("curve: 'vertex.position' 1 is not finite");
  set_array(tube, "vertex.position", three, OSP_VEC3F, 3);
  ospSetInt(tube, "basis", OSP_BEZIER);
  ospCommit(tube);
  api.expect_error("'vertex.position' with a constant 'radius' needs type OSP_ROUND and basis OSP_LINEAR");
  ospRemoveParam(tube, "basis");
  ospSetFloat(tube, "radius", NAN);
  ospCommit(tube);
  api.expect_error("curve geometry: parameter 'radius' must be finite and not negative");

  // A failed commit leaves the geometry as it was: the good spheres still render.
  ospSetInt(spheres, "type", 42);
  ospCommit(spheres);
  api.expect_error("unknown value 42");
  {
    ospRetain(spheres);
    GeometryScene scene(spheres);
    check_position(scene.pick(0.5f, 0.5f), 0.f, 0.f, -0.01f);
  }
  CHECK(api.messages.errors.empty());
  for (OSPObject o : std::initializer_list<OSPObject>{spheres, model, curve, curve_model, tube}) ospRelease(o);
}

// ---- instancing, box and plane geometry ---------------------------------------------------

namespace {

/// An affine3f as OSPRay stores it: the linear part's columns, then the translation.
std::array<float, 12> scale_then_move(float sx, float sy, float sz, float tx, float ty, float tz) {
  return {sx, 0.f, 0.f, 0.f, sy, 0.f, 0.f, 0.f, sz, tx, ty, tz};
}

void set_transform(OSPInstance instance, const std::array<float, 12>& m) {
  ospSetParam(instance, "transform", OSP_AFFINE3F, m.data());
}

/// A committed world of `instances` lit by a white ambient light of intensity 1 only.
OSPWorld new_world(const std::vector<OSPInstance>& instances) {
  OSPWorld world = ospNewWorld();
  OSPData list = ospNewSharedData1D(instances.data(), OSP_INSTANCE, instances.size());
  ospSetObject(world, "instance", list);
  ospRelease(list);
  OSPLight light = ospNewLight("ambient");
  ospCommit(light);
  ospSetObjectAsData(world, "light", OSP_LIGHT, light);
  ospRelease(light);
  ospCommit(world);
  return world;
}

/// A committed group of `models`.
OSPGroup new_group(const std::vector<OSPGeometricModel>& models) {
  OSPGroup group = ospNewGroup();
  if (!models.empty()) {
    OSPData list = ospNewSharedData1D(models.data(), OSP_GEOMETRIC_MODEL, models.size());
    ospSetObject(group, "geometry", list);
    ospRelease(list);
  }
  ospCommit(group);
  return group;
}

/// A committed instance of `group` placed by `m`.
OSPInstance new_instance(OSPGroup group, const std::array<float, 12>& m = scale_then_move(1, 1, 1, 0, 0, 0)) {
  OSPInstance instance = ospNewInstance(group);
  set_transform(instance, m);
  ospCommit(instance);
  return instance;
}

/// Picks along single rays: the centre ray of a perspective camera at `from` looking
/// along `dir`.
struct Picker {
  OSPCamera camera = ospNewCamera("perspective");
  OSPRenderer renderer = ospNewRenderer("scivis");
  OSPFrameBuffer fb = ospNewFrameBuffer(8, 8);

  Picker() { ospCommit(renderer); }
  Picker(const Picker&) = delete;
  Picker& operator=(const Picker&) = delete;
  ~Picker() {
    ospRelease(camera);
    ospRelease(renderer);
    ospRelease(fb);
  }

  /// The first hit; the caller releases its instance and model (see release_pick).
  OSPPickResult operator()(OSPWorld world, std::array<float, 3> from, std::array<float, 3> dir = {0.f, 0.f, 1.f}) {
    ospSetVec3f(camera, "position", from[0], from[1], from[2]);
    ospSetVec3f(camera, "direction", dir[0], dir[1], dir[2]);
    ospCommit(camera);
    OSPPickResult result;
    ospPick(&result, fb, renderer, camera, world, 0.5f, 0.5f);
    return result;
  }
};

void release_pick(const OSPPickResult& hit) {
  if (!hit.hasHit) return;
  ospRelease(hit.instance);
  ospRelease(hit.model);
}

/// The pick from `from` along `dir` must hit `instance` and `model` at (x, y, z).
void check_pick(Picker& pick, OSPWorld world, std::array<float, 3> from, std::array<float, 3> dir,
                OSPInstance instance, OSPGeometricModel model, std::array<float, 3> expected,
                float tolerance = 1e-4f) {
  const OSPPickResult hit = pick(world, from, dir);
  check_position(hit, expected[0], expected[1], expected[2], tolerance);
  CHECK(hit.instance == instance);
  CHECK(hit.model == model);
  release_pick(hit);
}

/// The debug summary of the last world build ("world: built with ...").
std::string last_build_summary(const Messages& messages) {
  for (auto it = messages.status.rbegin(); it != messages.status.rend(); ++it)
    if (it->rfind("world: built with", 0) == 0) return *it;
  return {};
}

std::uint64_t reported_memory(const std::string& summary) {
  const auto at = summary.find("engine memory ");
  REQUIRE(at != std::string::npos);
  return std::stoull(summary.substr(at + std::strlen("engine memory ")));
}

void log_debug(OSPDevice device) {
  ospDeviceSetParam(device, "logLevel", OSP_STRING, "debug");
  ospDeviceCommit(device);
}

void check_bounds(const OSPBounds& b, std::array<float, 3> lower, std::array<float, 3> upper) {
  for (int k = 0; k < 3; ++k) {
    INFO("axis " << k);
    CHECK(b.lower[k] == Approx(lower[k]).margin(1e-5));
    CHECK(b.upper[k] == Approx(upper[k]).margin(1e-5));
  }
}

}  // namespace

TEST_CASE("instancing: 1000 instances of a mesh group share one copy, render and pick where they are placed",
          "[c_api][instancing]") {
  ApiFixture api;
  log_debug(api.device);
  const sciray::MeshData bunny = sciray::io::read_ply(SCIRAY_DATA_DIR "/meshes/bunny.ply");
  OSPGeometry geometry = ospNewGeometry("mesh");
  set_array(geometry, "vertex.position", bunny.positions.data(), OSP_VEC3F, bunny.vertex_count());
  set_array(geometry, "index", bunny.indices.data(), OSP_VEC3UI, bunny.face_count());
  ospCommit(geometry);
  OSPGeometricModel model = ospNewGeometricModel(geometry);
  ospCommit(model);
  OSPGroup group = new_group({model});
  const OSPBounds b = ospGetBounds(group);
  const float cx = (b.lower[0] + b.upper[0]) / 2, cy = (b.lower[1] + b.upper[1]) / 2, top = b.upper[2] + 1.f;
  Picker pick;

  // One instance: the reference pick, and the engine memory of one copy.
  OSPInstance single = new_instance(group);
  OSPWorld one = new_world({single});
  const OSPPickResult reference = pick(one, {cx, cy, top}, {0.f, 0.f, -1.f});
  REQUIRE(reference.hasHit == 1);
  release_pick(reference);
  const std::string one_summary = last_build_summary(api.messages);
  CHECK_THAT(one_summary, Catch::Contains("world: built with 1 instances of 1 groups (1 built, 0 reused)"));
  const std::uint64_t one_copy = reported_memory(one_summary);

  // 1000 instances on a 40 x 25 grid, 0.25 apart (the bunny is 0.16 across).
  constexpr int columns = 40, rows = 25;
  constexpr float spacing = 0.25f;
  std::vector<OSPInstance> instances;
  for (int j = 0; j < rows; ++j)
    for (int i = 0; i < columns; ++i)
      instances.push_back(new_instance(group, scale_then_move(1, 1, 1, spacing * i, spacing * j, 0.f)));
  OSPWorld many = new_world(instances);
  check_bounds(ospGetBounds(many), {b.lower[0], b.lower[1], b.lower[2]},
               {b.upper[0] + spacing * (columns - 1), b.upper[1] + spacing * (rows - 1), b.upper[2]});

  std::vector<int> sampled;
  for (int k = 0; k < columns * rows; k += 37) sampled.push_back(k);
  sampled.push_back(columns * rows - 1);
  for (int k : sampled) {
    const float dx = spacing * static_cast<float>(k % columns), dy = spacing * static_cast<float>(k / columns);
    INFO("instance " << k);
    const OSPPickResult hit = pick(many, {cx + dx, cy + dy, top}, {0.f, 0.f, -1.f});
    check_position(hit, reference.worldPosition[0] + dx, reference.worldPosition[1] + dy, reference.worldPosition[2]);
    CHECK(hit.instance == instances[static_cast<std::size_t>(k)]);
    CHECK(hit.model == model);
    CHECK(hit.primID == reference.primID);
    release_pick(hit);
  }
  // One engine group for the 1000 instances: they add a top-level BVH, not 1000 copies
  // (each of which would hold the bunny's 1.2 MB of vertices and indices and its BVH).
  const std::string many_summary = last_build_summary(api.messages);
  CHECK_THAT(many_summary, Catch::Contains("world: built with 1000 instances of 1 groups (1 built, 0 reused)"));
  const std::uint64_t thousand = reported_memory(many_summary);
  CHECK(thousand > one_copy);
  CHECK(thousand < one_copy + 1'000'000);

  // Every bunny is in the image: the pixel next to each one's centre shows it, the
  // pixel half way to the next one the background. 40 pixels per unit, looking down -z.
  constexpr int W = 400, H = 250;
  OSPCamera camera = ospNewCamera("orthographic");
  ospSetVec3f(camera, "position", cx - spacing / 2 + 5.f, cy - spacing / 2 + 3.125f, top);
  ospSetVec3f(camera, "direction", 0.f, 0.f, -1.f);
  ospSetFloat(camera, "height", 6.25f);
  ospSetFloat(camera, "aspect", 1.6f);
  ospCommit(camera);
  OSPFrameBuffer fb = ospNewFrameBuffer(W, H, OSP_FB_RGBA32F, OSP_FB_COLOR);
  ospRenderFrameBlocking(fb, pick.renderer, camera, many);
  const auto* rgba = static_cast<const float*>(ospMapFrameBuffer(fb, OSP_FB_COLOR));
  int shown = 0, gaps = 0;
  for (int j = 0; j < rows; ++j)
    for (int i = 0; i < columns; ++i) {
      shown += rgba[4 * ((10 * j + 5) * W + 10 * i + 5) + 3] == 1.f;
      gaps += rgba[4 * ((10 * j) * W + 10 * i) + 3] == 0.f;
    }
  CHECK(shown == columns * rows);
  CHECK(gaps == columns * rows);
  ospUnmapFrameBuffer(rgba, fb);
  ospRelease(fb);
  ospRelease(camera);

  // Moving one instance needs its commit only; the group's BVH carries over.
  set_transform(instances[0], scale_then_move(1, 1, 1, -0.5f, 0.f, 0.f));
  ospCommit(instances[0]);
  check_pick(pick, many, {cx - 0.5f, cy, top}, {0.f, 0.f, -1.f}, instances[0], model,
             {reference.worldPosition[0] - 0.5f, reference.worldPosition[1], reference.worldPosition[2]});
  CHECK_THAT(last_build_summary(api.messages),
             Catch::Contains("world: built with 1000 instances of 1 groups (0 built, 1 reused)"));
  const OSPPickResult gone = pick(many, {cx, cy, top}, {0.f, 0.f, -1.f});
  CHECK(gone.hasHit == 0);
  release_pick(gone);

  CHECK(api.messages.errors.empty());
  for (OSPInstance i : instances) ospRelease(i);
  for (OSPObject o : std::initializer_list<OSPObject>{geometry, model, group, single, one, many}) ospRelease(o);
}

TEST_CASE("instancing: a non-uniformly scaled sphere is an exact ellipsoid", "[c_api][instancing][sphere]") {
  ApiFixture api;
  GeometryScene scene(new_spheres({0.f, 0.f, 0.f}, 1.f), true);
  // Stretched 3 times along x: the ellipsoid x²/9 + y² + z² = 1.
  set_transform(scene.instance, scale_then_move(3, 1, 1, 0, 0, 0));
  ospCommit(scene.instance);
  check_bounds(ospGetBounds(scene.instance), {-3.f, -1.f, -1.f}, {3.f, 1.f, 1.f});
  check_bounds(ospGetBounds(scene.world), {-3.f, -1.f, -1.f}, {3.f, 1.f, 1.f});
  Picker pick;
  for (const char* intersector : intersectors) {
    INFO("intersector " << intersector);
    ospSetString(scene.geometry, "intersector", intersector);
    ospCommit(scene.geometry);
    // Along the long axis, from both ends.
    check_pick(pick, scene.world, {-10.f, 0.f, 0.f}, {1.f, 0.f, 0.f}, scene.instance, scene.model, {-3.f, 0.f, 0.f});
    check_pick(pick, scene.world, {10.f, 0.f, 0.f}, {-1.f, 0.f, 0.f}, scene.instance, scene.model, {3.f, 0.f, 0.f});
    // Across it: x = 2 is inside the ellipsoid (a sphere of the mean radius 3^(1/3) = 1.44 would be missed).
    check_pick(pick, scene.world, {2.f, 0.f, -5.f}, {0.f, 0.f, 1.f}, scene.instance, scene.model,
               {2.f, 0.f, -std::sqrt(5.f) / 3.f});
    check_pick(pick, scene.world, {0.f, 0.6f, -5.f}, {0.f, 0.f, 1.f}, scene.instance, scene.model, {0.f, 0.6f, -0.8f});
    const OSPPickResult outside = pick(scene.world, {0.f, 1.1f, -5.f});
    CHECK(outside.hasHit == 0);
    release_pick(outside);

    // The silhouette is the ellipse x²/9 + y² = 1 (orthographic, 16 pixels per unit).
    ospSetFloat(scene.camera, "aspect", 2.f);
    ospCommit(scene.camera);
    constexpr int W = 128, H = 64;
    const auto image = scene.render(W, H);
    int checked = 0, wrong = 0;
    for (int py = 0; py < H; ++py)
      for (int px = 0; px < W; ++px) {
        const float x = -((px + 0.5f) / W * 8.f - 4.f), y = (py + 0.5f) / H * 4.f - 2.f;
        const float r = std::sqrt(x * x / 9.f + y * y);
        if (std::abs(r - 1.f) < 0.03f) continue;
        ++checked;
        wrong += (image[4 * (py * W + px) + 3] == 1.f) != (r < 1.f);
      }
    CHECK(checked > W * H * 9 / 10);
    CHECK(wrong == 0);
  }
  CHECK(api.messages.errors.empty());
}

TEST_CASE("instancing: a pick on the 2nd of 3 translated instances reports that instance and its model",
          "[c_api][instancing][pick]") {
  ApiFixture api;
  log_debug(api.device);
  // One group of two models, a unit cube at the origin and a sphere above it.
  const float cube[6] = {-0.5f, -0.5f, -0.5f, 0.5f, 0.5f, 0.5f};
  OSPGeometry box = ospNewGeometry("box");
  set_array(box, "box", cube, OSP_BOX3F, 1);
  ospCommit(box);
  OSPGeometry sphere = new_spheres({0.f, 2.f, 0.f}, 0.5f);
  OSPGeometricModel models[2] = {ospNewGeometricModel(box), ospNewGeometricModel(sphere)};
  for (OSPGeometricModel m : models) ospCommit(m);
  OSPGroup group = new_group({models[0], models[1]});
  OSPGroup empty = new_group({});  // legal: its instances contribute nothing
  check_bounds(ospGetBounds(group), {-0.5f, -0.5f, -0.5f}, {0.5f, 2.5f, 0.5f});
  OSPInstance instances[4] = {new_instance(group, scale_then_move(1, 1, 1, -3.f, 0.f, 0.f)),
                              new_instance(empty, scale_then_move(1, 1, 1, 3.f, 0.f, 0.f)),
                              new_instance(group, scale_then_move(1, 1, 1, 1.f, 0.f, 0.f)),
                              new_instance(group, scale_then_move(1, 1, 1, 5.f, 0.f, 0.f))};
  OSPInstance& second = instances[2];
  OSPWorld world = new_world({instances[0], instances[1], instances[2], instances[3]});
  check_bounds(ospGetBounds(world), {-3.5f, -0.5f, -0.5f}, {5.5f, 2.5f, 0.5f});
  Picker pick;
  for (auto isa : sciray::simd::all_isas) {
    if (!sciray::simd::cpu_supports(isa)) continue;
    const std::string isa_name(sciray::simd::isa_name(isa));
    INFO("ISA " << isa_name);
    ospDeviceSetParam(api.device, "isa", OSP_STRING, isa_name.c_str());
    ospDeviceCommit(api.device);
    // The groups are built again with this ISA's kernels.
    check_pick(pick, world, {1.f, 0.f, -5.f}, {0.f, 0.f, 1.f}, second, models[0], {1.f, 0.f, -0.5f});
    CHECK_THAT(last_build_summary(api.messages), Catch::Contains("4 instances of 2 groups (2 built, 0 reused)"));
    check_pick(pick, world, {1.f, 2.f, -5.f}, {0.f, 0.f, 1.f}, second, models[1], {1.f, 2.f, -0.5f});
    check_pick(pick, world, {1.f, 2.f, 5.f}, {0.f, 0.f, -1.f}, second, models[1], {1.f, 2.f, 0.5f});
    check_pick(pick, world, {-3.f, 0.f, -5.f}, {0.f, 0.f, 1.f}, instances[0], models[0], {-3.f, 0.f, -0.5f});
    check_pick(pick, world, {5.f, 2.f, -5.f}, {0.f, 0.f, 1.f}, instances[3], models[1], {5.f, 2.f, -0.5f});
    check_pick(pick, world, {-10.f, 2.f, 0.f}, {1.f, 0.f, 0.f}, instances[0], models[1], {-3.5f, 2.f, 0.f});
    const OSPPickResult nothing = pick(world, {3.f, 0.f, -5.f});  // the empty group's place
    CHECK(nothing.hasHit == 0);
    release_pick(nothing);
  }

  // Recommitting a model rebuilds its group once; the empty group carries over.
  const float radius = 0.25f;
  ospSetFloat(sphere, "radius", radius);
  ospCommit(sphere);
  check_pick(pick, world, {1.f, 2.f, -5.f}, {0.f, 0.f, 1.f}, second, models[1], {1.f, 2.f, -0.25f});
  CHECK_THAT(last_build_summary(api.messages), Catch::Contains("4 instances of 2 groups (1 built, 1 reused)"));
  CHECK(api.messages.errors.empty());
  for (OSPInstance i : instances) ospRelease(i);
  for (OSPObject o : std::initializer_list<OSPObject>{box, sphere, models[0], models[1], group, empty, world})
    ospRelease(o);
}

TEST_CASE("box: picks land on the analytic faces; bounds; colours; instanced boxes", "[c_api][box]") {
  ApiFixture api;
  // Box 0 spans x -2..-0.5, y -1..1, z -1..1; box 1 x 0.5..2, y -0.5..0.5, z 0..3.
  const float boxes[2][6] = {{-2.f, -1.f, -1.f, -0.5f, 1.f, 1.f}, {0.5f, -0.5f, 0.f, 2.f, 0.5f, 3.f}};
  OSPGeometry g = ospNewGeometry("box");
  set_array(g, "box", boxes, OSP_BOX3F, 2);
  ospCommit(g);
  GeometryScene scene(g, true);
  check_bounds(ospGetBounds(scene.geometry), {-2.f, -1.f, -1.f}, {2.f, 1.f, 3.f});
  Picker pick;
  check_pick(pick, scene.world, {-1.f, 0.5f, -5.f}, {0.f, 0.f, 1.f}, scene.instance, scene.model, {-1.f, 0.5f, -1.f});
  check_pick(pick, scene.world, {1.f, 0.f, -5.f}, {0.f, 0.f, 1.f}, scene.instance, scene.model, {1.f, 0.f, 0.f});
  check_pick(pick, scene.world, {1.f, 0.f, 10.f}, {0.f, 0.f, -1.f}, scene.instance, scene.model, {1.f, 0.f, 3.f});
  check_pick(pick, scene.world, {-10.f, 0.f, 0.5f}, {1.f, 0.f, 0.f}, scene.instance, scene.model, {-2.f, 0.f, 0.5f});
  // From inside a box, the exit face.
  check_pick(pick, scene.world, {-1.f, 0.f, 0.f}, {0.f, 0.f, 1.f}, scene.instance, scene.model, {-1.f, 0.f, 1.f});
  OSPPickResult hit = pick(scene.world, {1.f, 0.f, -5.f});
  CHECK(hit.primID == 1);
  release_pick(hit);
  hit = pick(scene.world, {0.f, 0.f, -5.f});  // between the boxes
  CHECK(hit.hasHit == 0);
  release_pick(hit);

  // Model colours, one per box, times the material's kd.
  const float colors[2][4] = {{1.f, 0.f, 0.f, 1.f}, {0.f, 0.f, 1.f, 1.f}};
  set_array(scene.model, "color", colors, OSP_VEC4F, 2);
  OSPMaterial material = ospNewMaterial("obj");
  ospSetVec3f(material, "kd", 0.5f, 0.5f, 0.5f);
  ospCommit(material);
  ospSetObject(scene.model, "material", material);
  ospCommit(scene.model);
  constexpr int W = 64, H = 64;  // 4 x 4 world units, screen x running along -x
  const auto image = scene.render(W, H);
  int red = 0, blue = 0, wrong = 0;
  for (int py = 0; py < H; ++py)
    for (int px = 0; px < W; ++px) {
      const float x = -((px + 0.5f) / W * 4.f - 2.f), y = (py + 0.5f) / H * 4.f - 2.f;
      const float* rgba = &image[4 * (py * W + px)];
      const auto within = [](float v, float lo, float hi) { return v > lo + 0.05f && v < hi - 0.05f; };
      const auto outside = [](float v, float lo, float hi) { return v < lo - 0.05f || v > hi + 0.05f; };
      if (within(x, -2.f, -0.5f) && within(y, -1.f, 1.f)) {
        ++red;
        wrong += !(rgba[0] == Approx(0.5f) && rgba[1] == 0.f && rgba[2] == 0.f && rgba[3] == 1.f);
      } else if (within(x, 0.5f, 2.f) && within(y, -0.5f, 0.5f)) {
        ++blue;
        wrong += !(rgba[0] == 0.f && rgba[1] == 0.f && rgba[2] == Approx(0.5f) && rgba[3] == 1.f);
      } else if ((outside(x, -2.f, -0.5f) || outside(y, -1.f, 1.f)) && (outside(x, 0.5f, 2.f) || outside(y, -0.5f, 0.5f))) {
        wrong += rgba[3] != 0.f;
      }
    }
  CHECK(red > 500);
  CHECK(blue > 150);
  CHECK(wrong == 0);

  // Instanced with a non-uniform scale: box 0 then spans x -4..-1, z -3..3.
  set_transform(scene.instance, scale_then_move(2, 1, 3, 0, 0, 0));
  ospCommit(scene.instance);
  check_bounds(ospGetBounds(scene.world), {-4.f, -1.f, -3.f}, {4.f, 1.f, 9.f});
  check_pick(pick, scene.world, {-10.f, 0.f, 0.f}, {1.f, 0.f, 0.f}, scene.instance, scene.model, {-4.f, 0.f, 0.f});
  check_pick(pick, scene.world, {-3.f, 0.f, -5.f}, {0.f, 0.f, 1.f}, scene.instance, scene.model, {-3.f, 0.f, -3.f});
  check_pick(pick, scene.world, {3.f, 0.f, 20.f}, {0.f, 0.f, -1.f}, scene.instance, scene.model, {3.f, 0.f, 9.f});
  ospRelease(material);
  CHECK(api.messages.errors.empty());
}

TEST_CASE("plane: picks land on the analytic plane; bounded planes; colours; instanced planes", "[c_api][plane]") {
  ApiFixture api;
  // z = 2, and x + z = 4 (its normal not normalized) bounded to x in [1, 3].
  const float planes[2][4] = {{0.f, 0.f, 1.f, -2.f}, {2.f, 0.f, 2.f, -8.f}};
  OSPGeometry g = ospNewGeometry("plane");
  set_array(g, "plane.coefficients", planes, OSP_VEC4F, 1);
  ospCommit(g);
  GeometryScene scene(g, true);
  CHECK(ospGetBounds(scene.geometry).lower[0] > ospGetBounds(scene.geometry).upper[0]);  // unbounded: empty
  Picker pick;
  check_pick(pick, scene.world, {0.3f, 0.7f, -5.f}, {0.f, 0.f, 1.f}, scene.instance, scene.model, {0.3f, 0.7f, 2.f});
  check_pick(pick, scene.world, {100.f, -50.f, -5.f}, {0.f, 0.f, 1.f}, scene.instance, scene.model,
             {100.f, -50.f, 2.f});
  check_pick(pick, scene.world, {0.f, 0.f, 10.f}, {0.f, 0.f, -1.f}, scene.instance, scene.model, {0.f, 0.f, 2.f});
  // Oblique rays meet it where the line does.
  const float s = 1.f / std::sqrt(2.f);
  check_pick(pick, scene.world, {0.f, 0.f, 0.f}, {s, 0.f, s}, scene.instance, scene.model, {2.f, 0.f, 2.f});

  // Two planes, the second bounded; one colour each.
  set_array(g, "plane.coefficients", planes, OSP_VEC4F, 2);
  const float bounds[2][6] = {{-100.f, -100.f, 1.f, 100.f, 100.f, 3.f}, {1.f, -1.f, 1.f, 3.f, 1.f, 3.f}};
  set_array(g, "plane.bounds", bounds, OSP_BOX3F, 2);
  ospCommit(g);
  const float colors[2][3] = {{0.f, 1.f, 0.f}, {1.f, 0.f, 1.f}};
  set_array(scene.model, "color", colors, OSP_VEC3F, 2);
  ospCommit(scene.model);
  check_bounds(ospGetBounds(scene.geometry), {-100.f, -100.f, 1.f}, {100.f, 100.f, 3.f});
  // x = 1.5: the tilted plane (z = 2.5) is behind z = 2 from below, in front from above.
  OSPPickResult hit = pick(scene.world, {1.5f, 0.f, -5.f});
  check_position(hit, 1.5f, 0.f, 2.f);
  CHECK(hit.primID == 0);
  release_pick(hit);
  hit = pick(scene.world, {1.5f, 0.f, 5.f}, {0.f, 0.f, -1.f});
  check_position(hit, 1.5f, 0.f, 2.5f);
  CHECK(hit.primID == 1);
  release_pick(hit);
  hit = pick(scene.world, {1.5f, 1.5f, 5.f}, {0.f, 0.f, -1.f});  // y = 1.5: outside the second's bounds
  check_position(hit, 1.5f, 1.5f, 2.f);
  CHECK(hit.primID == 0);
  release_pick(hit);
  hit = pick(scene.world, {150.f, 0.f, -5.f});  // outside both
  CHECK(hit.hasHit == 0);
  release_pick(hit);
  // The first plane fills the orthographic view in its colour.
  const auto image = scene.render(16, 16);
  int green = 0;
  for (std::size_t i = 0; i < image.size(); i += 4)
    green += image[i] == 0.f && image[i + 1] == 1.f && image[i + 2] == 0.f && image[i + 3] == 1.f;
  CHECK(green == 16 * 16);

  // Instanced: moved up by 1 and stretched 2 times along z, z = 2 becomes z = 5.
  set_transform(scene.instance, scale_then_move(1, 1, 2, 0, 0, 1));
  ospCommit(scene.instance);
  hit = pick(scene.world, {-20.f, 7.f, -5.f});
  check_position(hit, -20.f, 7.f, 5.f);
  CHECK(hit.instance == scene.instance);
  release_pick(hit);
  check_bounds(ospGetBounds(scene.world), {-100.f, -100.f, 3.f}, {100.f, 100.f, 7.f});
  CHECK(api.messages.errors.empty());
}

TEST_CASE("box and plane: bad input is named through the error callback", "[c_api][box][plane][errors]") {
  ApiFixture api;
  const float good_boxes[2][6] = {{0, 0, 0, 1, 1, 1}, {2, 2, 2, 3, 3, 3}};
  const float nan_boxes[2][6] = {{0, 0, 0, 1, 1, 1}, {2, 2, 2, 3, NAN, 3}};
  const float inverted_boxes[2][6] = {{0, 0, 0, 1, -1, 1}, {2, 2, 2, 3, 3, 3}};
  const float three[6] = {0, 0, 0, 1, 1, 1};

  OSPGeometry box = ospNewGeometry("box");
  ospCommit(box);
  api.expect_error("box geometry: required parameter 'box' (array of box3f) is missing");
  set_array(box, "box", three, OSP_VEC3F, 2);
  ospCommit(box);
  api.expect_error("box geometry: parameter 'box' must be an array of box3f, got an array of vec3f");
  set_array(box, "box", nan_boxes, OSP_BOX3F, 2);
  ospCommit(box);
  api.expect_error("box: 'box' 1 is not a finite box with lower <= upper");
  set_array(box, "box", inverted_boxes, OSP_BOX3F, 2);
  ospCommit(box);
  api.expect_error("box: 'box' 0 is not a finite box with lower <= upper");
  set_array(box, "box", good_boxes, OSP_BOX3F, 2);
  ospCommit(box);
  CHECK(api.messages.errors.empty());
  OSPGeometricModel model = ospNewGeometricModel(box);
  const float one_color[4] = {1, 0, 0, 1};
  set_array(model, "color", one_color, OSP_VEC4F, 1);
  ospCommit(model);
  CHECK(api.messages.errors.empty());  // one colour for both boxes

  const float good_planes[2][4] = {{0, 0, 1, 0}, {1, 0, 0, -1}};
  const float nan_planes[2][4] = {{0, 0, 1, 0}, {1, 0, 0, NAN}};
  const float flat_planes[2][4] = {{0, 0, 0, 1}, {1, 0, 0, -1}};
  OSPGeometry plane = ospNewGeometry("plane");
  ospCommit(plane);
  api.expect_error("plane geometry: required parameter 'plane.coefficients' (array of vec4f) is missing");
  set_array(plane, "plane.coefficients", three, OSP_VEC3F, 2);
  ospCommit(plane);
  api.expect_error("plane geometry: parameter 'plane.coefficients' must be an array of vec4f, got an array of vec3f");
  set_array(plane, "plane.coefficients", nan_planes, OSP_VEC4F, 2);
  ospCommit(plane);
  api.expect_error("plane: 'plane.coefficients' 1 is not finite");
  set_array(plane, "plane.coefficients", flat_planes, OSP_VEC4F, 2);
  ospCommit(plane);
  api.expect_error("plane: 'plane.coefficients' 0 has a zero normal (a, b, c)");
  set_array(plane, "plane.coefficients", good_planes, OSP_VEC4F, 2);
  set_array(plane, "plane.bounds", good_boxes, OSP_BOX3F, 1);
  ospCommit(plane);
  api.expect_error("plane: 'plane.bounds' has 1 elements but there are 2 planes");
  set_array(plane, "plane.bounds", good_planes, OSP_VEC4F, 2);
  ospCommit(plane);
  api.expect_error("plane geometry: parameter 'plane.bounds' must be an array of box3f, got an array of vec4f");
  set_array(plane, "plane.bounds", inverted_boxes, OSP_BOX3F, 2);
  ospCommit(plane);
  api.expect_error("plane: 'plane.bounds' 0 is not a finite box with lower <= upper");
  ospRemoveParam(plane, "plane.bounds");
  ospCommit(plane);
  CHECK(api.messages.errors.empty());

  // A failed commit leaves the geometry as it was: the good boxes still render.
  set_array(box, "box", nan_boxes, OSP_BOX3F, 2);
  ospCommit(box);
  api.expect_error("box: 'box' 1 is not a finite box");
  {
    ospRetain(box);
    GeometryScene scene(box);
    Picker pick;
    check_pick(pick, scene.world, {0.5f, 0.5f, -5.f}, {0.f, 0.f, 1.f}, scene.instance, scene.model, {0.5f, 0.5f, 0.f});
  }
  CHECK(api.messages.errors.empty());
  for (OSPObject o : std::initializer_list<OSPObject>{box, model, plane}) ospRelease(o);
}

// ---- clipping geometry ---------------------------------------------------------------------

namespace {

/// The 8 corners of [lower, upper] (corner k takes upper on axis i where bit i of k is
/// set) and the 12 outward-facing triangles over them.
std::vector<float> cube_corners(std::array<float, 3> lower, std::array<float, 3> upper) {
  std::vector<float> corners;
  for (int k = 0; k < 8; ++k)
    for (int i = 0; i < 3; ++i) corners.push_back(k & (1 << i) ? upper[i] : lower[i]);
  return corners;
}
const std::uint32_t cube_triangles[12][3] = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                                             {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};

/// A committed mesh geometry: the closed cube [lower, upper] as 12 triangles.
OSPGeometry new_cube_mesh(std::array<float, 3> lower, std::array<float, 3> upper) {
  const std::vector<float> corners = cube_corners(lower, upper);
  OSPGeometry g = ospNewGeometry("mesh");
  set_array(g, "vertex.position", corners.data(), OSP_VEC3F, 8);
  set_array(g, "index", cube_triangles, OSP_VEC3UI, 12);
  ospCommit(g);
  return g;
}

/// A committed model of `g`, which it takes over; `invert` sets invertNormals.
OSPGeometricModel new_model(OSPGeometry g, bool invert = false) {
  OSPGeometricModel model = ospNewGeometricModel(g);
  ospRelease(g);
  if (invert) ospSetBool(model, "invertNormals", true);
  ospCommit(model);
  return model;
}

/// Sets `group`'s clippingGeometry to `models` (none: removes it) and commits it.
void set_clipping(OSPGroup group, const std::vector<OSPGeometricModel>& models) {
  if (models.empty()) {
    ospRemoveParam(group, "clippingGeometry");
  } else {
    OSPData list = ospNewSharedData1D(models.data(), OSP_GEOMETRIC_MODEL, models.size());
    ospSetObject(group, "clippingGeometry", list);
    ospRelease(list);
  }
  ospCommit(group);
}

/// A rotation by `degrees` about the axis `axis` (0, 1, 2 for x, y, z), then a move.
std::array<float, 12> rotate_then_move(int axis, float degrees, float tx, float ty, float tz, float scale = 1.f) {
  const float a = degrees * 3.14159265358979f / 180.f, c = std::cos(a) * scale, s = std::sin(a) * scale;
  std::array<float, 12> m{};
  const int u = (axis + 1) % 3, v = (axis + 2) % 3;  // rotates u towards v
  m[3 * axis + axis] = scale;
  m[3 * u + u] = c, m[3 * u + v] = s;
  m[3 * v + u] = -s, m[3 * v + v] = c;
  m[9] = tx, m[10] = ty, m[11] = tz;
  return m;
}

/// The solid cube [-1, 1]³ as a mesh in one group and instance, and a second group
/// with clipping geometry only (none at first) in its own instance; lit by an ambient
/// light. Picks and orthographic depth images look down +z from z = -5.
struct ClipScene {
  OSPGeometricModel cube = new_model(new_cube_mesh({-1.f, -1.f, -1.f}, {1.f, 1.f, 1.f}));
  OSPGroup cube_group = new_group({cube});
  OSPInstance cube_instance = new_instance(cube_group);
  OSPGroup clip_group = new_group({});
  OSPInstance clip_instance = new_instance(clip_group);
  OSPWorld world = new_world({cube_instance, clip_instance});
  Picker pick;

  ClipScene() = default;
  ClipScene(const ClipScene&) = delete;
  ClipScene& operator=(const ClipScene&) = delete;
  ~ClipScene() {
    for (OSPObject o :
         std::initializer_list<OSPObject>{cube, cube_group, cube_instance, clip_group, clip_instance, world})
      ospRelease(o);
  }

  /// Clips with `models` placed by `m` (the models stay the caller's).
  void clip(const std::vector<OSPGeometricModel>& models,
            const std::array<float, 12>& m = scale_then_move(1, 1, 1, 0, 0, 0)) {
    set_clipping(clip_group, models);
    set_transform(clip_instance, m);
    ospCommit(clip_instance);
  }

  /// The pick from (x, y, -5) along +z must land on the cube at (x, y, z).
  void expect_cube(float x, float y, float z) {
    INFO("pick from (" << x << ", " << y << ", -5)");
    check_pick(pick, world, {x, y, -5.f}, {0.f, 0.f, 1.f}, cube_instance, cube, {x, y, z});
  }
  void expect_miss(float x, float y) {
    INFO("pick from (" << x << ", " << y << ", -5)");
    const OSPPickResult hit = pick(world, {x, y, -5.f});
    CHECK(hit.hasHit == 0);
    release_pick(hit);
  }

  /// Depth (distance from the plane z = -5: 4 on the front face, 6 on the back face,
  /// inf where nothing is hit) of an orthographic W x W view of [-2, 2]², with the
  /// screen's x running along -x; calls check(x, y, depth) for each pixel.
  template <class Check>
  void check_depth(int W, Check&& check) {
    OSPCamera camera = ospNewCamera("orthographic");
    ospSetVec3f(camera, "position", 0.f, 0.f, -5.f);
    ospSetVec3f(camera, "direction", 0.f, 0.f, 1.f);
    ospSetFloat(camera, "height", 4.f);
    ospCommit(camera);
    OSPFrameBuffer fb = ospNewFrameBuffer(W, W, OSP_FB_RGBA32F, OSP_FB_COLOR | OSP_FB_DEPTH);
    ospRenderFrameBlocking(fb, pick.renderer, camera, world);
    const auto* depth = static_cast<const float*>(ospMapFrameBuffer(fb, OSP_FB_DEPTH));
    REQUIRE(depth != nullptr);
    for (int py = 0; py < W; ++py)
      for (int px = 0; px < W; ++px)
        check(-((px + 0.5f) / W * 4.f - 2.f), (py + 0.5f) / W * 4.f - 2.f, depth[py * W + px]);
    ospUnmapFrameBuffer(depth, fb);
    ospRelease(fb);
    ospRelease(camera);
  }
};

constexpr float inf = std::numeric_limits<float>::infinity();

/// Counts pixels whose depth is not `expected(x, y)`; NaN means "do not check" (near an
/// edge of the clipped region).
template <class Expected>
int wrong_depths(ClipScene& scene, Expected&& expected, int* checked) {
  int wrong = 0;
  *checked = 0;
  scene.check_depth(64, [&](float x, float y, float depth) {
    const float want = expected(x, y);
    if (std::isnan(want)) return;
    ++*checked;
    if (std::isinf(want) ? !std::isinf(depth) : std::abs(depth - want) > 1e-3f) ++wrong;
  });
  return wrong;
}

/// Where the front face is cut by a disc of `radius` about (cx, cy) and the back face is
/// not: `inside` where the front face is clipped, `outside` elsewhere on the cube, inf
/// off it, NaN within `margin` of an edge.
float disc_depth(float x, float y, float cx, float cy, float radius, float inside, float outside,
                 float margin = 0.05f) {
  if (std::abs(std::abs(x) - 1.f) < margin || std::abs(std::abs(y) - 1.f) < margin) return NAN;
  if (std::abs(x) > 1.f || std::abs(y) > 1.f) return inf;
  const float r = std::hypot(x - cx, y - cy);
  if (std::abs(r - radius) < margin) return NAN;
  return r < radius ? inside : outside;
}

}  // namespace

TEST_CASE("clipping: a sphere bites the cube's front face; picks and frames reach the back face",
          "[c_api][clipping]") {
  ApiFixture api;
  ClipScene scene;
  scene.expect_cube(0.f, 0.f, -1.f);  // no clipping yet

  // A sphere of radius 0.5 about the front face's centre, in a group of its own: it
  // clips the other group's cube, and is not rendered itself.
  OSPGeometricModel ball = new_model(new_spheres({0.f, 0.f, -1.f}, 0.5f));
  scene.clip({ball});
  scene.expect_cube(0.f, 0.f, 1.f);
  scene.expect_cube(0.f, 0.3f, 1.f);
  scene.expect_cube(-0.3f, 0.3f, 1.f);
  scene.expect_cube(0.8f, 0.f, -1.f);
  scene.expect_cube(0.f, -0.6f, -1.f);
  check_pick(scene.pick, scene.world, {0.f, 0.f, 5.f}, {0.f, 0.f, -1.f}, scene.cube_instance, scene.cube,
             {0.f, 0.f, 1.f});  // the back face itself is whole
  const OSPPickResult beside = scene.pick(scene.world, {0.f, 1.3f, -5.f});  // the ball is not there
  CHECK(beside.hasHit == 0);
  release_pick(beside);
  check_bounds(ospGetBounds(scene.world), {-1.f, -1.f, -1.f}, {1.f, 1.f, 1.f});  // clipping adds no bounds
  int checked = 0;
  CHECK(wrong_depths(scene, [](float x, float y) { return disc_depth(x, y, 0.f, 0.f, 0.5f, 6.f, 4.f); }, &checked) ==
        0);
  CHECK(checked > 64 * 64 / 3);

  // Placed by a rotation with a uniform scale 2 and a move: the sphere (0, 0, -0.5) of
  // radius 0.25 about z becomes the sphere (0.3, 0, -1) of radius 0.5.
  OSPGeometricModel small = new_model(new_spheres({0.f, 0.f, -0.5f}, 0.25f));
  scene.clip({small}, rotate_then_move(2, 90.f, 0.3f, 0.f, 0.f, 2.f));
  scene.expect_cube(0.3f, 0.f, 1.f);
  scene.expect_cube(0.7f, 0.f, 1.f);
  scene.expect_cube(-0.3f, 0.f, -1.f);
  scene.expect_cube(0.3f, 0.6f, -1.f);

  // Clipping geometry in the rendered group itself, moved with it.
  set_clipping(scene.cube_group, {ball});
  scene.clip({});
  set_transform(scene.cube_instance, scale_then_move(1, 1, 1, 5, 0, 0));
  ospCommit(scene.cube_instance);
  check_pick(scene.pick, scene.world, {5.f, 0.f, -5.f}, {0.f, 0.f, 1.f}, scene.cube_instance, scene.cube,
             {5.f, 0.f, 1.f});
  check_pick(scene.pick, scene.world, {5.8f, 0.f, -5.f}, {0.f, 0.f, 1.f}, scene.cube_instance, scene.cube,
             {5.8f, 0.f, -1.f});
  ospRelease(ball);
  ospRelease(small);
  CHECK(api.messages.errors.empty());
}

TEST_CASE("clipping: invertNormals keeps only what lies inside", "[c_api][clipping]") {
  ApiFixture api;
  ClipScene scene;
  OSPGeometricModel ball = new_model(new_spheres({0.f, 0.f, -1.f}, 0.5f), true);
  scene.clip({ball});
  scene.expect_cube(0.f, 0.f, -1.f);
  scene.expect_cube(0.f, 0.3f, -1.f);
  scene.expect_miss(0.8f, 0.f);  // outside the ball: both faces clipped
  scene.expect_miss(0.f, -0.6f);
  int checked = 0;
  CHECK(wrong_depths(scene, [](float x, float y) { return disc_depth(x, y, 0.f, 0.f, 0.5f, 4.f, inf); }, &checked) ==
        0);
  CHECK(checked > 64 * 64 / 3);
  ospRelease(ball);
  CHECK(api.messages.errors.empty());
}

TEST_CASE("clipping: a plane in a moved and rotated instance clips in world space", "[c_api][clipping][plane]") {
  ApiFixture api;
  ClipScene scene;
  // z = 0 clips z < 0 in its group; rotated by 60 degrees about y and moved to
  // t = (0.2, 5, -0.3), it keeps n·(p - t) >= 0 with n = (sin 60°, 0, cos 60°).
  const float plane[4] = {0.f, 0.f, 1.f, 0.f};
  OSPGeometry g = ospNewGeometry("plane");
  set_array(g, "plane.coefficients", plane, OSP_VEC4F, 1);
  ospCommit(g);
  OSPGeometricModel model = new_model(g);
  scene.clip({model}, rotate_then_move(1, 60.f, 0.2f, 5.f, -0.3f));
  const float nx = std::sin(3.14159265f / 3.f), nz = 0.5f;
  const auto kept = [&](float x, float z) { return nx * (x - 0.2f) + nz * (z + 0.3f) >= 0.f; };
  for (float x : {-0.9f, -0.5f, 0.f, 0.3f, 0.5f, 0.8f, 0.95f})
    for (float y : {-0.5f, 0.f, 0.7f}) {
      INFO("x " << x << " y " << y);
      if (kept(x, -1.f))
        scene.expect_cube(x, y, -1.f);
      else if (kept(x, 1.f))
        scene.expect_cube(x, y, 1.f);  // the front clipped, the back face behind it kept
      else
        scene.expect_miss(x, y);
    }
  // Along +x the face x = -1 is clipped, x = 1 is kept.
  check_pick(scene.pick, scene.world, {-5.f, 0.f, 0.f}, {1.f, 0.f, 0.f}, scene.cube_instance, scene.cube,
             {1.f, 0.f, 0.f});
  int checked = 0;
  CHECK(wrong_depths(scene,
                     [&](float x, float y) -> float {
                       if (std::abs(std::abs(x) - 1.f) < 0.05f || std::abs(std::abs(y) - 1.f) < 0.05f) return NAN;
                       if (std::abs(x) > 1.f || std::abs(y) > 1.f) return inf;
                       const float front = nx * (x - 0.2f) + nz * (-1.f + 0.3f), back = front + 2.f * nz;
                       if (std::abs(front) < 0.05f || std::abs(back) < 0.05f) return NAN;
                       return front >= 0.f ? 4.f : back >= 0.f ? 6.f : inf;
                     },
                     &checked) == 0);
  CHECK(checked > 64 * 64 / 3);

  // A mirroring instance turns the clipped side around with the space: x = 0 clips
  // x < 0 in its group, which the mirror x -> -x places at x > 0.
  const float yz_plane[4] = {1.f, 0.f, 0.f, 0.f};
  set_array(g, "plane.coefficients", yz_plane, OSP_VEC4F, 1);
  ospCommit(g);
  scene.clip({model}, scale_then_move(-1, 1, 1, 0, 0, 0));
  scene.expect_cube(-0.5f, 0.f, -1.f);
  scene.expect_miss(0.5f, 0.f);
  ospRelease(model);
  CHECK(api.messages.errors.empty());
}

TEST_CASE("clipping: boxes, analytic under axis-aligned scales, exact meshes under rotations",
          "[c_api][clipping][box]") {
  ApiFixture api;
  ClipScene scene;
  const float box[6] = {-0.5f, -0.5f, -0.5f, 0.5f, 0.5f, 0.5f};
  OSPGeometry g = ospNewGeometry("box");
  set_array(g, "box", box, OSP_BOX3F, 1);
  ospCommit(g);
  OSPGeometricModel model = new_model(g);

  // Scaled along x and moved to the front face: it clips |x| < 0.4, |y| < 0.5 there.
  scene.clip({model}, scale_then_move(0.8f, 1, 1, 0, 0, -1));
  scene.expect_cube(0.35f, 0.45f, 1.f);
  scene.expect_cube(-0.35f, -0.45f, 1.f);
  scene.expect_cube(0.45f, 0.f, -1.f);
  scene.expect_cube(0.f, 0.55f, -1.f);

  // Rotated by 45 degrees about z: the diamond |x| + |y| < 0.5·√2 on the front face. An
  // axis-aligned box around it would clip (0.4, 0.4) too.
  scene.clip({model}, rotate_then_move(2, 45.f, 0, 0, -1));
  const float half_diagonal = 0.5f * std::sqrt(2.f);
  for (float x : {-0.6f, -0.3f, 0.f, 0.3f, 0.4f, 0.6f, 0.8f})
    for (float y : {-0.4f, 0.f, 0.3f, 0.4f}) {
      INFO("x " << x << " y " << y);
      if (std::abs(std::abs(x) + std::abs(y) - half_diagonal) < 0.02f) continue;
      scene.expect_cube(x, y, std::abs(x) + std::abs(y) < half_diagonal ? 1.f : -1.f);
    }
  int checked = 0;
  CHECK(wrong_depths(scene,
                     [&](float x, float y) -> float {
                       if (std::abs(std::abs(x) - 1.f) < 0.05f || std::abs(std::abs(y) - 1.f) < 0.05f) return NAN;
                       if (std::abs(x) > 1.f || std::abs(y) > 1.f) return inf;
                       const float d = std::abs(x) + std::abs(y) - half_diagonal;
                       if (std::abs(d) < 0.05f) return NAN;
                       return d < 0.f ? 6.f : 4.f;
                     },
                     &checked) == 0);
  CHECK(checked > 64 * 64 / 3);
  ospRelease(model);
  CHECK(api.messages.errors.empty());
}

TEST_CASE("clipping: a closed mesh clips its inside; meshes must be closed, at most 64", "[c_api][clipping]") {
  ApiFixture api;
  ClipScene scene;
  // The box [-0.5, 0.5]² x [-1.5, -0.5] as 6 quads with 4 vertices each (closed once
  // its vertices are welded by position), moved by 0.3 along x.
  const std::vector<float> c = cube_corners({-0.5f, -0.5f, -1.5f}, {0.5f, 0.5f, -0.5f});
  const std::uint32_t faces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                     {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  std::vector<float> positions;
  std::vector<std::uint32_t> quads;
  for (const auto& face : faces)
    for (std::uint32_t corner : face) {
      quads.push_back(static_cast<std::uint32_t>(positions.size() / 3));
      positions.insert(positions.end(), {c[3 * corner], c[3 * corner + 1], c[3 * corner + 2]});
    }
  OSPGeometry g = ospNewGeometry("mesh");
  set_array(g, "vertex.position", positions.data(), OSP_VEC3F, 24);
  set_array(g, "index", quads.data(), OSP_VEC4UI, 6);
  ospCommit(g);
  OSPGeometricModel model = new_model(g);
  scene.clip({model}, scale_then_move(1, 1, 1, 0.3f, 0, 0));
  scene.expect_cube(0.3f, 0.f, 1.f);
  scene.expect_cube(-0.15f, 0.4f, 1.f);
  scene.expect_cube(0.75f, -0.4f, 1.f);
  scene.expect_cube(-0.3f, 0.f, -1.f);
  scene.expect_cube(0.3f, 0.6f, -1.f);
  int checked = 0;
  CHECK(wrong_depths(scene,
                     [&](float x, float y) -> float {
                       if (std::abs(std::abs(x) - 1.f) < 0.05f || std::abs(std::abs(y) - 1.f) < 0.05f) return NAN;
                       if (std::abs(x) > 1.f || std::abs(y) > 1.f) return inf;
                       const float d = std::max(std::abs(x - 0.3f), std::abs(y)) - 0.5f;
                       if (std::abs(d) < 0.05f) return NAN;
                       return d < 0.f ? 6.f : 4.f;
                     },
                     &checked) == 0);
  CHECK(checked > 64 * 64 / 3);

  // Inverted: only the part of the cube inside the mesh remains.
  ospSetBool(model, "invertNormals", true);
  ospCommit(model);
  scene.expect_cube(0.3f, 0.f, -1.f);
  scene.expect_miss(-0.3f, 0.f);

  // Without its last face the mesh is open.
  set_array(g, "index", quads.data(), OSP_VEC4UI, 5);
  ospCommit(g);
  const OSPPickResult open = scene.pick(scene.world, {0.f, 0.f, -5.f});
  CHECK(open.hasHit == 0);
  CHECK(api.messages.any_error_containing(
      "ospPick: world: the group of instance 1, parameter 'clippingGeometry' element 0 (mesh geometry): only a closed "
      "mesh can clip, but the edge between vertices"));
  api.messages.errors.clear();

  // 65 instances of a group clipping with a mesh: the engine takes 64.
  set_array(g, "index", quads.data(), OSP_VEC4UI, 6);
  ospCommit(g);
  std::vector<OSPInstance> instances{scene.cube_instance};
  for (int i = 0; i < 65; ++i)
    instances.push_back(new_instance(scene.clip_group, scale_then_move(1, 1, 1, 0, 0, -3.f * i)));
  OSPWorld many = new_world(instances);
  const OSPPickResult too_many = scene.pick(many, {0.f, 0.f, -5.f});
  CHECK(too_many.hasHit == 0);
  CHECK(api.messages.any_error_containing("the group of instance 65, parameter 'clippingGeometry' element 0 (mesh "
                                          "geometry): clipping: at most 64 clipping meshes are supported"));
  api.messages.errors.clear();
  for (std::size_t i = 1; i < instances.size(); ++i) ospRelease(instances[i]);
  ospRelease(many);
  ospRelease(model);
}

TEST_CASE("clipping: what cannot clip is named through the error callback", "[c_api][clipping][errors]") {
  ApiFixture api;
  ClipScene scene;
  OSPGeometricModel ball = new_model(new_spheres({0.f, 0.f, -1.f}, 0.5f));
  scene.clip({ball});
  scene.expect_cube(0.f, 0.f, 1.f);
  CHECK(api.messages.errors.empty());

  // Curves: at the group's commit, which fails and leaves the group clipping with the ball.
  OSPGeometricModel curve = new_model(new_curves({0, 0, 0, 0.1f, 1, 0, 0, 0.1f}, {0}, OSP_ROUND, OSP_LINEAR));
  set_clipping(scene.clip_group, {curve});
  api.expect_error("ospCommit: group: parameter 'clippingGeometry' element 0: curve geometry cannot clip yet");
  scene.expect_cube(0.f, 0.f, 1.f);

  // Bounded planes: at the group's commit, and at the world's build when the plane was
  // given bounds after the group was committed.
  const float plane[4] = {0.f, 0.f, 1.f, 0.f};
  const float bounds[6] = {-1.f, -1.f, -1.f, 1.f, 1.f, 1.f};
  OSPGeometry plane_geometry = ospNewGeometry("plane");
  set_array(plane_geometry, "plane.coefficients", plane, OSP_VEC4F, 1);
  set_array(plane_geometry, "plane.bounds", bounds, OSP_BOX3F, 1);
  ospCommit(plane_geometry);
  ospRetain(plane_geometry);
  OSPGeometricModel bounded = new_model(plane_geometry);
  set_clipping(scene.clip_group, {bounded});
  api.expect_error("ospCommit: group: parameter 'clippingGeometry' element 0: planes with 'plane.bounds' are not "
               "supported as clipping geometry yet");
  ospRemoveParam(plane_geometry, "plane.bounds");
  ospCommit(plane_geometry);
  set_clipping(scene.clip_group, {bounded});
  scene.expect_cube(0.f, 0.5f, 1.f);  // z < 0 clipped
  set_array(plane_geometry, "plane.bounds", bounds, OSP_BOX3F, 1);
  ospCommit(plane_geometry);
  const OSPPickResult none = scene.pick(scene.world, {0.f, 0.f, -5.f});
  CHECK(none.hasHit == 0);
  api.expect_error("ospPick: world: the group of instance 1, parameter 'clippingGeometry' element 0 (plane geometry): "
               "planes with 'plane.bounds' are not supported as clipping geometry yet");

  // Discs enclose nothing.
  OSPGeometry discs = new_spheres({0.f, 0.f, -1.f}, 0.5f);
  ospSetInt(discs, "type", OSP_DISC);
  ospCommit(discs);
  OSPGeometricModel disc_model = new_model(discs);
  set_clipping(scene.clip_group, {disc_model});
  api.expect_error("parameter 'clippingGeometry' element 0: discs (sphere geometry of type OSP_DISC or "
               "OSP_ORIENTED_DISC) enclose nothing and cannot clip");

  // Spheres under a non-uniform scale: at the world's build, naming the group.
  scene.clip({ball}, scale_then_move(2, 1, 1, 0, 0, 0));
  OSPFrameBuffer fb = ospNewFrameBuffer(8, 8);
  OSPFuture future = ospRenderFrame(fb, scene.pick.renderer, scene.pick.camera, scene.world);
  CHECK(future == nullptr);
  api.expect_error("ospRenderFrame: world: the group of instance 1, parameter 'clippingGeometry' element 0 (sphere "
               "geometry): its instance's transform scales non-uniformly (a sphere becomes an ellipsoid), which "
               "clipping spheres do not support yet");
  ospRelease(fb);
  scene.clip({ball}, rotate_then_move(0, 30.f, 0, 0, 0, 3.f));  // uniform: fine
  const OSPPickResult uniform = scene.pick(scene.world, {0.f, 0.f, -5.f});
  CHECK(uniform.hasHit == 1);
  release_pick(uniform);
  CHECK(api.messages.errors.empty());
  scene.clip({ball});

  // Elements that are not models.
  OSPGeometry sphere_geometry = new_spheres({0.f, 0.f, 0.f}, 1.f);
  ospSetObjectAsData(scene.clip_group, "clippingGeometry", OSP_GEOMETRY, sphere_geometry);
  ospCommit(scene.clip_group);
  api.expect_error(
      "group: parameter 'clippingGeometry' must be an array of OSPGeometricModel, got an array of OSPGeometry");
  OSPGeometricModel uncommitted = ospNewGeometricModel(sphere_geometry);
  ospSetObjectAsData(scene.clip_group, "clippingGeometry", OSP_GEOMETRIC_MODEL, uncommitted);
  ospCommit(scene.clip_group);
  api.expect_error("group: parameter 'clippingGeometry' element 0 has not been committed");
  scene.expect_cube(0.f, 0.f, 1.f);  // still clipping with the ball
  for (OSPObject o : std::initializer_list<OSPObject>{ball, curve, plane_geometry, bounded, disc_model,
                                                     sphere_geometry, uncommitted})
    ospRelease(o);
  CHECK(api.messages.errors.empty());
}

TEST_CASE("clipping: recommitting clipping geometry, its model or instance changes the next frame",
          "[c_api][clipping][commit]") {
  ApiFixture api;
  log_debug(api.device);
  ClipScene scene;
  OSPGeometry g = new_spheres({0.f, 0.f, -1.f}, 0.5f);
  ospRetain(g);
  OSPGeometricModel ball = new_model(g);
  // In the rendered group: changing the clipping keeps the group's BVH.
  set_clipping(scene.cube_group, {ball});
  scene.expect_cube(0.f, 0.f, 1.f);
  int checked = 0;
  CHECK(wrong_depths(scene, [](float x, float y) { return disc_depth(x, y, 0.f, 0.f, 0.5f, 6.f, 4.f); }, &checked) ==
        0);

  // The geometry alone: the ball moves to the back face.
  const float back[3] = {0.f, 0.f, 1.f};
  set_array(g, "sphere.position", back, OSP_VEC3F, 1);
  ospCommit(g);
  scene.expect_cube(0.f, 0.f, -1.f);
  CHECK(last_build_summary(api.messages).find("(0 built, 2 reused)") != std::string::npos);
  CHECK(wrong_depths(scene, [](float x, float y) { return disc_depth(x, y, 0.f, 0.f, 0.5f, 4.f, 4.f); }, &checked) ==
        0);
  check_pick(scene.pick, scene.world, {0.f, 0.f, 5.f}, {0.f, 0.f, -1.f}, scene.cube_instance, scene.cube,
             {0.f, 0.f, -1.f});  // seen from behind, the back face is gone

  // The model: inverted.
  ospSetBool(ball, "invertNormals", true);
  ospCommit(ball);
  scene.expect_cube(0.f, 0.f, 1.f);
  scene.expect_miss(0.8f, 0.f);

  // The instance: the cube and its clipping move together.
  set_transform(scene.cube_instance, scale_then_move(1, 1, 1, 0, 0.7f, 0));
  ospCommit(scene.cube_instance);
  scene.expect_cube(0.f, 0.7f, 1.f);
  scene.expect_miss(0.f, 0.f);

  // The group: without clipping geometry the cube is whole again.
  set_clipping(scene.cube_group, {});
  scene.expect_cube(0.f, 0.f, -1.f);
  scene.expect_cube(0.8f, 0.f, -1.f);
  ospRelease(g);
  ospRelease(ball);
  CHECK(api.messages.errors.empty());
}

// ---- volumes ------------------------------------------------------------------------------

namespace {

/// A box1f range as OSPRay's `value` takes it.
void set_value_range(OSPTransferFunction tf, float lo, float hi) {
  const float range[2] = {lo, hi};
  ospSetParam(tf, "value", OSP_BOX1F, range);
}

/// A committed piecewiseLinear transfer function.
OSPTransferFunction new_transfer_function(const std::vector<float>& colors, const std::vector<float>& opacities,
                                          float lo, float hi) {
  OSPTransferFunction tf = ospNewTransferFunction("piecewiseLinear");
  set_array(tf, "color", colors.data(), OSP_VEC3F, colors.size() / 3);
  set_array(tf, "opacity", opacities.data(), OSP_FLOAT, opacities.size());
  set_value_range(tf, lo, hi);
  ospCommit(tf);
  return tf;
}

/// A volume through the C API: a structuredRegular volume, a transfer function, a
/// volumetric model in a group placed by an identity instance, a world; an orthographic
/// camera looking along +z through x, y in [0, 1]; scivis on a black, transparent
/// background. The volume's parameters are the caller's, before `commit`.
/// A shared 3D array of `voxels` (x fastest).
template <class T>
OSPData shared_voxels(const std::vector<T>& voxels, OSPDataType type, std::uint64_t nx, std::uint64_t ny,
                      std::uint64_t nz) {
  REQUIRE(voxels.size() == nx * ny * nz);
  return ospNewSharedData3D(voxels.data(), type, nx, ny, nz);
}

struct VolumeScene {
  OSPVolume volume = ospNewVolume("structuredRegular");
  OSPTransferFunction tf = nullptr;
  OSPVolumetricModel model = ospNewVolumetricModel(volume);
  OSPGroup group = ospNewGroup();
  OSPInstance instance = ospNewInstance(group);
  OSPWorld world = nullptr;
  OSPCamera camera = ospNewCamera("orthographic");
  OSPRenderer renderer = ospNewRenderer("scivis");
  const std::vector<float> unit_voxels = std::vector<float>(8, 1.f);

  VolumeScene() {
    ospSetVec3f(camera, "position", 0.5f, 0.5f, -5.f);
    ospSetVec3f(camera, "direction", 0.f, 0.f, 1.f);
    ospSetFloat(camera, "height", 1.f);
    ospCommit(camera);
    ospCommit(renderer);
  }
  VolumeScene(const VolumeScene&) = delete;
  VolumeScene& operator=(const VolumeScene&) = delete;
  ~VolumeScene() {
    for (OSPObject o : std::initializer_list<OSPObject>{volume, tf, model, group, instance, world, camera, renderer})
      ospRelease(o);
  }

  /// Commits the volume with `data`, and the model with `transfer_function` (taken over).
  void commit(OSPData data, OSPTransferFunction transfer_function, float density_scale = 1.f) {
    ospSetObject(volume, "data", data);
    ospCommit(volume);
    ospRelease(tf);
    tf = transfer_function;
    ospSetObject(model, "transferFunction", tf);
    ospSetFloat(model, "densityScale", density_scale);
    ospCommit(model);
    ospSetObjectAsData(group, "volume", OSP_VOLUMETRIC_MODEL, model);
    ospCommit(group);
    ospCommit(instance);
    if (!world) world = new_world({instance});
  }

  /// Commits the unit cube of constant value 1 (2³ shared voxels) with `transfer_function`.
  void commit_constant(OSPTransferFunction transfer_function, float density_scale = 1.f) {
    OSPData data = shared_voxels(unit_voxels, OSP_FLOAT, 2, 2, 2);
    commit(data, transfer_function, density_scale);
    ospRelease(data);
  }

  /// An RGBA32F frame (premultiplied by the volume's opacity), first row at the bottom.
  std::vector<float> render(int size = 16) const {
    OSPFrameBuffer fb = ospNewFrameBuffer(size, size, OSP_FB_RGBA32F, OSP_FB_COLOR);
    ospRenderFrameBlocking(fb, renderer, camera, world);
    const auto* pixels = static_cast<const float*>(ospMapFrameBuffer(fb, OSP_FB_COLOR));
    std::vector<float> out(pixels, pixels + 4 * size * size);
    ospUnmapFrameBuffer(pixels, fb);
    ospRelease(fb);
    return out;
  }
  /// The RGBA of the pixel at the centre of a size x size frame.
  std::array<float, 4> centre(int size = 16) const {
    const auto image = render(size);
    const std::size_t at = 4 * static_cast<std::size_t>(size / 2 * size + size / 2);
    return {image[at], image[at + 1], image[at + 2], image[at + 3]};
  }
};

}  // namespace

TEST_CASE("volume: a constant density renders the analytic opacity 1 - exp(-sigma L)", "[c_api][volume][render]") {
  ApiFixture api;
  VolumeScene scene;
  // 2x2x2 vertex-centred voxels of spacing 1: the unit cube, crossed along z (L = 1).
  // opacity 0.5 everywhere, densityScale 4: sigma = 2 per unit length.
  scene.commit_constant(new_transfer_function({1.f, 0.5f, 0.25f}, {0.5f}, 0.f, 2.f), 4.f);
  const float alpha = 1.f - std::exp(-2.f);
  for (auto isa : sciray::simd::all_isas) {
    if (!sciray::simd::cpu_supports(isa)) continue;
    const std::string name(sciray::simd::isa_name(isa));
    ospDeviceSetParam(api.device, "isa", OSP_STRING, name.c_str());
    ospDeviceCommit(api.device);
    for (float rate : {0.25f, 1.f, 3.7f}) {
      INFO("ISA " << name << ", volumeSamplingRate " << rate);
      ospSetFloat(scene.renderer, "volumeSamplingRate", rate);
      ospCommit(scene.renderer);
      const auto c = scene.centre();
      CHECK(c[3] == Approx(alpha).epsilon(1e-5));
      CHECK(c[0] == Approx(alpha).epsilon(1e-5));  // the colour (1, 0.5, 0.25), premultiplied
      CHECK(c[1] == Approx(0.5f * alpha).epsilon(1e-5));
      CHECK(c[2] == Approx(0.25f * alpha).epsilon(1e-5));
    }
  }
  ospDeviceSetParam(api.device, "isa", OSP_STRING, "auto");
  ospDeviceCommit(api.device);
  // The ao and pathtracer renderers integrate volumes on their rays too.
  for (const char* type : {"ao", "pathtracer"}) {
    OSPRenderer other = ospNewRenderer(type);
    ospSetFloat(other, "volumeSamplingRate", 2.f);
    ospCommit(other);
    std::swap(other, scene.renderer);
    CHECK(scene.centre()[3] == Approx(alpha).epsilon(1e-5));
    std::swap(other, scene.renderer);
    ospRelease(other);
  }
  // densityScale scales sigma: 1 - exp(-1) at densityScale 2.
  ospSetFloat(scene.model, "densityScale", 2.f);
  ospCommit(scene.model);
  CHECK(scene.centre()[3] == Approx(1.f - std::exp(-1.f)).epsilon(1e-5));
  CHECK(api.messages.errors.empty());
}

TEST_CASE("volume: the pathtracer scatters light once as the closed form says, for each anisotropy",
          "[c_api][volume][render]") {
  // A slab of σ = 2 and albedo 1, 0.5 thick and 20 wide, seen along +z; a distant light of
  // irradiance E enters through the same face at μ = 0.8. With maxPathLength 1 light
  // scatters once: E p(cos θ) (1 - exp(-σ h (1 + 1/μ))) / (1 + 1/μ), with p the
  // Henyey–Greenstein phase function of the model's `anisotropy` and cos θ = -0.8.
  ApiFixture api;
  VolumeScene scene;
  ospSetVec3f(scene.volume, "gridOrigin", -10.f, -10.f, 0.f);
  ospSetVec3f(scene.volume, "gridSpacing", 20.f, 20.f, 0.5f);
  scene.commit_constant(new_transfer_function({1.f, 1.f, 1.f}, {2.f}, 0.f, 2.f));
  OSPLight sun = ospNewLight("distant");
  ospSetVec3f(sun, "direction", 0.6f, 0.f, 0.8f);
  ospSetFloat(sun, "intensity", 3.f);
  ospCommit(sun);
  ospSetObjectAsData(scene.world, "light", OSP_LIGHT, sun);
  ospCommit(scene.world);
  OSPRenderer pathtracer = ospNewRenderer("pathtracer");
  ospSetInt(pathtracer, "maxPathLength", 1);
  ospCommit(pathtracer);
  for (float g : {0.6f, -0.6f}) {
    INFO("anisotropy " << g);
    ospSetFloat(scene.model, "anisotropy", g);
    ospCommit(scene.model);
    const int size = 32, frames = 64;
    OSPFrameBuffer fb = ospNewFrameBuffer(size, size, OSP_FB_RGBA32F, OSP_FB_COLOR | OSP_FB_ACCUM);
    for (int f = 0; f < frames; ++f) ospRenderFrameBlocking(fb, pathtracer, scene.camera, scene.world);
    const auto* rgba = static_cast<const float*>(ospMapFrameBuffer(fb, OSP_FB_COLOR));
    double mean = 0;
    for (int p = 0; p < size * size; ++p) mean += rgba[4 * p + 1] / (size * size);
    ospUnmapFrameBuffer(rgba, fb);
    ospRelease(fb);
    const double cos_theta = -0.8, mu = 0.8, sigma_h = 2 * 0.5;
    const double phase = (1 - g * g) / (4 * std::numbers::pi * std::pow(1 + g * g - 2 * g * cos_theta, 1.5));
    const double expected = 3 * phase * (1 - std::exp(-sigma_h * (1 + 1 / mu))) / (1 + 1 / mu);
    CHECK(mean == Approx(expected).epsilon(0.02));
  }
  ospRelease(pathtracer);
  ospRelease(sun);
  CHECK(api.messages.errors.empty());
}

TEST_CASE("volume: shared compact data is read in place, strided data is copied", "[c_api][volume][data]") {
  ApiFixture api;
  VolumeScene scene;
  // Opacity = value over [0, 1], densityScale 2: a constant value v gives 1 - exp(-2v).
  std::vector<float> voxels(8, 0.5f);
  OSPData data = shared_voxels(voxels, OSP_FLOAT, 2, 2, 2);
  scene.commit(data, new_transfer_function({1.f, 1.f, 1.f}, {0.f, 1.f}, 0.f, 1.f), 2.f);
  ospRelease(data);
  CHECK(scene.centre()[3] == Approx(1.f - std::exp(-1.f)).epsilon(1e-5));

  // The engine reads the application's array: a change shows in the next frame even
  // before a recommit (which OSPRay asks for, and which refreshes the empty-space
  // skipping's value ranges).
  std::fill(voxels.begin(), voxels.end(), 1.f);
  CHECK(scene.centre()[3] == Approx(1.f - std::exp(-2.f)).epsilon(1e-5));
  std::fill(voxels.begin(), voxels.end(), 0.25f);
  ospCommit(scene.volume);
  CHECK(scene.centre()[3] == Approx(1.f - std::exp(-0.5f)).epsilon(1e-5));
  std::fill(voxels.begin(), voxels.end(), 0.f);  // all empty: skipped, after the recommit
  ospCommit(scene.volume);
  CHECK(scene.centre()[3] == 0.f);

  // The same voxels interleaved with padding (x stride 8 bytes): copied at commit, so
  // the application's later changes need the recommit.
  std::vector<float> padded(16, -7.f);
  for (int i = 0; i < 8; ++i) padded[2 * i] = 0.5f;
  OSPData strided = ospNewSharedData(padded.data(), OSP_FLOAT, 2, 8, 2, 0, 2, 0);
  ospSetObject(scene.volume, "data", strided);
  ospRelease(strided);
  ospCommit(scene.volume);
  CHECK(scene.centre()[3] == Approx(1.f - std::exp(-1.f)).epsilon(1e-5));
  for (int i = 0; i < 8; ++i) padded[2 * i] = 1.f;
  CHECK(scene.centre()[3] == Approx(1.f - std::exp(-1.f)).epsilon(1e-5));  // the copy
  ospCommit(scene.volume);
  CHECK(scene.centre()[3] == Approx(1.f - std::exp(-2.f)).epsilon(1e-5));

  // An owned array (ospNewData + ospCopyData) is compact too.
  const std::vector<float> quarter(8, 0.25f);
  OSPData source = shared_voxels(quarter, OSP_FLOAT, 2, 2, 2);
  OSPData owned = ospNewData(OSP_FLOAT, 2, 2, 2);
  ospCopyData(source, owned, 0, 0, 0);
  ospSetObject(scene.volume, "data", owned);
  ospRelease(source);
  ospRelease(owned);
  ospCommit(scene.volume);
  CHECK(scene.centre()[3] == Approx(1.f - std::exp(-0.5f)).epsilon(1e-5));

  // The shared array stays alive while the volume (and a frame's world) reads it: its
  // deleter runs once the volume lets go.
  static int deleted = 0;
  deleted = 0;
  OSPData with_deleter = ospNewSharedData(voxels.data(), OSP_FLOAT, 2, 0, 2, 0, 2, 0,
                                          [](const void*, const void*) { ++deleted; }, nullptr);
  ospSetObject(scene.volume, "data", with_deleter);
  ospRelease(with_deleter);
  ospCommit(scene.volume);
  CHECK(scene.centre()[3] == 0.f);
  ospRemoveParam(scene.volume, "data");
  ospSetObject(scene.volume, "data", data = shared_voxels(padded, OSP_FLOAT, 4, 2, 2));
  ospRelease(data);
  CHECK(deleted == 0);
  ospCommit(scene.volume);
  scene.render();  // the world lets go of the old engine volume
  CHECK(deleted == 1);
  CHECK(api.messages.errors.empty());
}

TEST_CASE("volume: every voxel type renders", "[c_api][volume][render]") {
  ApiFixture api;
  // A constant value of 100 with opacity = value / 100 over [0, 200]: sigma = 1.
  const float expected = 1.f - std::exp(-1.f);
  const auto check_type = [&](OSPDataType type, const auto& voxels) {
    INFO("voxel type " << type);
    VolumeScene scene;
    OSPData data = shared_voxels(voxels, type, 2, 2, 2);
    scene.commit(data, new_transfer_function({1.f, 1.f, 1.f}, {0.f, 2.f}, 0.f, 200.f));
    ospRelease(data);
    CHECK(scene.centre()[3] == Approx(expected).epsilon(1e-5));
    // And bricked.
    ospSetString(scene.volume, "layout", "bricked");
    ospCommit(scene.volume);
    CHECK(scene.centre()[3] == Approx(expected).epsilon(1e-5));
  };
  check_type(OSP_UCHAR, std::vector<std::uint8_t>(8, 100));
  check_type(OSP_SHORT, std::vector<std::int16_t>(8, 100));
  check_type(OSP_USHORT, std::vector<std::uint16_t>(8, 100));
  check_type(OSP_FLOAT, std::vector<float>(8, 100.f));
  check_type(OSP_DOUBLE, std::vector<double>(8, 100.0));
  CHECK(api.messages.errors.empty());
}

TEST_CASE("volume: the bricked layout renders the linear layout's image; filters", "[c_api][volume][render]") {
  ApiFixture api;
  // 37x20x11 uchar voxels (across several bricks) of a ball of growing value.
  const std::uint64_t nx = 37, ny = 20, nz = 11;
  std::vector<std::uint8_t> voxels;
  for (std::uint64_t z = 0; z < nz; ++z)
    for (std::uint64_t y = 0; y < ny; ++y)
      for (std::uint64_t x = 0; x < nx; ++x) {
        const double dx = x / 36.0 - 0.5, dy = y / 19.0 - 0.5, dz = z / 10.0 - 0.5;
        voxels.push_back(static_cast<std::uint8_t>(std::max(0.0, 255 * (1 - 4 * (dx * dx + dy * dy + dz * dz)))));
      }
  VolumeScene scene;
  OSPData data = shared_voxels(voxels, OSP_UCHAR, nx, ny, nz);
  ospSetVec3f(scene.volume, "gridSpacing", 1.f / 36, 1.f / 19, 1.f / 10);
  scene.commit(data, new_transfer_function({0.f, 0.f, 1.f, 0.f, 1.f, 0.f, 1.f, 0.f, 0.f}, {0.f, 0.f, 3.f, 6.f}, 0.f, 255.f));
  ospRelease(data);
  const auto linear = scene.render(32);
  float total = 0.f;
  for (std::size_t i = 3; i < linear.size(); i += 4) total += linear[i];
  CHECK(total > 50.f);  // the ball shows
  ospSetString(scene.volume, "layout", "bricked");
  ospCommit(scene.volume);
  CHECK(max_abs_difference(scene.render(32), linear) < 1e-6f);
  ospSetString(scene.volume, "layout", "linear");
  ospSetInt(scene.volume, "filter", OSP_VOLUME_FILTER_NEAREST);
  ospCommit(scene.volume);
  const auto nearest = scene.render(32);
  CHECK(max_abs_difference(nearest, linear) > 1e-3f);
  ospSetInt(scene.volume, "filter", OSP_VOLUME_FILTER_LINEAR);
  ospCommit(scene.volume);
  CHECK(max_abs_difference(scene.render(32), linear) < 1e-6f);
  CHECK(api.messages.errors.empty());
}

TEST_CASE("volume: bounds of vertex- and cell-centred grids, of models, groups, instances and worlds",
          "[c_api][volume][bounds]") {
  ApiFixture api;
  VolumeScene scene;
  const std::vector<float> voxels(4 * 4 * 4, 1.f);
  OSPData data = shared_voxels(voxels, OSP_FLOAT, 4, 4, 4);
  ospSetVec3f(scene.volume, "gridOrigin", 1.f, 2.f, 3.f);
  ospSetVec3f(scene.volume, "gridSpacing", 0.5f, 1.f, 2.f);
  scene.commit(data, new_transfer_function({1.f, 1.f, 1.f}, {1.f}, 0.f, 1.f));
  ospRelease(data);
  // Vertex-centred: 3 cells a side.
  for (OSPObject o : std::initializer_list<OSPObject>{scene.volume, scene.model, scene.group, scene.instance, scene.world})
    check_bounds(ospGetBounds(o), {1.f, 2.f, 3.f}, {2.5f, 5.f, 9.f});
  // Cell-centred: 4 cells a side.
  ospSetBool(scene.volume, "cellCentered", 1);
  ospCommit(scene.volume);
  for (OSPObject o : std::initializer_list<OSPObject>{scene.volume, scene.model, scene.group, scene.instance, scene.world})
    check_bounds(ospGetBounds(o), {1.f, 2.f, 3.f}, {3.f, 6.f, 11.f});
  // With geometry in the group: both.
  const float box[6] = {-1.f, 0.f, 0.f, 0.f, 1.f, 1.f};
  OSPGeometry g = ospNewGeometry("box");
  set_array(g, "box", box, OSP_BOX3F, 1);
  ospCommit(g);
  OSPGeometricModel m = ospNewGeometricModel(g);
  ospCommit(m);
  ospSetObjectAsData(scene.group, "geometry", OSP_GEOMETRIC_MODEL, m);
  ospCommit(scene.group);
  check_bounds(ospGetBounds(scene.world), {-1.f, 0.f, 0.f}, {3.f, 6.f, 11.f});
  ospRelease(g);
  ospRelease(m);
  CHECK(api.messages.errors.empty());
}

TEST_CASE("volume: surfaces and volumes in one group; a surface inside the volume ends it",
          "[c_api][volume][render]") {
  ApiFixture api;
  VolumeScene scene;
  scene.commit_constant(new_transfer_function({0.f, 0.f, 1.f}, {2.f}, 0.f, 2.f));
  // A box filling x, y and z in [0.5, 2]: the volume in front of it is half as deep.
  const float box[6] = {-1.f, -1.f, 0.5f, 2.f, 2.f, 2.f};
  OSPGeometry g = ospNewGeometry("box");
  set_array(g, "box", box, OSP_BOX3F, 1);
  ospCommit(g);
  OSPGeometricModel m = ospNewGeometricModel(g);
  ospCommit(m);
  ospSetObjectAsData(scene.group, "geometry", OSP_GEOMETRIC_MODEL, m);
  ospCommit(scene.group);
  ospSetInt(scene.renderer, "volumeSamplingRate", 8);  // an int, as OSPRay promotes
  ospCommit(scene.renderer);
  const auto c = scene.centre();
  const float alpha = 1.f - std::exp(-1.f);
  CHECK(c[3] == Approx(1.f));       // the box is opaque
  CHECK(c[2] > alpha - 1e-4f);      // blue: the volume over the grey box
  CHECK(c[0] < (1 - alpha) + 1e-4f);  // red: the box only, behind the volume
  CHECK(c[0] > 0.f);
  ospRelease(g);
  ospRelease(m);
  CHECK(api.messages.errors.empty());
}

TEST_CASE("volume: clipping geometry cuts volumes", "[c_api][volume][clipping]") {
  ApiFixture api;
  VolumeScene scene;
  scene.commit_constant(new_transfer_function({1.f, 1.f, 1.f}, {2.f}, 0.f, 1.f));
  // The plane z = 0.5 clips z < 0.5: half the depth of sigma = 2.
  const float plane[4] = {0.f, 0.f, 1.f, -0.5f};
  OSPGeometry g = ospNewGeometry("plane");
  set_array(g, "plane.coefficients", plane, OSP_VEC4F, 1);
  ospCommit(g);
  OSPGeometricModel m = ospNewGeometricModel(g);
  ospCommit(m);
  ospSetObjectAsData(scene.group, "clippingGeometry", OSP_GEOMETRIC_MODEL, m);
  ospCommit(scene.group);
  ospSetFloat(scene.renderer, "volumeSamplingRate", 10.f);  // the plane falls on a step boundary
  ospCommit(scene.renderer);
  CHECK(scene.centre()[3] == Approx(1.f - std::exp(-1.f)).epsilon(1e-4));
  ospRelease(g);
  ospRelease(m);
  CHECK(api.messages.errors.empty());
}

TEST_CASE("volume: a recommitted transfer function keeps the macrocells; a recommitted volume rebuilds them",
          "[c_api][volume][commit]") {
  ApiFixture api;
  log_debug(api.device);
  VolumeScene scene;
  std::vector<float> voxels(8, 0.5f);
  OSPData data = shared_voxels(voxels, OSP_FLOAT, 2, 2, 2);
  scene.commit(data, new_transfer_function({1.f, 1.f, 1.f}, {0.f, 1.f}, 0.f, 1.f), 2.f);
  ospRelease(data);
  CHECK(scene.centre()[3] == Approx(1.f - std::exp(-1.f)).epsilon(1e-5));
  CHECK_THAT(last_build_summary(api.messages),
             Catch::Contains("1 volumes (0 rebuilt for a recommitted volume, 0 given a recommitted transfer function"));

  // The transfer function alone: opacity 2 x value; the next frame shows it, and the
  // world gives the kept model the new transfer function.
  const float opacities[2] = {0.f, 2.f};
  set_array(scene.tf, "opacity", opacities, OSP_FLOAT, 2);
  ospCommit(scene.tf);
  CHECK(scene.centre()[3] == Approx(1.f - std::exp(-2.f)).epsilon(1e-5));
  CHECK_THAT(last_build_summary(api.messages),
             Catch::Contains("1 volumes (0 rebuilt for a recommitted volume, 1 given a recommitted transfer function "
                             "without rebuilding their macrocells)"));
  // The value range.
  set_value_range(scene.tf, 0.f, 2.f);
  ospCommit(scene.tf);
  CHECK(scene.centre()[3] == Approx(1.f - std::exp(-1.f)).epsilon(1e-5));
  // A transfer function that becomes zero where the volume is: empty-space skipping
  // follows the new opacities.
  const float zero_low[3] = {0.f, 0.f, 1.f};
  set_array(scene.tf, "opacity", zero_low, OSP_FLOAT, 3);
  ospCommit(scene.tf);
  CHECK(scene.centre()[3] == 0.f);

  // The volume: rebuilt. Value 2 is opacity 1 on [0, 2] now.
  std::fill(voxels.begin(), voxels.end(), 2.f);
  ospCommit(scene.volume);
  CHECK(scene.centre()[3] == Approx(1.f - std::exp(-2.f)).epsilon(1e-5));
  CHECK_THAT(last_build_summary(api.messages), Catch::Contains("1 volumes (1 rebuilt for a recommitted volume, 0 given"));

  // Another transfer function object on the model.
  OSPTransferFunction replacement = new_transfer_function({1.f, 1.f, 1.f}, {0.5f}, 0.f, 1.f);
  ospSetObject(scene.model, "transferFunction", replacement);
  ospRelease(scene.tf);  // the model still holds it until its commit
  scene.tf = replacement;
  ospCommit(scene.model);
  CHECK(scene.centre()[3] == Approx(1.f - std::exp(-2.f * 0.5f)).epsilon(1e-5));  // densityScale 2
  CHECK(api.messages.errors.empty());
}

TEST_CASE("volume: volumes in transformed instances are refused by name", "[c_api][volume][errors]") {
  ApiFixture api;
  VolumeScene scene;
  scene.commit_constant(new_transfer_function({1.f, 1.f, 1.f}, {1.f}, 0.f, 1.f));
  set_transform(scene.instance, scale_then_move(1, 1, 1, 0.5f, 0, 0));
  ospCommit(scene.instance);
  CHECK(api.messages.any_error_containing(
      "ospCommit: instance: parameter 'transform': its group has volumes, and volumes in transformed instances are "
      "not supported yet"));
  api.messages.errors.clear();
  CHECK(scene.centre()[3] == Approx(1.f - std::exp(-1.f)).epsilon(1e-5));  // the instance is as it was

  // A transformed instance of a group that gains volumes later: refused at the frame.
  OSPGroup other = new_group({});
  OSPInstance moved = new_instance(other, scale_then_move(2, 2, 2, 0, 0, 0));
  OSPWorld world = new_world({scene.instance, moved});
  ospSetObjectAsData(other, "volume", OSP_VOLUMETRIC_MODEL, scene.model);
  ospCommit(other);
  OSPFrameBuffer fb = ospNewFrameBuffer(4, 4);
  CHECK(ospRenderFrame(fb, scene.renderer, scene.camera, world) == nullptr);
  CHECK(api.messages.any_error_containing(
      "ospRenderFrame: world: instance 1 places a group with volumes by a transform other than the identity: volumes "
      "in transformed instances are not supported yet"));
  for (OSPObject o : std::initializer_list<OSPObject>{other, moved, world, fb}) ospRelease(o);
}

TEST_CASE("volume: bad input is named through the error callback", "[c_api][volume][errors]") {
  ApiFixture api;
  std::vector<float> voxels(16, 1.f);
  OSPVolume volume = ospNewVolume("structuredRegular");
  ospCommit(volume);
  api.expect_error("ospCommit: structuredRegular volume: required parameter 'data' (3D array of uchar, short, ushort, "
               "float or double) is missing");
  const auto set_data = [&](OSPDataType type, std::uint64_t nx, std::uint64_t ny, std::uint64_t nz) {
    OSPData data = ospNewSharedData(voxels.data(), type, nx, 0, ny, 0, nz, 0, nullptr, nullptr);
    ospSetObject(volume, "data", data);
    ospRelease(data);
    ospCommit(volume);
  };
  set_data(OSP_FLOAT, 8, 1, 1);
  api.expect_error("structuredRegular volume: parameter 'data' must be a 3D array with at least 2 voxels in every "
               "direction (its dimensions are the grid's), got a 1D array of 8");
  set_data(OSP_FLOAT, 4, 2, 1);
  api.expect_error("got a 2D array of 4x2");
  set_data(OSP_FLOAT, 4, 1, 4);
  api.expect_error("got a 3D array of 4x1x4");
  set_data(OSP_VEC3F, 2, 2, 1);
  api.expect_error("structuredRegular volume: parameter 'data' must be an array of uchar, short, ushort, float or double, "
               "got an array of vec3f");
  set_data(OSP_HALF, 2, 2, 2);
  api.expect_error("got an array of half (half voxels are not supported yet)");
  ospSetFloat(volume, "data", 1.f);
  ospCommit(volume);
  api.expect_error("structuredRegular volume: parameter 'data' must be an OSPData array, got float");
  voxels[5] = NAN;
  set_data(OSP_FLOAT, 2, 2, 2);
  api.expect_error("structuredRegular volume: parameter 'data': voxel (1, 0, 1) is not finite");
  voxels[5] = INFINITY;
  set_data(OSP_FLOAT, 2, 2, 2);
  api.expect_error("voxel (1, 0, 1) is not finite");
  voxels[5] = 1.f;
  set_data(OSP_FLOAT, 2, 2, 2);
  CHECK(api.messages.errors.empty());

  ospSetVec3f(volume, "gridSpacing", 1.f, 0.f, 1.f);
  ospCommit(volume);
  api.expect_error("structuredRegular volume: parameter 'gridSpacing' must be positive on every axis, got (1, 0, 1)");
  ospSetVec3f(volume, "gridSpacing", 1.f, 1.f, -2.f);
  ospCommit(volume);
  api.expect_error("'gridSpacing' must be positive on every axis, got (1, 1, -2)");
  ospSetVec3f(volume, "gridSpacing", 1.f, 1.f, NAN);
  ospCommit(volume);
  api.expect_error("parameter 'gridSpacing' is not finite");
  ospSetVec3f(volume, "gridSpacing", 1.f, 1.f, 1.f);
  ospSetVec3f(volume, "gridOrigin", INFINITY, 1.f, 1.f);
  ospCommit(volume);
  api.expect_error("parameter 'gridOrigin' is not finite");
  ospRemoveParam(volume, "gridOrigin");
  ospSetInt(volume, "filter", OSP_VOLUME_FILTER_CUBIC);  // the tricubic B-spline
  ospCommit(volume);
  CHECK(api.messages.errors.empty());
  ospSetInt(volume, "filter", 7);
  ospCommit(volume);
  api.expect_error("structuredRegular volume: parameter 'filter' has unknown value 7 (OSP_VOLUME_FILTER_NEAREST = 0, "
               "OSP_VOLUME_FILTER_LINEAR = 100, OSP_VOLUME_FILTER_CUBIC = 200)");
  const std::uint8_t nearest = OSP_VOLUME_FILTER_NEAREST;  // set as a uchar
  ospSetParam(volume, "filter", OSP_UCHAR, &nearest);
  ospSetString(volume, "layout", "morton");
  ospCommit(volume);
  api.expect_error("structuredRegular volume: parameter 'layout' has unknown value 'morton' (linear, bricked)");
  ospSetInt(volume, "layout", 1);
  ospCommit(volume);
  api.expect_error("structuredRegular volume: parameter 'layout' must be a string, got int");
  ospSetString(volume, "layout", "bricked");
  ospSetFloat(volume, "gradientFilter", 1.f);
  ospCommit(volume);
  CHECK(api.messages.errors.empty());
  bool unused = false;
  for (const auto& s : api.messages.status) unused |= s.find("'gradientFilter' is not used") != std::string::npos;
  CHECK(unused);

  // Transfer functions.
  OSPTransferFunction tf = ospNewTransferFunction("piecewiseLinear");
  ospCommit(tf);
  api.expect_error("ospCommit: piecewiseLinear transfer function: required parameter 'color' (array of vec3f) is missing");
  const float colors[6] = {1, 0, 0, 0, 0, 1};
  const float opacities[2] = {0, 1};
  CHECK(ospNewData1D(OSP_VEC3F, 0) == nullptr);  // an empty array cannot be made...
  api.expect_error("data: every dimension must hold at least one item");
  ospSetObject(tf, "color", nullptr);  // ...and NULL is no array
  ospCommit(tf);
  api.expect_error("required parameter 'color' (array of vec3f) is missing");
  set_array(tf, "color", colors, OSP_VEC4F, 1);
  ospCommit(tf);
  api.expect_error("piecewiseLinear transfer function: parameter 'color' must be an array of vec3f, got an array of vec4f");
  set_array(tf, "color", colors, OSP_VEC3F, 2);
  ospCommit(tf);
  api.expect_error("piecewiseLinear transfer function: required parameter 'opacity' (array of float) is missing");
  ospSetObject(tf, "opacity", nullptr);
  ospCommit(tf);
  api.expect_error("required parameter 'opacity' (array of float) is missing");
  const float negative[2] = {0, -1};
  set_array(tf, "opacity", negative, OSP_FLOAT, 2);
  ospCommit(tf);
  api.expect_error("transferFunction: 'opacity' 1 must be finite and not negative");
  set_array(tf, "opacity", opacities, OSP_FLOAT, 2);
  set_value_range(tf, 1.f, 1.f);
  ospCommit(tf);
  api.expect_error("transferFunction: 'value' must be a finite range with lo < hi, got [1.000000, 1.000000]");
  set_value_range(tf, 2.f, 1.f);
  ospCommit(tf);
  api.expect_error("'value' must be a finite range with lo < hi");
  ospSetFloat(tf, "value", 1.f);
  ospCommit(tf);
  api.expect_error("piecewiseLinear transfer function: parameter 'value' must be a box1f (or vec2f) range, got float");
  ospSetVec2f(tf, "value", 0.f, 2.f);  // a vec2f is taken as the range
  ospCommit(tf);
  CHECK(api.messages.errors.empty());

  // Volumetric models.
  OSPVolumetricModel model = ospNewVolumetricModel(nullptr);
  ospCommit(model);
  api.expect_error("ospCommit: volumetric model: required parameter 'volume' (OSPVolume) is missing");
  ospSetObject(model, "volume", volume);
  ospCommit(model);
  api.expect_error("volumetric model: required parameter 'transferFunction' (OSPTransferFunction) is missing");
  ospSetObject(model, "transferFunction", volume);
  ospCommit(model);
  api.expect_error("volumetric model: parameter 'transferFunction' must be OSPTransferFunction, got OSPVolume");
  OSPTransferFunction uncommitted = ospNewTransferFunction("piecewiseLinear");
  ospSetObject(model, "transferFunction", uncommitted);
  ospCommit(model);
  api.expect_error("volumetric model: its transfer function has not been committed");
  ospSetObject(model, "transferFunction", tf);
  ospSetFloat(model, "densityScale", -1.f);
  ospCommit(model);
  api.expect_error("volumetric model: parameter 'densityScale' must be finite and not negative, got -1");
  ospSetFloat(model, "densityScale", NAN);
  ospCommit(model);
  api.expect_error("parameter 'densityScale' must be finite and not negative");
  ospSetFloat(model, "densityScale", 0.5f);
  ospSetFloat(model, "anisotropy", 1.5f);
  ospCommit(model);
  api.expect_error("volumetric model: parameter 'anisotropy' must be in [-1, 1], got 1.500000");
  ospSetFloat(model, "anisotropy", -0.3f);
  ospSetFloat(model, "gradientShadingScale", 1.5f);
  ospCommit(model);
  api.expect_error("volumetric model: parameter 'gradientShadingScale' must be in [0, 1], got 1.500000");
  ospSetFloat(model, "gradientShadingScale", NAN);
  ospCommit(model);
  api.expect_error("volumetric model: parameter 'gradientShadingScale' must be in [0, 1]");
  ospSetFloat(model, "gradientShadingScale", 1.f);
  ospCommit(model);
  CHECK(api.messages.errors.empty());
  unused = false;
  for (const auto& s : api.messages.status) unused |= s.find("'gradientShadingScale' is not used") != std::string::npos;
  CHECK(!unused);
  OSPVolume uncommitted_volume = ospNewVolume("structuredRegular");
  OSPVolumetricModel other = ospNewVolumetricModel(uncommitted_volume);
  ospSetObject(other, "transferFunction", tf);
  ospCommit(other);
  api.expect_error("volumetric model: its volume has not been committed");
  CHECK(ospNewVolumetricModel(reinterpret_cast<OSPVolume>(tf)) == nullptr);
  api.expect_error("ospNewVolumetricModel: volume must be OSPVolume but is OSPTransferFunction");

  // Groups.
  OSPGroup group = ospNewGroup();
  ospSetObjectAsData(group, "volume", OSP_VOLUMETRIC_MODEL, other);
  ospCommit(group);
  api.expect_error("ospCommit: group: parameter 'volume' element 0 has not been committed");
  ospSetObjectAsData(group, "volume", OSP_VOLUME, volume);
  ospCommit(group);
  api.expect_error("group: parameter 'volume' must be an array of OSPVolumetricModel, got an array of OSPVolume");
  ospSetObjectAsData(group, "volume", OSP_VOLUMETRIC_MODEL, model);
  ospCommit(group);
  CHECK(api.messages.errors.empty());

  // Renderers.
  OSPRenderer renderer = ospNewRenderer("scivis");
  ospSetFloat(renderer, "volumeSamplingRate", 0.f);
  ospCommit(renderer);
  api.expect_error("scivis renderer: parameter 'volumeSamplingRate' must be positive and finite, got 0");
  ospSetString(renderer, "volumeSamplingRate", "fast");
  ospCommit(renderer);
  api.expect_error("scivis renderer: parameter 'volumeSamplingRate' must be a float, got string");

  CHECK(ospNewVolume(nullptr) == nullptr);
  api.expect_error("ospNewVolume: the type name is NULL");
  ospGetBounds(uncommitted_volume);
  api.expect_error("ospGetBounds: structuredRegular volume has not been committed");
  for (OSPObject o : std::initializer_list<OSPObject>{volume, tf, uncommitted, model, uncommitted_volume, other, group,
                                                      renderer})
    ospRelease(o);
  CHECK(api.messages.errors.empty());
}

// ---- isosurfaces and slices ----------------------------------------------------------------

namespace {

/// f = x + 2y + 3z in world units: n³ voxels of `spacing` from the origin.
std::vector<float> linear_voxels(int n, float spacing) {
  std::vector<float> voxels;
  for (int z = 0; z < n; ++z)
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) voxels.push_back(spacing * static_cast<float>(x + 2 * y + 3 * z));
  return voxels;
}

/// Sets the volume's `data` to a copy of `voxels` (n³, x fastest).
void set_voxels(OSPVolume volume, const std::vector<float>& voxels, int n) {
  OSPData shared = shared_voxels(voxels, OSP_FLOAT, n, n, n);
  OSPData owned = ospNewData(OSP_FLOAT, n, n, n);
  ospCopyData(shared, owned, 0, 0, 0);
  ospSetObject(volume, "data", owned);
  ospRelease(shared);
  ospRelease(owned);
}

/// A committed structuredRegular volume holding a copy of `voxels` (n³ of `spacing`).
OSPVolume new_volume(const std::vector<float>& voxels, int n, float spacing) {
  OSPVolume volume = ospNewVolume("structuredRegular");
  set_voxels(volume, voxels, n);
  ospSetVec3f(volume, "gridSpacing", spacing, spacing, spacing);
  ospCommit(volume);
  return volume;
}

/// A committed isosurface of `volume` at one isovalue.
OSPGeometry new_isosurface(OSPVolume volume, float isovalue) {
  OSPGeometry g = ospNewGeometry("isosurface");
  ospSetObject(g, "volume", volume);
  ospSetFloat(g, "isovalue", isovalue);
  ospCommit(g);
  return g;
}

/// The pick from (x, y, −5) down +z must hit the scene's model at (x, y, z) on primitive
/// `prim`.
void check_iso_pick(const GeometryScene& scene, Picker& pick, float x, float y, float z, std::uint32_t prim) {
  INFO("pick at x = " << x << ", y = " << y);
  const OSPPickResult hit = pick(scene.world, {x, y, -5.f});
  check_position(hit, x, y, z);
  CHECK(hit.primID == prim);
  CHECK(hit.instance == scene.instance);
  CHECK(hit.model == scene.model);
  release_pick(hit);
}

}  // namespace

TEST_CASE("isosurface: picks land on the analytic surface; bounds; isovalue arrays; recommits take effect",
          "[c_api][isosurface]") {
  ApiFixture api;
  // f = x + 2y + 3z on [0, 1.9]³: trilinear interpolation reproduces it, so the surface
  // f = c is the plane x + 2y + 3z = c, met from (x, y, −5) down +z at z = (c − x − 2y)/3.
  const auto voxels = linear_voxels(20, 0.1f);
  OSPVolume volume = new_volume(voxels, 20, 0.1f);
  GeometryScene scene(new_isosurface(volume, 3.f), true);
  check_bounds(ospGetBounds(scene.geometry), {0.f, 0.f, 0.f}, {1.9f, 1.9f, 1.9f});
  check_bounds(ospGetBounds(scene.world), {0.f, 0.f, 0.f}, {1.9f, 1.9f, 1.9f});
  Picker pick;
  for (const auto& [x, y] : {std::pair{0.3f, 0.4f}, std::pair{1.2f, 0.1f}, std::pair{0.05f, 1.3f}})
    check_iso_pick(scene, pick, x, y, (3.f - x - 2 * y) / 3.f, 0);
  OSPPickResult hit = pick(scene.world, {1.8f, 1.8f, -5.f});  // f > 3 all along: no crossing
  CHECK(hit.hasHit == 0);
  release_pick(hit);

  // The ortho view (x, y in [−2, 2]) shows the surface in the default grey (kd 0.8 under
  // a white ambient light of intensity 1) where it lies inside the volume.
  for (auto isa : sciray::simd::all_isas) {
    if (!sciray::simd::cpu_supports(isa)) continue;
    const std::string name(sciray::simd::isa_name(isa));
    INFO("ISA " << name);
    ospDeviceSetParam(api.device, "isa", OSP_STRING, name.c_str());
    ospDeviceCommit(api.device);
    const int n = 16;
    const auto image = scene.render(n, n);
    int shown = 0, wrong = 0;
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const float x = 2.f - 4.f * (i + 0.5f) / n, y = 4.f * (j + 0.5f) / n - 2.f;  // right is −x
        const bool on = x > 0.f && x < 1.9f && y > 0.f && y < 1.9f && x + 2 * y < 3.f;
        const float* p = &image[4 * static_cast<std::size_t>(j * n + i)];
        shown += on;
        wrong += on ? !(p[0] == Approx(0.8f) && p[1] == Approx(0.8f) && p[2] == Approx(0.8f) && p[3] == 1.f)
                    : p[3] != 0.f;
      }
    CHECK(shown > 20);
    CHECK(wrong == 0);
  }
  ospDeviceSetParam(api.device, "isa", OSP_STRING, "auto");
  ospDeviceCommit(api.device);

  // Several isovalues: the nearest surface wins, and primID is the isovalue's index.
  const float isovalues[2] = {3.f, 1.f};
  set_array(scene.geometry, "isovalue", isovalues, OSP_FLOAT, 2);
  ospCommit(scene.geometry);
  check_iso_pick(scene, pick, 0.1f, 0.1f, (1.f - 0.3f) / 3.f, 1);
  check_iso_pick(scene, pick, 1.f, 0.5f, (3.f - 2.f) / 3.f, 0);  // f = 1 lies below z = 0 here

  // Instanced: stretched 2 times along z and moved up by 1; primID still the isovalue's.
  set_transform(scene.instance, scale_then_move(1, 1, 2, 0, 0, 1));
  ospCommit(scene.instance);
  check_iso_pick(scene, pick, 0.1f, 0.1f, 2.f * (1.f - 0.3f) / 3.f + 1.f, 1);
  check_iso_pick(scene, pick, 1.f, 0.5f, 2.f * (3.f - 2.f) / 3.f + 1.f, 0);
  set_transform(scene.instance, scale_then_move(1, 1, 1, 0, 0, 0));
  ospCommit(scene.instance);

  // A recommitted volume reaches the isosurface without recommitting the geometry: moved
  // up by 1, and with another field (f = 2 (x + 2y + 3z) before the move).
  ospSetVec3f(volume, "gridOrigin", 0.f, 0.f, 1.f);
  ospCommit(volume);
  check_bounds(ospGetBounds(scene.geometry), {0.f, 0.f, 1.f}, {1.9f, 1.9f, 2.9f});
  check_bounds(ospGetBounds(scene.world), {0.f, 0.f, 1.f}, {1.9f, 1.9f, 2.9f});
  check_iso_pick(scene, pick, 1.f, 0.5f, 1.f + (3.f - 2.f) / 3.f, 0);
  std::vector<float> doubled = voxels;
  for (float& v : doubled) v *= 2.f;
  set_voxels(volume, doubled, 20);
  ospCommit(volume);
  check_iso_pick(scene, pick, 0.1f, 0.1f, 1.f + (0.5f - 0.3f) / 3.f, 1);
  check_iso_pick(scene, pick, 0.4f, 0.2f, 1.f + (1.5f - 0.8f) / 3.f, 0);  // f = 1 lies below the volume here
  ospRelease(volume);
  CHECK(api.messages.errors.empty());
}

TEST_CASE("isosurface: bad input is named through the error callback", "[c_api][isosurface][errors]") {
  ApiFixture api;
  const auto voxels = linear_voxels(4, 1.f);
  OSPVolume volume = new_volume(voxels, 4, 1.f);
  OSPGeometry g = ospNewGeometry("isosurface");
  ospCommit(g);
  api.expect_error("ospCommit: isosurface geometry: required parameter 'volume' (OSPVolume) is missing");
  OSPVolumetricModel model = ospNewVolumetricModel(volume);
  ospSetObject(g, "volume", model);
  ospCommit(g);
  api.expect_error("isosurface geometry: parameter 'volume' must be OSPVolume, got OSPVolumetricModel (in OSPRay 3 an "
               "isosurface takes the volume itself, not a volumetric model)");
  OSPVolume uncommitted = ospNewVolume("structuredRegular");
  ospSetObject(g, "volume", uncommitted);
  ospCommit(g);
  api.expect_error("isosurface geometry: its volume has not been committed");
  ospSetObject(g, "volume", volume);
  ospCommit(g);
  api.expect_error("isosurface geometry: required parameter 'isovalue' (float, or array of float) is missing");
  ospSetFloat(g, "isovalue", NAN);
  ospCommit(g);
  api.expect_error("isosurface geometry: parameter 'isovalue' is not finite");
  const float with_nan[2] = {1.f, NAN};
  set_array(g, "isovalue", with_nan, OSP_FLOAT, 2);
  ospCommit(g);
  api.expect_error("isosurface geometry: parameter 'isovalue' element 1 is not finite");
  const int ints[2] = {1, 2};
  set_array(g, "isovalue", ints, OSP_INT, 2);
  ospCommit(g);
  api.expect_error("isosurface geometry: parameter 'isovalue' must be an array of float, got an array of int");
  ospSetVec3f(g, "isovalue", 1.f, 2.f, 3.f);
  ospCommit(g);
  api.expect_error("isosurface geometry: parameter 'isovalue' must be a float or an array of float, got vec3f");
  ospSetObject(g, "isovalue", volume);
  ospCommit(g);
  api.expect_error("isosurface geometry: parameter 'isovalue' must be a float or an array of float, got OSPVolume");
  ospSetFloat(g, "isovalue", 2.f);
  ospCommit(g);
  CHECK(api.messages.errors.empty());

  // Colours: one per isovalue (the isosurface's primitives; fewer is an error), or one
  // for all; here the material's.
  OSPGeometricModel m = ospNewGeometricModel(g);
  const float red[6] = {1.f, 0.f, 0.f, 1.f, 0.f, 0.f};
  set_array(m, "color", red, OSP_VEC3F, 2);
  ospCommit(m);
  CHECK(api.messages.errors.empty());
  const float three_isovalues[3] = {1.f, 2.f, 3.f};
  set_array(g, "isovalue", three_isovalues, OSP_FLOAT, 3);
  ospCommit(g);
  ospCommit(m);
  api.expect_error("geometric model: parameter 'color' has 2 elements but there are 3 primitives");
  const float blue[3] = {0.f, 0.f, 1.f};
  set_array(m, "color", blue, OSP_VEC3F, 1);
  ospCommit(m);
  CHECK(api.messages.errors.empty());
  const float blue_alpha[8] = {0.f, 0.f, 1.f, 0.5f};
  set_array(m, "color", blue_alpha, OSP_VEC4F, 1);  // one translucent colour: spread over the isovalues
  ospCommit(m);
  CHECK(api.messages.errors.empty());
  ospSetFloat(g, "isovalue", 2.f);
  ospCommit(g);
  ospRemoveParam(m, "color");
  OSPMaterial material = ospNewMaterial("obj");
  ospSetVec3f(material, "kd", 1.f, 0.f, 0.f);
  ospCommit(material);
  ospSetObject(m, "material", material);
  ospCommit(m);
  CHECK(api.messages.errors.empty());
  OSPGroup group = new_group({m});
  OSPInstance instance = new_instance(group);
  OSPWorld world = new_world({instance});
  // The isosurface x + 2y + 3z = 2 of the ramp, seen along z, shows the material's red.
  OSPCamera camera = ospNewCamera("orthographic");
  ospSetVec3f(camera, "position", 0.5f, 0.5f, -5.f);
  ospSetVec3f(camera, "direction", 0.f, 0.f, 1.f);
  ospSetFloat(camera, "height", 0.5f);
  ospCommit(camera);
  OSPRenderer renderer = ospNewRenderer("scivis");
  ospCommit(renderer);
  OSPFrameBuffer fb = ospNewFrameBuffer(4, 4, OSP_FB_RGBA32F, OSP_FB_COLOR);
  ospRenderFrameBlocking(fb, renderer, camera, world);
  const auto* rgba = static_cast<const float*>(ospMapFrameBuffer(fb, OSP_FB_COLOR));
  CHECK(rgba[4 * 5 + 0] > 0.1f);
  CHECK(rgba[4 * 5 + 1] == 0.f);
  CHECK(rgba[4 * 5 + 2] == 0.f);
  ospUnmapFrameBuffer(rgba, fb);
  CHECK(api.messages.errors.empty());

  // Isosurfaces cannot clip.
  ospSetObjectAsData(group, "clippingGeometry", OSP_GEOMETRIC_MODEL, m);
  ospCommit(group);
  api.expect_error("ospCommit: group: parameter 'clippingGeometry' element 0: isosurface geometry cannot clip yet");
  for (OSPObject o : std::initializer_list<OSPObject>{volume, g, model, uncommitted, m, material, group, instance,
                                                      world, camera, renderer, fb})
    ospRelease(o);
  CHECK(api.messages.errors.empty());
}

namespace {

/// A slice through f = x + 2y + 3z on [0, 1]³ (11³ voxels of 0.1): the plane z = 0.5,
/// bounded to x, y in [0.2, 0.8], coloured through a volume texture by a transfer
/// function of colour (v/6, 1 − v/6, 0.5) over [0, 6]; an orthographic view down +z of
/// x, y in [0, 1] lit by a white ambient light of intensity 1 only.
struct SliceScene {
  std::vector<float> voxels = linear_voxels(11, 0.1f);
  OSPVolume volume = new_volume(voxels, 11, 0.1f);
  OSPTransferFunction tf = new_transfer_function({0.f, 1.f, 0.5f, 1.f, 0.f, 0.5f}, {1.f}, 0.f, 6.f);
  OSPVolumetricModel volume_model = ospNewVolumetricModel(volume);
  OSPTexture texture = ospNewTexture("volume");
  OSPMaterial material = ospNewMaterial("obj");
  OSPGeometry plane = ospNewGeometry("plane");
  OSPGeometricModel model = ospNewGeometricModel(plane);
  OSPGroup group = nullptr;
  OSPInstance instance = nullptr;
  OSPWorld world = nullptr;
  OSPCamera camera = ospNewCamera("orthographic");
  OSPRenderer renderer = ospNewRenderer("scivis");
  static constexpr int size = 32;

  SliceScene() {
    ospSetObject(volume_model, "transferFunction", tf);
    ospCommit(volume_model);
    ospSetObject(texture, "volume", volume_model);
    ospCommit(texture);
    ospSetObject(material, "map_kd", texture);
    ospCommit(material);
    const float coefficients[4] = {0.f, 0.f, 1.f, -0.5f};
    const float bounds[6] = {0.2f, 0.2f, 0.f, 0.8f, 0.8f, 1.f};
    set_array(plane, "plane.coefficients", coefficients, OSP_VEC4F, 1);
    set_array(plane, "plane.bounds", bounds, OSP_BOX3F, 1);
    ospCommit(plane);
    ospSetObject(model, "material", material);
    ospCommit(model);
    group = new_group({model});
    instance = new_instance(group);
    world = new_world({instance});
    ospSetVec3f(camera, "position", 0.5f, 0.5f, -5.f);
    ospSetVec3f(camera, "direction", 0.f, 0.f, 1.f);
    ospSetFloat(camera, "height", 1.f);
    ospCommit(camera);
    ospCommit(renderer);
  }
  SliceScene(const SliceScene&) = delete;
  SliceScene& operator=(const SliceScene&) = delete;
  ~SliceScene() {
    for (OSPObject o : std::initializer_list<OSPObject>{volume, tf, volume_model, texture, material, plane, model,
                                                       group, instance, world, camera, renderer})
      ospRelease(o);
  }

  /// Every pixel must show `expected(x, y)` (RGB, alpha 1) inside the plane's bounds and
  /// the transparent background outside.
  template <class Expected>
  void check(Expected&& expected) const {
    OSPFrameBuffer fb = ospNewFrameBuffer(size, size, OSP_FB_RGBA32F, OSP_FB_COLOR);
    ospRenderFrameBlocking(fb, renderer, camera, world);
    const auto* image = static_cast<const float*>(ospMapFrameBuffer(fb, OSP_FB_COLOR));
    int shown = 0, wrong = 0;
    for (int j = 0; j < size; ++j)
      for (int i = 0; i < size; ++i) {
        const float x = 1.f - (i + 0.5f) / size, y = (j + 0.5f) / size;  // the camera's right is −x
        const float* p = image + 4 * (j * size + i);
        if (!(x > 0.2f && x < 0.8f && y > 0.2f && y < 0.8f)) {
          wrong += p[3] != 0.f;
          continue;
        }
        ++shown;
        const std::array<float, 3> want = expected(x, y);
        const bool ok = p[3] == 1.f && std::abs(p[0] - want[0]) < 1e-4f && std::abs(p[1] - want[1]) < 1e-4f &&
                        std::abs(p[2] - want[2]) < 1e-4f;
        if (!ok && wrong < 3)
          UNSCOPED_INFO("x = " << x << ", y = " << y << ": got (" << p[0] << ", " << p[1] << ", " << p[2] << ", "
                               << p[3] << "), want (" << want[0] << ", " << want[1] << ", " << want[2] << ", 1)");
        wrong += !ok;
      }
    ospUnmapFrameBuffer(image, fb);
    ospRelease(fb);
    CHECK(shown == 20 * 20);  // pixel centres 6.5 to 25.5 of 32 on both axes
    CHECK(wrong == 0);
  }
};

/// The transfer function's colour of value v, times `tint`.
std::array<float, 3> ramp(float v, std::array<float, 3> tint = {1.f, 1.f, 1.f}) {
  return {v / 6.f * tint[0], (1.f - v / 6.f) * tint[1], 0.5f * tint[2]};
}

}  // namespace

TEST_CASE("slice: a volume texture as map_kd colours a plane by the volume's transfer function",
          "[c_api][slice][render]") {
  ApiFixture api;
  SliceScene scene;
  // kd (default 0.8) times the transfer function's colour of f(x, y, 0.5) = x + 2y + 1.5.
  for (auto isa : sciray::simd::all_isas) {
    if (!sciray::simd::cpu_supports(isa)) continue;
    const std::string name(sciray::simd::isa_name(isa));
    INFO("ISA " << name);
    ospDeviceSetParam(api.device, "isa", OSP_STRING, name.c_str());
    ospDeviceCommit(api.device);
    scene.check([](float x, float y) { return ramp(x + 2 * y + 1.5f, {0.8f, 0.8f, 0.8f}); });
  }
  ospDeviceSetParam(api.device, "isa", OSP_STRING, "auto");
  ospDeviceCommit(api.device);
  check_bounds(ospGetBounds(scene.world), {0.2f, 0.2f, 0.f}, {0.8f, 0.8f, 1.f});

  // The material's kd and the model's colour multiply it.
  ospSetVec3f(scene.material, "kd", 1.f, 0.5f, 1.f);
  ospCommit(scene.material);
  scene.check([](float x, float y) { return ramp(x + 2 * y + 1.5f, {1.f, 0.5f, 1.f}); });
  const float color[3] = {0.5f, 1.f, 0.25f};
  set_array(scene.model, "color", color, OSP_VEC3F, 1);
  ospCommit(scene.model);
  scene.check([](float x, float y) { return ramp(x + 2 * y + 1.5f, {0.5f, 0.5f, 0.25f}); });
  ospRemoveParam(scene.model, "color");
  ospCommit(scene.model);
  ospSetVec3f(scene.material, "kd", 1.f, 1.f, 1.f);
  ospCommit(scene.material);
  scene.check([](float x, float y) { return ramp(x + 2 * y + 1.5f); });

  // A recommitted transfer function, and a recommitted volume, reach the next frame
  // without recommitting the texture, material or model.
  const float yellow_to_blue[6] = {1.f, 1.f, 0.f, 0.f, 0.f, 1.f};
  set_array(scene.tf, "color", yellow_to_blue, OSP_VEC3F, 2);
  ospCommit(scene.tf);
  scene.check([](float x, float y) {
    const float s = (x + 2 * y + 1.5f) / 6.f;  // from (1, 1, 0) to (0, 0, 1)
    return std::array<float, 3>{1.f - s, 1.f - s, s};
  });
  ospSetVec3f(scene.volume, "gridOrigin", 0.f, 0.f, -0.5f);  // f = x + 2y + 3 (z + 0.5)
  ospCommit(scene.volume);
  scene.check([](float x, float y) {
    const float s = (x + 2 * y + 3.f) / 6.f;
    return std::array<float, 3>{1.f - s, 1.f - s, s};
  });

  // OSPRay 3's form, the volume and a transfer function of the texture's own, shows the
  // same; recommits of either reach it.
  ospSetObject(scene.texture, "volume", scene.volume);
  ospSetObject(scene.texture, "transferFunction", scene.tf);
  ospCommit(scene.texture);
  scene.check([](float x, float y) {
    const float s = (x + 2 * y + 3.f) / 6.f;
    return std::array<float, 3>{1.f - s, 1.f - s, s};
  });
  const float red_to_green[6] = {1.f, 0.f, 0.f, 0.f, 1.f, 0.f};
  set_array(scene.tf, "color", red_to_green, OSP_VEC3F, 2);
  ospCommit(scene.tf);
  scene.check([](float x, float y) {
    const float s = (x + 2 * y + 3.f) / 6.f;
    return std::array<float, 3>{1.f - s, s, 0.f};
  });

  // Picks land on the plane and report the slice's model.
  Picker pick;
  check_pick(pick, scene.world, {0.3f, 0.7f, -5.f}, {0.f, 0.f, 1.f}, scene.instance, scene.model, {0.3f, 0.7f, 0.5f});
  const OSPPickResult miss = pick(scene.world, {0.1f, 0.5f, -5.f});  // outside the plane's bounds
  CHECK(miss.hasHit == 0);
  release_pick(miss);
  CHECK(api.messages.errors.empty());
}

TEST_CASE("slice: volume textures' bad input is named through the error callback", "[c_api][slice][errors]") {
  ApiFixture api;
  SliceScene scene;
  CHECK(api.messages.errors.empty());
  CHECK(ospNewTexture("checkerboard") == nullptr);
  api.expect_error("ospNewTexture: unknown texture type 'checkerboard' (sciray supports: volume, texture2d)");

  OSPTexture texture = ospNewTexture("volume");
  ospCommit(texture);
  api.expect_error("ospCommit: volume texture: required parameter 'volume' (OSPVolume, with 'transferFunction') is "
                   "missing");
  ospSetObject(texture, "volume", scene.volume);
  ospCommit(texture);
  api.expect_error("volume texture: required parameter 'transferFunction' (OSPTransferFunction) is missing");
  ospSetObject(texture, "transferFunction", scene.volume);
  ospCommit(texture);
  api.expect_error("volume texture: parameter 'transferFunction' must be OSPTransferFunction, got OSPVolume");
  ospSetObject(texture, "volume", scene.tf);
  ospCommit(texture);
  api.expect_error("volume texture: parameter 'volume' must be OSPVolume (OSPRay 3, with 'transferFunction') or "
                   "OSPVolumetricModel (OSPRay 2), got OSPTransferFunction");
  ospSetObject(texture, "volume", scene.volume_model);
  ospCommit(texture);
  api.expect_error("volume texture: parameter 'transferFunction' is for an OSPVolume 'volume'; a volumetric model "
                   "brings its own");
  ospRemoveParam(texture, "transferFunction");
  OSPVolumetricModel uncommitted_model = ospNewVolumetricModel(scene.volume);
  ospSetObject(texture, "volume", uncommitted_model);
  ospCommit(texture);
  api.expect_error("volume texture: its volumetric model has not been committed");

  OSPMaterial material = ospNewMaterial("obj");
  ospSetObject(material, "map_kd", texture);
  ospCommit(material);
  api.expect_error("ospCommit: obj material: parameter 'map_kd': its texture has not been committed");
  ospSetObject(material, "map_kd", scene.volume);
  ospCommit(material);
  api.expect_error("obj material: parameter 'map_kd' must be OSPTexture, got OSPVolume");
  ospSetObject(material, "map_kd", scene.texture);
  ospCommit(material);
  CHECK(api.messages.errors.empty());

  // A volume texture colours planes only, yet.
  OSPGeometry mesh = new_cube_mesh({0.f, 0.f, 0.f}, {1.f, 1.f, 1.f});
  OSPGeometricModel mesh_model = ospNewGeometricModel(mesh);
  ospSetObject(mesh_model, "material", material);
  ospCommit(mesh_model);
  api.expect_error("ospCommit: geometric model: its material's 'map_kd' (a volume texture) is not supported yet on mesh "
               "geometry; volume textures colour plane geometry only (slices)");
  OSPGeometry spheres = new_spheres({0.f, 0.f, 0.f}, 1.f);
  OSPGeometricModel sphere_model = ospNewGeometricModel(spheres);
  ospSetObject(sphere_model, "material", material);
  ospCommit(sphere_model);
  api.expect_error("geometric model: its material's 'map_kd' (a volume texture) is not supported yet on sphere geometry");

  // A texture given to the material of a committed mesh model is refused by the world.
  OSPMaterial plain = ospNewMaterial("obj");
  ospCommit(plain);
  ospSetObject(mesh_model, "material", plain);
  ospCommit(mesh_model);
  OSPGroup group = new_group({mesh_model});
  OSPInstance instance = new_instance(group);
  OSPWorld world = new_world({instance});
  ospSetObject(plain, "map_kd", scene.texture);
  ospCommit(plain);
  CHECK(api.messages.errors.empty());
  OSPFrameBuffer fb = ospNewFrameBuffer(4, 4);
  CHECK(ospRenderFrame(fb, scene.renderer, scene.camera, world) == nullptr);
  api.expect_error("ospRenderFrame: world: the group of instance 0, parameter 'geometry' element 0 (geometric model of "
               "mesh geometry): its material's 'map_kd' (a volume texture) is not supported yet on mesh geometry");
  for (OSPObject o : std::initializer_list<OSPObject>{texture, uncommitted_model, material, mesh, mesh_model, spheres,
                                                      sphere_model, plain, group, instance, world, fb})
    ospRelease(o);
  CHECK(api.messages.errors.empty());
}
