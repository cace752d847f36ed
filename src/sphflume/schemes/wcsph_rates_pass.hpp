// The rates pass's shared parts (schemes/wcsph_rates.cpp runs each particle over its cell's whole stencil,
// schemes/wcsph_rates_half.cpp each fluid pair once over half stencils): what the pass reads and its constants, the
// packed candidate columns and their gather, particle a's row, the reach of its blocks, and the fused single-precision
// pair loop over a range of candidates (rates_sums). Private to the scheme's rates files.
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <vector>

#include "sphflume/boundaries/walls.hpp"
#include "sphflume/core/pair_pass.hpp"
#include "sphflume/physics/turbulence.hpp"
#include "sphflume/schemes/wcsph_terms.hpp"

namespace sph::rates {
enum { X0, X1, X2, U0, U1, U2, W0, W1, W2, RHO, PRS, MASS, FLUID, CS, T0, PHI = T0 + 6, IPHI, REF, PHS, HS, NCOL };

/// What the rates pass reads and writes, and its constants. Every optional term is on the same
/// code path, scaled by a 0/1 (or coefficient) factor: the inner loop has no branches and
/// vectorises.
template <int D>
struct RatesPass {
  const Vec<D>* pos; const Vec<D>* vel; const double* rho; const double* prs; const double* mass;
  const Kind* kind;
  const float* wcorr;   // no-slip walls' ghost correction of the viscous velocity (or null)
  const double* phi;    // porous media (SPHAM, Kazemi eqs 4.56-4.57): φ of every particle (walls 1)
  const double* phase;  // phases: each particle's phase (its EOS in peos)
  const double* gam;    // Grenier: pressures enter as p/Γ (walls Γ = 1)
  const double* tau[6]; // turbulence: the stress of the previous pass (kinematic, τ/ρ)
  const double* hs;     // resolution levels: each particle's smoothing length
  const Eos* peos;
  Eos eos;
  Vec<D>* acc; double* drho; Vec<D>* xs; double* grad;
  std::size_t n_owned;
  bool dyn;  // walls evolve their density (dynamic walls get rates)
  double g[3], rho0, c0, xsph, fdiff, dcoef;
  // the loop's float constants; chi: interface repulsion
  // (resolution levels: support2 is the support factor squared, eta2 the coefficient of h_ij²)
  F32 support2, eta2, h, lam, alpha, four, sym, visc_wall, wall_in, chi;

