// Texture transforms and normal maps: OSPRay 3's composition of a map's rotation, scale
// and translation (which texel a transformed coordinate picks), the rotation normal maps
// turn with, a normal map tilting a lit quad's normal by a known angle (the lit value
// follows the cosine, in scivis through the C API), the path tracer's bounces that the
// tilt sends below the quad (they meet it again: a closed form, OSPRay's, and the white
// furnace), the default factor of a mapped parameter, and the errors bad transforms and
// bump maps give.
#include <catch2/catch.hpp>

#include <cmath>
#include <initializer_list>
#include <vector>

#include <ospray/ospray.h>
#include <ospray/ospray_util.h>

#include "sciray/render/material.hpp"
#include "support/api_fixture.hpp"

using namespace sciray;

namespace {

constexpr float pi = 3.14159265358979f;

void check_near(TexCoord<float> got, TexCoord<float> expected) {
  CHECK(got.u == Approx(expected.u).margin(1e-6));
  CHECK(got.v == Approx(expected.v).margin(1e-6));
}

}  // namespace

TEST_CASE("texture transforms: rotation, scale and translation compose as OSPRay 3", "[texture_maps]") {
  // The texture moves by the translation: u = 0.6 reads what was at 0.35.
  check_near(TexCoordTransform::of_texture(0.f, {1.f, 1.f}, {0.25f, 0.f})({0.6f, 0.5f}), {0.35f, 0.5f});
  // It grows about its centre: at half scale, 0.75 reads the texture's edge.
  check_near(TexCoordTransform::of_texture(0.f, {0.5f, 0.5f}, {0.f, 0.f})({0.75f, 0.5f}), {1.f, 0.5f});
  // It turns counterclockwise about its centre: the right edge's middle reads the bottom's.
  check_near(TexCoordTransform::of_texture(90.f, {1.f, 1.f}, {0.f, 0.f})({1.f, 0.5f}), {0.5f, 0.f});
  // The rotation applies to the coordinates first, then the scale (OSPRay's order): the
  // other order would read (0.5, 0).
  check_near(TexCoordTransform::of_texture(90.f, {0.5f, 1.f}, {0.f, 0.f})({0.75f, 0.5f}), {0.5f, 0.25f});
  // Composition: this after that.
  const TexCoordTransform shift = TexCoordTransform::translate({0.5f, 0.f});
  const TexCoordTransform twice = TexCoordTransform::scale({2.f, 2.f});
  check_near((shift * twice)({1.f, 1.f}), {2.5f, 2.f});
  check_near((twice * shift)({1.f, 1.f}), {3.f, 2.f});

  // Normals turn with the texture: a map turned 90 degrees turns its normals' +x to +y,
  // whatever the scale; a mirrored map keeps the mirror.
  const TexCoordTransform turn = TexCoordTransform::of_texture(90.f, {2.f, 0.5f}, {0.3f, 0.1f}).normal_rotation();
  check_near(turn({1.f, 0.f}), {0.f, 1.f});
  check_near(turn({0.f, 1.f}), {-1.f, 0.f});
  const TexCoordTransform mirror = TexCoordTransform::scale({-1.f, 1.f}).normal_rotation();
  check_near(mirror({1.f, 0.f}), {-1.f, 0.f});
  check_near(mirror({0.f, 1.f}), {0.f, 1.f});
}

