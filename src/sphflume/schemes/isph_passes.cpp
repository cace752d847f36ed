// ISPH's pair passes (schemes/isph.hpp): the summation density, the PPE's assembly and the
// pressure correction, on the vectorised skeleton every pair loop shares (core/cell_list.hpp,
// sweep_cells): the candidates of a cell's 3^D stencil are copied once into unit-stride columns
// and each particle of the cell runs a branch-free loop over them. The passes stay in double
// precision (the PPE's source is a small density difference). Tsurudome §3.4 (eqs 3.4.49-3.4.51).
#include <algorithm>
#include <cmath>

#include "sphflume/core/pair_pass.hpp"
#include "sphflume/boundaries/walls.hpp"
#include "sphflume/core/cell_list.hpp"
#include "sphflume/physics/porous.hpp"
#include "sphflume/schemes/isph.hpp"

namespace sph {
namespace {

/// The PPE's per-candidate columns of one cell's stencil (assemble), and each particle's sums over them.
struct PpeColumns {
  const double* __restrict x0; const double* __restrict x1; const double* __restrict x2;
  const double* __restrict u0; const double* __restrict u1; const double* __restrict u2;
  const double* __restrict rho; const double* __restrict m; const double* __restrict fl;
  const double* __restrict in; const double* __restrict phi; const double* __restrict mob;
  const double* __restrict col; const double* __restrict off;
  double* __restrict c;  // out: c_ij per candidate, -1 where the candidate is no neighbour
  std::size_t npad;
};
/// Particle i of the PPE (Tsurudome eq 3.4.49; porous: SPHAM): its position (relative to the cell's origin) and
/// velocity, density, fluid flag, porosity and mobility (1 outside media), its own column.
struct PpeRow {
  double xa0, xa1, xa2, va0, va1, va2, ri, fi, phii, mobi, me;
};
struct PpeSums {
  double diag = 0.0, div = 0.0, known = 0.0;
};

/// Σ_j over the stencil of particle a: the Laplacian's weights c_ij into b.c, the diagonal −Σ c_ij (its own
/// column left out), the velocity divergence Σ m_j F r_ij·(u_j − u_i) and the dummies' known offsets. Porous
/// (SPHAM): (1/φ_i) ∇·(φ ∇P/ρ) = (1/φ_i) ∇·(φ u*)/Δt + ...; a fluid neighbour's volume m/(φ ρ), a wall's its
/// own (dx^D); a wall continues the medium of the fluid it faces; the conductivity φ m_d, so that the correction
/// meets the drag as the prediction does. Outside media (Porous false) every φ and m_d is 1 and the terms are
/// the plain ones, one division a pair.
template <int D, bool Porous, class K>
PpeSums ppe_sums(const K& kl, const PpeColumns& b, const PpeRow& a, double eta2) {
  const double sup2 = kl.support2;
  const double xa0 = a.xa0, xa1 = a.xa1, xa2 = a.xa2, va0 = a.va0, va1 = a.va1, va2 = a.va2, ri = a.ri;
  const double fi = a.fi, phii = a.phii, mobi = a.mobi, me = a.me;
  const double* __restrict bx0 = b.x0;
  const double* __restrict bx1 = b.x1;
  const double* __restrict bx2 = b.x2;
  const double* __restrict bu0 = b.u0;
  const double* __restrict bu1 = b.u1;
  const double* __restrict bu2 = b.u2;
  const double* __restrict brho = b.rho;
  const double* __restrict bm = b.m;
  const double* __restrict bfl = b.fl;
  const double* __restrict bin = b.in;
  const double* __restrict bphi = b.phi;
  const double* __restrict bmob = b.mob;
  const double* __restrict bcol = b.col;
  const double* __restrict boff = b.off;
  double* __restrict cc = b.c;
  double diag = 0.0, div = 0.0, known = 0.0;
#pragma omp simd reduction(+ : diag, div, known)
  for (std::size_t m = 0; m < b.npad; ++m) {
    const double r0 = xa0 - bx0[m], r1 = xa1 - bx1[m], r2c = D == 3 ? xa2 - bx2[m] : 0.0;
    const double r2 = r0 * r0 + r1 * r1 + r2c * r2c;
    const double in = (r2 < sup2) & (r2 > 0.0) ? bin[m] : 0.0;
    const double F = kl.F(std::sqrt(r2));  // ∇_i W = F r_ij, F <= 0
    double c, dvol;  // c_ij; m_j F r_ij·(u_j − u_i) (porous: φ-weighted, over φ_a)
    if constexpr (Porous) {
      const double fj = bfl[m];
      const double pa = fi * phii + (1.0 - fi) * (fj * bphi[m] + (1.0 - fj));
      const double pb = fj * bphi[m] + (1.0 - fj) * pa;
      const double mj = bm[m] / (fj * pb + (1.0 - fj));
      const double ka = pa * (fi * mobi + (1.0 - fi) * (fj * bmob[m] + (1.0 - fj)));
      const double kb = pb * (fj * bmob[m] + (1.0 - fj) * ka / pa);
      const double rs = ri + brho[m];
      c = in * (-8.0 * mj / (rs * rs) * F * r2 / (r2 + eta2)) * (2.0 * ka * kb / ((ka + kb) * pa));
      const double dv = (pb * bu0[m] - pa * va0) * r0 + (pb * bu1[m] - pa * va1) * r1 +
                        (D == 3 ? (pb * bu2[m] - pa * va2) * r2c : 0.0);
      dvol = in * mj * F * dv / pa;
    } else {
      const double rs = ri + brho[m];
      c = in * (-8.0 * bm[m] * F * r2) / (rs * rs * (r2 + eta2));
      const double dv = (bu0[m] - va0) * r0 + (bu1[m] - va1) * r1 + (D == 3 ? (bu2[m] - va2) * r2c : 0.0);
      dvol = in * bm[m] * F * dv;
    }
    div += dvol;
    known -= c * boff[m];  // a dummy's P_foot + offset: the offset is known
    diag -= bcol[m] == me ? 0.0 : c;  // the particle itself (a dummy under it, or its own image): cancels
    cc[m] = in > 0.0 ? c : -1.0;  // (-1: no neighbour; c >= 0 otherwise)
  }
  return {diag, div, known};
}

}  // namespace

template <int D>
template <class K>
void ISPH<D>::kernel_density(System<D>& S, const K& ker) {
  // Σ_j (m_j/φ_j) W_ij of every owned fluid and wall particle, self included, into drho
  auto& P = S.particles;
  const std::size_t n_owned = P.n_owned();
  const double* phi = S.porous ? P.scalar(field::porosity).data() : nullptr;
  const Vec<D>* pos = P.pos.data();
  const double* mass = P.mass.data();
  const Kind* kind = P.kind.data();
  const std::uint32_t* sorted = S.cells.sorted().data();
  double* out = P.drho.data();
  const auto& cells = S.cells;
  enum { X0, X1, X2, MV, NCOL };
  sweep_cells<double>(cells, NCOL, kIsphLanes, [&](std::size_t cell) { return owned_in(cells, cell, n_owned, kind, false); },
                      [&](std::size_t cell, const CellStencil<D>& st, ScratchColumns<double>& B) {
    const K kl = ker;
    const double sup2 = kl.support2, w0 = kl.W(0.0);
    const std::uint32_t c0k = cells.cell_begin(cell), c1k = cells.cell_end(cell);
    const Vec<D> origin = pos[sorted[c0k]];
    gather_columns(st, B, pos, origin, column(MV, 0.0, [phi, mass](std::size_t b) { return phi ? mass[b] / phi[b] : mass[b]; }));
    const double* __restrict bx0 = B[X0];
    const double* __restrict bx1 = B[X1];
    const double* __restrict bx2 = B[X0 + D - 1];
    const double* __restrict bm = B[MV];
    const std::size_t npad = st.padded;
    std::uint64_t pairs = 0;
    for (std::uint32_t k = c0k; k < c1k; ++k) {
      const std::uint32_t a = sorted[k];
      if (a >= n_owned || (kind[a] != Kind::Fluid && kind[a] != Kind::Wall)) continue;
      double xa0, xa1, xa2;
      relative<D>(pos[a], origin, xa0, xa1, xa2);
      double s = 0.0;
#pragma omp simd reduction(+ : s)
      for (std::size_t m = 0; m < npad; ++m) {
        const double r0 = xa0 - bx0[m], r1 = xa1 - bx1[m], r2c = D == 3 ? xa2 - bx2[m] : 0.0;
        const double r2 = r0 * r0 + r1 * r1 + r2c * r2c;
        const double in = (r2 < sup2) & (r2 > 0.0) ? 1.0 : 0.0;
        s += in * bm[m] * kl.W(std::sqrt(r2));
      }
      out[a] = (phi ? mass[a] / phi[a] : mass[a]) * w0 + s;
      pairs += st.count;
    }
    return pairs;
  });
}

template <int D>
template <class K>
void ISPH<D>::assemble(System<D>& S, const K& ker, double dt) {
  auto& P = S.particles;
  const std::size_t n_owned = P.n_owned();
  const double eta2 = o_.eta2 * S.h * S.h;
  const bool split = o_.source == PpeSource::Split;
  const double gamma = o_.source == PpeSource::Hybrid ? o_.gamma : (o_.source == PpeSource::DivergenceFree || split) ? 1.0 : 0.0;
  const double rr = S.eos.rho0;  // the densities are normalised (solve_pressure)
  const std::size_t rows = static_cast<std::size_t>(std::count_if(unknown_.begin(), unknown_.end(), [](int k) { return k >= 0; }));
  const double* phi = S.porous ? P.scalar(field::porosity).data() : nullptr;
  const double* mob = S.porous ? P.scalar(field::mobility).data() : nullptr;
  // each row into its own slot (the slots keep their capacity from step to step), then
  // concatenated in row order (deterministic)
  rows_.resize(rows);
  std::vector<double> rhs(rows, 0.0);
  rhs_density_.assign(split ? rows : 0, 0.0);
  const Vec<D>* pos = P.pos.data();
  const Vec<D>* vel = P.vel.data();
  const double* mass = P.mass.data();
  const double* rho = P.rho.data();
  const Kind* kind = P.kind.data();
  const std::uint32_t* sorted = S.cells.sorted().data();
  const auto& cells = S.cells;
  // columns: position, velocity, density, mass, fluid flag, in-the-PPE flag (fluid or wall),
  // porosity and mobility (1 outside media), the PPE column a neighbour's pressure stands in
  // (-1: known), a dummy's known offset; per candidate of the particle: c_ij
  enum { X0, X1, X2, U0, U1, U2, RHO, MASS, FL, IN, PHI, MOB, COL, OFF, C, NCOL };
  sweep_cells<double>(cells, NCOL, kIsphLanes, [&](std::size_t cell) {
    const std::uint32_t* so = cells.sorted().data();
    std::size_t m = 0;
    for (std::uint32_t k = cells.cell_begin(cell); k < cells.cell_end(cell); ++k)
      if (so[k] < n_owned && unknown_[so[k]] >= 0) ++m;
    return m;
  }, [&](std::size_t cell, const CellStencil<D>& st, ScratchColumns<double>& B) {
    const K kl = ker;
    const std::uint32_t c0k = cells.cell_begin(cell), c1k = cells.cell_end(cell);
    const Vec<D> origin = pos[sorted[c0k]];
    auto velocity = [vel](int d) { return [vel, d](std::size_t b) { return vel[b][d]; }; };
    auto fluid = [kind](std::size_t b) { return kind[b] == Kind::Fluid; };
    gather_columns(st, B, pos, origin, column(U0, 0.0, velocity(0)), column(U1, 0.0, velocity(1)),
                   only_if<D == 3>(column(U2, 0.0, velocity(D - 1))), column(RHO, rr, [rho](std::size_t b) { return rho[b]; }),
                   column(MASS, 0.0, [mass](std::size_t b) { return mass[b]; }),
                   column(FL, 0.0, [fluid](std::size_t b) { return fluid(b) ? 1.0 : 0.0; }),
                   column(IN, 0.0, [kind](std::size_t b) { return kind[b] == Kind::Fluid || kind[b] == Kind::Wall ? 1.0 : 0.0; }),
                   column(PHI, 1.0, [phi, fluid](std::size_t b) { return phi && fluid(b) ? phi[b] : 1.0; }),
                   column(MOB, 1.0, [mob, fluid](std::size_t b) { return mob && fluid(b) ? mob[b] : 1.0; }),
                   column(COL, -1.0, [c = col_.data()](std::size_t b) { return c[b]; }),
                   column(OFF, 0.0, [o = off_.data()](std::size_t b) { return o[b]; }));
    const PpeColumns cols{B[X0], B[X1], B[X0 + D - 1], B[U0], B[U1], B[D == 3 ? U2 : U1], B[RHO], B[MASS], B[FL], B[IN], B[PHI],
                          B[MOB], B[COL], B[OFF], B[C], st.padded};
    const double* __restrict bcol = B[COL];
    const double* __restrict cc = B[C];
    const std::size_t cnt = st.count;
    std::uint64_t pairs = 0;
    for (std::uint32_t k = c0k; k < c1k; ++k) {
      const std::uint32_t i = sorted[k];
      if (i >= n_owned || unknown_[i] < 0) continue;
      auto& e = rows_[static_cast<std::size_t>(unknown_[i])];
      e.clear();
      PpeRow row;
      relative<D>(pos[i], origin, row.xa0, row.xa1, row.xa2);
      row.va0 = vel[i][0];
      row.va1 = vel[i][1];
      row.va2 = vel[i][D - 1];
      const double ri = row.ri = rho[i];
      row.fi = kind[i] == Kind::Fluid ? 1.0 : 0.0;
      row.phii = phi && row.fi > 0.0 ? phi[i] : 1.0;
      row.mobi = mob && row.fi > 0.0 ? mob[i] : 1.0;
      const double me = row.me = double(first_row_ + static_cast<std::size_t>(unknown_[i]));  // (global unknown numbers)
      const auto [diag, div, known] = phi ? ppe_sums<D, true>(kl, cols, row, eta2) : ppe_sums<D, false>(kl, cols, row, eta2);
      for (std::size_t m = 0; m < cnt; ++m)
        if (cc[m] >= 0.0 && bcol[m] >= 0.0 && bcol[m] != me) e.emplace_back(static_cast<int>(bcol[m]), cc[m]);
      pairs += cnt;
      const int mei = static_cast<int>(me);
      if (cls_[i] != 0) {  // a P = 0 particle's identity row (stable row numbering)
        e.assign(1, {mei, diag < 0.0 ? diag : -1.0});
        rhs[static_cast<std::size_t>(unknown_[i])] = 0.0;
        continue;
      }
      finish_row(e, mei, diag);
      const double b_hs = div / (rr * dt);
      // the density-invariant part: a deficit (a truncated support at the free surface, or a
      // particle the flow has just left room around) is not sucked back unless asked for
      const double b_std = (o_.density_deficit ? rr - ri : std::min(rr - ri, 0.0)) / (rr * dt * dt);
      rhs[static_cast<std::size_t>(unknown_[i])] = gamma * b_hs + (1.0 - gamma) * b_std + known;
      if (split) rhs_density_[static_cast<std::size_t>(unknown_[i])] = o_.relaxation * b_std;  // (a dummy's offset: not a density error)
    }
    return pairs;
  });
  sys_.first_row = first_row_;
  sys_.stable_rows = stable_rows_;
  sys_.set_rows(rows_);
  sys_.rhs.swap(rhs);
}

template <int D>
template <class K>
void ISPH<D>::correct(System<D>& S, const K& ker, double dt) {
  auto& P = S.particles;
  const std::size_t n_owned = P.n_owned();
  // the gradient normalised by its lattice moment (gradient_normalisation: lattice): exact for a
  // linear pressure on a full lattice (κ = 0.99 for Wendland C2 at h/dx 1.5)
  const double inv_kappa = o_.gradient_lattice && kappa_ > 0.0 ? 1.0 / kappa_ : 1.0;
  const double* phi = S.porous ? P.scalar(field::porosity).data() : nullptr;
  const double* mob = S.porous ? P.scalar(field::mobility).data() : nullptr;
  const double* psi = o_.source == PpeSource::Split ? P.scalar(field::psi).data() : nullptr;
  Vec<D>* dr = psi ? P.vector(field::density_shift).data() : nullptr;
  const Vec<D>* pos = P.pos.data();
  const double* mass = P.mass.data();
  const double* rho = P.rho.data();
  const double* prs = P.p.data();
  const Kind* kind = P.kind.data();
  const std::uint32_t* sorted = S.cells.sorted().data();
  Vec<D>* vel = P.vel.data();
  const auto& cells = S.cells;
  // columns: position; the neighbour's volume factor m_j (a porous fluid neighbour m_j/φ_j, 0
  // for a particle outside the PPE); P_j/ρ_j²; ψ_j/ρ_j² (source.type split)
  enum { X0, X1, X2, MV, PR, PS, NCOL };
  sweep_cells<double>(cells, NCOL, kIsphLanes, [&](std::size_t cell) { return owned_in(cells, cell, n_owned, kind, true); },
                      [&](std::size_t cell, const CellStencil<D>& st, ScratchColumns<double>& B) {
    const K kl = ker;
    const double sup2 = kl.support2;
    const std::uint32_t c0k = cells.cell_begin(cell), c1k = cells.cell_end(cell);
    const Vec<D> origin = pos[sorted[c0k]];
    gather_columns(st, B, pos, origin, column(MV, 0.0, [kind, mass, phi](std::size_t b) {
                     return kind[b] == Kind::Fluid ? (phi ? mass[b] / phi[b] : mass[b]) : kind[b] == Kind::Wall ? mass[b] : 0.0;
                   }),
                   column(PR, 0.0, [prs, rho](std::size_t b) { return prs[b] * (1.0 / (rho[b] * rho[b])); }),
                   column(PS, 0.0, [psi, rho](std::size_t b) { return psi ? psi[b] * (1.0 / (rho[b] * rho[b])) : 0.0; }));
    const double* __restrict bx0 = B[X0];
    const double* __restrict bx1 = B[X1];
    const double* __restrict bx2 = B[X0 + D - 1];
    const double* __restrict bmv = B[MV];
    const double* __restrict bpr = B[PR];
    const double* __restrict bps = B[PS];
    const std::size_t npad = st.padded;
    std::uint64_t pairs = 0;
    for (std::uint32_t k = c0k; k < c1k; ++k) {
      const std::uint32_t i = sorted[k];
      if (i >= n_owned || kind[i] != Kind::Fluid) continue;
      double xa0, xa1, xa2;
      relative<D>(pos[i], origin, xa0, xa1, xa2);
      const double ri2 = 1.0 / (rho[i] * rho[i]);
      const double pi = prs[i] * ri2, si = psi ? psi[i] * ri2 : 0.0;
      // the symmetric gradient (eq 3.4.51): Σ m_j (P_i/ρ_i² + P_j/ρ_j²) F r_ij
      double g0 = 0.0, g1 = 0.0, g2 = 0.0, h0 = 0.0, h1 = 0.0, h2 = 0.0;
#pragma omp simd reduction(+ : g0, g1, g2, h0, h1, h2)
      for (std::size_t m = 0; m < npad; ++m) {
        const double r0 = xa0 - bx0[m], r1 = xa1 - bx1[m], r2c = D == 3 ? xa2 - bx2[m] : 0.0;
        const double r2 = r0 * r0 + r1 * r1 + r2c * r2c;
        const double in = (r2 < sup2) & (r2 > 0.0) ? bmv[m] : 0.0;
        const double wF = in * kl.F(std::sqrt(r2));
        const double gp = wF * (pi + bpr[m]), gs = wF * (si + bps[m]);
        g0 += gp * r0; g1 += gp * r1; g2 += gp * r2c;
        h0 += gs * r0; h1 += gs * r1; h2 += gs * r2c;
      }
      pairs += st.count;
      const double scale = inv_kappa * (mob ? mob[i] : 1.0);
      Vec<D> grad{}, gpsi{};
      grad[0] = g0; grad[1] = g1; gpsi[0] = h0; gpsi[1] = h1;
      if constexpr (D == 3) { grad[2] = g2; gpsi[2] = h2; }
      vel[i] -= (dt * scale) * grad;
      if (dr) dr[i] = (-dt * dt * scale) * gpsi;
    }
    return pairs;
  });
}

#define SPH_ISPH_PASSES(D, K)                                                     \
  template void ISPH<D>::kernel_density<K<D>>(System<D>&, const K<D>&);           \
  template void ISPH<D>::assemble<K<D>>(System<D>&, const K<D>&, double);         \
  template void ISPH<D>::correct<K<D>>(System<D>&, const K<D>&, double);
SPH_ISPH_PASSES(2, WendlandC2)
SPH_ISPH_PASSES(2, CubicSpline)
SPH_ISPH_PASSES(2, QuinticSpline)
SPH_ISPH_PASSES(3, WendlandC2)
SPH_ISPH_PASSES(3, CubicSpline)
SPH_ISPH_PASSES(3, QuinticSpline)
#undef SPH_ISPH_PASSES

}  // namespace sph
