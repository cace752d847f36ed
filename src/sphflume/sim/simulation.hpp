// Runs a case: builds the particles, steps the scheme, writes snapshots, gauges, progress and
// summary.json. See shared conventions for the output folder contract.
#pragma once
#include <string>

#include "sphflume/io/case.hpp"

namespace sph {

struct RunOptions {
  std::string output = "output";
  int threads = 0;        // 0 = OpenMP default
  bool progress = true;   // progress line on stderr
  std::string version;
  long max_steps = 0;     // stop after this many steps (benchmarks); 0 = run to time.end
  bool write_output = true;  // snapshots and gauges (benchmarks switch them off)
  std::string restart;       // restart point to resume from (a snapshot or checkpoint.h5); empty = fresh
  double checkpoint_every = 1800.0;  // wall seconds between OUTPUT/checkpoint.h5 writes; 0 = never
};

struct RunResult {
  int exit_code = 0;  // 0 done, 3 failed (last good state written), 128 + signal when interrupted
  long steps = 0;
  double wall_seconds = 0.0;
  double cpu_seconds = 0.0;  // the process's CPU time in the time loop, every thread (std::clock)
  std::size_t fluid = 0, total = 0;
  double particle_steps_per_second = 0.0, fluid_particle_steps_per_second = 0.0;
  double pair_interactions_per_second = 0.0, bytes_per_particle = 0.0;
  double mass_error = 0.0;
};

/// Run the case (or resume it from o.restart). Throws InputError (before computing) for bad
/// input; returns exit code 3 after writing the last good state when the simulation fails,
/// 128 + the signal after writing OUTPUT/checkpoint.h5 on SIGINT/SIGTERM.
RunResult run_case(const Case& c, const RunOptions& o);

/// Text report of what a run would do: particle counts, h, c0, estimated dt and steps.
std::string check_case(const Case& c);

}  // namespace sph
