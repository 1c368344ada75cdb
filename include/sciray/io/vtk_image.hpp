#pragma once
// VTK image data, XML `.vti` (ImageData), read into an io::VolumeFile: a regular grid of
// voxels, x fastest, at Origin + index * Spacing. One array becomes the voxels: a point
// array gives a vertex-centred volume, a cell array a cell-centred one. UInt8, Int16,
// UInt16, Float32 and Float64 arrays keep their type; other types, and arrays of several
// components (by their magnitude), become Float32. Every encoding io/vtk.hpp reads
// (ASCII, base64, appended raw or base64, zlib, 32- or 64-bit headers, either byte
// order) is read here through its helpers. The pieces of a file are put together by
// their extents.
//
// The helpers here (StoredArray, choose_array, store_voxels) also build the volume of a
// legacy STRUCTURED_POINTS file (io/vtk_legacy.hpp).
#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
#include <optional>
#include <pugixml.hpp>
#include <sstream>
#include <string>
#include <type_traits>
#include <vector>

#include "sciray/error.hpp"
#include "sciray/io/volume.hpp"
#include "sciray/io/vtk.hpp"

namespace sciray::io {

namespace vtk_detail {

/// An array as the file holds it: bytes of a VTK number type (`type` by its XML name:
/// UInt8, Float32, ...) in the file's byte order, or the numbers of ASCII text.
struct StoredArray {
  std::string name;
  std::string type = "Float64";
  int components = 1;
  bool big_endian = false;
  std::vector<double> values;          ///< ASCII data
  std::vector<std::uint8_t> owned;     ///< binary data decoded from the file
  const std::uint8_t* view = nullptr;  ///< binary data read in place (legacy files); else `owned`
  std::size_t view_bytes = 0;
  bool ascii = true;

