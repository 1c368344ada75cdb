#pragma once
// PLY mesh reader (ascii, binary_little_endian, binary_big_endian, version 1.0) producing
// MeshData. The file is parsed from memory. Binary files with the usual layouts (vertex
// records without lists, faces as a lone `uchar count, int indices` list) take tight
// loops with no per-value dispatch; everything else takes a general path that walks each
// property, which also skips unknown elements and properties. Every error names the file
// and, where it applies, the element, entry, property and line (ascii) or byte offset.
//
// Vertex texture coordinates are read from `u`/`v`, `s`/`t` or `texture_u`/`texture_v`.
// PlyOptions::texcoord_from instead makes them from any per-vertex scalar property (a
// confidence, an intensity, a coordinate): u is its value mapped linearly from its range
// to [0, 1], v is 0.5, so that a colour-map image as a material's map_kd colours the mesh
// by that scalar, as VTK colours scalars through a 1D texture.
#include <algorithm>
#include <array>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "sciray/error.hpp"
#include "sciray/geometry/mesh_data.hpp"
#include "sciray/io/ply_format.hpp"

namespace sciray::io {

namespace ply_detail {

// Named scalar properties an element may have, in the order values are gathered.
enum Slot : int {
  slot_x,
  slot_y,
  slot_z,
  slot_nx,
  slot_ny,
  slot_nz,
  slot_red,
  slot_green,
  slot_blue,
  slot_alpha,
  slot_u,
  slot_v,
  slot_scalar  ///< the property PlyOptions::texcoord_from names
};
inline constexpr int slot_count = 13;
inline constexpr std::array<std::string_view, slot_count> slot_names = {
    "x", "y", "z", "nx", "ny", "nz", "red", "green", "blue", "alpha", "u", "v", ""};

/// Whether a property called `name` fills `slot` (texture coordinates go by three names).
inline bool names_slot(std::string_view name, int slot) {
  if (slot == slot_u) return name == "u" || name == "s" || name == "texture_u";
  if (slot == slot_v) return name == "v" || name == "t" || name == "texture_v";
  return name == slot_names[static_cast<std::size_t>(slot)];
}

/// Which property fills which slot, and how a colour property's values map to [0,1].
struct Layout {
  std::array<int, slot_count> property_of_slot;  ///< -1 when absent
  std::vector<int> slot_of_property;             ///< -1 for properties not read into a slot
  std::array<double, slot_count> divisor;        ///< colour values are divided by it
  int index_list = -1;                           ///< face element: the vertex index list property
  bool has_normals = false;
  bool has_colors = false;
  bool has_texcoords = false;  ///< u, v, or the scalar property that makes them

