// The PPE solved by hypre (Debian's libhypre-dev): BiCGSTAB preconditioned by one V-cycle of
// BoomerAMG, an algebraic multigrid whose iteration count stays nearly flat as the particle count
// grows (Jacobi-preconditioned Krylov solvers need ~N^(1/2) iterations on a 2D Poisson matrix).
// One process (MPI_COMM_SELF), or every rank of a distributed run with its own rows (MPI_COMM_WORLD).
// the C API only (OpenMPI's C++ bindings would need libmpi_cxx)
#define OMPI_SKIP_MPICXX 1
#define MPICH_SKIP_MPICXX 1
#include <mpi.h>

#include <HYPRE.h>
#include <HYPRE_IJ_mv.h>
#include <HYPRE_parcsr_ls.h>
#include <HYPRE_utilities.h>
// (hypre's internal header, for one process's matrix built directly: it warns under C++20 and -Wextra)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wvolatile"
#pragma GCC diagnostic ignored "-Wunused-parameter"
#pragma GCC diagnostic ignored "-Wpedantic"
#include <_hypre_parcsr_mv.h>
#pragma GCC diagnostic pop

#include <cmath>
#include <cstdint>
#include <algorithm>
#include <cstdlib>
#include <stdexcept>

#include "sphflume/schemes/pressure_solver.hpp"

namespace sph {
namespace {

/// MPI and hypre started once for the process (a serial run is an MPI singleton), stopped at exit.
void start_hypre() {
  static const bool started = [] {
    int init = 0;
    MPI_Initialized(&init);
    if (!init) {
      int provided = 0;
      MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
      std::atexit([] {
        int fin = 0;
        MPI_Finalized(&fin);
        if (!fin) {
          HYPRE_Finalize();
          MPI_Finalize();
        }
      });
    }
    HYPRE_Init();
    return true;
  }();
  (void)started;
}

/// A system matrix, made through hypre's IJ interface (a distributed run) or directly (one process).
struct Matrix {
  HYPRE_IJMatrix ij = nullptr;
  hypre_ParCSRMatrix* par = nullptr;
  void destroy() {
    if (ij) HYPRE_IJMatrixDestroy(ij);
    if (par) hypre_ParCSRMatrixDestroy(par);
    ij = nullptr;
    par = nullptr;
  }
};

/// One solve's vectors (right-hand side, solution, residual), destroyed together.
struct Vectors {
  HYPRE_IJVector made[3] = {nullptr, nullptr, nullptr};
  hypre_ParVector* par[3] = {nullptr, nullptr, nullptr};
  int count = 0;
  /// A one-process vector holding sign × v.
  HYPRE_ParVector local(const double* v, std::size_t n, double sign) {
    HYPRE_BigInt starts[2] = {0, static_cast<HYPRE_BigInt>(n)};
    hypre_ParVector* p = hypre_ParVectorCreate(MPI_COMM_SELF, static_cast<HYPRE_BigInt>(n), starts);
    hypre_ParVectorInitialize(p);
    double* d = hypre_VectorData(hypre_ParVectorLocalVector(p));
    for (std::size_t i = 0; i < n; ++i) d[i] = sign * v[i];
    par[count++] = p;
    return p;
  }
  /// A distributed vector through IJ (v already in hypre's sign).
  HYPRE_ParVector ij(MPI_Comm comm, HYPRE_Int lo, HYPRE_Int hi, const HYPRE_Int* rows, const double* v) {
    HYPRE_IJVector& V = made[count++];
    HYPRE_IJVectorCreate(comm, lo, hi, &V);
    HYPRE_IJVectorSetObjectType(V, HYPRE_PARCSR);
    HYPRE_IJVectorInitialize(V);
    HYPRE_IJVectorSetValues(V, hi - lo + 1, rows, v);
    HYPRE_IJVectorAssemble(V);
    HYPRE_ParVector p;
    HYPRE_IJVectorGetObject(V, reinterpret_cast<void**>(&p));
    return p;
  }
  void destroy() {
    for (auto& v : made)
      if (v) HYPRE_IJVectorDestroy(v);
    for (auto& v : par)
      if (v) hypre_ParVectorDestroy(v);
  }
};

/// One process's system as hypre's compressed rows, negated (−A, an M-matrix: what hypre's smoothers want), each
/// row's diagonal first (where hypre's smoothers read it); repeated columns are left as they are (the scheme sums
/// them: SparseRows).
hypre_ParCSRMatrix* local_matrix(const SparseRows& s) {
  const auto n = static_cast<HYPRE_Int>(s.rows());
  const auto nnz = static_cast<HYPRE_Int>(s.nonzeros());
  HYPRE_BigInt starts[2] = {0, n};
  hypre_ParCSRMatrix* A = hypre_ParCSRMatrixCreate(MPI_COMM_SELF, n, n, starts, starts, 0, nnz, 0);
  hypre_ParCSRMatrixInitialize(A);
  hypre_CSRMatrix* d = hypre_ParCSRMatrixDiag(A);
  HYPRE_Int* I = hypre_CSRMatrixI(d);
  HYPRE_Int* J = hypre_CSRMatrixJ(d);
  double* a = hypre_CSRMatrixData(d);
  int missing = 0;
#pragma omp parallel for schedule(static) reduction(max : missing)
  for (HYPRE_Int r = 0; r < n; ++r) {
    const std::size_t k0 = s.start[static_cast<std::size_t>(r)], k1 = s.start[static_cast<std::size_t>(r) + 1];
    I[r] = static_cast<HYPRE_Int>(k0);
    std::size_t dk = k1;  // the diagonal's place in the scheme's row (every scheme row has one: finish_row)
    for (std::size_t k = k0; k < k1; ++k)
      if (s.col[k] == r) { dk = k; break; }
    if (dk == k1) {
      missing = 1;
      continue;
    }
    J[k0] = r;
    a[k0] = -s.val[dk];
    std::size_t w = k0 + 1;
    for (std::size_t k = k0; k < k1; ++k)
      if (k != dk) {
        J[w] = s.col[k];
        a[w++] = -s.val[k];
      }
  }
  if (missing) {
    hypre_ParCSRMatrixDestroy(A);
    throw std::logic_error("hypre: a row of the pressure system has no diagonal entry");
  }
  I[n] = nnz;
  hypre_ParCSRMatrixSetNumNonzeros(A);
  hypre_MatvecCommPkgCreate(A);
  return A;
}

class HypreAmg final : public PressureSolver {
 public:
  HypreAmg(double tol, int maxit, bool all_ranks, AmgCycle cycle)
      : tol_(tol), maxit_(maxit), cycle_(cycle), comm_(all_ranks ? MPI_COMM_WORLD : MPI_COMM_SELF) {
    start_hypre();
  }
  const char* name() const override { return "hypre_boomeramg"; }

