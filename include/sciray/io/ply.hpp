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

#if defined(__linux__)
#include <sys/mman.h>
#endif

#include "sciray/error.hpp"
#include "sciray/geometry/mesh_data.hpp"

namespace sciray::io {

namespace ply_detail {

/// Asks Linux to back a fresh buffer with transparent huge pages before it is first
/// touched: on 4 KiB pages the page faults of a 20M-triangle load cost more than parsing it.
inline void advise_huge_pages([[maybe_unused]] const void* data, [[maybe_unused]] std::size_t bytes) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  constexpr std::uintptr_t huge_page = std::uintptr_t{2} << 20;
  const auto start = reinterpret_cast<std::uintptr_t>(data);
  const std::uintptr_t first = (start + huge_page - 1) & ~(huge_page - 1);
  const std::uintptr_t last = (start + bytes) & ~(huge_page - 1);
  if (last > first) madvise(reinterpret_cast<void*>(first), last - first, MADV_HUGEPAGE);  // only a hint
#endif
}

template <class T>
void reserve_huge(PaddedVector<T>& vector, std::size_t count) {
  vector.reserve(count);
  advise_huge_pages(vector.data(), vector.capacity() * sizeof(T));
}

enum class ScalarType : std::uint8_t { int8, uint8, int16, uint16, int32, uint32, float32, float64 };

inline std::size_t size_of(ScalarType type) {
  static constexpr std::size_t sizes[] = {1, 1, 2, 2, 4, 4, 4, 8};
  return sizes[static_cast<int>(type)];
}

inline std::string_view name_of(ScalarType type) {
  static constexpr std::string_view names[] = {"int8",  "uint8",  "int16",   "uint16",
                                               "int32", "uint32", "float32", "float64"};
  return names[static_cast<int>(type)];
}

inline bool is_integer(ScalarType type) { return type != ScalarType::float32 && type != ScalarType::float64; }

inline std::optional<ScalarType> parse_type_name(std::string_view name) {
  struct Alias {
    std::string_view name;
    ScalarType type;
  };
  static constexpr Alias aliases[] = {
      {"char", ScalarType::int8},      {"int8", ScalarType::int8},       {"uchar", ScalarType::uint8},
      {"uint8", ScalarType::uint8},    {"short", ScalarType::int16},     {"int16", ScalarType::int16},
      {"ushort", ScalarType::uint16},  {"uint16", ScalarType::uint16},   {"int", ScalarType::int32},
      {"int32", ScalarType::int32},    {"uint", ScalarType::uint32},     {"uint32", ScalarType::uint32},
      {"float", ScalarType::float32},  {"float32", ScalarType::float32}, {"double", ScalarType::float64},
      {"float64", ScalarType::float64}};
  for (const Alias& alias : aliases)
    if (alias.name == name) return alias.type;
  return std::nullopt;
}

struct Property {
  std::string name;
  ScalarType type = ScalarType::float32;      ///< the value type, or a list's item type
  std::optional<ScalarType> list_count_type;  ///< set for list properties
  bool is_list() const { return list_count_type.has_value(); }
};

struct Element {
  std::string name;
  std::uint64_t count = 0;
  std::vector<Property> properties;
};

enum class Format { ascii, binary_little_endian, binary_big_endian };

struct Header {
  Format format = Format::ascii;
  std::vector<Element> elements;
  std::size_t data_offset = 0;  ///< first byte after the end_header line
  std::size_t data_line = 0;    ///< number of the first line after end_header
};

[[noreturn]] inline void fail(std::string_view file, std::string_view message) {
  throw Error(std::string(file) + ": " + std::string(message));
}

inline bool is_space(char c) {
  return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f';
}

inline std::vector<std::string_view> split_words(std::string_view line) {
  std::vector<std::string_view> words;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && is_space(line[i])) ++i;
    const std::size_t start = i;
    while (i < line.size() && !is_space(line[i])) ++i;
    if (i > start) words.push_back(line.substr(start, i - start));
  }
  return words;
}

