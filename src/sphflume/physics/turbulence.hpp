// Eddy-viscosity turbulence closures (Kazemi §2.1, §3.1.1.2 eqs 3.6-3.8, §6.2.3 eqs 6.4-6.7).
//
//   S_ij  = (∂u_i/∂x_j + ∂u_j/∂x_i)/2,   (∂u_i/∂x_j)_a = Σ_b V_b (u_b − u_a)_i ∂W_ab/∂x_j
//   |S|   = sqrt(2 S:S)  (so that |S| = |du/dz| in a plane shear flow; Kazemi's printed
//           sqrt(S:S) is the option strain_norm: sqrt_ss)
//   ν_t   = (C_s Δ)² |S|             smagorinsky (SPS; Δ = dx unless given)
//         = l_m² |S|                 mixing_length (Kazemi's MSPH-ML) with l_m from
//           nezu_rodi   l_m = κ z_w sqrt(1 − ξ) / (1 + π Π ξ sin πξ) · F_vd,  ξ = z_w / H,
//                       z_w from the numerical bed, H from the bed to the free surface of the
//                       particle's column, F_vd = 1 − exp(−z_w⁺/A⁺) when van_driest is on
//                       (u* = sqrt(g_x H), the uniform-flow friction velocity);
//           three_layer Kazemi eq 6.7 (constant l_mb below z_0 = z_t + Δz_0, slope κ_r up to
//                       the crest z_c, then l_mc + κ_f (z − z_c) sqrt(1 − (z − z_c)/H_c));
//           constant    a given l_m.
//   τ/ρ   = 2 ν_t (S − tr(S)/3 I)   the stress, in the diffusive sign convention: the momentum
//           equation adds Σ_b m_b (τ_a/ρ_a² + τ_b/ρ_b²)·∇_a W_ab ≈ (∇·τ)/ρ.
//           (Kazemi's eq 2.14 prints the Reynolds-stress sign; used with '+' it would be
//           anti-diffusive; the isotropic part 2/3 k is left to the pressure.)
//
// The scheme's pair loop accumulates the velocity gradient of every fluid particle in the same
// pass as the other terms and uses the stress of the previous pass (one step behind, as in
// DualSPHysics' SPS), so turbulence costs no extra neighbour pass. Walls carry no modelled stress
// (τ_b = 0, as the boundary particles of SPHysics and DualSPHysics): the eddy viscosity vanishes
// at the wall (l_m = 0 at the numerical bed), the bed shear is the drag layer's and the laminar
// term's. (A wall carrying the stress of the fluid next to it was tried: it adds a bed friction
// of the first particle row's τ, ~30 % of ρ g H S0 in Kazemi's S004H50, which his model has not.)
// The stress (kinematic, τ/ρ in m²/s²) and ν_t are store fields, written to snapshots.
#pragma once
#include <string>
#include <vector>

#include "sphflume/core/system.hpp"
#include "sphflume/core/config.hpp"

namespace sph {

template <int D>
class Turbulence {
 public:
  static constexpr int kStress = D == 2 ? 3 : 6;  // independent components of the symmetric stress
  explicit Turbulence(const TurbulenceConfig& c) : cfg_(c) {}
  bool on() const { return cfg_.model != "none"; }
  const TurbulenceConfig& config() const { return cfg_; }

  /// Names of the stress store fields, in the order (xx, xz, zz) in 2D and
  /// (xx, yy, zz, xy, xz, yz) in 3D; component index pairs in stress_index().
  static const char* stress_name(int k);
  static std::pair<int, int> stress_index(int k);

  /// Gradient buffer for the pair loop: D*D doubles per owned particle, (i, j) = ∂u_i/∂x_j.
  double* gradient(std::size_t n) {
    grad_.assign(n * D * D, 0.0);
    return grad_.data();
  }
  /// After the pair loop: ν_t and the stress of every fluid-like particle from the gradient.
  void update(System<D>& S);
  /// Largest ν_t of the last update (for the viscous time-step limit).
  double nu_t_max() const { return nu_t_max_; }
  /// After a restart: the value saved with the state (the time step of the next step uses it).
  void restore_nu_t_max(double v) { nu_t_max_ = v; }

  /// Mixing length at height z (case frame) under a free surface at zs; g_x is the driving
  /// gravity component and nu the molecular viscosity (van Driest damping).
  double mixing_length(double z, double zs, double g_x, double nu) const;
  /// ν_t for the strain rate norm s (|S|) at a particle with mixing length lm (mixing_length
  /// model) or filter width delta (smagorinsky).
  double eddy_viscosity(double s, double lm, double delta) const;
  /// |S| from the velocity gradient G (row-major, G[i*D+j] = ∂u_i/∂x_j).
  double strain_norm(const double* G) const;

  /// Free-surface level of each particle's column (highest fluid particle of the column and
  /// its two neighbours, plus dx/2); exposed for tests and diagnostics.
  static std::vector<double> column_surface(const System<D>& S, double width);

 private:
  TurbulenceConfig cfg_;
  std::vector<double> grad_;
  double nu_t_max_ = 0.0;
};

}  // namespace sph
