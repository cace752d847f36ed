// Open boundaries (Federico's in/out-flow algorithm): profiles, and the per-step bookkeeping
// that moves particles between the inflow, fluid and outflow sets with every mass counted.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "sphflume/boundaries/open_boundary.hpp"
#include "sphflume/sim/simulation.hpp"
#include "test_helpers.hpp"

using namespace sph;

TEST(OpenBoundary, ProfilesMatchTheirFormulas) {
  ProfileConfig p;
  p.type = "uniform";
  p.u = 0.3;
  EXPECT_DOUBLE_EQ(profile_velocity(p, 0.07, 0.1), 0.3);
  p.type = "parabolic";
  p.u_surface = 0.2;
  EXPECT_DOUBLE_EQ(profile_velocity(p, 0.0, 0.1), 0.0);
  EXPECT_DOUBLE_EQ(profile_velocity(p, 0.1, 0.1), 0.2);
  EXPECT_NEAR(profile_velocity(p, 0.05, 0.1), 0.2 * 0.75, 1e-15);  // 2s - s^2 at s = 1/2
  p.type = "log";
  p.u_star = 0.05;
  p.ks = 0.01;
  EXPECT_NEAR(profile_velocity(p, 0.01, 0.1), 0.05 * 8.5, 1e-15);  // ln(1) = 0: u = 8.5 u*
  EXPECT_NEAR(profile_velocity(p, 0.1, 0.1), 0.05 * (std::log(10.0) / 0.41 + 8.5), 1e-14);
  p.type = "table";
  p.z = {0.0, 0.1};
  p.values = {0.0, 1.0};
  EXPECT_NEAR(profile_velocity(p, 0.025, 0.1), 0.25, 1e-15);
  EXPECT_DOUBLE_EQ(profile_velocity(p, 0.2, 0.1), 1.0);
}

namespace {
const char* kChannel = test::kOpenChannel2D;

std::size_t count(const ParticleStore<2>& P, Kind k) { return P.count(k); }
}  // namespace

TEST(OpenBoundary, SetupTurnsZoneFluidIntoImposedParticles) {
  test::Setup<2> s(kChannel);
  OpenBoundaries<2> ob(s.c);
  OpenFlowCounters k;
  const std::size_t fluid0 = count(s.S.particles, Kind::Fluid);
  ob.setup(s.S, k);
  const auto& P = s.S.particles;
  EXPECT_EQ(count(P, Kind::Inflow), 5u * 10u);   // 5 columns x 10 rows
  EXPECT_EQ(count(P, Kind::Outflow), 5u * 10u);
  EXPECT_EQ(count(P, Kind::Fluid), fluid0 - 100u);
  for (std::size_t i = 0; i < P.n_owned(); ++i) {
    if (P.kind[i] == Kind::Inflow) {
      EXPECT_DOUBLE_EQ(P.vel[i][0], 0.2);
      // hydrostatic pressure of the imposed depth
      EXPECT_NEAR(P.p[i], 1000.0 * 9.81 * (0.1 - P.pos[i][1]), 1e-9);
    }
    if (P.kind[i] == Kind::Outflow) {
      EXPECT_DOUBLE_EQ(P.vel[i][0], 0.1);
    }
  }
  EXPECT_GT(k.next_id, 0u);
}

