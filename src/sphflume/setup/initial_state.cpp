// The initial state of a built system (setup/setup.hpp): the equation of state, the particles with
// their hydrostatic density, the moving walls' fields and periodicity.
#include <algorithm>
#include <cmath>
#include <map>

#include "sphflume/setup/initial_state.hpp"

#include "sphflume/core/refinement.hpp"
#include "sphflume/setup/shape_lattice.hpp"

namespace sph {
using namespace setup_detail;

template <int D>
void relax_porous_interface(const Case& c, System<D>& S, FillPoints<D>& f, BuildReport& rep) {
  if (!S.porous || c.porous.relax_iterations <= 0) return;
  const auto rr = relax_porous_band<D>(*S.porous, c.kernel, S.h, c.dx, f.fluid_x, f.drop, f.wall_x, c.porous.relax_iterations);
  rep.porous_relax_band = rr.band;
  rep.porous_relax_residual0 = rr.residual0;
  rep.porous_relax_residual = rr.residual;
  rep.porous_relax_shift = rr.max_shift;
  if (rr.residual > rr.residual0)
    throw InputError(fmt::format("{}: line {}: 'porous.relax': the relaxation of the porous interface band did not "
                                 "converge (max h |sum V grad W| {:.3g} -> {:.3g}): the band meets a free surface or a "
                                 "thin layer it cannot settle; set porous.relax: 0 (the plain lattice fill)",
                                 c.file, c.porous.line, rr.residual0, rr.residual));
}

template <int D>
void set_eos(const Case& c, System<D>& S, double fluid_height) {
  // Equation of state: c0 = 10 U with U the reference velocity or sqrt(2 g H).
  S.eos.type = c.fluid.eos;
  S.eos.rho0 = c.fluid.density;
  S.eos.gamma = c.fluid.gamma;
  S.eos.background = c.fluid.background_pressure;
  double c0 = c.fluid.sound_speed;
  if (c0 <= 0.0) {
    const double gabs = norm(S.gravity);
    const double U = c.fluid.reference_velocity > 0 ? c.fluid.reference_velocity : std::sqrt(2.0 * gabs * fluid_height);
    if (!(U > 0.0))
      throw InputError(fmt::format("{}: cannot derive the sound speed (no gravity): set fluid.sound_speed, or "
                                   "fluid.reference_velocity (c0 = 10 x it)", c.file));
    c0 = 10.0 * U;
  }
  if (!std::isnormal(c0 * c0) || !std::isnormal(S.eos.B()))
    throw InputError(fmt::format("{}: the sound speed c0 = {:.4g} m/s (fluid.sound_speed, or 10 x fluid.reference_velocity "
                                 "or 10 sqrt(2 |g| H)) gives B = c0^2 rho0 / gamma = {:.4g} Pa: expected values of "
                                 "ordinary size (check gravity, fluid.sound_speed and fluid.gamma)",
                                 c.file, c0, c0 * c0 * c.fluid.density / c.fluid.gamma));
  S.eos.c0 = c0;
}

template <int D>
void add_particles(const Case& c, System<D>& S, const FillPoints<D>& f, BuildReport& rep) {
  const double dx = c.dx;
  const double m = c.fluid.density * std::pow(dx, D);
  constexpr int vz = D - 1;
  // Hydrostatic initial density: surface = top of the fluid in each lattice column.
  const double gz = -S.gravity[vz];
  std::map<std::vector<long>, double> top;
  auto column = [&](const Vec<D>& x) {
    std::vector<long> k;
    for (int d = 0; d < D - 1; ++d) k.push_back(std::lround(std::floor(x[d] / dx)));
    return k;
  };
  if (c.fluid.hydrostatic_init && gz > 0)
    for (std::size_t i = 0; i < f.fluid_x.size(); ++i) {
      if (f.drop[i]) continue;
      auto [it, fresh] = top.emplace(column(f.fluid_x[i]), f.fluid_x[i][vz] + f.fluid_half[i]);
      if (!fresh) it->second = std::max(it->second, f.fluid_x[i][vz] + f.fluid_half[i]);
    }

  auto& P = S.particles;
  P.reserve(P.size() + f.fluid_x.size() + f.wall_x.size());  // (growing by doubling held up to twice the store)
  const double rho_wall = S.eos.density(S.eos.background);
  for (std::size_t i = 0; i < f.fluid_x.size(); ++i) {
    if (f.drop[i]) { ++rep.fluid_dropped_in_walls; continue; }
    double rho = c.fluid.density;
    if (c.fluid.hydrostatic_init && gz > 0) {
      const double zs = top[column(f.fluid_x[i])];
      rho = S.eos.density(S.eos.background + c.fluid.density * gz * (zs - f.fluid_x[i][vz]));
    } else if (S.eos.background != 0.0) {
      rho = rho_wall;
    }
    if (!std::isnormal(rho) || rho < 0 || !std::isnormal(rho * m))
      throw InputError(fmt::format("{}: the initial density of the fluid at {} comes out as {:.4g} kg/m3 (hydrostatic "
                                   "pressure from gravity, fluid.gamma, fluid.background_pressure): expected a positive "
                                   "finite density (check those values, or set fluid.hydrostatic_init: false)",
                                   shape_where(c, f.fluid_shape[i]), f.fluid_x[i][0], rho));
    const int level = f.fluid_level.empty() ? 0 : f.fluid_level[i];
    P.add(f.fluid_x[i], f.fluid_v[i], rho, level_mass<D>(m, level), Kind::Fluid);
    ++rep.fluid;
  }
  const std::size_t first_wall = P.n_owned();
  rep.first_wall = first_wall;
  for (std::size_t i = 0; i < f.wall_x.size(); ++i) {
    P.add(f.wall_x[i], Vec<D>{}, rho_wall, level_mass<D>(m, f.wall_level.empty() ? 0 : f.wall_level[i]), Kind::Wall);
    ++rep.wall;
  }
  if (c.walls.backup && std::count(f.wall_covered.begin(), f.wall_covered.end(), 1) > 0) {  // (fill_shapes)
    auto& cov = P.scalar(field::wall_covered);
    for (std::size_t i = 0; i < f.wall_x.size(); ++i) cov[first_wall + i] = f.wall_covered[i];
  }
  if (c.resolution.on()) {  // resolution levels: each particle's h and level (walls: refine_fill's)
    auto& hs = P.scalar(field::smoothing_length);
    auto& lv = P.scalar(field::level);
    std::size_t k = 0;
    for (std::size_t i = 0; i < f.fluid_x.size(); ++i) {
      if (f.drop[i]) continue;
      const int level = f.fluid_level.empty() ? 0 : f.fluid_level[i];
      hs[k] = level_h(S.h, level);
      lv[k++] = level;
    }
    for (std::size_t i = first_wall; i < P.size(); ++i) {
      const int level = f.wall_level.empty() ? 0 : f.wall_level[i - first_wall];
      hs[i] = level_h(S.h, level);
      lv[i] = level;
    }
  }
  if (!c.motions.empty()) {  // moving walls: the motion of each wall particle and its place at X = 0
    auto& grp = P.scalar(field::motion_group);
    auto& org = P.vector(field::motion_origin);
    P.vector(field::wall_acc);
    for (std::size_t k = 0; k < f.wall_x.size(); ++k) {
      const std::string& mname = c.shapes[f.wall_shape[k]].motion;
      org[first_wall + k] = f.wall_x[k];
      for (std::size_t q = 0; q < c.motions.size(); ++q)
        if (!mname.empty() && c.motions[q].name == mname) grp[first_wall + k] = double(q + 1);
    }
  }
}

template <int D>
void set_periodic(const Case& c, System<D>& S) {
  if (!c.periodic.empty()) {
    S.periodic.lo = to_vec<D>(c.domain_min);
    S.periodic.hi = to_vec<D>(c.domain_max);
    for (int ax : c.periodic) {
      S.periodic.axis[ax] = true;
      if (S.periodic.period(ax) < 2.0 * S.support)
        throw InputError(fmt::format("{}: domain: the periodic length along {} ({:.4g} m) must be at least twice "
                                     "the kernel support ({:.4g} m)", c.file, "xyz"[D == 2 && ax == 1 ? 2 : ax],
                                     S.periodic.period(ax), S.support));
    }
  }
}

#define SPHFLUME_INSTANTIATE(D)                                                               \
  template void relax_porous_interface<D>(const Case&, System<D>&, FillPoints<D>&, BuildReport&); \
  template void set_eos<D>(const Case&, System<D>&, double);                                    \
  template void add_particles<D>(const Case&, System<D>&, const FillPoints<D>&, BuildReport&);   \
  template void set_periodic<D>(const Case&, System<D>&);
SPHFLUME_INSTANTIATE(2)
SPHFLUME_INSTANTIATE(3)
#undef SPHFLUME_INSTANTIATE

}  // namespace sph
