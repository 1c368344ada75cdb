#pragma once
// Procedural, deterministic scenes shared by tests, benchmarks and examples (no data to
// ship): a displaced torus whose triangle count is chosen by the caller, with vertex
// normals and a colour map on the displacement, as an isosurface of simulation data
// would carry.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <numbers>

#include "sciray/geometry/mesh_data.hpp"
#include "sciray/math/vec.hpp"

namespace sciray::testing {

/// A perceptually ordered blue-green-yellow colour map (viridis-like), linear RGB.
inline Vec3f colormap(float s) {
  static constexpr std::array<Vec3f, 5> stops{
      Vec3f{0.070f, 0.004f, 0.335f}, Vec3f{0.054f, 0.156f, 0.456f}, Vec3f{0.018f, 0.396f, 0.392f},
      Vec3f{0.200f, 0.672f, 0.162f}, Vec3f{0.973f, 0.820f, 0.012f}};
  const float x = std::clamp(s, 0.f, 1.f) * static_cast<float>(stops.size() - 1);
  const std::size_t i = std::min(static_cast<std::size_t>(x), stops.size() - 2);
  const float f = x - static_cast<float>(i);
  return stops[i] * (1.f - f) + stops[i + 1] * f;
}

/// A torus (major radius 1, minor 0.35) displaced along its normal by a sum of waves,
/// tessellated into about `target_triangles` triangles, with per-vertex normals and
/// colours. `quads` gives the same surface as a quad mesh.
inline MeshData wavy_torus(std::size_t target_triangles, bool quads = false) {
  const double cells = std::max<double>(8.0, static_cast<double>(target_triangles) / 2.0);
  // Around the tube (v) a third as many cells as along it (u), as the circumferences are.
  const int nv = std::max(4, static_cast<int>(std::sqrt(cells / 3.0)));
  const int nu = std::max(4, static_cast<int>(cells / nv));
  constexpr float major = 1.f, minor = 0.35f, amplitude = 0.06f;
  constexpr float two_pi = 2.f * std::numbers::pi_v<float>;

  const auto displacement = [](float u, float v) {
    return std::sin(7.f * u + 3.f * v) * std::cos(5.f * v - 2.f * u) + 0.5f * std::sin(13.f * u);
  };
  const auto point = [&](float u, float v) {
    const float r = minor * (1.f + amplitude / minor * displacement(u, v));
    const float ring = major + r * std::cos(v);
    return Vec3f{ring * std::cos(u), r * std::sin(v), ring * std::sin(u)};
  };

  MeshData mesh;
  const std::size_t vertex_count = static_cast<std::size_t>(nu) * static_cast<std::size_t>(nv);
  mesh.positions.reserve(3 * vertex_count);
  mesh.normals.reserve(3 * vertex_count);
  mesh.vertex_colors.reserve(4 * vertex_count);
  const float du = two_pi / static_cast<float>(nu), dv = two_pi / static_cast<float>(nv);
  for (int i = 0; i < nu; ++i) {
    for (int j = 0; j < nv; ++j) {
      const float u = static_cast<float>(i) * du, v = static_cast<float>(j) * dv;
      const Vec3f p = point(u, v);
      // Normal from central differences of the parametrization.
      const Vec3f tu = point(u + 0.5f * du, v) - point(u - 0.5f * du, v);
      const Vec3f tv = point(u, v + 0.5f * dv) - point(u, v - 0.5f * dv);
      const Vec3f n = normalize(cross(tv, tu));
      const Vec3f c = colormap(0.5f + 0.33f * displacement(u, v));
      mesh.positions.insert(mesh.positions.end(), {p.x, p.y, p.z});
      mesh.normals.insert(mesh.normals.end(), {n.x, n.y, n.z});
      mesh.vertex_colors.insert(mesh.vertex_colors.end(), {c.x, c.y, c.z, 1.f});
    }
  }
  const auto vertex = [&](int i, int j) { return static_cast<std::uint32_t>((i % nu) * nv + (j % nv)); };
  mesh.vertices_per_face = quads ? 4 : 3;
  mesh.indices.reserve(static_cast<std::size_t>(nu) * nv * (quads ? 4 : 6));
  for (int i = 0; i < nu; ++i) {
    for (int j = 0; j < nv; ++j) {
      const std::uint32_t a = vertex(i, j), b = vertex(i + 1, j), c = vertex(i + 1, j + 1), d = vertex(i, j + 1);
      if (quads)
        mesh.indices.insert(mesh.indices.end(), {a, b, c, d});
      else
        mesh.indices.insert(mesh.indices.end(), {a, b, c, a, c, d});
    }
  }
  return mesh;
}

}  // namespace sciray::testing
