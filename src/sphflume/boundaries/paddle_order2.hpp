// Second-order wave generation (Schäffer 1996, Coastal Eng. 28): the sub- and super-harmonic paddle
// motion that cancels the spurious free waves a first-order paddle sheds, for a piston or a flap,
// with the evanescent modes; and the bound second-order elevation (Longuet-Higgins & Stewart 1960,
// Sharma & Dean 1981) that the incident wave then carries (the target of active absorption).
// The derivation, its four checks and the test values are in docs/design/second_order_paddle/.
//
// First order (boundaries/wave_spectrum.hpp): η1 = Re Σ α_n e^{i(ω_n τ − k_n x)}, α_n = a_n e^{iφ_n},
// made by the displacement at the still-water level X1 = Re Σ X_n e^{iω_n τ}, X_n = −i α_n / c_n, c_n
// the first-order transfer function H/S. Second order:
//   X2 = Re[ Σ_n ½ F⁺_nn X_n² e^{2iω_n τ} + Σ_{n<m} F⁺_nm X_n X_m e^{i(ω_n+ω_m)τ}
//            + Σ_{ω_n>ω_m} F⁻_nm X_n X̄_m e^{i(ω_n−ω_m)τ} ],
// F± the complex transfer of the design notes (F2 there), summed over the progressive mode and J
// evanescent modes of each component (k_j = −iκ_j, ω² = −gκ tan κh); its truncation error falls
// like 1/J, so the sum is extrapolated, 2 F(J) − F(J/2) (J = 20 by default: within 0.1 % of
// J → ∞ for the test waves, tests/test_paddle_order2.cpp). The subharmonic self term (zero
// frequency) is left out, as Schäffer does.
// Evaluation: the components of the linear laws are evenly spaced in ω (ω_n = ω_0 + n Δω), so the
// pair sums collapse onto the sum frequencies 2ω_0 + s Δω and the differences d Δω: a time costs
// 3N complex products, not N² terms.
#pragma once
#include <complex>
#include <limits>
#include <map>
#include <mutex>
#include <vector>

#include "sphflume/boundaries/wave_spectrum.hpp"

namespace sph {

/// The paddle of the second-order theory: depth h, |g|, and a flap's hinge depth below the still-water
/// level (infinity: a piston; h: hinged at the bed; less: hinged above the bed, the wall below it fixed).
struct WavemakerShape {
  double depth = 0.0, gravity = 9.81, hinge_depth = std::numeric_limits<double>::infinity();
};

/// Schäffer's F± for the pair (ω_n, ω_m) (sign +1: sum; −1: difference, ω_n > ω_m) with J evanescent
/// modes (0: progressive modes only), without extrapolation.
std::complex<double> schaffer_transfer(const WavemakerShape& p, double wn, double wm, int sign, int modes);

/// The bound second-order elevation of a pair of progressive waves: η2 = Re[E± α_n α_m^(±) e^{i((ω_n±ω_m)τ − (k_n±k_m)x)}]
/// for a pair n ≠ m (½ E⁺ α_n² for the self term), α^(−) = ᾱ.
std::complex<double> bound_elevation(double depth, double g, double wn, double wm, int sign);

/// X2(τ), its rate and the bound elevation for a sum of evenly spaced components.
class SecondOrderPaddle {
 public:
  /// comps: the linear components; transfer: c_n = H/S of each; modes: J (extrapolated from J/2).
  SecondOrderPaddle(const std::vector<WaveComponent>& comps, const std::vector<double>& transfer, const WavemakerShape& p, int modes);
  /// X2 at τ (no ramp) [m].
  double displacement(double tau) const { return eval(tau, sum_, diff_, false); }
  /// dX2/dτ [m/s].
  double velocity(double tau) const { return eval(tau, sum_, diff_, true); }
  /// The bound second-order elevation a distance x ahead of the paddle [m].
  double elevation(double tau, double x) const;
  /// max |X2| over one repeat period (sampled): the correction's reach [m].
  double excursion() const { return excursion_; }

 private:
  struct Coeffs {
    std::vector<std::complex<double>> sum, diff;  // at 2ω_0 + sΔω (s = 0..2N−2) and dΔω (d = 1..N−1)
  };
  double eval(double tau, const std::vector<std::complex<double>>& sum, const std::vector<std::complex<double>>& diff, bool rate) const;
  std::vector<WaveComponent> comps_;
  double w0_ = 0.0, dw_ = 0.0, depth_ = 0.0, g_ = 9.81, excursion_ = 0.0;
  std::vector<std::complex<double>> sum_, diff_;
  mutable std::mutex mutex_;
  mutable std::map<double, Coeffs> bound_;  // by x
};

}  // namespace sph
