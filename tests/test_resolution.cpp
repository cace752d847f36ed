// Resolution levels (issue 42, docs/numerics.md §14): the split keeps mass, momentum and the
// centre of mass to round-off; a refined region gives 2^D children per lattice point with their
// level's mass and h; the per-pair h path (VarH) reproduces the one-level pass when every h is
// equal and conserves momentum between particles of different sizes; every wall model and the Shepard
// filter on a level-1 lattice everywhere are the uniform fine run's; the models the levels do
// not serve yet, and refined fluid next to walls, are refused with their lines.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <map>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>

#include <omp.h>

#include "sphflume/core/refinement.hpp"
#include "sphflume/physics/porous.hpp"
#include "sphflume/physics/resolution.hpp"
#include "sphflume/schemes/wcsph_common.hpp"
#include "test_helpers.hpp"

using namespace sph;

namespace {

// A still pool 0.6 m x 0.3 m in a tank; a refined box in its middle, one support (0.04 m at
// h/dx = 2) clear of the walls.
std::string pool(const std::string& region, const std::string& extra = "") {
  return R"(dimension: 2
particles: {dx: 0.01, kernel: wendland_c2, h_over_dx: 2.0}
fluid: {density: 1000.0, viscosity: 1.0e-6}
scheme: {viscosity: artificial, alpha: 0.02}
geometry:
  - {type: tank, fill: wall, min: [0.0, 0.0], max: [0.6, 0.4]}
  - {type: box, fill: fluid, min: [0.0, 0.0], max: [0.6, 0.3], velocity: [0.3, -0.1]}
resolution:
  regions:
    - )" + region + R"(
time: {end: 0.1}
)" + extra;
}
const char* kBlock = "{shape: box, min: [0.2, 0.1], max: [0.4, 0.4], level: 1}";
const char* kAboveWater = "{shape: box, min: [0.2, 0.33], max: [0.4, 0.4], level: 1}";

// A still pool 0.2 m deep in front of a 1:2 beach (toe x = 0.5 m, top 0.4 m); `porous`: the beach a
// porous region (Tsurudome's porous-particle field) instead of a wall slope; `region`: the refined one.
std::string beach_case(const std::string& region, bool porous = false) {
  std::string y = R"(dimension: 2
particles: {dx: 0.01, kernel: wendland_c2, h_over_dx: 2.0}
fluid: {density: 1000.0, viscosity: 1.0e-6}
scheme: {viscosity: artificial, alpha: 0.02}
)";
  if (porous)
    y += R"(porous:
  field: particles
  regions:
    - {shape: slope, toe: [0.5, 0.0], gradient: '1:2', top: 0.4, porosity: 0.49, diameter: 0.001,
       closure: {type: tsurudome, c1: 150, c2: 1.75}}
)";
  y += R"(geometry:
  - {type: tank, fill: wall, min: [0.0, 0.0], max: [1.4, 0.5]}
)";
  if (!porous) y += "  - {type: slope, toe: [0.5, 0.0], gradient: '1:2', top: 0.4}\n";
  y += R"(  - {type: box, fill: fluid, min: [0.0, 0.0], max: [1.4, 0.2]}
resolution:
  regions:
    - )" + region + "\ntime: {end: 0.1}\n";
  return y;
}

template <int D>
Vec<D> momentum(const System<D>& S) {
  Vec<D> p{};
  const auto& P = S.particles;
  for (std::size_t i = 0; i < P.n_owned(); ++i)
    if (P.kind[i] == Kind::Fluid) p += P.mass[i] * P.vel[i];
  return p;
}

}  // namespace

TEST(Resolution, SplitKeepsMassMomentumAndCentre) {
  const Vec<2> x{{0.123456789, -0.987654321}};
  const auto kids = split_positions<2>(x, 0.005);
  ASSERT_EQ(kids.size(), 4u);
  Vec<2> c{};
  for (const auto& k : kids) c += 0.25 * k;
  EXPECT_NEAR(c[0], x[0], 1e-15);
  EXPECT_NEAR(c[1], x[1], 1e-15);
  // the children sit on the finer lattice: dx/2 apart
  EXPECT_NEAR(norm(kids[1] - kids[0]), 0.005, 1e-15);
  EXPECT_NEAR(norm(kids[2] - kids[0]), 0.005, 1e-15);
  const double m = 0.1 * 0.1 * 1000.0;
  EXPECT_EQ(4.0 * level_mass<2>(m, 1), m);  // a power-of-two share: exact
  EXPECT_EQ(64.0 * level_mass<3>(m, 2), m);
  EXPECT_EQ(level_h(0.02, 2), 0.005);
  const auto k3 = split_positions<3>(Vec<3>{{1.0, 2.0, 3.0}}, 0.01);
  Vec<3> c3{};
  for (const auto& k : k3) c3 += 0.125 * k;
  EXPECT_NEAR(norm(c3 - Vec<3>{{1.0, 2.0, 3.0}}), 0.0, 1e-15);
}

TEST(Resolution, RegionSplitsTheLatticeKeepingMassAndMomentum) {
  test::Setup<2> one(pool(kAboveWater)), two(pool(kBlock));
  const auto& P1 = one.S.particles;
  const auto& P2 = two.S.particles;
  // the block's 20 x 20 lattice points become 40 x 40 children: 3 more per point
  EXPECT_EQ(P2.count(Kind::Fluid), P1.count(Kind::Fluid) + 3 * 400);
  EXPECT_EQ(two.rep.refined, 1600u);
  EXPECT_NEAR(two.S.total_mass(Kind::Fluid), one.S.total_mass(Kind::Fluid), 1e-12 * one.S.total_mass(Kind::Fluid));
  const Vec<2> p1 = momentum(one.S), p2 = momentum(two.S);
  for (int d = 0; d < 2; ++d) EXPECT_NEAR(p2[d], p1[d], 1e-12 * norm(p1));
  // each particle carries its level's mass and, before the first pass smooths it, its h
  const auto& lv = P2.require(field::level);
  const auto& h = P2.require(field::smoothing_length);
  const double m0 = 1000.0 * 0.01 * 0.01;
  for (std::size_t i = 0; i < P2.n_owned(); ++i) {
    if (P2.kind[i] != Kind::Fluid) {
      EXPECT_EQ(h[i], two.S.h);
      continue;
    }
    const int l = static_cast<int>(lv[i]);
    EXPECT_EQ(P2.mass[i], level_mass<2>(m0, l));
    EXPECT_EQ(h[i], level_h(two.S.h, l));
  }
  EXPECT_EQ(two.S.levels, 1);
  EXPECT_DOUBLE_EQ(two.S.finest_h(), 0.5 * two.S.h);
  // smoothed h: level 0 far from the block, level 1 deep inside it, in between across the interface
  two.S.update_neighbours();
  smooth_level_h(two.S);
  double hmin = 1.0, hmax = 0.0;
  for (std::size_t i = 0; i < P2.n_owned(); ++i)
    if (P2.kind[i] == Kind::Fluid) { hmin = std::min(hmin, h[i]); hmax = std::max(hmax, h[i]); }
  EXPECT_NEAR(hmin, 0.5 * two.S.h, 1e-12);
  EXPECT_NEAR(hmax, two.S.h, 1e-12);
}

