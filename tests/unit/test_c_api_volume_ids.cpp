// OSPRay C API: volumes in the depth and id channels, and the user ids (`id`) of
// geometric models, volumetric models and instances, as OSPRay 3.1's runtime writes them
// (measured with its runtime): scivis and the path tracer record a volume where it is
// seen (primitive 0, the model's index in its group or its `id`, the instance's index or
// its `id`), ao records none. scivis sees a volume at its first sample that absorbs more
// than `minContribution` over one of OSPRay's steps, on OSPRay's jittered sample grid.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include <ospray/ospray.h>
#include <ospray/ospray_util.h>

#include "support/api_fixture.hpp"

namespace {

using sciray_test::ApiFixture;

constexpr std::uint32_t none = 0xFFFFFFFFu;

/// A ball of opaque density (radius ~0.3) in the unit box around the origin, in front of
/// a box behind it (z in [0.6, 0.8]), with a box in front of its left half (x < 0,
/// z in [-0.8, -0.6]); an orthographic camera at z = -2 looks down +z (its right is -x).
struct VolumeBoxScene {
  std::vector<float> voxels;
  OSPGroup group = ospNewGroup();
  OSPInstance filler;  // a volume-only instance first: the instance index counts it
  OSPInstance instance;
  OSPWorld world = ospNewWorld();
  OSPCamera camera = ospNewCamera("orthographic");
  OSPGeometricModel boxes[2];
  OSPVolumetricModel volume;

  VolumeBoxScene() {
    const int n = 32;
    voxels.resize(n * n * n);
    for (int k = 0; k < n; ++k)
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
          const float x = (i + 0.5f) / n - 0.5f, y = (j + 0.5f) / n - 0.5f, z = (k + 0.5f) / n - 0.5f;
          voxels[(k * n + j) * n + i] = std::sqrt(x * x + y * y + z * z);
        }
    OSPVolume v = ospNewVolume("structuredRegular");
    OSPData data = ospNewSharedData3D(voxels.data(), OSP_FLOAT, n, n, n);
    ospSetObject(v, "data", data);
    ospSetVec3f(v, "gridOrigin", -0.5f, -0.5f, -0.5f);
    ospSetVec3f(v, "gridSpacing", 1.f / n, 1.f / n, 1.f / n);
    ospCommit(v);
    OSPTransferFunction tf = ospNewTransferFunction("piecewiseLinear");
    const float color[6] = {1, 1, 1, 1, 1, 1}, opacity[4] = {1, 1, 0, 0};
    OSPData colors = ospNewSharedData1D(color, OSP_VEC3F, 2), opacities = ospNewSharedData1D(opacity, OSP_FLOAT, 4);
    ospSetObject(tf, "color", colors);
    ospSetObject(tf, "opacity", opacities);
    // A box1f: OSPRay 3.1 ignores a vec2f `value` (and takes [0, 1]), sciray would not.
    const float range[2] = {0.f, 0.6f};
    ospSetParam(tf, "value", OSP_BOX1F, range);
    ospCommit(tf);
    volume = ospNewVolumetricModel(v);
    ospSetObject(volume, "transferFunction", tf);
    ospSetFloat(volume, "densityScale", 50.f);  // the path tracer collides at once
    ospCommit(volume);
    boxes[0] = box(-0.4f, -0.1f, -0.8f, -0.6f);
    boxes[1] = box(-0.6f, 0.6f, 0.6f, 0.8f);
    OSPData models = ospNewSharedData1D(boxes, OSP_GEOMETRIC_MODEL, 2);
    ospSetObject(group, "geometry", models);
    ospSetObjectAsData(group, "volume", OSP_VOLUMETRIC_MODEL, volume);
    ospCommit(group);
    OSPGroup volume_only = ospNewGroup();
    ospSetObjectAsData(volume_only, "volume", OSP_VOLUMETRIC_MODEL, volume);
    ospCommit(volume_only);
    filler = ospNewInstance(volume_only);
    const float out_of_sight[12] = {1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 5, 0};
    ospSetParam(filler, "transform", OSP_AFFINE3F, out_of_sight);
    ospCommit(filler);
    instance = ospNewInstance(group);
    ospCommit(instance);
    const OSPInstance instances[2] = {filler, instance};
    OSPData list = ospNewSharedData1D(instances, OSP_INSTANCE, 2);
    ospSetObject(world, "instance", list);
    ospCommit(world);
    ospSetVec3f(camera, "position", 0.f, 0.f, -2.f);
    ospSetVec3f(camera, "direction", 0.f, 0.f, 1.f);
    ospSetFloat(camera, "height", 1.6f);
    ospSetFloat(camera, "aspect", 1.f);
    ospCommit(camera);
    for (OSPObject o : {(OSPObject)data, (OSPObject)colors, (OSPObject)opacities, (OSPObject)models,
                        (OSPObject)list, (OSPObject)v, (OSPObject)tf, (OSPObject)volume_only})
      ospRelease(o);
  }
  ~VolumeBoxScene() {
    for (OSPObject o : {(OSPObject)boxes[0], (OSPObject)boxes[1], (OSPObject)volume, (OSPObject)group,
                        (OSPObject)filler, (OSPObject)instance, (OSPObject)world, (OSPObject)camera})
      ospRelease(o);
  }

