// Schäffer's (1996) second-order paddle correction and the bound waves (issue 59): the transfer
// functions against the values derived and checked four ways in docs/design/second_order_paddle
// (brute force, bound waves, Madsen's limit, the flap term), and the paddle laws that carry them.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <limits>
#include <numbers>
#include <vector>

#include "sphflume/boundaries/paddle.hpp"
#include "sphflume/boundaries/paddle_order2.hpp"
#include "test_helpers.hpp"

using namespace sph;

namespace {

constexpr double kPi = std::numbers::pi, kG = 9.81, kH = 0.4;

WavemakerShape piston() { return WavemakerShape{kH, kG, std::numeric_limits<double>::infinity()}; }

/// G± of the design notes (the stroke per unit elevation amplitudes, 1/m): F = −G c_n c_m (sum), F = G c_n c_m
/// (difference), c the piston's first-order transfer.
std::complex<double> G(double wn, double wm, int sign, int J, double cn, double cm) {
  const auto F = schaffer_transfer(piston(), wn, wm, sign, J);
  return (sign > 0 ? -F : F) / (cn * cm);
}

double c0(double w) { return piston_transfer(wave_number(w, kH, kG) * kH); }

/// The bichromatic test sea of the design notes (§4): h = 0.4, 0.6 and 0.7 Hz, a = 0.01 m, phases 0.
std::vector<WaveComponent> bichromatic() {
  std::vector<WaveComponent> c;
  for (double f : {0.6, 0.7}) c.push_back({0.01, 2 * kPi * f, wave_number(2 * kPi * f, kH, kG), 0.0});
  return c;
}

}  // namespace

// Regular wave h = 0.4, T = 1.5 s (§3): G⁺ = −1.16983i with the progressive mode alone (0.233966 mm of
// stroke sin 2ωt for H = 0.04, the closed form of §3), 0.15574 − 1.91974i with 10 evanescent modes,
// 0.15329 − 1.96704i with 100 (the notes' values to their 5 digits, so 1e-5 absolute).
TEST(PaddleOrder2, RegularPistonMatchesTheNotes) {
  const double w = 2 * kPi / 1.5, c = c0(w);
  EXPECT_NEAR(c, 0.945644, 1e-6);
  const auto g0 = G(w, w, +1, 0, c, c), g10 = G(w, w, +1, 10, c, c), g100 = G(w, w, +1, 100, c, c);
  EXPECT_NEAR(g0.real(), 0.0, 1e-9);
  EXPECT_NEAR(g0.imag(), -1.16983, 1e-5);
  EXPECT_NEAR(g10.real(), 0.15574, 1e-5);
  EXPECT_NEAR(g10.imag(), -1.91974, 1e-5);
  EXPECT_NEAR(g100.real(), 0.15329, 1e-5);
  EXPECT_NEAR(g100.imag(), -1.96704, 1e-5);
  // the stroke: ½ A² G, A = 0.02: J = 0 gives −0.233966 mm · i, i.e. +0.233966 mm sin 2ωt
  EXPECT_NEAR(0.5 * 0.02 * 0.02 * g0.imag() * 1e3, -0.233966, 1e-6);
}

// The law's default, 20 modes extrapolated from 10 (2 F(20) − F(10)), against the notes' J → ∞ stroke
// 0.0306 cos 2ωt + 0.3945 sin 2ωt mm (|X2| = 0.3957 mm): within 0.2 % of |X2| (it reads 0.07 %; 10 modes
// alone are 3 % off, 100 modes 0.3 %).
TEST(PaddleOrder2, ExtrapolatedModesReachTheLimit) {
  const double w = 2 * kPi / 1.5;
  const double k = wave_number(w, kH, kG);
  SecondOrderPaddle p({WaveComponent{0.02, w, k, 0.0}}, {c0(w)}, piston(), 20);
  // X2 = Re[C e^{2iωτ}] = Re C cos − Im C sin: at τ = 0 the cos part, at ωτ = π/4 the −sin part
  const double cpart = p.displacement(0.0) * 1e3, spart = p.displacement(kPi / 4 / w) * 1e3;
  EXPECT_NEAR(cpart, 0.0306, 0.002 * 0.3957);
  EXPECT_NEAR(spart, 0.3945, 0.002 * 0.3957);
  EXPECT_NEAR(p.excursion() * 1e3, 0.3957, 0.002 * 0.3957);
}

