// Where ray tracing meshes can fail, and what sciray does there (docs/accuracy.md):
// rays exactly through shared edges and vertices, data far from the origin, and
// degenerate triangles.
#include <catch2/catch.hpp>

#include <cmath>
#include <random>
#include <map>

#include "sciray/io/frame_io.hpp"
#include "sciray/io/ply.hpp"
#include "sciray/shim/engine.hpp"
#include "sciray/testing/image_compare.hpp"
#include "sciray/testing/scenes.hpp"
#include "support/isas.hpp"

using namespace sciray;
using sciray::test_support::supported_isas;

namespace {

Vec3f vertex(const MeshData& m, std::uint32_t i) {
  return {m.positions[3 * i], m.positions[3 * i + 1], m.positions[3 * i + 2]};
}

}  // namespace

TEST_CASE("rays exactly through shared edges of a closed mesh do not slip through", "[stability][mesh]") {
  const MeshData torus = testing::wavy_torus(20'000);

  // Every edge midpoint and every vertex, each approached from 2 units away in a random
  // direction that enters every triangle around it (at least 15 degrees off each one's
  // plane): the ray crosses the surface there, exactly between triangles. (A ray that
  // only touches a fold may rightly hit or miss it; that is not a crossing.)
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::vector<Vec3f>> edge_faces;
  std::vector<std::vector<Vec3f>> vertex_faces(torus.vertex_count());
  for (std::size_t f = 0; f < torus.face_count(); ++f) {
    const std::uint32_t* t = &torus.indices[3 * f];
    const Vec3f n = normalize(cross(vertex(torus, t[1]) - vertex(torus, t[0]), vertex(torus, t[2]) - vertex(torus, t[0])));
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = t[k], b = t[(k + 1) % 3];
      edge_faces[{std::min(a, b), std::max(a, b)}].push_back(n);
      vertex_faces[t[k]].push_back(n);
    }
  }
  std::vector<Vec3f> targets;
  std::vector<const std::vector<Vec3f>*> around;
  for (const auto& [edge, faces] : edge_faces) {
    targets.push_back((vertex(torus, edge.first) + vertex(torus, edge.second)) * 0.5f);
    around.push_back(&faces);
  }
  for (std::uint32_t v = 0; v < torus.vertex_count(); ++v) targets.push_back(vertex(torus, v)), around.push_back(&vertex_faces[v]);
  const std::size_t edge_count = edge_faces.size();
  std::mt19937 rng(7);
  std::normal_distribution<float> gauss;
  std::vector<Ray<float>> rays(targets.size());
  for (std::size_t i = 0; i < targets.size(); ++i) {
    Vec3f dir;
    bool crosses = false;
    while (!crosses) {
      dir = normalize(Vec3f{gauss(rng), gauss(rng), gauss(rng)});
      // All faces on the same side, and not grazing any: the sign of the first decides.
      const float side = dot(dir, around[i]->front()) < 0.f ? -1.f : 1.f;
      crosses = true;
      for (const Vec3f& n : *around[i]) crosses &= side * dot(dir, n) > 0.26f;
    }
    rays[i].dir = dir;
    rays[i].org = targets[i] - dir * 2.f;
  }
  // The first hit is at the target or before it (the tube may be in the way).
  const auto misses = [&](bool robust, simd::Isa isa, std::size_t first, std::size_t last) {
    accel::Device device;
    shim::EngineWorld world(device);
    world.set_robust(robust);
    world.add(TriangleMesh(torus));
    world.commit();
    std::vector<shim::TraceResult> hits(rays.size());
    shim::kernels(isa).trace(world, rays, hits);
    std::size_t count = 0;
    for (std::size_t i = first; i < last; ++i) count += !(hits[i].geom_id >= 0 && hits[i].t <= 2.f * (1.f + 1e-5f));
    return count;
  };
  for (auto isa : supported_isas()) {
    INFO("ISA " << simd::isa_name(isa) << ": " << edge_count << " rays through edges, " << rays.size() - edge_count
                << " through vertices");
    // Embree's default mode lets 3.2 % of them through (the failure case) ...
    CHECK(misses(false, isa, 0, edge_count) > edge_count / 100);
    // ... robust mode, sciray's default, none through edges; through vertices a few
    // remain (0.46 % here, 9.2 % in default mode), stated in docs/accuracy.md.
    CHECK(misses(true, isa, 0, edge_count) == 0);
    CHECK(misses(true, isa, edge_count, rays.size()) < (rays.size() - edge_count) / 100);
  }
}