  static OSPGeometricModel box(float x0, float x1, float z0, float z1) {
    OSPGeometry g = ospNewGeometry("box");
    const float b[6] = {x0, -0.4f, z0, x1, 0.4f, z1};
    OSPData shared = ospNewSharedData1D(b, OSP_BOX3F, 1), data = ospNewData1D(OSP_BOX3F, 1);
    ospCopyData1D(shared, data, 0);  // b is gone when the model is used
    ospRelease(shared);
    ospSetObject(g, "box", data);
    ospCommit(g);
    OSPGeometricModel m = ospNewGeometricModel(g);
    ospCommit(m);
    ospRelease(data);
    ospRelease(g);
    return m;
  }

  struct Pixel {
    float alpha, depth;
    std::uint32_t prim, object, instance;
  };

  /// The pixel of the middle row at world x (16 columns over [-0.8, 0.8], mirrored).
  Pixel at(const char* renderer_type, float x) const {
    constexpr int size = 16;
    OSPRenderer renderer = ospNewRenderer(renderer_type);
    ospCommit(renderer);
    OSPFrameBuffer fb = ospNewFrameBuffer(size, size, OSP_FB_RGBA32F,
                                          OSP_FB_COLOR | OSP_FB_DEPTH | OSP_FB_ID_PRIMITIVE | OSP_FB_ID_OBJECT |
                                              OSP_FB_ID_INSTANCE);
    ospRenderFrameBlocking(fb, renderer, camera, world);
    const int column = static_cast<int>((0.8f - x) / 1.6f * size);
    const std::size_t i = static_cast<std::size_t>((size / 2) * size + column);
    const auto* color = static_cast<const float*>(ospMapFrameBuffer(fb, OSP_FB_COLOR));
    const auto* depth = static_cast<const float*>(ospMapFrameBuffer(fb, OSP_FB_DEPTH));
    const auto* prim = static_cast<const std::uint32_t*>(ospMapFrameBuffer(fb, OSP_FB_ID_PRIMITIVE));
    const auto* object = static_cast<const std::uint32_t*>(ospMapFrameBuffer(fb, OSP_FB_ID_OBJECT));
    const auto* inst = static_cast<const std::uint32_t*>(ospMapFrameBuffer(fb, OSP_FB_ID_INSTANCE));
    const Pixel p{color[4 * i + 3], depth[i], prim[i], object[i], inst[i]};
    for (const void* mapped : {(const void*)color, (const void*)depth, (const void*)prim, (const void*)object,
                               (const void*)inst})
      ospUnmapFrameBuffer(mapped, fb);
    ospRelease(fb);
    ospRelease(renderer);
    return p;
  }
};

}  // namespace

