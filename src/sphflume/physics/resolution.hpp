// Resolution levels (docs/numerics.md §14): the one owner of the levels (Resolution<D>: the
// regions and their moving windows, each particle's h, splitting and merging with the children's
// settling, the interface's set-up relaxation, the step's h, the cell layout), and the operators
// it is made of.
#pragma once
#include <cstdint>
#include <vector>

#include "sphflume/core/config.hpp"
#include "sphflume/core/refinement.hpp"
#include "sphflume/core/system.hpp"

namespace sph {

/// Each owned particle's h (store field "h") as the Shepard average, over the level-0 support,
/// of its neighbours' level smoothing lengths h / 2^level (store field "level"):
///   h_a = Σ_b V_b W(r_ab, h) h_lev(b) / Σ_b V_b W(r_ab, h),
/// so that h varies smoothly across a level interface (a ramp about two level-0 supports wide)
/// while particle spacing and mass jump by 2 and 2^D. A jump in h itself breaks the kernel sums'
/// consistency there: with h_ab = (h_a + h_b)/2 a particle at the interface sees
/// Σ_b V_b ∇W_ab ≠ 0 in still water (an O(1/h) pressure force; the first refined still tank
/// moved at 0.18 m/s and lost 2–4 % of its hydrostatic pressure), whereas for an h field that
/// varies linearly the error vanishes to first order (∫ ∂W/∂h dV = 0). Images take their
/// source's h.
///
/// The pair terms then see the two lattices' kernel sums at the interface: M0_a = Σ_b V_b ∇W_ab
/// is not zero on the initial lattices there (a quadrature error of 1–2 % of the half-space
/// value), which the symmetric pressure gradient multiplies by 2 p_a/ρ_a: ±5 m/s² on the rows
/// beside a horizontal interface 0.4 m deep. relax_level_band removes it at set-up.
template <int D>
void smooth_level_h(System<D>& S);

/// What relax_level_band did.
struct LevelRelaxReport {
  std::size_t band = 0;    // points free to move
  int iterations = 0;
  double residual0 = 0.0;  // max h_a |Σ_b V_b ∇W_ab| over the band, before and after
  double residual = 0.0;
  double max_shift = 0.0;  // largest displacement [m]
};

/// Initial state with resolution levels: moves the fluid points of the level interface band
/// (points with a point of another level within the level-0 support) until the volumes
/// V_b = (dx / 2^l_b)^D tile space, Σ_b V_b ∇W(r_ab, h_ab) → 0, with the h the run uses
/// (smooth_level_h, h_ab = (h_a + h_b)/2): the zero-order consistency the symmetric pressure
/// gradient needs, as relax_porous_band does for the porosity interface. Shifting:
/// x_a ← x_a − 0.1 h_a² Σ_b V_b ∇W_ab, at most 0.05 dx_a per iteration and dx_a/4 from the
/// lattice site in all; points near the free surface (kernel-weighted neighbour centroid more
/// than 0.2 h away) and the walls stay.
template <int D>
LevelRelaxReport relax_level_band(KernelType kernel, double h0, double dx0, std::vector<Vec<D>>& fluid,
                                  const std::vector<int>& level, const std::vector<Vec<D>>& walls, int iterations);

/// The level a point should have: the highest level of the `resolution` regions that contain
/// it (0 outside them all).
int target_level(const ResolutionConfig& res, const double* x, int dim);

/// Is x outside every region of level >= l by at least `margin` (x + margin {−1, 0, 1}^D all
/// outside: a square (cube) about x, which holds the disc (ball) of radius margin)?
template <int D>
bool outside_levels(const ResolutionConfig& res, const Vec<D>& x, int l, double margin);

/// Bands that follow the waterline (`shape: band`, `follow: waterline`): each such region's
/// window [z_w − waterline_below, z_w + waterline_above] (RegionConfig::win_lo, win_hi) from the
/// waterline z_w of the points x[0, n) on its line: the line is cut into stretches 2 dx long
/// (dx the level-0 spacing), a stretch is wet when a point lies in it within the band's `below`
/// under the face and 1.5 dx above it (the run-up gauge's reach, docs/gauges), and the walk
/// goes up from the first wet stretch while they stay wet; z_w is the highest such point of the
/// last one. No wet stretch: the band is empty. `kind` null: every point is fluid (the set-up's
/// fill points). `comm`: the stretches are reduced over the ranks.
template <int D>
void set_waterline_windows(ResolutionConfig& res, const Vec<D>* x, const Kind* kind, std::size_t n, double dx,
                           const Communicator& comm);

/// What adapt_levels did.
struct AdaptCounts {
  std::size_t split = 0;   // particles split (each into 2^D children)
  std::size_t merged = 0;  // groups of 2^D merged into one particle
};

/// Splitting and merging during the run (docs/numerics.md §14, step 2), after a step and the
/// removal of escaped particles, on a freshly sorted store (the cell list current):
/// - a fluid particle of level l whose place wants a higher level (target_level) is split into
///   2^D children of level l + 1 (core/refinement.hpp: ±dx_l/4 about it, its velocity, density
///   and other fields, mass / 2^D): mass, momentum and centre of mass kept exactly;
/// - fluid particles of level l ≥ 1 that are outside every region of their level by at least
///   one smoothing length of level l − 1 (the hysteresis that keeps a particle from splitting and
///   merging back in turn) are merged in groups of 2^D of that level lying within a level-(l − 1)
///   spacing of the group's first (taken in store order, each with its nearest partners): the
///   merged particle has the group's mass, momentum (mass-weighted velocity) and centre of mass,
///   the density M / Σ V_i (the volume kept), the other fields' mass-weighted means and level
///   l − 1. Candidates without enough partners wait.
/// New particles take ids from next_id (advanced). Serial and in store order: bitwise
/// independent of the thread count. The caller re-sorts when anything changed.
template <int D>
AdaptCounts adapt_levels(System<D>& S, const ResolutionConfig& res, std::uint32_t& next_id);

/// The smoothing length the time step follows (the finest level present among the fluid and the wall particles,
/// the same on every rank): level_h of the finest fluid level, or the mean with a finer wall's (the pairs of the
/// fluid with finer walls); S.h with one resolution.
template <int D>
double finest_present_h(const System<D>& S);

/// Resolution levels' one owner (issue 58; docs/numerics.md §14, docs/architecture.md): the case's `resolution`
/// section (regions, bands that follow the waterline, relaxation, settling, cell layout, multirate) and everything
/// done with it. set-up (setup/build.cpp) makes it when a region refines and attaches it to the System
/// (System::resolution; null with one resolution); the schemes smooth h through it before their passes, the run
/// loop splits and merges through it after each step, the integrators take the step's h from it. The System keeps
/// the level count and the cell layout it hands the core's cell list (attach).
template <int D>
class Resolution {
 public:
  Resolution(const ResolutionConfig& cfg, KernelType kernel, double h0, double dx0)
      : cfg_(cfg), kernel_(kernel), h0_(h0), dx0_(dx0) {}
  const ResolutionConfig& config() const { return cfg_; }
  /// The finest level of the regions (0: one resolution).
  int levels() const { return cfg_.max_level(); }
  /// `resolution.multirate`: the coarse levels step twice the finest one's step (schemes/multirate.hpp).
  bool multirate() const { return cfg_.multirate; }
  /// The System's level count and cell layout (`cells: level0 | finest`), which its cell list reads.
  void attach(System<D>& S) const {
    S.levels = levels();
    S.cell_layout = S.levels > 0 ? cfg_.cells : CellLayout::Level0;
  }
  /// Each particle's h at its place (smooth_level_h); after every neighbour update a pass reads h from.
  void smooth_h(System<D>& S) const { smooth_level_h(S); }
  /// Split and merge where the particles' places want another level, the children settled (adapt_levels).
  AdaptCounts adapt(System<D>& S, std::uint32_t& next_id) const { return adapt_levels(S, cfg_, next_id); }
  /// The set-up relaxation of the fill points' interface band (relax_level_band with the case's iterations).
  LevelRelaxReport relax_setup(std::vector<Vec<D>>& fluid, const std::vector<int>& level, const std::vector<Vec<D>>& walls) const {
    return relax_level_band<D>(kernel_, h0_, dx0_, fluid, level, walls, cfg_.relax_iterations);
  }
  /// The step's h: the finest level present (finest_present_h).
  double step_h(const System<D>& S) const { return finest_present_h(S); }
  /// The h of the next-coarser level than the finest (a multirate step's slow particles).
  double slow_h(const System<D>& S) const { return level_h(S.h, S.levels - 1); }

 private:
  ResolutionConfig cfg_;
  KernelType kernel_;
  double h0_, dx0_;
};

}  // namespace sph
