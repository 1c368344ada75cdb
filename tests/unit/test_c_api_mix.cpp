// OSPRay's `mix` material through the C API: what the path tracer, scivis and ao show of
// it (against pixels of OSPRay 3.1's runtime), its factor map, and the mixes it refuses.
#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>

#include <ospray/ospray.h>
#include <ospray/ospray_util.h>

#include "support/api_fixture.hpp"
#include "support/c_api_scenes.hpp"

using namespace sciray_test;

namespace {

OSPMaterial new_obj(float r, float g, float b) {
  OSPMaterial m = ospNewMaterial("obj");
  ospSetVec3f(m, "kd", r, g, b);
  ospCommit(m);
  return m;
}

/// A mix of a red and a blue obj material (released: the mix holds them).
OSPMaterial new_red_blue_mix(float factor) {
  OSPMaterial red = new_obj(1.f, 0.f, 0.f), blue = new_obj(0.f, 0.f, 1.f);
  OSPMaterial mix = ospNewMaterial("mix");
  ospSetObject(mix, "material1", red);
  ospSetObject(mix, "material2", blue);
  ospSetFloat(mix, "factor", factor);
  ospCommit(mix);
  ospRelease(red), ospRelease(blue);
  return mix;
}

/// The centre pixel of a unit sphere seen head-on under an ambient light of radiance 1,
/// after 4 frames of `renderer`: a Lambertian material's albedo kd in the path tracer.
std::array<float, 3> centre(GeometryScene& scene, OSPMaterial material, const char* renderer_type) {
  ospSetObject(scene.model, "material", material);
  ospCommit(scene.model);
  ospCommit(scene.group);
  ospCommit(scene.instance);
  ospCommit(scene.world);
  OSPRenderer renderer = ospNewRenderer(renderer_type);
  ospSetInt(renderer, "pixelSamples", 64);
  ospCommit(renderer);
  OSPFrameBuffer fb = ospNewFrameBuffer(16, 16, OSP_FB_RGBA32F, OSP_FB_COLOR | OSP_FB_ACCUM);
  for (int f = 0; f < 4; ++f) ospRenderFrameBlocking(fb, renderer, scene.camera, scene.world);
  const auto* p = static_cast<const float*>(ospMapFrameBuffer(fb, OSP_FB_COLOR));
  const float* c = p + 4 * (8 * 16 + 8);
  const std::array<float, 3> rgb{c[0], c[1], c[2]};
  ospUnmapFrameBuffer(p, fb);
  ospRelease(fb);
  ospRelease(renderer);
  return rgb;
}

}  // namespace

TEST_CASE("C API: a mix shows its mixed colour in the path tracer and white in scivis and ao as OSPRay 3.1",
          "[c_api][mix]") {
  ApiFixture api;
  GeometryScene scene(new_spheres({0.f, 0.f, 0.f}, 1.f), true);
  OSPMaterial mix = new_red_blue_mix(0.25f), white = new_obj(1.f, 1.f, 1.f);
  // OSPRay 3.1's runtime, the same mix on a quad under the same light: the path tracer
  // shows (0.75, 0, 0.25), the obj of kd 0.75·red + 0.25·blue; scivis and ao show it as
  // they show a white obj (1 and 0.9974 in every channel), as every material but obj.
  const auto traced = centre(scene, mix, "pathtracer");
  const std::array<float, 3> mixed_kd{0.75f, 0.f, 0.25f};
  for (int k = 0; k < 3; ++k) CHECK(traced[k] == Approx(mixed_kd[k]).margin(0.01f));
  for (const char* renderer : {"scivis", "ao"}) {
    const auto shown = centre(scene, mix, renderer), expected = centre(scene, white, renderer);
    for (int k = 0; k < 3; ++k) {
      INFO(renderer << ", channel " << k);
      CHECK(expected[k] > 0.9f);
      CHECK(shown[k] == Approx(expected[k]).margin(0.01f));
    }
  }
  ospRelease(white);
  // A part committed again changes the mix, as in OSPRay.
  OSPMaterial green = new_obj(0.f, 1.f, 0.f);
  ospSetObject(mix, "material2", green);
  ospCommit(mix);
  const auto rgb = centre(scene, mix, "pathtracer");
  CHECK(rgb[0] == Approx(0.75f).margin(0.01f));
  CHECK(rgb[1] == Approx(0.25f).margin(0.01f));
  ospSetVec3f(green, "kd", 0.f, 0.f, 1.f);
  ospCommit(green);
  const auto recommitted = centre(scene, mix, "pathtracer");
  CHECK(recommitted[1] == Approx(0.f).margin(0.01f));
  CHECK(recommitted[2] == Approx(0.25f).margin(0.01f));
  CHECK(api.messages.errors.empty());
  ospRelease(green);
  ospRelease(mix);
}

