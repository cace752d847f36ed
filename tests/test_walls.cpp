// No fluid particle may cross a wall (issue 20, defect 6). A thin slow film is the hard case for
// wall models that take their pressure from the fluid: a 1 cm column at dx = 0.5 mm spreads into
// a film a few particles thick, whose pressures (tens of Pa) are of the order of the pressure
// noise, so dummy walls may pull a particle instead of pushing it. The backup force
// (walls.backup, WallModel::add_backup) must keep every fluid centre on the fluid side of the
// bed's surface (z = 0) at all times; the control run without it shows the film does drive
// particles through, so the test can fail.
#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <random>

#include "sphflume/core/interpolate.hpp"
#include "test_helpers.hpp"

using namespace sph;

namespace {
const char* kFilm = R"(
dimension: 2
gravity: [0.0, -9.81]
particles: {dx: 0.0005, kernel: wendland_c2, h_over_dx: 2.0}
fluid: {density: 1000.0, viscosity: 1.0e-6, sound_speed: 4.5}
scheme: {integrator: symplectic, density_diffusion: fourtakas, delta: 0.1, viscosity: artificial, alpha: 0.02, cfl: 0.2}
walls: {type: dummy, slip: no_slip}
geometry:
  - {type: tank, fill: wall, min: [0.0, 0.0], max: [0.12, 0.05]}
  - {type: box, fill: fluid, min: [0.0, 0.0], max: [0.015, 0.01]}
time: {end: 0.6}
)";

struct FilmResult {
  double min_z = std::numeric_limits<double>::infinity();  // lowest fluid centre over the run
  double time = 0.0;
  std::size_t fluid0 = 0, fluid = 0;
};

/// Runs the film to t_end (or until a fluid centre is below z_stop) and tracks the lowest fluid
/// centre, checked after every step.
FilmResult run_film(const std::vector<std::string>& sets, double t_end, double z_stop) {
  test::Setup<2> s(kFilm, sets);
  FilmResult r;
  r.fluid0 = s.S.particles.count(Kind::Fluid);
  s.scheme->initialise(s.S);
  while (s.S.time < t_end && r.min_z >= z_stop) {
    s.scheme->step(s.S, s.scheme->time_step(s.S));
    const auto& P = s.S.particles;
    for (std::size_t i = 0; i < P.n_owned(); ++i)
      if (P.kind[i] == Kind::Fluid) r.min_z = std::min(r.min_z, P.pos[i][1]);
  }
  s.S.particles.clear_images();
  r.time = s.S.time;
  r.fluid = s.S.particles.count(Kind::Fluid);
  return r;
}
}  // namespace

TEST(Walls, ThinSlowFilmNeverCrossesTheBed) {
  for (const char* walls : {"dummy", "dynamic"}) {
    SCOPED_TRACE(std::string(walls) + " walls");
    const FilmResult r = run_film({std::string("walls.type=") + walls}, 0.6, -1.0);
    EXPECT_GE(r.time, 0.6);
    EXPECT_EQ(r.fluid, r.fluid0);  // none removed
    // every centre stays on the fluid side of the surface z = 0 (the film sits at dx/2 = 2.5e-4)
    EXPECT_GT(r.min_z, 0.0);
  }
}

TEST(Walls, ThinSlowFilmSinksThroughDummyBedWithoutBackup) {
  // control: the same film over Adami dummy walls without the backup puts a particle's centre
  // below the surface (it reached z = -0.64 dx by t = 0.53 s when this test was written)
  const FilmResult r = run_film({"walls.backup=false"}, 0.6, -0.1 * 0.0005);
  EXPECT_LT(r.min_z, 0.0);
}

