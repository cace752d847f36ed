#include "sphflume/boundaries/walls.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <stdexcept>
#include <type_traits>

#include "sphflume/core/interpolate.hpp"
#include "sphflume/core/pair_pass.hpp"
#include "sphflume/core/refinement.hpp"

namespace sph {
namespace {

template <int D>
class DummyWalls final : public WallModel<D> {
 public:
  using WallModel<D>::WallModel;
  const char* name() const override { return "dummy"; }
  bool evolves_density() const override { return false; }
  const float* viscous_correction() const override { return this->cfg.no_slip ? corr_.data() : nullptr; }
  std::size_t bytes() const override {
    return WallModel<D>::bytes() + corr_.capacity() * sizeof(float);
  }

  void prepare(System<D>& S, const double* near_only) override {
    auto& P = S.particles;
    // the ghost velocity is only needed for no-slip walls (free-slip walls skip the viscous term)
    if (this->cfg.no_slip) corr_.resize(P.size() * D);
    // walls with no fluid within the kernel support keep the background state: skip their
    // neighbour search (most of a tank's walls, most of the time)
    const auto& cells = S.cells;
    const std::uint32_t* srt = cells.sorted().data();
    const auto has_walls = [&](std::size_t cell) {  // (only a cell with wall particles reads its mark)
      for (std::uint32_t k = cells.cell_begin(cell); k < cells.cell_end(cell); ++k)
        if (P.kind[srt[k]] == Kind::Wall) return true;
      return false;
    };
    S.cells.mark_near(this->near_, [&, fast = near_only](std::size_t j) { return fluid_like(P.kind[j]) && (!fast || fast[j] != 0.0); },
                      0.0, has_walls);
    const Pass p{cells.sorted().data(), P.pos.data(), P.vel.data(), P.rho.data(), P.p.data(), P.kind.data(),
                 P.find(field::wall_acc) ? P.find(field::wall_acc)->data() : nullptr,  // moving walls
                 this->cfg.no_slip ? corr_.data() : nullptr, P.n_owned(), this->cfg.clamp_negative_pressure,
                 S.eos.density(S.eos.background),
                 S.level_h()};
    S.with_kernel([&](const auto& K) {
      // cells with wall particles; those with no fluid within reach keep the background state
      auto needs = [&](std::size_t cell) {
        std::size_t walls_here = 0;  // the wall particles with fluid within reach
        for (std::uint32_t k = cells.cell_begin(cell); k < cells.cell_end(cell); ++k) {
          const std::uint32_t i = p.sorted[k];
          if (i >= p.n || p.kind[i] != Kind::Wall) continue;
          if (!this->near_[cell]) {  // no fluid within reach: the background state
            if (near_only) continue;  // (a multirate fast pass: no fast fluid near; the state of the last full pass stays)
            P.p[i] = S.eos.background;
            P.rho[i] = p.rho_bg;
            if (p.gv)
              for (int d = 0; d < D; ++d) p.gv[i * D + d] = 0.0f;
            continue;
          }
          ++walls_here;
        }
        return walls_here;
      };
      // float columns and 16 fixed lanes (as the pair passes): positions relative to the cell's
      // first particle; lane-wise partial sums reduced in a fixed order (the same bits on AVX2
      // and AVX-512); the velocity sums only for no-slip walls. (Packing the fluid candidates
      // alone was 6 % faster on the 3D dam break, but its other summation order tipped the
      // coarse regular-waves check, a marginal run near its paddle, into failure: bench/README.)
      // (resolution levels: the kernel at each pair's h_ij, fsupport2 the support factor²)
      using Ker = std::decay_t<decltype(K)>;
      const F32 fsupport2 = F32(p.hs ? Ker::support_factor * Ker::support_factor : K.support2);
      auto run = [&](auto no_slip, auto var_h) {
        constexpr bool NoSlip = decltype(no_slip)::value, VarH = decltype(var_h)::value;
        sweep_cells<F32>(cells, NCOL, L, needs, [&](std::size_t cell, const CellStencil<D>& st, ScratchColumns<F32>& B) {
          const std::uint32_t c0k = cells.cell_begin(cell), c1k = cells.cell_end(cell);
          const Vec<D> origin = p.pos[p.sorted[c0k]];
          gather<NoSlip, VarH>(p, st, B, origin);
          thread_local std::vector<std::uint32_t> blocks;
          fluid_blocks(B, st.padded, blocks);
          wall_states<NoSlip, VarH>(S, K, p, c0k, c1k, B, origin, blocks, fsupport2);
          return std::uint64_t(0);
        });
      };
      if (p.hs) {
        if (p.gv) run(std::true_type{}, std::true_type{});
        else run(std::false_type{}, std::true_type{});
      } else {
        if (p.gv) run(std::true_type{}, std::false_type{});
        else run(std::false_type{}, std::false_type{});
      }
    });
    S.refresh_halos();
    if (p.gv) S.refresh_halos(p.gv, D);  // images carry their source's correction (the sweep reads it for any wall candidate)
  }

