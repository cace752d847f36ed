// The particles of a case (setup/setup.hpp): build_system.
#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "sphflume/physics/porous.hpp"
#include "sphflume/physics/resolution.hpp"
#include "sphflume/setup/fill.hpp"
#include "sphflume/setup/initial_state.hpp"
#include "sphflume/setup/setup.hpp"
#include "sphflume/setup/shape_lattice.hpp"

namespace sph {

template <int D>
BuildReport build_system(const Case& c, System<D>& S, const BuildLimits& limits, std::vector<Vec<D>>* wall_surface) {
  BuildReport rep;
  S.kernel = c.kernel;
  S.dx = c.dx;
  S.h = c.h();
  S.support = kernel_support_factor(c.kernel) * S.h;
  S.nu = c.fluid.viscosity;
  S.gravity = setup_detail::to_vec<D>(c.gravity);
  const int layers = wall_layers_for(c);
  rep.wall_layers = layers;
  const double dx = c.dx;
  const double m = c.fluid.density * std::pow(dx, D);
  if (!std::isnormal(m) || !std::isnormal(S.h * S.h) || !std::isnormal(1.0 / (S.support * S.support)))
    throw InputError(fmt::format("{}: 'particles.dx' = {} m with 'fluid.density' = {} kg/m3 gives a particle mass of {:.3g} "
                                 "kg and h = {:.3g} m: expected sizes a double can square and invert (SI units: m, kg/m3)",
                                 c.file, dx, c.fluid.density, m, S.h));
  check_geometry<D>(c, limits, S.support, layers);

  // porous media: the fluid inside a porous region (or a `porous.fill` box) starts on a lattice
  // dx / phi0^(1/D) (Kazemi eq 5.1), so that every particle keeps the mass rho0 dx^D and the
  // volume m / (phi rho)
  if (c.porous.on()) S.porous = std::make_shared<PorousMedia<D>>(c.porous, c.kernel, S.h, dx, c.resolution.max_level());
  FillPoints<D> f = fill_shapes<D>(c, layers, S.porous.get());
  drop_inside_walls<D>(c, f);
  relax_porous_interface<D>(c, S, f, rep);
  refine_fill<D>(c, S.support, f);  // resolution levels (docs/numerics.md §14)
  if (c.resolution.max_level() > 0) {  // the levels' owner (physics/resolution.hpp)
    S.resolution = std::make_shared<Resolution<D>>(c.resolution, c.kernel, S.h, dx);
    S.resolution->attach(S);
  }
  if (S.levels > 0) {
    // (every point scans the level-0 support: 4^l (2D) or 8^l (3D) times a level-0 point's candidates at level l)
    const double reach = S.support / (dx / double(1 << S.levels));
    const double work = double(f.fluid_x.size()) * (D == 2 ? std::numbers::pi * reach * reach : 4.0 / 3.0 * std::numbers::pi * reach * reach * reach) *
                        double(c.resolution.relax_iterations + 2);
    if (!(work <= limits.max_setup_pairs))
      throw InputError(fmt::format("{}: line {}: 'resolution': the level interface's set-up relaxation would evaluate "
                                   "about {:.2g} kernel pairs, over this build's limit of {:.2g}: fewer levels or a "
                                   "smaller resolution.relax", c.file, c.resolution.line, work, limits.max_setup_pairs));
    const auto rr = S.resolution->relax_setup(f.fluid_x, f.fluid_level, f.wall_x);
    rep.levels = S.levels;
    for (const int l : f.fluid_level) rep.refined += l > 0 ? 1 : 0;
    rep.level_relax_band = rr.band;
    rep.level_relax_iterations = rr.iterations;
    rep.level_relax_residual0 = rr.residual0;
    rep.level_relax_residual = rr.residual;
    rep.level_relax_shift = rr.max_shift;
  }
  double zmin = 1e300, zmax = -1e300;
  for (std::size_t i = 0; i < f.fluid_x.size(); ++i)
    if (!f.drop[i]) { zmin = std::min(zmin, f.fluid_x[i][D - 1]); zmax = std::max(zmax, f.fluid_x[i][D - 1]); }
  rep.fluid_height = zmax - zmin + dx;
  if (S.levels > 0) {  // (the points' own half spacings: refined points sit closer to the surface)
    double top = -1e300, bottom = 1e300;
    for (std::size_t i = 0; i < f.fluid_x.size(); ++i)
      if (!f.drop[i]) {
        top = std::max(top, f.fluid_x[i][D - 1] + f.fluid_half[i]);
        bottom = std::min(bottom, f.fluid_x[i][D - 1] - f.fluid_half[i]);
      }
    rep.fluid_height = top - bottom;
  }
  set_eos<D>(c, S, rep.fluid_height);
  add_particles<D>(c, S, f, rep);
  if (wall_surface) *wall_surface = std::move(f.wall_s);
  set_periodic<D>(c, S);
  if (S.porous) S.porous->update(S);  // the initial porosity (snapshots, checks)
  S.particles.shrink_to_fit();  // particles were appended one by one: drop the growth slack
  return rep;
}

template BuildReport build_system<2>(const Case&, System<2>&, const BuildLimits&, std::vector<Vec<2>>*);
template BuildReport build_system<3>(const Case&, System<3>&, const BuildLimits&, std::vector<Vec<3>>*);

}  // namespace sph
