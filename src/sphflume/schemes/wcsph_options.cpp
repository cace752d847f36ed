// The weakly-compressible schemes' keys under `scheme:` (WCSPH, schemes/wcsph.hpp, and its
// `integrator: dual`, schemes/dual.hpp) and what they refuse (docs/case-file.md).
#include <string>

#include <fmt/format.h>

#include "sphflume/schemes/scheme_options.hpp"

namespace sph {

namespace {

/// integrator: dual carries dummy walls, one inviscid phase and no other model yet.
void check_dual(Reader& top, const Case& c) {
  // the Riemann passes carry the plain single-phase equations with dummy walls (what the dam
  // breaks need); the other models live in the one-pass loop of the other integrators
  std::string other;
  if (c.walls.type != "dummy" || c.walls.repulsive) other = "walls.type: " + c.walls.type;
  else if (c.turbulence.model != "none") other = "turbulence";
  else if (c.porous.on()) other = "porous";
  else if (c.transport.on()) other = "transport";
  else if (c.multiphase.on()) other = "multiphase";
  else if (!c.open_boundaries.empty()) other = "open_boundaries";
  else if (!c.motions.empty()) other = "motions";
  else if (c.scheme.shifting.on()) other = "scheme.shifting";
  else if (c.scheme.xsph > 0.0) other = "scheme.xsph";
  else if (c.scheme.shepard_every > 0) other = "scheme.shepard_every";
  else if (c.scheme.viscosity == ViscosityModel::Laminar && c.fluid.viscosity > 0.0) other = "fluid.viscosity > 0 with viscosity: laminar";
  if (!other.empty())
    top.fail_at(top.get("scheme"), "scheme.integrator: dual",
                fmt::format("a case without {} (the dual integrator's Riemann passes have dummy walls, one inviscid "
                            "phase and no other model yet): use integrator: symplectic or verlet", other));
  // pairs kept through an advection step hold store indices: no images (periodic axes) and one h
  if (c.scheme.pairs_per_advection && (c.resolution.on() || !c.periodic.empty()))
    top.fail_at(top.get("scheme"), "scheme.pairs: advection",
                fmt::format("a case without {} (the kept pairs hold one resolution and no periodic images): use "
                            "pairs: acoustic", c.resolution.on() ? "resolution levels" : "periodic axes"));
}

}  // namespace

void read_wcsph_options(Reader& r, Case& c) {
  // the projection scheme's own keys under type: wcsph are a mistake, not a typo: say whose they are
  for (const char* k : {"source", "free_surface", "solver", "dummy_pressure", "gradient_normalisation", "dt_max"})
    if (r.has(k))
      r.fail_at(r.get(k), fmt::format("scheme.{}", k),
                "scheme.type: isph (it is an option of the incompressible scheme), or drop the key");
  // the weakly-compressible scheme's keys
  const std::string integ = r.choice("integrator", "symplectic", {"symplectic", "predictor_corrector", "verlet", "dual"});
  c.scheme.integrator = integ == "symplectic" ? Integrator::Symplectic
                        : integ == "verlet"   ? Integrator::Verlet
                        : integ == "dual"     ? Integrator::Dual : Integrator::PredictorCorrector;
  const bool dual = c.scheme.integrator == Integrator::Dual;
  c.scheme.advection_cfl = r.in_range("advection_cfl", 0.25, 1e-3, 1.0);
  c.scheme.riemann_limiter = r.in_range("riemann_limiter", 3.0, 0.0, 1e3);
  c.scheme.density_reinit = r.scalar<bool>("density_reinit", true);
  c.scheme.pairs_per_advection = r.choice("pairs", "acoustic", {"acoustic", "advection"}) == "advection";
  if (!dual)
    for (const char* k : {"advection_cfl", "riemann_limiter", "density_reinit", "pairs"})
      if (r.has(k)) c.warnings.push_back(fmt::format("{}: scheme.{}: only used by integrator: dual (ignored)", r.file(), k));
  // the rates pass: each fluid pair once, its two sides from one evaluation (half stencils), or each particle over its
  // whole stencil (the pair evaluated at both ends; the sums of the versions before it, for comparisons)
  c.scheme.half_sweep = r.choice("pair_sweep", "half", {"half", "full"}) == "half";
  c.scheme.verlet_steps = r.scalar<int>("verlet_steps", 40);
  if (c.scheme.verlet_steps < 0) r.fail_at(r.get("verlet_steps"), "scheme.verlet_steps", "an integer >= 0 (0 = no Euler steps)");
  const std::string dd = r.choice("density_diffusion", "fourtakas", {"none", "molteni_colagrossi", "fourtakas"});
  c.scheme.density_diffusion = dd == "none" ? DensityDiffusion::None
                               : dd == "fourtakas" ? DensityDiffusion::Fourtakas : DensityDiffusion::MolteniColagrossi;
  c.scheme.delta = r.in_range("delta", 0.1, 0.0, 1.0);
  const std::string vm = r.choice("viscosity", "laminar", {"none", "laminar", "artificial"});
  c.scheme.viscosity = vm == "none" ? ViscosityModel::None : vm == "laminar" ? ViscosityModel::Laminar : ViscosityModel::Artificial;
  c.scheme.alpha = r.in_range("alpha", 0.01, 0.0, 10.0);
  c.scheme.pressure_gradient = r.choice("pressure_gradient", "sum", {"sum", "symmetric"}) == "sum"
                                   ? PressureGradient::Sum : PressureGradient::Symmetric;
  c.scheme.shepard_every = r.scalar<int>("shepard_every", 0);
  if (c.scheme.shepard_every < 0) r.fail_at(r.get("shepard_every"), "scheme.shepard_every", "an integer >= 0 (0 = off)");
  c.scheme.xsph = r.in_range("xsph", 0.0, 0.0, 1.0);
  if (r.has("shifting")) {
    Reader q(r.get("shifting"), r.file(), "scheme.shifting");
    c.scheme.shifting.coefficient = q.in_range("coefficient", 2.0, 0.0, 20.0);
    c.scheme.shifting.surface = q.in_range("surface", 0.0, 0.0, 3.0);
    q.finish();
  }
  // the dual integrator's acoustic steps are position-Verlet with Riemann dissipation: 0.6 is
  // stable (docs/numerics.md); the one-stage schemes keep DualSPHysics' 0.2
  c.scheme.cfl = r.in_range("cfl", dual ? 0.6 : 0.2, 1e-4, 1.5);
  c.scheme.viscous_coefficient = r.in_range("viscous_coefficient", 0.125, 1e-4, 1.0);
  c.scheme.force_coefficient = r.in_range("force_coefficient", 0.25, 1e-4, 1.0);
  c.scheme.eta2 = r.in_range("eta2", 0.01, 1e-8, 0.1);
  c.scheme.frozen = r.scalar<bool>("frozen", false);
  r.finish();
}

void check_wcsph_case(Reader& top, Case& c) {
  if (c.scheme.integrator == Integrator::Dual) check_dual(top, c);
  if (c.scheme.frozen && !c.transport.on())
    top.fail_at(top.get("scheme"), "scheme.frozen", "a 'transport:' section too (a frozen flow only transports scalars)");
}

}  // namespace sph
