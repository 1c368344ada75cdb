// The OSPRay C API: unstructured volumes (see test_c_api.cpp), against closed forms.
#include <catch2/catch.hpp>

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

/// The unit cube's corners in VTK's hexahedron order, and the cube cut into cells of one
/// OSPRay type: 1 hexahedron, 2 wedges, 3 pyramids or 6 tetrahedra.
const std::vector<float> unit_cube_corners = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1};

struct CubeCells {
  std::uint8_t type;
  std::vector<std::vector<std::uint32_t>> cells;
};
const CubeCells cube_cuts[] = {
    {OSP_HEXAHEDRON, {{0, 1, 2, 3, 4, 5, 6, 7}}},
    {OSP_WEDGE, {{0, 1, 3, 4, 5, 7}, {1, 2, 3, 5, 6, 7}}},
    {OSP_PYRAMID, {{0, 1, 5, 4, 6}, {0, 4, 7, 3, 6}, {0, 3, 2, 1, 6}}},
    {OSP_TETRAHEDRON, {{0, 1, 2, 6}, {0, 2, 3, 6}, {0, 3, 7, 6}, {0, 7, 4, 6}, {0, 4, 5, 6}, {0, 5, 1, 6}}}};

/// Sets the cube's cells of `cut` on `volume`, vertex values f(z) at the corners.
void set_cube(OSPVolume volume, const CubeCells& cut, float (*f)(float z)) {
  std::vector<std::uint32_t> index, cell_index;
  std::vector<std::uint8_t> types;
  for (const auto& c : cut.cells) {
    cell_index.push_back(static_cast<std::uint32_t>(index.size()));
    types.push_back(cut.type);
    index.insert(index.end(), c.begin(), c.end());
  }
  std::vector<float> values;
  for (int v = 0; v < 8; ++v) values.push_back(f(unit_cube_corners[3 * v + 2]));
  set_array(volume, "vertex.position", unit_cube_corners.data(), OSP_VEC3F, 8);
  set_array(volume, "vertex.data", values.data(), OSP_FLOAT, 8);
  set_array(volume, "index", index.data(), OSP_UINT, index.size());
  set_array(volume, "cell.index", cell_index.data(), OSP_UINT, cell_index.size());
  set_array(volume, "cell.type", types.data(), OSP_UCHAR, types.size());
}

}  // namespace

TEST_CASE("unstructured volume: the unit cube in every cell type renders the closed form", "[c_api][volume][unstructured]") {
  ApiFixture api;
  for (const CubeCells& cut : cube_cuts) {
    INFO("cell type " << static_cast<int>(cut.type));
    VolumeScene scene("unstructured");
    // A constant value 1 at opacity 0.5 and densityScale 4: sigma 2 along the crossing of
    // length 1, alpha 1 - exp(-2), whatever the sampling rate.
    set_cube(scene.volume, cut, [](float) { return 1.f; });
    scene.commit_model(new_transfer_function({1.f, 0.5f, 0.25f}, {0.5f}, 0.f, 2.f), 4.f);
    for (float rate : {0.5f, 1.f, 3.7f}) {
      INFO("volumeSamplingRate " << rate);
      ospSetFloat(scene.renderer, "volumeSamplingRate", rate);
      ospCommit(scene.renderer);
      const auto c = scene.centre();
      CHECK(c[3] == Approx(1.f - std::exp(-2.f)).epsilon(1e-5));
      CHECK(c[1] == Approx(0.5f * (1.f - std::exp(-2.f))).epsilon(1e-5));
    }
    // A value rising linearly along the ray, v = z, with opacity v on [0, 1]: sigma = 4 z,
    // its integral 2, and the midpoint rule is exact for a linear sigma.
    set_cube(scene.volume, cut, [](float z) { return z; });
    scene.commit_model(new_transfer_function({1.f, 1.f, 1.f, 1.f, 1.f, 1.f}, {0.f, 1.f}, 0.f, 1.f), 4.f);
    CHECK(scene.centre()[3] == Approx(1.f - std::exp(-2.f)).epsilon(1e-4));
  }
  CHECK(api.messages.errors.empty());
}

TEST_CASE("unstructured volume: cell values, and the background outside the cells", "[c_api][volume][unstructured]") {
  ApiFixture api;
  VolumeScene scene("unstructured");
  set_cube(scene.volume, cube_cuts[3], [](float) { return 0.f; });
  // cell.data takes precedence over vertex.data, as in OSPRay: six tetrahedra of value 1.
  const std::vector<float> ones(6, 1.f);
  set_array(scene.volume, "cell.data", ones.data(), OSP_FLOAT, 6);
  scene.commit_model(new_transfer_function({1.f, 1.f, 1.f}, {0.5f}, 0.f, 2.f), 4.f);
  CHECK(scene.centre()[3] == Approx(1.f - std::exp(-2.f)).epsilon(1e-5));
  // Half the cube: the three tetrahedra on the side x > y. Rays through the other half
  // cross no cell, and the background (NaN by default) is transparent.
  const std::vector<std::uint32_t> half_index = {0, 1, 2, 6, 0, 4, 5, 6, 0, 5, 1, 6}, half_cells = {0, 4, 8};
  const std::vector<std::uint8_t> half_types(3, OSP_TETRAHEDRON);
  set_array(scene.volume, "index", half_index.data(), OSP_UINT, 12);
  set_array(scene.volume, "cell.index", half_cells.data(), OSP_UINT, 3);
  set_array(scene.volume, "cell.type", half_types.data(), OSP_UCHAR, 3);
  set_array(scene.volume, "cell.data", ones.data(), OSP_FLOAT, 3);
  scene.commit_model(new_transfer_function({1.f, 1.f, 1.f}, {0.5f}, 0.f, 2.f), 4.f);
  const auto image = scene.render(16);
  // The camera looks along +z with y up, so the image's x runs along the world's -x.
  const auto alpha_at = [&](int x, int y) { return image[4 * (16 * y + x) + 3]; };
  CHECK(alpha_at(3, 3) == Approx(1.f - std::exp(-2.f)).epsilon(1e-5));  // world (0.8, 0.2): through the cells
  CHECK(alpha_at(12, 12) == 0.f);                                        // world (0.2, 0.8): no cell
  CHECK(api.messages.errors.empty());
}

