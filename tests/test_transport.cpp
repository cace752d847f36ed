// Transported scalars and phases (Federico ch. 4, 8, 9; docs/numerics.md, Errata): the
// diffusion operators' Laplacian on a lattice (the consistent one and Federico's (4.8) give
// D∇²C, (4.7) twice that, (4.10) D/ρ ∇²C), exact conservation of the pollutant mass Σ m C/ρ on
// a disordered two-phase cloud, the reaction term, the conservative −C∇·u correction, wall
// sources, phases' densities at a continuous pressure, and the case-file errors.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <memory>
#include <random>

#include "sphflume/io/gauges.hpp"
#include "sphflume/physics/multiphase.hpp"
#include "sphflume/physics/resolution.hpp"
#include "sphflume/physics/transport.hpp"
#include "sphflume/sim/health.hpp"
#include "test_helpers.hpp"

using namespace sph;

namespace {

std::string lattice_with(const std::string& transport, const std::string& extra = "") {
  return std::string(test::kLattice2D) + transport + extra;
}

const char* kScalar = R"(
transport:
  eta2: 1.0e-8
  scalars:
    - {name: c, diffusivity: 1.0e-3, initial: [{type: expression, expression: "x^2 + z^2"}]}
)";

/// 0.3 m x 0.1 m of still water on a bed (wall layers below z = 0 from x = -0.05 to 0.35).
constexpr const char* kWaterOnABed = R"(
dimension: 2
gravity: [0.0, 0.0]
particles: {dx: 0.01, kernel: wendland_c2, h_over_dx: 1.5}
fluid: {density: 1000.0, sound_speed: 10.0, hydrostatic_init: false}
geometry:
  - {type: plane, point: [0.0, 0.0], normal: [0.0, 1.0], min: [-0.05, -0.05], max: [0.35, 0.0]}
  - {type: box, fill: fluid, min: [0.0, 0.0], max: [0.3, 0.1]}
time: {end: 1.0}
)";

/// dY/dt at the particle nearest to the lattice's centre (with uniform ρ: dC/dt = ρ dY/dt).
double centre_rate(test::Setup<2>& s) {
  s.S.update_neighbours();
  s.S.transport->rates(s.S);
  const auto& P = s.S.particles;
  std::size_t best = 0;
  for (std::size_t i = 0; i < P.n_owned(); ++i)
    if (norm(P.pos[i] - Vec<2>{{0.15, 0.15}}) < norm(P.pos[best] - Vec<2>{{0.15, 0.15}})) best = i;
  return s.S.particles.scalar("_rate_c")[best] * P.rho[best];
}

}  // namespace

// D ∇²(x² + z²) = 4D: consistent and Zhu–Fox (Federico §4.2.1) within 3 %, Federico's (4.7) 8D
// (the documented factor 2), Monaghan's (4.10) 4D/ρ (the factor 1/ρ).
TEST(Transport, LaplacianOfEachOperatorOnALattice) {
  const double D = 1.0e-3, rho = 1000.0;
  const std::pair<const char*, double> cases[] = {
      {"consistent", 4 * D}, {"zhu_fox", 4 * D}, {"tartakovsky", 4 * D}, {"federico", 8 * D}, {"monaghan", 4 * D / rho}};
  for (const auto& [op, expect] : cases) {
    test::Setup<2> s(lattice_with(kScalar), {std::string("transport.operator=") + op});
    const double r = centre_rate(s);
    EXPECT_NEAR(r, -(-expect), 0.03 * expect) << op;  // dC/dt = D∇²C > 0 at a minimum of C
  }
}

// Σ m_a dY_a/dt = 0 to round-off with the consistent operator on a disordered cloud with two
// phases (densities 1000 and 300), unequal masses and a diffusivity field: the pair terms are
// antisymmetric whatever ρ, m and D are.
TEST(Transport, ConsistentOperatorConservesPollutantMassOnADisorderedTwoPhaseCloud) {
  test::Setup<2> s(lattice_with(R"(
transport:
  scalars:
    - {name: c, diffusivity: 2.0e-3, initial: [{type: expression, expression: "sin(20*x)*cos(13*z) + 2"}]}
multiphase:
  phases:
    - {name: light, density: 300.0, shape: circle, center: [0.15, 0.15], radius: 0.08}
)"));
  auto& P = s.S.particles;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-0.3, 0.3);
  for (std::size_t i = 0; i < P.n_owned(); ++i) {
    for (int d = 0; d < 2; ++d) P.pos[i][d] += u(rng) * s.S.dx;
    P.rho[i] *= 1.0 + 0.05 * u(rng);
  }
  s.S.update_neighbours();
  s.S.transport->rates(s.S);
  const auto& rate = P.scalar("_rate_c");
  double sum = 0.0, scale = 0.0;
  for (std::size_t i = 0; i < P.n_owned(); ++i) {
    sum += P.mass[i] * rate[i];
    scale += std::abs(P.mass[i] * rate[i]);
  }
  ASSERT_GT(scale, 0.0);
  EXPECT_LT(std::abs(sum), 1e-13 * scale);
}

