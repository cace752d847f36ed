// Kernel facts: unit integral (normalisation), gradient = dW/dr (finite differences), odd
// gradient, compact support.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "sphflume/core/kernels.hpp"

using namespace sph;

namespace {
// ∫ W dV in D dimensions by composite Simpson on r in [0, support].
template <int D, class K>
double integral(const K& k) {
  const int n = 20000;
  const double R = k.support, hstep = R / n;
  double s = 0.0;
  for (int i = 0; i <= n; ++i) {
    const double r = i * hstep;
    const double shell = D == 2 ? 2.0 * std::numbers::pi * r : 4.0 * std::numbers::pi * r * r;
    const double w = (i == 0 || i == n) ? 1.0 : (i % 2 ? 4.0 : 2.0);
    s += w * shell * k.W(r);
  }
  return s * hstep / 3.0;
}

template <int D, class K>
void check_kernel(const K& k) {
  EXPECT_NEAR(integral<D>(k), 1.0, 1e-6);
  // F(r) r = dW/dr, checked by central differences away from the origin
  for (double q = 0.05; q < K::support_factor; q += 0.05) {
    const double r = q * k.h, e = 1e-6 * k.h;
    const double fd = (k.W(r + e) - k.W(r - e)) / (2 * e);
    EXPECT_NEAR(k.F(r) * r, fd, 1e-5 * std::abs(k.W(0.0)) / k.h) << "q = " << q;
    EXPECT_LE(k.F(r), 0.0) << "kernel must decrease monotonically, q = " << q;
  }
  EXPECT_EQ(k.W(k.support * 1.0001), 0.0);
  EXPECT_EQ(k.F(k.support * 1.0001), 0.0);
}
}  // namespace

TEST(Kernels, WendlandC2UnitIntegralAndGradient) {
  check_kernel<2>(WendlandC2<2>(0.013));
  check_kernel<3>(WendlandC2<3>(0.013));
}
TEST(Kernels, CubicSplineUnitIntegralAndGradient) {
  check_kernel<2>(CubicSpline<2>(0.7));
  check_kernel<3>(CubicSpline<3>(0.7));
}
TEST(Kernels, QuinticSplineUnitIntegralAndGradient) {
  check_kernel<2>(QuinticSpline<2>(2.0));
  check_kernel<3>(QuinticSpline<3>(2.0));
}

TEST(Kernels, GradientIsOdd) {
  // grad_a W_ab = F(r) (x_a - x_b): swapping a and b flips the sign exactly
  WendlandC2<2> k(1.0);
  const double r = 0.8, F = k.F(r);
  const double ga = F * 0.6, gb = F * -0.6;
  EXPECT_DOUBLE_EQ(ga, -gb);
  EXPECT_LT(F, 0.0);
}
