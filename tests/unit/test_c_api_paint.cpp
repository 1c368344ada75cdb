// velvet, metallicPaint, carPaint and principled's backlight through the C API, against
// pixels of OSPRay 3.1's runtime (a C client rendering the same scene with it), and the
// white diffuse surface OSPRay's scivis and ao make of materials they do not know.
#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <string>
#include <vector>

#include <ospray/ospray.h>
#include <ospray/ospray_util.h>

#include "support/api_fixture.hpp"
#include "support/c_api_scenes.hpp"

using namespace sciray_test;

namespace {

/// A unit sphere at the origin under a white ambient light of radiance 1, seen along -z by
/// an orthographic camera whose one row of 201 pixels spans x in [-1, 1]: each pixel shows
/// the material's directional albedo where the view meets the normal at its cosine.
struct AlbedoRow {
  static constexpr int width = 201;
  GeometryScene scene{new_spheres({0.f, 0.f, 0.f}, 1.f), true};

  AlbedoRow() {
    ospSetVec3f(scene.camera, "position", 0.f, 0.f, 5.f);
    ospSetVec3f(scene.camera, "direction", 0.f, 0.f, -1.f);
    ospSetVec3f(scene.camera, "up", 0.f, 1.f, 0.f);
    ospSetFloat(scene.camera, "height", 2.f / width);
    ospSetFloat(scene.camera, "aspect", static_cast<float>(width));
    ospCommit(scene.camera);
  }

  /// The mean of the two pixels (left and right of the centre) where the cosine is `cos`,
  /// after `frames` frames of `renderer`.
  std::array<float, 3> at(OSPMaterial material, OSPRenderer renderer, float cos, int frames) {
    ospSetObject(scene.model, "material", material);
    ospCommit(scene.model);
    ospCommit(scene.group);
    ospCommit(scene.instance);
    ospCommit(scene.world);
    OSPFrameBuffer fb = ospNewFrameBuffer(width, 1, OSP_FB_RGBA32F, OSP_FB_COLOR | OSP_FB_ACCUM);
    for (int f = 0; f < frames; ++f) ospRenderFrameBlocking(fb, renderer, scene.camera, scene.world);
    const auto* p = static_cast<const float*>(ospMapFrameBuffer(fb, OSP_FB_COLOR));
    const float s = std::sqrt(1.f - cos * cos);
    const int right = std::min(static_cast<int>((s + 1.f) * 0.5f * width), width - 1), left = width - 1 - right;
    std::array<float, 3> c{};
    for (int k = 0; k < 3; ++k) c[k] = 0.5f * (p[4 * left + k] + p[4 * right + k]);
    ospUnmapFrameBuffer(p, fb);
    ospRelease(fb);
    return c;
  }
};

OSPMaterial new_material(const char* type, const std::vector<std::pair<const char*, std::array<float, 3>>>& colors,
                         const std::vector<std::pair<const char*, float>>& floats) {
  OSPMaterial m = ospNewMaterial(type);
  for (const auto& [name, c] : colors) ospSetVec3f(m, name, c[0], c[1], c[2]);
  for (const auto& [name, v] : floats) ospSetFloat(m, name, v);
  ospCommit(m);
  return m;
}

}  // namespace

