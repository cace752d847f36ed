// Particle snapshots: one HDF5 file per output time (snapshots/snap_NNNNNN.h5) plus one XDMF
// file (particles.xdmf) that lists them as a time series ParaView opens directly.
// Every file is written under a temporary name and renamed, so a crash never leaves a
// truncated file that looks valid.
// HDF5 layout (h5py: f["position"][:]): position, velocity (N x 3, 2D has y = 0), pressure,
// density, mass (N), kind (N, int32: 0 fluid, 1 wall, 2 inflow, 3 outflow), id (N, uint32),
// plus any extra per-particle scalar fields; attributes time, step, dimension; and the group
// /restart (io/restart.hpp) that makes every snapshot a restart point.
#pragma once
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "sphflume/core/communicator.hpp"
#include "sphflume/core/errors.hpp"
#include "sphflume/core/particles.hpp"

namespace sph {

struct RunState;
struct SnapshotEntry;

template <int D>
class SnapshotWriter {
 public:
  /// comm: the ranks of a distributed run. With parallel HDF5 every rank then writes its own
  /// particles into the same files together (collective MPI-IO writes; collective()), and every
  /// rank calls write, write_checkpoint and resume; the first rank renames the files into place
  /// and writes the XDMF.
  explicit SnapshotWriter(std::string dir, std::shared_ptr<const Communicator> comm = nullptr);
  /// Whether the ranks write their particles together (false in one process, and in a
  /// distributed run whose HDF5 has no MPI support: the caller then gathers the particles on
  /// the first rank, which writes alone).
  bool collective() const { return collective_; }
  /// Write the owned particles at time t as the next snapshot of the series; returns its path.
  /// With rs, the snapshot is a restart point (rs.snapshots is the series so far).
  std::string write(const ParticleStore<D>& P, double t, long step, const RunState* rs = nullptr);
  /// Write a restart point outside the series (e.g. OUTPUT/checkpoint.h5), atomically.
  void write_checkpoint(const std::string& path, const ParticleStore<D>& P, const RunState& rs) const;
  /// Continue a series after a restart: keep these entries, delete later snapshot files.
  void resume(const std::vector<SnapshotEntry>& entries);
  const std::string& dir() const { return dir_; }
  std::size_t count() const { return entries_.size(); }
  const std::vector<SnapshotEntry>& entries() const { return entries_; }
  /// Path of the last snapshot written or kept (empty before the first).
  std::string last_path() const;

 private:
  void write_xdmf() const;
  void write_file(const std::string& tmp, const ParticleStore<D>& P, double t, long step, const RunState* rs) const;
  std::string dir_;
  std::shared_ptr<const Communicator> comm_;
  bool collective_ = false;
  std::vector<SnapshotEntry> entries_;
};

/// Write text to path atomically (temporary file + rename).
void write_file_atomically(const std::string& path, const std::string& text);

}  // namespace sph
