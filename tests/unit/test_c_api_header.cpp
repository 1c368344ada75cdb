// What OSPRay 3.2's headers add over the earlier API, exercised through the C API:
// ospSetUInt, ospSetBox1f, ospSetLinear2f, ospNewAssignedData1D, every OSPTextureFormat
// (half floats included), the sphere types at their OSPRay 3 values (50, 51, 52), the
// enumerations' C++ underlying types, and ospInit's use of argv.
#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <initializer_list>
#include <limits>
#include <string>
#include <tuple>
#include <type_traits>
#include <vector>

#include <ospray/ospray.h>
#include <ospray/ospray_util.h>

#include "sciray/math/color.hpp"
#include "support/api_fixture.hpp"

namespace {

using sciray_test::ApiFixture;

// In C++ OSPRay fixes each enumeration's size: a program that passes an enum variable's
// address to ospSetParam (OSP_UINT, or OSP_UCHAR for cell types) relies on it.
template <class E, class Underlying>
constexpr bool underlying_is = std::is_same_v<std::underlying_type_t<E>, Underlying>;
static_assert(underlying_is<OSPLogLevel, std::uint32_t> && underlying_is<OSPDeviceProperty, std::uint32_t> &&
              underlying_is<OSPDataType, std::uint32_t> && underlying_is<OSPTextureFormat, std::uint32_t> &&
              underlying_is<OSPTextureFilter, std::uint32_t> && underlying_is<OSPTextureWrapMode, std::uint32_t> &&
              underlying_is<OSPError, std::uint32_t> && underlying_is<OSPFrameBufferFormat, std::uint32_t> &&
              underlying_is<OSPFrameBufferChannel, std::uint32_t> && underlying_is<OSPSyncEvent, std::uint32_t> &&
              underlying_is<OSPStereoMode, std::uint32_t> && underlying_is<OSPShutterType, std::uint32_t> &&
              underlying_is<OSPCurveType, std::uint32_t> && underlying_is<OSPSphereType, std::uint32_t> &&
              underlying_is<OSPCurveBasis, std::uint32_t> && underlying_is<OSPSubdivisionMode, std::uint32_t> &&
              underlying_is<OSPAMRMethod, std::uint32_t> && underlying_is<OSPVolumeFilter, std::uint32_t> &&
              underlying_is<OSPVolumeFormat, std::uint32_t> && underlying_is<OSPPixelFilterType, std::uint32_t> &&
              underlying_is<OSPIntensityQuantity, std::uint32_t> && underlying_is<OSPDenoiserQuality, std::uint32_t> &&
              underlying_is<OSPUnstructuredCellType, std::uint8_t>);

/// One model of `geometry` (with `material`, if any) under an ambient light, seen by an
/// orthographic camera at z = 5 looking down -z over [-1, 1]^2, rendered by scivis with
/// the point pixel filter into float colour and depth.
struct FlatScene {
  OSPGeometricModel model;
  OSPGroup group = ospNewGroup();
  OSPInstance instance = ospNewInstance(group);
  OSPWorld world = ospNewWorld();
  OSPLight light = ospNewLight("ambient");
  OSPCamera camera = ospNewCamera("orthographic");
  OSPRenderer renderer = ospNewRenderer("scivis");

  explicit FlatScene(OSPGeometry geometry, OSPMaterial material = nullptr) : model(ospNewGeometricModel(geometry)) {
    if (material) ospSetObject(model, "material", material);
    ospCommit(model);
    ospSetObjectAsData(group, "geometry", OSP_GEOMETRIC_MODEL, model);
    ospCommit(group);
    ospCommit(instance);
    ospSetObjectAsData(world, "instance", OSP_INSTANCE, instance);
    ospCommit(light);
    ospSetObjectAsData(world, "light", OSP_LIGHT, light);
    ospCommit(world);
    ospSetVec3f(camera, "position", 0.f, 0.f, 5.f);
    ospSetVec3f(camera, "direction", 0.f, 0.f, -1.f);
    ospSetFloat(camera, "height", 2.f);
    ospSetFloat(camera, "aspect", 1.f);
    ospCommit(camera);
    ospSetInt(renderer, "pixelFilter", OSP_PIXELFILTER_POINT);
    ospCommit(renderer);
  }
  FlatScene(const FlatScene&) = delete;
  FlatScene& operator=(const FlatScene&) = delete;
  ~FlatScene() {
    for (OSPObject o : std::initializer_list<OSPObject>{model, group, instance, world, light, camera, renderer})
      ospRelease(o);
  }

