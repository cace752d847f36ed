// The per-step health check: a NaN or a density outside the sane band is caught and the
// message names the step, time, particle id, kind, position and a likely cause.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "sphflume/sim/health.hpp"
#include "test_helpers.hpp"

using namespace sph;

namespace {
const char* kTank = R"(
dimension: 2
particles: {dx: 0.02}
fluid: {density: 1000.0}
geometry:
  - {type: tank, min: [0.0, 0.0], max: [0.4, 0.4]}
  - {type: box, fill: fluid, min: [0.0, 0.0], max: [0.2, 0.2]}
time: {end: 1.0}
)";

std::size_t first_fluid(const ParticleStore<2>& P, std::size_t skip) {
  for (std::size_t i = 0; i < P.n_owned(); ++i)
    if (P.kind[i] == Kind::Fluid && skip-- == 0) return i;
  return 0;
}

bool has(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }
}  // namespace

TEST(Health, HydrostaticInitialStateIsHealthy) {
  test::Setup<2> s(kTank);
  s.scheme->initialise(s.S);
  EXPECT_FALSE(check_health(s.S, HealthLimits{}).has_value());
}

TEST(Health, NonFiniteVelocityNamesTheParticle) {
  test::Setup<2> s(kTank);
  s.S.step = 4711;
  s.S.time = 0.125;
  auto& P = s.S.particles;
  const std::size_t i = first_fluid(P, 17);
  P.vel[i][1] = std::numeric_limits<double>::quiet_NaN();
  const auto m = check_health(s.S, HealthLimits{});
  ASSERT_TRUE(m.has_value());
  EXPECT_TRUE(has(*m, "step 4711")) << *m;
  EXPECT_TRUE(has(*m, "t = 0.125 s")) << *m;
  EXPECT_TRUE(has(*m, fmt::format("particle id {} (fluid)", P.id[i]))) << *m;
  EXPECT_TRUE(has(*m, fmt::format("at ({:.6g}, {:.6g})", P.pos[i][0], P.pos[i][1]))) << *m;
  EXPECT_TRUE(has(*m, "non-finite")) << *m;
  EXPECT_TRUE(has(*m, "likely cause")) << *m;
}

// An ISPH run names ISPH's causes (its pressure solve, its step), not the sound speed it does not have.
TEST(Health, IsphFailureNamesIsphCauses) {
  for (const char* f : {"lind", "tsurudome"}) {
    test::Setup<2> s(kTank, {"scheme={type: isph, formulation: " + std::string(f) + "}"});
    HealthLimits lim;
    lim.causes = s.named->failure_causes();
    ASSERT_NE(lim.causes, nullptr) << f;
    auto& P = s.S.particles;
    P.vel[first_fluid(P, 3)][0] = std::numeric_limits<double>::infinity();
    const auto m = check_health(s.S, lim);
    ASSERT_TRUE(m.has_value());
    EXPECT_TRUE(has(*m, "pressure solve")) << *m;
    EXPECT_FALSE(has(*m, "raise fluid.sound_speed")) << *m;
  }
  test::Setup<2> w(kTank);
  EXPECT_EQ(w.named->failure_causes(), nullptr);  // WCSPH: the sound speed's advice
}

TEST(Health, DensityOutsideTheBandIsCaughtOnBothSides) {
  test::Setup<2> s(kTank);
  auto& P = s.S.particles;
  const double rho0 = s.S.eos.rho0;
  const std::size_t i = first_fluid(P, 3);
  const double keep = P.rho[i];
  HealthLimits lim;  // [0.7, 1.3] rho0
  P.rho[i] = 1.31 * rho0;
  auto m = check_health(s.S, lim);
  ASSERT_TRUE(m.has_value());
  EXPECT_TRUE(has(*m, "above the sane band")) << *m;
  EXPECT_TRUE(has(*m, "sound speed")) << *m;
  P.rho[i] = 1.29 * rho0;  // inside: fine
  EXPECT_FALSE(check_health(s.S, lim).has_value());
  P.rho[i] = 0.69 * rho0;
  m = check_health(s.S, lim);
  ASSERT_TRUE(m.has_value());
  EXPECT_TRUE(has(*m, "below the sane band")) << *m;
  P.rho[i] = keep;
  EXPECT_FALSE(check_health(s.S, lim).has_value());
}

TEST(Health, WallParticlesAreCheckedForFinitenessOnly) {
  test::Setup<2> s(kTank);
  auto& P = s.S.particles;
  std::size_t w = 0;
  while (P.kind[w] != Kind::Wall) ++w;
  P.rho[w] = 3.0 * s.S.eos.rho0;  // walls carry any density the wall model gives them
  EXPECT_FALSE(check_health(s.S, HealthLimits{}).has_value());
  P.pos[w][0] = std::numeric_limits<double>::infinity();
  const auto m = check_health(s.S, HealthLimits{});
  ASSERT_TRUE(m.has_value());
  EXPECT_TRUE(has(*m, "(wall)")) << *m;
}
