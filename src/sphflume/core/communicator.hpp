// The global reductions of a run: the time step, the mass and particle counts, the gauges, the
// summary and the health check combine the values of every part of the domain through one
// Communicator. This one is a single process (every reduction is the value itself); an MPI
// run replaces it with one over its ranks (sim/ranks). Physics code calls these, never MPI.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

namespace sph {

class Communicator {
 public:
  virtual ~Communicator() = default;
  virtual int rank() const { return 0; }
  virtual int size() const { return 1; }
  /// Element-wise reductions of n values in place, over every rank.
  virtual void sum(double*, std::size_t) const {}
  virtual void sum(std::uint64_t*, std::size_t) const {}
  virtual void min(double*, std::size_t) const {}
  virtual void max(double*, std::size_t) const {}
  /// Every rank's values, concatenated in rank order, on every rank.
  virtual std::vector<double> allgather(const std::vector<double>& v) const { return v; }
  /// The sum of v over the ranks before this one (0 on the first), and the sum over all of
  /// them in `total`: numbering items that several ranks create, in rank order.
  virtual std::uint64_t exscan(std::uint64_t v, std::uint64_t& total) const { total = v; return 0; }
  /// Set up HDF5 property lists (file access, data transfer; hid_t values, -1 to skip one) for
  /// a file that every rank writes together: MPI-IO with collective transfers (parallel HDF5).
  /// False where this build or this run cannot (one process; HDF5 without MPI support).
  virtual bool parallel_hdf5(std::int64_t /*fapl*/, std::int64_t /*dxpl*/) const { return false; }
  double sum(double v) const { sum(&v, 1); return v; }
  std::uint64_t sum(std::uint64_t v) const { sum(&v, 1); return v; }
  double min(double v) const { min(&v, 1); return v; }
  double max(double v) const { max(&v, 1); return v; }
  /// Whether any rank says yes (a failure anywhere stops every rank).
  bool any(bool v) const { return max(v ? 1.0 : 0.0) > 0.0; }
  bool root() const { return rank() == 0; }
};

}  // namespace sph
