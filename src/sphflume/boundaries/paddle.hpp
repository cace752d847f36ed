// Paddle laws: the displacement X(t), velocity and acceleration of a piston wave maker
// (a prescribed wall motion, boundaries/motion.hpp). X(t) = 0 for t <= start; every law moves
// the paddle forward (along its direction) from rest.
//  solitary  (Tsurudome §3.5, eqs 3.5.1-3.5.15): the paddle follows the depth-averaged velocity of a
//            permanent-form wave, dX/dt = c η/(h0 + η) at x = X, which for η = H sech²θ gives
//              X(t) = (2ε/β) tanh[β (c t' − X)/2],  ε = H/h0,  c = sqrt(g (h0 + H)),
//            implicit in X and solved by Newton's method (F' = 1 + ε sech²θ > 0):
//              rayleigh: β = sqrt(3ε/(1 + ε))/h0 (Rayleigh/Serre; Guizien & Barthélemy 2002; the
//                        thesis's choice), stroke S = 4 sqrt(H (H + h0)/3)
//              goring:   β = sqrt(3ε)/h0 (Boussinesq; Goring 1978), stroke 4ε/β
//              rayleigh_explicit: the linearised X = (2ε/β) tanh(βct'/2)/(1 + ε(1 − tanh²)),
//                        which the thesis warns moves the paddle too fast early (a too large wave)
//            t' = t − start − t_s with c t_s = 7.6/β + S/2 (θ = −3.8 at the start; the thesis's shift
//            is not given (§3.5, Fig. 3.4), and t_s = 7.6/(β c) alone leaves θ = −3.8 + ε, up to
//            4e-3 c ε of paddle speed at the start), and X
//            shifted by its value at t' = −t_s so that the paddle starts exactly at 0 (0.05 % of S).
//            The explicit law has the same crest time; it then trails the implicit one before the
//            crest and leads after it (the two are odd about t' = 0 with the same peak speed
//            c ε/(1 + ε)), by up to 0.6 % of S at H/h0 = 0.28 (tests/test_paddle.cpp).
//  regular   first-order piston (Biesel transfer function): X = r(t) (S/2) sin ωt,
//            H/S = 2 (cosh 2kh − 1)/(sinh 2kh + 2kh), ω² = g k tanh kh, r the start-up ramp.
//  stokes2   second-order (Madsen 1971): the first-order motion plus
//            r(t) (H²/(32 h0)) (3 cosh kh/sinh³ kh − 2/m1) sin 2ωt, m1 = H/S of the first order,
//            which cancels the free second harmonic a first-order paddle sheds.
//  table     a displacement time series (what a lab hands over): a C1 cubic Hermite curve through
//            the samples (node slopes by central differences), so that the paddle's velocity is
//            continuous and its acceleration bounded; held at its last value after the end
//            (arriving at rest); displacement from the first sample, multiplied by the ramp.
//  irregular, focused, elevation: a sum of linear components, each through the transfer function
//            (boundaries/wave_spectrum.hpp): a JONSWAP or Pierson–Moskowitz sea with seeded random
//            phases, a NewWave group focused at a given place and time, a user's elevation series.
//  absorber  at rest, no wave: with `absorption`, an active absorber at the flume's end.
// second_order: true (regular, irregular, focused, elevation; piston or flap): Schäffer's (1996)
//            sub- and super-harmonic correction X2 with the evanescent modes added to the first-order
//            motion, and the bound second-order waves added to the law's elevation (the absorption's
//            target), both ramped by r² (boundaries/paddle_order2.hpp). `stokes2` is Madsen's (1971)
//            long-wave form of the regular wave's superharmonic (0.60 of Schäffer's at kh = 0.96).
// The ramp: r = (1 − cos(π τ/T_r))/2 for τ = t − start < T_r, 1 after (0: no ramp).
#pragma once
#include <limits>
#include <memory>
#include <vector>

#include "sphflume/boundaries/wave_spectrum.hpp"
#include "sphflume/core/config.hpp"

namespace sph {

class PaddleLaw {
 public:
  virtual ~PaddleLaw() = default;
  /// Displacement along the motion's direction at time t [m].
  virtual double displacement(double t) const = 0;
  /// Velocity [m/s] (analytic where the law allows, else a central difference of X).
  virtual double velocity(double t) const;
  /// Acceleration [m/s²]: a central difference of the velocity.
  double acceleration(double t) const;
  /// The total stroke the law intends (solitary: S; regular: S of the first order; table: max − min;
  /// a sum of components: Σ 2 a_n/m1_n, the bound of its excursion).
  virtual double stroke() const = 0;
  /// The incident wave's elevation a distance x ahead of the paddle's face that the law makes, in
  /// the theory it is built on (the target of active absorption): solitary H sech²θ; regular
  /// (H/2) cos(ωτ − kx) (stokes2 with its bound second harmonic); a sum of components
  /// Σ a_n cos(ω_n τ + φ_n − k_n x); table, given a depth, long-wave theory U(t − x/c) sqrt(h/g);
  /// absorber 0; NaN where the law has none.
  virtual double elevation(double t, double x) const { (void)t; (void)x; return std::numeric_limits<double>::quiet_NaN(); }
  /// The linear components the law is made of (irregular, focused, elevation); empty for the others.
  virtual std::vector<WaveComponent> components() const { return {}; }
};

/// The law of a motion (throws InputError with the case line for a law it cannot build).
std::unique_ptr<PaddleLaw> make_paddle_law(const MotionConfig& m, const std::string& file);

/// Wave number of linear waves of angular frequency ω in depth h: ω² = g k tanh(k h).
double wave_number(double omega, double depth, double g);
/// First-order piston transfer function H/S at relative depth kh.
double piston_transfer(double kh);
/// First-order flap transfer function H/S (S the stroke at the still-water level) for a flap hinged a
/// depth d below the still-water level (d = h: at the bed; the wall below the hinge fixed): from the
/// wavemaker theory's H/S = 4 k sinh kh ∫ f(z) cosh k(h + z) dz / (sinh 2kh + 2kh), f = (z + d)/d above
/// the hinge (Dean & Dalrymple 1991 §6.3; Hughes 1993 §2.3):
///   H/S = 4 sinh kh (sinh kh − (cosh kh − cosh k(h − d))/(kd)) / (sinh 2kh + 2kh).
double flap_transfer(double kh, double d_over_h);
/// The transfer function of the motion's paddle (piston or flap) at kh.
double paddle_transfer(const MotionConfig& m, double kh);

}  // namespace sph
