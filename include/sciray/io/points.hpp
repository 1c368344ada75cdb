#pragma once
// Point clouds and particles: positions, an optional radius per point and every other
// per-point scalar property by name (to colour by), read from
//  - PLY (ascii, binary little or big endian, every scalar type): the element `vertex`
//    with x, y, z, maybe `radius`, and any other properties. List properties and other
//    elements, faces included, are skipped; is_point_cloud_file() tells a PLY without faces
//    (or with an empty face element) from a mesh;
//  - `.xyz` and `.xyzr` text: x y z (r) per line, separated by white space; `#` starts a
//    comment; blank lines are skipped. (A chemistry .xyz, with element symbols, is not this.)
//  - `.f32xyzr`: raw float32 records x y z r, little endian, 16 bytes a point, no header.
// The file is read whole and parsed from memory: binary records by column copies, text
// with std::from_chars. to_spheres() makes SphereData: the file's radii, else a given
// radius, else a fifth of the points' mean spacing; coloured by a property through a colour
// map or by the file's red, green, blue (alpha). Every error names the file and, where it
// applies, the point (PLY element entry, text line, byte offset) and the property.
#include <algorithm>
#include <array>
#include <bit>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "sciray/error.hpp"
#include "sciray/geometry/data.hpp"
#include "sciray/geometry/spheres.hpp"
#include "sciray/io/ply_format.hpp"
#include "sciray/math/vec.hpp"

namespace sciray::io {

enum class PointFormat { from_extension, ply, xyz, xyzr, f32xyzr };

struct PointOptions {
  PointFormat format = PointFormat::from_extension;  ///< by default from .ply, .xyz, .xyzr, .f32xyzr
  std::string radius_property = "radius";            ///< PLY: the vertex property holding radii
  /// to_spheres: the radius when the file has none; 0: a fifth of the points' mean spacing.
  float radius = 0.f;
  /// to_spheres: colour by this property (x, y, z, radius or any scalar) through the colour map.
  std::string color_by;
  /// to_spheres: the values mapped to 0 and 1 (reversed reverses the map); default: the
  /// property's finite range.
  std::optional<std::array<double, 2>> range;
  bool file_colors = false;  ///< to_spheres: colour by the file's red, green, blue (alpha)
  /// to_spheres: size each point by this property: radius × (value / median)^radius_exponent,
  /// so that a point of the median value has `radius` (values must be positive and finite).
  std::string radius_by;
  float radius_exponent = 1.f;
};

/// A per-point scalar other than x, y, z and the radius.
struct PointScalar {
  std::string name;
  std::string type;  ///< the PLY type it was stored as ("uint8", "float32", ...)
  PaddedVector<float> values;
};

struct PointCloud {
  std::string source;             ///< the file, for messages
  PaddedVector<float> positions;  ///< x, y, z per point
  PaddedVector<float> radii;      ///< one per point (finite, >= 0), or empty
  std::string radius_name;        ///< the property the radii came from
  std::vector<PointScalar> scalars;

  std::size_t count() const { return positions.size() / 3; }
  const PointScalar* find(std::string_view name) const {
    for (const PointScalar& scalar : scalars)
      if (scalar.name == name) return &scalar;
    return nullptr;
  }
  /// x, y, z, the radius (if any) and the scalars, in file order.
  std::vector<std::string> property_names() const {
    std::vector<std::string> names{"x", "y", "z"};
    if (!radii.empty()) names.push_back(radius_name);
    for (const PointScalar& scalar : scalars) names.push_back(scalar.name);
    return names;
  }
};

namespace points_detail {

using namespace ply_detail;

/// The shortest text that reads back as `value` ("0.25", "nan", "-inf").
inline std::string number(double value) {
  char text[32];
  return std::string(text, std::to_chars(text, text + sizeof text, value).ptr);
}

inline bool point_ok(const float* p, const float* r) {
  return std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]) && (!r || (std::isfinite(*r) && *r >= 0));
}

/// What is wrong with a point point_ok() refused.
inline std::string point_problem(const float* p, const float* r) {
  if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
    return "coordinates (" + number(p[0]) + ", " + number(p[1]) + ", " + number(p[2]) + ") are not finite";
  return "radius " + number(*r) + (std::isfinite(*r) ? " is negative" : " is not finite");
}

