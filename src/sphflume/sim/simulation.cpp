#include "sphflume/sim/simulation.hpp"

#include <signal.h>
#include <unistd.h>

#include <csignal>
#include <limits>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>

#include <fmt/format.h>
#include <nlohmann/json.hpp>
#ifdef _OPENMP
#include <omp.h>
#endif

#include "sphflume/boundaries/motion.hpp"
#include "sphflume/boundaries/open_boundary.hpp"
#include "sphflume/boundaries/walls.hpp"
#include "sphflume/io/gauges.hpp"
#include "sphflume/io/restart.hpp"
#include "sphflume/io/snapshot.hpp"
#include "sphflume/physics/force_terms.hpp"
#include "sphflume/physics/multiphase.hpp"
#include "sphflume/physics/transport.hpp"
#include "sphflume/schemes/scheme.hpp"
#include "sphflume/setup/setup.hpp"
#include "sphflume/sim/health.hpp"
#include "sphflume/sim/ranks.hpp"

namespace sph {
namespace fs = std::filesystem;
namespace {

int thread_count() {
#ifdef _OPENMP
  return omp_get_max_threads();
#else
  return 1;
#endif
}

std::string hms(double s) {
  if (!std::isfinite(s) || s < 0) return "--:--:--";
  const long t = std::lround(s);
  return fmt::format("{:02d}:{:02d}:{:02d}", t / 3600, (t / 60) % 60, t % 60);
}

/// The box particles must stay in: the case's domain, or the initial bounding box with
/// room above for splashes.
template <int D>
void domain_box(const Case& c, const System<D>& S, Vec<D>& lo, Vec<D>& hi) {
  if (!c.domain_min.empty()) {
    for (int d = 0; d < D; ++d) { lo[d] = c.domain_min[d]; hi[d] = c.domain_max[d]; }
    return;
  }
  const auto& P = S.particles;
  for (int d = 0; d < D; ++d) { lo[d] = 1e300; hi[d] = -1e300; }
  for (std::size_t i = 0; i < P.n_owned(); ++i)
    for (int d = 0; d < D; ++d) { lo[d] = std::min(lo[d], P.pos[i][d]); hi[d] = std::max(hi[d], P.pos[i][d]); }
  for (int d = 0; d < D; ++d) {
    const double span = hi[d] - lo[d];
    lo[d] -= 0.1 * span + S.dx;
    hi[d] += (d == D - 1 ? 1.0 : 0.1) * span + S.dx;
  }
}

// SIGINT / SIGTERM: the loop finishes its step, writes a checkpoint and stops.
volatile std::sig_atomic_t g_signal = 0;
extern "C" void on_signal(int sig) { g_signal = sig; }

class SignalGuard {
 public:
  SignalGuard() {
    g_signal = 0;
    struct sigaction sa {};
    sa.sa_handler = on_signal;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, &old_int_);
    sigaction(SIGTERM, &sa, &old_term_);
  }
  ~SignalGuard() {
    sigaction(SIGINT, &old_int_, nullptr);
    sigaction(SIGTERM, &old_term_, nullptr);
  }
  int caught() const { return g_signal; }

 private:
  struct sigaction old_int_ {}, old_term_ {};
};

constexpr double kDtFloor = 1e-4;  // a time step below this fraction of the first one is a collapse

/// A run's system and counters, and the deterministic step: everything a restart or a replay
/// must reproduce bit for bit goes through advance().
template <int D>
struct Run {
  const Case& c;
  System<D> S;
  BuildReport rep;
  std::unique_ptr<Scheme<D>> scheme;
  Vec<D> lo, hi;  // particles outside are removed
  RunState rs;
  HealthLimits limits;
  OpenBoundaries<D> open;

  explicit Run(const Case& cs) : c(cs), open(cs) {
    scheme = setup_system<D>(c, S, rep);
    domain_box(c, S, lo, hi);  // from the case's geometry, so a restart gets the same box
    rs.case_text = c.fingerprint;
    open.setup(S, rs.open);  // fluid inside the zones becomes inflow/outflow particles
    if (S.transport) S.transport->impose(S);  // the inflow particles' prescribed values
    if (open.needs_prepare()) S.before_rates = [this](System<D>& s) { open.prepare(s); };
    if (!scheme->density_bounded_below()) limits.density_min_ratio = 0.0;  // (compression only)
  }

