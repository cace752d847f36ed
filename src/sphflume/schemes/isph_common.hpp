// What the two formulations of the projection scheme share (schemes/isph.hpp: Tsurudome's;
// schemes/isph_projection.hpp: Lind, Skillen and Chow's): the time step, the pressure solver and its
// choice, the solve statistics written to summary.json, and the refusal of a distributed run.
#pragma once
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "sphflume/core/cell_list.hpp"
#include "sphflume/core/config.hpp"
#include "sphflume/core/errors.hpp"
#include "sphflume/core/system.hpp"
#include "sphflume/schemes/pressure_solver.hpp"

namespace sph {

/// What a failed ISPH run names as its likely causes (it has no sound speed to raise).
inline const char* isph_failure_causes() {
  return "a pressure solve that met particles with a nearly empty or disordered support (a jet or splash against "
         "a wall, particles pressed into or through a wall: check the walls and the geometry), or a step too large "
         "for the projection (lower scheme.cfl or set scheme.dt_max; ISPH has no sound speed)";
}

/// Counters of the pressure solves since the start of the run (summary.json "pressure_solver").
struct PpeStats {
  long solves = 0;
  long iterations = 0;
  int max_iterations = 0;
  double max_residual = 0.0;
  std::size_t unknowns = 0, nonzeros = 0, free_surface = 0;  // last solve
  double assemble_s = 0.0, solve_s = 0.0;
  double predict_s = 0.0, correct_s = 0.0;  // the force pass and prediction; the correction (+ shifting)
  long redone = 0;  // steps redone with a shorter Δt (the Courant check after prediction or correction)
  /// The restart state: these counters and the scheme's last largest acceleration.
  std::map<std::string, double> save(double amax) const {
    std::map<std::string, double> s{{"amax", amax}};
    s["ppe_solves"] = double(solves);
    s["ppe_iterations"] = double(iterations);
    s["ppe_max_iterations"] = double(max_iterations);
    s["ppe_max_residual"] = max_residual;
    s["redone_steps"] = double(redone);
    return s;
  }
  /// Puts back what save() wrote; returns the acceleration.
  double load(const std::map<std::string, double>& s) {
    auto get = [&](const char* k) { auto it = s.find(k); return it == s.end() ? 0.0 : it->second; };
    solves = static_cast<long>(get("ppe_solves"));
    iterations = static_cast<long>(get("ppe_iterations"));
    max_iterations = static_cast<int>(get("ppe_max_iterations"));
    max_residual = get("ppe_max_residual");
    redone = static_cast<long>(get("redone_steps"));
    return get("amax");
  }
  nlohmann::ordered_json json(const char* solver, double tolerance) const {
    const double mean = solves > 0 ? double(iterations) / double(solves) : 0.0;
    return {{"name", solver}, {"solves", solves}, {"mean_iterations", mean}, {"max_iterations", max_iterations},
            {"max_residual", max_residual}, {"tolerance", tolerance}, {"unknowns", unknowns}, {"nonzeros", nonzeros},
            {"free_surface", free_surface}, {"assemble_seconds", assemble_s}, {"solve_seconds", solve_s},
            {"predict_seconds", predict_s}, {"correct_seconds", correct_s}, {"redone_steps", redone}};
  }
};

inline double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/// Δt = min(cfl dx/|u|max, force_coefficient √(h/a), viscous_coefficient h²/ν, cap), a = max(|g|, amax),
/// cap = dt_max or cfl dx/(c0/10) (docs/numerics.md §13).
template <int D>
double isph_time_step(const System<D>& S, const IsphConfig& o, double amax) {
  const auto& P = S.particles;
  double umax2 = 0.0;
  const std::size_t n = P.n_owned();
#pragma omp parallel for schedule(static) reduction(max : umax2)
  for (std::size_t i = 0; i < n; ++i)
    if (P.kind[i] == Kind::Fluid) umax2 = std::max(umax2, dot(P.vel[i], P.vel[i]));
  double dt = std::numeric_limits<double>::infinity();
  if (umax2 > 0.0) dt = o.cfl * S.dx / std::sqrt(umax2);
  const double a = std::max(norm(S.gravity), amax);
  if (a > 0.0) dt = std::min(dt, o.force_coefficient * std::sqrt(S.h / a));
  if (o.viscosity && S.nu > 0.0) dt = std::min(dt, o.viscous_coefficient * S.h * S.h / S.nu);
  // the cap: the Courant limit at the flow's reference speed (c0/10), so that a flow starting from
  // rest does not take one long step into the walls
  dt = std::min(dt, o.dt_max > 0.0 ? o.dt_max : o.cfl * S.dx / (0.1 * S.eos.c0));
  if (!std::isfinite(dt)) dt = o.dt_max > 0.0 ? o.dt_max : o.cfl * S.dx;  // no flow, no gravity
  return dt;
}

/// The prediction's force pass: WCSPH's pair loop (the case's scheme options) without pressure, density
/// diffusion, XSPH or shifting, with the projection's viscosity options.
SchemeConfig isph_force_config(const Case& c);

/// The ISPH pair passes' padding on the pair-pass skeleton (core/pair_pass.hpp): 8 doubles (one AVX-512 vector,
/// two AVX2 ones).
constexpr std::size_t kIsphLanes = 8;

/// Particle p's position relative to the cell's origin (the gathered columns' frame: small differences keep their
/// digits).
template <int D>
[[gnu::always_inline]] inline void relative(const Vec<D>& p, const Vec<D>& origin, double& a0, double& a1, double& a2) {
  a0 = p[0] - origin[0];
  a1 = p[1] - origin[1];
  a2 = p[D - 1] - origin[D - 1];
}

/// The owned fluid and wall particles of a cell (the particles ISPH's passes run); the count.
template <int D>
inline std::size_t owned_in(const CellList<D>& cells, std::size_t cell, std::size_t n_owned, const Kind* kind, bool fluid_only) {
  const std::uint32_t* sorted = cells.sorted().data();
  std::size_t m = 0;
  for (std::uint32_t k = cells.cell_begin(cell); k < cells.cell_end(cell); ++k) {
    const std::uint32_t a = sorted[k];
    if (a < n_owned && (kind[a] == Kind::Fluid || (!fluid_only && kind[a] == Kind::Wall))) ++m;
  }
  return m;
}

/// A PPE row's entries with its diagonal in place, the columns ascending and repeated columns (a particle and
/// its periodic image, the dummies standing in for one foot) summed.
inline void finish_row(std::vector<std::pair<int, double>>& e, int me, double diag) {
  e.emplace_back(me, diag);
  // insertion sort: a row's 20–60 entries come in cell order, their columns (rows by particle id) mostly
  // ascending already, where std::sort's partitioning cost 2.8 % of a dam break's time (perf)
  for (std::size_t i = 1; i < e.size(); ++i) {
    const auto x = e[i];
    std::size_t j = i;
    for (; j > 0 && e[j - 1].first > x.first; --j) e[j] = e[j - 1];
    e[j] = x;
  }
  std::size_t w = 0;
  for (std::size_t r = 1; r < e.size(); ++r) {
    if (e[r].first == e[w].first) e[w].second += e[r].second;
    else e[++w] = e[r];
  }
  e.resize(w + 1);
}

/// finish_row without the sort, for solvers that take a row's columns in any order (hypre, Eigen's SpMV and
/// Jacobi): the diagonal first, the others in the order they came, repeated columns summed through a marker per
/// column (the lind rows' columns are numbered by particle id, so that they come in no order: the insertion sort
/// cost 10 % of a dam break's time, perf, session 26)
inline void finish_row_unsorted(std::vector<std::pair<int, double>>& e, int me, double diag) {
  thread_local std::vector<int> slot;  // column -> its place in the row, -1 elsewhere (left so on return)
  e.emplace_back(me, diag);
  std::swap(e.front(), e.back());
  std::size_t w = 0;
  for (std::size_t r = 0; r < e.size(); ++r) {
    const auto c = static_cast<std::size_t>(e[r].first);
    if (c >= slot.size()) slot.resize(std::max(c + 1, 2 * slot.size()), -1);
    if (slot[c] >= 0) {
      e[static_cast<std::size_t>(slot[c])].second += e[r].second;
      continue;
    }
    slot[c] = static_cast<int>(w);
    e[w++] = e[r];
  }
  e.resize(w);
  for (const auto& q : e) slot[static_cast<std::size_t>(q.first)] = -1;
}

/// A row whose columns are distinct (no periodic image or halo copy among the neighbours, no Robin part over the
/// same neighbours): the diagonal put first, nothing to sum.
inline void finish_row_distinct(std::vector<std::pair<int, double>>& e, int me, double diag) {
  e.emplace_back(me, diag);
  std::swap(e.front(), e.back());
}

/// Rows numbered by particle id (one process with hypre): every owned particle with has_row(i) gets row
/// row_of_id[id] in id order, so that row r is the same particle from step to step and the solver may reuse
/// its multigrid hierarchy (pressure_solver.hpp); unknown[i] set, the row count returned.
template <int D, class Pred>
int rows_by_id(const ParticleStore<D>& P, Pred&& has_row, std::vector<int>& row_of_id, std::vector<int>& unknown) {
  const std::size_t n = P.n_owned();
  std::uint32_t top = 0;
  for (std::size_t i = 0; i < n; ++i) top = std::max(top, P.id[i]);
  row_of_id.assign(std::size_t(top) + 1, -1);
  for (std::size_t i = 0; i < n; ++i)
    if (has_row(i)) row_of_id[P.id[i]] = 0;
  int k = 0;
  for (auto& r : row_of_id)
    if (r >= 0) r = k++;
  for (std::size_t i = 0; i < n; ++i)
    if (has_row(i)) unknown[i] = row_of_id[P.id[i]];
  return k;
}

/// Why the projection scheme, as configured, cannot run over several ranks (empty: it can).
std::string isph_distributed_refusal(const IsphConfig& o);

/// The PPE's solver as the options choose it: Eigen's BiCGSTAB, hypre's BoomerAMG-preconditioned
/// BiCGSTAB, or (auto) hypre whenever the build has it; over every rank's rows in a distributed run.
class IsphSolver {
 public:
  explicit IsphSolver(const IsphConfig& o);
  /// Called before each solve: settles the choice (auto; a distributed run).
  void prepare(bool distributed);
  /// Solves `sys` from the warm start in x; statistics into `st`; a solve that does not converge
  /// throws a SimulationError naming the step, the time and the likely causes.
  void solve(const SparseRows& sys, std::vector<double>& x, PpeStats& st, long step, double time, const char* what,
             double tolerance);
  const PressureSolver& get() const { return *solver_; }
  bool reuses_preconditioner() const { return solver_->reuses_preconditioner(); }

 private:
  IsphConfig o_;
  std::unique_ptr<PressureSolver> solver_;
  bool chosen_ = false, all_ranks_ = false;
};

}  // namespace sph