template <class T, bool Swap>
void gather_as(const std::byte* first, std::size_t stride, std::size_t n, float* out, std::size_t out_stride) {
  for (std::size_t i = 0; i < n; ++i) out[i * out_stride] = static_cast<float>(load<T, Swap>(first + i * stride));
}

/// Copies one property of `n` fixed-size records into floats, with the type switch
/// outside the loop.
template <bool Swap>
void gather(const std::byte* first, ScalarType type, std::size_t stride, std::size_t n, float* out,
            std::size_t out_stride) {
  switch (type) {
    case ScalarType::int8: return gather_as<std::int8_t, Swap>(first, stride, n, out, out_stride);
    case ScalarType::uint8: return gather_as<std::uint8_t, Swap>(first, stride, n, out, out_stride);
    case ScalarType::int16: return gather_as<std::int16_t, Swap>(first, stride, n, out, out_stride);
    case ScalarType::uint16: return gather_as<std::uint16_t, Swap>(first, stride, n, out, out_stride);
    case ScalarType::int32: return gather_as<std::int32_t, Swap>(first, stride, n, out, out_stride);
    case ScalarType::uint32: return gather_as<std::uint32_t, Swap>(first, stride, n, out, out_stride);
    case ScalarType::float32: return gather_as<float, Swap>(first, stride, n, out, out_stride);
    case ScalarType::float64: return gather_as<double, Swap>(first, stride, n, out, out_stride);
  }
}

/// Where each vertex property goes: a float array and its stride, or nowhere (lists).
struct Target {
  float* data = nullptr;
  std::size_t stride = 1;
};

/// Sizes the cloud's arrays for `element` and says where each of its properties goes.
inline std::vector<Target> plan_vertices(const Element& element, const std::string& radius_name, std::string_view file,
                                         PointCloud& cloud) {
  const auto count = static_cast<std::size_t>(element.count);
  const auto where = [&](const Property& property) {
    return "property '" + property.name + "' of element '" + element.name + "'";
  };
  std::array<int, 4> found{-1, -1, -1, -1};  // x, y, z, radius
  std::size_t scalars = 0;
  for (std::size_t p = 0; p < element.properties.size(); ++p) {
    const Property& property = element.properties[p];
    for (std::size_t q = 0; q < p; ++q)
      if (element.properties[q].name == property.name) fail(file, where(property) + " is declared twice");
    const std::array<std::string_view, 4> named{"x", "y", "z", radius_name};
    const auto slot = std::find(named.begin(), named.end(), property.name) - named.begin();
    if (slot < 4) {
      if (property.is_list()) fail(file, where(property) + " must be a scalar, not a list");
      found[static_cast<std::size_t>(slot)] = static_cast<int>(p);
    } else if (!property.is_list()) {
      ++scalars;
    }
  }
  for (std::size_t axis = 0; axis < 3; ++axis)
    if (found[axis] < 0)
      fail(file,
           "element '" + element.name + "' has no property '" + std::string(1, static_cast<char>('x' + axis)) + "'");
  reserve_huge(cloud.positions, 3 * count);
  cloud.positions.resize(3 * count);
  if (found[3] >= 0) {
    reserve_huge(cloud.radii, count);
    cloud.radii.resize(count);
    cloud.radius_name = radius_name;
  }
  cloud.scalars.reserve(scalars);  // no reallocation below: targets point into them
  std::vector<Target> targets(element.properties.size());
  for (std::size_t p = 0; p < element.properties.size(); ++p) {
    const Property& property = element.properties[p];
    const auto slot = std::find(found.begin(), found.end(), static_cast<int>(p)) - found.begin();
    if (slot < 3) {
      // Without vertices the positions are empty, and their null data must not be offset.
      targets[p] = {count ? cloud.positions.data() + slot : nullptr, 3};
    } else if (slot == 3) {
      targets[p] = {cloud.radii.data(), 1};
    } else if (!property.is_list()) {
      PointScalar& scalar = cloud.scalars.emplace_back();
      scalar.name = property.name;
      scalar.type = name_of(property.type);
      reserve_huge(scalar.values, count);
      scalar.values.resize(count);
      targets[p] = {scalar.values.data(), 1};
    }
  }
  return targets;
}

