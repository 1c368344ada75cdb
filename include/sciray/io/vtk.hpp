#pragma once
// VTK's XML unstructured grid (.vtu): points, cells and their point and cell arrays, as
// ParaView, VisIt and finite-element codes write them. Data arrays may be ASCII, base64
// ("binary", with a UInt32 or UInt64 size header) or appended (raw or base64), each
// optionally zlib-compressed (vtkZLibDataCompressor's blocks), of any of VTK's number
// types, little- or big-endian. The XML is parsed by pugixml; raw appended data, which is
// not XML text, is cut off before parsing and read by offset.
//
// unstructured_volume() turns a grid and one of its arrays into an Unstructured volume:
// VTK's linear volume cells as they are, voxels reordered as hexahedra, quadratic cells by
// their corner vertices (the mid-edge nodes refine a cell whose corners are the linear
// one), vectors by their magnitude.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include <pugixml.hpp>
#include <zlib.h>

#include "sciray/error.hpp"
#include "sciray/math/vec.hpp"
#include "sciray/volume/unstructured.hpp"

namespace sciray::io {

/// One named data array: `components` values per tuple, tuple after tuple.
struct VtkArray {
  std::string name;
  int components = 1;
  std::vector<double> values;
  std::size_t tuples() const { return components > 0 ? values.size() / static_cast<std::size_t>(components) : 0; }
};

struct UnstructuredGridFile {
  std::vector<Vec3f> points;
  std::vector<std::int64_t> connectivity;  ///< the cells' point indices, one cell after another
  std::vector<std::int64_t> offsets;       ///< where each cell's points end in `connectivity`
  std::vector<std::uint8_t> types;         ///< VTK cell type per cell
  std::vector<VtkArray> point_arrays, cell_arrays;
  std::string default_point_array, default_cell_array;  ///< the Scalars attribute of PointData / CellData
};

namespace vtk_detail {

struct Context {
  std::string file;
  bool big_endian = false;
  bool header64 = false;
  bool compressed = false;
  std::string_view appended;  ///< the bytes after AppendedData's '_'
  bool appended_base64 = false;