inline Header parse_header(std::span<const std::byte> bytes, std::string_view file) {
  const char* const begin = reinterpret_cast<const char*>(bytes.data());
  const char* const end = begin + bytes.size();
  const char* cursor = begin;
  std::size_t line_number = 0;
  auto next_line = [&]() -> std::optional<std::string_view> {
    if (cursor == end) return std::nullopt;
    const auto* newline =
        static_cast<const char*>(std::memchr(cursor, '\n', static_cast<std::size_t>(end - cursor)));
    const char* line_end = newline ? newline : end;
    std::string_view line(cursor, static_cast<std::size_t>(line_end - cursor));
    cursor = newline ? newline + 1 : end;
    ++line_number;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    return line;
  };
  const auto first = next_line();
  if (!first || *first != "ply") fail(file, "not a PLY file: it does not start with the line 'ply'");

  Header header;
  bool has_format = false;
  while (const auto line = next_line()) {
    const std::vector<std::string_view> words = split_words(*line);
    if (words.empty()) continue;
    const std::string_view keyword = words[0];
    const std::string where = "header line " + std::to_string(line_number) + ": ";
    if (keyword == "comment" || keyword == "obj_info") continue;
    if (keyword == "end_header") {
      if (!has_format) fail(file, "the header has no 'format' line");
      header.data_offset = static_cast<std::size_t>(cursor - begin);
      header.data_line = line_number + 1;
      return header;
    }
    if (keyword == "format") {
      if (words.size() != 3) fail(file, where + "expected 'format <type> 1.0'");
      if (words[1] == "ascii") header.format = Format::ascii;
      else if (words[1] == "binary_little_endian") header.format = Format::binary_little_endian;
      else if (words[1] == "binary_big_endian") header.format = Format::binary_big_endian;
      else
        fail(file, where + "unknown format '" + std::string(words[1]) +
                       "' (expected ascii, binary_little_endian or binary_big_endian)");
      if (words[2] != "1.0" && words[2] != "1")
        fail(file, where + "unsupported PLY version '" + std::string(words[2]) + "' (expected 1.0)");
      has_format = true;
    } else if (keyword == "element") {
      if (words.size() != 3) fail(file, where + "expected 'element <name> <count>'");
      Element element;
      element.name = words[1];
      const std::string_view count = words[2];
      const auto [end_of_count, error] =
          std::from_chars(count.data(), count.data() + count.size(), element.count);
      if (error != std::errc() || end_of_count != count.data() + count.size())
        fail(file, where + "element '" + element.name + "' has count '" + std::string(count) +
                       "', which is not a non-negative 64-bit integer");
      header.elements.push_back(std::move(element));
    } else if (keyword == "property") {
      if (header.elements.empty()) fail(file, where + "'property' before any 'element'");
      Element& element = header.elements.back();
      Property property;
      const bool is_list = words.size() >= 2 && words[1] == "list";
      if (words.size() != (is_list ? 5u : 3u))
        fail(file, where + "expected 'property <type> <name>' or 'property list <count type> <type> <name>'");
      property.name = words.back();
      const std::string_view type_name = words[words.size() - 2];
      const auto type = parse_type_name(type_name);
      if (!type)
        fail(file, where + "unknown type '" + std::string(type_name) + "' of property '" + property.name +
                       "' of element '" + element.name + "'");
      property.type = *type;
      if (is_list) {
        const auto count_type = parse_type_name(words[2]);
        if (!count_type || !is_integer(*count_type))
          fail(file, where + "list property '" + property.name + "' of element '" + element.name +
                         "' has count type '" + std::string(words[2]) + "'; expected an integer type");
        property.list_count_type = *count_type;
      }
      element.properties.push_back(std::move(property));
    } else {
      fail(file, where + "unknown header keyword '" + std::string(keyword) + "'");
    }
  }
  fail(file, "the header has no 'end_header' line");
}

