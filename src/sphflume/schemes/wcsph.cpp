#include "sphflume/schemes/wcsph.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "sphflume/boundaries/walls.hpp"
#include "sphflume/physics/force_terms.hpp"
#include "sphflume/physics/multiphase.hpp"
#include "sphflume/physics/porous.hpp"
#include "sphflume/physics/transport.hpp"
#include "sphflume/physics/turbulence.hpp"

namespace sph {

template <int D>
void WCSPH<D>::initialise(System<D>& S) {
  update_pressure(S);
  S.update_neighbours();
  rates(S);
}

template <int D>
void WCSPH<D>::update_pressure(System<D>& S) const {
  auto& P = S.particles;
  const bool dyn = S.walls->evolves_density();
  const std::size_t n = P.n_owned();
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    if (P.kind[i] == Kind::Wall) {
      if (!dyn) continue;
      // dynamic walls must push, never pull (SPHysics/DualSPHysics practice)
      if (P.rho[i] < S.eos.rho0) P.rho[i] = S.eos.rho0;
    }
    P.p[i] = S.eos_of(i).pressure(P.rho[i]);
  }
}

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
  const double alpha = (cfg_.viscosity == ViscosityModel::Artificial) ? cfg_.alpha : 0.0;
  const double fdiff = (cfg_.density_diffusion != DensityDiffusion::None && cfg_.delta > 0.0) ? 1.0 : 0.0;
  const double four = cfg_.density_diffusion == DensityDiffusion::Fourtakas ? 1.0 : 0.0;
  const double sym = cfg_.pressure_gradient == PressureGradient::Symmetric ? 1.0 : 0.0;
  const double visc_wall = S.walls->cfg.no_slip ? 1.0 : 0.0;  // walls enter the viscous terms
  const double wall_in = S.walls->in_pair_sums() ? 1.0 : 0.0;  // walls enter the pair sums at all
  const double dcoef = 2.0 * cfg_.delta * h * c0;
  const double xsph = cfg_.xsph;
  std::vector<Vec<D>>* xs = xsph > 0.0 ? &P.vector("xsph") : nullptr;
  // turbulence: the stress of the previous pass (kinematic, τ/ρ) and the gradient buffer
  constexpr int NT = Turbulence<D>::kStress;
  const double* tau_in[6] = {nullptr, nullptr, nullptr, nullptr, nullptr, nullptr};
  double* grad_out = nullptr;
  if constexpr (Turb) {
    for (int k = 0; k < NT; ++k) tau_in[k] = P.scalar(Turbulence<D>::stress_name(k)).data();
    grad_out = turb_.gradient(P.n_owned());
  }
  // porous media (SPHAM, Kazemi eqs 4.56-4.57): φ of every particle (walls 1)
  const double* __restrict phi = Porous ? P.scalar("porosity").data() : nullptr;
  double g[3] = {0.0, 0.0, 0.0};
  for (int d = 0; d < D; ++d) g[d] = S.gravity[d];
  const double support2 = ker.support2;
  const Eos eos = S.eos;
  // phases: each particle's reference density and sound speed from its phase's EOS
  const double* __restrict phase = Multi ? P.scalar("phase").data() : nullptr;
  const std::vector<Eos>& peos = S.phase_eos;
  auto ref_of = [&](std::size_t b) { return Multi ? peos[static_cast<std::size_t>(phase[b])].rho0 : rho0; };
  auto sound_of = [&](std::size_t b, double rh) {
    return Multi ? peos[static_cast<std::size_t>(phase[b])].sound_speed(rh) : eos.sound_speed(rh);
  };

  const Vec<D>* __restrict pos = P.pos.data();
  const Vec<D>* __restrict vel = P.vel.data();
  const Vec<D>* __restrict wvel = S.walls->viscous_velocity(S).data();
  const double* __restrict rho = P.rho.data();
  const double* __restrict prs = P.p.data();
  const double* __restrict mass = P.mass.data();
  const Kind* __restrict kind = P.kind.data();
  const std::uint32_t* __restrict sorted = S.cells.sorted().data();
  Vec<D>* __restrict acc_out = P.acc.data();
  double* __restrict drho_out = P.drho.data();
  Vec<D>* __restrict xs_out = xs ? xs->data() : nullptr;
  const auto& cells = S.cells;
  const std::size_t ncell = cells.cell_count();
  const std::size_t n_owned = P.n_owned();
  std::uint64_t pairs = 0;

  // The pair loop runs in single precision (16 lanes of AVX-512, fast division and square
  // root), as DualSPHysics does on GPUs: positions are stored relative to the cell's first
  // particle (|r| < 3 supports, so float keeps ~1e-7 relative accuracy in r), the pair sums
  // are converted back to double per particle. Particle state and time integration stay in
  // double precision.
  using F32 = float;
  // Grenier: pressures enter as p/Γ (walls Γ = 1); chi: interface repulsion
  const double* __restrict gam = (Multi && S.grenier) ? P.scalar("_gamma").data() : nullptr;
  auto p_of = [&](std::size_t b) { return gam && fluid_like(kind[b]) ? prs[b] / gam[b] : prs[b]; };
  const F32 fchi = F32(Multi ? S.chi : 0.0);
  enum { X0, X1, X2, U0, U1, U2, W0, W1, W2, RHO, PRS, MASS, FLUID, CS, T0, PHI = T0 + 6, IPHI, REF, PHS, NCOL };
  const F32 fh = F32(h), feta2 = F32(eta2 + tiny), fsupport2 = F32(support2);
  const F32 flam = F32(lam), falpha = F32(alpha), ffour = F32(four);
  const F32 fsym = F32(sym), fvisc_wall = F32(visc_wall * wall_in), fwall_in = F32(wall_in);
  const F32 fg0 = F32(g[0]), fg1 = F32(g[1]), fg2 = F32(g[2]);
  const F32 ffar = F32(1.0e3);  // padding entries: 1 km away, outside every support

