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
#include <type_traits>

#include "sphflume/core/pair_pass.hpp"
#include "sphflume/boundaries/motion.hpp"
#include "sphflume/boundaries/walls.hpp"
#include "sphflume/physics/force_terms.hpp"
#include "sphflume/schemes/dual.hpp"
#include "sphflume/schemes/dual_terms.hpp"

namespace sph {

namespace {
constexpr std::size_t kLanes = 16;  // the pair loops' vector width (16 floats: AVX-512; 2 x AVX2)
using namespace dual;

/// What one Riemann pass reads and writes, and its constants.
template <int D>
struct RiemannPass {
  const Vec<D>* pos;
  const Vec<D>* vel;
  const double* rho;
  const double* prs;
  Vec<D>* acc;
  double* drho;
  double* rho_out;  // pass 2 writes the summation density in place (no other pass)
  const double* hs;  // resolution levels: each particle's h (null with one resolution)
  const double* mass;
  double g[3];
  double rho0, c0, sigma_inv, w_self;
  double vol_inv;  // levels: 1 / Σ V W of a full lattice (the summation density's reference, the same at every level)
  bool sym;
  F32 support2, fk;
};

/// Particle a of pass `Pass` over the cell's candidates [0, npad) (Walls: pass B with the fluid
/// candidates in [0, fluid_end) and the walls in [fluid_end, npad)); returns its pair count.
/// VarH (resolution levels): every pair's kernel at h_ab = (h_a + h_b)/2, and the summation density
/// ρ_a = ρ0 (V_a W(0, h_a) + Σ V_b W(r_ab, h_ab)) / Σ V W of a full lattice, V = m/ρ0 the rest volumes (on one
/// level it is the one-resolution ρ0 Σ W / σ0: the lattice sum is the same at every level, h/dx being one).
template <int D, int Pass, bool Walls, bool VarH, class K>
std::uint64_t riemann_particle(const RiemannPass<D>& q, const K& ker, const Block& cols, const Vec<D>& origin,
                               std::uint32_t a, std::size_t fluid_end, std::size_t npad) {
  const Vec<D>& x = q.pos[a];
  const Vec<D>& u = q.vel[a];
  const double rhoa = Pass == 2 ? q.rho0 : q.rho[a];  // (pass 2 writes rho: it must not read it)
  const Row row{F32(x[0] - origin[0]), F32(x[1] - origin[1]), F32(x[D - 1] - origin[D - 1]), F32(u[0]), F32(u[1]),
                F32(u[D - 1]), F32(q.sym ? q.prs[a] / (rhoa * rhoa) : q.prs[a]), VarH ? F32(q.hs[a]) : F32(0)};
  const F32 sup2 = q.support2, fk = q.fk;
  if constexpr (Pass == 2) {
    LaneSums<kLanes, 2> v;
    for (std::size_t k0 = 0; k0 < npad; k0 += kLanes) {
      const Block b = block_at(cols, k0);
      v.add([&](std::size_t l, auto&& acc) { density_terms<D, K, VarH>(ker, sup2, row, b, l, acc); });
    }
    const auto s = v.sums();
    if constexpr (VarH) {
      const double self = q.mass[a] / q.rho0 * ker.Wh(0.0, 1.0 / q.hs[a]);
      q.rho_out[a] = std::max(q.rho0 * q.vol_inv * (self + double(s[0])), q.rho0);
    } else {
      q.rho_out[a] = std::max(q.sigma_inv * (q.w_self + double(s[0])), q.rho0);  // (the pass reads positions only)
    }
    return static_cast<std::uint64_t>(s[1] + F32(0.5));
  } else if constexpr (Pass == 0) {
    LaneSums<kLanes, D + 2> v;
    for (std::size_t k0 = 0; k0 < npad; k0 += kLanes) {
      const Block b = block_at(cols, k0);
      v.add([&](std::size_t l, auto&& acc) { pressure_terms<D, K, VarH>(ker, sup2, row, b, l, acc); });
    }
    const auto s = v.sums();
    // pressure: −(1/ρa) Σ (pa + pb) ∇W Vb (sum form) or −Σ mb (pa/ρa² + pb/ρb²) ∇W
    const double f = q.sym ? -1.0 : -1.0 / rhoa;
    Vec<D> ac = q.acc[a];  // the dissipation of the last continuity pass
    for (int d = 0; d < D; ++d) ac[d] += f * double(s[d]) + q.g[d];
    q.acc[a] = ac;
    q.drho[a] = rhoa / (q.rho0 * q.c0) * double(s[D]);
    return static_cast<std::uint64_t>(s[D + 1] + F32(0.5));
  } else {
    LaneSums<kLanes, D + 1> v;
    const std::size_t fluid = Walls ? fluid_end : npad;
    for (std::size_t k0 = 0; k0 < fluid; k0 += kLanes) {
      const Block b = block_at(cols, k0);
      v.add([&](std::size_t l, auto&& acc) { continuity_terms<D, false, K, VarH>(ker, fk, row, b, l, acc); });
    }
    for (std::size_t k0 = fluid; k0 < npad; k0 += kLanes) {  // (Walls only)
      const Block b = block_at(cols, k0);
      v.add([&](std::size_t l, auto&& acc) { continuity_terms<D, true, K, VarH>(ker, fk, row, b, l, acc); });
    }
    const auto s = v.sums();
    q.drho[a] += rhoa * double(s[D]);
    const double f = -q.rho0 * q.c0 / rhoa;
    Vec<D> ac;
    for (int d = 0; d < D; ++d) ac[d] = f * double(s[d]);
    q.acc[a] = ac;
    return 0;  // (pass B counts none)
  }
}

}  // namespace

template <int D>
template <class K, int Pass, bool VarH>
void DualWCSPH<D>::riemann_sweep(System<D>& S, const K& ker) {
  // Pass 0: pressure (A), 1: continuity (B), 2: density summation
  auto& P = S.particles;
  const double rho0 = S.eos.rho0, c0 = S.eos.c0;
  if (sigma0_ <= 0.0) sigma0_ = lattice_kernel_sum<D>(ker, S.dx);  // (after a restart too)
  const bool sym = cfg_.pressure_gradient == PressureGradient::Symmetric;
  const double* hs = VarH ? P.require(field::smoothing_length).data() : nullptr;
  RiemannPass<D> q{P.pos.data(), P.vel.data(), P.rho.data(), P.p.data(), P.acc.data(), P.drho.data(), P.rho.data(),
                   hs, P.mass.data(), {0.0, 0.0, 0.0}, rho0, c0, rho0 / sigma0_, ker.W(0.0),
                   1.0 / (ipow<D>(S.dx) * sigma0_), sym, F32(ker.support2), F32(cfg_.riemann_limiter / c0)};
  if constexpr (VarH) q.support2 = F32(K::support_factor * K::support_factor);  // (compared with r²/h_ab²)
  for (int d = 0; d < D; ++d) q.g[d] = S.gravity[d];
  // walls: the dissipation acts along the wall normal (towards the fluid), on twice the
  // wall-relative normal speed (the mirror state), so that sliding along a wall is free
  pack_columns<D, Pass>(P, sym, pack_);
  const F32* pk = pack_.data();
  const std::size_t np = P.size(), n_owned = P.n_owned();
  const Kind* __restrict kind = P.kind.data();
  const std::uint32_t* __restrict sorted = S.cells.sorted().data();
  const auto& cells = S.cells;
  // the candidates' columns (column descriptors: the packed values)
  auto packed = [pk, np](int index, std::size_t offset) {
    return column(index, F32(0), [pk, off = offset * np](std::size_t j) { return pk[off + j]; });
  };
  auto normal = [pk, np](int index, std::size_t offset) {
    return second_part(index, F32(0), [pk, off = offset * np](std::size_t j) { return pk[off + j]; });
  };
  // levels: each candidate's h, and the density pass's rest volumes m/ρ0
  const auto h_col = only_if<VarH>(column(HS, F32(1), [hs](std::size_t j) { return F32(hs[j]); }));
  const double* __restrict mass = P.mass.data();
  const auto v0_col = only_if<VarH>(column(VOL, F32(0), [mass, rho0](std::size_t j) { return F32(mass[j] / rho0); }));
  const F32* __restrict flag = pk + (2 * D + 1) * np;  // (pass B)
  auto needs = [&](std::size_t cell) {  // the cell's owned fluid particles (the pass runs those)
    std::size_t m = 0;
    for (std::uint32_t k = cells.cell_begin(cell); k < cells.cell_end(cell); ++k)
      m += sorted[k] < n_owned && kind[sorted[k]] == Kind::Fluid ? 1 : 0;
    return m;
  };
  S.pairs_last_pass = sweep_cells<F32>(cells, NCOL, kLanes, needs,
                                       [&](std::size_t cell, const CellStencil<D>& st, ScratchColumns<F32>& B) {
    const std::uint32_t c0k = cells.cell_begin(cell), c1k = cells.cell_end(cell);
    const Vec<D> origin = q.pos[sorted[c0k]];
    std::size_t nwall = 0;  // pass B: the walls among the candidates (most cells have none)
    if constexpr (Pass == 1) {
      if (st.identity) {  // (a vector loop over each range: the candidate-wise callback was 6 % of the pass)
        st.for_ranges([&](std::uint32_t k0, std::size_t len, std::size_t) {
          const F32* __restrict fr = flag + k0;
          std::size_t w = 0;
#pragma omp simd reduction(+ : w)
          for (std::size_t i = 0; i < len; ++i) w += fr[i] < F32(1) ? 1 : 0;
          nwall += w;
        });
      } else {
        st.for_each([&](std::size_t, std::uint32_t j) { nwall += flag[j] < F32(1) ? 1 : 0; });
      }
    }
    std::size_t fluid_end = st.padded, end = st.padded;
    if constexpr (Pass == 0) {
      gather_columns(st, B, q.pos, origin, packed(PRS, 0), packed(VOL, 1), h_col);
    } else if constexpr (Pass == 1) {
      if (nwall == 0) {
        gather_columns(st, B, q.pos, origin, packed(U0, 0), packed(U1, 1), only_if<D == 3>(packed(U2, 2)), packed(VOL, D), h_col);
      } else {  // the fluid candidates first, then the walls: only the wall blocks pay for the normals
        B.reserve(st.padded + kLanes);
        const auto e = gather_split(st, B, q.pos, origin, kLanes, nwall, [flag](std::uint32_t j) { return flag[j] == F32(1); },
                                    packed(U0, 0), packed(U1, 1), only_if<D == 3>(packed(U2, 2)), packed(VOL, D), h_col,
                                    normal(N0, D + 1), normal(N1, D + 2), only_if<D == 3>(normal(N2, D + 3)));
        fluid_end = e.first_end;
        end = e.end;
      }
    } else {
      gather_columns(st, B, q.pos, origin, v0_col, h_col);
    }
    const Block cols = columns_of<D>(B);
    std::uint64_t pairs = 0;
    for (std::uint32_t kk = c0k; kk < c1k; ++kk) {
      const std::uint32_t a = sorted[kk];
      if (a >= n_owned || kind[a] != Kind::Fluid) continue;
      if (Pass == 1 && nwall > 0) pairs += riemann_particle<D, Pass, true, VarH>(q, ker, cols, origin, a, fluid_end, end);
      else pairs += riemann_particle<D, Pass, false, VarH>(q, ker, cols, origin, a, fluid_end, end);
    }
    return pairs;
  });
}

template <int D>
void DualWCSPH<D>::riemann_pass(System<D>& S, int pass) {
  auto run = [&](auto varh) {
    constexpr bool VarH = decltype(varh)::value;
    S.with_kernel([&](const auto& K) {
      using Ker = std::decay_t<decltype(K)>;
      if (pass == 0) this->template riemann_sweep<Ker, 0, VarH>(S, K);
      else if (pass == 1) this->template riemann_sweep<Ker, 1, VarH>(S, K);
      else this->template riemann_sweep<Ker, 2, VarH>(S, K);
    });
  };
  if (S.levels > 0) run(std::true_type{});  // (resolution levels: each pair at h_ab)
  else run(std::false_type{});
}

template void DualWCSPH<2>::riemann_pass(System<2>&, int);
template void DualWCSPH<3>::riemann_pass(System<3>&, int);

}  // namespace sph
