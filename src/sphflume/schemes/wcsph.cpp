#include "sphflume/schemes/wcsph.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "sphflume/boundaries/walls.hpp"
#include "sphflume/physics/force_terms.hpp"

namespace sph {

template <int D>
void WCSPH<D>::initialise(System<D>& S) {
  update_pressure(S);
  S.update_neighbours(true);
  rates(S);
}

template <int D>
void WCSPH<D>::update_pressure(System<D>& S) const {
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
    P.p[i] = S.eos.pressure(P.rho[i]);
  }
}

template <int D>
template <class K>
void WCSPH<D>::pair_loop(System<D>& S, const K& ker) {
  auto& P = S.particles;
  const std::size_t n = P.n_owned();
  const bool dyn = S.walls->evolves_density();
  const bool no_slip = S.walls->cfg.no_slip;
  const auto& wall_vel = S.walls->viscous_velocity(S);
  const double h = S.h, eta2 = cfg_.eta2 * h * h, c0 = S.eos.c0, rho0 = S.eos.rho0;
  const bool laminar = cfg_.viscosity == ViscosityModel::Laminar && S.nu > 0.0;
  const bool artificial = cfg_.viscosity == ViscosityModel::Artificial && cfg_.alpha > 0.0;
  const bool diffusion = cfg_.density_diffusion != DensityDiffusion::None && cfg_.delta > 0.0;
  const bool fourtakas = cfg_.density_diffusion == DensityDiffusion::Fourtakas;
  const bool sym_p = cfg_.pressure_gradient == PressureGradient::Symmetric;
  const double dcoef = 2.0 * cfg_.delta * h * c0;
  const double four_nu = 4.0 * S.nu;
  (void)rho0;
  const double alpha = cfg_.alpha;
  const double xsph = cfg_.xsph;
  std::vector<Vec<D>>* xs = xsph > 0.0 ? &P.vector("xsph") : nullptr;
  const Vec<D> g = S.gravity;
  const double support2 = ker.support2;
  std::uint64_t pairs = 0;
  // raw pointers: the loop must not reload vector data through possibly aliasing references
  const Vec<D>* __restrict pos = P.pos.data();
  const Vec<D>* __restrict vel = P.vel.data();
  const Vec<D>* __restrict wvel = wall_vel.data();
  const double* __restrict rho = P.rho.data();
  const double* __restrict prs = P.p.data();
  const double* __restrict mass = P.mass.data();
  const Kind* __restrict kind = P.kind.data();
  const std::uint32_t* __restrict sorted = S.cells.sorted().data();
  Vec<D>* __restrict acc_out = P.acc.data();
  double* __restrict drho_out = P.drho.data();
  Vec<D>* __restrict xs_out = xs ? xs->data() : nullptr;
  const Eos eos = S.eos;
  int overflow = 0;

#pragma omp parallel for schedule(static) reduction(+ : pairs) reduction(max : overflow)
  for (std::size_t a = 0; a < n; ++a) {
    const Kind ka = kind[a];
    if (ka == Kind::Wall && !dyn) { acc_out[a] = Vec<D>{}; drho_out[a] = 0.0; continue; }
    const Vec<D> xa = pos[a], va = vel[a];
    const double rhoa = rho[a], pa = prs[a];
    const double ca = eos.sound_speed(rhoa);
    const double pa_r2 = pa / (rhoa * rhoa);
    const double inv_rhoa = 1.0 / rhoa;
    double drho = 0.0, ddiff = 0.0;
    Vec<D> acc{}, dxs{};
    std::uint64_t np = 0;
    std::uint32_t rg[CellList<D>::kMaxRanges][2];
    const int nr = S.cells.ranges(xa, rg);
    // gather the neighbours first, branch-free (half the candidates are rejected, at random),
    // then run the pair physics on the compact list
    constexpr int kBuf = 1024;
    std::uint32_t nbr[kBuf];
    int nn = 0;
    for (int ri = 0; ri < nr; ++ri) {
      for (std::uint32_t k = rg[ri][0]; k < rg[ri][1]; ++k) {
        const std::uint32_t b = sorted[k];
        const Vec<D> rab = xa - pos[b];
        const double r2 = dot(rab, rab);
        nbr[nn] = b;
        nn += (r2 < support2) & (r2 > 0.0);
        if (nn == kBuf) [[unlikely]] { nn = kBuf - 1; overflow = 1; }  // clumped particles: reported below
      }
    }
    np = static_cast<std::uint64_t>(nn);
    for (int ni = 0; ni < nn; ++ni) {
      {
        const std::uint32_t b = nbr[ni];
        const Vec<D> rab = xa - pos[b];
        const double r2 = dot(rab, rab);
        const double r = std::sqrt(r2);
        const double F = ker.F(r);
        const Vec<D> gradW = F * rab;
        const Kind kb = kind[b];
        const double rhob = rho[b], mb = mass[b];
        const double inv_rhob = 1.0 / rhob;
        const double Vb = mb * inv_rhob;
        const Vec<D> uab = va - vel[b];
        const double udotgw = dot(uab, gradW);
        if (ka == Kind::Wall) {  // dynamic wall: continuity from the fluid only
          if (kb == Kind::Fluid) drho += rhoa * udotgw * Vb;
          continue;
        }
        drho += rhoa * udotgw * Vb;
        const bool fluid_b = kb == Kind::Fluid;
        const double fr = F * r2 / (r2 + eta2);  // r·∇W/(r²+η²) × r² / r²: the regularised F
        if (diffusion && fluid_b) {
          double drh = rhoa - rhob;
          if (fourtakas) {
            // hydrostatic density difference: dρ = ρ g·dr / c² with the pair's mean ρ and c²
            // (the EOS's local c, not c0: with Tait, c0 alone leaves a ~6 gH/c0² mismatch
            // between the diffusion's equilibrium and hydrostatic balance)
            const double cb = eos.sound_speed(rhob);
            drh -= (rhoa + rhob) / (ca * ca + cb * cb) * dot(g, rab);
          }
          ddiff += drh * fr * Vb;
        }
        const double pb = prs[b];
        const double pterm = sym_p ? mb * (pa_r2 + pb * inv_rhob * inv_rhob) : (pa + pb) * Vb * inv_rhoa;
        acc -= pterm * gradW;
        if (laminar || artificial) {
          if (fluid_b || no_slip) {
            const Vec<D> u = fluid_b ? uab : va - wvel[b];
            if (laminar) acc += (mb * four_nu * fr / (rhoa + rhob)) * u;
            if (artificial) {
              const double vr = dot(u, rab);
              if (vr < 0.0) {
                const double mu = h * vr / (r2 + eta2);
                const double cb = eos.sound_speed(rhob);
                const double pi_ab = -alpha * (ca + cb) * mu / (rhoa + rhob);
                acc -= (mb * pi_ab) * gradW;
              }
            }
          }
        }
        if (xs_out && fluid_b) dxs -= (mb / (0.5 * (rhoa + rhob)) * ker.W(r)) * uab;
      }
    }
    pairs += np;
    drho_out[a] = drho + dcoef * ddiff;
    if (ka == Kind::Fluid) {
      acc_out[a] = acc + g;
      if (xs_out) xs_out[a] = xsph * dxs;
    } else {
      acc_out[a] = Vec<D>{};
    }
  }
  S.pairs_last_pass = pairs;
  if (overflow)
    throw SimulationError(fmt::format("a particle has more than 1023 neighbours at step {}, t = {:.6g} s: particles "
                                      "have clumped (time step too large or sound speed too small)", S.step, S.time));
}

