// Restart points. Every snapshot (snapshots/snap_NNNNNN.h5) and every checkpoint
// (checkpoint.h5) holds, besides the fields ParaView shows, the whole state a run needs to go on
// bit for bit: every per-particle field in memory order (rates and integrator history included)
// and the run's counters, in the HDF5 group /restart:
//   /restart/acc, /restart/drho, /restart/vector_NAME (N x D), /restart/scalar_NAME (N)
//   /restart/case            the case (after --set) as canonical text, to refuse a different case
//   /restart/counters        name=value lines: time, step, next_output, dt_first, masses, ...
//   /restart/snapshot_index  one line per snapshot written before: file, time, count, scalars
// `sphflume run CASE --restart FILE` reads it back (read_restart).
#pragma once
#include <map>
#include <string>
#include <vector>


#include "sphflume/boundaries/open_boundary.hpp"
#include "sphflume/core/particles.hpp"

namespace sph {

/// One entry of the snapshot time series (what particles.xdmf lists).
struct SnapshotEntry {
  std::string file;  // relative to the output folder
  double time = 0.0;
  std::size_t n = 0;
  std::vector<std::string> scalars;  // extra per-particle scalar fields
};

/// The run's counters, besides the particles: what a restart restores.
struct RunState {
  double time = 0.0;
  long step = 0;
  double next_output = 0.0;   // the next output time
  double dt_first = 0.0;      // the first time step (the collapse criterion is relative to it)
  double initial_mass = 0.0;  // fluid mass at t = 0 (the mass balance covers the whole run)
  double removed_mass = 0.0;
  std::map<std::string, long> removed_by_face;
  std::map<std::string, double> removed_mass_by_face;  // the same faces' masses (the overtopping gauge's lee face)
  OpenFlowCounters open;                  // inflow/outflow masses, backflow count, next particle id
  long splits = 0, merges = 0;            // resolution levels: particles split, groups merged (physics/resolution)
  std::map<std::string, double> scheme;   // the scheme's own state (Scheme::state)
  std::vector<SnapshotEntry> snapshots;   // the time series so far
  std::string case_text;                  // canonical case text (Case::fingerprint)
};


namespace h5 { struct Rows; }
/// Write the /restart group into an open HDF5 file (hid_t passed as long long); rows: this
/// rank's part of a file every rank writes together (io/h5util.hpp), null for one process.
template <int D>
void write_restart_group(long long file_id, const ParticleStore<D>& P, const RunState& rs, const std::string& path,
                         const h5::Rows* rows = nullptr);

/// Read a restart point: replaces P's particles (memory order kept) and fills rs.
/// Throws InputError naming the file when it is not a restart point of a D-dimensional run.
template <int D>
void read_restart(const std::string& path, ParticleStore<D>& P, RunState& rs);

}  // namespace sph
