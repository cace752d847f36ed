// The output and checkpoint policy of a run (sim/output.hpp).
#include "sphflume/sim/output.hpp"

#include <chrono>
#include <filesystem>
#include <fstream>
#include <limits>
#include <numbers>

#include <fmt/format.h>

#include "sphflume/sim/ranks.hpp"
#include "sphflume/sim/summary.hpp"

namespace sph {
namespace fs = std::filesystem;
template <int D>
void write_wave_components(const WallMotion<D>& m, const std::string& dir);
namespace {

/// The output folder must be writable before anything is computed.
const std::string& writable_folder(const RunOptions& o) {
  std::error_code ec;
  fs::create_directories(o.output, ec);
  const std::string probe = o.output + "/.sphflume_write_test";
  {
    std::ofstream t(probe);
    if (ec || !t) throw InputError(fmt::format("output folder '{}' is not writable: {} (choose another with --output)", o.output, ec ? ec.message() : "cannot create files there"));
  }
  fs::remove(probe, ec);
  return o.output;
}

/// After a failure at step good_step + 1: write the state of step good_step as the last
/// snapshot. Runs are deterministic, so it is recomputed from the last restart point (or the
/// start) rather than kept in memory at every step. Returns its path ("" when impossible).
template <int D>
std::string recompute_last_good(const Case& c, SnapshotWriter<D>& snaps, const std::string& restart_point, long good_step,
                            long last_snapshot_step) {
  if (last_snapshot_step == good_step) return snaps.last_path();
  try {
    fmt::print(stderr, "recomputing step {} from {} to write the last good state\n", good_step,
               restart_point.empty() ? std::string("the initial state") : restart_point);
    Run<D> R(c);
    if (restart_point.empty()) R.start_fresh();
    else R.load(restart_point);
    double dt = 0.0;
    while (R.S.step < good_step) R.advance(dt);
    R.S.update_neighbours();
    const RunState st = R.state();
    return snaps.write(R.S.particles, R.S.time, R.S.step, &st);
  } catch (const std::exception& e) {
    fmt::print(stderr, "could not write the last good state: {}\n", e.what());
    return snaps.last_path();
  }
}

}  // namespace

template <int D>
RunOutput<D>::RunOutput(const Case& c, const RunOptions& o, Run<D>& R, std::shared_ptr<const Communicator> comm)
    : c_(c), o_(o), R_(R), comm_(comm), distributed_(comm->size() > 1),
      snaps_(writable_folder(o), comm),  // (distributed: the ranks write together where HDF5 has MPI-IO)
      restart_point_(o.restart), checkpoint_(o.output + "/checkpoint.h5") {
  std::error_code ec;
  if (!o.restart.empty()) {
    fs::path dir = fs::absolute(o.restart).parent_path();
    if (dir.filename() == "snapshots") dir = dir.parent_path();
    resume_ = fs::equivalent(dir, o.output, ec);
  }
  if (!o.write_output) return;
  if (resume_) snaps_.resume(R.rs.snapshots);  // later snapshots of the interrupted run go
  else if (comm->root() && fs::exists(o.output + "/snapshots"))  // a re-run must not leave an earlier run's snapshots behind
    for (const auto& e : fs::directory_iterator(o.output + "/snapshots", ec))
      if (e.path().extension() == ".h5" || e.path().extension() == ".tmp") fs::remove(e.path(), ec);
  gauges_ = std::make_unique<GaugeSet<D>>(c.gauges, o.output, R.hi[D - 1],
                                          resume_ ? R.S.time : std::numeric_limits<double>::quiet_NaN(), comm->root());
  if (R.S.motion && comm->root()) write_wave_components(*R.S.motion, o.output + "/motions");
}

/// motions/NAME.components.csv for every motion made of linear components (irregular, focused,
/// elevation): what sea the paddle makes, for the analysis (its target at any gauge).
template <int D>
void write_wave_components(const WallMotion<D>& m, const std::string& dir) {
  for (std::size_t k = 0; k < m.size(); ++k) {
    const auto comps = m.law(k).components();
    if (comps.empty()) continue;
    std::error_code ec;
    fs::create_directories(dir, ec);
    const std::string path = dir + "/" + m.name(k) + ".components.csv";
    std::ofstream f(path);
    if (!f) throw IoError(fmt::format("cannot write '{}' (is the output folder writable?)", path));
    f << "# motion '" << m.name(k) << "': eta(x, t) = sum of amplitude cos(2 pi frequency (t - start) + phase - wave_number x), "
      << "x from the paddle's rest face, start = " << fmt::format("{}", m.start(k)) << " s (docs/numerics.md §15)\n";
    f << "frequency,amplitude,wave_number,phase\n";
    for (const auto& w : comps)
      f << fmt::format("{:.17g},{:.17g},{:.17g},{:.17g}\n", w.omega / (2.0 * std::numbers::pi), w.amplitude, w.k, w.phase);
  }
}

template <int D>
RunState RunOutput<D>::global_state() const {
  const System<D>& S = R_.S;
  RunState st = R_.state();
  if (distributed_) {
    const Totals<D> tot(S, R_.rs);
    st.removed_mass = tot.removed_mass;
    st.removed_by_face = tot.removed_by_face;
    st.removed_mass_by_face = tot.removed_mass_by_face;
    st.open.inflow_mass = tot.inflow;
    st.open.outflow_mass = tot.outflow;
    st.open.backflow_mass = tot.backflow_mass;
    st.open.backflow = static_cast<long>(tot.backflow);
    // the scheme's state over the ranks: its largest acceleration and eddy viscosity (the
    // others are the same on every rank); pollutant source masses add up
    for (auto& [k, v] : st.scheme) v = k.rfind("source_mass.", 0) == 0 ? comm_->sum(v) : comm_->max(v);
  }
  return st;
}

// snapshots and checkpoints of a distributed run: every rank writes its particles into the same
// files together (parallel HDF5); with an HDF5 without MPI-IO, every rank's particles are
// gathered on the first, which writes the same files as one process (sim/ranks.hpp)
template <int D>
void RunOutput<D>::write_snapshot() {
  System<D>& S = R_.S;
  const auto t0 = std::chrono::steady_clock::now();
  const RunState st = global_state();
  if (!distributed_ || snaps_.collective()) {
    snaps_.write(S.particles, S.time, S.step, &st);
  } else {
    gather_particles(S, gathered_);
    if (comm_->root()) snaps_.write(gathered_, S.time, S.step, &st);
    gathered_ = ParticleStore<D>();
  }
  snapshot_seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

template <int D>
void RunOutput<D>::output(bool always) {
  if (!o_.write_output) return;
  System<D>& S = R_.S;
  S.update_neighbours();
  // snapshots at every snapshot_every-th output time (and the first and last); gauges at each
  const long k = std::lround(S.time / c_.output_interval);
  const bool snap = always || c_.snapshot_every <= 1 || k % c_.snapshot_every == 0 || S.time >= c_.t_end * (1.0 - 1e-12);
  if (R_.open.any()) {  // (the boundary_volume gauge's cumulative masses, summed over the ranks)
    const Totals<D> tot(S, R_.rs);
    S.counters["inflow_mass"] = tot.inflow;
    S.counters["outflow_mass"] = tot.outflow;
    S.counters["backflow_mass"] = tot.backflow_mass;
  }
  {  // the mass that left the domain through each face (summed over the ranks): the overtopping gauge's
    static constexpr const char* faces[6] = {"x-", "x+", "y-", "y+", "z-", "z+"};
    double m[6];
    for (int f = 0; f < 6; ++f) {
      const auto it = R_.rs.removed_mass_by_face.find(faces[f]);
      m[f] = it == R_.rs.removed_mass_by_face.end() ? 0.0 : it->second;
    }
    S.comm->sum(m, 6);
    for (int f = 0; f < 6; ++f) S.counters[std::string("removed_mass.") + faces[f]] = m[f];
  }
  if (S.transport)
    for (std::size_t q = 0; q < S.transport->count(); ++q)  // (summed over the ranks)
      S.counters["source_mass." + S.transport->name(q)] = S.comm->sum(S.transport->source_mass(q));
  // the gauges' rows before the snapshot: a run killed between the two leaves a snapshot only
  // where its rows are on disk (a restart keeps the rows up to its snapshot's time and writes
  // none at that time; robustness_restart saw the row at the restart time lost the other way)
  gauges_->sample(S);
  if (snap) write_snapshot();
  if (snap) {
    last_snapshot_step_ = S.step;
    restart_point_ = snaps_.last_path();
  }
}

template <int D>
void RunOutput<D>::tick() {
  // windowed pressure sensors sample after every step (on the neighbour lists of the last pass)
  if (o_.write_output && gauges_->needs_tick()) gauges_->tick(R_.S);
}

template <int D>
void RunOutput<D>::write_checkpoint() {
  System<D>& S = R_.S;
  RunState st = global_state();
  st.snapshots = snaps_.entries();
  if (!distributed_ || snaps_.collective()) {
    snaps_.write_checkpoint(checkpoint_, S.particles, st);
    return;
  }
  gather_particles(S, gathered_);
  if (comm_->root()) snaps_.write_checkpoint(checkpoint_, gathered_, st);
  gathered_ = ParticleStore<D>();
}

template <int D>
std::string RunOutput<D>::write_last_good(long good_step) {
  return recompute_last_good<D>(c_, snaps_, restart_point_, good_step, last_snapshot_step_);
}

template class RunOutput<2>;
template class RunOutput<3>;

}  // namespace sph