/// Reads the vertices value by value: ascii, or binary records with list properties.
template <class Source>
void read_vertices_general(Source& source, const Element& element, const std::vector<Target>& targets,
                           PointCloud& cloud) {
  const float* radii = cloud.radii.empty() ? nullptr : cloud.radii.data();
  for (std::uint64_t v = 0; v < element.count; ++v) {
    [[maybe_unused]] const std::byte* entry = nullptr;  // where a bad point's entry starts
    if constexpr (Source::is_binary) entry = source.cursor();
    for (std::size_t p = 0; p < element.properties.size(); ++p) {
      const Property& property = element.properties[p];
      const Where where{&element, v, &property};
      if (!targets[p].data) {
        skip_property(source, property, where);
        continue;
      }
      targets[p].data[v * targets[p].stride] = static_cast<float>(source.scalar(property.type, where));
    }
    const float* position = cloud.positions.data() + 3 * v;
    if (point_ok(position, radii ? radii + v : nullptr)) [[likely]]
      continue;
    const std::string problem = point_problem(position, radii ? radii + v : nullptr);
    if constexpr (Source::is_binary)
      source.fail_at(entry, Where{&element, v, nullptr}, problem);
    else
      source.fail(Where{&element, v, nullptr}, problem);
  }
}

template <class Source>
void read_vertices(Source& source, const Element& element, const std::vector<Target>& targets, PointCloud& cloud) {
  if constexpr (Source::is_binary) {
    if (const auto entry_size = fixed_entry_size(element)) {
      const std::byte* records = source.take_entries(element, *entry_size);
      const auto count = static_cast<std::size_t>(element.count);
      std::size_t offset = 0;
      for (std::size_t p = 0; p < element.properties.size(); ++p) {
        const ScalarType type = element.properties[p].type;
        gather<Source::swaps>(records + offset, type, *entry_size, count, targets[p].data, targets[p].stride);
        offset += size_of(type);
      }
      const float* radii = cloud.radii.empty() ? nullptr : cloud.radii.data();
      for (std::size_t v = 0; v < count; ++v) {
        const float* position = cloud.positions.data() + 3 * v;
        if (!point_ok(position, radii ? radii + v : nullptr)) [[unlikely]]
          source.fail_at(records + v * *entry_size, Where{&element, v, nullptr},
                         point_problem(position, radii ? radii + v : nullptr));
      }
      return;
    }
  }
  read_vertices_general(source, element, targets, cloud);
}

inline const Element* find_element(const Header& header, std::string_view name, std::string_view file) {
  const Element* found = nullptr;
  for (const Element& element : header.elements) {
    if (element.name != name) continue;
    if (found) fail(file, "the header declares element '" + element.name + "' twice");
    found = &element;
  }
  return found;
}

inline PointCloud parse_ply_points(std::span<const std::byte> bytes, std::string_view file,
                                   const std::string& radius_name) {
  const Header header = parse_header(bytes, file);
  const Element* vertices = find_element(header, "vertex", file);
  if (!vertices) fail(file, "the header has no element 'vertex'");
  // Before anything is allocated from a count: it must fit in the bytes that follow.
  check_counts_fit(header, bytes.size() - header.data_offset, file);
  PointCloud cloud;
  const std::vector<Target> targets = plan_vertices(*vertices, radius_name, file, cloud);
  const auto read = [&](auto source) {
    for (const Element& element : header.elements) {
      if (&element == vertices)
        read_vertices(source, element, targets, cloud);
      else
        skip_element(source, element);
    }
  };
  if (header.format == Format::ascii)
    read(AsciiSource(bytes, header, file));
  else if ((header.format == Format::binary_little_endian) == (std::endian::native == std::endian::little))
    read(BinarySource<false>(bytes, header.data_offset, file));
  else
    read(BinarySource<true>(bytes, header.data_offset, file));
  return cloud;
}

