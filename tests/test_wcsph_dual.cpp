// The dual-criteria Riemann integrator (`scheme.integrator: dual`, schemes/dual.hpp):
//  - the summation density of a full lattice is rho0 in the interior (its reference sigma0 is
//    that lattice's own sum) and at least rho0 at the free surface;
//  - its pressure pass is the SPH gradient of the pressure (a linear field through the linear
//    EOS gives the exact acceleration times the lattice moment);
//  - every pair term is antisymmetric, so an isolated block's momentum is conserved to float
//    round-off by a step, whatever the velocities and densities;
//  - a dam break keeps its mass and its fluid inside the tank, and the result does not depend on
//    the thread count.
#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>
#include <cstring>
#include <random>

#include <omp.h>

#include "test_helpers.hpp"

using namespace sph;

namespace {
// a 0.3 x 0.3 block on a lattice, no walls; linear EOS (p = c0² (ρ − ρ0)), no gravity
const char* kBlock = R"(
dimension: 2
gravity: [0.0, 0.0]
particles: {dx: 0.01, kernel: wendland_c2, h_over_dx: 1.5}
fluid: {density: 1000.0, viscosity: 0.0, sound_speed: 10.0, eos: linear, hydrostatic_init: false}
scheme: {integrator: dual}
geometry:
  - {type: box, fill: fluid, min: [0.0, 0.0], max: [0.3, 0.3]}
time: {end: 1.0}
)";

bool interior(const Vec<2>& x) { return x[0] > 0.1 && x[0] < 0.2 && x[1] > 0.1 && x[1] < 0.2; }
}  // namespace

TEST(WCSPHDual, SummationDensityIsRho0OnTheLatticeAndNeverBelow) {
  test::Setup<2> s(kBlock);
  s.named->initialise(s.S);  // the dual integrator re-initialises the density by summation
  const auto& P = s.S.particles;
  int n = 0;
  for (std::size_t i = 0; i < P.n_owned(); ++i) {
    // the float sum of ~29 kernel values against the double lattice sum: 32 FLT_EPSILON
    EXPECT_GE(P.rho[i], 1000.0 * (1.0 - 32 * FLT_EPSILON));
    if (!interior(P.pos[i])) continue;
    ++n;
    EXPECT_NEAR(P.rho[i], 1000.0, 1000.0 * 32 * FLT_EPSILON);
  }
  EXPECT_GT(n, 50);
}

TEST(WCSPHDual, PressurePassIsTheSphGradient) {
  // a stiff fluid (c0 = 300 m/s): the density that carries the pressure varies by 7e-6, so the
  // volumes V_b are uniform to that order and Σ (p_a + p_b) ∇W V_b is the gradient's operator
  test::Setup<2> s(kBlock, {"scheme.density_reinit=false", "fluid.sound_speed=300"});
  auto& P = s.S.particles;
  const double c0 = 300.0, G = 2.0e3;  // dp/dz [Pa/m] through ρ = ρ0 + G z / c0²
  for (std::size_t i = 0; i < P.n_owned(); ++i) P.rho[i] = 1000.0 + G * P.pos[i][1] / (c0 * c0);
  s.named->initialise(s.S);  // the continuity pass at rest: Dρ = 0, no dissipation
  const double dt = 1e-6;
  std::vector<double> z0(P.n_owned());
  for (std::size_t i = 0; i < P.n_owned(); ++i) z0[i] = P.pos[i][1];
  s.named->step(s.S, dt);
  int n = 0;
  for (std::size_t i = 0; i < P.n_owned(); ++i) {
    if (!interior(P.pos[i])) continue;
    ++n;
    const double m = test::lattice_moments(s.S, i).first;
    // u = Δt a, a = −(1/ρ) Σ (p_a + p_b) ∇W V_b = −G m / ρ_a (the linear field's lattice moment);
    // float pair sums: 1e-3 of the value bounds their round-off (32 FLT_EPSILON Σ|terms|)
    const double a_exact = -G * m / P.rho[i];
    EXPECT_NEAR(P.vel[i][1] / dt, a_exact, 1e-3 * std::abs(a_exact));
    EXPECT_NEAR(P.vel[i][0] / dt, 0.0, 1e-3 * std::abs(a_exact));
  }
  EXPECT_GT(n, 50);
}