  bool has(int slot) const { return property_of_slot[static_cast<std::size_t>(slot)] >= 0; }
};

/// Maps the slots in [first_slot, last_slot] and checks their types and completeness;
/// `scalar` names the property for slot_scalar (if any).
inline Layout make_layout(const Element& element, int first_slot, int last_slot, std::string_view file,
                          std::string_view scalar = {}) {
  Layout layout;
  layout.property_of_slot.fill(-1);
  layout.divisor.fill(1.0);
  layout.slot_of_property.assign(element.properties.size(), -1);
  const auto where = [&](const Property& property) {
    return "property '" + property.name + "' of element '" + element.name + "'";
  };
  for (std::size_t p = 0; p < element.properties.size(); ++p) {
    const Property& property = element.properties[p];
    if (!scalar.empty() && property.name == scalar) {
      if (property.is_list()) fail(file, where(property) + " must be a scalar, not a list, to make texture coordinates");
      layout.property_of_slot[slot_scalar] = static_cast<int>(p);  // read as well as any slot it also fills
    }
    for (int slot = first_slot; slot <= last_slot; ++slot) {
      if (slot == slot_scalar || !names_slot(property.name, slot)) continue;
      if (layout.has(slot)) fail(file, where(property) + " is declared twice");
      if (property.is_list()) fail(file, where(property) + " must be a scalar, not a list");
      layout.property_of_slot[static_cast<std::size_t>(slot)] = static_cast<int>(p);
      layout.slot_of_property[p] = slot;
      if (slot >= slot_red && slot <= slot_alpha) {
        switch (property.type) {
          case ScalarType::uint8: layout.divisor[static_cast<std::size_t>(slot)] = 255.0; break;
          case ScalarType::uint16: layout.divisor[static_cast<std::size_t>(slot)] = 65535.0; break;
          case ScalarType::uint32: layout.divisor[static_cast<std::size_t>(slot)] = 4294967295.0; break;
          case ScalarType::float32:
          case ScalarType::float64: break;
          default:
            fail(file, where(property) + " has type " + std::string(name_of(property.type)) +
                           "; a colour must be an unsigned integer (scaled to [0,1]) or a float");
        }
      }
    }
  }
  const auto require_group = [&](int first, int last, std::string_view group) {
    bool any = false;
    for (int slot = first; slot <= last; ++slot) any = any || layout.has(slot);
    if (!any) return false;
    for (int slot = first; slot <= last; ++slot)
      if (!layout.has(slot))
        fail(file, "element '" + element.name + "' has " + std::string(group) + " but no property '" +
                       std::string(slot_names[static_cast<std::size_t>(slot)]) + "'");
    return true;
  };
  if (first_slot == slot_x) {
    for (int slot = slot_x; slot <= slot_z; ++slot)
      if (!layout.has(slot))
        fail(file, "element '" + element.name + "' has no property '" +
                       std::string(slot_names[static_cast<std::size_t>(slot)]) + "'");
    layout.has_normals = require_group(slot_nx, slot_nz, "normal properties");
    layout.has_texcoords = require_group(slot_u, slot_v, "texture coordinate properties");
    if (!scalar.empty()) {
      if (!layout.has(slot_scalar))
        fail(file, "element '" + element.name + "' has no property '" + std::string(scalar) +
                       "' to make texture coordinates from");
      layout.has_texcoords = true;
    }
  }
  layout.has_colors = require_group(slot_red, slot_blue, "colour properties");
  if (layout.has(slot_alpha) && !layout.has_colors)
    fail(file, "element '" + element.name + "' has property 'alpha' but no 'red', 'green', 'blue'");
  return layout;
}

inline Layout make_face_layout(const Element& element, std::string_view file) {
  Layout layout = make_layout(element, slot_red, slot_alpha, file);
  for (std::size_t p = 0; p < element.properties.size(); ++p) {
    const Property& property = element.properties[p];
    if (property.name != "vertex_indices" && property.name != "vertex_index") continue;
    if (layout.index_list >= 0) fail(file, "element 'face' has more than one vertex index list");
    if (!property.is_list() || !is_integer(property.type))
      fail(file, "property '" + property.name + "' of element 'face' must be a list of integers");
    layout.index_list = static_cast<int>(p);
  }
  if (layout.index_list < 0)
    fail(file, "element 'face' has no list property 'vertex_indices' or 'vertex_index'");
  return layout;
}

/// Stores one vertex's gathered slot values.
template <class Source>
void store_vertex(Source& source, const Where& where, const Layout& layout,
                  const std::array<double, slot_count>& values, MeshData& mesh) {
  const std::size_t v = static_cast<std::size_t>(where.entry);
  float* position = mesh.positions.data() + 3 * v;
  for (int axis = 0; axis < 3; ++axis)
    position[axis] = static_cast<float>(values[static_cast<std::size_t>(axis)]);
  if (!std::isfinite(position[0]) || !std::isfinite(position[1]) || !std::isfinite(position[2]))
    source.fail(where, "coordinates (" + std::to_string(position[0]) + ", " + std::to_string(position[1]) +
                           ", " + std::to_string(position[2]) + ") are not finite");
  if (layout.has_normals)
    for (int axis = 0; axis < 3; ++axis)
      mesh.normals[3 * v + static_cast<std::size_t>(axis)] =
          static_cast<float>(values[static_cast<std::size_t>(slot_nx + axis)]);
  if (layout.has_colors)
    for (int channel = 0; channel < 4; ++channel) {
      const auto slot = static_cast<std::size_t>(slot_red + channel);
      mesh.vertex_colors[4 * v + static_cast<std::size_t>(channel)] =
          static_cast<float>(values[slot] / layout.divisor[slot]);
    }
  if (layout.has_texcoords) {
    const bool from_scalar = layout.has(slot_scalar);
    const float u = static_cast<float>(values[from_scalar ? slot_scalar : slot_u]);
    const float t = from_scalar ? 0.5f : static_cast<float>(values[slot_v]);
    if (!std::isfinite(u) || !std::isfinite(t))
      source.fail(where, "texture coordinates (" + std::to_string(u) + ", " + std::to_string(t) + ") are not finite");
    mesh.texcoords[2 * v] = u, mesh.texcoords[2 * v + 1] = t;
  }
}

/// Vertex records without lists: each attribute at a fixed offset of a fixed stride.
template <bool Swap, bool FloatPositions>
void read_fixed_vertices(BinarySource<Swap>& source, const Element& element, const Layout& layout,
                         std::size_t entry_size, MeshData& mesh) {
  std::array<std::size_t, slot_count> offset{};
  std::array<ScalarType, slot_count> type{};
  std::size_t running = 0;
  for (std::size_t p = 0; p < element.properties.size(); ++p) {
    if (const int slot = layout.slot_of_property[p]; slot >= 0) {
      offset[static_cast<std::size_t>(slot)] = running;
      type[static_cast<std::size_t>(slot)] = element.properties[p].type;
    }
    if (layout.property_of_slot[slot_scalar] == static_cast<int>(p))
      offset[slot_scalar] = running, type[slot_scalar] = element.properties[p].type;
    running += size_of(element.properties[p].type);
  }
  const std::byte* records = source.take_entries(element, entry_size);
  const auto load_slot = [&](const std::byte* record, int slot) {
    return load_scalar<Swap>(record + offset[static_cast<std::size_t>(slot)],
                             type[static_cast<std::size_t>(slot)]);
  };
  float* positions = mesh.positions.data();
  for (std::size_t v = 0; v < element.count; ++v) {
    const std::byte* record = records + v * entry_size;
    float xyz[3];
    for (int axis = 0; axis < 3; ++axis) {
      if constexpr (FloatPositions)
        xyz[axis] = load<float, Swap>(record + offset[static_cast<std::size_t>(axis)]);
      else xyz[axis] = static_cast<float>(load_slot(record, axis));
    }
    if (!std::isfinite(xyz[0]) || !std::isfinite(xyz[1]) || !std::isfinite(xyz[2]))
      source.fail_at(record, Where{&element, v, nullptr},
                     "coordinates (" + std::to_string(xyz[0]) + ", " + std::to_string(xyz[1]) + ", " +
                         std::to_string(xyz[2]) + ") are not finite");
    std::memcpy(positions + 3 * v, xyz, sizeof xyz);
  }
  if (layout.has_normals)
    for (std::size_t v = 0; v < element.count; ++v)
      for (int axis = 0; axis < 3; ++axis)
        mesh.normals[3 * v + static_cast<std::size_t>(axis)] =
            static_cast<float>(load_slot(records + v * entry_size, slot_nx + axis));
  if (layout.has_colors)
    for (std::size_t v = 0; v < element.count; ++v)
      for (int channel = 0; channel < 4; ++channel) {
        const int slot = slot_red + channel;
        const double value = layout.has(slot) ? load_slot(records + v * entry_size, slot) : 1.0;
        mesh.vertex_colors[4 * v + static_cast<std::size_t>(channel)] =
            static_cast<float>(value / layout.divisor[static_cast<std::size_t>(slot)]);
      }
  if (layout.has_texcoords) {
    const bool from_scalar = layout.has(slot_scalar);
    for (std::size_t v = 0; v < element.count; ++v) {
      const std::byte* record = records + v * entry_size;
      const float u = static_cast<float>(load_slot(record, from_scalar ? slot_scalar : slot_u));
      const float t = from_scalar ? 0.5f : static_cast<float>(load_slot(record, slot_v));
      if (!std::isfinite(u) || !std::isfinite(t))
        source.fail_at(record, Where{&element, v, nullptr},
                       "texture coordinates (" + std::to_string(u) + ", " + std::to_string(t) + ") are not finite");
      mesh.texcoords[2 * v] = u, mesh.texcoords[2 * v + 1] = t;
    }
  }
}

template <class Source>
void read_vertices(Source& source, const Element& element, const Layout& layout, MeshData& mesh) {
  const auto count = static_cast<std::size_t>(element.count);
  reserve_huge(mesh.positions, 3 * count);
  mesh.positions.resize(3 * count);
  if (layout.has_normals) {
    reserve_huge(mesh.normals, 3 * count);
    mesh.normals.resize(3 * count);
  }
  if (layout.has_colors) {
    reserve_huge(mesh.vertex_colors, 4 * count);
    mesh.vertex_colors.resize(4 * count);
  }
  if (layout.has_texcoords) {
    reserve_huge(mesh.texcoords, 2 * count);
    mesh.texcoords.resize(2 * count);
  }
  if constexpr (Source::is_binary) {
    if (const auto entry_size = fixed_entry_size(element)) {
      bool float_positions = true;
      for (int axis = 0; axis < 3; ++axis)
        float_positions = float_positions &&
                          element.properties[static_cast<std::size_t>(
                                                 layout.property_of_slot[static_cast<std::size_t>(axis)])]
                                  .type == ScalarType::float32;
      if (float_positions)
        read_fixed_vertices<Source::swaps, true>(source, element, layout, *entry_size, mesh);
      else read_fixed_vertices<Source::swaps, false>(source, element, layout, *entry_size, mesh);
      return;
    }
  }
  std::array<double, slot_count> values{};
  values[slot_alpha] = layout.divisor[slot_alpha];  // opaque unless the file says otherwise
  for (std::uint64_t v = 0; v < element.count; ++v) {
    for (std::size_t p = 0; p < element.properties.size(); ++p) {
      const Property& property = element.properties[p];
      const Where where{&element, v, &property};
      const int slot = layout.slot_of_property[p];
      const bool scalar = layout.property_of_slot[slot_scalar] == static_cast<int>(p);
      if (slot < 0 && !scalar) {
        skip_property(source, property, where);
        continue;
      }
      const double value = source.scalar(property.type, where);
      if (slot >= 0) values[static_cast<std::size_t>(slot)] = value;
      if (scalar) values[slot_scalar] = value;
    }
    store_vertex(source, Where{&element, v, nullptr}, layout, values, mesh);
  }
}

/// Collects faces as triangles until the first quad, then switches the whole mesh to quads
/// (a triangle becomes v0,v1,v2,v2), so files are read in one pass whatever they hold.
class FaceSink {
public:
  FaceSink(MeshData& mesh, std::uint64_t declared_faces) : mesh_(mesh), declared_faces_(declared_faces) {
    mesh.vertices_per_face = 3;
    reserve_huge(mesh.indices, 3 * declared_faces);
  }