  SolveReport solve(const SparseRows& s, std::vector<double>& x) override {
    SolveReport rep;
    rep.unknowns = s.rows();
    rep.nonzeros = s.nonzeros();
    const auto n = static_cast<HYPRE_Int>(s.rows());
    const auto lo = static_cast<HYPRE_Int>(s.first_row), hi = lo + n - 1;  // this rank's rows (hi < lo: none)
    if (x.size() != s.rows()) x.assign(s.rows(), 0.0);
    std::uint64_t sizes[2] = {s.rows(), s.nonzeros()};
    if (comm_ != MPI_COMM_SELF) MPI_Allreduce(MPI_IN_PLACE, sizes, 2, MPI_UINT64_T, MPI_SUM, comm_);
    rep.unknowns = sizes[0];
    rep.nonzeros = sizes[1];
    if (sizes[0] == 0) { rep.converged = true; return rep; }  // (the same answer on every rank)
    // the matrix and the vectors: one process builds hypre's compressed rows directly from the scheme's (one copy;
    // through the IJ interface the a/40 dam break's solve took 25 % longer, bench/README.md, session 26); a
    // distributed run goes through IJ
    Matrix A;
    HYPRE_ParCSRMatrix pA;
    HYPRE_ParVector pb, px, pr;
    Vectors V;
    if (comm_ == MPI_COMM_SELF) {
      A.par = local_matrix(s);
      pA = A.par;
      pb = V.local(s.rhs.data(), s.rows(), -1.0);
      px = V.local(x.data(), s.rows(), 1.0);  // x: the warm start
      pr = V.local(s.rhs.data(), s.rows(), -1.0);
    } else {
      load(s, lo);
      HYPRE_IJMatrixCreate(comm_, lo, hi, lo, hi, &A.ij);
      HYPRE_IJMatrixSetObjectType(A.ij, HYPRE_PARCSR);
      HYPRE_IJMatrixSetRowSizes(A.ij, ncols_.data());
      HYPRE_IJMatrixInitialize(A.ij);
      HYPRE_IJMatrixSetValues(A.ij, n, ncols_.data(), rows_.data(), cols_.data(), vals_.data());
      HYPRE_IJMatrixAssemble(A.ij);
      HYPRE_IJMatrixGetObject(A.ij, reinterpret_cast<void**>(&pA));
      pb = V.ij(comm_, lo, hi, rows_.data(), rhs_.data());
      px = V.ij(comm_, lo, hi, rows_.data(), x.data());
      pr = V.ij(comm_, lo, hi, rows_.data(), rhs_.data());
    }

    // the hierarchy: rebuilt for this matrix, or the last one reused (rows numbered by particle,
    // same size, not too old, and the last solve not much slower than the one after the build).
    // The reused V-cycle smooths with this matrix on the finest level and the old Galerkin
    // products below it: a preconditioner for a nearby matrix, which the Krylov method corrects
    const bool reuse = s.stable_rows && !s.fresh && amg_ && sizes[0] == setup_rows_ && age_ < kMaxAge &&
                       last_its_ <= std::max(2 * setup_its_, setup_its_ + 3);
    if (!reuse) release_hierarchy();
    if (!amg_) make_amg();
    HYPRE_Solver krylov;
    HYPRE_ParCSRBiCGSTABCreate(comm_, &krylov);
    const double tol = std::max(tol_, s.tolerance);
    HYPRE_ParCSRBiCGSTABSetTol(krylov, tol);
    HYPRE_ParCSRBiCGSTABSetMaxIter(krylov, maxit_);
    HYPRE_ParCSRBiCGSTABSetPrintLevel(krylov, 0);
    HYPRE_ParCSRBiCGSTABSetPrecond(krylov, reinterpret_cast<HYPRE_PtrToParSolverFcn>(HYPRE_BoomerAMGSolve),
                                   reuse ? reinterpret_cast<HYPRE_PtrToParSolverFcn>(keep_hierarchy)
                                         : reinterpret_cast<HYPRE_PtrToParSolverFcn>(HYPRE_BoomerAMGSetup),
                                   amg_);
    HYPRE_ParCSRBiCGSTABSetup(krylov, pA, pb, px);
    HYPRE_ParCSRBiCGSTABSolve(krylov, pA, pb, px);
    HYPRE_Int its = 0;
    HYPRE_ParCSRBiCGSTABGetNumIterations(krylov, &its);
    HYPRE_ClearAllErrors();  // a non-convergence is judged below from the residual itself
    // the plain residual |b − A x| / |b| (of −A and −b: the same norms), over every rank's rows
    HYPRE_ParCSRMatrixMatvec(-1.0, pA, px, 1.0, pr);
    double rn = 0.0, bn = 0.0;
    HYPRE_ParVectorInnerProd(pr, pr, &rn);
    HYPRE_ParVectorInnerProd(pb, pb, &bn);
    if (comm_ == MPI_COMM_SELF) {
      const double* xs = hypre_VectorData(hypre_ParVectorLocalVector(px));
      std::copy(xs, xs + s.rows(), x.begin());
    } else {
      HYPRE_IJVectorGetValues(V.made[1], n, rows_.data(), x.data());
    }
    HYPRE_ParCSRBiCGSTABDestroy(krylov);
    V.destroy();
    if (reuse) {
      A.destroy();  // (the hierarchy keeps the matrix it was built from)
      ++age_;
    } else if (s.stable_rows) {
      setup_A_ = A;  // kept alive with its hierarchy
      setup_rows_ = sizes[0];
      setup_its_ = static_cast<int>(its);
      age_ = 0;
    } else {
      release_hierarchy();
      A.destroy();
    }
    last_its_ = static_cast<int>(its);
    rep.setup = !reuse;

    rep.iterations = static_cast<int>(its);
    rep.residual = bn > 0.0 ? std::sqrt(rn / bn) : std::sqrt(rn);
    // hypre's BiCGSTAB stops on its own (preconditioned) norm: allow a factor 10 on the plain one
    rep.converged = std::isfinite(rep.residual) && rep.residual <= 10.0 * tol;
    bytes_ = s.nonzeros() * (3 * sizeof(double) + 2 * sizeof(HYPRE_Int)) + s.rows() * 16 * sizeof(double);
    return rep;
  }
  std::size_t bytes() const override { return bytes_; }
  bool reuses_preconditioner() const override { return comm_ == MPI_COMM_SELF; }
  ~HypreAmg() override { release_hierarchy(); }