// The backup's search (packed float columns, a widened float test, the exact double test) finds
// exactly the pairs of its definition: every fluid particle a and first-layer wall particle k
// (depth d_k < dx below the surface) with |x_a − x_k| < hypot(dx + s0, dx), s = r·n_k − d_k < s0
// = dx/4 and r∥ < dx, r = x_a − x_k. The bottom layer of a column is pushed down by random
// amounts from 0 to 0.8 dx (many particles inside the s0 band, some past the surface), and the
// force is compared with a brute-force sum over all pairs, in 2D and 3D.
namespace {
template <int D>
void backup_matches_brute_force(const char* yaml) {
  test::Setup<D> s(yaml);
  auto& P = s.S.particles;
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const double dx = s.S.dx;
  for (std::size_t i = 0; i < P.n_owned(); ++i) {
    if (P.kind[i] != Kind::Fluid) continue;
    for (int d = 0; d < D; ++d) P.vel[i][d] = 0.2 * (u(rng) - 0.5);
    if (P.pos[i][D - 1] < dx) P.pos[i][D - 1] -= 0.8 * dx * u(rng);  // the bottom layer (at dx/2)
  }
  s.S.update_neighbours();
  for (auto& a : P.acc) a = Vec<D>{};
  s.S.walls->add_forces(s.S);
  const auto& to = P.vector(field::wall_to_surface);
  const auto& cfg = s.S.walls->cfg;
  const double s0 = 0.25 * dx, reach = std::hypot(dx + s0, dx), c0 = s.S.eos.c0, pi = std::acos(-1.0);
  std::size_t pushed = 0;
  double fmax = 0.0;
  for (std::size_t a = 0; a < P.n_owned(); ++a) {
    if (P.kind[a] != Kind::Fluid) continue;
    Vec<D> f{};
    for (std::size_t k = 0; k < P.n_owned(); ++k) {
      if (P.kind[k] != Kind::Wall) continue;
      const double depth = std::sqrt(dot(to[k], to[k]));
      if (!(depth > 0.0) || depth >= dx) continue;
      const Vec<D> nk = (1.0 / depth) * to[k], r = P.pos[a] - P.pos[k];
      const double rn = dot(r, nk), r2 = dot(r, r);
      if (!(r2 < reach * reach) || rn - depth >= s0 || r2 - rn * rn >= dx * dx) continue;
      const double rt = std::sqrt(std::max(0.0, r2 - rn * rn)), q = 1.0 - (rn - depth) / s0;
      const double A = std::max(0.0, cfg.beta1 * c0 * c0 + cfg.beta2 * c0 * -dot(P.vel[a] - P.vel[k], nk)) / s.S.h;
      f += (A * q * q * 0.5 * (1.0 + std::cos(pi * rt / dx))) * nk;
    }
    pushed += norm(f) > 0.0;
    fmax = std::max(fmax, norm(f));
    for (int d = 0; d < D; ++d) ASSERT_NEAR(P.acc[a][d], f[d], 1e-12 * (1.0 + norm(f))) << "particle " << a;
  }
  EXPECT_GT(pushed, 10u);  // not vacuous
  EXPECT_GT(fmax, 0.0);
}
}  // namespace

// a 0.6 x 0.3 m tank with dummy walls (dx 0.01, h = 1.5 dx), its geometry list open for more shapes
constexpr const char* kDummyTank2D = R"(
dimension: 2
gravity: [0.0, -9.81]
particles: {dx: 0.01, kernel: wendland_c2, h_over_dx: 1.5}
fluid: {density: 1000.0, viscosity: 1.0e-6, sound_speed: 20.0}
walls: {type: dummy, slip: free_slip}
time: {end: 1.0}
geometry:
  - {type: tank, fill: wall, min: [0.0, 0.0], max: [0.6, 0.3]}
)";

TEST(Walls, BackupFindsExactlyItsPairs2D) {
  backup_matches_brute_force<2>((std::string(kDummyTank2D) + "  - {type: box, fill: fluid, min: [0.0, 0.0], max: [0.4, 0.1]}\n").c_str());
}

TEST(Walls, BackupFindsExactlyItsPairs3D) {
  backup_matches_brute_force<3>(R"(
dimension: 3
gravity: [0.0, 0.0, -9.81]
particles: {dx: 0.02, kernel: wendland_c2, h_over_dx: 1.5}
fluid: {density: 1000.0, viscosity: 1.0e-6, sound_speed: 20.0}
walls: {type: dummy, slip: free_slip}
geometry:
  - {type: tank, fill: wall, min: [0.0, 0.0, 0.0], max: [0.4, 0.2, 0.3]}
  - {type: box, fill: fluid, min: [0.0, 0.0, 0.0], max: [0.3, 0.2, 0.1]}
time: {end: 1.0}
)");
}

