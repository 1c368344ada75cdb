// 10,000 create/commit/render/release cycles of a changing scene through the C API: resident
// memory stays flat after warm-up (docs/reliability.md).
#include <catch2/catch.hpp>

#include <unistd.h>

#include <cstdio>
#include <vector>

#include <ospray/ospray.h>
#include <ospray/ospray_util.h>

#include "support/api_fixture.hpp"
#include "support/c_api_scenes.hpp"

namespace {

/// Resident set size in bytes (/proc/self/statm's second field, in pages).
long resident_bytes() {
  long pages_total = 0, pages_resident = 0;
  if (std::FILE* f = std::fopen("/proc/self/statm", "r")) {
    if (std::fscanf(f, "%ld %ld", &pages_total, &pages_resident) != 2) pages_resident = 0;
    std::fclose(f);
  }
  return pages_resident * sysconf(_SC_PAGESIZE);
}

/// One cycle: a scene (mesh, model, group, instance, world, light, camera, renderer) whose
/// vertices move with `k`, rendered into a new frame buffer, and everything released.
void cycle(int k) {
  const float shift = 0.001f * static_cast<float>(k % 100);
  std::vector<float> vertices;
  std::vector<unsigned> indices;
  for (unsigned i = 0; i < 64; ++i) {
    const float x = static_cast<float>(i % 8) / 8.f - 0.5f + shift, y = static_cast<float>(i / 8) / 8.f - 0.5f;
    vertices.insert(vertices.end(), {x, y, 0.f, x + 0.1f, y, 0.f, x, y + 0.1f, 0.f});
    indices.insert(indices.end(), {3 * i, 3 * i + 1, 3 * i + 2});
  }
  OSPGeometry mesh = ospNewGeometry("mesh");
  OSPData position = ospNewSharedData1D(vertices.data(), OSP_VEC3F, vertices.size() / 3);
  OSPData index = ospNewSharedData1D(indices.data(), OSP_VEC3UI, indices.size() / 3);
  ospSetObject(mesh, "vertex.position", position);
  ospSetObject(mesh, "index", index);
  ospRelease(position);
  ospRelease(index);
  ospCommit(mesh);
  const sciray_test::GeometryScene scene(mesh);
  OSPFrameBuffer fb = ospNewFrameBuffer(16, 16, OSP_FB_SRGBA, OSP_FB_COLOR | OSP_FB_ACCUM);
  ospRenderFrameBlocking(fb, scene.renderer, scene.camera, scene.world);
  ospRelease(fb);
}

}  // namespace

TEST_CASE("C API: 10,000 commit/render/release cycles keep resident memory flat", "[c_api][memory][long]") {
  sciray_test::ApiFixture api;
  constexpr int warm_up = 1'000, cycles = 10'000;
  for (int k = 0; k < warm_up; ++k) cycle(k);
  const long after_warm_up = resident_bytes();
  for (int k = 0; k < cycles; ++k) cycle(k);
  const long after = resident_bytes();
  const double growth = static_cast<double>(after - after_warm_up) / static_cast<double>(after_warm_up);
  std::printf("[long run] resident memory after %d warm-up cycles %.1f MB, after %d more %.1f MB (%+.3f %%)\n", warm_up,
              after_warm_up / 1e6, cycles, after / 1e6, 100.0 * growth);
  REQUIRE(after_warm_up > 0);
#ifdef SCIRAY_SANITIZED
  WARN("resident memory is not checked under a sanitizer: its allocator quarantines freed memory");
#else
  CHECK(growth < 0.01);
#endif
  CHECK(api.messages.errors.empty());
}
