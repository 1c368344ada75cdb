#pragma once
// A fresh directory under the system temporary directory for a test's files, removed
// with its contents.
#include <chrono>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>

namespace sciray_test {

class TempDir {
public:
  /// `prefix` names the test file ("sciray_test_ply_"); a time and a random number follow.
  explicit TempDir(const std::string& prefix)
      : path_(std::filesystem::temp_directory_path() /
              (prefix + std::to_string(std::chrono::steady_clock::now().time_since_epoch().count()) + "_" +
               std::to_string(std::random_device()()))) {
    std::filesystem::create_directories(path_);
  }
  ~TempDir() { std::filesystem::remove_all(path_); }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  const std::filesystem::path& path() const { return path_; }
  /// Writes `contents` to `name` (which may hold folders) and returns its path.
  std::filesystem::path write(const std::string& name, const std::string& contents) const {
    const std::filesystem::path file = path_ / name;
    std::filesystem::create_directories(file.parent_path());
    std::ofstream(file, std::ios::binary).write(contents.data(), static_cast<std::streamsize>(contents.size()));
    return file;
  }

private:
  std::filesystem::path path_;
};

}  // namespace sciray_test
