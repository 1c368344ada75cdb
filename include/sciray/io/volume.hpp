#pragma once
// Regular-grid volume readers producing the voxels, dims and grid a StructuredRegular
// volume needs:
//  - `.raw` (any extension other than .nrrd/.nhdr): headerless little-endian voxels, x
//    fastest. Dims and voxel type come from VolumeReadOptions, else from a JSON sidecar
//    beside the file (same stem, `.json`: dims, type, spacing, origin, range), else from
//    the file name (`name_XxYxZ_type.raw`). The file size must match exactly.
//  - NRRD (NRRD0001-NRRD0005), attached `.nrrd` or detached `.nhdr` (`data file:` relative
//    to the header): 3-D, raw or gzip encoding, either byte order, `spacings` or axis-aligned
//    `space directions` with `space origin`, `centers`, `line skip` and `byte skip`.
// Sizes are 64-bit throughout (files over 4 GiB work) and the byte count of the dims is
// checked for overflow before anything is allocated. Every error is a sciray::Error naming
// the file and what is wrong with it.
#include <zlib.h>

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
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <system_error>
#include <utility>
#include <vector>

#include "sciray/error.hpp"
#include "sciray/math/vec.hpp"
#include "sciray/volume/structured_regular.hpp"

namespace sciray::io {

/// The voxel types StructuredRegular samples.
enum class VoxelKind : std::uint8_t { uint8, int16, uint16, float32, float64 };

inline std::string_view voxel_kind_name(VoxelKind kind) {
  switch (kind) {
    case VoxelKind::uint8: return "uint8";
    case VoxelKind::int16: return "int16";
    case VoxelKind::uint16: return "uint16";
    case VoxelKind::float32: return "float32";
    case VoxelKind::float64: return "float64";
  }
  return "unknown";
}

inline std::size_t voxel_size(VoxelKind kind) {
  switch (kind) {
    case VoxelKind::uint8: return 1;
    case VoxelKind::int16:
    case VoxelKind::uint16: return 2;
    case VoxelKind::float32: return 4;
    case VoxelKind::float64: return 8;
  }
  return 0;
}

/// Our names (uint8, int16, uint16, float32, float64), the C names (uchar, short, ushort,
/// float, double) and every NRRD spelling of these five types ("unsigned char", "uint8_t",
/// "signed short int", ...); case and runs of blanks do not matter.
inline std::optional<VoxelKind> parse_voxel_kind(std::string_view name) {
  std::string normal;  // lower case, single blanks, trimmed
  for (const char c : name) {
    if (c == ' ' || c == '\t') {
      if (!normal.empty() && normal.back() != ' ') normal.push_back(' ');
    } else {
      normal.push_back(c >= 'A' && c <= 'Z' ? static_cast<char>(c - 'A' + 'a') : c);
    }
  }
  if (!normal.empty() && normal.back() == ' ') normal.pop_back();
  struct Alias {
    std::string_view name;
    VoxelKind kind;
  };
  static constexpr Alias aliases[] = {
      {"uint8", VoxelKind::uint8},
      {"uchar", VoxelKind::uint8},
      {"unsigned char", VoxelKind::uint8},
      {"uint8_t", VoxelKind::uint8},
      {"int16", VoxelKind::int16},
      {"short", VoxelKind::int16},
      {"short int", VoxelKind::int16},
      {"signed short", VoxelKind::int16},
      {"signed short int", VoxelKind::int16},
      {"int16_t", VoxelKind::int16},
      {"uint16", VoxelKind::uint16},
      {"ushort", VoxelKind::uint16},
      {"unsigned short", VoxelKind::uint16},
      {"unsigned short int", VoxelKind::uint16},
      {"uint16_t", VoxelKind::uint16},
      {"float32", VoxelKind::float32},
      {"float", VoxelKind::float32},
      {"float64", VoxelKind::float64},
      {"double", VoxelKind::float64},
  };
  for (const Alias& alias : aliases)
    if (alias.name == normal) return alias.kind;
  return std::nullopt;
}

struct VolumeFile {
  VoxelKind kind = VoxelKind::uint8;
  VolumeDims dims{};
  VolumeGrid grid;  ///< origin/spacing from the sidecar or NRRD header; defaults otherwise
  /// dims product * voxel_size bytes, native byte order, x fastest.
  std::shared_ptr<std::vector<std::byte>> voxels;
  std::optional<std::array<float, 2>> range;  ///< from a sidecar if given
};

struct VolumeReadOptions {
  std::optional<VolumeDims> dims;  ///< raw: overrides the sidecar and the file name; NRRD: must match
  std::optional<VoxelKind> kind;   ///< raw: overrides the sidecar and the file name; NRRD: must match
};

namespace volume_detail {

[[noreturn]] inline void fail(const std::filesystem::path& file, std::string_view message) {
  throw Error(file.string() + ": " + std::string(message));
}

inline std::string dims_text(const VolumeDims& dims) {
  return std::to_string(dims[0]) + "x" + std::to_string(dims[1]) + "x" + std::to_string(dims[2]);
}

inline std::string voxels_text(const VolumeDims& dims, VoxelKind kind) {
  return dims_text(dims) + " " + std::string(voxel_kind_name(kind)) + " voxels";
}

inline constexpr std::string_view kind_list = "uint8, int16, uint16, float32, float64";

/// The bytes `dims` voxels of `kind` take; each dim must be at least 1 and the count must
/// fit in 64 bits.
inline std::uint64_t byte_count(const VolumeDims& dims, VoxelKind kind, const std::filesystem::path& file) {
  for (int k = 0; k < 3; ++k)
    if (dims[k] < 1) fail(file, "dims " + dims_text(dims) + " are invalid: every dim must be at least 1");
  std::uint64_t bytes = voxel_size(kind);
  for (int k = 0; k < 3; ++k) {
    const auto d = static_cast<std::uint64_t>(dims[k]);
    if (bytes > std::numeric_limits<std::uint64_t>::max() / d)
      fail(file, "the byte count of " + voxels_text(dims, kind) + " overflows 64 bits");
    bytes *= d;
  }
  return bytes;
}

/// A buffer of `bytes` bytes, refused when it cannot exist on this machine.
inline std::shared_ptr<std::vector<std::byte>> allocate(std::uint64_t bytes, const std::filesystem::path& file) {
  if (bytes > std::vector<std::byte>().max_size())
    fail(file, "the voxels need " + std::to_string(bytes) + " bytes, more than this machine can address");
  return std::make_shared<std::vector<std::byte>>(static_cast<std::size_t>(bytes));
}

template <class U>
U byteswap(U x) {
  if constexpr (sizeof(U) == 2) {
    return static_cast<U>((x >> 8) | (x << 8));
  } else if constexpr (sizeof(U) == 4) {
    return (x >> 24) | ((x >> 8) & 0xff00u) | ((x << 8) & 0xff0000u) | (x << 24);
  } else {
    return (U{byteswap(static_cast<std::uint32_t>(x))} << 32) | byteswap(static_cast<std::uint32_t>(x >> 32));
  }
}

template <class U>
void swap_all(std::byte* data, std::size_t count) {
  for (std::size_t i = 0; i < count; ++i) {
    U value;
    std::memcpy(&value, data + i * sizeof(U), sizeof(U));
    value = byteswap(value);
    std::memcpy(data + i * sizeof(U), &value, sizeof(U));
  }
}

/// Reverses the byte order of every voxel.
inline void swap_bytes(std::vector<std::byte>& voxels, std::size_t size) {
  const std::size_t count = voxels.size() / size;
  if (size == 2)
    swap_all<std::uint16_t>(voxels.data(), count);
  else if (size == 4)
    swap_all<std::uint32_t>(voxels.data(), count);
  else if (size == 8)
    swap_all<std::uint64_t>(voxels.data(), count);
}

/// Reverses the order of the voxels along `axis`.
inline void flip_axis(std::vector<std::byte>& voxels, const VolumeDims& dims, int axis, std::size_t size) {
  const std::array<std::uint64_t, 3> stride = {size, size * static_cast<std::uint64_t>(dims[0]),
                                               size * static_cast<std::uint64_t>(dims[0] * dims[1])};
  const int a = (axis + 1) % 3, b = (axis + 2) % 3;
  const std::int64_t n = dims[axis];
  for (std::int64_t j = 0; j < dims[b]; ++j)
    for (std::int64_t i = 0; i < dims[a]; ++i) {
      std::byte* line =
          voxels.data() + static_cast<std::uint64_t>(i) * stride[a] + static_cast<std::uint64_t>(j) * stride[b];
      for (std::int64_t k = 0; k < n / 2; ++k)
        std::swap_ranges(line + static_cast<std::uint64_t>(k) * stride[axis],
                         line + static_cast<std::uint64_t>(k) * stride[axis] + size,
                         line + static_cast<std::uint64_t>(n - 1 - k) * stride[axis]);
    }
}

/// Reads `count` bytes from the stream's current position, in pieces so that no single
/// read is larger than a stream's size type allows.
inline void read_exact(std::istream& in, std::byte* out, std::uint64_t count, const std::filesystem::path& file) {
  constexpr std::uint64_t piece = std::uint64_t{1} << 28;
  while (count > 0) {
    const std::uint64_t n = std::min(count, piece);
    if (!in.read(reinterpret_cast<char*>(out), static_cast<std::streamsize>(n)))
      fail(file, "cannot read the file (it ended early or a read failed)");
    out += n;
    count -= n;
  }
}

inline std::uint64_t size_of_file(const std::filesystem::path& file) {
  std::error_code error;
  const auto status = std::filesystem::status(file, error);
  if (error || !std::filesystem::exists(status)) fail(file, "cannot open the file: it does not exist");
  if (std::filesystem::is_directory(status)) fail(file, "cannot open the file: it is a directory");
  const std::uintmax_t size = std::filesystem::file_size(file, error);
  if (error) fail(file, "cannot read the file's size: " + error.message());
  return static_cast<std::uint64_t>(size);
}

inline std::ifstream open_file(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) fail(file, "cannot open the file");
  return in;
}

/// `value` in the fewest digits that read back to it ("1e+300", not 300 digits).
inline std::string shortest(double value) {
  char text[32];
  return {text, std::to_chars(text, text + sizeof text, value).ptr};
}

/// A finite double parsed from the whole of `text`.
inline std::optional<double> parse_double(std::string_view text) {
  if (text.size() > 1 && text[0] == '+') text.remove_prefix(1);
  double value = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc() || end != text.data() + text.size() || !std::isfinite(value)) return std::nullopt;
  return value;
}