TEST(OpenBoundary, CrossingsConvertCreateAndDeleteWithEveryMassCounted) {
  test::Setup<2> s(kChannel);
  OpenBoundaries<2> ob(s.c);
  OpenFlowCounters k;
  ob.setup(s.S, k);
  auto& P = s.S.particles;
  const std::uint32_t id0 = k.next_id;
  const double m_fluid0 = s.S.total_mass(Kind::Fluid);
  // move the last inflow column past the zone's end, the last fluid column into the outflow
  // zone and the last outflow column past the outlet
  std::size_t moved_in = 0, moved_f = 0, moved_out = 0;
  double zin = -1.0;
  for (std::size_t i = 0; i < P.n_owned(); ++i) {
    if (P.kind[i] == Kind::Inflow && P.pos[i][0] > 0.04) { P.pos[i][0] += 0.01; ++moved_in; if (zin < 0) zin = P.pos[i][1]; }
    else if (P.kind[i] == Kind::Fluid && P.pos[i][0] > 0.34) { P.pos[i][0] += 0.011; ++moved_f; }
    else if (P.kind[i] == Kind::Outflow && P.pos[i][0] > 0.39) { P.pos[i][0] += 0.011; ++moved_out; }
  }
  ASSERT_EQ(moved_in, 10u);
  ASSERT_EQ(moved_f, 10u);
  ASSERT_EQ(moved_out, 10u);
  const std::size_t n_before = P.n_owned();
  EXPECT_TRUE(ob.update(s.S, k));
  const double m = P.mass[0];
  EXPECT_NEAR(k.inflow_mass, 10 * m, 1e-12);
  EXPECT_NEAR(k.outflow_mass, 10 * m, 1e-12);
  EXPECT_EQ(P.n_owned(), n_before);  // 10 created, 10 deleted
  EXPECT_EQ(count(P, Kind::Inflow), 50u);
  EXPECT_EQ(count(P, Kind::Outflow), 50u);
  // mass balance of the fluid set: initial + inflow - outflow = now
  EXPECT_NEAR(s.S.total_mass(Kind::Fluid), m_fluid0 + k.inflow_mass - k.outflow_mass, 1e-12);
  // the new inflow particles: one zone length upstream of the converted ones, fresh ids, imposed state
  std::size_t fresh = 0;
  for (std::size_t i = 0; i < P.n_owned(); ++i) {
    if (P.id[i] < id0) continue;
    ++fresh;
    EXPECT_EQ(P.kind[i], Kind::Inflow);
    EXPECT_NEAR(P.pos[i][0], 0.045 + 0.01 - 0.05, 1e-12);
    EXPECT_DOUBLE_EQ(P.vel[i][0], 0.2);
  }
  EXPECT_EQ(fresh, 10u);
  EXPECT_EQ(k.next_id, id0 + 10u);
  // converted outflow particles carry the imposed outflow velocity
  for (std::size_t i = 0; i < P.n_owned(); ++i) {
    if (P.kind[i] == Kind::Outflow) {
      EXPECT_DOUBLE_EQ(P.vel[i][0], 0.1);
    }
  }
  EXPECT_FALSE(ob.update(s.S, k));  // nothing crossed since

  // a fluid particle pushed back into the inflow zone is removed and counted, not left to
  // overlap the inflow lattice
  std::size_t f = 0;
  while (P.kind[f] != Kind::Fluid) ++f;
  P.pos[f][0] = 0.03;  // 2 dx inside the zone [0, 0.05)
  const double before = s.S.total_mass(Kind::Fluid);
  EXPECT_TRUE(ob.update(s.S, k));
  EXPECT_EQ(k.backflow, 1);
  EXPECT_NEAR(k.backflow_mass, m, 1e-15);
  EXPECT_NEAR(s.S.total_mass(Kind::Fluid), before - m, 1e-12);
}

TEST(OpenBoundary, AveragedInflowAndExtrapolatedOutflowCopyTheFluidNextToThem) {
  // Kazemi's unknown-discharge inflow and a zero-gradient outflow: in a uniform stream the
  // Shepard average at the nodes is exactly the stream's state (the inflow takes its streamwise
  // velocity and density, the outflow its whole velocity); a hydrostatic outflow takes
  // the pressure of the local depth (highest fluid particle next to the zone + dx/2).
  test::Setup<2> s(kChannel, {"open_boundaries.0.velocity=averaged", "open_boundaries.1.velocity=extrapolated",
                              "open_boundaries.1.pressure=hydrostatic"});
  OpenBoundaries<2> ob(s.c);
  OpenFlowCounters k;
  ob.setup(s.S, k);
  ASSERT_TRUE(ob.needs_prepare());
  auto& P = s.S.particles;
  for (std::size_t i = 0; i < P.n_owned(); ++i)
    if (P.kind[i] == Kind::Fluid) { P.vel[i][0] = 0.37; P.vel[i][1] = -0.02; P.rho[i] = 1001.5; }
  s.S.update_neighbours();
  ob.prepare(s.S);
  std::size_t nin = 0, nout = 0;
  for (std::size_t i = 0; i < P.n_owned(); ++i) {
    if (P.kind[i] == Kind::Inflow) {
      ++nin;
      EXPECT_NEAR(P.vel[i][0], 0.37, 1e-12);
      EXPECT_EQ(P.vel[i][1], 0.0);  // the streamwise part only: inflow rows keep their elevation
      EXPECT_NEAR(P.rho[i], 1001.5, 1e-9);
      EXPECT_NEAR(P.p[i], s.S.eos.pressure(1001.5), 1e-6);
    } else if (P.kind[i] == Kind::Outflow) {
      ++nout;
      EXPECT_NEAR(P.vel[i][0], 0.37, 1e-12);
      // the fluid column next to the outflow zone reaches z = 0.095 (+ dx/2 = 0.1)
      EXPECT_NEAR(P.p[i], 1000.0 * 9.81 * (0.1 - P.pos[i][1]), 1e-6);
    }
  }
  EXPECT_EQ(nin, 50u);
  EXPECT_EQ(nout, 50u);
  // a stream running upstream is not copied into the inlet: no backflow through the inflow zone
  for (std::size_t i = 0; i < P.n_owned(); ++i)
    if (P.kind[i] == Kind::Fluid) P.vel[i][0] = -0.1;
  ob.prepare(s.S);
  for (std::size_t i = 0; i < P.n_owned(); ++i) {
    if (P.kind[i] == Kind::Inflow) {
      EXPECT_EQ(P.vel[i][0], 0.0);
    }
  }
}

