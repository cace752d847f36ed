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
#include <map>
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

/// Σ m u over the owned particles, and Σ m |u| (its scale).
std::pair<Vec<2>, double> momentum(const ParticleStore<2>& P) {
  Vec<2> m{};
  double scale = 0.0;
  for (std::size_t i = 0; i < P.n_owned(); ++i) {
    m += P.mass[i] * P.vel[i];
    scale += P.mass[i] * std::sqrt(dot(P.vel[i], P.vel[i]));
  }
  return {m, scale};
}
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
  const auto [m0, scale] = momentum(P);
  for (int k = 0; k < 5; ++k) s.named->step(s.S, s.named->time_step(s.S));
  const auto [m1, unused] = momentum(P);
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

// Resolution levels (issue 58, docs/numerics.md §14): every pair's kernel at h_ab = (h_a + h_b)/2 and the summation
// density over the rest volumes m/ρ0. A level-1 lattice everywhere is the uniform run at dx/2: the same summation
// density and the same step (velocities and densities at each lattice site to the float sums' round-off, 1e-5 of the
// largest; the two runs sum their candidates in different orders).
TEST(WCSPHDual, OnOneLevelEverywhereItIsTheUniformFineScheme) {
  const std::string refined = std::string(kBlock) + "resolution: {regions: [{shape: box, min: [-1.0, -1.0], max: [1.0, 1.0], level: 1}]}\n";
  test::Setup<2> lev(refined), uni(kBlock, {"particles.dx=0.005"});
  ASSERT_EQ(lev.S.levels, 1);
  ASSERT_EQ(lev.S.particles.n_owned(), uni.S.particles.n_owned());
  auto site = [](const Vec<2>& x) { return std::make_pair(std::lround(x[0] / 0.0025), std::lround(x[1] / 0.0025)); };
  std::map<std::pair<long, long>, std::array<double, 4>> at;  // the uniform run's (ρ after set-up, ρ, u, w after a step)
  double umax = 0.0;
  int compared = 0;
  for (auto* s : {&uni, &lev}) {
    auto& P = s->S.particles;
    s->named->initialise(s->S);  // the summation density
    std::vector<double> rho0(P.n_owned());
    for (std::size_t i = 0; i < P.n_owned(); ++i) {
      rho0[i] = P.rho[i];
      P.vel[i] = Vec<2>{{0.3 * std::sin(17.0 * P.pos[i][1]), 0.2 * std::cos(11.0 * P.pos[i][0])}};
    }
    s->named->step(s->S, 1.0e-4);  // (the step opens an advection step: the density summed again, then both passes)
    for (std::size_t i = 0; i < P.n_owned(); ++i) {
      const std::array<double, 4> v{rho0[i], P.rho[i], P.vel[i][0], P.vel[i][1]};
      if (s == &uni) {
        at[site(P.pos[i])] = v;
        umax = std::max(umax, std::sqrt(dot(P.vel[i], P.vel[i])));
        continue;
      }
      ASSERT_TRUE(at.count(site(P.pos[i])));
      const auto& w = at[site(P.pos[i])];
      for (int k = 0; k < 2; ++k) EXPECT_NEAR(v[k], w[k], 1000.0 * 32 * FLT_EPSILON) << k;
      for (int k = 2; k < 4; ++k) EXPECT_NEAR(v[k], w[k], 1e-5 * umax) << k;
      ++compared;
    }
  }
  EXPECT_EQ(compared, 60 * 60);
}

// A block whose middle is refined (level 1 inside 0.1 … 0.3 m), rough velocities and densities: the pair terms
// with h_ab are antisymmetric, so five steps keep the momentum to the float sums' round-off (1e-5 of Σ m|u|, as
// the one-level test above). The summation density of the block at rest is ρ0 on each level's own lattice (the
// test above) and off it only by the interface's quadrature: the relaxed band and the smoothed h (1.0 % at most
// here; within 1.5 %, the largest gap between the lattices' Σ V W being a few per cent without the smoothing).
TEST(WCSPHDual, ConservesMomentumAcrossLevels) {
  test::Setup<2> s(test::refined_block_2d("0.0"), {"scheme.integrator=dual", "scheme.viscosity=none"});
  ASSERT_EQ(s.S.levels, 1);
  auto& P = s.S.particles;
  s.named->initialise(s.S);
  const auto& lv = P.require(field::level);
  int fine = 0, coarse = 0;
  double worst = 0.0;
  for (std::size_t i = 0; i < P.n_owned(); ++i) {
    const auto& x = P.pos[i];
    if (std::min({x[0], x[1], 0.4 - x[0], 0.4 - x[1]}) < 0.045) continue;  // (the block's free surface)
    worst = std::max(worst, std::abs(P.rho[i] / 1000.0 - 1.0));
    (lv[i] > 0.0 ? fine : coarse) += 1;
  }
  EXPECT_LT(worst, 0.015);
  EXPECT_GT(worst, 0.0);  // (the interface's quadrature: not the lattice's exact sum)
  EXPECT_GT(fine, 1000);
  EXPECT_GT(coarse, 50);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> U(-0.5, 0.5);
  for (std::size_t i = 0; i < P.n_owned(); ++i) {
    P.vel[i] = Vec<2>{{U(rng), U(rng)}};
    P.rho[i] *= 1.0 + 0.01 * U(rng);
  }
  const auto [m0, scale] = momentum(P);
  for (int k = 0; k < 5; ++k) s.named->step(s.S, s.named->time_step(s.S));
  const auto [m1, unused] = momentum(P);
  for (int d = 0; d < 2; ++d) EXPECT_NEAR(m1[d], m0[d], 1e-5 * scale) << d;
}