  bool prepare_from_pairs(System<D>& S, const WallPairs& wp) override {
    // Adami et al.'s rule as wall_states below, over the kept pairs: p_w = (Σ p_a W + (g − a_w)·Σ ρ_a r W)/Σ W,
    // the no-slip ghost velocity 2 v_w − Σ u_a W/Σ W; no fluid partner: the background state
    auto& P = S.particles;
    const std::size_t n = P.n_owned();
    if (this->cfg.no_slip) corr_.resize(P.size() * D);
    const Vec<D>* aw = P.find(field::wall_acc) ? P.find(field::wall_acc)->data() : nullptr;
    const bool clamp = this->cfg.clamp_negative_pressure, no_slip = this->cfg.no_slip;
    const double rho_bg = S.eos.density(S.eos.background);
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < n; ++i) {
      if (P.kind[i] != Kind::Wall) continue;
      double sw = 0.0, sp = 0.0;
      Vec<D> srr{}, sv{};
      for (std::uint32_t k = wp.begin[i]; k < wp.end[i]; ++k) {
        const std::uint32_t a = wp.fluid[k];
        const double w = wp.w[k];
        sw += w;
        sp += P.p[a] * w;
        const double rw = P.rho[a] * w;
        for (int d = 0; d < D; ++d) srr[d] += rw * wp.r[std::size_t(k) * D + d];
        if (no_slip) sv += w * P.vel[a];
      }
      double pw = S.eos.background;
      Vec<D> g = P.vel[i];
      if (sw > 0.0) {
        pw = (sp + dot(aw ? S.gravity - aw[i] : S.gravity, srr)) / sw;
        g = 2.0 * P.vel[i] - (1.0 / sw) * sv;
      }
      if (clamp) pw = std::max(pw, S.eos.background);
      P.p[i] = pw;
      P.rho[i] = sw > 0.0 ? S.eos.density(pw) : rho_bg;
      if (no_slip)
        for (int d = 0; d < D; ++d) corr_[i * D + d] = float(P.vel[i][d] - g[d]);
    }
    S.refresh_halos();
    return true;
  }

 private:
  using F32 = float;
  static constexpr std::size_t L = 16;  // the lanes of the sums
  enum { X0, X1, X2, V0, V1, V2, PRS, RHO, FLUID, HS, NCOL };
  /// What one prepare() pass reads: the store's arrays and the constants.
  struct Pass {
    const std::uint32_t* sorted;
    const Vec<D>* pos;
    const Vec<D>* vel;
    const double* rho;
    const double* prs;
    const Kind* kind;
    const Vec<D>* aw;  // moving walls' acceleration (none: nullptr)
    float* gv;         // no-slip: the ghost correction written here (free slip: nullptr)
    std::size_t n;     // owned particles
    bool clamp;
    double rho_bg;
    const double* hs;  // resolution levels: each particle's h (one level: nullptr)
  };