TEST_CASE("unstructured volume: instance transforms place it, and every renderer integrates it",
          "[c_api][volume][unstructured][instancing]") {
  ApiFixture api;
  VolumeScene scene("unstructured");
  set_cube(scene.volume, cube_cuts[3], [](float) { return 1.f; });
  scene.commit_model(new_transfer_function({1.f, 1.f, 1.f}, {1.f}, 0.f, 1.f));
  scene.check_placed_by_instance_transforms();
  // Left turned, 1 thick: the ao renderer and the path tracer integrate it too.
  OSPRenderer ao = ospNewRenderer("ao");
  ospCommit(ao);
  CHECK(scene.centre_with(ao)[3] == Approx(1.f - std::exp(-1.f)).epsilon(1e-5));
  ospRelease(ao);
  CHECK(std::abs(scene.path_traced_alpha() - (1.0 - std::exp(-1.0))) < 0.011);
  CHECK(api.messages.errors.empty());
}

TEST_CASE("unstructured volume: bad input is named through the error callback", "[c_api][volume][unstructured][errors]") {
  ApiFixture api;
  OSPVolume volume = ospNewVolume("unstructured");
  ospCommit(volume);
  api.expect_error("ospCommit: unstructured volume: required parameter 'vertex.position' (array of vec3f) is missing");
  set_cube(volume, cube_cuts[0], [](float z) { return z; });
  const std::uint32_t bad_index[8] = {0, 1, 2, 3, 4, 5, 6, 8};
  set_array(volume, "index", bad_index, OSP_UINT, 8);
  ospCommit(volume);
  api.expect_error("unstructured volume: cell 0 refers to vertex 8 but 'vertex.position' has 8");
  set_cube(volume, cube_cuts[0], [](float z) { return z; });
  const std::uint8_t quad = 9;
  set_array(volume, "cell.type", &quad, OSP_UCHAR, 1);
  ospCommit(volume);
  api.expect_error("unstructured volume: cell 0 has type 9, which is none of tetrahedron (10), hexahedron (12), wedge "
                   "(13), pyramid (14)");
  set_cube(volume, cube_cuts[0], [](float z) { return z; });
  const float index_as_float = 0.f;
  set_array(volume, "cell.index", &index_as_float, OSP_FLOAT, 1);
  ospCommit(volume);
  api.expect_error("unstructured volume: parameter 'cell.index'");
  set_cube(volume, cube_cuts[0], [](float z) { return z; });
  ospCommit(volume);
  CHECK(api.messages.errors.empty());
  // Values constant in each cell have no isosurface: a named error, not a wrong image.
  const float one = 1.f;
  ospRemoveParam(volume, "vertex.data");
  set_array(volume, "cell.data", &one, OSP_FLOAT, 1);
  ospCommit(volume);
  CHECK(api.messages.errors.empty());
  OSPGeometry iso = ospNewGeometry("isosurface");
  ospSetObject(iso, "volume", volume);
  ospSetFloat(iso, "isovalue", 0.5f);
  ospCommit(iso);
  api.expect_error("isosurface: the unstructured volume has 'cell.data', constant in each cell, which has no isosurface");
  ospRelease(iso);
  ospRelease(volume);
}

TEST_CASE("unstructured volume: its isosurface in every cell type is the analytic plane", "[c_api][isosurface][unstructured]") {
  ApiFixture api;
  // f = (x + 2y + 3z) / 6 at the unit cube's corners: every cell type reproduces a linear
  // field, so f = 0.5 is the plane x + 2y + 3z = 3, met from (x, y, −5) down +z at
  // z = (3 − x − 2y) / 3.
  std::vector<float> linear;
  for (int v = 0; v < 8; ++v)
    linear.push_back((unit_cube_corners[3 * v] + 2 * unit_cube_corners[3 * v + 1] + 3 * unit_cube_corners[3 * v + 2]) / 6.f);
  for (const CubeCells& cut : cube_cuts) {
    INFO("cell type " << static_cast<int>(cut.type));
    OSPVolume volume = ospNewVolume("unstructured");
    set_cube(volume, cut, [](float z) { return z; });
    set_array(volume, "vertex.data", linear.data(), OSP_FLOAT, 8);
    ospCommit(volume);
    OSPGeometry iso = ospNewGeometry("isosurface");
    ospSetObject(iso, "volume", volume);
    ospSetFloat(iso, "isovalue", 0.5f);
    ospCommit(iso);
    GeometryScene scene(iso, true);
    Picker pick;
    for (const auto& [x, y] : {std::pair{0.3f, 0.4f}, std::pair{0.9f, 0.1f}, std::pair{0.05f, 0.6f}, std::pair{0.5f, 0.5f}}) {
      INFO("pick at x = " << x << ", y = " << y);
      const OSPPickResult hit = pick(scene.world, {x, y, -5.f});
      check_position(hit, x, y, (3.f - x - 2 * y) / 3.f);
      CHECK(hit.primID == 0);
      release_pick(hit);
    }
    OSPPickResult miss = pick(scene.world, {1.2f, 0.5f, -5.f});  // beside the cells
    CHECK(miss.hasHit == 0);
    release_pick(miss);
    ospRelease(volume);
  }
  CHECK(api.messages.errors.empty());
}
