// Loading a 20M-triangle binary little-endian PLY: a 3163 x 3163-cell height field
// (z = 0.1 sin(3x) cos(2y) over [0,1]^2, two triangles per cell, 10,010,896 vertices,
// 20,009,138 triangles, about 380 MB), written once to a temporary file.
#include <benchmark/benchmark.h>

#include <bit>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "sciray/io/ply.hpp"

namespace {

class HeightFieldPly {
public:
  static constexpr std::uint32_t cells = 3163;

  HeightFieldPly()
      : path_(std::filesystem::temp_directory_path() /
              ("sciray_bench_ply_" +
               std::to_string(std::chrono::steady_clock::now().time_since_epoch().count()) + ".ply")) {
    const std::uint32_t side = cells + 1;
    std::ofstream out(path_, std::ios::binary);
    out << "ply\nformat binary_little_endian 1.0\ncomment sciray benchmark height field\n"
        << "element vertex " << std::uint64_t{side} * side
        << "\nproperty float x\nproperty float y\nproperty float z\n"
        << "element face " << triangles() << "\nproperty list uchar int vertex_indices\nend_header\n";
    // One row at a time keeps the writer's memory small.
    std::vector<char> row;
    for (std::uint32_t j = 0; j < side; ++j) {
      row.clear();
      for (std::uint32_t i = 0; i < side; ++i) {
        const float x = static_cast<float>(i) / cells, y = static_cast<float>(j) / cells;
        for (const float value : {x, y, 0.1f * std::sin(3.0f * x) * std::cos(2.0f * y)})
          append(row, std::bit_cast<std::uint32_t>(value));
      }
      out.write(row.data(), static_cast<std::streamsize>(row.size()));
    }
    for (std::uint32_t j = 0; j < cells; ++j) {
      row.clear();
      for (std::uint32_t i = 0; i < cells; ++i) {
        const std::uint32_t v = j * side + i, up = v + side;
        append_triangle(row, v, v + 1, up + 1);
        append_triangle(row, v, up + 1, up);
      }
      out.write(row.data(), static_cast<std::streamsize>(row.size()));
    }
    out.close();
    if (!out) {
      std::filesystem::remove(path_);
      throw std::runtime_error("cannot write " + path_.string());
    }
    // One untimed load: right after the file fills the page cache the kernel must first
    // compact memory to hand out huge pages, a one-off cost (about 1 s) that is not the reader's.
    sciray::io::read_ply(path_);
  }
  ~HeightFieldPly() { std::filesystem::remove(path_); }
  HeightFieldPly(const HeightFieldPly&) = delete;
  HeightFieldPly& operator=(const HeightFieldPly&) = delete;

  const std::filesystem::path& path() const { return path_; }
  static std::uint64_t triangles() { return 2ull * cells * cells; }

private:
  static void append(std::vector<char>& bytes, std::uint32_t value) {  // little endian whatever the host
    for (int shift = 0; shift < 32; shift += 8) bytes.push_back(static_cast<char>(value >> shift));
  }
  static void append_triangle(std::vector<char>& bytes, std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    bytes.push_back(3);
    for (const std::uint32_t index : {a, b, c}) append(bytes, index);
  }

  std::filesystem::path path_;
};

void ply_binary_load(benchmark::State& state) {
  static const HeightFieldPly file;
  for (auto _ : state) {
    sciray::MeshData mesh = sciray::io::read_ply(file.path());
    benchmark::DoNotOptimize(mesh.indices.data());
  }
  state.counters["triangles/s"] = benchmark::Counter(
      static_cast<double>(HeightFieldPly::triangles()) * static_cast<double>(state.iterations()),
      benchmark::Counter::kIsRate);
}
// Single-threaded reading: wall time is the figure, as a user waits for it.
const auto* const ply_benchmark =
    benchmark::RegisterBenchmark("io/ply/binary_little_endian/heightfield_20M", ply_binary_load)
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime();

}  // namespace
