// Two (or more) fluid phases in one weakly-compressible flow (Federico ch. 3.3, 8, 9; digest
// federico.md §2.7-2.8, §7): a pollutant lighter than water, or air. Each phase has its own
// reference density and Tait equation of state; with B equal across phases (the thesis's
// choice) c0_k = c0_w sqrt(γ_k ρ_w / (γ_w ρ_k)). Particles carry the store field "phase".
//
// The WCSPH pair loop then uses, per particle, its phase's equation of state and sound speed,
// the Colagrossi–Landrini (2003) forms it already has (continuity ρ_a Σ V_b u_ab·∇W, momentum
// −(1/ρ_a) Σ (p_a + p_b) V_b ∇W: both smooth across density jumps), and restricts δ-SPH
// density diffusion and the Shepard filter to pairs of the same phase (a density jump is no
// error to diffuse).
#pragma once
#include "sphflume/core/system.hpp"
#include "sphflume/io/case.hpp"

namespace sph {

/// Assign the phases of the case's `multiphase:` regions to the fluid particles in them: their
/// mass, and their density at the water's (hydrostatic) pressure from their own equation of state.
template <int D>
void setup_phases(const Case& c, System<D>& S);

}  // namespace sph
