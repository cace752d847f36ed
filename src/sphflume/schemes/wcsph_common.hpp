// What the weakly-compressible schemes (schemes/wcsph.hpp, schemes/dual.hpp) share: the
// equation of state applied to the owned particles, the explicit time-step rule and the
// non-finite check. Defined once, in wcsph.cpp.
#pragma once
#include "sphflume/core/config.hpp"
#include "sphflume/core/system.hpp"

namespace sph {

/// p = EOS(ρ) of the owned particles; dynamic walls are first clamped to ρ ≥ ρ0 (they push,
/// never pull: SPHysics/DualSPHysics practice).
template <int D>
void eos_pressure(System<D>& S);

/// The smoothing length the explicit step follows: S.h for one level; with resolution levels
/// (docs/numerics.md §14) that of the finest level any fluid particle has now, or, where finer
/// wall particles exist, the mean of the two (their pairs' h_ij): a refined region that holds no
/// fluid yet (an impact wall before the surge, a dry swash zone) does not halve the step. The
/// levels present are taken over every rank (a collective call: every rank calls it).
template <int D>
double step_h(const System<D>& S);

/// The explicit step: cfl h/(c_max + |u|_max), the scalars' limit, the viscous limits with ν
/// and ν_t,max, and force_coefficient sqrt(h/|a|_max) (Federico §3.5; docs/numerics.md).
/// h: the smoothing length it follows (0: step_h).
template <int D>
double explicit_time_step(const System<D>& S, const SchemeConfig& cfg, double nu_t_max, double max_acc, double h = 0.0);

/// Throws a SimulationError naming the first owned particle with a non-finite state.
template <int D>
void check_finite(const System<D>& S);

}  // namespace sph
