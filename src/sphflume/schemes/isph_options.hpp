// The options of the incompressible (projection) scheme, `scheme: {type: isph, ...}`, as a plain
// struct, and their reader. The reader needs no YAML (core/reader.hpp): io/ calls it with the
// scheme's mapping. Keys of the weakly-compressible scheme given under `type: isph` are not
// errors: they are listed in `ignored` (file line and key) and reported as warnings, so that one
// case file runs with either scheme by changing `type` alone (docs/case-file.md).
#pragma once
#include <string>
#include <vector>

#include "sphflume/core/reader.hpp"
#include "sphflume/physics/shifting.hpp"

namespace sph {

enum class PpeSource { Hybrid, Standard, DivergenceFree };

struct IsphConfig {
  double cfl = 0.2;                  // dt <= cfl dx / |u|max (Tsurudome §6: the particle spacing, not h)
  double force_coefficient = 0.25;   // dt <= coef sqrt(h / |a|max), |a| at least |g|
  double viscous_coefficient = 0.125;// dt <= coef h^2 / (nu + nu_t)
  double dt_max = 0.0;               // 0: no cap beyond the limits above
  double eta2 = 0.01;                // η²/h² in 1/(r² + η²) (Laplacian and viscous term)
  bool viscosity = true;             // the laminar (Lo & Shao) viscous term; false = inviscid
  PpeSource source = PpeSource::Hybrid;
  double gamma = 0.97;               // hybrid source: γ div-free + (1 − γ) density-invariant
  bool fs_divergence = false;        // free surface by ∇·r < threshold (Lee et al. 2008) instead of the density
  double fs_threshold = 0.99;        // density: ρ_sum < threshold ρ_ref (Tsurudome eq 4.2.3; thesis 1.0);
                                     // divergence: 1.5 (2D), 2.4 (3D) unless given
  double tolerance = 1e-6;           // the PPE's relative residual
  int max_iterations = 2000;
  ShiftingConfig shifting;           // particle shifting after the step (off by default, as in the thesis)
  std::vector<std::string> ignored;  // WCSPH keys given here: "line N: scheme.KEY"
};

/// Reads the keys of `r` (a reader on the `scheme:` mapping, `type` already read) into `o`;
/// calls r.finish() (unknown keys are InputErrors).
void read_isph_options(Reader& r, IsphConfig& o);

}  // namespace sph