  void add_triangle(std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    auto& indices = mesh_.indices;
    indices.push_back(a);
    indices.push_back(b);
    indices.push_back(c);
    if (mesh_.vertices_per_face == 4) indices.push_back(c);
  }

  /// Adds a polygon of `n` >= 3 vertices and returns how many faces it became.
  std::size_t add_polygon(const std::uint32_t* vertex, std::size_t n) {
    if (n == 4) {
      if (mesh_.vertices_per_face == 3) switch_to_quads();
      mesh_.indices.insert(mesh_.indices.end(), vertex, vertex + 4);
      return 1;
    }
    for (std::size_t k = 1; k + 1 < n; ++k) add_triangle(vertex[0], vertex[k], vertex[k + 1]);
    return n - 2;
  }

private:
  void switch_to_quads() {
    auto& indices = mesh_.indices;
    const std::size_t faces = indices.size() / 3;
    reserve_huge(indices, std::max<std::size_t>(4 * declared_faces_, 4 * faces));
    indices.resize(4 * faces);
    // Back to front: face f moves from 3f to 4f >= 3f, never over a face not yet moved.
    for (std::size_t f = faces; f-- > 0;) {
      const std::uint32_t a = indices[3 * f], b = indices[3 * f + 1], c = indices[3 * f + 2];
      indices[4 * f] = a;
      indices[4 * f + 1] = b;
      indices[4 * f + 2] = c;
      indices[4 * f + 3] = c;
    }
    mesh_.vertices_per_face = 4;
  }

