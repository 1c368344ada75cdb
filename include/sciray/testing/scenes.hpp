#pragma once
// Procedural, deterministic scenes shared by tests, benchmarks and examples (no data to
// ship): a displaced torus whose triangle count is chosen by the caller, with vertex
// normals and a colour map on the displacement, as an isosurface of simulation data
// would carry; random spheres (particles); streamlines of a steady flow (tubes).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <numbers>
#include <optional>

#include <filesystem>
#include <map>
#include <vector>
#include <string>
#include <string_view>

#include "sciray/error.hpp"
#include "sciray/geometry/boxes.hpp"
#include "sciray/geometry/curves.hpp"
#include "sciray/geometry/mesh_data.hpp"
#include "sciray/geometry/spheres.hpp"
#include "sciray/io/ply.hpp"
#include "sciray/io/volume.hpp"
#include "sciray/math/affine.hpp"
#include "sciray/math/vec.hpp"
#include "sciray/render/camera.hpp"
#include "sciray/render/light.hpp"
#include "sciray/render/material.hpp"

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

/// A uniform value in [0,1) from a counter: the same on every platform and standard
/// library (unlike std:: distributions), so generated scenes are reproducible.
inline float hash_uniform(std::uint64_t counter) {
  std::uint64_t z = counter + 0x9E3779B97F4A7C15ull;  // splitmix64
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  z ^= z >> 31;
  return static_cast<float>(z >> 40) * 0x1p-24f;
}

/// `count` spheres with centres uniform in the unit cube, radii between 0.25 and 0.75 of
/// the mean spacing (so the cube is about half filled whatever the count), coloured by
/// position.
inline SphereData random_spheres(std::size_t count, std::uint64_t seed = 1) {
  SphereData spheres;
  spheres.positions.resize(3 * count);
  spheres.radii.resize(count);
  spheres.colors.resize(4 * count);
  const float spacing = std::cbrt(1.f / static_cast<float>(std::max<std::size_t>(count, 1)));
  const std::uint64_t base = seed * 0x100000000ull * 8;
  for (std::size_t i = 0; i < count; ++i) {
    for (int k = 0; k < 3; ++k) spheres.positions[3 * i + k] = hash_uniform(base + 5 * i + k);
    spheres.radii[i] = spacing * (0.25f + 0.5f * hash_uniform(base + 5 * i + 3));
    const Vec3f c = colormap(hash_uniform(base + 5 * i + 4));
    spheres.colors[4 * i] = c.x, spheres.colors[4 * i + 1] = c.y, spheres.colors[4 * i + 2] = c.z;
    spheres.colors[4 * i + 3] = 1.f;
  }
  return spheres;
}

