// The dual integrator with `scheme.pairs: advection` (schemes/dual_pairs.cpp): each advection step's pairs, their
// W'(r) and direction e, found at its start and kept through its acoustic steps, as SPHinXsys's configuration.
//  - Where the particles have not moved since the pairs were found, the kept passes are the cell passes: one step of
//    1e-9 s from a flowing state gives the same pressure acceleration, Riemann dissipation, density rate, summation
//    density and wall pressures as `pairs: acoustic`, to the float sums' round-off (the two add the same terms, W' e
//    against F r, in other orders).
//  - Outputs re-sort the store between steps (the run loop re-sorts after every step): the kept rows follow their
//    particles, so a run re-sorted between its steps ends where the same run without re-sorts does, to round-off.
//  - What the kept pairs cannot hold is refused: resolution levels (and periodic axes, MPI ranks).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "test_helpers.hpp"

using namespace sph;

namespace {
const char* kDam = R"(
dimension: 2
gravity: [0.0, -9.81]
particles: {dx: 0.01}
fluid: {density: 1000.0, viscosity: 0.0}
walls: {type: dummy, slip: free_slip}
scheme: {integrator: dual}
geometry:
  - {type: tank, min: [0.0, 0.0], max: [0.6, 0.5]}
  - {type: box, fill: fluid, min: [0.0, 0.0], max: [0.3, 0.3]}
time: {end: 1.0}
)";

/// A field of each particle by id (the two runs' stores may hold them in other orders).
template <class F>
std::vector<double> by_id(const ParticleStore<2>& P, F&& f) {
  std::vector<double> v(P.n_owned(), 0.0);
  for (std::size_t i = 0; i < P.n_owned(); ++i) v[P.id[i]] = f(i);
  return v;
}
double largest(const std::vector<double>& v) {
  double m = 0.0;
  for (const double x : v) m = std::max(m, std::abs(x));
  return m;
}
}  // namespace

TEST(WCSPHDualPairs, KeptPassesAreTheCellPassesWhereNothingMoved) {
  const double dt = 1e-9;  // (the particles move by 1e-10 m: the kernel changes by 1e-8 of itself)
  struct Result {
    std::vector<double> ax, az, dissx, dissz, drho, rho, pwall;
    double c0 = 0.0;
  };
  auto run = [&](const char* pairs) {
    test::Setup<2> s(kDam, {std::string("scheme.pairs=") + pairs});
    auto& P = s.S.particles;
    s.named->initialise(s.S);
    std::mt19937 rng(7);  // a flow: velocities up to 0.5 m/s, the same in both runs (by id)
    std::uniform_real_distribution<double> u(-0.5, 0.5);
    std::vector<Vec<2>> v0(P.n_owned());
    for (std::size_t k = 0; k < P.n_owned(); ++k) v0[k] = Vec<2>{u(rng), u(rng)};
    for (std::size_t i = 0; i < P.n_owned(); ++i)
      if (P.kind[i] == Kind::Fluid) P.vel[i] = v0[P.id[i]];
    const auto before = by_id(P, [&](std::size_t i) { return P.kind[i] == Kind::Fluid ? 1.0 : 0.0; });
    const auto vx0 = by_id(P, [&](std::size_t i) { return P.vel[i][0]; });
    const auto vz0 = by_id(P, [&](std::size_t i) { return P.vel[i][1]; });
    s.named->step(s.S, dt);
    Result r;
    r.ax = by_id(P, [&](std::size_t i) { return P.vel[i][0]; });
    r.az = by_id(P, [&](std::size_t i) { return P.vel[i][1]; });
    for (std::size_t k = 0; k < r.ax.size(); ++k) {  // pass A's acceleration: (u − u0)/Δt
      r.ax[k] = before[k] > 0.0 ? (r.ax[k] - vx0[k]) / dt : 0.0;
      r.az[k] = before[k] > 0.0 ? (r.az[k] - vz0[k]) / dt : 0.0;
    }
    auto fluid = [&](auto f) { return [&, f](std::size_t i) { return P.kind[i] == Kind::Fluid ? f(i) : 0.0; }; };
    r.dissx = by_id(P, fluid([&](std::size_t i) { return P.acc[i][0]; }));  // pass B's dissipation for the next kick
    r.dissz = by_id(P, fluid([&](std::size_t i) { return P.acc[i][1]; }));
    r.drho = by_id(P, fluid([&](std::size_t i) { return P.drho[i]; }));
    r.rho = by_id(P, fluid([&](std::size_t i) { return P.rho[i]; }));
    r.pwall = by_id(P, [&](std::size_t i) { return P.kind[i] == Kind::Wall ? P.p[i] : 0.0; });
    r.c0 = s.S.eos.c0;
    return r;
  };
  const Result a = run("acoustic"), b = run("advection");
  // Float sums of ~30 terms of either sign: the rates within 1e-5 of their largest value (~100 float ulps of it).
  // The pressures carry the summation density's rounding through the EOS, dp = ρ0 c0² dρ/ρ0 (Tait: the same at
  // ρ0): a few float ulps of ρ (2^-23 relative each) make δp = 4 ρ0 c0² 2^-23 (0.14 Pa here, on 200 Pa at the
  // bed), and the pressure acceleration δp/(ρ0 dx).
  auto same = [](const std::vector<double>& x, const std::vector<double>& y, double tol, const char* what) {
    ASSERT_EQ(x.size(), y.size());
    EXPECT_GT(largest(x), 0.0) << what;
    double worst = 0.0;
    for (std::size_t k = 0; k < x.size(); ++k) worst = std::max(worst, std::abs(x[k] - y[k]));
    EXPECT_LE(worst, tol) << what << ": largest difference " << worst << " of " << largest(x);
  };
  const double dp = 4.0 * 1000.0 * a.c0 * a.c0 * std::ldexp(1.0, -23);
  same(a.ax, b.ax, dp / (1000.0 * 0.01), "pressure acceleration x");
  same(a.az, b.az, dp / (1000.0 * 0.01), "pressure acceleration z");
  same(a.dissx, b.dissx, 1e-5 * largest(a.dissx), "Riemann dissipation x");
  same(a.dissz, b.dissz, 1e-5 * largest(a.dissz), "Riemann dissipation z");
  same(a.drho, b.drho, 1e-5 * largest(a.drho), "density rate");
  same(a.rho, b.rho, 1e-6 * 1000.0, "summation density");
  same(a.pwall, b.pwall, dp, "wall pressure");
}

