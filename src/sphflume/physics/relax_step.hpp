// One shift of a set-up relaxation (physics/porous.hpp relax_porous_band, physics/resolution.hpp
// relax_level_band): both move a point against Σ_b V_b ∇W_ab until the volumes tile space.
#pragma once
#include "sphflume/core/vec.hpp"

namespace sph {

/// The shift of a point at x (lattice site x0, spacing dx, smoothing length h) for the gradient
/// g = Σ_b V_b ∇W_ab: −0.1 h² g, at most 0.05 dx an iteration, and none that would take the point
/// more than dx/4 from its site (the band needs less; a point that would go further is not in a
/// band the shift can fix).
template <int D>
Vec<D> relax_step(const Vec<D>& g, double h, double dx, const Vec<D>& x, const Vec<D>& x0) {
  Vec<D> step = (-0.1 * h * h) * g;
  const double len = norm(step);
  if (len > 0.05 * dx) step *= 0.05 * dx / len;
  if (norm(x + step - x0) > 0.25 * dx) step = Vec<D>{};
  return step;
}

}  // namespace sph