  /// The candidates' columns of one cell (column descriptors): positions relative to `origin`,
  /// and the fluid's pressure, density and flag (0 for walls), the velocity for no-slip walls
  /// (a wall's weight is 0, so its velocity, finite and not written by this pass, is copied as
  /// it is); padding far away, no fluid. Only fluid pressures and densities are read: other
  /// threads are writing wall pressures meanwhile.
  template <bool NoSlip, bool VarH>
  static void gather(const Pass& p, const CellStencil<D>& st, ScratchColumns<F32>& B, const Vec<D>& origin) {
    const Vec<D>* __restrict vel = p.vel;
    const double* __restrict rho = p.rho;
    const double* __restrict prs = p.prs;
    const Kind* __restrict kind = p.kind;
    const auto fluid = column(FLUID, F32(0), [kind](std::size_t j) { return fluid_like(kind[j]) ? F32(1) : F32(0); });
    const auto pressure = column(PRS, F32(0), [kind, prs](std::size_t j) { return fluid_like(kind[j]) ? F32(prs[j]) : F32(0); });
    const auto density = column(RHO, F32(0), [kind, rho](std::size_t j) { return fluid_like(kind[j]) ? F32(rho[j]) : F32(0); });
    auto velocity = [vel](int d, int index) {
      return column(index, F32(0), [vel, d](std::size_t j) { return F32(vel[j][d]); });
    };
    const double* __restrict hs = p.hs;
    const auto smoothing = column(HS, F32(1), [hs](std::size_t j) { return F32(hs[j]); });
    if constexpr (!NoSlip) gather_columns(st, B, p.pos, origin, pressure, density, fluid, only_if<VarH>(smoothing));
    else gather_columns(st, B, p.pos, origin, pressure, density, fluid, velocity(0, V0), velocity(1, V1),
                        only_if<D == 3>(velocity(D - 1, V2)), only_if<VarH>(smoothing));
  }

  /// The offsets of the blocks of L candidates that hold fluid.
  static void fluid_blocks(ScratchColumns<F32>& B, std::size_t npad, std::vector<std::uint32_t>& blocks) {
    // the blocks of L candidates that hold fluid: a block of walls and padding adds only
    // zeros (its weights are 0), so the wall particles below skip it (next to a floor, half
    // the stencil is wall cells)
    blocks.clear();
    for (std::size_t k0 = 0; k0 < npad; k0 += L) {
      const F32* __restrict bf = B[FLUID] + k0;
      F32 any = 0;
#pragma omp simd reduction(max : any)
      for (std::size_t l = 0; l < L; ++l) any = std::max(any, bf[l]);
      if (any > F32(0)) blocks.push_back(static_cast<std::uint32_t>(k0));
    }
  }

