#include "sphflume/schemes/wcsph.hpp"
#include "sphflume/schemes/wcsph_common.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "sphflume/boundaries/motion.hpp"
#include "sphflume/boundaries/walls.hpp"
#include "sphflume/core/refinement.hpp"
#include "sphflume/physics/force_terms.hpp"
#include "sphflume/physics/multiphase.hpp"
#include "sphflume/physics/porous.hpp"
#include "sphflume/physics/resolution.hpp"
#include "sphflume/physics/transport.hpp"
#include "sphflume/physics/turbulence.hpp"

namespace sph {

template <int D>
void WCSPH<D>::initialise(System<D>& S) {
  eos_pressure(S);
  S.update_neighbours();
  rates(S);
}

template <int D>
void eos_pressure(System<D>& S) {
  auto& P = S.particles;
  const bool dyn = S.walls->evolves_density();
  const std::size_t n = P.n_owned();
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    if (P.kind[i] == Kind::Wall) {
      if (!dyn) continue;
      // dynamic walls must push, never pull (SPHysics/DualSPHysics practice)
      if (P.rho[i] < S.eos.rho0) P.rho[i] = S.eos.rho0;
    }
    P.p[i] = S.eos_of(i).pressure(P.rho[i]);
  }
}

template <int D>
void check_finite(const System<D>& S) {
  const auto& P = S.particles;
  for (std::size_t i = 0; i < P.n_owned(); ++i) {
    bool ok = std::isfinite(P.rho[i]) && std::isfinite(P.p[i]) && std::isfinite(P.drho[i]);
    for (int d = 0; d < D; ++d) ok &= std::isfinite(P.pos[i][d]) && std::isfinite(P.vel[i][d]) && std::isfinite(P.acc[i][d]);
    if (!ok)
      throw SimulationError(fmt::format(
          "non-finite value at step {}, t = {:.6g} s: particle id {} ({}) at position ({:.4g}, {:.4g}{}); "
          "likely causes: time step too large (lower scheme.cfl), sound speed too small for the flow "
          "(raise fluid.sound_speed), or particles penetrating a wall",
          S.step, S.time, P.id[i], kind_name(P.kind[i]), P.pos[i][0], P.pos[i][1],
          D == 3 ? fmt::format(", {:.4g}", P.pos[i][D - 1]) : std::string()));
  }
}

template <int D>
double WCSPH<D>::time_step(const System<D>& S) const {
  if (cfg_.frozen) {  // the scalars' limits only (a long step when nothing diffuses or reacts)
    const double dts = S.transport ? S.transport->time_step(S, cfg_.viscous_coefficient) : 1.0;
    return std::min(dts, 1.0);
  }
  if (multirate_ && S.levels > 0) {
    const double nut = turb_.on() ? turb_.nu_t_max() : 0.0;
    return multirate_->time_step(S, [&](double h) { return explicit_time_step(S, cfg_, nut, max_acc_, h); });
  }
  return explicit_time_step(S, cfg_, turb_.on() ? turb_.nu_t_max() : 0.0, max_acc_);
}

template <int D>
double step_h(const System<D>& S) {
  return S.resolution ? S.resolution->step_h(S) : S.h;  // (the finest level present, physics/resolution.hpp)
}

template <int D>
double explicit_time_step(const System<D>& S, const SchemeConfig& cfg_, double nu_t_max, double max_acc_, double h_step) {
  const auto& P = S.particles;
  double umax2 = 0.0, cmax = S.eos.sound_speed(S.eos.rho0);
  const std::size_t n = P.n_owned();
#pragma omp parallel for schedule(static) reduction(max : umax2, cmax)
  for (std::size_t i = 0; i < n; ++i) {
    if (P.kind[i] != Kind::Fluid) continue;
    umax2 = std::max(umax2, dot(P.vel[i], P.vel[i]));
    cmax = std::max(cmax, S.eos_of(i).sound_speed(P.rho[i]));
  }
  for (const auto& e : S.phase_eos) cmax = std::max(cmax, e.c0);
  const double h = h_step > 0.0 ? h_step : step_h(S);  // (one level: S.h)
  double dt = cfg_.cfl * h / (cmax + std::sqrt(umax2));
  if (S.transport) dt = std::min(dt, S.transport->time_step(S, cfg_.viscous_coefficient));
  if (cfg_.viscosity == ViscosityModel::Laminar && S.nu > 0.0)
    dt = std::min(dt, cfg_.viscous_coefficient * h * h / S.nu);
  if (nu_t_max > 0.0) dt = std::min(dt, cfg_.viscous_coefficient * h * h / (S.nu + nu_t_max));
  if (max_acc_ > 0.0) dt = std::min(dt, cfg_.force_coefficient * std::sqrt(h / max_acc_));
  return dt;
}