  static constexpr int size = 8;
  struct Image {
    std::vector<float> rgba, depth;
    /// Pixel (x, y), row 0 at the bottom.
    const float* color(int x, int y) const { return &rgba[4 * (y * size + x)]; }
  };
  Image render() const {
    OSPFrameBuffer fb = ospNewFrameBuffer(size, size, OSP_FB_RGBA32F, OSP_FB_COLOR | OSP_FB_DEPTH);
    ospRenderFrameBlocking(fb, renderer, camera, world);
    Image image;
    const auto* rgba = static_cast<const float*>(ospMapFrameBuffer(fb, OSP_FB_COLOR));
    image.rgba.assign(rgba, rgba + 4 * size * size);
    ospUnmapFrameBuffer(rgba, fb);
    const auto* depth = static_cast<const float*>(ospMapFrameBuffer(fb, OSP_FB_DEPTH));
    image.depth.assign(depth, depth + size * size);
    ospUnmapFrameBuffer(depth, fb);
    ospRelease(fb);
    return image;
  }
};

/// The bytes of one texel of channels `values`.
template <class T, class... More>
std::vector<std::uint8_t> of(T first, More... more) {
  const T values[] = {first, more...};
  std::vector<std::uint8_t> bytes(sizeof values);
  std::memcpy(bytes.data(), values, sizeof values);
  return bytes;
}

/// The quad [-1, 1]^2 at z = 0 facing the camera, texture coordinates (0, 0) to (1, 1).
OSPGeometry textured_quad() {
  static const float positions[] = {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0};
  static const std::uint32_t index[] = {0, 1, 2, 3};
  static const float texcoords[] = {0, 0, 1, 0, 1, 1, 0, 1};
  OSPGeometry quad = ospNewGeometry("mesh");
  for (auto [id, data, type, count] :
       {std::tuple{"vertex.position", static_cast<const void*>(positions), OSP_VEC3F, 4},
        std::tuple{"index", static_cast<const void*>(index), OSP_VEC4UI, 1},
        std::tuple{"vertex.texcoord", static_cast<const void*>(texcoords), OSP_VEC2F, 4}}) {
    OSPData d = ospNewSharedData1D(data, type, count);
    ospSetObject(quad, id, d);
    ospRelease(d);
  }
  ospCommit(quad);
  return quad;
}

/// A nearest-filtered texture2d of width x height texels of `type`.
OSPTexture new_texture(OSPTextureFormat format, const void* texels, OSPDataType type, int width, int height) {
  OSPTexture texture = ospNewTexture("texture2d");
  OSPData data = ospNewSharedData2D(texels, type, width, height);
  ospSetObject(texture, "data", data);
  ospRelease(data);
  ospSetUInt(texture, "format", format);
  ospSetInt(texture, "filter", OSP_TEXTURE_FILTER_NEAREST);
  ospCommit(texture);
  return texture;
}

/// The colour of the quad under an obj material whose map_kd is `texture` (kd 1).
std::array<float, 3> quad_color(OSPTexture texture) {
  OSPGeometry quad = textured_quad();
  OSPMaterial material = ospNewMaterial("obj");
  ospSetVec3f(material, "kd", 1.f, 1.f, 1.f);  // the map's colour itself (the default kd is 0.8)
  ospSetObject(material, "map_kd", texture);
  ospCommit(material);
  FlatScene scene(quad, material);
  const auto image = scene.render();
  const float* c = image.color(FlatScene::size / 2, FlatScene::size / 2);
  ospRelease(material);
  ospRelease(quad);
  return {c[0], c[1], c[2]};
}

}  // namespace

