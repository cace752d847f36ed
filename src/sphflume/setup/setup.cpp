// The set-up of a run (setup/setup.hpp): setup_system, build_system's particles made a runnable system.
#include "sphflume/setup/setup.hpp"

#include <stdexcept>

#include <fmt/format.h>

#include "sphflume/boundaries/motion.hpp"
#include "sphflume/boundaries/walls.hpp"
#include "sphflume/physics/force_terms.hpp"
#include "sphflume/physics/multiphase.hpp"
#include "sphflume/physics/porous.hpp"
#include "sphflume/physics/transport.hpp"

namespace sph {

template <int D>
std::unique_ptr<Scheme<D>> setup_system(const Case& c, System<D>& S, BuildReport& rep, const BuildLimits& limits) {
  std::vector<Vec<D>> surface;
  rep = build_system<D>(c, S, limits, &surface);
  if (c.multiphase.on()) {
    if (c.turbulence.model != "none" || c.porous.on())
      throw InputError(fmt::format("{}: line {}: 'multiphase': several phases with a turbulence model or porous regions "
                                   "are not supported in this version: remove one of them", c.file, c.multiphase.line));
    if (c.scheme.shifting.on())
      throw InputError(fmt::format("{}: line {}: 'multiphase': particle shifting (scheme.shifting) across a phase "
                                   "interface is not supported in this version: remove scheme.shifting", c.file, c.multiphase.line));
    if (c.multiphase.grenier && c.scheme.pressure_gradient != PressureGradient::Sum)
      throw InputError(fmt::format("{}: line {}: multiphase.formulation: grenier needs scheme.pressure_gradient: sum "
                                   "(its p/Γ terms take the place of (p_a + p_b))", c.file, c.multiphase.line));
    setup_phases<D>(c, S);
  }
  if (c.transport.on()) {
    S.transport = std::make_shared<ScalarTransport<D>>(c.transport, c.transport.eta2, rep.wall_layers);
    try {
      S.transport->initialise(S);
    } catch (const InputError& e) {
      throw InputError(fmt::format("{}: {}", c.file, e.what()));
    }
  }
  std::unique_ptr<Scheme<D>> scheme;
  try {
    S.walls = wall_registry<D>().create(c.walls.type, c.walls);
    scheme = scheme_registry<D>().create(c.scheme.type, c);
  } catch (const std::invalid_argument& e) {
    throw InputError(fmt::format("{}: {}", c.file, e.what()));
  }
  // the per-wall-particle fields: the wall model's own, and the vector to the wall's surface where
  // the scheme or a wall motion reads it
  S.walls->init_fields(S, rep.first_wall, surface);
  if (scheme->needs_wall_surface() || !c.motions.empty()) {
    auto& to = S.particles.vector(field::wall_to_surface);
    for (std::size_t k = 0; k < surface.size(); ++k) to[rep.first_wall + k] = surface[k] - S.particles.pos[rep.first_wall + k];
  }
  bool flap = false;
  for (const auto& m : c.motions) flap |= m.paddle == "flap";
  if (flap) {  // a flap turns its walls' surface vectors (and normals) from their rest values
    S.particles.vector(field::motion_surface0) = S.particles.vector(field::wall_to_surface);
    if (S.particles.has(field::wall_normal)) S.particles.vector(field::motion_normal0) = S.particles.vector(field::wall_normal);
  }
  add_force_terms<D>(c.forces, c.file, S);
  if (!c.motions.empty()) S.motion = std::make_shared<WallMotion<D>>(c.motions, c.file);
  return scheme;
}

#define SPHFLUME_INSTANTIATE(D)                                                                                      \
  template std::unique_ptr<Scheme<D>> setup_system<D>(const Case&, System<D>&, BuildReport&, const BuildLimits&);
SPHFLUME_INSTANTIATE(2)
SPHFLUME_INSTANTIATE(3)
#undef SPHFLUME_INSTANTIATE

}  // namespace sph