TEST_CASE("normal maps: the map tilts the shading normal in the texture derivatives' frame", "[texture_maps]") {
  const float tilt = pi / 3.f;
  const Vec3f encoded{0.5f + 0.5f * std::sin(tilt), 0.5f, 0.5f + 0.5f * std::cos(tilt)};  // (n + 1) / 2
  ObjMaterial obj;
  obj.map_bump.map.texture = std::make_shared<const Texture2D>(1, 1, std::vector<Vec3f>{encoded});
  const Material material = obj;
  REQUIRE(has_normal_map(material));
  CHECK_FALSE(has_normal_map(Material{ObjMaterial{}}));
  // dP/ds along +y, dP/dt along -x (lengths do not matter), the normal +z: the tilt leans
  // the normal towards +y.
  const Vec3f n = mapped_normal(material, {0.f, 0.f, 1.f}, {0.f, 3.f, 0.f}, {-0.5f, 0.f, 0.f}, {0.3f, 0.7f});
  CHECK(n.x == Approx(0.f).margin(1e-6));
  CHECK(n.y == Approx(std::sin(tilt)).margin(1e-6));
  CHECK(n.z == Approx(std::cos(tilt)).margin(1e-6));
  // Turned 90 degrees with the texture, it leans towards dP/dt.
  obj.map_bump.map.transform = TexCoordTransform::of_texture(90.f, {1.f, 1.f}, {0.f, 0.f});
  const Vec3f turned = mapped_normal(obj, {0.f, 0.f, 1.f}, {0.f, 3.f, 0.f}, {-0.5f, 0.f, 0.f}, {0.3f, 0.7f});
  CHECK(turned.x == Approx(-std::sin(tilt)).margin(1e-6));
  CHECK(turned.y == Approx(0.f).margin(1e-6));
  // Principled's `normal` scales the tilt's tangent part.
  PrincipledMaterial principled;
  principled.map_normal = obj.map_bump;
  principled.map_normal.map.transform = {};
  principled.normal = 0.f;
  const Vec3f flat = mapped_normal(principled, {0.f, 0.f, 1.f}, {1.f, 0.f, 0.f}, {0.f, 1.f, 0.f}, {0.f, 0.f});
  CHECK(flat.z == Approx(1.f).margin(1e-6));
  // A degenerate frame leaves the normal as it is.
  const Vec3f kept = mapped_normal(material, {0.f, 0.f, 1.f}, {0.f, 0.f, 0.f}, {0.f, 1.f, 0.f}, {0.f, 0.f});
  CHECK(kept.z == 1.f);
}

namespace {

/// A quad [-1, 1]^2 at z = 0 with texcoords (0,0)..(1,1), an obj material (kd 1, with the
/// given normal map texel, RGB32F) lit by a distant light of irradiance pi, seen along +z by
/// an orthographic camera in scivis (or the given renderer): the centre pixel is kd times
/// the cosine between the (mapped) normal and the light.
struct LitQuad {
  sciray_test::ApiFixture api;
  OSPGeometry mesh = ospNewGeometry("mesh");
  OSPTexture texture = ospNewTexture("texture2d");
  OSPMaterial material = ospNewMaterial("obj");
  OSPLight light = ospNewLight("distant");
  OSPWorld world = ospNewWorld();
  OSPCamera camera = ospNewCamera("orthographic");
  OSPRenderer renderer;
  OSPFrameBuffer fb = ospNewFrameBuffer(4, 4, OSP_FB_RGBA32F, OSP_FB_COLOR);
  std::vector<float> positions = {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0};
  std::vector<float> texcoords = {0, 0, 1, 0, 1, 1, 0, 1};
  std::vector<std::uint32_t> index = {0, 1, 2, 3};
  float texel[3];