  void start_fresh() {
    scheme->initialise(S);
    rs.dt_first = S.comm->min(scheme->time_step(S));
    rs.initial_mass = S.comm->sum(S.total_mass(Kind::Fluid));
    rs.next_output = c.output_interval;
  }

  void load(const std::string& path) {
    RunState saved;
    read_restart<D>(path, S.particles, saved);
    if (!S.phase_eos.empty()) S.bind_phase_field();  // the store was rebuilt: its "phase" field is new
    if (saved.case_text != rs.case_text)
      throw InputError(fmt::format("--restart {}: the case differs from the one that wrote this restart point (only "
                                   "time.end may change): use the same case file and --set options", path));
    saved.case_text = rs.case_text;
    rs = std::move(saved);
    S.time = rs.time;
    S.step = rs.step;
    scheme->restore(rs.scheme);
    if (S.transport) {
      std::vector<double> m;
      for (std::size_t k = 0; k < S.transport->count(); ++k) {
        auto it = rs.scheme.find("source_mass." + S.transport->name(k));
        m.push_back(it == rs.scheme.end() ? 0.0 : it->second);
      }
      S.transport->restore_source_masses(m);
    }
  }

  RunState state() const {
    RunState r = rs;
    r.time = S.time;
    r.step = S.step;
    r.scheme = scheme->state();
    if (S.transport)
      for (std::size_t k = 0; k < S.transport->count(); ++k) r.scheme["source_mass." + S.transport->name(k)] = S.transport->source_mass(k);
    return r;
  }

  /// One time step, the removal of particles that left the domain, and the health check.
  /// Returns true when an output is due (next_output has then moved past it).
  bool advance(double& dt) {
    dt = S.comm->min(scheme->time_step(S));
    if (!(dt > kDtFloor * rs.dt_first)) {
      const std::size_t i = fastest_accelerating(S);
      throw SimulationError(fmt::format(
          "at step {}, t = {:.9g} s: the time step collapsed to {:.3g} s (it started at {:.3g} s; the floor is {} x "
          "that); {} has the largest acceleration, |a| = {:.3g} m/s2; likely cause: particles accelerated violently, "
          "by penetrating a wall or colliding (raise fluid.sound_speed, lower scheme.cfl, check the walls)",
          S.step, S.time, dt, rs.dt_first, kDtFloor, describe_particle(S, i), norm(S.particles.acc[i])));
    }
    const double to_out = std::min(rs.next_output, c.t_end) - S.time;
    if (dt > to_out && to_out > 1e-12 * dt) dt = to_out;
    // schemes that want no short step (a projection's density source scales with 1/dt²):
    // the last two steps before an output share what is left
    else if (scheme->even_steps() && to_out > dt && to_out < 2.0 * dt) dt = 0.5 * to_out;
    try {
      scheme->step(S, dt);
    } catch (const SimulationError&) {
      throw;
    } catch (const std::runtime_error& e) {  // e.g. the cell list meets a non-finite position
      S.particles.clear_images();
      const auto h = check_health(S, limits);
      throw SimulationError(h ? *h : fmt::format("at step {}, t = {:.9g} s: {}", S.step, S.time, e.what()));
    }
    // open boundaries; then re-sort if particles were created or deleted (see remove_escaped)
    if (open.any() && S.comm->any(open.update(S, rs.open))) S.update_neighbours();
    remove_escaped();
    health();
    const bool last = S.time >= c.t_end * (1.0 - 1e-12);
    if (!(S.time >= rs.next_output * (1.0 - 1e-9) || last)) return false;
    while (rs.next_output <= S.time * (1.0 + 1e-9)) rs.next_output += c.output_interval;
    return true;
  }

  /// A failure on any rank stops every rank (each says what it saw).
  void health() {
    const auto h = check_health(S, limits);
    if (S.comm->any(h.has_value()))
      throw SimulationError(h ? *h : fmt::format("at step {}, t = {:.9g} s: another rank failed (its message says why)", S.step, S.time));
  }

