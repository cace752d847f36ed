// Multirate time stepping for resolution levels (`resolution.multirate: true`; schemes/multirate.hpp,
// docs/numerics.md §14, issue 42). The time step of a run with levels is the finest level's everywhere, so the
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
#include "sphflume/physics/resolution.hpp"
#include "sphflume/physics/transport.hpp"
#include "sphflume/schemes/multirate.hpp"
#include "sphflume/schemes/wcsph_common.hpp"

namespace sph {

template <int D>
double MultirateIntegrator<D>::time_step(const System<D>& S, const StepLimit& limit) const {
  const double slow = limit(S.resolution->slow_h(S));
  const double fast = limit(S.resolution->step_h(S));  // (the finest level present)
  return std::min(slow, 2.0 * fast);
}

namespace {

/// The per-particle updates of a multirate step: the symplectic stages of schemes/wcsph.cpp's
/// two_stage_step over a given step from the start state (x0, v0, ρ0), with the store fields
/// looked up again after every re-sort (`look_up`; a lookup by name per particle was a sixth of
/// the step).
template <int D>
class Stages {
 public:
  Stages(System<D>& S, bool xsph, bool dyn) : S_(S), P_(S.particles), xsph_(xsph), dyn_(dyn) { look_up(); }
  void look_up() {
    x0_ = P_.vector(field::x0.name).data();
    v0_ = P_.vector(field::v0.name).data();
    xs_ = xsph_ ? P_.vector(field::xsph).data() : nullptr;
    r0_ = P_.scalar(field::rho0.name).data();
    fast_ = P_.scalar(field::fast.name).data();
    rm_ = P_.scalar(field::rho_mid.name).data();
    kr_ = S_.porous ? P_.scalar(field::drag_rate).data() : nullptr;
    im_ = S_.porous ? P_.scalar(field::inertia).data() : nullptr;
  }
  bool fast(std::size_t i) const { return fast_[i] != 0.0; }
  double& rho_mid(std::size_t i) { return rm_[i]; }
  /// x0, v0, ρ0 from the present state (fast_only: the fast particles' second step)
  void start(bool fast_only) {
    const std::size_t n = P_.n_owned();
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < n; ++i) {
      if (fast_only && !fast(i)) continue;
      x0_[i] = P_.pos[i];
      v0_[i] = P_.vel[i];
      r0_[i] = P_.rho[i];
    }
  }
  /// the first stage: `step` from the start along the start's rates
  void stage1(std::size_t i, double step) {
    if (P_.kind[i] == Kind::Fluid) {
      Vec<D> u = v0_[i];
      if (xs_) u += xs_[i];
      P_.pos[i] = x0_[i] + step * u;
      P_.vel[i] = advance(i, v0_[i], step);
      P_.rho[i] = r0_[i] + step * P_.drho[i];
    } else if (P_.kind[i] == Kind::Wall && dyn_) {
      P_.rho[i] = r0_[i] + step * P_.drho[i];
    }
  }
  /// the symplectic close over `step` with the mid-step rates, ρ_stage the stage's density
  void stage2(std::size_t i, double step, double rho_stage) {
    if (P_.kind[i] != Kind::Fluid && !(P_.kind[i] == Kind::Wall && dyn_)) return;
    const double eps = -P_.drho[i] / rho_stage * step;
    P_.rho[i] = r0_[i] * (2.0 - eps) / (2.0 + eps);
    if (P_.kind[i] != Kind::Fluid) return;
    Vec<D> xcorr{};
    if (xs_) xcorr = xs_[i];
    P_.vel[i] = advance(i, v0_[i], step);
    P_.pos[i] = x0_[i] + step * (0.5 * (P_.vel[i] + v0_[i]) + xcorr);
  }

