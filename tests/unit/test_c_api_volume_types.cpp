// The OSPRay C API: the particle, structuredSpherical, vdb and amr volumes with OSPRay's
// parameters, each against an analytic field's closed-form integral (see test_c_api.cpp).
#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include <ospray/ospray.h>
#include <ospray/ospray_util.h>

#include "sciray/shim/engine.hpp"
#include "support/api_fixture.hpp"
#include "support/c_api_scenes.hpp"

using namespace sciray_test;

namespace {

/// The alpha of the one ray a 1x1 frame casts through the pixel's centre, (0.5, 0.5)
/// along +z, with the point pixel filter (no offset), at `rate` samples per cell.
float alpha_through_centre(VolumeScene& scene, float rate) {
  ospSetInt(scene.renderer, "pixelFilter", OSP_PIXELFILTER_POINT);
  ospSetFloat(scene.renderer, "volumeSamplingRate", rate);
  ospCommit(scene.renderer);
  return scene.centre(1)[3];
}

}  // namespace

TEST_CASE("particle volume: one Gaussian's line integral, its isosurface and its bounds", "[c_api][volume][particle]") {
  ApiFixture api;
  VolumeScene scene("particle");
  // w exp(−d²/2r²) cut off at 3r, opacity = value on [0, 1], densityScale D: through the
  // centre ∫σ = D w r √(2π) erf(3/√2).
  const float centre[3] = {0.5f, 0.5f, 0.5f}, radius = 0.1f, weight = 0.8f, density = 6.f;
  set_array(scene.volume, "particle.position", centre, OSP_VEC3F, 1);
  set_array(scene.volume, "particle.radius", &radius, OSP_FLOAT, 1);
  set_array(scene.volume, "particle.weight", &weight, OSP_FLOAT, 1);
  scene.commit_model(new_transfer_function({1.f, 1.f, 1.f, 1.f, 1.f, 1.f}, {0.f, 1.f}, 0.f, 1.f), density);
  check_bounds(ospGetBounds(scene.volume), {0.2f, 0.2f, 0.2f}, {0.8f, 0.8f, 0.8f});
  const double depth = density * weight * radius * std::sqrt(2 * M_PI) * std::erf(3 / std::sqrt(2.0));
  CHECK(alpha_through_centre(scene, 8.f) == Approx(1 - std::exp(-depth)).epsilon(2e-3));
  // The isosurface of value 0.4 is the sphere d = r √(2 ln(w / 0.4)), met from below.
  OSPGeometry iso = ospNewGeometry("isosurface");
  ospSetObject(iso, "volume", scene.volume);
  ospSetFloat(iso, "isovalue", 0.4f);
  ospCommit(iso);
  GeometryScene surface(iso, true);
  Picker pick;
  const OSPPickResult hit = pick(surface.world, {0.5f, 0.5f, -5.f});
  check_position(hit, 0.5f, 0.5f, 0.5f - radius * std::sqrt(2.f * std::log(weight / 0.4f)), 1e-4f);
  release_pick(hit);
  // Bad input is named.
  const float negative = -1.f;
  set_array(scene.volume, "particle.radius", &negative, OSP_FLOAT, 1);
  ospCommit(scene.volume);
  api.expect_error("particle volume: 'particle.radius' 0 must be finite and greater than 0, got -1");
  CHECK(api.messages.errors.empty());
}

TEST_CASE("structuredSpherical volume: a constant shell absorbs along its chord", "[c_api][volume][spherical]") {
  ApiFixture api;
  VolumeScene scene("structuredSpherical");
  // Value 1 on radius [1, 2], inclination [0, 180], azimuth [0, 360] (2 x 3 x 5 vertices),
  // moved to the camera's axis by the instance: the ray at distance h = 0 from the centre
  // crosses the shell twice, 2 units in all.
  const std::vector<float> ones(2 * 3 * 5, 1.f);
  OSPData data = ospNewSharedData3D(ones.data(), OSP_FLOAT, 2, 3, 5);
  ospSetObject(scene.volume, "data", data);
  ospRelease(data);
  ospSetVec3f(scene.volume, "gridOrigin", 1.f, 0.f, 0.f);
  ospSetVec3f(scene.volume, "gridSpacing", 1.f, 90.f, 90.f);
  scene.commit_model(new_transfer_function({1.f, 1.f, 1.f}, {0.5f}, 0.f, 2.f));
  const OSPBounds shell = ospGetBounds(scene.volume);  // the sphere's box, padded by a hair
  for (int k = 0; k < 3; ++k) {
    CHECK(shell.lower[k] == Approx(-2.f).margin(1e-3));
    CHECK(shell.upper[k] == Approx(2.f).margin(1e-3));
  }
  set_transform(scene.instance, scale_then_move(1, 1, 1, 0.5f, 0.5f, 0.f));
  ospCommit(scene.instance);
  ospCommit(scene.world);
  CHECK(alpha_through_centre(scene, 64.f) == Approx(1 - std::exp(-0.5 * 2.0)).epsilon(1e-2));
  const float bad_spacing[3] = {1.f, 0.f, 90.f};
  ospSetVec3f(scene.volume, "gridSpacing", bad_spacing[0], bad_spacing[1], bad_spacing[2]);
  ospCommit(scene.volume);
  api.expect_error("structuredSpherical volume: 'gridSpacing'");
  CHECK(api.messages.errors.empty());
}