#pragma omp parallel reduction(+ : pairs)
  {
    ScratchColumns<F32> B(NCOL);
    CellStencil<D> st;
#pragma omp for schedule(dynamic, 16)
    for (std::size_t cell = 0; cell < ncell; ++cell) {
      const std::uint32_t c0k = cells.cell_begin(cell), c1k = cells.cell_end(cell);
      // owned particles of this cell that need rates (fluid; walls only when dynamic)
      bool any = false;
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
        any = true;
      }
      if (!any) continue;
      st.set(cells, cell, 16);  // 16 float lanes (AVX-512)
      const std::size_t npad = st.padded;
      B.reserve(npad);
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
            cw[d][m] = fl ? F32(0) : F32(vel[b][d] - wvel[b][d]);  // ghost correction of the viscous velocity
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
          for (int d = 0; d < D; ++d) { cx[d][m] = ffar; cu[d][m] = 0; cw[d][m] = 0; }
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
          // (purely repulsive walls are in no sum: fwall_in = 0)
          const F32 in = ((r2 < fsupport2) & (r2 > F32(0))) ? (wa + (F32(1) - wa) * fb) * (fb + (F32(1) - fb) * fwall_in) : F32(0);
          const F32 r = std::sqrt(r2);
          const F32 Fk = ker.F(r) * in;
          const F32 gw0 = Fk * r0, gw1 = Fk * r1, gw2 = Fk * r2c;
          const F32 devb = brho[k], rhob = (Multi ? bref[k] : frho0) + devb, mb = bm[k], pb = bp[k];
          const F32 cb = bcs[k];
          const F32 u0 = va0 - bu0[k], u1 = va1 - bu1[k], u2 = D == 3 ? va2 - bu2[k] : F32(0);
          // one division for the four reciprocals this pair needs
          const F32 cb2 = cb * cb;
          const F32 r2e = r2 + feta2, rsum = rhoa + rhob, csum = ca2 + cb2;
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
          const F32 gr = fg0 * r0 + fg1 * r1 + fg2 * r2c;
          // (phases: within a phase only; the density jump between phases is no error to diffuse)
          const F32 same = Multi ? (bphs[k] == pha ? F32(1) : F32(0)) : F32(1);
          dd += same * fb * (deva - devb - ffour * rsum * inv_csum * gr) * fr * Vb;
          const F32 pterm = Press ? fsym * mbp * (pa_r2 + pb * inv_rhob * inv_rhob) + (F32(1) - fsym) * (pa + pb) * Vb * inv_rhoa
                                  : F32(0);
          // viscous velocity difference: fluid b its velocity, wall b the wall model's (ghost) one
          const F32 mv = fb + (F32(1) - fb) * fvisc_wall;
          const F32 w0 = u0 + bw0[k], w1 = u1 + bw1[k], w2 = D == 3 ? u2 + bw2[k] : F32(0);
          const F32 vr = std::min(w0 * r0 + w1 * r1 + w2 * r2c, F32(0));
          const F32 pi_ab = -falpha * (ca + cb) * fh * vr * inv_r2e * inv_rsum;  // Monaghan Π_ab
          F32 gcoef = pterm + mv * mbp * pi_ab;
          if constexpr (Multi) {  // interface repulsion −(χ/ρ_a) Σ_{b∉X} (|p_a|/Γ_a + |p_b|/Γ_b) ∇W V_b
            const F32 other = fb * (bphs[k] != pha ? F32(1) : F32(0));
            gcoef += fchi * other * (std::abs(pa) + std::abs(pb)) * Vb * inv_rhoa;
          }
          if constexpr (Porous) {
            // Kazemi eq 4.57: μ m_b/(φ_a φ_b) [2 (φu)_ab + φ_ab u_ab] ... = the plain term on
            // (φ_a − φ_b) u_a + (φ_a + φ_b)/2 (u_a − u_b), φ_b the flow porosity above
            const F32 lamf = mv * flam * mbp * fr * inv_rsum * iphia;
            const F32 dphi = phia - phf, mphi = F32(0.5) * (phia + phf);
            a0 += lamf * (dphi * va0 + mphi * w0) - gcoef * gw0;
            a1 += lamf * (dphi * va1 + mphi * w1) - gcoef * gw1;
            a2 += lamf * (dphi * (D == 3 ? va2 : F32(0)) + mphi * w2) - gcoef * gw2;
          } else {
            const F32 lamf = mv * flam * mb * fr * inv_rsum;
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
            const F32 xw = fb * F32(2) * mb * inv_rsum * ker.W(r) * in;
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
    }
  }
  S.pairs_last_pass = pairs;
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

