// Worlds of geometries and instances: Embree instancing places shared groups by affine
// transforms, hits report the instance, shading sees world-space normals, and instances
// cost almost nothing beyond their group.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdlib>
#include <memory>
#include <vector>

#include "sciray/io/frame_io.hpp"
#include "sciray/io/ply.hpp"
#include "sciray/shim/engine.hpp"
#include "sciray/testing/image_compare.hpp"
#include "sciray/testing/scenes.hpp"
#include "support/isas.hpp"

using namespace sciray;
using sciray::test_support::supported_isas;

namespace {

/// A rotation about `axis` by `degrees`, then a scale and a translation.
Affine3f rotate_scale_translate(Vec3f axis, float degrees, float scale, Vec3f translation) {
  axis = normalize(axis);
  const float a = degrees * 3.14159265f / 180.f, c = std::cos(a), s = std::sin(a);
  const auto column = [&](const Vec3f& e) {
    return (e * c + cross(axis, e) * s + axis * (dot(axis, e) * (1 - c))) * scale;
  };
  return {column({1, 0, 0}), column({0, 1, 0}), column({0, 0, 1}), translation};
}

}  // namespace

TEST_CASE("instances of one group are hit where their transforms put them", "[world][instancing][simd]") {
  SphereData unit;
  unit.positions = {0.f, 0.f, 0.f};
  unit.radius = 1.f;
  for (auto isa : supported_isas()) {
    INFO(simd::isa_name(isa));
    accel::Device device;
    shim::EngineWorld world(device);
    auto group = std::make_shared<shim::EngineWorld::GroupType>(device);
    group->add(Spheres(unit));
    world.add(Boxes({Box3f{{-1.f, -1.f, 9.f}, {1.f, 1.f, 10.f}}}));  // a direct geometry: id 0
    for (float x : {-4.f, 0.f, 4.f}) world.add_instance(group, Affine3f::translate({x, 0.f, 0.f}));
    world.add_instance(group, Affine3f::scale(2.f) * Affine3f::translate({0.f, 3.f, 0.f}));  // centre (0,6,0), r 2
    shim::kernels(isa).commit(world);

    const std::vector<Ray<float>> rays{{{-4.f, 0.f, -5.f}, {0.f, 0.f, 1.f}}, {{0.f, 0.f, -5.f}, {0.f, 0.f, 1.f}},
                                       {{4.5f, 0.f, -5.f}, {0.f, 0.f, 1.f}}, {{0.f, 6.f, -5.f}, {0.f, 0.f, 1.f}},
                                       {{0.f, 3.f, -5.f}, {0.f, 0.f, 1.f}}};
    std::vector<shim::TraceResult> got(rays.size());
    shim::kernels(isa).trace(world, rays, got);
    // Instances take the top-level ids after the direct geometries.
    CHECK(got[0].inst_id == 1);
    CHECK(got[0].t == Approx(4.f));
    CHECK(got[1].inst_id == 2);
    CHECK(got[2].inst_id == 3);
    CHECK(got[2].t == Approx(5.f - std::sqrt(0.75f)).epsilon(1e-5));
    CHECK(got[3].inst_id == 4);
    CHECK(got[3].t == Approx(3.f).epsilon(1e-5));  // the scaled sphere: radius 2
    CHECK(got[4].inst_id == -1);                    // between the instances: the box behind
    CHECK(got[4].geom_id == -1);
  }
}