TEST_CASE("vdb volume: a dense leaf and a tile, placed by indexToObject", "[c_api][volume][vdb]") {
  ApiFixture api;
  VolumeScene scene("vdb");
  // Two level-3 nodes side by side along z: a dense leaf of 1s at index (0, 0, 0) and a
  // tile of 1 at (0, 0, 8), scaled into [0, 1] x [0, 1] x [0, 2] by indexToObject. Voxel i
  // sits at index i, so the last voxel layer blends with the background (NaN,
  // transparent): along z the value is 1 over index [0, 15], object length 15/8.
  const std::uint32_t levels[2] = {3, 3};
  const std::int32_t origins[6] = {0, 0, 0, 0, 0, 8};
  set_array(scene.volume, "node.level", levels, OSP_UINT, 2);
  set_array(scene.volume, "node.origin", origins, OSP_VEC3I, 2);
  const std::vector<float> dense(512, 1.f), tile(1, 1.f);
  OSPData leaf = ospNewSharedData3D(dense.data(), OSP_FLOAT, 8, 8, 8);
  OSPData constant = ospNewSharedData1D(tile.data(), OSP_FLOAT, 1);
  OSPData nodes[2] = {leaf, constant};
  OSPData list = ospNewSharedData1D(nodes, OSP_DATA, 2);
  ospSetObject(scene.volume, "node.data", list);
  ospRelease(list);
  ospRelease(leaf);
  ospRelease(constant);
  const float index_to_object[12] = {0.125f, 0.f, 0.f, 0.f, 0.125f, 0.f, 0.f, 0.f, 0.125f, 0.f, 0.f, 0.f};
  set_array(scene.volume, "indexToObject", index_to_object, OSP_FLOAT, 12);
  scene.commit_model(new_transfer_function({1.f, 1.f, 1.f}, {0.5f}, 0.f, 2.f), 2.f);
  check_bounds(ospGetBounds(scene.volume), {0.f, 0.f, 0.f}, {1.f, 1.f, 2.f});
  CHECK(alpha_through_centre(scene, 1.f) == Approx(1 - std::exp(-1.0 * 15.0 / 8.0)).epsilon(1e-4));
  const std::uint32_t bad_level = 5;
  set_array(scene.volume, "node.level", &bad_level, OSP_UINT, 1);
  ospCommit(scene.volume);
  api.expect_error("vdb volume:");
  CHECK(api.messages.errors.empty());
}

