#include "sphflume/sim/simulation.hpp"

#include <signal.h>
#include <unistd.h>

#include <chrono>
#include <ctime>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <limits>

#include <fmt/format.h>
#ifdef _OPENMP
#include <omp.h>
#endif

#include "sphflume/sim/output.hpp"
#include "sphflume/sim/ranks.hpp"
#include "sphflume/sim/run.hpp"
#include "sphflume/sim/summary.hpp"

namespace sph {

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

namespace {

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

/// --restart: the restart point read and checked against time.end; over MPI ranks each rank keeps
/// its slab (sim/ranks.hpp) and the restart point's global counters stay with the first rank.
template <int D>
void load_and_distribute(Run<D>& R, const Case& c, const RunOptions& o, const Communicator& comm,
                         std::shared_ptr<const Communicator> shared) {
  System<D>& S = R.S;
  const bool restart = !o.restart.empty(), distributed = comm.size() > 1;
  if (restart) {
    R.load(o.restart);
    if (S.time >= c.t_end * (1.0 - 1e-12))
      throw InputError(fmt::format("--restart {}: it is at t = {:.9g} s, at or past time.end = {} s: raise the end time "
                                   "(--set time.end=...)", o.restart, S.time, c.t_end));
  }
  // mpirun -np N: every rank built (or read) the whole case; each keeps its slab (sim/ranks.hpp)
  if (distributed) {
    if (const std::string why = R.scheme->distributed_refusal(); !why.empty())
      throw InputError(fmt::format("{}: {} in a distributed run (mpirun -np {}) is not supported: run it in one "
                                   "process (without mpirun)", c.file, why, comm.size()));
    distribute<D>(S, shared);  // (every gauge reduces its value over the ranks: io/gauges.cpp)
  }
  if (distributed && restart && !comm.root()) {  // the restart point's counters are global: the first rank keeps them
    R.rs.removed_mass = 0.0;
    R.rs.removed_by_face.clear();
    R.rs.removed_mass_by_face.clear();
    const std::uint32_t next_id = R.rs.open.next_id;  // (the next new particle's id is the same on every rank)
    R.rs.open = OpenFlowCounters{};
    R.rs.open.next_id = next_id;
    if (S.transport) S.transport->restore_source_masses(std::vector<double>(S.transport->count(), 0.0));
  }
}

/// How the step loop ended.
struct LoopEnd {
  std::string status = "done", failure, last_good;
  double dt = 0.0;
};

/// The time steps to time.end (or --max-steps), with outputs, checkpoints (on the clock or a
/// signal) and the progress line; a failure ends it with exit code 3 and the last good state.
template <int D>
LoopEnd step_loop(Run<D>& R, RunOutput<D>& out, const Case& c, const RunOptions& o, const Communicator& comm,
                  LoopCounters& n, RunResult& res) {
  System<D>& S = R.S;
  const bool distributed = comm.size() > 1;
  const auto t0 = std::chrono::steady_clock::now();
  const std::clock_t cpu0 = std::clock();
  auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };
  LoopEnd end;
  const bool tty = isatty(fileno(stderr));
  double last_progress = 0.0, last_checkpoint = 0.0;
  long good_step = S.step;
  SignalGuard signals;
  try {
    if (!out.resumes()) out.output(true);
    while (S.time < c.t_end * (1.0 - 1e-12) && (o.max_steps == 0 || n.steps < o.max_steps)) {
      const std::size_t n_before = S.particles.n_owned();
      const bool at_output = R.advance(end.dt);
      ++n.steps;
      good_step = S.step;
      n.pairs += S.pairs_last_pass * static_cast<std::uint64_t>(R.scheme->passes_per_step());
      n.particle_steps += static_cast<double>(n_before);
      n.fluid_particle_steps += static_cast<double>(S.particles.count(Kind::Fluid));
      if (at_output) out.output(false);
      else out.tick();
      const double w = elapsed();
      // (in a distributed run every rank takes the same decisions: a signal or the checkpoint
      // clock of any rank counts for all)
      if (const int sig = distributed ? static_cast<int>(comm.max(double(signals.caught()))) : signals.caught()) {
        out.write_checkpoint();
        end.status = "interrupted";
        end.failure = fmt::format("stopped by signal {} at step {}, t = {:.9g} s; checkpoint written: resume with "
                                  "sphflume run {} --restart {}", sig, S.step, S.time, c.file, out.checkpoint_path());
        res.exit_code = 128 + sig;
        break;
      }
      if (o.checkpoint_every > 0 && comm.any(w - last_checkpoint >= o.checkpoint_every)) {
        last_checkpoint = w;
        out.write_checkpoint();
        out.set_restart_point(out.checkpoint_path());
      }
      if (o.progress && w - last_progress >= (tty ? 0.5 : 15.0)) {
        last_progress = w;
        const double frac = S.time / c.t_end;
        const double eta = frac > 0 ? w * (1.0 - frac) / frac : -1.0;
        fmt::print(stderr, "{}t = {:.4f} / {:.4f} s  step {}  dt {:.2e} s  {:.2f} M particle-steps/s  ETA {}{}",
                   tty ? "\r" : "", S.time, c.t_end, S.step, end.dt, n.particle_steps / w / 1e6, hms(eta), tty ? "   " : "\n");
        std::fflush(stderr);
      }
    }
  } catch (const SimulationError& e) {
    end.status = "failed";
    end.failure = e.what();
    res.exit_code = 3;
    if (distributed) abort_ranks(comm, end.failure, 3);
    if (o.write_output) end.last_good = out.write_last_good(good_step);
  } catch (const IoError& e) {  // a write failed (full disk, ...): the files already written are whole
    end.status = "failed";
    end.failure = e.what();
    res.exit_code = 3;
    if (distributed) abort_ranks(comm, end.failure, 3);
  } catch (const std::exception& e) {
    if (distributed) abort_ranks(comm, e.what(), 3);
    throw;
  }
  if (o.progress && tty) fmt::print(stderr, "\n");
  res.wall_seconds = elapsed();
  res.cpu_seconds = static_cast<double>(std::clock() - cpu0) / CLOCKS_PER_SEC;
  return end;
}

/// The driver: set-up (or restart), the output policy, the step loop, summary.json and the report.
template <int D>
RunResult run_dim(const Case& c, const RunOptions& o) {
  const auto comm = world();
#ifdef _OPENMP
  if (o.threads > 0) omp_set_num_threads(o.threads);  // (before the set-up: --threads holds for all of the run)
#endif
  Run<D> R(c);
  System<D>& S = R.S;
  load_and_distribute<D>(R, c, o, *comm, comm);
  RunOutput<D> out(c, o, R, comm);
  if (o.restart.empty()) {
    R.start_fresh();
    const auto h = check_health(S, R.limits);
    if (S.comm->any(h.has_value()))
      throw InputError(fmt::format("{}: the initial state is not sane, {}", c.file, h ? *h : std::string("on another rank")));
  }
  RunResult res;
  LoopCounters n;
  const LoopEnd end = step_loop<D>(R, out, c, o, *comm, n, res);
  S.particles.clear_images();
  finish_result<D>(R, n, res.wall_seconds, res);
  const bool distributed = comm->size() > 1;
  Summary sm{end.status, end.failure, end.last_good, o.restart, end.dt, out.snapshot_count(), res.wall_seconds, res.cpu_seconds,
             out.snapshot_seconds(), !distributed ? "one process" : out.collective() ? "collective" : "gathered"};
  try {
    write_summary<D>(o, c, R, sm, res);
  } catch (const IoError& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    if (res.exit_code == 0) res.exit_code = 3;
  }
  print_report<D>(o, R, res, end.failure, end.last_good);
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
  if (rep.levels)
    s += fmt::format("\nresolution: {} refined fluid particles (levels 1 to {}); the level interface: {} points relaxed "
                     "(at most {:.3g} dx), h |sum V grad W| {:.3g} -> {:.3g} in {} iterations",
                     rep.refined, rep.levels, rep.level_relax_band, rep.level_relax_shift / c.dx, rep.level_relax_residual0,
                     rep.level_relax_residual, rep.level_relax_iterations);
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
