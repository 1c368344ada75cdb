#pragma once
// Messages as bytes: what ranks send each other (tiles, commands) is written field by
// field into a byte vector and read back in the same order, every read checked against
// the message's end. Ranks of one job run the same build on the same kind of machine,
// so values go in native byte order.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>
#include <string>
#include <type_traits>
#include <vector>

#include "sciray/error.hpp"

namespace sciray::mpi {

class Writer {
public:
  template <class T>
    requires std::is_trivially_copyable_v<T>
  void put(const T& value) {
    put_bytes(&value, sizeof(T));
  }
  void put_bytes(const void* data, std::size_t size) {
    const auto* bytes = static_cast<const std::byte*>(data);
    buffer_.insert(buffer_.end(), bytes, bytes + size);
  }
  void put_string(const std::string& s) {
    put<std::uint64_t>(s.size());
    put_bytes(s.data(), s.size());
  }
  template <class T>
  void put_span(std::span<const T> values) {
    put<std::uint64_t>(values.size());
    put_bytes(values.data(), values.size_bytes());
  }

  std::vector<std::byte>& bytes() { return buffer_; }
  const std::byte* data() const { return buffer_.data(); }
  std::size_t size() const { return buffer_.size(); }
  void clear() { buffer_.clear(); }

private:
  std::vector<std::byte> buffer_;
};

class Reader {
public:
  explicit Reader(std::span<const std::byte> bytes) : bytes_(bytes) {}

  template <class T>
    requires std::is_trivially_copyable_v<T>
  T get() {
    T value;
    std::memcpy(&value, take(sizeof(T)), sizeof(T));
    return value;
  }
  const std::byte* take(std::size_t size) {
    if (size > bytes_.size() - at_)
      throw Error("mpi: a message ends " + std::to_string(size - (bytes_.size() - at_)) +
                  " bytes short of its next field (truncated or from another version)");
    const std::byte* p = bytes_.data() + at_;
    at_ += size;
    return p;
  }
  std::string get_string() {
    const auto size = get<std::uint64_t>();
    const auto* p = take(size);
    return std::string(reinterpret_cast<const char*>(p), size);
  }
  template <class T>
  std::vector<T> get_vector() {
    const auto count = get<std::uint64_t>();
    if (count > (bytes_.size() - at_) / sizeof(T))
      throw Error("mpi: a message announces " + std::to_string(count) + " values but holds " +
                  std::to_string((bytes_.size() - at_) / sizeof(T)));
    std::vector<T> values(count);
    const std::byte* from = take(count * sizeof(T));
    if (count) std::memcpy(values.data(), from, count * sizeof(T));  // an empty vector's data() may be null
    return values;
  }
  bool done() const { return at_ == bytes_.size(); }

private:
  std::span<const std::byte> bytes_;
  std::size_t at_ = 0;
};

}  // namespace sciray::mpi
