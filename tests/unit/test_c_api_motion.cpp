// Camera and instance placement through the C API: `transform`, `motion.*` in both forms
// over `time`, `shutter` and the other camera parameters, read as OSPRay defines them
// (picks see a moving instance where Embree places it at the pick ray's time) and
// range-checked at commit with the object and parameter named.
#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include <ospray/ospray.h>
#include <ospray/ospray_util.h>

#include "support/api_fixture.hpp"

using sciray_test::ApiFixture;

namespace {

using Affine = std::array<float, 12>;

Affine translate(float x, float y, float z) { return {1, 0, 0, 0, 1, 0, 0, 0, 1, x, y, z}; }

/// A sphere of radius 0.2 at (2, 0, 0) in a group of its own.
struct SphereGroup {
  OSPGeometry sphere = ospNewGeometry("sphere");
  OSPGeometricModel model = nullptr;
  OSPGroup group = ospNewGroup();

  SphereGroup() {
    const float centre[3] = {2.f, 0.f, 0.f};
    OSPData position = ospNewSharedData1D(centre, OSP_VEC3F, 1);
    ospSetObject(sphere, "sphere.position", position);
    ospRelease(position);
    ospSetFloat(sphere, "radius", 0.2f);
    ospCommit(sphere);
    model = ospNewGeometricModel(sphere);
    ospCommit(model);
    ospSetObjectAsData(group, "geometry", OSP_GEOMETRIC_MODEL, model);
    ospCommit(group);
  }
  ~SphereGroup() {
    ospRelease(sphere);
    ospRelease(model);
    ospRelease(group);
  }
};

/// Picks straight down +z through (x, y) at time `time` (a shutter of that instant),
/// the camera placed by `transform` from the origin; returns the hit's z or NaN.
float pick_z(OSPWorld world, float x, float y, float time) {
  OSPCamera camera = ospNewCamera("orthographic");
  ospSetVec3f(camera, "direction", 0.f, 0.f, 1.f);
  const Affine placed = translate(x, y, -5.f);
  ospSetParam(camera, "transform", OSP_AFFINE3F, placed.data());
  const float shutter[2] = {time, time};
  ospSetParam(camera, "shutter", OSP_BOX1F, shutter);
  ospCommit(camera);
  OSPRenderer renderer = ospNewRenderer("scivis");
  ospCommit(renderer);
  OSPFrameBuffer fb = ospNewFrameBuffer(4, 4);
  OSPPickResult result;
  ospPick(&result, fb, renderer, camera, world, 0.5f, 0.5f);
  const float z = result.hasHit ? result.worldPosition[2] : std::numeric_limits<float>::quiet_NaN();
  if (result.hasHit) ospRelease(result.instance), ospRelease(result.model);
  for (OSPObject o : {static_cast<OSPObject>(camera), static_cast<OSPObject>(renderer), static_cast<OSPObject>(fb)})
    ospRelease(o);
  return z;
}

}  // namespace

TEST_CASE(
    "C API: an instance turning by motion.rotation (quatf: i j k then r) over 'time' is picked where Embree "
    "places it",
    "[c_api][motion][pick]") {
  ApiFixture api;
  SphereGroup s;
  OSPInstance instance = ospNewInstance(s.group);
  // A quarter turn about +z: the sphere's centre sweeps from (2, 0, 0) to (0, 2, 0) on
  // the circle, halfway at 45 degrees. OSPRay's quatf holds the real part last (measured
  // with OSPRay 3.1's runtime: r first turns its MotionBlurBoxes instance about x).
  const float h = std::sqrt(0.5f);
  const float rotation[8] = {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, h, h};
  OSPData keys = ospNewSharedData1D(rotation, OSP_QUATF, 2);
  ospSetObject(instance, "motion.rotation", keys);
  ospRelease(keys);
  const float range[2] = {0.f, 0.5f};  // the turn takes the first half of the shutter
  ospSetParam(instance, "time", OSP_BOX1F, range);
  ospCommit(instance);
  OSPWorld world = ospNewWorld();
  ospSetObjectAsData(world, "instance", OSP_INSTANCE, instance);
  ospCommit(world);

  CHECK(pick_z(world, 2.f, 0.f, 0.f) == Approx(-0.2f));
  const float c = 2.f * std::cos(std::acos(-1.f) / 8.f), d = 2.f * std::sin(std::acos(-1.f) / 8.f);  // 22.5 degrees
  CHECK(pick_z(world, c, d, 0.125f) == Approx(-0.2f));
  CHECK(pick_z(world, std::sqrt(2.f), std::sqrt(2.f), 0.25f) == Approx(-0.2f));
  CHECK(std::isnan(pick_z(world, 1.f, 1.f, 0.25f)));  // where averaged matrices would put it
  const float e = 2.f * std::cos(0.4f * std::acos(-1.f)), f = 2.f * std::sin(0.4f * std::acos(-1.f));  // 72 degrees
  CHECK(pick_z(world, e, f, 0.4f) == Approx(-0.2f));
  // From the end of its time range on, the instance is gone (Embree's range is half open).
  CHECK(std::isnan(pick_z(world, 0.f, 2.f, 0.5f)));
  CHECK(std::isnan(pick_z(world, 0.f, 2.f, 0.75f)));
  CHECK(api.messages.errors.empty());
  ospRelease(instance);
  ospRelease(world);
}

