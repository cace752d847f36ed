// The dual-criteria Riemann scheme's per-pair terms (schemes/dual_passes.cpp runs them over each
// cell's gathered candidates, 16 lanes at a time, core/pair_pass.hpp's LaneSums): Zhang, Hu &
// Adams (2017) as in the scheme's description, docs/numerics.md. In a header of their own so
// that each term is unit-tested on its own (tests/test_dual_terms.cpp).
#pragma once

#include <cmath>
#include <cstddef>

#include "sphflume/core/lanes8.hpp"
#include "sphflume/core/pair_pass.hpp"
#include "sphflume/core/particles.hpp"

namespace sph::dual {

using F32 = float;
/// The scratch columns of the passes: positions, velocities (pass B), wall normals (pass B's
/// wall part), p (sym: p/ρ²) (pass A), V = m/ρ (sym: m; the density pass on levels: m/ρ0) and,
/// with resolution levels, the smoothing length h.
enum { X0, X1, X2, U0, U1, U2, N0, N1, N2, PRS, VOL, HS, NCOL };

/// The columns of one block of kLanes candidates from k0 (pointers offset to the block: an index
/// k0 + l was a "complicated access pattern" to GCC's AVX2 vectoriser; x2 = x1 etc. in 2D).
struct Block {
  const F32* __restrict x0; const F32* __restrict x1; const F32* __restrict x2;
  const F32* __restrict u0; const F32* __restrict u1; const F32* __restrict u2;
  const F32* __restrict n0; const F32* __restrict n1; const F32* __restrict n2;
  const F32* __restrict p; const F32* __restrict v; const F32* __restrict h;
};
template <int D>
Block columns_of(ScratchColumns<F32>& B) {
  return {B[X0], B[X1], B[X0 + D - 1], B[U0], B[U1], B[U0 + D - 1], B[N0], B[N1], B[N0 + D - 1], B[PRS], B[VOL], B[HS]};
}
inline Block block_at(const Block& c, std::size_t k0) {
  return {c.x0 + k0, c.x1 + k0, c.x2 + k0, c.u0 + k0, c.u1 + k0, c.u2 + k0,
          c.n0 + k0, c.n1 + k0, c.n2 + k0, c.p + k0, c.v + k0, c.h + k0};
}

/// Particle a of a Riemann pass: its position relative to the cell's origin, velocity,
/// pressure term (sym: p/ρ²) and (levels) its smoothing length.
struct Row {
  F32 xa0, xa1, xa2, va0, va1, va2, pa, ha;
};

/// The kernel of one pair: W'(r)/r (F) and W (Wk) at the common h (one resolution) or at the pair's h_ab = (h_a +
/// h_b)/2 (VarH, resolution levels, docs/numerics.md §14; symmetric, so the pair sums conserve momentum across
/// levels), and whether b lies within the support (support2: the support² at the common h; VarH: the support
/// factor², compared with r²/h_ab²).
template <bool VarH>
struct PairKernel {
  F32 ih;  // 1/h_ab (VarH)
  [[gnu::always_inline]] PairKernel(const Row& a, const Block& b, std::size_t l) {
    if constexpr (VarH) ih = F32(2) / (a.ha + b.h[l]);
    else ih = F32(1);
  }
  [[gnu::always_inline]] bool inside(F32 r2, F32 support2) const {
    if constexpr (VarH) return (r2 * ih * ih < support2) & (r2 > F32(0));
    else return (r2 < support2) & (r2 > F32(0));
  }
  template <class K>
  [[gnu::always_inline]] F32 F(const K& ker, F32 r) const {
    if constexpr (VarH) return ker.Fh(r, ih);
    else return ker.F(r);
  }
  template <class K>
  [[gnu::always_inline]] F32 W(const K& ker, F32 r) const {
    if constexpr (VarH) return ker.Wh(r, ih);
    else return ker.W(r);
  }
};

/// r = x_a − x_b of particle a and lane l of block b, |r|² and |r| (2D: r2c = 0, not in the sums).
struct Separation {
  F32 r0, r1, r2c, r2, r;
};
template <int D>
[[gnu::always_inline]] inline Separation separation(const Row& a, const Block& b, std::size_t l) {
  const F32 r0 = a.xa0 - b.x0[l], r1 = a.xa1 - b.x1[l];
  const F32 r2c = D == 3 ? a.xa2 - b.x2[l] : F32(0);
  const F32 r2 = D == 3 ? r0 * r0 + r1 * r1 + r2c * r2c : r0 * r0 + r1 * r1;
  return {r0, r1, r2c, r2, std::sqrt(r2)};
}

/// The per-pair terms of the three passes: each adds one pair's terms (particle a against lane l
/// of block b) into its accumulators acc[i][l] in place, branch-free (in place, not returned:
/// each accumulation stays one expression, so GCC contracts it to a fused multiply-add).
/// Accumulators: density acc[0] Σ W, acc[1] the count; pressure acc[0..D) the pressure sum,
/// acc[D] the acoustic dissipation, acc[D+1] the count; continuity acc[0..D) the dissipation,
/// acc[D] (ua − ub)·∇W V_b. (The 2D terms spell out no third component: x * 0 and x + 0 are not folded away
/// under IEEE semantics, they would cost an operation each.)
/// Pass 2, the density summation: W(r) (VarH: W(r, h_ab) m_b/ρ0) and the neighbour count (the self term apart).
template <int D, class K, bool VarH = false, class Acc>
[[gnu::always_inline]] inline void density_terms(const K& ker, F32 support2, const Row& a, const Block& b, std::size_t l, Acc&& acc) {
  const auto [r0, r1, r2c, r2, r] = separation<D>(a, b, l);
  const PairKernel<VarH> pk(a, b, l);
  const F32 in = pk.inside(r2, support2) ? F32(1) : F32(0);
  if constexpr (VarH) acc[0][l] += pk.W(ker, r) * b.v[l] * in;
  else acc[0][l] += ker.W(r) * in;
  acc[1][l] += in;
}
/// Pass A, pressure: (pa + pb) F r V_b (sym: m_b), the acoustic dissipation's W'(r) V_b (pa − pb)
/// and the neighbour count. No mask: F is 0 from the support on (the padding sits far away) and
/// the self pair's terms carry r = 0.
template <int D, class K, bool VarH = false, class Acc>
[[gnu::always_inline]] inline void pressure_terms(const K& ker, F32 support2, const Row& a, const Block& b, std::size_t l, Acc&& acc) {
  const auto [r0, r1, r2c, r2, r] = separation<D>(a, b, l);
  const PairKernel<VarH> pk(a, b, l);
  acc[D + 1][l] += pk.inside(r2, support2) ? F32(1) : F32(0);  // the count
  const F32 Fv = pk.F(ker, r) * b.v[l];  // W'(r)/r V_b (sym: m_b)
  const F32 pp = (a.pa + b.p[l]) * Fv;
  acc[0][l] += pp * r0;
  acc[1][l] += pp * r1;
  if constexpr (D == 3) acc[2][l] += pp * r2c;
  acc[D][l] += (a.pa - b.p[l]) * Fv * r;  // W'(r) V_b (pa − pb)
}
/// The Riemann dissipation's factor β U (the pair's weight): β = min(k max(U, 0)/c0, 1), fk = k/c0. max(U, 0) as
/// (U + |U|)/2 (exact in float) and min as a value select: GCC 12 left the pass's loop scalar on AVX2 with std::max
/// or a select here (AVX-512 was fine).
/// One lane (F32) or eight (lanes8::v8f, the kept rows). (-Wpsabi: as in core/lanes8.hpp.)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"
[[gnu::always_inline]] inline F32 abs_lanes(F32 x) { return std::abs(x); }
[[gnu::always_inline]] inline lanes8::v8f abs_lanes(lanes8::v8f x) { return lanes8::abs(x); }
[[gnu::always_inline]] inline F32 min1_lanes(F32 x) { return x < F32(1) ? x : F32(1); }
[[gnu::always_inline]] inline lanes8::v8f min1_lanes(lanes8::v8f x) { return x < F32(1) ? x : lanes8::splat(1.0f); }
template <class T>
[[gnu::always_inline]] inline T limited_dissipation(T fk, T U, T weight) {
  const T bu = fk * F32(0.5) * (U + abs_lanes(U));
  const T beta = min1_lanes(bu);
  return beta * U * weight;
}
#pragma GCC diagnostic pop
/// Pass B, continuity and dissipation: (ua − ub)·r F V_b and β U F V_b d, U = −(ua − ub)·e the
/// approach speed and d the dissipation's direction times r: r itself for fluid b; against a wall
/// (WallBlock) twice the speed along n', its normal turned towards a, and d = r n' (the
/// padding's n = 0 adds nothing).
template <int D, bool WallBlock, class K, bool VarH = false, class Acc>
[[gnu::always_inline]] inline void continuity_terms(const K& ker, F32 fk, const Row& a, const Block& b, std::size_t l, Acc&& acc) {
  const auto [r0, r1, r2c, r2, r] = separation<D>(a, b, l);
  const F32 Fv = PairKernel<VarH>(a, b, l).F(ker, r) * b.v[l];
  const F32 u0 = a.va0 - b.u0[l], u1 = a.va1 - b.u1[l];
  const F32 u2 = D == 3 ? a.va2 - b.u2[l] : F32(0);
  const F32 ur = D == 3 ? u0 * r0 + u1 * r1 + u2 * r2c : u0 * r0 + u1 * r1;  // (ua − ub)·r
  acc[D][l] += ur * Fv;
  F32 d0 = r0, d1 = r1, d2 = r2c, U;
  if constexpr (WallBlock) {
    const F32 n0 = b.n0[l], n1 = b.n1[l], n2 = D == 3 ? b.n2[l] : F32(0);
    const F32 rn = D == 3 ? r0 * n0 + r1 * n1 + r2c * n2 : r0 * n0 + r1 * n1;
    const F32 sn = (rn < F32(0) ? F32(-1) : F32(1)) * r;
    d0 = sn * n0;
    d1 = sn * n1;
    if constexpr (D == 3) d2 = sn * n2;
    const F32 ud = D == 3 ? u0 * d0 + u1 * d1 + u2 * d2 : u0 * d0 + u1 * d1;
    U = F32(-2) * ud / (r + F32(1e-30));
  } else {
    U = -ur / (r + F32(1e-30));
  }
  const F32 q = limited_dissipation(fk, U, Fv);
  acc[0][l] += q * d0;
  acc[1][l] += q * d1;
  if constexpr (D == 3) acc[2][l] += q * d2;
}

/// Pack the per-particle values the candidates of pass `Pass` need, once per pass in store order
/// (a division per particle, not one per particle per stencil it falls in), so that the per-cell
/// gathers only move floats; the pair sums are bitwise those of gathering from the particle
/// arrays. Pass A: p (sym: p/ρ²) and V = m/ρ (sym: m); pass B: u, V, the wall normal (unit,
/// walls only) and the fluid flag. Columns (the cell passes: value c of particle i at c np + i), or
/// with Records the kept passes' records (dual_pairs.cpp, core/lanes8.hpp): pass A {p, V} at 2 i;
/// pass B {u, V} in four floats at 4 i (2D: u0, u1, V, 0) and the normal {n, 0} at 4 np + 4 i (no
/// fluid flag). The same values either way.
template <int D, int Pass, bool Records = false>
inline void pack_columns(ParticleStore<D>& P, bool sym, std::vector<float>& pack) {
  const double* __restrict rho = P.rho.data();
  const double* __restrict prs = P.p.data();
  const double* __restrict mass = P.mass.data();
  const Vec<D>* __restrict vel = P.vel.data();
  const Kind* __restrict kind = P.kind.data();
  const std::size_t np = P.size();
  const int npack = Pass == 0 ? 2 : Pass == 1 ? 2 * D + 2 : 0;
  if constexpr (Records) {
    // (one size for both passes: resizing from pass A's to pass B's filled the difference with zeros each step)
    if (pack.size() < 8 * np) pack.resize(8 * np);
  } else {
    pack.resize(static_cast<std::size_t>(npack) * np);
  }
  F32* __restrict pk = pack.data();
  if constexpr (Pass == 0) {
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < np; ++i) {
      const F32 pv = F32(sym ? prs[i] / (rho[i] * rho[i]) : prs[i]);
      const F32 vv = F32(sym ? mass[i] : mass[i] / rho[i]);
      pk[Records ? 2 * i : i] = pv;
      pk[Records ? 2 * i + 1 : np + i] = vv;
    }
  } else if constexpr (Pass == 1) {
    const Vec<D>* __restrict wn = P.vector(field::wall_to_surface).data();
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < np; ++i) {
      F32 u[4] = {0, 0, 0, 0}, n[4] = {0, 0, 0, 0};
      for (int d = 0; d < D; ++d) u[d] = F32(vel[i][d]);
      u[D] = F32(mass[i] / rho[i]);
      const bool fl = fluid_like(kind[i]);
      const double len = fl ? 0.0 : std::sqrt(dot(wn[i], wn[i]));
      for (int d = 0; d < D; ++d) n[d] = len > 0.0 ? F32(wn[i][d] / len) : F32(0);
      if constexpr (Records) {
        for (int c = 0; c < 4; ++c) {
          pk[4 * i + c] = u[c];
          pk[4 * (np + i) + c] = n[c];
        }
      } else {
        for (int c = 0; c <= D; ++c) pk[c * np + i] = u[c];
        for (int d = 0; d < D; ++d) pk[(D + 1 + d) * np + i] = n[d];
        pk[(2 * D + 1) * np + i] = fl ? F32(1) : F32(0);
      }
    }
  }
}

}  // namespace sph::dual
