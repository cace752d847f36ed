// Incompressible SPH on the projection the robust codes share (`scheme.formulation: lind`; Tsurudome's,
// schemes/isph.hpp, stays the default of `scheme.type: isph` until this one passes every validation): Lind, Xu,
// Stansby & Rogers (2012, J. Comput. Phys. 231), Skillen, Lind, Stansby & Rogers (2013, CMAME 265), as the ISPH of
// the DualSPHysics family builds it (Chow, Rogers, Lind & Stansby 2018, Comput. Phys. Commun. 226), with the
// changes measured in docs/numerics.md §13b. One step from (r_n, u_n):
//  1. prediction at r_n: u* = u_n + Δt (a − g), a the weakly-compressible pair loop with the pressure off
//     (viscosity, force terms; a porous drag point-implicit), r* = r_n + Δt u_n;
//  2. at r*: the kernel-gradient correction L_i = [Σ_j V_j r_ji ⊗ ∇_iW_ij]⁻¹ (fluid and wet wall
//     neighbours, eigenvalues held from below), ∇·r_i = tr of the same sum, ∇C_i; free surface where
//     ∇·r < 1.5 (2D) / 2.4 (3D), this ∇·r taken with h_d = min(h, 1.5 × the particle's spacing) (the lattice's
//     first two rows stay apart at h = 2 dx); the neighbours, their kernel factors and the walls within dx kept
//     for 4 and 5;
//  3. walls: a wall near the fluid is an unknown, P_b = Σ_j w_j P_j + ρ0 (g − a_w)·(r_b − r_m), w_j the linear
//     MLS weights of the fluid at the mirror point r_m across the wall surface (Adami's extrapolation around the
//     wall particle where r_m lies inside another solid, or in the air with the wall under its fluid: then the
//     offset's part along the wall's normal), or in the air (P = 0, out of the sums);
//  4. the PPE: the first-order corrected Laplacian = (ρ0/Δt) Σ_j V_j (u*_j − u*_i)·L_i∇W_ij (a divergence-free
//     source only) inside; P + (dx/2) n·∇P = 0 on surface particles (P = 0 at the surface), blended into the
//     interior's row over ∇·r ∈ [1.5, 1.5 + blend] (the band ending below the lattice's second row); solved by a
//     PressureSolver from the last pressures;
//  5. correction u_{n+1} = u* + Δt (g − L_i Σ_j V_j (P_j − P_i) ∇W_ij/ρ0) for every fluid particle, no flow
//     or displacement into a wall, r_{n+1} = r_n + Δt (u_n + u_{n+1})/2, then shifting (Skillen's
//     velocity-scaled form by default, from the moments' ∇C; Lind's constant D with `form: constant`).
// V_j = m_j/(φ_j ρ0): the density is ρ0 throughout (porous media: the intrinsic one).
#pragma once
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "sphflume/core/config.hpp"
#include "sphflume/physics/shifting.hpp"
#include "sphflume/schemes/isph_common.hpp"
#include "sphflume/schemes/pressure_solver.hpp"
#include "sphflume/schemes/scheme.hpp"
#include "sphflume/schemes/wcsph.hpp"

namespace sph {
namespace projection_detail {
struct MomentCols;
struct MomentSums;
}

template <int D>
class ProjectionISPH final : public Scheme<D> {
 public:
  explicit ProjectionISPH(const Case& c);
  const char* name() const override { return "isph"; }
  const char* integrator() const override { return "projection"; }
  bool density_bounded_below() const override { return false; }
  bool needs_wall_surface() const override { return true; }  // the mirror points
  std::string distributed_refusal() const override { return isph_distributed_refusal(o_); }
  void initialise(System<D>& S) override;
  double time_step(const System<D>& S) const override { return isph_time_step(S, o_, amax_); }
  void step(System<D>& S, double dt) override;
  int passes_per_step() const override { return 4; }  // forces; moments + walls; PPE; gradient (+ shifting)
  std::size_t bytes() const override;
  std::map<std::string, double> state() const override;
  void restore(const std::map<std::string, double>& s) override;
  void summary(nlohmann::ordered_json& j) const override;
  /// A short sliver before an output disturbs the scheme (its shift is per step): the driver evens the last steps.
  bool even_steps() const override { return true; }
  const char* failure_causes() const override { return isph_failure_causes(); }

  const PpeStats& stats() const { return stats_; }
  /// Steps 2-4 at the current positions (exposed for tests: a still tank's pressure).
  void solve_pressure(System<D>& S, double dt);
  /// The corrected gradient's matrix L_i of owned particle i (D×D, row-major) and its ∇·r, after solve_pressure.
  const double* correction(std::size_t i) const { return &L_[i * D * D]; }
  double divergence_of_position(std::size_t i) const { return divr_[i]; }

 private:
  template <class K> void moments(System<D>& S, const K& ker);
  /// The moments' per-particle steps after its vector loop: its neighbours kept (F, V, c_ij), the first-layer walls.
  void keep_neighbours(std::size_t i, int tid, std::size_t cnt, const projection_detail::MomentCols& b, const double* idx);
  void first_layer_walls(const System<D>& S, std::size_t i, std::size_t cnt, const double* wall1, const double* idx);
  void store_moments(std::size_t i, const projection_detail::MomentSums& sm, double lmin, double thr);
  template <class K> void wall_rows(System<D>& S, const K& ker);
  /// Wall b's row by Adami's extrapolation from the fluid around it (weights and lever into mls_[b], lever_[b]);
  /// with `mirror_in_air` (its mirror point in the air, not inside another solid) it is Known unless it lies under
  /// that fluid, and then takes the offset's part along its normal.
  template <class K> void adami_row(const System<D>& S, const K& ker, std::size_t b, bool mirror_in_air);
  template <class K> void assemble(System<D>& S, const K& ker, double dt);
  /// The surface's Robin row P + (dx/2) n·∇P = 0 of particle i, times −weight × the lattice diagonal, into e
  /// (its diagonal returned); the interior row (the corrected Laplacian, the blend, the source) into e, its
  /// right-hand side returned.
  template <class K>
  double robin_entries(const System<D>& S, const K& ker, std::size_t i, int me, double weight,
                       std::vector<std::pair<int, double>>& e) const;
  template <class K>
  double inner_row(const System<D>& S, const K& ker, std::size_t i, int me, double dt,
                   std::vector<std::pair<int, double>>& e) const;
  template <class K> void correct(System<D>& S, const K& ker, double dt);
  void number_unknowns(System<D>& S);
  /// The lattice's constants: the wall rows' weight, the full support's Σ V W, the blend band.
  void constants(const System<D>& S);

