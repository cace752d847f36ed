#pragma once
#include <cmath>
#include <memory>
#include <utility>
#include <string>

#include "sphflume/boundaries/walls.hpp"
#include "sphflume/io/case.hpp"
#include "sphflume/setup/setup.hpp"
#include "sphflume/physics/force_terms.hpp"
#include "sphflume/physics/multiphase.hpp"
#include "sphflume/physics/transport.hpp"
#include "sphflume/schemes/wcsph.hpp"

/// A message that contains a part (the message printed when it does not).
#define EXPECT_HAS(msg, part) EXPECT_NE((msg).find(part), std::string::npos) << "message: " << (msg) << "\nlacks: " << (part)

namespace sph::test {

/// The InputError message of reading and building a case from text (empty when it builds).
template <int D>
std::string build_error(const std::string& text) {
  try {
    const Case c = parse_case(text, "case.yaml");
    System<D> S;
    build_system<D>(c, S);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

/// A System built from case-file text, with its wall model and force terms, ready to step.
template <int D>
struct Setup {
  Case c;
  System<D> S;
  BuildReport rep;
  std::unique_ptr<WCSPH<D>> scheme;  // WCSPH's own passes, which the operator tests call
  std::unique_ptr<Scheme<D>> named;   // the scheme the case names, as the CLI makes it
  explicit Setup(const std::string& yaml, const std::vector<std::string>& overrides = {}) {
    c = parse_case(yaml, "test.yaml", overrides);
    named = setup_system<D>(c, S, rep);  // the CLI's set-up (setup/setup.hpp)
    scheme = std::make_unique<WCSPH<D>>(c);
  }
};

/// A 0.3 m x 0.3 m block of fluid on a regular lattice (dx = 0.01, Wendland C2, h/dx = 1.5), at
/// rest, no gravity, no walls: the operator tests set a field on it and take one rates pass.
inline constexpr const char* kLattice2D = R"(
dimension: 2
gravity: [0.0, 0.0]
particles: {dx: 0.01, kernel: wendland_c2, h_over_dx: 1.5}
fluid: {density: 1000.0, viscosity: 1.0e-3, sound_speed: 10.0, hydrostatic_init: false}
scheme: {density_diffusion: none, viscosity: laminar}
geometry:
  - {type: box, fill: fluid, min: [0.0, 0.0], max: [0.3, 0.3]}
time: {end: 1.0}
)";

/// Lattice moments of the SPH operators around particle a (Wendland C2 kernel): the first-
/// derivative moment m = -Σ_b V_b F(r) z_ab² and the Laplacian moment
/// m_L = -Σ_b V_b F(r) z_ab² r²/(r² + η²), η² = eta2 h² (both 1 in the continuum).
inline std::pair<double, double> lattice_moments(const System<2>& S, std::size_t a, double eta2 = 0.01) {
  const auto& P = S.particles;
  WendlandC2<2> k(S.h);
  double m = 0.0, mL = 0.0;
  const double e2 = eta2 * S.h * S.h;
  S.cells.for_neighbours(P.pos, P.pos[a], k.support, [&](std::uint32_t b, const Vec<2>& r, double r2) {
    if (r2 == 0.0) return;
    const double V = P.mass[b] / P.rho[b], F = k.F(std::sqrt(r2));
    m -= V * F * r[1] * r[1];
    mL -= V * F * r[1] * r[1] * r2 / (r2 + e2);
  });
  return {m, mL};
}

/// A 0.4 m x 0.4 m block of fluid, no gravity, no walls, its middle (0.1 … 0.3 m) refined to level 1 (dx 0.01,
/// h/dx 2.0); `nu` the viscosity, `extra` more top-level keys: the pair terms of a model across levels.
inline std::string refined_block_2d(const std::string& nu = "1.0e-3", const std::string& extra = "") {
  return R"(dimension: 2
gravity: [0.0, 0.0]
particles: {dx: 0.01, kernel: wendland_c2, h_over_dx: 2.0}
fluid: {density: 1000.0, viscosity: )" + nu + R"(, sound_speed: 10.0, hydrostatic_init: false}
scheme: {viscosity: laminar}
geometry:
  - {type: box, fill: fluid, min: [0.0, 0.0], max: [0.4, 0.4]}
resolution:
  regions:
    - {shape: box, min: [0.1, 0.1], max: [0.3, 0.3]}
time: {end: 0.1}
)" + extra;
}

/// |Σ m a| and Σ m |a| over the owned particles: a rates pass's momentum balance and its scale.
template <int D>
std::pair<double, double> momentum_balance(const ParticleStore<D>& P) {
  Vec<D> sum{};
  double scale = 0.0;
  for (std::size_t i = 0; i < P.n_owned(); ++i) {
    sum += P.mass[i] * P.acc[i];
    scale += P.mass[i] * norm(P.acc[i]);
  }
  return {norm(sum), scale};
}

/// A 2D open channel 0.4 m long, 0.1 m deep (dx 0.01): an inflow zone [0, 0.05) imposing 0.2 m/s and an
/// outflow zone [0.35, 0.4) imposing 0.1 m/s (tests/test_open_boundary*.cpp).
inline constexpr const char* kOpenChannel2D = R"(
dimension: 2
gravity: [0.0, -9.81]
particles: {dx: 0.01}
fluid: {density: 1000.0, viscosity: 1.0e-3}
geometry:
  - {type: plane, point: [0.0, 0.0], normal: [0.0, 1.0], min: [-0.05, -0.05], max: [0.45, 0.0]}
  - {type: box, fill: fluid, min: [0.0, 0.0], max: [0.4, 0.1]}
open_boundaries:
  - {type: inflow, zone: [0.0, 0.05], depth: 0.1, profile: {type: uniform, u: 0.2}}
  - {type: outflow, zone: [0.35, 0.4], depth: 0.1, profile: {type: uniform, u: 0.1}}
time: {end: 1.0}
)";

/// A 2D block of still water 0.3 m long, 0.1 m deep, with Kazemi's imaginary-wall outlet at x = 0.3
/// (tests/test_porous.cpp, tests/test_open_boundary_3d.cpp).
inline constexpr const char* kImaginaryWall2D = R"(
dimension: 2
gravity: [0.0, -9.81]
particles: {dx: 0.01, kernel: wendland_c2, h_over_dx: 1.5}
fluid: {density: 1000.0, viscosity: 1.0e-6, sound_speed: 10.0}
geometry:
  - {type: box, fill: fluid, min: [0.0, 0.0], max: [0.3, 0.1]}
forces:
  - {type: imaginary_wall, x: 0.3, bed: 0.0, height: 0.1}
time: {end: 1.0}
)";

/// A wave-maker motion named "paddle" of `law` in still water `depth` deep (the wave tests fill in the rest).
inline MotionConfig wave_motion(const std::string& law, double depth, double gravity = 9.81) {
  MotionConfig m;
  m.name = "paddle";
  m.law = law;
  m.depth = depth;
  m.gravity = gravity;
  return m;
}

}  // namespace sph::test
