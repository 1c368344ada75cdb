// The volume readers: every shipped volume against its sidecar, the file-name convention,
// options, NRRD files written here from real voxels (both byte orders, gzip, detached
// headers, spacings, space directions and origins, skips), and every error path.
#include <zlib.h>

#include <algorithm>
#include <array>
#include <catch2/catch.hpp>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <random>
#include <string>
#include <vector>

#include "sciray/io/volume.hpp"
#include "support/temp_dir.hpp"

using sciray_test::TempDir;
namespace {

namespace fs = std::filesystem;
using Catch::Contains;
using sciray::VolumeDims;
using sciray::io::parse_voxel_kind;
using sciray::io::read_volume;
using sciray::io::VolumeFile;
using sciray::io::VolumeReadOptions;
using sciray::io::voxel_kind_name;
using sciray::io::voxel_size;
using sciray::io::VoxelKind;

fs::path volume_path(const std::string& name) {
  return fs::path(SCIRAY_DATA_DIR) / "volumes" / name;
}

std::string file_contents(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  REQUIRE(in);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}


/// Voxel i of a loaded volume as a double.
double voxel(const VolumeFile& volume, std::size_t i) {
  const std::byte* p = volume.voxels->data() + i * voxel_size(volume.kind);
  const auto get = [p]<class T>(T value) {
    std::memcpy(&value, p, sizeof value);
    return static_cast<double>(value);
  };
  switch (volume.kind) {
    case VoxelKind::uint8: return get(std::uint8_t{});
    case VoxelKind::int16: return get(std::int16_t{});
    case VoxelKind::uint16: return get(std::uint16_t{});
    case VoxelKind::float32: return get(float{});
    case VoxelKind::float64: return get(double{});
  }
  return 0;
}

std::size_t voxel_count(const VolumeFile& volume) {
  return static_cast<std::size_t>(volume.dims[0] * volume.dims[1] * volume.dims[2]);
}

std::array<double, 2> value_range(const VolumeFile& volume) {
  std::array<double, 2> range{voxel(volume, 0), voxel(volume, 0)};
  for (std::size_t i = 1; i < voxel_count(volume); ++i) {
    const double v = voxel(volume, i);
    range[0] = std::min(range[0], v), range[1] = std::max(range[1], v);
  }
  return range;
}

/// The voxels as they would be stored in a file of the given byte order.
std::string stored(const VolumeFile& volume, bool big_endian) {
  std::string bytes(reinterpret_cast<const char*>(volume.voxels->data()), volume.voxels->size());
  const std::size_t size = voxel_size(volume.kind);
  if (big_endian)
    for (std::size_t i = 0; i < bytes.size(); i += size)
      std::reverse(bytes.begin() + static_cast<std::ptrdiff_t>(i),
                   bytes.begin() + static_cast<std::ptrdiff_t>(i + size));
  return bytes;
}

std::string gzip(const std::string& data) {
  z_stream stream{};
  REQUIRE(deflateInit2(&stream, Z_BEST_SPEED, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY) == Z_OK);
  std::string out(deflateBound(&stream, data.size()) + 64, '\0');
  stream.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(data.data()));
  stream.avail_in = static_cast<uInt>(data.size());
  stream.next_out = reinterpret_cast<Bytef*>(out.data());
  stream.avail_out = static_cast<uInt>(out.size());
  REQUIRE(deflate(&stream, Z_FINISH) == Z_STREAM_END);
  out.resize(stream.total_out);
  deflateEnd(&stream);
  return out;
}

void require_same_voxels(const VolumeFile& a, const VolumeFile& b) {
  REQUIRE(a.kind == b.kind);
  REQUIRE(a.dims == b.dims);
  REQUIRE(a.voxels->size() == b.voxels->size());
  for (std::size_t i = 0; i < voxel_count(a); ++i)
    if (voxel(a, i) != voxel(b, i)) FAIL("voxel " << i << " differs: " << voxel(a, i) << " vs " << voxel(b, i));
  SUCCEED();
}

std::string dims_words(const VolumeDims& d) {
  return std::to_string(d[0]) + " " + std::to_string(d[1]) + " " + std::to_string(d[2]);
}

/// A NRRD header (without the blank line that ends an attached one).
std::string nrrd_header(const std::string& type, const VolumeDims& dims, const std::string& endian,
                        const std::string& encoding, const std::string& extra = "",
                        const std::string& magic = "NRRD0004") {
  return magic + "\n# written by test_volume_io\ntype: " + type + "\ndimension: 3\nsizes: " + dims_words(dims) +
         "\nendian: " + endian + "\nencoding: " + encoding + "\n" + extra;
}

const VolumeFile& headsq() {  // uint16: shows byte order
  static const VolumeFile volume = read_volume(volume_path("headsq_64x64x93_uint16.raw"));
  return volume;
}
const VolumeFile& carotid() {  // float32 with an origin
  static const VolumeFile volume = read_volume(volume_path("carotid_76x49x45_float32.raw"));
  return volume;
}
const VolumeFile& headmr() {  // small uint8
  static const VolumeFile volume = read_volume(volume_path("headmr_48x62x42_uint8.raw"));
  return volume;
}

}  // namespace