  IsphConfig o_;
  WCSPH<D> forces_;
  Shifting<D> shift_;
  IsphSolver solver_;
  double amax_ = 0.0;
  double wall_scale_ = 1.0;  // a wall row's weight: the lattice's Laplacian diagonal (rows of one size)
  PpeStats stats_;
  // per owned particle: its class in the PPE, its row, L (D×D), ∇·r, ∇C (the surface's normal); per
  // particle incl. images: the PPE column (-1: a known zero pressure), the flag "in the sums" (walls)
  enum Cls : char {
    Inner = 0,    // a fluid unknown: the Laplacian row
    Known = 1,    // P = 0 (a surface particle with `condition: particles`, a wall in the air)
    WallRow = 2,  // a wall unknown: its mirror point's interpolated pressure plus the body-force offset
    Out = 3,      // no fluid within reach: out of the sums
    Surface = 4,  // a surface particle with `condition: surface`: P + (dx/2) n·∇P = 0
  };
  static bool unknown(char c) { return c == Inner || c == WallRow || c == Surface; }
  std::vector<char> cls_;
  std::vector<double> gc_, conc_;  // conc_: Σ_j V_j W_ij (the particle's number density × its volume)
  double conc_ref_ = 1.0;  // the same on a full lattice
  double blend_ = 0.0;  // the surface's blend band's width in ∇·r (initialise: `blend`, ending below the second row)
  // the free surface is found with a kernel of smoothing length h_d = min(h, 1.5 s_i), s_i = (m_i/(φ_i ρ0))^(1/D) the
  // particle's spacing (dx outside a porous medium): its ∇·r keeps the lattice's first and second rows 0.58 apart
  // (1.24 / 1.82) where h = 2 dx would put them 0.44 apart with the second row only 0.13 above the threshold
  // (docs/numerics.md §13b)
  double detect_h_ = 0.0;  // 1.5 dx where h is larger (the blend band's lattice), else h
  bool detect_ = false;    // h > 1.5 dx: some particles take the detection kernel's ∇·r
  std::vector<std::vector<std::pair<std::uint32_t, double>>> mls_;  // a wall row's weights (MLS at its mirror point, or Adami's)
  std::vector<Vec<D>> lever_;  // a wall row's offset ρ0 (g − a_w)·lever: r_b − r_m, or Adami's Σ w (r_b − r_f)
  std::vector<Vec<D>> ub_;     // a wet wall's velocity in the divergence (per particle incl. images)
  double dt_ = 0.0;            // the step being solved (wall_rows' wall velocity at t_n)
  // per owned fluid particle, D slots: the walls within dx (their normals, 0 where none, and velocities)
  std::vector<Vec<D>> wall_n_, wall_u_;
  // the moments' neighbours (fluid and wet walls) of each owned fluid particle with their kernel factor F_ij, for
  // the rows and the correction at the same positions (one neighbour search per step instead of three): per thread
  // a buffer; per particle its thread, first entry and count
  // V: m/(ρ0 φ) of the fluid, m/ρ0 of a wet wall; c: the interior row's Laplacian weight c_ij (moments())
  struct Near { std::uint32_t j; double F, V, c; };
  // one list per thread, each on its own cache lines (their headers side by side, the threads' push_backs
  // shared a line: the moments took as long on two threads as on one, perf, session 26)
  struct alignas(64) NearList { std::vector<Near> v; };
  std::vector<NearList> near_buf_;
  std::vector<std::uint32_t> near_thread_, near_first_, near_count_;
  /// f(neighbour, r_ij, r²) over particle i's cached neighbours, in the order the moments met them.
  template <class Fn>
  void for_near(const System<D>& S, std::size_t i, Fn&& f) const {
    const auto& P = S.particles;
    const Near* e = near_buf_[near_thread_[i]].v.data() + near_first_[i];
    for (std::uint32_t k = 0; k < near_count_[i]; ++k) {
      const Vec<D> r = P.pos[i] - P.pos[e[k].j];
      f(e[k], r, dot(r, r));
    }
  }
  std::vector<int> unknown_;
  std::vector<double> L_, divr_;
  // per owned fluid particle, from the moments: the Laplacian weights' first moment Σ c r_ji (D), half second
  // moment ½ Σ c r², and the corrected divergence of u* (the interior row's source)
  std::vector<double> lap_a_, lap_m2_, div_;
  std::vector<double> col_, wet_;
  std::vector<std::vector<std::pair<int, double>>> rows_;
  std::vector<double> offset_;  // a wall row's right-hand side ρ0 (g − a_w)·(r_b − r_m)
  std::size_t first_row_ = 0;
  bool stable_rows_ = false;
  mutable bool fresh_hierarchy_ = true;  // state() wrote a restart point: the next solve builds afresh
  std::vector<int> row_of_id_;
  SparseRows sys_;
  std::vector<double> x_;
};

}  // namespace sph
