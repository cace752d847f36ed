// The output and checkpoint policy of a run (sim/, internal): the output folder, the snapshot
// series (each snapshot a restart point), the gauges, checkpoint.h5, and the last good state after
// a failure. In a distributed run the ranks write together (parallel HDF5) or gather on the first.
#pragma once
#include <memory>
#include <string>

#include "sphflume/core/communicator.hpp"
#include "sphflume/io/gauges.hpp"
#include "sphflume/io/snapshot.hpp"
#include "sphflume/sim/run.hpp"
#include "sphflume/sim/simulation.hpp"

namespace sph {

template <int D>
class RunOutput {
 public:
  /// Checks that the output folder is writable (InputError otherwise), then opens the snapshot
  /// series: a restart into its own run folder continues it, into another folder it starts a new
  /// one (snapshot 0 = the restart state, gauges from the restart time on).
  RunOutput(const Case& c, const RunOptions& o, Run<D>& R, std::shared_ptr<const Communicator> comm);
  /// Whether this run continues the series of the run folder it restarts from.
  bool resumes() const { return resume_; }
  /// At an output time: the gauges' rows, then a snapshot every snapshot_every-th output (always:
  /// the first output).
  void output(bool always);
  /// After a step that is not an output: the windowed pressure gauges' sample.
  void tick();
  /// OUTPUT/checkpoint.h5, a restart point outside the series.
  void write_checkpoint();
  /// After a failure at step good_step + 1: the state of step good_step as the last snapshot,
  /// recomputed from the last restart point (runs are deterministic). Returns its path.
  std::string write_last_good(long good_step);
  /// The last restart point written (a snapshot or the checkpoint; the --restart file at first).
  const std::string& restart_point() const { return restart_point_; }
  void set_restart_point(const std::string& p) { restart_point_ = p; }
  const std::string& checkpoint_path() const { return checkpoint_; }
  std::size_t snapshot_count() const { return snaps_.count(); }
  /// Wall seconds spent writing snapshots (the file, the XDMF index; in a distributed run also the gather).
  double snapshot_seconds() const { return snapshot_seconds_; }
  bool collective() const { return snaps_.collective(); }

 private:
  /// The state a restart point records: in a distributed run the counters summed over the ranks.
  RunState global_state() const;
  void write_snapshot();
  const Case& c_;
  const RunOptions& o_;
  Run<D>& R_;
  std::shared_ptr<const Communicator> comm_;
  bool distributed_, resume_ = false;
  SnapshotWriter<D> snaps_;
  std::unique_ptr<GaugeSet<D>> gauges_;
  ParticleStore<D> gathered_;  // a gathered store (HDF5 without MPI-IO), empty between writes
  long last_snapshot_step_ = -1;
  double snapshot_seconds_ = 0.0;
  std::string restart_point_;
  std::string checkpoint_;
};

}  // namespace sph