TEST_CASE("volume_io: voxel kind names, aliases and sizes", "[volume_io]") {
  const VoxelKind kinds[] = {VoxelKind::uint8, VoxelKind::int16, VoxelKind::uint16, VoxelKind::float32,
                             VoxelKind::float64};
  const char* names[] = {"uint8", "int16", "uint16", "float32", "float64"};
  const std::size_t sizes[] = {1, 2, 2, 4, 8};
  for (int k = 0; k < 5; ++k) {
    CHECK(voxel_kind_name(kinds[k]) == names[k]);
    CHECK(parse_voxel_kind(names[k]) == kinds[k]);
    CHECK(voxel_size(kinds[k]) == sizes[k]);
  }
  CHECK(parse_voxel_kind("uchar") == VoxelKind::uint8);
  CHECK(parse_voxel_kind("short") == VoxelKind::int16);
  CHECK(parse_voxel_kind("ushort") == VoxelKind::uint16);
  CHECK(parse_voxel_kind("float") == VoxelKind::float32);
  CHECK(parse_voxel_kind("double") == VoxelKind::float64);
  // NRRD's spellings.
  for (const char* name : {"unsigned char", "uint8_t"}) CHECK(parse_voxel_kind(name) == VoxelKind::uint8);
  for (const char* name : {"short int", "signed short", "signed short int", "int16_t"})
    CHECK(parse_voxel_kind(name) == VoxelKind::int16);
  for (const char* name : {"unsigned short", "unsigned short int", "uint16_t"})
    CHECK(parse_voxel_kind(name) == VoxelKind::uint16);
  CHECK(parse_voxel_kind("  unsigned   short ") == VoxelKind::uint16);
  CHECK(parse_voxel_kind("FLOAT") == VoxelKind::float32);
  for (const char* name : {"", "int", "int32", "int8", "signed char", "uint", "long", "float16", "block"})
    CHECK_FALSE(parse_voxel_kind(name).has_value());
}

TEST_CASE("volume_io: every shipped volume loads as its sidecar describes", "[volume_io]") {
  int count = 0;
  for (const auto& entry : fs::directory_iterator(fs::path(SCIRAY_DATA_DIR) / "volumes")) {
    if (entry.path().extension() != ".raw") continue;
    ++count;
    const fs::path sidecar_path = fs::path(entry.path()).replace_extension(".json");
    INFO(entry.path().string());
    REQUIRE(fs::exists(sidecar_path));
    const auto sidecar = nlohmann::json::parse(file_contents(sidecar_path));
    const VolumeFile volume = read_volume(entry.path());
    for (int k = 0; k < 3; ++k) {
      CHECK(volume.dims[static_cast<std::size_t>(k)] == sidecar["dims"][k].get<std::int64_t>());
      CHECK(volume.grid.spacing[k] == sidecar["spacing"][k].get<float>());
      CHECK(volume.grid.origin[k] == sidecar["origin"][k].get<float>());
    }
    CHECK(voxel_kind_name(volume.kind) == sidecar["type"].get<std::string>());
    CHECK_FALSE(volume.grid.cell_centered);
    REQUIRE(volume.voxels->size() == voxel_count(volume) * voxel_size(volume.kind));
    REQUIRE(volume.voxels->size() == fs::file_size(entry.path()));
    REQUIRE(volume.range.has_value());
    CHECK((*volume.range)[0] == sidecar["range"][0].get<float>());
    CHECK((*volume.range)[1] == sidecar["range"][1].get<float>());
    const auto range = value_range(volume);
    CHECK(range[0] == sidecar["range"][0].get<double>());
    CHECK(range[1] == sidecar["range"][1].get<double>());
  }
  CHECK(count >= 7);
}

TEST_CASE("volume_io: raw dims and type from the file name when there is no sidecar", "[volume_io]") {
  TempDir dir("sciray_test_volume_io_");
  const fs::path copy = dir.write("scan_64x64x93_uint16.raw", file_contents(volume_path("headsq_64x64x93_uint16.raw")));
  const VolumeFile volume = read_volume(copy);
  CHECK(volume.kind == VoxelKind::uint16);
  CHECK(volume.dims == VolumeDims{64, 64, 93});
  CHECK(volume.grid.spacing.x == 1.f);
  CHECK(volume.grid.spacing.z == 1.f);
  CHECK(volume.grid.origin.x == 0.f);
  CHECK_FALSE(volume.range.has_value());
  CHECK((*volume.voxels == *headsq().voxels));

  // Underscores in the name and other extensions are fine; the type is read case-blind.
  const fs::path other =
      dir.write("head_mr_t1_48x62x42_UINT8.bin", file_contents(volume_path("headmr_48x62x42_uint8.raw")));
  const VolumeFile mr = read_volume(other);
  CHECK(mr.kind == VoxelKind::uint8);
  CHECK(mr.dims == VolumeDims{48, 62, 42});
  CHECK((*mr.voxels == *headmr().voxels));
}