TEST_CASE("ospInit touches only argv[0 .. *argc - 1]", "[c_api][device]") {
  // The application passes fewer arguments than its array holds: what lies past them
  // is not ospInit's, whether or not it removes arguments.
  const char* sentinel = "not ospInit's";
  {
    int argc = 2;
    const char* argv[] = {"app", "scene.ply", sentinel};
    REQUIRE(ospInit(&argc, argv) == OSP_NO_ERROR);
    CHECK(argc == 2);
    CHECK(std::string(argv[1]) == "scene.ply");
    CHECK(argv[2] == sentinel);
    ospShutdown();
  }
  {
    int argc = 3;
    const char* argv[] = {"app", "--osp:num-threads=1", "scene.ply", sentinel};
    REQUIRE(ospInit(&argc, argv) == OSP_NO_ERROR);
    CHECK(argc == 2);
    CHECK(std::string(argv[1]) == "scene.ply");
    CHECK(argv[3] == sentinel);
    ospShutdown();
  }
  {
    int argc = 0;  // no program name either
    const char* argv[] = {sentinel};
    REQUIRE(ospInit(&argc, argv) == OSP_NO_ERROR);
    CHECK(argc == 0);
    CHECK(argv[0] == sentinel);
    ospShutdown();
  }
  REQUIRE(ospInit(nullptr, nullptr) == OSP_NO_ERROR);
  ospShutdown();
}

TEST_CASE("ospSetUInt sets an enumeration: sphere types are OSPRay 3's 50, 51, 52", "[c_api][spheres]") {
  ApiFixture api;
  // One sphere of radius 0.75 at the origin seen from z = 5: a sphere's depth grows
  // towards its rim, a disc facing the camera lies at depth 5 everywhere.
  const float position[3] = {0.f, 0.f, 0.f}, radius = 0.75f;
  OSPGeometry spheres = ospNewGeometry("sphere");
  OSPData data = ospNewSharedData1D(position, OSP_VEC3F, 1);
  ospSetObject(spheres, "sphere.position", data);
  ospRelease(data);
  ospSetFloat(spheres, "radius", radius);
  for (const OSPSphereType type : {OSP_SPHERE, OSP_DISC}) {
    INFO("type " << static_cast<unsigned>(type));
    ospSetUInt(spheres, "type", type);
    ospCommit(spheres);
    REQUIRE(api.messages.errors.empty());
    FlatScene scene(spheres);
    const auto image = scene.render();
    // Pixels (4, 4) and (5, 5) are centred on the diagonal at 0.125 and 0.375.
    for (const int i : {4, 5}) {
      const float offset = -1.f + (i + 0.5f) * 2.f / FlatScene::size;
      const float expected = type == OSP_DISC ? 5.f : 5.f - std::sqrt(radius * radius - 2 * offset * offset);
      CHECK(image.depth[i * FlatScene::size + i] == Approx(expected).margin(1e-4));
    }
    CHECK(image.depth[0] == std::numeric_limits<float>::infinity());  // a corner: nothing
  }
  // OSPRay 2's value of OSP_DISC is not a sphere type in OSPRay 3.
  ospSetUInt(spheres, "type", 1);
  ospCommit(spheres);
  api.expect_error(
      "sphere geometry: parameter 'type' has unknown value 1 (OSP_SPHERE = 50, OSP_DISC = 51, "
      "OSP_ORIENTED_DISC = 52)");
  ospRelease(spheres);
}