TEST(WCSPHDual, IsolatedBlockConservesMomentum) {
  test::Setup<2> s(kBlock);
  auto& P = s.S.particles;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> U(-0.5, 0.5);
  s.named->initialise(s.S);
  for (std::size_t i = 0; i < P.n_owned(); ++i) {
    P.vel[i] = Vec<2>{{U(rng), U(rng)}};  // a rough field: every Riemann term is active
    P.rho[i] *= 1.0 + 0.01 * U(rng);
  }
  auto momentum = [&] {
    Vec<2> m{};
    double scale = 0.0;
    for (std::size_t i = 0; i < P.n_owned(); ++i) {
      m += P.mass[i] * P.vel[i];
      scale += P.mass[i] * std::sqrt(dot(P.vel[i], P.vel[i]));
    }
    return std::make_pair(m, scale);
  };
  const auto [m0, scale] = momentum();
  for (int k = 0; k < 5; ++k) s.named->step(s.S, s.named->time_step(s.S));
  const auto [m1, unused] = momentum();
  // pair terms cancel between a and b; what is left is float round-off of the per-particle sums
  // (each ~1e-7 relative of its own terms): 1e-5 of Σ m|u| is far below a single missing pair
  for (int d = 0; d < 2; ++d) EXPECT_NEAR(m1[d], m0[d], 1e-5 * scale) << d;
}

TEST(WCSPHDual, DamBreakKeepsMassAndIsThreadIndependent) {
  const char* dam = R"(
dimension: 2
particles: {dx: 0.01}
fluid: {density: 1000.0, viscosity: 0.0}
walls: {type: dummy, slip: free_slip}
scheme: {integrator: dual}
geometry:
  - {type: tank, min: [0.0, 0.0], max: [0.6, 0.5]}
  - {type: box, fill: fluid, min: [0.0, 0.0], max: [0.15, 0.3]}
time: {end: 1.0}
)";
  const int saved = omp_get_max_threads();
  auto run = [&](int threads) {
    omp_set_num_threads(threads);
    auto s = std::make_unique<test::Setup<2>>(dam);
    s->named->initialise(s->S);
    for (int i = 0; i < 400; ++i) s->named->step(s->S, s->named->time_step(s->S));
    return s;
  };
  auto a = run(1);
  auto b = run(2);
  omp_set_num_threads(saved);
  const auto &Pa = a->S.particles, &Pb = b->S.particles;
  EXPECT_GT(a->S.time, 0.1);  // the acoustic step is ~3x the one-pass schemes' (0.6 h/c)
  double mass = 0.0, front = 0.0;
  for (std::size_t i = 0; i < Pa.n_owned(); ++i) {
    if (Pa.kind[i] != Kind::Fluid) continue;
    mass += Pa.mass[i];
    front = std::max(front, Pa.pos[i][0]);
    EXPECT_GE(Pa.pos[i][0], 0.0);
    EXPECT_LE(Pa.pos[i][0], 0.6);
    EXPECT_GE(Pa.pos[i][1], 0.0);
  }
  EXPECT_EQ(mass, a->S.total_mass(Kind::Fluid));
  EXPECT_GT(front, 0.2);  // the column has collapsed (Ritter: ~2 sqrt(g H) t)
  ASSERT_EQ(Pa.n_owned(), Pb.n_owned());
  EXPECT_EQ(0, std::memcmp(Pa.pos.data(), Pb.pos.data(), Pa.n_owned() * sizeof(Vec<2>)));
  EXPECT_EQ(0, std::memcmp(Pa.vel.data(), Pb.vel.data(), Pa.n_owned() * sizeof(Vec<2>)));
  EXPECT_EQ(0, std::memcmp(Pa.rho.data(), Pb.rho.data(), Pa.n_owned() * sizeof(double)));
}
