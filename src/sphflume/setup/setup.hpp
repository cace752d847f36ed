// The set-up layer (docs/architecture.md, "Set-up"): builds the System of a case, the one path the
// CLI, the tests and the fuzzer share. build_system makes the particles (lattice fill of the shapes,
// porous zones at their own spacing, fluid inside walls dropped, hydrostatic initial density, EOS);
// setup_system adds the wall model, the scheme, phases, scalars, force terms and wall motion, and
// lets each wall model and the scheme create the per-particle fields they read.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "sphflume/core/system.hpp"
#include "sphflume/io/case.hpp"
#include "sphflume/schemes/scheme.hpp"

namespace sph {

struct BuildReport {
  std::size_t fluid = 0, wall = 0;
  std::size_t fluid_dropped_in_walls = 0;  // fluid lattice points that fell inside walls
  std::size_t first_wall = 0;              // index of the first wall particle (walls follow the fluid)
  int wall_layers = 0;
  double fluid_height = 0.0;  // vertical extent of the fluid
  // porous.relax: points moved, max h |Σ V ∇W| before and after, largest displacement [m]
  std::size_t porous_relax_band = 0;
  double porous_relax_residual0 = 0.0, porous_relax_residual = 0.0, porous_relax_shift = 0.0;
  // resolution levels: the finest, the refined fluid particles, the level interface's relaxation
  int levels = 0, level_relax_iterations = 0;
  std::size_t refined = 0, level_relax_band = 0;
  double level_relax_residual0 = 0.0, level_relax_residual = 0.0, level_relax_shift = 0.0;
};

/// What build_system refuses before allocating anything (InputError): a geometry that would
/// make more particles, or span more neighbour-search cells (side = the kernel support) over
/// the run's box, than this. The defaults only stop absurd cases (a dx typo); the fuzzer and
/// tests pass smaller limits.
struct BuildLimits {
  double max_particles = 5e8;
  double max_cells = 268435456.0;  // 2^28: 1 GiB of cell starts
  // the level interface's set-up relaxation (resolution levels): points x candidates within the level-0 support
  // at the finest spacing x iterations, an estimate of its kernel evaluations (no limit for a run; the fuzzing
  // target bounds it, as it bounds the particles, to keep every input within its time limit)
  double max_setup_pairs = 1e300;
};

/// Fill S.particles from the case geometry and set kernel, h, EOS, gravity, periodicity.
/// Checks the geometry first (docs/case-file.md, "Errors"): fluid shapes inside the domain,
/// not mostly inside walls, a sane particle count; throws InputError before computing.
/// wall_surface (optional): each wall particle's nearest point of its shape's surface, in the
/// order of the wall particles from report.first_wall.
template <int D>
BuildReport build_system(const Case& c, System<D>& S, const BuildLimits& limits = {},
                         std::vector<Vec<D>>* wall_surface = nullptr);

/// The whole set-up of a run: build_system, then the wall model (which creates its own fields),
/// the scheme (the wall-surface vectors when it needs them), phases, scalar transport, force
/// terms and wall motion. Returns the scheme; rep is build_system's report.
template <int D>
std::unique_ptr<Scheme<D>> setup_system(const Case& c, System<D>& S, BuildReport& rep, const BuildLimits& limits = {});

/// Refuse, before anything is allocated: fluid outside the domain, absurd particle counts,
/// shapes spread over absurdly many neighbour-search cells or too far out for dx (setup/checks.cpp).
template <int D>
void check_geometry(const Case& c, const BuildLimits& limits, double support, int layers);

}  // namespace sph
