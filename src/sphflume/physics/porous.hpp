// Porous media (Kazemi ch. 4-6: SPHAM §4.3, porosity §4.4, drag §4.2.1, §6.2.2; Tsurudome §4.1-4.3):
// the porosity field phi(x) of the SPH-averaged macroscopic (SPHAM) equations and the drag
// closures. The scheme solves for the intrinsic density, velocity and pressure; a particle's
// volume is m / (phi rho).
//
// Porosity field: phi(x) = 1 - Σ_r (1 - phi0_r) S_r(x), clamped to [min phi0, 1], with S_r the
// (smoothed) indicator of region r:
//   smoothed   Kazemi's Situation #1 (eq 4.54): S_r = Σ_c G(x - x_c) χ_r(c) / Σ_c G(x - x_c) over
//              a background mesh of spacing h_Ω / mesh_ratio, G the case's kernel with support
//              r_Ω = layer / 2 (layer = d_s by default: h_Ω = d_s / 4, the transition is one
//              grain diameter thick, centred on the region's outline = the separating line);
//   particles  Tsurudome eq 4.2.1: porous particles on a lattice dx / phi0^(1/D) inside the
//              region, S_r = Σ_j W(x - x_j) / Σ_lattice W(x - x_j) (ρ_p over a full block's, not ρ_w,
//              so that phi = phi0 inside; docs/numerics.md, Errata), or as printed S_r = ρ_p / ρ_w =
//              dx^D Σ_j W (normalisation: thesis_literal; gives 1 - (1 - phi0) phi0 inside);
//   sharp      S_r = χ_r(x);
//   profile    regions of shape `profile` prescribe 1 - S_r (1 - phi0) = phi(z) or phi(x, z)
//              directly (Kazemi's Situation #2), bilinear in the table, constant beyond it.
// The field depends on position only (G fixed in time, Kazemi's constraint #3); it is
// re-evaluated at every particle before every rates pass. Each lattice node's inside test is made once per region
// (a mask and its summed-area table): a stencil wholly inside or outside is answered at once, the interface's
// stencils read the mask (the same sums, bitwise; bench/README.md, session 48).
//
// Drag (per unit mass, on the intrinsic velocity u): du/dt = ... - K u, K = a + b |u|, with
//   ergun      a = c1 (1-φ)²/φ² ν/d²,  b = c2 (1-φ)/φ / d          Kazemi eq 4.29 (c1 150, c2 1.75)
//   tsurudome  a = c1 (1-φ)²/φ³ ν/d²,  b = c2 (1-φ)/φ³ / d          Tsurudome eq 4.1.2 (ν/Kp form)
//   van_gent   a = α (1-φ)²/φ² ν/d²,  b = β (1 + 7.5/KC)(1-φ)/φ / d, and an added-mass factor
//              M = 1 + γ (1-φ)/φ dividing the other accelerations (van Gent 1995 as Liu et al.
//              1999 use it, per unit mass of the intrinsic velocity; α 1000, β 1.1, γ 0.34).
//              olaFlow's (a, b, c) differ: α = a (1-φ), β = b, γ = c φ/(1-φ) (docs/porous-closures.md)
//   roughness  a = 0, b = factor C_d (1-φ) / d                        Kazemi eq 6.2 (C_d 0.9)
// The region whose term dominates phi at a particle gives the closure and d. Fine grains make K
// dt > 1, so the schemes integrate the drag point-implicitly: u^{n+1} = (u_base + Δt a_other / M)
// / (1 + Δt K / M), with K from the current |u| (steady balances are exact).
#pragma once
#include <cstdint>
#include <utility>
#include <vector>

#include "sphflume/core/system.hpp"
#include "sphflume/core/config.hpp"

namespace sph {

template <int D>
class PorousMedia {
 public:
  /// `kernel` and `h` are the run's (the particles field and the smoothed field's kernel shape).
  /// `levels` > 0 (resolution levels, docs/numerics.md §14): the porous-particle field of `field:
  /// particles` is also built at each level's spacing dx/2^l and h/2^l, so that a particle of
  /// level l sees the porosity a uniform run at its spacing sees.
  PorousMedia(const PorousConfig& c, KernelType kernel, double h, double dx, int levels = 0);

  std::size_t size() const { return regions_.size(); }
  const PorousRegionConfig& region(std::size_t r) const { return regions_[r].cfg; }
  const PorousConfig& config() const { return cfg_; }
  double min_porosity() const { return phi_min_; }

