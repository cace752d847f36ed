// SPH operators of the WCSPH scheme on a regular lattice, through the scheme's own rates pass:
// pressure gradient of a linear field, divergence of a linear velocity field (continuity),
// Laplacian of a quadratic velocity field (laminar viscosity), and the Adami wall pressure
// extrapolated on a hydrostatic column.
// On a lattice, the SPH first-derivative operators equal the exact derivative times the
// lattice moment m = -Σ_b V_b F(r) z_ab² (1 in the continuum), and the Laplacian operator
// times m_L = -Σ_b V_b F(r) z_ab² r²/(r²+η²). So each test asserts (a) the operator equals
// exact × moment to round-off (the implementation is right), and (b) the moment is within 0.5 % of
// 1 for first derivatives (0.9974 at the default h/dx = 1.5) and 2 % for the Laplacian (the
// η² = 0.01 h² regularisation alone costs 1.2 %).
#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>
#include <limits>

#include "sphflume/core/eos.hpp"
#include "sphflume/io/gauges.hpp"
#include "test_helpers.hpp"

using namespace sph;

namespace {
const char* kLattice = test::kLattice2D;

bool interior(const Vec<2>& x) { return x[0] > 0.1 && x[0] < 0.2 && x[1] > 0.1 && x[1] < 0.2; }

/// Lattice moments around particle a (see the header comment).
std::pair<double, double> moments(const System<2>& S, std::size_t a) { return test::lattice_moments(S, a); }

/// Round-off bound of the pair loop, which evaluates and sums the pair terms in single
/// precision: each term and each partial sum carries a relative error of FLT_EPSILON, so the
/// result is within ~ N FLT_EPSILON Σ|term_b| of the exact sum; 32 FLT_EPSILON Σ|term_b| for
/// the ~28 neighbours (a loose, but float-sized, bound: 1e3 times tighter than a wrong term).
template <class Term>
double float_roundoff(const System<2>& S, std::size_t a, Term&& term) {
  const auto& P = S.particles;
  WendlandC2<2> k(S.h);
  double sum = 0.0;
  S.cells.for_neighbours(P.pos, P.pos[a], k.support, [&](std::uint32_t b, const Vec<2>& r, double r2) {
    if (r2 == 0.0) return;
    sum += std::abs(term(b, r, r2, P.mass[b] / P.rho[b] * k.F(std::sqrt(r2))));
  });
  return 32.0 * FLT_EPSILON * sum;
}
}  // namespace

TEST(WCSPH, PressureGradientOfLinearField) {
  test::Setup<2> s(kLattice);
  auto& P = s.S.particles;
  const double G = 2.0e4;  // dp/dz [Pa/m]
  for (std::size_t i = 0; i < P.n_owned(); ++i) P.p[i] = 1.0e3 + G * P.pos[i][1];
  s.S.nu = 0.0;
  s.S.update_neighbours();
  s.scheme->rates(s.S);
  int n = 0;
  for (std::size_t i = 0; i < P.n_owned(); ++i) {
    if (!interior(P.pos[i])) continue;
    ++n;
    const double m = moments(s.S, i).first;
    EXPECT_NEAR(m, 1.0, 0.005);
    // pair term (p_a + p_b) V_b F r / rho_a
    const double tol = float_roundoff(s.S, i, [&](std::uint32_t b, const Vec<2>& r, double, double VF) {
      return (P.p[i] + P.p[b]) * VF * std::sqrt(dot(r, r)) / P.rho[i];
    });
    EXPECT_LT(tol, 1e-3 * G / 1000.0);  // the bound itself is small against the gradient (0.1 %)
    EXPECT_NEAR(P.acc[i][1], -G / 1000.0 * m, tol);
    EXPECT_NEAR(P.acc[i][0], 0.0, tol);
  }
  EXPECT_GT(n, 50);
}

TEST(WCSPH, ContinuityOfLinearVelocityField) {
  test::Setup<2> s(kLattice);
  auto& P = s.S.particles;
  const double A = 0.5, B = -0.2;  // u = A x, w = B z: div u = A + B
  for (std::size_t i = 0; i < P.n_owned(); ++i) P.vel[i] = Vec<2>{{A * P.pos[i][0], B * P.pos[i][1]}};
  s.S.update_neighbours();
  s.scheme->rates(s.S);
  for (std::size_t i = 0; i < P.n_owned(); ++i) {
    if (!interior(P.pos[i])) continue;
    const double m = moments(s.S, i).first;
    // pair term rho_a (u_a - u_b)·r V_b F
    const double tol = float_roundoff(s.S, i, [&](std::uint32_t b, const Vec<2>& r, double, double VF) {
      return P.rho[i] * dot(P.vel[i] - P.vel[b], r) * VF;
    });
    EXPECT_LT(tol, 1e-3 * 1000.0 * std::abs(A + B));
    EXPECT_NEAR(P.drho[i], -1000.0 * (A + B) * m, tol);
  }
}

