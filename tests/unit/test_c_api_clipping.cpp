// The OSPRay C API: clipping geometry (see test_c_api.cpp).
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

// ---- clipping geometry ---------------------------------------------------------------------


TEST_CASE("clipping: a sphere bites the cube's front face, picks and frames reach the back face",
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

TEST_CASE("clipping: a closed mesh clips its inside, meshes must be closed, at most 64", "[c_api][clipping]") {
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

TEST_CASE("clipping: a round curve in a turned and scaled and moved instance clips the inside of its tube",
          "[c_api][clipping][curves]") {
  ApiFixture api;
  ClipScene scene;
  // A tube of radius 0.15 from (-0.25, 0, 0) to (0.25, 0, 0) (OSPRay's constant-radius
  // form), turned 90 degrees about z, scaled by 2 and moved to (0.2, 0.1, -1): the tube
  // of radius 0.3 from (0.2, -0.4, -1) to (0.2, 0.6, -1) through the front face, which
  // it cuts in a stadium.
  const float position[6] = {-0.25f, 0.f, 0.f, 0.25f, 0.f, 0.f};
  const std::uint32_t index = 0;
  OSPGeometry g = ospNewGeometry("curve");
  set_array(g, "vertex.position", position, OSP_VEC3F, 2);
  set_array(g, "index", &index, OSP_UINT, 1);
  ospSetFloat(g, "radius", 0.15f);
  ospCommit(g);
  OSPGeometricModel tube = new_model(g);
  scene.clip({tube}, rotate_then_move(2, 90.f, 0.2f, 0.1f, -1.f, 2.f));
  const auto stadium = [](float x, float y) {
    const float along = std::clamp(y, -0.4f, 0.6f);
    return disc_depth(x, y, 0.2f, along, 0.3f, 6.f, 4.f);
  };
  int checked = 0;
  CHECK(wrong_depths(scene, stadium, &checked) == 0);
  CHECK(checked > 64 * 64 / 3);
  scene.expect_cube(0.2f, 0.55f, 1.f);
  scene.expect_cube(0.2f, 0.85f, 1.f);  // in the end's half disc
  scene.expect_cube(0.2f, 0.95f, -1.f);
  scene.expect_cube(0.45f, 0.f, 1.f);
  scene.expect_cube(0.55f, 0.f, -1.f);
  ospRelease(tube);
  CHECK(api.messages.errors.empty());
}

TEST_CASE("clipping: what cannot clip is named through the error callback", "[c_api][clipping][errors]") {
  ApiFixture api;
  ClipScene scene;
  OSPGeometricModel ball = new_model(new_spheres({0.f, 0.f, -1.f}, 0.5f));
  scene.clip({ball});
  scene.expect_cube(0.f, 0.f, 1.f);
  CHECK(api.messages.errors.empty());

  // Flat curves: at the group's commit, which fails and leaves the group clipping with
  // the ball.
  OSPGeometricModel curve = new_model(new_curves({0, 0, 0, 0.1f, 1, 0, 0, 0.1f}, {0}, OSP_FLAT, OSP_LINEAR));
  set_clipping(scene.clip_group, {curve});
  api.expect_error("ospCommit: group: parameter 'clippingGeometry' element 0: flat curves and ribbons (curve geometry "
                   "of type OSP_FLAT or OSP_RIBBON) enclose nothing and cannot clip; use OSP_ROUND");
  scene.expect_cube(0.f, 0.f, 1.f);

  // Round curves in an instance that scales non-uniformly: at the world's build.
  OSPGeometricModel tube = new_model(new_curves({0, 0, 0, 0.1f, 1, 0, 0, 0.1f}, {0}, OSP_ROUND, OSP_LINEAR));
  scene.clip({tube}, scale_then_move(1, 2, 1, 0, 0, 0));
  const OSPPickResult stretched = scene.pick(scene.world, {0.f, 0.f, -5.f});
  CHECK(stretched.hasHit == 0);
  api.expect_error("ospPick: world: the group of instance 1, parameter 'clippingGeometry' element 0 (curve geometry): "
                   "its instance's transform scales non-uniformly (a round tube becomes elliptic), which clipping "
                   "curves do not support yet");
  scene.clip({ball});
  ospRelease(tube);

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

  // Spheres under a non-uniform scale clip as ellipsoids: the ball scaled by (2, 1, 1)
  // reaches x = ±1 on the front face but only y = ±0.5.
  scene.clip({ball}, scale_then_move(2, 1, 1, 0, 0, 0));
  scene.expect_cube(0.8f, 0.f, 1.f);
  scene.expect_cube(0.f, 0.6f, -1.f);
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

TEST_CASE("clipping: a moving instance's clipping sphere clips where the instance is at the ray's time",
          "[c_api][clipping][motion]") {
  ApiFixture api;
  ClipScene scene;
  // The ball of radius 0.5 on the front face, carried from x = -0.5 at time 0 to
  // x = +0.5 at time 1 by motion.transform; picks at an instant of the shutter.
  OSPGeometricModel ball = new_model(new_spheres({0.f, 0.f, -1.f}, 0.5f));
  set_clipping(scene.clip_group, {ball});
  const std::array<std::array<float, 12>, 2> keys{scale_then_move(1, 1, 1, -0.5f, 0, 0),
                                                  scale_then_move(1, 1, 1, 0.5f, 0, 0)};
  OSPData motion = ospNewSharedData1D(keys.data(), OSP_AFFINE3F, 2);
  ospSetObject(scene.clip_instance, "motion.transform", motion);
  ospRelease(motion);
  ospRemoveParam(scene.clip_instance, "transform");
  ospCommit(scene.clip_instance);
  const auto at = [&](float time) {
    const float shutter[2] = {time, time};
    ospSetParam(scene.pick.camera, "shutter", OSP_BOX1F, shutter);
  };
  at(0.f);
  scene.expect_cube(-0.5f, 0.f, 1.f);  // bitten
  scene.expect_cube(0.5f, 0.f, -1.f);
  at(0.5f);
  scene.expect_cube(0.f, 0.f, 1.f);
  at(0.99f);
  scene.expect_cube(-0.5f, 0.f, -1.f);
  scene.expect_cube(0.5f, 0.f, 1.f);
  at(1.f);  // from the end of its time range on the moving instance is absent, as Embree shows it
  scene.expect_cube(0.5f, 0.f, -1.f);
  ospRelease(ball);
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