  explicit LitQuad(Vec3f normal_texel, const char* renderer_type = "scivis")
      : renderer(ospNewRenderer(renderer_type)), texel{normal_texel.x, normal_texel.y, normal_texel.z} {
    set(mesh, "vertex.position", ospNewSharedData1D(positions.data(), OSP_VEC3F, 4));
    set(mesh, "vertex.texcoord", ospNewSharedData1D(texcoords.data(), OSP_VEC2F, 4));
    set(mesh, "index", ospNewSharedData1D(index.data(), OSP_VEC4UI, 1));
    ospCommit(mesh);
    set(texture, "data", ospNewSharedData2D(texel, OSP_VEC3F, 1, 1));
    ospSetInt(texture, "format", OSP_TEXTURE_RGB32F);
    ospCommit(texture);
    ospSetVec3f(material, "kd", 1.f, 1.f, 1.f);
    ospSetObject(material, "map_bump", texture);
    ospCommit(material);
    OSPGeometricModel model = ospNewGeometricModel(mesh);
    ospSetObject(model, "material", material);
    ospCommit(model);
    OSPGroup group = ospNewGroup();
    set(group, "geometry", ospNewSharedData1D(&model, OSP_GEOMETRIC_MODEL, 1));
    ospCommit(group);
    OSPInstance instance = ospNewInstance(group);
    ospCommit(instance);
    ospSetFloat(light, "intensity", pi);
    ospCommit(light);
    set(world, "instance", ospNewSharedData1D(&instance, OSP_INSTANCE, 1));
    set(world, "light", ospNewSharedData1D(&light, OSP_LIGHT, 1));
    ospCommit(world);
    for (OSPObject o : std::initializer_list<OSPObject>{model, group, instance}) ospRelease(o);
    ospSetVec3f(camera, "position", 0.f, 0.f, -5.f);
    ospSetVec3f(camera, "direction", 0.f, 0.f, 1.f);
    ospSetFloat(camera, "height", 2.f);
    ospSetFloat(camera, "aspect", 1.f);
    ospCommit(camera);
    ospSetInt(renderer, "pixelFilter", OSP_PIXELFILTER_POINT);
    ospCommit(renderer);
  }
  ~LitQuad() {
    for (OSPObject o :
         std::initializer_list<OSPObject>{mesh, texture, material, light, world, camera, renderer, fb})
      ospRelease(o);
  }
  static void set(OSPObject o, const char* name, OSPData data) {
    ospSetObject(o, name, data);
    ospRelease(data);
  }
  /// The centre pixel's red with the light travelling along `direction`.
  float lit(Vec3f direction) {
    ospSetVec3f(light, "direction", direction.x, direction.y, direction.z);
    ospCommit(light);
    ospCommit(world);
    ospRenderFrameBlocking(fb, renderer, camera, world);
    const auto* rgba = static_cast<const float*>(ospMapFrameBuffer(fb, OSP_FB_COLOR));
    const float red = rgba[4 * (2 * 4 + 2)];
    ospUnmapFrameBuffer(rgba, fb);
    return red;
  }
  /// The mean red of a 4x4 image that accumulates `frames` frames.
  float accumulated(int frames) {
    OSPFrameBuffer accum = ospNewFrameBuffer(4, 4, OSP_FB_RGBA32F, OSP_FB_COLOR | OSP_FB_ACCUM);
    for (int f = 0; f < frames; ++f) ospRenderFrameBlocking(accum, renderer, camera, world);
    const auto* rgba = static_cast<const float*>(ospMapFrameBuffer(accum, OSP_FB_COLOR));
    float sum = 0.f;
    for (int p = 0; p < 16; ++p) sum += rgba[4 * p];
    ospUnmapFrameBuffer(rgba, accum);
    ospRelease(accum);
    return sum / 16.f;
  }
};

}  // namespace

