// A short dam break: mass is conserved exactly (constant particle masses, none lost), no
// fluid particle crosses a wall, and two runs with the same thread count are bitwise equal.
#include <gtest/gtest.h>

#include <cstring>

#include <omp.h>

#include "test_helpers.hpp"

using namespace sph;

namespace {
const char* kDam = R"(
dimension: 2
particles: {dx: 0.01}
fluid: {density: 1000.0}
walls: {type: dummy, slip: free_slip}
scheme: {viscosity: artificial, alpha: 0.02}
geometry:
  - {type: tank, min: [0.0, 0.0], max: [0.6, 0.5]}
  - {type: box, fill: fluid, min: [0.0, 0.0], max: [0.15, 0.3]}
time: {end: 1.0}
)";

template <int D>
void run_steps(test::Setup<D>& s, int n) {
  s.scheme->initialise(s.S);
  for (int i = 0; i < n; ++i) s.scheme->step(s.S, s.scheme->time_step(s.S));
  s.S.particles.clear_images();
}
}  // namespace

TEST(Conservation, DamBreakMassAndWalls) {
  for (const char* integ : {"symplectic", "verlet", "predictor_corrector"})
  for (const char* walls : {"dummy", "dynamic"}) {
    SCOPED_TRACE(std::string(integ) + " integrator, " + walls + " walls");
    test::Setup<2> s(kDam, {std::string("walls.type=") + walls, std::string("scheme.integrator=") + integ});
    const double m0 = s.S.total_mass(Kind::Fluid);
    const std::size_t n0 = s.S.particles.count(Kind::Fluid);
    run_steps(s, 600);
    EXPECT_GT(s.S.time, 0.05);
    EXPECT_EQ(s.S.particles.count(Kind::Fluid), n0);
    EXPECT_EQ(s.S.total_mass(Kind::Fluid), m0);  // exact: masses are constant
    const auto& P = s.S.particles;
    for (std::size_t i = 0; i < P.n_owned(); ++i) {
      if (P.kind[i] != Kind::Fluid) continue;
      EXPECT_GE(P.pos[i][0], 0.0) << walls;
      EXPECT_LE(P.pos[i][0], 0.6) << walls;
      EXPECT_GE(P.pos[i][1], 0.0) << walls;
    }
  }
}

TEST(Conservation, RunsAreBitwiseReproducible) {
  test::Setup<2> a(kDam), b(kDam);
  run_steps(a, 200);
  run_steps(b, 200);
  const auto &Pa = a.S.particles, &Pb = b.S.particles;
  ASSERT_EQ(Pa.n_owned(), Pb.n_owned());
  EXPECT_EQ(0, std::memcmp(Pa.pos.data(), Pb.pos.data(), Pa.n_owned() * sizeof(Vec<2>)));
  EXPECT_EQ(0, std::memcmp(Pa.vel.data(), Pb.vel.data(), Pa.n_owned() * sizeof(Vec<2>)));
  EXPECT_EQ(0, std::memcmp(Pa.rho.data(), Pb.rho.data(), Pa.n_owned() * sizeof(double)));
}

// Each particle's pair sums are taken by one thread in a fixed order and the reductions are
// exact (max), so the thread count does not change a single bit of the result.
TEST(Conservation, RunsAreBitwiseIndependentOfThreadCount) {
  const int saved = omp_get_max_threads();
  omp_set_num_threads(1);
  test::Setup<2> a(kDam, {"scheme.integrator=verlet"});
  run_steps(a, 200);
  omp_set_num_threads(2);
  test::Setup<2> b(kDam, {"scheme.integrator=verlet"});
  run_steps(b, 200);
  omp_set_num_threads(saved);
  const auto &Pa = a.S.particles, &Pb = b.S.particles;
  ASSERT_EQ(Pa.n_owned(), Pb.n_owned());
  EXPECT_EQ(0, std::memcmp(Pa.pos.data(), Pb.pos.data(), Pa.n_owned() * sizeof(Vec<2>)));
  EXPECT_EQ(0, std::memcmp(Pa.vel.data(), Pb.vel.data(), Pa.n_owned() * sizeof(Vec<2>)));
  EXPECT_EQ(0, std::memcmp(Pa.rho.data(), Pb.rho.data(), Pa.n_owned() * sizeof(double)));
}

TEST(Conservation, ThreeDimensionalDamBreakRuns) {
  test::Setup<3> s(R"(
dimension: 3
particles: {dx: 0.02}
fluid: {density: 1000.0}
walls: {type: dummy, slip: free_slip}
scheme: {viscosity: artificial, alpha: 0.02}
geometry:
  - {type: tank, min: [0.0, 0.0, 0.0], max: [0.4, 0.1, 0.4]}
  - {type: box, fill: fluid, min: [0.0, 0.0, 0.0], max: [0.1, 0.1, 0.2]}
time: {end: 1.0}
)");
  const double m0 = s.S.total_mass(Kind::Fluid);
  run_steps(s, 150);
  EXPECT_EQ(s.S.total_mass(Kind::Fluid), m0);
  // the column has started to collapse: the front moved forward
  double front = 0.0;
  for (std::size_t i = 0; i < s.S.particles.n_owned(); ++i)
    if (s.S.particles.kind[i] == Kind::Fluid) front = std::max(front, s.S.particles.pos[i][0]);
  EXPECT_GT(front, 0.1);
  EXPECT_LT(front, 0.4);
}
