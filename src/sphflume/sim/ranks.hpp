// Distributed runs: `mpirun -np N sphflume run CASE` splits the particles over N MPI ranks.
// Each rank owns the particles of one slab of the domain along its longest axis (cuts balanced
// by the fluid particle count) and keeps copies of its neighbours'
// particles within the halo margin: a Halo layer (core/halo.hpp) under the neighbour search,
// built, refreshed and migrated by System like periodic images, plus a Communicator for the
// global reductions. Physics code never calls MPI; everything MPI lives in ranks_mpi.cpp (a
// build without MPI has ranks_serial.cpp: one process).
#pragma once
#include <memory>
#include <string>

#include "sphflume/core/communicator.hpp"
#include "sphflume/core/system.hpp"

namespace sph {

/// The ranks this process runs with: one process (serial) unless it was started by mpirun with
/// more than one rank (MPI is then initialised, once, and finalised at exit). A build without
/// MPI started by mpirun with several ranks throws an InputError that says how to build one.
std::shared_ptr<const Communicator> world();

/// Split the system over the ranks of `comm` (size > 1): every rank has built the whole case;
/// each keeps the particles of its slab and gets the slab halo layer and the communicator.
template <int D>
void distribute(System<D>& S, std::shared_ptr<const Communicator> comm);

/// Every rank's owned particles on the first rank, ordered by particle id (snapshots and
/// checkpoints of a distributed run: the same files as one process writes, readable by the same
/// tools, and a restart point for any number of ranks). Every rank calls it; the others get an
/// empty store.
template <int D>
void gather_particles(const System<D>& S, ParticleStore<D>& all);

/// A failure in a distributed run: the other ranks may be waiting in a collective call, so the
/// run cannot wind down as one process does (no summary.json; the snapshots already written are
/// whole, and the last one is the restart point). Prints the message with the rank and aborts
/// every rank with `code`.
[[noreturn]] void abort_ranks(const Communicator& comm, const std::string& message, int code);

/// Halo traffic and load balance of a distributed run, for summary.json (zeros in one process).
struct RankStats {
  double halo_bytes_per_step = 0.0;  // bytes sent per rank per step (builds and refreshes), mean over ranks
  double imbalance = 1.0;            // max over ranks of owned particles / the mean
  double migrated_per_step = 0.0;    // particles handed to another rank per step, all ranks
  double fluid_imbalance = 1.0;      // the same for the fluid particles (what the cuts balance)
  long rebalances = 0;               // times the cuts were moved
};
template <int D>
RankStats rank_stats(const System<D>& S, long steps);

}  // namespace sph
