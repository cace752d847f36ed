#include <algorithm>

#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseCore>

#include "sphflume/schemes/pressure_solver.hpp"

namespace sph {
namespace {

class EigenBicgstab final : public PressureSolver {
 public:
  EigenBicgstab(double tol, int maxit) : tol_(tol), maxit_(maxit) {}
  const char* name() const override { return "eigen_bicgstab"; }

  SolveReport solve(const SparseRows& s, std::vector<double>& x) override {
    const auto n = static_cast<Eigen::Index>(s.rows());
    SolveReport rep;
    rep.unknowns = s.rows();
    rep.nonzeros = s.nonzeros();
    if (x.size() != s.rows()) x.assign(s.rows(), 0.0);
    if (n == 0) { rep.converged = true; return rep; }
    // the rows are assembled in order: map them as a row-major matrix without copying
    outer_.assign(s.start.begin(), s.start.end());
    Eigen::Map<const Eigen::SparseMatrix<double, Eigen::RowMajor, int>> A(
        n, n, static_cast<Eigen::Index>(s.nonzeros()), outer_.data(), s.col.data(), s.val.data());
    Eigen::Map<const Eigen::VectorXd> b(s.rhs.data(), n);
    Eigen::Map<Eigen::VectorXd> xv(x.data(), n);
    solver_.setTolerance(std::max(tol_, s.tolerance));
    solver_.setMaxIterations(maxit_);
    solver_.compute(A);
    const Eigen::VectorXd guess = xv;
    xv = solver_.solveWithGuess(b, guess);
    rep.iterations = static_cast<int>(solver_.iterations());
    const double bn = b.norm();
    rep.residual = bn > 0.0 ? (b - A * xv).norm() / bn : (A * xv).norm();
    rep.converged = solver_.info() == Eigen::Success && std::isfinite(rep.residual);
    bytes_ = s.nonzeros() * (sizeof(double) + sizeof(int)) + s.rows() * (sizeof(int) + 9 * sizeof(double));
    return rep;
  }
  std::size_t bytes() const override { return bytes_; }

 private:
  double tol_;
  int maxit_;
  std::vector<int> outer_;
  std::size_t bytes_ = 0;
  Eigen::BiCGSTAB<Eigen::SparseMatrix<double, Eigen::RowMajor, int>, Eigen::DiagonalPreconditioner<double>> solver_;
};

}  // namespace

std::unique_ptr<PressureSolver> make_eigen_solver(double tolerance, int max_iterations) {
  return std::make_unique<EigenBicgstab>(tolerance, max_iterations);
}

}  // namespace sph