TEST_CASE("meshes far from the origin lose precision with float vertices", "[stability][mesh]") {
  // The bunny (15 cm) rendered at growing offsets from the origin, with the camera moved
  // along, against the image at the origin. Float vertices keep 24 bits: at 1e5 their
  // spacing is 8 mm, 5 % of the bunny, and the shape breaks. sciray does not recentre
  // data yet; applications keep it near the origin (or, once instancing lands, place it
  // with an instance transform).
  const MeshData bunny = io::read_ply(SCIRAY_DATA_DIR "/meshes/bunny.ply");
  const auto render_at = [&](float offset) {
    MeshData moved = bunny;
    for (std::size_t i = 0; i < moved.positions.size(); ++i) moved.positions[i] += offset;
    accel::Device device;
    shim::EngineWorld world(device);
    world.add(TriangleMesh(std::move(moved)));
    world.commit();
    PerspectiveCamera camera;
    camera.position = Vec3f{-0.02f, 0.11f, 0.3f} + Vec3f{offset, offset, offset};
    camera.direction = {0.f, 0.f, -1.f};
    camera.fovy = 40.f;
    FrameBuffer fb(96, 96, ColorFormat::rgba32f, channel_color);
    shim::kernels(shim::select_isa()).render_scivis(world, SciVisParams{}, camera, fb, nullptr);
    return io::color_image(fb);
  };
  const auto reference = render_at(0.f);
  const auto rmse_at = [&](float offset) { return testing::compare_images(render_at(offset), reference).rmse; };
  // Stated results (docs/accuracy.md, RMSE 0.0006 / 0.009 / 0.014 / 0.083 / 0.20 at
  // 1e1..1e5): harmless at 1e1, noticeable from 1e2, broken at 1e5.
  CHECK(rmse_at(1e1f) < 0.002);
  CHECK(rmse_at(1e2f) < 0.02);
  CHECK(rmse_at(1e4f) > rmse_at(1e2f));
  CHECK(rmse_at(1e5f) > 0.1);
}

TEST_CASE("degenerate triangles neither crash nor produce NaN nor steal hits", "[stability][mesh]") {
  // A unit square of two triangles, plus zero-area triangles: a repeated vertex, three
  // collinear vertices, and one collapsed to a point.
  MeshData m;
  m.positions = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0.5f, 0.5f, 0, 0.25f, 0.25f, 0};
  m.indices = {0, 1, 2, 0, 2, 3, 0, 0, 1, 0, 4, 2, 5, 5, 5};
  accel::Device device;
  shim::EngineWorld world(device);
  world.add(TriangleMesh(std::move(m)));
  world.commit();
  PerspectiveCamera camera;
  camera.position = {0.5f, 0.5f, 1.f};
  camera.direction = {0.f, 0.f, -1.f};
  camera.fovy = 60.f;
  for (auto isa : supported_isas()) {
    INFO("ISA " << simd::isa_name(isa));
    FrameBuffer fb(33, 33, ColorFormat::rgba32f);
    shim::kernels(isa).render_scivis(world, SciVisParams{}, camera, fb, nullptr);
    for (float v : fb.color32f()) REQUIRE(std::isfinite(v));
    // Rays straight down through the degenerate triangles' points hit the square.
    std::vector<Ray<float>> rays;
    for (const Vec3f p : {Vec3f{0.5f, 0.5f, 1.f}, Vec3f{0.25f, 0.25f, 1.f}, Vec3f{0.5f, 0.f, 1.f}}) {
      Ray<float> r;
      r.org = p;
      r.dir = {0.f, 0.f, -1.f};
      rays.push_back(r);
    }
    std::vector<shim::TraceResult> hits(rays.size());
    shim::kernels(isa).trace(world, rays, hits);
    for (const auto& h : hits) {
      CHECK(h.geom_id == 0);
      CHECK(h.prim_id < 2);
      CHECK(h.t == Approx(1.f));
    }
  }
}