  [[gnu::always_inline]] double ref_of(std::size_t b) const { return phase ? peos[static_cast<std::size_t>(phase[b])].rho0 : rho0; }
  [[gnu::always_inline]] double sound_of(std::size_t b, double rh) const {
    return phase ? peos[static_cast<std::size_t>(phase[b])].sound_speed(rh) : eos.sound_speed(rh);
  }
  [[gnu::always_inline]] double p_of(std::size_t b) const { return gam && fluid_like(kind[b]) ? prs[b] / gam[b] : prs[b]; }
  /// imposed-state particles need no rates: walls (unless dynamic) and outflow particles; inflow
  /// particles get theirs (unused while they are inflow) so that one turning into fluid has the
  /// rates of its state, which the Verlet integrator's next step uses
  [[gnu::always_inline]] bool runs(std::uint32_t a) const { return !((kind[a] == Kind::Wall && !dyn) || kind[a] == Kind::Outflow); }
};

/// The rates pass's inputs, outputs and constants (turbulence's stress and gradient set by the sweep).
template <int D, class K, bool Porous, bool Multi, bool VarH>
RatesPass<D> rates_pass_of(System<D>& S, const SchemeConfig& cfg, const K& ker) {
  auto& P = S.particles;
  const double h = S.h;
  const double tiny = 1e-12 * h * h;  // keeps the masked self pair finite when eta2 = 0
  RatesPass<D> q{};
  q.pos = P.pos.data(); q.vel = P.vel.data(); q.rho = P.rho.data(); q.prs = P.p.data(); q.mass = P.mass.data();
  q.kind = P.kind.data();
  q.wcorr = S.walls->viscous_correction();
  q.phi = Porous ? P.scalar(field::porosity).data() : nullptr;
  q.phase = Multi ? P.scalar(field::phase).data() : nullptr;
  q.gam = (Multi && S.grenier) ? P.scalar(field::gamma_grenier).data() : nullptr;
  q.hs = VarH ? P.require(field::smoothing_length).data() : nullptr;
  q.peos = S.phase_eos.data();
  q.eos = S.eos;
  q.acc = P.acc.data(); q.drho = P.drho.data();
  q.xs = cfg.xsph > 0.0 ? P.vector(field::xsph).data() : nullptr;
  q.n_owned = P.n_owned();
  q.dyn = S.walls->evolves_density();
  for (int d = 0; d < D; ++d) q.g[d] = S.gravity[d];
  q.rho0 = S.eos.rho0; q.c0 = S.eos.c0; q.xsph = cfg.xsph;
  q.fdiff = (cfg.density_diffusion != DensityDiffusion::None && cfg.delta > 0.0) ? 1.0 : 0.0;
  q.dcoef = 2.0 * cfg.delta * (VarH ? 1.0 : h) * q.c0;  // (levels: h_ij in the pair sum)
  const double wall_in = S.walls->in_pair_sums() ? 1.0 : 0.0;  // walls enter the pair sums at all
  const double visc_wall = S.walls->cfg.no_slip ? 1.0 : 0.0;    // walls enter the viscous terms
  q.support2 = F32(ker.support2); q.eta2 = F32(cfg.eta2 * h * h + tiny); q.h = F32(h);
  if constexpr (VarH) {  // per pair: the support factor², η² / h_ij²
    q.support2 = F32(K::support_factor * K::support_factor);
    q.eta2 = F32(cfg.eta2 + 1e-12);
  }
  q.lam = F32((cfg.viscosity == ViscosityModel::Laminar) ? 4.0 * S.nu : 0.0);
  q.alpha = F32((cfg.viscosity == ViscosityModel::Artificial) ? cfg.alpha : cfg.alpha_on_laminar);
  q.four = F32(cfg.density_diffusion == DensityDiffusion::Fourtakas ? 1.0 : 0.0);
  q.sym = F32(cfg.pressure_gradient == PressureGradient::Symmetric ? 1.0 : 0.0);
  q.visc_wall = F32(visc_wall * wall_in); q.wall_in = F32(wall_in); q.chi = F32(Multi ? S.chi : 0.0);
  return q;
}

/// The packed columns a pass with these terms reads, one after another: column c's slot, or -1 when the pass does not
/// read it (a 2D pass without turbulence, porosity, phases or levels packs 9 of the 22 columns).
template <int D, bool Turb, bool Porous, bool Multi, bool VarH>
constexpr int pack_slot(int c) {
  constexpr int NT = Turbulence<D>::kStress;
  int s = 0;
  for (int k = U0; k < NCOL; ++k) {
    const bool used = k < U0 + D || (k >= W0 && k < W0 + D) || (k >= RHO && k <= CS) || (Turb && k >= T0 && k < T0 + NT) ||
                      (Porous && (k == PHI || k == IPHI)) || (Multi && (k == REF || k == PHS)) || (VarH && k == HS);
    if (k == c) return used ? s : -1;
    s += used ? 1 : 0;
  }
  return s;  // (c == NCOL: the number of packed columns)
}

/// Every column's slot, computed by the compiler (GCC evaluated pack_slot's loop at run time inside the pack's particle
/// loop when levels add the HS column: the pack then cost five times as much per particle).
template <int D, bool Turb, bool Porous, bool Multi, bool VarH>
inline constexpr std::array<int, NCOL + 1> kPackSlots = [] {
  std::array<int, NCOL + 1> s{};
  for (int c = 0; c <= NCOL; ++c) s[static_cast<std::size_t>(c)] = pack_slot<D, Turb, Porous, Multi, VarH>(c);
  return s;
}();

/// Column c of the pack (the pack's start for a column the pass does not read, which it never dereferences).
template <int D, bool Turb, bool Porous, bool Multi, bool VarH, class T>
T* packed_column(T* pk, std::size_t np, int c) {
  const int s = kPackSlots<D, Turb, Porous, Multi, VarH>[static_cast<std::size_t>(c)];
  return pk + static_cast<std::size_t>(s < 0 ? 0 : s) * np;
}

/// The candidates' columns, packed once per pass in store order (a particle's values computed
/// once, not once per stencil it falls in: the candidate-wise copy was a fifth of the 2D dam
/// break's time, mostly the sound speed's power law): velocity, the no-slip walls' ghost
/// correction, the density's deviation from its phase's reference (neighbour differences keep
/// full float precision), pressure, mass, fluid flag, sound speed c(ρ_b) (any EOS); turbulence
/// τ_b/ρ_b (walls carry none of their own); porous φ and 1/φ; phases ρ_ref and the phase.
/// Column c of particle i at pack[slot(c) np + i], only the columns the pass reads (pack_slot); the per-cell gathers
/// then only move floats.
template <int D, bool Turb, bool Porous, bool Multi, bool VarH>
void pack_rates(const RatesPass<D>& q, std::size_t np, std::vector<F32>& pack) {
  constexpr int NT = Turbulence<D>::kStress;
  pack.resize(static_cast<std::size_t>(pack_slot<D, Turb, Porous, Multi, VarH>(NCOL)) * np);
  F32* __restrict pk = pack.data();
  auto col = [pk, np](int c) { return packed_column<D, Turb, Porous, Multi, VarH>(pk, np, c); };
  // (the columns' starts before the particle loop: nothing per particle but the values)
  F32* __restrict cu[D];
  F32* __restrict cw[D];
  for (int d = 0; d < D; ++d) { cu[d] = col(U0 + d); cw[d] = col(W0 + d); }
  F32* __restrict crho = col(RHO); F32* __restrict cprs = col(PRS); F32* __restrict cm = col(MASS);
  F32* __restrict cfl = col(FLUID); F32* __restrict ccs = col(CS); F32* __restrict cref = col(REF); F32* __restrict cphs = col(PHS);
  F32* __restrict cphi = col(PHI); F32* __restrict ciphi = col(IPHI); F32* __restrict chs = col(HS);
  F32* __restrict ct[NT];
  for (int t = 0; t < NT; ++t) ct[t] = col(T0 + t);
  const Eos eos = q.eos;
  if (np == 0) return;
#pragma omp parallel
  {
    // (the columns and the plain inputs as the thread's own locals: read through the region's shared struct, each
    // was loaded again after every store and the loop ran scalar, a twentieth of a band run's time on two threads;
    // the same values)
    F32* __restrict u0 = cu[0]; F32* __restrict u1 = cu[1]; [[maybe_unused]] F32* __restrict u2 = cu[D - 1];
    F32* __restrict w0 = cw[0]; F32* __restrict w1 = cw[1]; [[maybe_unused]] F32* __restrict w2 = cw[D - 1];
    F32* __restrict lrho = crho; F32* __restrict lprs = cprs; F32* __restrict lm = cm; F32* __restrict lfl = cfl;
    F32* __restrict lcs = ccs; [[maybe_unused]] F32* __restrict lhs = chs;
    const Kind* __restrict kind = q.kind;
    const double* __restrict vel = q.vel->c.data();
    const double* __restrict rho = q.rho; const double* __restrict prs = q.prs; const double* __restrict mass = q.mass;
    const double* __restrict gam = q.gam; [[maybe_unused]] const double* __restrict hs = q.hs;
    const float* __restrict wcorr = q.wcorr;
    const double rho0 = q.rho0;
#pragma omp for schedule(static)
    for (std::size_t b = 0; b < np; ++b) {
      const bool fl = fluid_like(kind[b]);
      const double rb = rho[b];
      const double ref = Multi ? q.peos[static_cast<std::size_t>(q.phase[b])].rho0 : rho0;
      u0[b] = F32(vel[D * b]);
      u1[b] = F32(vel[D * b + 1]);
      w0[b] = fl || !wcorr ? F32(0) : wcorr[b * D];
      w1[b] = fl || !wcorr ? F32(0) : wcorr[b * D + 1];
      if constexpr (D == 3) {
        u2[b] = F32(vel[D * b + 2]);
        w2[b] = fl || !wcorr ? F32(0) : wcorr[b * D + 2];
      }
      lrho[b] = F32(rb - ref);
      lprs[b] = F32(gam && fl ? prs[b] / gam[b] : prs[b]);
      lm[b] = F32(mass[b]);
      lfl[b] = fl ? F32(1) : F32(0);
      lcs[b] = F32(Multi ? q.peos[static_cast<std::size_t>(q.phase[b])].sound_speed(rb) : eos.sound_speed(rb));
      if constexpr (Multi) {
        cref[b] = F32(ref);
        cphs[b] = F32(q.phase[b]);
      }
      if constexpr (Turb)
        for (int t = 0; t < NT; ++t) ct[t][b] = fl ? F32(q.tau[t][b] / rb) : F32(0);
      if constexpr (Porous) {
        cphi[b] = F32(q.phi[b]);
        ciphi[b] = F32(1.0 / q.phi[b]);
      }
      if constexpr (VarH) lhs[b] = F32(hs[b]);
    }
  }
}

/// A cell's candidate columns (column descriptors over the packed values; padding: far away,
/// massless, φ = 1, the reference phase).
template <int D, bool Turb, bool Porous, bool Multi, bool VarH>
void gather_rates(const RatesPass<D>& q, const F32* pk, std::size_t np, const CellStencil<D>& st,
                  ScratchColumns<F32>& B, const Vec<D>& origin) {
  auto packed = [pk, np](int c, F32 pad = F32(0)) {
    return column(c, pad, [p = packed_column<D, Turb, Porous, Multi, VarH>(pk, np, c)](std::size_t j) { return p[j]; });
  };
  constexpr int NT = Turbulence<D>::kStress;
  gather_columns(st, B, q.pos, origin, packed(U0), packed(U1), only_if<D == 3>(packed(U2)), packed(W0), packed(W1),
              only_if<D == 3>(packed(W2)), packed(RHO), packed(PRS), packed(MASS), packed(FLUID), packed(CS, F32(q.c0)),
              only_if<Turb>(packed(T0)), only_if<Turb>(packed(T0 + 1)), only_if<Turb>(packed(T0 + 2)),
              only_if<(Turb && NT > 3)>(packed(T0 + 3)), only_if<(Turb && NT > 4)>(packed(T0 + 4)),
              only_if<(Turb && NT > 5)>(packed(T0 + 5)), only_if<Porous>(packed(PHI, F32(1))),
              only_if<Porous>(packed(IPHI, F32(1))), only_if<Multi>(packed(REF, F32(q.rho0))),
              only_if<Multi>(packed(PHS, F32(-1))), only_if<VarH>(packed(HS, F32(1))));
}

/// One cell's candidate columns as the pair loop reads them (x2 = x1 etc. in 2D; stress columns
/// 2D: xx, xz, zz; 3D: xx, yy, zz, xy, xz, yz).
struct RatesColumns {
  const F32 *x0, *x1, *x2, *u0, *u1, *u2, *w0, *w1, *w2, *rho, *p, *m, *f, *cs;
  const F32 *t0, *t1, *t2, *t3, *t4, *t5, *phi, *iphi, *ref, *phs, *hs;
  std::size_t npad;
};
template <int D>
RatesColumns rates_columns(ScratchColumns<F32>& B, std::size_t npad) {
  return {B[X0], B[X1], B[X0 + D - 1], B[U0], B[U1], B[U0 + D - 1], B[W0], B[W1], B[W0 + D - 1], B[RHO], B[PRS],
          B[MASS], B[FLUID], B[CS], B[T0], B[T0 + 1], B[T0 + 2], B[T0 + (D == 3 ? 3 : 0)], B[T0 + (D == 3 ? 4 : 0)],
          B[T0 + (D == 3 ? 5 : 0)], B[PHI], B[IPHI], B[REF], B[PHS], B[HS], npad};
}

template <int D, bool Turb, bool Porous, bool Multi, bool VarH>
[[gnu::always_inline]] inline RatesRow rates_row(const RatesPass<D>& q, const Vec<D>& origin, std::uint32_t a) {
  constexpr int NT = Turbulence<D>::kStress;
  RatesRow r;
  const Vec<D>& x = q.pos[a];
  const Vec<D>& v = q.vel[a];
  r.xa0 = F32(x[0] - origin[0]); r.xa1 = F32(x[1] - origin[1]); r.xa2 = F32(x[D - 1] - origin[D - 1]);
  r.va0 = F32(v[0]); r.va1 = F32(v[1]); r.va2 = F32(v[D - 1]);
  const double rhoa_d = q.rho[a];
  r.rhoa_d = rhoa_d;
  r.deva = F32(rhoa_d - q.ref_of(a));
  r.rhoa = F32(rhoa_d);
  r.pa = F32(q.p_of(a));
  r.ca = F32(q.sound_of(a, rhoa_d));
  r.ca2 = r.ca * r.ca;
  r.pha = Multi ? F32(q.phase[a]) : F32(0);
  r.pa_r2 = F32(q.prs[a] / (rhoa_d * rhoa_d));
  r.inv_rhoa = F32(1.0 / rhoa_d);
  r.wa = q.kind[a] == Kind::Wall ? F32(0) : F32(1);
  F32 ta[6] = {0, 0, 0, 0, 0, 0};
  if constexpr (Turb)
    for (int t = 0; t < NT; ++t) ta[t] = F32(q.tau[t][a] / rhoa_d);
  r.ta0 = ta[0]; r.ta1 = ta[1]; r.ta2 = ta[2]; r.ta3 = ta[3]; r.ta4 = ta[4]; r.ta5 = ta[5];
  r.phia_d = Porous ? q.phi[a] : 1.0;
  r.phia = F32(r.phia_d);
  r.iphia = F32(1.0 / r.phia_d);
  r.ha = VarH ? F32(q.hs[a]) : F32(0);
  return r;
}

/// Particle a's pair sums, as the loop leaves them.
struct RatesSums {
  F32 a0, a1, a2, s0, s1, s2, dr, dd;
  F32 g[9];  // the velocity gradient (turbulence; 2D: xx, xz, zx, zz)
};
/// Particle a's rates from its sums: the density rate (continuity, δ-SPH's diffusion), the
/// acceleration with gravity, XSPH's velocity, the turbulence's velocity gradient; a dynamic
/// wall only its density rate.
template <int D, bool Turb>
[[gnu::always_inline]] inline void store_rates(const RatesPass<D>& q, std::uint32_t a, const RatesRow& r,
                                                const RatesSums& s) {
  if constexpr (Turb) {
    double* G = q.grad + std::size_t(a) * D * D;
    for (int i = 0; i < D * D; ++i) G[i] = s.g[i];
  }
  if (q.kind[a] == Kind::Wall) {
    q.drho[a] = r.rhoa_d * double(s.dr);
    q.acc[a] = Vec<D>{};
    return;
  }
  q.drho[a] = r.rhoa_d / r.phia_d * double(s.dr) + q.fdiff * q.dcoef * double(s.dd);
  Vec<D> acc, sx;
  for (int d = 0; d < D; ++d) acc[d] = double(d == 0 ? s.a0 : d == 1 ? s.a1 : s.a2) + q.g[d];
  for (int d = 0; d < D; ++d) sx[d] = q.xsph * double(d == 0 ? s.s0 : d == 1 ? s.s1 : s.s2);
  q.acc[a] = acc;
  if (q.xs) q.xs[a] = sx;
}

/// The candidates particle a can reach, as whole blocks of 16 (the loop's lanes): the stencil's first and last cell rows
/// lie beyond a's support when a sits near its cell's other side (a fifth of the 2D dam break's blocks), and every
/// term of a candidate beyond the support is a zero. Blocks are dropped only from the two ends, so that every
/// candidate left keeps its vector lane (k mod 8 and mod 16) and each lane's sum its order: the sums are bitwise those
/// of the whole range. The test counts a itself, walls and 1 % beyond the support as within reach (only ever a block
/// too many).
struct BlockRange {
  std::size_t begin, end;
};
template <int D, bool VarH>
[[gnu::always_inline]] inline BlockRange reach_blocks(const RatesRow& ra, const RatesColumns& c, F32 support2, std::size_t b,
                                                      std::size_t e) {
  constexpr std::size_t L = 16;
  const F32 reach = F32(1.01) * support2;  // (a margin: the loop's own test may round r² differently, by FMA)
  auto within = [&](std::size_t k0) {
    // (each lane's r² − limit, then their minimum by halves: the compiler's own `omp simd` reduction added the lanes
    // one by one through the stack)
    alignas(64) F32 d[L];
#pragma omp simd
    for (std::size_t l = 0; l < L; ++l) {
      const std::size_t k = k0 + l;
      const F32 r0 = ra.xa0 - c.x0[k], r1 = ra.xa1 - c.x1[k], r2c = D == 3 ? ra.xa2 - c.x2[k] : F32(0);
      const F32 r2 = r0 * r0 + r1 * r1 + r2c * r2c;
      F32 lim = reach;
      if constexpr (VarH) {
        const F32 hij = F32(0.5) * (ra.ha + c.hs[k]);
        lim = reach * hij * hij;
      }
      d[l] = r2 - lim;
    }
    // (the halves' minimum as whole vectors: GCC's vector extensions, 16 lanes on AVX-512, two halves of 8 on AVX2)
    using V16 = F32 __attribute__((vector_size(64)));
    using V8 = F32 __attribute__((vector_size(32)));
    using V4 = F32 __attribute__((vector_size(16)));
    V16 x;
    std::memcpy(&x, d, sizeof x);
    const V8 lo8 = __builtin_shufflevector(x, x, 0, 1, 2, 3, 4, 5, 6, 7), hi8 = __builtin_shufflevector(x, x, 8, 9, 10, 11, 12, 13, 14, 15);
    const V8 m8 = lo8 < hi8 ? lo8 : hi8;
    const V4 lo4 = __builtin_shufflevector(m8, m8, 0, 1, 2, 3), hi4 = __builtin_shufflevector(m8, m8, 4, 5, 6, 7);
    const V4 m4 = lo4 < hi4 ? lo4 : hi4;
    const F32 m2a = m4[0] < m4[2] ? m4[0] : m4[2], m2b = m4[1] < m4[3] ? m4[1] : m4[3];
    return (m2a < m2b ? m2a : m2b) < F32(0);
  };
  while (b < e && !within(b)) b += L;
  while (e > b && !within(e - L)) e -= L;
  return {b, e};
}

/// Particle a's pair sums over the candidates [kbeg, kend) of its cell's columns (the fused, vectorised loop: every
/// term of the momentum and continuity equations in one pass); adds its pair count to cnt.
/// VarH (resolution levels): the pair's h_ab = (h_a + h_b)/2 in the kernel, η², Π_ab and δ-SPH.
template <int D, class K, bool Xsph, bool Turb, bool Porous, bool Multi, bool Press, bool VarH>
[[gnu::always_inline]] inline RatesSums rates_sums(const RatesPass<D>& q, const K& kl, const RatesColumns& c, const RatesRow& ra,
                                                   std::size_t kbeg, std::size_t kend, F32& cnt_out) {
  // the loop's constants as locals (read through a pointer, GCC's AVX2 vectoriser could not keep
  // them in registers and left the loop scalar)
  const F32 l_fsupport2 = q.support2, l_feta2 = q.eta2, l_flam = q.lam;
  const F32 l_ffour = q.four, l_fwall_in = q.wall_in;
  const MomentumConstants mk{q.sym, q.visc_wall, q.alpha, q.h, q.chi};
  const F32 l_fg0 = F32(q.g[0]), l_fg1 = F32(q.g[1]), l_fg2 = F32(q.g[2]), frho0 = F32(q.rho0);
  const F32* __restrict bx0 = c.x0; const F32* __restrict bx1 = c.x1; const F32* __restrict bx2 = c.x2;
  const F32* __restrict bu0 = c.u0; const F32* __restrict bu1 = c.u1; const F32* __restrict bu2 = c.u2;
  const F32* __restrict bw0 = c.w0; const F32* __restrict bw1 = c.w1; const F32* __restrict bw2 = c.w2;
  const F32* __restrict brho = c.rho; const F32* __restrict bp = c.p; const F32* __restrict bm = c.m;
  const F32* __restrict bf = c.f; const F32* __restrict bcs = c.cs;
  const F32* __restrict bt0 = c.t0; const F32* __restrict bt1 = c.t1; const F32* __restrict bt2 = c.t2;
  const F32* __restrict bt3 = c.t3; const F32* __restrict bt4 = c.t4; const F32* __restrict bt5 = c.t5;
  const F32* __restrict bphi = c.phi; const F32* __restrict biphi = c.iphi;
  const F32* __restrict bref = c.ref; const F32* __restrict bphs = c.phs; const F32* __restrict bhs = c.hs;
  F32 a0 = 0, a1 = 0, a2 = 0, s0 = 0, s1 = 0, s2 = 0, dr = 0, dd = 0, cnt = 0;
  F32 g00 = 0, g01 = 0, g02 = 0, g10 = 0, g11 = 0, g12 = 0, g20 = 0, g21 = 0, g22 = 0;
#pragma omp simd reduction(+ : a0, a1, a2, s0, s1, s2, dr, dd, cnt, g00, g01, g02, g10, g11, g12, g20, g21, g22)
  for (std::size_t k = kbeg; k < kend; ++k) {
    const F32 fb = bf[k];
    const F32 hij = VarH ? F32(0.5) * (ra.ha + bhs[k]) : F32(1), ih = VarH ? F32(1) / hij : F32(1);
    const PairGeometry g = pair_geometry<D, K, VarH>(kl, ra, bx0[k], bx1[k], bx2[k], fb, l_fsupport2, l_fwall_in, ih);
    const F32 devb = brho[k], rhob = (Multi ? bref[k] : frho0) + devb, mb = bm[k], pb = bp[k];
    const F32 cb = bcs[k];
    const F32 u0 = ra.va0 - bu0[k], u1 = ra.va1 - bu1[k], u2 = D == 3 ? ra.va2 - bu2[k] : F32(0);
    const PairInverses iv = pair_inverses(ra, g.r2, VarH ? l_feta2 * hij * hij : l_feta2, rhob, cb);
    // porous: b's volume m/(φ_b ρ_b); continuity of the porosity-weighted velocity (φ_a u_a − φ_b u_b)
    const F32 ivb = Porous ? biphi[k] : F32(1);
    const F32 mbp = mb * ivb;
    const F32 Vb = mbp * iv.rhob;
    const F32 phf = Porous ? flow_porosity(ra, fb, bphi[k]) : F32(1);
    const F32 pa_c = Porous ? ra.wa * ra.phia + (F32(1) - ra.wa) : F32(1);
    const F32 uc0 = Porous ? pa_c * ra.va0 - phf * bu0[k] : u0;
    const F32 uc1 = Porous ? pa_c * ra.va1 - phf * bu1[k] : u1;
    const F32 uc2 = Porous ? (D == 3 ? pa_c * ra.va2 - phf * bu2[k] : F32(0)) : u2;
    dr += (uc0 * g.gw0 + uc1 * g.gw1 + uc2 * g.gw2) * Vb;
    const F32 fr = g.Fk * g.r2 * iv.r2e;  // regularised F (r·∇W/(r²+η²))
    // δ-SPH: Fourtakas removes the hydrostatic density difference ρ g·r / c² (pair means)
    const F32 gr = l_fg0 * g.r0 + l_fg1 * g.r1 + l_fg2 * g.r2c;
    // (phases: within a phase only; the density jump between phases is no error to diffuse)
    const F32 same = Multi ? (bphs[k] == ra.pha ? F32(1) : F32(0)) : F32(1);
    if constexpr (VarH) dd += same * fb * (ra.deva - devb - l_ffour * iv.rho_sum * iv.csum * gr) * fr * Vb * hij;
    else dd += same * fb * (ra.deva - devb - l_ffour * iv.rho_sum * iv.csum * gr) * fr * Vb;
    const MomentumCoefficient mc = momentum_coefficient<D, Press, Multi>(
        VarH ? MomentumConstants{mk.sym, mk.visc_wall, mk.alpha, hij, mk.chi} : mk, ra, g, iv, u0, u1, u2, bw0[k], bw1[k], bw2[k], fb, pb, cb, mbp, Vb, Multi ? bphs[k] : F32(0));
    if constexpr (Porous) {
      // Kazemi eq 4.57: μ m_b/(φ_a φ_b) [2 (φu)_ab + φ_ab u_ab] ... = the plain term on
      // (φ_a − φ_b) u_a + (φ_a + φ_b)/2 (u_a − u_b), φ_b the flow porosity above
      const F32 lamf = mc.mv * l_flam * mbp * fr * iv.rsum * ra.iphia;
      const F32 dphi = ra.phia - phf, mphi = F32(0.5) * (ra.phia + phf);
      a0 += lamf * (dphi * ra.va0 + mphi * mc.w0) - mc.gcoef * g.gw0;
      a1 += lamf * (dphi * ra.va1 + mphi * mc.w1) - mc.gcoef * g.gw1;
      a2 += lamf * (dphi * (D == 3 ? ra.va2 : F32(0)) + mphi * mc.w2) - mc.gcoef * g.gw2;
    } else {
      const F32 lamf = mc.mv * l_flam * mb * fr * iv.rsum;
      a0 += lamf * mc.w0 - mc.gcoef * g.gw0;
      a1 += lamf * mc.w1 - mc.gcoef * g.gw1;
      a2 += lamf * mc.w2 - mc.gcoef * g.gw2;
    }
    if constexpr (Turb) {
      // velocity gradient (∂u_i/∂x_j)_a = Σ V_b (u_b − u_a)_i ∂_j W, walls through the
      // wall model's velocity as in the viscous term
      const F32 gv = mc.mv * Vb;
      g00 -= mc.w0 * g.gw0 * gv; g01 -= mc.w0 * g.gw1 * gv;
      g10 -= mc.w1 * g.gw0 * gv; g11 -= mc.w1 * g.gw1 * gv;
      if constexpr (D == 3) {
        g02 -= mc.w0 * g.gw2 * gv; g12 -= mc.w1 * g.gw2 * gv;
        g20 -= mc.w2 * g.gw0 * gv; g21 -= mc.w2 * g.gw1 * gv; g22 -= mc.w2 * g.gw2 * gv;
      }
      // stress divergence Σ m_b (τ_a/ρ_a² + τ_b/ρ_b²)·∇W; walls carry no modelled stress;
      // porous: Σ m_b/(φ_a φ_b) (φ_a τ_a/ρ_a² + φ_b τ_b/ρ_b²)·∇W (Kazemi eq 4.57). (In the loop:
      // returned from a function, the terms were added in another order, the bits changed)
      const F32 fa = mbp, fbm = Porous ? mb * ra.iphia : mb;
      if constexpr (D == 2) {  // (xx, xz, zz)
        a0 += (fa * ra.ta0 + fbm * bt0[k]) * g.gw0 + (fa * ra.ta1 + fbm * bt1[k]) * g.gw1;
        a1 += (fa * ra.ta1 + fbm * bt1[k]) * g.gw0 + (fa * ra.ta2 + fbm * bt2[k]) * g.gw1;
      } else {  // (xx, yy, zz, xy, xz, yz)
        const F32 txx = fa * ra.ta0 + fbm * bt0[k], tyy = fa * ra.ta1 + fbm * bt1[k], tzz = fa * ra.ta2 + fbm * bt2[k];
        const F32 txy = fa * ra.ta3 + fbm * bt3[k], txz = fa * ra.ta4 + fbm * bt4[k], tyz = fa * ra.ta5 + fbm * bt5[k];
        a0 += txx * g.gw0 + txy * g.gw1 + txz * g.gw2;
        a1 += txy * g.gw0 + tyy * g.gw1 + tyz * g.gw2;
        a2 += txz * g.gw0 + tyz * g.gw1 + tzz * g.gw2;
      }
    }
    if constexpr (Xsph) {
      const F32 xw = fb * F32(2) * mb * iv.rsum * (VarH ? kl.Wh(g.r, ih) : kl.W(g.r)) * g.in;
      s0 -= xw * u0;
      s1 -= xw * u1;
      s2 -= xw * u2;
    }
    cnt += g.in;
  }
  cnt_out += cnt;
  if constexpr (D == 2) return {a0, a1, a2, s0, s1, s2, dr, dd, {g00, g01, g10, g11}};
  else return {a0, a1, a2, s0, s1, s2, dr, dd, {g00, g01, g02, g10, g11, g12, g20, g21, g22}};
}

/// Particle a's rates from its pair sums over all its cell's candidates; returns its pair count.
template <int D, class K, bool Xsph, bool Turb, bool Porous, bool Multi, bool Press, bool VarH>
[[gnu::always_inline]] inline std::uint64_t rates_particle(const RatesPass<D>& q, const K& kl, const RatesColumns& c,
                                                          const Vec<D>& origin, std::uint32_t a) {
  const RatesRow ra = rates_row<D, Turb, Porous, Multi, VarH>(q, origin, a);
  const auto [kbeg, kend] = reach_blocks<D, VarH>(ra, c, q.support2, 0, c.npad);
  F32 cnt = 0;
  const RatesSums s = rates_sums<D, K, Xsph, Turb, Porous, Multi, Press, VarH>(q, kl, c, ra, kbeg, kend, cnt);
  store_rates<D, Turb>(q, a, ra, s);
  return static_cast<std::uint64_t>(cnt + F32(0.5));
}

}  // namespace sph::rates