  /// Each wall particle of the cell [c0k, c1k): pressure (and density) from the Shepard-weighted
  /// fluid pressures plus the hydrostatic part along (g − a_w), and the no-slip ghost velocity.
  template <bool NoSlip, bool VarH, class Ker>
  static void wall_states(System<D>& S, const Ker& K_, const Pass& p, std::uint32_t c0k, std::uint32_t c1k,
                          ScratchColumns<F32>& B, const Vec<D>& origin, const std::vector<std::uint32_t>& blocks,
                          F32 fsupport2) {
    auto& P = S.particles;
    const auto& K = K_;
    const std::uint32_t* __restrict sorted = p.sorted;
    const Vec<D>* __restrict pos = p.pos;
    const Vec<D>* __restrict vel = p.vel;
    const Kind* __restrict kind = p.kind;
    const Vec<D>* aw = p.aw;
    float* gv = p.gv;
    const std::size_t n = p.n;
    const bool clamp = p.clamp;
    const F32 l_support2 = fsupport2;  // (locals, not captures: read through a closure, AVX2 loops stay scalar)
    for (std::uint32_t k = c0k; k < c1k; ++k) {
      const std::uint32_t i = sorted[k];
      if (i >= n || kind[i] != Kind::Wall) continue;
      // Shepard-weighted sums over the fluid neighbours (branch-free, vectorised): W, p W,
      // ρ W r (D) and, no-slip, W u (D)
      LaneSums<L, NoSlip ? 2 * D + 2 : D + 2> v;
      const F32 xi0 = F32(pos[i][0] - origin[0]), xi1 = F32(pos[i][1] - origin[1]);
      const F32 xi2 = F32(pos[i][D - 1] - origin[D - 1]);
      [[maybe_unused]] const F32 hi = VarH ? F32(p.hs[i]) : F32(0);
      for (const std::uint32_t k0 : blocks) {
        const F32* __restrict bx0 = B[X0] + k0;
        const F32* __restrict bx1 = B[X1] + k0;
        const F32* __restrict bx2 = B[X0 + D - 1] + k0;
        const F32* __restrict bv0 = B[V0] + k0;
        const F32* __restrict bv1 = B[V1] + k0;
        const F32* __restrict bv2 = B[V0 + D - 1] + k0;
        const F32* __restrict bp = B[PRS] + k0;
        const F32* __restrict br = B[RHO] + k0;
        const F32* __restrict bf = B[FLUID] + k0;
        [[maybe_unused]] const F32* __restrict bh = B[HS] + k0;
        v.add([&](std::size_t l, auto&& acc) {
          const F32 r0 = xi0 - bx0[l], r1 = xi1 - bx1[l];
          const F32 r2c = D == 3 ? xi2 - bx2[l] : F32(0);
          const F32 r2 = D == 3 ? r0 * r0 + r1 * r1 + r2c * r2c : r0 * r0 + r1 * r1;
          // (the mask as a factor: a select of a column load left this loop scalar)
          F32 w;
          if constexpr (VarH) {  // the pair's h_ij = (h_i + h_b)/2
            const F32 ih = F32(2) / (hi + bh[l]);
            w = K.Wh(std::sqrt(r2), ih) * (((r2 * ih * ih < l_support2) ? F32(1) : F32(0)) * bf[l]);
          } else {
            w = K.W(std::sqrt(r2)) * (((r2 < l_support2) ? F32(1) : F32(0)) * bf[l]);
          }
          acc[0][l] += w;
          acc[1][l] += bp[l] * w;
          const F32 rw = br[l] * w;
          acc[2][l] += rw * r0;
          acc[3][l] += rw * r1;
          if constexpr (D == 3) acc[4][l] += rw * r2c;
          if constexpr (NoSlip) {
            acc[D + 2][l] += w * bv0[l];
            acc[D + 3][l] += w * bv1[l];
            if constexpr (D == 3) acc[D + 4][l] += w * bv2[l];
          }
        });
      }
      const auto s = v.sums();
      const double sw = s[0], sp = s[1];
      Vec<D> srr{}, sv{};
      for (int d = 0; d < D; ++d) srr[d] = s[2 + d];
      if constexpr (NoSlip)
        for (int d = 0; d < D; ++d) sv[d] = s[D + 2 + d];
      double pw = S.eos.background;
      Vec<D> g = vel[i];
      if (sw > 0.0) {
        pw = (sp + dot(aw ? S.gravity - aw[i] : S.gravity, srr)) / sw;  // (g − a_w)·Σ ρ r W
        g = 2.0 * vel[i] - (1.0 / sw) * sv;
      }
      if (clamp) pw = std::max(pw, S.eos.background);
      P.p[i] = pw;
      P.rho[i] = S.eos.density(pw);
      if (gv)
        for (int d = 0; d < D; ++d) gv[i * D + d] = float(vel[i][d] - g[d]);
    }
  }