TEST_CASE("C API: camera and instance placement and shutter parameters are range-checked at commit by name",
          "[c_api][motion][errors]") {
  ApiFixture api;
  OSPCamera camera = ospNewCamera("perspective");
  const auto commit_expecting = [&](const char* fragment) {
    ospCommit(camera);
    api.expect_error(fragment);
  };
  const float backwards[2] = {0.6f, 0.4f}, half[2] = {0.f, 0.5f};
  ospSetParam(camera, "shutter", OSP_BOX1F, backwards);
  commit_expecting("perspective camera: 'shutter' must satisfy 0 <= lower <= upper <= 1");
  ospSetParam(camera, "shutter", OSP_BOX1F, half);
  ospSetFloat(camera, "rollingShutterDuration", 0.9f);
  commit_expecting("'rollingShutterDuration' must be in [0, shutter upper - lower] = [0, 0.5");
  ospSetFloat(camera, "rollingShutterDuration", 0.5f);
  ospSetInt(camera, "shutterType", 7);
  commit_expecting("perspective camera: 'shutterType' must be OSP_SHUTTER_GLOBAL (0)");
  ospSetInt(camera, "shutterType", OSP_SHUTTER_ROLLING_DOWN);
  ospSetFloat(camera, "nearClip", -1.f);
  commit_expecting("perspective camera: 'nearClip' must be finite and not negative");
  ospSetFloat(camera, "nearClip", 0.1f);
  ospSetVec2f(camera, "imageStart", 0.5f, 0.f);
  ospSetVec2f(camera, "imageEnd", 0.5f, 1.f);
  commit_expecting("'imageStart' and 'imageEnd' must differ in x and in y");
  ospSetVec3f(camera, "imageEnd", 1.f, 1.f, 0.f);
  commit_expecting("perspective camera: parameter 'imageEnd' must be a vec2f, got vec3f");
  ospSetVec2f(camera, "imageEnd", 1.f, 1.f);
  const Affine flat = {1, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0};
  ospSetParam(camera, "transform", OSP_AFFINE3F, flat.data());
  commit_expecting("perspective camera: parameter 'transform' is singular");
  ospRemoveParam(camera, "transform");  // motion.* replaces it
  const std::vector<Affine> keys = {translate(0, 0, 0), {1, 0, 0, 0, 1, 0, 0, 0, 1, std::nanf(""), 0, 0}};
  OSPData data = ospNewSharedData1D(keys.data(), OSP_AFFINE3F, 2);
  ospSetObject(camera, "motion.transform", data);
  ospRelease(data);
  commit_expecting("perspective camera: parameter 'motion.transform' element 1 is not finite");
  const std::vector<Affine> good = {translate(0, 0, 0), translate(1, 0, 0)};
  data = ospNewSharedData1D(good.data(), OSP_AFFINE3F, 2);
  ospSetObject(camera, "motion.transform", data);
  ospRelease(data);
  ospCommit(camera);  // the rest is valid: a rolling, moving camera over half the shutter
  CHECK(api.messages.errors.empty());

  SphereGroup s;
  OSPInstance instance = ospNewInstance(s.group);
  const float rotations[8] = {1.f, 0.f, 0.f, 0.f, 2.f, 0.f, 0.f, 0.f};
  data = ospNewSharedData1D(rotations, OSP_QUATF, 2);
  ospSetObject(instance, "motion.rotation", data);
  ospRelease(data);
  ospCommit(instance);
  api.expect_error("instance: parameter 'motion.rotation' element 1 must be a unit quaternion, its length is 2");
  const float turns[8] = {1.f, 0.f, 0.f, 0.f, 0.f, 0.f, 0.f, 1.f};
  data = ospNewSharedData1D(turns, OSP_QUATF, 2);
  ospSetObject(instance, "motion.rotation", data);
  ospRelease(data);
  ospSetParam(instance, "time", OSP_BOX1F, backwards);
  ospCommit(instance);
  api.expect_error("instance: parameter 'time' must have lower <= upper");
  ospSetParam(instance, "time", OSP_BOX1F, half);
  const float vectors[3] = {0.f, 0.f, 0.f};
  data = ospNewSharedData1D(vectors, OSP_VEC3F, 1);
  ospSetObject(instance, "motion.transform", data);
  ospRelease(data);
  ospCommit(instance);
  api.expect_error("instance: parameter 'motion.transform' must be an array of affine3f, got an array of vec3f");
  ospRemoveParam(instance, "motion.transform");
  ospCommit(instance);
  CHECK(api.messages.errors.empty());
  ospRelease(instance);
  ospRelease(camera);
}

