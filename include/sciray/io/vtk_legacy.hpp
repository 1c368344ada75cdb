#pragma once
// Legacy VTK files (`.vtk`, "# vtk DataFile Version 2.0" to 5.1), ASCII or BINARY (numbers
// big-endian, as VTK writes them), of three dataset types:
//  - STRUCTURED_POINTS -> VolumeFile, one point or cell array as the voxels (as read_vti);
//  - UNSTRUCTURED_GRID -> UnstructuredGridFile, for io::unstructured_volume;
//  - POLYDATA          -> PolyDataFile (triangulated polygons and strips, or points).
// Cells in either layout: version 5's OFFSETS and CONNECTIVITY arrays, or the older
// "count, point ids" per cell. POINT_DATA and CELL_DATA hold SCALARS (with their
// LOOKUP_TABLE line), COLOR_SCALARS, VECTORS, NORMALS, TEXTURE_COORDINATES, TENSORS,
// GLOBAL_IDS, PEDIGREE_IDS and FIELD arrays; standalone LOOKUP_TABLEs, the dataset's own
// FIELD data and METADATA blocks are skipped. Every error names the file, the line (ASCII)
// or byte (binary) and the section.
#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <system_error>
#include <variant>
#include <vector>

#include "sciray/error.hpp"
#include "sciray/io/volume.hpp"
#include "sciray/io/vtk.hpp"
#include "sciray/io/vtk_image.hpp"
#include "sciray/io/vtk_polydata.hpp"

namespace sciray::io {

/// What a legacy file holds: a STRUCTURED_POINTS volume, an UNSTRUCTURED_GRID, POLYDATA.
using LegacyVtkFile = std::variant<VolumeFile, UnstructuredGridFile, PolyDataFile>;

namespace vtk_detail {

inline std::string upper_case(std::string text) {
  for (char& ch : text) ch = static_cast<char>(ch >= 'a' && ch <= 'z' ? ch - 'a' + 'A' : ch);
  return text;
}

/// The XML name of a legacy number type, or "" for one that is not a number type read here.
inline std::string xml_type_of(std::string legacy) {
  for (char& ch : legacy) ch = static_cast<char>(ch >= 'A' && ch <= 'Z' ? ch - 'A' + 'a' : ch);
  // clang-format off
  static constexpr std::array<std::array<const char*, 2>, 14> names = {{
      {"char", "Int8"}, {"signed_char", "Int8"}, {"unsigned_char", "UInt8"}, {"short", "Int16"},
      {"unsigned_short", "UInt16"}, {"int", "Int32"}, {"unsigned_int", "UInt32"},
      {"vtkidtype", "Int32"},  // VTK writes ids as int
      {"long", "Int64"}, {"unsigned_long", "UInt64"}, {"vtktypeint64", "Int64"}, {"vtktypeuint64", "UInt64"},
      {"float", "Float32"}, {"double", "Float64"}}};
  // clang-format on
  for (const auto& [from, to] : names)
    if (legacy == from) return to;
  return "";
}

/// A legacy file in memory, read keyword by keyword.
class LegacyReader {
public:
  explicit LegacyReader(const std::string& path) {
    c.file = path;
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(path + ": cannot open file");
    std::error_code error;
    const std::uintmax_t size = std::filesystem::file_size(path, error);
    if (error) throw Error(path + ": cannot read the file: " + error.message());
    text_.resize(static_cast<std::size_t>(size));
    if (!in.read(text_.data(), static_cast<std::streamsize>(size))) throw Error(path + ": cannot read the file");
  }

  Context c;
  bool binary = false;

