// Builds the particles of a case from its shapes: fluid and wall particles on a lattice of
// spacing dx, wall thickness from the kernel support, hydrostatic initial density.
#pragma once
#include <string>

#include "sphflume/core/system.hpp"
#include "sphflume/io/case.hpp"

namespace sph {

struct BuildReport {
  std::size_t fluid = 0, wall = 0;
  std::size_t fluid_dropped_in_walls = 0;  // fluid lattice points that fell inside walls
  int wall_layers = 0;
  double fluid_height = 0.0;  // vertical extent of the fluid
  // porous.relax: points moved, max h |Σ V ∇W| before and after, largest displacement [m]
  std::size_t porous_relax_band = 0;
  double porous_relax_residual0 = 0.0, porous_relax_residual = 0.0, porous_relax_shift = 0.0;
};

/// What build_system refuses before allocating anything (InputError): a geometry that would
/// make more particles, or span more neighbour-search cells (side = the kernel support) over
/// the run's box, than this. The defaults only stop absurd cases (a dx typo); the fuzzer and
/// tests pass smaller limits.
struct BuildLimits {
  double max_particles = 5e8;
  double max_cells = 268435456.0;  // 2^28: 1 GiB of cell starts
};

/// Number of wall layers that covers the kernel support.
int wall_layers_for(const Case& c);

/// Fill S.particles from the case geometry and set kernel, h, EOS, gravity, periodicity.
/// Checks the geometry first (docs/case-file.md, "Errors"): fluid shapes inside the domain,
/// not mostly inside walls, a sane particle count; throws InputError before computing.
template <int D>
BuildReport build_system(const Case& c, System<D>& S, const BuildLimits& limits = {});

}  // namespace sph
