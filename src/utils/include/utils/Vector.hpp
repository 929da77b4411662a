#pragma once
// A small fixed-size 3-vector for the engine's hot loops (trivially copyable,
// no heap, all operations inline).
#include <array>
#include <cmath>
#include <cstddef>

namespace Utils {

template <typename T> struct Vector3 {
  std::array<T, 3> m{};

  constexpr Vector3() = default;
  constexpr Vector3(T x, T y, T z) : m{x, y, z} {}
  constexpr T &operator[](std::size_t i) { return m[i]; }
  constexpr T const &operator[](std::size_t i) const { return m[i]; }
  T *data() { return m.data(); }
  T const *data() const { return m.data(); }
  static constexpr Vector3 broadcast(T v) { return {v, v, v}; }

  constexpr Vector3 &operator+=(Vector3 const &o) {
    m[0] += o[0]; m[1] += o[1]; m[2] += o[2];
    return *this;
  }
  constexpr Vector3 &operator-=(Vector3 const &o) {
    m[0] -= o[0]; m[1] -= o[1]; m[2] -= o[2];
    return *this;
  }
  constexpr Vector3 &operator*=(T s) {
    m[0] *= s; m[1] *= s; m[2] *= s;
    return *this;
  }
  constexpr T norm2() const { return m[0] * m[0] + m[1] * m[1] + m[2] * m[2]; }
  T norm() const { return std::sqrt(norm2()); }
  friend constexpr bool operator==(Vector3 const &, Vector3 const &) = default;
};

using Vector3d = Vector3<double>;
using Vector3i = Vector3<int>;

template <typename T>
constexpr Vector3<T> operator+(Vector3<T> a, Vector3<T> const &b) { return a += b; }
template <typename T>
constexpr Vector3<T> operator-(Vector3<T> a, Vector3<T> const &b) { return a -= b; }
template <typename T> constexpr Vector3<T> operator-(Vector3<T> const &a) {
  return {-a[0], -a[1], -a[2]};
}
template <typename T> constexpr Vector3<T> operator*(T s, Vector3<T> a) { return a *= s; }
template <typename T> constexpr Vector3<T> operator*(Vector3<T> a, T s) { return a *= s; }
template <typename T> constexpr Vector3<T> operator/(Vector3<T> a, T s) {
  return {a[0] / s, a[1] / s, a[2] / s};
}
/** Scalar product. */
template <typename T> constexpr T operator*(Vector3<T> const &a, Vector3<T> const &b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
template <typename T> constexpr Vector3<T> cross(Vector3<T> const &a, Vector3<T> const &b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
template <typename T> constexpr Vector3<T> hadamard(Vector3<T> const &a, Vector3<T> const &b) {
  return {a[0] * b[0], a[1] * b[1], a[2] * b[2]};
}
inline bool isfinite(Vector3d const &a) {
  return std::isfinite(a[0]) && std::isfinite(a[1]) && std::isfinite(a[2]);
}

} // namespace Utils
