// The weakly-compressible rates pass's per-pair terms (schemes/wcsph_rates.cpp inlines them into
// its one fused, vectorised pair loop, rates_particle): each term a short function of particle
// a's row and candidate b's columns, in a header of its own so that each is unit-tested
// (tests/test_wcsph_terms.cpp). The accumulations themselves stay in the loop: returned or
// passed by reference they changed the bits or cost 4-7 % (docs/architecture.md §6).
#pragma once

#include <cmath>

namespace sph::rates {

// The pair loop runs in single precision (16 lanes of AVX-512, fast division and square root), as
// DualSPHysics does on GPUs: positions are stored relative to the cell's first particle (|r| < 3
// supports, so float keeps ~1e-7 relative accuracy in r), the pair sums are converted back to
// double per particle. Particle state and time integration stay in double precision.
using F32 = float;

/// Particle a as its pair loop reads it (positions relative to the cell's origin; τ_a/ρ_a²;
/// porous φ_a; a dynamic wall takes continuity from fluid only: wa = 0).
struct RatesRow {
  F32 xa0, xa1, xa2, va0, va1, va2, deva, rhoa, pa, ca, ca2, pha, pa_r2, inv_rhoa, wa;
  F32 ta0, ta1, ta2, ta3, ta4, ta5, phia, iphia;
  F32 ha;  // resolution levels: a's smoothing length
  double rhoa_d, phia_d;
};
/// One pair's geometry: r = x_a − x_b, |r|², the mask `in` (a neighbour within the support, not
/// a itself; a wall a only sees fluid; purely repulsive walls are in no sum: wall_in = 0) and
/// ∇_a W = F(r) r, masked. The pair terms below are each one short function of these, inlined
/// into the one fused loop (rates_particle).
struct PairGeometry {
  F32 r0, r1, r2c, r2, r, in, Fk, gw0, gw1, gw2;
};
/// VarH (resolution levels, docs/numerics.md §14): the kernel at the pair's h_ij = (h_a + h_b)/2,
/// given as ih = 1/h_ij, and support2 the support factor squared (the support test r²/h_ij² <
/// factor²); h_ij is symmetric, so ∇_a W_ab = −∇_b W_ba and the pair terms conserve momentum
/// between particles of different sizes.
template <int D, class K, bool VarH = false>
[[gnu::always_inline]] inline PairGeometry pair_geometry(const K& kl, const RatesRow& ra, F32 xb0, F32 xb1, F32 xb2, F32 fb,
                                                         F32 support2, F32 wall_in, [[maybe_unused]] F32 ih = F32(1),
                                                         F32 mask = F32(1)) {
  PairGeometry g;
  g.r0 = ra.xa0 - xb0; g.r1 = ra.xa1 - xb1; g.r2c = D == 3 ? ra.xa2 - xb2 : F32(0);
  g.r2 = g.r0 * g.r0 + g.r1 * g.r1 + g.r2c * g.r2c;
  if constexpr (VarH)
    g.in = ((g.r2 * ih * ih < support2) & (g.r2 > F32(0))) ? mask * (ra.wa + (F32(1) - ra.wa) * fb) * (fb + (F32(1) - fb) * wall_in) : F32(0);
  else
    g.in = ((g.r2 < support2) & (g.r2 > F32(0))) ? mask * (ra.wa + (F32(1) - ra.wa) * fb) * (fb + (F32(1) - fb) * wall_in) : F32(0);
  g.r = std::sqrt(g.r2);
  if constexpr (VarH) g.Fk = kl.Fh(g.r, ih) * g.in;
  else g.Fk = kl.F(g.r) * g.in;
  g.gw0 = g.Fk * g.r0; g.gw1 = g.Fk * g.r1; g.gw2 = g.Fk * g.r2c;
  return g;
}

/// The four reciprocals a pair needs (1/ρ_b, 1/(r² + η²), 1/(ρ_a + ρ_b), 1/(c_a² + c_b²)) from one
/// division, and ρ_a + ρ_b.
struct PairInverses {
  F32 rhob, r2e, rsum, csum, rho_sum;
};
[[gnu::always_inline]] inline PairInverses pair_inverses(const RatesRow& ra, F32 r2, F32 eta2, F32 rhob, F32 cb) {
  const F32 cb2 = cb * cb;
  const F32 r2e = r2 + eta2, rsum = ra.rhoa + rhob, csum = ra.ca2 + cb2;
  const F32 p1 = rhob * r2e, p2 = rsum * csum;
  const F32 inv = F32(1) / (p1 * p2);
  return {inv * r2e * p2, inv * rhob * p2, inv * p1 * csum, inv * p1 * rsum, rsum};
}

/// The porosity b's velocity is weighted with in the continuity and viscous terms (SPHAM, Kazemi
/// eqs 4.56-4.57): φ_b for fluid b seen by fluid a; a wall b takes the porosity of the fluid it
/// faces (it is no porosity interface); a wall a sees its fluid neighbours as plain fluid.
[[gnu::always_inline]] inline F32 flow_porosity(const RatesRow& ra, F32 fb, F32 phib) {
  const F32 sel = fb * ra.wa;
  return sel * phib + (F32(1) - sel) * (ra.wa * ra.phia + (F32(1) - ra.wa));
}

/// The coefficient of ∇W in a pair's momentum terms: pressure (symmetric or sum form, p/Γ) plus
/// Monaghan's Π_ab on the viscous velocity difference w (fluid b its velocity, wall b the wall
/// model's ghost one, mv = 0 where walls take no viscosity), plus the phases' interface repulsion
/// −(χ/ρ_a) Σ_{b∉X} (|p_a|/Γ_a + |p_b|/Γ_b) ∇W V_b.
struct MomentumCoefficient {
  F32 gcoef, mv, w0, w1, w2;
};
struct MomentumConstants {  // (a local copy in the loop's function: see rates_particle)
  F32 sym, visc_wall, alpha, h, chi;
};
template <int D, bool Press, bool Multi>
[[gnu::always_inline]] inline MomentumCoefficient momentum_coefficient(const MomentumConstants& q, const RatesRow& ra,
                                                                       const PairGeometry& g, const PairInverses& iv,
                                                                       F32 u0, F32 u1, F32 u2, F32 bw0, F32 bw1, F32 bw2,
                                                                       F32 fb, F32 pb, F32 cb, F32 mbp, F32 Vb, F32 phsb) {
  MomentumCoefficient m;
  const F32 pterm = Press ? q.sym * mbp * (ra.pa_r2 + pb * iv.rhob * iv.rhob) + (F32(1) - q.sym) * (ra.pa + pb) * Vb * ra.inv_rhoa
                          : F32(0);
  m.mv = fb + (F32(1) - fb) * q.visc_wall;
  m.w0 = u0 + bw0; m.w1 = u1 + bw1; m.w2 = D == 3 ? u2 + bw2 : F32(0);
  // (a value select, not std::min: its reference result kept GCC's AVX2 code scalar)
  const F32 wr = m.w0 * g.r0 + m.w1 * g.r1 + m.w2 * g.r2c;
  const F32 vr = wr < F32(0) ? wr : F32(0);
  const F32 pi_ab = -q.alpha * (ra.ca + cb) * q.h * vr * iv.r2e * iv.rsum;  // Monaghan Π_ab
  m.gcoef = pterm + m.mv * mbp * pi_ab;
  if constexpr (Multi) {
    const F32 other = fb * (phsb != ra.pha ? F32(1) : F32(0));
    m.gcoef += q.chi * other * (std::abs(ra.pa) + std::abs(pb)) * Vb * ra.inv_rhoa;
  }
  return m;
}

}  // namespace sph::rates
