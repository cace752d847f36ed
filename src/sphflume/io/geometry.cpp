#include "sphflume/io/geometry.hpp"

#include <algorithm>
#include <cmath>
#include <map>

#include <fmt/format.h>

namespace sph {
namespace {

template <int D>
Vec<D> to_vec(const std::vector<double>& v) {
  Vec<D> out{};
  for (int d = 0; d < D; ++d) out[d] = v[static_cast<std::size_t>(d)];
  return out;
}

/// Calls f(x) for every lattice point min + (i + 1/2) dx inside [lo, hi).
template <int D, class Fn>
void lattice(const Vec<D>& lo, const Vec<D>& hi, double dx, Fn&& f) {
  long n[D];
  for (int d = 0; d < D; ++d) n[d] = std::max(0L, std::lround(std::floor((hi[d] - lo[d]) / dx + 1e-9)));
  if constexpr (D == 2) {
    for (long k = 0; k < n[1]; ++k)
      for (long i = 0; i < n[0]; ++i) f(Vec<2>{{lo[0] + (i + 0.5) * dx, lo[1] + (k + 0.5) * dx}});
  } else {
    for (long k = 0; k < n[2]; ++k)
      for (long j = 0; j < n[1]; ++j)
        for (long i = 0; i < n[0]; ++i)
          f(Vec<3>{{lo[0] + (i + 0.5) * dx, lo[1] + (j + 0.5) * dx, lo[2] + (k + 0.5) * dx}});
  }
}

bool inside_polygon(const std::vector<std::array<double, 2>>& v, double x, double z) {
  bool in = false;
  for (std::size_t i = 0, j = v.size() - 1; i < v.size(); j = i++) {
    if (((v[i][1] > z) != (v[j][1] > z)) && (x < (v[j][0] - v[i][0]) * (z - v[i][1]) / (v[j][1] - v[i][1]) + v[i][0]))
      in = !in;
  }
  return in;
}

}  // namespace

int wall_layers_for(const Case& c) {
  if (c.walls.layers > 0) return c.walls.layers;
  const double support = kernel_support_factor(c.kernel) * c.h_over_dx;  // in units of dx
  return static_cast<int>(std::ceil(support - 1e-9));
}

template <int D>
BuildReport build_system(const Case& c, System<D>& S) {
  BuildReport rep;
  S.kernel = c.kernel;
  S.dx = c.dx;
  S.h = c.h();
  S.support = kernel_support_factor(c.kernel) * S.h;
  S.nu = c.fluid.viscosity;
  S.gravity = to_vec<D>(c.gravity);
  const int layers = wall_layers_for(c);
  rep.wall_layers = layers;
  const double dx = c.dx;
  const double vol = std::pow(dx, D);
  const double m = c.fluid.density * vol;
  constexpr int vz = D - 1;

  std::vector<Vec<D>> fluid_x, fluid_v, wall_x;
  for (const auto& s : c.shapes) {
    const Vec<D> v0 = to_vec<D>(s.velocity);
    auto emit = [&](const Vec<D>& x) {
      if (s.fill == "fluid") { fluid_x.push_back(x); fluid_v.push_back(v0); }
      else wall_x.push_back(x);
    };
    if (s.type == "box") {
      lattice<D>(to_vec<D>(s.min), to_vec<D>(s.max), dx, emit);
    } else if (s.type == "tank") {
      const Vec<D> lo = to_vec<D>(s.min), hi = to_vec<D>(s.max);
      Vec<D> olo = lo, ohi = hi;
      for (int d = 0; d < D; ++d) { olo[d] -= layers * dx; ohi[d] += layers * dx; }
      if (s.open_top) ohi[vz] = hi[vz];
      lattice<D>(olo, ohi, dx, [&](const Vec<D>& x) {
        bool inner = true;
        for (int d = 0; d < D; ++d) inner &= x[d] > lo[d] && x[d] < hi[d];
        if (!inner) emit(x);
      });
    } else if (s.type == "polygon") {
      if constexpr (D == 2) {
        Vec<2> lo{{1e300, 1e300}}, hi{{-1e300, -1e300}};
        for (const auto& p : s.vertices)
          for (int d = 0; d < 2; ++d) { lo[d] = std::min(lo[d], p[d]); hi[d] = std::max(hi[d], p[d]); }
        // anchor the lattice on the global dx grid so polygons line up with boxes at 0
        for (int d = 0; d < 2; ++d) { lo[d] = std::floor(lo[d] / dx) * dx; hi[d] = std::ceil(hi[d] / dx) * dx; }
        lattice<2>(lo, hi, dx, [&](const Vec<2>& x) { if (inside_polygon(s.vertices, x[0], x[1])) emit(x); });
      }
    } else if (s.type == "plane") {
      Vec<D> nrm = to_vec<D>(s.normal);
      nrm *= 1.0 / norm(nrm);
      const Vec<D> p0 = to_vec<D>(s.point);
      const double thick = s.thickness > 0 ? s.thickness : layers * dx;
      lattice<D>(to_vec<D>(s.min), to_vec<D>(s.max), dx, [&](const Vec<D>& x) {
        const double sd = dot(x - p0, nrm);
        if (sd <= 0.0 && sd > -thick) emit(x);
      });
    }
  }
  if (fluid_x.empty())
    throw InputError(fmt::format("{}: the geometry makes no fluid particles (add a shape with 'fill: fluid' at least "
                                 "dx = {} wide)", c.file, dx));

  // Drop fluid lattice points that fall inside the walls (closer than dx/2 to a wall particle),
  // e.g. a fluid box drawn over a sloping bed.
  std::vector<char> drop(fluid_x.size(), 0);
  if (!wall_x.empty()) {
    CellList<D> wl;
    wl.build(wall_x, wall_x.size(), dx);
    for (std::size_t i = 0; i < fluid_x.size(); ++i)
      wl.for_neighbours(wall_x, fluid_x[i], 0.5 * dx * 0.999, [&](std::uint32_t, const Vec<D>&, double) { drop[i] = 1; });
  }

  if (std::count(drop.begin(), drop.end(), 0) == 0)
    throw InputError(fmt::format("{}: every fluid particle lies inside a wall: move the fluid shapes off the walls", c.file));
  double zmin = 1e300, zmax = -1e300;
  for (std::size_t i = 0; i < fluid_x.size(); ++i)
    if (!drop[i]) { zmin = std::min(zmin, fluid_x[i][vz]); zmax = std::max(zmax, fluid_x[i][vz]); }
  rep.fluid_height = zmax - zmin + dx;

  // Equation of state: c0 = 10 U with U the reference velocity or sqrt(2 g H).
  S.eos.type = c.fluid.eos;
  S.eos.rho0 = c.fluid.density;
  S.eos.gamma = c.fluid.gamma;
  S.eos.background = c.fluid.background_pressure;
  double c0 = c.fluid.sound_speed;
  if (c0 <= 0.0) {
    const double gabs = norm(S.gravity);
    const double U = c.fluid.reference_velocity > 0 ? c.fluid.reference_velocity : std::sqrt(2.0 * gabs * rep.fluid_height);
    if (!(U > 0.0))
      throw InputError(fmt::format("{}: cannot derive the sound speed (no gravity): set fluid.sound_speed, or "
                                   "fluid.reference_velocity (c0 = 10 x it)", c.file));
    c0 = 10.0 * U;
  }
  S.eos.c0 = c0;

  // Hydrostatic initial density: surface = top of the fluid in each lattice column.
  const double gz = -S.gravity[vz];
  std::map<std::vector<long>, double> top;
  auto column = [&](const Vec<D>& x) {
    std::vector<long> k;
    for (int d = 0; d < D - 1; ++d) k.push_back(std::lround(std::floor(x[d] / dx)));
    return k;
  };
  if (c.fluid.hydrostatic_init && gz > 0)
    for (std::size_t i = 0; i < fluid_x.size(); ++i) {
      if (drop[i]) continue;
      auto [it, fresh] = top.emplace(column(fluid_x[i]), fluid_x[i][vz]);
      if (!fresh) it->second = std::max(it->second, fluid_x[i][vz]);
    }

  auto& P = S.particles;
  for (std::size_t i = 0; i < fluid_x.size(); ++i) {
    if (drop[i]) { ++rep.fluid_dropped_in_walls; continue; }
    double rho = c.fluid.density;
    if (c.fluid.hydrostatic_init && gz > 0) {
      const double zs = top[column(fluid_x[i])] + 0.5 * dx;
      rho = S.eos.density(S.eos.background + c.fluid.density * gz * (zs - fluid_x[i][vz]));
    } else if (S.eos.background != 0.0) {
      rho = S.eos.density(S.eos.background);
    }
    P.add(fluid_x[i], fluid_v[i], rho, m, Kind::Fluid);
    ++rep.fluid;
  }
  for (const auto& x : wall_x) {
    P.add(x, Vec<D>{}, S.eos.density(S.eos.background), m, Kind::Wall);
    ++rep.wall;
  }

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
  S.particles.shrink_to_fit();  // particles were appended one by one: drop the growth slack
  return rep;
}

template BuildReport build_system<2>(const Case&, System<2>&);
template BuildReport build_system<3>(const Case&, System<3>&);

}  // namespace sph