TEST_CASE("volume_io: options override the sidecar and the file name", "[volume_io]") {
  // Against a real sidecar: the same bytes read as twice as many uint8 voxels keep the
  // sidecar's spacing and origin but not its range, which is about uint16 values.
  VolumeReadOptions as_bytes;
  as_bytes.dims = VolumeDims{128, 64, 93};
  as_bytes.kind = VoxelKind::uint8;
  const VolumeFile bytes = read_volume(volume_path("headsq_64x64x93_uint16.raw"), as_bytes);
  CHECK(bytes.kind == VoxelKind::uint8);
  CHECK(bytes.dims == VolumeDims{128, 64, 93});
  CHECK(bytes.grid.spacing.x == 3.2f);
  CHECK(bytes.grid.spacing.z == 1.5f);
  CHECK_FALSE(bytes.range.has_value());
  CHECK((*bytes.voxels == *headsq().voxels));

  // Only the type: dims still come from the sidecar (headsq's values fit an int16).
  VolumeReadOptions as_int16;
  as_int16.kind = VoxelKind::int16;
  const VolumeFile signed_volume = read_volume(volume_path("headsq_64x64x93_uint16.raw"), as_int16);
  CHECK(signed_volume.kind == VoxelKind::int16);
  CHECK(signed_volume.dims == VolumeDims{64, 64, 93});
  CHECK(value_range(signed_volume) == value_range(headsq()));

  // Options that agree with the sidecar keep its range.
  VolumeReadOptions same;
  same.dims = VolumeDims{64, 64, 93};
  same.kind = VoxelKind::uint16;
  CHECK(read_volume(volume_path("headsq_64x64x93_uint16.raw"), same).range.has_value());

  TempDir dir("sciray_test_volume_io_");
  // A name without the convention and no sidecar needs both options.
  const fs::path plain = dir.write("plain.raw", file_contents(volume_path("headsq_64x64x93_uint16.raw")));
  REQUIRE_THROWS_WITH(read_volume(plain), Contains("plain.raw: cannot tell the dims and voxel type") &&
                                              Contains("no sidecar plain.json") && Contains("name_XxYxZ_type"));
  const VolumeFile from_options = read_volume(plain, same);
  CHECK((*from_options.voxels == *headsq().voxels));
  CHECK(from_options.grid.spacing.x == 1.f);

  // Options fill in what the name gives, one field at a time.
  const fs::path named =
      dir.write("named_64x64x93_uint16.raw", file_contents(volume_path("headsq_64x64x93_uint16.raw")));
  VolumeReadOptions dims_only;
  dims_only.dims = VolumeDims{64, 93, 64};
  const VolumeFile reshaped = read_volume(named, dims_only);
  CHECK(reshaped.kind == VoxelKind::uint16);
  CHECK(reshaped.dims == VolumeDims{64, 93, 64});
  VolumeReadOptions kind_only;
  kind_only.kind = VoxelKind::uint8;
  REQUIRE_THROWS_WITH(read_volume(named, kind_only), Contains("holds 761856 bytes but 64x64x93 uint8 voxels need "
                                                              "380928 bytes"));
  VolumeReadOptions halved;
  halved.dims = VolumeDims{64, 64, 186};
  halved.kind = VoxelKind::uint8;
  CHECK(read_volume(named, halved).dims == VolumeDims{64, 64, 186});

  // A sidecar of our own with only some fields: the rest from the options, defaults otherwise.
  dir.write("partial.raw", file_contents(volume_path("headmr_48x62x42_uint8.raw")));
  const fs::path partial = dir.path() / "partial.raw";
  dir.write("partial.json", R"({"dims": [48, 62, 42], "origin": [1.5, -2, 3e1]})");
  REQUIRE_THROWS_WITH(read_volume(partial), Contains("partial.json: the sidecar has no 'type'"));
  VolumeReadOptions uint8_only;
  uint8_only.kind = VoxelKind::uint8;
  const VolumeFile partial_volume = read_volume(partial, uint8_only);
  CHECK(partial_volume.dims == VolumeDims{48, 62, 42});
  CHECK(partial_volume.grid.origin.x == 1.5f);
  CHECK(partial_volume.grid.origin.y == -2.f);
  CHECK(partial_volume.grid.origin.z == 30.f);
  CHECK(partial_volume.grid.spacing.y == 1.f);
  CHECK_FALSE(partial_volume.range.has_value());
}

TEST_CASE("volume_io: NRRD raw in both byte orders and gzip reads the raw file's voxels", "[volume_io]") {
  TempDir dir("sciray_test_volume_io_");
  const VolumeFile& reference = headsq();
  const std::string spacings = "spacings: 3.2 3.2 1.5\n";
  for (const bool big : {false, true}) {
    const std::string endian = big ? "big" : "little";
    INFO(endian);
    const fs::path raw =
        dir.write("raw_" + endian + ".nrrd", nrrd_header("unsigned short", reference.dims, endian, "raw", spacings) +
                                                 "\n" + stored(reference, big));
    const VolumeFile from_raw = read_volume(raw);
    require_same_voxels(from_raw, reference);
    CHECK(from_raw.grid.spacing.x == 3.2f);
    CHECK(from_raw.grid.spacing.y == 3.2f);
    CHECK(from_raw.grid.spacing.z == 1.5f);
    CHECK(from_raw.grid.origin.x == 0.f);
    CHECK_FALSE(from_raw.grid.cell_centered);
    CHECK_FALSE(from_raw.range.has_value());

    for (const std::string encoding : {"gzip", "gz"}) {
      const fs::path packed = dir.write(
          encoding + "_" + endian + ".nrrd",
          nrrd_header("uint16", reference.dims, endian, encoding, spacings) + "\n" + gzip(stored(reference, big)));
      require_same_voxels(read_volume(packed), reference);
    }
  }

  // float32, float64, int16 and uint8 in some of their spellings, and every magic version.
  const VolumeFile& flow = carotid();
  require_same_voxels(read_volume(dir.write("flow.nrrd", nrrd_header("float", flow.dims, "big", "raw", "", "NRRD0001") +
                                                             "\n" + stored(flow, true))),
                      flow);
  VolumeFile as_double = flow;
  as_double.kind = VoxelKind::float64;
  as_double.voxels = std::make_shared<std::vector<std::byte>>(voxel_count(flow) * 8);
  for (std::size_t i = 0; i < voxel_count(flow); ++i) {
    const double v = voxel(flow, i);
    std::memcpy(as_double.voxels->data() + i * 8, &v, 8);
  }
  require_same_voxels(
      read_volume(dir.write("flow64.nrrd", nrrd_header("double", flow.dims, "big", "gzip", "", "NRRD0002") + "\n" +
                                               gzip(stored(as_double, true)))),
      as_double);
  VolumeFile as_int16 = reference;
  as_int16.kind = VoxelKind::int16;
  require_same_voxels(read_volume(dir.write("signed.nrrd", nrrd_header("signed short int", reference.dims, "little",
                                                                       "raw", "", "NRRD0003") +
                                                               "\n" + stored(reference, false))),
                      as_int16);
  // uint8 needs no 'endian'; CRLF line ends, key:=value pairs and comments are allowed.
  const VolumeFile& mr = headmr();
  const std::string crlf =
      "NRRD0005\r\n# a comment\r\ntype: uchar\r\ndimension: 3\r\nsizes: 48 62 42\r\n"
      "encoding: raw\r\nmodality:=MR\r\ncontent: head\r\n\r\n";
  require_same_voxels(read_volume(dir.write("mr.nrrd", crlf + stored(mr, false))), mr);
}