template <int D>
void WCSPH<D>::rates(System<D>& S) {
  S.walls->prepare(S);
  S.with_kernel([&](const auto& K) { this->pair_loop(S, K); });
  for (auto& f : S.forces) f->add(S);
  auto& P = S.particles;
  double amax = 0.0;
  const std::size_t n = P.n_owned();
#pragma omp parallel for schedule(static) reduction(max : amax)
  for (std::size_t i = 0; i < n; ++i)
    if (P.kind[i] == Kind::Fluid) amax = std::max(amax, dot(P.acc[i], P.acc[i]));
  max_acc_ = std::sqrt(amax);
  if (!std::isfinite(max_acc_)) check_finite(S);
}

template <int D>
void WCSPH<D>::check_finite(const System<D>& S) const {
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
  const auto& P = S.particles;
  double umax2 = 0.0, rhomax = S.eos.rho0;
  const std::size_t n = P.n_owned();
#pragma omp parallel for schedule(static) reduction(max : umax2, rhomax)
  for (std::size_t i = 0; i < n; ++i) {
    if (P.kind[i] != Kind::Fluid) continue;
    umax2 = std::max(umax2, dot(P.vel[i], P.vel[i]));
    rhomax = std::max(rhomax, P.rho[i]);
  }
  const double cmax = S.eos.sound_speed(rhomax);
  double dt = cfg_.cfl * S.h / (cmax + std::sqrt(umax2));
  if (cfg_.viscosity == ViscosityModel::Laminar && S.nu > 0.0)
    dt = std::min(dt, cfg_.viscous_coefficient * S.h * S.h / S.nu);
  if (max_acc_ > 0.0) dt = std::min(dt, cfg_.force_coefficient * std::sqrt(S.h / max_acc_));
  return dt;
}