template <int D>
void WCSPH<D>::frozen_step(System<D>& S, double dt) {
  // the particles stay where they are: explicit midpoint for the scalars alone
  S.update_neighbours();
  if (!S.transport) return;
  S.transport->begin_step(S);
  S.transport->rates(S);
  S.transport->advance(S, 0.5 * dt, false);
  S.refresh_halos();
  S.transport->rates(S);
  S.transport->advance(S, dt, true);
}

template <int D>
void WCSPH<D>::step(System<D>& S, double dt) {
  if (cfg_.frozen) {
    frozen_step(S, dt);
    S.time += dt;
    ++S.step;
    return;
  }
  // shifting: displacements from the state being advanced (its neighbour lists: the Verlet
  // step's are those of its last rates pass; the two-stage steps rebuild theirs first)
  if (shift_.on()) {
    if (cfg_.integrator != Integrator::Verlet) S.update_neighbours();
    shift_.compute(S, dt);
  }
  if (multirate_ && S.levels > 0) multirate_->step(S, dt, [this](System<D>& s, bool fast_only) { rates_pass(s, fast_only, false); });
  else if (cfg_.integrator == Integrator::Verlet) verlet_step(S, dt);
  else two_stage_step(S, dt);
  if (shift_.on()) shift_.apply(S);
  S.periodic.wrap(S.particles);
  S.time += dt;
  ++S.step;
  if (cfg_.shepard_every > 0 && S.step % cfg_.shepard_every == 0) shepard_filter(S);
  eos_pressure(S);
  if (cfg_.integrator == Integrator::Verlet) {
    // the rates of the new state: the next step and its time-step estimate use them
    S.update_neighbours();
    rates(S);
  }
}

template <int D>
void WCSPH<D>::verlet_step(System<D>& S, double dt) {
  // DualSPHysics' Verlet (Monaghan 1989 leapfrog form): one rates evaluation per step,
  //   x^{n+1} = x^n + dt u^n + dt²/2 a^n,  u^{n+1} = u^{n-1} + 2 dt a^n,  ρ^{n+1} = ρ^{n-1} + 2 dt Dρ^n,
  // and every verlet_steps-th step an Euler step (u^{n+1} = u^n + dt a^n, ...) that re-couples
  // the odd and even sequences. acc/drho hold the rates of the current state on entry.
  auto& P = S.particles;
  const std::size_t n = P.n_owned();
  auto& vprev = P.vector(field::v_prev);
  auto& rprev = P.scalar(field::rho_prev);
  const bool dyn = S.walls->evolves_density();
  std::vector<Vec<D>>* xs = cfg_.xsph > 0.0 ? &P.vector(field::xsph) : nullptr;
  const bool euler = !verlet_started_ || (cfg_.verlet_steps > 0 && (S.step + 1) % cfg_.verlet_steps == 0);
  verlet_started_ = true;
  const double dt2 = euler ? dt : 2.0 * dt;
  const double hdt2 = 0.5 * dt * dt;
  // porous drag, point-implicit: u = (u_base + Δt a/M) / (1 + Δt K/M)
  const double* kr = S.porous ? P.scalar(field::drag_rate).data() : nullptr;
  const double* im = S.porous ? P.scalar(field::inertia).data() : nullptr;
  if (S.transport) S.transport->begin_step(S);  // scalars: forward Euler on Y = C/ρ
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    const bool fluid = P.kind[i] == Kind::Fluid;
    if (P.kind[i] == Kind::Inflow || P.kind[i] == Kind::Outflow) {
      P.pos[i] += dt * P.vel[i];  // open-boundary particles move with their imposed velocity
      // their imposed state is also their previous one: an inflow particle that becomes fluid
      // starts its leapfrog from it (a new particle has no previous state of its own)
      vprev[i] = P.vel[i];
      rprev[i] = P.rho[i];
      continue;
    }
    if (!fluid && !(P.kind[i] == Kind::Wall && dyn)) continue;
    const double r_new = (euler ? P.rho[i] : rprev[i]) + dt2 * P.drho[i];
    rprev[i] = P.rho[i];
    P.rho[i] = r_new;
    if (!fluid) continue;
    const Vec<D> v = P.vel[i];
    Vec<D> u = v;
    if (xs) u += (*xs)[i];
    const Vec<D> vb = euler ? v : vprev[i];
    if (kr) {
      P.vel[i] = (1.0 / (1.0 + dt2 * kr[i])) * (vb + (dt2 * im[i]) * P.acc[i]);
      P.pos[i] += dt * u + (hdt2 / dt2) * (P.vel[i] - vb);  // the acceleration the drag left
    } else {
      P.pos[i] += dt * u + hdt2 * P.acc[i];
      P.vel[i] = vb + dt2 * P.acc[i];
    }
    vprev[i] = v;
  }
  move_walls(S, S.time + dt);  // the walls of the next rates pass (at t + dt)
  if (S.transport) S.transport->advance(S, dt, true);
}