// The bichromatic sea (§4): X2 at t = 0, 0.5, 1, 2.5, 7.3 s, summed over the self, sum and difference
// terms through the evenly spaced evaluation, equals the notes' brute-force pair sums: J = 0 to
// 1e-6 mm (their digits), and the extrapolated 20 modes within 0.2 % of the largest |X2| of the J = 100
// row (which is itself up to 0.3 % from J → ∞; the extrapolation reads within 0.06 %).
TEST(PaddleOrder2, BichromaticStrokeMatchesThePairSums) {
  const auto comps = bichromatic();
  std::vector<double> c;
  for (const auto& w : comps) c.push_back(c0(w.omega));
  const double t[] = {0.0, 0.5, 1.0, 2.5, 7.3};
  const double j0[] = {0.0, -1.289585, -1.802415, -3.357238, 3.415041};
  const double j100[] = {0.029638, -1.283981, -1.414955, -2.831192, 2.967750};
  SecondOrderPaddle p0(comps, c, piston(), 0), p20(comps, c, piston(), 20);
  for (int i = 0; i < 5; ++i) {
    EXPECT_NEAR(p0.displacement(t[i]) * 1e3, j0[i], 1e-6) << t[i];
    EXPECT_NEAR(p20.displacement(t[i]) * 1e3, j100[i], 0.002 * 2.97) << t[i];
  }
  // the rate is the derivative of the displacement (central difference, 1e-5 s)
  for (double tt : {0.3, 2.1, 5.9}) {
    const double fd = (p20.displacement(tt + 1e-5) - p20.displacement(tt - 1e-5)) / 2e-5;
    EXPECT_NEAR(p20.velocity(tt), fd, 1e-8) << tt;
  }
}

// The subharmonic's transfer for 0.7 − 0.6 Hz: G⁻ = 0.02047 + 30.38120i with 100 modes (the notes'
// table); the sum's transfer is symmetric in its pair (the pair sums count each once).
TEST(PaddleOrder2, DifferenceTermAndSymmetry) {
  const double w1 = 2 * kPi * 0.6, w2 = 2 * kPi * 0.7;
  const auto gm = G(w2, w1, -1, 100, c0(w2), c0(w1));
  EXPECT_NEAR(gm.real(), 0.02047, 1e-4);
  EXPECT_NEAR(gm.imag(), 30.38120, 1e-4);
  const auto a = schaffer_transfer(piston(), w1, w2, +1, 10), b = schaffer_transfer(piston(), w2, w1, +1, 10);
  EXPECT_NEAR(std::abs(a - b), 0.0, 1e-10 * std::abs(a));
}

// A flap hinged at the bed (§3, l = 0; c_0 = 0.506123): G⁺ = 1.37186i with the progressive mode alone
// and −1.73976 + 3.64245i with 100 modes.
TEST(PaddleOrder2, BottomHingedFlap) {
  const double w = 2 * kPi / 1.5, k = wave_number(w, kH, kG);
  const double c = flap_transfer(k * kH, 1.0);
  EXPECT_NEAR(c, 0.506123, 1e-6);
  const WavemakerShape flap{kH, kG, kH};
  const auto g0 = -schaffer_transfer(flap, w, w, +1, 0) / (c * c);
  const auto g100 = -schaffer_transfer(flap, w, w, +1, 100) / (c * c);
  EXPECT_NEAR(g0.real(), 0.0, 1e-9);
  EXPECT_NEAR(g0.imag(), 1.37186, 1e-5);
  EXPECT_NEAR(g100.real(), -1.73976, 1e-5);
  EXPECT_NEAR(g100.imag(), 3.64245, 1e-5);
}