template <int D>
void WCSPH<D>::check_finite(const System<D>& S) const {
  const auto& P = S.particles;
  for (std::size_t i = 0; i < P.n_owned(); ++i) {
    bool ok = std::isfinite(P.rho[i]) && std::isfinite(P.p[i]) && std::isfinite(P.drho[i]);
    for (int d = 0; d < D; ++d) ok &= std::isfinite(P.pos[i][d]) && std::isfinite(P.vel[i][d]) && std::isfinite(P.acc[i][d]);
    if (!ok)
      throw SimulationError(fmt::format(
          "non-finite value at step {}, t = {:.6g} s: particle id {} ({}) at position ({:.4g}, {:.4g}{}); "
          "likely causes: time step too large (lower scheme.cfl), sound speed too small for the flow "
          "(raise fluid.sound_speed), or particles penetrating a wall",
          S.step, S.time, P.id[i], kind_name(P.kind[i]), P.pos[i][0], P.pos[i][1],
          D == 3 ? fmt::format(", {:.4g}", P.pos[i][D - 1]) : std::string()));
  }
}

template <int D>
double WCSPH<D>::time_step(const System<D>& S) const {
  const auto& P = S.particles;
  if (cfg_.frozen) {  // the scalars' limits only (a long step when nothing diffuses or reacts)
    const double dts = S.transport ? S.transport->time_step(S, cfg_.viscous_coefficient) : 1.0;
    return std::min(dts, 1.0);
  }
  double umax2 = 0.0, cmax = S.eos.sound_speed(S.eos.rho0);
  const std::size_t n = P.n_owned();
#pragma omp parallel for schedule(static) reduction(max : umax2, cmax)
  for (std::size_t i = 0; i < n; ++i) {
    if (P.kind[i] != Kind::Fluid) continue;
    umax2 = std::max(umax2, dot(P.vel[i], P.vel[i]));
    cmax = std::max(cmax, S.eos_of(i).sound_speed(P.rho[i]));
  }
  for (const auto& e : S.phase_eos) cmax = std::max(cmax, e.c0);
  double dt = cfg_.cfl * S.h / (cmax + std::sqrt(umax2));
  if (S.transport) dt = std::min(dt, S.transport->time_step(S, cfg_.viscous_coefficient));
  if (cfg_.viscosity == ViscosityModel::Laminar && S.nu > 0.0)
    dt = std::min(dt, cfg_.viscous_coefficient * S.h * S.h / S.nu);
  if (turb_.on() && turb_.nu_t_max() > 0.0)
    dt = std::min(dt, cfg_.viscous_coefficient * S.h * S.h / (S.nu + turb_.nu_t_max()));
  if (max_acc_ > 0.0) dt = std::min(dt, cfg_.force_coefficient * std::sqrt(S.h / max_acc_));
  return dt;
}

