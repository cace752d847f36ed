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
};

/// Number of wall layers that covers the kernel support.
int wall_layers_for(const Case& c);

/// Fill S.particles from the case geometry and set kernel, h, EOS, gravity, periodicity.
template <int D>
BuildReport build_system(const Case& c, System<D>& S);

}  // namespace sph