inline std::optional<std::int64_t> parse_int(std::string_view text) {
  if (text.size() > 1 && text[0] == '+') text.remove_prefix(1);
  std::int64_t value = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc() || end != text.data() + text.size()) return std::nullopt;
  return value;
}

inline std::vector<std::string_view> split_words(std::string_view text) {
  std::vector<std::string_view> words;
  std::size_t i = 0;
  while (i < text.size()) {
    while (i < text.size() && (text[i] == ' ' || text[i] == '\t')) ++i;
    const std::size_t start = i;
    while (i < text.size() && text[i] != ' ' && text[i] != '\t') ++i;
    if (i > start) words.push_back(text.substr(start, i - start));
  }
  return words;
}

inline std::string_view trim(std::string_view text) {
  while (!text.empty() && (text.front() == ' ' || text.front() == '\t')) text.remove_prefix(1);
  while (!text.empty() && (text.back() == ' ' || text.back() == '\t' || text.back() == '\r')) text.remove_suffix(1);
  return text;
}

// ---------------------------------------------------------------------------------------
// A small JSON reader for the sidecars: objects, arrays, strings, numbers (kept as text so
// that 64-bit integers stay exact), true, false, null.

struct Json {
  enum class Type { null, boolean, number, string, array, object } type = Type::null;
  bool boolean = false;
  std::string text;  ///< a number's digits or a string's value
  std::vector<Json> items;
  // A struct of its own, not std::pair<std::string, Json>: clang with libstdc++ rejects
  // that pair while Json is incomplete (its checks of Json need the pair complete).
  struct Member;
  std::vector<Member> members;

