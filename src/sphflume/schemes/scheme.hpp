// A scheme advances the shared System by one time step: WCSPH (schemes/wcsph.*) and ISPH
// (projection + PPE, schemes/isph.*) share particles, neighbour search, walls, force terms and
// I/O. A new scheme: a class behind this interface plus one line in schemes/registry.cpp.
#pragma once
#include <map>
#include <stdexcept>
#include <string>

#include <nlohmann/json.hpp>

#include "sphflume/core/errors.hpp"
#include "sphflume/core/registry.hpp"
#include "sphflume/core/system.hpp"
#include "sphflume/core/config.hpp"

namespace sph {

template <int D>
class Scheme {
 public:
  virtual ~Scheme() = default;
  virtual const char* name() const = 0;
  /// Compute the rates of the initial state (needed by the first time step estimate).
  virtual void initialise(System<D>& S) = 0;
  /// Largest stable time step for the current state.
  virtual double time_step(const System<D>& S) const = 0;
  /// Advance by dt.
  virtual void step(System<D>& S, double dt) = 0;
  /// The time integration, as summary.json's "integrator" names it.
  virtual const char* integrator() const = 0;
  /// False where the scheme's density may fall far below ρ0 without anything being wrong (a
  /// projection scheme's summation density at a free surface): the health check then looks for
  /// compression only.
  virtual bool density_bounded_below() const { return true; }
  /// Whether the scheme reads each wall particle's vector to its wall surface ("wall_to_surface",
  /// made at set-up): ISPH's wall pressure, the dual integrator's Riemann dissipation at walls.
  virtual bool needs_wall_surface() const { return false; }
  /// Why this scheme, as configured, cannot run over several MPI ranks (empty: it can).
  virtual std::string distributed_refusal() const { return {}; }
  /// Rates passes (neighbour sweeps) per step, for throughput accounting.
  virtual int passes_per_step() const = 0;
  /// Bytes held by the scheme itself, in total (integrator state, a pressure system and its solver): the run's
  /// bytes per particle add them to the store's, the cell list's and the walls' (sim/summary.cpp).
  virtual std::size_t bytes() const = 0;
  /// The scheme's own state beyond the particle store, by name: restart points save it and
  /// restore() puts it back, so that a restarted run goes on bit for bit.
  virtual std::map<std::string, double> state() const { return {}; }
  virtual void restore(const std::map<std::string, double>&) {}
  /// True when a step much shorter than the last one disturbs the scheme (the driver then
  /// splits the time left before an output into two equal steps instead of leaving a sliver).
  virtual bool even_steps() const { return false; }
  /// The likely causes a failed run names (a collapsing time step, a non-finite value); nullptr: the
  /// weakly-compressible ones (sound speed, time step, walls).
  virtual const char* failure_causes() const { return nullptr; }
  /// The scheme's own keys in summary.json (docs/output.md), added to `j` (none by default).
  virtual void summary(nlohmann::ordered_json& j) const { (void)j; }
};

template <int D>
Registry<Scheme<D>, const Case&>& scheme_registry();

}  // namespace sph
