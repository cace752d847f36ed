// The halo layer under the neighbour search. A part of the domain (the whole domain in one
// process, a slab of it on an MPI rank) needs, for its pair sums, copies of particles it does
// not own: periodic images, and particles of neighbouring ranks. Both are kept in the store's
// image range [n_owned, size()) and both are one Halo: System::update_neighbours builds every
// layer after the re-sort, the schemes refresh them after changing fields the pair loops read
// (System::refresh_halos), and particles that left the part are handed over at the start of
// update_neighbours (migrate). A particle just outside its part until then is still sent to
// its neighbours as a halo copy (the margin covers it). Physics code sees images as read-only
// neighbours and never talks to a layer directly.
#pragma once
#include <cstddef>

#include "sphflume/core/particles.hpp"

namespace sph {

template <int D>
class Halo {
 public:
  virtual ~Halo() = default;
  virtual const char* name() const = 0;
  /// Whether the layer does anything (a layer that does nothing costs nothing).
  virtual bool active() const = 0;
  /// Owned particles that left this part of the domain, handed to the rank that now owns them
  /// (MPI). Called by update_neighbours before the re-sort; the store has no images.
  virtual void migrate(ParticleStore<D>& P) = 0;
  /// Append the images this part needs: copies of every particle within `margin` of its edge.
  /// After the owned particles are sorted; the layers are built one after the other.
  virtual void build(ParticleStore<D>& P, double margin) = 0;
  /// Copy every store field into this layer's images from their sources again.
  virtual void refresh(ParticleStore<D>& P) = 0;
  /// The same for one per-particle array outside the store (width bytes per particle, indexed
  /// as the store): a model's scratch that images must carry.
  virtual void refresh_column(const ParticleStore<D>& P, std::byte* column, std::size_t width) = 0;
  /// Whether point x lies in this part of the domain (a gauge's point is read by one part).
  virtual bool owns(const Vec<D>&) const { return true; }
};

}  // namespace sph