/// The same particles' rates in two set-ups (matched by position: the cell list's order may
/// differ): {max |a|, max |dρ/dt| of the first, max |Δa|, max |Δ dρ/dt|}; NaN when a particle
/// of the first has no twin in the second.
std::array<double, 4> rate_differences(const ParticleStore<2>& Pa, const ParticleStore<2>& Pb) {
  std::map<std::pair<double, double>, std::size_t> in_b;
  for (std::size_t j = 0; j < Pb.n_owned(); ++j) in_b[{Pb.pos[j][0], Pb.pos[j][1]}] = j;
  std::array<double, 4> r{0.0, 0.0, 0.0, 0.0};
  for (std::size_t i = 0; i < Pa.n_owned(); ++i) {
    const auto it = in_b.find({Pa.pos[i][0], Pa.pos[i][1]});
    if (it == in_b.end() || Pa.n_owned() != Pb.n_owned()) return {NAN, NAN, NAN, NAN};
    const std::size_t j = it->second;
    r[0] = std::max(r[0], norm(Pa.acc[i]));
    r[1] = std::max(r[1], std::abs(Pa.drho[i]));
    r[2] = std::max(r[2], norm(Pa.acc[i] - Pb.acc[j]));
    r[3] = std::max(r[3], std::abs(Pa.drho[i] - Pb.drho[j]));
  }
  return r;
}

TEST(Resolution, EqualSmoothingLengthsReproduceTheOneLevelPass) {
  // a region above the water: the case runs the per-pair h path with every h = h0, which must
  // give the one-level pass's rates to single-precision round-off
  const std::string one_level = pool(kAboveWater).substr(0, pool(kAboveWater).find("resolution:")) + "time: {end: 0.1}\n";
  test::Setup<2> a(one_level), b(pool(kAboveWater));
  ASSERT_EQ(a.S.particles.size(), b.S.particles.size());
  a.scheme->initialise(a.S);
  b.scheme->initialise(b.S);
  const auto [amax, dmax, da, dd] = rate_differences(a.S.particles, b.S.particles);
  ASSERT_GT(amax, 1.0);  // (gravity and the initial velocity's viscous and continuity terms)
  EXPECT_LT(da, 1e-5 * amax);  // float pair sums: ~1e-7 per term, over ~50 neighbours
  EXPECT_LT(dd, 1e-5 * dmax + 1e-9);
}

TEST(Resolution, FinestCellsGiveTheLevel0CellsRates) {
  // `resolution.cells: finest`: cells as wide as the fine pairs' support, each cell's stencil
  // narrowed to its own pairs (CellList::set_reach). The same pairs as the level-0 cells' 3^D
  // stencil: the rates agree to the float pair sums' round-off (another summation order)
  test::Setup<2> a(pool(std::string(kBlock) + "\n  cells: level0")), b(pool(std::string(kBlock) + "\n  cells: finest"));
  ASSERT_EQ(a.S.particles.size(), b.S.particles.size());
  a.scheme->initialise(a.S);
  b.scheme->initialise(b.S);
  ASSERT_FALSE(a.S.cells.level_grids());
  EXPECT_LT(b.S.cells.cell_size(), 0.51 * a.S.cells.cell_size());  // (the test exercises the narrow cells)
  int narrow = 0;
  for (const auto c : b.S.cells.occupied()) narrow += b.S.cells.reach(c) == 1 ? 1 : 0;
  EXPECT_GT(narrow, 10);
  const auto [amax, dmax, da, dd] = rate_differences(a.S.particles, b.S.particles);
  ASSERT_GT(amax, 1.0);
  // float pair sums with the positions taken relative to another cell's first particle: the
  // pressure terms (~30x the net acceleration each) round at ~1e-7 over ~50-200 neighbours,
  // ~2e-5 of amax; a pair missed within the support would move a rate by ~1e-2 of amax (the
  // completeness itself: CellList.VariableReachHoldsEveryPair2D)
  EXPECT_LT(da, 1e-4 * amax);
  EXPECT_LT(dd, 1e-4 * dmax + 1e-9);
}

TEST(Resolution, LevelGridsGiveTheLevel0CellsRates) {
  // `resolution.cells: levels` (the default): one grid of cells per level (core/cell_grids.hpp).
  // The same pairs as the level-0 cells' 3^D stencil, so the same rates to the float sums'
  // round-off (tolerances as above; the completeness itself: CellList.LevelGridsHoldEveryPair2D),
  // and the same mass and particles; the level-1 cells are half as wide and hold only level 1
  test::Setup<2> a(pool(std::string(kBlock) + "\n  cells: level0")), b(pool(kBlock));
  ASSERT_EQ(a.S.particles.size(), b.S.particles.size());
  a.scheme->initialise(a.S);
  b.scheme->initialise(b.S);
  ASSERT_TRUE(b.S.cells.level_grids());
  const auto& lv = b.S.particles.scalar(field::level);
  std::size_t fine = 0;
  for (const auto c : b.S.cells.occupied()) {
    const std::uint32_t k0 = b.S.cells.cell_begin(c);
    const double l = lv[b.S.cells.sorted()[k0]];
    for (std::uint32_t k = k0; k < b.S.cells.cell_end(c); ++k) ASSERT_EQ(lv[b.S.cells.sorted()[k]], l) << "a cell holds two levels";
    fine += l == 1.0 ? 1 : 0;
  }
  EXPECT_GT(fine, 10u);
  const auto [amax, dmax, da, dd] = rate_differences(a.S.particles, b.S.particles);
  ASSERT_GT(amax, 1.0);
  EXPECT_LT(da, 1e-4 * amax);
  EXPECT_LT(dd, 1e-4 * dmax + 1e-9);
}