  /// Porosity at x; `region` (optional) receives the index of the dominating region, -1 where
  /// phi = 1.
  /// `level`: the particle's resolution level (the field of that level's lattice; 0 without levels).
  double porosity(const Vec<D>& x, int* region = nullptr, int level = 0) const;
  /// Is x inside region r's shape (box or polygon; a profile region contains nothing)?
  bool inside(std::size_t r, const Vec<D>& x) const;
  /// Lattice spacing of the fluid initially inside region r: dx / phi0^(1/D); 0 for profiles.
  double fill_spacing(std::size_t r) const;
  static double fill_spacing_of(double phi, double dx);

  /// Store field "porosity" of every owned particle (walls 1) and of the images, from the
  /// particle positions; remembers each owned particle's dominating region for drag().
  void update(System<D>& S);
  /// Store fields "drag_rate" (K/M, 1/s) and "inertia" (1/M) of the owned fluid particles, from
  /// their porosity (update() first) and current speed.
  void drag(System<D>& S);

  /// Closure of one region: K [1/s] and the added-mass factor M at porosity phi and speed |u|.
  static std::pair<double, double> closure(const PorousClosureConfig& c, double phi, double speed, double nu, double d);

 private:
  struct Region {
    PorousRegionConfig cfg;
    Vec<D> lo{}, hi{};          // the shape's bounding box
    Vec<D> origin{};            // lattice (mesh or porous particles) origin
    double spacing = 0.0;       // nominal lattice spacing
    Vec<D> step{};              // lattice spacing per direction (a box's lattice fits it)
    double h = 0.0, reach = 0.0;  // G's smoothing length and support radius
    bool box = false, profile = false;  // (the shape, read per node)
    // Each lattice node's inside test, made once (make_node_mask): nodes first[d] .. first[d] + count[d] - 1 of each
    // direction (the bounding box and twice the reach around it; every node beyond is outside), and their counts
    // inside, summed from the first node (a summed-area table, (count + 1) per direction), which answer "all nodes
    // of a particle's stencil inside" or "none" at once. Empty: too many nodes, each tested as it is met.
    int first[3] = {0, 0, 0}, count[3] = {1, 1, 1};
    std::vector<std::uint8_t> mask;
    std::vector<std::uint32_t> summed;
    bool nearest_in_reach = false;  // a stencil's nearest node lies within the reach (its W > 0)
    std::size_t node(const int* i) const;  // (index into mask; i relative to first)
    std::uint32_t inside_count(const int* lo, const int* hi) const;  // nodes inside in the index box [lo, hi]
  };
  Region make_region(const PorousRegionConfig& rc, double h, double dx) const;
  void make_node_mask(Region& g) const;
  double indicator(const Region& g, const Vec<D>& x, double dx) const;
  double profile(const Region& g, const Vec<D>& x) const;
  bool inside(const Region& g, const Vec<D>& x) const;

  PorousConfig cfg_;
  bool sharp_ = false, literal_ = false;  // field: sharp; field: particles with normalisation: thesis_literal
  KernelType kernel_;
  double dx_;
  double phi_min_ = 1.0;
  std::vector<Region> regions_;
  std::vector<std::vector<Region>> finer_;  // levels 1.. of the porous-particle field (field: particles)
  std::vector<int> region_of_;  // per owned particle, set by update()
};

/// What relax_porous_band did.
struct PorousRelaxReport {
  std::size_t band = 0;        // fluid points that were free to move
  int iterations = 0;
  double residual0 = 0.0;      // max h |Σ_b V_b ∇W_ab| over the band, before and after
  double residual = 0.0;
  double max_shift = 0.0;      // largest total displacement [m]
};

/// Initial state: moves the fluid points of the porosity interface band (points whose kernel
/// support sees the porosity vary) until the bulk volumes V_b = dx^D / φ(x_b) (walls dx^D) tile
/// space: Σ_b V_b ∇W_ab → 0, the zero-order consistency the conservative pressure gradient
/// needs. The lattice fill changes its spacing abruptly (dx to dx/φ0^(1/D)) while the smoothed
/// φ changes over a layer; without this, a particle in the layer feels the spurious force
/// 2 p_a Σ V_b ∇W ∝ depth, and still water over a porous bed settles with a pressure error
/// there. Shifting: x_a ← x_a − β h² Σ_b V_b ∇W_ab (β = 0.1, at most 0.05 dx per iteration).
/// The band also holds the porous fill's points next to walls, whose lattice meets the walls'.
/// Points near the free surface (kernel-weighted neighbour centroid more than 0.2 h away) and
/// points in `fixed` do not move, the walls are fixed, and no point moves more than dx/4 from
/// its lattice site. The caller refuses a relaxation that ends with a larger residual.
template <int D>
PorousRelaxReport relax_porous_band(const PorousMedia<D>& pm, KernelType kernel, double h, double dx,
                                    std::vector<Vec<D>>& fluid, const std::vector<char>& fixed,
                                    const std::vector<Vec<D>>& walls, int iterations);

}  // namespace sph