  std::vector<float> corr_;  // no-slip: v − v_ghost of each wall particle (viscous_correction)
};

/// Monaghan & Kos (1999) walls alone: the wall particles are outside every pair sum; only the
/// repulsive force (WallModel::add_forces) keeps the fluid out.
template <int D>
class RepulsiveWalls final : public WallModel<D> {
 public:
  using WallModel<D>::WallModel;
  const char* name() const override { return "repulsive"; }
  bool evolves_density() const override { return false; }
  bool in_pair_sums() const override { return false; }
  void prepare(System<D>&, const double*) override {}
};

template <int D>
class DynamicWalls final : public WallModel<D> {
 public:
  using WallModel<D>::WallModel;
  const char* name() const override { return "dynamic"; }
  bool evolves_density() const override { return true; }
  void prepare(System<D>&, const double*) override {}  // pressure follows the density in the integrator
};

}  // namespace

template <int D>
void WallModel<D>::init_fields(System<D>& S, std::size_t first_wall, const std::vector<Vec<D>>& surface) const {
  auto& P = S.particles;
  if (cfg.repulsive) {  // unit normal of each wall particle towards the fluid side of its surface
    auto& nrm = P.vector(field::wall_normal);
    for (std::size_t k = 0; k < surface.size(); ++k) {
      const Vec<D> v = surface[k] - P.pos[first_wall + k];
      const double len = norm(v);
      nrm[first_wall + k] = len > 0.0 ? (1.0 / len) * v : Vec<D>{};
    }
  }
  if (cfg.backup) {  // the vector from each wall particle to its surface point (depth, normal)
    auto& to = P.vector(field::wall_to_surface);
    for (std::size_t k = 0; k < surface.size(); ++k) to[first_wall + k] = surface[k] - P.pos[first_wall + k];
  }
}

template <int D>
void WallModel<D>::add_forces(System<D>& S, const double* near_only) const {
  if (cfg.backup) add_backup(S, near_only);
  if (!cfg.repulsive) return;
  auto& P = S.particles;
  if (!P.has(field::wall_normal))
    throw std::logic_error("repulsive walls: the geometry made no wall normals (wall_normal)");
  const auto& nrm = P.vector(field::wall_normal);
  const std::size_t n = P.n_owned();
  const double dx = S.dx, c0 = S.eos.c0, h = S.h, pi = std::acos(-1.0);
  const double b1 = cfg.beta1 * c0 * c0, b2 = cfg.beta2 * c0;
  // resolution levels: each wall particle repels over its own level's spacing and h (a split wall's children stand
  // dx_l apart, as a uniform fine run's walls; docs/numerics.md §14); level 0 (and one-level runs) dx and h
  const double* lv = S.levels > 0 ? P.scalar(field::level).data() : nullptr;
#pragma omp parallel for schedule(dynamic, 64)
  for (std::size_t a = 0; a < n; ++a) {
    if (P.kind[a] != Kind::Fluid) continue;
    Vec<D> f{};
    S.cells.for_neighbours(P.pos, P.pos[a], dx, [&](std::uint32_t k, const Vec<D>& r, double r2) {
      if (P.kind[k] != Kind::Wall) return;
      const int l = lv ? static_cast<int>(lv[k]) : 0;
      const double dxk = level_h(dx, l), hk = level_h(h, l);  // (l = 0: dx and h exactly)
      const Vec<D>& nk = nrm[k];  // (images carry their source's normal)
      const double rn = dot(r, nk);  // r = x_a − x_k: distance on the fluid side of the wall particle
      if (!(rn > 0.0) || rn >= dxk) return;
      const double rt = std::sqrt(std::max(0.0, r2 - rn * rn));
      if (rt >= dxk) return;
      const double q = rn / dxk;
      const double v = -dot(P.vel[a] - P.vel[k], nk);
      const double A = std::max(0.0, b1 + b2 * v) / hk;
      f += (A * (1.0 - q) / std::sqrt(q) * 0.5 * (1.0 + std::cos(pi * rt / dxk))) * nk;
    });
    P.acc[a] += f;
  }
}

