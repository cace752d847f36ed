// Irregular waves as a sum of linear components (the paddle laws irregular, focused and elevation,
// boundaries/paddle.hpp). Each component n is a progressive linear wave of amplitude a_n,
// angular frequency ω_n, wave number k_n (ω² = g k tanh kh) and phase φ_n, whose elevation at the
// paddle's rest face is a_n cos(ω_n τ + φ_n) (τ = t − start); a piston makes it with the
// displacement (a_n / m1(k_n h)) sin(ω_n τ + φ_n), m1 = H/S the first-order transfer function
// (Biesel; Dean & Dalrymple 1991 §6.3: the progressive wave is in phase with the paddle's velocity).
//
// Spectra (Hz): JONSWAP (Hasselmann et al. 1973; the form of Goda 2000 §2.3)
//   S(f) ∝ f⁻⁵ exp(−1.25 (fp/f)⁴) γ^exp(−(f − fp)²/(2 σ² fp²)),  σ = 0.07 (f ≤ fp), 0.09 (f > fp),
// and Pierson–Moskowitz (γ = 1), scaled so that the discrete components hold Hm0 exactly:
// 4 sqrt(Σ a_n²/2) = Hm0. Frequencies are evenly spaced, f_n = f_min + (n − ½) Δf over
// [f_min, f_max] (default [0.5 fp, 3 fp], which holds 99.0 % of a JONSWAP γ = 3.3 sea's m0, 98.5 % of
// a Pierson–Moskowitz sea's), with the
// deterministic amplitudes a_n = sqrt(2 S(f_n) Δf) and phases uniform in [0, 2π) from a seeded
// 64-bit Mersenne twister (the same sea on every machine). The sea repeats after 1/Δf: the default
// number of components makes that 200 peak periods (a longer run gets a warning).
// Focused group (NewWave, Tromans et al. 1991): a_n = A S(f_n)Δf / Σ S Δf and φ_n = k_n x_f − ω_n t_f,
// so that every crest meets at the focus x_f at τ = t_f with the linear crest A.
// Elevation series: the user's η(t) at the paddle, resampled evenly and decomposed by a discrete
// Fourier transform over its length; the components in [f_min, f_max] are kept.
#pragma once
#include <cstdint>
#include <vector>

#include "sphflume/core/config.hpp"

namespace sph {

struct WaveComponent {
  double amplitude = 0.0, omega = 0.0, k = 0.0, phase = 0.0;
};

/// The unscaled spectral shape at f [Hz] for peak frequency fp (γ = 1: Pierson–Moskowitz).
double jonswap_shape(double f, double fp, double gamma);

/// The components of a motion of law irregular, focused or elevation (m.depth, m.gravity set).
std::vector<WaveComponent> wave_components(const MotionConfig& m);

/// The band [f_min, f_max] of irregular and focused (default [0.5, 3]/Tp where the case leaves it open).
void spectrum_band(const MotionConfig& m, double& f0, double& f1);

/// The number of components irregular and focused use by default: the sea repeats after 1/Δf =
/// 200 Tp (500 components over the default band), at least 64. It does not depend on the run's
/// length, so a restart with a later time.end goes on with the same sea.
int default_components(const MotionConfig& m);

/// A uniform double in [0, 1) from a 64-bit Mersenne twister (53 bits; portable, unlike
/// std::uniform_real_distribution).
double uniform01(std::uint64_t word);

}  // namespace sph
