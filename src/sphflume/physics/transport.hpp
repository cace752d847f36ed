// Transported scalars (Federico ch. 4, eqs 4.1-4.15, and ch. 9): concentrations,
// temperatures, ... carried by the particles, each with its diffusivity, an optional first-order
// reaction, and boundary conditions.
//
// State and conservation. A scalar C is a concentration per volume (kg/m³). The particles carry
// C, but what is integrated is the specific content Y = C/ρ, so that a particle's pollutant mass
// m Y = V C changes only by diffusion, reaction and sources:
//     ρ DY/Dt = ∇·(ρ D ∇Y) − R (C − C_eq),   i.e.  DC/Dt = ∇·(ρD∇Y) − R (C − C_eq) − C ∇·u.
// The −C∇·u part is Federico's advective correction (4.12), its u_ab (undefined in the thesis) read
// as u_b − u_a (u_a − u_b gives +C∇·u; docs/numerics.md, Errata), here exact and conservative: the
// total Σ m Y = Σ V C is conserved to round-off by every pairwise-antisymmetric operator, whatever
// the density does (compression waves, Shepard re-initialisation, two phases of different density).
//
// Diffusion operators (F_ab = r_ab·∇_a W / (r_ab² + η²) ≤ 0), selected by transport.operator:
//   consistent   Cleary–Monaghan on Y with conductivity κ = ρD (harmonic mean across jumps):
//                dY_a/dt = Σ_b m_b/(ρ_a ρ_b) 4κ_aκ_b/(κ_a+κ_b) F_ab (Y_a − Y_b)   = D∇²C for uniform ρ, D
//   federico     Federico (4.7) on C: Σ_b m_b/(ρ_aρ_b) 4D_aD_b/(D_a+D_b) (ρ_a+ρ_b) F_ab C_ab
//                = 2 D∇²C: diffuses at TWICE the rate of Fick's law (docs/numerics.md, Errata)
//   zhu_fox      (4.8): Σ_b m_a/(ρ_aρ_b) (D_aρ_a + D_bρ_b) F_ab C_ab               = D∇²C
//   tartakovsky  (4.9): Σ_b (m_b ρ_a D_a + m_a ρ_b D_b)/(ρ_aρ_b) F_ab C_ab          = D∇²C
//   monaghan     (4.10): Σ_b m_b/(ρ_aρ_b) 4D_aD_b/(D_a+D_b) F_ab C_ab              = (D/ρ)∇²C:
//                κ replaced by D, not ρD: about 1000 times too slow in SI units (docs/numerics.md, Errata)
// The thesis forms act on C; their rate is turned into dY = dC/ρ, so with uniform ρ they are
// exactly the printed equations. transport.advection: conservative (default, the −C∇·u
// correction), none (DC/Dt is the diffusion alone: C does not follow compression), or
// thesis_literal (4.12 read with u_ab = u_a − u_b: +C∇·u).
//
// Diffusivity: D = molecular + ν_t/Sc_t (turbulent_schmidt > 0 with a turbulence model).
// Reaction: − R (C − C_eq) (Federico 4.13, its ± taken as − for decay towards C_eq; R a rate in 1/s,
// since (4.14)'s R = D/δ is a velocity: docs/numerics.md, Errata).
// Boundaries: walls are no-flux (not in the sums); inflow particles carry a prescribed value
// (Dirichlet at the inlet, they take part in the sums); outflow particles keep the value they
// had; wall regions can hold a prescribed value (those wall particles enter the sums) or
// release a prescribed flux q [kg/(m² s)] (total q × area, area = region wall particles ×
// dx^{D-1} / wall layers, shared among the fluid particles near them in proportion to
// Σ_w W_aw V_a).
// Time integration: the WCSPH integrators advance Y with the flow (explicit midpoint in the
// two-stage ones, second order; forward Euler in verlet); time step ≤ coef h²/D_max and
// ≤ 0.05/R_max.
#pragma once
#include <string>
#include <vector>

#include "sphflume/core/system.hpp"
#include "sphflume/core/config.hpp"

namespace sph {

template <int D>
class ScalarTransport {
 public:
  ScalarTransport(const TransportConfig& cfg, double eta2, int wall_layers);

  const TransportConfig& config() const { return cfg_; }
  std::size_t count() const { return cfg_.scalars.size(); }
  const std::string& name(std::size_t k) const { return cfg_.scalars[k].name; }
  /// Store field holding scalar k's concentration C.
  std::vector<double>& field(System<D>& S, std::size_t k) const { return S.particles.scalar(cfg_.scalars[k].name); }

  /// Create the fields, set the initial values and mark the source walls.
  void initialise(System<D>& S) const;
  /// dY/dt of every owned particle (index order of the current sort; valid until the next).
  /// Needs the cell list and images up to date, and the scheme's drho (advection variants).
  void rates(System<D>& S);
  /// Save Y = C/ρ of the start of the step.
  void begin_step(System<D>& S) const;
  /// C = ρ (Y_start + step · dY/dt) for fluid particles; `final` (the step's last stage)
  /// accumulates the sources' mass.
  void advance(System<D>& S, double step, bool final);
  /// Before the density of fluid particles is replaced by rho_new (Shepard filter): keep Y.
  void rescale(System<D>& S, const std::vector<double>& rho_new) const;
  /// Stable time step of the scalars (infinity without diffusion and reaction).
  double time_step(const System<D>& S, double viscous_coefficient) const;
  /// Reset the imposed values (inflow particles, Dirichlet walls).
  void impose(System<D>& S) const;
  /// Cumulative mass released by the sources of scalar k.
  double source_mass(std::size_t k) const { return source_mass_[k]; }
  std::vector<double> source_masses() const { return source_mass_; }
  void restore_source_masses(const std::vector<double>& m) { if (m.size() == source_mass_.size()) source_mass_ = m; }

 private:
  template <class K>
  void rates_kernel(System<D>& S, const K& ker);

  TransportConfig cfg_;
  double eta2_;
  int layers_;
  std::vector<std::vector<double>> rate_;     // per scalar, per owned particle: dY/dt
  std::vector<double> source_rate_;           // per scalar: source mass per second of the last pass
  std::vector<double> source_mass_;           // per scalar: cumulative
  std::vector<double> from_walls_;            // per owned particle: m_a × its pair sum's part from source walls
};

}  // namespace sph
