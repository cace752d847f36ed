// The end of a run (sim/summary.hpp).
#include "sphflume/sim/summary.hpp"

#include <filesystem>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "sphflume/io/h5util.hpp"
#include "sphflume/sim/ranks.hpp"

namespace sph {
namespace fs = std::filesystem;

template <int D>
void finish_result(const Run<D>& R, LoopCounters n, double wall, RunResult& res) {
  const System<D>& S = R.S;
  res.steps = n.steps;
  res.wall_seconds = wall;
  {  // totals over the ranks
    std::uint64_t cnt[3] = {S.particles.count(Kind::Fluid), S.particles.n_owned(), n.pairs};
    S.comm->sum(cnt, 3);
    double ps[2] = {n.particle_steps, n.fluid_particle_steps};
    S.comm->sum(ps, 2);
    res.fluid = cnt[0];
    res.total = cnt[1];
    n.pairs = cnt[2];
    n.particle_steps = ps[0];
    n.fluid_particle_steps = ps[1];
  }
  res.particle_steps_per_second = wall > 0 ? n.particle_steps / wall : 0.0;
  res.fluid_particle_steps_per_second = wall > 0 ? n.fluid_particle_steps / wall : 0.0;
  res.pair_interactions_per_second = wall > 0 ? static_cast<double>(n.pairs) / wall : 0.0;
  res.bytes_per_particle = static_cast<double>(S.particles.bytes() + S.cells.bytes() + R.scheme->bytes() + S.walls->bytes()) /
                           static_cast<double>(std::max<std::size_t>(1, res.total));
  const Totals<D> tot(S, R.rs);
  const double m0 = R.rs.initial_mass;
  res.mass_error = m0 > 0 ? (m0 + tot.inflow - tot.outflow - tot.backflow_mass - tot.removed_mass - tot.final_mass) / m0 : 0.0;
}

/// Every rank calls it (the totals are reductions); the first rank writes the file.
template <int D>
void write_summary(const RunOptions& o, const Case& c, const Run<D>& R, const Summary& sm, const RunResult& res) {
  const System<D>& S = R.S;
  const RunState& rs = R.rs;
  const Totals<D> tot(S, rs);
  const RankStats ranks = rank_stats(S, res.steps);
  std::vector<std::uint64_t> per(static_cast<std::size_t>(S.levels) + 1, 0);  // fluid per resolution level
  if (S.levels > 0) {
    const auto& lv = S.particles.require(field::level);
    for (std::size_t i = 0; i < S.particles.n_owned(); ++i)
      if (S.particles.kind[i] == Kind::Fluid) ++per[static_cast<std::size_t>(lv[i])];
    S.comm->sum(per.data(), per.size());
  }
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
  j["cpu_seconds"] = sm.cpu;
  j["snapshot_seconds"] = sm.snapshot_seconds;
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
  if (S.levels > 0)  // resolution levels: the splits and merges of the run (physics/resolution.hpp)
    j["resolution"] = {{"levels", S.levels}, {"fluid_per_level", per}, {"splits", rs.splits}, {"merges", rs.merges}};
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
void print_report(const RunOptions& o, const Run<D>& R, const RunResult& res, const std::string& failure,
                  const std::string& last_good) {
  const System<D>& S = R.S;
  const Totals<D> tot(S, R.rs);
  const std::uint64_t walls_total = tot[Kind::Wall];
  if (!S.comm->root()) {  // (the first rank reports the run; the others only their own failure)
    if (res.exit_code != 0 && !failure.empty()) fmt::print(stderr, "rank {}: {}\n", S.comm->rank(), failure);
    return;
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
             res.total, res.fluid, walls_total, res.steps, S.time, hms(res.wall_seconds),
             res.particle_steps_per_second / 1e6, res.pair_interactions_per_second / 1e6, res.bytes_per_particle,
             thread_count(), res.mass_error,
             faces.empty() ? "" : fmt::format(" (particles left the domain and were removed: {})", faces),
             fs::absolute(o.output).string());
}

#define SPHFLUME_INSTANTIATE(D)                                                                                  \
  template void finish_result<D>(const Run<D>&, LoopCounters, double, RunResult&);                              \
  template void write_summary<D>(const RunOptions&, const Case&, const Run<D>&, const Summary&, const RunResult&); \
  template void print_report<D>(const RunOptions&, const Run<D>&, const RunResult&, const std::string&, const std::string&);
SPHFLUME_INSTANTIATE(2)
SPHFLUME_INSTANTIATE(3)
#undef SPHFLUME_INSTANTIATE

}  // namespace sph