  /// Fluid particles outside the domain box are removed and counted per face.
  void remove_escaped() {
    auto& P = S.particles;
    // a parallel look first (nearly every step removes nothing), the serial pass only if needed
    const std::size_t n = P.n_owned();
    bool any = false;
#pragma omp parallel for schedule(static) reduction(|| : any)
    for (std::size_t i = 0; i < n; ++i) {
      if (P.kind[i] != Kind::Fluid) continue;
      for (int d = 0; d < D; ++d)
        any = any || (!S.periodic.axis[d] && !(P.pos[i][d] >= lo[d] && P.pos[i][d] <= hi[d]));
    }
    if (!S.comm->any(any)) return;
    std::vector<char> flag;
    for (std::size_t i = 0; i < P.n_owned(); ++i) {
      if (P.kind[i] != Kind::Fluid) continue;
      for (int d = 0; d < D; ++d) {
        if (S.periodic.axis[d]) continue;
        if (P.pos[i][d] < lo[d] || P.pos[i][d] > hi[d]) {
          if (flag.empty()) flag.assign(P.n_owned(), 0);
          flag[i] = 1;
          rs.removed_mass += P.mass[i];
          ++rs.removed_by_face[fmt::format("{}{}", "xyz"[D == 2 && d == 1 ? 2 : d], P.pos[i][d] < lo[d] ? "-" : "+")];
          break;
        }
      }
    }
    if (!flag.empty()) {
      P.clear_images();
      P.remove_if_flagged(flag);
    }
    // re-sort now: the order the next step starts from must not depend on whether an output
    // (which sorts) came in between, or restarts would not be bitwise
    S.update_neighbours();
  }
};

/// After a failure at step good_step + 1: write the state of step good_step as the last
/// snapshot. Runs are deterministic, so it is recomputed from the last restart point (or the
/// start) rather than kept in memory at every step. Returns its path ("" when impossible).
template <int D>
std::string write_last_good(const Case& c, SnapshotWriter<D>& snaps, const std::string& restart_point, long good_step,
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

struct Summary {
  std::string status, message, last_good, restarted_from;
  double last_dt = 0.0;
  std::size_t snapshots = 0;
  double wall = 0.0;
  std::string snapshot_writes = "one process";  // distributed: "collective" (parallel HDF5) or "gathered"
};

/// Global sums of what each rank counted (the same values in one process).
template <int D>
struct Totals {
  std::uint64_t kind[kKindCount]{};
  double removed_mass = 0.0, inflow = 0.0, outflow = 0.0, backflow_mass = 0.0, final_mass = 0.0;
  std::uint64_t backflow = 0;
  std::map<std::string, long> removed_by_face;
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
    }
  }
  std::uint64_t operator[](Kind k) const { return kind[static_cast<int>(k)]; }
};

/// Every rank calls it (the totals are reductions); the first rank writes the file.
template <int D>
void write_summary(const RunOptions& o, const Case& c, const Run<D>& R, const Summary& sm, const RunResult& res) {
  const System<D>& S = R.S;
  const RunState& rs = R.rs;
  const Totals<D> tot(S, rs);
  const RankStats ranks = rank_stats(S, res.steps);
  if (!S.comm->root()) return;
  // the output contract (docs/output.md): keys in this order, numbers as JSON numbers (NaN: null)
  nlohmann::ordered_json j;
  j["version"] = o.version;
  j["case"] = c.name;
  j["case_file"] = c.file;
  j["dimension"] = D;
  j["scheme"] = R.scheme->name();
  j["kernel"] = kernel_name(c.kernel);
  j["integrator"] = R.scheme->integrator();
  j["passes_per_step"] = R.scheme->passes_per_step();
  j["ignored_keys"] = c.warnings;  // (every warning, the name kept for old readers)
  j["warnings"] = c.warnings;
  R.scheme->summary(j);  // the scheme's own block (ISPH: "pressure_solver")
  j["dx"] = S.dx;
  j["h"] = S.h;
  j["sound_speed"] = S.eos.c0;
  j["particles"] = {{"fluid", tot[Kind::Fluid]}, {"wall", tot[Kind::Wall]}, {"inflow", tot[Kind::Inflow]},
                    {"outflow", tot[Kind::Outflow]}, {"total", res.total}, {"initial_fluid", R.rep.fluid}};
  j["steps"] = res.steps;
  j["total_steps"] = S.step;
  j["simulated_time"] = S.time;
  j["end_time"] = c.t_end;
  j["wall_seconds"] = sm.wall;
  j["threads"] = thread_count();
  j["ranks"] = {{"count", S.comm->size()}, {"halo_bytes_per_step", ranks.halo_bytes_per_step},
                {"imbalance", ranks.imbalance}, {"fluid_imbalance", ranks.fluid_imbalance},
                {"rebalances", ranks.rebalances}, {"migrated_per_step", ranks.migrated_per_step},
                {"snapshot_writes", sm.snapshot_writes}};
  j["particle_steps_per_second"] = res.particle_steps_per_second;
  j["fluid_particle_steps_per_second"] = res.fluid_particle_steps_per_second;
  j["pair_interactions_per_second"] = res.pair_interactions_per_second;
  j["bytes_per_particle"] = res.bytes_per_particle;
  j["last_dt"] = sm.last_dt;
  j["snapshots"] = sm.snapshots;
  j["mass"] = {{"initial", rs.initial_mass}, {"inflow", tot.inflow}, {"outflow", tot.outflow},
               {"backflow", tot.backflow_mass}, {"removed", tot.removed_mass}, {"final", tot.final_mass},
               {"relative_error", res.mass_error}};
  j["backflow"] = {{"particles", tot.backflow}, {"mass", tot.backflow_mass}};
  long removed = 0;
  nlohmann::ordered_json faces = nlohmann::ordered_json::object();
  for (const auto& [f, n] : tot.removed_by_face) {
    faces[f] = n;
    removed += n;
  }
  j["removed_particles"] = faces;
  j["removed_particles_total"] = removed;
  j["restarted_from"] = sm.restarted_from;
  j["last_good_snapshot"] = sm.last_good;
  j["exit_status"] = sm.status;
  j["exit_code"] = res.exit_code;
  j["message"] = sm.message;
  // (a message or path that is not valid UTF-8 is written with U+FFFD, not refused)
  const std::string json = j.dump(2, ' ', false, nlohmann::ordered_json::error_handler_t::replace) + "\n";
  write_file_atomically(o.output + "/summary.json", json);
}

