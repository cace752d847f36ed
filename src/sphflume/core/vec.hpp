// Small fixed-size vector used for positions, velocities and accelerations.
// 2D runs live in the (x, z) plane: component 0 is x, component D-1 is vertical (z).
#pragma once
#include <array>
#include <cmath>
#include <cstddef>

namespace sph {

template <int D>
struct Vec {
  static_assert(D == 2 || D == 3, "SPHFlume supports 2D and 3D");
  std::array<double, D> c{};

  constexpr double& operator[](int i) { return c[static_cast<std::size_t>(i)]; }
  constexpr double operator[](int i) const { return c[static_cast<std::size_t>(i)]; }

  static constexpr Vec zero() { return Vec{}; }

  constexpr Vec& operator+=(const Vec& o) {
    for (int i = 0; i < D; ++i) c[i] += o.c[i];
    return *this;
  }
  constexpr Vec& operator-=(const Vec& o) {
    for (int i = 0; i < D; ++i) c[i] -= o.c[i];
    return *this;
  }
  constexpr Vec& operator*=(double s) {
    for (int i = 0; i < D; ++i) c[i] *= s;
    return *this;
  }
  friend constexpr Vec operator+(Vec a, const Vec& b) { return a += b; }
  friend constexpr Vec operator-(Vec a, const Vec& b) { return a -= b; }
  friend constexpr Vec operator*(Vec a, double s) { return a *= s; }
  friend constexpr Vec operator*(double s, Vec a) { return a *= s; }
  friend constexpr Vec operator-(Vec a) {
    for (int i = 0; i < D; ++i) a.c[i] = -a.c[i];
    return a;
  }
};

template <int D>
constexpr double dot(const Vec<D>& a, const Vec<D>& b) {
  double s = 0.0;
  for (int i = 0; i < D; ++i) s += a[i] * b[i];
  return s;
}

template <int D>
inline double norm(const Vec<D>& a) { return std::sqrt(dot(a, a)); }

/// Index of the vertical axis (z): 1 in 2D (x, z), 2 in 3D (x, y, z).
template <int D>
constexpr int vertical_axis() { return D - 1; }

}  // namespace sph
