// Particle shifting (Lind et al. 2012, with Skillen et al. 2013's diffusion coefficient): after
// the step's advection each fluid particle moves down the gradient of the particle concentration,
//   δr_a = −A h |u_a| Δt ∇C_a,   ∇C_a = Σ_b V_b ∇_a W_ab   (fluid, wall and open-boundary b),
// which keeps the particle set near-uniform in sheared flows. Without it the disordered set of a
// long shear flow carries part of the shear through its pressure forces (validation/rough_bed:
// 43 % of the stress above the roughness after 20 s). At the free surface, where the
// concentration falls by construction, particles are not shifted: a particle whose position
// divergence ∇·r_a = −Σ_b V_b r_ab·∇_a W_ab is below `surface` (DualSPHysics' free-surface
// threshold: 1.5 in 2D, 2.75 in 3D, against D inside the fluid) keeps its place, and one with
// such a particle within its support moves only along the surface (the component along the
// surface particles' mean outward normal −∇C/|∇C| is removed, Lind et al. 2012): otherwise the
// second row, whose ∇C points inwards, would be pushed into the first. With resolution levels
// (docs/numerics.md §14) the pairs take h_ab = (h_a + h_b)/2 and each particle its own h in D. Shared by the schemes:
// they call compute() with the neighbour lists of the state being advanced and apply() after it.
#pragma once
#include <vector>

#include "sphflume/core/config.hpp"  // ShiftingConfig
#include "sphflume/core/vec.hpp"

namespace sph {

template <int D>
struct System;

template <int D>
class Shifting {
 public:
  explicit Shifting(const ShiftingConfig& c) : cfg_(c) {}
  bool on() const { return cfg_.on(); }
  /// Displacements δr of the owned fluid particles for a step dt, from the current positions
  /// and neighbour lists (S.cells valid for S.particles.pos); zero for other kinds.
  /// Stored in the particle field "shift", so that they follow the store's re-sorting.
  void compute(System<D>& S, double dt);
  /// The same (the velocity-scaled form) with ∇C (D per owned particle) and ∇·r of the owned particles given, as a
  /// scheme has just summed them at these positions (ProjectionISPH's moments, over the fluid and wet walls): the
  /// first pass skipped. The constant form, or null arrays, compute them as compute(S, dt) does.
  void compute(System<D>& S, double dt, const double* gc, const double* divr);
  /// Adds the displacements compute() found to the positions.
  void apply(System<D>& S) const;
  /// Lind et al. (2012)'s form (ShiftingConfig::constant): a constant diffusion coefficient D = coefficient h²,
  /// the anti-clustering term, the normal component removed near the surface, the shift capped.
  void compute_constant(System<D>& S);
  /// The constant form's coefficient D/h² for the case's kernel on its lattice: 1.5/(λ h²), λ the stiffest
  /// displacement mode's rate (lattice_shift_rate in shifting.cpp), which that mode then halves, sign flipped,
  /// each step (stable up to 2/(λ h²)): 0.382 for Wendland C2 at h/dx 1.5, 0.296 at 1.3, 0.508 at 2.0.
  double stable_coefficient(const System<D>& S) const;
  /// The coefficient D/h² in use (the constant form).
  double coefficient() const { return cfg_.automatic ? auto_coefficient_ : cfg_.coefficient; }

 private:
  ShiftingConfig cfg_;
  double auto_coefficient_ = 0.0;
  void displace(System<D>& S, double dt);  // the velocity-scaled form's second pass, from gc_ and at_surface_
  std::vector<Vec<D>> gc_;       // ∇C per particle (images included)
  std::vector<char> at_surface_;  // ∇·r below the threshold
  std::vector<double> divr_;      // ∇·r per particle (both forms)
  std::vector<char> near_cells_;  // cells within one cell of a surface particle's
};

}  // namespace sph
