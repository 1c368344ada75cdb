#pragma once
// The PLY format, as every PLY reader here needs it: the header (elements, their scalar
// and list properties, the format), and sources of values that walk the data in ascii or
// in binary of either byte order, skipping what a reader does not want. Every error names
// the file and, where it applies, the element, entry, property and line (ascii) or byte
// offset. The mesh reader (ply.hpp) builds on it.
#include <algorithm>
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

namespace sciray::io::ply_detail {

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

/// A file's bytes, read whole.
struct FileBytes {
  std::unique_ptr<std::byte[]> data;
  std::size_t size = 0;
  std::span<const std::byte> span() const { return {data.get(), size}; }
};

/// Reads `path` whole into a fresh (huge-page) buffer; errors name the file as `name`.
inline FileBytes read_whole_file(const std::filesystem::path& path, const std::string& name) {
  std::ifstream file(path, std::ios::binary | std::ios::ate);
  if (!file) throw Error(name + ": cannot open the file");
  const std::streamoff size = file.tellg();
  if (size < 0) throw Error(name + ": cannot read the file");
  // Uninitialised: zeroing hundreds of megabytes only to read over them costs time.
  FileBytes bytes{std::make_unique_for_overwrite<std::byte[]>(static_cast<std::size_t>(size)),
                  static_cast<std::size_t>(size)};
  advise_huge_pages(bytes.data.get(), bytes.size);
  file.seekg(0);
  if (!file.read(reinterpret_cast<char*>(bytes.data.get()), size)) throw Error(name + ": cannot read the file");
  return bytes;
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

}  // namespace sciray::io::ply_detail
