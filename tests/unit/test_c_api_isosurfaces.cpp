// The OSPRay C API: isosurfaces and slices (see test_c_api.cpp).
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
#include "support/c_api_scenes.hpp"


using namespace sciray_test;

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

TEST_CASE("isosurface: picks land on the analytic surface, bounds, isovalue arrays, recommits take effect",
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
    const float coefficients[4] = {0.f, 0.f, 1.f, 0.5f};  // z = 0.5 (OSPRay's a·x + b·y + c·z = d)
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
  // The transfer function's colour of f(x, y, 0.5) = x + 2y + 1.5 (kd, not given, is 1
  // with a map, as in OSPRay).
  for (auto isa : sciray::simd::all_isas) {
    if (!sciray::simd::cpu_supports(isa)) continue;
    const std::string name(sciray::simd::isa_name(isa));
    INFO("ISA " << name);
    ospDeviceSetParam(api.device, "isa", OSP_STRING, name.c_str());
    ospDeviceCommit(api.device);
    scene.check([](float x, float y) { return ramp(x + 2 * y + 1.5f, {1.f, 1.f, 1.f}); });
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

TEST_CASE("volume texture: a sphere shows the transfer function at its hit points and nothing outside the volume",
          "[c_api][volume_texture][render]") {
  // The sphere of radius 0.3 about (0.5, 0.5, 0.5) in f = x + 2y + 3z on [0, 1]³, seen
  // down +z, textured with map_kd.transform moving its points by -0.35 in z: the front
  // points nearer than z = 0.35 sample outside the volume, where OSPRay's volume texture
  // gives colour and opacity 0, so the inside of the back half shows there.
  ApiFixture api;
  SliceScene scene;
  OSPGeometry sphere = new_spheres({0.5f, 0.5f, 0.5f}, 0.3f);
  OSPGeometricModel model = ospNewGeometricModel(sphere);
  const float move[12] = {1.f, 0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, 0.f, 0.f, -0.35f};
  ospSetParam(scene.material, "map_kd.transform", OSP_AFFINE3F, move);
  ospCommit(scene.material);
  ospSetObject(model, "material", scene.material);
  ospCommit(model);
  OSPGroup group = new_group({model});
  OSPInstance instance = new_instance(group);
  OSPWorld world = new_world({instance});
  constexpr int size = SliceScene::size;
  OSPFrameBuffer fb = ospNewFrameBuffer(size, size, OSP_FB_RGBA32F, OSP_FB_COLOR);
  ospRenderFrameBlocking(fb, scene.renderer, scene.camera, world);
  const auto* image = static_cast<const float*>(ospMapFrameBuffer(fb, OSP_FB_COLOR));
  int front = 0, back = 0, wrong = 0;
  for (int j = 0; j < size; ++j)
    for (int i = 0; i < size; ++i) {
      const float x = 1.f - (i + 0.5f) / size, y = (j + 0.5f) / size;  // the camera's right is −x
      const float* p = image + 4 * (j * size + i);
      const float d2 = (x - 0.5f) * (x - 0.5f) + (y - 0.5f) * (y - 0.5f);
      if (d2 > 0.09f * 1.05f) {
        wrong += p[3] != 0.f;
        continue;
      }
      const float half = std::sqrt(std::max(0.09f - d2, 0.f)), near = 0.5f - half - 0.35f;
      if (d2 > 0.09f * 0.95f || std::abs(near) < 1e-3f) continue;  // an edge
      const float z = near >= 0.f ? near : 0.5f + half - 0.35f;
      ++(near >= 0.f ? front : back);
      const std::array<float, 3> want = ramp(x + 2 * y + 3 * z);
      const bool ok = p[3] == 1.f && std::abs(p[0] - want[0]) < 1e-4f && std::abs(p[1] - want[1]) < 1e-4f &&
                      std::abs(p[2] - want[2]) < 1e-4f;
      if (!ok && wrong < 3)
        UNSCOPED_INFO("x = " << x << ", y = " << y << ": got (" << p[0] << ", " << p[1] << ", " << p[2] << ", "
                             << p[3] << "), want (" << want[0] << ", " << want[1] << ", " << want[2] << ", 1)");
      wrong += !ok;
    }
  ospUnmapFrameBuffer(image, fb);
  CHECK(wrong == 0);
  CHECK(front > 50);
  CHECK(back > 50);
  for (OSPObject o : std::initializer_list<OSPObject>{fb, sphere, model, group, instance, world}) ospRelease(o);
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

  // A volume texture colours planes and spheres only, yet; not discs.
  OSPGeometry mesh = new_cube_mesh({0.f, 0.f, 0.f}, {1.f, 1.f, 1.f});
  OSPGeometricModel mesh_model = ospNewGeometricModel(mesh);
  ospSetObject(mesh_model, "material", material);
  ospCommit(mesh_model);
  api.expect_error("ospCommit: geometric model: its material's 'map_kd' (a volume texture) is not supported yet on "
                   "mesh geometry; volume textures colour plane geometry (slices) and spheres only");
  OSPGeometry spheres = new_spheres({0.f, 0.f, 0.f}, 1.f);
  ospSetInt(spheres, "type", OSP_DISC);
  ospCommit(spheres);
  OSPGeometricModel sphere_model = ospNewGeometricModel(spheres);
  ospSetObject(sphere_model, "material", material);
  ospCommit(sphere_model);
  api.expect_error("geometric model: its material's 'map_kd' (a volume texture) colours spheres of type OSP_SPHERE "
                   "only, not discs");

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