 private:
  static constexpr int kMaxAge = 25;  // solves a hierarchy serves at most
  static HYPRE_Int keep_hierarchy(HYPRE_Solver, HYPRE_ParCSRMatrix, HYPRE_ParVector, HYPRE_ParVector) { return 0; }
  /// The system as hypre's IJ arrays, negated: the scheme's Laplacian has a negative diagonal, and
  /// hypre's smoothers want −A (an M-matrix).
  void load(const SparseRows& s, HYPRE_Int lo) {
    ncols_.resize(s.rows());
    rows_.resize(s.rows());
    cols_.assign(s.col.begin(), s.col.end());
    vals_.resize(s.nonzeros());
    for (std::size_t r = 0; r < s.rows(); ++r) {
      rows_[r] = lo + static_cast<HYPRE_Int>(r);
      ncols_[r] = static_cast<HYPRE_Int>(s.start[r + 1] - s.start[r]);
    }
    for (std::size_t k = 0; k < s.nonzeros(); ++k) vals_[k] = -s.val[k];
    rhs_.resize(s.rows());
    for (std::size_t r = 0; r < s.rows(); ++r) rhs_[r] = -s.rhs[r];
  }
  void make_amg() {
    HYPRE_BoomerAMGCreate(&amg_);
    HYPRE_BoomerAMGSetPrintLevel(amg_, 0);
    HYPRE_BoomerAMGSetCoarsenType(amg_, 10);     // HMIS
    HYPRE_BoomerAMGSetInterpType(amg_, 6);       // extended+i
    HYPRE_BoomerAMGSetPMaxElmts(amg_, 4);
    HYPRE_BoomerAMGSetStrongThreshold(amg_, 0.25);
    HYPRE_BoomerAMGSetRelaxType(amg_, 8);        // l1 symmetric Gauss-Seidel
    HYPRE_BoomerAMGSetNumSweeps(amg_, 1);
    HYPRE_BoomerAMGSetMaxIter(amg_, 1);          // one V-cycle as the preconditioner
    HYPRE_BoomerAMGSetTol(amg_, 0.0);
    if (cycle_.aggressive_levels > 0)  // (with HMIS: multipass interpolation there)
      HYPRE_BoomerAMGSetAggNumLevels(amg_, cycle_.aggressive_levels);
    if (cycle_.one_way_sweeps) {  // hybrid Gauss–Seidel forward on the way down, backward on the way up
      HYPRE_BoomerAMGSetCycleRelaxType(amg_, 3, 1);
      HYPRE_BoomerAMGSetCycleRelaxType(amg_, 4, 2);
    }
  }
  void release_hierarchy() {
    if (amg_) HYPRE_BoomerAMGDestroy(amg_);
    setup_A_.destroy();
    amg_ = nullptr;
  }
  HYPRE_Solver amg_ = nullptr;
  Matrix setup_A_;
  std::uint64_t setup_rows_ = 0;
  int setup_its_ = 0, last_its_ = 0, age_ = 0;
  double tol_;
  int maxit_;
  AmgCycle cycle_;
  MPI_Comm comm_;
  std::vector<HYPRE_Int> ncols_, rows_, cols_;
  std::vector<double> vals_, rhs_;
  std::size_t bytes_ = 0;
};

}  // namespace

bool have_hypre() { return true; }

std::unique_ptr<PressureSolver> make_hypre_solver(double tolerance, int max_iterations, bool all_ranks,
                                                  AmgCycle cycle) {
  return std::make_unique<HypreAmg>(tolerance, max_iterations, all_ranks, cycle);
}

}  // namespace sph