TEST(WCSPH, LaminarViscosityIsNuLaplacian) {
  test::Setup<2> s(kLattice);
  auto& P = s.S.particles;
  const double C = 3.0;  // u = C z^2 -> nu ∇²u = 2 C nu
  for (std::size_t i = 0; i < P.n_owned(); ++i) P.vel[i] = Vec<2>{{C * P.pos[i][1] * P.pos[i][1], 0.0}};
  s.S.update_neighbours();
  s.scheme->rates(s.S);
  const double expected = 2.0 * C * 1.0e-3;
  int n = 0;
  for (std::size_t i = 0; i < P.n_owned(); ++i) {
    if (!interior(P.pos[i])) continue;
    ++n;
    const double mL = moments(s.S, i).second;
    EXPECT_NEAR(mL, 1.0, 0.02);  // includes the η² = 0.01 h² bias of ~1.2 %
    // pair term 4 nu m_b F r²/(r²+η²) |u_a - u_b| / (rho_a + rho_b)
    const double eta2 = 0.01 * s.S.h * s.S.h;
    const double tol = float_roundoff(s.S, i, [&](std::uint32_t b, const Vec<2>&, double r2, double VF) {
      return 4.0e-3 * P.rho[b] * VF * r2 / (r2 + eta2) * std::abs(P.vel[i][0] - P.vel[b][0]) / (P.rho[i] + P.rho[b]);
    });
    EXPECT_LT(tol, 1e-3 * expected);
    EXPECT_NEAR(P.acc[i][0], expected * mL, tol);
  }
  EXPECT_GT(n, 50);
}

TEST(WCSPH, EosRoundTrip) {
  for (auto type : {EosType::Tait, EosType::Linear}) {
    Eos e;
    e.type = type;
    e.c0 = 25.0;
    for (double rho : {990.0, 1000.0, 1003.7, 1020.0}) EXPECT_NEAR(e.density(e.pressure(rho)), rho, 1e-9 * rho);
    EXPECT_NEAR(e.pressure(1000.0), 0.0, 1e-9);
  }
  // gamma = 7 inverts without std::pow within 1.4 % of rho0 (a series and a Halley step): the same density as
  // std::pow's to a few units of round-off, across that range and just outside it (where std::pow takes over)
  Eos w;
  w.c0 = 20.0;
  double worst = 0.0;
  for (double base = 0.85; base <= 1.15; base += 1e-4) {
    const double p = (base - 1.0) * w.B();
    worst = std::max(worst, std::abs(w.density(p) / (w.rho0 * std::pow(base, 1.0 / 7.0)) - 1.0));
  }
  EXPECT_LE(worst, 4.0 * std::numeric_limits<double>::epsilon());
  Eos t;
  t.c0 = 20.0;
  // c^2 = dp/drho
  const double r = 1010.0, d = 1e-4;
  EXPECT_NEAR(std::pow(t.sound_speed(r), 2), (t.pressure(r + d) - t.pressure(r - d)) / (2 * d), 1e-5 * 400);
}

// A tank of water 0.5 m deep (0.4 m wide, walls 0.6 m high), dummy walls, hydrostatic at set-up.
const char* const kHydrostaticColumn = R"(
dimension: 2
gravity: [0.0, -9.81]
particles: {dx: 0.01}
fluid: {density: 1000.0, sound_speed: 30.0}
walls: {type: dummy}
geometry:
  - {type: tank, min: [0.0, 0.0], max: [0.4, 0.6]}
  - {type: box, fill: fluid, min: [0.0, 0.0], max: [0.4, 0.5]}
time: {end: 1.0}
)";