  [[noreturn]] void fail(const std::string& what) const { c.fail(here() + ": " + what); }
  /// Where the reader is: a line of an ASCII file, a byte of a binary one.
  std::string here() const {
    if (binary) return "byte " + std::to_string(pos_);
    return "line " +
           std::to_string(1 + std::count(text_.begin(), text_.begin() + static_cast<std::ptrdiff_t>(pos_), '\n'));
  }
  bool at_end() {
    skip_blanks();
    return pos_ >= text_.size();
  }
  /// The rest of the current line, and the reader after it.
  std::string line() {
    const std::size_t end = std::min(text_.find('\n', pos_), text_.size());
    std::string out = text_.substr(pos_, end - pos_);
    pos_ = std::min(end + 1, text_.size());
    if (!out.empty() && out.back() == '\r') out.pop_back();
    return out;
  }
  /// The next blank-separated word ("" at the end of the file).
  std::string word() {
    skip_blanks();
    const std::size_t begin = pos_;
    while (pos_ < text_.size() && !is_blank(text_[pos_])) ++pos_;
    return text_.substr(begin, pos_ - begin);
  }
  std::string keyword() {
    std::string w = word();
    for (char& ch : w) ch = static_cast<char>(ch >= 'A' && ch <= 'Z' ? ch - 'A' + 'a' : ch);
    return w;
  }
  /// A word as a message shows it: printable and short.
  static std::string shown(std::string w) {
    if (w.size() > 40) w = w.substr(0, 40) + "...";
    for (char& ch : w) ch = ch >= 32 && ch < 127 ? ch : '?';
    return w;
  }
  std::int64_t count(const std::string& what) {
    const std::string w = word();
    std::int64_t v = -1;
    const auto [end, error] = std::from_chars(w.data(), w.data() + w.size(), v);
    if (w.empty() || error != std::errc() || end != w.data() + w.size() || v < 0)
      fail(what + ": expected a count, got '" + shown(w) + "'");
    return v;
  }
  double number(const std::string& what) {
    const std::string w = word();
    double v = 0;
    const auto [end, error] = std::from_chars(w.data(), w.data() + w.size(), v);
    if (w.empty() || error != std::errc() || end != w.data() + w.size())
      fail(what + ": expected a number, got '" + shown(w) + "'");
    return v;
  }
  /// `tuples` tuples of `components` values of legacy type `type`: in binary files the
  /// bytes that start on the next line, in ASCII files as many numbers.
  StoredArray data(const std::string& where, const std::string& type, std::size_t tuples, int components) {
    StoredArray a;
    a.type = xml_type_of(type);
    if (a.type.empty())
      fail(where + ": data type '" + shown(type) + "' is not supported (the number types char to double are)");
    a.components = components;
    a.big_endian = true;
    if (components < 1 || components > (1 << 20)) fail(where + ": " + std::to_string(components) + " components");
    // Counts from the file are bounded before they are multiplied or anything is allocated.
    const std::size_t size = static_cast<std::size_t>(type_size(a.type)), left = text_.size() - pos_;
    if (tuples > std::numeric_limits<std::size_t>::max() / 16 / static_cast<std::size_t>(components))
      fail(where + ": " + std::to_string(tuples) + " tuples are more than any file holds");
    const std::size_t n = tuples * static_cast<std::size_t>(components);
    if (binary) {
      a.ascii = false;
      line();  // the data start on the next line
      const std::size_t need = n * size, rest = text_.size() - pos_;
      if (need > rest)
        fail(where + ": the binary data is truncated: " + std::to_string(need) + " bytes of " + type + " needed, " +
             std::to_string(rest) + " left in the file");
      a.view = reinterpret_cast<const std::uint8_t*>(text_.data() + pos_), a.view_bytes = need;
      pos_ += need;
      skip_array_metadata();
      return a;
    }
    if (n > left)
      fail(where + ": " + std::to_string(n) + " values are needed, more than the file's " + std::to_string(left) +
           " bytes left could hold");
    a.values.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      const std::string w = word();
      if (w.empty())
        fail(where + ": the file ends after " + std::to_string(i) + " of " + std::to_string(n) + " values");
      const auto [end, error] = std::from_chars(w.data(), w.data() + w.size(), a.values[i]);
      if (error != std::errc() || end != w.data() + w.size())
        fail(where + ": value " + std::to_string(i) + " of " + std::to_string(n) + " is '" + shown(w) +
             "', not a number");
    }
    skip_array_metadata();
    return a;
  }
  /// The METADATA block VTK 9 may write after an array (its component names and
  /// information keys), as VTK reads it: a METADATA line, then lines up to a blank one.
  void skip_array_metadata() {
    const std::size_t at = pos_;
    if (keyword() != "metadata") {
      pos_ = at;
      return;
    }
    line();
    while (pos_ < text_.size() && line().find_first_not_of(" \t\r") != std::string::npos) {
    }
  }
  /// A name as VTK writes it, with %XX escapes for the characters a word cannot hold.
  std::string name() {
    const std::string w = word();
    std::string out;
    for (std::size_t i = 0; i < w.size(); ++i) {
      int v = 0;
      if (w[i] == '%' && i + 2 < w.size() &&
          std::from_chars(w.data() + i + 1, w.data() + i + 3, v, 16).ptr == w.data() + i + 3)
        out += static_cast<char>(v), i += 2;
      else
        out += w[i];
    }
    return out;
  }

private:
  static bool is_blank(char ch) { return ch == ' ' || ch == '\t' || ch == '\r' || ch == '\n'; }
  void skip_blanks() {
    while (pos_ < text_.size() && is_blank(text_[pos_])) ++pos_;
  }
  std::string text_;
  std::size_t pos_ = 0;
};

/// Cells in either layout, as connectivity and the offsets where each cell ends. `header`
/// is the keyword (CELLS, POLYGONS, ...), its counts just after it.
inline PolyCells read_cell_list(LegacyReader& r, const std::string& header, int major) {
  PolyCells cells;
  const std::int64_t first = r.count(header), second = r.count(header);
  if (major >= 5) {  // OFFSETS (cells + 1 of them, from 0) and CONNECTIVITY arrays
    if (first < 1) return cells;
    for (const char* part : {"offsets", "connectivity"}) {
      const std::string key = r.keyword();
      if (key != part) r.fail(header + ": expected " + part + ", got '" + LegacyReader::shown(key) + "'");
      const std::string type = r.word();
      const VtkArray v = to_vtk_array(
          r.data(header + " " + part, type, static_cast<std::size_t>(key == "offsets" ? first : second), 1));
      auto& target = key == "offsets" ? cells.offsets : cells.connectivity;
      for (double x : v.values) target.push_back(whole_number(x));
    }
    if (cells.offsets.front() != 0 || cells.offsets.back() != second)
      r.fail(header + ": the offsets run from " + std::to_string(cells.offsets.front()) + " to " +
             std::to_string(cells.offsets.back()) + ", not from 0 to the connectivity's " + std::to_string(second));
    cells.offsets.erase(cells.offsets.begin());
    return cells;
  }
  // Each cell: its number of points, then the points.
  const VtkArray v = to_vtk_array(r.data(header, "int", static_cast<std::size_t>(second), 1));
  std::size_t at = 0;
  for (std::int64_t cell = 0; cell < first; ++cell) {
    const std::int64_t n = at < v.values.size() ? whole_number(v.values[at]) : -1;
    if (n < 0 || at + 1 + static_cast<std::size_t>(n) > v.values.size())
      r.fail(header + ": cell " + std::to_string(cell) + " of " + std::to_string(first) + " does not fit in the " +
             std::to_string(second) + " values given");
    for (std::size_t k = 0; k < static_cast<std::size_t>(n); ++k)
      cells.connectivity.push_back(whole_number(v.values[at + 1 + k]));
    cells.offsets.push_back(static_cast<std::int64_t>(cells.connectivity.size()));
    at += 1 + static_cast<std::size_t>(n);
  }
  if (at != v.values.size())
    r.fail(header + ": the " + std::to_string(first) + " cells take " + std::to_string(at) + " of the " +
           std::to_string(second) + " values given");
  return cells;
}

/// The arrays of a POINT_DATA or CELL_DATA section, and the names of its attributes.
struct LegacyData {
  std::vector<StoredArray> arrays;
  std::string scalars, normals, tcoords;  ///< the first SCALARS, NORMALS, TEXTURE_COORDINATES
};

/// Reads one attribute of a data section (`key` already read), or returns false for a
/// keyword that is not one.
inline bool read_attribute(LegacyReader& r, const std::string& key, const std::string& section, std::size_t tuples,
                           LegacyData& data) {
  const auto add = [&](StoredArray a, std::string name, std::string* attribute) {
    a.name = std::move(name);
    if (attribute && attribute->empty()) *attribute = a.name;
    data.arrays.push_back(std::move(a));
  };
  const auto where = [&](const std::string& name) { return section + " " + upper_case(key) + " '" + name + "'"; };
  if (key == "scalars") {
    const std::string name = r.name(), type = r.word();
    std::string next = r.keyword();
    int components = 1;
    if (next != "lookup_table") {  // the number of components, then LOOKUP_TABLE
      const auto [end, error] = std::from_chars(next.data(), next.data() + next.size(), components);
      if (error != std::errc() || end != next.data() + next.size() || components < 1)
        r.fail(where(name) + ": expected a number of components or LOOKUP_TABLE, got '" + LegacyReader::shown(next) +
               "'");
      next = r.keyword();
    }
    if (next != "lookup_table")
      r.fail(where(name) + ": expected LOOKUP_TABLE, got '" + LegacyReader::shown(next) + "'");
    r.word();  // the table's name
    add(r.data(where(name), type, tuples, components), name, &data.scalars);
  } else if (key == "color_scalars") {
    const std::string name = r.name();
    const auto components = static_cast<int>(std::min<std::int64_t>(r.count(where(name) + " components"), 1 << 21));
    StoredArray a = r.data(where(name), r.binary ? "unsigned_char" : "float", tuples, components);
    for (double& v : a.values) v = std::floor(255.0 * v + 0.5);  // ASCII gives [0,1]; VTK keeps bytes
    add(std::move(a), name, &data.scalars);
  } else if (key == "vectors" || key == "normals" || key == "tensors" || key == "tensors6") {
    const std::string name = r.name(), type = r.word();
    const int components = key == "tensors" ? 9 : key == "tensors6" ? 6 : 3;
    add(r.data(where(name), type, tuples, components), name, key == "normals" ? &data.normals : nullptr);
  } else if (key == "texture_coordinates") {
    const std::string name = r.name();
    const std::int64_t components = r.count(where(name) + " dimension");
    const std::string type = r.word();
    if (components < 1 || components > 3)
      r.fail(where(name) + ": dimension " + std::to_string(components) + " is not 1 to 3");
    add(r.data(where(name), type, tuples, static_cast<int>(components)), name, &data.tcoords);
  } else if (key == "global_ids" || key == "pedigree_ids") {
    const std::string name = r.name(), type = r.word();
    add(r.data(where(name), type, tuples, 1), name, nullptr);
  } else if (key == "lookup_table") {  // a table of its own: skipped
    const std::string name = r.name();
    const auto size = static_cast<std::size_t>(r.count(section + " LOOKUP_TABLE '" + name + "' size"));
    r.data(section + " LOOKUP_TABLE '" + name + "'", r.binary ? "unsigned_char" : "float", size, 4);
  } else if (key == "field") {
    r.word();  // the field's name
    const std::int64_t arrays = r.count(section + " FIELD arrays");
    for (std::int64_t i = 0; i < arrays; ++i) {
      const std::string name = r.name();
      if (name == "NULL_ARRAY") continue;
      const auto components = static_cast<int>(
          std::min<std::int64_t>(r.count(section + " FIELD array '" + name + "' components"), 1 << 21));
      const auto count = static_cast<std::size_t>(r.count(section + " FIELD array '" + name + "' tuples"));
      const std::string type = r.word();
      if (components < 1) r.fail(section + " FIELD array '" + name + "': 0 components");
      if (section != "DATASET" && count != tuples)
        r.fail(section + " FIELD array '" + name + "' has " + std::to_string(count) + " tuples, " +
               std::to_string(tuples) + " expected");
      StoredArray a = r.data(section + " FIELD array '" + name + "'", type, count, components);
      if (section != "DATASET") add(std::move(a), name, nullptr);
    }
  } else {
    return false;
  }
  return true;
}

}  // namespace vtk_detail