  const Json* find(std::string_view key) const;
};

struct Json::Member {
  std::string name;
  Json value;
};

inline const Json* Json::find(std::string_view key) const {
  for (const auto& [name, value] : members)
    if (name == key) return &value;
  return nullptr;
}

class JsonParser {
public:
  JsonParser(std::string_view text, const std::filesystem::path& file) : text_(text), file_(file) {}

  Json parse_document() {
    Json value = parse_value(0);
    skip_space();
    if (pos_ != text_.size()) error("unexpected text after the JSON value");
    return value;
  }

private:
  [[noreturn]] void error(std::string_view message) const {
    fail(file_, "invalid JSON at byte " + std::to_string(pos_) + ": " + std::string(message));
  }
  void skip_space() {
    while (pos_ < text_.size() &&
           (text_[pos_] == ' ' || text_[pos_] == '\t' || text_[pos_] == '\n' || text_[pos_] == '\r'))
      ++pos_;
  }
  bool take(std::string_view word) {
    if (text_.substr(pos_, word.size()) != word) return false;
    pos_ += word.size();
    return true;
  }
  Json parse_value(int depth) {
    if (depth > 64) error("nested too deeply");
    skip_space();
    if (pos_ == text_.size()) error("the text ends where a value should be");
    Json value;
    const char c = text_[pos_];
    if (c == '{') {
      value.type = Json::Type::object;
      ++pos_;
      skip_space();
      if (take("}")) return value;
      while (true) {
        skip_space();
        if (pos_ == text_.size() || text_[pos_] != '"') error("expected a member name in quotes");
        std::string name = parse_string();
        skip_space();
        if (!take(":")) error("expected ':' after a member name");
        value.members.push_back({std::move(name), parse_value(depth + 1)});
        skip_space();
        if (take("}")) return value;
        if (!take(",")) error("expected ',' or '}' in an object");
      }
    }
    if (c == '[') {
      value.type = Json::Type::array;
      ++pos_;
      skip_space();
      if (take("]")) return value;
      while (true) {
        value.items.push_back(parse_value(depth + 1));
        skip_space();
        if (take("]")) return value;
        if (!take(",")) error("expected ',' or ']' in an array");
      }
    }
    if (c == '"') {
      value.type = Json::Type::string;
      value.text = parse_string();
      return value;
    }
    if (take("true")) {
      value.type = Json::Type::boolean;
      value.boolean = true;
      return value;
    }
    if (take("false")) {
      value.type = Json::Type::boolean;
      return value;
    }
    if (take("null")) return value;
    if (c == '-' || (c >= '0' && c <= '9')) {
      const std::size_t start = pos_;
      if (text_[pos_] == '-') ++pos_;
      const auto digits = [&] {
        const std::size_t first = pos_;
        while (pos_ < text_.size() && text_[pos_] >= '0' && text_[pos_] <= '9') ++pos_;
        if (pos_ == first) error("malformed number");
      };
      digits();
      if (pos_ < text_.size() && text_[pos_] == '.') ++pos_, digits();
      if (pos_ < text_.size() && (text_[pos_] == 'e' || text_[pos_] == 'E')) {
        ++pos_;
        if (pos_ < text_.size() && (text_[pos_] == '+' || text_[pos_] == '-')) ++pos_;
        digits();
      }
      value.type = Json::Type::number;
      value.text = std::string(text_.substr(start, pos_ - start));
      return value;
    }
    error(std::string("unexpected character '") + c + "'");
  }
  std::string parse_string() {
    ++pos_;  // the opening quote
    std::string out;
    while (true) {
      if (pos_ >= text_.size()) error("unterminated string");
      const char c = text_[pos_++];
      if (c == '"') return out;
      if (c != '\\') {
        out.push_back(c);
        continue;
      }
      if (pos_ >= text_.size()) error("unterminated string");
      const char e = text_[pos_++];
      switch (e) {
        case '"': out.push_back('"'); break;
        case '\\': out.push_back('\\'); break;
        case '/': out.push_back('/'); break;
        case 'b': out.push_back('\b'); break;
        case 'f': out.push_back('\f'); break;
        case 'n': out.push_back('\n'); break;
        case 'r': out.push_back('\r'); break;
        case 't': out.push_back('\t'); break;
        case 'u': {
          if (pos_ + 4 > text_.size()) error("short \\u escape");
          unsigned code = 0;
          const auto [end, err] = std::from_chars(text_.data() + pos_, text_.data() + pos_ + 4, code, 16);
          if (err != std::errc() || end != text_.data() + pos_ + 4) error("bad \\u escape");
          pos_ += 4;
          // UTF-8 of the code unit (surrogate pairs are not combined: sidecar text is ASCII).
          if (code < 0x80) {
            out.push_back(static_cast<char>(code));
          } else if (code < 0x800) {
            out.push_back(static_cast<char>(0xc0 | (code >> 6)));
            out.push_back(static_cast<char>(0x80 | (code & 0x3f)));
          } else {
            out.push_back(static_cast<char>(0xe0 | (code >> 12)));
            out.push_back(static_cast<char>(0x80 | ((code >> 6) & 0x3f)));
            out.push_back(static_cast<char>(0x80 | (code & 0x3f)));
          }
          break;
        }
        default: error(std::string("bad escape '\\") + e + "'");
      }
    }
  }

