#include "sphflume/sim/health.hpp"

#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "sphflume/physics/transport.hpp"

namespace sph {

template <int D>
std::string describe_particle(const System<D>& S, std::size_t i) {
  const auto& P = S.particles;
  std::string x = fmt::format("{:.6g}", P.pos[i][0]);
  for (int d = 1; d < D; ++d) x += fmt::format(", {:.6g}", P.pos[i][d]);
  return fmt::format("particle id {} ({}) at ({})", P.id[i], kind_name(P.kind[i]), x);
}

template <int D>
std::optional<std::string> check_health(const System<D>& S, const HealthLimits& lim) {
  const auto& P = S.particles;
  const std::size_t n = P.n_owned();
  // (with several phases, each particle's band is about its own phase's rho0)
  std::size_t first = std::numeric_limits<std::size_t>::max();
  // one phase: a branch-free vector pass first (every step; most find nothing), the search
  // for the first bad particle below only when it found one
  bool suspect = true;
  if (S.phase_eos.empty() && n > 0) {
    const double lo = lim.density_min_ratio * S.eos.rho0, hi = lim.density_max_ratio * S.eos.rho0;
    const double* __restrict rho = P.rho.data();
    const double* __restrict prs = P.p.data();
    const double* __restrict x = P.pos[0].c.data();
    const double* __restrict v = P.vel[0].c.data();
    const Kind* __restrict kind = P.kind.data();
    int bad = 0;
#pragma omp parallel for schedule(static) reduction(| : bad)
    for (std::size_t i = 0; i < n; ++i) {
      int ok = std::isfinite(rho[i]) & std::isfinite(prs[i]);
      for (int d = 0; d < D; ++d) ok &= std::isfinite(x[D * i + d]) & std::isfinite(v[D * i + d]);
      ok &= (kind[i] != Kind::Fluid) | ((rho[i] >= lo) & (rho[i] <= hi));
      bad |= ok ^ 1;
    }
    suspect = bad != 0;
  }
#pragma omp parallel for schedule(static) reduction(min : first) if (suspect)
  for (std::size_t i = 0; i < (suspect ? n : 0); ++i) {
    bool ok = std::isfinite(P.rho[i]) && std::isfinite(P.p[i]);
    for (int d = 0; d < D; ++d) ok = ok && std::isfinite(P.pos[i][d]) && std::isfinite(P.vel[i][d]);
    const double r0 = S.eos_of(i).rho0;
    if (P.kind[i] == Kind::Fluid) ok = ok && P.rho[i] >= lim.density_min_ratio * r0 && P.rho[i] <= lim.density_max_ratio * r0;
    if (!ok) first = std::min(first, i);
  }
  if (first == std::numeric_limits<std::size_t>::max()) {
    // transported scalars: every value finite
    if (S.transport)
      for (std::size_t k = 0; k < S.transport->count(); ++k) {
        const auto* C = P.find_scalar(S.transport->name(k));
        if (!C) continue;
        for (std::size_t j = 0; j < n; ++j)
          if (!std::isfinite((*C)[j]))
            return fmt::format("at step {}, t = {:.9g} s: {} has a non-finite {} ({}); likely cause: a time step too "
                               "large for the diffusion or reaction (lower scheme.viscous_coefficient), or a "
                               "non-finite initial or inflow value",
                               S.step, S.time, describe_particle(S, j), S.transport->name(k), (*C)[j]);
      }
    return std::nullopt;
  }
  const std::size_t i = first;
  bool finite = std::isfinite(P.rho[i]) && std::isfinite(P.p[i]);
  for (int d = 0; d < D; ++d) finite = finite && std::isfinite(P.pos[i][d]) && std::isfinite(P.vel[i][d]);
  const double rho0 = S.eos_of(i).rho0, rhi = lim.density_max_ratio * rho0;
  std::string what, cause;
  if (!finite) {
    what = fmt::format("a non-finite value (density {}, pressure {}, velocity {}{})", P.rho[i], P.p[i], P.vel[i][0],
                       D == 3 ? fmt::format(", {}, {}", P.vel[i][1], P.vel[i][2]) : fmt::format(", {}", P.vel[i][1]));
    cause = lim.causes ? lim.causes
                       : "a time step too large for the forces (lower scheme.cfl), a sound speed too small for the flow "
                         "(raise fluid.sound_speed or fluid.reference_velocity), or particles penetrating a wall";
  } else if (P.rho[i] > rhi) {
    what = fmt::format("density {:.6g} kg/m3 = {:.4g} x rho0, above the sane band [{}, {}] x rho0", P.rho[i],
                       P.rho[i] / rho0, lim.density_min_ratio, lim.density_max_ratio);
    cause = "compression far beyond weak compressibility: the sound speed is too small for the flow speed (raise "
            "fluid.sound_speed or fluid.reference_velocity), the time step too large (lower scheme.cfl), or "
            "particles pressed into a wall";
  } else {
    what = fmt::format("density {:.6g} kg/m3 = {:.4g} x rho0, below the sane band [{}, {}] x rho0", P.rho[i],
                       P.rho[i] / rho0, lim.density_min_ratio, lim.density_max_ratio);
    cause = "strong tension (particles pulled apart: tensile instability, a fluid region torn open), or a time "
            "step too large (lower scheme.cfl)";
  }
  return fmt::format("at step {}, t = {:.9g} s: {} has {}; likely cause: {}", S.step, S.time, describe_particle(S, i),
                     what, cause);
}

template <int D>
std::size_t fastest_accelerating(const System<D>& S) {
  const auto& P = S.particles;
  std::size_t best = 0;
  double amax = -1.0;
  for (std::size_t i = 0; i < P.n_owned(); ++i) {
    if (P.kind[i] != Kind::Fluid) continue;
    const double a = dot(P.acc[i], P.acc[i]);
    if (a > amax) { amax = a; best = i; }
  }
  return best;
}

template std::optional<std::string> check_health<2>(const System<2>&, const HealthLimits&);
template std::optional<std::string> check_health<3>(const System<3>&, const HealthLimits&);
template std::string describe_particle<2>(const System<2>&, std::size_t);
template std::string describe_particle<3>(const System<3>&, std::size_t);
template std::size_t fastest_accelerating<2>(const System<2>&);
template std::size_t fastest_accelerating<3>(const System<3>&);

}  // namespace sph
