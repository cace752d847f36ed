// Wall models. A wall model sets the state of wall particles before each rates pass; the
// scheme's pair loop then treats walls as neighbours with that state.
//  - dummy:   Adami, Hu & Adams (2012): pressure extrapolated from the fluid (with the body
//             force), density from the inverse EOS, ghost velocity 2 v_w - v~ for no-slip.
//  - dynamic: SPHysics "dynamic boundary particles" (Kazemi's walls): density evolves by the
//             continuity equation, pressure from the EOS, not moved.
//  - fixed_ghost: Marrone et al. (2011) fixed ghost particles (Federico §5.2.6): MLS
//             interpolation at points mirrored across the wall surface, Neumann pressure,
//             reversed velocity (no-slip), reversed normal velocity (free-slip), or the
//             tangential part scaled by psi (Federico's eq 5.8).
//  - repulsive: Monaghan & Kos (1999) normal repulsive force (Federico §5.2.1c) alone: the wall
//             particles enter no pair sum (free-slip); any model can add the same force with
//             `repulsion:` (Federico §5.2.5 couples it with ghosts).
//  Repulsive force per unit mass on fluid particle a from wall particle k within dx:
//     f = n_k R(r⊥) P(r∥),  R = A5 (1 − q)/sqrt(q), q = r⊥/dx (r⊥ < dx),
//     P = (1 + cos(π r∥/dx))/2 (r∥ < dx),  A5 = max(0, β1 c0² + β2 c0 v)/h,
//  n_k the wall particle's unit normal towards the fluid, v = −(u_a − u_k)·n_k the speed at which
//  a approaches the wall (Monaghan & Kos: stronger when approaching; clamped so that it never
//  attracts). P sums to 1 over wall particles dx apart, so a flat wall pushes uniformly.
//  Backup (walls.backup, on by default for every model but repulsive): the same force, acting
//  only on fluid closer than dx/4 to the wall surface (add_backup), so that no wall model lets a
//  particle through (thin slow films over dummy beds did).
// New models: derive from WallModel and add one line to wall_registry().
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "sphflume/core/registry.hpp"
#include "sphflume/core/system.hpp"
#include "sphflume/core/config.hpp"

namespace sph {

/// The (wall, fluid) pairs a scheme keeps through several steps (scheme.pairs: advection, schemes/dual_pairs.cpp):
/// wall particle w's fluid partners are entries [begin[w], end[w]) (store indices; other particles' rows empty),
/// each with its fluid particle, the kernel W(r) and the separation r = x_w − x_a (D per entry) when they were found.
struct WallPairs {
  std::vector<std::uint32_t> begin, end, fluid;
  std::vector<float> w, r;
  std::size_t bytes() const { return (begin.capacity() + end.capacity() + fluid.capacity() + w.capacity() + r.capacity()) * 4; }
};

template <int D>
class WallModel {
 public:
  explicit WallModel(const WallConfig& c) : cfg(c) {}
  virtual ~WallModel() = default;
  virtual const char* name() const = 0;
  /// Walls whose density is integrated by the continuity equation.
  virtual bool evolves_density() const = 0;
  /// Set wall particles' p, rho and the velocity the viscous term sees. near_only (a multirate pass of the fast
  /// particles, schemes/multirate.cpp: their flags, the store field "_fast"): only the walls near a flagged
  /// fluid particle; null: near any fluid.
  virtual void prepare(System<D>& S, const double* near_only) = 0;
  /// The same from kept pairs (their kernel values and separations as found, the fluid's state now): true where the
  /// model has that form (dummy walls); false: the scheme calls prepare().
  virtual bool prepare_from_pairs(System<D>&, const WallPairs&) { return false; }
  /// The no-slip ghost correction of the viscous term: D floats per particle, v_j − v_ghost,j
  /// of wall particle j (what the viscous term subtracts from the wall's velocity); entries of
  /// other particles are not read. nullptr: no correction (free-slip dummy walls, and the other
  /// models, whose walls the viscous term sees at their own velocity). Scratch of the current step, rewritten by prepare(): 4 D bytes per particle
  /// instead of a stored double velocity field.
  virtual const float* viscous_correction() const { return nullptr; }
  /// Bytes of the model's own per-step scratch (counted in bytes_per_particle).
  virtual std::size_t bytes() const { return hits_.capacity() * sizeof(hits_[0]) + near_.capacity(); }
  /// Whether wall particles enter the fluid's pair sums (pressure, continuity, viscosity);
  /// purely repulsive walls act through their force alone.
  virtual bool in_pair_sums() const { return true; }
  /// After the pair loop: forces the walls add to fluid particles (the Monaghan–Kos repulsion
  /// when cfg.repulsive).
  void add_forces(System<D>& S, const double* near_only = nullptr) const;
  /// Set-up (setup/setup.cpp): create the per-wall-particle fields this model reads, from each
  /// wall particle's nearest point of its shape's surface (surface[k] for particle first_wall + k):
  /// "wall_normal" (repulsion), "wall_to_surface" (backup); fixed ghosts add "ghost_mirror".
  virtual void init_fields(System<D>& S, std::size_t first_wall, const std::vector<Vec<D>>& surface) const;
  WallConfig cfg;

 protected:
  /// Cells with fluid within the cell list's reach (CellList::mark_near), the models' scratch.
  mutable std::vector<char> near_;

 private:
  /// The backup against penetration (cfg.backup): a fluid particle a closer than s0 = dx/4 to
  /// the surface of a first-layer wall particle k (depth d_k < dx below the surface, unit
  /// normal n_k) gets  f = A5 (1 − s/s0)² P(r∥) n_k,  s = (x_a − x_k)·n_k − d_k, with the
  /// Monaghan–Kos strength A5 and tangential weight P. The fluid's normal distance from the
  /// surface is dx/2, so a flow the wall model holds never feels it. A wall particle whose face
  /// another fixed wall covers ("wall_covered", set up by fill_shapes) has no surface to hold.
  /// Resolution levels: dx, s0 and h are wall particle k's level's (its children stand dx_l apart, the fluid beside
  /// them dx_l/2 off the surface).
  void add_backup(System<D>& S, const double* near_only) const;
  void apply_backup(System<D>& S) const;  // the force of each (fluid, wall) pair in hits_, in their sorted order
  mutable std::vector<std::pair<std::uint32_t, std::uint32_t>> hits_;  // (fluid, wall) pairs within reach
  mutable std::vector<std::uint32_t> moving_covered_;  // moving first-layer walls resting on a fixed wall (add_backup)
  void find_moving_covered(const System<D>& S) const;  // moving_covered_ at the current positions
};

template <int D>
Registry<WallModel<D>, const WallConfig&>& wall_registry();

/// The fixed ghost walls (boundaries/walls_fixed_ghost.cpp), for wall_registry().
template <int D>
std::unique_ptr<WallModel<D>> make_fixed_ghost_walls(const WallConfig& c);

}  // namespace sph