template <int D>
void WCSPH<D>::frozen_step(System<D>& S, double dt) {
  // the particles stay where they are: explicit midpoint for the scalars alone
  S.update_neighbours();
  if (!S.transport) return;
  S.transport->begin_step(S);
  S.transport->rates(S);
  S.transport->advance(S, 0.5 * dt, false);
  S.particles.refresh_images();
  S.transport->rates(S);
  S.transport->advance(S, dt, true);
}

template <int D>
void WCSPH<D>::step(System<D>& S, double dt) {
  if (cfg_.frozen) {
    frozen_step(S, dt);
    S.time += dt;
    ++S.step;
    return;
  }
  // shifting: displacements from the state being advanced (its neighbour lists: the Verlet
  // step's are those of its last rates pass; the two-stage steps rebuild theirs first)
  if (shift_.on()) {
    if (cfg_.integrator != Integrator::Verlet) S.update_neighbours();
    shift_.compute(S, dt);
  }
  if (cfg_.integrator == Integrator::Verlet) verlet_step(S, dt);
  else two_stage_step(S, dt);
  if (shift_.on()) shift_.apply(S);
  S.periodic.wrap(S.particles);
  S.time += dt;
  ++S.step;
  if (cfg_.shepard_every > 0 && S.step % cfg_.shepard_every == 0) shepard_filter(S);
  update_pressure(S);
  if (cfg_.integrator == Integrator::Verlet) {
    // the rates of the new state: the next step and its time-step estimate use them
    S.update_neighbours();
    rates(S);
  }
}