TEST_CASE("volume_io: gzip NRRD data may be several concatenated members", "[volume_io]") {
  TempDir dir("sciray_test_volume_io_");
  const VolumeFile& reference = headsq();
  const std::string data = stored(reference, false);
  const std::string packed = gzip(data.substr(0, 1000)) + gzip(data.substr(1000));
  require_same_voxels(
      read_volume(dir.write("members.nrrd", nrrd_header("uint16", reference.dims, "little", "gzip") + "\n" + packed)),
      reference);
}

TEST_CASE("volume_io: detached NRRD headers find their data relative to the header", "[volume_io]") {
  TempDir dir("sciray_test_volume_io_");
  const VolumeFile& reference = headsq();
  dir.write("data/headsq.raw", stored(reference, true));
  dir.write("data/headsq.raw.gz", gzip(stored(reference, false)));
  // No blank line is needed at the end of a detached header.
  const fs::path raw = dir.write(
      "headers/raw.nhdr", nrrd_header("ushort", reference.dims, "big", "raw", "data file: ../data/headsq.raw\n"));
  require_same_voxels(read_volume(raw), reference);
  const fs::path packed =
      dir.write("headers/packed.nhdr",
                nrrd_header("uint16", reference.dims, "little", "gzip", "datafile: ../data/headsq.raw.gz\n") + "\n");
  require_same_voxels(read_volume(packed), reference);
  // An absolute path works too, also from a .nrrd header.
  const fs::path absolute =
      dir.write("absolute.nrrd", nrrd_header("uint16", reference.dims, "big", "raw",
                                             "data file: " + (dir.path() / "data" / "headsq.raw").string() + "\n") +
                                     "\n");
  require_same_voxels(read_volume(absolute), reference);
}

TEST_CASE("volume_io: NRRD space directions, space origin and centers place the grid", "[volume_io]") {
  TempDir dir("sciray_test_volume_io_");
  const VolumeFile& flow = carotid();
  const std::string data = stored(flow, false);
  const std::string space =
      "space: right-anterior-superior\nspace directions: (0.5,0,0) (0, 2, 0) (0,0,1.25)\n"
      "space origin: (100,80,1)\n";
  const VolumeFile placed =
      read_volume(dir.write("placed.nrrd", nrrd_header("float", flow.dims, "little", "raw", space) + "\n" + data));
  require_same_voxels(placed, flow);
  CHECK(placed.grid.spacing.x == 0.5f);
  CHECK(placed.grid.spacing.y == 2.f);
  CHECK(placed.grid.spacing.z == 1.25f);
  CHECK(placed.grid.origin.x == 100.f);
  CHECK(placed.grid.origin.y == 80.f);
  CHECK(placed.grid.origin.z == 1.f);
  CHECK_FALSE(placed.grid.cell_centered);

  // NRRD's origin is the first sample's centre; a cell-centred grid starts half a cell before.
  const VolumeFile cells = read_volume(
      dir.write("cells.nrrd",
                nrrd_header("float", flow.dims, "little", "raw", space + "centers: cell cell cell\n") + "\n" + data));
  CHECK(cells.grid.cell_centered);
  CHECK(cells.grid.origin.x == 99.75f);
  CHECK(cells.grid.origin.y == 79.f);
  CHECK(cells.grid.origin.z == 0.375f);
  const VolumeFile nodes = read_volume(
      dir.write("nodes.nrrd",
                nrrd_header("float", flow.dims, "little", "raw", space + "centers: node node node\n") + "\n" + data));
  CHECK_FALSE(nodes.grid.cell_centered);
  CHECK(nodes.grid.origin.x == 100.f);

  // A backwards axis (as in RAS/LPS files): the voxels are reversed along it and the grid
  // starts at its far end, so every sample keeps its world position.
  const VolumeFile flipped = read_volume(
      dir.write("flipped.nrrd", nrrd_header("float", flow.dims, "little", "raw",
                                            "space dimension: 3\nspace directions: (-2,0,0) (0,1,0) (0,0,-0.5)\n"
                                            "space origin: (10, 0, 5)\n") +
                                    "\n" + data));
  CHECK(flipped.grid.spacing.x == 2.f);
  CHECK(flipped.grid.spacing.z == 0.5f);
  CHECK(flipped.grid.origin.x == static_cast<float>(10 - 2 * (flow.dims[0] - 1)));
  CHECK(flipped.grid.origin.z == static_cast<float>(5 - 0.5 * static_cast<double>(flow.dims[2] - 1)));
  const VolumeDims d = flow.dims;
  bool same = true;
  for (std::int64_t z = 0; z < d[2]; ++z)
    for (std::int64_t y = 0; y < d[1]; ++y)
      for (std::int64_t x = 0; x < d[0]; ++x)
        same = same && voxel(flipped, static_cast<std::size_t>((z * d[1] + y) * d[0] + x)) ==
                           voxel(flow, static_cast<std::size_t>(((d[2] - 1 - z) * d[1] + y) * d[0] + (d[0] - 1 - x)));
  CHECK(same);
}

