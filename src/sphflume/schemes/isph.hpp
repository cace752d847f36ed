// Incompressible SPH (Tsurudome 2020, ch. 3-4; Shao & Lo 2003; Asai et al. 2012): a projection
// scheme on the particles, neighbour search, walls and force terms the weakly-compressible
// scheme uses. One step (after Tsurudome §3.2 and §4.5, Fig. 4.4):
//  1. prediction at r_t: u* = u_t + Δt (g + ν∇²u + ∇·τ/ρ + force terms), the porous drag
//     point-implicit, r* = r_t + Δt u* (the forces are WCSPH's pair loop with the pressure off:
//     one particle loop for both schemes);
//  2. at r*: summation density ρ*_i = Σ m_j W_ij; free surface where ρ* < β ρ_ref (ρ_ref: the
//     lattice sum of the kernel, so that a full support reads 1); pressure P = 0 there;
//  3. the PPE  Σ_j 8 m_j/(ρ_i+ρ_j)² P_ij r_ij·∇W/(r²+η²) = γ ∇·u*/Δt + (1−γ)(ρ_ref−ρ*)/(ρ_ref Δt²)
//     for the fluid and the first layer of wall particles; the deeper (dummy) wall particles
//     carry the pressure of the first-layer particle at their foot (homogeneous Neumann);
//     solved by a PressureSolver from the last step's pressure;
//  4. correction u_{t+1} = u* − Δt Σ m_j (P_i/ρ_i² + P_j/ρ_j²) ∇W, r_{t+1} = r_t + Δt (u_t + u_{t+1})/2.
// Time step: Δt = min(cfl dx/|u|max, coef sqrt(h/|a|max), viscous limit, dt_max).
#pragma once
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "sphflume/core/config.hpp"
#include "sphflume/schemes/isph_common.hpp"
#include "sphflume/schemes/pressure_solver.hpp"
#include "sphflume/schemes/scheme.hpp"
#include "sphflume/schemes/wcsph.hpp"

namespace sph {

template <int D>
class ISPH final : public Scheme<D> {
 public:
  explicit ISPH(const Case& c);
  const char* name() const override { return "isph"; }
  const char* integrator() const override { return "projection"; }
  // the summation density is low at the free surface by construction (a splash particle alone
  // reads m W(0)): only compression is a sign of failure
  bool density_bounded_below() const override { return false; }
  bool needs_wall_surface() const override { return true; }  // the wall pressure's Neumann condition
  std::string distributed_refusal() const override { return isph_distributed_refusal(o_); }
  void initialise(System<D>& S) override;
  double time_step(const System<D>& S) const override { return isph_time_step(S, o_, amax_); }
  void step(System<D>& S, double dt) override;
  int passes_per_step() const override { return 3; }  // forces, density + PPE, correction
  std::size_t bytes() const override;
  std::map<std::string, double> state() const override;
  void restore(const std::map<std::string, double>& s) override;
  void summary(nlohmann::ordered_json& j) const override;
  bool even_steps() const override { return true; }
  const char* failure_causes() const override { return isph_failure_causes(); }

  /// The reference density: the kernel's sum over a full lattice of spacing dx (exposed for tests).
  double reference_density() const { return rho_ref_; }
  /// −(1/D) Σ dx^D F(r) r² over the same lattice: the symmetric gradient of a linear field is κ ∇P.
  double gradient_moment() const { return kappa_; }
  const PpeStats& stats() const { return stats_; }
  /// The PPE's weight of neighbour j in row i (Tsurudome eq 3.4.53 with η²): the Laplacian
  /// ∇·(∇P/ρ)_i = Σ_j c_ij (P_j − P_i), c_ij = −8 m_j F r²/((ρ_i+ρ_j)² (r² + η²)) ≥ 0, where
  /// ∇_i W_ij = F r_ij. Exposed so that the operator is tested on a lattice (tests/test_isph.cpp,
  /// LatticeOperatorsLaplacianAndGradient).
  static double laplacian_weight(double mj, double rhoi, double rhoj, double F, double r2, double eta2) {
    const double rs = rhoi + rhoj;
    return -8.0 * mj / (rs * rs) * F * r2 / (r2 + eta2);
  }
  /// The symmetric pressure-gradient pair term (eq 3.4.51): (∇P/ρ)_i = Σ_j m_j (P_i/ρ_i² + P_j/ρ_j²) F r_ij,
  /// returned as the scalar that multiplies r_ij.
  static double gradient_weight(double mj, double pi, double rhoi, double pj, double rhoj, double F) {
    return mj * (pi / (rhoi * rhoi) + pj / (rhoj * rhoj)) * F;
  }
  /// Steps 2-4 at the current positions (r*): densities, free surface, PPE, pressures of every
  /// particle (exposed for tests: a still tank's pressure).
  void solve_pressure(System<D>& S, double dt);

 private:
  // the pair passes (schemes/isph_passes.cpp): Σ (m/φ) W into drho; the PPE's rows; u -= Δt ∇P/ρ
  template <class K> void kernel_density(System<D>& S, const K& ker);
  template <class K> void assemble(System<D>& S, const K& ker, double dt);
  template <class K> void correct(System<D>& S, const K& ker, double dt);
  void classify(System<D>& S);
  /// Solves sys_ into a per-particle field (warm start, statistics, the dummies' values); pressure: the
  /// pressure (its dummies carry their known offsets), else the split source's ψ.
  void solve_into(System<D>& S, std::vector<double>& field, bool pressure);
  void set_reference(const System<D>& S);

  IsphConfig o_;
  WCSPH<D> forces_;
  Shifting<D> shift_;
  IsphSolver solver_;
  double rho_ref_ = 0.0;
  // porous media: the reference density of a lattice of spacing dx/φ^(1/D) (the fluid inside a
  // medium of porosity φ), tabulated over φ ∈ [phi_lo_, 1] (Tsurudome §4.2.2, eq 4.2.4)
  std::vector<double> rho_ref_phi_;
  double phi_lo_ = 1.0;
  std::vector<std::pair<double, double>> rho_ref_exact_;  // (φ0, reference) of each region's own porosity
  double reference_at(double phi) const;
  double kappa_ = 1.0;  // the gradient's lattice moment
  double amax_ = 0.0;  // largest net acceleration of the last step
  PpeStats stats_;
  // per solve (indexed by owned particle): 0 unknown, 1 P = 0 (free surface or dry wall),
  // 2 dummy (P of map_[i]); unknown numbers; the system
  std::vector<char> cls_;
  std::vector<int> unknown_, map_;
  bool stable_rows_ = false;        // rows numbered by particle id (classify)
  mutable bool fresh_hierarchy_ = true;  // state() wrote a restart point: the next solve builds afresh
  std::vector<int> row_of_id_;
  std::vector<double> dummy_off_;  // dummy_pressure body_force: P_dummy − P_foot
  std::size_t first_row_ = 0;      // the global number of this rank's first unknown
  std::vector<double> col_, off_;  // per particle, images included: PPE column (-1 none), dummy offset
  SparseRows sys_;
  std::vector<std::vector<std::pair<int, double>>> rows_;  // assemble's rows (capacity kept between steps)
  std::vector<double> x_;
  std::vector<double> rhs_density_;  // source.type split: the density error's right-hand side
  static constexpr double kDensityTolerance = 1e-3;  // its solve's relative residual
};

}  // namespace sph