  [[noreturn]] void fail(const std::string& what) const { throw Error(file + ": " + what); }
};

inline std::vector<std::uint8_t> decode_base64(std::string_view text, const Context& c, const std::string& where) {
  std::vector<std::uint8_t> out;
  out.reserve(text.size() * 3 / 4);
  std::uint32_t bits = 0;
  int count = 0;
  // A group cut short (by padding or the end): 2 or 3 characters carry 1 or 2 bytes.
  const auto flush_partial = [&] {
    if (count == 2) out.push_back(static_cast<std::uint8_t>(bits >> 4));
    if (count == 3) out.push_back(static_cast<std::uint8_t>(bits >> 10)), out.push_back(static_cast<std::uint8_t>(bits >> 2));
    bits = 0, count = 0;
  };
  for (char ch : text) {
    int v;
    if (ch >= 'A' && ch <= 'Z') v = ch - 'A';
    else if (ch >= 'a' && ch <= 'z') v = ch - 'a' + 26;
    else if (ch >= '0' && ch <= '9') v = ch - '0' + 52;
    else if (ch == '+') v = 62;
    else if (ch == '/') v = 63;
    else if (ch == '=') {  // padding ends a block; another may follow (VTK encodes headers apart)
      flush_partial();
      continue;
    } else if (ch == ' ' || ch == '\n' || ch == '\r' || ch == '\t') {
      continue;
    } else {
      c.fail(where + ": '" + std::string(1, ch) + "' is not base64");
    }
    bits = bits << 6 | static_cast<std::uint32_t>(v);
    if (++count == 4) {
      out.push_back(static_cast<std::uint8_t>(bits >> 16));
      out.push_back(static_cast<std::uint8_t>(bits >> 8));
      out.push_back(static_cast<std::uint8_t>(bits));
      bits = 0, count = 0;
    }
  }
  flush_partial();
  return out;
}

/// The number of bytes in base64 text of `n` bytes (padded).
inline std::size_t base64_length(std::size_t n) { return (n + 2) / 3 * 4; }

inline std::uint64_t read_header_word(const std::uint8_t* p, const Context& c) {
  std::uint64_t v = 0;
  const int size = c.header64 ? 8 : 4;
  for (int k = 0; k < size; ++k) {
    const int byte = c.big_endian ? size - 1 - k : k;
    v |= static_cast<std::uint64_t>(p[byte]) << (8 * k);
  }
  return v;
}

/// The array's bytes from a block of header + payload: `bytes` starts at the header. For
/// base64 text, `base64` decodes as needed (a compressed block's header and payload are
/// encoded separately).
inline std::vector<std::uint8_t> payload(std::string_view block, bool base64, const Context& c, const std::string& where) {
  const std::size_t word = c.header64 ? 8 : 4;
  const auto need = [&](std::size_t have, std::size_t want) {
    if (have < want) c.fail(where + ": the data block is truncated (" + std::to_string(have) + " bytes, " +
                            std::to_string(want) + " needed)");
  };
  if (!c.compressed) {
    std::vector<std::uint8_t> raw;
    if (base64) {
      raw = decode_base64(block, c, where);
    } else {
      need(block.size(), word);
      const std::uint64_t n = read_header_word(reinterpret_cast<const std::uint8_t*>(block.data()), c);
      need(block.size() - word, n);
      const auto* begin = reinterpret_cast<const std::uint8_t*>(block.data()) + word;
      return {begin, begin + n};
    }
    need(raw.size(), word);
    const std::uint64_t n = read_header_word(raw.data(), c);
    need(raw.size() - word, n);
    return {raw.begin() + static_cast<std::ptrdiff_t>(word), raw.begin() + static_cast<std::ptrdiff_t>(word + n)};
  }
  // Compressed: [blocks, block size, last block size, compressed size of each block], then the blocks.
  // A block count the data cannot hold is refused before (3 + blocks) * word can overflow.
  const auto check_blocks = [&](std::uint64_t blocks) {
    if (blocks > block.size() / word)
      c.fail(where + ": the data block is truncated (its header counts " + std::to_string(blocks) +
             " zlib blocks, more than its " + std::to_string(block.size()) + " bytes hold)");
  };
  std::vector<std::uint8_t> header, data;
  std::size_t header_text = 0;
  if (base64) {
    const std::vector<std::uint8_t> first = decode_base64(block.substr(0, std::min(block.size(), base64_length(3 * word))), c, where);
    need(first.size(), 3 * word);
    const std::uint64_t blocks = read_header_word(first.data(), c);
    check_blocks(blocks);
    header_text = base64_length((3 + blocks) * word);
    need(block.size(), header_text);
    header = decode_base64(block.substr(0, header_text), c, where);
  } else {
    need(block.size(), 3 * word);
    const std::uint64_t blocks = read_header_word(reinterpret_cast<const std::uint8_t*>(block.data()), c);
    check_blocks(blocks);
    need(block.size(), (3 + blocks) * word);
    header.assign(block.begin(), block.begin() + static_cast<std::ptrdiff_t>((3 + blocks) * word));
  }
  const std::uint64_t blocks = read_header_word(header.data(), c);
  const std::uint64_t block_size = read_header_word(header.data() + word, c);
  const std::uint64_t last_size = read_header_word(header.data() + 2 * word, c);
  need(header.size(), (3 + blocks) * word);
  std::uint64_t compressed_total = 0;
  for (std::uint64_t b = 0; b < blocks; ++b) {
    const std::uint64_t size = read_header_word(header.data() + (3 + b) * word, c);
    if (size > std::numeric_limits<std::uint64_t>::max() - compressed_total)  // a sum that wraps would pass `need`
      c.fail(where + ": the data block is truncated (its zlib blocks' sizes add up to more than 64 bits hold)");
    compressed_total += size;
  }
  if (base64) {
    data = decode_base64(block.substr(header_text), c, where);
  } else {
    const std::size_t start = static_cast<std::size_t>((3 + blocks) * word);
    need(block.size() - start, compressed_total);
    data.assign(block.begin() + static_cast<std::ptrdiff_t>(start),
                block.begin() + static_cast<std::ptrdiff_t>(start + compressed_total));
  }
  need(data.size(), compressed_total);
  std::vector<std::uint8_t> out;
  std::uint64_t at = 0;
  for (std::uint64_t b = 0; b < blocks; ++b) {
    const std::uint64_t size = read_header_word(header.data() + (3 + b) * word, c);
    const std::uint64_t expected = b + 1 == blocks && last_size != 0 ? last_size : block_size;
    // zlib expands at most 1032 times: a header that says more is corrupt (and would
    // make us allocate what it says).
    if (expected > 1032 * size + 64)
      c.fail(where + ": zlib block " + std::to_string(b) + " says " + std::to_string(size) +
             " compressed bytes hold " + std::to_string(expected) + ", more than zlib can expand them to");
    const std::size_t from = out.size();
    out.resize(from + expected);
    uLongf length = static_cast<uLongf>(expected);
    if (uncompress(out.data() + from, &length, data.data() + at, static_cast<uLong>(size)) != Z_OK || length != expected)
      c.fail(where + ": zlib block " + std::to_string(b) + " of " + std::to_string(blocks) + " does not decompress");
    at += size;
  }
  return out;
}

/// `x` as an index or count; -1 (which every range check refuses) when it is not finite or
/// beyond ±2^62, where the conversion would be undefined.
inline std::int64_t whole_number(double x) {
  return x >= -0x1p62 && x <= 0x1p62 ? static_cast<std::int64_t>(x) : -1;
}

/// The size in bytes of VTK number type `type`, or 0 for one that is not.
inline int type_size(const std::string& type) {
  if (type == "Int8" || type == "UInt8") return 1;
  if (type == "Int16" || type == "UInt16") return 2;
  if (type == "Int32" || type == "UInt32" || type == "Float32") return 4;
  if (type == "Int64" || type == "UInt64" || type == "Float64") return 8;
  return 0;
}

inline double number_at(const std::uint8_t* p, const std::string& type, bool big_endian) {
  std::uint8_t bytes[8];
  const int size = type_size(type);
  for (int k = 0; k < size; ++k) bytes[k] = p[big_endian ? size - 1 - k : k];
  const auto as = [&](auto v) {
    std::memcpy(&v, bytes, sizeof v);
    return static_cast<double>(v);
  };
  if (type == "Int8") return as(std::int8_t{});
  if (type == "UInt8") return as(std::uint8_t{});
  if (type == "Int16") return as(std::int16_t{});
  if (type == "UInt16") return as(std::uint16_t{});
  if (type == "Int32") return as(std::int32_t{});
  if (type == "UInt32") return as(std::uint32_t{});
  if (type == "Int64") return as(std::int64_t{});
  if (type == "UInt64") return as(std::uint64_t{});
  if (type == "Float32") return as(float{});
  return as(double{});
}

/// The bytes of a DataArray element whose `format` is "binary" or "appended" (decoded,
/// decompressed, still in the file's byte order); `where` names it in messages.
inline std::vector<std::uint8_t> encoded_bytes(const pugi::xml_node& node, const std::string& format, const Context& c,
                                               const std::string& where) {
  if (format == "binary") {
    std::string_view text = node.child_value();
    text.remove_prefix(std::min(text.find_first_not_of(" \t\r\n"), text.size()));
    return payload(text, true, c, where);
  }
  if (format == "appended") {
    const std::uint64_t offset = node.attribute("offset").as_ullong();
    if (offset >= c.appended.size())
      c.fail(where + ": appended offset " + std::to_string(offset) + " is past the appended data's " +
             std::to_string(c.appended.size()) + " bytes");
    return payload(c.appended.substr(static_cast<std::size_t>(offset)), c.appended_base64, c, where);
  }
  c.fail(where + ": unknown format '" + format + "' (ascii, binary, appended)");
}

/// The values of a DataArray element, `expected` tuples (0: as many as it has).
inline VtkArray read_array(const pugi::xml_node& node, const Context& c, std::size_t expected) {
  VtkArray a;
  a.name = node.attribute("Name").as_string();
  a.components = node.attribute("NumberOfComponents").as_int(1);
  const std::string type = node.attribute("type").as_string();
  const std::string format = node.attribute("format").as_string("ascii");
  const std::string where = "DataArray '" + a.name + "'";
  if (a.components < 1) c.fail(where + ": NumberOfComponents must be at least 1");
  if (type_size(type) == 0) c.fail(where + ": unknown type '" + type + "'");
  if (format == "ascii") {
    std::istringstream in(node.child_value());
    double v;
    while (in >> v) a.values.push_back(v);
    if (!in.eof()) c.fail(where + ": ASCII data has something that is not a number");
  } else {
    const std::vector<std::uint8_t> bytes = encoded_bytes(node, format, c, where);
    const int size = type_size(type);
    if (bytes.size() % static_cast<std::size_t>(size) != 0)
      c.fail(where + ": " + std::to_string(bytes.size()) + " bytes are not a whole number of " + type + " values");
    a.values.resize(bytes.size() / static_cast<std::size_t>(size));
    for (std::size_t i = 0; i < a.values.size(); ++i) a.values[i] = number_at(bytes.data() + i * size, type, c.big_endian);
  }
  if (a.values.size() % static_cast<std::size_t>(a.components) != 0)
    c.fail(where + ": " + std::to_string(a.values.size()) + " values are not whole tuples of " +
           std::to_string(a.components));
  if (expected != 0 && a.tuples() != expected)
    c.fail(where + ": has " + std::to_string(a.tuples()) + " tuples, " + std::to_string(expected) + " expected");
  return a;
}

/// A VTK XML file that must be of `type` (UnstructuredGrid, ImageData, PolyData), parsed,
/// with the Context its arrays are read in. Raw appended data, which is not XML, is cut
/// off before parsing and read by offset; `c.appended` points into `text`, so an XmlFile
/// stays where it was made.
struct XmlFile {
  std::string text;
  pugi::xml_document doc;
  Context c;
  pugi::xml_node root;  ///< the VTKFile element

