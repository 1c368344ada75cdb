// Volume textures: planes (slices) and spheres coloured by a volume through a transfer
// function. A linear field through a linear transfer function gives every point of the
// surface a colour in closed form; the rendered pixels must show it, on every ISA, inside
// the plane's bounds only, and on spheres nothing where the point is outside the volume.
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <memory>
#include <optional>
#include <vector>

#include "sciray/shim/engine.hpp"
#include "support/isas.hpp"

using namespace sciray;
using sciray::test_support::supported_isas;

namespace {

/// f = x + 2y + 3z in world units on [0, 1]³: float voxels, linear layout, 11³ at 0.1.
std::shared_ptr<const StructuredRegular<float>> float_field() {
  const VolumeDims d{11, 11, 11};
  auto voxels = std::make_shared<std::vector<float>>();
  for (std::int64_t z = 0; z < d[2]; ++z)
    for (std::int64_t y = 0; y < d[1]; ++y)
      for (std::int64_t x = 0; x < d[0]; ++x) voxels->push_back(0.1f * static_cast<float>(x + 2 * y + 3 * z));
  return std::make_shared<const StructuredRegular<float>>(LinearLayout<float>(voxels->data(), d, voxels),
                                                          VolumeGrid{{0.f, 0.f, 0.f}, {0.1f, 0.1f, 0.1f}, false});
}

/// 16 (x + 2y + 3z) on [0, 1]³: uint8 voxels 4 (i + 2j + 3k), bricked, 5³ at 0.25.
std::shared_ptr<const StructuredRegular<std::uint8_t, BrickedLayout>> uint8_field() {
  const VolumeDims d{5, 5, 5};
  std::vector<std::uint8_t> voxels;
  for (std::int64_t z = 0; z < d[2]; ++z)
    for (std::int64_t y = 0; y < d[1]; ++y)
      for (std::int64_t x = 0; x < d[0]; ++x) voxels.push_back(static_cast<std::uint8_t>(4 * (x + 2 * y + 3 * z)));
  return std::make_shared<const StructuredRegular<std::uint8_t, BrickedLayout>>(
      BrickedLayout<std::uint8_t>(voxels.data(), d), VolumeGrid{{0.f, 0.f, 0.f}, {0.25f, 0.25f, 0.25f}, false});
}

/// Colour (v/hi, 1 − v/hi, 0.5) over [0, hi]: two entries, so linear in v.
TransferFunction ramp(float hi) { return TransferFunction({{0.f, 1.f, 0.5f}, {1.f, 0.f, 0.5f}}, {1.f}, {0.f, hi}); }

Vec3f ramp_color(float v, float hi) { return {v / hi, 1.f - v / hi, 0.5f}; }

constexpr int size = 32;

/// An orthographic view down +z of x, y in [0, 1] (RGBA32F, first row at the bottom),
/// lit by a white ambient light only, so a pixel shows the surface's albedo.
std::vector<float> render(simd::Isa isa, shim::EngineWorld& world) {
  OrthographicCamera camera;
  camera.position = {0.5f, 0.5f, -5.f};
  camera.direction = {0.f, 0.f, 1.f};
  camera.height = 1.f;
  SciVisParams params;
  params.lights = {AmbientLight{}};
  shim::kernels(isa).commit(world);
  FrameBuffer fb(size, size, ColorFormat::rgba32f, channel_color);
  shim::kernels(isa).render_scivis(world, params, Camera(camera), fb, nullptr);
  return fb.color32f();
}

/// The world point (x, y) of pixel (i, j)'s ray (the camera's own arithmetic).
std::array<float, 2> pixel_xy(int i, int j) {
  OrthographicCamera camera;
  camera.position = {0.5f, 0.5f, -5.f};
  camera.direction = {0.f, 0.f, 1.f};
  camera.height = 1.f;
  const Ray<float> ray = prepare(camera).generate((i + 0.5f) / size, (j + 0.5f) / size);
  return {ray.org.x, ray.org.y};
}

/// Every pixel must show `expected(x, y)` (RGB, alpha 1) or, where it gives nothing, the
/// transparent background. Returns how many pixels show the plane.
int check_image(const std::vector<float>& image, const std::function<std::optional<Vec3f>(float, float)>& expected) {
  int shown = 0, wrong = 0;
  for (int j = 0; j < size; ++j)
    for (int i = 0; i < size; ++i) {
      const auto [x, y] = pixel_xy(i, j);
      const float* p = &image[4 * static_cast<std::size_t>(j * size + i)];
      const auto want = expected(x, y);
      if (!want) {
        wrong += p[3] != 0.f;
        continue;
      }
      ++shown;
      const bool ok = p[3] == 1.f && std::abs(p[0] - want->x) < 2e-5f && std::abs(p[1] - want->y) < 2e-5f &&
                      std::abs(p[2] - want->z) < 2e-5f;
      if (!ok && wrong < 5) {
        UNSCOPED_INFO("pixel (" << i << ", " << j << ") at x = " << x << ", y = " << y << ": got (" << p[0] << ", "
                                << p[1] << ", " << p[2] << ", " << p[3] << "), want (" << want->x << ", " << want->y
                                << ", " << want->z << ", 1)");
      }
      wrong += !ok;
    }
  CHECK(wrong == 0);
  return shown;
}

bool inside(float v, float lo, float hi) { return v > lo && v < hi; }

}  // namespace