TEST(Resolution, PairTermsConserveMomentumBetweenSizes) {
  // no gravity, no walls within reach: a sheared, compressed block whose middle is refined;
  // every pair force is antisymmetric with h_ab = (h_a + h_b)/2, so Σ m a = 0 to round-off
  test::Setup<2> s(test::refined_block_2d());
  auto& P = s.S.particles;
  for (std::size_t i = 0; i < P.n_owned(); ++i) {
    P.vel[i] = Vec<2>{{std::sin(17.0 * P.pos[i][1]), 0.5 * std::cos(11.0 * P.pos[i][0])}};
    P.rho[i] = 1000.0 * (1.0 + 0.01 * std::sin(23.0 * P.pos[i][0] + 7.0 * P.pos[i][1]));
  }
  s.scheme->initialise(s.S);
  const auto [sum, scale] = test::momentum_balance(P);
  ASSERT_GT(scale, 0.0);
  EXPECT_LT(sum, 1e-5 * scale);  // the float pair sums' round-off
}

TEST(Resolution, RefusesWhatTheLevelsCannotServeYet) {
  auto err = [](const std::string& region, const std::string& extra) { return test::build_error<2>(pool(region, extra)); };
  std::string isph = pool(kBlock);
  isph.replace(isph.find("scheme: {"), 9, "scheme: {type: isph, ");
  const std::string e1 = test::build_error<2>(isph);
  EXPECT_HAS(e1, "line 8: 'resolution'");
  EXPECT_HAS(e1, "scheme.type: isph (line 4)");
  EXPECT_EQ(err(kBlock, "multiphase: {phases: [{name: oil, density: 900.0, shape: box, min: [0.05, 0.05], max: [0.15, 0.15]}]}\n"),
            "");  // served since issue 58
  EXPECT_EQ(err(kBlock, "transport: {scalars: [{name: c, diffusivity: 1.0e-3}]}\n"), "");  // served since issue 58
  EXPECT_EQ(err(std::string(kBlock) + "\n  multirate: true", "transport: {scalars: [{name: c, diffusivity: 1.0e-3}]}\n"),
            "");  // served since issue 58 (Transport.MultirateStepAdvancesTheScalarsAsTheFixedStep)
  EXPECT_EQ(err(kBlock, "turbulence: {model: mixing_length}\n"), "");  // served since issue 58
  for (const char* w : {"walls: {type: dynamic}\n", "walls: {type: fixed_ghost}\n", "walls: {type: repulsive}\n"})
    EXPECT_EQ(err(kBlock, w), "") << w;  // served since issue 58 (Resolution.WallModelsOnOneLevelEverywhereAreTheUniformFineWalls)
  EXPECT_EQ(test::build_error<2>(pool(kBlock)), "");
  EXPECT_HAS(err("{shape: box, min: [0.2, 0.1], max: [0.4, 0.4], level: 4}", ""), "resolution.regions.0.level");
  EXPECT_HAS(err("{shape: box, min: [0.2, 0.1], max: [0.4, 0.4], level: 1.5}", ""), "a whole number of halvings");
  EXPECT_HAS(err("{shape: box, min: [0.2, 0.1], max: [0.4, 0.4], levl: 1}", ""), "levl");
}

TEST(Resolution, WallsNearARegionTakeItsLevel) {
  // a region against the left wall and the bed: the wall points within a level-0 support of it
  // are split to level 1 (their mass, h and surface vectors with them); the others stay level 0
  test::Setup<2> one(pool(kAboveWater)), w(pool("{shape: box, min: [0.0, 0.0], max: [0.2, 0.4]}"));
  const auto& P = w.S.particles;
  const auto& lv = P.require(field::level);
  const double m0 = 1000.0 * 0.01 * 0.01;
  std::size_t fine = 0, coarse = 0;
  double wall_mass = 0.0;
  for (std::size_t i = 0; i < P.n_owned(); ++i) {
    if (P.kind[i] != Kind::Wall) continue;
    wall_mass += P.mass[i];
    const bool near = P.pos[i][0] < 0.2 + w.S.support;
    EXPECT_EQ(lv[i], near ? 1.0 : 0.0) << P.pos[i][0] << ", " << P.pos[i][1];
    EXPECT_EQ(P.mass[i], level_mass<2>(m0, near ? 1 : 0));
    (near ? fine : coarse) += 1;
  }
  EXPECT_GT(fine, 0u);
  EXPECT_GT(coarse, 0u);
  EXPECT_NEAR(wall_mass, one.S.total_mass(Kind::Wall), 1e-12 * wall_mass);  // each wall point's mass shared
  EXPECT_EQ(P.count(Kind::Wall), one.S.particles.count(Kind::Wall) + 3 * fine / 4);
}

TEST(Resolution, SplitWallsStayInsideTheirBody) {
  // a block on the floor (a polygon: its points are the global lattice's inside it) whose right face (x = 0.397) lies
  // off the level-0 lattice, 0.002 m (< dx/4) beyond its last column of points (x = 0.395): split to level 1, that column's right children (x = 0.3975) would stand outside the
  // face, in the water's way (the 3D obstacle's impact, docs/numerics.md §14). Every wall particle stays inside its
  // body: none in the water's strip beyond the face, and the face's own fine column is there (x = 0.3925). The left
  // face (x = 0.2965) is the converse: the level-0 column at 0.295 lies outside the block, so the fine column at
  // 0.2975, inside it, has no parent; it is added (add_face_points), and the fluid child that stood there removed.
  const std::string yaml = R"(dimension: 2
particles: {dx: 0.01, kernel: wendland_c2, h_over_dx: 2.0}
fluid: {density: 1000.0, viscosity: 1.0e-6}
geometry:
  - {type: tank, fill: wall, min: [0.0, 0.0], max: [0.6, 0.4]}
  - {type: polygon, fill: wall, vertices: [[0.2965, 0.0], [0.397, 0.0], [0.397, 0.1], [0.2965, 0.1]]}
  - {type: box, fill: fluid, min: [0.0, 0.0], max: [0.6, 0.2]}
resolution:
  regions:
    - {shape: box, min: [0.25, 0.0], max: [0.45, 0.15], level: 1}
time: {end: 0.1}
)";
  test::Setup<2> s(yaml);
  const auto& P = s.S.particles;
  const auto& lv = P.require(field::level);
  std::size_t face = 0, left = 0;
  for (std::size_t i = 0; i < P.n_owned(); ++i) {
    if (P.pos[i][1] < 0.0 || P.pos[i][1] > 0.1) continue;  // (the block's height)
    if (P.kind[i] != Kind::Wall) {  // no fluid inside the block
      EXPECT_FALSE(P.pos[i][0] > 0.2965 && P.pos[i][0] < 0.397) << "fluid in the block at " << P.pos[i][0] << ", " << P.pos[i][1];
      continue;
    }
    EXPECT_FALSE(P.pos[i][0] > 0.397 && P.pos[i][0] < 0.6) << "a wall particle in the water at " << P.pos[i][0] << ", " << P.pos[i][1];
    EXPECT_FALSE(P.pos[i][0] > 0.01 && P.pos[i][0] < 0.2965) << "a wall particle in the water at " << P.pos[i][0] << ", " << P.pos[i][1];
    if (std::abs(P.pos[i][0] - 0.3925) < 1e-9 && lv[i] == 1.0) ++face;
    if (std::abs(P.pos[i][0] - 0.2975) < 1e-9 && lv[i] == 1.0) ++left;
  }
  EXPECT_EQ(face, 20u);  // the right face's fine column, 0.1 m at 0.005 m
  EXPECT_EQ(left, 20u);  // the left face's (x = 0.2965): its parents at x = 0.295 lay outside the block
}

