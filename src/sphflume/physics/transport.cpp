#include "sphflume/physics/transport.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>
#include <muParser.h>

namespace sph {
namespace {

std::string src_name(const std::string& n) { return "_src_" + n; }
std::string y0_name(const std::string& n) { return "_y0_" + n; }
std::string rate_name(const std::string& n) { return "_rate_" + n; }

}  // namespace

template <int D>
ScalarTransport<D>::ScalarTransport(const TransportConfig& cfg, double eta2, int wall_layers)
    : cfg_(cfg), eta2_(eta2), layers_(std::max(1, wall_layers)) {
  source_rate_.assign(cfg_.scalars.size(), 0.0);
  source_mass_.assign(cfg_.scalars.size(), 0.0);
}

template <int D>
void ScalarTransport<D>::initialise(System<D>& S) const {
  auto& P = S.particles;
  const std::size_t n = P.n_owned();
  for (const auto& sc : cfg_.scalars) {
    auto& C = P.scalar(sc.name);
    auto& src = P.scalar(src_name(sc.name));
    (void)P.scalar(y0_name(sc.name));
    (void)P.scalar(rate_name(sc.name));
    for (const auto& in : sc.initial) {
      mu::Parser parser;
      double xv[3] = {0.0, 0.0, 0.0};
      if (in.type == "expression") {
        parser.DefineVar("x", &xv[0]);
        parser.DefineVar("y", &xv[1]);
        parser.DefineVar("z", &xv[2]);
        parser.SetExpr(in.expression);
      }
      for (std::size_t i = 0; i < n; ++i) {
        if (P.kind[i] == Kind::Wall) continue;
        const auto& x = P.pos[i];
        if (in.type == "uniform") {
          C[i] = in.value;
        } else if (in.type == "region") {
          if (in.region.contains(x.c.data(), D)) C[i] = in.value;
        } else if (in.type == "gaussian") {
          double r2 = 0.0;
          for (int d = 0; d < D; ++d) {
            const bool use = in.axes.empty() || std::find(in.axes.begin(), in.axes.end(), d) != in.axes.end();
            if (use) r2 += (x[d] - in.center[static_cast<std::size_t>(d)]) * (x[d] - in.center[static_cast<std::size_t>(d)]);
          }
          C[i] = in.value * std::exp(-r2 / (2.0 * in.sigma * in.sigma));
        } else {
          xv[0] = x[0];
          xv[1] = D == 3 ? x[1] : 0.0;
          xv[2] = x[D - 1];
          const double v = parser.Eval();
          if (!std::isfinite(v))
            throw InputError(fmt::format("line {}: transport scalar '{}': the initial expression '{}' is not finite at "
                                         "({:.4g}, {:.4g}): expected an expression finite over the fluid",
                                         in.line, sc.name, in.expression, x[0], x[D - 1]));
          C[i] = v;
        }
      }
    }
    int flux_index = 0;
    for (const auto& so : sc.sources) {
      std::size_t hit = 0;
      for (std::size_t i = 0; i < n; ++i) {
        if (P.kind[i] != Kind::Wall || !so.region.contains(P.pos[i].c.data(), D)) continue;
        ++hit;
        if (so.has_value) { src[i] = 1.0; C[i] = so.value; }
        else src[i] = 2.0 + flux_index;
      }
      if (!so.has_value) ++flux_index;
      if (hit == 0)
        throw InputError(fmt::format("line {}: transport scalar '{}': the source region holds no wall particles: "
                                     "expected a region over a wall (sources act through wall particles)", so.line, sc.name));
    }
  }
  impose(S);
}

template <int D>
void ScalarTransport<D>::impose(System<D>& S) const {
  auto& P = S.particles;
  const std::size_t n = P.n_owned();
  for (const auto& sc : cfg_.scalars) {
    auto& C = P.scalar(sc.name);
    for (std::size_t i = 0; i < n; ++i)
      if (P.kind[i] == Kind::Inflow) {
        const double z = P.pos[i][D - 1];
        C[i] = (sc.has_inflow && z >= sc.inflow_z[0] && z <= sc.inflow_z[1]) ? sc.inflow : 0.0;
      }
  }
}

template <int D>
void ScalarTransport<D>::rates(System<D>& S) {
  S.with_kernel([&](const auto& K) { this->rates_kernel(S, K); });
}

template <int D>
template <class K>
void ScalarTransport<D>::rates_kernel(System<D>& S, const K& ker) {
  auto& P = S.particles;
  const std::size_t n = P.n_owned();
  const double eta2 = eta2_ * S.h * S.h;
  // resolution levels (docs/numerics.md §14): the pair's h_ab = (h_a + h_b)/2 in F and η², so that every pair term
  // stays antisymmetric and Σ m C/ρ is kept between particles of different sizes
  const double* hs = S.level_h();
  const double* nut = P.has(field::nu_t) ? P.scalar(field::nu_t).data() : nullptr;
  const double advect = cfg_.advection == ScalarAdvection::Conservative ? 0.0
                        : cfg_.advection == ScalarAdvection::None ? 1.0 : 2.0;
  const DiffusionOperator op = cfg_.op;
  const double cell_area = std::pow(S.dx, D - 1) / layers_;
  for (std::size_t k = 0; k < cfg_.scalars.size(); ++k) {
    const auto& sc = cfg_.scalars[k];
    const double* C = P.scalar(sc.name).data();
    const double* src = P.scalar(src_name(sc.name)).data();
    double* rate = P.scalar(rate_name(sc.name)).data();
    const double Dm = sc.diffusivity, isc = (sc.schmidt_turbulent > 0.0 && nut) ? 1.0 / sc.schmidt_turbulent : 0.0;
    auto diff = [&](std::size_t i) { return Dm + (isc > 0.0 ? nut[i] * isc : 0.0); };
    double src_rate = 0.0;
#pragma omp parallel for schedule(dynamic, 256) reduction(+ : src_rate)
    for (std::size_t a = 0; a < n; ++a) {
      if (P.kind[a] != Kind::Fluid) { rate[a] = 0.0; continue; }
      const double rhoa = P.rho[a], ma = P.mass[a], Da = diff(a), ya = C[a] / rhoa, ka = rhoa * Da;
      double sum = 0.0, from_walls = 0.0;
      S.cells.for_neighbours(P.pos, P.pos[a], ker.support, [&](std::uint32_t b, const Vec<D>&, double r2) {
        if (r2 <= 0.0) return;
        const Kind kb = P.kind[b];
        const bool wall_src = kb == Kind::Wall && src[b] == 1.0;
        if (!(fluid_like(kb) || wall_src)) return;
        const double rhob = P.rho[b], mb = P.mass[b], Db = diff(b);
        const double hab = hs ? 0.5 * (hs[a] + hs[b]) : 0.0;
        const double F = hs ? ker.Fh(std::sqrt(r2), 1.0 / hab) * r2 / (r2 + eta2_ * hab * hab)
                            : ker.F(std::sqrt(r2)) * r2 / (r2 + eta2);
        double t = 0.0;
        switch (op) {
          case DiffusionOperator::Consistent: {
            const double kb_ = rhob * Db;
            const double kk = ka + kb_ > 0.0 ? 4.0 * ka * kb_ / (ka + kb_) : 0.0;
            t = mb / (rhoa * rhob) * kk * F * (ya - C[b] / rhob);
            break;
          }
          case DiffusionOperator::Federico: {
            const double dd = Da + Db > 0.0 ? 4.0 * Da * Db / (Da + Db) : 0.0;
            t = mb / (rhoa * rhob) * dd * (rhoa + rhob) * F * (C[a] - C[b]) / rhoa;
            break;
          }
          case DiffusionOperator::ZhuFox:
            t = ma / (rhoa * rhob) * (Da * rhoa + Db * rhob) * F * (C[a] - C[b]) / rhoa;
            break;
          case DiffusionOperator::Tartakovsky:
            t = (mb * rhoa * Da + ma * rhob * Db) / (rhoa * rhob) * F * (C[a] - C[b]) / rhoa;
            break;
          case DiffusionOperator::Monaghan: {
            const double dd = Da + Db > 0.0 ? 4.0 * Da * Db / (Da + Db) : 0.0;
            t = mb / (rhoa * rhob) * dd * F * (C[a] - C[b]) / rhoa;
            break;
          }
        }
        sum += t;
        if (wall_src) from_walls += t;
      });
      double r = sum - advect * ya / rhoa * P.drho[a];
      if (sc.reaction_rate > 0.0) r -= sc.reaction_rate * (C[a] - sc.equilibrium) / rhoa;
      rate[a] = r;
      src_rate += ma * from_walls;
    }
    // flux sources: region r releases q_r × area_r, shared in proportion to Σ_w W_aw V_a
    int flux_index = 0;
    for (const auto& so : sc.sources) {
      if (so.has_value) continue;
      const double tag = 2.0 + flux_index++;
      std::uint64_t nw = 0;
      for (std::size_t i = 0; i < n; ++i) nw += (P.kind[i] == Kind::Wall && src[i] == tag);
      nw = S.comm->sum(nw);  // (the region's wall particles on every rank: it may straddle a cut)
      const double Q = so.flux * cell_area * static_cast<double>(nw);
      std::vector<double> omega(n, 0.0);
      double total = 0.0;
#pragma omp parallel for schedule(dynamic, 256) reduction(+ : total)
      for (std::size_t a = 0; a < n; ++a) {
        if (P.kind[a] != Kind::Fluid) continue;
        double w = 0.0;
        S.cells.for_neighbours(P.pos, P.pos[a], ker.support, [&](std::uint32_t b, const Vec<D>&, double r2) {
          if (P.kind[b] == Kind::Wall && src[b] == tag) w += hs ? ker.Wh(std::sqrt(r2), 2.0 / (hs[a] + hs[b])) : ker.W(std::sqrt(r2));
        });
        omega[a] = w * P.mass[a] / P.rho[a];
        total += omega[a];
      }
      const double mine = total;
      total = S.comm->sum(total);  // (shared among the fluid near the region on every rank)
      if (!(total > 0.0)) continue;  // no fluid near the source now: nothing released
      for (std::size_t a = 0; a < n; ++a)
        if (omega[a] > 0.0) rate[a] += Q * omega[a] / total / P.mass[a];
      src_rate += S.comm->size() > 1 ? Q * (mine / total) : Q;  // (this rank's share; one process: Q)
    }
    source_rate_[k] = src_rate;
  }
}

template <int D>
void ScalarTransport<D>::begin_step(System<D>& S) const {
  auto& P = S.particles;
  const std::size_t n = P.n_owned();
  for (const auto& sc : cfg_.scalars) {
    const auto& C = P.scalar(sc.name);
    auto& y0 = P.scalar(y0_name(sc.name));
    for (std::size_t i = 0; i < n; ++i) y0[i] = C[i] / P.rho[i];
  }
}

template <int D>
void ScalarTransport<D>::advance(System<D>& S, double step, bool final) {
  auto& P = S.particles;
  const std::size_t n = P.n_owned();
  for (std::size_t k = 0; k < cfg_.scalars.size(); ++k) {
    const auto& sc = cfg_.scalars[k];
    auto& C = P.scalar(sc.name);
    const auto& y0 = P.scalar(y0_name(sc.name));
    const auto& rate = P.scalar(rate_name(sc.name));
    for (std::size_t i = 0; i < n; ++i)
      if (P.kind[i] == Kind::Fluid) C[i] = P.rho[i] * (y0[i] + step * rate[i]);
    if (final) source_mass_[k] += step * source_rate_[k];
  }
  impose(S);
}

template <int D>
void ScalarTransport<D>::rescale(System<D>& S, const std::vector<double>& rho_new) const {
  auto& P = S.particles;
  const std::size_t n = P.n_owned();
  for (const auto& sc : cfg_.scalars) {
    auto& C = P.scalar(sc.name);
    for (std::size_t i = 0; i < n; ++i)
      if (P.kind[i] == Kind::Fluid) C[i] *= rho_new[i] / P.rho[i];
  }
}

template <int D>
double ScalarTransport<D>::time_step(const System<D>& S, double coef) const {
  const auto& P = S.particles;
  double nut_max = 0.0;
  if (const auto* nut = P.find(field::nu_t))
    for (std::size_t i = 0; i < P.n_owned(); ++i) nut_max = std::max(nut_max, (*nut)[i]);
  double dt = std::numeric_limits<double>::infinity();
  for (const auto& sc : cfg_.scalars) {
    double Dmax = sc.diffusivity + (sc.schmidt_turbulent > 0.0 ? nut_max / sc.schmidt_turbulent : 0.0);
    // Federico's (4.7) diffuses at twice the rate: its stable step is half as long
    if (cfg_.op == DiffusionOperator::Federico) Dmax *= 2.0;
    if (Dmax > 0.0) dt = std::min(dt, coef * S.finest_h() * S.finest_h() / Dmax);  // (levels: the finest h)
    if (sc.reaction_rate > 0.0) dt = std::min(dt, 0.05 / sc.reaction_rate);
  }
  return dt;
}

template class ScalarTransport<2>;
template class ScalarTransport<3>;

}  // namespace sph
