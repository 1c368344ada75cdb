// OSPRay's parameter conventions through the C API: a single value where an array is
// expected is a one-element array, a one-element per-primitive array applies to every
// primitive, one model colour overrides the geometry's colours, and models name their
// materials one for all, one per primitive, or by index into the renderer's list.
#include <catch2/catch.hpp>

#include <array>
#include <cstdint>
#include <initializer_list>
#include <vector>

#include <ospray/ospray.h>
#include <ospray/ospray_util.h>

#include "support/api_fixture.hpp"

namespace {

using sciray_test::ApiFixture;

void set_array(OSPObject o, const char* id, const void* values, OSPDataType type, std::uint64_t n) {
  OSPData data = ospNewSharedData1D(values, type, n);
  ospSetObject(o, id, data);
  ospRelease(data);
}

OSPMaterial new_obj(float r, float g, float b) {
  OSPMaterial m = ospNewMaterial("obj");
  ospSetVec3f(m, "kd", r, g, b);
  ospCommit(m);
  return m;
}

/// Two unit quads side by side in z = 0 (primitive 0 at x < 0, primitive 1 at x > 0),
/// seen from above by an orthographic camera under white ambient light of radiance 1
/// only: scivis shows each pixel at exactly its surface's colour times kd.
struct TwoQuads {
  OSPGeometry mesh = ospNewGeometry("mesh");
  OSPGeometricModel model = nullptr;
  OSPGroup group = ospNewGroup();
  OSPInstance instance = nullptr;
  OSPWorld world = ospNewWorld();
  OSPCamera camera = ospNewCamera("orthographic");
  OSPLight ambient = ospNewLight("ambient");
  OSPRenderer renderer = ospNewRenderer("scivis");

  TwoQuads() {
    // Static: the array is shared (not copied), and tests commit the mesh again later.
    static constexpr float positions[] = {-1, -1, 0, 0, -1, 0, 0, 1, 0, -1, 1, 0, 0, -1, 0, 1, -1, 0, 1, 1, 0, 0, 1, 0};
    set_array(mesh, "vertex.position", positions, OSP_VEC3F, 8);
    ospSetBool(mesh, "quadSoup", true);  // no `index`: consecutive vertices make the quads
    ospCommit(mesh);
    model = ospNewGeometricModel(mesh);
    ospCommit(model);
    ospSetObjectAsData(group, "geometry", OSP_GEOMETRIC_MODEL, model);
    ospCommit(group);
    instance = ospNewInstance(group);
    ospCommit(instance);
    ospSetObjectAsData(world, "instance", OSP_INSTANCE, instance);
    ospCommit(ambient);
    ospSetObjectAsData(world, "light", OSP_LIGHT, ambient);
    ospCommit(world);
    ospSetVec3f(camera, "position", 0.f, 0.f, 5.f);
    ospSetVec3f(camera, "direction", 0.f, 0.f, -1.f);
    ospSetFloat(camera, "height", 1.5f);
    ospCommit(camera);
    ospSetInt(renderer, "pixelFilter", OSP_PIXELFILTER_POINT);
    ospCommit(renderer);
  }
  ~TwoQuads() {
    for (OSPObject o : std::initializer_list<OSPObject>{mesh, model, group, instance, world, camera, ambient, renderer})
      ospRelease(o);
  }
  /// After a change to the model: the mean RGB of the left (x < 0) and right halves.
  std::array<std::array<float, 3>, 2> render() {
    ospCommit(model);
    ospCommit(group);
    ospCommit(world);
    OSPFrameBuffer fb = ospNewFrameBuffer(8, 8, OSP_FB_RGBA32F, OSP_FB_COLOR);
    ospRenderFrameBlocking(fb, renderer, camera, world);
    const auto* rgba = static_cast<const float*>(ospMapFrameBuffer(fb, OSP_FB_COLOR));
    std::array<std::array<float, 3>, 2> mean{};
    for (int y = 0; y < 8; ++y)
      for (int x = 0; x < 8; ++x)
        for (int c = 0; c < 3; ++c) mean[x < 4 ? 0 : 1][c] += rgba[4 * (8 * y + x) + c] / 32.f;
    ospUnmapFrameBuffer(rgba, fb);
    ospRelease(fb);
    return mean;
  }
};

void check_color(const std::array<float, 3>& got, float r, float g, float b) {
  CHECK(got[0] == Approx(r).margin(1e-5));
  CHECK(got[1] == Approx(g).margin(1e-5));
  CHECK(got[2] == Approx(b).margin(1e-5));
}

}  // namespace