// A block resting on the floor: its bottom face and the floor under it are covered, never wet
// (fill_shapes flags their wall particles "wall_covered"). Their surface points must not push the
// fluid, or the block's foot pushes the fluid beside it down into the floor-block corner at up to
// four times the force at the surface (docs/numerics.md §14, the refined 3D obstacle). The fluid
// column beside the block is pressed against the block's face by 0.35 dx: the backup must push it
// away from the face and never into the floor; with the flags cleared (the control) the block's
// bottom-face particles at its foot push some of it down.
namespace {
const std::string kBlockOnFloor = std::string(kDummyTank2D) +
                                  "  - {type: box, fill: wall, min: [0.3, 0.0], max: [0.4, 0.1]}\n"
                                  "  - {type: box, fill: fluid, min: [0.0, 0.0], max: [0.3, 0.1]}\n";
// the same block as a piston paddle sliding on the floor (a moving body: fill_shapes flags fixed faces only)
const std::string kPistonOnFloor = std::string(kDummyTank2D) +
                                   "  - {type: box, fill: wall, min: [0.3, 0.0], max: [0.4, 0.1], motion: piston}\n"
                                   "  - {type: box, fill: fluid, min: [0.0, 0.0], max: [0.3, 0.1]}\n"
                                   "motions:\n  - {name: piston, law: regular, height: 0.01, depth: 0.1, period: 1.0}\n";
// the smallest vertical backup acceleration over the fluid beside the block's foot
double lowest_push_beside_block(bool clear_flags, const std::string& yaml = kBlockOnFloor) {
  test::Setup<2> s(yaml);
  auto& P = s.S.particles;
  const double dx = s.S.dx;
  if (clear_flags) for (auto& v : P.require(field::wall_covered)) v = 0.0;
  for (std::size_t i = 0; i < P.n_owned(); ++i)
    if (P.kind[i] == Kind::Fluid && P.pos[i][0] > 0.3 - dx) P.pos[i][0] += 0.35 * dx;  // into the s0 band (dx/4 from the face)
  s.S.update_neighbours();
  for (auto& a : P.acc) a = Vec<2>{};
  s.S.walls->add_forces(s.S);
  double lowest = 0.0;
  for (std::size_t i = 0; i < P.n_owned(); ++i)
    if (P.kind[i] == Kind::Fluid && P.pos[i][0] > 0.3 - dx) {
      if (P.pos[i][1] > dx) {  // (the bottom row's face particle is the corner's: its surface point is on the bottom face)
        EXPECT_LT(P.acc[i][0], 0.0) << "the block's face pushes the particle at y = " << P.pos[i][1] << " away";
      }
      lowest = std::min(lowest, P.acc[i][1]);
    }
  return lowest;
}
}  // namespace

TEST(Walls, CoveredFacesAreFlaggedAndPushNoFluid) {
  test::Setup<2> s(kBlockOnFloor);
  const auto& P = s.S.particles;
  const auto& cov = P.require(field::wall_covered);
  const auto& to = P.require(field::wall_to_surface);
  std::size_t block_bottom = 0, floor_under = 0;
  for (std::size_t k = 0; k < P.n_owned(); ++k) {
    if (P.kind[k] != Kind::Wall) continue;
    const Vec<2> sp = P.pos[k] + to[k];
    const bool on_floor_line = std::abs(sp[1]) < 1e-12 && sp[0] > 0.3 && sp[0] < 0.4;  // the covered strip
    const bool expect = on_floor_line && norm(to[k]) > 0.0;
    EXPECT_EQ(cov[k] != 0.0, expect) << "wall particle at (" << P.pos[k][0] << ", " << P.pos[k][1] << ")";
    if (expect && std::abs(P.pos[k][1] - 0.005) < 1e-9) ++block_bottom;
    if (expect && std::abs(P.pos[k][1] + 0.005) < 1e-9) ++floor_under;
  }
  EXPECT_GE(block_bottom, 8u);  // the block's bottom row: 10 particles; its two corners tie between the bottom and
  EXPECT_LE(block_bottom, 10u); // the side faces, and the float distances decide
  EXPECT_EQ(floor_under, 10u);  // the floor's top row under it (deeper rows and the block's lower inside are flagged too)
  const double g = 9.81;
  EXPECT_GE(lowest_push_beside_block(false), -1e-9 * g);  // nothing pushes the fluid into the floor
  EXPECT_LT(lowest_push_beside_block(true), -g);           // the control: the foot does, without the flags
}

// A moving body's face resting on a fixed wall (a piston paddle's foot on the bed) is covered while it rests there,
// found each pass (WallModel::add_backup): the piston's bottom face pushes no fluid into the floor. (Without it the
// coarse regular waves pushed fluid under the paddle's front edge into the bed until it tore: session 42.)
TEST(Walls, MovingFaceRestingOnAFixedWallPushesNoFluid) {
  const double g = 9.81;
  EXPECT_GE(lowest_push_beside_block(false, kPistonOnFloor), -1e-9 * g);
}