namespace {
/// The walls' backup's float pre-test of first-layer wall k (xk: its position relative to the
/// cell's first particle; nk: its unit normal) against the fluid candidates gathered in B (their
/// positions in columns [0, D), nf of them, padded far away): 16 lanes at a time, a slightly
/// wider test than the exact one (the float round-off ~1e-7 against a relative widening of
/// 1e-3); found(m) for each candidate entry m that passes, in order.
struct BackupTest {
  float reach2, dx2, s0, abs_tol;  // (widened)
};
template <int D, class Found>
void backup_candidates(ScratchColumns<float>& B, const float* xk, const float* nk, float depth, const BackupTest& t,
                       std::size_t nf, Found&& found) {
  constexpr std::size_t L = 16;
  const float lim = depth + t.s0 + t.abs_tol;
  for (std::size_t k0 = 0; k0 < nf; k0 += L) {
    alignas(64) int pass[L];
    const float* __restrict bx0 = B[0] + k0;
    const float* __restrict bx1 = B[1] + k0;
    const float* __restrict bx2 = B[D - 1] + k0;
    int any = 0;
#pragma omp simd reduction(| : any)
    for (std::size_t l = 0; l < L; ++l) {
      const float r0 = xk[0] - bx0[l], r1 = xk[1] - bx1[l], r2c = D == 3 ? xk[2] - bx2[l] : 0.0f;
      const float r2 = r0 * r0 + r1 * r1 + r2c * r2c;
      const float rn = -(r0 * nk[0] + r1 * nk[1] + r2c * nk[2]);
      pass[l] = (r2 < t.reach2) & (rn < lim) & (r2 - rn * rn < t.dx2);
      any |= pass[l];
    }
    if (!any) continue;
    for (std::size_t l = 0; l < L && k0 + l < nf; ++l)
      if (pass[l]) found(k0 + l);
  }
}
}  // namespace

template <int D>
void WallModel<D>::find_moving_covered(const System<D>& S) const {
  // A moving body's face that rests on a fixed wall (a piston's foot sliding on the bed) is covered while it rests
  // there: its backup would push the fluid beside the face's edge into the corner the two bodies make (the coarse
  // regular waves: fluid pushed under the paddle's front edge into the bed). Found each pass, as fill_shapes'
  // covered_walls does for fixed bodies once: a fixed wall point within dx/2 of the point dx/2 beyond the face.
  moving_covered_.clear();
  const auto& P = S.particles;
  const auto* grp = P.find(field::motion_group);
  const auto* surface = P.find(field::wall_to_surface);
  if (!grp || !surface) return;
  const auto& to = *surface;
  const double dx = S.dx;
  const std::size_t nall = P.size();
  // (the tests on the threads, the list then in store order)
  std::vector<char> covered(nall, 0);
#pragma omp parallel for schedule(static)
  for (std::size_t k = 0; k < nall; ++k) {
    if (P.kind[k] != Kind::Wall || (*grp)[k] == 0.0) continue;
    const double depth2 = dot(to[k], to[k]);
    if (!(depth2 > 0.0 && depth2 < dx * dx)) continue;
    const double len = std::sqrt(depth2);
    const Vec<D> probe = P.pos[k] + to[k] + (0.5 * dx / len) * to[k];
    bool on_fixed = false;
    S.cells.for_neighbours(P.pos, probe, 0.5 * dx * 0.999, [&](std::uint32_t j, const Vec<D>&, double) {
      on_fixed = on_fixed || (P.kind[j] == Kind::Wall && (*grp)[j] == 0.0);
    });
    covered[k] = on_fixed;
  }
  for (std::size_t k = 0; k < nall; ++k)
    if (covered[k]) moving_covered_.push_back(static_cast<std::uint32_t>(k));
}