/// Parses one text value; values beyond float's range become 0 or infinity (checked later).
inline bool parse_float(std::string_view text, float& value) {
  if (text.size() > 1 && text[0] == '+') text.remove_prefix(1);  // from_chars rejects a leading '+'
  const char* end = text.data() + text.size();
  std::from_chars_result result = std::from_chars(text.data(), end, value);
  if (result.ec == std::errc::result_out_of_range) {
    double wide = 0;
    result = std::from_chars(text.data(), end, wide);
    value = static_cast<float>(wide);
  }
  return result.ec == std::errc() && result.ptr == end;
}

inline PointCloud parse_xyz(std::span<const std::byte> bytes, std::string_view file, bool with_radius) {
  PointCloud cloud;
  if (with_radius) cloud.radius_name = "radius";
  const std::size_t expected = with_radius ? 4 : 3;
  const char* cursor = reinterpret_cast<const char*>(bytes.data());
  const char* const end = cursor + bytes.size();
  std::size_t line = 0;
  while (cursor != end) {
    const auto* newline = static_cast<const char*>(std::memchr(cursor, '\n', static_cast<std::size_t>(end - cursor)));
    std::string_view text(cursor, static_cast<std::size_t>((newline ? newline : end) - cursor));
    cursor = newline ? newline + 1 : end;
    ++line;
    if (const std::size_t hash = text.find('#'); hash != std::string_view::npos) text = text.substr(0, hash);
    float values[4];
    std::size_t found = 0;
    for (std::size_t i = 0; i < text.size();) {
      if (is_space(text[i])) {
        ++i;
        continue;
      }
      const std::size_t start = i;
      while (i < text.size() && !is_space(text[i])) ++i;
      const std::string_view token = text.substr(start, i - start);
      if (found < expected && !parse_float(token, values[found]))
        fail(file, "line " + std::to_string(line) + ": '" + std::string(token) + "' is not a number");
      ++found;
    }
    if (found == 0) continue;
    if (found != expected)
      fail(file, "line " + std::to_string(line) + ": " + std::to_string(found) + " values, expected " +
                     std::to_string(expected) + (with_radius ? " (x y z r)" : " (x y z)"));
    const float* radius = with_radius ? values + 3 : nullptr;
    if (!point_ok(values, radius)) [[unlikely]]
      fail(file, "line " + std::to_string(line) + ", point " + std::to_string(cloud.count()) + ": " +
                     point_problem(values, radius));
    cloud.positions.insert(cloud.positions.end(), values, values + 3);
    if (with_radius) cloud.radii.push_back(values[3]);
  }
  return cloud;
}

inline PointCloud parse_f32xyzr(std::span<const std::byte> bytes, std::string_view file) {
  constexpr std::size_t record = 4 * sizeof(float);
  if (bytes.size() % record != 0)
    fail(file, "the file has " + std::to_string(bytes.size()) +
                   " bytes, not a multiple of 16: a .f32xyzr file holds x, y, z, r as float32 per point");
  const std::size_t count = bytes.size() / record;
  PointCloud cloud;
  cloud.radius_name = "radius";
  // An empty file is an empty cloud, as an empty .xyz is (to_spheres refuses it); the
  // gathers below would offset the empty vectors' null data.
  if (count == 0) return cloud;
  reserve_huge(cloud.positions, 3 * count);
  cloud.positions.resize(3 * count);
  reserve_huge(cloud.radii, count);
  cloud.radii.resize(count);
  constexpr bool swap = std::endian::native != std::endian::little;
  for (std::size_t axis = 0; axis < 3; ++axis)
    gather_as<float, swap>(bytes.data() + 4 * axis, record, count, cloud.positions.data() + axis, 3);
  gather_as<float, swap>(bytes.data() + 12, record, count, cloud.radii.data(), 1);
  for (std::size_t i = 0; i < count; ++i)
    if (!point_ok(cloud.positions.data() + 3 * i, cloud.radii.data() + i)) [[unlikely]]
      fail(file, "point " + std::to_string(i) + ", byte offset " + std::to_string(i * record) + ": " +
                     point_problem(cloud.positions.data() + 3 * i, cloud.radii.data() + i));
  return cloud;
}

