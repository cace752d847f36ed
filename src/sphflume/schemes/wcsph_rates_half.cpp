// The weakly-compressible rates pass visiting each fluid pair once (scheme.pair_sweep: half, the default for the plain
// terms; docs/numerics.md §2): each cell's fluid rows against the fluid of its half stencil (CellList::half_ranges),
// a pair's two sides from one evaluation of the pair terms (schemes/wcsph_terms.hpp, Newton's third law), against the
// walls of its whole stencil as schemes/wcsph_rates.cpp's sweep does; the cells run in colours (sweep_colours), so
// the sums do not depend on the thread count. Resolution levels with one cell grid per level: the same within each
// level's grid, with per-pair h, and a pair between two levels visited from both ends (CellList::grid_half_ranges).
#include <cstdint>
#include <vector>

#include "sphflume/core/pair_pass.hpp"
#include "sphflume/schemes/wcsph.hpp"
#include "sphflume/schemes/wcsph_rates_pass.hpp"

namespace sph {

using namespace rates;  // (single precision: schemes/wcsph_terms.hpp)

namespace {
/// The candidates' columns a pass visiting each pair once adds b's side of its pairs into (one cell's part one), and
/// each entry's index as a float (the mask of a's own entry and those before it).
enum { ODR = NCOL, ODD, OA0, OA1, OA2, OS0, OS1, OS2, OKF, NCOL_ONCE };
struct OnceColumns {
  F32 *dr, *dd, *a0, *a1, *a2, *s0, *s1, *s2;
  const F32* kf;
};

/// Particle a's pair sums with the fluid candidates [kbeg, kend) of its cell's half stencil (part one of
/// gather_halves), the entries up to its own (pf) masked: the same terms as rates_sums for a fluid pair, each pair's
/// image for b added into b's columns. The terms' coefficients are taken per unit mass of b (momentum_coefficient with
/// m_b = 1, V_b = 1/ρ_b), so that a's side is m_b times them and b's −m_a times (continuity and the momentum's
/// pressure, viscosity and Π_ab are symmetric in the pair, ∇_b W = −∇_a W; δ-SPH's ψ_ab and XSPH's u_ab are
/// antisymmetric). VarH (resolution levels): the pair's h_ab = (h_a + h_b)/2 in the kernel, η², Π_ab and δ-SPH, as
/// rates_sums. No turbulence, porosity or phases (WCSPH::pair_loop runs those over the whole stencil).
template <int D, class K, bool Xsph, bool VarH>
[[gnu::always_inline]] inline RatesSums once_sums(const RatesPass<D>& q, const K& kl, const RatesColumns& c, const OnceColumns& o,
                                                  const RatesRow& ra, F32 ma, F32 pf, std::size_t kbeg, std::size_t kend,
                                                  F32& cnt_out) {
  constexpr std::size_t L = 16;
  const F32 l_fsupport2 = q.support2, l_feta2 = q.eta2, l_flam = q.lam;
  const F32 l_ffour = q.four, l_fwall_in = q.wall_in;
  const MomentumConstants mk{q.sym, q.visc_wall, q.alpha, q.h, q.chi};
  const F32 l_fg0 = F32(q.g[0]), l_fg1 = F32(q.g[1]), l_fg2 = F32(q.g[2]), frho0 = F32(q.rho0);
  const F32 Va = ma * ra.inv_rhoa;
  // a's sums in 16 fixed lanes, added in a fixed order at the end (lane_sum: the same bits on AVX2 and AVX-512; the
  // compiler's own reduction of `omp simd` added the lanes one by one, as costly as a block of pairs)
  enum { SA0, SA1, SA2, SS0, SS1, SS2, SDR, SDD, SCN, NS };
  alignas(64) F32 v[NS][L];
#pragma GCC unroll 16
  for (int i = 0; i < NS; ++i)
#pragma omp simd
    for (std::size_t l = 0; l < L; ++l) v[i][l] = F32(0);
  for (std::size_t k0 = kbeg; k0 < kend; k0 += L) {
    const F32* __restrict bx0 = c.x0 + k0; const F32* __restrict bx1 = c.x1 + k0; const F32* __restrict bx2 = c.x2 + k0;
    const F32* __restrict bu0 = c.u0 + k0; const F32* __restrict bu1 = c.u1 + k0; const F32* __restrict bu2 = c.u2 + k0;
    const F32* __restrict brho = c.rho + k0; const F32* __restrict bp = c.p + k0; const F32* __restrict bm = c.m + k0;
    const F32* __restrict bcs = c.cs + k0; const F32* __restrict kf = o.kf + k0;
    [[maybe_unused]] const F32* __restrict bhs = c.hs + k0;
    F32* __restrict odr = o.dr + k0; F32* __restrict odd = o.dd + k0;
    F32* __restrict oa0 = o.a0 + k0; F32* __restrict oa1 = o.a1 + k0; F32* __restrict oa2 = o.a2 + k0;
    F32* __restrict os0 = o.s0 + k0; F32* __restrict os1 = o.s1 + k0; F32* __restrict os2 = o.s2 + k0;
#pragma omp simd
    for (std::size_t l = 0; l < L; ++l) {
      const F32 after = kf[l] > pf ? F32(1) : F32(0);
      const F32 hij = VarH ? F32(0.5) * (ra.ha + bhs[l]) : F32(1), ih = VarH ? F32(1) / hij : F32(1);
      const PairGeometry g = pair_geometry<D, K, VarH>(kl, ra, bx0[l], bx1[l], bx2[l], F32(1), l_fsupport2, l_fwall_in, ih, after);
      const F32 devb = brho[l], rhob = frho0 + devb, mb = bm[l], pb = bp[l];
      const F32 cb = bcs[l];
      const F32 u0 = ra.va0 - bu0[l], u1 = ra.va1 - bu1[l], u2 = D == 3 ? ra.va2 - bu2[l] : F32(0);
      const PairInverses iv = pair_inverses(ra, g.r2, VarH ? l_feta2 * hij * hij : l_feta2, rhob, cb);
      const F32 cont = u0 * g.gw0 + u1 * g.gw1 + u2 * g.gw2;
      v[SDR][l] += cont * (mb * iv.rhob);
      odr[l] += cont * Va;
      const F32 fr = g.Fk * g.r2 * iv.r2e;
      const F32 gr = l_fg0 * g.r0 + l_fg1 * g.r1 + l_fg2 * g.r2c;
      const F32 psi = VarH ? (ra.deva - devb - l_ffour * iv.rho_sum * iv.csum * gr) * fr * hij
                           : (ra.deva - devb - l_ffour * iv.rho_sum * iv.csum * gr) * fr;
      v[SDD][l] += psi * (mb * iv.rhob);
      odd[l] -= psi * Va;
      const MomentumCoefficient mc = momentum_coefficient<D, true, false>(VarH ? MomentumConstants{mk.sym, mk.visc_wall, mk.alpha, hij, mk.chi} : mk,
                                                                          ra, g, iv, u0, u1, u2, F32(0), F32(0), F32(0),
                                                                          F32(1), pb, cb, F32(1), iv.rhob, F32(0));
      const F32 lamf = l_flam * fr * iv.rsum;
      const F32 m0 = lamf * mc.w0 - mc.gcoef * g.gw0, m1 = lamf * mc.w1 - mc.gcoef * g.gw1;
      v[SA0][l] += mb * m0; v[SA1][l] += mb * m1;
      oa0[l] -= ma * m0; oa1[l] -= ma * m1;
      if constexpr (D == 3) {
        const F32 m2 = lamf * mc.w2 - mc.gcoef * g.gw2;
        v[SA2][l] += mb * m2;
        oa2[l] -= ma * m2;
      }
      if constexpr (Xsph) {
        const F32 xw = F32(2) * iv.rsum * (VarH ? kl.Wh(g.r, ih) : kl.W(g.r)) * g.in;
        v[SS0][l] -= mb * xw * u0; v[SS1][l] -= mb * xw * u1;
        os0[l] += ma * xw * u0; os1[l] += ma * xw * u1;
        if constexpr (D == 3) {
          v[SS2][l] -= mb * xw * u2;
          os2[l] += ma * xw * u2;
        }
      }
      v[SCN][l] += g.in;
    }
  }
  cnt_out += lane_sum<L>(v[SCN]);
  const F32 a2 = D == 3 ? lane_sum<L>(v[SA2]) : F32(0);
  const F32 s0 = Xsph ? lane_sum<L>(v[SS0]) : F32(0), s1 = Xsph ? lane_sum<L>(v[SS1]) : F32(0);
  const F32 s2 = Xsph && D == 3 ? lane_sum<L>(v[SS2]) : F32(0);
  return {lane_sum<L>(v[SA0]), lane_sum<L>(v[SA1]), a2, s0, s1, s2, lane_sum<L>(v[SDR]), lane_sum<L>(v[SDD]), {}};
}

/// Adds one side of particle j's pair sums to its rates (the half-stencil sweep; WCSPH::sweep_once zeroes them and
/// adds gravity first): the density rate ρ_j Σ X V + δ-SPH's diffusion, the acceleration, XSPH's velocity.
template <int D, bool Xsph>
[[gnu::always_inline]] inline void add_rates(const RatesPass<D>& q, std::uint32_t j, F32 dr, F32 dd, const F32* a, const F32* s) {
  q.drho[j] += q.rho[j] * double(dr) + q.fdiff * q.dcoef * double(dd);
  for (int d = 0; d < D; ++d) q.acc[j][d] += double(a[d]);
  if constexpr (Xsph)
    for (int d = 0; d < D; ++d) q.xs[j][d] += q.xsph * double(s[d]);
}

/// Each side of the pairs is added to the rates: zero them, gravity for the particles that run (walls here have none).
template <int D>
void start_rates(const RatesPass<D>& q, std::size_t n) {
#pragma omp parallel for schedule(static)
  for (std::size_t a = 0; a < n; ++a) {
    Vec<D> g0{};
    if (q.runs(static_cast<std::uint32_t>(a)))
      for (int d = 0; d < D; ++d) g0[d] = q.g[d];
    q.acc[a] = g0;
    q.drho[a] = 0.0;
    if (q.xs) q.xs[a] = Vec<D>{};
  }
}

/// A store in cell order: how many walls come before each entry (np + 1 counts), so that the gathers copy a range
/// without walls as one run and skip the other half's ranges without walls.
inline void count_walls(const Kind* kind, std::size_t np, std::vector<std::uint32_t>& before) {
  before.resize(np + 1);
  std::uint32_t w = 0;
  for (std::size_t k = 0; k < np; ++k) {
    before[k] = w;
    w += fluid_like(kind[k]) ? 0u : 1u;
  }
  before[np] = w;
}

}  // namespace

template <int D>
template <class K, bool Xsph, bool VarH>
void WCSPH<D>::sweep_once(System<D>& S, const K& ker) {
  constexpr std::size_t L = 16;
  auto& P = S.particles;
  RatesPass<D> q = rates_pass_of<D, K, false, false, VarH>(S, cfg_, ker);
  const std::size_t np = P.size(), n = q.n_owned;
  pack_rates<D, false, false, false, VarH>(q, np, pack_);
  const F32* pk = pack_.data();
  start_rates(q, n);
  const auto& cells = S.cells;
  const std::uint32_t* __restrict sorted = cells.sorted().data();
  const Kind* kind = q.kind;
  auto fluid = [kind](std::uint32_t j) { return fluid_like(kind[j]); };
  if (cells.identity()) count_walls(kind, np, walls_before_);
  else walls_before_.resize(np + 1);
  const std::uint32_t* walls_before = walls_before_.data();
  // a cell's work: its fluid rows (a store in cell order: its entries less its walls; else all its entries)
  auto weight = [&](std::size_t cell) {
    const std::uint32_t b = cells.cell_begin(cell), e = cells.cell_end(cell);
    return cells.identity() ? (e - b) - (walls_before[e] - walls_before[b]) : e - b;
  };
  S.pairs_last_pass = sweep_colours<F32>(cells, NCOL_ONCE, weight, [&](std::size_t cell, ScratchColumns<F32>& B, std::vector<std::uint32_t>& ids) {
    const std::uint32_t c0k = cells.cell_begin(cell), c1k = cells.cell_end(cell);
    bool rows = false;  // the cell's fluid particles (halo ones too: their pairs give the owned their sums)
    for (std::uint32_t k = c0k; k < c1k && !rows; ++k) rows = fluid(sorted[k]);
    if (!rows) return std::uint64_t(0);
    CellStencil<D> half, other, cross;
    if (cells.level_grids()) half.nr = cells.grid_half_ranges(cell, half.rg, other.rg, other.nr, cross.rg, cross.nr);
    else half.nr = cells.half_ranges(cell, half.rg, other.rg, other.nr);
    for (CellStencil<D>* st : {&half, &other, &cross}) {
      st->count = 0;
      for (int r = 0; r < st->nr; ++r) st->count += st->rg[r][1] - st->rg[r][0];
      st->sorted = sorted;
      st->identity = cells.identity();
    }
    B.reserve((half.count + L - 1) / L * L + half.count + other.count + cross.count + 2 * L);
    if (ids.size() < half.count) ids.resize(half.count + half.count / 2);
    const Vec<D> origin = q.pos[sorted[c0k]];
    auto packed = [pk, np](int col, F32 pad = F32(0)) {
      return column(col, pad, [p = packed_column<D, false, false, false, VarH>(pk, np, col)](std::size_t j) { return p[j]; });
    };
    // part one: the fluid of the half stencil, from 0; part two: every wall of the stencil, from second
    const std::size_t second = (half.count + L - 1) / L * L;
    const HalvesEnds e = gather_halves(half, other, cross, B, ids.data(), q.pos, origin, L, second, walls_before, fluid, packed(U0),
                                       packed(U1), only_if<D == 3>(packed(U2)), packed(W0), packed(W1), only_if<D == 3>(packed(W2)),
                                       packed(RHO), packed(PRS), packed(MASS), packed(FLUID), packed(CS, F32(q.c0)),
                                       only_if<VarH>(packed(HS, F32(1))));
    RatesColumns c = rates_columns<D>(B, e.end);
    const OnceColumns o{B[ODR], B[ODD], B[OA0], B[OA1], B[OA2], B[OS0], B[OS1], B[OS2], B[OKF]};
    const std::size_t end1 = (e.count_first + L - 1) / L * L;  // (part one's blocks)
    {
      F32* __restrict z[8] = {o.dr, o.dd, o.a0, o.a1, o.a2, o.s0, o.s1, o.s2};
      F32* __restrict kf = B[OKF];
      for (int i = 0; i < (Xsph ? 8 : D == 3 ? 5 : 4); ++i) {
        F32* __restrict zi = z[i];
#pragma omp simd
        for (std::size_t m = 0; m < end1; ++m) zi[m] = F32(0);
      }
#pragma omp simd
      for (std::size_t m = 0; m < end1; ++m) kf[m] = F32(static_cast<int>(m));
    }
    const K kl = ker;
    F32 once = 0, walls = 0;
    std::size_t p = 0;  // a's entry in part one (the cell's own fluid come first, in store order)
    for (std::uint32_t k = c0k; k < c1k; ++k) {
      const std::uint32_t a = sorted[k];
      if (!fluid(a)) continue;
      const RatesRow ra = rates_row<D, false, false, false, VarH>(q, origin, a);
      const auto [b1, e1] = reach_blocks<D, VarH>(ra, c, q.support2, (p + 1) / L * L, end1);
      RatesSums s = once_sums<D, K, Xsph, VarH>(q, kl, c, o, ra, F32(q.mass[a]), F32(p), b1, e1, once);
      ++p;
      if (a >= q.n_owned || !q.runs(a)) continue;
      if (e.end > second) {  // the walls within reach (and the other grids' fluid: their pairs visited from both ends)
        const auto [b2, e2] = reach_blocks<D, VarH>(ra, c, q.support2, second, e.end);
        if (e2 > b2) {
          const RatesSums w = rates_sums<D, K, Xsph, false, false, false, true, VarH>(q, kl, c, ra, b2, e2, walls);
          s.a0 += w.a0; s.a1 += w.a1; s.a2 += w.a2; s.s0 += w.s0; s.s1 += w.s1; s.s2 += w.s2; s.dr += w.dr; s.dd += w.dd;
        }
      }
      const F32 sa[3] = {s.a0, s.a1, s.a2}, ss[3] = {s.s0, s.s1, s.s2};
      add_rates<D, Xsph>(q, a, s.dr, s.dd, sa, ss);
    }
    for (std::size_t m = 0; m < e.count_first; ++m) {  // b's side
      const std::uint32_t j = ids[m];
      if (j >= q.n_owned || !q.runs(j)) continue;
      const F32 sa[3] = {o.a0[m], o.a1[m], o.a2[m]}, ss[3] = {o.s0[m], o.s1[m], o.s2[m]};
      add_rates<D, Xsph>(q, j, o.dr[m], o.dd[m], sa, ss);
    }
    return static_cast<std::uint64_t>(F32(2) * once + walls + F32(0.5));  // (each fluid pair serves both ends)
  });
}

template <int D>
void WCSPH<D>::half_sweep(System<D>& S) {
  S.with_kernel([&](const auto& K) {
    using Ker = std::decay_t<decltype(K)>;
    if (S.levels > 0) {  // (per-pair h)
      if (cfg_.xsph > 0.0) sweep_once<Ker, true, true>(S, K);
      else sweep_once<Ker, false, true>(S, K);
    } else if (cfg_.xsph > 0.0) {
      sweep_once<Ker, true, false>(S, K);
    } else {
      sweep_once<Ker, false, false>(S, K);
    }
  });
}

template void WCSPH<2>::half_sweep(System<2>&);
template void WCSPH<3>::half_sweep(System<3>&);

}  // namespace sph