  const std::uint8_t* bytes() const { return view ? view : owned.data(); }
  std::size_t count() const {
    return ascii ? values.size() : (view ? view_bytes : owned.size()) / static_cast<std::size_t>(type_size(type));
  }
  std::size_t tuples() const { return count() / static_cast<std::size_t>(components); }
};

/// Calls `f(i, value)` for every value of `a`, the type dispatched once.
template <class F>
void for_each_value(const StoredArray& a, F&& f) {
  if (a.ascii) {
    for (std::size_t i = 0; i < a.values.size(); ++i) f(i, a.values[i]);
    return;
  }
  const std::size_t n = a.count();
  const std::uint8_t* p = a.bytes();
  const auto loop = [&](auto zero) {
    using T = decltype(zero);
    for (std::size_t i = 0; i < n; ++i) {
      std::uint8_t b[sizeof(T)];
      for (std::size_t k = 0; k < sizeof(T); ++k) b[k] = p[i * sizeof(T) + (a.big_endian ? sizeof(T) - 1 - k : k)];
      T v;
      std::memcpy(&v, b, sizeof(T));
      f(i, static_cast<double>(v));
    }
  };
  const std::string& t = a.type;
  if (t == "Int8")
    loop(std::int8_t{});
  else if (t == "UInt8")
    loop(std::uint8_t{});
  else if (t == "Int16")
    loop(std::int16_t{});
  else if (t == "UInt16")
    loop(std::uint16_t{});
  else if (t == "Int32")
    loop(std::int32_t{});
  else if (t == "UInt32")
    loop(std::uint32_t{});
  else if (t == "Int64")
    loop(std::int64_t{});
  else if (t == "UInt64")
    loop(std::uint64_t{});
  else if (t == "Float32")
    loop(float{});
  else
    loop(double{});
}

/// `v` as a T: integers clamped to T's range (NaN as 0), where a plain conversion is undefined.
template <class T>
T narrow(double v) {
  if constexpr (std::is_integral_v<T>) {
    if (!(v >= static_cast<double>(std::numeric_limits<T>::lowest())))
      return v > 0 ? std::numeric_limits<T>::max() : T{};
    if (!(v <= static_cast<double>(std::numeric_limits<T>::max()))) return std::numeric_limits<T>::max();
  }
  return static_cast<T>(v);
}

inline VtkArray to_vtk_array(const StoredArray& a) {
  VtkArray out;
  out.name = a.name;
  out.components = a.components;
  if (a.ascii) {
    out.values = a.values;
  } else {
    out.values.resize(a.count());
    for_each_value(a, [&](std::size_t i, double v) { out.values[i] = v; });
  }
  return out;
}

/// The voxel kind an array is kept as: its own type where VolumeFile holds it, else float32.
inline VoxelKind voxel_kind_of(const StoredArray& a) {
  if (a.components == 1) {
    if (a.type == "UInt8") return VoxelKind::uint8;
    if (a.type == "Int16") return VoxelKind::int16;
    if (a.type == "UInt16") return VoxelKind::uint16;
    if (a.type == "Float64") return VoxelKind::float64;
  }
  return VoxelKind::float32;
}

/// Writes the tuples of `a` as voxels of `kind` (voxel_kind_of(a)) to `out`: the bytes as
/// they are where the types agree, else each tuple's value (or magnitude) converted.
inline void store_voxels(const StoredArray& a, VoxelKind kind, std::byte* out) {
  const std::size_t size = voxel_size(kind);
  if (!a.ascii && a.components == 1 && (kind != VoxelKind::float32 || a.type == "Float32")) {
    std::memcpy(out, a.bytes(), a.count() * size);
    if (a.big_endian != (std::endian::native == std::endian::big)) {
      if (size == 2) volume_detail::swap_all<std::uint16_t>(out, a.count());
      if (size == 4) volume_detail::swap_all<std::uint32_t>(out, a.count());
      if (size == 8) volume_detail::swap_all<std::uint64_t>(out, a.count());
    }
    return;
  }
  const auto store = [&](auto zero) {
    using T = decltype(zero);
    const auto put = [&](std::size_t t, double v) {
      const T x = narrow<T>(v);
      std::memcpy(out + t * sizeof(T), &x, sizeof(T));
    };
    if (a.components == 1) {
      for_each_value(a, put);
    } else {
      const auto n = static_cast<std::size_t>(a.components);
      double sum = 0;
      for_each_value(a, [&](std::size_t i, double v) {
        sum += v * v;
        if (i % n == n - 1) put(i / n, std::sqrt(sum)), sum = 0;
      });
    }
  };
  switch (kind) {
    case VoxelKind::uint8: store(std::uint8_t{}); break;
    case VoxelKind::int16: store(std::int16_t{}); break;
    case VoxelKind::uint16: store(std::uint16_t{}); break;
    case VoxelKind::float32: store(float{}); break;
    case VoxelKind::float64: store(double{}); break;
  }
}

/// Names an array list in a message: 'a', 'b' (or none).
inline std::string array_names(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& n : names) {
    if (!out.empty()) out += ", ";
    out += '\'' + n + '\'';
  }
  return out.empty() ? std::string("none") : out;
}

struct ArrayChoice {
  bool cell = false;
  std::size_t index = 0;
};

/// The array `field` names, a point array before a cell array of the same name; empty:
/// the point data's Scalars, else the first point array, else the cell data's Scalars,
/// else the first cell array.
inline ArrayChoice choose_array(const std::vector<std::string>& point_names, const std::vector<std::string>& cell_names,
                                const std::string& point_scalars, const std::string& cell_scalars,
                                const std::string& field, const Context& c) {
  const auto find = [](const std::vector<std::string>& names, const std::string& name) {
    return static_cast<std::size_t>(std::find(names.begin(), names.end(), name) - names.begin());
  };
  const auto pick = [&](const std::string& name) -> std::optional<ArrayChoice> {
    if (const std::size_t i = find(point_names, name); i < point_names.size()) return ArrayChoice{false, i};
    if (const std::size_t i = find(cell_names, name); i < cell_names.size()) return ArrayChoice{true, i};
    return std::nullopt;
  };
  if (!field.empty()) {
    if (const auto chosen = pick(field)) return *chosen;
    c.fail("has no point or cell array '" + field + "' (its point arrays: " + array_names(point_names) +
           "; its cell arrays: " + array_names(cell_names) + ")");
  }
  if (find(point_names, point_scalars) < point_names.size()) return *pick(point_scalars);
  if (!point_names.empty()) return {false, 0};
  if (find(cell_names, cell_scalars) < cell_names.size()) return {true, find(cell_names, cell_scalars)};
  if (!cell_names.empty()) return {true, 0};
  c.fail("has no point or cell array to make a volume of");
}

/// The attribute `name` of `node` as `N` numbers (`fallback` when absent).
template <std::size_t N>
std::array<double, N> attribute_numbers(const pugi::xml_node& node, const char* name, std::array<double, N> fallback,
                                        const Context& c) {
  const pugi::xml_attribute attribute = node.attribute(name);
  if (!attribute) return fallback;
  std::istringstream in(attribute.value());
  std::array<double, N> out{};
  std::string extra;
  for (double& v : out)
    if (!(in >> v))
      c.fail(std::string(node.name()) + " " + name + " '" + attribute.value() + "' must be " + std::to_string(N) +
             " numbers");
  if (in >> extra)
    c.fail(std::string(node.name()) + " " + name + " '" + attribute.value() + "' must be " + std::to_string(N) +
           " numbers");
  for (double v : out)
    if (!std::isfinite(v)) c.fail(std::string(node.name()) + " " + name + " '" + attribute.value() + "' is not finite");
  return out;
}

/// An empty volume of `dims` voxels of `kind`, placed later by place_volume.
inline VolumeFile make_volume(const VolumeDims& dims, VoxelKind kind, bool cell_centered, const Context& c) {
  VolumeFile volume;
  volume.kind = kind;
  volume.dims = dims;
  volume.voxels = volume_detail::allocate(volume_detail::byte_count(dims, kind, c.file), c.file);
  volume.grid.cell_centered = cell_centered;
  return volume;
}

/// Puts the volume's first sample (a cell-centred volume's first corner) at `corner`, `spacing`
/// apart. VTK allows a negative spacing: the voxels along that axis are then flipped and the
/// corner moved to the other end, so that the grid's spacing is positive.
inline void place_volume(VolumeFile& volume, std::array<double, 3> corner, std::array<double, 3> spacing,
                         const Context& c) {
  for (std::size_t k = 0; k < 3; ++k) {
    if (spacing[k] == 0) c.fail("the spacing along axis " + std::to_string(k) + " is zero");
    if (spacing[k] > 0) continue;
    volume_detail::flip_axis(*volume.voxels, volume.dims, static_cast<int>(k), voxel_size(volume.kind));
    corner[k] += spacing[k] * static_cast<double>(volume.dims[k] - (volume.grid.cell_centered ? 0 : 1));
    spacing[k] = -spacing[k];
  }
  volume.grid.origin =
      Vec3f{static_cast<float>(corner[0]), static_cast<float>(corner[1]), static_cast<float>(corner[2])};
  volume.grid.spacing =
      Vec3f{static_cast<float>(spacing[0]), static_cast<float>(spacing[1]), static_cast<float>(spacing[2])};
  for (int k = 0; k < 3; ++k)
    if (!std::isfinite(volume.grid.origin[k]) || !std::isfinite(volume.grid.spacing[k]) ||
        !(volume.grid.spacing[k] > 0.f))
      c.fail("the spacing or origin does not fit a float");
}

/// A DataArray element as stored: `expected` tuples (0: any); the XML attributes name it.
inline StoredArray read_stored(const pugi::xml_node& node, const Context& c, std::size_t expected) {
  StoredArray a;
  a.name = node.attribute("Name").as_string();
  a.type = node.attribute("type").as_string();
  a.components = node.attribute("NumberOfComponents").as_int(1);
  a.big_endian = c.big_endian;
  const std::string format = node.attribute("format").as_string("ascii");
  const std::string where = "DataArray '" + a.name + "'";
  if (format == "ascii") {
    VtkArray values = read_array(node, c, expected);  // checks the type, components and count
    a.values = std::move(values.values);
    return a;
  }
  if (a.components < 1) c.fail(where + ": NumberOfComponents must be at least 1");
  if (type_size(a.type) == 0) c.fail(where + ": unknown type '" + a.type + "'");
  a.ascii = false;
  a.owned = encoded_bytes(node, format, c, where);
  const auto size = static_cast<std::size_t>(type_size(a.type));
  if (a.owned.size() % (size * static_cast<std::size_t>(a.components)) != 0)
    c.fail(where + ": " + std::to_string(a.owned.size()) + " bytes are not whole tuples of " +
           std::to_string(a.components) + " " + a.type + " values");
  if (expected != 0 && a.tuples() != expected)
    c.fail(where + ": has " + std::to_string(a.tuples()) + " tuples, " + std::to_string(expected) + " expected");
  return a;
}

/// A DataArray element's values, as read_array gives them, converted with the type
/// dispatched once per array rather than once per value.
inline VtkArray read_values(const pugi::xml_node& node, const Context& c, std::size_t expected) {
  return to_vtk_array(read_stored(node, c, expected));
}

/// The names of the DataArray children of `data` (a PointData or CellData element).
inline std::vector<std::string> data_array_names(const pugi::xml_node& data) {
  std::vector<std::string> names;
  for (const pugi::xml_node a : data.children("DataArray")) names.emplace_back(a.attribute("Name").as_string());
  return names;
}

}  // namespace vtk_detail