template <int D>
void WCSPH<D>::verlet_step(System<D>& S, double dt) {
  // DualSPHysics' Verlet (Monaghan 1989 leapfrog form): one rates evaluation per step,
  //   x^{n+1} = x^n + dt u^n + dt²/2 a^n,  u^{n+1} = u^{n-1} + 2 dt a^n,  ρ^{n+1} = ρ^{n-1} + 2 dt Dρ^n,
  // and every verlet_steps-th step an Euler step (u^{n+1} = u^n + dt a^n, ...) that re-couples
  // the odd and even sequences. acc/drho hold the rates of the current state on entry.
  auto& P = S.particles;
  const std::size_t n = P.n_owned();
  auto& vprev = P.vector("v_prev");
  auto& rprev = P.scalar("rho_prev");
  const bool dyn = S.walls->evolves_density();
  std::vector<Vec<D>>* xs = cfg_.xsph > 0.0 ? &P.vector("xsph") : nullptr;
  const bool euler = !verlet_started_ || (cfg_.verlet_steps > 0 && (S.step + 1) % cfg_.verlet_steps == 0);
  verlet_started_ = true;
  const double dt2 = euler ? dt : 2.0 * dt;
  const double hdt2 = 0.5 * dt * dt;
  // porous drag, point-implicit: u = (u_base + Δt a/M) / (1 + Δt K/M)
  const double* kr = S.porous ? P.scalar("drag_rate").data() : nullptr;
  const double* im = S.porous ? P.scalar("inertia").data() : nullptr;
  if (S.transport) S.transport->begin_step(S);  // scalars: forward Euler on Y = C/ρ
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    const bool fluid = P.kind[i] == Kind::Fluid;
    if (P.kind[i] == Kind::Inflow || P.kind[i] == Kind::Outflow) {
      P.pos[i] += dt * P.vel[i];  // open-boundary particles move with their imposed velocity
      // their imposed state is also their previous one: an inflow particle that becomes fluid
      // starts its leapfrog from it (a new particle has no previous state of its own)
      vprev[i] = P.vel[i];
      rprev[i] = P.rho[i];
      continue;
    }
    if (!fluid && !(P.kind[i] == Kind::Wall && dyn)) continue;
    const double r_new = (euler ? P.rho[i] : rprev[i]) + dt2 * P.drho[i];
    rprev[i] = P.rho[i];
    P.rho[i] = r_new;
    if (!fluid) continue;
    const Vec<D> v = P.vel[i];
    Vec<D> u = v;
    if (xs) u += (*xs)[i];
    const Vec<D> vb = euler ? v : vprev[i];
    if (kr) {
      P.vel[i] = (1.0 / (1.0 + dt2 * kr[i])) * (vb + (dt2 * im[i]) * P.acc[i]);
      P.pos[i] += dt * u + (hdt2 / dt2) * (P.vel[i] - vb);  // the acceleration the drag left
    } else {
      P.pos[i] += dt * u + hdt2 * P.acc[i];
      P.vel[i] = vb + dt2 * P.acc[i];
    }
    vprev[i] = v;
  }
  if (S.transport) S.transport->advance(S, dt, true);
}

