#include "sphflume/schemes/isph_common.hpp"

namespace sph {

SchemeConfig isph_force_config(const Case& c) {
  SchemeConfig f = c.scheme;
  f.pressure = false;
  f.density_diffusion = DensityDiffusion::None;
  f.delta = 0.0;
  f.xsph = 0.0;
  f.shifting = ShiftingConfig{};
  f.frozen = false;
  f.viscosity = !c.isph.viscosity ? ViscosityModel::None
                : c.isph.laminar ? ViscosityModel::Laminar : ViscosityModel::Artificial;
  f.alpha = c.isph.viscosity ? c.isph.alpha : 0.0;
  f.alpha_on_laminar = c.isph.viscosity && c.isph.laminar ? c.isph.alpha : 0.0;
  f.eta2 = c.isph.eta2;
  return f;
}

std::string isph_distributed_refusal(const IsphConfig& o) {
  if (!have_hypre())
    return "the ISPH scheme without hypre (its pressure equation across ranks is solved by hypre: install "
           "libhypre-dev and rebuild)";
  if (!o.amg && !o.solver_auto)
    return "scheme.solver.type: bicgstab (Eigen's solver holds the whole system in one process: use "
           "scheme.solver.type: boomeramg or auto, hypre over every rank's rows)";
  return {};
}

namespace {
// lind's V-cycle: aggressive coarsening on the first level (its solve 13 % cheaper on the a/80 dam break at the same
// tolerance) and one Gauss–Seidel sweep each way (11 % cheaper at a/40; the dam break's front, Martin & Moyce's
// RMS and the wall pressure's high-frequency content within their run-to-run scatter, bench/README.md, session 26);
// Tsurudome's formulation keeps the hierarchy its results were measured with
AmgCycle amg_cycle(const IsphConfig& o) {
  return o.formulation == IsphFormulation::Lind ? AmgCycle{1, true} : AmgCycle{};
}
}  // namespace

IsphSolver::IsphSolver(const IsphConfig& o)
    : o_(o), solver_(o.amg ? make_hypre_solver(o.tolerance, o.max_iterations, false, amg_cycle(o))
                           : make_eigen_solver(o.tolerance, o.max_iterations)) {}

void IsphSolver::prepare(bool distributed) {
  if (o_.solver_auto && !chosen_) {
    // solver.type auto: hypre's BoomerAMG whenever the build has it (its hierarchy reused over
    // steps: faster than Eigen's Jacobi BiCGSTAB from 1 k unknowns on, docs/numerics.md §13)
    chosen_ = true;
    if (have_hypre()) solver_ = make_hypre_solver(o_.tolerance, o_.max_iterations, false, amg_cycle(o_));
  }
  if (distributed && !all_ranks_) {  // a distributed run: hypre over every rank's rows
    solver_ = make_hypre_solver(o_.tolerance, o_.max_iterations, true, amg_cycle(o_));
    all_ranks_ = chosen_ = true;
  }
}

void IsphSolver::solve(const SparseRows& sys, std::vector<double>& x, PpeStats& st, long step, double time,
                       const char* what, double tolerance) {
  const auto t1 = std::chrono::steady_clock::now();
  const SolveReport rep = solver_->solve(sys, x);
  st.solve_s += seconds_since(t1);
  ++st.solves;
  st.iterations += rep.iterations;
  st.max_iterations = std::max(st.max_iterations, rep.iterations);
  st.max_residual = std::max(st.max_residual, rep.residual);
  st.unknowns = rep.unknowns;
  st.nonzeros = rep.nonzeros;
  if (!rep.converged)
    throw SimulationError(fmt::format(
        "at step {}, t = {:.6g} s: the {} did not converge ({} unknowns, {} iterations, relative residual {:.3g} > "
        "scheme.solver.tolerance {:.3g}); likely causes: a time step too large for the flow (lower scheme.cfl, or "
        "set scheme.dt_max), particles packed into a wall (check the walls and the fill), or a tolerance tighter "
        "than the solver reaches (raise scheme.solver.tolerance or scheme.solver.max_iterations)",
        step, time, what, rep.unknowns, rep.iterations, rep.residual, tolerance));
}

}  // namespace sph