  MeshData& mesh_;
  std::uint64_t declared_faces_;
};

template <class Source>
std::uint32_t checked_index(Source& source, std::int64_t index, std::uint64_t vertex_count,
                            const Where& where) {
  if (index < 0) source.fail(where, "vertex index " + std::to_string(index) + " is negative");
  if (static_cast<std::uint64_t>(index) >= vertex_count)
    source.fail(where, "vertex index " + std::to_string(index) + " is out of range: the file has " +
                           std::to_string(vertex_count) + " vertices");
  return static_cast<std::uint32_t>(index);
}

/// Faces stored as a lone `uchar count, 32-bit index` list, as nearly every writer does.
template <bool Swap, class Index>
void read_faces_uchar_list(BinarySource<Swap>& source, const Element& element, const Layout& layout,
                           std::uint64_t vertex_count, FaceSink& sink) {
  const Property& list = element.properties[static_cast<std::size_t>(layout.index_list)];
  const std::byte* cursor = source.cursor();
  const std::byte* const end = source.end();
  std::vector<std::uint32_t> polygon;
  for (std::uint64_t f = 0; f < element.count; ++f) {
    const Where where{&element, f, &list};
    if (cursor == end) source.fail_truncated(cursor, 1, where);
    const auto n = static_cast<std::size_t>(load<std::uint8_t, Swap>(cursor));
    if (n < 3)
      source.fail_at(cursor, where, "face has " + std::to_string(n) + " vertices; a face needs at least 3");
    if (1 + n * sizeof(Index) > static_cast<std::size_t>(end - cursor))
      source.fail_truncated(cursor, 1 + n * sizeof(Index), where);
    const std::byte* items = cursor + 1;
    cursor = items + n * sizeof(Index);
    const auto vertex = [&](std::size_t k) {
      const Index index = load<Index, Swap>(items + k * sizeof(Index));
      if (static_cast<std::uint64_t>(index) < vertex_count) return static_cast<std::uint32_t>(index);
      source.set_cursor(items + k * sizeof(Index));
      return checked_index(source, index, vertex_count, where);
    };
    if (n == 3) {
      sink.add_triangle(vertex(0), vertex(1), vertex(2));
    } else {
      polygon.resize(n);
      for (std::size_t k = 0; k < n; ++k) polygon[k] = vertex(k);
      sink.add_polygon(polygon.data(), n);
    }
  }
  source.set_cursor(cursor);
}

template <class Source>
void read_faces(Source& source, const Element& element, const Layout& layout, std::uint64_t vertex_count,
                MeshData& mesh) {
  FaceSink sink(mesh, element.count);
  const Property& list = element.properties[static_cast<std::size_t>(layout.index_list)];
  if constexpr (Source::is_binary) {
    if (element.properties.size() == 1 && list.list_count_type == ScalarType::uint8) {
      if (list.type == ScalarType::int32)
        return read_faces_uchar_list<Source::swaps, std::int32_t>(source, element, layout, vertex_count,
                                                                  sink);
      if (list.type == ScalarType::uint32)
        return read_faces_uchar_list<Source::swaps, std::uint32_t>(source, element, layout, vertex_count,
                                                                   sink);
    }
  }
  if (layout.has_colors) reserve_huge(mesh.face_colors, 4 * element.count);
  std::vector<std::uint32_t> polygon;
  std::array<double, slot_count> values{};
  values[slot_alpha] = layout.divisor[slot_alpha];
  for (std::uint64_t f = 0; f < element.count; ++f) {
    for (std::size_t p = 0; p < element.properties.size(); ++p) {
      const Property& property = element.properties[p];
      const Where where{&element, f, &property};
      if (static_cast<int>(p) == layout.index_list) {
        const std::uint64_t n = source.list_length(property, where);
        if (n < 3) source.fail(where, "face has " + std::to_string(n) + " vertices; a face needs at least 3");
        polygon.resize(static_cast<std::size_t>(n));
        for (auto& index : polygon)
          index = checked_index(source, source.integer(property.type, where), vertex_count, where);
      } else if (const int slot = layout.slot_of_property[p]; slot >= 0) {
        values[static_cast<std::size_t>(slot)] = source.scalar(property.type, where);
      } else {
        skip_property(source, property, where);
      }
    }
    const std::size_t faces = sink.add_polygon(polygon.data(), polygon.size());
    if (layout.has_colors)
      for (std::size_t k = 0; k < faces; ++k)
        for (int channel = 0; channel < 4; ++channel) {
          const auto slot = static_cast<std::size_t>(slot_red + channel);
          mesh.face_colors.push_back(static_cast<float>(values[slot] / layout.divisor[slot]));
        }
  }
}

/// The elements the mesh comes from and how their properties map, checked before any data is read.
struct MeshLayout {
  const Element* vertices = nullptr;
  const Element* faces = nullptr;
  Layout vertex;
  std::optional<Layout> face;
};

inline MeshLayout make_mesh_layout(const Header& header, std::string_view file, std::string_view texcoord_from) {
  MeshLayout mesh;
  for (const Element& element : header.elements) {
    const Element** known = element.name == "vertex" ? &mesh.vertices
                            : element.name == "face" ? &mesh.faces
                                                     : nullptr;
    if (!known) continue;
    if (*known) fail(file, "the header declares element '" + element.name + "' twice");
    *known = &element;
  }
  if (!mesh.vertices) fail(file, "the header has no element 'vertex'");
  if (mesh.vertices->count > std::numeric_limits<std::uint32_t>::max())
    fail(file, "element 'vertex' has " + std::to_string(mesh.vertices->count) +
                   " entries; vertex indices are 32-bit, so at most 4294967295 are supported");
  mesh.vertex = make_layout(*mesh.vertices, slot_x, slot_scalar, file, texcoord_from);
  if (mesh.faces) mesh.face = make_face_layout(*mesh.faces, file);
  return mesh;
}

template <class Source>
MeshData read_elements(Source& source, const Header& header, const MeshLayout& layout) {
  MeshData mesh;
  for (const Element& element : header.elements) {
    if (&element == layout.vertices) read_vertices(source, element, layout.vertex, mesh);
    else if (&element == layout.faces)
      read_faces(source, element, *layout.face, layout.vertices->count, mesh);
    else skip_element(source, element);
  }
  return mesh;
}

/// Maps the u of every texture coordinate linearly from its range to [0, 1] (0.5 where
/// the scalar is constant).
inline void normalize_u(PaddedVector<float>& texcoords) {
  if (texcoords.empty()) return;
  float lo = texcoords[0], hi = texcoords[0];
  for (std::size_t i = 0; i < texcoords.size(); i += 2) lo = std::min(lo, texcoords[i]), hi = std::max(hi, texcoords[i]);
  const double range = static_cast<double>(hi) - lo;
  for (std::size_t i = 0; i < texcoords.size(); i += 2)
    texcoords[i] = range > 0.0 ? static_cast<float>((texcoords[i] - static_cast<double>(lo)) / range) : 0.5f;
}

}  // namespace ply_detail

/// How to read a PLY file beyond its geometry.
struct PlyOptions {
  /// A per-vertex scalar property to make texture coordinates from (u over its range,
  /// v = 0.5), instead of the file's own u, v; empty for none.
  std::string texcoord_from;
};

/// Parses a PLY file held in memory; `name_for_errors` prefixes every error message.
inline MeshData parse_ply(std::span<const std::byte> bytes, std::string_view name_for_errors,
                          const PlyOptions& options = {}) {
  using namespace ply_detail;
  static_assert(std::endian::native == std::endian::little || std::endian::native == std::endian::big);
  const Header header = parse_header(bytes, name_for_errors);
  const MeshLayout layout = make_mesh_layout(header, name_for_errors, options.texcoord_from);
  check_counts_fit(header, bytes.size() - header.data_offset, name_for_errors);
  const auto read = [&]() -> MeshData {
    if (header.format == Format::ascii) {
      AsciiSource source(bytes, header, name_for_errors);
      return read_elements(source, header, layout);
    }
    const bool file_little = header.format == Format::binary_little_endian;
    if (file_little == (std::endian::native == std::endian::little)) {
      BinarySource<false> source(bytes, header.data_offset, name_for_errors);
      return read_elements(source, header, layout);
    }
    BinarySource<true> source(bytes, header.data_offset, name_for_errors);
    return read_elements(source, header, layout);
  };
  MeshData mesh = read();
  if (!options.texcoord_from.empty()) normalize_u(mesh.texcoords);
  return mesh;
}

/// Reads a whole PLY file (ascii or binary) into memory and parses it.
inline MeshData read_ply(const std::filesystem::path& path, const PlyOptions& options = {}) {
  const std::string name = path.string();
  return parse_ply(ply_detail::read_whole_file(path, name).span(), name, options);
}

}  // namespace sciray::io