  XmlFile(const std::string& path, const std::string& type) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(path + ": cannot open file");
    text.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    c.file = path;
    std::string xml = text;
    if (const std::size_t tag = text.find("<AppendedData"); tag != std::string::npos) {
      const std::size_t close = text.find('>', tag);
      const std::size_t underscore = close == std::string::npos ? close : text.find('_', close);
      if (underscore == std::string::npos) c.fail("AppendedData has no '_' before its data");
      c.appended_base64 = text.substr(tag, close - tag).find("encoding=\"base64\"") != std::string::npos;
      std::size_t end = text.rfind("</AppendedData>");
      if (end == std::string::npos || end < underscore) end = text.size();
      c.appended = std::string_view(text).substr(underscore + 1, end - underscore - 1);
      xml = text.substr(0, tag) + "</VTKFile>";
    }
    const pugi::xml_parse_result parsed = doc.load_string(xml.c_str());
    if (!parsed) c.fail(std::string("not valid XML: ") + parsed.description() + " at byte " + std::to_string(parsed.offset));
    root = doc.child("VTKFile");
    if (!root) c.fail("not a VTK XML file (no VTKFile element)");
    if (std::string(root.attribute("type").as_string()) != type)
      c.fail("a VTK file of type '" + std::string(root.attribute("type").as_string()) + "', not " + type);
    c.big_endian = std::string(root.attribute("byte_order").as_string("LittleEndian")) == "BigEndian";
    c.header64 = std::string(root.attribute("header_type").as_string("UInt32")) == "UInt64";
    const std::string compressor = root.attribute("compressor").as_string();
    c.compressed = !compressor.empty();
    if (c.compressed && compressor != "vtkZLibDataCompressor")
      c.fail("compressor '" + compressor + "' is not supported (vtkZLibDataCompressor is)");
  }
  XmlFile(const XmlFile&) = delete;
  XmlFile& operator=(const XmlFile&) = delete;
};

/// Refuses points (x,y,z after x,y,z) with a NaN or infinite coordinate, or one beyond
/// float's range (which would become infinite), naming the first by its index (`base` +
/// its place) in the array `name`.
inline void check_finite_points(const std::vector<double>& xyz, const char* name, std::size_t base, const Context& c) {
  const auto fits = [](double v) { return std::abs(v) <= std::numeric_limits<float>::max(); };
  for (std::size_t i = 0; i + 2 < xyz.size(); i += 3)
    if (!fits(xyz[i]) || !fits(xyz[i + 1]) || !fits(xyz[i + 2])) {
      std::ostringstream point;
      point << '(' << xyz[i] << ", " << xyz[i + 1] << ", " << xyz[i + 2] << ')';
      c.fail(std::string(name) + ": point " + std::to_string(base + i / 3) + " is " + point.str() +
             ", not finite as a float");
    }
}

/// Refuses a cell list's entry that is not the index of one of `points` points; `entry`
/// names the list's entries in the message.
inline void check_point_indices(const std::vector<std::int64_t>& connectivity, std::size_t points,
                                const std::string& entry, const Context& c) {
  for (std::size_t i = 0; i < connectivity.size(); ++i)
    if (connectivity[i] < 0 || connectivity[i] >= static_cast<std::int64_t>(points))
      c.fail(entry + " " + std::to_string(i) + " refers to point " + std::to_string(connectivity[i]) +
             ", but there are " + std::to_string(points) + " points");
}

}  // namespace vtk_detail

