// The named per-particle fields of the engine (issue 41: typed handles). A field is created by
// the code that owns it, at set-up or on its first step, with ParticleStore::scalar(handle) /
// vector(handle); the others read it with find(handle) (null when absent) or require(handle),
// which names the field when it is missing. A misspelt handle does not compile. Fields named at
// run time (a transported scalar, a stress component) use the string accessors; a string literal
// there is refused by scripts/check_fields.cmake (CTest fields_engine_uses_typed_handles).
#pragma once

namespace sph {

struct ScalarField {
  const char* name;
};
struct VectorField {
  const char* name;
};

namespace field {
// scalars
inline constexpr ScalarField porosity{"porosity"};          // φ (physics/porous)
inline constexpr ScalarField inertia{"inertia"};            // porous added-mass factor
inline constexpr ScalarField drag_rate{"drag_rate"};        // porous drag, applied point-implicitly
inline constexpr ScalarField phase{"phase"};                // phase index (physics/multiphase)
inline constexpr ScalarField rho0{"rho0"};                  // step-start density (two-stage integrators)
inline constexpr ScalarField gamma_grenier{"_gamma"};       // Grenier's Γ (scratch)
inline constexpr ScalarField rho_prev{"rho_prev"};          // the Verlet integrator's ρ(n-1)
inline constexpr ScalarField nu_t{"nu_t"};                  // eddy viscosity (physics/turbulence)
inline constexpr ScalarField free_surface{"free_surface"};  // ISPH's free-surface flag
inline constexpr ScalarField mobility{"_mobility"};         // ISPH scratch
inline constexpr ScalarField psi{"_psi"};                   // ISPH scratch
inline constexpr ScalarField wall_covered{"wall_covered"};  // 1: the wall's face is covered by another (backup skips it)
inline constexpr ScalarField motion_group{"motion_group"};  // 0 fixed, k + 1 the k-th wall motion
inline constexpr ScalarField smoothing_length{"h"};         // per-particle h (resolution levels, core/refinement)
inline constexpr ScalarField level{"level"};                // resolution level: spacing dx / 2^level
inline constexpr ScalarField fast{"_fast"};                 // multirate levels: sub-cycled in this step (scratch)
inline constexpr ScalarField rho_mid{"_rho_mid"};           // multirate levels: a slow particle's mid-step ρ (scratch)
// vectors
inline constexpr VectorField wall_to_surface{"wall_to_surface"};  // wall particle -> its surface point
inline constexpr VectorField wall_normal{"wall_normal"};          // repulsive walls' unit normal
inline constexpr VectorField ghost_mirror{"ghost_mirror"};        // fixed ghosts' interpolation point
inline constexpr VectorField motion_origin{"motion_origin"};      // a moving wall particle at X = 0
inline constexpr VectorField motion_surface0{"motion_surface0"};  // a flap's wall_to_surface at rest
inline constexpr VectorField motion_normal0{"motion_normal0"};    // a flap's wall_normal at rest (repulsive walls)
inline constexpr VectorField wall_acc{"wall_acc"};                // a moving wall particle's acceleration
inline constexpr VectorField xsph{"xsph"};                        // XSPH velocity correction
inline constexpr VectorField x0{"x0"};                            // step-start position
inline constexpr VectorField v0{"v0"};                            // step-start velocity
inline constexpr VectorField v_prev{"v_prev"};                    // the Verlet integrator's u(n-1)
inline constexpr VectorField shift{"shift"};                      // particle shifting displacement
inline constexpr VectorField density_shift{"_density_shift"};     // ISPH split source's shift (scratch)
}  // namespace field

}  // namespace sph