TEST_CASE("Velvet and the paints and backlight match OSPRay 3.1's pixels", "[c_api][renderers]") {
  ApiFixture api;
  AlbedoRow row;
  OSPRenderer pathtracer = ospNewRenderer("pathtracer");
  ospSetInt(pathtracer, "pixelSamples", 64);
  ospSetInt(pathtracer, "maxPathLength", 20);
  ospCommit(pathtracer);

  struct Case {
    const char* what;
    OSPMaterial material;
    std::array<float, 3> at_normal, at_60;  // OSPRay 3.1's pixels, 4096 samples each
    float margin = 0.015f;
  };
  OSPMaterial backlit = new_material("principled",
                                     {{"baseColor", {0.04f, 0.2f, 1.f}}, {"transmissionColor", {0.04f, 0.2f, 1.f}}},
                                     {{"transmission", 0.3f}, {"ior", 1.5f}, {"backlight", 1.f}});
  ospSetBool(backlit, "thin", true);
  ospCommit(backlit);
  const std::vector<Case> cases = {
      {"velvet", new_material("velvet", {}, {}), {0.3200f, 0.f, 0.f}, {0.3817f, 0.0229f, 0.0229f}},
      {"metallicPaint", new_material("metallicPaint", {}, {}), {0.7886f, 0.7905f, 0.7923f}, {0.7923f, 0.7940f, 0.7956f}},
      {"carPaint with pearlescent flakes",
       new_material("carPaint",
                    {{"baseColor", {0.0177f, 0.189f, 0.59f}},
                     {"flakeColor", {0.277f, 0.717f, 0.99f}},
                     {"flipflopColor", {0.252f, 0.0385f, 0.55f}}},
                    {{"flakeDensity", 1.f}, {"flakeScale", 1000.f}, {"flipflopFalloff", 0.f}}),
       {0.3013f, 0.7149f, 0.9759f},
       {0.1722f, 0.2213f, 0.5529f}},
      // Light crosses the sheet twice (in and out of the sphere): noisier, in OSPRay's too.
      {"principled thin, backlight 1", backlit, {0.0540f, 0.1234f, 0.9984f}, {0.1025f, 0.1656f, 1.0024f}, 0.03f}};
  for (const Case& c : cases) {
    const auto normal = row.at(c.material, pathtracer, 1.f, 8);
    const auto sixty = row.at(c.material, pathtracer, 0.5f, 8);
    for (int k = 0; k < 3; ++k) {
      INFO(c.what << ", channel " << k);
      CHECK(normal[k] == Approx(c.at_normal[k]).margin(c.margin));
      CHECK(sixty[k] == Approx(c.at_60[k]).margin(c.margin));
    }
    ospRelease(c.material);
  }
  CHECK(api.messages.errors.empty());
  ospRelease(pathtracer);
}

TEST_CASE("scivis and ao show velvet and the paints as white diffuse surfaces as OSPRay 3.1's do", "[c_api][renderers]") {
  ApiFixture api;
  AlbedoRow row;
  // OSPRay's scivis and ao shade every material but obj with the geometry's colour: here
  // 1 everywhere in scivis, the cosine to the view in ao (measured with its runtime).
  for (const char* type : {"velvet", "metallicPaint", "carPaint"}) {
    const bool has_base = std::string(type) != "velvet";
    OSPMaterial m = has_base ? new_material(type, {{"baseColor", {0.2f, 0.3f, 0.4f}}}, {})
                             : new_material(type, {{"reflectance", {0.2f, 0.3f, 0.4f}}}, {});
    for (const char* renderer_type : {"scivis", "ao"}) {
      OSPRenderer renderer = ospNewRenderer(renderer_type);
      ospCommit(renderer);
      const bool ao = std::string(renderer_type) == "ao";
      for (const float cos : {1.f, 0.5f}) {
        const auto c = row.at(m, renderer, cos, 1);
        INFO(type << " in " << renderer_type << " at cos " << cos);
        for (int k = 0; k < 3; ++k) CHECK(c[k] == Approx(ao ? cos : 1.f).margin(0.01));
      }
      ospRelease(renderer);
    }
    ospRelease(m);
  }
  CHECK(api.messages.errors.empty());
}

TEST_CASE("Bad velvet and paint and backlight parameters are named", "[c_api][renderers][errors]") {
  ApiFixture api;
  OSPMaterial paint = ospNewMaterial("carPaint");
  ospSetFloat(paint, "flakeDensity", 3.f);
  ospCommit(paint);
  api.expect_error("'flakeDensity' must be in [0, 1]");
  OSPMaterial metallic = ospNewMaterial("metallicPaint");
  ospSetFloat(metallic, "eta", -1.f);
  ospCommit(metallic);
  api.expect_error("'eta' must be positive");
  OSPMaterial velvet = ospNewMaterial("velvet");
  ospSetFloat(velvet, "horizonScatteringFallOff", -2.f);
  ospCommit(velvet);
  api.expect_error("'horizonScatteringFallOff' must be finite and not negative");
  OSPMaterial principled = ospNewMaterial("principled");
  ospSetFloat(principled, "backlight", 3.f);
  ospCommit(principled);
  api.expect_error("'backlight' must be in [0, 2]");
  OSPMaterial unknown = ospNewMaterial("chalk");
  CHECK(unknown == nullptr);
  api.expect_error("velvet, metallicPaint, carPaint");
  for (OSPMaterial m : {paint, metallic, velvet, principled}) ospRelease(m);
}
