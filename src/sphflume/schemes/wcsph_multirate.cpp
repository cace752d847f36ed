// Multirate time stepping for resolution levels (`resolution.multirate: true`; docs/numerics.md
// §14, issue 42). The time step of a run with levels is the finest level's everywhere, so the
// coarse particles, most of a coastal run, take twice the steps their h needs: a band run of Flume A
// cost 0.44 of the uniform fine run for 0.35 of its particles. Here the slow particles (every level
// but the finest, away from the level interface) take one symplectic step Δ, and the fast ones (the
// finest level, and the particles whose h the interface lowered) two of Δ/2, as the individual
// (block) time steps of Gadget-2 (Springel 2005) and the multiple time stepping of multi-resolution
// SPH (e.g. Zhang et al. 2021's SPHinXsys, fluid-structure): per Δ the rates of every particle at
// t and t + Δ/2, and of the fast ones also at t + Δ/4 and t + 3Δ/4, where the slow neighbours stand
// at their own stage's prediction (their position, velocity and density at that time along the
// symplectic step they are taking). The pairs between a fast and a slow particle then act at
// different times on the two: mass stays exact, momentum to the step's truncation error.
#include <algorithm>
#include <cmath>
#include <vector>

#include "sphflume/boundaries/motion.hpp"
#include "sphflume/boundaries/walls.hpp"
#include "sphflume/physics/porous.hpp"
#include "sphflume/core/refinement.hpp"
#include "sphflume/schemes/wcsph.hpp"
#include "sphflume/schemes/wcsph_common.hpp"

