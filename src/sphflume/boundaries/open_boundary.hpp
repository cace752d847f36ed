// Open boundaries for channels: Federico's in/out-flow algorithm (thesis §5.3.1).
//
// Along the channel (flow in +x) an inflow zone [x0, x1) and an outflow zone [x0, x1) hold
// particles whose state is imposed, not integrated: they enter the fluid particles' sums like
// fluid (fluid_like), move with their own velocity, and every step
//   - an inflow particle past the zone's end becomes fluid (keeping its state), and a new inflow
//     particle takes its place one zone length upstream (same z, the imposed state): the zone
//     stays full and the spacing regular;
//   - a fluid particle entering the outflow zone becomes an outflow particle: from then on its
//     velocity is the imposed profile (or frozen at its value on entering), its density frozen;
//   - an outflow particle past the zone's end is deleted.
// Inflow particles carry the imposed profile u(z) and the hydrostatic pressure of the imposed
// depth (ρ from the EOS). The masses converted are the inflow and outflow of the mass balance;
// fluid particles that move back into the inflow zone (the algorithm assumes none; splashes of a
// hydraulic jump's roller can) would overlap the inflow lattice: they are removed and counted.
// Kazemi's variant (velocity: averaged) takes the inflow state from the fluid next to the zone
// instead, so the discharge is not imposed; outflows may be extrapolated (zero gradient) or get
// the hydrostatic pressure of the local depth (prepare()).
#pragma once
#include <cstdint>
#include <vector>

#include "sphflume/core/system.hpp"
#include "sphflume/core/config.hpp"

namespace sph {

/// u(z) of a profile, z above the bed, for a flow of the given depth.
double profile_velocity(const ProfileConfig& p, double z, double depth);

struct OpenFlowCounters {
  double inflow_mass = 0.0, outflow_mass = 0.0;
  long backflow = 0;          // fluid particles that went back into the inflow zone (removed)
  double backflow_mass = 0.0; // their mass (a term of the mass balance)
  std::uint32_t next_id = 0;  // id of the next particle created
};

template <int D>
class OpenBoundaries {
 public:
  explicit OpenBoundaries(const Case& c);
  bool any() const { return in_ || out_; }
  /// At set-up: fluid particles inside the zones become inflow/outflow particles with the
  /// imposed state; counters.next_id is set past the largest id.
  void setup(System<D>& S, OpenFlowCounters& k) const;
  /// After every step: conversions, creation and deletion. Returns true when particles were
  /// created or deleted (the store must then be re-sorted).
  bool update(System<D>& S, OpenFlowCounters& k) const;
  /// Whether prepare() has work: an averaged inflow or an extrapolated/hydrostatic outflow.
  bool needs_prepare() const;
  /// Before every rates pass (System::before_rates): averaged inflow particles take the Shepard
  /// average of the fluid's velocity and density at a node 0.5 dx downstream of the inflow zone
  /// at their height (Kazemi §3.1.4.1: du/dx = 0, dp/dx = 0 at the boundary line, the discharge
  /// emerges); extrapolated outflow particles the same at a node 0.5 dx upstream of the outflow
  /// zone; a hydrostatic outflow pressure uses the local depth there.
  void prepare(System<D>& S) const;

 private:
  /// The free surface next to the outflow zone: the highest fluid particle within dx of its
  /// face, + dx/2 (all ranks; the outflow's depth above its bed when none is there).
  double outflow_level(const System<D>& S) const;
  /// Shepard averages (found, ρ, u) over the fluid around each of the gathered nodes this part
  /// holds (D coordinates each; NaN: no node), D + 2 values per node, zero elsewhere.
  std::vector<double> node_averages(const System<D>& S, const std::vector<double>& nodes) const;
  void impose(System<D>& S, std::size_t i, const OpenBoundaryConfig& b, bool density) const;
  void impose_outflow(System<D>& S, std::size_t i) const;
  const OpenBoundaryConfig* in_ = nullptr;
  const OpenBoundaryConfig* out_ = nullptr;
  double gz_ = 9.81;  // |g| normal to the bed (the vertical component)
  double rho0_ = 1000.0, background_ = 0.0;
  double dx_ = 0.0;
};

}  // namespace sph