TEST_CASE("volume_io: NRRD line skip and byte skip", "[volume_io]") {
  TempDir dir("sciray_test_volume_io_");
  const VolumeFile& reference = headsq();
  const std::string data = stored(reference, false);
  dir.write("skipped.raw", "first line\nsecond line\n12345" + data);
  require_same_voxels(read_volume(dir.write("skipped.nhdr", nrrd_header("uint16", reference.dims, "little", "raw",
                                                                        "data file: skipped.raw\nline skip: 2\n"
                                                                        "byte skip: 5\n"))),
                      reference);
  // byte skip -1: the data is the end of the file, whatever precedes it.
  dir.write("tail.raw", "a header of some other format\n\x01\x02\x03" + data);
  require_same_voxels(read_volume(dir.write("tail.nhdr", nrrd_header("uint16", reference.dims, "little", "raw",
                                                                     "data file: tail.raw\nbyte skip: -1\n"))),
                      reference);
  require_same_voxels(
      read_volume(dir.write("attached_tail.nrrd",
                            nrrd_header("uint16", reference.dims, "little", "raw", "byteskip: -1\n") + "\nxyz" + data)),
      reference);
  // With gzip, line skip applies to the file and byte skip to the decompressed data.
  dir.write("skipped.gz", "line one\n" + gzip("0123456" + data));
  require_same_voxels(read_volume(dir.write("skipped_gz.nhdr", nrrd_header("uint16", reference.dims, "little", "gzip",
                                                                           "data file: skipped.gz\nlineskip: 1\n"
                                                                           "byteskip: 7\n"))),
                      reference);
}

