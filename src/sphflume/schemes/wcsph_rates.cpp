// The weakly-compressible scheme's rates pass (schemes/wcsph.hpp): the services in their order
// and the fused single-precision pair loop. ISPH's force pass is the same loop with the
// pressure switched off (SchemeConfig::pressure), so no particle loop is written twice.
#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "sphflume/boundaries/walls.hpp"
#include "sphflume/physics/force_terms.hpp"
#include "sphflume/physics/multiphase.hpp"
#include "sphflume/physics/porous.hpp"
#include "sphflume/physics/transport.hpp"
#include "sphflume/physics/turbulence.hpp"
#include "sphflume/schemes/wcsph.hpp"
#include "sphflume/schemes/wcsph_common.hpp"

namespace sph {

template <int D>
template <class K>
void WCSPH<D>::pair_loop(System<D>& S, const K& ker) {
  // XSPH's smoothed velocity needs W(r) in every pair, turbulence the velocity gradient and
  // the stress divergence: each is compiled in only when it is on
  // porosity the SPHAM terms (volumes m/(φρ), porosity-weighted velocities)
  const bool turb = turb_.on();
  auto with_bool = [](bool b, auto&& f) {
    if (b) f(std::true_type{});
    else f(std::false_type{});
  };
  if (!cfg_.pressure) {  // the forces alone (ISPH's prediction: no pressure, no XSPH, one phase)
    with_bool(turb, [&](auto tu) {
      with_bool(static_cast<bool>(S.porous), [&](auto po) {
        this->template sweep<K, false, decltype(tu)::value, decltype(po)::value, false, false>(S, ker);
      });
    });
  } else if (!S.phase_eos.empty()) {  // several phases (setup refuses them with turbulence or porosity)
    with_bool(cfg_.xsph > 0.0, [&](auto xs) { this->template sweep<K, decltype(xs)::value, false, false, true>(S, ker); });
  } else {
    with_bool(cfg_.xsph > 0.0, [&](auto xs) {
      with_bool(turb, [&](auto tu) {
        with_bool(static_cast<bool>(S.porous), [&](auto po) {
          this->template sweep<K, decltype(xs)::value, decltype(tu)::value, decltype(po)::value, false>(S, ker);
        });
      });
    });
  }
  if (turb) turb_.update(S);
}

template <int D>
template <class K, bool Xsph, bool Turb, bool Porous, bool Multi, bool Press>
void WCSPH<D>::sweep(System<D>& S, const K& ker) {
  auto& P = S.particles;
  const bool dyn = S.walls->evolves_density();
  const double h = S.h, eta2 = cfg_.eta2 * h * h, c0 = S.eos.c0, rho0 = S.eos.rho0;
  const double tiny = 1e-12 * h * h;  // keeps the masked self pair finite when eta2 = 0
  // every optional term is on the same code path, scaled by a 0/1 (or coefficient) factor:
  // the inner loop has no branches and vectorises
  const double lam = (cfg_.viscosity == ViscosityModel::Laminar) ? 4.0 * S.nu : 0.0;
  const double alpha = (cfg_.viscosity == ViscosityModel::Artificial) ? cfg_.alpha : cfg_.alpha_on_laminar;
  const double fdiff = (cfg_.density_diffusion != DensityDiffusion::None && cfg_.delta > 0.0) ? 1.0 : 0.0;
  const double four = cfg_.density_diffusion == DensityDiffusion::Fourtakas ? 1.0 : 0.0;
  const double sym = cfg_.pressure_gradient == PressureGradient::Symmetric ? 1.0 : 0.0;
  const double visc_wall = S.walls->cfg.no_slip ? 1.0 : 0.0;  // walls enter the viscous terms
  const double wall_in = S.walls->in_pair_sums() ? 1.0 : 0.0;  // walls enter the pair sums at all
  const double dcoef = 2.0 * cfg_.delta * h * c0;
  const double xsph = cfg_.xsph;
  std::vector<Vec<D>>* xs = xsph > 0.0 ? &P.vector(field::xsph) : nullptr;
  // turbulence: the stress of the previous pass (kinematic, τ/ρ) and the gradient buffer
  constexpr int NT = Turbulence<D>::kStress;
  const double* tau_in[6] = {nullptr, nullptr, nullptr, nullptr, nullptr, nullptr};
  double* grad_out = nullptr;
  if constexpr (Turb) {
    for (int k = 0; k < NT; ++k) tau_in[k] = P.scalar(Turbulence<D>::stress_name(k)).data();
    grad_out = turb_.gradient(P.n_owned());
  }
  // porous media (SPHAM, Kazemi eqs 4.56-4.57): φ of every particle (walls 1)
  const double* __restrict phi = Porous ? P.scalar(field::porosity).data() : nullptr;
  double g[3] = {0.0, 0.0, 0.0};
  for (int d = 0; d < D; ++d) g[d] = S.gravity[d];
  const double support2 = ker.support2;
  const Eos eos = S.eos;
  // phases: each particle's reference density and sound speed from its phase's EOS
  const double* __restrict phase = Multi ? P.scalar(field::phase).data() : nullptr;
  const std::vector<Eos>& peos = S.phase_eos;
  auto ref_of = [&](std::size_t b) { return Multi ? peos[static_cast<std::size_t>(phase[b])].rho0 : rho0; };
  auto sound_of = [&](std::size_t b, double rh) {
    return Multi ? peos[static_cast<std::size_t>(phase[b])].sound_speed(rh) : eos.sound_speed(rh);
  };

  const Vec<D>* __restrict pos = P.pos.data();
  const Vec<D>* __restrict vel = P.vel.data();
  const float* __restrict wcorr = S.walls->viscous_correction();  // no-slip walls' ghost correction
  const double* __restrict rho = P.rho.data();
  const double* __restrict prs = P.p.data();
  const double* __restrict mass = P.mass.data();
  const Kind* __restrict kind = P.kind.data();
  const std::uint32_t* __restrict sorted = S.cells.sorted().data();
  Vec<D>* __restrict acc_out = P.acc.data();
  double* __restrict drho_out = P.drho.data();
  Vec<D>* __restrict xs_out = xs ? xs->data() : nullptr;
  const auto& cells = S.cells;
  const std::size_t n_owned = P.n_owned();

  // The pair loop runs in single precision (16 lanes of AVX-512, fast division and square
  // root), as DualSPHysics does on GPUs: positions are stored relative to the cell's first
  // particle (|r| < 3 supports, so float keeps ~1e-7 relative accuracy in r), the pair sums
  // are converted back to double per particle. Particle state and time integration stay in
  // double precision.
  using F32 = float;
  // Grenier: pressures enter as p/Γ (walls Γ = 1); chi: interface repulsion
  const double* __restrict gam = (Multi && S.grenier) ? P.scalar(field::gamma_grenier).data() : nullptr;
  auto p_of = [&](std::size_t b) { return gam && fluid_like(kind[b]) ? prs[b] / gam[b] : prs[b]; };
  const F32 fchi = F32(Multi ? S.chi : 0.0);
  enum { X0, X1, X2, U0, U1, U2, W0, W1, W2, RHO, PRS, MASS, FLUID, CS, T0, PHI = T0 + 6, IPHI, REF, PHS, NCOL };
  const F32 fh = F32(h), feta2 = F32(eta2 + tiny), fsupport2 = F32(support2);
  const F32 flam = F32(lam), falpha = F32(alpha), ffour = F32(four);
  const F32 fsym = F32(sym), fvisc_wall = F32(visc_wall * wall_in), fwall_in = F32(wall_in);
  const F32 fg0 = F32(g[0]), fg1 = F32(g[1]), fg2 = F32(g[2]);
  const F32 ffar = F32(1.0e3);  // padding entries: 1 km away, outside every support

  // a cell needs the loop when it holds owned particles that need rates (fluid; walls only
  // when dynamic); the others get zero rates here
  auto needs = [&](std::size_t cell) {
    const std::uint32_t c0k = cells.cell_begin(cell), c1k = cells.cell_end(cell);
    std::size_t m = 0;  // the particles the pass runs
    for (std::uint32_t k = c0k; k < c1k; ++k) {
      const std::uint32_t a = sorted[k];
      if (a >= n_owned) continue;
      // imposed-state particles need no rates: walls (unless dynamic) and outflow particles;
      // inflow particles get theirs (unused while they are inflow) so that one turning into
      // fluid has the rates of its state, which the Verlet integrator's next step uses
      if ((kind[a] == Kind::Wall && !dyn) || kind[a] == Kind::Outflow) {
        acc_out[a] = Vec<D>{};
        drho_out[a] = 0.0;
        continue;
      }
      ++m;
    }
    return m;
  };
  S.pairs_last_pass = sweep_cells<F32>(cells, NCOL, 16, needs,
                                       [&](std::size_t cell, const CellStencil<D>& st, ScratchColumns<F32>& B) {
      const std::uint32_t c0k = cells.cell_begin(cell), c1k = cells.cell_end(cell);
      const std::size_t npad = st.padded;
      std::uint64_t pairs = 0;
      // the loop's constants as locals of this function: read through the closure, GCC's AVX2
      // vectoriser could not keep them in registers and left the loop scalar
      const K kl = ker;
      const F32 l_fsupport2 = fsupport2, l_feta2 = feta2, l_fh = fh, l_flam = flam, l_falpha = falpha, l_ffour = ffour, l_fsym = fsym, l_fvisc_wall = fvisc_wall, l_fwall_in = fwall_in, l_fg0 = fg0, l_fg1 = fg1, l_fg2 = fg2, l_fchi = fchi, l_ffar = ffar;
      const Vec<D> origin = pos[sorted[c0k]];
      {
        F32* __restrict cx[D]; F32* __restrict cu[D]; F32* __restrict cw[D];
        for (int d = 0; d < D; ++d) { cx[d] = B[X0 + d]; cu[d] = B[U0 + d]; cw[d] = B[W0 + d]; }
        F32* __restrict crho = B[RHO];
        F32* __restrict cp = B[PRS];
        F32* __restrict cm = B[MASS];
        F32* __restrict cf = B[FLUID];
        F32* __restrict ccs = B[CS];
        st.for_each([&](std::size_t m, std::uint32_t b) {
          const bool fl = fluid_like(kind[b]);
          for (int d = 0; d < D; ++d) {
            cx[d][m] = F32(pos[b][d] - origin[d]);
            cu[d][m] = F32(vel[b][d]);
            cw[d][m] = fl || !wcorr ? F32(0) : wcorr[b * D + d];  // ghost correction of the viscous velocity
          }
          crho[m] = F32(rho[b] - ref_of(b));  // deviations: neighbour differences keep full float precision
          cp[m] = F32(p_of(b));
          cm[m] = F32(mass[b]);
          cf[m] = fl ? F32(1) : F32(0);
          ccs[m] = F32(sound_of(b, rho[b]));  // sound speed c(rho_b) (any EOS)
          if constexpr (Multi) {
            B[REF][m] = F32(ref_of(b));
            B[PHS][m] = F32(phase[b]);
          }
          if constexpr (Turb)  // τ_b/ρ_b²; walls carry none of their own (see wall factor below)
            for (int t = 0; t < NT; ++t) B[T0 + t][m] = fl ? F32(tau_in[t][b] / rho[b]) : F32(0);
          if constexpr (Porous) {
            B[PHI][m] = F32(phi[b]);
            B[IPHI][m] = F32(1.0 / phi[b]);
          }
        });
        for (std::size_t m = st.count; m < npad; ++m) {  // padding: far away, massless
          for (int d = 0; d < D; ++d) { cx[d][m] = l_ffar; cu[d][m] = 0; cw[d][m] = 0; }
          crho[m] = 0; cp[m] = 0; cm[m] = 0; cf[m] = 0; ccs[m] = F32(c0);
          if constexpr (Turb)
            for (int t = 0; t < NT; ++t) B[T0 + t][m] = 0;
          if constexpr (Porous) { B[PHI][m] = 1; B[IPHI][m] = 1; }
          if constexpr (Multi) { B[REF][m] = F32(rho0); B[PHS][m] = F32(-1); }
        }
      }
      const F32* __restrict bx0 = B[X0];
      const F32* __restrict bx1 = B[X1];
      const F32* __restrict bx2 = B[X0 + D - 1];
      const F32* __restrict bu0 = B[U0];
      const F32* __restrict bu1 = B[U1];
      const F32* __restrict bu2 = B[U0 + D - 1];
      const F32* __restrict bw0 = B[W0];
      const F32* __restrict bw1 = B[W1];
      const F32* __restrict bw2 = B[W0 + D - 1];
      const F32* __restrict brho = B[RHO];
      const F32* __restrict bp = B[PRS];
      const F32* __restrict bm = B[MASS];
      const F32* __restrict bf = B[FLUID];
      const F32* __restrict bcs = B[CS];
      // stress columns (2D: xx, xz, zz; 3D: xx, yy, zz, xy, xz, yz)
      const F32* __restrict bt0 = B[T0];
      const F32* __restrict bt1 = B[T0 + 1];
      const F32* __restrict bt2 = B[T0 + 2];
      const F32* __restrict bt3 = B[T0 + (D == 3 ? 3 : 0)];
      const F32* __restrict bt4 = B[T0 + (D == 3 ? 4 : 0)];
      const F32* __restrict bt5 = B[T0 + (D == 3 ? 5 : 0)];
      const F32* __restrict bphi = B[PHI];
      const F32* __restrict biphi = B[IPHI];
      const F32* __restrict bref = B[REF];
      const F32* __restrict bphs = B[PHS];

      for (std::uint32_t ka_k = c0k; ka_k < c1k; ++ka_k) {
        const std::uint32_t a = sorted[ka_k];
        if (a >= n_owned) continue;
        const Kind ka = kind[a];
        if ((ka == Kind::Wall && !dyn) || ka == Kind::Outflow) continue;
        const F32 xa0 = F32(pos[a][0] - origin[0]), xa1 = F32(pos[a][1] - origin[1]);
        const F32 xa2 = F32(pos[a][D - 1] - origin[D - 1]);
        const F32 va0 = F32(vel[a][0]), va1 = F32(vel[a][1]), va2 = F32(vel[a][D - 1]);
        const double rhoa_d = rho[a];
        const F32 frho0 = F32(rho0), deva = F32(rhoa_d - ref_of(a));
        const F32 rhoa = F32(rhoa_d), pa = F32(p_of(a));
        const F32 ca = F32(sound_of(a, rhoa_d)), ca2 = ca * ca;
        const F32 pha = Multi ? F32(phase[a]) : F32(0);
        const F32 pa_r2 = F32(prs[a] / (rhoa_d * rhoa_d));
        const F32 inv_rhoa = F32(1.0 / rhoa_d);
        const F32 wa = ka == Kind::Wall ? F32(0) : F32(1);  // a dynamic wall: continuity from fluid only
        F32 ta[6] = {0, 0, 0, 0, 0, 0};  // τ_a/ρ_a²
        if constexpr (Turb)
          for (int t = 0; t < NT; ++t) ta[t] = F32(tau_in[t][a] / rhoa_d);
        const F32 ta0 = ta[0], ta1 = ta[1], ta2 = ta[2], ta3 = ta[3], ta4 = ta[4], ta5 = ta[5];
        const double phia_d = Porous ? phi[a] : 1.0;
        const F32 phia = F32(phia_d), iphia = F32(1.0 / phia_d);
        F32 a0 = 0, a1 = 0, a2 = 0, s0 = 0, s1 = 0, s2 = 0, dr = 0, dd = 0, cnt = 0;
        F32 g00 = 0, g01 = 0, g02 = 0, g10 = 0, g11 = 0, g12 = 0, g20 = 0, g21 = 0, g22 = 0;
#pragma omp simd reduction(+ : a0, a1, a2, s0, s1, s2, dr, dd, cnt, g00, g01, g02, g10, g11, g12, g20, g21, g22)
        for (std::size_t k = 0; k < npad; ++k) {
          const F32 r0 = xa0 - bx0[k], r1 = xa1 - bx1[k], r2c = D == 3 ? xa2 - bx2[k] : F32(0);
          const F32 r2 = r0 * r0 + r1 * r1 + r2c * r2c;
          const F32 fb = bf[k];
          // in: a neighbour within the support (not a itself); a wall a only sees fluid
          // (purely repulsive walls are in no sum: l_fwall_in = 0)
          const F32 in = ((r2 < l_fsupport2) & (r2 > F32(0))) ? (wa + (F32(1) - wa) * fb) * (fb + (F32(1) - fb) * l_fwall_in) : F32(0);
          const F32 r = std::sqrt(r2);
          const F32 Fk = kl.F(r) * in;
          const F32 gw0 = Fk * r0, gw1 = Fk * r1, gw2 = Fk * r2c;
          const F32 devb = brho[k], rhob = (Multi ? bref[k] : frho0) + devb, mb = bm[k], pb = bp[k];
          const F32 cb = bcs[k];
          const F32 u0 = va0 - bu0[k], u1 = va1 - bu1[k], u2 = D == 3 ? va2 - bu2[k] : F32(0);
          // one division for the four reciprocals this pair needs
          const F32 cb2 = cb * cb;
          const F32 r2e = r2 + l_feta2, rsum = rhoa + rhob, csum = ca2 + cb2;
          const F32 p1 = rhob * r2e, p2 = rsum * csum;
          const F32 inv = F32(1) / (p1 * p2);
          const F32 inv_rhob = inv * r2e * p2;
          const F32 inv_r2e = inv * rhob * p2;
          const F32 inv_rsum = inv * p1 * csum;
          const F32 inv_csum = inv * p1 * rsum;
          // porous: b's volume m/(φ_b ρ_b); continuity of the porosity-weighted velocity
          // (φ_a u_a − φ_b u_b), where a wall takes the porosity of the fluid it faces (it is no
          // porosity interface) and a wall a sees its fluid neighbours as plain fluid
          const F32 ivb = Porous ? biphi[k] : F32(1);
          const F32 mbp = mb * ivb;
          const F32 Vb = mbp * inv_rhob;
          F32 phf = F32(1);
          if constexpr (Porous) {
            const F32 sel = fb * wa;
            phf = sel * bphi[k] + (F32(1) - sel) * (wa * phia + (F32(1) - wa));
          }
          const F32 pa_c = Porous ? wa * phia + (F32(1) - wa) : F32(1);
          const F32 uc0 = Porous ? pa_c * va0 - phf * bu0[k] : u0;
          const F32 uc1 = Porous ? pa_c * va1 - phf * bu1[k] : u1;
          const F32 uc2 = Porous ? (D == 3 ? pa_c * va2 - phf * bu2[k] : F32(0)) : u2;
          dr += (uc0 * gw0 + uc1 * gw1 + uc2 * gw2) * Vb;
          const F32 fr = Fk * r2 * inv_r2e;  // regularised F (r·∇W/(r²+η²))
          // δ-SPH: Fourtakas removes the hydrostatic density difference ρ g·r / c² (pair means)
          const F32 gr = l_fg0 * r0 + l_fg1 * r1 + l_fg2 * r2c;
          // (phases: within a phase only; the density jump between phases is no error to diffuse)
          const F32 same = Multi ? (bphs[k] == pha ? F32(1) : F32(0)) : F32(1);
          dd += same * fb * (deva - devb - l_ffour * rsum * inv_csum * gr) * fr * Vb;
          const F32 pterm = Press ? l_fsym * mbp * (pa_r2 + pb * inv_rhob * inv_rhob) + (F32(1) - l_fsym) * (pa + pb) * Vb * inv_rhoa
                                  : F32(0);
          // viscous velocity difference: fluid b its velocity, wall b the wall model's (ghost) one
          const F32 mv = fb + (F32(1) - fb) * l_fvisc_wall;
          const F32 w0 = u0 + bw0[k], w1 = u1 + bw1[k], w2 = D == 3 ? u2 + bw2[k] : F32(0);
          // (a value select, not std::min: its reference result kept GCC's AVX2 code scalar)
          const F32 wr = w0 * r0 + w1 * r1 + w2 * r2c;
          const F32 vr = wr < F32(0) ? wr : F32(0);
          const F32 pi_ab = -l_falpha * (ca + cb) * l_fh * vr * inv_r2e * inv_rsum;  // Monaghan Π_ab
          F32 gcoef = pterm + mv * mbp * pi_ab;
          if constexpr (Multi) {  // interface repulsion −(χ/ρ_a) Σ_{b∉X} (|p_a|/Γ_a + |p_b|/Γ_b) ∇W V_b
            const F32 other = fb * (bphs[k] != pha ? F32(1) : F32(0));
            gcoef += l_fchi * other * (std::abs(pa) + std::abs(pb)) * Vb * inv_rhoa;
          }
          if constexpr (Porous) {
            // Kazemi eq 4.57: μ m_b/(φ_a φ_b) [2 (φu)_ab + φ_ab u_ab] ... = the plain term on
            // (φ_a − φ_b) u_a + (φ_a + φ_b)/2 (u_a − u_b), φ_b the flow porosity above
            const F32 lamf = mv * l_flam * mbp * fr * inv_rsum * iphia;
            const F32 dphi = phia - phf, mphi = F32(0.5) * (phia + phf);
            a0 += lamf * (dphi * va0 + mphi * w0) - gcoef * gw0;
            a1 += lamf * (dphi * va1 + mphi * w1) - gcoef * gw1;
            a2 += lamf * (dphi * (D == 3 ? va2 : F32(0)) + mphi * w2) - gcoef * gw2;
          } else {
            const F32 lamf = mv * l_flam * mb * fr * inv_rsum;
            a0 += lamf * w0 - gcoef * gw0;
            a1 += lamf * w1 - gcoef * gw1;
            a2 += lamf * w2 - gcoef * gw2;
          }
          if constexpr (Turb) {
            // velocity gradient (∂u_i/∂x_j)_a = Σ V_b (u_b − u_a)_i ∂_j W, walls through the
            // wall model's velocity as in the viscous term
            const F32 gv = mv * Vb;
            g00 -= w0 * gw0 * gv; g01 -= w0 * gw1 * gv;
            g10 -= w1 * gw0 * gv; g11 -= w1 * gw1 * gv;
            if constexpr (D == 3) {
              g02 -= w0 * gw2 * gv; g12 -= w1 * gw2 * gv;
              g20 -= w2 * gw0 * gv; g21 -= w2 * gw1 * gv; g22 -= w2 * gw2 * gv;
            }
            // stress divergence Σ m_b (τ_a/ρ_a² + τ_b/ρ_b²)·∇W; walls carry no modelled stress;
            // porous: Σ m_b/(φ_a φ_b) (φ_a τ_a/ρ_a² + φ_b τ_b/ρ_b²)·∇W (Kazemi eq 4.57)
            const F32 fa = mbp, fbm = Porous ? mb * iphia : mb;
            if constexpr (D == 2) {  // (xx, xz, zz)
              a0 += (fa * ta0 + fbm * bt0[k]) * gw0 + (fa * ta1 + fbm * bt1[k]) * gw1;
              a1 += (fa * ta1 + fbm * bt1[k]) * gw0 + (fa * ta2 + fbm * bt2[k]) * gw1;
            } else {  // (xx, yy, zz, xy, xz, yz)
              const F32 txx = fa * ta0 + fbm * bt0[k], tyy = fa * ta1 + fbm * bt1[k], tzz = fa * ta2 + fbm * bt2[k];
              const F32 txy = fa * ta3 + fbm * bt3[k], txz = fa * ta4 + fbm * bt4[k], tyz = fa * ta5 + fbm * bt5[k];
              a0 += txx * gw0 + txy * gw1 + txz * gw2;
              a1 += txy * gw0 + tyy * gw1 + tyz * gw2;
              a2 += txz * gw0 + tyz * gw1 + tzz * gw2;
            }
          }
          if constexpr (Xsph) {
            const F32 xw = fb * F32(2) * mb * inv_rsum * kl.W(r) * in;
            s0 -= xw * u0;
            s1 -= xw * u1;
            s2 -= xw * u2;
          }
          cnt += in;
        }
        pairs += static_cast<std::uint64_t>(cnt + F32(0.5));
        if constexpr (Turb) {
          double* G = grad_out + std::size_t(a) * D * D;
          G[0] = g00; G[1] = g01;
          if constexpr (D == 2) { G[2] = g10; G[3] = g11; }
          else { G[2] = g02; G[3] = g10; G[4] = g11; G[5] = g12; G[6] = g20; G[7] = g21; G[8] = g22; }
        }
        if (ka == Kind::Wall) {
          drho_out[a] = rhoa_d * double(dr);
          acc_out[a] = Vec<D>{};
          continue;
        }
        drho_out[a] = rhoa_d / phia_d * double(dr) + fdiff * dcoef * double(dd);
        Vec<D> acc, sx;
        acc[0] = double(a0) + g[0];
        acc[1] = double(a1) + g[1];
        sx[0] = xsph * double(s0);
        sx[1] = xsph * double(s1);
        if constexpr (D == 3) { acc[2] = double(a2) + g[2]; sx[2] = xsph * double(s2); }
        acc_out[a] = acc;
        if (xs_out) xs_out[a] = sx;
      }
      return pairs;
  });
}

template <int D>
void WCSPH<D>::rates(System<D>& S) {
  if (cfg_.frozen) {  // only the scalars move
    if (S.transport) S.transport->rates(S);
    return;
  }
  if (S.before_rates) S.before_rates(S);
  if (S.porous) S.porous->update(S);  // φ at the current positions (before the pair loop reads it)
  if (S.grenier) grenier_gamma(S);  // Γ of Grenier's pressure gradient
  S.walls->prepare(S);
  S.with_kernel([&](const auto& K) { this->pair_loop(S, K); });
  S.walls->add_forces(S);
  for (auto& f : S.forces) f->add(S);
  if (S.porous) S.porous->drag(S);  // the drag rate the integrator applies point-implicitly
  if (S.transport) S.transport->rates(S);  // after the pair loop: the advection variants use drho
  auto& P = S.particles;
  double amax = 0.0;
  const std::size_t n = P.n_owned();
#pragma omp parallel for schedule(static) reduction(max : amax)
  for (std::size_t i = 0; i < n; ++i)
    if (P.kind[i] == Kind::Fluid) amax = std::max(amax, dot(P.acc[i], P.acc[i]));
  max_acc_ = std::sqrt(amax);
  if (!std::isfinite(max_acc_)) check_finite(S);
}

template void WCSPH<2>::rates(System<2>&);
template void WCSPH<3>::rates(System<3>&);

}  // namespace sph
