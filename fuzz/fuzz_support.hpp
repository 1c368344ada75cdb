#pragma once
// Shared by the libFuzzer targets (fuzz_*.cpp, built and run by scripts/fuzz.sh): a
// scratch folder per process for readers that take a path, splitting an input into the
// files of a multi-file format, and running a reader so that only sciray::Error, the
// readers' documented way to refuse a file, counts as a clean outcome. Any other exception
// escapes to libFuzzer, which reports it as a crash, as it does sanitizer findings.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <utility>

#include "sciray/error.hpp"

namespace sciray_fuzz {

/// The input as text.
inline std::string_view text_of(const std::uint8_t* data, std::size_t size) {
  return {reinterpret_cast<const char*>(data), size};
}

/// A folder of this process's own (fuzzers may run side by side), removed at exit: in
/// /dev/shm where there is one, since on a disk's file system (ext4 flushes a file that is
/// truncated and rewritten when it is closed) the writes would take most of the time.
inline const std::filesystem::path& scratch_folder() {
  // Never destroyed: the exit handler runs after the destructors of statics made before it.
  static const std::filesystem::path* const folder = [] {
    std::error_code error;
    const std::filesystem::path base = std::filesystem::is_directory("/dev/shm", error)
                                           ? std::filesystem::path("/dev/shm")
                                           : std::filesystem::temp_directory_path();
    const auto* path = new std::filesystem::path(base / ("sciray-fuzz-" + std::to_string(::getpid())));
    std::filesystem::create_directories(*path);
    std::atexit([] {
      std::error_code ignored;
      std::filesystem::remove_all(scratch_folder(), ignored);
    });
    return path;
  }();
  return *folder;
}

/// Writes `bytes` to `name` in the scratch folder and returns its path.
inline std::filesystem::path write_file(const std::string& name, std::string_view bytes) {
  const std::filesystem::path path = scratch_folder() / name;
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (!out) std::abort();  // the harness's own failure, not the reader's
  return path;
}

/// Removes `name` from the scratch folder, so that a part missing from one input is not
/// left over from the one before.
inline void remove_file(const std::string& name) {
  std::error_code ignored;
  std::filesystem::remove(scratch_folder() / name, ignored);
}

/// The input cut at the first `separator`: what comes before it and what after (empty
/// when there is no separator).
inline std::pair<std::string_view, std::string_view> split(std::string_view input, std::string_view separator) {
  const std::size_t at = input.find(separator);
  if (at == std::string_view::npos) return {input, {}};
  return {input.substr(0, at), input.substr(at + separator.size())};
}

/// Runs `read`; a sciray::Error is a clean refusal, anything else escapes to libFuzzer.
/// With SCIRAY_FUZZ_VERBOSE set, says how each input ended (to check that seeds are valid).
template <class Read>
int run(Read&& read) {
  static const bool verbose = std::getenv("SCIRAY_FUZZ_VERBOSE") != nullptr;
  try {
    read();
    if (verbose) std::fprintf(stderr, "read\n");
  } catch (const sciray::Error& error) {
    if (verbose) std::fprintf(stderr, "refused: %s\n", error.what());
  }
  return 0;
}

}  // namespace sciray_fuzz