TEST_CASE("C API: a normal map tilts a lit quad's normal by its angle (scivis)", "[c_api][texture_maps]") {
  // The quad faces the camera (-z); dP/ds is +x, dP/dt +y. The map tilts the normal by 60
  // degrees towards +x: n = (sin 60, 0, -cos 60).
  const float tilt = pi / 3.f;
  LitQuad quad({0.5f + 0.5f * std::sin(tilt), 0.5f, 0.5f + 0.5f * std::cos(tilt)});
  // Light along the quad's own normal reaches the tilted one at 60 degrees.
  const float head_on = quad.lit({0.f, 0.f, 1.f});
  // Light along the tilted normal reaches it head on.
  const float along = quad.lit({-std::sin(tilt), 0.f, std::cos(tilt)});
  CHECK(head_on == Approx(std::cos(tilt)).margin(1e-4));
  CHECK(along == Approx(1.f).margin(1e-4));
  // map_bump.rotation turns the tilt with the texture, to +y: the light along +x's tilt now
  // meets it at the angle between the two tilted normals (cos^2 60).
  ospSetFloat(quad.material, "map_bump.rotation", 90.f);
  ospCommit(quad.material);
  const float turned = quad.lit({-std::sin(tilt), 0.f, std::cos(tilt)});
  const float turned_along = quad.lit({0.f, -std::sin(tilt), std::cos(tilt)});
  CHECK(turned == Approx(std::cos(tilt) * std::cos(tilt)).margin(1e-4));
  CHECK(turned_along == Approx(1.f).margin(1e-4));
  CHECK(quad.api.messages.errors.empty());
}

TEST_CASE("C API: bounces a normal map sends below the surface meet it again (pathtracer)", "[c_api][texture_maps]") {
  // Lit head on, a Lambertian quad whose map tilts its normal by theta reflects kd cos θ
  // straight from the light; of its bounces, the share (1 - cos θ) / 2 that the tilted
  // normal sends below the quad meets it again, with the same normal and kd, so
  // L = kd cos θ + kd (1 - cos θ) / 2 · L: L = kd cos θ / (1 - kd (1 - cos θ) / 2). OSPRay
  // 3.1's runtime renders this scene (pixelSamples 64, 16 frames) at that value to 0.3 %
  // (θ 30°-89°, kd 0.25-1; e.g. 0.49930 for θ 60°, kd 0.8, and 0.07130 for θ 75°, kd
  // 0.25); dropping those bounces would leave kd cos θ.
  const auto tilted = [](float degrees) {
    const float theta = degrees * pi / 180.f;
    return Vec3f{0.5f + 0.5f * std::sin(theta), 0.5f, 0.5f + 0.5f * std::cos(theta)};
  };
  const auto traced = [](LitQuad& quad, float kd, float view_degrees) {
    ospSetVec3f(quad.material, "kd", kd, kd, kd);
    ospCommit(quad.material);
    // The view turns towards +x, away from the tilt: past 30° the camera sees the quad
    // from below its shading normal.
    const float view = view_degrees * pi / 180.f;
    ospSetVec3f(quad.camera, "position", -5.f * std::sin(view), 0.f, -5.f * std::cos(view));
    ospSetVec3f(quad.camera, "direction", std::sin(view), 0.f, std::cos(view));
    ospSetFloat(quad.camera, "height", 0.25f);
    ospCommit(quad.camera);
    ospCommit(quad.world);
    return quad.accumulated(16);
  };
  const auto closed_form = [](float degrees, float kd) {
    const float c = std::cos(degrees * pi / 180.f);
    return kd * c / (1.f - kd * (1.f - c) / 2.f);
  };
  struct Case {
    float theta, kd, view;
  };
  for (const Case c : {Case{30.f, 1.f, 0.f}, Case{60.f, 0.8f, 0.f}, Case{75.f, 0.25f, 0.f}, Case{89.f, 0.8f, 0.f},
                       // Seen from below its shading normal, a Lambertian surface reflects as
                       // from above (OSPRay: 0.50007 at view 75° and at -75°).
                       Case{60.f, 0.8f, 75.f}}) {
    INFO("theta " << c.theta << ", kd " << c.kd << ", view " << c.view);
    LitQuad quad(tilted(c.theta), "pathtracer");
    ospSetInt(quad.renderer, "pixelSamples", 64);
    ospSetInt(quad.renderer, "maxPathLength", 50);
    ospSetInt(quad.renderer, "roulettePathLength", 50);
    ospCommit(quad.renderer);
    ospSetVec3f(quad.light, "direction", 0.f, 0.f, 1.f);
    ospCommit(quad.light);
    const float expected = closed_form(c.theta, c.kd);
    CHECK(traced(quad, c.kd, c.view) == Approx(expected).epsilon(0.01));
    CHECK(quad.api.messages.errors.empty());
  }

  // White furnace: under ambient light of radiance 1 every bounce that leaves sees 1, and
  // those below the quad scatter again: L = kd (1 + cos θ) / 2 / (1 - kd (1 - cos θ) / 2),
  // 1 for kd 1 (OSPRay: 0.99990 for θ 45°, 0.75043 for θ 60° and kd 0.8).
  for (const float kd : {1.f, 0.8f}) {
    INFO("furnace, kd " << kd);
    LitQuad quad(tilted(60.f), "pathtracer");
    ospSetInt(quad.renderer, "pixelSamples", 64);
    ospSetInt(quad.renderer, "maxPathLength", 50);
    ospSetInt(quad.renderer, "roulettePathLength", 50);
    ospCommit(quad.renderer);
    OSPLight ambient = ospNewLight("ambient");
    ospCommit(ambient);
    LitQuad::set(quad.world, "light", ospNewSharedData1D(&ambient, OSP_LIGHT, 1));
    const float c = 0.5f;
    CHECK(traced(quad, kd, 0.f) == Approx(kd * (1.f + c) / 2.f / (1.f - kd * (1.f - c) / 2.f)).epsilon(0.01));
    ospRelease(ambient);
  }

  // A flat map leaves the path tracer's quad as it is: kd exactly.
  LitQuad flat({0.5f, 0.5f, 1.f}, "pathtracer");
  ospSetVec3f(flat.light, "direction", 0.f, 0.f, 1.f);
  ospCommit(flat.light);
  CHECK(traced(flat, 0.8f, 0.f) == Approx(0.8f).margin(1e-4));
}

