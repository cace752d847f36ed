#include "sphflume/schemes/isph_options.hpp"

#include "sphflume/core/errors.hpp"
#include "sphflume/version.hpp"  // SPHFLUME_HYPRE

#include <fmt/format.h>

namespace sph {

namespace {

/// The lind formulation's shifting (`scheme.shifting` under `formulation: lind`), on by default.
void read_lind_shifting(Reader& r, IsphConfig& o) {
  // shifting on by default: Skillen et al. (2013)'s velocity-scaled form, D = 2 h |u| Δt (§7a), which leaves still
  // water still; Lind et al. (2012)'s constant D = coefficient h² (`form: constant`; auto: from the kernel's
  // lattice stability, 0.382 for Wendland C2 at h/dx 1.5, where Lind's 0.5 is at the limit 0.509) made every still
  // tank grow unstable within 2-6 s (docs/numerics.md §13b); the constant form has R = 0.2, n = 4, |δr| ≤ 0.2 dx and
  // the normal component removed near the surface, the velocity form §7a's surface treatment
  o.shifting.constant = false;
  o.shifting.coefficient = 2.0;
  if (r.has("shifting")) {
    Reader q(r.get("shifting"), r.file(), "scheme.shifting");
    o.shifting.constant = q.choice("form", "velocity", {"constant", "velocity"}) == "constant";
    if (!o.shifting.constant) {
      o.shifting.coefficient = q.in_range("coefficient", 2.0, 0.0, 20.0);
    } else if (!q.has("coefficient") || q.get("coefficient").text() == "auto") {
      o.shifting.automatic = true;
      o.shifting.coefficient = 1.0;  // (on; the value: Shifting::stable_coefficient)
    } else {
      o.shifting.coefficient = q.in_range("coefficient", 0.5, 0.0, 5.0);
    }
    o.shifting.surface = q.in_range("surface", 0.0, 0.0, 3.0);
    o.shifting.tensile = q.in_range("tensile", 0.2, 0.0, 1.0);
    o.shifting.exponent = q.in_range("exponent", 4.0, 1.0, 8.0);
    o.shifting.cap = q.in_range("cap", 0.2, 0.0, 1.0);
    q.finish();
  }
}

/// The keys that belong to one formulation: refused under the other (with the fix), read under their own.
void read_formulation_keys(Reader& r, IsphConfig& o, bool lind) {
  // keys of one formulation given to the other: refused with the fix
  auto only = [&](const char* key, bool ok, const char* which) {
    if (r.has(key) && !ok)
      r.fail_at(r.get(key), fmt::format("scheme.{}", key),
                fmt::format("scheme.formulation: {} (this key belongs to it; drop it, or set the formulation)", which));
  };
  for (const char* k : {"dummy_pressure", "gradient_normalisation", "source"}) only(k, !lind, "tsurudome");
  only("correction", lind, "lind");
  only("wall_pressure", lind, "lind");
  only("laplacian", lind, "lind");
  only("volume_correction", lind, "lind");
  only("negative_pressure", lind, "lind");
  if (lind) o.volume_correction = r.in_range("volume_correction", 0.0, 0.0, 1.0);
  if (lind) o.laplacian_corrected = r.choice("laplacian", "corrected", {"corrected", "morris"}) == "corrected";
  if (lind) o.wall_adami = r.choice("wall_pressure", "mirror", {"mirror", "adami"}) == "adami";
  // `clamp`: no tension in the water, the fluid's solved pressure held at ≥ 0 (an isolated particle of a splash,
  // or one under a lifting gate, could otherwise take −10⁴ … −10⁵ Pa and be thrown out; docs/numerics.md §13b)
  if (lind) o.clamp_negative = r.choice("negative_pressure", "keep", {"keep", "clamp"}) == "clamp";
}

}  // namespace

void read_isph_options(Reader& r, IsphConfig& o) {
  // keys of the weakly-compressible scheme: meaningless here, reported, not refused
  for (const char* k : {"integrator", "verlet_steps", "density_diffusion", "delta", "pressure_gradient",
                        "shepard_every", "xsph", "frozen"})
    if (r.has(k)) {
      const Node& n = r.get(k);
      o.ignored.push_back(fmt::format("{}: scheme.{}", n.key_line() > 0 ? fmt::format("line {}", n.key_line())
                                                                      : std::string("(given with --set)"), k));
    }
  const std::string form = r.choice("formulation", "lind", {"lind", "tsurudome"});
  o.formulation = form == "lind" ? IsphFormulation::Lind : IsphFormulation::Tsurudome;
  const bool lind = o.formulation == IsphFormulation::Lind;
  read_formulation_keys(r, o, lind);
  // the Courant number on dx/|u|max: Tsurudome's 0.2 (§3.6, eq 3.6.6); 0.4 under lind, where the dam break's
  // front, wall pressure and energy are those of 0.2 (docs/numerics.md §13b) in half the steps
  o.cfl = r.in_range("cfl", lind ? 0.4 : 0.2, 1e-4, 1.0);
  o.force_coefficient = r.in_range("force_coefficient", 0.25, 1e-4, 1.0);
  o.viscous_coefficient = r.in_range("viscous_coefficient", 0.125, 1e-4, 1.0);
  o.dt_max = r.in_range("dt_max", 0.0, 0.0, 1e3);
  o.eta2 = r.in_range("eta2", 0.01, 1e-8, 0.1);
  const std::string vm = r.choice("viscosity", "laminar", {"none", "laminar", "artificial"});
  o.viscosity = vm != "none";
  // Monaghan's term (c0 the case's reference sound speed) beside the laminar one: it damps the
  // particle-scale velocity noise of the projection (docs/numerics.md §13); `viscosity: artificial`
  // is the same with the laminar term off. 0.05 under lind (PySPH's SISPH default, Muta et al. 2020): at 0.02 the
  // noise of a thin layer on a 1:20 slope grew until particles were thrown out (cases/still_shore_isph.yaml, at
  // 0.05 and 0.1 it stays bounded, docs/numerics.md §13b)
  o.alpha = r.in_range("alpha", lind ? 0.05 : 0.02, 0.0, 1.0);
  o.laminar = vm == "laminar";
  if (lind) {
    read_lind_shifting(r, o);
  } else if (r.has("shifting")) {  // the same keys as under wcsph (physics/shifting.hpp)
    Reader q(r.get("shifting"), r.file(), "scheme.shifting");
    o.shifting.coefficient = q.in_range("coefficient", 2.0, 0.0, 20.0);
    o.shifting.surface = q.in_range("surface", 0.0, 0.0, 3.0);
    q.finish();
  }
  if (r.has("correction")) {
    Reader q(r.get("correction"), r.file(), "scheme.correction");
    o.correction_min_eigenvalue = q.in_range("min_eigenvalue", 0.25, 1e-3, 1.0);
    q.finish();
  }
  o.dummy_body_force = r.choice("dummy_pressure", "copy", {"copy", "body_force"}) == "body_force";
  o.gradient_lattice = r.choice("gradient_normalisation", "none", {"none", "lattice"}) == "lattice";
  if (r.has("source")) {
    Reader q(r.get("source"), r.file(), "scheme.source");
    const std::string t = q.choice("type", "hybrid", {"hybrid", "split", "standard", "divergence_free"});
    o.source = t == "hybrid" ? PpeSource::Hybrid : t == "standard" ? PpeSource::Standard
               : t == "split" ? PpeSource::Split : PpeSource::DivergenceFree;
    o.gamma = q.in_range("gamma", 0.97, 0.0, 1.0);
    o.relaxation = q.in_range("relaxation", 0.1, 1e-6, 1.0);
    const bool hyb = o.source == PpeSource::Hybrid, spl = o.source == PpeSource::Split;
    if (q.has("gamma") && !hyb)
      q.fail_at(q.get("gamma"), "scheme.source.gamma", "type: hybrid (gamma weighs the hybrid source; drop it, or set type: hybrid)");
    if (q.has("relaxation") && !spl)
      q.fail_at(q.get("relaxation"), "scheme.source.relaxation", "type: split (relaxation belongs to the split source)");
    o.density_deficit = q.choice("density_error", "both", {"both", "compression"}) == "both";
    q.finish();
  }
  if (r.has("free_surface")) {
    Reader q(r.get("free_surface"), r.file(), "scheme.free_surface");
    if (lind) {  // ∇·r only
      o.fs_threshold = q.in_range("threshold", 0.0, 0.0, 3.0);
      o.fs_at_surface = q.choice("condition", "surface", {"particles", "surface"}) == "surface";
      o.fs_blend = q.in_range("blend", 0.2, 0.0, 1.0);
    } else {
      o.fs_divergence = q.choice("criterion", "density", {"density", "divergence"}) == "divergence";
      o.fs_threshold = o.fs_divergence ? q.in_range("threshold", 0.0, 0.0, 3.0) : q.in_range("threshold", 0.99, 0.5, 1.2);
      if (q.has("blend")) q.fail_at(q.get("blend"), "scheme.free_surface.blend", "scheme.formulation: lind (the blend belongs to it)");
    }
    q.finish();
  }
  if (lind && !r.has("free_surface")) o.fs_threshold = 0.0;  // ∇·r < 1.5 (2D) / 2.4 (3D), P = 0 at the surface
  // the PPE's relative residual, 1e-6 (under lind 1e-5 kept the dam break's metrics with 21 % fewer iterations, but
  // Liu's porous dam break took 12 % more steps, its surface RMSE 11.8 → 12.4 mm, a particle inside the saturated
  // dam flagged: bench/README.md, session 26)
  o.tolerance = 1e-6;
  if (r.has("solver")) {
    Reader q(r.get("solver"), r.file(), "scheme.solver");
    const std::string st = q.choice("type", "auto", {"auto", "bicgstab", "boomeramg"});
    o.amg = st == "boomeramg";
    o.solver_auto = st == "auto";
    if (o.amg && !SPHFLUME_HYPRE)
      q.fail_at(q.get("type"), "scheme.solver.type",
                "bicgstab: this build has no hypre (install libhypre-dev, scripts/install-deps.sh, and rebuild)");
    o.tolerance = q.in_range("tolerance", o.tolerance, 1e-14, 1e-2);
    o.max_iterations = q.scalar<int>("max_iterations", 2000);
    if (o.max_iterations < 1 || o.max_iterations > 1000000)
      q.fail_at(q.get("max_iterations"), "scheme.solver.max_iterations", "an integer in [1, 1000000]");
    q.finish();
  }
  r.finish();
}

void check_isph_models(const Case& c) {
  // the shared models this scheme supports (the rest: a clear refusal, not a silent misuse)
  auto refuse = [&](int line, const std::string& what, const std::string& fix) {
    throw InputError(fmt::format("{}: {}{} is not supported with scheme.type: isph in this version: {}", c.file,
                                 line > 0 ? fmt::format("line {}: ", line) : std::string(), what, fix));
  };
  if (c.walls.type != "dummy" || c.walls.repulsive)
    refuse(0, fmt::format("walls.type: {}{}", c.walls.type, c.walls.repulsive ? " with repulsion" : ""),
           "use walls.type: dummy (the first wall layer carries the PPE's wall pressure, the deeper ones copy it)");
  if (!c.open_boundaries.empty()) refuse(c.open_boundaries[0].line, "open_boundaries", "use scheme.type: wcsph");
  if (c.multiphase.on()) refuse(c.multiphase.line, "multiphase", "use scheme.type: wcsph");
  if (c.transport.on()) refuse(0, "transport", "use scheme.type: wcsph");
}

}  // namespace sph
