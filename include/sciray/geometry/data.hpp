#pragma once
// Arrays that geometry reads: either owned by sciray or shared with the caller
// (zero-copy). Embree reads vertex buffers with 16-byte loads, so the last element
// of a buffer it shares must be followed by readable memory; PaddedVector allocates
// that slack so owned data can be handed to Embree without a copy.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <new>
#include <span>
#include <vector>

namespace sciray {

/// Bytes Embree may read past the end of a shared buffer.
inline constexpr std::size_t embree_buffer_padding = 16;

template <class T>
struct PaddedAllocator {
  using value_type = T;
  PaddedAllocator() = default;
  template <class U>
  PaddedAllocator(const PaddedAllocator<U>&) noexcept {}

  T* allocate(std::size_t n) {
    return static_cast<T*>(::operator new(n * sizeof(T) + embree_buffer_padding, std::align_val_t{16}));
  }
  void deallocate(T* p, std::size_t) noexcept { ::operator delete(p, std::align_val_t{16}); }

  template <class U>
  bool operator==(const PaddedAllocator<U>&) const noexcept {
    return true;
  }
};

/// A std::vector whose storage Embree may share directly.
template <class T>
using PaddedVector = std::vector<T, PaddedAllocator<T>>;

/// A read-only strided view of `count` elements of `components` T each, as OSPRay's
/// shared data arrays: element i starts at byte `i * byte_stride`.
template <class T>
struct StridedView {
  const std::byte* base = nullptr;
  std::size_t count = 0;
  std::size_t byte_stride = 0;

  StridedView() = default;
  StridedView(const T* data, std::size_t count_, std::size_t stride_bytes)
      : base(reinterpret_cast<const std::byte*>(data)), count(count_), byte_stride(stride_bytes) {}

  bool empty() const { return count == 0; }
  const T* element(std::size_t i) const { return reinterpret_cast<const T*>(base + i * byte_stride); }
  const T* data() const { return reinterpret_cast<const T*>(base); }
};

}  // namespace sciray