TEST_CASE("slice: a linear field through a linear transfer function shows its analytic colour, per ISA",
          "[slice][simd]") {
  const auto volume = float_field();
  // z = 0.5 bounded to x, y in [0.2, 0.8]; and 2x + 2z = 2 (z = 1 − x, its normal not
  // normalized), bounded far outside the view, behind it.
  const std::vector<Planes::Plane> planes{{0.f, 0.f, 1.f, -0.5f}, {2.f, 0.f, 2.f, -2.f}};
  const std::vector<Box3f> bounds{{{0.2f, 0.2f, 0.f}, {0.8f, 0.8f, 1.f}},
                                  {{-1e6f, -1e6f, -1e6f}, {1e6f, 1e6f, 1e6f}}};
  for (auto isa : supported_isas()) {
    INFO(simd::isa_name(isa));
    accel::Device device;
    shim::EngineWorld world(device);
    world.add(VolumeSlice(planes, bounds, volume, ramp(6.f)));
    const auto image = render(isa, world);
    const int shown = check_image(image, [](float x, float y) -> std::optional<Vec3f> {
      // The bounded plane z = 0.5 is in front (from z = -5) wherever it is, except where
      // z = 1 − x is nearer: x > 0.5.
      if (inside(x, 0.2f, 0.8f) && inside(y, 0.2f, 0.8f) && x < 0.5f) return ramp_color(x + 2 * y + 1.5f, 6.f);
      return ramp_color(x + 2 * y + 3 * (1 - x), 6.f);
    });
    CHECK(shown == size * size);
  }
}

TEST_CASE("slice: bounds cut the plane, colours multiply, any voxel type and layout", "[slice]") {
  const auto volume = uint8_field();
  // x + y + z = 1.45 bounded to x in [0.3, 0.7] and z in [0, 1] (inside the volume).
  const std::vector<Planes::Plane> planes{{1.f, 1.f, 1.f, -1.45f}};
  const std::vector<Box3f> bounds{{{0.3f, -1.f, 0.f}, {0.7f, 2.f, 1.f}}};
  for (auto isa : supported_isas()) {
    INFO(simd::isa_name(isa));
    accel::Device device;
    shim::EngineWorld world(device);
    world.add(VolumeSlice(planes, bounds, volume, ramp(96.f), {0.5f, 1.f, 0.25f, 1.f}));
    const auto image = render(isa, world);
    const int shown = check_image(image, [](float x, float y) -> std::optional<Vec3f> {
      const float z = 1.45f - x - y;
      if (!inside(x, 0.3f, 0.7f) || !inside(z, 0.f, 1.f)) return std::nullopt;
      return ramp_color(16.f * (x + 2 * y + 3 * z), 96.f) * Vec3f{0.5f, 1.f, 0.25f};
    });
    CHECK(shown > size * size / 4);
    CHECK(shown < size * size / 2);
  }
  // The hit's u, v are its coordinates in the plane, from the point of the plane nearest
  // the centre of its bounds.
  accel::Device device;
  shim::EngineWorld world(device);
  world.add(VolumeSlice(planes, bounds, volume, ramp(96.f)));
  shim::kernels(shim::select_isa()).commit(world);
  std::vector<Ray<float>> rays{{{0.5f, 0.25f, -5.f}, {0.f, 0.f, 1.f}}};
  std::vector<shim::TraceResult> hits(1);
  shim::kernels(shim::select_isa()).trace(world, rays, hits);
  REQUIRE(hits[0].prim_id == 0);
  CHECK(hits[0].t == Approx(5.7f));
  const Vec3f centre{0.5f, 0.5f, 0.5f}, n = normalize(Vec3f{1.f, 1.f, 1.f});
  const Vec3f origin = centre - n * (dot(n, centre) - 1.45f / std::sqrt(3.f));
  CHECK(std::hypot(hits[0].u, hits[0].v) == Approx(length(Vec3f{0.5f, 0.25f, 0.7f} - origin)).margin(1e-5));
}