template <int D>
void WallModel<D>::add_backup(System<D>& S, const double* near_only) const {
  auto& P = S.particles;
  if (!P.has(field::wall_to_surface))
    throw std::logic_error("wall backup: the geometry made no wall surface vectors (wall_to_surface)");
  const auto& to = P.vector(field::wall_to_surface);
  const std::size_t n = P.n_owned();
  const double dx = S.dx;
  const double s0 = 0.25 * dx;  // the fluid's normal distance from the surface is dx/2
  const double reach = std::hypot(dx + s0, dx);
  // resolution levels: each wall particle holds the fluid over its own level's spacing dx_l (its first layer lies
  // within dx_l of the surface, the fluid beside it dx_l/2 off, its children dx_l apart: docs/numerics.md §14), as
  // the repulsive walls do; the gathers and the float pre-test keep level 0's (the widest) reach
  const double* lv = S.levels > 0 ? P.scalar(field::level).data() : nullptr;
  const auto dx_of = [lv, dx](std::size_t k) { return lv ? level_h(dx, static_cast<int>(lv[k])) : dx; };  // (l = 0: dx)
  // Found from the first-layer wall particles' side (far fewer than the fluid near walls; owned
  // walls and images alike, pushing only owned fluid, so that a periodic image or another
  // rank's wall pushes this part's fluid exactly once), in cells with fluid within reach
  // (reach < the cell size): the stencil's owned fluid is gathered in float columns relative to
  // the cell's first particle (gather_if) and pre-tested in float (backup_candidates); the few
  // candidates it passes are tested again in double, as the force uses them. The rare pairs
  // found are applied serially, sorted, so the sums do not depend on the threads.
  hits_.clear();
  const auto& cells = S.cells;
  const std::uint32_t* __restrict sorted = cells.sorted().data();
  const auto* covered = P.find(field::wall_covered);  // (set-up: faces another fixed wall covers)
  find_moving_covered(S);
  const auto first_layer = [&, cov = covered ? covered->data() : nullptr](std::size_t k) {  // (owned or image: images carry the fields)
    if (P.kind[k] != Kind::Wall || (cov && cov[k] != 0.0)) return false;
    const double depth2 = dot(to[k], to[k]), dxk = dx_of(k);
    if (!(depth2 > 0.0 && depth2 < dxk * dxk)) return false;  // a corner's own point has no normal
    return moving_covered_.empty() || !std::binary_search(moving_covered_.begin(), moving_covered_.end(), static_cast<std::uint32_t>(k));
  };
  const auto has_first_layer = [&](std::size_t cell) {  // (only such a cell reads its mark)
    for (std::uint32_t k = cells.cell_begin(cell); k < cells.cell_end(cell); ++k)
      if (first_layer(sorted[k])) return true;
    return false;
  };
  // (levels: cells may be narrower than the reach)
  S.cells.mark_near(this->near_, [&, fast = near_only](std::size_t j) { return fluid_like(P.kind[j]) && (!fast || fast[j] != 0.0); },
                    reach, has_first_layer);
  const auto hit = [&](std::uint32_t j, std::size_t k) {  // the exact test
    const Vec<D> r = P.pos[k] - P.pos[j];
    const double r2 = dot(r, r);
    if (!(r2 < reach * reach)) return false;
    const double depth = std::sqrt(dot(to[k], to[k])), dxk = dx_of(k);
    const double rn = -dot(r, (1.0 / depth) * to[k]);
    return rn - depth < 0.25 * dxk && r2 - rn * rn < dxk * dxk;  // a's distance from the surface; tangential
  };
  constexpr int IDX = D;  // the candidates' store indices, bit-cast (after the positions)
  const float w = 1.0f + 1.0e-3f;  // the float test's relative widening
  const BackupTest test{float(reach * reach) * w, float(dx * dx) * w, float(s0) * w, float(dx) * 1.0e-3f};
  const auto index = column(IDX, 0.0f, [](std::size_t j) { return std::bit_cast<float>(static_cast<std::uint32_t>(j)); });
  sweep_cells<float>(
      cells, D + 1, 16,
      [&](std::size_t cell) {  // the first-layer walls of a cell with fluid within reach
        std::size_t m = 0;
        if (near_[cell])
          for (std::uint32_t k = cells.cell_begin(cell); k < cells.cell_end(cell); ++k) m += first_layer(sorted[k]) ? 1 : 0;
        return m;
      },
      [&](std::size_t cell, const CellStencil<D>& st, ScratchColumns<float>& B) {
        const std::uint32_t c0k = cells.cell_begin(cell), c1k = cells.cell_end(cell);
        const Vec<D> origin = P.pos[sorted[c0k]];
        // each part pushes its own fluid
        const std::size_t nf = gather_if(st, B, P.pos.data(), origin, 16,
                                         [&](std::uint32_t j) { return j < n && P.kind[j] == Kind::Fluid; }, index);
        for (std::uint32_t kk = c0k; kk < c1k; ++kk) {
          const std::size_t k = sorted[kk];
          if (!first_layer(k)) continue;
          const double depth = std::sqrt(dot(to[k], to[k]));
          float xk[3] = {0, 0, 0}, nk[3] = {0, 0, 0};
          for (int d = 0; d < D; ++d) { xk[d] = float(P.pos[k][d] - origin[d]); nk[d] = float(to[k][d] / depth); }
          backup_candidates<D>(B, xk, nk, float(depth), test, nf, [&](std::size_t m) {
            const std::uint32_t j = std::bit_cast<std::uint32_t>(B[IDX][m]);
            if (!hit(j, k)) return;
#pragma omp critical(sphflume_wall_backup)
            hits_.emplace_back(j, static_cast<std::uint32_t>(k));
          });
        }
        return std::uint64_t(0);
      },
      reach);
  if (hits_.empty()) return;
  std::sort(hits_.begin(), hits_.end());
  apply_backup(S);
}