TEST_CASE("C API: a mapped parameter defaults to 1, and texture transforms are checked", "[c_api][texture_maps][errors]") {
  // The map alone colours: without kd, a white texel shows white, not 0.8 (OSPRay's factor).
  LitQuad quad({0.5f, 0.5f, 1.f});  // a flat normal map
  const float flat = quad.lit({0.f, 0.f, 1.f});
  CHECK(flat == Approx(1.f).margin(1e-4));
  OSPTexture white = ospNewTexture("texture2d");
  const float one[3] = {1.f, 1.f, 1.f};
  LitQuad::set(white, "data", ospNewSharedData2D(one, OSP_VEC3F, 1, 1));
  ospSetInt(white, "format", OSP_TEXTURE_RGB32F);
  ospCommit(white);
  ospRemoveParam(quad.material, "kd");
  ospSetObject(quad.material, "map_kd", white);
  ospCommit(quad.material);
  CHECK(quad.lit({0.f, 0.f, 1.f}) == Approx(1.f).margin(1e-4));

  ospSetFloat(quad.material, "map_kd.transform", 2.f);
  ospCommit(quad.material);
  quad.api.expect_error("obj material: parameter 'map_kd.transform' must be a linear2f or an affine2f (an affine3f "
                        "transforms volume textures only), got float");
  ospRemoveParam(quad.material, "map_kd.transform");
  ospSetVec2f(quad.material, "map_bump.scale", 0.f, 1.f);
  ospCommit(quad.material);
  quad.api.expect_error("obj material: parameter 'map_bump.scale' must not be zero");
  ospRemoveParam(quad.material, "map_bump.scale");
  ospSetFloat(quad.material, "map_bump.translation", 1.f);
  ospCommit(quad.material);
  quad.api.expect_error("obj material: parameter 'map_bump.translation' must be a vec2f, got float");
  ospRemoveParam(quad.material, "map_bump.translation");
  ospCommit(quad.material);
  CHECK(quad.api.messages.errors.empty());
  ospRelease(white);
}