/// Rejects counts the data cannot hold before anything is allocated from them: every
/// binary entry needs its scalars and list counts, every ascii value a digit and a separator.
inline void check_counts_fit(const Header& header, std::size_t data_bytes, std::string_view file) {
  const bool ascii = header.format == Format::ascii;
  std::uint64_t remaining = ascii ? data_bytes + 1 : data_bytes;  // the last ascii value needs no separator
  for (const Element& element : header.elements) {
    std::uint64_t min_entry_bytes = 0;
    for (const Property& property : element.properties)
      min_entry_bytes += ascii ? 2 : size_of(property.list_count_type.value_or(property.type));
    if (min_entry_bytes == 0) continue;
    if (element.count > remaining / min_entry_bytes)
      fail(file, "element '" + element.name + "' declares " + std::to_string(element.count) +
                     " entries of at least " + std::to_string(min_entry_bytes) + " bytes each, but only " +
                     std::to_string(data_bytes) +
                     " bytes of data follow the header: the file is truncated or the count is wrong");
    remaining -= element.count * min_entry_bytes;
  }
}

template <class T>
using UnsignedOfSize =
    std::conditional_t<sizeof(T) == 1, std::uint8_t,
                       std::conditional_t<sizeof(T) == 2, std::uint16_t,
                                          std::conditional_t<sizeof(T) == 4, std::uint32_t, std::uint64_t>>>;

inline std::uint8_t byteswap(std::uint8_t x) { return x; }
inline std::uint16_t byteswap(std::uint16_t x) { return static_cast<std::uint16_t>((x >> 8) | (x << 8)); }
inline std::uint32_t byteswap(std::uint32_t x) {
  return (x >> 24) | ((x >> 8) & 0xff00u) | ((x << 8) & 0xff0000u) | (x << 24);
}
inline std::uint64_t byteswap(std::uint64_t x) {
  return (std::uint64_t{byteswap(static_cast<std::uint32_t>(x))} << 32) |
         byteswap(static_cast<std::uint32_t>(x >> 32));
}

/// Loads a T stored at `p` (any alignment), reversing its bytes when the file's byte
/// order differs from the machine's.
template <class T, bool Swap>
T load(const std::byte* p) {
  UnsignedOfSize<T> bits;
  std::memcpy(&bits, p, sizeof bits);
  if constexpr (Swap) bits = byteswap(bits);
  return std::bit_cast<T>(bits);
}

template <bool Swap>
double load_scalar(const std::byte* p, ScalarType type) {
  switch (type) {
    case ScalarType::int8: return load<std::int8_t, Swap>(p);
    case ScalarType::uint8: return load<std::uint8_t, Swap>(p);
    case ScalarType::int16: return load<std::int16_t, Swap>(p);
    case ScalarType::uint16: return load<std::uint16_t, Swap>(p);
    case ScalarType::int32: return load<std::int32_t, Swap>(p);
    case ScalarType::uint32: return load<std::uint32_t, Swap>(p);
    case ScalarType::float32: return load<float, Swap>(p);
    case ScalarType::float64: return load<double, Swap>(p);
  }
  return 0;
}

/// Where a value is, for error messages: entry `entry` of `element`, in `property`.
struct Where {
  const Element* element = nullptr;
  std::uint64_t entry = 0;
  const Property* property = nullptr;

  std::string describe() const {
    std::string text = element->name + " " + std::to_string(entry);
    if (property) text += ", property '" + property->name + "'";
    return text;
  }
};

template <bool Swap>
class BinarySource {
public:
  static constexpr bool is_binary = true;
  static constexpr bool swaps = Swap;

  BinarySource(std::span<const std::byte> bytes, std::size_t data_offset, std::string_view file)
      : begin_(bytes.data()), cursor_(begin_ + data_offset), end_(begin_ + bytes.size()), file_(file) {}

  [[noreturn]] void fail_at(const std::byte* position, const Where& where, std::string_view message) const {
    ply_detail::fail(file_, where.describe() + ", byte offset " + std::to_string(position - begin_) + ": " +
                                std::string(message));
  }
  [[noreturn]] void fail(const Where& where, std::string_view message) const {
    fail_at(cursor_, where, message);
  }

