// The dual-criteria Riemann scheme (schemes/dual.hpp), one step as Zhang, Zhang & Hu (2020):
// every advection step (advection_cfl h / max(U, |u|, sqrt(4 h |a|)), U = c0/10) the density is
// re-initialised by summation, at least ρ0; inside it, acoustic steps of cfl h/(c + |u|) (0.6)
//   ρ += Δt/2 Dρ,  x += Δt/2 u,  [pass A]  u += Δt a,  x += Δt/2 u,  [pass B]  ρ += Δt/2 Dρ
// (position Verlet, symplectic for the acoustic system); the passes are in dual_passes.cpp.
#include "sphflume/schemes/dual.hpp"

#include <algorithm>
#include <cmath>

#include "sphflume/boundaries/walls.hpp"
#include "sphflume/physics/force_terms.hpp"
#include "sphflume/physics/resolution.hpp"
#include "sphflume/schemes/wcsph_common.hpp"

namespace sph {

template <int D>
void DualWCSPH<D>::initialise(System<D>& S) {
  S.update_neighbours();
  if (S.resolution) S.resolution->smooth_h(S);  // (resolution levels: h at the particles' places)
  if (cfg_.density_reinit) reinit_density(S);
  eos_pressure(S);
  // the continuity pass at t = 0: Dρ and the dissipation the first kick adds
  riemann_pass(S, 1);
  adv_left_ = 0.0;  // the first step opens an advection step
}

template <int D>
void DualWCSPH<D>::reinit_density(System<D>& S) {
  // ρ = max(ρ0 Σ W / σ0, ρ0) of every fluid particle, from the current neighbours
  riemann_pass(S, 2);
}

template <int D>
void DualWCSPH<D>::step(System<D>& S, double dt) {
  auto& P = S.particles;
  const std::size_t n = P.n_owned();
  const double hdt = 0.5 * dt;
  const bool kept = cfg_.pairs_per_advection;
  if (adv_left_ <= 0.0) {  // a new advection step: summation density, its length
    if (kept) {  // pairs: advection — the cells at the step's start, its pairs and their summation density
      S.update_neighbours();
      find_pairs(S, true);
    } else if (cfg_.density_reinit) {
      S.refresh_halos();  // (images at the positions the last step ended with)
      reinit_density(S);
    }
    double umax2 = 0.0;
#pragma omp parallel for schedule(static) reduction(max : umax2)
    for (std::size_t i = 0; i < n; ++i)
      if (P.kind[i] == Kind::Fluid) umax2 = std::max(umax2, dot(P.vel[i], P.vel[i]));
    umax2 = S.comm->max(umax2);  // (every rank opens the same advection steps)
    const double h = step_h(S);  // (levels: the finest level present's h, as the acoustic step's)
    const double speed = std::sqrt(std::max({umax2, 4.0 * h * S.comm->max(max_acc_), 0.01 * S.eos.c0 * S.eos.c0}));
    adv_left_ += cfg_.advection_cfl * h / speed;
  }
  // half step of density and position, the pressure of the new density (the walls' comes
  // from walls->prepare: the case reader allows only dummy walls with this integrator)
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    if (P.kind[i] != Kind::Fluid) continue;
    P.rho[i] += hdt * P.drho[i];
    P.pos[i] += hdt * P.vel[i];
    P.p[i] = S.eos_of(i).pressure(P.rho[i]);
  }
  // pass A: pressure force and acoustic density dissipation; the kick
  if (kept) {
    // the pairs of the advection step's start (a restart or an output's re-sort in between: found or followed);
    // the cell list stays that of the step's start, for the walls' extrapolation (W < 3e-4 of its peak where a
    // particle that moved 0.25 h into a support from beyond its stencil would count)
    if (!kept_.valid) find_pairs(S, false);
    else if (P.layout() != kept_.layout) follow_resort(S);
    if (!S.walls->prepare_from_pairs(S, kept_.walls)) S.walls->prepare(S, nullptr);
    kept_pass_dispatch(S, 0);
  } else {
    S.update_neighbours();
    if (S.resolution) S.resolution->smooth_h(S);  // (levels: h at the new places; pass B and the next summation keep it)
    S.walls->prepare(S, nullptr);
    riemann_pass(S, 0);
  }
  S.walls->add_forces(S);
  for (auto& f : S.forces) f->add(S);
  // the owned particles after the re-sort: in a distributed run it also handed the particles
  // that crossed into another rank's part to that rank
  const std::size_t na = P.n_owned();
  double amax = 0.0;
#pragma omp parallel for schedule(static) reduction(max : amax)
  for (std::size_t i = 0; i < na; ++i) {
    if (P.kind[i] != Kind::Fluid) continue;
    amax = std::max(amax, dot(P.acc[i], P.acc[i]));
    P.vel[i] += dt * P.acc[i];
    P.pos[i] += hdt * P.vel[i];
  }
  max_acc_ = std::sqrt(amax);
  if (!finite_bits(max_acc_)) check_finite(S);
  const std::uint64_t pairs_a = S.pairs_last_pass;
  // pass B: continuity and the Riemann dissipation of the next kick; the second half of Dρ.
  // It reuses pass A's cell list: since then particles moved by ½Δt|u| < 0.05 h, so a pair can
  // only be missed where W' ~ (δ/h)³ < 1e-4 of its peak, and it is then missed by both particles
  // (the stencils are symmetric and the distance test uses the same positions): momentum stays
  // exact. (Rebuilding here would cost a second, partly serial, re-sort per step.)
  S.refresh_halos();  // images (periodic, other ranks') at the kicked velocities and drifted positions
  if (kept) kept_pass_dispatch(S, 1);
  else riemann_pass(S, 1);
  // the second half of Dρ; gauges and output see the pressure of the step's end
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < na; ++i) {
    if (P.kind[i] != Kind::Fluid) continue;
    P.rho[i] += hdt * P.drho[i];
    P.p[i] = S.eos_of(i).pressure(P.rho[i]);
  }
  S.pairs_last_pass = pairs_a;  // (pass B counts no pairs: it sees the same ones)
  adv_left_ -= dt;
  S.time += dt;
  ++S.step;
}

template <int D>
double DualWCSPH<D>::time_step(const System<D>& S) const {
  // the acoustic step (cfl 0.6 by default); step() opens the advection steps
  return explicit_time_step(S, cfg_, 0.0, max_acc_);
}

template class DualWCSPH<2>;
template class DualWCSPH<3>;

}  // namespace sph