  std::string_view text_;
  const std::filesystem::path& file_;
  std::size_t pos_ = 0;
};

/// What a sidecar says; each field is optional in the file.
struct Sidecar {
  std::optional<VolumeDims> dims;
  std::optional<VoxelKind> kind;
  std::optional<Vec3f> spacing, origin;
  std::optional<std::array<float, 2>> range;
};

template <std::size_t N>
std::array<double, N> json_numbers(const Json* value, std::string_view key, std::string_view what,
                                   const std::filesystem::path& file) {
  std::string problem = "'";  // appended piece by piece: GCC 12 warns falsely (-Wrestrict) on "'" + string
  problem.append(key).append("' must be an array of ").append(std::to_string(N)).append(" ").append(what);
  if (value->type != Json::Type::array || value->items.size() != N) fail(file, problem);
  std::array<double, N> numbers{};
  for (std::size_t i = 0; i < N; ++i) {
    const Json& item = value->items[i];
    const auto number = item.type == Json::Type::number ? parse_double(item.text) : std::nullopt;
    if (!number) fail(file, problem);
    numbers[i] = *number;
  }
  return numbers;
}

inline Sidecar read_sidecar(const std::filesystem::path& file) {
  std::ifstream in = open_file(file);
  const std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  const Json root = JsonParser(text, file).parse_document();
  if (root.type != Json::Type::object) fail(file, "the sidecar must hold a JSON object");
  Sidecar sidecar;
  if (const Json* dims = root.find("dims")) {
    const std::string problem = "'dims' must be an array of 3 positive integers";
    if (dims->type != Json::Type::array || dims->items.size() != 3) fail(file, problem);
    VolumeDims d{};
    for (int k = 0; k < 3; ++k) {
      const Json& item = dims->items[static_cast<std::size_t>(k)];
      const auto value = item.type == Json::Type::number ? parse_int(item.text) : std::nullopt;
      if (!value || *value < 1) fail(file, problem + ", got '" + item.text + "' at index " + std::to_string(k));
      d[static_cast<std::size_t>(k)] = *value;
    }
    sidecar.dims = d;
  }
  if (const Json* type = root.find("type")) {
    if (type->type != Json::Type::string) fail(file, "'type' must be a string");
    sidecar.kind = parse_voxel_kind(type->text);
    if (!sidecar.kind)
      fail(file, "unknown voxel type '" + type->text + "' (expected one of " + std::string(kind_list) + ")");
  }
  // The values are kept as floats: a double beyond float's range would become infinite
  // (and its conversion is undefined), so it is refused.
  const auto check_floats = [&](const auto& values, std::string_view key) {
    for (const double v : values)
      if (!(std::abs(v) <= std::numeric_limits<float>::max()))
        fail(file, "'" + std::string(key) + "' value " + shortest(v) + " does not fit a float");
  };
  if (const Json* spacing = root.find("spacing")) {
    const auto s = json_numbers<3>(spacing, "spacing", "positive numbers", file);
    for (const double v : s)
      if (!(v > 0) || !(v <= std::numeric_limits<float>::max()) || !(static_cast<float>(v) > 0.f))
        fail(file, "'spacing' must be an array of 3 positive numbers");
    sidecar.spacing = Vec3f{static_cast<float>(s[0]), static_cast<float>(s[1]), static_cast<float>(s[2])};
  }
  if (const Json* origin = root.find("origin")) {
    const auto o = json_numbers<3>(origin, "origin", "finite numbers", file);
    check_floats(o, "origin");
    sidecar.origin = Vec3f{static_cast<float>(o[0]), static_cast<float>(o[1]), static_cast<float>(o[2])};
  }
  if (const Json* range = root.find("range")) {
    const auto r = json_numbers<2>(range, "range", "finite numbers, the smaller first", file);
    check_floats(r, "range");
    if (r[0] > r[1]) fail(file, "'range' must be an array of 2 finite numbers, the smaller first");
    sidecar.range = std::array<float, 2>{static_cast<float>(r[0]), static_cast<float>(r[1])};
  }
  return sidecar;
}

/// Dims and type from a file name `name_XxYxZ_type.ext`; nullopt when the name does not
/// follow the convention; an error when it does but names an unknown type.
inline std::optional<std::pair<VolumeDims, VoxelKind>> parse_file_name(const std::filesystem::path& file) {
  const std::string stem = file.stem().string();
  const std::size_t type_at = stem.rfind('_');
  if (type_at == std::string::npos || type_at == 0) return std::nullopt;
  const std::size_t dims_at = stem.rfind('_', type_at - 1);
  const std::string_view dims_part = std::string_view(stem).substr(
      dims_at == std::string::npos ? 0 : dims_at + 1, type_at - (dims_at == std::string::npos ? 0 : dims_at + 1));
  const std::string_view type_part = std::string_view(stem).substr(type_at + 1);
  VolumeDims dims{};
  std::size_t start = 0;
  for (int k = 0; k < 3; ++k) {
    const std::size_t end = k < 2 ? dims_part.find('x', start) : dims_part.size();
    if (end == std::string_view::npos) return std::nullopt;
    const std::string_view digits = dims_part.substr(start, end - start);
    if (digits.empty() || digits.find_first_not_of("0123456789") != std::string_view::npos) return std::nullopt;
    const auto value = parse_int(digits);
    if (!value) fail(file, "the dims '" + std::string(dims_part) + "' in the file name do not fit 64 bits");
    dims[static_cast<std::size_t>(k)] = *value;
    start = end + 1;
  }
  const auto kind = parse_voxel_kind(type_part);
  if (!kind)
    fail(file, "the file name gives the unknown voxel type '" + std::string(type_part) + "' (expected one of " +
                   std::string(kind_list) + ")");
  return std::pair{dims, *kind};
}

