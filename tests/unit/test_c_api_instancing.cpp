// The OSPRay C API: instancing, box and plane geometry (see test_c_api.cpp).
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

// ---- instancing, box and plane geometry ---------------------------------------------------


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

TEST_CASE("box: picks land on the analytic faces, bounds, colours, instanced boxes", "[c_api][box]") {
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

TEST_CASE("plane: picks land on the analytic plane, bounded planes, colours, instanced planes", "[c_api][plane]") {
  ApiFixture api;
  // z = 2, and x + z = 4 (its normal not normalized) bounded to x in [1, 3]: OSPRay's
  // coefficients mean a·x + b·y + c·z = d (measured against OSPRay 3.1's runtime).
  const float planes[2][4] = {{0.f, 0.f, 1.f, 2.f}, {2.f, 0.f, 2.f, 8.f}};
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

TEST_CASE("compactMode and dynamicScene of groups and worlds: the same image, and compact leaves take less memory",
          "[c_api][instancing][memory]") {
  ApiFixture api;
  log_debug(api.device);
  BunnyScene scene;
  const auto build = [&](bool compact, bool dynamic) {
    for (OSPObject o : {static_cast<OSPObject>(scene.group), static_cast<OSPObject>(scene.world)}) {
      ospSetBool(o, "compactMode", compact);
      ospSetBool(o, "dynamicScene", dynamic);
    }
    ospCommit(scene.group);
    ospCommit(scene.instance);
    ospCommit(scene.world);
    std::vector<std::uint8_t> image = render_rgba8(scene, 96, 96);
    const std::uint64_t memory = reported_memory(last_build_summary(api.messages));
    return std::pair{std::move(image), memory};
  };
  const auto [fast, fast_memory] = build(false, false);
  const auto [compact, compact_memory] = build(true, false);
  const auto [dynamic, dynamic_memory] = build(false, true);
  CHECK(api.messages.errors.empty());
  CHECK_FALSE(api.messages.any_status_containing("compactMode"));  // read, not reported unused
  // The bunny's 69,451 triangles: leaves that index the vertices instead of copying them.
  INFO("engine memory: fast " << fast_memory << ", compact " << compact_memory << ", dynamic " << dynamic_memory);
  CHECK(compact_memory < fast_memory * 3 / 4);
  // Every layout finds the same surfaces: no 8-bit channel differs by more than one step.
  for (const auto* other : {&compact, &dynamic}) {
    int differing = 0;
    for (std::size_t i = 0; i < fast.size(); ++i) differing += std::abs(int(fast[i]) - int((*other)[i])) > 1;
    CHECK(differing == 0);
  }
}