TEST_CASE("volume_io: raw file errors", "[volume_io]") {
  TempDir dir("sciray_test_volume_io_");
  const std::string mr = file_contents(volume_path("headmr_48x62x42_uint8.raw"));  // 124992 bytes
  REQUIRE_THROWS_WITH(read_volume(dir.path() / "missing_4x4x4_uint8.raw"),
                      Contains("missing_4x4x4_uint8.raw: cannot open the file"));

  const fs::path truncated = dir.write("cut_48x62x42_uint8.raw", mr.substr(0, mr.size() - 100));
  REQUIRE_THROWS_WITH(read_volume(truncated),
                      Contains("cut_48x62x42_uint8.raw: the file holds 124892 bytes but 48x62x42 uint8 voxels need "
                               "124992 bytes (the file is truncated)"));
  const fs::path oversized = dir.write("big_48x62x42_uint8.raw", mr + "x");
  REQUIRE_THROWS_WITH(read_volume(oversized), Contains("the file holds 124993 bytes but 48x62x42 uint8 voxels need "
                                                       "124992 bytes (the file is too large"));

  // Unknown types: in the file name and in a sidecar.
  const fs::path int32 = dir.write("v_4x4x4_int32.raw", std::string(256, '\0'));
  REQUIRE_THROWS_WITH(read_volume(int32), Contains("v_4x4x4_int32.raw: the file name gives the unknown voxel type "
                                                   "'int32'") &&
                                              Contains("uint8, int16, uint16, float32, float64"));
  dir.write("s.raw", std::string(64, '\0'));
  dir.write("s.json", R"({"dims": [4, 4, 4], "type": "int8"})");
  REQUIRE_THROWS_WITH(read_volume(dir.path() / "s.raw"), Contains("s.json: unknown voxel type 'int8'"));
  dir.write("s.json", R"({"dims": [4, 0, 4], "type": "uint8"})");
  REQUIRE_THROWS_WITH(read_volume(dir.path() / "s.raw"),
                      Contains("s.json: 'dims' must be an array of 3 positive integers, got '0' at index 1"));
  dir.write("s.json", R"({"type": "uint8"})");
  REQUIRE_THROWS_WITH(read_volume(dir.path() / "s.raw"), Contains("s.json: the sidecar has no 'dims'"));
  dir.write("s.json", R"({"dims": [4, 4, 4], "type": "uint8", "spacing": [1, -1, 1]})");
  REQUIRE_THROWS_WITH(read_volume(dir.path() / "s.raw"),
                      Contains("s.json: 'spacing' must be an array of 3 positive numbers"));
  dir.write("s.json", R"({"dims": [4, 4, 4], "type": "uint8", "range": [5, 1]})");
  REQUIRE_THROWS_WITH(read_volume(dir.path() / "s.raw"), Contains("'range' must be an array of 2 finite numbers"));
  dir.write("s.json", R"({"dims": [4, 4, 4], "type": "uint8",})");
  REQUIRE_THROWS_WITH(read_volume(dir.path() / "s.raw"), Contains("s.json: invalid JSON at byte"));
  dir.write("s.json", R"({"dims": [4, 4, 4], "type": "uint8", "range": [0, 0]})");
  CHECK(read_volume(dir.path() / "s.raw").range == std::array<float, 2>{0.f, 0.f});

  // Dims below 1, and byte counts that overflow 64 bits, fail before any allocation.
  VolumeReadOptions zero;
  zero.dims = VolumeDims{48, 0, 42};
  zero.kind = VoxelKind::uint8;
  REQUIRE_THROWS_WITH(read_volume(truncated, zero), Contains("dims 48x0x42 are invalid: every dim must be at least 1"));
  VolumeReadOptions negative;
  negative.dims = VolumeDims{-1, 62, 42};
  REQUIRE_THROWS_WITH(read_volume(truncated, negative), Contains("dims -1x62x42 are invalid"));
  VolumeReadOptions huge;
  huge.dims = VolumeDims{std::int64_t{1} << 22, std::int64_t{1} << 21, std::int64_t{1} << 20};
  huge.kind = VoxelKind::uint8;  // 2^63 bytes: fits 64 bits, not memory
  REQUIRE_THROWS_WITH(read_volume(truncated, huge),
                      Contains("the file holds 124892 bytes") && Contains("need 9223372036854775808 bytes"));
  huge.kind = VoxelKind::uint16;  // 2^64 bytes
  REQUIRE_THROWS_WITH(read_volume(truncated, huge),
                      Contains("the byte count of 4194304x2097152x1048576 uint16 voxels overflows 64 bits"));
  VolumeReadOptions max_dims;
  max_dims.dims = VolumeDims{INT64_MAX, INT64_MAX, 1};
  max_dims.kind = VoxelKind::uint8;
  REQUIRE_THROWS_WITH(read_volume(truncated, max_dims), Contains("overflows 64 bits"));

  // More than 2^32 voxels: the expected size is computed in 64 bits.
  VolumeReadOptions large;
  large.dims = VolumeDims{65536, 65536, 2};
  large.kind = VoxelKind::uint8;
  REQUIRE_THROWS_WITH(read_volume(truncated, large),
                      Contains("the file holds 124892 bytes but 65536x65536x2 uint8 voxels need 8589934592 bytes "
                               "(the file is truncated)"));
  large.dims = VolumeDims{2048, 2048, 1025};
  large.kind = VoxelKind::float64;
  REQUIRE_THROWS_WITH(read_volume(truncated, large), Contains("need 34393292800 bytes"));
  // And with dims from the file name.
  const fs::path named_large = dir.write("large_100000x50000x1_uint16.raw", "xy");
  REQUIRE_THROWS_WITH(read_volume(named_large),
                      Contains("the file holds 2 bytes but 100000x50000x1 uint16 voxels need 10000000000 bytes"));
}