inline VolumeFile read_raw(const std::filesystem::path& file, const VolumeReadOptions& options) {
  VolumeFile volume;
  std::optional<VolumeDims> dims = options.dims;
  std::optional<VoxelKind> kind = options.kind;
  const std::filesystem::path sidecar_path = std::filesystem::path(file).replace_extension(".json");
  std::optional<Sidecar> sidecar;
  if (std::error_code error; std::filesystem::exists(sidecar_path, error)) sidecar = read_sidecar(sidecar_path);
  if (sidecar && (!dims || !kind)) {
    if (!dims && !sidecar->dims) fail(sidecar_path, "the sidecar has no 'dims' and no dims were given");
    if (!kind && !sidecar->kind) fail(sidecar_path, "the sidecar has no 'type' and no voxel type was given");
    if (!dims) dims = sidecar->dims;
    if (!kind) kind = sidecar->kind;
  }
  if (!dims || !kind) {
    const auto named = parse_file_name(file);
    if (!named)
      fail(file, "cannot tell the dims and voxel type: none were given, there is no sidecar " +
                     sidecar_path.filename().string() + ", and the file name does not follow name_XxYxZ_type" +
                     file.extension().string() + " (type one of " + std::string(kind_list) + ")");
    if (!dims) dims = named->first;
    if (!kind) kind = named->second;
  }
  volume.dims = *dims;
  volume.kind = *kind;
  if (sidecar) {
    if (sidecar->spacing) volume.grid.spacing = *sidecar->spacing;
    if (sidecar->origin) volume.grid.origin = *sidecar->origin;
    // The range describes the values as the sidecar reads them, not under other dims or type.
    if ((!sidecar->dims || *sidecar->dims == volume.dims) && (!sidecar->kind || *sidecar->kind == volume.kind))
      volume.range = sidecar->range;
  }

  const std::uint64_t needed = byte_count(volume.dims, volume.kind, file);
  const std::uint64_t size = size_of_file(file);
  if (size != needed)
    fail(file, "the file holds " + std::to_string(size) + " bytes but " + voxels_text(volume.dims, volume.kind) +
                   " need " + std::to_string(needed) + " bytes" +
                   (size < needed ? " (the file is truncated)" : " (the file is too large: wrong dims or type?)"));
  std::ifstream in = open_file(file);
  volume.voxels = allocate(needed, file);
  read_exact(in, volume.voxels->data(), needed, file);
  if constexpr (std::endian::native == std::endian::big) swap_bytes(*volume.voxels, voxel_size(volume.kind));
  return volume;
}

// ---------------------------------------------------------------------------------------
// NRRD

/// Decompresses a gzip (or zlib) stream, possibly of several members, dropping its first
/// `skip` bytes and filling `out` with the rest, which must be exactly `out.size()` bytes.
/// `needs` says what the data should hold, for messages ("sizes 4x4x4 uint8 voxels need 64 bytes").
inline void inflate_into(std::span<const std::byte> in, std::uint64_t skip, std::span<std::byte> out,
                         const std::filesystem::path& file, std::string needs) {
  if (skip > 0) needs += " after a byte skip of " + std::to_string(skip);
  z_stream stream{};
  if (inflateInit2(&stream, 15 + 32) != Z_OK) fail(file, "cannot start zlib's decompressor");
  struct End {
    z_stream* stream;
    ~End() { inflateEnd(stream); }
  } end{&stream};
  const std::uint64_t total = skip + out.size();
  constexpr std::uint64_t max_piece = std::uint64_t{1} << 30;  // z_stream counts in 32 bits
  std::vector<unsigned char> scratch(std::size_t{1} << 16);
  std::uint64_t in_pos = 0, produced = 0;
  while (true) {
    if (stream.avail_in == 0 && in_pos < in.size()) {
      const std::uint64_t n = std::min<std::uint64_t>(in.size() - in_pos, max_piece);
      stream.next_in = reinterpret_cast<unsigned char*>(const_cast<std::byte*>(in.data() + in_pos));
      stream.avail_in = static_cast<unsigned>(n);
      in_pos += n;
    }
    if (produced < skip) {
      stream.next_out = scratch.data();
      stream.avail_out = static_cast<unsigned>(std::min<std::uint64_t>(skip - produced, scratch.size()));
    } else if (produced < total) {
      stream.next_out = reinterpret_cast<unsigned char*>(out.data() + (produced - skip));
      stream.avail_out = static_cast<unsigned>(std::min<std::uint64_t>(total - produced, max_piece));
    } else {  // everything is there: any further output is too much
      stream.next_out = scratch.data();
      stream.avail_out = static_cast<unsigned>(scratch.size());
    }
    const unsigned room = stream.avail_out;
    const int result = inflate(&stream, Z_NO_FLUSH);
    produced += room - stream.avail_out;
    // Output past `total` is an error, reported once the stream has been checked to the end
    // (its CRC), so that damage reads as damage rather than as extra data.
    if (result == Z_STREAM_END) {
      if (stream.avail_in == 0 && in_pos == in.size()) break;
      if (inflateReset(&stream) != Z_OK) fail(file, "cannot restart zlib's decompressor");
      continue;  // another gzip member follows
    }
    if (result == Z_BUF_ERROR && stream.avail_in == 0 && in_pos == in.size())
      fail(file, "the gzip data is truncated: it ends after " + std::to_string(produced) + " decompressed bytes, but " +
                     needs);
    if (result != Z_OK && result != Z_BUF_ERROR)
      fail(file, "the gzip data is corrupt (zlib: " +
                     std::string(stream.msg ? stream.msg : "error " + std::to_string(result)) + ") after " +
                     std::to_string(produced) + " decompressed bytes");
  }
  if (produced > total) fail(file, "the gzip data decompresses to more bytes than expected: " + needs);
  if (produced < total)
    fail(file, "the gzip data decompresses to " + std::to_string(produced) + " bytes, but " + needs);
}