/// Reads a .vti file into a volume of one array: `field` names a point or a cell array;
/// empty picks the point data's Scalars, else the first point array, else the cell data's
/// Scalars, else the first cell array. A cell array gives a cell-centred volume. A Direction
/// other than the identity is refused; a negative spacing flips the voxels along that axis.
inline VolumeFile read_vti(const std::string& path, const std::string& field = "") {
  using namespace vtk_detail;
  const XmlFile file(path, "ImageData");
  const Context& c = file.c;
  const pugi::xml_node image = file.root.child("ImageData");
  if (!image) c.fail("no ImageData element");
  const auto origin = attribute_numbers<3>(image, "Origin", {0, 0, 0}, c);
  const auto spacing = attribute_numbers<3>(image, "Spacing", {1, 1, 1}, c);
  const auto direction = attribute_numbers<9>(image, "Direction", {1, 0, 0, 0, 1, 0, 0, 0, 1}, c);
  for (std::size_t k = 0; k < 9; ++k)
    if (direction[k] != (k % 4 == 0 ? 1.0 : 0.0))
      c.fail(std::string("ImageData Direction '") + image.attribute("Direction").value() +
             "' is not the identity: rotated or mirrored images are not supported");

  const auto extent_of = [&](const pugi::xml_node& node, const char* name) {
    if (!node.attribute(name)) c.fail(std::string(node.name()) + " has no " + name);
    const auto e = attribute_numbers<6>(node, name, {}, c);
    std::array<std::int64_t, 6> out{};
    for (std::size_t k = 0; k < 6; ++k) {
      out[k] = whole_number(e[k]);
      if (static_cast<double>(out[k]) != e[k] || std::abs(e[k]) > 0x1p40)
        c.fail(std::string(node.name()) + " " + name + " '" + node.attribute(name).value() +
               "' must be integers below 2^40");
    }
    for (std::size_t k = 0; k < 3; ++k)
      if (out[2 * k + 1] < out[2 * k])
        c.fail(std::string(node.name()) + " " + name + " '" + node.attribute(name).value() + "' is empty along axis " +
               std::to_string(k));
    return out;
  };
  std::vector<pugi::xml_node> pieces;
  for (const pugi::xml_node piece : image.children("Piece")) pieces.push_back(piece);
  if (pieces.empty()) c.fail("no ImageData Piece");
  // The volume spans the pieces' extents (a piece of a .pvti alone spans its own).
  std::array<std::int64_t, 6> whole = extent_of(pieces[0], "Extent");
  for (const pugi::xml_node& piece : pieces) {
    const auto e = extent_of(piece, "Extent");
    for (std::size_t k = 0; k < 3; ++k)
      whole[2 * k] = std::min(whole[2 * k], e[2 * k]), whole[2 * k + 1] = std::max(whole[2 * k + 1], e[2 * k + 1]);
  }

  const pugi::xml_node first = pieces[0];
  const ArrayChoice choice =
      choose_array(data_array_names(first.child("PointData")), data_array_names(first.child("CellData")),
                   first.child("PointData").attribute("Scalars").as_string(),
                   first.child("CellData").attribute("Scalars").as_string(), field, c);
  const char* data_kind = choice.cell ? "CellData" : "PointData";
  const std::string name = data_array_names(first.child(data_kind))[choice.index];
  // Samples per axis of an extent: its points, or its cells (a flat axis has one).
  const auto samples = [&](const std::array<std::int64_t, 6>& e) {
    VolumeDims d{};
    for (std::size_t k = 0; k < 3; ++k)
      d[k] = e[2 * k + 1] - e[2 * k] + (choice.cell ? 0 : 1), d[k] = std::max<std::int64_t>(d[k], 1);
    return d;
  };
  const VolumeDims dims = samples(whole);
  volume_detail::byte_count(dims, VoxelKind::float64, c.file);  // refuses dims whose count overflows
  // Each piece lies within the whole, so its count fits; their sum saturates at the whole's
  // rather than wrapping around past 2^64 with many huge pieces.
  const auto whole_count = static_cast<std::uint64_t>(dims[0] * dims[1] * dims[2]);
  std::uint64_t held = 0;
  for (const pugi::xml_node& piece : pieces) {
    const VolumeDims d = samples(extent_of(piece, "Extent"));
    held = std::min(whole_count, held + static_cast<std::uint64_t>(d[0] * d[1] * d[2]));
  }
  if (held < whole_count)
    c.fail("the pieces hold " + std::to_string(held) + " samples, too few to cover their extents' " +
           volume_detail::dims_text(dims));
  std::array<double, 3> corner{};
  for (std::size_t k = 0; k < 3; ++k) corner[k] = origin[k] + static_cast<double>(whole[2 * k]) * spacing[k];

  // Every piece's array is read, and so checked against its extent, before the whole is allocated.
  std::vector<StoredArray> stored;
  for (const pugi::xml_node& piece : pieces) {
    const VolumeDims d = samples(extent_of(piece, "Extent"));
    pugi::xml_node node;
    for (const pugi::xml_node a : piece.child(data_kind).children("DataArray"))
      if (name == a.attribute("Name").as_string()) node = a;
    if (!node)
      c.fail(std::string("Piece ") + piece.attribute("Extent").value() + " has no " + data_kind + " array '" + name +
             "'");
    stored.push_back(read_stored(node, c, static_cast<std::size_t>(d[0] * d[1] * d[2])));
    if (voxel_kind_of(stored.back()) != voxel_kind_of(stored.front()))
      c.fail("DataArray '" + name + "' is " + stored.back().type + " in one piece and " + stored.front().type +
             " in another");
  }
  VolumeFile volume = make_volume(dims, voxel_kind_of(stored.front()), choice.cell, c);
  const std::size_t size = voxel_size(volume.kind);
  std::vector<bool> covered;
  for (std::size_t p = 0; p < pieces.size(); ++p) {
    const auto e = extent_of(pieces[p], "Extent");
    const VolumeDims d = samples(e);
    if (d == dims) {
      store_voxels(stored[p], volume.kind, volume.voxels->data());
      continue;
    }
    // A piece of several: its rows go to their place in the whole, which is checked to be covered.
    std::vector<std::byte> part(static_cast<std::size_t>(d[0] * d[1] * d[2]) * size);
    store_voxels(stored[p], volume.kind, part.data());
    stored[p] = {};
    if (covered.empty()) covered.assign(static_cast<std::size_t>(dims[0] * dims[1] * dims[2]), false);
    const std::int64_t x0 = e[0] - whole[0], y0 = e[2] - whole[2], z0 = e[4] - whole[4];
    for (std::int64_t z = 0; z < d[2]; ++z)
      for (std::int64_t y = 0; y < d[1]; ++y) {
        const auto to = static_cast<std::size_t>(((z0 + z) * dims[1] + y0 + y) * dims[0] + x0);
        std::memcpy(volume.voxels->data() + to * size,
                    part.data() + static_cast<std::size_t>((z * d[1] + y) * d[0]) * size,
                    static_cast<std::size_t>(d[0]) * size);
        std::fill_n(covered.begin() + static_cast<std::ptrdiff_t>(to), d[0], true);
      }
  }
  if (const auto gap = std::find(covered.begin(), covered.end(), false); !covered.empty() && gap != covered.end()) {
    const auto i = static_cast<std::int64_t>(gap - covered.begin());
    c.fail("sample (" + std::to_string(whole[0] + i % dims[0]) + ", " +
           std::to_string(whole[2] + i / dims[0] % dims[1]) + ", " +
           std::to_string(whole[4] + i / (dims[0] * dims[1])) + ") is in no Piece");
  }
  place_volume(volume, corner, spacing, c);
  return volume;
}

}  // namespace sciray::io