TEST_CASE("an instanced mesh renders as the same mesh transformed in place", "[world][instancing][render]") {
  const Affine3f transform = rotate_scale_translate({0.3f, 1.f, 0.2f}, 35.f, 1.7f, {0.5f, -0.2f, 3.f});
  MeshData bunny = io::read_ply(SCIRAY_DATA_DIR "/meshes/bunny.ply");
  MeshData moved = bunny;
  for (std::size_t v = 0; v < moved.vertex_count(); ++v) {
    const Vec3f p = transform.point({moved.positions[3 * v], moved.positions[3 * v + 1], moved.positions[3 * v + 2]});
    moved.positions[3 * v] = p.x, moved.positions[3 * v + 1] = p.y, moved.positions[3 * v + 2] = p.z;
  }
  SciVisParams params;
  params.lights = default_lights({0.5f, -0.7f, -0.6f});
  for (auto isa : supported_isas()) {
    INFO(simd::isa_name(isa));
    const auto& kernels = shim::kernels(isa);
    accel::Device device;
    shim::EngineWorld flat(device), instanced(device);
    flat.add(TriangleMesh(moved));
    kernels.commit(flat);
    auto group = std::make_shared<shim::EngineWorld::GroupType>(device);
    group->add(TriangleMesh(bunny));
    instanced.add_instance(group, transform);
    kernels.commit(instanced);
    // An instance's bounds are its group's box transformed: they enclose the mesh.
    const auto box = instanced.bounds(), tight = flat.bounds();
    for (int k = 0; k < 3; ++k) {
      CHECK(box.lower[k] <= tight.lower[k] + 1e-5f);
      CHECK(box.upper[k] >= tight.upper[k] - 1e-5f);
    }

    const Camera camera = frame_bounds(flat.bounds(), 1.f);
    FrameBuffer a(96, 96, ColorFormat::rgba32f), b(96, 96, ColorFormat::rgba32f);
    kernels.render_scivis(flat, params, camera, a, nullptr);
    kernels.render_scivis(instanced, params, camera, b, nullptr);
    const auto diff = testing::compare_images(io::color_image(b), io::color_image(a), 1e-3);
    INFO(testing::describe(diff));
    // The instance traces in the group's space (rays transformed by the inverse): float
    // rounding may flip a silhouette pixel, but shading and normals must agree.
    CHECK(diff.differing_pixels <= 5);
    CHECK(diff.rmse < 0.01);
  }
}