/// Reads a .vtu file (its first piece).
inline UnstructuredGridFile read_vtu(const std::string& path) {
  using namespace vtk_detail;
  const XmlFile file(path, "UnstructuredGrid");
  const Context& c = file.c;
  const pugi::xml_node piece = file.root.child("UnstructuredGrid").child("Piece");
  if (!piece) c.fail("no UnstructuredGrid Piece");
  const std::size_t points = piece.attribute("NumberOfPoints").as_ullong();
  const std::size_t cells = piece.attribute("NumberOfCells").as_ullong();

  UnstructuredGridFile out;
  const VtkArray p = read_array(piece.child("Points").child("DataArray"), c, points);
  if (p.components != 3) c.fail("Points must have 3 components, got " + std::to_string(p.components));
  check_finite_points(p.values, "Points", 0, c);
  out.points.resize(points);
  for (std::size_t i = 0; i < points; ++i)
    out.points[i] = {static_cast<float>(p.values[3 * i]), static_cast<float>(p.values[3 * i + 1]),
                     static_cast<float>(p.values[3 * i + 2])};
  for (const pugi::xml_node a : piece.child("Cells").children("DataArray")) {
    const std::string name = a.attribute("Name").as_string();
    if (name != "connectivity" && name != "offsets" && name != "types") continue;
    const VtkArray v = read_array(a, c, name == "connectivity" ? 0 : cells);
    // Checked before they are converted: a value beyond the integer type is undefined behaviour.
    const auto refuse = [&](std::size_t i, double value, const std::string& what) {
      std::ostringstream text;
      text << value;
      c.fail("Cells '" + name + "' value " + std::to_string(i) + " is " + text.str() + ", not " + what);
    };
    if (name == "types") {
      for (std::size_t i = 0; i < v.values.size(); ++i) {
        const double type = v.values[i];
        if (!(type >= 0 && type <= 255) || type != std::floor(type))
          refuse(i, type, "a VTK cell type (an integer from 0 to 255)");
        out.types.push_back(static_cast<std::uint8_t>(type));
      }
    } else {
      auto& target = name == "connectivity" ? out.connectivity : out.offsets;
      for (std::size_t i = 0; i < v.values.size(); ++i) {
        const std::int64_t value = whole_number(v.values[i]);
        if (value < 0 || static_cast<double>(value) != v.values[i])
          refuse(i, v.values[i], "an index (an integer from 0 to 2^62)");
        target.push_back(value);
      }
    }
  }
  if (out.offsets.size() != cells || out.types.size() != cells)
    c.fail("Cells needs 'offsets' and 'types' arrays of " + std::to_string(cells) + " entries");
  std::int64_t previous = 0;
  for (std::size_t i = 0; i < cells; ++i) {
    if (out.offsets[i] < previous || out.offsets[i] > static_cast<std::int64_t>(out.connectivity.size()))
      c.fail("cell " + std::to_string(i) + ": offset " + std::to_string(out.offsets[i]) + " is outside [" +
             std::to_string(previous) + ", " + std::to_string(out.connectivity.size()) + "]");
    previous = out.offsets[i];
  }
  check_point_indices(out.connectivity, points, "Cells 'connectivity' value", c);
  for (const char* kind : {"PointData", "CellData"}) {
    const pugi::xml_node data = piece.child(kind);
    const bool point = std::string(kind) == "PointData";
    (point ? out.default_point_array : out.default_cell_array) = data.attribute("Scalars").as_string();
    for (const pugi::xml_node a : data.children("DataArray"))
      (point ? out.point_arrays : out.cell_arrays).push_back(read_array(a, c, point ? points : cells));
  }
  return out;
}