template <int D>
void WCSPH<D>::two_stage_step(System<D>& S, double dt) {
  auto& P = S.particles;
  // stage 1: rates at t^n
  S.update_neighbours();
  rates(S);
  // start-of-step state as store fields: they follow the particles through the re-sort below
  // (the handles' names: the string form keeps this function's code, and its results, as they were)
  auto& x0 = P.vector(field::x0.name);
  auto& v0 = P.vector(field::v0.name);
  auto& rho0 = P.scalar(field::rho0.name);
  const std::size_t n = P.n_owned();
  const bool dyn = S.walls->evolves_density();
  std::vector<Vec<D>>* xs = cfg_.xsph > 0.0 ? &P.vector(field::xsph) : nullptr;
  const double hdt = 0.5 * dt;
  // porous drag, point-implicit: u = (u_base + Δt a/M) / (1 + Δt K/M), K of the stage's state
  // (fields looked up per call: the store re-sorts between the stages)
  auto advance = [&P, por = static_cast<bool>(S.porous)](std::size_t i, const Vec<D>& base, double step,
                                                          const double* kr, const double* im) {
    if (!por) return base + step * P.acc[i];
    return (1.0 / (1.0 + step * kr[i])) * (base + (step * im[i]) * P.acc[i]);
  };
  const double* kr = S.porous ? P.scalar(field::drag_rate).data() : nullptr;
  const double* im = S.porous ? P.scalar(field::inertia).data() : nullptr;
  if (S.transport) S.transport->begin_step(S);  // scalars: explicit midpoint on Y = C/ρ
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    x0[i] = P.pos[i];
    v0[i] = P.vel[i];
    rho0[i] = P.rho[i];
    if (P.kind[i] == Kind::Fluid) {
      Vec<D> u = P.vel[i];
      if (xs) u += (*xs)[i];
      P.pos[i] += hdt * u;
      P.vel[i] = advance(i, P.vel[i], hdt, kr, im);
      P.rho[i] += hdt * P.drho[i];
    } else if (P.kind[i] == Kind::Inflow || P.kind[i] == Kind::Outflow) {
      P.pos[i] += hdt * P.vel[i];  // open-boundary particles move with their imposed velocity
    } else if (P.kind[i] == Kind::Wall && dyn) {
      P.rho[i] += hdt * P.drho[i];
    }
  }
  if (S.transport) S.transport->advance(S, hdt, false);
  move_walls(S, S.time + hdt);
  eos_pressure(S);
  // stage 2: rates at t^{n+1/2}
  S.update_neighbours();
  rates(S);
  const bool symplectic = cfg_.integrator == Integrator::Symplectic;
  kr = S.porous ? P.scalar(field::drag_rate).data() : nullptr;
  im = S.porous ? P.scalar(field::inertia).data() : nullptr;
  // (the owned particles again: in a distributed run the re-sort above also hands particles
  // that crossed into another rank's part to it, with their x0, v0 and rho0)
  const std::size_t n2 = P.n_owned();
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n2; ++i) {
    const bool fluid = P.kind[i] == Kind::Fluid;
    if (P.kind[i] == Kind::Inflow || P.kind[i] == Kind::Outflow) {
      P.pos[i] = x0[i] + dt * P.vel[i];
      continue;
    }
    if (!fluid && !(P.kind[i] == Kind::Wall && dyn)) continue;
    if (symplectic) {
      const double eps = -P.drho[i] / P.rho[i] * dt;
      P.rho[i] = rho0[i] * (2.0 - eps) / (2.0 + eps);
    } else {
      P.rho[i] = rho0[i] + dt * P.drho[i];
    }
    if (!fluid) continue;
    Vec<D> xcorr{};
    if (xs) xcorr = (*xs)[i];
    if (symplectic) {
      P.vel[i] = advance(i, v0[i], dt, kr, im);
      P.pos[i] = x0[i] + dt * (0.5 * (P.vel[i] + v0[i]) + xcorr);
    } else {  // Monaghan predictor-corrector: corrected mid-step, then extrapolate
      const Vec<D> vc = advance(i, v0[i], hdt, kr, im);
      P.pos[i] = x0[i] + dt * (vc + xcorr);
      P.vel[i] = advance(i, v0[i], dt, kr, im);
    }
  }
  move_walls(S, S.time + dt);
  if (S.transport) S.transport->advance(S, dt, true);
}