TEST(Walls, DummyWallPressureOnHydrostaticColumn) {
  // Adami et al. 2012: p_w = (Σ p_f W + g·Σ ρ_f r_wf W)/Σ W is exact for a hydrostatic field.
  test::Setup<2> s(kHydrostaticColumn);
  s.scheme->initialise(s.S);
  const auto& P = s.S.particles;
  int n = 0;
  for (std::size_t i = 0; i < P.n_owned(); ++i) {
    if (P.kind[i] != Kind::Wall || P.pos[i][1] > 0.0 || P.pos[i][0] < 0.05 || P.pos[i][0] > 0.35) continue;
    if (P.pos[i][1] < -0.02) continue;  // the layers the kernel reaches from the fluid
    ++n;
    const double expected = 1000.0 * 9.81 * (0.5 - P.pos[i][1]);
    EXPECT_NEAR(P.p[i], expected, 0.005 * 1000.0 * 9.81 * 0.5) << "wall particle at z = " << P.pos[i][1];
  }
  EXPECT_GT(n, 20);
}

// The wall_force gauge integrates the dummy walls' pressure over their faces (io/gauge_line.cpp). On a hydrostatic
// column each face-layer particle holds ρ g (H − z) within 0.5 % of ρ g H (the test above) and the midpoint sum of
// the linear profile over faces of dx is exact (clamped at 0 above the surface), so the side wall's force is ½ ρ g H²
// within 0.005 ρ g H × H = 1 %; the bed's is ρ g (H + dx/2) L (its face layer's centres lie dx/2 below the bed)
// within 0.5 %. With the wall's right part split to level 1 at set-up (faces of dx/2) the sums are the same.
TEST(Walls, WallForceGaugeIntegratesAHydrostaticColumn) {
  const std::string base = kHydrostaticColumn;
  const double rg = 1000.0 * 9.81, H = 0.5, L = 0.4, dx = 0.01;
  for (const std::string extra : {"", "resolution: {regions: [{shape: box, min: [0.25, 0.0], max: [0.4, 0.6], level: 1}]}\n"}) {
    test::Setup<2> s(base + extra);
    s.scheme->initialise(s.S);
    auto force = [&](std::vector<double> a, std::vector<double> b) {
      GaugeConfig g;
      g.type = "wall_force";
      g.start = a;
      g.end = b;
      return GaugeSet<2>::evaluate(g, s.S, 1.0)[0];
    };
    const std::string tag = extra.empty() ? "one level" : "right part at level 1";
    EXPECT_NEAR(force({0.4, 0.0}, {0.4, 0.6}), 0.5 * rg * H * H, 0.01 * 0.5 * rg * H * H) << tag;  // right wall, +x
    EXPECT_NEAR(force({0.0, 0.6}, {0.0, 0.0}), 0.5 * rg * H * H, 0.01 * 0.5 * rg * H * H) << tag;  // left wall, −x
    EXPECT_NEAR(force({0.0, 0.0}, {0.4, 0.0}), rg * (H + 0.5 * dx) * L, 0.005 * rg * H * L) << tag;  // the bed, −z
    // a stretch: the lower half of the right wall carries ¾ of the force; the face going the other way sees none
    EXPECT_NEAR(force({0.4, 0.0}, {0.4, 0.25}), 0.375 * rg * H * H, 0.01 * 0.5 * rg * H * H) << tag;
    EXPECT_EQ(force({0.4, 0.6}, {0.4, 0.0}), 0.0) << tag;
  }
}

// The same in 3D [N]: a tank 0.2 x 0.2 m with water 0.3 m deep (dx 0.02); the right wall's face (normal −x, into the
// water) carries ½ ρ g H² W and the bed's (normal +z) ρ g (H + dx/2) L W, within the 2D test's 1 % and 0.5 % of their
// scale; the face's lowest 0.16 m ρ g W (H z − z²/2); a normal pointing out of the water, nothing.
TEST(Walls, WallForceGaugeIntegratesAHydrostaticColumn3D) {
  test::Setup<3> s(R"(
dimension: 3
gravity: [0.0, 0.0, -9.81]
particles: {dx: 0.02}
fluid: {density: 1000.0, sound_speed: 30.0}
walls: {type: dummy}
geometry:
  - {type: tank, min: [0.0, 0.0, 0.0], max: [0.2, 0.2, 0.4]}
  - {type: box, fill: fluid, min: [0.0, 0.0, 0.0], max: [0.2, 0.2, 0.3]}
time: {end: 1.0}
)");
  s.scheme->initialise(s.S);
  const double rg = 1000.0 * 9.81, H = 0.3, W = 0.2, dx = 0.02;
  auto force = [&](std::vector<double> a, std::vector<double> b, std::vector<double> n) {
    GaugeConfig g;
    g.type = "wall_force";
    g.start = a;
    g.end = b;
    g.normal = n;
    return GaugeSet<3>::evaluate(g, s.S, 1.0)[0];
  };
  const double side = 0.5 * rg * H * H * W, bed = rg * (H + 0.5 * dx) * W * W;
  EXPECT_NEAR(force({0.2, 0.0, 0.0}, {0.2, 0.2, 0.4}, {-1, 0, 0}), side, 0.01 * side);
  EXPECT_NEAR(force({0.0, 0.0, 0.0}, {0.2, 0.2, 0.0}, {0, 0, 1}), bed, 0.005 * rg * H * W * W);
  const double z1 = 0.16;  // (8 rows of the face)
  EXPECT_NEAR(force({0.2, 0.0, 0.0}, {0.2, 0.2, z1}, {-1, 0, 0}), rg * W * (H * z1 - 0.5 * z1 * z1), 0.01 * side);
  EXPECT_EQ(force({0.2, 0.0, 0.0}, {0.2, 0.2, 0.4}, {1, 0, 0}), 0.0);
}

