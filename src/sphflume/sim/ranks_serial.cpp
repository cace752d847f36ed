// A build without MPI: one process. Started by mpirun with several ranks, it says how to get
// a distributed build instead of running the same case N times side by side.
#include <cstdlib>
#include <stdexcept>

#include <fmt/format.h>

#include "sphflume/core/errors.hpp"
#include "sphflume/sim/ranks.hpp"

namespace sph {

std::shared_ptr<const Communicator> world() {
  const char* n = std::getenv("OMPI_COMM_WORLD_SIZE");
  if (!n) n = std::getenv("PMI_SIZE");
  if (n && std::atoi(n) > 1)
    throw InputError(fmt::format("started by mpirun with {} ranks, but this sphflume was built without MPI: install "
                                 "libopenmpi-dev and configure with -DSPHFLUME_MPI=ON (README.md, 'Distributed runs')", n));
  return std::make_shared<Communicator>();
}

template <int D>
void distribute(System<D>&, std::shared_ptr<const Communicator>) {}

template <int D>
RankStats rank_stats(const System<D>&, long) { return {}; }

void abort_ranks(const Communicator&, const std::string& message, int) {
  throw std::logic_error("abort_ranks: a build without MPI has one process (" + message + ")");
}

template <int D>
void gather_particles(const System<D>&, ParticleStore<D>&) {
  throw std::logic_error("gather_particles: a build without MPI has one process");
}
template void gather_particles<2>(const System<2>&, ParticleStore<2>&);
template void gather_particles<3>(const System<3>&, ParticleStore<3>&);

template void distribute<2>(System<2>&, std::shared_ptr<const Communicator>);
template void distribute<3>(System<3>&, std::shared_ptr<const Communicator>);
template RankStats rank_stats<2>(const System<2>&, long);
template RankStats rank_stats<3>(const System<3>&, long);

}  // namespace sph
