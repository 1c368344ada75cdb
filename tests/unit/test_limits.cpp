// The largest inputs each geometry accepts, refused by name beyond them (docs/reliability.md,
// "Limits"). The arrays are views with the counts of giant arrays over a few real floats:
// the checks come before any element is read.
#include <catch2/catch.hpp>

#include <cstdint>
#include <vector>

#include <ospray/ospray.h>

#include "sciray/frame/framebuffer.hpp"
#include "sciray/geometry/spheres.hpp"
#include "sciray/geometry/triangle_mesh.hpp"
#include "support/api_fixture.hpp"

using namespace sciray;

namespace {
constexpr std::size_t giant_rows = 715'827'883;  // 3 * giant_rows = 2^31 + 1
}  // namespace

TEST_CASE("limits: meshes and spheres of more than 2^31 array elements are refused by name", "[limits]") {
  static_assert(3 * giant_rows > std::size_t{INT32_MAX});
  std::vector<float> few(12, 0.f);
  std::vector<std::uint32_t> face{0, 1, 2, 0};
  TriangleMesh::SharedArrays mesh;
  mesh.positions = {few.data(), giant_rows, 3 * sizeof(float)};  // 8.6 GB of vertices, beyond 2^32 bytes
  mesh.indices = {face.data(), 1, 3 * sizeof(std::uint32_t)};
  CHECK_THROWS_WITH(TriangleMesh::shared(mesh).validate(),
                    Catch::Contains("mesh: more than 2^31 array elements; split the mesh into several geometries"));
  mesh.positions = {few.data(), 4, 3 * sizeof(float)};
  mesh.indices = {face.data(), giant_rows, 3 * sizeof(std::uint32_t)};
  CHECK_THROWS_WITH(TriangleMesh::shared(mesh).validate(), Catch::Contains("more than 2^31 array elements"));

  Spheres::SharedArrays spheres;
  spheres.positions = {few.data(), giant_rows, 3 * sizeof(float)};
  CHECK_THROWS_WITH(Spheres::shared(spheres).validate(),
                    Catch::Contains("sphere: 'sphere.position' has more than 2^31 floats; split the spheres"));
}

TEST_CASE("limits: frame buffers of 2^31 pixels or more than memory and swap, through the C API", "[limits][c_api]") {
  sciray_test::ApiFixture api;
  OSPFrameBuffer too_many = ospNewFrameBuffer(65536, 32769, OSP_FB_SRGBA, OSP_FB_COLOR);
  CHECK(too_many == nullptr);
  api.expect_error("must be positive with fewer than 2^31 pixels");
  const unsigned all = OSP_FB_COLOR | OSP_FB_DEPTH | OSP_FB_ACCUM | OSP_FB_VARIANCE | OSP_FB_NORMAL | OSP_FB_ALBEDO |
                       OSP_FB_ID_PRIMITIVE | OSP_FB_ID_OBJECT | OSP_FB_ID_INSTANCE;
  const std::size_t needed = std::size_t{46000} * 46000 * 100;  // at least 100 bytes a pixel with all channels
  if (needed > detail::memory_and_swap_bytes()) {
    OSPFrameBuffer too_big = ospNewFrameBuffer(46000, 46000, OSP_FB_RGBA32F, all);
    CHECK(too_big == nullptr);
    api.expect_error("46000x46000 with these channels needs");
  }
  // 32768 x 32768 RGBA8 alone (4.3 GB) is within the limits where memory allows.
  CHECK(FrameBuffer::bytes_per_pixel(ColorFormat::srgba, channel_color, ErrorEstimate::luminance) == 4);
}
