// Texture maps through the C API and the tool: a texture2d as map_kd with vertex.texcoord,
// map transforms, the errors bad texcoords and bad maps give, and the tool colouring the
// bunny by its confidence through a colour map.
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include <ospray/ospray.h>
#include <ospray/ospray_util.h>

#include "sciray/io/image.hpp"
#include "sciray/io/ply.hpp"
#include "sciray/math/color.hpp"
#include "sciray/shim/engine.hpp"
#include "support/api_fixture.hpp"
#include "support/checker.hpp"

using namespace sciray;
using sciray::test_support::checker_at;

namespace {

OSPData shared_floats(const std::vector<float>& values, OSPDataType type, std::size_t count) {
  return ospNewSharedData1D(values.data(), type, static_cast<uint32_t>(count));
}

}  // namespace

TEST_CASE("C API: a texture2d as map_kd and vertex.texcoord colour a quad by the checker",
          "[c_api][texture_maps]") {
  sciray_test::ApiFixture api;
  const int n = 4, size = 32;
  const Vec3f a{0.9f, 0.1f, 0.1f}, b{0.1f, 0.2f, 0.9f}, kd{1.f, 0.5f, 0.8f};
  const std::vector<float> positions = {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0};
  const std::vector<std::uint32_t> index = {0, 1, 2, 3};
  const std::vector<float> texcoords = {0, 0, 1, 0, 1, 1, 0, 1};
  std::vector<float> texels;
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const Vec3f c = (x + y) % 2 == 0 ? a : b;
      texels.insert(texels.end(), {c.x, c.y, c.z});
    }

  OSPGeometry mesh = ospNewGeometry("mesh");
  OSPData data = shared_floats(positions, OSP_VEC3F, 4);
  ospSetObject(mesh, "vertex.position", data);
  ospRelease(data);
  data = ospNewSharedData1D(index.data(), OSP_VEC4UI, 1);
  ospSetObject(mesh, "index", data);
  ospRelease(data);
  data = shared_floats(texcoords, OSP_VEC2F, 4);
  ospSetObject(mesh, "vertex.texcoord", data);
  ospRelease(data);
  ospCommit(mesh);

  OSPTexture texture = ospNewTexture("texture2d");
  data = ospNewSharedData2D(texels.data(), OSP_VEC3F, n, n);
  ospSetObject(texture, "data", data);
  ospRelease(data);
  ospSetInt(texture, "format", OSP_TEXTURE_RGB32F);
  ospSetInt(texture, "filter", OSP_TEXTURE_FILTER_NEAREST);
  ospCommit(texture);
  OSPMaterial material = ospNewMaterial("obj");
  ospSetVec3f(material, "kd", kd.x, kd.y, kd.z);  // baked into the geometry's colour: still multiplies
  ospSetObject(material, "map_kd", texture);
  ospCommit(material);
  REQUIRE(api.messages.errors.empty());

  OSPGeometricModel model = ospNewGeometricModel(mesh);
  ospSetObject(model, "material", material);
  ospCommit(model);
  OSPGroup group = ospNewGroup();
  data = ospNewSharedData1D(&model, OSP_GEOMETRIC_MODEL, 1);
  ospSetObject(group, "geometry", data);
  ospRelease(data);
  ospCommit(group);
  OSPInstance instance = ospNewInstance(group);
  ospCommit(instance);
  OSPLight light = ospNewLight("ambient");
  ospCommit(light);
  OSPWorld world = ospNewWorld();
  data = ospNewSharedData1D(&instance, OSP_INSTANCE, 1);
  ospSetObject(world, "instance", data);
  ospRelease(data);
  data = ospNewSharedData1D(&light, OSP_LIGHT, 1);
  ospSetObject(world, "light", data);
  ospRelease(data);
  ospCommit(world);
  OSPCamera camera = ospNewCamera("orthographic");
  ospSetVec3f(camera, "position", 0.f, 0.f, 5.f);
  ospSetVec3f(camera, "direction", 0.f, 0.f, -1.f);
  ospSetFloat(camera, "height", 2.f);
  ospSetFloat(camera, "aspect", 1.f);
  ospCommit(camera);
  OSPRenderer renderer = ospNewRenderer("scivis");
  ospSetInt(renderer, "pixelFilter", OSP_PIXELFILTER_POINT);
  ospCommit(renderer);
  OSPFrameBuffer fb = ospNewFrameBuffer(size, size, OSP_FB_RGBA32F, OSP_FB_COLOR);

  const auto max_error = [&](float shift_u) {
    ospRenderFrameBlocking(fb, renderer, camera, world);
    const auto* rgba = static_cast<const float*>(ospMapFrameBuffer(fb, OSP_FB_COLOR));
    double worst = 0.0;
    for (int y = 0; y < size; ++y)
      for (int x = 0; x < size; ++x) {
        const float u = (x + 0.5f) / size + shift_u, v = (y + 0.5f) / size;
        const Vec3f expected = kd * checker_at(u - std::floor(u), v, n, a, b);
        const float* got = rgba + 4 * (y * size + x);
        worst = std::max({worst, double(std::abs(got[0] - expected.x)), double(std::abs(got[1] - expected.y)),
                          double(std::abs(got[2] - expected.z))});
      }
    ospUnmapFrameBuffer(rgba, fb);
    return worst;
  };
  const double plain = max_error(0.f);
  // map_kd.transform (affine2f: vx, vy, p) moves the lookup by a cell in u; a
  // recommitted material reaches the world.
  const float transform[6] = {1.f, 0.f, 0.f, 1.f, 0.25f, 0.f};
  ospSetParam(material, "map_kd.transform", OSP_AFFINE2F, transform);
  ospCommit(material);
  const double moved = max_error(0.25f);
  // A recommitted texture reaches the world too: all texels the same colour.
  std::vector<float> grey(texels.size(), 0.5f);
  data = ospNewSharedData2D(grey.data(), OSP_VEC3F, n, n);
  ospSetObject(texture, "data", data);
  ospRelease(data);
  ospCommit(texture);
  ospRenderFrameBlocking(fb, renderer, camera, world);
  const auto* rgba = static_cast<const float*>(ospMapFrameBuffer(fb, OSP_FB_COLOR));
  const float centre_red = rgba[4 * (size / 2 * size + size / 2)], centre_green = rgba[4 * (size / 2 * size + size / 2) + 1];
  ospUnmapFrameBuffer(rgba, fb);
  std::printf("[texture_maps] C API checker map_kd: max |error| %.2e, with map_kd.transform %.2e\n", plain, moved);
  CHECK(plain < 1e-5);
  CHECK(moved < 1e-5);
  CHECK(centre_red == Approx(0.5f * kd.x).margin(1e-5));
  CHECK(centre_green == Approx(0.5f * kd.y).margin(1e-5));
  CHECK(api.messages.errors.empty());

  for (OSPObject o : std::initializer_list<OSPObject>{mesh, texture, material, model, group, instance, light, world,
                                                      camera, renderer, fb})
    ospRelease(o);
}