TEST(Resolution, DualMultirateIsRefused) {
  const std::string base = pool(kBlock);
  auto msg_of = [](const std::string& text, const std::vector<std::string>& o) {
    try {
      const Case c = parse_case(text, "case.yaml", o);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_EQ(msg_of(base, {"scheme.shepard_every=30"}), "");  // served since issue 58 (Resolution.ShepardOnOneLevel...)
  // the dual integrator steps every level together (served since issue 58); multirate sub-cycles the symplectic one
  EXPECT_HAS(msg_of(pool(std::string(kBlock) + "\n  multirate: true"), {"scheme.integrator=dual"}), "false with scheme.integrator: dual");
}

TEST(Resolution, RunsAreBitwiseIndependentOfThreadCount) {
  // (the smoothed h and the relaxed interface are per-particle results: no thread writes another's)
  const int saved = omp_get_max_threads();
  auto run = [](int threads) {
    omp_set_num_threads(threads);
    auto s = std::make_unique<test::Setup<2>>(pool(kBlock));
    s->scheme->initialise(s->S);
    for (int i = 0; i < 40; ++i) s->scheme->step(s->S, s->scheme->time_step(s->S));
    s->S.particles.clear_images();
    return s;
  };
  const auto a = run(1), b = run(2);
  omp_set_num_threads(saved);
  const auto &Pa = a->S.particles, &Pb = b->S.particles;
  ASSERT_EQ(Pa.n_owned(), Pb.n_owned());
  EXPECT_EQ(0, std::memcmp(Pa.pos.data(), Pb.pos.data(), Pa.n_owned() * sizeof(Vec<2>)));
  EXPECT_EQ(0, std::memcmp(Pa.vel.data(), Pb.vel.data(), Pa.n_owned() * sizeof(Vec<2>)));
  EXPECT_EQ(0, std::memcmp(Pa.rho.data(), Pb.rho.data(), Pa.n_owned() * sizeof(double)));
  const auto &ha = Pa.require(field::smoothing_length), &hb = Pb.require(field::smoothing_length);
  EXPECT_EQ(0, std::memcmp(ha.data(), hb.data(), Pa.n_owned() * sizeof(double)));
}

TEST(Resolution, SplitAndMergeKeepMassMomentumAndCentre) {
  // the pool refined in kBlock; then the region moves 0.15 m to the right: the level-0 particles
  // that it now covers split, and the level-1 particles it left (by more than a level-0 h) merge
  test::Setup<2> s(pool(kBlock));
  auto& P = s.S.particles;
  for (std::size_t i = 0; i < P.n_owned(); ++i)
    if (P.kind[i] == Kind::Fluid) {
      P.vel[i] = Vec<2>{{std::sin(17.0 * P.pos[i][1]), 0.5 * std::cos(11.0 * P.pos[i][0])}};
      P.rho[i] = 1000.0 * (1.0 + 0.01 * std::sin(23.0 * P.pos[i][0] + 7.0 * P.pos[i][1]));
    }
  s.S.update_neighbours();
  auto totals = [&](double& m, Vec<2>& mv, Vec<2>& mx, double& vol) {
    m = 0.0; vol = 0.0; mv = Vec<2>{}; mx = Vec<2>{};
    for (std::size_t i = 0; i < P.n_owned(); ++i)
      if (P.kind[i] == Kind::Fluid) { m += P.mass[i]; mv += P.mass[i] * P.vel[i]; mx += P.mass[i] * P.pos[i]; vol += P.mass[i] / P.rho[i]; }
  };
  double m0, v0, m1, v1;
  Vec<2> p0, x0, p1, x1;
  totals(m0, p0, x0, v0);
  const std::size_t fine0 = P.count(Kind::Fluid);
  ResolutionConfig moved = s.c.resolution;
  moved.regions[0].region.min[0] += 0.15;
  moved.regions[0].region.max[0] += 0.15;
  moved.settle_iterations = 0;  // (the children where the split puts them; settled below)
  std::uint32_t next_id = 0;
  const AdaptCounts k = adapt_levels(s.S, moved, next_id);
  totals(m1, p1, x1, v1);
  // 0.2 ≤ x < 0.35 leaves the region (level-0 h = 0.02 of hysteresis: 0.2 ≤ x < 0.33 merges),
  // 0.4 ≤ x < 0.55 enters it; z from 0.1 to the surface at 0.3: 20 rows of coarse points
  EXPECT_EQ(k.split, 15u * 20u);
  EXPECT_GE(k.merged, 13u * 20u * 9 / 10);  // groups of four with partners within a level-0 spacing
  EXPECT_LE(k.merged, 13u * 20u);
  EXPECT_EQ(P.count(Kind::Fluid), fine0 + 3 * k.split - 3 * k.merged);
  EXPECT_NEAR(m1, m0, 1e-12 * m0);  // (issue 42: to round-off, 1e-12; the sums over 20 k particles in another order)
  EXPECT_NEAR(v1, v0, 1e-12 * v0);  // merges keep the volume Σ m/ρ
  for (int d = 0; d < 2; ++d) {
    EXPECT_NEAR(p1[d], p0[d], 1e-12 * m0);  // momentum (velocities of order 1 m/s)
    EXPECT_NEAR(x1[d], x0[d], 1e-12 * m0);  // centre of mass (positions of order 1 m)
  }
  // every fluid particle inside the moved region is level 1; the ids stay unique
  const auto& lv = P.require(field::level);
  std::vector<std::uint32_t> ids;
  for (std::size_t i = 0; i < P.n_owned(); ++i) {
    ids.push_back(P.id[i]);
    if (P.kind[i] != Kind::Fluid) continue;
    if (moved.regions[0].region.contains(P.pos[i].c.data(), 2)) { EXPECT_EQ(lv[i], 1.0); }
    EXPECT_EQ(P.mass[i], level_mass<2>(1000.0 * 0.01 * 0.01, static_cast<int>(lv[i])));
  }
  std::sort(ids.begin(), ids.end());
  EXPECT_TRUE(std::adjacent_find(ids.begin(), ids.end()) == ids.end());
  // nothing more to do on a second call
  s.S.update_neighbours();
  const AdaptCounts k2 = adapt_levels(s.S, moved, next_id);
  EXPECT_EQ(k2.split, 0u);

  // the same with the children settled (resolution.settle, default 10): positions only, each
  // child at most dx_1/4 from its place, so the centre of mass moves by less than that
  test::Setup<2> t(pool(kBlock));
  for (std::size_t i = 0; i < t.S.particles.n_owned(); ++i) t.S.particles.vel[i] = P.vel[0];
  t.S.update_neighbours();
  double n0, w0, n1, w1;
  Vec<2> q0, c0, q1, c1;
  auto totals_t = [&](double& m, Vec<2>& mv, Vec<2>& mx, double& vol) {
    const auto& T = t.S.particles;
    m = 0.0; vol = 0.0; mv = Vec<2>{}; mx = Vec<2>{};
    for (std::size_t i = 0; i < T.n_owned(); ++i)
      if (T.kind[i] == Kind::Fluid) { m += T.mass[i]; mv += T.mass[i] * T.vel[i]; mx += T.mass[i] * T.pos[i]; vol += T.mass[i] / T.rho[i]; }
  };
  totals_t(n0, q0, c0, w0);
  moved.settle_iterations = 10;
  std::uint32_t next_t = 0;
  EXPECT_EQ(adapt_levels(t.S, moved, next_t).split, k.split);
  totals_t(n1, q1, c1, w1);
  EXPECT_NEAR(n1, n0, 1e-12 * n0);
  for (int d = 0; d < 2; ++d) {
    EXPECT_NEAR(q1[d], q0[d], 1e-12 * n0);
    EXPECT_LT(std::abs(c1[d] - c0[d]) / n0, 0.25 * 0.005);
  }
}

TEST(Resolution, SettleTakesAWholeNumberOfIterations) {
  for (const char* o : {"resolution.settle=1.5", "resolution.settle=-1", "resolution.settle=2000"}) {
    SCOPED_TRACE(o);
    std::string msg;
    try {
      const Case c = parse_case(pool(kBlock), "case.yaml", {o});
    } catch (const InputError& e) {
      msg = e.what();
    }
    EXPECT_HAS(msg, "resolution.settle");
  }
  const Case ok = parse_case(pool(kBlock), "case.yaml", {"resolution.settle=0"});
  EXPECT_EQ(ok.resolution.settle_iterations, 0);
}

// `shape: band` (issue 42: "a band along a slope"): the fluid within `above` and `below` of a
// slope's face, between z_min and z_max, is refined at set-up; the fluid clearly outside it is
// not (a margin of one level-0 spacing for the interface's relaxation, at most dx/4); a band
// named by an index that is not a slope is refused with its line.
TEST(Resolution, BandAlongASlopeRefinesTheSwashZone) {
  auto beach = [](const std::string& band) { return beach_case(band); };

  const char* kBand = "{shape: band, slope: 1, above: 0.06, below: 0.03, z_min: 0.1, z_max: 0.35, level: 1}";
  test::Setup<2> T(beach(kBand));
  const auto& P = T.S.particles;
  const auto& lv = P.require(field::level);
  const double ux = 2.0 / std::sqrt(5.0), uz = 1.0 / std::sqrt(5.0), dx = 0.01;
  std::size_t inside = 0, outside = 0;
  for (std::size_t i = 0; i < P.n_owned(); ++i) {
    if (P.kind[i] != Kind::Fluid) continue;
    const double rx = P.pos[i][0] - 0.5, rz = P.pos[i][1];
    const double n = rz * ux - rx * uz, along = rx * ux + rz * uz;  // above the face, normal to it; along it
    const double z = P.pos[i][1];
    if (along > 0.0 && along < std::sqrt(0.8) - dx && z > 0.1 + dx && z < 0.35 - dx && n < 0.06 - dx && n > -0.03 + dx) {
      EXPECT_EQ(lv[i], 1.0) << P.pos[i][0] << " " << z;
      ++inside;
    } else if (z < 0.1 - dx || n > 0.06 + dx || along > std::sqrt(0.8) + dx) {  // (the lee basin behind the top)
      EXPECT_EQ(lv[i], 0.0) << P.pos[i][0] << " " << z;
      ++outside;
    }
  }
  EXPECT_GT(inside, 100u);
  EXPECT_GT(outside, 1000u);
  RegionConfig r;  // the shape itself, also below the face (a porous beach's layer)
  r.type = "band";
  r.vertices = {{{0.5, 0.0}}, {{1.3, 0.4}}};
  r.above = 0.06;
  r.below = 0.03;
  r.z_min = 0.1;
  r.z_max = 0.35;
  const double below[2] = {0.5 + 0.3 * ux + 0.02 * uz, 0.3 * uz - 0.02 * ux}, far[2] = {0.5 + 0.3 * ux + 0.04 * uz, 0.3 * uz - 0.04 * ux};
  EXPECT_TRUE(r.contains(below, 2));
  EXPECT_FALSE(r.contains(far, 2));
  EXPECT_HAS(test::build_error<2>(beach("{shape: band, slope: 0, above: 0.06, below: 0.03, level: 1}")),
             "resolution.regions.0.slope");
  EXPECT_HAS(test::build_error<2>(beach("{shape: band, slope: 1, above: 0.06, below: 0.03, z_min: 0.3, z_max: 0.2, level: 1}")),
             "z_max > z_min");
}

TEST(Resolution, PorousBeachBandTakesEachLevelsPorosityField) {
  // a permeable 1:2 beach (Tsurudome's porous-particle field, `field: particles`) with a band along
  // its surface refined (`porous: 0`): the band's particles below the surface are fine, and every
  // particle reads the porosity that a uniform run at its own spacing reads at its place (the field
  // of its level's porous lattice and h; issue 42, check 5)
  const std::string yaml = beach_case("{shape: band, porous: 0, above: 0.04, below: 0.04, z_min: 0.05, z_max: 0.35, level: 1}", true);
  test::Setup<2> T(yaml);
  const auto& P = T.S.particles;
  ASSERT_TRUE(T.S.porous);
  const auto& lv = P.require(field::level);
  const auto& phi = P.require(field::porosity);
  const double h = T.S.h;
  PorousMedia<2> coarse(T.c.porous, T.c.kernel, h, 0.01), fine(T.c.porous, T.c.kernel, 0.5 * h, 0.005);
  const double ux = 2.0 / std::sqrt(5.0), uz = 1.0 / std::sqrt(5.0);
  std::size_t fine_in_body = 0, fine_at_face = 0, coarse_in_body = 0;
  for (std::size_t i = 0; i < P.n_owned(); ++i) {
    if (P.kind[i] != Kind::Fluid) continue;
    const bool f = lv[i] == 1.0;
    EXPECT_EQ(phi[i], (f ? fine : coarse).porosity(P.pos[i])) << P.pos[i][0] << " " << P.pos[i][1];
    const double n = P.pos[i][1] * ux - (P.pos[i][0] - 0.5) * uz;  // above the face, normal to it
    if (f && n < -0.01) ++fine_in_body;
    if (f && std::abs(n) < 0.01 && phi[i] > 0.6 && phi[i] < 0.9) ++fine_at_face;
    if (!f && n < -0.06 && P.pos[i][1] > 0.05) ++coarse_in_body;
  }
  EXPECT_GT(fine_in_body, 100u);
  EXPECT_GT(coarse_in_body, 100u);
  EXPECT_GT(fine_at_face, 10u);
  // where the two fields differ (the face's transition, one support of each level wide), a fine
  // particle would read the coarse field without its level: the test can tell them apart
  double most = 0.0;
  for (std::size_t i = 0; i < P.n_owned(); ++i)
    if (P.kind[i] == Kind::Fluid && lv[i] == 1.0) most = std::max(most, std::abs(coarse.porosity(P.pos[i]) - phi[i]));
  EXPECT_GT(most, 0.05);
  EXPECT_HAS(test::build_error<2>(std::string(yaml).replace(yaml.find("porous: 0"), 9, "porous: 1")),
             "resolution.regions.0.porous");
}

TEST(Resolution, BandFollowsTheWaterline) {
  // `follow: waterline`: the band's elevations are a window about the waterline on its line; at
  // set-up the still water's, during the run wherever the water reaches up the face
  const std::string yaml = beach_case(
      "{shape: band, slope: 1, above: 0.06, below: 0.03, follow: waterline, waterline_below: 0.05, waterline_above: 0.05, level: 1}");
  test::Setup<2> T(yaml);
  const auto& P = T.S.particles;
  const auto& lv = P.require(field::level);
  const double ux = 2.0 / std::sqrt(5.0), uz = 1.0 / std::sqrt(5.0), dx = 0.01;
  const double zw = 0.195;  // the top row of the still water (the waterline on the face)
  std::size_t fine = 0, below = 0;
  for (std::size_t i = 0; i < P.n_owned(); ++i) {
    if (P.kind[i] != Kind::Fluid) continue;
    const double rx = P.pos[i][0] - 0.5, z = P.pos[i][1];
    const double n = z * ux - rx * uz;
    if (n > 0.06 - dx || n < -0.03 + dx) continue;
    if (z > zw - 0.05 + dx) { EXPECT_EQ(lv[i], 1.0) << P.pos[i][0] << " " << z; ++fine; }
    if (z < zw - 0.05 - dx) { EXPECT_EQ(lv[i], 0.0) << P.pos[i][0] << " " << z; ++below; }
  }
  EXPECT_GT(fine, 30u);
  EXPECT_GT(below, 30u);
  // the walk: a film up the face to z = 0.30 and a splash beyond a dry stretch at 0.38
  ResolutionConfig res = T.c.resolution;
  std::vector<Vec<2>> pts;
  for (double s = 0.0; s * uz < 0.30; s += 0.005) pts.push_back(Vec<2>{{0.5 + s * ux - 0.004 * uz, s * uz + 0.004 * ux}});
  pts.push_back(Vec<2>{{0.5 + 0.38 / uz * ux, 0.38 + 0.005}});
  set_waterline_windows<2>(res, pts.data(), nullptr, pts.size(), dx, Communicator{});
  const auto& g = res.regions[0].region;
  EXPECT_NEAR(g.win_lo + 0.05, 0.30, 0.006);
  EXPECT_NEAR(g.win_hi - 0.05, 0.30, 0.006);
  set_waterline_windows<2>(res, pts.data(), nullptr, 0, dx, Communicator{});
  const double on_face[2] = {0.5 + 0.2 / uz * ux + 0.01 * uz, 0.2};
  EXPECT_FALSE(res.regions[0].region.contains(on_face, 2));  // no water on the line: empty
  EXPECT_HAS(test::build_error<2>(std::string(yaml).replace(yaml.find("follow: waterline, "), 19, "")),
             "without `follow: waterline`");
}

TEST(Resolution, MultirateSubCyclesTheFineLevel) {
  // resolution.multirate: the coarse particles take one step of twice the fine level's, the fine
  // ones (and the interface) two; over 0.05 s of the moving pool with its refined block it takes
  // half the steps, keeps the mass exact, and stays as close to the fixed-step run (every particle
  // at the fine step) as a run with every particle at the doubled step does, within the factor below
  struct Out { long steps; double ke, zc, mass; };
  // to 0.05 s with steps of `factor` times the scheme's
  auto run = [](const std::string& yaml, double factor) {
    test::Setup<2> T(yaml);
    T.named->initialise(T.S);
    const double end = 0.05;
    long steps = 0;
    while (T.S.time < end * (1.0 - 1e-12)) {
      T.named->step(T.S, std::min(factor * T.named->time_step(T.S), end - T.S.time));
      ++steps;
    }
    T.S.particles.clear_images();
    const auto& P = T.S.particles;
    Out o{steps, 0.0, 0.0, 0.0};
    for (std::size_t i = 0; i < P.n_owned(); ++i) {
      if (P.kind[i] != Kind::Fluid) continue;
      o.ke += 0.5 * P.mass[i] * dot(P.vel[i], P.vel[i]);
      o.zc += P.mass[i] * P.pos[i][1];
      o.mass += P.mass[i];
    }
    o.zc /= o.mass;
    return o;
  };
  const Out fixed = run(pool(kBlock), 1.0), dbl = run(pool(kBlock), 2.0);
  std::string ymr = pool(kBlock);  // (`multirate` is a key of the resolution mapping)
  ymr.replace(ymr.find("level: 1}"), 9, "level: 1}\n  multirate: true");
  test::Setup<2> probe(ymr);
  ASSERT_TRUE(probe.c.resolution.multirate);
  const Out m = run(ymr, 1.0);
  EXPECT_LE(m.steps, static_cast<long>(0.55 * fixed.steps)) << m.steps << " vs " << fixed.steps;
  EXPECT_NEAR(m.mass, fixed.mass, 1e-12 * fixed.mass);
  // within 3 times what a doubled global step changes (the time-discretisation error at the coarse
  // step; the fast-slow pairs, evaluated at different times, add one of the same order). Measured
  // 2026-11-27: kinetic energy −1.1e-4 J/m against −5.1e-5, centre of mass −3.5e-7 m against −7.2e-7
  EXPECT_LE(std::abs(m.ke - fixed.ke), 3.0 * std::abs(dbl.ke - fixed.ke)) << m.ke << " " << fixed.ke << " " << dbl.ke;
  EXPECT_LE(std::abs(m.zc - fixed.zc), 3.0 * std::abs(dbl.zc - fixed.zc)) << m.zc << " " << fixed.zc << " " << dbl.zc;
  std::string verlet = ymr;
  verlet.replace(verlet.find("scheme: {"), 9, "scheme: {integrator: verlet, ");
  EXPECT_HAS(test::build_error<2>(verlet), "resolution.multirate");
}

TEST(Resolution, TheStepFollowsTheFinestLevelPresent) {
  // the explicit step's h (schemes/wcsph_common.hpp step_h): a refined region that holds no fluid
  // (above the water) leaves the step at level 0's h; a refined block in the water halves it; a
  // region over the wall alone (its wall points split, no fluid in it) gives the fluid-wall pairs'
  // mean h, 3/4 of level 0's. The same with multirate: no fast particle, the step of level 0.
  test::Setup<2> dry(pool(kAboveWater)), wet(pool(kBlock)),
      wall(pool("{shape: box, min: [0.0, 0.33], max: [0.05, 0.4], level: 1}"));
  const double h0 = dry.S.h;
  EXPECT_EQ(step_h(dry.S), h0);
  EXPECT_EQ(step_h(wet.S), 0.5 * h0);
  const auto& lv = wall.S.particles.require(field::level);
  ASSERT_GT(std::count(lv.begin(), lv.end(), 1.0), 0);  // (split wall points)
  EXPECT_EQ(step_h(wall.S), 0.75 * h0);
  // the steps themselves (at t = 0 the acoustic limit, linear in h: exactly twice over the dry
  // region what it is with the wet block), and the multirate step over the dry region the same
  std::string ymr = pool(kAboveWater);
  ymr.replace(ymr.find("level: 1}"), 9, "level: 1}\n  multirate: true");
  test::Setup<2> mr(ymr);
  for (auto* T : {&dry, &wet, &mr}) T->named->initialise(T->S);
  const double dt_dry = dry.named->time_step(dry.S);
  EXPECT_EQ(dt_dry, 2.0 * wet.named->time_step(wet.S));
  EXPECT_EQ(mr.named->time_step(mr.S), dt_dry);
}

TEST(Resolution, SetupRelaxationWorkLimitIsNamed) {
  // BuildLimits::max_setup_pairs (no limit for a run; the fuzzing target's 2e7): refused with the fix
  const Case c = parse_case(pool(kBlock), "case.yaml");
  System<2> S;
  BuildLimits limits;
  limits.max_setup_pairs = 1e3;
  std::string msg;
  try {
    build_system<2>(c, S, limits);
  } catch (const InputError& e) {
    msg = e.what();
  }
  EXPECT_HAS(msg, "line 8: 'resolution'");
  EXPECT_HAS(msg, "resolution.relax");
  System<2> T;
  EXPECT_NO_THROW(build_system<2>(c, T));  // (the default: no limit)
}

// The wall models other than dummy walls on levels (issue 58): a level-1 region over the whole tank, walls included,
// is the uniform dx/2 run: its fluid's rates at every lattice site are the uniform run's to the float sums'
// round-off. The fixed ghosts' MLS takes each fluid particle's h (core/interpolate.hpp); the repulsive force acts over
// each wall particle's own spacing and h (WallModel::add_forces: with the level-0 spacing it reaches the second fluid
// row, with the level-0 h its strength halves: either moves the first rows' rates by ~c0²/h); dynamic walls carry
// their level's mass. The split tank has more wall layers than the uniform run's (the level-0 layers' children):
// beyond the fine fluid's reach. The walls' backup is off (its range is level 0's: docs/numerics.md §14).
TEST(Resolution, WallModelsOnOneLevelEverywhereAreTheUniformFineWalls) {
  for (const std::string type : {"fixed_ghost", "repulsive", "dynamic"}) {
    SCOPED_TRACE(type);
    const std::string walls = "walls: {type: " + type + ", backup: false}\n";
    const std::string lev = pool("{shape: box, min: [-0.1, -0.1], max: [0.7, 0.5], level: 1}", walls);
    test::Setup<2> a(lev.substr(0, lev.find("resolution:")) + "time: {end: 0.1}\n" + walls, {"particles.dx=0.005"}), b(lev);
    ASSERT_EQ(b.S.levels, 1);
    a.scheme->initialise(a.S);
    b.scheme->initialise(b.S);
    const auto &Pa = a.S.particles, &Pb = b.S.particles;
    auto site = [](const Vec<2>& x) { return std::make_pair(std::lround(x[0] / 0.0025), std::lround(x[1] / 0.0025)); };
    std::map<std::pair<long, long>, std::size_t> in_b;
    for (std::size_t j = 0; j < Pb.n_owned(); ++j)
      if (Pb.kind[j] == Kind::Fluid) in_b[site(Pb.pos[j])] = j;
    double amax = 0.0, dmax = 0.0, da = 0.0, dd = 0.0, awall = 0.0;
    std::size_t fluid = 0;
    for (std::size_t i = 0; i < Pa.n_owned(); ++i) {
      if (Pa.kind[i] != Kind::Fluid) continue;
      ++fluid;
      const auto it = in_b.find(site(Pa.pos[i]));
      ASSERT_NE(it, in_b.end()) << Pa.pos[i][0] << ", " << Pa.pos[i][1];
      const std::size_t j = it->second;
      amax = std::max(amax, norm(Pa.acc[i]));
      dmax = std::max(dmax, std::abs(Pa.drho[i]));
      da = std::max(da, norm(Pa.acc[i] - Pb.acc[j]));
      dd = std::max(dd, std::abs(Pa.drho[i] - Pb.drho[j]));
      if (Pa.pos[i][1] < 0.005) awall = std::max(awall, norm(Pa.acc[i] - Vec<2>{{0.0, -9.81}}));  // (the bed's row)
    }
    EXPECT_EQ(fluid, in_b.size());
    ASSERT_GT(awall, 1.0);  // (the walls act on the bed's row: the comparison tests them)
    EXPECT_LT(da, 1e-4 * amax);  // (float pair sums, as Resolution.LevelGridsGiveTheLevel0CellsRates)
    EXPECT_LT(dd, 1e-4 * dmax + 1e-9);
  }
}

// The dummy walls' backup against penetration on levels (session 45): each wall particle holds the fluid over its own
// level's spacing (s0 = dx_l/4 from the surface, its first layer within dx_l, h_l in the strength). A level-1 region
// over the whole tank is the uniform dx/2 run: the bed's fluid row pushed to 1 mm above the bed (its lattice place is
// 2.5 mm), inside the fine backup's reach (1.25 mm), gets the uniform run's rates. At level 0's spacing the backup's
// reach was 2.5 mm, its second fine wall layer pushed too and its strength took level 0's h: 9x the force and more.
TEST(Resolution, WallBackupOnOneLevelEverywhereIsTheUniformFineBackup) {
  const std::string walls = "walls: {type: dummy, backup: true}\n";
  const std::string lev = pool("{shape: box, min: [-0.1, -0.1], max: [0.7, 0.5], level: 1}", walls);
  const std::string uniform = lev.substr(0, lev.find("resolution:")) + "time: {end: 0.1}\n";
  test::Setup<2> a(uniform + walls, {"particles.dx=0.005"}), b(lev), c(uniform + "walls: {type: dummy, backup: false}\n", {"particles.dx=0.005"});
  ASSERT_EQ(b.S.levels, 1);
  for (auto* s : {&a, &b, &c}) {  // (the bed's fluid row, at y = dx/4 of level 0, to 1 mm)
    auto& P = s->S.particles;
    for (std::size_t i = 0; i < P.n_owned(); ++i)
      if (P.kind[i] == Kind::Fluid && P.pos[i][1] < 0.004) P.pos[i][1] = 0.001;
  }
  for (auto* s : {&a, &b, &c}) s->scheme->initialise(s->S);
  const auto &Pa = a.S.particles, &Pb = b.S.particles, &Pc = c.S.particles;
  ASSERT_EQ(Pa.n_owned(), Pc.n_owned());
  auto site = [](const Vec<2>& x) { return std::make_pair(std::lround(x[0] / 0.0025), std::lround(x[1] / 0.0025 - 0.4)); };
  std::map<std::pair<long, long>, std::size_t> in_b;
  for (std::size_t j = 0; j < Pb.n_owned(); ++j)
    if (Pb.kind[j] == Kind::Fluid) in_b[site(Pb.pos[j])] = j;
  double amax = 0.0, da = 0.0, backup = 0.0;
  for (std::size_t i = 0; i < Pa.n_owned(); ++i) {
    if (Pa.kind[i] != Kind::Fluid) continue;
    const auto it = in_b.find(site(Pa.pos[i]));
    ASSERT_NE(it, in_b.end()) << Pa.pos[i][0] << ", " << Pa.pos[i][1];
    amax = std::max(amax, norm(Pa.acc[i]));
    da = std::max(da, norm(Pa.acc[i] - Pb.acc[it->second]));
    backup = std::max(backup, norm(Pa.acc[i] - Pc.acc[i]));  // (the same store order: the same set-up)
  }
  ASSERT_GT(backup, 0.05 * amax);  // (the backup acts on the pushed row: the comparison tests it)
  EXPECT_LT(da, 1e-4 * amax);  // (float pair sums, as above)
}

// The Shepard filter on levels (issue 58): each pair's kernel at h_ab. A level-1 region over the whole tank is the
// uniform dx/2 run: a ±1 % checkerboard of density, one step of 1e-5 s with the filter after it, gives the uniform run's
// densities at every lattice site (the filter halves the checkerboard; at the level-0 h it would average over twice
// the radius, a difference of ~0.1 % of ρ0 at the surface and the walls).
TEST(Resolution, ShepardOnOneLevelEverywhereIsTheUniformFineFilter) {
  const std::string lev = pool("{shape: box, min: [-0.1, -0.1], max: [0.7, 0.5], level: 1}");
  test::Setup<2> a(lev.substr(0, lev.find("resolution:")) + "time: {end: 0.1}\n", {"particles.dx=0.005", "scheme.shepard_every=1"});
  test::Setup<2> b(lev, {"scheme.shepard_every=1"});
  ASSERT_EQ(b.S.levels, 1);
  auto site = [](const Vec<2>& x) { return std::make_pair(std::lround(x[0] / 0.0025), std::lround(x[1] / 0.0025)); };
  std::map<std::pair<long, long>, double> before;
  for (auto* s : {&a, &b}) {
    auto& P = s->S.particles;
    for (std::size_t i = 0; i < P.n_owned(); ++i) {
      if (P.kind[i] != Kind::Fluid) continue;
      const auto k = site(P.pos[i]);
      P.rho[i] *= 1.0 + 0.01 * (((k.first + k.second) / 2) % 2 == 0 ? 1.0 : -1.0);  // (sites at odd multiples of dx/4)
      before[k] = P.rho[i];
    }
    eos_pressure(s->S);
    s->named->initialise(s->S);
    s->named->step(s->S, 1e-5);
  }
  std::map<std::pair<long, long>, double> rho_a;
  for (std::size_t i = 0; i < a.S.particles.n_owned(); ++i)
    if (a.S.particles.kind[i] == Kind::Fluid) rho_a[site(a.S.particles.pos[i])] = a.S.particles.rho[i];
  const auto& P = b.S.particles;
  double diff = 0.0, change = 0.0;
  std::size_t fluid = 0;
  for (std::size_t i = 0; i < P.n_owned(); ++i) {
    if (P.kind[i] != Kind::Fluid) continue;
    ++fluid;
    const auto k = site(P.pos[i]);
    ASSERT_TRUE(rho_a.count(k)) << P.pos[i][0] << ", " << P.pos[i][1];
    diff = std::max(diff, std::abs(P.rho[i] - rho_a[k]));
    change = std::max(change, std::abs(P.rho[i] - before[k]));
  }
  EXPECT_EQ(fluid, rho_a.size());
  ASSERT_GT(change, 3.0);  // (the filter moved the densities: ~5 kg/m3 of the 10 kg/m3 checkerboard)
  EXPECT_LT(diff, 1e-3);   // (the step's float rates: ~1e-5 of dρ/dt over 1e-5 s; a wrong h: ~1 kg/m3)
}
