// Smoothing kernels. Each kernel gives W(r) and F(r) = W'(r)/r, so that
// grad_a W_ab = F(r_ab) * (r_a - r_b). h is the smoothing length; the support radius is
// support_factor * h. Normalisations are the standard ones (Federico §2.2 misprints (2.18) and
// garbles (2.20); neither is reproduced here: docs/numerics.md §2 and Errata).
#pragma once
#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace sph {

enum class KernelType { WendlandC2, CubicSpline, QuinticSpline };

inline KernelType kernel_from_name(std::string_view name) {
  if (name == "wendland_c2") return KernelType::WendlandC2;
  if (name == "cubic_spline") return KernelType::CubicSpline;
  if (name == "quintic_spline") return KernelType::QuinticSpline;
  throw std::invalid_argument("unknown kernel '" + std::string(name) +
                              "' (expected wendland_c2, cubic_spline or quintic_spline)");
}

inline const char* kernel_name(KernelType k) {
  switch (k) {
    case KernelType::WendlandC2: return "wendland_c2";
    case KernelType::CubicSpline: return "cubic_spline";
    case KernelType::QuinticSpline: return "quintic_spline";
  }
  return "?";
}

/// Support radius in units of h.
inline double kernel_support_factor(KernelType k) { return k == KernelType::QuinticSpline ? 3.0 : 2.0; }

/// Sensible range of h/dx for each kernel (enough neighbours, not absurdly many).
inline std::pair<double, double> kernel_h_over_dx_range(KernelType k) {
  switch (k) {
    case KernelType::WendlandC2: return {1.0, 2.5};
    case KernelType::CubicSpline: return {1.0, 2.0};
    case KernelType::QuinticSpline: return {0.8, 1.5};
  }
  return {1.0, 2.0};
}

/// Default h/dx: Wendland 1.5, cubic 1.2 (Kazemi), quintic 1.0. For Wendland C2 the lattice
/// gradient moment -Σ V F z² is 0.974 at h/dx = 1.3 (a 2.6 % weak pressure gradient: the
/// hydrostatic pressure comes out 2.6 % high) and 0.9974 (2D) / 1.0006 (3D) at 1.5.
inline double kernel_default_h_over_dx(KernelType k) {
  switch (k) {
    case KernelType::WendlandC2: return 1.5;
    case KernelType::CubicSpline: return 1.2;
    case KernelType::QuinticSpline: return 1.0;
  }
  return 1.5;
}

/// max and min as value selects: vectorise as vmaxps/blends on every SIMD level (std::max
/// returns a reference, which GCC 12 turned into a branch in AVX2 loops, not in AVX-512 ones)
template <class T> inline T vmax(T a, T b) { return a > b ? a : b; }
template <class T> inline T vmin(T a, T b) { return a < b ? a : b; }

/// x^N for a small N (the kernels' normalisations h^-D and their gradients' h^-(D+2)).
template <int N, class T>
inline T ipow(T x) {
  T p = x;
  for (int i = 1; i < N; ++i) p *= x;
  return p;
}