TEST_CASE("C API: a deforming mesh's motion.vertex.position and time, and luminous parameters, are range-checked "
          "at commit by name",
          "[c_api][motion][errors]") {
  ApiFixture api;
  const float square[12] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0}, moved[12] = {2, 0, 0, 3, 0, 0, 3, 1, 0, 2, 1, 0};
  const unsigned index[4] = {0, 1, 2, 3};
  OSPGeometry mesh = ospNewGeometry("mesh");
  OSPData indices = ospNewSharedData1D(index, OSP_VEC4UI, 1);
  ospSetObject(mesh, "index", indices);
  ospRelease(indices);
  OSPData first = ospNewSharedData1D(square, OSP_VEC3F, 4), second = ospNewSharedData1D(moved, OSP_VEC3F, 4),
          three = ospNewSharedData1D(moved, OSP_VEC3F, 3);
  const auto set_steps = [&](std::vector<OSPData> steps) {
    OSPData list = ospNewSharedData1D(steps.data(), OSP_DATA, static_cast<std::uint32_t>(steps.size()));
    ospSetObject(mesh, "motion.vertex.position", list);
    ospRelease(list);
    ospCommit(mesh);
  };
  set_steps({first});
  api.expect_error("mesh geometry: parameter 'motion.vertex.position' needs at least two time steps, got 1");
  set_steps({first, three});
  api.expect_error("parameter 'motion.vertex.position' element 1 has 3 vertices but element 0 has 4");
  const float backwards[2] = {1.f, 0.f};
  ospSetParam(mesh, "time", OSP_BOX1F, backwards);
  set_steps({first, second});
  api.expect_error("mesh geometry: parameter 'time' must have lower <= upper");
  ospRemoveParam(mesh, "time");
  ospCommit(mesh);  // two steps of four vertices over the default [0, 1]
  CHECK(api.messages.errors.empty());
  ospRelease(first), ospRelease(second), ospRelease(three);

  OSPMaterial luminous = ospNewMaterial("luminous");
  ospSetFloat(luminous, "transparency", 1.5f);
  ospCommit(luminous);
  api.expect_error("luminous material: parameter 'transparency' must be in [0, 1]");
  ospSetFloat(luminous, "transparency", 0.5f);
  ospSetFloat(luminous, "intensity", -1.f);
  ospCommit(luminous);
  api.expect_error("luminous material: parameter 'intensity' must be finite and not negative");
  ospSetFloat(luminous, "intensity", 2.f);
  const float texel[3] = {1.f, 0.5f, 0.25f};
  OSPData texels = ospNewSharedData2D(texel, OSP_VEC3F, 1, 1);
  OSPTexture texture = ospNewTexture("texture2d");
  ospSetObject(texture, "data", texels);
  ospSetInt(texture, "format", OSP_TEXTURE_RGB32F);
  ospCommit(texture);
  ospSetObject(luminous, "map_color", texture);
  ospCommit(luminous);  // map_color is a luminous parameter now
  CHECK(api.messages.errors.empty());
  ospRelease(texels), ospRelease(texture), ospRelease(luminous), ospRelease(mesh);
}