/// One `key: value` field of a NRRD header.
struct NrrdField {
  std::string value;
  std::size_t line = 0;
};

/// A field name without blanks, as NRRD allows both "data file" and "datafile".
inline std::string field_key(std::string_view name) {
  std::string key;
  for (const char c : name)
    if (c != ' ' && c != '\t') key.push_back(c >= 'A' && c <= 'Z' ? static_cast<char>(c - 'A' + 'a') : c);
  return key;
}

/// "(x,y,z)" vectors and "none" words, as in `space directions` and `space origin`.
inline std::vector<std::optional<std::array<double, 3>>> parse_vectors(std::string_view text, std::string_view field,
                                                                       const std::filesystem::path& file) {
  std::vector<std::optional<std::array<double, 3>>> vectors;
  std::size_t i = 0;
  const auto bad = [&](std::string_view why) {
    fail(file, "'" + std::string(field) + "' value '" + std::string(text) + "' is malformed: " + std::string(why));
  };
  while (true) {
    while (i < text.size() && (text[i] == ' ' || text[i] == '\t')) ++i;
    if (i == text.size()) break;
    if (text.substr(i, 4) == "none") {
      vectors.emplace_back(std::nullopt);
      i += 4;
      continue;
    }
    if (text[i] != '(') bad("expected '(' or 'none'");
    const std::size_t close = text.find(')', i);
    if (close == std::string_view::npos) bad("a '(' has no ')'");
    const std::string_view inside = text.substr(i + 1, close - i - 1);
    if (std::count(inside.begin(), inside.end(), ',') != 2) bad("a vector needs exactly 3 comma-separated components");
    std::array<double, 3> v{};
    std::size_t start = 0;
    for (int k = 0; k < 3; ++k) {
      const std::size_t comma = k < 2 ? inside.find(',', start) : inside.size();
      const auto value = parse_double(trim(inside.substr(start, comma - start)));
      if (!value) bad("a component is not a finite number");
      v[static_cast<std::size_t>(k)] = *value;
      start = comma + 1;
    }
    vectors.emplace_back(v);
    i = close + 1;
  }
  return vectors;
}