TEST_CASE("ospSetBox1f sets a range: a transfer function's value", "[c_api][volume]") {
  ApiFixture api;
  OSPTransferFunction tf = ospNewTransferFunction("piecewiseLinear");
  const float colors[6] = {0, 0, 0, 1, 1, 1};
  const float opacities[2] = {0, 1};
  OSPData color = ospNewSharedData1D(colors, OSP_VEC3F, 2);
  OSPData opacity = ospNewSharedData1D(opacities, OSP_FLOAT, 2);
  ospSetObject(tf, "color", color);
  ospSetObject(tf, "opacity", opacity);
  ospRelease(color);
  ospRelease(opacity);
  ospSetBox1f(tf, "value", -2.f, 3.f);
  ospCommit(tf);
  CHECK(api.messages.errors.empty());
  // Both ends arrive, in order: a reversed range is refused with them.
  ospSetBox1f(tf, "value", 3.f, -2.f);
  ospCommit(tf);
  api.expect_error("'value' must be a finite range with lo < hi, got [3.000000, -2.000000]");
  ospRelease(tf);
}

TEST_CASE("ospSetLinear2f sets a map's transform: mirrored u reads the other half", "[c_api][texture_maps]") {
  ApiFixture api;
  const float texels[6] = {1.f, 0.f, 0.f, 0.f, 1.f, 0.f};  // 2x1: red | green
  OSPTexture texture = new_texture(OSP_TEXTURE_RGB32F, texels, OSP_VEC3F, 2, 1);
  OSPGeometry quad = textured_quad();
  OSPMaterial material = ospNewMaterial("obj");
  ospSetVec3f(material, "kd", 1.f, 1.f, 1.f);  // the map's colour itself (the default kd is 0.8)
  ospSetObject(material, "map_kd", texture);
  ospCommit(material);
  const auto left_pixel = [&] {
    FlatScene scene(quad, material);
    const auto image = scene.render();
    return std::array<float, 3>{image.color(1, 4)[0], image.color(1, 4)[1], image.color(1, 4)[2]};  // u = 0.19
  };
  const auto red = left_pixel();
  CHECK((red[0] == Approx(1.f).margin(1e-5) && red[1] == Approx(0.f).margin(1e-5)));
  ospSetLinear2f(material, "map_kd.transform", -1.f, 0.f, 0.f, 1.f);  // u -> -u, tiled: 0.81
  ospCommit(material);
  const auto green = left_pixel();
  CHECK((green[0] == Approx(0.f).margin(1e-5) && green[1] == Approx(1.f).margin(1e-5)));
  CHECK(api.messages.errors.empty());
  // OSPRay's legacy vec4f form is the same linear2f.
  ospSetVec4f(material, "map_kd.transform", -1.f, 0.f, 0.f, 1.f);
  ospCommit(material);
  const auto legacy = left_pixel();
  CHECK((legacy[0] == Approx(0.f).margin(1e-5) && legacy[1] == Approx(1.f).margin(1e-5)));
  ospSetVec3f(material, "map_kd.transform", -1.f, 0.f, 0.f);
  ospCommit(material);
  api.expect_error("obj material: parameter 'map_kd.transform' must be a linear2f or an affine2f (an affine3f "
                   "transforms volume textures only), got vec3f");
  for (OSPObject o : std::initializer_list<OSPObject>{texture, quad, material}) ospRelease(o);
}