template <int D>
struct WendlandC2 {
  static constexpr double support_factor = 2.0;
  double h, inv_h, sigma, support, support2, sigma1;  // sigma1: sigma at h = 1 (sigma h^D)
  explicit WendlandC2(double h_) : h(h_), inv_h(1.0 / h_) {
    sigma = (D == 2) ? 7.0 / (4.0 * std::numbers::pi * h * h) : 21.0 / (16.0 * std::numbers::pi * h * h * h);
    support = support_factor * h;
    support2 = support * support;
    sigma1 = sigma * ipow<D>(h);
  }
  // W and F = W'(r)/r are templates on the scalar type (double, or float in the vectorised
  // pair loops) and branch-free: t = 0 at and beyond the support
  template <class T>
  T W(T r) const {
    const T q = r * T(inv_h);
    const T t = vmax(T(1) - T(0.5) * q, T(0));
    const T t2 = t * t;
    return T(sigma) * t2 * t2 * (T(2) * q + T(1));
  }
  /// W'(r)/r: dW/dq = sigma (-5 q) (1 - q/2)^3; divide by r = q h, multiply by dq/dr = 1/h
  template <class T>
  T F(T r) const {
    const T t = vmax(T(1) - T(0.5) * r * T(inv_h), T(0));
    return T(-5.0 * sigma * inv_h * inv_h) * t * t * t;
  }
  /// The same with a per-pair smoothing length, given as ih = 1/h_ij (variable resolution,
  /// docs/numerics.md §14): sigma ∝ h^−D from the unit kernel's; t = 0 beyond the support.
  template <class T>
  T Wh(T r, T ih) const {
    const T q = r * ih;
    const T t = vmax(T(1) - T(0.5) * q, T(0));
    const T t2 = t * t;
    return T(sigma1) * ipow<D>(ih) * t2 * t2 * (T(2) * q + T(1));
  }
  template <class T>
  T Fh(T r, T ih) const {
    const T t = vmax(T(1) - T(0.5) * r * ih, T(0));
    return T(-5.0 * sigma1) * ipow<D + 2>(ih) * t * t * t;
  }
};

template <int D>
struct CubicSpline {
  static constexpr double support_factor = 2.0;
  double h, inv_h, sigma, support, support2, sigma1;  // sigma1: sigma at h = 1 (sigma h^D)
  explicit CubicSpline(double h_) : h(h_), inv_h(1.0 / h_) {
    sigma = (D == 2) ? 10.0 / (7.0 * std::numbers::pi * h * h) : 1.0 / (std::numbers::pi * h * h * h);
    support = support_factor * h;
    support2 = support * support;
    sigma1 = sigma * ipow<D>(h);
  }
  template <class T>
  T W(T r) const {
    const T q = r * T(inv_h);
    const T t = vmax(T(2) - q, T(0));
    return q < T(1) ? T(sigma) * (T(1) - T(1.5) * q * q + T(0.75) * q * q * q) : T(0.25 * sigma) * t * t * t;
  }
  /// branch-free: inner piece sigma (-3 + 9q/4) (the 1/q cancels), outer -3/4 sigma (2-q)^2 / q
  template <class T>
  T F(T r) const {
    const T q = r * T(inv_h);
    const T t = vmax(T(2) - q, T(0));
    const T inner = T(sigma) * (T(-3) + T(2.25) * q);
    const T outer = T(-0.75 * sigma) * t * t / vmax(q, T(1));
    return (q < T(1) ? inner : outer) * T(inv_h * inv_h);
  }
  template <class T>
  T Wh(T r, T ih) const {
    const T q = r * ih;
    const T t = vmax(T(2) - q, T(0));
    const T s = T(sigma1) * ipow<D>(ih);
    return q < T(1) ? s * (T(1) - T(1.5) * q * q + T(0.75) * q * q * q) : T(0.25) * s * t * t * t;
  }
  template <class T>
  T Fh(T r, T ih) const {
    const T q = r * ih;
    const T t = vmax(T(2) - q, T(0));
    const T s = T(sigma1) * ipow<D + 2>(ih);
    const T inner = T(-3) + T(2.25) * q;
    const T outer = T(-0.75) * t * t / vmax(q, T(1));
    return (q < T(1) ? inner : outer) * s;
  }
};

