// The OSPRay C API: volumes (see test_c_api.cpp).
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

// ---- volumes ------------------------------------------------------------------------------


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
  // The ao renderer integrates volumes on its rays too.
  OSPRenderer ao = ospNewRenderer("ao");
  ospSetFloat(ao, "volumeSamplingRate", 2.f);
  ospCommit(ao);
  CHECK(scene.centre_with(ao)[3] == Approx(alpha).epsilon(1e-5));
  ospRelease(ao);
  CHECK(std::abs(scene.path_traced_alpha() - alpha) < 0.011);
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

TEST_CASE("volume: the bricked layout renders the linear layout's image, filters", "[c_api][volume][render]") {
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

TEST_CASE("volume: surfaces and volumes in one group, a surface inside the volume ends it",
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
  // The plane z = 0.5 (OSPRay's a·x + b·y + c·z = d) clips z < 0.5: half the depth of sigma = 2.
  const float plane[4] = {0.f, 0.f, 1.f, 0.5f};
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

TEST_CASE("volume: a recommitted transfer function keeps the macrocells, a recommitted volume rebuilds them",
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

TEST_CASE("volume: instance transforms place volumes, one model serves several instances", "[c_api][volume][instancing]") {
  ApiFixture api;
  log_debug(api.device);
  VolumeScene scene;
  scene.commit_constant(new_transfer_function({1.f, 1.f, 1.f}, {1.f}, 0.f, 1.f));
  scene.check_placed_by_instance_transforms();

  // The same model in a second instance, behind the first, of a group that gains its
  // volume after the instance's commit: both show.
  set_transform(scene.instance, scale_then_move(1, 1, 1, 0, 0, 0));
  ospCommit(scene.instance);
  OSPGroup other = new_group({});
  OSPInstance behind = new_instance(other, scale_then_move(1, 1, 1, 0, 0, 2));
  ospRelease(scene.world);
  scene.world = new_world({scene.instance, behind});
  ospSetObjectAsData(other, "volume", OSP_VOLUMETRIC_MODEL, scene.model);
  ospCommit(other);
  CHECK(scene.centre()[3] == Approx(1.f - std::exp(-2.f)).epsilon(1e-5));
  CHECK_THAT(last_build_summary(api.messages), Catch::Contains("1 volumes ("));  // one engine model, placed twice
  CHECK(api.messages.errors.empty());
  for (OSPObject o : std::initializer_list<OSPObject>{other, behind}) ospRelease(o);
}

TEST_CASE("volume: motion.transform moves a volume over the shutter", "[c_api][volume][instancing][motion]") {
  ApiFixture api;
  VolumeScene scene;
  scene.commit_constant(new_transfer_function({1.f, 1.f, 1.f}, {1.f}, 0.f, 1.f));
  // In view at time 0, moved 4 units right (out of view) at time 1.
  const std::array<float, 24> keys{1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 4, 0, 0};
  OSPData data = ospNewSharedData1D(keys.data(), OSP_AFFINE3F, 2);
  ospSetObject(scene.instance, "motion.transform", data);
  ospRelease(data);
  ospCommit(scene.instance);
  for (const auto& [time, expected] : {std::pair{0.f, 1.f - std::exp(-1.f)}, {0.5f, 0.f}}) {
    INFO("shutter at " << time);
    ospSetVec2f(scene.camera, "shutter", time, time);
    ospCommit(scene.camera);
    CHECK(scene.centre()[3] == Approx(expected).margin(1e-5));
  }
  CHECK(api.messages.errors.empty());
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
