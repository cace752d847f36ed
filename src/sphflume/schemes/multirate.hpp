// Multirate time stepping for resolution levels (`resolution.multirate: true`; docs/numerics.md §14,
// issues 42 and 58): an integrator a scheme composes (WCSPH holds one when the case asks for it) and drives
// with its own rates pass. The slow particles (every level but the finest, away from the level interface)
// take one symplectic step Δ, the fast ones (the finest level and the particles whose h the interface
// lowered) two of Δ/2; schemes/multirate.cpp has the stages.
#pragma once
#include <functional>

#include "sphflume/core/system.hpp"

namespace sph {

template <int D>
class MultirateIntegrator {
 public:
  /// The composing scheme's rates pass: every particle's (fast_only false) or the fast particles' only (the
  /// store field "_fast" != 0; the others keep the rates of their stage, and the walls are set near the fast ones).
  using RatesPass = std::function<void(System<D>&, bool fast_only)>;
  /// The composing scheme's explicit step for particles of smoothing length h.
  using StepLimit = std::function<double(double h)>;
  /// xsph: the scheme's XSPH correction is on (the stages carry it).
  explicit MultirateIntegrator(bool xsph) : xsph_(xsph) {}
  /// The step Δ: the slow particles' limit (with the next-coarser level's h) and twice the fast ones' (the finest
  /// level present's h).
  double time_step(const System<D>& S, const StepLimit& limit) const;
  /// One step Δ = dt: per Δ the rates of every particle at t and t + Δ/2, and of the fast ones also at t + Δ/4
  /// and t + 3Δ/4.
  void step(System<D>& S, double dt, const RatesPass& rates) const;

 private:
  bool xsph_;
};

}  // namespace sph