// C = ρ Y: compressing a particle raises C in proportion and leaves its pollutant mass m C/ρ
// (the conservative advection, −C∇·u); advection: none keeps C.
TEST(Transport, ConservativeAdvectionFollowsTheDensity) {
  for (const char* adv : {"conservative", "none"}) {
    test::Setup<2> s(lattice_with(R"(
transport:
  scalars:
    - {name: c, initial: 1.0}
)"), {std::string("transport.advection=") + adv});
    auto& P = s.S.particles;
    P.drho.assign(P.size(), 10.0);  // dρ/dt = 10 kg/m³/s everywhere
    s.S.update_neighbours();
    s.S.transport->rates(s.S);
    s.S.transport->begin_step(s.S);
    const double dt = 0.01;
    for (std::size_t i = 0; i < P.n_owned(); ++i) P.rho[i] += dt * P.drho[i];
    s.S.transport->advance(s.S, dt, true);
    const double c = P.scalar("c")[0];
    if (std::string(adv) == "conservative") EXPECT_NEAR(c, (1000.0 + 0.1) / 1000.0, 1e-12);
    else EXPECT_NEAR(c, 1.0, 2e-8);  // C (1 + ε)(1 − ε), ε = Δρ/ρ = 1e-4: the Euler step's O(ε²)
  }
}

// dC/dt = −R (C − C_eq) exactly in the rate.
TEST(Transport, FirstOrderReactionRate) {
  test::Setup<2> s(lattice_with(R"(
transport:
  scalars:
    - {name: c, initial: 1.0, reaction: {rate: 0.5, equilibrium: 0.2}}
)"));
  s.S.update_neighbours();
  s.S.transport->rates(s.S);
  auto& P = s.S.particles;
  EXPECT_NEAR(P.scalar("_rate_c")[0] * P.rho[0], -0.5 * (1.0 - 0.2), 1e-14);
}

// A flux source releases q × area per second into the fluid in total, whatever the particles.
TEST(Transport, FluxSourceReleasesItsTotal) {
  test::Setup<2> s(std::string(kWaterOnABed) + R"(
transport:
  scalars:
    - {name: c, sources: [{shape: box, min: [0.1, -0.1], max: [0.2, 0.0], flux: 0.02}]}
)");
  s.S.update_neighbours();
  s.S.transport->rates(s.S);
  auto& P = s.S.particles;
  const auto& rate = P.scalar("_rate_c");
  double total = 0.0;
  for (std::size_t i = 0; i < P.n_owned(); ++i) total += P.mass[i] * rate[i];
  // 0.1 m of bed: 10 wall columns x layers particles, area = count dx / layers = 0.1 m
  EXPECT_NEAR(total, 0.02 * 0.1, 1e-12);
}

// Phases start at the water's hydrostatic pressure (continuous p across the interface), with
// their own density and mass, and equal B: c0_k = c0 sqrt(γ_k ρ_w / (γ_w ρ_k)).
TEST(Multiphase, PhasesStartAtTheWatersPressure) {
  test::Setup<2> s(R"(
dimension: 2
gravity: [0.0, -9.81]
particles: {dx: 0.01, kernel: wendland_c2, h_over_dx: 1.5}
fluid: {density: 1000.0, sound_speed: 20.0}
geometry:
  - {type: box, fill: fluid, min: [0.0, 0.0], max: [0.3, 0.3]}
multiphase:
  phases:
    - {name: air, density: 1.0, gamma: 1.4, shape: box, min: [0.1, 0.1], max: [0.2, 0.2]}
time: {end: 1.0}
)");
  const auto& P = s.S.particles;
  const auto& ph = P.find(field::phase);
  ASSERT_NE(ph, nullptr);
  ASSERT_EQ(s.S.phase_eos.size(), 2u);
  EXPECT_NEAR(s.S.phase_eos[1].c0, 20.0 * std::sqrt(1.4 * 1000.0 / 7.0), 1e-9);
  std::size_t n_air = 0;
  for (std::size_t i = 0; i < P.n_owned(); ++i) {
    if ((*ph)[i] != 1.0) continue;
    ++n_air;
    const double p_expect = 1000.0 * 9.81 * (0.3 - P.pos[i][1]);  // the water column above the point
    EXPECT_NEAR(s.S.phase_eos[1].pressure(P.rho[i]), p_expect, 1e-6 * p_expect + 1e-9);
    EXPECT_NEAR(P.mass[i], 1.0 * 0.01 * 0.01, 1e-15);
  }
  EXPECT_EQ(n_air, 100u);
}

// Grenier's Γ_a = Σ_b V_b W_ab (Federico §3.3, eq 3.26; physics/multiphase.cpp): the vectorised cell sums equal
// the sum over every pair taken one by one (to the round-off of another order: 1e-13 of a sum of ~20 terms of
// order 1), 1 to within the lattice's quadrature error where the support lies inside the block (the Wendland C2
// kernel summed over the square lattice at h = 1.5 dx: 1.0051; gate 1 %), and at a corner the continuum's integral
// of W over the part of the support inside the block (to 10 %: the lattice's quadrature of a cut support is 5 % off
// there). No gravity: both phases' volumes are dx².
TEST(Multiphase, GrenierGammaIsTheKernelSumOfVolumes) {
  test::Setup<2> s(R"(
dimension: 2
gravity: [0.0, 0.0]
particles: {dx: 0.01, kernel: wendland_c2, h_over_dx: 1.5}
fluid: {density: 1000.0, sound_speed: 20.0}
scheme: {pressure_gradient: sum}
geometry:
  - {type: box, fill: fluid, min: [0.0, 0.0], max: [0.3, 0.3]}
multiphase:
  formulation: grenier
  phases:
    - {name: air, density: 1.0, gamma: 1.4, shape: box, min: [0.1, 0.1], max: [0.2, 0.2]}
time: {end: 1.0}
)");
  auto& S = s.S;
  S.update_neighbours();
  grenier_gamma(S);
  const auto& P = S.particles;
  const auto& gam = *P.find(field::gamma_grenier);
  const WendlandC2<2> K(S.h);
  std::size_t inside = 0, corner = 0;
  for (std::size_t a = 0; a < P.n_owned(); ++a) {
    double g = 0.0;
    for (std::size_t b = 0; b < P.n_owned(); ++b) {
      const Vec<2> r = P.pos[a] - P.pos[b];
      const double r2 = dot(r, r);
      if (r2 < K.support2) g += P.mass[b] / P.rho[b] * K.W(std::sqrt(r2));
    }
    ASSERT_NEAR(gam[a], g, 1e-13) << "particle " << a;
    const double x = P.pos[a][0], z = P.pos[a][1], m = K.support;
    if (x > m && x < 0.3 - m && z > m && z < 0.3 - m) {
      ++inside;
      EXPECT_NEAR(gam[a], 1.0, 1e-2) << "particle " << a;
    }
    if (x < 0.01 && z < 0.01) {  // half a dx from two edges: the continuum's ∫ W over the quadrant it sees
      ++corner;
      const int m = 600;
      const double lo = -0.005, d = (K.support - lo) / m;
      double fill = 0.0;
      for (int i = 0; i < m; ++i)
        for (int j = 0; j < m; ++j) fill += K.W(std::hypot(lo + (i + 0.5) * d, lo + (j + 0.5) * d)) * d * d;
      EXPECT_NEAR(gam[a], fill, 0.1 * fill);  // (0.562 against 0.536: the lattice's quadrature of a cut support)
    }
  }
  EXPECT_GT(inside, 300u);
  EXPECT_EQ(corner, 1u);
}

TEST(TransportInput, ErrorsNameTheLineAndTheFix) {
  const std::string base = std::string(test::kLattice2D);
  auto message = [&](const std::string& extra) {
    try {
      (void)parse_case(base + extra, "t.yaml");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  const std::string bad_expr = message("transport:\n  scalars:\n    - {name: c, initial: [{type: expression, expression: \"exp(-(z-0.5)^2\"}]}\n");
  EXPECT_NE(bad_expr.find("line 12"), std::string::npos) << bad_expr;
  EXPECT_NE(bad_expr.find("expression"), std::string::npos) << bad_expr;
  const std::string bad_op = message("transport:\n  operator: federicco\n  scalars: [{name: c}]\n");
  EXPECT_NE(bad_op.find("one of consistent"), std::string::npos) << bad_op;
  const std::string bad_gauge = message("transport:\n  scalars: [{name: c}]\ngauges:\n  - {name: g, type: scalar, field: d, point: [0.1, 0.1]}\n");
  EXPECT_NE(bad_gauge.find("not a transported scalar"), std::string::npos) << bad_gauge;
  const std::string frozen = message("scheme2: 1\n");
  EXPECT_NE(frozen.find("unknown key"), std::string::npos);
  const std::string no_scalars = message("transport:\n  operator: consistent\n");
  EXPECT_NE(no_scalars.find("transport.scalars"), std::string::npos) << no_scalars;
}

// A wall region held at C = 1 feeds the fluid next to it (and only there), and the mass it
// feeds is what the fluid gains: Σ m dY/dt over the fluid = the source rate the run counts.
TEST(Transport, DirichletWallFeedsTheFluidNextToIt) {
  test::Setup<2> s(std::string(kWaterOnABed) + R"(
transport:
  scalars:
    - {name: c, diffusivity: 1.0e-3, sources: [{shape: box, min: [0.1, -0.1], max: [0.2, 0.0], value: 1.0}]}
)");
  auto& P = s.S.particles;
  s.S.update_neighbours();
  s.S.transport->rates(s.S);
  s.S.transport->begin_step(s.S);
  const auto& rate = P.scalar("_rate_c");
  double total = 0.0;
  std::size_t fed = 0;
  for (std::size_t i = 0; i < P.n_owned(); ++i) {
    if (P.kind[i] != Kind::Fluid) continue;
    total += P.mass[i] * rate[i];
    const double x = P.pos[i][0], z = P.pos[i][1];
    if (rate[i] > 0.0) {
      ++fed;
      EXPECT_LT(z, s.S.support) << "fed far above the wall";
      EXPECT_GT(x, 0.1 - s.S.support);
      EXPECT_LT(x, 0.2 + s.S.support);
    } else {
      EXPECT_EQ(rate[i], 0.0);
    }
  }
  EXPECT_GT(fed, 10u);
  s.S.transport->advance(s.S, 0.01, true);
  EXPECT_NEAR(s.S.transport->source_mass(0), 0.01 * total, 1e-15 + 1e-12 * std::abs(total));
  EXPECT_GT(total, 0.0);
}

// A non-finite concentration stops the run like a non-finite velocity: the message names the
// particle and the scalar.
TEST(Transport, NonFiniteScalarFailsTheHealthCheck) {
  test::Setup<2> s(lattice_with(R"(
transport:
  scalars:
    - {name: dye, initial: 1.0}
)"));
  EXPECT_FALSE(check_health(s.S, HealthLimits{}).has_value());
  s.S.particles.scalar("dye")[7] = std::nan("");
  const auto h = check_health(s.S, HealthLimits{});
  ASSERT_TRUE(h.has_value());
  EXPECT_NE(h->find("non-finite dye"), std::string::npos) << *h;
}

// A pool whose middle is refined, carrying a scalar (the levels' transport tests).
const char* const kRefinedPoolScalar = R"(dimension: 2
particles: {dx: 0.01, kernel: wendland_c2, h_over_dx: 2.0}
fluid: {density: 1000.0, viscosity: 1.0e-6}
scheme: {viscosity: artificial, alpha: 0.02}
geometry:
  - {type: tank, fill: wall, min: [0.0, 0.0], max: [0.6, 0.4]}
  - {type: box, fill: fluid, min: [0.0, 0.0], max: [0.6, 0.3]}
resolution:
  regions:
    - {shape: box, min: [0.2, 0.1], max: [0.4, 0.4], level: 1}
transport:
  scalars:
    - {name: c, diffusivity: 1.0e-3, initial: [{type: expression, expression: "sin(20*x)*cos(13*z) + 2"}]}
time: {end: 0.1}
)";

// Resolution levels (docs/numerics.md §14): a pool whose middle is refined, with a scalar and densities that vary
// from particle to particle. The diffusion's pairs take h_ab, so Σ m (dC/ρ)/dt = 0 across the levels to round-off;
// moving the region splits the particles it now covers and merges those it left, and the scalar mass Σ m C/ρ is
// kept through both (a merge takes the mass-weighted mean of C/ρ at the merged density).
TEST(Transport, ScalarMassIsKeptAcrossLevels) {
  const std::string yaml = kRefinedPoolScalar;
  test::Setup<2> s(yaml);
  ASSERT_EQ(s.S.levels, 1);
  ASSERT_TRUE(s.S.transport);
  auto& P = s.S.particles;
  for (std::size_t i = 0; i < P.n_owned(); ++i)
    if (P.kind[i] == Kind::Fluid) {
      const double r = 1.0 + 0.01 * std::sin(23.0 * P.pos[i][0] + 7.0 * P.pos[i][1]);
      s.S.transport->field(s.S, 0)[i] *= r;  // (the same mass fraction C/ρ as before)
      P.rho[i] *= r;
    }
  s.scheme->initialise(s.S);  // (the levels' h)
  s.S.update_neighbours();
  s.S.transport->rates(s.S);
  const auto& rate = P.scalar("_rate_c");
  double sum = 0.0, scale = 0.0;
  for (std::size_t i = 0; i < P.n_owned(); ++i)
    if (P.kind[i] == Kind::Fluid) { sum += P.mass[i] * rate[i]; scale += P.mass[i] * std::abs(rate[i]); }
  ASSERT_GT(scale, 0.0);
  EXPECT_LT(std::abs(sum), 1e-12 * scale);
  auto scalar_mass = [&] {
    double m = 0.0;
    const auto& C = s.S.transport->field(s.S, 0);
    for (std::size_t i = 0; i < P.n_owned(); ++i)
      if (P.kind[i] == Kind::Fluid) m += P.mass[i] * C[i] / P.rho[i];
    return m;
  };
  const double before = scalar_mass();
  ResolutionConfig moved = s.c.resolution;
  moved.regions[0].region.min[0] += 0.15;
  moved.regions[0].region.max[0] += 0.15;
  std::uint32_t next_id = 0;
  const AdaptCounts k = adapt_levels(s.S, moved, next_id);
  EXPECT_GT(k.split, 100u);
  EXPECT_GT(k.merged, 100u);
  EXPECT_NEAR(scalar_mass(), before, 1e-12 * before);
}

// Scalars under the multirate step (issue 58): every particle's scalar takes the slow step Δ by the explicit midpoint
// rule (rates at t, the scalar at t + Δ/2, rates there; the fast passes leave the scalars' rates alone). The same
// refined pool as above, diffusing a sin·cos field for 0.02 s: the scalar mass Σ m C/ρ is kept to round-off through
// the steps, and C follows the fixed-step run's (the finest level's step everywhere) within 2 % of what diffusion
// changed (a multirate step that did not advance the scalars would miss all of it).
TEST(Transport, MultirateStepAdvancesTheScalarsAsTheFixedStep) {
  std::string yaml = kRefinedPoolScalar;
  auto run = [&](bool multirate, std::size_t& steps) {
    std::string y = yaml;
    if (multirate) y.insert(y.find("transport:"), "  multirate: true\n");
    auto s = std::make_unique<test::Setup<2>>(y);
    s->named->initialise(s->S);
    const double t_end = 0.02;
    steps = 0;
    while (s->S.time < t_end - 1e-12) {
      s->named->step(s->S, std::min(s->named->time_step(s->S), t_end - s->S.time));
      ++steps;
    }
    return s;
  };
  std::size_t n_mr = 0, n_fix = 0;
  const auto mr = run(true, n_mr), fix = run(false, n_fix);
  ASSERT_TRUE(mr->c.resolution.multirate);
  EXPECT_LT(n_mr, 0.7 * double(n_fix));  // (the slow step is longer: the test runs the multirate integrator)
  auto by_id = [](const test::Setup<2>& s) {
    std::map<std::uint32_t, std::pair<double, double>> m;  // id -> C, C at the start
    const auto& P = s.S.particles;
    const auto& C = s.S.transport->field(const_cast<System<2>&>(s.S), 0);
    for (std::size_t i = 0; i < P.n_owned(); ++i)
      if (P.kind[i] == Kind::Fluid) m[P.id[i]] = {C[i], std::sin(20 * P.pos[i][0]) * std::cos(13 * P.pos[i][1]) + 2};
    return m;
  };
  auto scalar_mass = [](const test::Setup<2>& s) {
    double m = 0.0;
    const auto& P = s.S.particles;
    const auto& C = s.S.transport->field(const_cast<System<2>&>(s.S), 0);
    for (std::size_t i = 0; i < P.n_owned(); ++i)
      if (P.kind[i] == Kind::Fluid) m += P.mass[i] * C[i] / P.rho[i];
    return m;
  };
  const double m_fix = scalar_mass(*fix), m_mr = scalar_mass(*mr);
  EXPECT_NEAR(m_mr, m_fix, 1e-11 * m_fix);  // (both keep the start's Σ m C/ρ: the pair sums are antisymmetric)
  const auto a = by_id(*mr), b = by_id(*fix);
  double change = 0.0, diff = 0.0;
  for (const auto& [id, v] : b) {
    const auto it = a.find(id);
    if (it == a.end()) continue;  // (no split or merge here: the region holds still; ids match)
    change = std::max(change, std::abs(v.first - v.second));
    diff = std::max(diff, std::abs(it->second.first - v.first));
  }
  EXPECT_EQ(a.size(), b.size());
  ASSERT_GT(change, 1e-3);
  EXPECT_LT(diff, 0.02 * change);
}

// Two phases on resolution levels (issue 58): a pool whose middle is refined holds a lighter phase across the
// refined block's left face, its edges cutting through the refined particles' parents (so that the merges' groups
// would mix the phases if they could). Moving the region splits and merges particles: each phase keeps its mass and its area
// Σ m/ρ to round-off, a merge never mixes phases (every particle's phase stays a whole index), and the rates pass
// over both levels and both phases conserves momentum (no gravity, no walls within reach).
TEST(Transport, PhasesKeepTheirMassAndAreaAcrossLevels) {
  const std::string yaml = R"(dimension: 2
gravity: [0.0, 0.0]
particles: {dx: 0.01, kernel: wendland_c2, h_over_dx: 2.0}
fluid: {density: 1000.0, viscosity: 1.0e-3, sound_speed: 10.0, hydrostatic_init: false}
scheme: {viscosity: laminar}
geometry:
  - {type: box, fill: fluid, min: [0.0, 0.0], max: [0.6, 0.4]}
multiphase:
  phases:
    - {name: oil, density: 800.0, shape: box, min: [0.1, 0.1], max: [0.295, 0.295]}  # (through the refined parents)
resolution:
  regions:
    - {shape: box, min: [0.2, 0.1], max: [0.4, 0.3], level: 1}
time: {end: 0.1}
)";
  test::Setup<2> s(yaml);
  ASSERT_EQ(s.S.levels, 1);
  ASSERT_EQ(s.S.phase_eos.size(), 2u);
  auto& P = s.S.particles;
  for (std::size_t i = 0; i < P.n_owned(); ++i)
    P.vel[i] = Vec<2>{{std::sin(17.0 * P.pos[i][1]), 0.5 * std::cos(11.0 * P.pos[i][0])}};
  s.scheme->initialise(s.S);
  const auto [sum, scale] = test::momentum_balance(P);
  ASSERT_GT(scale, 0.0);
  EXPECT_LT(sum, 1e-5 * scale);  // the float pair sums' round-off
  auto totals = [&](int phase, double& m, double& area) {
    m = 0.0; area = 0.0;
    const auto& ph = P.scalar(field::phase);
    for (std::size_t i = 0; i < P.n_owned(); ++i)
      if (P.kind[i] == Kind::Fluid && static_cast<int>(ph[i]) == phase) { m += P.mass[i]; area += P.mass[i] / P.rho[i]; }
  };
  double m0[2], a0[2];
  for (int k = 0; k < 2; ++k) totals(k, m0[k], a0[k]);
  ASSERT_GT(a0[1], 0.03);
  ResolutionConfig moved = s.c.resolution;
  moved.regions[0].region.min[0] -= 0.15;  // the block now covers the oil's left part, and leaves x > 0.25
  moved.regions[0].region.max[0] -= 0.15;
  s.S.update_neighbours();
  std::uint32_t next_id = 0;
  const AdaptCounts k = adapt_levels(s.S, moved, next_id);
  EXPECT_GT(k.split, 100u);
  EXPECT_GT(k.merged, 50u);
  for (int p = 0; p < 2; ++p) {
    double m1, a1;
    totals(p, m1, a1);
    EXPECT_NEAR(m1, m0[p], 1e-12 * m0[p]) << "phase " << p;
    EXPECT_NEAR(a1, a0[p], 1e-12 * a0[p]) << "phase " << p;
  }
  const auto& ph = P.scalar(field::phase);
  for (std::size_t i = 0; i < P.n_owned(); ++i) ASSERT_EQ(ph[i], std::round(ph[i]));
}
