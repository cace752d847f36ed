// The dual-criteria Riemann scheme's pair passes (schemes/dual.hpp):
// Zhang, Hu & Adams (2017, J. Comput. Phys. 335) low-dissipation Riemann-solver WCSPH with the
// dual-criteria time stepping of Zhang, Zhang & Hu (2020, J. Comput. Phys. 404), the scheme of
// SPHinXsys's fluid dynamics. Every advection step (advection_cfl h / max(U, |u|, sqrt(4 h |a|)),
// U = c0/10) the density is re-initialised by summation, at least ρ0 (a free-surface particle
// has a truncated sum); inside it, acoustic steps of cfl h/(c + |u|) (0.6) integrate
//   ρ += Δt/2 Dρ,  x += Δt/2 u,  [pass A]  u += Δt a,  x += Δt/2 u,  [pass B]  ρ += Δt/2 Dρ
// (position Verlet, symplectic for the acoustic system). The pair sums are the Riemann
// solver's, split over the two passes as the scheme needs them:
//   pass A (pressure):    a_a = a_diss + g − (1/ρa) Σ (pa + pb) ∇aW Vb
//                         Dρa = ρa/(ρ0 c0) Σ (pa − pb) W'(r) Vb        (the acoustic dissipation
//                         of the Riemann velocity u* = ū + (pa − pb)/(2 ρ0 c0) e)
//   pass B (continuity):  Dρa += ρa Σ (ua − ub)·∇aW Vb
//                         a_diss = −(ρ0 c0/ρa) Σ β U ∇aW Vb,  U = −(ua − ub)·e the approach
//                         speed (twice the wall-relative one against a wall: its mirror state),
//                         β = min(k max(U, 0)/c0, 1) the low-dissipation limiter (k = 3)
// so each step costs two light passes (SPHinXsys: pressure relaxation and density relaxation).
// No artificial viscosity or δ-SPH term: the Riemann solver's dissipation replaces both.
#include <algorithm>
#include <cmath>

#include "sphflume/core/pair_pass.hpp"
#include "sphflume/boundaries/motion.hpp"
#include "sphflume/boundaries/walls.hpp"
#include "sphflume/physics/force_terms.hpp"
#include "sphflume/schemes/dual.hpp"