inline std::optional<PointFormat> format_by_extension(std::string_view file) {
  std::string extension = std::filesystem::path(file).extension().string();
  for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (extension == ".ply") return PointFormat::ply;
  if (extension == ".xyz") return PointFormat::xyz;
  if (extension == ".xyzr") return PointFormat::xyzr;
  if (extension == ".f32xyzr") return PointFormat::f32xyzr;
  return std::nullopt;
}

/// A property's values, wherever the cloud keeps them.
struct Values {
  const float* data = nullptr;
  std::size_t stride = 1;
  float operator[](std::size_t i) const { return data[i * stride]; }
};

[[noreturn]] inline void fail_missing(const PointCloud& cloud, std::string_view name, std::string_view use) {
  std::string message = "no point property '";
  message += name;
  message += "' ";
  message += use;
  message += "; the points have ";
  const std::vector<std::string> names = cloud.property_names();
  for (std::size_t i = 0; i < names.size(); ++i) message += (i == 0 ? "" : ", ") + names[i];
  fail(cloud.source, message);
}

inline Values values_of(const PointCloud& cloud, std::string_view name, std::string_view use) {
  if (name.size() == 1 && name[0] >= 'x' && name[0] <= 'z') return {cloud.positions.data() + (name[0] - 'x'), 3};
  if (!cloud.radii.empty() && name == cloud.radius_name) return {cloud.radii.data(), 1};
  if (const PointScalar* scalar = cloud.find(name)) return {scalar->values.data(), 1};
  fail_missing(cloud, name, use);
}

}  // namespace points_detail

/// Parses a point file held in memory; `name_for_errors` prefixes every error and, with
/// PointFormat::from_extension, gives the format by its extension.
inline PointCloud parse_points(std::span<const std::byte> bytes, std::string_view name_for_errors,
                               const PointOptions& options = {}) {
  using namespace points_detail;
  PointFormat format = options.format;
  if (format == PointFormat::from_extension) {
    const auto by_extension = format_by_extension(name_for_errors);
    if (!by_extension)
      fail(name_for_errors, "unknown point file extension '" +
                                std::filesystem::path(name_for_errors).extension().string() +
                                "' (expected .ply, .xyz, .xyzr or .f32xyzr)");
    format = *by_extension;
  }
  PointCloud cloud = format == PointFormat::ply ? parse_ply_points(bytes, name_for_errors, options.radius_property)
                     : format == PointFormat::f32xyzr ? parse_f32xyzr(bytes, name_for_errors)
                                                      : parse_xyz(bytes, name_for_errors, format == PointFormat::xyzr);
  cloud.source = name_for_errors;
  return cloud;
}

/// Reads a whole point file (.ply, .xyz, .xyzr, .f32xyzr) into memory and parses it.
inline PointCloud read_points(const std::string& path, const PointOptions& options = {}) {
  return parse_points(ply_detail::read_whole_file(path, path).span(), path, options);
}

/// Whether `path` is a point cloud: a .xyz, .xyzr or .f32xyzr file, or a PLY file whose
/// header has a vertex element and no face element or an empty one. Only a PLY header is
/// read; false for anything else, unreadable files included (the mesh reader says why).
inline bool is_point_cloud_file(const std::string& path) {
  const auto format = points_detail::format_by_extension(path);
  if (format != PointFormat::ply) return format.has_value();
  std::ifstream file(path, std::ios::binary);
  std::string header(std::size_t{1} << 20, '\0');  // a PLY header is far shorter; parsing stops at its end
  file.read(header.data(), static_cast<std::streamsize>(header.size()));
  header.resize(static_cast<std::size_t>(file.gcount()));
  try {
    const auto bytes = std::as_bytes(std::span(header.data(), header.size()));
    const ply_detail::Header parsed = ply_detail::parse_header(bytes, path);
    const ply_detail::Element* faces = points_detail::find_element(parsed, "face", path);
    return points_detail::find_element(parsed, "vertex", path) && (!faces || faces->count == 0);
  } catch (const Error&) {
    return false;
  }
}