// The bound waves: the self term ½ E⁺ A² is Stokes' second harmonic (k A²/4) cosh kh (2 + cosh 2kh)/sinh³ kh
// (Dean & Dalrymple 1991 eq. 11.48) to 1e-10, and the difference term equals the closed form of
// Longuet-Higgins & Stewart's set-down for a pair (the Hasselmann-type D of docs/design's boundcheck.py).
TEST(PaddleOrder2, BoundWavesAreStokesAndLonguetHiggins) {
  for (double T : {1.0, 1.5, 3.0}) {
    const double w = 2 * kPi / T, k = wave_number(w, kH, kG), kh = k * kH, A = 0.02;
    const auto e = 0.5 * bound_elevation(kH, kG, w, w, +1) * A * A;
    const double stokes = k * A * A / 4 * std::cosh(kh) * (2 + std::cosh(2 * kh)) / std::pow(std::sinh(kh), 3);
    EXPECT_NEAR(e.real(), stokes, 1e-10 * stokes) << T;
    EXPECT_NEAR(e.imag(), 0.0, 1e-12) << T;
  }
  const double w1 = 2 * kPi * 0.7, w2 = 2 * kPi * 0.6;
  const double k1 = wave_number(w1, kH, kG), k2 = wave_number(w2, kH, kG), kij = k1 - k2, g = kG;
  const double C = (w1 - w2) * (w1 * w1 * w2 * w2 / (g * g) + k1 * k2) -
                   0.5 * (w1 * k2 * k2 / std::pow(std::cosh(k2 * kH), 2) - w2 * k1 * k1 / std::pow(std::cosh(k1 * kH), 2));
  const double D = -g * k1 * k2 / (2 * w1 * w2) + (w1 * w1 - w1 * w2 + w2 * w2) / (2 * g) -
                   C * g * (w1 - w2) / (w1 * w2 * (g * kij * std::tanh(kij * kH) - (w1 - w2) * (w1 - w2)));
  const auto e = bound_elevation(kH, kG, w1, w2, -1);
  EXPECT_NEAR(e.real(), D, 1e-10 * std::abs(D));
  EXPECT_NEAR(e.imag(), 0.0, 1e-12);
}

// The laws: `second_order: true` adds r² X2 to the irregular law's first-order motion (r the ramp), and
// its velocity is the derivative of its displacement; the regular law's correction is the same
// SecondOrderPaddle's for one component; the bound harmonic joins the law's elevation.
TEST(PaddleOrder2, LawsCarryTheCorrection) {
  MotionConfig m = test::wave_motion("irregular", kH, kG);
  m.hm0 = 0.03;
  m.tp = 1.5;
  m.components = 64;
  m.ramp = 3.0;
  const auto first = make_paddle_law(m, "t.yaml");
  m.second_order = true;
  const auto second = make_paddle_law(m, "t.yaml");
  const auto comps = wave_components(m);
  std::vector<double> c;
  for (const auto& w : comps) c.push_back(c0(w.omega));
  const SecondOrderPaddle p(comps, c, piston(), 20);
  for (double t : {1.0, 4.0, 17.3}) {
    const double r = t < 3.0 ? 0.5 * (1 - std::cos(kPi * t / 3.0)) : 1.0;
    EXPECT_NEAR(second->displacement(t) - first->displacement(t), r * r * p.displacement(t), 1e-12) << t;
    const double fd = (second->displacement(t + 1e-5) - second->displacement(t - 1e-5)) / 2e-5;
    EXPECT_NEAR(second->velocity(t), fd, 1e-7) << t;
  }
  EXPECT_GT(p.excursion(), 0.0);
  EXPECT_GT(second->stroke(), first->stroke());
  // regular: the bound harmonic of the elevation is Stokes' (as stokes2's) and the stroke's second harmonic
  // Schäffer's (0.3957 mm for H = 0.04, T = 1.5 in 0.4 m, against Madsen's 0.140 in stokes2)
  MotionConfig r = test::wave_motion("regular", kH, kG);
  r.height = 0.04;
  r.period = 1.5;
  const auto lin = make_paddle_law(r, "t.yaml");
  r.second_order = true;
  const auto sch = make_paddle_law(r, "t.yaml");
  r.second_order = false;
  r.law = "stokes2";
  const auto mad = make_paddle_law(r, "t.yaml");
  double dmax = 0.0, emax = 0.0;
  for (int q = 0; q < 400; ++q) {
    const double t = 10.0 + 1.5 * q / 400.0;
    dmax = std::max(dmax, std::abs(sch->displacement(t) - lin->displacement(t)));
    emax = std::max(emax, std::abs(sch->elevation(t, 0.3) - mad->elevation(t, 0.3)));
  }
  EXPECT_NEAR(dmax * 1e3, 0.3957, 0.002 * 0.3957);
  EXPECT_LT(emax, 1e-9);
}