TEST_CASE("slice: an instanced slice samples the volume in its own space", "[slice]") {
  const auto volume = float_field();
  const std::vector<Planes::Plane> planes{{0.f, 0.f, 1.f, -0.5f}};
  for (auto isa : supported_isas()) {
    INFO(simd::isa_name(isa));
    accel::Device device;
    shim::EngineWorld world(device);
    auto group = std::make_shared<shim::EngineWorld::GroupType>(device);
    group->add(VolumeSlice(planes, {}, volume, ramp(6.f)));
    // Moved by (0.1, 0, 2): world (x, y) shows the group's (x − 0.1, y) at z = 0.5, and
    // where that lies outside the volume (x < 0.1) the value at its border.
    world.add_instance(group, Affine3f::translate({0.1f, 0.f, 2.f}));
    const auto image = render(isa, world);
    check_image(image, [](float x, float y) -> std::optional<Vec3f> {
      return ramp_color(std::max(x - 0.1f, 0.f) + 2 * y + 1.5f, 6.f);
    });
  }
}

TEST_CASE("slice: bad planes and a missing volume are named", "[slice]") {
  const auto volume = float_field();
  CHECK_THROWS_WITH(VolumeSlice({{0.f, 0.f, 0.f, 1.f}}, {}, volume, ramp(1.f)),
                    Catch::Contains("plane: 'plane.coefficients' 0 has a zero normal"));
  CHECK_THROWS_WITH(VolumeSlice({}, {}, volume, ramp(1.f)), Catch::Contains("'plane.coefficients' is missing"));
  CHECK_THROWS_WITH(
      VolumeSlice({{0.f, 0.f, 1.f, 0.f}}, {}, std::shared_ptr<const StructuredRegular<float>>(), ramp(1.f)),
      Catch::Contains("slice: the volume is missing"));
}

// ---- volume textures on spheres ------------------------------------------------------------

namespace {

/// Every pixel whose ray meets the sphere of `centre` and `radius` (x, y seen down +z)
/// away from its outline must show `expected(front, back)`, the colour given the front
/// and back hit points (nothing: too near an edge to tell); pixels beside it the
/// transparent background. Returns how many pixels were checked on the sphere.
int check_sphere_image(const std::vector<float>& image, const Vec3f& centre, float radius,
                       const std::function<std::optional<Vec3f>(const Vec3f&, const Vec3f&)>& expected) {
  int checked = 0, wrong = 0;
  for (int j = 0; j < size; ++j)
    for (int i = 0; i < size; ++i) {
      const auto [x, y] = pixel_xy(i, j);
      const float* p = &image[4 * static_cast<std::size_t>(j * size + i)];
      const float d2 = (x - centre.x) * (x - centre.x) + (y - centre.y) * (y - centre.y);
      if (d2 > radius * radius * 1.05f) {
        wrong += p[3] != 0.f;
        continue;
      }
      if (d2 > radius * radius * 0.95f) continue;  // the outline
      const float half = std::sqrt(radius * radius - d2);
      const std::optional<Vec3f> expect = expected({x, y, centre.z - half}, {x, y, centre.z + half});
      if (!expect) continue;
      const Vec3f want = *expect;
      ++checked;
      const bool ok = p[3] == 1.f && std::abs(p[0] - want.x) < 1e-4f && std::abs(p[1] - want.y) < 1e-4f &&
                      std::abs(p[2] - want.z) < 1e-4f;
      if (!ok && wrong < 5)
        UNSCOPED_INFO("pixel (" << i << ", " << j << ") at x = " << x << ", y = " << y << ": got (" << p[0] << ", "
                                << p[1] << ", " << p[2] << ", " << p[3] << "), want (" << want.x << ", " << want.y
                                << ", " << want.z << ", 1)");
      wrong += !ok;
    }
  CHECK(wrong == 0);
  return checked;
}

Spheres textured_sphere(const Vec3f& centre, float radius, std::shared_ptr<const VolumeTexture> texture,
                        std::vector<float> rgba = {}) {
  SphereData data;
  data.positions = {centre.x, centre.y, centre.z};
  data.radius = radius;
  data.colors.assign(rgba.begin(), rgba.end());
  return std::move(Spheres(std::move(data)).set_volume_texture(std::move(texture)));
}

}  // namespace