 private:
  // the point-implicit porous drag of two_stage_step: K/M and 1/M of the particle's last rates
  Vec<D> advance(std::size_t i, const Vec<D>& base, double step) const {
    if (!kr_) return base + step * P_.acc[i];
    return (1.0 / (1.0 + step * kr_[i])) * (base + (step * im_[i]) * P_.acc[i]);
  }
  System<D>& S_;
  ParticleStore<D>& P_;
  bool xsph_, dyn_;
  Vec<D>*x0_ = nullptr, *v0_ = nullptr, *xs_ = nullptr;
  double *r0_ = nullptr, *fast_ = nullptr, *rm_ = nullptr, *kr_ = nullptr, *im_ = nullptr;
};

/// This step's fast set (store field "_fast"): the finest level, and every fluid particle whose
/// h the interface lowered below the next-coarser level's by more than the float average's
/// round-off (its CFL limit is then below the slow step).
template <int D>
bool mark_fast(System<D>& S) {
  auto& P = S.particles;
  auto& fast = P.scalar(field::fast.name);
  const auto& lv = P.require(field::level);
  const auto& hs = P.require(field::smoothing_length);
  const double h_slow = level_h(S.h, S.levels - 1);
  bool any = false;
  const std::size_t n = P.n_owned();
#pragma omp parallel for schedule(static) reduction(|| : any)
  for (std::size_t i = 0; i < n; ++i) {
    fast[i] = P.kind[i] == Kind::Fluid && (static_cast<int>(lv[i]) == S.levels || hs[i] < (1.0 - 1e-3) * h_slow) ? 1.0 : 0.0;
    any = any || fast[i] != 0.0;
  }
  return S.comm->any(any);
}

}  // namespace

template <int D>
void MultirateIntegrator<D>::step(System<D>& S, double dt, const RatesPass& rates) const {
  auto& P = S.particles;
  const double t0 = S.time, half = 0.5 * dt, quarter = 0.25 * dt;
  // (the per-particle stages are independent: each loop runs on the threads, the same bits on any count; the owned
  // count is read again at each loop: a pass's update_neighbours may hand particles to other ranks)
  S.update_neighbours();  // rates at t for every particle
  // h at the particles' places once per step Δ: every pass of the step keeps it (the fast ones move a quarter step
  // between passes, the slow ones less than a tenth of their spacing in the step: h is a smooth field, and both
  // sides of a pair read the same h_ab; bench/README.md, session 45, has the cost of a second average per step).
  S.resolution->smooth_h(S);
  if (S.transport) S.transport->begin_step(S);  // scalars: explicit midpoint over Δ for every particle (as two_stage_step)
  rates(S, false);
  // (no fast particle on any rank, e.g. a refined zone the flow has not reached: the fast-only
  // passes would only cost their fixed work, about 1 ms each on Flume B; the step is then the
  // symplectic step of the slow particles)
  const bool any_fast = mark_fast(S);
  Stages<D> g(S, xsph_, S.walls->evolves_density());
  auto pass = [&](double t, bool fast_only) {
    if (fast_only && !any_fast) return;
    move_walls(S, t);
    eos_pressure(S);
    S.update_neighbours();
    rates(S, fast_only);
    g.look_up();
  };
  g.start(false);
  // t + Δ/4: every particle along its first stage (the fast ones' first half step, the slow
  // ones' prediction along theirs)
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < P.n_owned(); ++i) g.stage1(i, quarter);
  pass(t0 + quarter, true);
  // t + Δ/2: the fast ones close their first step (ρ at t + Δ/4 is their stage's); the slow
  // ones reach their mid-step
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < P.n_owned(); ++i) {
    if (g.fast(i)) g.stage2(i, half, P.rho[i]);
    else g.stage1(i, half);
  }
  // the scalars to t + Δ/2 along the rates at t (the fast passes leave them: WCSPH::rates_pass)
  if (S.transport) S.transport->advance(S, half, false);
  pass(t0 + half, false);  // every particle: the fast ones' start rates, the slow ones' mid-step rates
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < P.n_owned(); ++i)
    if (!g.fast(i)) g.rho_mid(i) = P.rho[i];
  g.start(true);
  // t + 3Δ/4: the fast ones' second first stage; the slow ones predicted along their close
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < P.n_owned(); ++i) {
    if (g.fast(i)) g.stage1(i, quarter);
    else g.stage2(i, 3.0 * quarter, g.rho_mid(i));
  }
  pass(t0 + 3.0 * quarter, true);
  // t + Δ: both close
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < P.n_owned(); ++i) {
    if (g.fast(i)) g.stage2(i, half, P.rho[i]);
    else g.stage2(i, dt, g.rho_mid(i));
  }
  move_walls(S, t0 + dt);
  if (S.transport) S.transport->advance(S, dt, true);  // along the mid-step rates
}

template class MultirateIntegrator<2>;
template class MultirateIntegrator<3>;

}  // namespace sph