template <int D>
void WCSPH<D>::shepard_filter(System<D>& S) const {
  S.update_neighbours();
  auto& P = S.particles;
  const std::size_t n = P.n_owned();
  std::vector<double> out(n);
  const double* phi = S.porous ? P.scalar(field::porosity).data() : nullptr;  // volumes m/(φρ)
  const double* phase = S.phase_eos.empty() ? nullptr : P.scalar(field::phase).data();  // within a phase
  // resolution levels: each pair's kernel at h_ab = (h_a + h_b)/2 (docs/numerics.md §14), over the level-0 support
  const double* hs = S.level_h();
  S.with_kernel([&](const auto& K) {
#pragma omp parallel for schedule(static)
    for (std::size_t a = 0; a < n; ++a) {
      out[a] = P.rho[a];
      if (P.kind[a] != Kind::Fluid) continue;
      double num = 0.0, den = 0.0;
      S.cells.for_neighbours(P.pos, P.pos[a], K.support, [&](std::uint32_t b, const Vec<D>&, double r2) {
        if (P.kind[b] != Kind::Fluid || (phase && phase[b] != phase[a])) return;
        const double wk = hs ? K.Wh(std::sqrt(r2), 2.0 / (hs[a] + hs[b])) : K.W(std::sqrt(r2));
        const double w = wk * (phi ? 1.0 / phi[b] : 1.0);
        num += P.mass[b] * w;
        den += P.mass[b] / P.rho[b] * w;
      });
      if (den > 0.0) out[a] = num / den;
    }
  });
  // Verlet keeps the previous density too: shift it by the same correction
  if (P.has(field::rho_prev)) {
    auto& rp = P.scalar(field::rho_prev);
    for (std::size_t a = 0; a < n; ++a) rp[a] += out[a] - P.rho[a];
  }
  if (S.transport) S.transport->rescale(S, out);  // keep each particle's pollutant mass m C/ρ
  for (std::size_t a = 0; a < n; ++a) P.rho[a] = out[a];
}

template class WCSPH<2>;
template class WCSPH<3>;
template void eos_pressure(System<2>&);
template void eos_pressure(System<3>&);
template void check_finite(const System<2>&);
template void check_finite(const System<3>&);
template double step_h(const System<2>&);
template double step_h(const System<3>&);
template double explicit_time_step(const System<2>&, const SchemeConfig&, double, double, double);
template double explicit_time_step(const System<3>&, const SchemeConfig&, double, double, double);


}  // namespace sph