TEST(Walls, FixedGhostsMirrorAHydrostaticColumn) {
  // Marrone et al. 2011: linear MLS reproduces the linear hydrostatic field at the mirrored
  // interpolation point exactly (up to the initial density's round-off), and the Neumann
  // condition adds ρ g d: every ghost under the bed gets p = ρ g (H − z_ghost); velocities are
  // reversed (no-slip), so a fluid moving uniformly sees ghosts moving the other way.
  test::Setup<2> s(R"(
dimension: 2
gravity: [0.0, -9.81]
particles: {dx: 0.01}
fluid: {density: 1000.0, sound_speed: 30.0}
walls: {type: fixed_ghost, slip: no_slip, clamp_negative_pressure: false}
geometry:
  - {type: tank, min: [0.0, 0.0], max: [0.4, 0.6]}
  - {type: box, fill: fluid, min: [0.0, 0.0], max: [0.4, 0.5], velocity: [0.1, 0.0]}
time: {end: 1.0}
)");
  s.scheme->initialise(s.S);
  const auto& P = s.S.particles;
  const auto& mir = s.S.particles.require(field::ghost_mirror);
  int n = 0;
  for (std::size_t i = 0; i < P.n_owned(); ++i) {
    if (P.kind[i] != Kind::Wall || P.pos[i][1] > 0.0 || P.pos[i][0] < 0.05 || P.pos[i][0] > 0.35) continue;
    ++n;
    // mirror point straight above, as far above the bed as the ghost is below it
    EXPECT_NEAR(mir[i][0], P.pos[i][0], 1e-12);
    EXPECT_NEAR(mir[i][1], -P.pos[i][1], 1e-12);
    const double expected = 1000.0 * 9.81 * (0.5 - P.pos[i][1]);
    EXPECT_NEAR(P.p[i], expected, 0.002 * 1000.0 * 9.81 * 0.5) << "ghost at z = " << P.pos[i][1];
    EXPECT_NEAR(P.vel[i][0], -0.1, 1e-9);
    EXPECT_NEAR(P.vel[i][1], 0.0, 1e-9);
  }
  EXPECT_GT(n, 60);  // every layer under the bed (the mirror points of the deepest lie in the fluid too)
}