/// The smallest and largest finite values of property `name` ({0, 0} when none is finite).
inline std::array<double, 2> finite_range(const PointCloud& cloud, std::string_view name) {
  const points_detail::Values values = points_detail::values_of(cloud, name, "to take the range of");
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (std::size_t i = 0; i < cloud.count(); ++i)
    if (const float v = values[i]; std::isfinite(v)) lo = std::min<double>(lo, v), hi = std::max<double>(hi, v);
  return lo <= hi ? std::array<double, 2>{lo, hi} : std::array<double, 2>{0, 0};
}

/// RGBA per point: property `name` mapped linearly from `given_range` (default: its finite
/// range) to [0, 1], clamped (0 for an empty range), through `colormap`; NaN takes VTK's NaN
/// colour (0.5, 0, 0).
inline PaddedVector<float> colors_by(const PointCloud& cloud, std::string_view name,
                                     const std::function<Vec3f(float)>& colormap,
                                     std::optional<std::array<double, 2>> given_range = {}) {
  const points_detail::Values values = points_detail::values_of(cloud, name, "to colour by");
  const std::array<double, 2> range = given_range ? *given_range : finite_range(cloud, name);
  if (!colormap) ply_detail::fail(cloud.source, "colouring by '" + std::string(name) + "' needs a colour map");
  if (!std::isfinite(range[0]) || !std::isfinite(range[1]))
    ply_detail::fail(cloud.source, "the colour range [" + points_detail::number(range[0]) + ", " +
                                       points_detail::number(range[1]) + "] is not finite");
  PaddedVector<float> colors(4 * cloud.count());
  for (std::size_t i = 0; i < cloud.count(); ++i) {
    const double v = values[i];
    Vec3f rgb{0.5f, 0.f, 0.f};
    if (!std::isnan(v)) {
      const double s = range[1] != range[0] ? (v - range[0]) / (range[1] - range[0]) : 0.0;
      rgb = colormap(static_cast<float>(std::clamp(s, 0.0, 1.0)));
    }
    float* c = colors.data() + 4 * i;
    c[0] = rgb.x, c[1] = rgb.y, c[2] = rgb.z, c[3] = 1.f;
  }
  return colors;
}

/// RGBA per point from the properties red, green, blue and maybe alpha (opaque without):
/// unsigned integers scaled from their full range to [0, 1], floats as they are (clamped).
inline PaddedVector<float> file_colors(const PointCloud& cloud) {
  std::array<const PointScalar*, 4> channel{};
  std::array<double, 4> scale{1, 1, 1, 1};
  constexpr std::array<std::string_view, 4> names{"red", "green", "blue", "alpha"};
  for (std::size_t k = 0; k < 4; ++k)
    if (!(channel[k] = cloud.find(names[k])) && k < 3)
      points_detail::fail_missing(cloud, names[k], "for the file's colours");
  for (std::size_t k = 0; k < 4 && channel[k]; ++k) {
    const std::string& type = channel[k]->type;
    scale[k] = type == "uint8" ? 255.0 : type == "uint16" ? 65535.0 : type == "uint32" ? 4294967295.0 : 1.0;
    if (scale[k] == 1.0 && type != "float32" && type != "float64")
      ply_detail::fail(cloud.source, "property '" + channel[k]->name + "' has type " + type +
                                         "; a colour must be an unsigned integer (scaled to [0,1]) or a float");
  }
  PaddedVector<float> colors(4 * cloud.count());
  for (std::size_t i = 0; i < cloud.count(); ++i)
    for (std::size_t k = 0; k < 4; ++k) {
      const double c = channel[k] ? channel[k]->values[i] / scale[k] : 1.0;
      colors[4 * i + k] = std::isnan(c) ? 0.f : static_cast<float>(std::clamp(c, 0.0, 1.0));
    }
  return colors;
}