TEST_CASE("id channels: scivis records a volume in front of a surface as OSPRay does", "[c_api][frame][volume]") {
  ApiFixture api;
  VolumeBoxScene scene;
  // The ball in front of the back box: the volume, at its first sample where the opacity
  // is above 0 (r < 0.4: t > 1.606; OSPRay 1.616, at its jittered sample; sciray 1.609),
  // not where the ray enters the grid's box (t 1.5).
  const auto ball = scene.at("scivis", 0.05f);
  CHECK(ball.alpha > 0.4f);
  CHECK(ball.depth > 1.6f);
  CHECK(ball.depth < 1.64f);
  CHECK(ball.prim == 0u);
  CHECK(ball.object == 0u);    // its index among the group's volumes
  CHECK(ball.instance == 1u);  // the world's second instance
  // The front box hides the ball: the surface.
  const auto front = scene.at("scivis", -0.25f);
  CHECK(front.depth == Approx(1.2f).margin(1e-3f));
  CHECK(front.object == 0u);
  CHECK(front.instance == 1u);
  // Beside the ball, where the volume is transparent, the back box.
  const auto back = scene.at("scivis", 0.55f);
  CHECK(back.depth == Approx(2.6f).margin(1e-3f));
  CHECK(back.object == 1u);
  CHECK(back.prim == 0u);
  CHECK(api.messages.errors.empty());
}

TEST_CASE("id channels: the ao renderer gives volumes no ids and no depth", "[c_api][frame][volume]") {
  ApiFixture api;
  VolumeBoxScene scene;
  const auto ball = scene.at("ao", 0.05f);
  CHECK(ball.alpha > 0.4f);
  CHECK(ball.depth == Approx(2.6f).margin(1e-3f));  // the box behind it
  CHECK(ball.object == 1u);
  CHECK(api.messages.errors.empty());
}

TEST_CASE("id channels: the path tracer records its first collision in a volume", "[c_api][frame][volume]") {
  ApiFixture api;
  VolumeBoxScene scene;
  const auto ball = scene.at("pathtracer", 0.05f);
  CHECK(ball.alpha == 1.f);
  CHECK(ball.depth > 1.5f);
  CHECK(ball.depth < 2.f);  // inside the ball: the dense volume stops every path there
  CHECK(ball.prim == 0u);
  CHECK(ball.object == 0u);
  CHECK(ball.instance == 1u);
  CHECK(api.messages.errors.empty());
}

TEST_CASE("id channels: user ids of models and instances replace their indices", "[c_api][frame][volume]") {
  ApiFixture api;
  VolumeBoxScene scene;
  ospSetUInt(scene.volume, "id", 3u);
  ospCommit(scene.volume);
  ospSetUInt(scene.boxes[0], "id", 44u);
  ospCommit(scene.boxes[0]);
  ospSetUInt(scene.instance, "id", 7u);
  ospCommit(scene.instance);
  ospCommit(scene.group);
  ospCommit(scene.world);
  for (const char* renderer : {"scivis", "pathtracer"}) {
    INFO(renderer);
    const auto ball = scene.at(renderer, 0.05f);
    CHECK(ball.object == 3u);
    CHECK(ball.instance == 7u);
    const auto front = scene.at(renderer, -0.25f);
    CHECK(front.object == 44u);
    CHECK(front.instance == 7u);
    const auto back = scene.at(renderer, 0.55f);
    CHECK(back.object == 1u);  // no id: its index
    CHECK(back.instance == 7u);
  }
  const auto nothing = scene.at("scivis", 0.75f);
  CHECK(nothing.object == none);
  CHECK(nothing.instance == none);
  CHECK(api.messages.errors.empty());
}

TEST_CASE("id channels: an id of another type than uint is an error naming it", "[c_api][frame]") {
  ApiFixture api;
  VolumeBoxScene scene;
  ospSetInt(scene.volume, "id", 3);
  ospCommit(scene.volume);
  api.expect_error("volumetric model: parameter 'id' must be a uint");
  ospSetFloat(scene.boxes[0], "id", 1.f);
  ospCommit(scene.boxes[0]);
  api.expect_error("geometric model: parameter 'id' must be a uint");
  ospSetInt(scene.instance, "id", 2);
  ospCommit(scene.instance);
  api.expect_error("instance: parameter 'id' must be a uint");
}

namespace {

/// A volume over [-1, 1]³ of n³ vertices valued f(x) (x in [0, 1] across the grid), a
/// white transfer function of opacity 0 to 1 over [0, 1], with `id` 9; optionally a box
/// behind it (z in [-3, -2.5]) with `id` 7. An orthographic camera from `position` along
/// `direction` (up +y) sees `width` × `width`·H/W.
struct GridScene {
  std::vector<float> voxels;
  OSPWorld world = ospNewWorld();
  OSPCamera camera = ospNewCamera("orthographic");

