// Prescribed wall motion (moving walls, the piston wave maker): the wall particles of the shapes
// that name a motion (`geometry: - {..., fill: wall, motion: NAME}`) translate rigidly,
//   x_k(t) = x_k(0) + X(t) e,   u_k = X'(t) e,   a_k = X''(t) e,
// with X from the motion's paddle law (boundaries/paddle.hpp) and e its unit direction. The
// motion is separate from the physics (as DualSPHysics separates JMotion from the solver): each
// scheme calls move_walls(S, t) with the time of its next rates pass (WCSPH: each stage; ISPH:
// the prediction), the cell lists are rebuilt from the new positions by that pass, and the wall
// model sees the paddle's velocity (no-slip ghost velocity, the PPE's divergence) and its
// acceleration (the dummy walls' pressure, Adami et al. 2012: (g − a_w)·r).
// Active absorption (Schäffer & Klopman 2000; the AWAS of DualSPHysics, Altomare et al. 2017,
// Coastal Eng. 127): a motion with `absorption` reads the water level η_m at its face (at the offset
// of a water_level gauge, moving with the paddle) at each call, compares it with the incident
// elevation its law makes there (PaddleLaw::elevation), and adds to the law's motion the velocity
// that, in long-wave theory, cancels the difference (what the structure reflected):
//   u_c = −G (e(t − d/c) − ē),  e = η_m − η_I(d),   x_c = ∫ (u_c − x_c/τ) dt,
// G = sqrt(g/h) (long waves) or ω/m1(kh) for a law of one period (regular, stokes2, an absorber given
// its period), η_I(d) the law's elevation at the gauge's distance d from the face, read d/c late (c the
// celerity at the law's period, or √(gh)): what reaches the face now passed the gauge then,
// ē the mean of e over the drift time τ (an exponential average: the SPH level's offset from the
// still level and the set-down do not drive the paddle), and the −x_c/τ drift correction that keeps
// the paddle about its mean place. Together they high-pass the correction twice; their phase lead
// at the law's frequency, 2 atan(1/(ωτ)), is taken out by delaying the reading further (τ = 4 T
// by default: 9° at ω, and a 1 mm step of the level's mean moves the paddle by at most ~2 G τ/e mm). The correction starts after the law's ramp (at least 1 s: the SPH
// level near the paddle settles over the first second, by up to half a dx); ē starts as the plain
// mean of e over the start-up's last period (the near field's oscillation averages out over it), so
// that neither the start-up's transient nor a constant offset of the SPH level drives the paddle. The correction's acceleration is left out of wall_acc: a
// reflected amplitude a_r at ω adds ρ ω sqrt(g/h) a_r r to the dummy walls' pressure, r ≤ the wall's
// depth (about 1 % of the hydrostatic pressure for a 2 cm reflection at T = 1.2 s, h = 0.4 m).
// The state (x_c, u_c, ē, the last time) goes into restart points (state(), restore()).
// A flap (`paddle: flap`) rotates rigidly about a horizontal hinge line through `hinge`, the axis
// z × e, by θ = atan(X/d), X the law's displacement at the still-water level and d the hinge's
// depth below it: x = x_h + R(θ)(x0 − x_h), u = θ' a × r, a_w = θ'' a × r − θ'² r; the vectors to the
// wall's surface (and repulsive walls' normals) turn with it from their rest values
// ("motion_surface0", "motion_normal0").
// Store fields: "motion_group" (0 fixed, k + 1 the k-th motion), "motion_origin" (x at X = 0),
// "wall_acc" (a_w, for the wall model); all follow the particles through sorts and restarts.
#pragma once
#include <deque>
#include <map>
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
  /// Put every moving wall particle at its place, velocity and acceleration of time t (an absorbing
  /// motion first reads the level at its face and updates its correction, when t is past the last call).
  void apply(System<D>& S, double t);
  /// The paddle's displacement and velocity along its direction: the law's plus the absorption's.
  double displacement(std::size_t k, double t) const;
  double velocity(std::size_t k, double t) const;
  /// The absorbing motions' state, "motion.NAME.KEY" (restart points), and its return.
  std::map<std::string, double> state() const;
  void restore(const std::map<std::string, double>& s);
  std::size_t size() const { return laws_.size(); }
  const std::string& name(std::size_t k) const { return cfg_[k].name; }
  std::size_t index(const std::string& name) const;
  const PaddleLaw& law(std::size_t k) const { return *laws_[k]; }
  double start(std::size_t k) const { return cfg_[k].start; }
  const Vec<D>& direction(std::size_t k) const { return dir_[k]; }
  /// Force of the water's pressure on the walls of motion k [N, per m in 2D], as a lab's array of
  /// pressure sensors would read it: Σ p(s_k) dx^(D−1) (−n_k) over the first-layer wall particles,
  /// p the fluid's linear-MLS pressure at each one's surface point s_k (the pressure gauge's
  /// interpolation), n_k the outward normal there; dry elements read nothing. The same for both
  /// schemes; S needs up-to-date neighbour lists.
  Vec<D> pressure_force(const System<D>& S, std::size_t k) const;

 private:
  struct Absorber {
    bool on = false, started = false;
    Vec<D> point{};        // the level's point with the paddle at rest
    double c_h = 0.0;      // sqrt(g/h)
    double tau = 0.0;      // the drift time
    double top = 0.0;      // where the level's scan starts (the paddle's top)
    double offset = 0.0;   // the gauge's distance ahead of the paddle's face (the target is read there)
    double celerity = 1.0; // the waves' speed (the law's period, else long waves) and the delay offset/celerity
    double delay = 0.0;
    std::deque<std::pair<double, double>> hist;  // (t, e) over the last delay
    double start = 0.0;    // the correction acts after it (before: ē is the plain mean of e over the last window)
    double window = 0.0;   // the law's period (0: the start-up's second half)
    double e_sum = 0.0, e_time = 0.0;
    double t_first = 0.0, t_last = 0.0, e_mean = 0.0, x = 0.0, u = 0.0;
  };
  void absorb(System<D>& S, std::size_t k, double t);

  std::vector<MotionConfig> cfg_;
  std::vector<std::unique_ptr<PaddleLaw>> laws_;
  std::vector<Vec<D>> dir_;
  std::vector<Vec<D>> hinge_;  // flaps: a point of the hinge line
  std::vector<Absorber> abs_;
};

/// Move the walls of S to time t (no-op without motions).
template <int D>
inline void move_walls(System<D>& S, double t) {
  if (S.motion) S.motion->apply(S, t);
}

}  // namespace sph
