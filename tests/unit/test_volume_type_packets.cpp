// Every volume type's packets, through each ISA's compiled kernels, give its scalar
// samples (the per-ISA build is where the packet code runs; the types' own tests are
// compiled for the build's default target).
#include <catch2/catch.hpp>

#include <memory>
#include <vector>

#include "sciray/shim/engine.hpp"
#include "sciray/testing/scenes.hpp"
#include "support/isas.hpp"

using namespace sciray;
using sciray::test_support::supported_isas;

namespace {

/// 4,096 points in a box 10 % wider than `volume`'s (some outside it).
template <class Volume>
std::vector<Vec3f> points_around(const Volume& volume) {
  const Box3f b = volume.bounds();
  const Vec3f size = b.upper - b.lower;
  std::vector<Vec3f> out;
  for (std::uint64_t i = 0; i < 4096; ++i)
    out.push_back(b.lower - size * 0.05f +
                  Vec3f{testing::hash_uniform(3 * i), testing::hash_uniform(3 * i + 1), testing::hash_uniform(3 * i + 2)} *
                      (size * 1.1f));
  return out;
}

template <class Volume, class Kernel>
void check_every_isa(const Volume& volume, Kernel shim::IsaKernels::*kernel) {
  const auto points = points_around(volume);
  for (auto isa : supported_isas()) {
    INFO(simd::isa_name(isa));
    std::vector<float> packets(points.size());
    (shim::kernels(isa).*kernel)(volume, points, packets);
    int differing = 0;
    for (std::size_t i = 0; i < points.size(); ++i) {
      const float scalar = volume.sample(points[i]);
      differing += !(packets[i] == scalar || (scalar != scalar && packets[i] != packets[i]) ||
                     std::abs(packets[i] - scalar) <= 1e-5f * (1.f + std::abs(scalar)));
    }
    CHECK(differing == 0);
  }
}

}  // namespace

TEST_CASE("every volume type samples the same in packets of every ISA as one point at a time", "[volume][simd]") {
  ParticleData particles;
  for (std::uint64_t i = 0; i < 200; ++i) {
    particles.positions.push_back({testing::hash_uniform(3 * i), testing::hash_uniform(3 * i + 1), testing::hash_uniform(3 * i + 2)});
    particles.radii.push_back(0.05f + 0.05f * testing::hash_uniform(i + 999));
    particles.weights.push_back(testing::hash_uniform(i + 5000) - 0.3f);
  }
  check_every_isa(Particles(std::move(particles)), &shim::IsaKernels::sample_particles);

  StructuredSphericalData spherical;
  spherical.dimensions = {5, 7, 9};
  spherical.grid_origin = {0.5f, 10.f, 0.f};
  spherical.grid_spacing = {0.25f, 20.f, 40.f};
  for (std::uint64_t i = 0; i < 5 * 7 * 9; ++i) spherical.values.push_back(testing::hash_uniform(i));
  check_every_isa(StructuredSpherical(std::move(spherical)), &shim::IsaKernels::sample_spherical);

  VdbData vdb;
  for (int k = 0; k < 3; ++k) {
    vdb.level.push_back(3);
    vdb.origin.push_back({8 * k, 8 * (k % 2), 0});
    std::vector<float> leaf;
    for (std::uint64_t v = 0; v < 512; ++v) leaf.push_back(testing::hash_uniform(512 * k + v));
    vdb.data.push_back(std::move(leaf));
  }
  check_every_isa(Vdb(std::move(vdb)), &shim::IsaKernels::sample_vdb);

  AmrData amr;
  amr.cell_width = {1.f, 0.5f};
  amr.block_bounds = {{{0, 0, 0}, {7, 7, 7}}, {{4, 4, 4}, {11, 11, 11}}};
  amr.block_level = {0, 1};
  for (int b = 0; b < 2; ++b) {
    std::vector<float> cells;
    for (std::uint64_t c = 0; c < 512; ++c) cells.push_back(testing::hash_uniform(1000 * b + c));
    amr.block_data.push_back(std::move(cells));
  }
  check_every_isa(Amr(std::move(amr)), &shim::IsaKernels::sample_amr);
}