  template <class F>
  GridScene(int n, F f, float density, bool box_behind) {
    voxels.resize(static_cast<std::size_t>(n) * n * n);
    for (std::size_t i = 0; i < voxels.size(); ++i) voxels[i] = f(static_cast<float>(i % n) / (n - 1));
    OSPVolume v = ospNewVolume("structuredRegular");
    OSPData data = ospNewSharedData3D(voxels.data(), OSP_FLOAT, n, n, n);
    ospSetObject(v, "data", data);
    ospSetVec3f(v, "gridOrigin", -1.f, -1.f, -1.f);
    const float spacing = 2.f / (n - 1);
    ospSetVec3f(v, "gridSpacing", spacing, spacing, spacing);
    ospCommit(v);
    OSPTransferFunction tf = ospNewTransferFunction("piecewiseLinear");
    const float color[6] = {1, 1, 1, 1, 1, 1}, opacity[2] = {0, 1}, range[2] = {0, 1};
    OSPData colors = ospNewSharedData1D(color, OSP_VEC3F, 2), opacities = ospNewSharedData1D(opacity, OSP_FLOAT, 2);
    ospSetObject(tf, "color", colors);
    ospSetObject(tf, "opacity", opacities);
    ospSetParam(tf, "value", OSP_BOX1F, range);
    ospCommit(tf);
    OSPVolumetricModel model = ospNewVolumetricModel(v);
    ospSetObject(model, "transferFunction", tf);
    ospSetFloat(model, "densityScale", density);
    ospSetUInt(model, "id", 9u);
    ospCommit(model);
    OSPGroup group = ospNewGroup();
    ospSetObjectAsData(group, "volume", OSP_VOLUMETRIC_MODEL, model);
    OSPGeometry box = ospNewGeometry("box");
    OSPGeometricModel box_model = ospNewGeometricModel(box);
    if (box_behind) {
      const float b[6] = {-3.f, -3.f, -3.f, 3.f, 3.f, -2.5f};
      OSPData shared = ospNewSharedData1D(b, OSP_BOX3F, 1), boxes = ospNewData1D(OSP_BOX3F, 1);
      ospCopyData1D(shared, boxes, 0);  // b is gone when the box is used
      ospSetObject(box, "box", boxes);
      ospCommit(box);
      ospSetUInt(box_model, "id", 7u);
      ospCommit(box_model);
      ospSetObjectAsData(group, "geometry", OSP_GEOMETRIC_MODEL, box_model);
      ospRelease(shared);
      ospRelease(boxes);
    }
    ospCommit(group);
    OSPInstance instance = ospNewInstance(group);
    ospCommit(instance);
    ospSetObjectAsData(world, "instance", OSP_INSTANCE, instance);
    ospCommit(world);
    for (OSPObject o : {(OSPObject)data, (OSPObject)colors, (OSPObject)opacities, (OSPObject)v, (OSPObject)tf,
                        (OSPObject)model, (OSPObject)box, (OSPObject)box_model, (OSPObject)group, (OSPObject)instance})
      ospRelease(o);
  }
  ~GridScene() {
    ospRelease(world);
    ospRelease(camera);
  }

  void look(const float (&position)[3], const float (&direction)[3], float width, int w, int h) {
    ospSetParam(camera, "position", OSP_VEC3F, position);
    ospSetParam(camera, "direction", OSP_VEC3F, direction);
    ospSetVec3f(camera, "up", 0.f, 1.f, 0.f);
    ospSetFloat(camera, "height", width * h / w);
    ospSetFloat(camera, "aspect", static_cast<float>(w) / h);
    ospCommit(camera);
  }

