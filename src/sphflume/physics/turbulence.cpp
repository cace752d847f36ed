#include "sphflume/physics/turbulence.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include <fmt/format.h>

#include "sphflume/core/errors.hpp"
#include "sphflume/core/fields.hpp"
#include "sphflume/core/refinement.hpp"

namespace sph {

template <int D>
const char* Turbulence<D>::stress_name(int k) {
  if constexpr (D == 2) {
    static const char* n[] = {"tau_xx", "tau_xz", "tau_zz"};
    return n[k];
  } else {
    static const char* n[] = {"tau_xx", "tau_yy", "tau_zz", "tau_xy", "tau_xz", "tau_yz"};
    return n[k];
  }
}

template <int D>
std::pair<int, int> Turbulence<D>::stress_index(int k) {
  if constexpr (D == 2) {
    static const std::pair<int, int> p[] = {{0, 0}, {0, 1}, {1, 1}};
    return p[k];
  } else {
    static const std::pair<int, int> p[] = {{0, 0}, {1, 1}, {2, 2}, {0, 1}, {0, 2}, {1, 2}};
    return p[k];
  }
}

template <int D>
double Turbulence<D>::strain_norm(const double* G) const {
  double ss = 0.0;
  for (int i = 0; i < D; ++i)
    for (int j = 0; j < D; ++j) {
      const double s = 0.5 * (G[i * D + j] + G[j * D + i]);
      ss += s * s;
    }
  return std::sqrt((cfg_.strain_literal ? 1.0 : 2.0) * ss);
}

template <int D>
double Turbulence<D>::mixing_length(double z, double zs, double g_x, double nu) const {
  if (cfg_.profile == "constant") return cfg_.length;
  if (cfg_.profile == "three_layer") {
    const double z0 = cfg_.z_trough + cfg_.dz0, zc = cfg_.z_crest;
    if (z <= z0) return cfg_.l_mb;
    if (z <= zc) return cfg_.l_mb + cfg_.kappa_r * (z - z0);
    const double lmc = cfg_.l_mb + cfg_.kappa_r * std::max(zc - z0, 0.0);
    const double hc = zs - zc;
    if (!(hc > 0.0)) return lmc;
    const double xi = std::min((z - zc) / hc, 1.0);
    return lmc + cfg_.kappa_f * (z - zc) * std::sqrt(1.0 - xi);
  }
  // nezu_rodi
  const double zw = z - cfg_.bed, H = zs - cfg_.bed;
  if (!(zw > 0.0) || !(H > 0.0) || zw >= H) return 0.0;
  const double xi = zw / H;
  double lm = cfg_.kappa * zw * std::sqrt(1.0 - xi) /
              (1.0 + std::numbers::pi * cfg_.coles_pi * xi * std::sin(std::numbers::pi * xi));
  if (cfg_.van_driest && nu > 0.0) {
    const double ustar = std::sqrt(std::abs(g_x) * H);
    lm *= 1.0 - std::exp(-zw * ustar / nu / cfg_.a_plus);
  }
  return lm;
}

template <int D>
double Turbulence<D>::eddy_viscosity(double s, double lm, double delta) const {
  if (cfg_.model == "smagorinsky") {
    const double l = cfg_.cs * delta;
    return l * l * s;
  }
  if (cfg_.model == "mixing_length") return lm * lm * s;
  return 0.0;
}

template <int D>
std::vector<double> Turbulence<D>::column_surface(const System<D>& S, double width) {
  // the highest water particle of every column (width x width in plan), as a grid over the
  // columns the water spans, filled by every part of the domain and reduced to its maximum over
  // them (a column may be cut across, or its neighbour be another rank's)
  const auto& P = S.particles;
  const std::size_t n = P.n_owned();
  constexpr double inf = std::numeric_limits<double>::infinity();
  auto col = [&](double x) { return std::floor(x / width); };
  double lo[2] = {inf, inf}, hi[2] = {-inf, -inf};
  for (std::size_t a = 0; a < n; ++a) {
    if (!fluid_like(P.kind[a])) continue;
    for (int d = 0; d < D - 1; ++d) {
      lo[d] = std::min(lo[d], col(P.pos[a][d]));
      hi[d] = std::max(hi[d], col(P.pos[a][d]));
    }
  }
  S.comm->min(lo, 2);
  S.comm->max(hi, 2);
  std::vector<double> zs(n, -inf);
  if (!(lo[0] <= hi[0])) return zs;  // no water anywhere
  // one empty column on either side, so that every particle's neighbours are on the grid
  const double nxd = hi[0] - lo[0] + 3.0, nyd = D == 3 ? hi[1] - lo[1] + 3.0 : 1.0;
  if (nxd * nyd > 5.0e7)
    throw SimulationError(fmt::format("mixing length: the water spans {:.3g} x {:.3g} columns of width {:.3g} m (particles "
                                      "flew apart? or set turbulence.column_width larger)", nxd, nyd, width));
  const std::size_t nx = static_cast<std::size_t>(nxd), ny = static_cast<std::size_t>(nyd);
  auto cell = [&](const Vec<D>& x, int di, int dj) {
    const std::size_t i = static_cast<std::size_t>(col(x[0]) - lo[0] + 1.0 + di);
    const std::size_t j = D == 3 ? static_cast<std::size_t>(col(x[1]) - lo[1] + 1.0 + dj) : 0;
    return j * nx + i;
  };
  // each column's top: the highest particle's z plus its half spacing (resolution levels: its level's, dx/2^l)
  const double* lv = S.levels > 0 ? P.require(field::level).data() : nullptr;
  std::vector<double> top(nx * ny, -inf);
  for (std::size_t a = 0; a < n; ++a)
    if (fluid_like(P.kind[a])) {
      const double half = 0.5 * (lv ? level_h(S.dx, static_cast<int>(lv[a])) : S.dx);
      top[cell(P.pos[a], 0, 0)] = std::max(top[cell(P.pos[a], 0, 0)], P.pos[a][D - 1] + half);
    }
  S.comm->max(top.data(), top.size());
  const int r3 = D == 3 ? 1 : 0;
  for (std::size_t a = 0; a < n; ++a) {
    if (!fluid_like(P.kind[a])) continue;
    double z = -inf;
    for (int di = -1; di <= 1; ++di)
      for (int dj = -r3; dj <= r3; ++dj) z = std::max(z, top[cell(P.pos[a], di, dj)]);
    zs[a] = z;
  }
  return zs;
}

template <int D>
void Turbulence<D>::update(System<D>& S) {
  auto& P = S.particles;
  const std::size_t n = P.n_owned();
  if (grad_.size() < n * D * D) return;  // no pass has filled the gradient yet
  auto& nut = P.scalar(field::nu_t);
  std::vector<double>* tau[kStress];
  for (int k = 0; k < kStress; ++k) tau[k] = &P.scalar(stress_name(k));
  const bool ml = cfg_.model == "mixing_length";
  std::vector<double> zs;
  if (ml && cfg_.profile != "constant") zs = column_surface(S, cfg_.column_width > 0.0 ? cfg_.column_width : 2.0 * S.dx);
  // the SPS filter width: the particle spacing (resolution levels: each particle's level's, dx/2^l)
  const double delta = cfg_.delta > 0.0 ? cfg_.delta : S.dx;
  const double* lv = S.levels > 0 && !(cfg_.delta > 0.0) ? P.require(field::level).data() : nullptr;
  const double gx = S.gravity[0];
  double numax = 0.0;
#pragma omp parallel for schedule(static) reduction(max : numax)
  for (std::size_t a = 0; a < n; ++a) {
    if (!fluid_like(P.kind[a])) {
      nut[a] = 0.0;
      for (int k = 0; k < kStress; ++k) (*tau[k])[a] = 0.0;
      continue;
    }
    if (P.kind[a] == Kind::Outflow) continue;  // frozen: keeps the stress it had as fluid
    const double* G = grad_.data() + a * D * D;
    const double s = strain_norm(G);
    const double lm = ml ? mixing_length(P.pos[a][D - 1], zs.empty() ? 0.0 : zs[a], gx, S.nu) : 0.0;
    const double nu = eddy_viscosity(s, lm, lv ? level_h(S.dx, static_cast<int>(lv[a])) : delta);
    nut[a] = nu;
    numax = std::max(numax, nu);
    double tr = 0.0;
    for (int i = 0; i < D; ++i) tr += G[i * D + i];
    for (int k = 0; k < kStress; ++k) {
      const auto [i, j] = stress_index(k);
      const double sij = 0.5 * (G[i * D + j] + G[j * D + i]) - (i == j ? tr / 3.0 : 0.0);
      (*tau[k])[a] = 2.0 * nu * sij;
    }
  }
  nu_t_max_ = numax;
}

template class Turbulence<2>;
template class Turbulence<3>;

}  // namespace sph