// The rates pass visiting each fluid pair once (scheme.pair_sweep: half, the default) gives what the pass over each
// particle's whole stencil gives, to float round-off: a pool with dummy no-slip walls, sheared and compressed, with
// and without XSPH, in 2D and 3D. The same single-precision pair terms summed in another order: each rate is a sum
// of ~30 (2D) to ~100 (3D) terms, some several times the result, so the two agree to ~1e-5 of the largest rate (a
// term with a wrong sign or a missed pair is of the order of the rates themselves). `levels`: a refined block in the
// pool (per-pair h, one cell grid per level: CellList::grid_half_ranges; or level 0's cells).
template <int D>
void half_sweep_equals_full_sweep(const char* xsph, const char* levels = nullptr) {
  const std::string yaml = D == 2 ? R"(
dimension: 2
gravity: [0.0, -9.81]
particles: {dx: 0.005, kernel: wendland_c2, h_over_dx: 1.5}
fluid: {density: 1000.0, viscosity: 1.0e-6, sound_speed: 20.0}
scheme: {integrator: symplectic, density_diffusion: fourtakas, viscosity: artificial, alpha: 0.05}
walls: {type: dummy, slip: no_slip}
geometry:
  - {type: tank, fill: wall, min: [0.0, 0.0], max: [0.3, 0.2]}
  - {type: box, fill: fluid, min: [0.0, 0.0], max: [0.3, 0.15]}
time: {end: 1.0}
)" : R"(
dimension: 3
gravity: [0.0, 0.0, -9.81]
particles: {dx: 0.01, kernel: wendland_c2, h_over_dx: 1.5}
fluid: {density: 1000.0, viscosity: 1.0e-6, sound_speed: 20.0}
scheme: {integrator: symplectic, density_diffusion: fourtakas, viscosity: laminar}
walls: {type: dummy, slip: no_slip}
geometry:
  - {type: tank, fill: wall, min: [0.0, 0.0, 0.0], max: [0.2, 0.1, 0.15]}
  - {type: box, fill: fluid, min: [0.0, 0.0, 0.0], max: [0.2, 0.1, 0.1]}
time: {end: 1.0}
)";
  std::vector<std::string> common = {std::string("scheme.xsph=") + xsph};
  if (levels) common.push_back(levels);
  auto full = common;
  full.push_back("scheme.pair_sweep=full");
  test::Setup<D> a(yaml, common), b(yaml, full);
  if (levels) {  // (the refined block and its cells are there)
    ASSERT_GT(a.S.levels, 0);
    ASSERT_EQ(a.S.particles.n_owned(), b.S.particles.n_owned());
  }
  for (auto* s : {&a, &b}) {
    auto& P = s->S.particles;
    for (std::size_t i = 0; i < P.n_owned(); ++i) {
      if (P.kind[i] != Kind::Fluid) continue;
      const auto& x = P.pos[i];
      P.vel[i][0] = 0.3 * std::sin(20.0 * x[D - 1]);
      P.vel[i][D - 1] = 0.1 * std::cos(17.0 * x[0]);
      P.rho[i] *= 1.0 + 0.001 * std::sin(31.0 * x[0] + 7.0 * x[D - 1]);
    }
    s->scheme->initialise(s->S);
    s->scheme->rates(s->S);
  }
  auto& A = a.S.particles;
  auto& B = b.S.particles;
  ASSERT_EQ(A.n_owned(), B.n_owned());
  const bool xs = std::string(xsph) != "0";
  double amax = 0.0, dmax = 0.0, smax = 0.0, ea = 0.0, ed = 0.0, es = 0.0;
  for (std::size_t i = 0; i < A.n_owned(); ++i) {
    ASSERT_EQ(A.id[i], B.id[i]);
    if (A.kind[i] != Kind::Fluid) {
      EXPECT_EQ(norm(A.acc[i]), 0.0);  // walls: no rates
      continue;
    }
    amax = std::max(amax, norm(A.acc[i] - a.S.gravity));
    dmax = std::max(dmax, std::abs(B.drho[i]));
    ea = std::max(ea, norm(A.acc[i] - B.acc[i]));
    ed = std::max(ed, std::abs(A.drho[i] - B.drho[i]));
    if (xs) {
      smax = std::max(smax, norm(B.vector(field::xsph)[i]));
      es = std::max(es, norm(A.vector(field::xsph)[i] - B.vector(field::xsph)[i]));
    }
  }
  EXPECT_GT(amax, 1.0);
  EXPECT_GT(dmax, 1.0);
  EXPECT_GT(ea, 0.0);  // (the two passes ran: their sums differ in order)
  EXPECT_LE(ea, 1e-5 * amax) << "acceleration, xsph " << xsph;
  EXPECT_LE(ed, 1e-5 * dmax) << "density rate, xsph " << xsph;
  if (xs) {
    EXPECT_GT(smax, 0.0);
    EXPECT_LE(es, 1e-5 * smax) << "XSPH velocity";
  }
}
TEST(WCSPH, HalfSweepEqualsFullSweep2D) {
  half_sweep_equals_full_sweep<2>("0");
  half_sweep_equals_full_sweep<2>("0.5");
}
TEST(WCSPH, HalfSweepEqualsFullSweep3D) { half_sweep_equals_full_sweep<3>("0.5"); }
TEST(WCSPH, HalfSweepEqualsFullSweepOnLevels2D) {
  const char* block = "resolution={regions: [{shape: box, min: [0.1, 0.05], max: [0.2, 0.2], level: 1}]}";
  half_sweep_equals_full_sweep<2>("0", block);
  half_sweep_equals_full_sweep<2>("0.5", block);
  half_sweep_equals_full_sweep<2>("0", "resolution={regions: [{shape: box, min: [0.1, 0.05], max: [0.2, 0.2], level: 1}], cells: level0}");
}