TEST_CASE("10,000 instances of a 1M-triangle group cost about one copy", "[world][instancing][memory]") {
  accel::Device device;
  auto group = std::make_shared<shim::EngineWorld::GroupType>(device);
  group->add(TriangleMesh(testing::wavy_torus(1'000'000)));
  shim::EngineWorld one(device);
  one.add_instance(group);
  one.commit();
  const std::size_t one_copy = one.memory_bytes();

  shim::EngineWorld many(device);
  for (int i = 0; i < 10'000; ++i)
    many.add_instance(group, Affine3f::translate({3.f * (i % 100), 3.f * (i / 100), 0.f}));
  many.commit();
  // The device counts every scene it holds; what `many` adds is its top-level BVH.
  const std::size_t added = many.memory_bytes() - one_copy;
  INFO("one copy " << one_copy << " bytes; 10,000 instances add " << added << " bytes");
  CHECK(one_copy > 1'000'000 * 50);  // the torus and its BVH
  CHECK(added < one_copy / 10);
  CHECK(many.bounds().upper.x > 290.f);
}

TEST_CASE("BVH settings: compact leaves cost less memory, every layout renders the same image",
          "[world][memory][render]") {
  const MeshData bunny = io::read_ply(SCIRAY_DATA_DIR "/meshes/bunny.ply");
  SciVisParams params;
  params.lights = default_lights({0.5f, -0.7f, -0.6f});
  const auto& kernels = shim::kernels(simd::best_supported_isa());
  std::vector<std::size_t> memory;
  std::vector<std::vector<float>> images;
  for (const BvhSettings settings : {BvhSettings{}, BvhSettings{.compact = true}, BvhSettings{.dynamic = true}}) {
    accel::Device device;  // one per layout: the device counts what its scenes hold
    shim::EngineWorld world(device);
    world.set_bvh(settings);
    world.add(TriangleMesh(bunny));
    kernels.commit(world);
    memory.push_back(world.memory_bytes());
    FrameBuffer fb(96, 96, ColorFormat::rgba32f);
    kernels.render_scivis(world, params, frame_bounds(world.bounds(), 1.f), fb, nullptr);
    images.push_back(io::color_image(fb).pixels);
  }
  INFO("bytes: fast " << memory[0] << ", compact " << memory[1] << ", dynamic " << memory[2]);
  CHECK(memory[1] < memory[0] * 3 / 4);
  CHECK(images[1] == images[0]);
  CHECK(images[2] == images[0]);
}

TEST_CASE("the device reports how far a BVH build is, and 1 when it is done", "[world][progress]") {
  accel::Device device;
  CHECK(device.build_progress() == 0.0);
  shim::EngineWorld world(device);
  world.add(TriangleMesh(testing::wavy_torus(200'000)));
  shim::kernels(simd::best_supported_isa()).commit(world);
  CHECK(device.build_progress() == 1.0);  // Embree's progress monitor ran to the end
}

TEST_CASE("a scene of every geometry type, instanced and clipped, matches its reference", "[world][reference]") {
  accel::Device device;
  shim::EngineWorld world(device);
  // A floor plane bounded to a square, boxes standing on it, a molecule-like cluster of
  // spheres instanced three times, a tube, and a clipping sphere cutting into a box.
  world.add(Planes({{0.f, 1.f, 0.f, 0.f}}, {Box3f{{-3.f, -0.01f, -3.f}, {3.f, 0.01f, 3.f}}}, {0.7f, 0.7f, 0.7f, 1.f}));
  world.add(Boxes({Box3f{{-2.5f, 0.f, -2.5f}, {-1.f, 1.5f, -1.f}}, Box3f{{1.f, 0.f, -2.f}, {2.f, 0.8f, -1.f}}},
                  {0.8f, 0.3f, 0.2f, 1.f, 0.2f, 0.4f, 0.8f, 1.f}));
  CurveData tube;
  tube.position_radius = {-2.5f, 0.3f, 1.5f, 0.15f, 0.f, 1.2f, 2.f, 0.15f, 2.5f, 0.3f, 1.5f, 0.15f};
  tube.indices = {0, 1};
  tube.colors = {1, 0.8f, 0, 1, 0, 0.8f, 0.4f, 1, 0.6f, 0, 0.8f, 1};
  world.add(Curves(tube));
  auto cluster = std::make_shared<shim::EngineWorld::GroupType>(device);
  SphereData spheres = testing::random_spheres(40, 11);
  for (float& r : spheres.radii) r *= 2.f;
  cluster->add(Spheres(spheres));
  for (int i = 0; i < 3; ++i)
    world.add_instance(cluster, rotate_scale_translate({0.f, 1.f, 0.f}, 40.f * i, 0.9f, {-1.6f + 1.6f * i, 0.1f, 0.6f}));
  auto clipping = std::make_shared<Clipping>();
  clipping->add_sphere({-1.75f, 0.9f, -1.f}, 0.55f);
  world.set_clipping(clipping);
  const auto& kernels = shim::kernels(shim::select_isa());
  kernels.commit(world);

  SciVisParams params;
  params.background_color = {0.1f, 0.1f, 0.12f};
  params.background_alpha = 1.f;
  params.lights = default_lights({0.4f, -0.8f, -0.5f});
  PerspectiveCamera camera;
  camera.position = {0.f, 5.5f, 6.f};
  camera.direction = Vec3f{0.f, 0.6f, 0.f} - camera.position;
  camera.fovy = 45.f;
  camera.aspect = 200.f / 150.f;
  FrameBuffer framed(200, 150, ColorFormat::srgba);
  kernels.render_scivis(world, params, camera, framed, nullptr);
  const std::string reference = SCIRAY_REFERENCE_DIR "/every_type_scivis.png";
  if (std::getenv("SCIRAY_UPDATE_REFERENCES")) io::write_color(framed, reference);
  const auto diff = testing::compare_images(io::color_image(framed), io::read_png(reference), 2.5 / 255);
  INFO(testing::describe(diff));
  // The tolerance of every reference image (docs/accuracy.md).
  CHECK(diff.rmse <= 0.005);
  CHECK(diff.local_mean_error_max <= 0.02);
}