template <int D>
RunResult run_dim(const Case& c, const RunOptions& o) {
  const auto comm = world();
  const bool distributed = comm->size() > 1;
  Run<D> R(c);
  System<D>& S = R.S;
  const bool restart = !o.restart.empty();
  if (restart) {
    R.load(o.restart);
    if (S.time >= c.t_end * (1.0 - 1e-12))
      throw InputError(fmt::format("--restart {}: it is at t = {:.9g} s, at or past time.end = {} s: raise the end time "
                                   "(--set time.end=...)", o.restart, S.time, c.t_end));
  }
  // mpirun -np N: every rank built (or read) the whole case; each keeps its slab (sim/ranks.hpp)
  if (distributed) {
    auto refuse = [&](const std::string& what) {
      throw InputError(fmt::format("{}: {} in a distributed run (mpirun -np {}) is not supported: run it in one "
                                   "process (without mpirun)", c.file, what, comm->size()));
    };
    if (const std::string why = R.scheme->distributed_refusal(); !why.empty()) refuse(why);
    distribute<D>(S, comm);  // (every gauge reduces its value over the ranks: io/gauges.cpp)
  }
  if (distributed && restart && !comm->root()) {  // the restart point's counters are global: the first rank keeps them
    R.rs.removed_mass = 0.0;
    R.rs.removed_by_face.clear();
    const std::uint32_t next_id = R.rs.open.next_id;  // (the next new particle's id is the same on every rank)
    R.rs.open = OpenFlowCounters{};
    R.rs.open.next_id = next_id;
    if (S.transport) S.transport->restore_source_masses(std::vector<double>(S.transport->count(), 0.0));
  }
#ifdef _OPENMP
  if (o.threads > 0) omp_set_num_threads(o.threads);
#endif
  // output folder: must be writable before anything is computed
  std::error_code ec;
  fs::create_directories(o.output, ec);
  const std::string probe = o.output + "/.sphflume_write_test";
  {
    std::ofstream t(probe);
    if (ec || !t) throw InputError(fmt::format("output folder '{}' is not writable: {} (choose another with --output)", o.output, ec ? ec.message() : "cannot create files there"));
  }
  fs::remove(probe, ec);

  // a restart into its own run folder continues the series there; into another folder it
  // starts a new series (snapshot 0 = the restart state, gauges from the restart time on)
  bool resume = false;
  if (restart) {
    fs::path dir = fs::absolute(o.restart).parent_path();
    if (dir.filename() == "snapshots") dir = dir.parent_path();
    resume = fs::equivalent(dir, o.output, ec);
  }
  SnapshotWriter<D> snaps(o.output, comm);  // (distributed: the ranks write together where HDF5 has MPI-IO)
  std::unique_ptr<GaugeSet<D>> gauges;
  if (o.write_output) {
    if (resume) snaps.resume(R.rs.snapshots);  // later snapshots of the interrupted run go
    else if (comm->root() && fs::exists(o.output + "/snapshots"))  // a re-run must not leave an earlier run's snapshots behind
      for (const auto& e : fs::directory_iterator(o.output + "/snapshots", ec))
        if (e.path().extension() == ".h5" || e.path().extension() == ".tmp") fs::remove(e.path(), ec);
    gauges = std::make_unique<GaugeSet<D>>(c.gauges, o.output, R.hi[D - 1],
                                           resume ? S.time : std::numeric_limits<double>::quiet_NaN(), comm->root());
  }
  if (!restart) {
    R.start_fresh();
    const auto h = check_health(S, R.limits);
    if (S.comm->any(h.has_value()))
      throw InputError(fmt::format("{}: the initial state is not sane, {}", c.file, h ? *h : std::string("on another rank")));
  }

  const auto t0 = std::chrono::steady_clock::now();
  auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };
  RunResult res;
  std::uint64_t pairs_total = 0;
  std::string status = "done", failure, last_good;
  long last_snapshot_step = -1;
  std::string restart_point = restart ? o.restart : std::string();
  const std::string checkpoint = o.output + "/checkpoint.h5";

  // the state a restart point records: in a distributed run the counters summed over the ranks
  auto global_state = [&] {
    RunState st = R.state();
    if (distributed) {
      const Totals<D> tot(S, R.rs);
      st.removed_mass = tot.removed_mass;
      st.removed_by_face = tot.removed_by_face;
      st.open.inflow_mass = tot.inflow;
      st.open.outflow_mass = tot.outflow;
      st.open.backflow_mass = tot.backflow_mass;
      st.open.backflow = static_cast<long>(tot.backflow);
      // the scheme's state over the ranks: its largest acceleration and eddy viscosity (the
      // others are the same on every rank); pollutant source masses add up
      for (auto& [k, v] : st.scheme) v = k.rfind("source_mass.", 0) == 0 ? comm->sum(v) : comm->max(v);
    }
    return st;
  };
  // snapshots and checkpoints of a distributed run: every rank writes its particles into the same
  // files together (parallel HDF5); with an HDF5 without MPI-IO, every rank's particles are
  // gathered on the first, which writes the same files as one process (sim/ranks.hpp)
  ParticleStore<D> gathered;
  auto write_snapshot = [&] {
    const RunState st = global_state();
    if (!distributed || snaps.collective()) {
      snaps.write(S.particles, S.time, S.step, &st);
      return;
    }
    gather_particles(S, gathered);
    if (comm->root()) snaps.write(gathered, S.time, S.step, &st);
    gathered = ParticleStore<D>();
  };
  auto output = [&](bool always) {
    if (!o.write_output) return;
    S.update_neighbours();
    // snapshots at every snapshot_every-th output time (and the first and last); gauges at each
    const long k = std::lround(S.time / c.output_interval);
    const bool snap = always || c.snapshot_every <= 1 || k % c.snapshot_every == 0 || S.time >= c.t_end * (1.0 - 1e-12);
    if (R.open.any()) {  // (the boundary_volume gauge's cumulative masses, summed over the ranks)
      const Totals<D> tot(S, R.rs);
      S.counters["inflow_mass"] = tot.inflow;
      S.counters["outflow_mass"] = tot.outflow;
      S.counters["backflow_mass"] = tot.backflow_mass;
    }
    if (S.transport)
      for (std::size_t k = 0; k < S.transport->count(); ++k)  // (summed over the ranks)
        S.counters["source_mass." + S.transport->name(k)] = S.comm->sum(S.transport->source_mass(k));
    // the gauges' rows before the snapshot: a run killed between the two leaves a snapshot only
    // where its rows are on disk (a restart keeps the rows up to its snapshot's time and writes
    // none at that time; robustness_restart saw the row at the restart time lost the other way)
    gauges->sample(S);
    if (snap) write_snapshot();
    if (snap) {
      last_snapshot_step = S.step;
      restart_point = snaps.last_path();
    }
  };

  const bool tty = isatty(fileno(stderr));
  double last_progress = 0.0, last_checkpoint = 0.0;
  double dt = 0.0;
  long steps_done = 0, good_step = S.step;
  double particle_steps = 0.0, fluid_particle_steps = 0.0;
  SignalGuard signals;
  try {
    if (!resume) output(true);
    while (S.time < c.t_end * (1.0 - 1e-12) && (o.max_steps == 0 || steps_done < o.max_steps)) {
      const std::size_t n_before = S.particles.n_owned();
      const bool out = R.advance(dt);
      ++steps_done;
      good_step = S.step;
      pairs_total += S.pairs_last_pass * static_cast<std::uint64_t>(R.scheme->passes_per_step());
      particle_steps += static_cast<double>(n_before);
      fluid_particle_steps += static_cast<double>(S.particles.count(Kind::Fluid));
      // windowed pressure sensors sample after every step (on the neighbour lists of the last pass)
      if (o.write_output && gauges->needs_tick() && !out) gauges->tick(S);
      if (out) output(false);
      const double w = elapsed();
      auto write_checkpoint = [&] {
        RunState st = global_state();
        st.snapshots = snaps.entries();
        if (!distributed || snaps.collective()) {
          snaps.write_checkpoint(checkpoint, S.particles, st);
          return;
        }
        gather_particles(S, gathered);
        if (comm->root()) snaps.write_checkpoint(checkpoint, gathered, st);
        gathered = ParticleStore<D>();
      };
      // (in a distributed run every rank takes the same decisions: a signal or the checkpoint
      // clock of any rank counts for all)
      if (const int sig = distributed ? static_cast<int>(comm->max(double(signals.caught()))) : signals.caught()) {
        write_checkpoint();
        status = "interrupted";
        failure = fmt::format("stopped by signal {} at step {}, t = {:.9g} s; checkpoint written: resume with "
                              "sphflume run {} --restart {}", sig, S.step, S.time, c.file, checkpoint);
        res.exit_code = 128 + sig;
        break;
      }
      if (o.checkpoint_every > 0 && comm->any(w - last_checkpoint >= o.checkpoint_every)) {
        last_checkpoint = w;
        write_checkpoint();
        restart_point = checkpoint;
      }
      if (o.progress && w - last_progress >= (tty ? 0.5 : 15.0)) {
        last_progress = w;
        const double frac = S.time / c.t_end;
        const double eta = frac > 0 ? w * (1.0 - frac) / frac : -1.0;
        fmt::print(stderr, "{}t = {:.4f} / {:.4f} s  step {}  dt {:.2e} s  {:.2f} M particle-steps/s  ETA {}{}",
                   tty ? "\r" : "", S.time, c.t_end, S.step, dt, particle_steps / w / 1e6, hms(eta), tty ? "   " : "\n");
        std::fflush(stderr);
      }
    }
  } catch (const SimulationError& e) {
    status = "failed";
    failure = e.what();
    res.exit_code = 3;
    if (distributed) abort_ranks(*comm, failure, 3);
    if (o.write_output) last_good = write_last_good<D>(c, snaps, restart_point, good_step, last_snapshot_step);
  } catch (const IoError& e) {  // a write failed (full disk, ...): the files already written are whole
    status = "failed";
    failure = e.what();
    res.exit_code = 3;
    if (distributed) abort_ranks(*comm, failure, 3);
  } catch (const std::exception& e) {
    if (distributed) abort_ranks(*comm, e.what(), 3);
    throw;
  }
  if (o.progress && tty) fmt::print(stderr, "\n");
  const double wall = elapsed();
  S.particles.clear_images();

  res.steps = steps_done;
  res.wall_seconds = wall;
  {  // totals over the ranks
    std::uint64_t cnt[3] = {S.particles.count(Kind::Fluid), S.particles.n_owned(), pairs_total};
    S.comm->sum(cnt, 3);
    double ps[2] = {particle_steps, fluid_particle_steps};
    S.comm->sum(ps, 2);
    res.fluid = cnt[0];
    res.total = cnt[1];
    pairs_total = cnt[2];
    particle_steps = ps[0];
    fluid_particle_steps = ps[1];
  }
  res.particle_steps_per_second = wall > 0 ? particle_steps / wall : 0.0;
  res.fluid_particle_steps_per_second = wall > 0 ? fluid_particle_steps / wall : 0.0;
  res.pair_interactions_per_second = wall > 0 ? static_cast<double>(pairs_total) / wall : 0.0;
  res.bytes_per_particle = static_cast<double>(S.particles.bytes() + S.cells.bytes() + R.scheme->bytes() + S.walls->bytes()) /
                           static_cast<double>(std::max<std::size_t>(1, res.total));
  const Totals<D> tot(S, R.rs);
  const double m0 = R.rs.initial_mass;
  res.mass_error = m0 > 0 ? (m0 + tot.inflow - tot.outflow - tot.backflow_mass - tot.removed_mass - tot.final_mass) / m0 : 0.0;
  const std::uint64_t walls_total = tot[Kind::Wall];

  Summary sm{status, failure, last_good, restart ? o.restart : std::string(), dt, snaps.count(), wall,
             !distributed ? "one process" : snaps.collective() ? "collective" : "gathered"};
  try {
    write_summary<D>(o, c, R, sm, res);
  } catch (const IoError& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    if (res.exit_code == 0) res.exit_code = 3;
  }

  if (!comm->root()) {  // (the first rank reports the run; the others only their own failure)
    if (res.exit_code != 0 && !failure.empty()) fmt::print(stderr, "rank {}: {}\n", comm->rank(), failure);
    return res;
  }
  std::string faces;
  for (const auto& [f, n] : tot.removed_by_face) faces += fmt::format("{}{}: {}", faces.empty() ? "" : ", ", f, n);
  if (res.exit_code == 3)
    fmt::print(stderr, "error: the simulation failed: {}\n{}\n", failure,
               last_good.empty() ? "no snapshot could be written"
                                 : fmt::format("last good state written to {}", last_good));
  else if (res.exit_code != 0)
    fmt::print(stderr, "{}\n", failure);
  fmt::print("{} particles ({} fluid, {} wall), {} steps, simulated {:.4g} s in {} wall ({:.2f} M particle-steps/s, "
             "{:.1f} M pair interactions/s, {:.0f} bytes/particle, {} threads)\nmass error {:.2e}{}\noutput: {}\n",
             res.total, res.fluid, walls_total, res.steps, S.time, hms(wall),
             res.particle_steps_per_second / 1e6, res.pair_interactions_per_second / 1e6, res.bytes_per_particle,
             thread_count(), res.mass_error,
             faces.empty() ? "" : fmt::format(" (particles left the domain and were removed: {})", faces),
             fs::absolute(o.output).string());
  return res;
}