/// Spheres as triangle meshes: an icosahedron subdivided `subdivisions` times (20·4^n
/// triangles a sphere), with per-vertex normals and the spheres' colours, i.e. what a
/// rasterizing pipeline would have to store for the same picture.
inline MeshData tessellate_spheres(const SphereData& spheres, int subdivisions) {
  const float g = (1.f + std::sqrt(5.f)) / 2;
  std::vector<Vec3f> unit{{-1, g, 0}, {1, g, 0}, {-1, -g, 0}, {1, -g, 0}, {0, -1, g}, {0, 1, g},
                          {0, -1, -g}, {0, 1, -g}, {g, 0, -1}, {g, 0, 1}, {-g, 0, -1}, {-g, 0, 1}};
  for (auto& v : unit) v = normalize(v);
  std::vector<std::array<std::uint32_t, 3>> faces{{0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11},
                                                  {1, 5, 9}, {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                                  {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8}, {3, 8, 9},
                                                  {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
  for (int level = 0; level < subdivisions; ++level) {
    std::vector<std::array<std::uint32_t, 3>> finer;
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> midpoints;
    const auto midpoint = [&](std::uint32_t a, std::uint32_t b) {
      const auto [it, added] = midpoints.try_emplace({std::min(a, b), std::max(a, b)}, 0);
      if (added) it->second = static_cast<std::uint32_t>(unit.size()), unit.push_back(normalize(unit[a] + unit[b]));
      return it->second;
    };
    for (const auto& [a, b, c] : faces) {
      const std::uint32_t ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
      finer.insert(finer.end(), {{a, ab, ca}, {b, bc, ab}, {c, ca, bc}, {ab, bc, ca}});
    }
    faces = std::move(finer);
  }
  MeshData mesh;
  const std::size_t n = spheres.count();
  mesh.positions.reserve(3 * n * unit.size());
  mesh.normals.reserve(3 * n * unit.size());
  mesh.indices.reserve(3 * n * faces.size());
  if (!spheres.colors.empty()) mesh.vertex_colors.reserve(4 * n * unit.size());
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3f center{spheres.positions[3 * i], spheres.positions[3 * i + 1], spheres.positions[3 * i + 2]};
    const float r = spheres.radii.empty() ? spheres.radius : spheres.radii[i];
    const auto first = static_cast<std::uint32_t>(mesh.vertex_count());
    for (const Vec3f& v : unit) {
      const Vec3f p = center + v * r;
      mesh.positions.insert(mesh.positions.end(), {p.x, p.y, p.z});
      mesh.normals.insert(mesh.normals.end(), {v.x, v.y, v.z});
      if (!spheres.colors.empty())
        mesh.vertex_colors.insert(mesh.vertex_colors.end(), &spheres.colors[4 * i], &spheres.colors[4 * i] + 4);
    }
    for (const auto& f : faces) mesh.indices.insert(mesh.indices.end(), {first + f[0], first + f[1], first + f[2]});
  }
  return mesh;
}

/// Streamlines of the ABC (Arnold–Beltrami–Childress) flow, a steady chaotic field often
/// used for flow visualization, traced with RK4 from `lines` seeds of a 2π-periodic cell:
/// round linear curves of `points` vertices each, coloured by speed.
inline CurveData streamlines(std::size_t lines, std::size_t points, float radius = 0.02f) {
  constexpr float A = 1.f, B = 0.7f, C = 0.43f;
  const auto velocity = [](const Vec3f& p) {
    return Vec3f{A * std::sin(p.z) + C * std::cos(p.y), B * std::sin(p.x) + A * std::cos(p.z),
                 C * std::sin(p.y) + B * std::cos(p.x)};
  };
  CurveData curves;
  curves.position_radius.reserve(4 * lines * points);
  curves.colors.reserve(4 * lines * points);
  constexpr float step = 0.05f;
  for (std::size_t line = 0; line < lines; ++line) {
    Vec3f p = Vec3f{hash_uniform(3 * line), hash_uniform(3 * line + 1), hash_uniform(3 * line + 2)} *
              (2.f * std::numbers::pi_v<float>);
    const auto first = static_cast<std::uint32_t>(curves.vertex_count());
    for (std::size_t k = 0; k < points; ++k) {
      const Vec3f v = velocity(p);
      curves.position_radius.insert(curves.position_radius.end(), {p.x, p.y, p.z, radius});
      const Vec3f c = colormap(length(v) / 2.2f);
      curves.colors.insert(curves.colors.end(), {c.x, c.y, c.z, 1.f});
      const Vec3f k1 = v, k2 = velocity(p + k1 * (step / 2)), k3 = velocity(p + k2 * (step / 2)),
                  k4 = velocity(p + k3 * step);
      p += (k1 + k2 * 2.f + k3 * 2.f + k4) * (step / 6);
    }
    for (std::uint32_t s = 0; s + 1 < points; ++s) curves.indices.push_back(first + s);
  }
  return curves;
}

/// A float volume of `n`³ voxels over the unit cube filled by `f(x, y, z)` (coordinates in
/// [0, 1]), as a volume file would give it.
template <class F>
io::VolumeFile procedural_volume(std::int64_t n, F&& f) {
  io::VolumeFile file;
  file.kind = io::VoxelKind::float32;
  file.dims = {n, n, n};
  file.grid.spacing = Vec3f{1.f, 1.f, 1.f} / static_cast<float>(n - 1);
  file.voxels = std::make_shared<std::vector<std::byte>>(static_cast<std::size_t>(n * n * n) * sizeof(float));
  auto* voxels = reinterpret_cast<float*>(file.voxels->data());
  const float scale = 1.f / static_cast<float>(n - 1);
  for (std::int64_t z = 0; z < n; ++z)
    for (std::int64_t y = 0; y < n; ++y)
      for (std::int64_t x = 0; x < n; ++x)
        voxels[(z * n + y) * n + x] = f(x * scale, y * scale, z * scale);
  return file;
}

/// OSPRay's gravity-spheres test volume: the gravitational potential of 8 point masses,
/// falling off as 1/r from each (seeded positions and masses), clamped near them.
inline io::VolumeFile gravity_spheres_volume(std::int64_t n) {
  std::array<Vec3f, 8> centres;
  std::array<float, 8> masses;
  for (int i = 0; i < 8; ++i) {
    centres[i] = {0.15f + 0.7f * hash_uniform(31 * i), 0.15f + 0.7f * hash_uniform(31 * i + 1),
                  0.15f + 0.7f * hash_uniform(31 * i + 2)};
    masses[i] = 0.5f + hash_uniform(31 * i + 3);
  }
  return procedural_volume(n, [&](float x, float y, float z) {
    float potential = 0.f;
    for (int i = 0; i < 8; ++i) potential += masses[i] / std::max(length(Vec3f{x, y, z} - centres[i]), 0.02f);
    return potential;
  });
}

/// Perlin gradient noise (Perlin 2002, "Improving noise"), 4 octaves at 8 cells per unit:
/// a volume with structure at every scale and no empty space.
inline io::VolumeFile perlin_noise_volume(std::int64_t n) {
  std::array<int, 512> perm;
  for (int i = 0; i < 256; ++i) perm[i] = i;
  for (int i = 255; i > 0; --i) std::swap(perm[i], perm[static_cast<int>(hash_uniform(977 + i) * (i + 1))]);
  for (int i = 0; i < 256; ++i) perm[256 + i] = perm[i];
  const auto fade = [](float t) { return t * t * t * (t * (t * 6 - 15) + 10); };
  const auto grad = [](int h, float x, float y, float z) {
    const float u = (h & 15) < 8 ? x : y, v = (h & 15) < 4 ? y : ((h & 15) == 12 || (h & 15) == 14 ? x : z);
    return ((h & 1) ? -u : u) + ((h & 2) ? -v : v);
  };
  const auto noise = [&](float x, float y, float z) {
    const int X = static_cast<int>(std::floor(x)) & 255, Y = static_cast<int>(std::floor(y)) & 255,
              Z = static_cast<int>(std::floor(z)) & 255;
    x -= std::floor(x), y -= std::floor(y), z -= std::floor(z);
    const float u = fade(x), v = fade(y), w = fade(z);
    const int A = perm[X] + Y, AA = perm[A] + Z, AB = perm[A + 1] + Z, B = perm[X + 1] + Y, BA = perm[B] + Z,
              BB = perm[B + 1] + Z;
    const auto lerp = [](float t, float a, float b) { return a + t * (b - a); };
    return lerp(w, lerp(v, lerp(u, grad(perm[AA], x, y, z), grad(perm[BA], x - 1, y, z)),
                        lerp(u, grad(perm[AB], x, y - 1, z), grad(perm[BB], x - 1, y - 1, z))),
                lerp(v, lerp(u, grad(perm[AA + 1], x, y, z - 1), grad(perm[BA + 1], x - 1, y, z - 1)),
                     lerp(u, grad(perm[AB + 1], x, y - 1, z - 1), grad(perm[BB + 1], x - 1, y - 1, z - 1))));
  };
  return procedural_volume(n, [&](float x, float y, float z) {
    float sum = 0.f, amplitude = 1.f, frequency = 8.f;
    for (int octave = 0; octave < 4; ++octave, amplitude *= 0.5f, frequency *= 2.f)
      sum += amplitude * noise(x * frequency, y * frequency, z * frequency);
    return sum;
  });
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

/// The box's ceiling light as a quad light just below its quad, emitting downwards.
inline std::vector<Light> cornell_box_lights() {
  QuadLight light;
  light.position = {343.f, 548.6f, 227.f};
  light.edge1 = {0.f, 0.f, 105.f};
  light.edge2 = {-130.f, 0.f, 0.f};  // edge1 x edge2 points down
  light.color = {1.f, 0.85f, 0.6f};
  light.intensity = 30.f;
  return {light};
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
/// many triangles), "cornell_box", "spheres_100k", "spheres_1M", "spheres_10M" (random
/// spheres), "spheres_100k_mesh" (the 100k spheres tessellated, 80 triangles each),
/// "streamlines" (2,000 ABC-flow streamlines of 500 points), "gravity_spheres_128" and
/// "gravity_spheres_512" (float volumes of 8 point masses' potential), "perlin_128" (a
/// float volume of Perlin noise), "transparency_stack" (16 squares behind each other
/// with an obj material of opacity 0.5), "instanced_boxes" (a group
/// of 8 boxes placed 10,000 times), "instanced_torus" (the 1M-triangle torus placed
/// 10,000 times), or a real mesh of the shared data ("bunny", "lucy", "horse",
/// "turbineblade", "footbones") read from `data_dir`.
struct StandardScene {
  std::optional<MeshData> mesh;
  std::optional<SphereData> spheres;
  std::optional<CurveData> curves;
  std::vector<Box3f> boxes;
  std::vector<float> box_colors;
  /// Empty: the geometry is placed directly. Otherwise it forms one group, placed once
  /// per transform.
  std::vector<Affine3f> instances;
  std::optional<io::VolumeFile> volume;
  std::optional<PerspectiveCamera> camera;  ///< empty: frame the bounds
  std::vector<Light> lights;                ///< empty: the renderer's default lights
  /// The material of every geometry of the scene (none: own colours).
  std::optional<Material> material;
};

/// `layers` parallel unit squares 0.1 apart along z, coloured along a colour map, for a
/// material of opacity below 1: a ray passes every layer (transparency and maxPathLength).
inline MeshData transparency_stack(int layers) {
  MeshData mesh;
  mesh.vertices_per_face = 4;
  for (int k = 0; k < layers; ++k) {
    const float z = 0.1f * static_cast<float>(k), shift = 0.05f * static_cast<float>(k);
    const auto first = static_cast<std::uint32_t>(mesh.vertex_count());
    for (const auto& [x, y] : {std::pair{0.f, 0.f}, {1.f, 0.f}, {1.f, 1.f}, {0.f, 1.f}})
      mesh.positions.insert(mesh.positions.end(), {x + shift, y + shift, z});
    mesh.indices.insert(mesh.indices.end(), {first, first + 1, first + 2, first + 3});
    const Vec3f c = colormap(static_cast<float>(k) / static_cast<float>(std::max(layers - 1, 1)));
    mesh.face_colors.insert(mesh.face_colors.end(), {c.x, c.y, c.z, 1.f});
  }
  return mesh;
}

/// A 100 × 100 grid of transforms spaced `spacing` apart, each turned about y by a
/// different angle.
inline std::vector<Affine3f> instance_grid(float spacing) {
  std::vector<Affine3f> transforms;
  for (int i = 0; i < 10'000; ++i) {
    const float angle = 6.2831853f * hash_uniform(0xB0C5 + i), c = std::cos(angle), s = std::sin(angle);
    transforms.push_back({{c, 0, -s}, {0, 1, 0}, {s, 0, c}, {spacing * (i % 100), 0.f, spacing * (i / 100)}});
  }
  return transforms;
}

inline StandardScene standard_scene(std::string_view name, const std::filesystem::path& data_dir = {}) {
  StandardScene scene;
  if (name == "torus_1M") scene.mesh = wavy_torus(1'000'000);
  else if (name == "torus_5M") scene.mesh = wavy_torus(5'000'000);
  else if (name == "torus_20M") scene.mesh = wavy_torus(20'000'000);
  else if (name == "cornell_box") scene.mesh = cornell_box(), scene.camera = cornell_box_camera(), scene.lights = cornell_box_lights();
  else if (name == "spheres_100k") scene.spheres = random_spheres(100'000);
  else if (name == "spheres_100k_mesh") scene.mesh = tessellate_spheres(random_spheres(100'000), 1);
  else if (name == "spheres_1M") scene.spheres = random_spheres(1'000'000);
  else if (name == "spheres_10M") scene.spheres = random_spheres(10'000'000);
  else if (name == "streamlines") scene.curves = streamlines(2'000, 500);
  else if (name == "gravity_spheres_128") scene.volume = gravity_spheres_volume(128);
  else if (name == "gravity_spheres_512") scene.volume = gravity_spheres_volume(512);
  else if (name == "perlin_128") scene.volume = perlin_noise_volume(128);
  else if (name == "instanced_torus") scene.mesh = wavy_torus(1'000'000), scene.instances = instance_grid(3.f);
  else if (name == "transparency_stack") {
    scene.mesh = transparency_stack(16);
    ObjMaterial half_opaque;
    half_opaque.kd = {1.f, 1.f, 1.f};
    half_opaque.d = 0.5f;
    scene.material = half_opaque;
  } else if (name == "instanced_boxes") {
    for (int k = 0; k < 8; ++k) {
      const Vec3f corner{0.6f * (k & 1), 0.6f * ((k >> 1) & 1) + 0.3f * (k & 1), 0.6f * (k >> 2)};
      scene.boxes.push_back({corner, corner + Vec3f{0.4f, 0.25f + 0.1f * k, 0.4f}});
      const Vec3f c = colormap(k / 7.f);
      scene.box_colors.insert(scene.box_colors.end(), {c.x, c.y, c.z, 1.f});
    }
    scene.instances = instance_grid(1.6f);
  }
  for (const char* real : {"bunny", "lucy", "horse", "turbineblade", "footbones"})
    if (name == real) scene.mesh = io::read_ply(data_dir / "meshes" / (std::string(name) + ".ply"));
  if (!scene.mesh && !scene.spheres && !scene.curves && scene.boxes.empty() && !scene.volume)
    throw Error("unknown standard scene '" + std::string(name) +
                "' (torus_1M, torus_5M, torus_20M, cornell_box, spheres_100k, spheres_100k_mesh, spheres_1M, "
                "spheres_10M, streamlines, transparency_stack, instanced_boxes, instanced_torus, gravity_spheres_128, "
                "gravity_spheres_512, "
                "perlin_128, bunny, lucy, "
                "horse, turbineblade, footbones)");
  return scene;
}

}  // namespace sciray::testing
