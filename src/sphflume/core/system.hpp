// The state every scheme shares: particles, neighbour search, kernel, equation of state,
// gravity, periodic images, the wall model and the registered force terms.
#pragma once
#include <functional>
#include <map>
#include <string>
#include <memory>
#include <vector>

#include "sphflume/core/periodic.hpp"
#include "sphflume/core/cell_list.hpp"
#include "sphflume/core/communicator.hpp"
#include "sphflume/core/config.hpp"
#include "sphflume/core/halo.hpp"
#include "sphflume/core/kernels.hpp"
#include "sphflume/core/particles.hpp"
#include "sphflume/core/eos.hpp"

namespace sph {

template <int D> class WallModel;
template <int D> class ForceTerm;
template <int D> class PorousMedia;
template <int D> class ScalarTransport;
template <int D> class WallMotion;
template <int D> class Resolution;

template <int D>
struct System {
  using V = Vec<D>;
  ParticleStore<D> particles;
  CellList<D> cells;
  KernelType kernel = KernelType::WendlandC2;
  double dx = 0.0, h = 0.0, support = 0.0;
  /// Resolution levels (docs/numerics.md §14): levels > 0 when a `resolution:` section refines
  /// regions; the particles then carry the store fields "h" and "level" (spacing dx / 2^level,
  /// h / 2^level, mass / 2^(D level)). dx, h and support stay level 0's; the cell list is built
  /// with the largest support (its 3^D stencil holds every pair), or (cell_layout,
  /// `resolution.cells`) with cells as wide as the finest pairs' support (cell_side) and each
  /// cell's stencil narrowed to its own pairs (CellList::set_reach: ±1 cell among fine particles,
  /// ±2 near coarse ones), or with one grid of cells per level (core/cell_grids.hpp: each level's
  /// particles in cells of its own support, each cell's stencil the cells of every level that may
  /// hold its pairs).
  int levels = 0;
  CellLayout cell_layout = CellLayout::Level0;
  /// The levels' owner (physics/resolution.hpp; null with one resolution): regions, h, split, merge, settling, the
  /// step's h; it sets levels and cell_layout above (Resolution::attach).
  std::shared_ptr<Resolution<D>> resolution;
  /// The cell list's side: level 0's support; with the finest pairs' cells the finest level's support, at
  /// least half the largest (CellList::kMaxReach), with a margin of 1e-6 (a fine pair's support
  /// is then within one cell however h rounds).
  double cell_side() const {
    if (cell_layout != CellLayout::Finest) return support;
    return std::max(support / h * finest_h(), support / CellList<D>::kMaxReach) * (1.0 + 1.0e-6);
  }
  /// Narrow the cell list's stencils to each cell's pairs (levels; after h or the list changed).
  void set_cell_reach() {
    if (cell_layout == CellLayout::Level0) return;
    const auto* hs = particles.find(field::smoothing_length);
    if (!hs || hs->size() < cells.sorted().size()) return;  // (before the levels' h is set: the widest stencil)
    const double* hv = hs->data();
    cells.set_reach([hv](std::uint32_t j) { return hv[j]; }, support / h);
  }
  /// The smallest smoothing length (the time step's).
  double finest_h() const { return levels > 0 ? h / double(1 << levels) : h; }
  /// Each particle's smoothing length with resolution levels (store field "h", docs/numerics.md §14); null with
  /// one resolution, where every pair takes h.
  const double* level_h() const { return levels > 0 ? particles.require(field::smoothing_length).data() : nullptr; }
  Eos eos;
  double nu = 0.0;  // kinematic viscosity
  V gravity{};
  Periodic<D> periodic;
  std::unique_ptr<WallModel<D>> walls;
  std::vector<std::unique_ptr<ForceTerm<D>>> forces;
  /// Porous regions (null without a `porous:` section): the porosity field and drag closures
  /// of the SPHAM equations; particles then carry the store field "porosity".
  std::shared_ptr<PorousMedia<D>> porous;
  /// Prescribed wall motions (null without a `motions:` section): the wave makers. Schemes move
  /// the walls to the time of each rates pass with move_walls (boundaries/motion.hpp).
  std::shared_ptr<WallMotion<D>> motion;
  /// Transported scalars (null without a `transport:` section): each a store field named after it.
  std::shared_ptr<ScalarTransport<D>> transport;
  /// Equations of state of the fluid phases (empty: one phase, `eos`); particles then carry
  /// the store field "phase" (0 = water, the index into phase_eos; walls 0).
  std::vector<Eos> phase_eos;
  std::vector<std::string> phase_names;
  /// Grenier et al. (2009) two-phase formulation (Federico's System 4): density by a per-phase
  /// Shepard sum, pressure gradient Σ (p_a/Γ_a + p_b/Γ_b) ∇W V_b (store field "_gamma" = Γ);
  /// chi: the interface repulsion between phases (either formulation).
  bool grenier = false;
  double chi = 0.0;
  /// The equation of state of particle i.
  const Eos& eos_of(std::size_t i) const {
    if (phase_eos.empty()) return eos;
    return phase_eos[static_cast<std::size_t>((*phase_field_)[i])];
  }
  void bind_phase_field() { phase_field_ = &particles.scalar(field::phase); }
  /// Boundary conditions that set imposed particles from the fluid before every rates pass
  /// (e.g. open boundaries with averaged or extrapolated states); called before the walls.
  std::function<void(System&)> before_rates;
  double time = 0.0;
  long step = 0;
  std::uint64_t pairs_last_pass = 0;  // neighbour pairs visited in the last rates pass
  /// Cumulative boundary masses the run keeps (inflow_mass, outflow_mass, backflow_mass), for
  /// the gauges; set by the driver before each output.
  std::map<std::string, double> counters;

