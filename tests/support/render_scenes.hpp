#pragma once
// Small scenes and cameras the renderer tests build from: quads and boxes of quads, lists
// of spheres, top-down orthographic views, point-sampled frames.
#include <array>
#include <chrono>
#include <numbers>
#include <utility>
#include <vector>

#include "sciray/geometry/mesh_data.hpp"
#include "sciray/geometry/spheres.hpp"
#include "sciray/render/camera.hpp"
#include "sciray/frame/render_frame.hpp"

namespace sciray::test_support {

inline constexpr double pi = std::numbers::pi;

// ---- geometry ---------------------------------------------------------------------

using Quad = std::array<Vec3f, 4>;

inline MeshData quads(const std::vector<Quad>& list, const std::vector<Vec3f>& colors = {}) {
  MeshData mesh;
  mesh.vertices_per_face = 4;
  for (std::size_t q = 0; q < list.size(); ++q) {
    const auto first = static_cast<std::uint32_t>(mesh.vertex_count());
    for (const Vec3f& p : list[q]) mesh.positions.insert(mesh.positions.end(), {p.x, p.y, p.z});
    mesh.indices.insert(mesh.indices.end(), {first, first + 1, first + 2, first + 3});
    if (!colors.empty()) mesh.face_colors.insert(mesh.face_colors.end(), {colors[q].x, colors[q].y, colors[q].z, 1.f});
  }
  return mesh;
}

/// The square [-h, h]^2 at height z, normal +z.
inline Quad square(float h, float z) { return {Vec3f{-h, -h, z}, {h, -h, z}, {h, h, z}, {-h, h, z}}; }

/// The six faces of the box [lo, hi], wound to face inwards.
inline MeshData closed_box(Vec3f lo, Vec3f hi) {
  const Vec3f a{lo.x, lo.y, lo.z}, b{hi.x, lo.y, lo.z}, c{hi.x, hi.y, lo.z}, d{lo.x, hi.y, lo.z};
  const Vec3f e{lo.x, lo.y, hi.z}, f{hi.x, lo.y, hi.z}, g{hi.x, hi.y, hi.z}, h{lo.x, hi.y, hi.z};
  return quads({{a, b, c, d}, {e, h, g, f}, {a, e, f, b}, {b, f, g, c}, {c, g, h, d}, {d, h, e, a}});
}

inline Spheres spheres(const std::vector<std::pair<Vec3f, float>>& list) {
  SphereData data;
  for (const auto& [c, r] : list) {
    data.positions.insert(data.positions.end(), {c.x, c.y, c.z});
    data.radii.push_back(r);
  }
  return Spheres(std::move(data));
}

/// An orthographic camera looking straight down -z at (cx, cy), +y up in the image.
inline OrthographicCamera top_view(float cx, float cy, float z, float height, float aspect = 1.f) {
  OrthographicCamera c;
  c.position = {cx, cy, z};
  c.direction = {0.f, 0.f, -1.f};
  c.up = {0.f, 1.f, 0.f};
  c.height = height;
  c.aspect = aspect;
  return c;
}

/// Where the centre of pixel (x, y) of a width x height image looks at the plane z = 0.
inline Vec3f floor_point(const OrthographicCamera& camera, int x, int y, int width, int height) {
  const Ray<float> ray = prepare(camera).generate((x + 0.5f) / static_cast<float>(width),
                                                  (y + 0.5f) / static_cast<float>(height));
  return ray.org + ray.dir * (-ray.org.z / ray.dir.z);
}

inline FrameSettings point_sampled() {
  FrameSettings s;
  s.pixel_filter = PixelFilter::point;
  return s;
}

inline double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}


}  // namespace sciray::test_support