// Averaged (Kazemi) inflow: the inflow rows are stacked at the heights of the hydrostatically
// compressed column (each particle m/(rho dx) tall), so the column stands as high as the fluid
// settles and not dx per row: the column is sum_k m/(rho_k dx) tall, shorter than the imposed
// depth by the mean compression, and rows keep their order and touch.
TEST(OpenBoundary, AveragedInflowRowsStackAtTheSettledHeights) {
  test::Setup<2> s(kChannel, {"open_boundaries.0.velocity=averaged", "fluid.sound_speed=5.0", "fluid.eos=linear"});
  OpenBoundaries<2> ob(s.c);
  OpenFlowCounters k;
  ob.setup(s.S, k);
  const auto& P = s.S.particles;
  std::vector<std::pair<double, double>> col;  // (z, height) of the inflow column at x = 0.005
  for (std::size_t i = 0; i < P.n_owned(); ++i)
    if (P.kind[i] == Kind::Inflow && std::abs(P.pos[i][0] - 0.005) < 1e-9) col.push_back({P.pos[i][1], P.mass[i] / (P.rho[i] * 0.01)});
  std::sort(col.begin(), col.end());
  ASSERT_EQ(col.size(), 10u);
  EXPECT_NEAR(col[0].first, 0.005, 1e-12);  // the bottom row stays
  const double bottom = col[0].first - 0.5 * col[0].second;  // the bottom row's lower face
  double height = 0.0;
  for (std::size_t r = 0; r < col.size(); ++r) {
    EXPECT_LT(col[r].second, 0.01);  // compressed: shorter than dx
    if (r > 0) {
      EXPECT_NEAR(col[r].first - col[r - 1].first, 0.5 * (col[r].second + col[r - 1].second), 1e-12);
    }
    height += col[r].second;
  }
  // linear EOS: a row at pressure p is dx rho0/(rho0 + p/c0²) tall, so the column is shorter by
  // about g H²/(2 c0²) = 1.96 mm (to first order in p/(rho0 c0²) <= 3.7 %: within 5 % of it)
  const double expected = 0.1 * (1.0 - 1000.0 * 9.81 * 0.1 / (2.0 * 1000.0 * 25.0));
  EXPECT_NEAR(col.back().first + 0.5 * col.back().second, bottom + height, 1e-12);  // rows touch
  EXPECT_NEAR(height, expected, 0.05 * (0.1 - expected));
}

// Resolution levels (docs/numerics.md §14, issue 58): the channel with a refined bed layer over its whole length,
// run whole (run_case: the crossings, the splits and the merges of the run loop). New inflow particles are level 0
// and split where they enter the layer; particles leave through the outflow at whatever level they have. Every
// mass is counted: initial + inflow − outflow (+ backflow) = final to round-off, with splits and merges on the way.
TEST(OpenBoundary, MassBalanceClosesWithALevelLayer) {
  const std::string yaml = std::string(kChannel).substr(0, std::string(kChannel).find("time:")) +
      "resolution: {regions: [{shape: box, min: [-0.1, -0.1], max: [0.5, 0.03], level: 1}]}\n"
      "time: {end: 0.3, output_interval: 0.3}\n";
  const Case c = parse_case(yaml, "channel.yaml");
  ASSERT_TRUE(c.resolution.on());
  RunOptions o;
  o.output = (std::filesystem::temp_directory_path() / "sphflume_test_open_levels").string();
  o.progress = false;
  o.threads = 1;
  const RunResult r = run_case(c, o);
  ASSERT_EQ(r.exit_code, 0);
  EXPECT_LT(std::abs(r.mass_error), 1e-12);
  std::ifstream f(o.output + "/summary.json");
  const auto j = nlohmann::json::parse(f);
  EXPECT_GT(j["resolution"]["splits"].get<long>(), 0);     // inflow particles entering the layer
  EXPECT_GT(j["mass"]["inflow"].get<double>(), 0.0);
  EXPECT_GT(j["mass"]["outflow"].get<double>(), 0.0);
  std::filesystem::remove_all(o.output);
}
