// Weakly-compressible SPH (the theses' WCSPH, Federico ch. 3, Kazemi §3.1 and §5.1):
//  continuity  Dρa/Dt = ρa Σ (ua-ub)·∇aW Vb  + δ-SPH diffusion (Molteni–Colagrossi, or
//              Fourtakas et al. 2019 with the hydrostatic part removed)
//  momentum    Dua/Dt = -Σ mb (pa+pb)/(ρaρb) ∇aW   [or pa/ρa²+pb/ρb²]
//              + Lo & Shao laminar viscosity Σ mb 4ν (rab·∇aW)/((ρa+ρb)(r²+η²)) uab
//                or Monaghan artificial viscosity, + g + registered force terms
//  Tait or linear EOS; XSPH; Shepard filter every N steps;
//  porous media (S.porous): the SPHAM equations of Kazemi eqs 4.56-4.57 on intrinsic ρ, u, p with
//              volumes m/(φρ), and the closure's drag integrated point-implicitly
//              (physics/porous.hpp); with φ = 1 every term is the plain one;
//  time integration:
//   symplectic           position-Verlet as in DualSPHysics: rates at t^n and t^{n+1/2}
//                        (two neighbour passes per step), second order;
//   predictor_corrector  Monaghan (1989) as in SPHysics / Kazemi (two passes);
//   verlet               DualSPHysics' Verlet: one pass per step, an Euler step every
//                        verlet_steps steps.
//  (`integrator: dual`, the Riemann-solver scheme with dual-criteria time stepping, is a
//  scheme of its own: schemes/dual.hpp.)
//  The pair loops are branch-free over each cell range (optional terms scaled by 0/1
//  factors) so that the compiler vectorises them; the store is re-sorted by cell before every
//  pass, so without images the ranges index the particle arrays directly.
#pragma once
#include <memory>
#include <vector>

#include "sphflume/physics/shifting.hpp"
#include "sphflume/physics/turbulence.hpp"
#include "sphflume/schemes/multirate.hpp"
#include "sphflume/schemes/scheme.hpp"

namespace sph {

template <int D>
class WCSPH final : public Scheme<D> {
 public:
  /// With `resolution.multirate` it composes the multirate integrator (schemes/multirate.hpp).
  explicit WCSPH(const Case& c) : WCSPH(c.scheme, c.turbulence) {
    if (c.resolution.on() && c.resolution.multirate) multirate_ = std::make_unique<MultirateIntegrator<D>>(cfg_.xsph > 0.0);
  }
  /// From the plain configurations; `cfg.pressure = false` makes rates() the force pass of a
  /// projection scheme (gravity, viscosity, turbulence, walls, force terms, porous drag rate).
  WCSPH(const SchemeConfig& cfg, const TurbulenceConfig& turb) : cfg_(cfg), turb_(turb), shift_(cfg.shifting) {}
  const char* name() const override { return "wcsph"; }
  const char* integrator() const override {
    switch (cfg_.integrator) {
      case Integrator::Verlet: return "verlet";
      case Integrator::Symplectic: return "symplectic";
      case Integrator::PredictorCorrector: return "predictor_corrector";
      case Integrator::Dual: break;  // (schemes/dual.hpp)
    }
    return "?";
  }
  void initialise(System<D>& S) override;
  double time_step(const System<D>& S) const override;
  void step(System<D>& S, double dt) override;
  int passes_per_step() const override { return cfg_.integrator == Integrator::Verlet && !cfg_.frozen ? 1 : 2; }
  // the packed columns of the rates pass and the half-stencil sweep's wall counts
  std::size_t bytes() const override { return pack_.capacity() * sizeof(float) + walls_before_.capacity() * sizeof(std::uint32_t); }
  std::map<std::string, double> state() const override {
    return {{"max_acc", max_acc_}, {"verlet_started", verlet_started_ ? 1.0 : 0.0}, {"nu_t_max", turb_.nu_t_max()}};
  }
  void restore(const std::map<std::string, double>& s) override {
    if (auto it = s.find("max_acc"); it != s.end()) max_acc_ = it->second;
    if (auto it = s.find("nu_t_max"); it != s.end()) turb_.restore_nu_t_max(it->second);
    if (auto it = s.find("verlet_started"); it != s.end()) verlet_started_ = it->second != 0.0;
  }

  /// One rates pass: fills acc and drho of owned particles (exposed for tests).
  void rates(System<D>& S) { rates_pass(S, false); }

 private:
  /// A rates pass; fast_only: the multirate integrator's pass of its fast particles (store field "_fast" != 0),
  /// the others keeping their rates. smooth_h: resolution levels' h set at the particles' places first (the
  /// multirate integrator sets it once per step itself and passes false).
  void rates_pass(System<D>& S, bool fast_only, bool smooth_h = true);
  /// fast: the fast particles' flags of a fast-only pass (null: every particle).
  template <class K>
  void pair_loop(System<D>& S, const K& kernel, const double* fast);
  template <class K, bool Xsph, bool Turb, bool Porous, bool Multi, bool Press = true, bool VarH = false>
  void sweep(System<D>& S, const K& kernel, const double* fast);
  /// The same pass visiting each fluid pair once (half stencils, wcsph_rates_half.cpp): the plain terms, on one grid
  /// or on one cell grid per level (per-pair h: VarH).
  void half_sweep(System<D>& S);
  template <class K, bool Xsph, bool VarH>
  void sweep_once(System<D>& S, const K& kernel);
  void frozen_step(System<D>& S, double dt);
  void verlet_step(System<D>& S, double dt);
  void two_stage_step(System<D>& S, double dt);
  void shepard_filter(System<D>& S) const;

  SchemeConfig cfg_;
  Turbulence<D> turb_;
  Shifting<D> shift_;
  bool verlet_started_ = false;
  std::unique_ptr<MultirateIntegrator<D>> multirate_;  // resolution.multirate (null: the integrator above)
  double max_acc_ = 0.0;
  std::vector<float> pack_;  // the per-particle columns of the rates pass (wcsph_rates.cpp)
  std::vector<std::uint32_t> walls_before_;  // the half-stencil sweep's count of walls before each store entry
  // a multirate fast pass: the slow particles' rates of their stage, put back after the pass (wcsph_rates.cpp)
  struct Kept {
    std::vector<Vec<D>> acc, xs;
    std::vector<double> drho, kr, im;
  } kept_;
};

}  // namespace sph