TEST_CASE("C API: a mix's map_factor multiplies its factor", "[c_api][mix]") {
  ApiFixture api;
  GeometryScene scene(new_spheres({0.f, 0.f, 0.f}, 1.f), true);
  for (const std::uint8_t texel : {std::uint8_t{0}, std::uint8_t{255}}) {
    OSPTexture texture = ospNewTexture("texture2d");
    OSPData data = ospNewSharedData2D(&texel, OSP_UCHAR, 1, 1);
    ospSetObject(texture, "data", data);
    ospRelease(data);
    ospSetInt(texture, "format", OSP_TEXTURE_R8);
    ospSetInt(texture, "filter", OSP_TEXTURE_FILTER_NEAREST);
    ospCommit(texture);
    OSPMaterial mix = new_red_blue_mix(0.25f);
    ospSetObject(mix, "map_factor", texture);
    ospCommit(mix);
    const auto rgb = centre(scene, mix, "pathtracer");
    const float factor = texel ? 0.25f : 0.f;
    INFO("texel " << int(texel));
    CHECK(rgb[0] == Approx(1.f - factor).margin(0.01f));
    CHECK(rgb[2] == Approx(factor).margin(0.01f));
    ospRelease(mix);
    ospRelease(texture);
  }
  CHECK(api.messages.errors.empty());
}

TEST_CASE("C API: a mix without its parts, of a bad factor or containing itself is refused by name",
          "[c_api][mix][errors]") {
  ApiFixture api;
  OSPMaterial red = new_obj(1.f, 0.f, 0.f);
  OSPMaterial lonely = ospNewMaterial("mix");
  ospSetObject(lonely, "material1", red);
  ospCommit(lonely);
  api.expect_error("required parameter 'material2'");
  for (const float factor : {-0.5f, 1.5f, std::numeric_limits<float>::quiet_NaN()}) {
    OSPMaterial bad = new_red_blue_mix(factor);
    api.expect_error("'factor' must be in [0, 1]");
    ospRelease(bad);
  }
  OSPMaterial uncommitted = ospNewMaterial("obj");
  OSPMaterial waiting = ospNewMaterial("mix");
  ospSetObject(waiting, "material1", red);
  ospSetObject(waiting, "material2", uncommitted);
  ospCommit(waiting);
  api.expect_error("parameter 'material2': its material has not been committed");

  OSPMaterial selfish = ospNewMaterial("mix");
  ospSetObject(selfish, "material1", red);
  ospSetObject(selfish, "material2", selfish);
  api.expect_error("parameter 'material2': mix material refers to this mix material");
  // Through another mix: a contains b, then b is given a.
  OSPMaterial a = new_red_blue_mix(0.5f), b = new_red_blue_mix(0.5f);
  ospSetObject(a, "material1", b);
  ospCommit(a);
  CHECK(api.messages.errors.empty());
  ospSetObject(b, "material2", a);
  api.expect_error("parameter 'material2': mix material refers to this mix material");
  for (OSPMaterial m : {red, lonely, uncommitted, waiting, selfish, a, b}) ospRelease(m);
}
