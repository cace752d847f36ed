// The linear solver behind a projection scheme's pressure Poisson equation (PPE). The scheme
// assembles A x = b in compressed-row form (one row per pressure unknown) and hands it over; a
// solver solves it from a warm start and reports what it did. The Eigen solver (BiCGSTAB with a
// diagonal preconditioner) implements it for one process; a distributed solver (hypre) can
// implement the same interface.
#pragma once
#include <cstddef>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace sph {

/// A sparse system in compressed-row form: row r's entries are col[start[r] .. start[r+1]).
/// In a distributed run each rank holds its own rows, first_row.. of the global system, and the
/// columns are global unknown numbers (one process: first_row 0).
struct SparseRows {
  std::size_t first_row = 0;
  std::vector<std::size_t> start{0};
  std::vector<int> col;
  std::vector<double> val;
  std::vector<double> rhs;
  /// True when row r is the same particle from one system to the next (rows numbered by particle
  /// identity, P = 0 particles kept as identity rows): a solver may then precondition a system with
  /// what it built for an earlier one of the same size (hypre: the BoomerAMG hierarchy).
  bool stable_rows = false;
  /// Build the preconditioner for this system even where an earlier one could serve: the scheme has just
  /// written a restart point, and a run restarted there starts with none (restarts stay bitwise).
  bool fresh = false;
  /// The relative residual this system needs, when looser than the solver's own (0: the solver's).
  double tolerance = 0.0;
  std::size_t rows() const { return start.size() - 1; }
  std::size_t nonzeros() const { return col.size(); }
  /// The matrix from rows of (column, value) entries, in row order (the right-hand side apart).
  void set_rows(const std::vector<std::vector<std::pair<int, double>>>& rows) {
    start.resize(rows.size() + 1);
    start[0] = 0;
    for (std::size_t r = 0; r < rows.size(); ++r) start[r + 1] = start[r] + rows[r].size();
    col.resize(start.back());
    val.resize(start.back());
#pragma omp parallel for schedule(static)
    for (std::size_t r = 0; r < rows.size(); ++r) {
      std::size_t k = start[r];
      for (const auto& [c, v] : rows[r]) {
        col[k] = c;
        val[k++] = v;
      }
    }
  }
};

struct SolveReport {
  int iterations = 0;
  bool setup = true;  // the preconditioner was built for this system (false: an earlier one reused)
  double residual = 0.0;  // |b − A x| / |b| at the end
  bool converged = false;
  std::size_t unknowns = 0, nonzeros = 0;
};

class PressureSolver {
 public:
  virtual ~PressureSolver() = default;
  virtual const char* name() const = 0;
  /// Solve `sys` for x; x holds the warm start on entry (resized with zeros if it does not fit).
  virtual SolveReport solve(const SparseRows& sys, std::vector<double>& x) = 0;
  /// Bytes the solver holds (matrix copies, preconditioner, Krylov vectors).
  virtual std::size_t bytes() const = 0;
  /// True when the solver keeps its preconditioner for the next system of SparseRows::stable_rows.
  virtual bool reuses_preconditioner() const { return false; }
};

/// Eigen's BiCGSTAB with a Jacobi (diagonal) preconditioner: the matrix is not symmetric once
/// the dummy wall particles are folded into their wall particle's unknown.
std::unique_ptr<PressureSolver> make_eigen_solver(double tolerance, int max_iterations);

/// hypre's BiCGSTAB with a BoomerAMG V-cycle as the preconditioner (scheme.solver.type: boomeramg),
/// when SPHFlume was built with hypre (have_hypre()). all_ranks: the system is distributed over
/// the ranks of MPI_COMM_WORLD (each passes its rows; every rank calls solve), else one process's.
/// cycle: BoomerAMG's V-cycle as a formulation tunes it (the defaults: Tsurudome's, as its results were measured).
struct AmgCycle {
  int aggressive_levels = 0;    // levels coarsened aggressively (0: none)
  bool one_way_sweeps = false;  // one forward Gauss–Seidel sweep down and one backward up, instead of a
                                // symmetric sweep (forward and backward) each way: half the smoothing
};
bool have_hypre();
std::unique_ptr<PressureSolver> make_hypre_solver(double tolerance, int max_iterations, bool all_ranks = false,
                                                  AmgCycle cycle = {});

}  // namespace sph