  /// The object id channel of a w × h scivis frame (rows from the bottom).
  std::vector<std::uint32_t> object_ids(int w, int h, float min_contribution = 0.001f) const {
    OSPRenderer renderer = ospNewRenderer("scivis");
    ospSetFloat(renderer, "minContribution", min_contribution);
    ospCommit(renderer);
    OSPFrameBuffer fb = ospNewFrameBuffer(w, h, OSP_FB_RGBA32F, OSP_FB_COLOR | OSP_FB_ID_OBJECT);
    ospRenderFrameBlocking(fb, renderer, camera, world);
    const auto* ids = static_cast<const std::uint32_t*>(ospMapFrameBuffer(fb, OSP_FB_ID_OBJECT));
    std::vector<std::uint32_t> out(ids, ids + static_cast<std::size_t>(w) * h);
    ospUnmapFrameBuffer(ids, fb);
    ospRelease(fb);
    ospRelease(renderer);
    return out;
  }
};

}  // namespace

TEST_CASE("id channels: scivis sees a volume only where a step absorbs more than minContribution",
          "[c_api][frame][volume]") {
  // Opacity rising along x from 0 to 1 over [-1, 1], density 0.032, steps of 1/16 (33³
  // vertices) seen along -z in front of the box: a step absorbs more than 0.001 where the
  // opacity is above 0.5003, x > 0.0005; above 0.0005 (minContribution 0.0005) where it is
  // above 0.25, x > -0.5. Measured with OSPRay 3.1's runtime on this scene (64 columns over
  // x in [-1.2, 1.2]): the volume from column 32 on (x 0.019; column 31 at x -0.019 shows
  // the box), and from column 19 on (x -0.469; column 18 at -0.506) at 0.0005.
  ApiFixture api;
  GridScene scene(33, [](float x) { return x; }, 0.032f, true);
  constexpr int w = 64, h = 4;
  scene.look({0.f, 0.f, 5.f}, {0.f, 0.f, -1.f}, 2.4f, w, h);
  const auto column = [&](const std::vector<std::uint32_t>& ids, int c) { return ids[(h / 2) * w + c]; };
  const auto ids = scene.object_ids(w, h);
  CHECK(column(ids, 16) == 7u);  // x -0.58
  CHECK(column(ids, 31) == 7u);
  CHECK(column(ids, 32) == 9u);
  CHECK(column(ids, 48) == 9u);  // x 0.62
  const auto finer = scene.object_ids(w, h, 0.0005f);
  CHECK(column(finer, 18) == 7u);
  CHECK(column(finer, 19) == 9u);
  CHECK(api.messages.errors.empty());
}

TEST_CASE("id channels: scivis sees a volume where a ray crosses at least half of OSPRay's step of it",
          "[c_api][frame][volume]") {
  // An opaque volume (density 10) of cell 0.125 seen at 45° across its edge x = 1, z = -1:
  // a ray d from the edge crosses 2d of it. OSPRay samples at (k + jitter) steps of
  // Open VKL's length along the ray, a cell along the axis the ray crosses fastest:
  // 0.125·√2 here. Measured with OSPRay 3.1's runtime, the share of 256 rows that show the
  // volume, by crossing / cell: 0.31: 0.23, 0.56: 0.36, 0.81: 0.55, 1.19: 0.84, 1.44: 1.
  // sciray shows it where the crossing is half a step or more (0.71 cells).
  ApiFixture api;
  GridScene scene(17, [](float) { return 1.f; }, 10.f, false);
  constexpr float s = 0.70710678f, cell = 0.125f;
  constexpr int w = 32, h = 8;
  scene.look({1.f - 5.f * s, 0.f, -1.f - 5.f * s}, {s, 0.f, s}, 2.f * cell, w, h);
  const auto ids = scene.object_ids(w, h);
  // Column c is (c + 0.5)/32·0.25 − 0.125 from the edge, into the volume: crossing/cell = (2c + 1)/16 − 2.
  const auto shows_volume = [&](float crossing_per_cell) {
    const int c = static_cast<int>(std::lround(((crossing_per_cell + 2.f) * 16.f - 1.f) / 2.f));
    bool all = true;
    for (int row = 0; row < h; ++row) all = all && ids[row * w + c] == 9u;
    return all;
  };
  CHECK_FALSE(shows_volume(-0.0625f));
  CHECK_FALSE(shows_volume(0.3125f));
  CHECK_FALSE(shows_volume(0.5625f));  // OSPRay's step, not a cell: half a cell would show it
  CHECK(shows_volume(0.8125f));
  CHECK(shows_volume(1.1875f));
  CHECK(api.messages.errors.empty());
}
