// Two (or more) fluid phases in one weakly-compressible flow (Federico §3.3-3.4, ch. 8 and 9): a
// pollutant lighter than water, or air. Each phase has its own reference density and Tait equation
// of state; with B equal across phases (the thesis's choice) c0_k = c0_w sqrt(γ_k ρ_w / (γ_w ρ_k)).
// Particles carry the store field "phase".
//
// The WCSPH pair loop then uses, per particle, its phase's equation of state and sound speed,
// the Colagrossi–Landrini (2003) forms it already has (continuity ρ_a Σ V_b u_ab·∇W, momentum
// −(1/ρ_a) Σ (p_a + p_b) V_b ∇W: both smooth across density jumps), and restricts δ-SPH
// density diffusion and the Shepard filter to pairs of the same phase (a density jump is no
// error to diffuse).
//
// multiphase.formulation: grenier switches to Grenier et al. (2009), Federico's System 4 (§3.3-3.4):
// Γ_a = Σ_b V_b W_ab over all particles (< 1 near the free surface) and the pressure gradient
// Σ_b (p_a/Γ_a + p_b/Γ_b) ∇_a W V_b (eq 3.26). The density: eq 3.24 (a per-phase Shepard sum
// with V = m/ρ) is a fixed point of any uniform compression, so by itself it cannot evolve the
// density; the density is evolved by continuity and eq 3.24 is applied as the per-phase
// Shepard re-initialisation (scheme.shepard_every).
// multiphase.chi adds the interface term (3.35) with the 1/ρ_a it lacks and its sign reversed, so
// that it repels as the thesis's text intends (docs/numerics.md, Errata):
// −(χ/ρ_a) Σ_{b∉X} (|p_a|/Γ_a + |p_b|/Γ_b) ∇_a W V_b (Γ = 1 in the Colagrossi–Landrini formulation).
#pragma once
#include "sphflume/core/system.hpp"
#include "sphflume/core/config.hpp"

namespace sph {

/// Assign the phases of the case's `multiphase:` regions to the fluid particles in them: their
/// mass, and their density at the water's (hydrostatic) pressure from their own equation of state.
template <int D>
void setup_phases(const Case& c, System<D>& S);

/// Grenier's Γ at the current positions (cell list and images up to date) into the store
/// field "_gamma"; the images are refreshed afterwards.
template <int D>
void grenier_gamma(System<D>& S);

}  // namespace sph
