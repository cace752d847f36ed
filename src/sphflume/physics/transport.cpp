#include "sphflume/physics/transport.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>
#include <muParser.h>

#include "sphflume/core/pair_pass.hpp"

namespace sph {
namespace {

std::string src_name(const std::string& n) { return "_src_" + n; }
std::string y0_name(const std::string& n) { return "_y0_" + n; }
std::string rate_name(const std::string& n) { return "_rate_" + n; }

/// One pair's term of dY_a/dt under each diffusion operator (the forms of docs/numerics.md), as num / den with the
/// kernel's F r²/(r² + η²) folded in: one division per pair (the harmonic means' and the regularisation's), so that
/// the candidate loop vectorises without a division's latency per factor. Branch-free: a lane whose den is zero is
/// dropped by a select, never summed.
struct PairSide {
  double rho, irho, m, D, C, y;  // y = C/ρ
};
template <DiffusionOperator Op>
[[gnu::always_inline]] inline double pair_term(double F, double r2, double r2e, const PairSide& a, const PairSide& b) {
  double num, den;
  if constexpr (Op == DiffusionOperator::Consistent) {  // m_b/(ρ_a ρ_b) 4 k_a k_b/(k_a + k_b) F (y_a − y_b), k = ρ D
    const double ka = a.rho * a.D, kb = b.rho * b.D;
    num = b.m * a.irho * b.irho * 4.0 * ka * kb * (a.y - b.y);
    den = ka + kb;
  } else if constexpr (Op == DiffusionOperator::Federico) {  // m_b/(ρ_a ρ_b) 4 D_a D_b/(D_a + D_b) (ρ_a + ρ_b) F (C_a − C_b)/ρ_a
    num = b.m * a.irho * b.irho * 4.0 * a.D * b.D * (a.rho + b.rho) * (a.C - b.C) * a.irho;
    den = a.D + b.D;
  } else if constexpr (Op == DiffusionOperator::ZhuFox) {  // m_a/(ρ_a ρ_b) (D_a ρ_a + D_b ρ_b) F (C_a − C_b)/ρ_a
    num = a.m * a.irho * b.irho * (a.D * a.rho + b.D * b.rho) * (a.C - b.C) * a.irho;
    den = 1.0;
  } else if constexpr (Op == DiffusionOperator::Tartakovsky) {  // (m_b ρ_a D_a + m_a ρ_b D_b)/(ρ_a ρ_b) F (C_a − C_b)/ρ_a
    num = (b.m * a.rho * a.D + a.m * b.rho * b.D) * a.irho * b.irho * (a.C - b.C) * a.irho;
    den = 1.0;
  } else {  // Monaghan: m_b/(ρ_a ρ_b) 4 D_a D_b/(D_a + D_b) F (C_a − C_b)/ρ_a
    num = b.m * a.irho * b.irho * 4.0 * a.D * b.D * (a.C - b.C) * a.irho;
    den = a.D + b.D;
  }
  const double q = den * r2e;
  return den > 0.0 ? F * r2 * num / q : 0.0;
}

/// The scalar pass's candidate columns after the positions (pair_pass.hpp): ρ, m, D (molecular + turbulent),
/// 1/ρ, C, C/ρ, whether b enters a's sum (fluid-like, or a wall of prescribed value), whether b is such a wall, h_b (levels).
enum TransportColumn : int { kRho = 3, kIRho, kMass, kDiff, kConc, kY, kIn, kWallSrc, kHs, kTransportColumns };

/// Scalar k's pair sums of every owned fluid particle over its cell's candidates, in double precision (the loop
/// vectorised over the candidates: the operators of docs/numerics.md, the turbulent diffusivity, h_ab on levels);
/// writes rate (the pair sum) and from_walls (m_a × the part from walls of prescribed value).
template <int D, class K, DiffusionOperator Op, bool Lev>
void pair_sums(System<D>& S, const K& ker, double eta2u, const double* C, const double* src, double Dm, double isc,
               const double* nut, double* rate, double* from_walls) {
  auto& P = S.particles;
  const std::size_t n = P.n_owned();
  const double eta2 = eta2u * S.h * S.h, support2 = ker.support2;
  const double* hs = Lev ? S.level_h() : nullptr;
  const Kind* kind = P.kind.data();
  const double *rho = P.rho.data(), *mass = P.mass.data();
  auto diff = [Dm, isc, nut](std::size_t j) { return nut ? Dm + nut[j] * isc : Dm; };
  const auto& cells = S.cells;
  const std::uint32_t* sorted = cells.sorted().data();
  auto needs = [&](std::size_t cell) {
    std::size_t m = 0;
    for (std::uint32_t k = cells.cell_begin(cell); k < cells.cell_end(cell); ++k) {
      const std::uint32_t a = sorted[k];
      if (a >= n) continue;
      if (kind[a] == Kind::Fluid) ++m;
      else rate[a] = from_walls[a] = 0.0;
    }
    return m;
  };
  sweep_cells<double>(cells, kTransportColumns, 8, needs, [&](std::size_t cell, const CellStencil<D>& st, ScratchColumns<double>& B) {
    const Vec<D> origin = P.pos[sorted[cells.cell_begin(cell)]];
    gather_columns<D, double>(
        st, B, P.pos.data(), origin, column(kRho, 1.0, [rho](std::size_t j) { return rho[j]; }),
        column(kIRho, 1.0, [rho](std::size_t j) { return 1.0 / rho[j]; }),
        column(kY, 0.0, [C, rho](std::size_t j) { return C[j] / rho[j]; }),
        column(kMass, 0.0, [mass](std::size_t j) { return mass[j]; }), column(kDiff, 0.0, diff),
        column(kConc, 0.0, [C](std::size_t j) { return C[j]; }),
        column(kIn, 0.0, [kind, src](std::size_t j) {
          return (fluid_like(kind[j]) || (kind[j] == Kind::Wall && src[j] == 1.0)) ? 1.0 : 0.0;
        }),
        column(kWallSrc, 0.0, [kind, src](std::size_t j) { return (kind[j] == Kind::Wall && src[j] == 1.0) ? 1.0 : 0.0; }),
        only_if<Lev>(column(kHs, 1.0, [hs](std::size_t j) { return hs[j]; })));
    const double* __restrict x0 = B[0];
    const double* __restrict x1 = B[1];
    const double* __restrict x2 = B[D - 1];
    const double* __restrict brho = B[kRho];
    const double* __restrict birho = B[kIRho];
    const double* __restrict by = B[kY];
    const double* __restrict bm = B[kMass];
    const double* __restrict bd = B[kDiff];
    const double* __restrict bc = B[kConc];
    const double* __restrict bin = B[kIn];
    const double* __restrict bws = B[kWallSrc];
    const double* __restrict bh = B[kHs];
    const std::size_t npad = st.padded;
    // the loop's constants as locals (read through the captured references, GCC gathered them lane by lane)
    const K kl = ker;
    const double l_eta2 = eta2, l_eta2u = eta2u, l_support2 = support2;
    for (std::uint32_t q = cells.cell_begin(cell); q < cells.cell_end(cell); ++q) {
      const std::uint32_t a = sorted[q];
      if (a >= n || kind[a] != Kind::Fluid) continue;
      const PairSide pa{rho[a], 1.0 / rho[a], mass[a], diff(a), C[a], C[a] / rho[a]};
      const double ha = Lev ? hs[a] : 0.0;
      const double xa0 = P.pos[a][0] - origin[0], xa1 = P.pos[a][1] - origin[1], xa2 = P.pos[a][D - 1] - origin[D - 1];
      double sum = 0.0, walls = 0.0;
#pragma omp simd reduction(+ : sum, walls)
      for (std::size_t k = 0; k < npad; ++k) {
        const double r0 = xa0 - x0[k], r1 = xa1 - x1[k], r2c = D == 3 ? xa2 - x2[k] : 0.0;
        const double r2 = r0 * r0 + r1 * r1 + r2c * r2c;
        double F, r2e;
        if constexpr (Lev) {
          const double hab = 0.5 * (ha + bh[k]);
          F = kl.Fh(std::sqrt(r2), 1.0 / hab);  // (the one division left besides the term's: h_ab's)
          r2e = r2 + l_eta2u * hab * hab;
        } else {
          F = kl.F(std::sqrt(r2));
          r2e = r2 + l_eta2;
        }
        const double t = pair_term<Op>(F, r2, r2e, pa, PairSide{brho[k], birho[k], bm[k], bd[k], bc[k], by[k]});
        const bool in = (r2 > 0.0) & (r2 < l_support2) & (bin[k] > 0.0);
        const double tt = in ? t : 0.0;
        sum += tt;
        walls += tt * bws[k];
      }
      rate[a] = sum;
      from_walls[a] = pa.m * walls;
    }
    return std::uint64_t{0};  // (no pair count: nothing reads it)
  });
}

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
    const double* nut_k = isc > 0.0 ? nut : nullptr;  // (the turbulent part only when the scalar takes it)
    // the pair sums (vectorised over each cell's candidates), then the advection and reaction terms; the walls'
    // release summed in index order (the same bits on any number of threads)
    from_walls_.resize(n);
    auto run = [&]<DiffusionOperator Op>() {
      if (hs) pair_sums<D, K, Op, true>(S, ker, eta2_, C, src, Dm, isc, nut_k, rate, from_walls_.data());
      else pair_sums<D, K, Op, false>(S, ker, eta2_, C, src, Dm, isc, nut_k, rate, from_walls_.data());
    };
    switch (op) {
      case DiffusionOperator::Consistent: run.template operator()<DiffusionOperator::Consistent>(); break;
      case DiffusionOperator::Federico: run.template operator()<DiffusionOperator::Federico>(); break;
      case DiffusionOperator::ZhuFox: run.template operator()<DiffusionOperator::ZhuFox>(); break;
      case DiffusionOperator::Tartakovsky: run.template operator()<DiffusionOperator::Tartakovsky>(); break;
      case DiffusionOperator::Monaghan: run.template operator()<DiffusionOperator::Monaghan>(); break;
    }
    double src_rate = 0.0;
    for (std::size_t a = 0; a < n; ++a) {
      if (P.kind[a] != Kind::Fluid) continue;
      const double rhoa = P.rho[a], ya = C[a] / rhoa;
      double r = rate[a] - advect * ya / rhoa * P.drho[a];
      if (sc.reaction_rate > 0.0) r -= sc.reaction_rate * (C[a] - sc.equilibrium) / rhoa;
      rate[a] = r;
      src_rate += from_walls_[a];
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
