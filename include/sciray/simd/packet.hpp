#pragma once
// Lane types: every algorithm is written once over Float<Arch>/Int<Arch>/Mask<Arch>,
// which are xsimd batches for a packet architecture and plain float/int/bool for
// `scalar`. The helpers below have an overload for each so that code reads the same.
#include <cmath>
#include <cstdint>

#include <xsimd/xsimd.hpp>

#include "sciray/simd/arch.hpp"

namespace sciray::simd {

template <class Arch>
struct lanes {
  using Float = xsimd::batch<float, Arch>;
  using Int = xsimd::batch<std::int32_t, Arch>;
  using Mask = xsimd::batch_bool<float, Arch>;
  static constexpr int width = static_cast<int>(Float::size);
};

template <>
struct lanes<scalar> {
  using Float = float;
  using Int = std::int32_t;
  using Mask = bool;
  static constexpr int width = 1;
};

template <class Arch>
using Float = typename lanes<Arch>::Float;
template <class Arch>
using Int = typename lanes<Arch>::Int;
template <class Arch>
using Mask = typename lanes<Arch>::Mask;
template <class Arch>
inline constexpr int width = lanes<Arch>::width;

/// The xsimd architecture compiled for each packet ISA.
template <Isa>
struct arch_of;
template <>
struct arch_of<Isa::scalar> {
  using type = scalar;
};
template <>
struct arch_of<Isa::sse42> {
  using type = xsimd::sse4_2;
};
template <>
struct arch_of<Isa::avx2> {
  using type = xsimd::avx2;
};
template <>
struct arch_of<Isa::avx512> {
  using type = xsimd::avx512bw;
};

// ---- scalar overloads ---------------------------------------------------------------
inline float select(bool m, float a, float b) { return m ? a : b; }
inline std::int32_t select(bool m, std::int32_t a, std::int32_t b) { return m ? a : b; }
inline bool any(bool m) { return m; }
inline bool all(bool m) { return m; }
inline float sqrt(float x) { return std::sqrt(x); }
inline float abs(float x) { return std::fabs(x); }
inline float min(float a, float b) { return a < b ? a : b; }
inline float max(float a, float b) { return a > b ? a : b; }
inline float fma(float a, float b, float c) { return std::fma(a, b, c); }
inline float lane(float x, int) { return x; }
inline std::int32_t lane(std::int32_t x, int) { return x; }
inline bool lane(bool m, int) { return m; }
inline float to_float(std::int32_t i) { return static_cast<float>(i); }
inline std::int32_t to_int(float x) { return static_cast<std::int32_t>(x); }  // truncates, as cvttps

// ---- packet overloads -------------------------------------------------------------
template <class A>
xsimd::batch<float, A> select(const xsimd::batch_bool<float, A>& m, const xsimd::batch<float, A>& a,
                              const xsimd::batch<float, A>& b) {
  return xsimd::select(m, a, b);
}
template <class A>
xsimd::batch<std::int32_t, A> select(const xsimd::batch_bool<float, A>& m, const xsimd::batch<std::int32_t, A>& a,
                                     const xsimd::batch<std::int32_t, A>& b) {
  // Reinterpret the float mask bits as an int mask of the same width.
  const auto bits = xsimd::bitwise_cast<xsimd::batch<std::int32_t, A>>(xsimd::bitwise_cast<A>(m));
  return (a & bits) | (b & ~bits);
}
template <class A>
bool any(const xsimd::batch_bool<float, A>& m) {
  return xsimd::any(m);
}
template <class A>
bool all(const xsimd::batch_bool<float, A>& m) {
  return xsimd::all(m);
}
template <class A>
xsimd::batch<float, A> sqrt(const xsimd::batch<float, A>& x) {
  return xsimd::sqrt(x);
}
template <class A>
xsimd::batch<float, A> abs(const xsimd::batch<float, A>& x) {
  return xsimd::abs(x);
}
template <class A>
xsimd::batch<float, A> min(const xsimd::batch<float, A>& a, const xsimd::batch<float, A>& b) {
  return xsimd::min(a, b);
}
template <class A>
xsimd::batch<float, A> max(const xsimd::batch<float, A>& a, const xsimd::batch<float, A>& b) {
  return xsimd::max(a, b);
}
template <class A>
xsimd::batch<float, A> fma(const xsimd::batch<float, A>& a, const xsimd::batch<float, A>& b,
                           const xsimd::batch<float, A>& c) {
  return xsimd::fma(a, b, c);
}
template <class T, class A>
T lane(const xsimd::batch<T, A>& x, int i) {
  return x.get(static_cast<std::size_t>(i));
}
template <class A>
bool lane(const xsimd::batch_bool<float, A>& m, int i) {
  return m.get(static_cast<std::size_t>(i));
}
template <class A>
xsimd::batch<float, A> to_float(const xsimd::batch<std::int32_t, A>& i) {
  return xsimd::to_float(i);
}

template <class A>
xsimd::batch<std::int32_t, A> to_int(const xsimd::batch<float, A>& x) {
  return xsimd::to_int(x);
}

/// Mask as Embree's `valid` array wants it: -1 for active lanes, 0 otherwise.
template <class A>
xsimd::batch<std::int32_t, A> valid_lanes(const xsimd::batch_bool<float, A>& m) {
  return xsimd::bitwise_cast<xsimd::batch<std::int32_t, A>>(xsimd::bitwise_cast<A>(m));
}

/// Loads `width<Arch>` consecutive values (one for scalar).
template <class Arch>
Float<Arch> load(const float* p) {
  if constexpr (std::is_same_v<Arch, scalar>)
    return *p;
  else
    return Float<Arch>::load_unaligned(p);
}
template <class Arch>
Int<Arch> load(const std::int32_t* p) {
  if constexpr (std::is_same_v<Arch, scalar>)
    return *p;
  else
    return Int<Arch>::load_unaligned(p);
}
template <class Arch>
void store(float* p, const Float<Arch>& v) {
  if constexpr (std::is_same_v<Arch, scalar>)
    *p = v;
  else
    v.store_unaligned(p);
}
template <class Arch>
void store(std::int32_t* p, const Int<Arch>& v) {
  if constexpr (std::is_same_v<Arch, scalar>)
    *p = v;
  else
    v.store_unaligned(p);
}

/// Reads base[index[i]] for each lane (`index` in elements). xsimd 8.1 gathers AVX-512
/// batches one lane at a time, so the hardware gathers are called directly.
template <class Arch, class T>
auto gather(const T* base, const Int<Arch>& index) {
  static_assert(std::is_same_v<T, float> || std::is_same_v<T, std::int32_t>);
  if constexpr (std::is_same_v<Arch, scalar>) {
    return base[index];
  } else {
    using Batch = xsimd::batch<T, Arch>;
#if defined(__AVX512F__)
    if constexpr (std::is_base_of_v<xsimd::avx512f, Arch>) {
      if constexpr (std::is_same_v<T, float>)
        return Batch(_mm512_i32gather_ps(index, base, sizeof(T)));
      else
        return Batch(_mm512_i32gather_epi32(index, base, sizeof(T)));
    }
#endif
#if defined(__AVX2__)
    if constexpr (std::is_base_of_v<xsimd::avx2, Arch>) {
      if constexpr (std::is_same_v<T, float>)
        return Batch(_mm256_i32gather_ps(base, index, sizeof(T)));
      else
        return Batch(_mm256_i32gather_epi32(reinterpret_cast<const int*>(base), index, sizeof(T)));
    }
#endif
    alignas(64) std::int32_t at[width<Arch>];
    alignas(64) T values[width<Arch>];
    index.store_aligned(at);
    for (int i = 0; i < width<Arch>; ++i) values[i] = base[at[i]];
    return Batch::load_aligned(values);
  }
}

/// Reads the byte base[index[i]] for each lane, widened to 32 bits (index + 3 must fit an
/// int32). The hardware gathers load the aligned 4-byte words that hold the bytes: such a
/// word never leaves the page of the byte it holds, so no read faults past the array.
template <class Arch>
Int<Arch> gather_bytes(const std::uint8_t* base, const Int<Arch>& index) {
  if constexpr (std::is_same_v<Arch, scalar>) {
    return base[index];
  } else {
#if defined(__AVX2__)
    if constexpr (std::is_base_of_v<xsimd::avx2, Arch> || std::is_base_of_v<xsimd::avx512f, Arch>) {
      using I = Int<Arch>;
      const auto address = reinterpret_cast<std::uintptr_t>(base);
      const auto* words = reinterpret_cast<const std::int32_t*>(address & ~std::uintptr_t{3});
      const I offset = index + I(static_cast<std::int32_t>(address & 3));
      const I word = gather<Arch>(words, offset >> 2);
      return (word >> ((offset & I(3)) << 3)) & I(0xFF);
    }
#endif
    alignas(64) std::int32_t at[width<Arch>];
    alignas(64) std::int32_t values[width<Arch>];
    index.store_aligned(at);
    for (int i = 0; i < width<Arch>; ++i) values[i] = base[at[i]];
    return Int<Arch>::load_aligned(values);
  }
}

/// Lane indices 0, 1, ..., W-1 as floats.
template <class Arch>
Float<Arch> lane_index() {
  if constexpr (std::is_same_v<Arch, scalar>) {
    return 0.f;
  } else {
    alignas(64) float idx[width<Arch>];
    for (int i = 0; i < width<Arch>; ++i) idx[i] = static_cast<float>(i);
    return Float<Arch>::load_aligned(idx);
  }
}

}  // namespace sciray::simd
