#include "sphflume/physics/multiphase.hpp"

#include <cmath>
#include <type_traits>

#include <fmt/format.h>

#include "sphflume/core/fields.hpp"
#include "sphflume/core/volume_sweep.hpp"

namespace sph {

template <int D>
void setup_phases(const Case& c, System<D>& S) {
  if (!c.multiphase.on()) return;
  auto& P = S.particles;
  S.phase_eos = {S.eos};
  S.grenier = c.multiphase.grenier;
  S.chi = c.multiphase.chi;
  S.phase_names = {"water"};
  auto& phase = P.scalar(field::phase);
  S.bind_phase_field();
  for (std::size_t k = 0; k < c.multiphase.phases.size(); ++k) {
    const auto& pc = c.multiphase.phases[k];
    Eos e = S.eos;
    e.rho0 = pc.density;
    e.gamma = pc.gamma;
    e.c0 = pc.sound_speed > 0.0 ? pc.sound_speed
                                : S.eos.c0 * std::sqrt(pc.gamma * S.eos.rho0 / (S.eos.gamma * pc.density));
    S.phase_eos.push_back(e);
    S.phase_names.push_back(pc.name);
    std::size_t hit = 0;
    for (std::size_t i = 0; i < P.n_owned(); ++i) {
      if (P.kind[i] != Kind::Fluid || !pc.region.contains(P.pos[i].c.data(), D)) continue;
      const Eos& old = S.phase_eos[static_cast<std::size_t>(phase[i])];
      const double p = old.pressure(P.rho[i]);
      P.mass[i] *= pc.density / old.rho0;
      P.rho[i] = e.density(p);
      phase[i] = static_cast<double>(k + 1);
      ++hit;
    }
    if (hit == 0)
      throw InputError(fmt::format("{}: line {}: multiphase.phases.{} ('{}'): the region holds no fluid particles: "
                                   "expected a region inside the fluid (the phase takes the fluid particles in it)",
                                   c.file, pc.line, k, pc.name));
  }
}

namespace {
/// Γ_a = Σ_b V_b W_ab (V_b = m_b/ρ_b, b = a included, every kind; levels: h_ab) of every owned fluid particle, on
/// the pair-pass seam in double precision (core/volume_sweep.hpp).
template <int D, class K, bool Lev>
void gamma_sums(System<D>& S, const K& ker, double* gam) {
  const double *rho = S.particles.rho.data(), *mass = S.particles.mass.data();
  const double support2 = ker.support2;
  volume_sweep<D, Lev>(
      S, [rho, mass](std::size_t j) { return mass[j] / rho[j]; },
      [&](std::uint32_t a, double xa0, double xa1, double xa2, double ha, const double* __restrict x0,
          const double* __restrict x1, const double* __restrict x2, const double* __restrict bv,
          const double* __restrict bh, std::size_t npad) {
        const K kl = ker;
        const double l_support2 = support2;
        double g = 0.0;
#pragma omp simd reduction(+ : g)
        for (std::size_t k = 0; k < npad; ++k) {
          const double r0 = xa0 - x0[k], r1 = xa1 - x1[k], r2c = D == 3 ? xa2 - x2[k] : 0.0;
          const double r2 = r0 * r0 + r1 * r1 + r2c * r2c;
          const double rr = std::sqrt(r2);
          const double W = Lev ? kl.Wh(rr, 2.0 / (ha + bh[k])) : kl.W(rr);
          g += r2 < l_support2 ? W * bv[k] : 0.0;
        }
        gam[a] = g;
      });
}
}  // namespace

template <int D>
void grenier_gamma(System<D>& S) {
  auto& P = S.particles;
  const std::size_t n = P.n_owned();
  auto& gam = P.scalar(field::gamma_grenier);
  for (std::size_t a = 0; a < n; ++a)
    if (P.kind[a] != Kind::Fluid) gam[a] = 1.0;
  S.with_kernel([&](const auto& K) {
    using Kt = std::decay_t<decltype(K)>;
    if (S.level_h()) gamma_sums<D, Kt, true>(S, K, gam.data());
    else gamma_sums<D, Kt, false>(S, K, gam.data());
  });
  S.refresh_halos();
}

template void setup_phases<2>(const Case&, System<2>&);
template void setup_phases<3>(const Case&, System<3>&);
template void grenier_gamma<2>(System<2>&);
template void grenier_gamma<3>(System<3>&);

}  // namespace sph
