// Wall models. A wall model sets the state of wall particles before each rates pass; the
// scheme's pair loop then treats walls as neighbours with that state.
//  - dummy:   Adami, Hu & Adams (2012): pressure extrapolated from the fluid (with the body
//             force), density from the inverse EOS, ghost velocity 2 v_w - v~ for no-slip.
//  - dynamic: SPHysics "dynamic boundary particles" (Kazemi's walls): density evolves by the
//             continuity equation, pressure from the EOS, not moved.
//  - fixed_ghost: Marrone et al. (2011) fixed ghost particles (Federico §5.2.6): MLS
//             interpolation at points mirrored across the wall surface, Neumann pressure,
//             reversed velocity (no-slip) or reversed normal velocity (free-slip).
// New models: derive from WallModel and add one line to wall_registry().
#pragma once
#include <memory>
#include <string>

#include "sphflume/core/registry.hpp"
#include "sphflume/core/system.hpp"
#include "sphflume/io/case.hpp"

namespace sph {

template <int D>
class WallModel {
 public:
  explicit WallModel(const WallConfig& c) : cfg(c) {}
  virtual ~WallModel() = default;
  virtual const char* name() const = 0;
  /// Walls whose density is integrated by the continuity equation.
  virtual bool evolves_density() const = 0;
  /// Set wall particles' p, rho and the velocity the viscous term sees.
  virtual void prepare(System<D>& S) = 0;
  /// Velocity of wall particle j as seen by the viscous term (no-slip).
  virtual const std::vector<Vec<D>>& viscous_velocity(const System<D>& S) const { return S.particles.vel; }
  WallConfig cfg;
};

template <int D>
Registry<WallModel<D>, const WallConfig&>& wall_registry();

}  // namespace sph