TEST_CASE("volume_io: NRRD errors", "[volume_io]") {
  TempDir dir("sciray_test_volume_io_");
  const VolumeFile& reference = headsq();
  const VolumeDims d = reference.dims;
  const std::string data = stored(reference, false);
  const auto attached = [&](const std::string& name, const std::string& header, const std::string& body) {
    return dir.write(name, header + "\n" + body);
  };

  REQUIRE_THROWS_WITH(read_volume(dir.path() / "none.nrrd"), Contains("none.nrrd: cannot open the file"));
  REQUIRE_THROWS_WITH(read_volume(dir.write("magic.nrrd", "NRRD0009\ntype: uint8\n")),
                      Contains("magic.nrrd: not a NRRD file: it does not start with NRRD0001 to NRRD0005"));
  REQUIRE_THROWS_WITH(read_volume(dir.write("ply.nrrd", "ply\nformat ascii 1.0\n")), Contains("not a NRRD file"));
  REQUIRE_THROWS_WITH(read_volume(dir.write("empty.nhdr", "")), Contains("empty.nhdr: not a NRRD file"));

  // Missing required fields, each named.
  REQUIRE_THROWS_WITH(
      read_volume(
          attached("nosizes.nrrd", "NRRD0004\ntype: uint16\ndimension: 3\nendian: little\nencoding: raw\n", data)),
      Contains("nosizes.nrrd: the header has no 'sizes' field"));
  REQUIRE_THROWS_WITH(
      read_volume(
          attached("notype.nrrd", "NRRD0004\ndimension: 3\nsizes: 64 64 93\nendian: little\nencoding: raw\n", data)),
      Contains("the header has no 'type' field"));
  REQUIRE_THROWS_WITH(
      read_volume(
          attached("nodim.nrrd", "NRRD0004\ntype: uint16\nsizes: 64 64 93\nendian: little\nencoding: raw\n", data)),
      Contains("the header has no 'dimension' field"));
  REQUIRE_THROWS_WITH(
      read_volume(
          attached("noenc.nrrd", "NRRD0004\ntype: uint16\ndimension: 3\nsizes: 64 64 93\nendian: little\n", data)),
      Contains("the header has no 'encoding' field"));
  REQUIRE_THROWS_WITH(
      read_volume(
          attached("noendian.nrrd", "NRRD0004\ntype: uint16\ndimension: 3\nsizes: 64 64 93\nencoding: raw\n", data)),
      Contains("the header has no 'endian' field, which uint16 data needs"));
  REQUIRE_THROWS_WITH(read_volume(dir.write("nodata.nhdr", nrrd_header("uint16", d, "little", "raw"))),
                      Contains("nodata.nhdr: the header has no 'data file' field"));
  REQUIRE_THROWS_WITH(read_volume(dir.write("noblank.nrrd", nrrd_header("uint16", d, "little", "raw"))),
                      Contains("the header does not end with a blank line"));

  // Bad field values.
  REQUIRE_THROWS_WITH(read_volume(attached("int.nrrd", nrrd_header("int", d, "little", "raw"), data)),
                      Contains("int.nrrd: header line 3: type 'int' is not supported"));
  REQUIRE_THROWS_WITH(read_volume(attached("int32.nrrd", nrrd_header("int32", d, "little", "raw"), data)),
                      Contains("type 'int32' is not supported"));
  REQUIRE_THROWS_WITH(
      read_volume(attached("dim2.nrrd", "NRRD0004\ntype: uint8\ndimension: 2\nsizes: 64 64\nencoding: raw\n", data)),
      Contains("dimension '2' is not supported: only 3-D volumes are read"));
  REQUIRE_THROWS_WITH(read_volume(attached("sizes.nrrd", nrrd_header("uint16", {64, 0, 93}, "little", "raw"), data)),
                      Contains("sizes '64 0 93' must be 3 positive integers"));
  REQUIRE_THROWS_WITH(read_volume(attached("endian.nrrd", nrrd_header("uint16", d, "middle", "raw"), data)),
                      Contains("endian 'middle' must be 'little' or 'big'"));
  REQUIRE_THROWS_WITH(
      read_volume(attached("twice.nrrd", nrrd_header("uint16", d, "little", "raw", "type: uint16\n"), data)),
      Contains("header line 8: field 'type' already appeared on line 3"));
  REQUIRE_THROWS_WITH(read_volume(attached("junk.nrrd", nrrd_header("uint16", d, "little", "raw", "junk\n"), data)),
                      Contains("header line 8: expected 'field: value', got 'junk'"));
  REQUIRE_THROWS_WITH(
      read_volume(attached("sizes_overflow.nrrd",
                           nrrd_header("uint16", {4294967296, 4294967296, 4294967296}, "little", "raw"), data)),
      Contains("the byte count of 4294967296x4294967296x4294967296 uint16 voxels overflows 64 bits"));
  VolumeReadOptions wrong;
  wrong.kind = VoxelKind::float32;
  REQUIRE_THROWS_WITH(read_volume(attached("opt.nrrd", nrrd_header("uint16", d, "little", "raw"), data), wrong),
                      Contains("the header's type is uint16 but the options ask for float32"));

  // Unsupported encodings.
  for (const std::string encoding : {"ascii", "text", "hex", "bzip2", "bz2"})
    REQUIRE_THROWS_WITH(read_volume(attached(encoding + ".nrrd", nrrd_header("uint16", d, "little", encoding), data)),
                        Contains("encoding '" + encoding + "' is not supported (only raw and gzip are)"));
  REQUIRE_THROWS_WITH(read_volume(attached("zip.nrrd", nrrd_header("uint16", d, "little", "zip"), data)),
                      Contains("unknown encoding 'zip'"));

  // Geometry.
  REQUIRE_THROWS_WITH(
      read_volume(attached(
          "oblique.nrrd",
          nrrd_header("uint16", d, "little", "raw", "space: RAS\nspace directions: (1,0.5,0) (0,1,0) (0,0,1)\n"),
          data)),
      Contains("space directions '(1,0.5,0) (0,1,0) (0,0,1)' are not axis-aligned (only diagonal directions are "
               "supported): axis 0 has a non-zero component 1"));
  REQUIRE_THROWS_WITH(
      read_volume(attached("permuted.nrrd",
                           nrrd_header("uint16", d, "little", "raw", "space directions: (0,1,0) (1,0,0) (0,0,1)\n"),
                           data)),
      Contains("are not axis-aligned"));
  REQUIRE_THROWS_WITH(
      read_volume(attached(
          "nonevec.nrrd", nrrd_header("uint16", d, "little", "raw", "space directions: none (0,1,0) (0,0,1)\n"), data)),
      Contains("space direction of axis 0 is 'none'"));
  REQUIRE_THROWS_WITH(
      read_volume(attached(
          "twovec.nrrd", nrrd_header("uint16", d, "little", "raw", "space directions: (1,0) (0,1,0) (0,0,1)\n"), data)),
      Contains("a vector needs exactly 3 comma-separated components"));
  REQUIRE_THROWS_WITH(read_volume(attached("both.nrrd",
                                           nrrd_header("uint16", d, "little", "raw",
                                                       "spacings: 1 1 1\nspace directions: (1,0,0) (0,1,0) (0,0,1)\n"),
                                           data)),
                      Contains("both 'spacings' and 'space directions'"));
  REQUIRE_THROWS_WITH(
      read_volume(attached("zero.nrrd", nrrd_header("uint16", d, "little", "raw", "spacings: 1 0 1\n"), data)),
      Contains("spacing '0' of axis 1 is not a finite non-zero number"));
  REQUIRE_THROWS_WITH(
      read_volume(attached("origin.nrrd", nrrd_header("uint16", d, "little", "raw", "space origin: (1,2,x)\n"), data)),
      Contains("'space origin' value '(1,2,x)' is malformed"));

  REQUIRE_THROWS_WITH(
      read_volume(
          attached("centers.nrrd", nrrd_header("uint16", d, "little", "raw", "centers: cell node cell\n"), data)),
      Contains("centers 'cell node cell' mix cell and node centering"));
  REQUIRE_THROWS_WITH(
      read_volume(attached("space2.nrrd", nrrd_header("uint16", d, "little", "raw", "space dimension: 2\n"), data)),
      Contains("space dimension '2' is not supported"));
  REQUIRE_THROWS_WITH(
      read_volume(attached("skip2.nrrd", nrrd_header("uint16", d, "little", "raw", "byte skip: -2\n"), data)),
      Contains("header line 8: byte skip '-2' must be -1 or a non-negative integer"));

  // Data of the wrong length.
  REQUIRE_THROWS_WITH(read_volume(attached("short.nrrd", nrrd_header("uint16", d, "little", "raw"), data.substr(1))),
                      Contains("short.nrrd: the file holds 761855 bytes of data after byte") &&
                          Contains("but sizes 64x64x93 uint16 voxels need 761856 bytes (the data is truncated)"));
  REQUIRE_THROWS_WITH(read_volume(attached("long.nrrd", nrrd_header("uint16", d, "little", "raw"), data + "\n")),
                      Contains("the file holds 761857 bytes of data") && Contains("(the data is too long"));
  REQUIRE_THROWS_WITH(
      read_volume(attached("tail.nrrd", nrrd_header("uint16", d, "little", "raw", "byte skip: -1\n"), data.substr(2))),
      Contains("the data is truncated"));
  REQUIRE_THROWS_WITH(
      read_volume(dir.write("lost.nhdr", nrrd_header("uint16", d, "little", "raw", "data file: lost.raw\n"))),
      Contains("lost.raw: cannot open the file: it does not exist"));
  dir.write("two.raw", "just one line\n");
  REQUIRE_THROWS_WITH(read_volume(dir.write("lines.nhdr", nrrd_header("uint16", d, "little", "raw",
                                                                      "data file: two.raw\nline skip: 3\n"))),
                      Contains("two.raw: line skip 3 goes past the end of the file"));
  REQUIRE_THROWS_WITH(
      read_volume(dir.write("list.nhdr", nrrd_header("uint16", d, "little", "raw", "data file: LIST\n"))),
      Contains("data split over several files is not supported"));
  REQUIRE_THROWS_WITH(
      read_volume(attached("gzskip.nrrd", nrrd_header("uint16", d, "little", "gzip", "byte skip: -1\n"), gzip(data))),
      Contains("byte skip -1 (data at the end of the file) is only allowed with raw encoding"));
}