TEST_CASE("a model's colour: one value or a one-element array colours every primitive, over the geometry's colours",
          "[c_api][conventions]") {
  ApiFixture api;
  TwoQuads scene;
  // Vertex colours of the geometry: red, which the model's colour replaces.
  std::vector<float> red(8 * 4, 0.f);
  for (int v = 0; v < 8; ++v) red[4 * v] = red[4 * v + 3] = 1.f;
  set_array(scene.mesh, "vertex.color", red.data(), OSP_VEC4F, 8);
  ospCommit(scene.mesh);
  check_color(scene.render()[0], 1.f, 0.f, 0.f);

  ospSetVec4f(scene.model, "color", 0.2f, 0.4f, 0.6f, 1.f);
  auto halves = scene.render();
  check_color(halves[0], 0.2f, 0.4f, 0.6f);
  check_color(halves[1], 0.2f, 0.4f, 0.6f);

  const float one[3] = {0.5f, 0.25f, 1.f};
  set_array(scene.model, "color", one, OSP_VEC3F, 1);
  halves = scene.render();
  check_color(halves[0], 0.5f, 0.25f, 1.f);
  check_color(halves[1], 0.5f, 0.25f, 1.f);

  // With a material, the colour multiplies its kd.
  OSPMaterial half = new_obj(0.5f, 0.5f, 0.5f);
  ospSetObject(scene.model, "material", half);
  check_color(scene.render()[1], 0.25f, 0.125f, 0.5f);
  ospRelease(half);

  // A colour of the wrong type stays an error naming the model and the parameter.
  ospSetFloat(scene.model, "color", 0.5f);
  ospCommit(scene.model);
  api.expect_error("geometric model: parameter 'color' must be an OSPData array of vec4f or vec3f (or one vec4f or "
                   "vec3f), got float");
}

TEST_CASE("a model's materials: one for all, one per primitive, or indices into the renderer's list",
          "[c_api][conventions]") {
  ApiFixture api;
  TwoQuads scene;
  OSPMaterial a = new_obj(0.9f, 0.1f, 0.1f), b = new_obj(0.1f, 0.9f, 0.1f);

  // One material in a one-element array: every primitive.
  ospSetObjectAsData(scene.model, "material", OSP_MATERIAL, a);
  auto halves = scene.render();
  check_color(halves[0], 0.9f, 0.1f, 0.1f);
  check_color(halves[1], 0.9f, 0.1f, 0.1f);

  // One per primitive.
  OSPMaterial both[2] = {b, a};
  set_array(scene.model, "material", both, OSP_MATERIAL, 2);
  halves = scene.render();
  check_color(halves[0], 0.1f, 0.9f, 0.1f);
  check_color(halves[1], 0.9f, 0.1f, 0.1f);

  // Indices into the renderer's `material` list, per primitive; an index beyond the list
  // shows the default obj material (kd 0.8).
  set_array(scene.renderer, "material", both, OSP_MATERIAL, 2);
  ospCommit(scene.renderer);
  const std::uint32_t indices[2] = {1, 7};
  set_array(scene.model, "material", indices, OSP_UINT, 2);
  halves = scene.render();
  check_color(halves[0], 0.9f, 0.1f, 0.1f);
  check_color(halves[1], 0.8f, 0.8f, 0.8f);
  // One index for all, as a single value.
  ospSetUInt(scene.model, "material", 0);
  halves = scene.render();
  check_color(halves[0], 0.1f, 0.9f, 0.1f);
  check_color(halves[1], 0.1f, 0.9f, 0.1f);
  CHECK(api.messages.errors.empty());

  // More materials than primitives: the extra ones are ignored, as by OSPRay; a negative
  // index is an error naming the element.
  const std::uint32_t three_indices[3] = {0, 1, 0};
  OSPGeometry three = ospNewGeometry("mesh");
  const float positions[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  set_array(three, "vertex.position", positions, OSP_VEC3F, 3);
  ospCommit(three);  // one triangle
  OSPGeometricModel single = ospNewGeometricModel(three);
  set_array(single, "material", three_indices, OSP_UINT, 3);
  ospCommit(single);
  CHECK(api.messages.errors.empty());
  const std::int32_t negative[2] = {0, -1};
  set_array(scene.model, "material", negative, OSP_INT, 2);
  ospCommit(scene.model);
  api.expect_error("geometric model: parameter 'material' element 1 is a negative index -1");
  for (OSPObject o : std::initializer_list<OSPObject>{a, b, three, single}) ospRelease(o);
}

TEST_CASE("a one-element sphere.radius is every sphere's radius", "[c_api][conventions]") {
  ApiFixture api;
  OSPGeometry spheres = ospNewGeometry("sphere");
  const float centers[6] = {0, 0, 0, 10, 0, 0};
  const float radius = 2.f;
  set_array(spheres, "sphere.position", centers, OSP_VEC3F, 2);
  set_array(spheres, "sphere.radius", &radius, OSP_FLOAT, 1);
  ospCommit(spheres);
  const OSPBounds bounds = ospGetBounds(spheres);
  CHECK(bounds.lower[0] == Approx(-2.f));
  CHECK(bounds.upper[0] == Approx(12.f));
  CHECK(bounds.upper[1] == Approx(2.f));
  const float radii[3] = {1.f, 3.f, 99.f};  // a third radius for no sphere is ignored
  set_array(spheres, "sphere.radius", radii, OSP_FLOAT, 3);
  ospCommit(spheres);
  CHECK(ospGetBounds(spheres).upper[0] == Approx(13.f));
  CHECK(api.messages.errors.empty());
  ospRelease(spheres);
}