TEST(WCSPHDualPairs, KeptRowsFollowTheStoreWhenItIsResorted) {
  auto run = [&](bool resort) {
    test::Setup<2> s(kDam, {"scheme.pairs=advection"});
    auto& P = s.S.particles;
    s.named->initialise(s.S);
    int moved = 0;
    for (int k = 0; k < 300; ++k) {
      s.named->step(s.S, s.named->time_step(s.S));
      if (!resort) continue;
      const auto layout = P.layout();
      s.S.update_neighbours();  // (what an output or the run loop does between steps)
      moved += P.layout() != layout;
    }
    if (resort) {
      EXPECT_GT(moved, 10);  // (the store was re-sorted under the kept rows)
    }
    EXPECT_GT(s.S.time, 0.05);
    return std::make_pair(by_id(P, [&](std::size_t i) { return P.pos[i][0]; }),
                          by_id(P, [&](std::size_t i) { return P.rho[i]; }));
  };
  const auto a = run(false), b = run(true);
  // The same sums where the rows follow their particles. The runs differ at round-off only: each advection step
  // finds its pairs after a re-sort, whose order within a cell depends on the re-sorts before, so the rows add the
  // same terms in other orders (measured: 5e-8 m and 2.5e-7 ρ0 after 300 steps). A partner lost or swapped moves
  // a particle by a fraction of dx (1e-2 m) within a few steps.
  double dx = 0.0, drho = 0.0;
  for (std::size_t k = 0; k < a.first.size(); ++k) {
    dx = std::max(dx, std::abs(a.first[k] - b.first[k]));
    drho = std::max(drho, std::abs(a.second[k] - b.second[k]));
  }
  EXPECT_LE(dx, 1e-6);
  EXPECT_LE(drho, 1e-5 * 1000.0);
}

TEST(WCSPHDualPairs, RefusedWithResolutionLevels) {
  auto error_of = [](const std::vector<std::string>& sets) {
    try {
      test::Setup<2> s(kDam, sets);
    } catch (const std::exception& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  const std::string levels = error_of({"scheme.pairs=advection",
                                       "resolution={regions: [{shape: box, min: [0.3, 0.0], max: [0.6, 0.5], level: 1}]}"});
  EXPECT_NE(levels.find("scheme.pairs: advection"), std::string::npos) << levels;
  EXPECT_NE(levels.find("resolution levels"), std::string::npos) << levels;
  const std::string bad = error_of({"scheme.pairs=sometimes"});
  EXPECT_NE(bad.find("scheme.pairs"), std::string::npos) << bad;
  EXPECT_EQ(error_of({"scheme.pairs=advection"}), "");
}
