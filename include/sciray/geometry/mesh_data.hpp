#pragma once
// The owned form of a triangle or quad mesh, as loaders produce it.
#include <cstdint>
#include <vector>

#include "sciray/geometry/data.hpp"

namespace sciray {

/// A polygon mesh with every face a triangle (3 indices) or every face a quad
/// (4 indices; a triangle in a quad mesh repeats its last index, as Embree and OSPRay
/// allow). Optional arrays are empty when absent.
struct MeshData {
  PaddedVector<float> positions;       ///< x,y,z per vertex
  PaddedVector<std::uint32_t> indices;  ///< vertices_per_face per face
  unsigned vertices_per_face = 3;       ///< 3 or 4
  PaddedVector<float> normals;          ///< x,y,z per vertex, or empty
  PaddedVector<float> vertex_colors;    ///< r,g,b,a per vertex in [0,1], or empty
  PaddedVector<float> face_colors;      ///< r,g,b,a per face in [0,1], or empty
  PaddedVector<float> texcoords;        ///< u,v per vertex, or empty
  /// A deforming mesh's x,y,z per vertex at each of at least two time steps spaced evenly
  /// over [time_start, time_end] (`positions` then holds the first); empty for a rigid one.
  std::vector<PaddedVector<float>> motion_positions;
  /// A deforming mesh's x,y,z normal per vertex at each of its time steps (as many as
  /// motion_positions), or empty: then `normals`, if any, at every time.
  std::vector<PaddedVector<float>> motion_normals;
  float time_start = 0.f, time_end = 1.f;

  std::size_t vertex_count() const { return positions.size() / 3; }
  std::size_t face_count() const { return indices.size() / vertices_per_face; }
};

}  // namespace sciray
