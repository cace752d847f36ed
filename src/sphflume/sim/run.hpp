// A run's system and its deterministic step (sim/, internal): Run<D> owns the System built by
// setup_system, the open boundaries and the restart state; advance() is everything a restart or
// a replay must reproduce bit for bit. Used by the driver (simulation.cpp), the output policy
// (output.cpp) and the summary (summary.cpp).
#pragma once
#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "sphflume/boundaries/motion.hpp"
#include "sphflume/boundaries/open_boundary.hpp"
#include "sphflume/boundaries/walls.hpp"
#include "sphflume/physics/force_terms.hpp"
#include "sphflume/physics/multiphase.hpp"
#include "sphflume/physics/resolution.hpp"
#include "sphflume/io/restart.hpp"
#include "sphflume/physics/transport.hpp"
#include "sphflume/schemes/scheme.hpp"
#include "sphflume/setup/setup.hpp"
#include "sphflume/sim/health.hpp"

namespace sph {

/// OpenMP threads of this process (1 without OpenMP).
int thread_count();
/// Seconds as hh:mm:ss ("--:--:--" when unknown).
std::string hms(double s);

/// The box particles must stay in: the case's domain, or the initial bounding box with
/// room above for splashes.
template <int D>
inline void domain_box(const Case& c, const System<D>& S, Vec<D>& lo, Vec<D>& hi) {
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
    limits.causes = scheme->failure_causes();
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
    if (S.motion) S.motion->restore(rs.scheme);  // active absorption's state ("motion.NAME.KEY")
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
    if (S.motion)
      for (const auto& [k, v] : S.motion->state()) r.scheme[k] = v;
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
          "that); {} has the largest acceleration, |a| = {:.3g} m/s2; likely cause: {}",
          S.step, S.time, dt, rs.dt_first, kDtFloor, describe_particle(S, i), norm(S.particles.acc[i]),
          scheme->failure_causes() ? scheme->failure_causes()
                                   : "particles accelerated violently, by penetrating a wall or colliding (raise "
                                     "fluid.sound_speed, lower scheme.cfl, check the walls)"));
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
    if (S.resolution) adapt_levels_now();
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

  /// Resolution levels: split and merge where the particles' places want another level
  /// (physics/resolution.hpp), then re-sort as remove_escaped does.
  void adapt_levels_now() {
    const AdaptCounts k = S.resolution->adapt(S, rs.open.next_id);
    std::uint64_t n[2] = {k.split, k.merged};
    S.comm->sum(n, 2);  // (every rank counts the run's splits and merges, and re-sorts if any rank changed)
    if (n[0] == 0 && n[1] == 0) return;
    rs.splits += static_cast<long>(n[0]);
    rs.merges += static_cast<long>(n[1]);
    S.update_neighbours();
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
          const std::string face = fmt::format("{}{}", "xyz"[D == 2 && d == 1 ? 2 : d], P.pos[i][d] < lo[d] ? "-" : "+");
          ++rs.removed_by_face[face];
          rs.removed_mass_by_face[face] += P.mass[i];
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

}  // namespace sph
