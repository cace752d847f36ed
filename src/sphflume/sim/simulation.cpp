#include "sphflume/sim/simulation.hpp"

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>

#include <fmt/format.h>
#ifdef _OPENMP
#include <omp.h>
#endif

#include "sphflume/boundaries/walls.hpp"
#include "sphflume/io/gauges.hpp"
#include "sphflume/io/geometry.hpp"
#include "sphflume/io/snapshot.hpp"
#include "sphflume/physics/force_terms.hpp"
#include "sphflume/schemes/scheme.hpp"

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

std::string json_escape(const std::string& in) {
  std::string s;
  for (char ch : in) {
    if (ch == '"' || ch == '\\') s += '\\';
    if (ch == '\n') { s += "\\n"; continue; }
    s += ch;
  }
  return s;
}

std::string hms(double s) {
  if (!std::isfinite(s) || s < 0) return "--:--:--";
  const long t = std::lround(s);
  return fmt::format("{:02d}:{:02d}:{:02d}", t / 3600, (t / 60) % 60, t % 60);
}

template <int D>
void setup(const Case& c, System<D>& S, BuildReport& rep, std::unique_ptr<Scheme<D>>& scheme) {
  rep = build_system<D>(c, S);
  try {
    S.walls = wall_registry<D>().create(c.walls.type, c.walls);
    scheme = scheme_registry<D>().create(c.scheme.type, c);
  } catch (const std::invalid_argument& e) {
    throw InputError(fmt::format("{}: {}", c.file, e.what()));
  }
  if (c.forces.IsDefined())
    for (std::size_t i = 0; i < c.forces.size(); ++i) {
      const YAML::Node n = c.forces[i];
      const std::string where = fmt::format("{}: line {}: forces.{}", c.file, n.Mark().line + 1, i);
      if (!n.IsMap() || !n["type"]) throw InputError(where + ": expected {type: NAME, ...}");
      try {
        S.forces.push_back(force_registry<D>().create(n["type"].as<std::string>(), n, where));
      } catch (const std::invalid_argument& e) {
        throw InputError(fmt::format("{}: {}", where, e.what()));
      } catch (const YAML::Exception& e) {
        throw InputError(fmt::format("{}: {}", where, e.msg));
      }
    }
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

template <int D>
RunResult run_dim(const Case& c, const RunOptions& o) {
  System<D> S;
  BuildReport rep;
  std::unique_ptr<Scheme<D>> scheme;
  setup(c, S, rep, scheme);
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
  // a re-run into the same folder must not leave snapshots of an earlier, longer run behind
  if (o.write_output && fs::exists(o.output + "/snapshots"))
    for (const auto& e : fs::directory_iterator(o.output + "/snapshots", ec))
      if (e.path().extension() == ".h5" || e.path().extension() == ".tmp") fs::remove(e.path(), ec);

  Vec<D> lo, hi;
  domain_box(c, S, lo, hi);
  const double m0 = S.total_mass(Kind::Fluid);
  double removed_mass = 0.0;
  std::map<std::string, long> removed_by_face;

  SnapshotWriter<D> snaps(o.output);
  std::unique_ptr<GaugeSet<D>> gauges;
  if (o.write_output) gauges = std::make_unique<GaugeSet<D>>(c.gauges, o.output, hi[D - 1]);

  const auto t0 = std::chrono::steady_clock::now();
  auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };
  RunResult res;
  std::uint64_t pairs_total = 0;
  std::string status = "done";
  std::string failure;

  auto output = [&] {
    if (!o.write_output) return;
    S.update_neighbours();
    snaps.write(S.particles, S.time, S.step);
    gauges->sample(S);
  };

  const bool tty = isatty(fileno(stderr));
  double last_progress = 0.0;
  double dt = 0.0, dt_first = 0.0;
  long steps_done = 0;
  double particle_steps = 0.0, fluid_particle_steps = 0.0;
  try {
    scheme->initialise(S);
    output();
    double next_out = c.output_interval;
    dt_first = scheme->time_step(S);
    while (S.time < c.t_end * (1.0 - 1e-12) && (o.max_steps == 0 || steps_done < o.max_steps)) {
      dt = scheme->time_step(S);
      if (!(dt > 1e-4 * dt_first))
        throw SimulationError(fmt::format("time step collapsed to {:.3g} s (started at {:.3g} s) at step {}, t = {:.6g} s: "
                                          "particles are being accelerated violently (check walls and the sound speed)",
                                          dt, dt_first, S.step, S.time));
      const double to_out = std::min(next_out, c.t_end) - S.time;
      if (dt > to_out && to_out > 1e-12 * dt) dt = to_out;
      scheme->step(S, dt);
      ++steps_done;
      pairs_total += S.pairs_last_pass * static_cast<std::uint64_t>(scheme->passes_per_step());
      const std::size_t n_owned = S.particles.n_owned();
      particle_steps += static_cast<double>(n_owned);
      // particles that left the domain are removed and counted per face
      {
        auto& P = S.particles;
        std::vector<char> flag;
        for (std::size_t i = 0; i < P.n_owned(); ++i) {
          if (P.kind[i] != Kind::Fluid) continue;
          for (int d = 0; d < D; ++d) {
            if (S.periodic.axis[d]) continue;
            if (P.pos[i][d] < lo[d] || P.pos[i][d] > hi[d]) {
              if (flag.empty()) flag.assign(P.n_owned(), 0);
              flag[i] = 1;
              removed_mass += P.mass[i];
              ++removed_by_face[fmt::format("{}{}", "xyz"[D == 2 && d == 1 ? 2 : d], P.pos[i][d] < lo[d] ? "-" : "+")];
              break;
            }
          }
        }
        if (!flag.empty()) { P.clear_images(); P.remove_if_flagged(flag); }
      }
      fluid_particle_steps += static_cast<double>(S.particles.count(Kind::Fluid));
      const bool last = S.time >= c.t_end * (1.0 - 1e-12);
      if (S.time >= next_out * (1.0 - 1e-9) || last) {
        output();
        while (next_out <= S.time * (1.0 + 1e-9)) next_out += c.output_interval;
      }
      const double w = elapsed();
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
    S.particles.clear_images();
    if (o.write_output) try { snaps.write(S.particles, S.time, S.step); } catch (const std::exception&) {}
  }
  if (o.progress && tty) fmt::print(stderr, "\n");
  const double wall = elapsed();
  S.particles.clear_images();
  const double m1 = S.total_mass(Kind::Fluid);

  res.steps = steps_done;
  res.wall_seconds = wall;
  res.fluid = S.particles.count(Kind::Fluid);
  res.total = S.particles.n_owned();
  res.particle_steps_per_second = wall > 0 ? particle_steps / wall : 0.0;
  res.fluid_particle_steps_per_second = wall > 0 ? fluid_particle_steps / wall : 0.0;
  res.pair_interactions_per_second = wall > 0 ? static_cast<double>(pairs_total) / wall : 0.0;
  res.bytes_per_particle = static_cast<double>(S.particles.bytes() + S.cells.bytes() + scheme->bytes()) /
                           static_cast<double>(std::max<std::size_t>(1, res.total));
  res.mass_error = m0 > 0 ? (m0 - removed_mass - m1) / m0 : 0.0;

  std::string faces;
  for (const auto& [f, n] : removed_by_face) faces += fmt::format("{}\"{}\": {}", faces.empty() ? "" : ", ", f, n);
  std::string json = "{\n";
  json += fmt::format("  \"version\": \"{}\",\n  \"case\": \"{}\",\n  \"case_file\": \"{}\",\n", o.version, json_escape(c.name), json_escape(c.file));
  json += fmt::format("  \"dimension\": {},\n  \"scheme\": \"{}\",\n  \"kernel\": \"{}\",\n", D, scheme->name(), kernel_name(c.kernel));
  json += fmt::format("  \"integrator\": \"{}\",\n  \"passes_per_step\": {},\n",
                      c.scheme.integrator == Integrator::Verlet ? "verlet"
                      : c.scheme.integrator == Integrator::Symplectic ? "symplectic" : "predictor_corrector",
                      scheme->passes_per_step());
  json += fmt::format("  \"dx\": {:.9g},\n  \"h\": {:.9g},\n  \"sound_speed\": {:.9g},\n", S.dx, S.h, S.eos.c0);
  json += fmt::format("  \"particles\": {{\"fluid\": {}, \"wall\": {}, \"inflow\": {}, \"outflow\": {}, \"total\": {}, \"initial_fluid\": {}}},\n",
                      S.particles.count(Kind::Fluid), S.particles.count(Kind::Wall), S.particles.count(Kind::Inflow),
                      S.particles.count(Kind::Outflow), res.total, rep.fluid);
  json += fmt::format("  \"steps\": {},\n  \"simulated_time\": {:.9g},\n  \"end_time\": {:.9g},\n  \"wall_seconds\": {:.6g},\n  \"threads\": {},\n",
                      res.steps, S.time, c.t_end, wall, thread_count());
  json += fmt::format("  \"particle_steps_per_second\": {:.6g},\n  \"fluid_particle_steps_per_second\": {:.6g},\n",
                      res.particle_steps_per_second, res.fluid_particle_steps_per_second);
  json += fmt::format("  \"pair_interactions_per_second\": {:.6g},\n  \"bytes_per_particle\": {:.1f},\n",
                      res.pair_interactions_per_second, res.bytes_per_particle);
  json += fmt::format("  \"last_dt\": {:.6g},\n  \"snapshots\": {},\n", dt, snaps.count());
  json += fmt::format("  \"mass\": {{\"initial\": {:.17g}, \"inflow\": 0, \"outflow\": 0, \"removed\": {:.17g}, \"final\": {:.17g}, \"relative_error\": {:.3e}}},\n",
                      m0, removed_mass, m1, res.mass_error);
  json += fmt::format("  \"removed_particles\": {{{}}},\n", faces);
  json += fmt::format("  \"exit_status\": \"{}\",\n  \"exit_code\": {},\n  \"message\": \"{}\"\n}}\n", status, res.exit_code,
                      json_escape(failure));
  write_file_atomically(o.output + "/summary.json", json);

  if (res.exit_code != 0) fmt::print(stderr, "error: the simulation failed: {}\nlast state written to {}/\n", failure, o.output);
  fmt::print("{} particles ({} fluid, {} wall), {} steps, simulated {:.4g} s in {} wall ({:.2f} M particle-steps/s, "
             "{:.1f} M pair interactions/s, {:.0f} bytes/particle, {} threads)\nmass error {:.2e}{}\noutput: {}\n",
             res.total, res.fluid, S.particles.count(Kind::Wall), res.steps, S.time, hms(wall),
             res.particle_steps_per_second / 1e6, res.pair_interactions_per_second / 1e6, res.bytes_per_particle,
             thread_count(), res.mass_error,
             removed_by_face.empty() ? "" : fmt::format(" ({} particles left the domain and were removed: {})",
                                                         rep.fluid - res.fluid, faces),
             fs::absolute(o.output).string());
  return res;
}

template <int D>
std::string check_dim(const Case& c) {
  System<D> S;
  BuildReport rep;
  std::unique_ptr<Scheme<D>> scheme;
  setup(c, S, rep, scheme);
  scheme->initialise(S);
  const double dt = scheme->time_step(S);
  std::string s;
  s += fmt::format("case '{}' ({}D, {}, scheme {}, walls {})\n", c.name, D, c.file, scheme->name(), c.walls.type);
  s += fmt::format("particles: {} fluid, {} wall ({} layers), {} in all", rep.fluid, rep.wall, rep.wall_layers, rep.fluid + rep.wall);
  if (rep.fluid_dropped_in_walls) s += fmt::format("; {} fluid lattice points inside walls were left out", rep.fluid_dropped_in_walls);
  s += fmt::format("\ndx = {} m, kernel {} with h = {:.4g} m (h/dx = {}), support {:.4g} m\n", c.dx, kernel_name(c.kernel), S.h, c.h_over_dx, S.support);
  s += fmt::format("sound speed c0 = {:.4g} m/s, fluid height {:.4g} m\n", S.eos.c0, rep.fluid_height);
  s += fmt::format("estimated time step {:.3e} s: about {:.0f} steps to t = {} s, {} snapshots\n", dt, std::ceil(c.t_end / dt), c.t_end,
                   static_cast<long>(std::floor(c.t_end / c.output_interval + 1e-9)) + 1);
  return s;
}

}  // namespace

RunResult run_case(const Case& c, const RunOptions& o) {
  return c.dimension == 2 ? run_dim<2>(c, o) : run_dim<3>(c, o);
}

std::string check_case(const Case& c) { return c.dimension == 2 ? check_dim<2>(c) : check_dim<3>(c); }

}  // namespace sph
