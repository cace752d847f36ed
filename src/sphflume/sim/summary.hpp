// The end of a run (sim/, internal): the totals over the ranks, summary.json (the output contract,
// docs/output.md) and the report printed on the console.
#pragma once
#include <cstdint>
#include <map>
#include <string>

#include "sphflume/sim/run.hpp"
#include "sphflume/sim/simulation.hpp"

namespace sph {

struct Summary {
  std::string status, message, last_good, restarted_from;
  double last_dt = 0.0;
  std::size_t snapshots = 0;
  double wall = 0.0;
  double cpu = 0.0;  // the first rank's CPU time in the time loop (every thread)
  double snapshot_seconds = 0.0;  // of wall: writing snapshots
  std::string snapshot_writes = "one process";  // distributed: "collective" (parallel HDF5) or "gathered"
};

/// Global sums of what each rank counted (the same values in one process).
template <int D>
struct Totals {
  std::uint64_t kind[kKindCount]{};
  double removed_mass = 0.0, inflow = 0.0, outflow = 0.0, backflow_mass = 0.0, final_mass = 0.0;
  std::uint64_t backflow = 0;
  std::map<std::string, long> removed_by_face;
  std::map<std::string, double> removed_mass_by_face;
  Totals(const System<D>& S, const RunState& rs) {
    for (int k = 0; k < kKindCount; ++k) kind[k] = S.particles.count(static_cast<Kind>(k));
    S.comm->sum(kind, kKindCount);
    double m[5] = {rs.removed_mass, rs.open.inflow_mass, rs.open.outflow_mass, rs.open.backflow_mass, S.total_mass(Kind::Fluid)};
    S.comm->sum(m, 5);
    removed_mass = m[0]; inflow = m[1]; outflow = m[2]; backflow_mass = m[3]; final_mass = m[4];
    backflow = S.comm->sum(static_cast<std::uint64_t>(rs.open.backflow));
    for (const char* f : {"x-", "x+", "y-", "y+", "z-", "z+"}) {
      auto it = rs.removed_by_face.find(f);
      const std::uint64_t n = S.comm->sum(static_cast<std::uint64_t>(it == rs.removed_by_face.end() ? 0 : it->second));
      if (n > 0) removed_by_face[f] = static_cast<long>(n);
      auto im = rs.removed_mass_by_face.find(f);
      const double mf = S.comm->sum(im == rs.removed_mass_by_face.end() ? 0.0 : im->second);
      if (n > 0) removed_mass_by_face[f] = mf;
    }
  }
  std::uint64_t operator[](Kind k) const { return kind[static_cast<int>(k)]; }
};

/// What the step loop counted in this process (summed over the ranks by finish_result).
struct LoopCounters {
  long steps = 0;
  double particle_steps = 0.0, fluid_particle_steps = 0.0;
  std::uint64_t pairs = 0;
};

/// The run's result from the loop's counters: totals over the ranks, throughput, bytes per
/// particle, the mass balance.
template <int D>
void finish_result(const Run<D>& R, LoopCounters n, double wall, RunResult& res);

/// Every rank calls it (the totals are reductions); the first rank writes OUTPUT/summary.json.
template <int D>
void write_summary(const RunOptions& o, const Case& c, const Run<D>& R, const Summary& sm, const RunResult& res);

/// The first rank prints the run's totals (and a failure); the others only their own failure.
template <int D>
void print_report(const RunOptions& o, const Run<D>& R, const RunResult& res, const std::string& failure,
                  const std::string& last_good);

}  // namespace sph
