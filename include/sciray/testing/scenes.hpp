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
#include <optional>

#include <filesystem>
#include <string>
#include <string_view>

#include "sciray/error.hpp"
#include "sciray/geometry/mesh_data.hpp"
#include "sciray/io/ply.hpp"
#include "sciray/math/vec.hpp"
#include "sciray/render/camera.hpp"

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

/// The Cornell box (the Cornell program's published dimensions, in mm: a 555 mm cube
/// open at the front, red left wall, green right wall, a short and a tall block, the
/// light patch under the ceiling) as a quad mesh with per-face colours.
inline MeshData cornell_box() {
  MeshData mesh;
  mesh.vertices_per_face = 4;
  const auto quad = [&](Vec3f a, Vec3f b, Vec3f c, Vec3f d, Vec3f color) {
    const auto first = static_cast<std::uint32_t>(mesh.vertex_count());
    for (const Vec3f& p : {a, b, c, d}) mesh.positions.insert(mesh.positions.end(), {p.x, p.y, p.z});
    mesh.indices.insert(mesh.indices.end(), {first, first + 1, first + 2, first + 3});
    mesh.face_colors.insert(mesh.face_colors.end(), {color.x, color.y, color.z, 1.f});
  };
  const Vec3f white{0.73f, 0.73f, 0.73f}, red{0.65f, 0.05f, 0.05f}, green{0.12f, 0.45f, 0.15f}, light{1.f, 1.f, 1.f};
  quad({552.8f, 0, 0}, {0, 0, 0}, {0, 0, 559.2f}, {549.6f, 0, 559.2f}, white);                    // floor
  quad({556, 548.8f, 0}, {556, 548.8f, 559.2f}, {0, 548.8f, 559.2f}, {0, 548.8f, 0}, white);      // ceiling
  quad({549.6f, 0, 559.2f}, {0, 0, 559.2f}, {0, 548.8f, 559.2f}, {556, 548.8f, 559.2f}, white);   // back
  quad({0, 0, 559.2f}, {0, 0, 0}, {0, 548.8f, 0}, {0, 548.8f, 559.2f}, green);                    // right
  quad({552.8f, 0, 0}, {549.6f, 0, 559.2f}, {556, 548.8f, 559.2f}, {556, 548.8f, 0}, red);        // left
  quad({343, 548.7f, 227}, {343, 548.7f, 332}, {213, 548.7f, 332}, {213, 548.7f, 227}, light);    // light
  // A block from its top face down to the floor.
  const auto block = [&](std::array<Vec3f, 4> top) {
    quad(top[0], top[1], top[2], top[3], white);
    for (int k = 0; k < 4; ++k) {
      const Vec3f a = top[k], b = top[(k + 1) % 4];
      quad(a, {a.x, 0, a.z}, {b.x, 0, b.z}, b, white);
    }
  };
  block({Vec3f{130, 165, 65}, {82, 165, 225}, {240, 165, 272}, {290, 165, 114}});
  block({Vec3f{423, 330, 247}, {265, 330, 296}, {314, 330, 456}, {472, 330, 406}});
  return mesh;
}

/// The camera the Cornell program published for the box.
inline PerspectiveCamera cornell_box_camera(float aspect = 1.f) {
  PerspectiveCamera camera;
  camera.position = {278, 273, -800};
  camera.direction = {0, 0, 1};
  camera.fovy = 39.3f;
  camera.aspect = aspect;
  return camera;
}

/// A standard scene by name: "torus_1M", "torus_5M", "torus_20M" (displaced tori of that
/// many triangles), "cornell_box", or a real mesh of the shared data ("bunny", "lucy",
/// "horse", "turbineblade", "footbones") read from `data_dir`.
struct StandardScene {
  MeshData mesh;
  std::optional<PerspectiveCamera> camera;  ///< empty: frame the bounds
};

inline StandardScene standard_scene(std::string_view name, const std::filesystem::path& data_dir = {}) {
  if (name == "torus_1M") return {wavy_torus(1'000'000), std::nullopt};
  if (name == "torus_5M") return {wavy_torus(5'000'000), std::nullopt};
  if (name == "torus_20M") return {wavy_torus(20'000'000), std::nullopt};
  if (name == "cornell_box") return {cornell_box(), cornell_box_camera()};
  for (const char* real : {"bunny", "lucy", "horse", "turbineblade", "footbones"})
    if (name == real) return {io::read_ply(data_dir / "meshes" / (std::string(name) + ".ply")), std::nullopt};
  throw Error("unknown standard scene '" + std::string(name) +
              "' (torus_1M, torus_5M, torus_20M, cornell_box, bunny, lucy, horse, turbineblade, footbones)");
}

}  // namespace sciray::testing
