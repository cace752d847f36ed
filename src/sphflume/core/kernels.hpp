// Smoothing kernels. Each kernel gives W(r) and F(r) = W'(r)/r, so that
// grad_a W_ab = F(r_ab) * (r_a - r_b). h is the smoothing length; the support radius is
// support_factor * h. Normalisations are the standard ones (see shared/spec/federico.md §1.2
// for the thesis's misprints, which are not reproduced here).
#pragma once
#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>
#include <string_view>

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

template <int D>
struct WendlandC2 {
  static constexpr double support_factor = 2.0;
  double h, inv_h, sigma, support, support2;
  explicit WendlandC2(double h_) : h(h_), inv_h(1.0 / h_) {
    sigma = (D == 2) ? 7.0 / (4.0 * std::numbers::pi * h * h) : 21.0 / (16.0 * std::numbers::pi * h * h * h);
    support = support_factor * h;
    support2 = support * support;
  }
  double W(double r) const {
    const double q = r * inv_h;
    const double t = std::max(1.0 - 0.5 * q, 0.0);
    const double t2 = t * t;
    return sigma * t2 * t2 * (2.0 * q + 1.0);
  }
  /// W'(r)/r
  double F(double r) const {
    // branch-free (vectorises in the pair loops): t = 0 at and beyond the support
    const double t = std::max(1.0 - 0.5 * r * inv_h, 0.0);
    // dW/dq = sigma * (-5 q) (1 - q/2)^3 ; divide by r = q h and multiply by dq/dr = 1/h
    return -5.0 * sigma * t * t * t * inv_h * inv_h;
  }
};

template <int D>
struct CubicSpline {
  static constexpr double support_factor = 2.0;
  double h, inv_h, sigma, support, support2;
  explicit CubicSpline(double h_) : h(h_), inv_h(1.0 / h_) {
    sigma = (D == 2) ? 10.0 / (7.0 * std::numbers::pi * h * h) : 1.0 / (std::numbers::pi * h * h * h);
    support = support_factor * h;
    support2 = support * support;
  }
  double W(double r) const {
    const double q = r * inv_h;
    const double t = std::max(2.0 - q, 0.0);
    return q < 1.0 ? sigma * (1.0 - 1.5 * q * q + 0.75 * q * q * q) : sigma * 0.25 * t * t * t;
  }
  double F(double r) const {
    // branch-free: inner piece sigma (-3 + 9q/4) (the 1/q cancels), outer -3/4 sigma (2-q)^2 / q
    const double q = r * inv_h;
    const double t = std::max(2.0 - q, 0.0);
    const double inner = sigma * (-3.0 + 2.25 * q);
    const double outer = -0.75 * sigma * t * t / std::max(q, 1.0);
    return (q < 1.0 ? inner : outer) * inv_h * inv_h;
  }
};

template <int D>
struct QuinticSpline {
  static constexpr double support_factor = 3.0;
  double h, inv_h, sigma, support, support2;
  explicit QuinticSpline(double h_) : h(h_), inv_h(1.0 / h_) {
    sigma = (D == 2) ? 7.0 / (478.0 * std::numbers::pi * h * h) : 1.0 / (120.0 * std::numbers::pi * h * h * h);
    support = support_factor * h;
    support2 = support * support;
  }
  static double p5(double t) { return t * t * t * t * t; }
  static double p4(double t) { return t * t * t * t; }
  double W(double r) const {
    const double q = r * inv_h;
    const double t3 = std::max(3.0 - q, 0.0), t2 = std::max(2.0 - q, 0.0), t1 = std::max(1.0 - q, 0.0);
    return sigma * (p5(t3) - 6.0 * p5(t2) + 15.0 * p5(t1));
  }
  double F(double r) const {
    // branch-free: dW/dq vanishes at q = 0 exactly (-405 + 480 - 75), so d / max(q, tiny) is 0 there
    const double q = r * inv_h;
    const double t3 = std::max(3.0 - q, 0.0), t2 = std::max(2.0 - q, 0.0), t1 = std::max(1.0 - q, 0.0);
    const double d = -5.0 * p4(t3) + 30.0 * p4(t2) - 75.0 * p4(t1);
    return sigma * d / std::max(q, 1e-12) * inv_h * inv_h;
  }
};

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