TEST_CASE("C API: bad texcoords and bad maps are named", "[c_api][texture_maps][errors]") {
  sciray_test::ApiFixture api;
  const std::vector<float> positions = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  const std::vector<std::uint32_t> index = {0, 1, 2};
  OSPGeometry mesh = ospNewGeometry("mesh");
  OSPData data = shared_floats(positions, OSP_VEC3F, 3);
  ospSetObject(mesh, "vertex.position", data);
  ospRelease(data);
  data = ospNewSharedData1D(index.data(), OSP_VEC3UI, 1);
  ospSetObject(mesh, "index", data);
  ospRelease(data);
  const std::vector<float> two = {0, 0, 1, 1};
  data = shared_floats(two, OSP_VEC2F, 2);
  ospSetObject(mesh, "vertex.texcoord", data);
  ospRelease(data);
  ospCommit(mesh);
  api.expect_error("mesh geometry: parameter 'vertex.texcoord' has 2 elements but there are 3 vertices");
  OSPTexture wrapping = ospNewTexture("texture2d");
  const float two_texels[6] = {1, 0, 0, 0, 0, 1};
  OSPData texels = ospNewSharedData2D(two_texels, OSP_VEC3F, 2, 1);
  ospSetObject(wrapping, "data", texels);
  ospRelease(texels);
  ospSetInt(wrapping, "format", OSP_TEXTURE_RGB32F);
  ospSetInt(wrapping, "wrapMode", 7);
  ospCommit(wrapping);
  api.expect_error("texture2d texture: parameter 'wrapMode' must be OSP_TEXTURE_WRAP_REPEAT (0), _MIRRORED_REPEAT (1) "
                   "or _CLAMP_TO_EDGE (2), got 7");
  ospSetVec2i(wrapping, "wrapMode", OSP_TEXTURE_WRAP_CLAMP_TO_EDGE, OSP_TEXTURE_WRAP_MIRRORED_REPEAT);
  ospCommit(wrapping);
  CHECK(api.messages.errors.empty());
  ospRelease(wrapping);
  data = shared_floats(positions, OSP_VEC3F, 3);
  ospSetObject(mesh, "vertex.texcoord", data);
  ospRelease(data);
  ospCommit(mesh);
  api.expect_error("parameter 'vertex.texcoord' must be an array of vec2f, got an array of vec3f");
  const std::vector<float> nan = {0, 0, 1, std::numeric_limits<float>::quiet_NaN(), 0, 1};
  data = shared_floats(nan, OSP_VEC2F, 3);
  ospSetObject(mesh, "vertex.texcoord", data);
  ospRelease(data);
  ospCommit(mesh);
  api.expect_error("mesh: 'vertex.texcoord' 1 is not finite");

  OSPGeometry spheres = ospNewGeometry("sphere");
  data = shared_floats(positions, OSP_VEC3F, 3);
  ospSetObject(spheres, "sphere.position", data);
  ospRelease(data);
  data = shared_floats(two, OSP_VEC2F, 2);
  ospSetObject(spheres, "sphere.texcoord", data);
  ospRelease(data);
  ospCommit(spheres);
  api.expect_error("sphere geometry: parameter 'sphere.texcoord' has 2 elements but there are 3 spheres");

  // A volume texture colours only an obj material's map_kd (slices).
  const float voxels[8] = {0, 1, 0, 1, 0, 1, 0, 1};
  OSPVolume volume = ospNewVolume("structuredRegular");
  data = ospNewSharedData3D(voxels, OSP_FLOAT, 2, 2, 2);
  ospSetObject(volume, "data", data);
  ospRelease(data);
  ospCommit(volume);
  OSPTransferFunction tf = ospNewTransferFunction("piecewiseLinear");
  const float colors[6] = {0, 0, 0, 1, 1, 1}, opacities[2] = {0, 1};
  data = ospNewSharedData1D(colors, OSP_VEC3F, 2);
  ospSetObject(tf, "color", data);
  ospRelease(data);
  data = ospNewSharedData1D(opacities, OSP_FLOAT, 2);
  ospSetObject(tf, "opacity", data);
  ospRelease(data);
  ospCommit(tf);
  OSPVolumetricModel volume_model = ospNewVolumetricModel(volume);
  ospSetObject(volume_model, "transferFunction", tf);
  ospCommit(volume_model);
  OSPTexture volume_texture = ospNewTexture("volume");
  ospSetObject(volume_texture, "volume", volume_model);
  ospCommit(volume_texture);
  REQUIRE(api.messages.errors.empty());
  OSPMaterial obj = ospNewMaterial("obj");
  ospSetObject(obj, "map_ks", volume_texture);
  ospCommit(obj);
  api.expect_error("obj material: parameter 'map_ks': a volume texture colours only an obj material's map_kd; give a "
                   "texture2d");
  OSPMaterial principled = ospNewMaterial("principled");
  ospSetObject(principled, "map_baseColor", volume_texture);
  ospCommit(principled);
  api.expect_error("principled material: parameter 'map_baseColor': a volume texture colours only");

  OSPTexture image = ospNewTexture("texture2d");
  const float texel[3] = {1, 1, 1};
  data = ospNewSharedData2D(texel, OSP_VEC3F, 1, 1);
  ospSetObject(image, "data", data);
  ospRelease(data);
  ospSetInt(image, "format", OSP_TEXTURE_RGB32F);
  ospCommit(image);
  ospRemoveParam(obj, "map_ks");
  ospSetObject(obj, "map_d", image);
  ospSetFloat(obj, "map_d.transform", 2.f);
  ospCommit(obj);
  api.expect_error("obj material: parameter 'map_d.transform' must be a linear2f or an affine2f (an affine3f transforms volume textures only), got float");
  ospRemoveParam(obj, "map_d.transform");
  ospSetVec2f(obj, "map_d.scale", 0.f, 1.f);
  ospCommit(obj);
  api.expect_error("obj material: parameter 'map_d.scale' must not be zero");
  ospSetVec2f(obj, "map_d.scale", 2.f, 2.f);
  ospSetFloat(obj, "map_d.rotation", 45.f);
  ospCommit(obj);
  CHECK(api.messages.errors.empty());
  OSPTexture uncommitted = ospNewTexture("texture2d");
  ospSetObject(principled, "map_baseColor", uncommitted);
  ospCommit(principled);
  api.expect_error("principled material: parameter 'map_baseColor': its texture has not been committed");

  for (OSPObject o : std::initializer_list<OSPObject>{mesh, spheres, volume, tf, volume_model, volume_texture, obj,
                                                      principled, image, uncommitted})
    ospRelease(o);
}