/// Reads a legacy .vtk file. For STRUCTURED_POINTS, `field` picks the array as read_vti's
/// does (empty: the point data's first SCALARS, else its first array, else the cell data's);
/// grids and poly data keep all their arrays and ignore it.
inline LegacyVtkFile read_legacy_vtk(const std::string& path, const std::string& field = "") {
  using namespace vtk_detail;
  LegacyReader r(path);
  const Context& c = r.c;
  const std::string version = r.line();
  if (version.rfind("# vtk DataFile Version", 0) != 0)
    c.fail("not a legacy VTK file: the first line is '" + LegacyReader::shown(version) +
           "', not '# vtk DataFile Version x.x'");
  // The major version decides the cell lists' layout (5 and later: offsets and connectivity).
  int major = 0;
  const std::size_t digits = version.find_first_not_of(" \t", 22);
  if (digits == std::string::npos ||
      std::from_chars(version.data() + digits, version.data() + version.size(), major).ec != std::errc{})
    c.fail("the version in '" + LegacyReader::shown(version) + "' is not a number");
  r.line();  // the title
  std::string format = upper_case(r.line());
  format.erase(format.find_last_not_of(" \t") + 1);
  if (format != "ASCII" && format != "BINARY")
    c.fail("line 3 must say ASCII or BINARY, not '" + LegacyReader::shown(format) + "'");
  r.binary = format == "BINARY";
  if (const std::string key = r.keyword(); key != "dataset")
    r.fail("expected DATASET, got '" + LegacyReader::shown(key) + "'");
  const std::string dataset = upper_case(r.keyword());
  if (dataset != "STRUCTURED_POINTS" && dataset != "UNSTRUCTURED_GRID" && dataset != "POLYDATA")
    r.fail("DATASET " + LegacyReader::shown(dataset) +
           " is not supported (STRUCTURED_POINTS, UNSTRUCTURED_GRID and POLYDATA are)");

  std::array<std::int64_t, 3> dims{-1, -1, -1};
  std::array<double, 3> origin{0, 0, 0}, spacing{1, 1, 1};
  std::vector<double> xyz;
  std::array<PolyCells, 4> poly;  // VERTICES, LINES, POLYGONS, TRIANGLE_STRIPS
  PolyCells cells;
  std::vector<std::uint8_t> types;
  LegacyData point_data, cell_data;
  std::string section;  // POINT_DATA or CELL_DATA once one has begun
  std::size_t tuples = 0;
  const auto point_count = [&]() -> std::size_t {
    if (dataset == "STRUCTURED_POINTS") return dims[0] < 0 ? 0 : static_cast<std::size_t>(dims[0] * dims[1] * dims[2]);
    return xyz.size() / 3;
  };  // DIMENSIONS are checked to multiply within 64 bits as they are read
  const auto cell_count = [&]() -> std::size_t {
    if (dataset == "STRUCTURED_POINTS") {
      std::size_t n = dims[0] < 0 ? 0 : 1;
      for (const std::int64_t d : dims) n *= static_cast<std::size_t>(std::max<std::int64_t>(d - 1, 1));
      return n;
    }
    if (dataset == "UNSTRUCTURED_GRID") return cells.offsets.size();
    std::size_t n = 0;
    for (const PolyCells& list : poly) n += list.offsets.size();
    return n;
  };
  static constexpr std::array<const char*, 4> poly_keys = {"vertices", "lines", "polygons", "triangle_strips"};
  while (!r.at_end()) {
    const std::string key = r.keyword(), upper = upper_case(key);
    if (key == "point_data" || key == "cell_data") {
      section = upper;
      tuples = static_cast<std::size_t>(r.count(section));
      const std::size_t expected = key == "point_data" ? point_count() : cell_count();
      if (tuples != expected)
        r.fail(section + " " + std::to_string(tuples) + " does not match the dataset's " + std::to_string(expected) +
               (key == "point_data" ? " points" : " cells"));
    } else if (!section.empty() &&
               read_attribute(r, key, section, tuples, section == "POINT_DATA" ? point_data : cell_data)) {
    } else if (section.empty() && key == "field") {  // the dataset's own field data: skipped
      LegacyData unused;
      read_attribute(r, key, "DATASET", 0, unused);
    } else if (dataset == "STRUCTURED_POINTS" && key == "dimensions") {
      for (std::int64_t& d : dims)
        if ((d = r.count("DIMENSIONS")) < 1 || d > (std::int64_t{1} << 40)) r.fail("DIMENSIONS must be 1 to 2^40");
      volume_detail::byte_count(VolumeDims{dims[0], dims[1], dims[2]}, VoxelKind::float64, c.file);
    } else if (dataset == "STRUCTURED_POINTS" && (key == "origin" || key == "spacing" || key == "aspect_ratio")) {
      for (double& v : key == "origin" ? origin : spacing)
        if (!std::isfinite(v = r.number(upper))) r.fail(upper + " is not finite");
    } else if (dataset != "STRUCTURED_POINTS" && key == "points") {
      const auto n = static_cast<std::size_t>(r.count("POINTS"));
      xyz = to_vtk_array(r.data("POINTS", r.word(), n, 3)).values;
    } else if (dataset == "UNSTRUCTURED_GRID" && key == "cells") {
      cells = read_cell_list(r, "CELLS", major);
    } else if (dataset == "UNSTRUCTURED_GRID" && key == "cell_types") {
      const auto n = static_cast<std::size_t>(r.count("CELL_TYPES"));
      if (n != cells.offsets.size())
        r.fail("CELL_TYPES " + std::to_string(n) + " does not match the " + std::to_string(cells.offsets.size()) +
               " CELLS");
      for (double t : to_vtk_array(r.data("CELL_TYPES", "int", n, 1)).values) {
        if (!(t >= 0 && t <= 255)) r.fail("CELL_TYPES: " + std::to_string(whole_number(t)) + " is not a VTK cell type");
        types.push_back(static_cast<std::uint8_t>(t));
      }
    } else if (const auto* at = std::find(poly_keys.begin(), poly_keys.end(), key);
               dataset == "POLYDATA" && at != poly_keys.end()) {
      poly[static_cast<std::size_t>(at - poly_keys.begin())] = read_cell_list(r, upper, major);
    } else {
      r.fail("unexpected keyword '" + LegacyReader::shown(key) + "' in " +
             (section.empty() ? "DATASET " + dataset : section) +
             (std::isdigit(static_cast<unsigned char>(key[0])) || key[0] == '-' || key[0] == '.'
                  ? " (a number where a keyword should be: more values than the section's count?)"
                  : ""));
    }
  }

  // Sections may come in any order, so their counts are checked against the dataset's again.
  for (const bool point : {true, false})
    for (const StoredArray& a : (point ? point_data : cell_data).arrays)
      if (const std::size_t n = point ? point_count() : cell_count(); a.tuples() != n)
        c.fail(std::string(point ? "POINT_DATA" : "CELL_DATA") + " array '" + a.name + "' has " +
               std::to_string(a.tuples()) + " tuples, but the dataset has " + std::to_string(n) +
               (point ? " points" : " cells"));
  const auto names = [](const LegacyData& d) {
    std::vector<std::string> out;
    for (const StoredArray& a : d.arrays) out.push_back(a.name);
    return out;
  };
  if (dataset == "STRUCTURED_POINTS") {
    if (dims[0] < 0) c.fail("STRUCTURED_POINTS has no DIMENSIONS");
    const ArrayChoice choice =
        choose_array(names(point_data), names(cell_data), point_data.scalars, cell_data.scalars, field, c);
    const StoredArray& a = (choice.cell ? cell_data : point_data).arrays[choice.index];
    VolumeDims d{dims[0], dims[1], dims[2]};
    if (choice.cell)
      for (std::int64_t& n : d) n = std::max<std::int64_t>(n - 1, 1);
    VolumeFile volume = make_volume(d, voxel_kind_of(a), choice.cell, c);
    store_voxels(a, volume.kind, volume.voxels->data());
    place_volume(volume, origin, spacing, c);
    return volume;
  }
  const auto arrays = [](const LegacyData& d) {
    std::vector<VtkArray> out;
    for (const StoredArray& a : d.arrays) out.push_back(to_vtk_array(a));
    return out;
  };
  if (dataset == "UNSTRUCTURED_GRID") {
    if (types.size() != cells.offsets.size())
      c.fail("UNSTRUCTURED_GRID has " + std::to_string(cells.offsets.size()) + " CELLS but " +
             std::to_string(types.size()) + " CELL_TYPES");
    UnstructuredGridFile grid;
    const std::size_t n = xyz.size() / 3;
    check_finite_points(xyz, "POINTS", 0, c);
    for (std::size_t i = 0; i < n; ++i)
      grid.points.push_back(Vec3f{static_cast<float>(xyz[3 * i]), static_cast<float>(xyz[3 * i + 1]),
                                  static_cast<float>(xyz[3 * i + 2])});
    std::int64_t previous = 0;
    for (std::size_t i = 0; i < cells.offsets.size(); ++i) {
      if (cells.offsets[i] < previous || cells.offsets[i] > static_cast<std::int64_t>(cells.connectivity.size()))
        c.fail("CELLS: cell " + std::to_string(i) + " ends at " + std::to_string(cells.offsets[i]) + ", outside [" +
               std::to_string(previous) + ", " + std::to_string(cells.connectivity.size()) + "]");
      previous = cells.offsets[i];
    }
    check_point_indices(cells.connectivity, n, "CELLS: entry", c);
    grid.connectivity = std::move(cells.connectivity);
    grid.offsets = std::move(cells.offsets);
    grid.types = std::move(types);
    grid.point_arrays = arrays(point_data);
    grid.cell_arrays = arrays(cell_data);
    grid.default_point_array = point_data.scalars;
    grid.default_cell_array = cell_data.scalars;
    return grid;
  }
  PolyDataFile out;
  out.source = path;
  add_poly_piece(out, xyz, poly, 0, c, {"POINTS", "VERTICES", "LINES", "POLYGONS", "TRIANGLE_STRIPS"});
  out.point_arrays = arrays(point_data);
  out.cell_arrays = arrays(cell_data);
  out.default_point_array = point_data.scalars;
  out.default_cell_array = cell_data.scalars;
  attach_normals_and_texcoords(out, point_data.normals, point_data.tcoords);
  return out;
}

}  // namespace sciray::io