// First-order MLS (core/interpolate.hpp; the fixed ghost walls' interpolation, Marrone et al. 2011, Federico §5.2.6)
// reproduces a linear field exactly wherever the moment matrix is regular: inside the block, at a corner where
// three quarters of the support are empty, and at a point outside the block with fluid within its support (a
// mirror point's case), in 2D and 3D; several fields at once. Round-off of sums of order 1: 1e-10.
template <int D>
void mls_reproduces_linear_fields(const std::string& yaml, const std::vector<Vec<D>>& points) {
  test::Setup<D> s(yaml);
  auto& S = s.S;
  auto& P = S.particles;
  auto lin = [](const Vec<D>& x, int k) {
    double v = 3.0 + k;
    for (int d = 0; d < D; ++d) v += (d + 1.5) * (k % 2 ? -1.0 : 1.0) * x[d];
    return v;
  };
  S.update_neighbours();
  for (const auto& x : points) {
    const auto v = interpolate_mls_n<D, D + 1>(S, x, [&](std::uint32_t b) {
      std::array<double, D + 1> f;
      for (int k = 0; k <= D; ++k) f[k] = lin(P.pos[b], k);
      return f;
    });
    ASSERT_TRUE(v.has_value());
    for (int k = 0; k <= D; ++k) EXPECT_NEAR((*v)[k], lin(x, k), 1e-10) << "field " << k << " at " << x[0] << ", " << x[1];
  }
  // several points under one stencil (interpolate_mls_shared, the fixed ghost walls' cells): each point's values are
  // bitwise those of interpolate_mls_n there (the same candidates in the same order)
  auto fields = [&](std::uint32_t b) {
    std::array<double, D + 1> f;
    for (int k = 0; k <= D; ++k) f[k] = lin(P.pos[b], k) + 0.1 * std::sin(37.0 * P.pos[b][0] + 11.0 * P.pos[b][D - 1] * k);
    return f;
  };
  const double support = S.with_kernel([](const auto& K) { return K.support; });
  for (const auto& x : points) {
    std::vector<Vec<D>> near;
    for (int k = 0; k < 7; ++k) {
      Vec<D> y = x;
      for (int d = 0; d < D; ++d) y[d] += 0.3 * support * std::sin(1.7 * k + d);
      near.push_back(y);
    }
    std::vector<std::array<std::uint32_t, 2>> rg(CellList<D>::kMaxRanges);
    auto* r = reinterpret_cast<std::uint32_t(*)[2]>(rg.data());
    const int nr = S.cells.ranges(x, r, 2.0 * support);  // (covers each point's support)
    std::size_t seen = 0;
    interpolate_mls_shared<D, D + 1>(S, r, nr, near.data(), near.size(), fields, [&](std::size_t j, const auto& v) {
      const auto one = interpolate_mls_n<D, D + 1>(S, near[j], fields);
      ASSERT_EQ(v.has_value(), one.has_value());
      if (v) {
        for (int k = 0; k <= D; ++k) EXPECT_EQ((*v)[k], (*one)[k]) << "point " << j << ", field " << k;
      }
      ++seen;
    });
    EXPECT_EQ(seen, near.size());
  }
  // no water within the support: empty
  Vec<D> far{};
  far[0] = 10.0;
  EXPECT_FALSE((interpolate_mls_n<D, 1>(S, far, [&](std::uint32_t) { return std::array<double, 1>{1.0}; })).has_value());
}

TEST(Walls, MlsReproducesLinearFieldsWhereTheSupportIsCut) {
  mls_reproduces_linear_fields<2>(test::kLattice2D, {Vec<2>{{0.15, 0.15}}, Vec<2>{{0.297, 0.296}}, Vec<2>{{0.31, 0.15}}});
  mls_reproduces_linear_fields<3>(R"(
dimension: 3
gravity: [0.0, 0.0, 0.0]
particles: {dx: 0.02, kernel: wendland_c2, h_over_dx: 1.5}
fluid: {density: 1000.0, sound_speed: 10.0, hydrostatic_init: false}
geometry:
  - {type: box, fill: fluid, min: [0.0, 0.0, 0.0], max: [0.2, 0.2, 0.2]}
time: {end: 1.0}
)",
                                  {Vec<3>{{0.1, 0.1, 0.1}}, Vec<3>{{0.195, 0.196, 0.197}}, Vec<3>{{0.1, 0.1, 0.215}}});
}