/// A fifth of the mean spacing the points would have filling their bounding box evenly:
/// (box measure / count)^(1/d) over the d axes along which the box is not flat (a plane
/// of points is spaced by its area, a line by its length); 1 when all points coincide.
inline float default_radius(const PointCloud& cloud) {
  std::array<double, 3> lo{}, hi{};
  lo.fill(std::numeric_limits<double>::infinity()), hi.fill(-std::numeric_limits<double>::infinity());
  for (std::size_t i = 0; i < cloud.count(); ++i)
    for (std::size_t axis = 0; axis < 3; ++axis)
      lo[axis] = std::min<double>(lo[axis], cloud.positions[3 * i + axis]),
      hi[axis] = std::max<double>(hi[axis], cloud.positions[3 * i + axis]);
  const double largest = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2], 0.0});
  if (!(largest > 0)) return 1.f;
  double measure = 1;
  int dimensions = 0;
  for (std::size_t axis = 0; axis < 3; ++axis)
    if (hi[axis] - lo[axis] > 1e-6 * largest) measure *= hi[axis] - lo[axis], ++dimensions;
  return static_cast<float>(0.2 * std::pow(measure / static_cast<double>(cloud.count()), 1.0 / dimensions));
}

/// Radii `base` × (value / median)^exponent, one per value of `values(i)`, i < count; the
/// first value that is not positive and finite is named (`point`, `name` in `source`).
template <class Values>
PaddedVector<float> scaled_radii(const Values& values, std::size_t count, float base, float exponent,
                                 std::string_view name, std::string_view source) {
  if (!std::isfinite(exponent))
    ply_detail::fail(source, "the radius exponent must be finite, got " + points_detail::number(exponent));
  std::vector<double> sorted(count);
  for (std::size_t i = 0; i < count; ++i) {
    sorted[i] = static_cast<double>(values(i));
    if (!(sorted[i] > 0) || !std::isfinite(sorted[i]))
      ply_detail::fail(source, "point " + std::to_string(i) + " has " + std::string(name) + " " +
                                   points_detail::number(sorted[i]) + ", and a radius needs a positive finite value");
  }
  std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(count / 2), sorted.end());
  const double median = count ? sorted[count / 2] : 1.0;
  PaddedVector<float> radii(count);
  for (std::size_t i = 0; i < count; ++i)
    radii[i] = static_cast<float>(base * std::pow(static_cast<double>(values(i)) / median, exponent));
  return radii;
}

/// Spheres of the points. Radius: the file's radii, else options.radius if > 0, else
/// default_radius(); scaled per point by options.radius_by. Colour: options.color_by through `colormap` over options.range (default
/// the property's finite range), or with options.file_colors the file's own; else none.
inline SphereData to_spheres(PointCloud cloud, const PointOptions& options = {},
                             const std::function<Vec3f(float)>& colormap = {}) {
  using ply_detail::fail;
  if (cloud.count() == 0) fail(cloud.source, "no points to make spheres of");
  if (!(options.radius >= 0.f) || !std::isfinite(options.radius))
    fail(cloud.source, "the radius must be finite and positive (or 0 for one from the spacing), got " +
                           points_detail::number(options.radius));
  if (!options.color_by.empty() && options.file_colors)
    fail(cloud.source, "colour by the property '" + options.color_by + "' or by the file's colours, not both");
  SphereData spheres;
  if (!options.color_by.empty())
    spheres.colors = colors_by(cloud, options.color_by, colormap, options.range);
  else if (options.file_colors)
    spheres.colors = file_colors(cloud);
  PaddedVector<float> scale;  // per point, from options.radius_by
  if (!options.radius_by.empty()) {
    const points_detail::Values values = points_detail::values_of(cloud, options.radius_by, "to size the spheres by");
    scale = scaled_radii([&](std::size_t i) { return values[i]; }, cloud.count(), 1.f, options.radius_exponent,
                         options.radius_by, cloud.source);
  }
  if (!cloud.radii.empty()) {
    for (std::size_t i = 0; i < cloud.radii.size(); ++i)
      if (!(cloud.radii[i] > 0.f))
        fail(cloud.source,
             "point " + std::to_string(i) + " has " + cloud.radius_name + " 0, and a sphere needs a positive radius");
    spheres.radii = std::move(cloud.radii);
  } else {
    spheres.radius = options.radius > 0.f ? options.radius : default_radius(cloud);
  }
  if (!scale.empty()) {
    for (std::size_t i = 0; i < scale.size(); ++i) scale[i] *= spheres.radii.empty() ? spheres.radius : spheres.radii[i];
    spheres.radii = std::move(scale);
  }
  spheres.positions = std::move(cloud.positions);
  return spheres;
}

}  // namespace sciray::io