  /// The MPI ranks' halo layer (sim/ranks; null in one process): built before the periodic images.
  std::shared_ptr<Halo<D>> ranks;
  /// The global reductions (time step, mass, gauges, summary): a no-op in one process.
  std::shared_ptr<const Communicator> comm = std::make_shared<Communicator>();

  /// Whether point x lies in this process's part of the domain (always, in one process).
  bool owns(const Vec<D>& x) const { return !ranks || ranks->owns(x); }

  /// The active halo layers, in build order (core/halo.hpp).
  int halo_layers(Halo<D>** out) {
    int k = 0;
    if (ranks && ranks->active()) out[k++] = ranks.get();
    if (periodic.active()) out[k++] = &periodic;
    return k;
  }

  /// Hand the particles that left this part of the domain to their new owners (Halo::migrate),
  /// sort the owned particles into cell order (moving every per-particle field), build the halo
  /// layers and rebin. Without images the cell list then indexes the store directly
  /// (cells.identity()); images sit after the owned particles and are reached through sorted().
  /// Particle indices change: anything indexed by particle must be a store field.
  void update_neighbours() {
    particles.clear_images();
    Halo<D>* layer[2];
    const int nl = halo_layers(layer);
    for (int l = 0; l < nl; ++l) layer[l]->migrate(particles);  // (what left this part since the last build)
    // (the store still in the order of the last re-sort: only the particles that changed cell
    // are re-placed)
    const double side = cell_side();
    const double* lv = level_grid_field();
    cells.build(particles.pos, particles.n_owned(), support, cells_layout_ == particles.layout(), side, lv, levels + 1);
    if (cells.updated())
      particles.permute_runs(cells.moved(), cells.moved_from(), cells.moved_to());
    else
      particles.permute(cells.sorted());
    cells.adopt_permutation();
    cells_layout_ = particles.layout();
    for (int l = 0; l < nl; ++l) layer[l]->build(particles, support * 1.1 + dx);
    if (particles.size() > particles.n_owned()) {
      cells.build(particles.pos, particles.size(), support, false, side, level_grid_field(), levels + 1);
      cells_layout_ = 0;  // (the list now holds the images too)
    }
    set_cell_reach();
  }
  std::uint64_t cells_layout_ = 0;  // the store's layout() the cell list was last sorted for
  /// The particles' levels when the cell list takes one grid per level (null otherwise).
  const double* level_grid_field() const {
    if (cell_layout != CellLayout::Levels || levels == 0) return nullptr;
    const auto* lv = particles.find(field::level);
    return lv ? lv->data() : nullptr;
  }
  /// Copy the fields of every image from its source again (after a pass changed fields that
  /// later pair loops read from neighbours).
  void refresh_halos() {
    Halo<D>* layer[2];
    const int nl = halo_layers(layer);
    for (int l = 0; l < nl; ++l) layer[l]->refresh(particles);
  }
  /// The same for a per-particle array outside the store (a model's scratch), T per particle
  /// times `per`, indexed as the store.
  template <class T>
  void refresh_halos(T* column, std::size_t per = 1) {
    Halo<D>* layer[2];
    const int nl = halo_layers(layer);
    for (int l = 0; l < nl; ++l) layer[l]->refresh_column(particles, reinterpret_cast<std::byte*>(column), per * sizeof(T));
  }

  template <class Fn>
  decltype(auto) with_kernel(Fn&& f) const { return sph::with_kernel<D>(kernel, h, std::forward<Fn>(f)); }

  /// (the "phase" field's vector: its address stays put while particles are added or sorted)
  std::vector<double>* phase_field_ = nullptr;

  double total_mass(Kind k) const {
    double m = 0.0;
    for (std::size_t i = 0; i < particles.n_owned(); ++i)
      if (particles.kind[i] == k) m += particles.mass[i];
    return m;
  }
};

}  // namespace sph