  void need(std::uint64_t bytes, const Where& where) const {
    if (bytes > static_cast<std::uint64_t>(end_ - cursor_)) fail_truncated(cursor_, bytes, where);
  }
  [[noreturn]] void fail_truncated(const std::byte* position, std::uint64_t bytes, const Where& where) const {
    fail_at(position, where,
            "the file is truncated: " + std::to_string(bytes) + " bytes needed but only " +
                std::to_string(end_ - position) + " left");
  }

  double scalar(ScalarType type, const Where& where) {
    need(size_of(type), where);
    const double value = load_scalar<Swap>(cursor_, type);
    cursor_ += size_of(type);
    return value;
  }
  /// An integer-typed value (every integer PLY type fits a double exactly).
  std::int64_t integer(ScalarType type, const Where& where) {
    return static_cast<std::int64_t>(scalar(type, where));
  }
  void skip_scalar(ScalarType type, const Where& where) {
    need(size_of(type), where);
    cursor_ += size_of(type);
  }
  /// Reads a list's length and checks that its items are all present.
  std::uint64_t list_length(const Property& property, const Where& where) {
    const std::int64_t length = integer(*property.list_count_type, where);
    if (length < 0) fail(where, "negative list length " + std::to_string(length));
    need(static_cast<std::uint64_t>(length) * size_of(property.type), where);
    return static_cast<std::uint64_t>(length);
  }
  void skip_list_items(const Property& property, std::uint64_t length) {
    cursor_ += length * size_of(property.type);
  }

  /// Takes all records of an element without lists, each `entry_size` bytes long.
  const std::byte* take_entries(const Element& element, std::size_t entry_size) {
    // No overflow: check_counts_fit bounded count * entry_size by the data size.
    const std::uint64_t bytes = element.count * entry_size;
    const auto available = static_cast<std::uint64_t>(end_ - cursor_);
    if (bytes > available) {
      const std::uint64_t entry = available / entry_size;
      fail_truncated(cursor_ + entry * entry_size, entry_size, Where{&element, entry, nullptr});
    }
    const std::byte* start = cursor_;
    cursor_ += bytes;
    return start;
  }

  const std::byte* cursor() const { return cursor_; }
  const std::byte* end() const { return end_; }
  void set_cursor(const std::byte* cursor) { cursor_ = cursor; }

private:
  const std::byte* begin_;
  const std::byte* cursor_;
  const std::byte* end_;
  std::string_view file_;
};

class AsciiSource {
public:
  static constexpr bool is_binary = false;

  AsciiSource(std::span<const std::byte> bytes, const Header& header, std::string_view file)
      : cursor_(reinterpret_cast<const char*>(bytes.data()) + header.data_offset),
        end_(reinterpret_cast<const char*>(bytes.data()) + bytes.size()),
        line_(header.data_line),
        file_(file) {}

  [[noreturn]] void fail(const Where& where, std::string_view message) const {
    ply_detail::fail(file_,
                     "line " + std::to_string(line_) + ", " + where.describe() + ": " + std::string(message));
  }