TEST_CASE("ospNewAssignedData1D shares the application's array and calls its deleter once", "[c_api][data]") {
  ApiFixture api;
  struct Deletions {
    int count = 0;
    const void* user = nullptr;
    const void* shared = nullptr;
  } deletions;
  const float positions[6] = {0.f, 0.f, 0.f, 2.f, 3.f, 4.f};
  OSPData data = ospNewAssignedData1D(
      positions, OSP_VEC3F, 2,
      [](const void* user, const void* shared) {
        auto* d = static_cast<Deletions*>(const_cast<void*>(user));
        ++d->count;
        d->user = user;
        d->shared = shared;
      },
      &deletions);
  REQUIRE(data);
  OSPGeometry spheres = ospNewGeometry("sphere");
  ospSetObject(spheres, "sphere.position", data);
  ospSetFloat(spheres, "radius", 0.5f);
  ospCommit(spheres);
  ospRelease(data);
  CHECK(deletions.count == 0);  // the geometry still holds the array
  // Its contents are the application's: the bounds span both spheres.
  const OSPBounds b = ospGetBounds(spheres);
  CHECK(std::vector<float>(b.lower, b.lower + 3) == std::vector<float>{-0.5f, -0.5f, -0.5f});
  CHECK(std::vector<float>(b.upper, b.upper + 3) == std::vector<float>{2.5f, 3.5f, 4.5f});
  ospRelease(spheres);
  CHECK(deletions.count == 1);
  CHECK(deletions.user == &deletions);
  CHECK(deletions.shared == positions);
  CHECK(api.messages.errors.empty());
}

