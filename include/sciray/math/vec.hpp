#pragma once
// Vec3<T> with T = float (one ray) or a packet Float<Arch> (W rays): one definition
// serves the scalar reference path and every ISA.
#include "sciray/simd/packet.hpp"

namespace sciray {

template <class T>
struct Vec3 {
  T x{}, y{}, z{};

  Vec3() = default;
  constexpr Vec3(T x_, T y_, T z_) : x(x_), y(y_), z(z_) {}
  /// Broadcasts a scalar vector into every lane of a packet vector.
  template <class U>
    requires(!std::is_same_v<T, U>)
  explicit Vec3(const Vec3<U>& v) : x(T(v.x)), y(T(v.y)), z(T(v.z)) {}

  T operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
};

using Vec3f = Vec3<float>;

/// (v, v, v).
template <class T>
constexpr Vec3<T> splat(const T& v) {
  return {v, v, v};
}

template <class T>
Vec3<T> operator+(const Vec3<T>& a, const Vec3<T>& b) {
  return {a.x + b.x, a.y + b.y, a.z + b.z};
}
template <class T>
Vec3<T> operator-(const Vec3<T>& a, const Vec3<T>& b) {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}
template <class T>
Vec3<T> operator-(const Vec3<T>& a) {
  return {-a.x, -a.y, -a.z};
}
template <class T>
Vec3<T> operator*(const Vec3<T>& a, const Vec3<T>& b) {
  return {a.x * b.x, a.y * b.y, a.z * b.z};
}
template <class T, class S>
Vec3<T> operator*(const Vec3<T>& a, const S& s) {
  return {a.x * s, a.y * s, a.z * s};
}
template <class T, class S>
Vec3<T> operator*(const S& s, const Vec3<T>& a) {
  return {a.x * s, a.y * s, a.z * s};
}
template <class T, class S>
Vec3<T> operator/(const Vec3<T>& a, const S& s) {
  return a * (T(1) / s);
}
template <class T>
Vec3<T>& operator+=(Vec3<T>& a, const Vec3<T>& b) {
  return a = a + b;
}
template <class T>
bool operator==(const Vec3<T>& a, const Vec3<T>& b)
  requires std::is_same_v<T, float>
{
  return a.x == b.x && a.y == b.y && a.z == b.z;
}

template <class T>
T dot(const Vec3<T>& a, const Vec3<T>& b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
template <class T>
Vec3<T> cross(const Vec3<T>& a, const Vec3<T>& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
template <class T>
T length(const Vec3<T>& a) {
  return simd::sqrt(dot(a, a));
}
template <class T>
Vec3<T> normalize(const Vec3<T>& a) {
  return a * (T(1) / length(a));
}
template <class T>
Vec3<T> min(const Vec3<T>& a, const Vec3<T>& b) {
  return {simd::min(a.x, b.x), simd::min(a.y, b.y), simd::min(a.z, b.z)};
}
template <class T>
Vec3<T> max(const Vec3<T>& a, const Vec3<T>& b) {
  return {simd::max(a.x, b.x), simd::max(a.y, b.y), simd::max(a.z, b.z)};
}
template <class M, class T>
Vec3<T> select(const M& m, const Vec3<T>& a, const Vec3<T>& b) {
  return {simd::select(m, a.x, b.x), simd::select(m, a.y, b.y), simd::select(m, a.z, b.z)};
}

/// Any unit vector perpendicular to the unit vector `n` (Duff et al. 2017, branchless ONB),
/// per lane for packets.
template <class T>
Vec3<T> perpendicular(const Vec3<T>& n) {
  using std::copysign;  // xsimd's for packets, by argument-dependent lookup
  const T sign = copysign(T(1.f), n.z);
  const T a = T(-1.f) / (sign + n.z);
  return {T(1.f) + sign * n.x * n.x * a, sign * n.x * n.y * a, -sign * n.x};
}

}  // namespace sciray