TEST_CASE("volume_io: corrupt and wrong-length gzip streams", "[volume_io]") {
  TempDir dir("sciray_test_volume_io_");
  const VolumeFile& reference = headsq();
  const VolumeDims d = reference.dims;
  const std::string packed = gzip(stored(reference, false));
  const auto load = [&](const std::string& name, const std::string& body, VolumeDims dims) {
    return read_volume(dir.write(name, nrrd_header("uint16", dims, "little", "gzip") + "\n" + body));
  };
  // Damage in the middle of the deflate stream, or in the gzip header.
  std::string damaged = packed;
  for (std::size_t i = damaged.size() / 2; i < damaged.size() / 2 + 64; ++i)
    damaged[i] = static_cast<char>(~damaged[i]);
  REQUIRE_THROWS_WITH(load("damaged.nrrd", damaged, d), Contains("damaged.nrrd: the gzip data is corrupt (zlib: "));
  std::string bad_header = packed;
  bad_header[0] = 'X';
  REQUIRE_THROWS_WITH(load("header.nrrd", bad_header, d),
                      Contains("the gzip data is corrupt (zlib: incorrect header check) after 0 decompressed bytes"));
  // A stream cut short, one that holds more than the sizes, one that holds less.
  REQUIRE_THROWS_WITH(load("cut.nrrd", packed.substr(0, packed.size() / 2), d),
                      Contains("cut.nrrd: the gzip data is truncated: it ends after") &&
                          Contains("decompressed bytes, but sizes 64x64x93 uint16 voxels need 761856 bytes"));
  REQUIRE_THROWS_WITH(load("more.nrrd", packed, {64, 64, 92}),
                      Contains("the gzip data decompresses to more bytes than expected: sizes 64x64x92 uint16 "
                               "voxels need 753664 bytes"));
  const std::string data = stored(reference, false);
  REQUIRE_THROWS_WITH(load("less.nrrd", gzip(data.substr(0, data.size() - 1000)), d),
                      Contains("the gzip data decompresses to 760856 bytes, but sizes 64x64x93 uint16 voxels need "
                               "761856 bytes"));
  // With a byte skip the message says so.
  REQUIRE_THROWS_WITH(
      read_volume(
          dir.write("skip.nrrd", nrrd_header("uint16", d, "little", "gzip", "byte skip: 10\n") + "\n" + packed)),
      Contains("the gzip data decompresses to 761856 bytes, but sizes 64x64x93 uint16 voxels need 761856 bytes after "
               "a byte skip of 10"));
  // Sizes that a gzip stream this short cannot hold are refused before allocating them.
  REQUIRE_THROWS_WITH(load("huge.nrrd", packed, {100000, 100000, 1000}),
                      Contains("the gzip data is truncated: sizes 100000x100000x1000 uint16 voxels need "
                               "20000000000000 bytes, more than its") &&
                          Contains("compressed bytes can hold"));
}