template <int D>
struct QuinticSpline {
  static constexpr double support_factor = 3.0;
  double h, inv_h, sigma, support, support2, sigma1;  // sigma1: sigma at h = 1 (sigma h^D)
  explicit QuinticSpline(double h_) : h(h_), inv_h(1.0 / h_) {
    sigma = (D == 2) ? 7.0 / (478.0 * std::numbers::pi * h * h) : 1.0 / (120.0 * std::numbers::pi * h * h * h);
    support = support_factor * h;
    support2 = support * support;
    sigma1 = sigma * ipow<D>(h);
  }
  template <class T> static T p5(T t) { return t * t * t * t * t; }
  template <class T> static T p4(T t) { return t * t * t * t; }
  template <class T>
  T W(T r) const {
    const T q = r * T(inv_h);
    const T t3 = vmax(T(3) - q, T(0)), t2 = vmax(T(2) - q, T(0)), t1 = vmax(T(1) - q, T(0));
    return T(sigma) * (p5(t3) - T(6) * p5(t2) + T(15) * p5(t1));
  }
  /// branch-free: dW/dq vanishes at q = 0 exactly (-405 + 480 - 75), so d / max(q, tiny) is 0 there
  template <class T>
  T F(T r) const {
    const T q = r * T(inv_h);
    const T t3 = vmax(T(3) - q, T(0)), t2 = vmax(T(2) - q, T(0)), t1 = vmax(T(1) - q, T(0));
    const T d = T(-5) * p4(t3) + T(30) * p4(t2) - T(75) * p4(t1);
    return T(sigma) * d / vmax(q, T(1e-12)) * T(inv_h * inv_h);
  }
  template <class T>
  T Wh(T r, T ih) const {
    const T q = r * ih;
    const T t3 = vmax(T(3) - q, T(0)), t2 = vmax(T(2) - q, T(0)), t1 = vmax(T(1) - q, T(0));
    return T(sigma1) * ipow<D>(ih) * (p5(t3) - T(6) * p5(t2) + T(15) * p5(t1));
  }
  template <class T>
  T Fh(T r, T ih) const {
    const T q = r * ih;
    const T t3 = vmax(T(3) - q, T(0)), t2 = vmax(T(2) - q, T(0)), t1 = vmax(T(1) - q, T(0));
    const T d = T(-5) * p4(t3) + T(30) * p4(t2) - T(75) * p4(t1);
    return T(sigma1) * ipow<D + 2>(ih) * d / vmax(q, T(1e-12));
  }
};

/// Σ W(|x_k|) over a square (cubic) lattice of spacing s, the particle itself included: the
/// number density a full support of particles at rest has (summation densities' reference).
template <int D, class K>
double lattice_kernel_sum(const K& ker, double s) {
  const int nl = static_cast<int>(std::ceil(ker.support / s)) + 1;
  double sum = 0.0;
  for (int a = -nl; a <= nl; ++a)
    for (int b = -nl; b <= nl; ++b)
      for (int e = (D == 3 ? -nl : 0); e <= (D == 3 ? nl : 0); ++e) {
        const double r = s * std::sqrt(double(a * a + b * b + e * e));
        if (r < ker.support) sum += ker.W(r);
      }
  return sum;
}

/// ∇·r = −Σ_k s^D F(|x_k|) |x_k|² of a particle k rows below the free surface of a square (cubic) lattice of
/// spacing s (its neighbours above the top row missing), for k = 0, 1, … until the support is full: how the
/// position divergence sees each row's depth (the ISPH surface's blend band ends below row 1's value,
/// docs/numerics.md §13b).
template <int D, class K>
std::vector<double> lattice_divr_by_depth(const K& ker, double s) {
  const int nl = static_cast<int>(std::ceil(ker.support / s)) + 1;
  std::vector<double> t;
  for (int k = 0; k <= nl; ++k) {
    double sum = 0.0;
    for (int a = -nl; a <= nl; ++a)
      for (int b = -nl; b <= k; ++b)  // b: the vertical offset, ≤ k rows above the particle
        for (int e = (D == 3 ? -nl : 0); e <= (D == 3 ? nl : 0); ++e) {
          const double r = s * std::sqrt(double(a * a + b * b + e * e));
          if (r > 0.0 && r < ker.support) sum -= std::pow(s, D) * ker.F(r) * r * r;
        }
    t.push_back(sum);
  }
  return t;
}

/// Calls f(kernel_object) with the concrete kernel type for this KernelType, so hot loops
/// are compiled once per kernel with no virtual calls.
template <int D, class Fn>
decltype(auto) with_kernel(KernelType k, double h, Fn&& f) {
  switch (k) {
    case KernelType::WendlandC2: return f(WendlandC2<D>(h));
    case KernelType::CubicSpline: return f(CubicSpline<D>(h));
    case KernelType::QuinticSpline: return f(QuinticSpline<D>(h));
  }
  throw std::logic_error("bad kernel type");
}

}  // namespace sph