TEST_CASE("volume texture: a sphere shows the transfer function of the volume's value at each hit point on every ISA",
          "[volume_texture][simd]") {
  // f = x + 2y + 3z through the linear ramp over [0, 6]: the colour of every hit point in
  // closed form. The sphere lies inside the volume; the sphere's colour multiplies.
  const auto texture = std::make_shared<const VolumeTexture>(float_field(), ramp(6.f));
  const Vec3f centre{0.5f, 0.5f, 0.4f};
  for (auto isa : supported_isas()) {
    for (auto intersector : {SphereIntersector::sciray, SphereIntersector::embree}) {
      INFO(simd::isa_name(isa) << (intersector == SphereIntersector::sciray ? " sciray" : " embree"));
      accel::Device device;
      shim::EngineWorld world(device);
      world.add(textured_sphere(centre, 0.3f, texture, {0.5f, 1.f, 0.25f, 1.f}).set_intersector(intersector));
      const int checked = check_sphere_image(
          render(isa, world), centre, 0.3f, [](const Vec3f& front, const Vec3f&) -> std::optional<Vec3f> {
            return ramp_color(front.x + 2 * front.y + 3 * front.z, 6.f) * Vec3f{0.5f, 1.f, 0.25f};
          });
      CHECK(checked > 200);
    }
  }
}

TEST_CASE("volume texture: spheres show nothing beyond the volume, the transform and instances move the samples",
          "[volume_texture][instancing]") {
  const auto volume = float_field();
  for (auto isa : supported_isas()) {
    INFO(simd::isa_name(isa));
    // The front of the sphere about (0.5, 0.5, 0.2) reaches z = -0.1, outside [0, 1]³:
    // there it is transparent (OSPRay's volume texture gives colour and opacity 0) and
    // the inside of its back half shows.
    {
      accel::Device device;
      shim::EngineWorld world(device);
      const Vec3f centre{0.5f, 0.5f, 0.2f};
      world.add(textured_sphere(centre, 0.3f, std::make_shared<const VolumeTexture>(volume, ramp(6.f))));
      const auto f = [](const Vec3f& p) { return ramp_color(p.x + 2 * p.y + 3 * p.z, 6.f); };
      int front = 0, back = 0;
      check_sphere_image(render(isa, world), centre, 0.3f,
                         [&](const Vec3f& near, const Vec3f& far) -> std::optional<Vec3f> {
                           if (std::abs(near.z) < 1e-3f) return std::nullopt;
                           ++(near.z >= 0.f ? front : back);
                           return near.z >= 0.f ? f(near) : f(far);
                         });
      CHECK(front > 50);
      CHECK(back > 50);
    }
    // The same sphere about (0.5, 0.5, -0.1) with the texture's transform moving its
    // points by +0.3 in z: the sample points are the previous sphere's minus 0.1 in z.
    {
      accel::Device device;
      shim::EngineWorld world(device);
      const Vec3f centre{0.5f, 0.5f, -0.1f};
      const auto moved =
          std::make_shared<const VolumeTexture>(volume, ramp(6.f), Affine3f::translate({0.f, 0.f, 0.3f}));
      world.add(textured_sphere(centre, 0.3f, moved));
      check_sphere_image(render(isa, world), centre, 0.3f,
                         [](const Vec3f& near, const Vec3f& far) -> std::optional<Vec3f> {
                           if (std::abs(near.z + 0.3f) < 1e-3f) return std::nullopt;
                           const Vec3f p = (near.z + 0.3f >= 0.f ? near : far) + Vec3f{0.f, 0.f, 0.3f};
                           return ramp_color(p.x + 2 * p.y + 3 * p.z, 6.f);
                         });
    }
    // Instanced and moved by (0.1, 0, 2): the group's point, not the world's, is sampled.
    {
      accel::Device device;
      shim::EngineWorld world(device);
      auto group = std::make_shared<shim::EngineWorld::GroupType>(device);
      group->add(textured_sphere({0.4f, 0.5f, 0.4f}, 0.3f, std::make_shared<const VolumeTexture>(volume, ramp(6.f))));
      world.add_instance(group, Affine3f::translate({0.1f, 0.f, 2.f}));
      check_sphere_image(render(isa, world), {0.5f, 0.5f, 2.4f}, 0.3f,
                         [](const Vec3f& near, const Vec3f&) -> std::optional<Vec3f> {
                           return ramp_color(near.x - 0.1f + 2 * near.y + 3 * (near.z - 2.f), 6.f);
                         });
    }
  }
}

TEST_CASE("volume texture: discs cannot take one", "[volume_texture][errors]") {
  Spheres discs =
      textured_sphere({0.f, 0.f, 0.f}, 1.f, std::make_shared<const VolumeTexture>(float_field(), ramp(1.f)));
  discs.set_type(SphereType::disc);
  CHECK_THROWS_WITH(discs.validate(), Catch::Contains("a volume texture colours spheres only, not discs"));
  CHECK_THROWS_WITH(VolumeTexture(std::shared_ptr<const StructuredRegular<float>>(), ramp(1.f)),
                    Catch::Contains("volume texture: the volume is missing"));
}
