#include "sphflume/physics/multiphase.hpp"

#include <cmath>

#include <fmt/format.h>

#include "sphflume/core/fields.hpp"

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

template <int D>
void grenier_gamma(System<D>& S) {
  auto& P = S.particles;
  const std::size_t n = P.n_owned();
  auto& gam = P.scalar(field::gamma_grenier);
  const double* hs = S.level_h();  // (levels: h_ab)
  S.with_kernel([&](const auto& K) {
#pragma omp parallel for schedule(dynamic, 256)
    for (std::size_t a = 0; a < n; ++a) {
      if (P.kind[a] != Kind::Fluid) { gam[a] = 1.0; continue; }
      double g = 0.0;
      S.cells.for_neighbours(P.pos, P.pos[a], K.support, [&](std::uint32_t b, const Vec<D>&, double r2) {
        const double r = std::sqrt(r2);
        g += P.mass[b] / P.rho[b] * (hs ? K.Wh(r, 2.0 / (hs[a] + hs[b])) : K.W(r));
      });
      gam[a] = g;
    }
  });
  S.refresh_halos();
}

template void setup_phases<2>(const Case&, System<2>&);
template void setup_phases<3>(const Case&, System<3>&);
template void grenier_gamma<2>(System<2>&);
template void grenier_gamma<3>(System<3>&);

}  // namespace sph
