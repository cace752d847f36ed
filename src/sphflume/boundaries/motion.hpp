// Prescribed wall motion (moving walls, the piston wave maker): the wall particles of the shapes
// that name a motion (`geometry: - {..., fill: wall, motion: NAME}`) translate rigidly,
//   x_k(t) = x_k(0) + X(t) e,   u_k = X'(t) e,   a_k = X''(t) e,
// with X from the motion's paddle law (boundaries/paddle.hpp) and e its unit direction. The
// motion is separate from the physics (as DualSPHysics separates JMotion from the solver): each
// scheme calls move_walls(S, t) with the time of its next rates pass (WCSPH: each stage; ISPH:
// the prediction), the cell lists are rebuilt from the new positions by that pass, and the wall
// model sees the paddle's velocity (no-slip ghost velocity, the PPE's divergence) and its
// acceleration (the dummy walls' pressure, Adami et al. 2012: (g − a_w)·r).
// Store fields: "motion_group" (0 fixed, k + 1 the k-th motion), "motion_origin" (x at X = 0),
// "wall_acc" (a_w, for the wall model); all follow the particles through sorts and restarts.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "sphflume/boundaries/paddle.hpp"
#include "sphflume/core/config.hpp"
#include "sphflume/core/system.hpp"

namespace sph {

template <int D>
class WallMotion {
 public:
  WallMotion(const std::vector<MotionConfig>& motions, const std::string& file);
  /// Put every moving wall particle at its place, velocity and acceleration of time t.
  void apply(System<D>& S, double t) const;
  std::size_t size() const { return laws_.size(); }
  const std::string& name(std::size_t k) const { return cfg_[k].name; }
  std::size_t index(const std::string& name) const;
  const PaddleLaw& law(std::size_t k) const { return *laws_[k]; }
  const Vec<D>& direction(std::size_t k) const { return dir_[k]; }
  /// Force of the water's pressure on the walls of motion k [N, per m in 2D], as a lab's array of
  /// pressure sensors would read it: Σ p(s_k) dx^(D−1) (−n_k) over the first-layer wall particles,
  /// p the fluid's linear-MLS pressure at each one's surface point s_k (the pressure gauge's
  /// interpolation), n_k the outward normal there; dry elements read nothing. The same for both
  /// schemes; S needs up-to-date neighbour lists.
  Vec<D> pressure_force(const System<D>& S, std::size_t k) const;

 private:
  std::vector<MotionConfig> cfg_;
  std::vector<std::unique_ptr<PaddleLaw>> laws_;
  std::vector<Vec<D>> dir_;
};

/// Move the walls of S to time t (no-op without motions).
template <int D>
inline void move_walls(System<D>& S, double t) {
  if (S.motion) S.motion->apply(S, t);
}

}  // namespace sph