namespace {

struct ToolRun {
  int exit_code;
  std::string output;
};

ToolRun run_tool(const std::string& arguments) {
  const std::string command = std::string(SCIRAY_TOOL) + " " + arguments + " 2>&1";
  FILE* pipe = popen(command.c_str(), "r");
  REQUIRE(pipe);
  std::string output;
  std::array<char, 4096> buffer;
  while (const std::size_t got = std::fread(buffer.data(), 1, buffer.size(), pipe)) output.append(buffer.data(), got);
  const int status = pclose(pipe);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, output};
}

std::filesystem::path scratch(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / "sciray_texture_maps_test";
  std::filesystem::create_directories(dir);
  return dir / name;
}

}  // namespace

TEST_CASE("sciray render: the bunny coloured by its confidence through a colour-map map_kd",
          "[tool][texture_maps]") {
  // A colour map from blue (t = 0) to red (t = 1) with a constant green: in linear RGB,
  // (lin(t), lin(0.5), lin(1 - t)). Lit by white lights, every bunny pixel is a multiple
  // of one colour of the map, so its green against red + blue says which t it is.
  const int entries = 256;
  std::vector<std::uint8_t> colormap;
  for (int i = 0; i < entries; ++i) colormap.insert(colormap.end(), {std::uint8_t(i), 128, std::uint8_t(255 - i)});
  const auto map_file = scratch("colormap.png");
  io::write_png(map_file, entries, 1, 3, colormap.data());
  const auto out = scratch("bunny_confidence.png");
  const std::string material = "'{\"type\":\"obj\",\"kd\":0.8,\"map_kd\":\"" + map_file.string() + "\"}'";
  const ToolRun run = run_tool("render " SCIRAY_DATA_DIR "/meshes/bunny.ply --size 160x120 --threads 2 "
                               "--pixel-filter point --texcoord-from confidence --material " + material +
                               " -o " + out.string());
  INFO(run.output);
  REQUIRE(run.exit_code == 0);

  const io::Image image = io::read_png(out);
  // Each bright pixel's t from red / (red + blue), then its green against the map's.
  int bunny = 0, off_map = 0;
  std::vector<float> ts;
  double worst = 0.0;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      const float r = srgb_to_linear(image.at(x, y, 0)), g = srgb_to_linear(image.at(x, y, 1)),
                  b = srgb_to_linear(image.at(x, y, 2));
      if (r + g + b < 0.15f) continue;  // background, or too dark for 8 bits to tell
      ++bunny;
      // On the map: (r, g, b) = s (lin(t), lin(0.5), lin(1 - t)) for some s and t.
      float best = 1e9f, best_t = 0.f;
      for (int i = 0; i < entries; ++i) {
        const float t = i / 255.f;
        const Vec3f c{srgb_to_linear(t), srgb_to_linear(128 / 255.f), srgb_to_linear(1.f - t)};
        const float s = (r * c.x + g * c.y + b * c.z) / dot(c, c);
        const float d = std::sqrt((r - s * c.x) * (r - s * c.x) + (g - s * c.y) * (g - s * c.y) +
                                  (b - s * c.z) * (b - s * c.z)) /
                        (r + g + b);
        if (d < best) best = d, best_t = t;
      }
      worst = std::max(worst, double(best));
      off_map += best > 0.03f;
      ts.push_back(best_t);
    }
  std::sort(ts.begin(), ts.end());
  const float p5 = ts.empty() ? 0.f : ts[ts.size() / 20], p95 = ts.empty() ? 0.f : ts[ts.size() * 19 / 20];
  std::printf("[texture_maps] tool: bunny by confidence: %d pixels, %d off the colour map (worst relative distance "
              "%.3f); colour-map position t: 5th percentile %.2f, 95th %.2f\n",
              bunny, off_map, worst, p5, p95);
  CHECK(bunny > 2000);
  CHECK(off_map <= bunny / 100);
  CHECK(p95 - p5 > 0.1f);  // the colours vary with the confidence

  // A property the file lacks, a map that cannot be read, a scene that is no PLY mesh.
  const ToolRun bad = run_tool("render " SCIRAY_DATA_DIR "/meshes/bunny.ply --size 16x16 --texcoord-from colour -o " +
                               scratch("x.png").string());
  CHECK(bad.exit_code != 0);
  CHECK(bad.output.find("has no property 'colour' to make texture coordinates from") != std::string::npos);
  const ToolRun missing = run_tool("render " SCIRAY_DATA_DIR "/meshes/bunny.ply --size 16x16 --material "
                                   "'{\"type\":\"obj\",\"map_kd\":\"/nonexistent/map.png\"}' -o " + scratch("x.png").string());
  CHECK(missing.exit_code != 0);
  CHECK(missing.output.find("--material 1: \"map_kd\": read_png: /nonexistent/map.png") != std::string::npos);
  const ToolRun not_ply = run_tool("render builtin:cornell_box --size 16x16 --texcoord-from confidence -o " +
                                   scratch("x.png").string());
  CHECK(not_ply.exit_code != 0);
  CHECK(not_ply.output.find("--texcoord-from: needs a PLY mesh") != std::string::npos);
  std::ofstream(scratch("points.xyz")) << "0 0 0\n1 0 0\n";
  const ToolRun points = run_tool("render " + scratch("points.xyz").string() + " --size 16x16 --texcoord-from x -o " +
                                  scratch("x.png").string());
  CHECK(points.exit_code != 0);
  CHECK(points.output.find("--texcoord-from: needs a PLY mesh") != std::string::npos);
}