namespace sph {

namespace {
constexpr std::size_t kLanes = 16;  // the pair loops' vector width (16 floats: AVX-512; 2 x AVX2)


}  // namespace

template <int D>
template <class K, int Pass>
void DualWCSPH<D>::riemann_sweep(System<D>& S, const K& ker) {
  // Pass 0: pressure (A), 1: continuity (B), 2: density summation
  auto& P = S.particles;
  const double rho0 = S.eos.rho0, c0 = S.eos.c0;
  const double* __restrict rho = P.rho.data();
  const double* __restrict prs = P.p.data();
  const double* __restrict mass = P.mass.data();
  const Vec<D>* __restrict pos = P.pos.data();
  const Vec<D>* __restrict vel = P.vel.data();
  const Kind* __restrict kind = P.kind.data();
  const std::uint32_t* __restrict sorted = S.cells.sorted().data();
  Vec<D>* __restrict acc_out = P.acc.data();
  double* __restrict drho_out = P.drho.data();
  double* rho_out = P.rho.data();  // pass 2 writes the summation density in place (no other pass)
  const auto& cells = S.cells;
  const std::size_t n_owned = P.n_owned();
  double g[3] = {0.0, 0.0, 0.0};
  for (int d = 0; d < D; ++d) g[d] = S.gravity[d];
  const bool sym = cfg_.pressure_gradient == PressureGradient::Symmetric;
  if (sigma0_ <= 0.0) sigma0_ = lattice_kernel_sum<D>(ker, S.dx);  // (after a restart too)
  const double sigma_inv = rho0 / sigma0_;
  const double w_self = ker.W(0.0);
  using F32 = float;
  enum { X0, X1, X2, U0, U1, U2, N0, N1, N2, PRS, VOL, NCOL };
  const F32 fsupport2 = F32(ker.support2), ffar = F32(1.0e3), fk = F32(cfg_.riemann_limiter / c0);
  // walls: the dissipation acts along the wall normal (towards the fluid), on twice the
  // wall-relative normal speed (the mirror state), so that sliding along a wall is free
  const Vec<D>* __restrict wn = Pass == 1 ? P.vector(field::wall_to_surface).data() : nullptr;
  // the per-particle columns the candidates need, packed once per pass in store order (a
  // division per particle, not one per particle per stencil it falls in), so that the per-cell
  // stencil copies below only move floats; the pair sums are bitwise those of gathering the
  // candidates from the particle arrays
  const std::size_t np = P.size();
  const int npack = Pass == 0 ? 2 : Pass == 1 ? 2 * D + 2 : 0;
  pack_.resize(static_cast<std::size_t>(npack) * np);
  F32* __restrict pk = pack_.data();
  if constexpr (Pass == 0) {
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < np; ++i) {
      pk[i] = F32(sym ? prs[i] / (rho[i] * rho[i]) : prs[i]);
      pk[np + i] = F32(sym ? mass[i] : mass[i] / rho[i]);
    }
  } else if constexpr (Pass == 1) {
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < np; ++i) {
      for (int d = 0; d < D; ++d) pk[d * np + i] = F32(vel[i][d]);
      pk[D * np + i] = F32(mass[i] / rho[i]);
      const bool fl = fluid_like(kind[i]);
      const double len = fl ? 0.0 : std::sqrt(dot(wn[i], wn[i]));
      for (int d = 0; d < D; ++d) pk[(D + 1 + d) * np + i] = len > 0.0 ? F32(wn[i][d] / len) : F32(0);
      pk[(2 * D + 1) * np + i] = fl ? F32(1) : F32(0);
    }
  }
  // the cell's owned fluid particles (the pass runs those)
  auto needs = [&](std::size_t cell) {
    std::size_t m = 0;
    for (std::uint32_t k = cells.cell_begin(cell); k < cells.cell_end(cell); ++k)
      m += sorted[k] < n_owned && kind[sorted[k]] == Kind::Fluid ? 1 : 0;
    return m;
  };
  S.pairs_last_pass = sweep_cells<F32>(cells, NCOL, 16, needs,
                                       [&](std::size_t cell, const CellStencil<D>& st, ScratchColumns<F32>& B) {
      const std::uint32_t c0k = cells.cell_begin(cell), c1k = cells.cell_end(cell);
      const std::size_t npad = st.padded;
      std::uint64_t pairs = 0;
      const Vec<D> origin = pos[sorted[c0k]];
      if constexpr (Pass == 1) B.reserve(st.padded + kLanes);  // (the wall split pads twice; before the column pointers)
      F32* __restrict cx[D]; F32* __restrict cu[D]; F32* __restrict cn[D];
      for (int d = 0; d < D; ++d) { cx[d] = B[X0 + d]; cu[d] = B[U0 + d]; cn[d] = B[N0 + d]; }
      F32* __restrict cp = B[PRS];
      F32* __restrict cv = B[VOL];
      bool walls_near = false;  // any wall among the candidates (most cells have none)
      std::size_t nwall = 0;    // (how many, in a cell-ordered store)
      if constexpr (Pass == 1) {
        const F32* __restrict flag = pk + (2 * D + 1) * np;
        if (st.identity) {  // (a vector loop over each range: the candidate-wise callback was 6 % of the pass)
          std::size_t w = 0;
          st.for_ranges([&](std::uint32_t k0, std::size_t len, std::size_t) {
            const F32* __restrict fr = flag + k0;
#pragma omp simd reduction(+ : w)
            for (std::size_t i = 0; i < len; ++i) w += fr[i] < F32(1) ? 1 : 0;
          });
          nwall = w;
          walls_near = w != 0;
        } else {
          st.for_each([&](std::size_t, std::uint32_t b) { walls_near |= flag[b] < F32(1); });
        }
      }
      // the columns of store entries [k0, k0 + len) (a cell-ordered store) at entry m: positions
      // relative to the cell's first particle and the packed values, plain strided loops; the
      // packed values in loops of their own (fused with the positions GCC 12 left the loop
      // scalar; `omp simd` keeps the copies from becoming memcpy calls, slower for ranges of
      // ~30 entries); pass B's wall normals only where asked (fluid blocks do not read them)
      auto copy_run = [&](std::uint32_t k0, std::size_t len, std::size_t m, bool normals) {
        copy_positions<D>(pos, k0, len, origin, cx, m);
        const F32* __restrict in = pk + k0;
        if constexpr (Pass == 0) {
          F32* __restrict op = cp + m;
          F32* __restrict ov = cv + m;
#pragma omp simd
          for (std::size_t i = 0; i < len; ++i) {
            op[i] = in[i];
            ov[i] = in[np + i];
          }
        } else if constexpr (Pass == 1) {
          F32* __restrict u0 = cu[0] + m;
          F32* __restrict u1 = cu[1] + m;
          F32* __restrict u2 = cu[D - 1] + m;
          F32* __restrict ov = cv + m;
#pragma omp simd
          for (std::size_t i = 0; i < len; ++i) {
            u0[i] = in[i];
            u1[i] = in[np + i];
            if constexpr (D == 3) u2[i] = in[2 * np + i];
            ov[i] = in[D * np + i];
          }
          if (normals) {
            const F32* __restrict nin = pk + (D + 1) * np + k0;
            F32* __restrict n0 = cn[0] + m;
            F32* __restrict n1 = cn[1] + m;
            F32* __restrict n2 = cn[D - 1] + m;
#pragma omp simd
            for (std::size_t i = 0; i < len; ++i) {
              n0[i] = nin[i];
              n1[i] = nin[np + i];
              if constexpr (D == 3) n2[i] = nin[2 * np + i];
            }
          }
        }
      };
      // pass B with walls among the candidates: the fluid candidates first, then the walls,
      // each part padded to whole blocks, so that only the wall blocks pay for the normals
      std::size_t fluid_end = npad, npad_all = npad;
      if (Pass == 1 && walls_near) {
        const F32* __restrict flag = pk + (2 * D + 1) * np;
        auto put = [&](std::size_t m, std::uint32_t b) {
          for (int d = 0; d < D; ++d) {
            cx[d][m] = F32(pos[b][d] - origin[d]);
            cu[d][m] = pk[d * np + b];
            cn[d][m] = pk[(D + 1 + d) * np + b];
          }
          cv[m] = pk[D * np + b];
        };
        auto pad = [&](std::size_t m0, std::size_t m1) {
          for (std::size_t m = m0; m < m1; ++m) {
            for (int d = 0; d < D; ++d) { cx[d][m] = ffar; cu[d][m] = 0; cn[d][m] = 0; }
            cv[m] = 0;
          }
        };
        if (st.identity) {
          // the same order from the runs of one kind in each range (a cell's particles keep their
          // order, so fluid and walls come in a few runs): vector copies of each run. A branch
          // per candidate was a quarter of pass B in 3D, where nearly every cell has walls near.
          fluid_end = (st.count - nwall + kLanes - 1) / kLanes * kLanes;
          std::size_t mf = 0, mw = fluid_end;
          st.for_ranges([&](std::uint32_t k0, std::size_t len, std::size_t) {
            const F32* __restrict fr = flag + k0;
            for (std::size_t q = 0; q < len;) {
              const bool fl = fr[q] == F32(1);
              std::size_t e = q + 1;
              while (e < len && (fr[e] == F32(1)) == fl) ++e;
              std::size_t& m = fl ? mf : mw;
              copy_run(k0 + static_cast<std::uint32_t>(q), e - q, m, !fl);
              m += e - q;
              q = e;
            }
          });
          pad(mf, fluid_end);
          npad_all = (mw + kLanes - 1) / kLanes * kLanes;
          pad(mw, npad_all);
        } else {
          std::size_t m = 0;
          st.for_each([&](std::size_t, std::uint32_t b) { if (flag[b] == F32(1)) put(m++, b); });
          fluid_end = (m + kLanes - 1) / kLanes * kLanes;
          pad(m, fluid_end);
          m = fluid_end;
          st.for_each([&](std::size_t, std::uint32_t b) { if (flag[b] != F32(1)) put(m++, b); });
          npad_all = (m + kLanes - 1) / kLanes * kLanes;
          pad(m, npad_all);
        }
      } else if (st.identity) {  // the stencil's contiguous ranges
        st.for_ranges([&](std::uint32_t k0, std::size_t len, std::size_t m) { copy_run(k0, len, m, false); });
      } else {
        st.for_each([&](std::size_t m, std::uint32_t b) {
          for (int d = 0; d < D; ++d) cx[d][m] = F32(pos[b][d] - origin[d]);
          if constexpr (Pass == 0) {
            cp[m] = pk[b];
            cv[m] = pk[np + b];
          } else if constexpr (Pass == 1) {
            for (int d = 0; d < D; ++d) cu[d][m] = pk[d * np + b];
            cv[m] = pk[D * np + b];
          }
        });
      }
      if (!(Pass == 1 && walls_near))
        for (std::size_t m = st.count; m < npad; ++m) {
          for (int d = 0; d < D; ++d) { cx[d][m] = ffar; cu[d][m] = 0; }
          cp[m] = 0; cv[m] = 0;
        }
      auto particles = [&](auto walls) {
        constexpr bool Walls = decltype(walls)::value;
        for (std::uint32_t kk = c0k; kk < c1k; ++kk) {
          const std::uint32_t a = sorted[kk];
          if (a >= n_owned || kind[a] != Kind::Fluid) continue;
          const F32 xa0 = F32(pos[a][0] - origin[0]), xa1 = F32(pos[a][1] - origin[1]);
          const F32 xa2 = F32(pos[a][D - 1] - origin[D - 1]);
          const F32 va0 = F32(vel[a][0]), va1 = F32(vel[a][1]), va2 = F32(vel[a][D - 1]);
          const double rhoa = Pass == 2 ? rho0 : rho[a];  // (pass 2 writes rho: it must not read it)
          const F32 pa = F32(sym ? prs[a] / (rhoa * rhoa) : prs[a]);
          // lane-wise partial sums (kLanes apart), reduced by a fixed tree after the loop: the
          // order of the additions does not depend on the vector width, so AVX2 and AVX-512
          // builds give bitwise the same sums (bench/README.md); as fast as `omp simd reduction`
          alignas(64) F32 v0[kLanes] = {}, v1[kLanes] = {}, v2[kLanes] = {}, vr[kLanes] = {}, vc[kLanes] = {};
          // one block of kLanes candidates from k0; WallBlock: a block of pass B's wall part
          auto block = [&](std::size_t k0, auto wall_block) {
          constexpr bool WallBlock = decltype(wall_block)::value;
          // this block of candidates as plain arrays (an index k0 + l was a "complicated access
          // pattern" to GCC's AVX2 vectoriser)
          const F32* __restrict bx0 = B[X0] + k0;
          const F32* __restrict bx1 = B[X1] + k0;
          const F32* __restrict bx2 = B[X0 + D - 1] + k0;
          const F32* __restrict bu0 = B[U0] + k0;
          const F32* __restrict bu1 = B[U1] + k0;
          const F32* __restrict bu2 = B[U0 + D - 1] + k0;
          const F32* __restrict bn0 = B[N0] + k0;
          const F32* __restrict bn1 = B[N1] + k0;
          const F32* __restrict bn2 = B[N0 + D - 1] + k0;
          const F32* __restrict bp = B[PRS] + k0;
          const F32* __restrict bv = B[VOL] + k0;
#pragma omp simd
          for (std::size_t l = 0; l < kLanes; ++l) {
            const std::size_t k = l;
            // (the 2D loops spell out no third component: x * 0 and x + 0 are not folded away
            // under IEEE semantics, they would cost an operation each)
            const F32 r0 = xa0 - bx0[k], r1 = xa1 - bx1[k];
            const F32 r2c = D == 3 ? xa2 - bx2[k] : F32(0);
            const F32 r2 = D == 3 ? r0 * r0 + r1 * r1 + r2c * r2c : r0 * r0 + r1 * r1;
            const F32 r = std::sqrt(r2);
            if constexpr (Pass == 2) {
              const F32 in = ((r2 < fsupport2) & (r2 > F32(0))) ? F32(1) : F32(0);  // (the self term apart)
              vc[l] += in;
              vr[l] += ker.W(r) * in;
            } else if constexpr (Pass == 0) {
              // no mask: F is 0 from the support on (the padding sits far away) and the self
              // pair's terms carry r = 0
              vc[l] += ((r2 < fsupport2) & (r2 > F32(0))) ? F32(1) : F32(0);
              const F32 Fv = ker.F(r) * bv[k];  // W'(r)/r V_b (sym: m_b)
              const F32 pp = (pa + bp[k]) * Fv;
              v0[l] += pp * r0;
              v1[l] += pp * r1;
              if constexpr (D == 3) v2[l] += pp * r2c;
              vr[l] += (pa - bp[k]) * Fv * r;  // W'(r) V_b (pa − pb)
            } else {
              const F32 Fv = ker.F(r) * bv[k];
              const F32 u0 = va0 - bu0[k], u1 = va1 - bu1[k];
              const F32 u2 = D == 3 ? va2 - bu2[k] : F32(0);
              const F32 ur = D == 3 ? u0 * r0 + u1 * r1 + u2 * r2c : u0 * r0 + u1 * r1;  // (ua − ub)·r
              vr[l] += ur * Fv;
              // U = −(ua − ub)·e, the approach speed, and d the dissipation's direction times r:
              // r itself for fluid b; against a wall twice the speed along n', its normal turned
              // towards a, and d = r n' (the padding's n = 0 adds nothing)
              F32 d0 = r0, d1 = r1, d2 = r2c, U;
              if constexpr (WallBlock) {
                const F32 n0 = bn0[k], n1 = bn1[k], n2 = D == 3 ? bn2[k] : F32(0);
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
              // max(U, 0) as (U + |U|)/2 (exact in float) and min as a value select: GCC 12 left
              // this loop scalar on AVX2 with std::max or a select here (AVX-512 was fine)
              const F32 bu = fk * F32(0.5) * (U + std::abs(U));
              const F32 beta = bu < F32(1) ? bu : F32(1);
              const F32 q = beta * U * Fv;
              v0[l] += q * d0;
              v1[l] += q * d1;
              if constexpr (D == 3) v2[l] += q * d2;
            }
          }
          };
          if constexpr (Walls) {  // pass B: the fluid part, then the wall part
            for (std::size_t k0 = 0; k0 < fluid_end; k0 += kLanes) block(k0, std::false_type{});
            for (std::size_t k0 = fluid_end; k0 < npad_all; k0 += kLanes) block(k0, std::true_type{});
          } else {
            for (std::size_t k0 = 0; k0 < npad; k0 += kLanes) block(k0, std::false_type{});
          }
          const F32 s0 = lane_sum<kLanes>(v0), s1 = lane_sum<kLanes>(v1), s2 = D == 3 ? lane_sum<kLanes>(v2) : F32(0);
          const F32 sr = lane_sum<kLanes>(vr);
          if constexpr (Pass != 1) pairs += static_cast<std::uint64_t>(lane_sum<kLanes>(vc) + F32(0.5));  // (pass B counts none)
          if constexpr (Pass == 0) {
            // pressure: −(1/ρa) Σ (pa + pb) ∇W Vb (sum form) or −Σ mb (pa/ρa² + pb/ρb²) ∇W
            const double f = sym ? -1.0 : -1.0 / rhoa;
            Vec<D> ac = acc_out[a];  // the dissipation of the last continuity pass
            ac[0] += f * double(s0) + g[0];
            ac[1] += f * double(s1) + g[1];
            if constexpr (D == 3) ac[2] += f * double(s2) + g[2];
            acc_out[a] = ac;
            drho_out[a] = rhoa / (rho0 * c0) * double(sr);
          } else if constexpr (Pass == 1) {
            drho_out[a] += rhoa * double(sr);
            const double f = -rho0 * c0 / rhoa;
            Vec<D> ac;
            ac[0] = f * double(s0);
            ac[1] = f * double(s1);
            if constexpr (D == 3) ac[2] = f * double(s2);
            acc_out[a] = ac;
          } else {
            rho_out[a] = std::max(sigma_inv * (w_self + double(sr)), rho0);  // (the pass reads positions only)
          }
        }
      };
      if (Pass == 1 && walls_near) particles(std::true_type{});
      else particles(std::false_type{});
      return pairs;
  });
}

template <int D>
void DualWCSPH<D>::riemann_pass(System<D>& S, int pass) {
  S.with_kernel([&](const auto& K) {
    using Ker = std::decay_t<decltype(K)>;
    if (pass == 0) this->template riemann_sweep<Ker, 0>(S, K);
    else if (pass == 1) this->template riemann_sweep<Ker, 1>(S, K);
    else this->template riemann_sweep<Ker, 2>(S, K);
  });
}

template void DualWCSPH<2>::riemann_pass(System<2>&, int);
template void DualWCSPH<3>::riemann_pass(System<3>&, int);

}  // namespace sph