/// The unstructured volume of `grid` with the values of array `field` (a point or a cell
/// array; empty: the Scalars array of the point data, else of the cell data, else the
/// first array), vectors by their magnitude. `file` names the grid in messages.
inline UnstructuredData unstructured_volume(const UnstructuredGridFile& grid, const std::string& field,
                                            const std::string& file) {
  const auto fail = [&](const std::string& what) { throw Error(file + ": " + what); };
  const VtkArray* chosen = nullptr;
  bool per_cell = false;
  const auto find = [&](const std::vector<VtkArray>& arrays, const std::string& name) -> const VtkArray* {
    for (const VtkArray& a : arrays)
      if (a.name == name) return &a;
    return nullptr;
  };
  std::string want = field;
  if (want.empty()) want = !grid.default_point_array.empty() ? grid.default_point_array : grid.default_cell_array;
  if (!want.empty()) {
    chosen = find(grid.point_arrays, want);
    if (!chosen) chosen = find(grid.cell_arrays, want), per_cell = chosen != nullptr;
  } else if (!grid.point_arrays.empty()) {
    chosen = &grid.point_arrays.front();
  } else if (!grid.cell_arrays.empty()) {
    chosen = &grid.cell_arrays.front(), per_cell = true;
  }
  if (!chosen) {
    std::string names;
    for (const auto* arrays : {&grid.point_arrays, &grid.cell_arrays})
      for (const VtkArray& a : *arrays) names += (names.empty() ? "" : ", ") + ("'" + a.name + "'");
    fail(want.empty() ? std::string("has no point or cell array to render")
                      : "has no array '" + want + "' (its arrays: " + (names.empty() ? "none" : names) + ")");
  }
  UnstructuredData d;
  d.positions = grid.points;
  std::vector<float>& values = per_cell ? d.cell_values : d.vertex_values;
  for (std::size_t t = 0; t < chosen->tuples(); ++t) {
    double sum = 0;
    for (int k = 0; k < chosen->components; ++k) {
      const double v = chosen->values[t * static_cast<std::size_t>(chosen->components) + static_cast<std::size_t>(k)];
      sum += chosen->components == 1 ? v : v * v;
    }
    values.push_back(static_cast<float>(chosen->components == 1 ? sum : std::sqrt(sum)));
  }
  for (std::size_t cell = 0; cell < grid.types.size(); ++cell) {
    const std::int64_t begin = cell == 0 ? 0 : grid.offsets[cell - 1], end = grid.offsets[cell];
    const int vtk_type = grid.types[cell];
    // VTK's volume cells: the linear type each is, and how many of its first points are corners.
    CellType type;
    int corners;
    switch (vtk_type) {
      case 10: case 24: type = CellType::tetrahedron, corners = 4; break;  // tetra, quadratic tetra
      case 11: case 12: case 25: case 29: type = CellType::hexahedron, corners = 8; break;  // voxel, hexahedra
      case 13: case 26: type = CellType::wedge, corners = 6; break;  // wedge, quadratic wedge
      case 14: case 27: type = CellType::pyramid, corners = 5; break;  // pyramid, quadratic pyramid
      default:  // thrown here, not by `fail`, so compilers see that type and corners are always set
        throw Error(file + ": cell " + std::to_string(cell) + " has VTK type " + std::to_string(vtk_type) +
                    ", which is not a volume cell (tetrahedra, voxels, hexahedra, wedges, pyramids and their quadratic "
                    "forms are)");
    }
    if (end - begin < corners)
      fail("cell " + std::to_string(cell) + " of VTK type " + std::to_string(vtk_type) + " has " +
           std::to_string(end - begin) + " points, " + std::to_string(corners) + " expected at least");
    d.cell_index.push_back(d.index.size());
    d.cell_type.push_back(static_cast<std::uint8_t>(type));
    static constexpr int voxel_order[8] = {0, 1, 3, 2, 4, 5, 7, 6};  // a voxel's points are x fastest
    for (int k = 0; k < corners; ++k) {
      const std::int64_t at = grid.connectivity[static_cast<std::size_t>(begin + (vtk_type == 11 ? voxel_order[k] : k))];
      if (at < 0) fail("cell " + std::to_string(cell) + " refers to point " + std::to_string(at));
      d.index.push_back(static_cast<std::uint64_t>(at));
    }
  }
  return d;
}

}  // namespace sciray::io