  double scalar(ScalarType type, const Where& where) {
    if (is_integer(type)) return static_cast<double>(integer(type, where));
    std::string_view text = token(where);
    if (text.size() > 1 && text[0] == '+') text.remove_prefix(1);  // from_chars rejects a leading '+'
    if (type == ScalarType::float32) return parse<float>(text, type, where);
    return parse<double>(text, type, where);
  }
  std::int64_t integer(ScalarType type, const Where& where) {
    std::string_view text = token(where);
    if (text.size() > 1 && text[0] == '+') text.remove_prefix(1);
    const auto value = parse<std::int64_t>(text, type, where);
    if (!fits(value, type))
      fail(where, "value " + std::string(text) + " does not fit " + std::string(name_of(type)));
    return value;
  }
  void skip_scalar(ScalarType, const Where& where) { token(where); }
  std::uint64_t list_length(const Property& property, const Where& where) {
    const std::int64_t length = integer(*property.list_count_type, where);
    if (length < 0) fail(where, "negative list length " + std::to_string(length));
    if (static_cast<std::uint64_t>(length) > static_cast<std::uint64_t>(end_ - cursor_))
      fail(where, "the file is truncated: the list has " + std::to_string(length) +
                      " items but the file ends sooner");
    return static_cast<std::uint64_t>(length);
  }

private:
  std::string_view token(const Where& where) {
    while (cursor_ != end_ && is_space(*cursor_)) {
      if (*cursor_ == '\n') ++line_;
      ++cursor_;
    }
    if (cursor_ == end_) fail(where, "the file is truncated: it ends before this value");
    const char* start = cursor_;
    while (cursor_ != end_ && !is_space(*cursor_)) ++cursor_;
    return {start, static_cast<std::size_t>(cursor_ - start)};
  }

  template <class T>
  T parse(std::string_view text, ScalarType type, const Where& where) const {
    T value{};
    const auto [parsed_end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (error != std::errc() || parsed_end != text.data() + text.size())
      fail(where, "cannot parse '" + std::string(text) + "' as " + std::string(name_of(type)));
    return value;
  }

  static bool fits(std::int64_t value, ScalarType type) {
    switch (type) {
      case ScalarType::int8: return value >= -128 && value <= 127;
      case ScalarType::uint8: return value >= 0 && value <= 255;
      case ScalarType::int16: return value >= -32768 && value <= 32767;
      case ScalarType::uint16: return value >= 0 && value <= 65535;
      case ScalarType::int32:
        return value >= std::numeric_limits<std::int32_t>::min() &&
               value <= std::numeric_limits<std::int32_t>::max();
      case ScalarType::uint32: return value >= 0 && value <= std::numeric_limits<std::uint32_t>::max();
      default: return true;
    }
  }

  const char* cursor_;
  const char* end_;
  std::size_t line_;
  std::string_view file_;
};

template <class Source>
void skip_property(Source& source, const Property& property, const Where& where) {
  if (!property.is_list()) return source.skip_scalar(property.type, where);
  const std::uint64_t length = source.list_length(property, where);
  if constexpr (Source::is_binary) {
    source.skip_list_items(property, length);
  } else {
    for (std::uint64_t i = 0; i < length; ++i) source.skip_scalar(property.type, where);
  }
}

/// Record size of an element without list properties.
inline std::optional<std::size_t> fixed_entry_size(const Element& element) {
  std::size_t size = 0;
  for (const Property& property : element.properties) {
    if (property.is_list()) return std::nullopt;
    size += size_of(property.type);
  }
  return size;
}

template <class Source>
void skip_element(Source& source, const Element& element) {
  if (element.properties.empty()) return;
  if constexpr (Source::is_binary) {
    if (const auto entry_size = fixed_entry_size(element)) {
      source.take_entries(element, *entry_size);
      return;
    }
  }
  for (std::uint64_t entry = 0; entry < element.count; ++entry)
    for (const Property& property : element.properties)
      skip_property(source, property, {&element, entry, &property});
}

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
  std::ifstream file(path, std::ios::binary | std::ios::ate);
  if (!file) throw Error(name + ": cannot open the file");
  const std::streamoff size = file.tellg();
  if (size < 0) throw Error(name + ": cannot read the file");
  // Uninitialised: zeroing hundreds of megabytes only to read over them costs time.
  const auto bytes = std::make_unique_for_overwrite<std::byte[]>(static_cast<std::size_t>(size));
  ply_detail::advise_huge_pages(bytes.get(), static_cast<std::size_t>(size));
  file.seekg(0);
  if (!file.read(reinterpret_cast<char*>(bytes.get()), size)) throw Error(name + ": cannot read the file");
  return parse_ply({bytes.get(), static_cast<std::size_t>(size)}, name, options);
}

}  // namespace sciray::io
