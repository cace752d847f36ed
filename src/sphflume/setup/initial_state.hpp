// The initial state of a built system (setup/initial_state.cpp). Internal to setup/.
#pragma once
#include "sphflume/setup/fill.hpp"
#include "sphflume/setup/setup.hpp"

namespace sph {

/// porous.relax: the fluid points of the porous interface band relaxed towards a uniform kernel sum
/// (physics/porous.hpp, relax_porous_band); refuses a relaxation that does not converge.
template <int D>
void relax_porous_interface(const Case& c, System<D>& S, FillPoints<D>& f, BuildReport& rep);

/// The equation of state; c0 = 10 U with U the reference velocity or sqrt(2 g H), H the fluid's height.
template <int D>
void set_eos(const Case& c, System<D>& S, double fluid_height);

/// The fluid (hydrostatic initial density: surface = the top of the fluid in each lattice column)
/// and wall particles, and the moving walls' fields (motion_group, motion_origin, wall_acc).
template <int D>
void add_particles(const Case& c, System<D>& S, const FillPoints<D>& f, BuildReport& rep);

/// The periodic axes of the case's domain.
template <int D>
void set_periodic(const Case& c, System<D>& S);

}  // namespace sph
