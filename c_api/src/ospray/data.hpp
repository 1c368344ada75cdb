#pragma once
// OSPData: 1D-3D arrays of values or object handles, owned or shared with the
// application (with byte strides and an optional deleter), as OSPRay defines them.
#include <array>
#include <vector>

#include "object.hpp"

namespace sciray::ospray {

class Data : public Object {
public:
  /// Shares the application's memory; `strides` of 0 mean compact.
  Data(const void* shared, OSPDataType type, std::array<std::uint64_t, 3> counts,
       std::array<std::int64_t, 3> strides, OSPDeleterCallback deleter, const void* deleter_user_data);
  /// Owns zero-initialized memory (object arrays hold NULL handles).
  Data(OSPDataType type, std::array<std::uint64_t, 3> counts);
  ~Data() override;

  OSPDataType element_type() const { return element_type_; }
  const std::array<std::uint64_t, 3>& counts() const { return counts_; }
  std::uint64_t size() const { return counts_[0] * counts_[1] * counts_[2]; }
  int dimensions() const { return counts_[2] > 1 ? 3 : (counts_[1] > 1 ? 2 : 1); }
  /// Byte strides between neighbours along each dimension (compact ones filled in).
  const std::array<std::int64_t, 3>& strides() const { return strides_; }
  /// Whether the elements lie one after another, the first dimension fastest.
  bool compact() const {
    const auto element = static_cast<std::int64_t>(size_of(element_type_));
    return strides_[0] == element && strides_[1] == element * static_cast<std::int64_t>(counts_[0]) &&
           strides_[2] == strides_[1] * static_cast<std::int64_t>(counts_[1]);
  }
  const std::byte* element(std::uint64_t i, std::uint64_t j = 0, std::uint64_t k = 0) const {
    return base_ + static_cast<std::int64_t>(i) * strides_[0] + static_cast<std::int64_t>(j) * strides_[1] +
           static_cast<std::int64_t>(k) * strides_[2];
  }
  /// Whether the elements are the application's memory (ospNewSharedData).
  bool shares_memory() const { return shared_ != nullptr; }
  /// The object at linear index `i` of an object array (may be NULL).
  Object* object(std::uint64_t i) const { return objects_.at(i).get(); }

  /// Copies `source` into this array at the given offset (ospCopyData).
  void copy_from(const Data& source, std::array<std::uint64_t, 3> offset);

  void for_each_reference(const std::function<void(const Object&)>& visit) const override;

  /// The elements of a 1D array of `type` (one of `accepted`), converted to T by `convert`.
  template <class T, class Convert>
  std::vector<T> to_vector(Convert&& convert) const {
    std::vector<T> out;
    out.reserve(size());
    for (std::uint64_t k = 0; k < counts_[2]; ++k)
      for (std::uint64_t j = 0; j < counts_[1]; ++j)
        for (std::uint64_t i = 0; i < counts_[0]; ++i) out.push_back(convert(element(i, j, k)));
    return out;
  }

private:
  void retain_objects();

  OSPDataType element_type_;
  std::array<std::uint64_t, 3> counts_;
  std::array<std::int64_t, 3> strides_;
  const std::byte* base_ = nullptr;
  std::vector<std::byte> owned_;
  std::vector<Ref<Object>> objects_;  // references held by object arrays
  OSPDeleterCallback deleter_ = nullptr;
  const void* deleter_user_data_ = nullptr;
  const void* shared_ = nullptr;
};

}  // namespace sciray::ospray