TEST_CASE("amr volume: a refined block inside a coarse one, a constant and a stepped field", "[c_api][volume][amr]") {
  ApiFixture api;
  VolumeScene scene("amr");
  // Level 0: 4³ cells of width 1; level 1 (width 0.5): cells [2, 5]³, the middle of the
  // domain; gridSpacing 0.25 maps AMR space [0, 4]³ onto the camera's [0, 1]³.
  const std::int32_t bounds[12] = {0, 0, 0, 3, 3, 3, 2, 2, 2, 5, 5, 5};
  const std::int32_t levels[2] = {0, 1};
  const float widths[2] = {1.f, 0.5f};
  set_array(scene.volume, "block.bounds", bounds, OSP_BOX3I, 2);
  set_array(scene.volume, "block.level", levels, OSP_INT, 2);
  set_array(scene.volume, "cellWidth", widths, OSP_FLOAT, 2);
  ospSetVec3f(scene.volume, "gridSpacing", 0.25f, 0.25f, 0.25f);
  std::vector<float> coarse_cells, fine_cells;  // shared with the volume: alive while it is
  const auto set_values = [&](float coarse, float fine) {
    coarse_cells.assign(64, coarse), fine_cells.assign(64, fine);
    OSPData blocks[2] = {ospNewSharedData1D(coarse_cells.data(), OSP_FLOAT, 64),
                         ospNewSharedData1D(fine_cells.data(), OSP_FLOAT, 64)};
    OSPData shared_list = ospNewSharedData1D(blocks, OSP_DATA, 2), list = ospNewData1D(OSP_DATA, 2);
    ospCopyData1D(shared_list, list, 0);  // the handles are copied: `blocks` may go
    ospSetObject(scene.volume, "block.data", list);
    ospRelease(shared_list);
    ospRelease(list);
    ospRelease(blocks[0]);
    ospRelease(blocks[1]);
  };
  set_values(1.f, 1.f);
  scene.commit_model(new_transfer_function({1.f, 1.f, 1.f, 1.f, 1.f, 1.f}, {0.f, 1.f}, 0.f, 2.f), 2.f);
  check_bounds(ospGetBounds(scene.volume), {0.f, 0.f, 0.f}, {1.f, 1.f, 1.f});
  // Constant 1 at opacity ½ and densityScale 2 over the unit crossing: 1 − e⁻¹.
  CHECK(alpha_through_centre(scene, 2.f) == Approx(1 - std::exp(-1.0)).epsilon(1e-4));
  // The refined block holds 2 and wins where it lies: σ = 2 over its half of the crossing
  // (z in [0.25, 0.75]), 1 elsewhere, so ∫σ = 0.5 + 1 = 1.5, up to the dual cells at the
  // refinement's faces, where values blend over a fine cell (an eighth) either side.
  set_values(1.f, 2.f);
  scene.commit_model(new_transfer_function({1.f, 1.f, 1.f, 1.f, 1.f, 1.f}, {0.f, 1.f}, 0.f, 2.f), 2.f);
  CHECK(alpha_through_centre(scene, 8.f) == Approx(1 - std::exp(-1.5)).epsilon(2e-2));
  const float one_width = 1.f;
  set_array(scene.volume, "cellWidth", &one_width, OSP_FLOAT, 1);
  ospCommit(scene.volume);
  api.expect_error("amr volume:");
  CHECK(api.messages.errors.empty());
}

TEST_CASE("unstructured volume: exact integration through tetrahedra from the renderer's volumeIntegration",
          "[c_api][volume][unstructured][exact]") {
  ApiFixture api;
  VolumeScene scene("unstructured");
  // A tetrahedron's value rises linearly along the ray; opacity = value² is not linear in
  // the value, which the sampled integrator only approximates, and exact integration gets
  // to float rounding. The unit cube's six tetrahedra, value z, opacity table 0, .25, 1.
  const float corners[24] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1};
  const std::uint32_t index[24] = {0, 1, 2, 6, 0, 2, 3, 6, 0, 3, 7, 6, 0, 7, 4, 6, 0, 4, 5, 6, 0, 5, 1, 6};
  const std::uint32_t cells[6] = {0, 4, 8, 12, 16, 20};
  const std::uint8_t types[6] = {OSP_TETRAHEDRON, OSP_TETRAHEDRON, OSP_TETRAHEDRON,
                                 OSP_TETRAHEDRON, OSP_TETRAHEDRON, OSP_TETRAHEDRON};
  std::vector<float> z;
  for (int v = 0; v < 8; ++v) z.push_back(corners[3 * v + 2]);
  set_array(scene.volume, "vertex.position", corners, OSP_VEC3F, 8);
  set_array(scene.volume, "vertex.data", z.data(), OSP_FLOAT, 8);
  set_array(scene.volume, "index", index, OSP_UINT, 24);
  set_array(scene.volume, "cell.index", cells, OSP_UINT, 6);
  set_array(scene.volume, "cell.type", types, OSP_UCHAR, 6);
  scene.commit_model(new_transfer_function({1.f, 1.f, 1.f}, {0.f, 0.25f, 1.f}, 0.f, 1.f), 3.f);
  // ∫σ = 3 ∫ o(z) dz with o piecewise linear through (0, 0), (½, ¼), (1, 1): 3 · (1/16 + 5/16).
  const double exact = 1 - std::exp(-3.0 * (1.0 / 16 + 5.0 / 16));
  ospSetString(scene.renderer, "volumeIntegration", "exact");
  CHECK(alpha_through_centre(scene, 0.25f) == Approx(exact).epsilon(1e-5));
  ospSetString(scene.renderer, "volumeIntegration", "sampled");
  CHECK(std::abs(alpha_through_centre(scene, 0.25f) - exact) > 1e-3);  // a coarse step is off
  ospSetString(scene.renderer, "volumeIntegration", "analytic");
  ospCommit(scene.renderer);
  api.expect_error("parameter 'volumeIntegration' has unknown value 'analytic' (sampled, preintegrated, exact)");
  CHECK(api.messages.errors.empty());
}