TEST_CASE("every OSPTextureFormat colours a map_kd, half floats included", "[c_api][texture_maps]") {
  ApiFixture api;
  // Half floats: 0.25, 0.5, 0.75 and 1 in IEEE 754 binary16.
  constexpr std::uint16_t h25 = 0x3400, h50 = 0x3800, h75 = 0x3A00, h1 = 0x3C00;
  const float quarter_srgb = sciray::srgb_to_linear(64.f / 255.f);
  struct Case {
    OSPTextureFormat format;
    OSPDataType type;
    std::vector<std::uint8_t> bytes;  // one texel, opaque: a map_kd's alpha is opacity (test_texture_maps.cpp)
    std::array<float, 3> linear;      // sciray's textures are RGB: grey from one or two channels
  };
  using u8 = std::uint8_t;
  using u16 = std::uint16_t;
  const Case cases[] = {
      {OSP_TEXTURE_RGBA8, OSP_VEC4UC, of(u8{255}, u8{0}, u8{51}, u8{255}), {1.f, 0.f, 0.2f}},
      {OSP_TEXTURE_SRGBA, OSP_VEC4UC, of(u8{64}, u8{255}, u8{0}, u8{255}), {quarter_srgb, 1.f, 0.f}},
      {OSP_TEXTURE_RGBA32F, OSP_VEC4F, of(0.5f, 0.25f, 1.f, 1.f), {0.5f, 0.25f, 1.f}},
      {OSP_TEXTURE_RGB8, OSP_VEC3UC, of(u8{0}, u8{51}, u8{255}), {0.f, 0.2f, 1.f}},
      {OSP_TEXTURE_SRGB, OSP_VEC3UC, of(u8{255}, u8{64}, u8{0}), {1.f, quarter_srgb, 0.f}},
      {OSP_TEXTURE_RGB32F, OSP_VEC3F, of(0.75f, 0.f, 0.5f), {0.75f, 0.f, 0.5f}},
      {OSP_TEXTURE_R8, OSP_UCHAR, of(u8{51}), {0.2f, 0.f, 0.f}},
      {OSP_TEXTURE_R32F, OSP_FLOAT, of(0.75f), {0.75f, 0.f, 0.f}},
      {OSP_TEXTURE_L8, OSP_UCHAR, of(u8{64}), {quarter_srgb, quarter_srgb, quarter_srgb}},
      {OSP_TEXTURE_RA8, OSP_VEC2UC, of(u8{102}, u8{255}), {0.4f, 0.f, 0.f}},
      {OSP_TEXTURE_LA8, OSP_VEC2UC, of(u8{64}, u8{255}), {quarter_srgb, quarter_srgb, quarter_srgb}},
      {OSP_TEXTURE_RGBA16, OSP_VEC4US, of(u16{65535}, u16{0}, u16{13107}, u16{65535}), {1.f, 0.f, 0.2f}},
      {OSP_TEXTURE_RGB16, OSP_VEC3US, of(u16{13107}, u16{65535}, u16{0}), {0.2f, 1.f, 0.f}},
      {OSP_TEXTURE_RA16, OSP_VEC2US, of(u16{26214}, u16{65535}), {0.4f, 0.f, 0.f}},
      {OSP_TEXTURE_R16, OSP_USHORT, of(u16{52428}), {0.8f, 0.f, 0.f}},
      {OSP_TEXTURE_RGBA16F, OSP_VEC4US, of(h25, h50, h75, h1), {0.25f, 0.5f, 0.75f}},
      {OSP_TEXTURE_RGBA16F, OSP_VEC4H, of(h1, h75, h50, h1), {1.f, 0.75f, 0.5f}},
      {OSP_TEXTURE_RGB16F, OSP_VEC3US, of(h75, h25, h1), {0.75f, 0.25f, 1.f}},
      {OSP_TEXTURE_RGB16F, OSP_VEC3H, of(h50, h1, h25), {0.5f, 1.f, 0.25f}},
      {OSP_TEXTURE_RA16F, OSP_VEC2US, of(h75, h1), {0.75f, 0.f, 0.f}},
      {OSP_TEXTURE_RA16F, OSP_VEC2H, of(h25, h1), {0.25f, 0.f, 0.f}},
      {OSP_TEXTURE_R16F, OSP_USHORT, of(h50), {0.5f, 0.f, 0.f}},
      {OSP_TEXTURE_R16F, OSP_HALF, of(u16{0x0200}), {0x1p-15f, 0.f, 0.f}},  // subnormal: 512 * 2^-24
      {OSP_TEXTURE_RA32F, OSP_VEC2F, of(0.25f, 1.f), {0.25f, 0.f, 0.f}}};
  for (const Case& c : cases) {
    INFO("format " << static_cast<unsigned>(c.format) << " as data type " << static_cast<unsigned>(c.type));
    OSPTexture texture = new_texture(c.format, c.bytes.data(), c.type, 1, 1);
    REQUIRE(api.messages.errors.empty());
    const auto color = quad_color(texture);
    for (int k = 0; k < 3; ++k) CHECK(color[k] == Approx(c.linear[k]).epsilon(1e-4).margin(1e-6));
    ospRelease(texture);
  }
  CHECK(api.messages.errors.empty());

  // A half format needs 16-bit elements, and a format must be one OSPRay has.
  const float texel[3] = {0.5f, 0.5f, 0.5f};
  OSPTexture texture = new_texture(OSP_TEXTURE_RGB16F, texel, OSP_VEC3F, 1, 1);
  api.expect_error(
      "texture2d texture: parameter 'data' holds vec3f elements but 'format' OSP_TEXTURE_RGB16F needs vec3us or vec3h");
  ospSetUInt(texture, "format", 20);
  ospCommit(texture);
  api.expect_error("texture2d texture: parameter 'format' 20 is not an OSPTextureFormat (OSP_TEXTURE_RGBA8, SRGBA");
  // Half infinities and NaNs are not colours.
  const std::uint16_t infinite[3] = {0x7C00, h50, h50};
  OSPData data = ospNewSharedData2D(infinite, OSP_VEC3US, 1, 1);
  ospSetObject(texture, "data", data);
  ospRelease(data);
  ospSetUInt(texture, "format", OSP_TEXTURE_RGB16F);
  ospCommit(texture);
  api.expect_error("texture2d texture: texture2d: texel 0 is negative or not finite");
  ospRelease(texture);
}

TEST_CASE("OSPRay 3.2's denoiser is absent, said so by name", "[c_api][errors]") {
  ApiFixture api;
  // OSPDenoiserQuality is the denoiser's 'quality': the headers declare it, sciray has no
  // denoiser.
  CHECK(ospNewImageOperation("denoiser") == nullptr);
  api.expect_error("unknown image operation type 'denoiser' (sciray supports: tonemapper, debug)");
  CHECK(ospLoadModule("denoiser") != OSP_NO_ERROR);
}