template <int D>
std::string check_dim(const Case& c) {
  System<D> S;
  BuildReport rep;
  std::unique_ptr<Scheme<D>> scheme;
  scheme = setup_system<D>(c, S, rep);
  scheme->initialise(S);
  const double dt = scheme->time_step(S);
  std::string s;
  s += fmt::format("case '{}' ({}D, {}, scheme {}, walls {})\n", c.name, D, c.file, scheme->name(), c.walls.type);
  s += fmt::format("particles: {} fluid, {} wall ({} layers), {} in all", rep.fluid, rep.wall, rep.wall_layers, rep.fluid + rep.wall);
  if (rep.fluid_dropped_in_walls) s += fmt::format("; {} fluid lattice points inside walls were left out", rep.fluid_dropped_in_walls);
  if (rep.porous_relax_band)
    s += fmt::format("\nporous.relax: {} points of the interface band shifted (at most {:.3g} dx); h |sum V grad W| "
                     "{:.3g} -> {:.3g}", rep.porous_relax_band, rep.porous_relax_shift / c.dx, rep.porous_relax_residual0,
                     rep.porous_relax_residual);
  s += fmt::format("\ndx = {} m, kernel {} with h = {:.4g} m (h/dx = {}), support {:.4g} m\n", c.dx, kernel_name(c.kernel), S.h, c.h_over_dx, S.support);
  s += fmt::format("sound speed c0 = {:.4g} m/s, fluid height {:.4g} m\n", S.eos.c0, rep.fluid_height);
  s += fmt::format("estimated time step {:.3e} s: about {:.0f} steps to t = {} s, {} snapshots\n", dt, std::ceil(c.t_end / dt), c.t_end,
                   static_cast<long>(std::floor(c.t_end / (c.output_interval * double(c.snapshot_every)) + 1e-9)) + 1);
  return s;
}

}  // namespace

RunResult run_case(const Case& c, const RunOptions& o) {
  return c.dimension == 2 ? run_dim<2>(c, o) : run_dim<3>(c, o);
}

std::string check_case(const Case& c) { return c.dimension == 2 ? check_dim<2>(c) : check_dim<3>(c); }

}  // namespace sph
