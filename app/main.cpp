// sphflume: the command-line front end. Exit codes: 0 done, 2 bad input, 3 simulation failed,
// 128 + N stopped by signal N (SIGINT 130, SIGTERM 143) after writing a checkpoint.
#include <cstdio>
#include <filesystem>
#include <iostream>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "sphflume/io/case.hpp"
#include "sphflume/io/snapshot.hpp"
#include "sphflume/schemes/scheme.hpp"
#include "sphflume/sim/simulation.hpp"
#include "sphflume/version.hpp"

int main(int argc, char** argv) {
  CLI::App app{"SPHFlume: free-surface water with Smoothed Particle Hydrodynamics (a numerical flume)", "sphflume"};
  app.set_version_flag("--version", std::string("sphflume ") + SPHFLUME_VERSION);
  app.require_subcommand(1);

  std::string case_file, output, restart;
  double checkpoint_every = 1800.0;
  int threads = 0;
  std::vector<std::string> sets;
  bool quiet = false;
  long max_steps = 0;
  bool no_output = false;

  auto* run = app.add_subcommand("run", "run a case and write snapshots, gauges and summary.json");
  run->add_option("case", case_file, "case file (YAML)")->required();
  run->add_option("-o,--output", output,
                  "output folder (created if missing); default 'output', or with --restart the run folder of the restart file");
  run->add_option("-t,--threads", threads, "OpenMP threads (0 = all cores)")->check(CLI::NonNegativeNumber);
  run->add_option("--set", sets, "override a case value by its dotted path, e.g. --set particles.dx=0.005")
      ->allow_extra_args(false);
  run->add_flag("-q,--quiet", quiet, "no progress line");
  run->add_option("--max-steps", max_steps, "stop after N steps (benchmarks)")->check(CLI::NonNegativeNumber);
  run->add_flag("--no-output", no_output, "write no snapshots or gauges, only summary.json (benchmarks)");
  run->add_option("--restart", restart,
                  "resume from a restart point: any snapshot (OUTPUT/snapshots/snap_NNNNNN.h5) or OUTPUT/checkpoint.h5; "
                  "same case and --set options (time.end may grow)");
  run->add_option("--checkpoint-every", checkpoint_every,
                  "wall seconds between OUTPUT/checkpoint.h5 writes (0 = never; SIGINT/SIGTERM always write one)")
      ->check(CLI::NonNegativeNumber)->capture_default_str();

  auto* check = app.add_subcommand("check", "read a case, report particle counts and the time step; run nothing");
  check->add_option("case", case_file, "case file (YAML)")->required();
  check->add_option("--set", sets, "override a case value by its dotted path")->allow_extra_args(false);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int rc = app.exit(e);
    return rc == 0 ? 0 : 2;
  }

  try {
    const sph::Case c = sph::load_case(case_file, sets);
    for (const auto& w : c.warnings) fmt::print(stderr, "warning: {}\n", w);
    if (check->parsed()) {
      fmt::print("{}", sph::check_case(c));
      return 0;
    }
    sph::RunOptions o;
    if (output.empty()) {  // a restart continues in its own run folder
      output = "output";
      if (!restart.empty()) {
        const std::filesystem::path dir = std::filesystem::absolute(restart).parent_path();
        output = (dir.filename() == "snapshots" ? dir.parent_path() : dir).string();
      }
    }
    o.output = output;
    o.restart = restart;
    o.checkpoint_every = checkpoint_every;
    o.threads = threads;
    o.progress = !quiet;
    o.version = SPHFLUME_VERSION;
    o.max_steps = max_steps;
    o.write_output = !no_output;
    const auto r = sph::run_case(c, o);
    return r.exit_code;
  } catch (const sph::InputError& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return 2;
  } catch (const sph::IoError& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return 3;
  } catch (const sph::SimulationError& e) {
    fmt::print(stderr, "error: the simulation failed: {}\n", e.what());
    return 3;
  } catch (const std::exception& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return 3;
  }
}