template <int D>
void WCSPH<D>::step(System<D>& S, double dt) {
  auto& P = S.particles;
  if (cfg_.reorder_every > 0 && S.step % cfg_.reorder_every == 0) S.reorder_by_cell();
  // stage 1: rates at t^n
  S.update_neighbours(true);
  rates(S);
  const std::size_t n = P.n_owned();
  x0_.resize(n);
  v0_.resize(n);
  rho0_.resize(n);
  const bool dyn = S.walls->evolves_density();
  std::vector<Vec<D>>* xs = cfg_.xsph > 0.0 ? &P.vector("xsph") : nullptr;
  const double hdt = 0.5 * dt;
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    x0_[i] = P.pos[i];
    v0_[i] = P.vel[i];
    rho0_[i] = P.rho[i];
    if (P.kind[i] == Kind::Fluid) {
      Vec<D> u = P.vel[i];
      if (xs) u += (*xs)[i];
      P.pos[i] += hdt * u;
      P.vel[i] += hdt * P.acc[i];
      P.rho[i] += hdt * P.drho[i];
    } else if (P.kind[i] == Kind::Wall && dyn) {
      P.rho[i] += hdt * P.drho[i];
    }
  }
  update_pressure(S);
  // stage 2: rates at t^{n+1/2}
  S.update_neighbours(false);
  rates(S);
  const bool symplectic = cfg_.integrator == Integrator::Symplectic;
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    const bool fluid = P.kind[i] == Kind::Fluid;
    if (!fluid && !(P.kind[i] == Kind::Wall && dyn)) continue;
    if (symplectic) {
      const double eps = -P.drho[i] / P.rho[i] * dt;
      P.rho[i] = rho0_[i] * (2.0 - eps) / (2.0 + eps);
    } else {
      P.rho[i] = rho0_[i] + dt * P.drho[i];
    }
    if (!fluid) continue;
    Vec<D> xcorr{};
    if (xs) xcorr = (*xs)[i];
    if (symplectic) {
      P.vel[i] = v0_[i] + dt * P.acc[i];
      P.pos[i] = x0_[i] + dt * (0.5 * (P.vel[i] + v0_[i]) + xcorr);
    } else {  // Monaghan predictor-corrector: corrected mid-step, then extrapolate
      const Vec<D> vc = v0_[i] + hdt * P.acc[i];
      P.pos[i] = x0_[i] + dt * (vc + xcorr);
      P.vel[i] = v0_[i] + dt * P.acc[i];
    }
  }
  S.periodic.wrap(P);
  S.time += dt;
  ++S.step;
  if (cfg_.shepard_every > 0 && S.step % cfg_.shepard_every == 0) shepard_filter(S);
  update_pressure(S);
}

template <int D>
void WCSPH<D>::shepard_filter(System<D>& S) const {
  S.update_neighbours(true);
  auto& P = S.particles;
  const std::size_t n = P.n_owned();
  std::vector<double> out(n);
  S.with_kernel([&](const auto& K) {
#pragma omp parallel for schedule(static)
    for (std::size_t a = 0; a < n; ++a) {
      out[a] = P.rho[a];
      if (P.kind[a] != Kind::Fluid) continue;
      double num = 0.0, den = 0.0;
      S.cells.for_neighbours(P.pos, P.pos[a], K.support, [&](std::uint32_t b, const Vec<D>&, double r2) {
        if (P.kind[b] != Kind::Fluid) return;
        const double w = K.W(std::sqrt(r2));
        num += P.mass[b] * w;
        den += P.mass[b] / P.rho[b] * w;
      });
      if (den > 0.0) out[a] = num / den;
    }
  });
  for (std::size_t a = 0; a < n; ++a) P.rho[a] = out[a];
}

template <int D>
std::size_t WCSPH<D>::bytes() const {
  return x0_.capacity() * sizeof(Vec<D>) + v0_.capacity() * sizeof(Vec<D>) + rho0_.capacity() * sizeof(double);
}

template class WCSPH<2>;
template class WCSPH<3>;

template <int D>
Registry<Scheme<D>, const Case&>& scheme_registry() {
  static Registry<Scheme<D>, const Case&> r = [] {
    Registry<Scheme<D>, const Case&> reg;
    reg.add("wcsph", [](const Case& c) { return std::make_unique<WCSPH<D>>(c); });
    return reg;
  }();
  return r;
}
template Registry<Scheme<2>, const Case&>& scheme_registry<2>();
template Registry<Scheme<3>, const Case&>& scheme_registry<3>();

}  // namespace sph