template <int D>
void WCSPH<D>::two_stage_step(System<D>& S, double dt) {
  auto& P = S.particles;
  // stage 1: rates at t^n
  S.update_neighbours();
  rates(S);
  // start-of-step state as store fields: they follow the particles through the re-sort below
  auto& x0 = P.vector("x0");
  auto& v0 = P.vector("v0");
  auto& rho0 = P.scalar("rho0");
  const std::size_t n = P.n_owned();
  const bool dyn = S.walls->evolves_density();
  std::vector<Vec<D>>* xs = cfg_.xsph > 0.0 ? &P.vector("xsph") : nullptr;
  const double hdt = 0.5 * dt;
  // porous drag, point-implicit: u = (u_base + Δt a/M) / (1 + Δt K/M), K of the stage's state
  // (fields looked up per call: the store re-sorts between the stages)
  auto advance = [&P, por = static_cast<bool>(S.porous)](std::size_t i, const Vec<D>& base, double step,
                                                          const double* kr, const double* im) {
    if (!por) return base + step * P.acc[i];
    return (1.0 / (1.0 + step * kr[i])) * (base + (step * im[i]) * P.acc[i]);
  };
  const double* kr = S.porous ? P.scalar("drag_rate").data() : nullptr;
  const double* im = S.porous ? P.scalar("inertia").data() : nullptr;
  if (S.transport) S.transport->begin_step(S);  // scalars: explicit midpoint on Y = C/ρ
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    x0[i] = P.pos[i];
    v0[i] = P.vel[i];
    rho0[i] = P.rho[i];
    if (P.kind[i] == Kind::Fluid) {
      Vec<D> u = P.vel[i];
      if (xs) u += (*xs)[i];
      P.pos[i] += hdt * u;
      P.vel[i] = advance(i, P.vel[i], hdt, kr, im);
      P.rho[i] += hdt * P.drho[i];
    } else if (P.kind[i] == Kind::Inflow || P.kind[i] == Kind::Outflow) {
      P.pos[i] += hdt * P.vel[i];  // open-boundary particles move with their imposed velocity
    } else if (P.kind[i] == Kind::Wall && dyn) {
      P.rho[i] += hdt * P.drho[i];
    }
  }
  if (S.transport) S.transport->advance(S, hdt, false);
  update_pressure(S);
  // stage 2: rates at t^{n+1/2}
  S.update_neighbours();
  rates(S);
  const bool symplectic = cfg_.integrator == Integrator::Symplectic;
  kr = S.porous ? P.scalar("drag_rate").data() : nullptr;
  im = S.porous ? P.scalar("inertia").data() : nullptr;
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    const bool fluid = P.kind[i] == Kind::Fluid;
    if (P.kind[i] == Kind::Inflow || P.kind[i] == Kind::Outflow) {
      P.pos[i] = x0[i] + dt * P.vel[i];
      continue;
    }
    if (!fluid && !(P.kind[i] == Kind::Wall && dyn)) continue;
    if (symplectic) {
      const double eps = -P.drho[i] / P.rho[i] * dt;
      P.rho[i] = rho0[i] * (2.0 - eps) / (2.0 + eps);
    } else {
      P.rho[i] = rho0[i] + dt * P.drho[i];
    }
    if (!fluid) continue;
    Vec<D> xcorr{};
    if (xs) xcorr = (*xs)[i];
    if (symplectic) {
      P.vel[i] = advance(i, v0[i], dt, kr, im);
      P.pos[i] = x0[i] + dt * (0.5 * (P.vel[i] + v0[i]) + xcorr);
    } else {  // Monaghan predictor-corrector: corrected mid-step, then extrapolate
      const Vec<D> vc = advance(i, v0[i], hdt, kr, im);
      P.pos[i] = x0[i] + dt * (vc + xcorr);
      P.vel[i] = advance(i, v0[i], dt, kr, im);
    }
  }
  if (S.transport) S.transport->advance(S, dt, true);
}

template <int D>
void WCSPH<D>::shepard_filter(System<D>& S) const {
  S.update_neighbours();
  auto& P = S.particles;
  const std::size_t n = P.n_owned();
  std::vector<double> out(n);
  const double* phi = S.porous ? P.scalar("porosity").data() : nullptr;  // volumes m/(φρ)
  const double* phase = S.phase_eos.empty() ? nullptr : P.scalar("phase").data();  // within a phase
  S.with_kernel([&](const auto& K) {
#pragma omp parallel for schedule(static)
    for (std::size_t a = 0; a < n; ++a) {
      out[a] = P.rho[a];
      if (P.kind[a] != Kind::Fluid) continue;
      double num = 0.0, den = 0.0;
      S.cells.for_neighbours(P.pos, P.pos[a], K.support, [&](std::uint32_t b, const Vec<D>&, double r2) {
        if (P.kind[b] != Kind::Fluid || (phase && phase[b] != phase[a])) return;
        const double w = K.W(std::sqrt(r2)) * (phi ? 1.0 / phi[b] : 1.0);
        num += P.mass[b] * w;
        den += P.mass[b] / P.rho[b] * w;
      });
      if (den > 0.0) out[a] = num / den;
    }
  });
  // Verlet keeps the previous density too: shift it by the same correction
  if (P.has_scalar("rho_prev")) {
    auto& rp = P.scalar("rho_prev");
    for (std::size_t a = 0; a < n; ++a) rp[a] += out[a] - P.rho[a];
  }
  if (S.transport) S.transport->rescale(S, out);  // keep each particle's pollutant mass m C/ρ
  for (std::size_t a = 0; a < n; ++a) P.rho[a] = out[a];
}

template <int D>
std::size_t WCSPH<D>::bytes() const {
  return 0;  // the integrator's state lives in the particle store (x0/v0/rho0 or v_prev/rho_prev)
}

template class WCSPH<2>;
template class WCSPH<3>;


}  // namespace sph