TEST_CASE("C API: a deforming mesh's motion.vertex.normal and motion.normal are interpolated at the ray's time",
          "[c_api][motion][mesh]") {
  ApiFixture api;
  // A quad in z = 0 facing the camera at z = -5 that stays put while its normal turns from
  // -z (facing the camera) at time 0 to +x at time 1. Lerped and normalized as OSPRay's
  // Mesh.ispc: at time t the normal is (t, 0, -(1 - t)) / |(t, 0, -(1 - t))|. The normal
  // channel shows it at the instant the shutter opens and closes.
  const float square[12] = {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0};
  const float facing[12] = {0, 0, -1, 0, 0, -1, 0, 0, -1, 0, 0, -1}, turned[12] = {1, 0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0};
  const unsigned index[4] = {0, 1, 2, 3};
  OSPData positions = ospNewSharedData1D(square, OSP_VEC3F, 4);
  OSPData normals[2] = {ospNewSharedData1D(facing, OSP_VEC3F, 4), ospNewSharedData1D(turned, OSP_VEC3F, 4)};
  const OSPData position_steps[2] = {positions, positions};
  const auto set_list = [](OSPGeometry g, const char* id, const OSPData* steps, std::uint32_t count) {
    OSPData list = ospNewSharedData1D(steps, OSP_DATA, count);
    ospSetObject(g, id, list);
    ospRelease(list);
  };
  OSPGeometry mesh = ospNewGeometry("mesh");
  set_list(mesh, "motion.vertex.position", position_steps, 2);
  OSPData indices = ospNewSharedData1D(index, OSP_VEC4UI, 1);
  ospSetObject(mesh, "index", indices);

  OSPCamera camera = ospNewCamera("orthographic");
  ospSetVec3f(camera, "position", 0.f, 0.f, -5.f);
  ospSetVec3f(camera, "direction", 0.f, 0.f, 1.f);
  ospSetFloat(camera, "height", 1.f);
  OSPRenderer renderer = ospNewRenderer("scivis");
  ospCommit(renderer);
  const auto normal_at = [&](float time) {
    OSPGeometricModel model = ospNewGeometricModel(mesh);
    ospCommit(model);
    OSPGroup group = ospNewGroup();
    ospSetObjectAsData(group, "geometry", OSP_GEOMETRIC_MODEL, model);
    ospCommit(group);
    OSPInstance instance = ospNewInstance(group);
    ospCommit(instance);
    OSPWorld world = ospNewWorld();
    ospSetObjectAsData(world, "instance", OSP_INSTANCE, instance);
    ospCommit(world);
    const float shutter[2] = {time, time};
    ospSetParam(camera, "shutter", OSP_BOX1F, shutter);
    ospCommit(camera);
    OSPFrameBuffer fb = ospNewFrameBuffer(4, 4, OSP_FB_RGBA32F, OSP_FB_COLOR | OSP_FB_NORMAL);
    ospRenderFrameBlocking(fb, renderer, camera, world);
    const auto* n = static_cast<const float*>(ospMapFrameBuffer(fb, OSP_FB_NORMAL));
    REQUIRE(n != nullptr);
    const std::array<float, 3> centre{n[3 * 10], n[3 * 10 + 1], n[3 * 10 + 2]};
    ospUnmapFrameBuffer(n, fb);
    for (OSPObject o : std::initializer_list<OSPObject>{fb, world, instance, group, model}) ospRelease(o);
    return centre;
  };
  const auto expect_turned = [&](float time) {
    INFO("time " << time);
    const float length = std::hypot(time, 1.f - time);
    const std::array<float, 3> n = normal_at(time);
    CHECK(n[0] == Approx(time / length).margin(1e-5));
    CHECK(n[1] == Approx(0.f).margin(1e-5));
    CHECK(n[2] == Approx(-(1.f - time) / length).margin(1e-5));
  };

  set_list(mesh, "motion.vertex.normal", normals, 2);
  ospCommit(mesh);
  for (const float time : {0.f, 0.5f, 0.75f}) expect_turned(time);

  // Face-varying: one normal per face corner (here the quad's four, in index order).
  ospRemoveParam(mesh, "motion.vertex.normal");
  set_list(mesh, "motion.normal", normals, 2);
  ospCommit(mesh);
  expect_turned(0.75f);
  CHECK(api.messages.errors.empty());

  // Fewer steps than the positions, or a step that is not vec3f, are named.
  ospRemoveParam(mesh, "motion.normal");
  set_list(mesh, "motion.vertex.normal", normals, 1);
  ospCommit(mesh);
  api.expect_error(
      "mesh geometry: parameter 'motion.vertex.normal' has 1 time steps but 'motion.vertex.position' "
      "has 2");
  const OSPData mixed[2] = {normals[0], indices};
  set_list(mesh, "motion.vertex.normal", mixed, 2);
  ospCommit(mesh);
  api.expect_error("mesh geometry: parameter 'motion.vertex.normal[1]' must be a 1D array of vec3f");
  for (OSPObject o :
       std::initializer_list<OSPObject>{positions, normals[0], normals[1], indices, mesh, camera, renderer})
    ospRelease(o);
}