inline VolumeFile read_nrrd(const std::filesystem::path& file, const VolumeReadOptions& options) {
  std::ifstream in = open_file(file);
  char magic[8] = {};
  in.read(magic, sizeof magic);
  const std::string_view found(magic, static_cast<std::size_t>(in.gcount()));
  if (found.size() < 8 || found.substr(0, 7) != "NRRD000" || found[7] < '1' || found[7] > '5')
    fail(file, "not a NRRD file: it does not start with NRRD0001 to NRRD0005");
  in.clear();
  in.seekg(0);

  // The header: the magic line, then fields up to a blank line (or the end of a detached header).
  std::map<std::string, NrrdField> fields;
  std::uint64_t header_bytes = 0;
  bool blank_line = false;
  std::string line;
  std::size_t line_number = 0;
  while (std::getline(in, line)) {
    ++line_number;
    header_bytes += line.size() + (in.eof() ? 0 : 1);
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line_number == 1) continue;  // the magic
    if (line.empty()) {
      blank_line = true;
      break;
    }
    if (line[0] == '#') continue;
    const std::size_t field_at = line.find(": "), pair_at = line.find(":=");
    if (pair_at != std::string::npos && (field_at == std::string::npos || pair_at < field_at)) continue;  // key:=value
    if (field_at == std::string::npos)
      fail(file, "header line " + std::to_string(line_number) + ": expected 'field: value', got '" + line + "'");
    const std::string key = field_key(line.substr(0, field_at));
    const auto [it, added] =
        fields.emplace(key, NrrdField{std::string(trim(std::string_view(line).substr(field_at + 2))), line_number});
    if (!added)
      fail(file, "header line " + std::to_string(line_number) + ": field '" + line.substr(0, field_at) +
                     "' already appeared on line " + std::to_string(it->second.line));
  }
  const auto get = [&](std::string_view key) -> const NrrdField* {
    const auto it = fields.find(std::string(key));
    return it == fields.end() ? nullptr : &it->second;
  };
  const auto require = [&](std::string_view key, std::string_view name) -> const NrrdField& {
    const NrrdField* field = get(key);
    if (!field) fail(file, "the header has no '" + std::string(name) + "' field");
    return *field;
  };
  const auto where = [&](const NrrdField& field) { return "header line " + std::to_string(field.line) + ": "; };

  VolumeFile volume;
  const NrrdField& type = require("type", "type");
  const auto kind = parse_voxel_kind(type.value);
  if (!kind)
    fail(file, where(type) + "type '" + type.value + "' is not supported (expected one of " + std::string(kind_list) +
                   " in any NRRD spelling)");
  volume.kind = *kind;

  const NrrdField& dimension = require("dimension", "dimension");
  if (dimension.value != "3")
    fail(file, where(dimension) + "dimension '" + dimension.value + "' is not supported: only 3-D volumes are read");

  const NrrdField& sizes = require("sizes", "sizes");
  {
    const auto words = split_words(sizes.value);
    const std::string problem = "sizes '" + sizes.value + "' must be 3 positive integers";
    if (words.size() != 3) fail(file, where(sizes) + problem);
    for (std::size_t k = 0; k < 3; ++k) {
      const auto value = parse_int(words[k]);
      if (!value || *value < 1) fail(file, where(sizes) + problem);
      volume.dims[k] = *value;
    }
  }
  // Options cannot reinterpret a NRRD file, but they may state what the caller expects.
  if (options.kind && *options.kind != volume.kind)
    fail(file, "the header's type is " + std::string(voxel_kind_name(volume.kind)) + " but the options ask for " +
                   std::string(voxel_kind_name(*options.kind)));
  if (options.dims && *options.dims != volume.dims)
    fail(file,
         "the header's sizes are " + dims_text(volume.dims) + " but the options ask for " + dims_text(*options.dims));
  const std::uint64_t needed = byte_count(volume.dims, volume.kind, file);
  const std::string needs =
      "sizes " + voxels_text(volume.dims, volume.kind) + " need " + std::to_string(needed) + " bytes";

  const NrrdField& encoding_field = require("encoding", "encoding");
  const std::string encoding = field_key(encoding_field.value);
  bool gzip = false;
  if (encoding == "gzip" || encoding == "gz")
    gzip = true;
  else if (encoding == "ascii" || encoding == "text" || encoding == "txt" || encoding == "hex" || encoding == "bzip2" ||
           encoding == "bz2")
    fail(file,
         where(encoding_field) + "encoding '" + encoding_field.value + "' is not supported (only raw and gzip are)");
  else if (encoding != "raw")
    fail(file, where(encoding_field) + "unknown encoding '" + encoding_field.value + "' (only raw and gzip are read)");

  bool big_endian = false;
  if (const NrrdField* endian = get("endian")) {
    if (endian->value == "big")
      big_endian = true;
    else if (endian->value != "little")
      fail(file, where(*endian) + "endian '" + endian->value + "' must be 'little' or 'big'");
  } else if (voxel_size(volume.kind) > 1) {
    fail(file, "the header has no 'endian' field, which " + std::string(voxel_kind_name(volume.kind)) + " data needs");
  }

  // Where each axis goes: a signed step along x, y or z, and the first sample's position.
  std::array<double, 3> step = {1, 1, 1}, origin = {0, 0, 0};
  const NrrdField* spacings = get("spacings");
  const NrrdField* directions = get("spacedirections");
  if (spacings && directions)
    fail(file, where(*directions) + "the header has both 'spacings' and 'space directions'; NRRD allows one");
  if (spacings) {
    const auto words = split_words(spacings->value);
    if (words.size() != 3) fail(file, where(*spacings) + "spacings '" + spacings->value + "' must be 3 numbers");
    for (std::size_t k = 0; k < 3; ++k) {
      const auto value = parse_double(words[k]);
      if (!value || *value == 0)
        fail(file, where(*spacings) + "spacing '" + std::string(words[k]) + "' of axis " + std::to_string(k) +
                       " is not a finite non-zero number");
      step[k] = *value;
    }
  }
  if (directions) {
    const auto vectors = parse_vectors(directions->value, "space directions", file);
    if (vectors.size() != 3)
      fail(file, where(*directions) + "space directions '" + directions->value + "' must be 3 vectors");
    for (std::size_t k = 0; k < 3; ++k) {
      if (!vectors[k])
        fail(file, where(*directions) + "space direction of axis " + std::to_string(k) +
                       " is 'none': every axis of a volume must be spatial");
      const auto& v = *vectors[k];
      for (std::size_t j = 0; j < 3; ++j)
        if (j != k && v[j] != 0)
          fail(file, where(*directions) + "space directions '" + directions->value +
                         "' are not axis-aligned (only diagonal directions are supported): axis " + std::to_string(k) +
                         " has a non-zero component " + std::to_string(j));
      if (v[k] == 0) fail(file, where(*directions) + "space direction of axis " + std::to_string(k) + " is zero");
      step[k] = v[k];
    }
  }
  if (const NrrdField* space_origin = get("spaceorigin")) {
    const auto vectors = parse_vectors(space_origin->value, "space origin", file);
    if (vectors.size() != 1 || !vectors[0])
      fail(file, where(*space_origin) + "space origin '" + space_origin->value + "' must be one vector (x,y,z)");
    origin = *vectors[0];
  }
  if (const NrrdField* space_dimension = get("spacedimension"); space_dimension && space_dimension->value != "3")
    fail(file, where(*space_dimension) + "space dimension '" + space_dimension->value + "' is not supported (only 3)");
  bool cell_centered = false;
  if (const NrrdField* centers = get("centers")) {
    const auto words = split_words(centers->value);
    if (words.size() != 3) fail(file, where(*centers) + "centers '" + centers->value + "' must be 3 words");
    const auto count = [&](std::string_view word) { return std::count(words.begin(), words.end(), word); };
    if (count("cell") == 3)
      cell_centered = true;
    else if (count("cell") != 0)
      fail(file, where(*centers) + "centers '" + centers->value + "' mix cell and node centering");
  }

  std::int64_t line_skip = 0, byte_skip = 0;
  if (const NrrdField* field = get("lineskip")) {
    const auto value = parse_int(field->value);
    if (!value || *value < 0)
      fail(file, where(*field) + "line skip '" + field->value + "' must be a non-negative integer");
    line_skip = *value;
  }
  if (const NrrdField* field = get("byteskip")) {
    const auto value = parse_int(field->value);
    if (!value || *value < -1)
      fail(file, where(*field) + "byte skip '" + field->value + "' must be -1 or a non-negative integer");
    if (*value == -1 && gzip)
      fail(file, where(*field) + "byte skip -1 (data at the end of the file) is only allowed with raw encoding");
    byte_skip = *value;
  }

  // The data: in a detached file, or after the header's blank line.
  std::filesystem::path data_path = file;
  std::uint64_t data_start = 0;
  if (const NrrdField* data_file = get("datafile")) {
    const auto words = split_words(data_file->value);
    if (words.empty()) fail(file, where(*data_file) + "'data file' is empty");
    if (words[0] == "LIST" || (words.size() >= 3 && data_file->value.find('%') != std::string::npos))
      fail(file, where(*data_file) + "data split over several files is not supported");
    data_path = std::filesystem::path(data_file->value);
    if (data_path.is_relative()) data_path = file.parent_path() / data_path;
  } else {
    std::string extension = file.extension().string();
    for (char& c : extension) c = c >= 'A' && c <= 'Z' ? static_cast<char>(c - 'A' + 'a') : c;
    if (extension == ".nhdr") fail(file, "the header has no 'data file' field, which a detached .nhdr header needs");
    if (!blank_line)
      fail(file, "the header does not end with a blank line before the data, and no 'data file' field names the data");
    data_start = header_bytes;
  }
  in.close();

  const std::uint64_t data_size = size_of_file(data_path);
  std::ifstream data = open_file(data_path);
  data.seekg(static_cast<std::streamoff>(data_start));
  for (std::int64_t i = 0; i < line_skip; ++i) {
    data.ignore(std::numeric_limits<std::streamsize>::max(), '\n');
    if (data.eof()) fail(data_path, "line skip " + std::to_string(line_skip) + " goes past the end of the file");
  }
  const std::streamoff after_lines = data.tellg();
  if (after_lines < 0) fail(data_path, "cannot read the file");
  std::uint64_t start = static_cast<std::uint64_t>(after_lines);

  if (!gzip) {
    if (byte_skip == -1) {
      if (data_size < start || data_size - start < needed)
        fail(data_path, "the data is truncated: the file holds " + std::to_string(data_size) + " bytes but " + needs +
                            " after its first " + std::to_string(start) + " bytes");
      start = data_size - needed;
    } else {
      start += static_cast<std::uint64_t>(byte_skip);
    }
    const std::uint64_t available = data_size > start ? data_size - start : 0;
    if (available != needed)
      fail(data_path,
           "the file holds " + std::to_string(available) + " bytes of data after byte " + std::to_string(start) +
               " but " + needs +
               (available < needed ? " (the data is truncated)" : " (the data is too long: wrong sizes or type?)"));
    volume.voxels = allocate(needed, data_path);
    data.seekg(static_cast<std::streamoff>(start));
    read_exact(data, volume.voxels->data(), needed, data_path);
  } else {
    const std::uint64_t compressed = data_size > start ? data_size - start : 0;
    // Deflate expands at most 1032:1: refuse sizes the data cannot hold before allocating.
    constexpr std::uint64_t most = std::numeric_limits<std::uint64_t>::max();
    const std::uint64_t limit = compressed < (most - 4096) / 1100 ? compressed * 1100 + 4096 : most;
    if (needed > limit || static_cast<std::uint64_t>(byte_skip) > limit - needed)
      fail(data_path, "the gzip data is truncated: " + needs + ", more than its " + std::to_string(compressed) +
                          " compressed bytes can hold");
    const auto packed = allocate(compressed, data_path);
    read_exact(data, packed->data(), compressed, data_path);
    volume.voxels = allocate(needed, data_path);
    inflate_into(*packed, static_cast<std::uint64_t>(byte_skip), *volume.voxels, data_path, needs);
  }
  if ((std::endian::native == std::endian::big) != big_endian) swap_bytes(*volume.voxels, voxel_size(volume.kind));

  // A negative step runs the axis backwards: reverse the voxels so the grid's spacing is
  // positive, and start at the other end.
  for (int k = 0; k < 3; ++k) {
    const auto axis = static_cast<std::size_t>(k);
    if (step[axis] < 0) {
      flip_axis(*volume.voxels, volume.dims, k, voxel_size(volume.kind));
      origin[axis] += step[axis] * static_cast<double>(volume.dims[axis] - 1);
      step[axis] = -step[axis];
    }
  }
  // NRRD's origin is the first sample's centre; a cell-centred grid's origin is its corner.
  if (cell_centered)
    for (std::size_t k = 0; k < 3; ++k) origin[k] -= 0.5 * step[k];
  volume.grid.spacing = Vec3f{static_cast<float>(step[0]), static_cast<float>(step[1]), static_cast<float>(step[2])};
  volume.grid.origin =
      Vec3f{static_cast<float>(origin[0]), static_cast<float>(origin[1]), static_cast<float>(origin[2])};
  volume.grid.cell_centered = cell_centered;
  for (int k = 0; k < 3; ++k)
    if (!std::isfinite(volume.grid.spacing[k]) || !(volume.grid.spacing[k] > 0.f) ||
        !std::isfinite(volume.grid.origin[k]))
      fail(file, "the spacing or origin does not fit a float");
  return volume;
}

}  // namespace volume_detail

/// Reads a volume: NRRD for `.nrrd` and `.nhdr` files, headerless raw voxels otherwise.
/// For raw files the options override the sidecar and the file name; a NRRD header says
/// what its data is, so there options that disagree with it are an error.
inline VolumeFile read_volume(const std::filesystem::path& path, const VolumeReadOptions& options = {}) {
  std::string extension = path.extension().string();
  for (char& c : extension) c = c >= 'A' && c <= 'Z' ? static_cast<char>(c - 'A' + 'a') : c;
  if (extension == ".nrrd" || extension == ".nhdr") return volume_detail::read_nrrd(path, options);
  return volume_detail::read_raw(path, options);
}

}  // namespace sciray::io