namespace sph {

template <int D>
double WCSPH<D>::multirate_time_step(const System<D>& S) const {
  const double nut = turb_.on() ? turb_.nu_t_max() : 0.0;
  const double slow = explicit_time_step(S, cfg_, nut, max_acc_, level_h(S.h, S.levels - 1));
  const double fast = explicit_time_step(S, cfg_, nut, max_acc_, S.finest_h());
  return std::min(slow, 2.0 * fast);
}

template <int D>
void WCSPH<D>::multirate_step(System<D>& S, double dt) {
  auto& P = S.particles;
  const bool dyn = S.walls->evolves_density();
  const double t0 = S.time, half = 0.5 * dt, quarter = 0.25 * dt;
  // rates at t for every particle
  S.update_neighbours();
  fast_only_ = false;
  rates(S);
  // this step's fast set: the finest level, and every particle whose h the interface lowered
  // below the next-coarser level's by more than the float average's round-off (its CFL limit
  // is then below the slow step)
  {
    auto& fast = P.scalar(field::fast.name);
    const auto& lv = P.require(field::level);
    const auto& hs = P.require(field::smoothing_length);
    const double h_slow = level_h(S.h, S.levels - 1);
    for (std::size_t i = 0; i < P.n_owned(); ++i)
      fast[i] = P.kind[i] == Kind::Fluid && (static_cast<int>(lv[i]) == S.levels || hs[i] < (1.0 - 1e-3) * h_slow) ? 1.0 : 0.0;
  }
  // the store fields of the step, looked up again after every re-sort (a lookup by name per
  // particle was a sixth of the step)
  struct Fields {
    Vec<D>*x0, *v0, *xs;
    double *r0, *fast, *rm, *kr, *im;
  } f{};
  auto fields = [&] {
    f.x0 = P.vector(field::x0.name).data();
    f.v0 = P.vector(field::v0.name).data();
    f.xs = cfg_.xsph > 0.0 ? P.vector(field::xsph).data() : nullptr;
    f.r0 = P.scalar(field::rho0.name).data();
    f.fast = P.scalar(field::fast.name).data();
    f.rm = P.scalar(field::rho_mid.name).data();
    f.kr = S.porous ? P.scalar(field::drag_rate).data() : nullptr;
    f.im = S.porous ? P.scalar(field::inertia).data() : nullptr;
  };
  fields();
  // the point-implicit porous drag of two_stage_step, K/M and 1/M of the particle's last rates
  auto advance = [&](std::size_t i, const Vec<D>& base, double step) {
    if (!f.kr) return base + step * P.acc[i];
    return (1.0 / (1.0 + step * f.kr[i])) * (base + (step * f.im[i]) * P.acc[i]);
  };
  auto symplectic_rho = [&P](std::size_t i, double rho_start, double rho_stage, double step) {
    const double eps = -P.drho[i] / rho_stage * step;
    return rho_start * (2.0 - eps) / (2.0 + eps);
  };
  auto start = [&](bool fast_only) {  // x0, v0, ρ0: the step's start (fast_only: the fast particles' second step)
    for (std::size_t i = 0; i < P.n_owned(); ++i) {
      if (fast_only && f.fast[i] == 0.0) continue;
      f.x0[i] = P.pos[i];
      f.v0[i] = P.vel[i];
      f.r0[i] = P.rho[i];
    }
  };
  // stage 1 (a half step `step` from the start along the start's rates): every particle at t + Δ/4,
  // the fast ones again at t + 3Δ/4, and the slow ones to their mid-step at t + Δ/2
  auto stage1 = [&](std::size_t i, double step) {
    if (P.kind[i] == Kind::Fluid) {
      Vec<D> u = f.v0[i];
      if (f.xs) u += f.xs[i];
      P.pos[i] = f.x0[i] + step * u;
      P.vel[i] = advance(i, f.v0[i], step);
      P.rho[i] = f.r0[i] + step * P.drho[i];
    } else if (P.kind[i] == Kind::Wall && dyn) {
      P.rho[i] = f.r0[i] + step * P.drho[i];
    }
  };
  // stage 2 (the symplectic close with the mid-step rates over `step`)
  auto stage2 = [&](std::size_t i, double step, double rho_stage) {
    if (P.kind[i] != Kind::Fluid && !(P.kind[i] == Kind::Wall && dyn)) return;
    P.rho[i] = symplectic_rho(i, f.r0[i], rho_stage, step);
    if (P.kind[i] != Kind::Fluid) return;
    Vec<D> xcorr{};
    if (f.xs) xcorr = f.xs[i];
    P.vel[i] = advance(i, f.v0[i], step);
    P.pos[i] = f.x0[i] + step * (0.5 * (P.vel[i] + f.v0[i]) + xcorr);
  };
  auto pass = [&](double t, bool fast_only) {
    move_walls(S, t);
    eos_pressure(S);
    S.update_neighbours();
    fast_only_ = fast_only;
    rates(S);
    fast_only_ = false;
    fields();
  };
  start(false);
  // t + Δ/4: every particle along its first stage (the fast ones' first half step, the slow ones'
  // prediction along theirs)
  for (std::size_t i = 0; i < P.n_owned(); ++i) stage1(i, quarter);
  pass(t0 + quarter, true);
  // t + Δ/2: the fast ones close their first step; the slow ones reach their mid-step
  for (std::size_t i = 0; i < P.n_owned(); ++i) {
    if (f.fast[i] != 0.0) stage2(i, half, P.rho[i]);  // (ρ at t + Δ/4: the stage's)
    else stage1(i, half);
  }
  pass(t0 + half, false);  // every particle: the fast ones' start rates, the slow ones' mid-step rates
  for (std::size_t i = 0; i < P.n_owned(); ++i)
    if (f.fast[i] == 0.0) f.rm[i] = P.rho[i];
  start(true);
  // t + 3Δ/4: the fast ones' second first stage; the slow ones predicted along their close
  for (std::size_t i = 0; i < P.n_owned(); ++i) {
    if (f.fast[i] != 0.0) stage1(i, quarter);
    else stage2(i, 3.0 * quarter, f.rm[i]);
  }
  pass(t0 + 3.0 * quarter, true);
  // t + Δ: both close
  for (std::size_t i = 0; i < P.n_owned(); ++i) {
    if (f.fast[i] != 0.0) stage2(i, half, P.rho[i]);  // (ρ at t + 3Δ/4: the stage's)
    else stage2(i, dt, f.rm[i]);
  }
  move_walls(S, t0 + dt);
}

template void WCSPH<2>::multirate_step(System<2>&, double);
template void WCSPH<3>::multirate_step(System<3>&, double);
template double WCSPH<2>::multirate_time_step(const System<2>&) const;
template double WCSPH<3>::multirate_time_step(const System<3>&) const;

}  // namespace sph