template <int D>
void WallModel<D>::apply_backup(System<D>& S) const {
  auto& P = S.particles;
  const auto& to = P.vector(field::wall_to_surface);
  const double dx = S.dx, c0 = S.eos.c0, h = S.h, pi = std::acos(-1.0);
  const double b1 = cfg.beta1 * c0 * c0, b2 = cfg.beta2 * c0;
  const double* lv = S.levels > 0 ? P.scalar(field::level).data() : nullptr;  // (as add_backup: wall k's level)
  for (const auto& [j, k] : hits_) {
    const int l = lv ? static_cast<int>(lv[k]) : 0;
    const double dxk = level_h(dx, l), hk = level_h(h, l), s0 = 0.25 * dxk;  // (l = 0: dx and h exactly)
    const std::size_t a = j;  // (owned: every part pushes its own fluid, from its walls and its images' walls)
    const double depth = std::sqrt(dot(to[k], to[k]));
    const Vec<D> nk = (1.0 / depth) * to[k];
    const Vec<D> r = P.pos[j] - P.pos[k];
    const double rn = dot(r, nk);
    const double sd = rn - depth;  // signed distance of a from the surface (positive: fluid side)
    const double rt = std::sqrt(std::max(0.0, dot(r, r) - rn * rn));
    const double approach = -dot(P.vel[a] - P.vel[k], nk);
    const double A = std::max(0.0, b1 + b2 * approach) / hk;
    const double q = 1.0 - sd / s0;  // 0 at s0, 1 on the surface, > 1 past it
    P.acc[a] += (A * q * q * 0.5 * (1.0 + std::cos(pi * rt / dxk))) * nk;
  }
}

template class WallModel<2>;
template class WallModel<3>;

template <int D>
Registry<WallModel<D>, const WallConfig&>& wall_registry() {
  static Registry<WallModel<D>, const WallConfig&> r = [] {
    Registry<WallModel<D>, const WallConfig&> reg;
    reg.add("dummy", [](const WallConfig& c) { return std::make_unique<DummyWalls<D>>(c); });
    reg.add("dynamic", [](const WallConfig& c) { return std::make_unique<DynamicWalls<D>>(c); });
    reg.add("fixed_ghost", [](const WallConfig& c) { return make_fixed_ghost_walls<D>(c); });
    reg.add("repulsive", [](const WallConfig& c) { return std::make_unique<RepulsiveWalls<D>>(c); });
    return reg;
  }();
  return r;
}

template Registry<WallModel<2>, const WallConfig&>& wall_registry<2>();
template Registry<WallModel<3>, const WallConfig&>& wall_registry<3>();

}  // namespace sph
