// Particle shifting (physics/shifting.hpp): it relaxes a disordered particle set towards a
// uniform one, leaves a regular lattice where it is, keeps free-surface particles in place and
// moves the row under the surface only along it.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <map>
#include <string>

#include "sphflume/core/fields.hpp"
#include "sphflume/physics/shifting.hpp"
#include "test_helpers.hpp"

using namespace sph;

namespace {
// a doubly periodic block of fluid (no walls, no gravity), dx = 0.01, h = 1.5 dx
const char* kPeriodic = R"(
dimension: 2
gravity: [0.0, 0.0]
particles: {dx: 0.01, kernel: wendland_c2, h_over_dx: 1.5}
fluid: {density: 1000.0, viscosity: 1.0e-6, sound_speed: 10.0, hydrostatic_init: false}
scheme: {density_diffusion: none, viscosity: laminar}
domain: {min: [0.0, 0.0], max: [0.2, 0.2], periodic: [x, z]}
geometry:
  - {type: box, fill: fluid, min: [0.0, 0.0], max: [0.2, 0.2]}
time: {end: 1.0}
)";

/// RMS over the owned fluid particles of h |∇C|, ∇C = Σ_b V_b ∇W_ab (0 on a regular lattice).
double disorder(const System<2>& S) {
  const auto& P = S.particles;
  WendlandC2<2> k(S.h);
  double s = 0.0;
  for (std::size_t a = 0; a < P.n_owned(); ++a) {
    Vec<2> g{};
    S.cells.for_neighbours(P.pos, P.pos[a], k.support, [&](std::uint32_t b, const Vec<2>& r, double r2) {
      if (r2 > 0.0) g += (P.mass[b] / P.rho[b] * k.F(std::sqrt(r2))) * r;
    });
    s += dot(g, g) * S.h * S.h;
  }
  return std::sqrt(s / double(P.n_owned()));
}

/// n shifts of the periodic block s by sh, each from freshly built neighbour lists.
void shift_times(test::Setup<2>& s, Shifting<2>& sh, double dt, int n) {
  for (int k = 0; k < n; ++k) {
    s.S.update_neighbours();
    sh.compute(s.S, dt);
    sh.apply(s.S);
    s.S.periodic.wrap(s.S.particles);
  }
}
}  // namespace

// A lattice disturbed by up to ±0.2 dx (fixed pseudo-random numbers): shifting is a diffusion of
// the particle concentration, so the disorder must fall, steadily, far below its start; the
// particles' mass and velocity are untouched.
TEST(Shifting, RelaxesADisturbedLatticeTowardsUniform) {
  test::Setup<2> s(kPeriodic, {"scheme.shifting.coefficient=2"});
  auto& P = s.S.particles;
  std::uint32_t seed = 12345u;
  auto rnd = [&] { seed = seed * 1664525u + 1013904223u; return double(seed >> 8) / double(1u << 24) - 0.5; };
  for (std::size_t i = 0; i < P.n_owned(); ++i) {
    P.pos[i] += Vec<2>{{0.4 * 0.01 * rnd(), 0.4 * 0.01 * rnd()}};
    P.vel[i] = Vec<2>{{1.0, 0.0}};
  }
  s.S.periodic.wrap(P);
  Shifting<2> sh(s.c.scheme.shifting);
  const double dt = 0.02 * s.S.h / 1.0;  // |u| dt / h = 0.02: a WCSPH step at u = c/10
  s.S.update_neighbours();
  const double d0 = disorder(s.S);
  EXPECT_GT(d0, 0.05);
  double prev = d0;
  for (int block = 0; block < 5; ++block) {
    shift_times(s, sh, dt, 100);
    s.S.update_neighbours();
    const double d = disorder(s.S);
    EXPECT_LT(d, prev) << "block " << block;
    prev = d;
  }
  EXPECT_LT(prev, 0.1 * d0);
  for (std::size_t i = 0; i < P.n_owned(); ++i) {
    ASSERT_DOUBLE_EQ(P.vel[i][0], 1.0);
    ASSERT_DOUBLE_EQ(P.vel[i][1], 0.0);
  }
}

// A regular block with free surfaces all round, moving uniformly: the surface rows (∇·r < 1.5)
// stay, the interior of a lattice has ∇C = 0 and stays, and the row under a flat surface, whose
// ∇C points inwards (h ∇C_z = 0.116 on this lattice), does not move towards it. Away from the
// corners (where two surfaces meet) nothing moves to round-off.
TEST(Shifting, KeepsTheSurfaceAndTheRowBelowIt) {
  test::Setup<2> s(test::kLattice2D, {"scheme.shifting.coefficient=2"});
  auto& P = s.S.particles;
  for (std::size_t i = 0; i < P.n_owned(); ++i) P.vel[i] = Vec<2>{{1.0, 0.0}};
  s.S.update_neighbours();
  Shifting<2> sh(s.c.scheme.shifting);
  const double dt = 0.02 * s.S.h;
  sh.compute(s.S, dt);
  const auto& dr = P.vector(field::shift);
  const double scale = 2.0 * s.S.h * 1.0 * dt / s.S.h;  // A h |u| dt times a ∇C of 1/h
  int n = 0, second = 0;
  for (std::size_t i = 0; i < P.n_owned(); ++i) {
    const double x = P.pos[i][0], z = P.pos[i][1];
    if (x < 0.06 || x > 0.24 || z < 0.06) continue;  // away from the sides and the bottom corners
    ++n;
    if (z > 0.28 && z < 0.29) ++second;
    EXPECT_LT(std::sqrt(dot(dr[i], dr[i])), 1e-9 * scale) << x << ", " << z;
  }
  EXPECT_GT(n, 300);
  EXPECT_GT(second, 15);
  // without the tangential projection the second row would move by about 0.116 * scale upwards:
  // check that the scale of the test is right (the bare ∇C there is that large)
  for (std::size_t i = 0; i < P.n_owned(); ++i)
    if (P.pos[i][0] > 0.1 && P.pos[i][0] < 0.2 && P.pos[i][1] > 0.28 && P.pos[i][1] < 0.29) {
      Vec<2> g{};
      WendlandC2<2> k(s.S.h);
      s.S.cells.for_neighbours(P.pos, P.pos[i], k.support, [&](std::uint32_t b, const Vec<2>& r, double r2) {
        if (r2 > 0.0) g += (P.mass[b] / P.rho[b] * k.F(std::sqrt(r2))) * r;
      });
      EXPECT_NEAR(g[1] * s.S.h, -0.116, 0.01);
    }
}

// Resolution levels (docs/numerics.md §14): the shift takes the pair's h_ab = (h_a + h_b)/2 in ∇C and each
// particle's own h in D = A h_a |u| Δt.
namespace {
/// The periodic block of kPeriodic refined everywhere (level 1: dx/2, h/2) or, with `middle`, in its middle only.
std::string periodic_levels(bool middle) {
  return std::string(kPeriodic) + (middle ? "resolution: {regions: [{shape: box, min: [0.05, 0.05], max: [0.15, 0.15], level: 1}]}\n"
                                          : "resolution: {regions: [{shape: box, min: [-1.0, -1.0], max: [1.0, 1.0], level: 1}]}\n");
}
/// A smooth, deterministic disturbance of a point (up to ±0.1 of the fine spacing 0.005).
Vec<2> wobble(const Vec<2>& x) {
  return Vec<2>{{0.0005 * std::sin(97.0 * x[0] + 31.0 * x[1]), 0.0005 * std::cos(53.0 * x[0] - 71.0 * x[1])}};
}
/// RMS of h_a |∇C_a| with the pairs' h_ab.
double disorder_levels(const System<2>& S) {
  const auto& P = S.particles;
  const auto& hs = P.require(field::smoothing_length);
  WendlandC2<2> k(S.h);
  double s = 0.0;
  for (std::size_t a = 0; a < P.n_owned(); ++a) {
    Vec<2> g{};
    S.cells.for_neighbours(P.pos, P.pos[a], k.support, [&](std::uint32_t b, const Vec<2>& r, double r2) {
      if (r2 > 0.0) g += (P.mass[b] / P.rho[b] * k.Fh(std::sqrt(r2), 2.0 / (hs[a] + hs[b]))) * r;
    });
    s += dot(g, g) * hs[a] * hs[a];
  }
  return std::sqrt(s / double(P.n_owned()));
}
}  // namespace

// One level everywhere: the shift of a disturbed level-1 lattice is the shift of the same lattice run at dx/2
// without levels, to round-off (the per-pair h path reduces to the one-level one).
TEST(Shifting, OneLevelEverywhereIsTheUniformFineShift) {
  test::Setup<2> lev(periodic_levels(false), {"scheme.shifting.coefficient=2"});
  test::Setup<2> uni(kPeriodic, {"scheme.shifting.coefficient=2", "particles.dx=0.005"});
  ASSERT_EQ(lev.S.levels, 1);
  ASSERT_EQ(lev.S.particles.n_owned(), uni.S.particles.n_owned());
  std::map<std::pair<long, long>, Vec<2>> shift_at;  // the uniform run's shift by lattice site
  auto site = [](const Vec<2>& x) { return std::make_pair(std::lround(x[0] / 0.0025), std::lround(x[1] / 0.0025)); };
  double largest = 0.0;
  for (auto* s : {&uni, &lev}) {
    auto& P = s->S.particles;
    for (std::size_t i = 0; i < P.n_owned(); ++i) {
      P.vel[i] = Vec<2>{{1.0, 0.0}};
      P.pos[i] += wobble(P.pos[i]);
    }
    s->S.periodic.wrap(P);
    s->S.update_neighbours();
    Shifting<2> sh(s->c.scheme.shifting);
    sh.compute(s->S, 1e-4);
    const auto& dr = P.vector(field::shift);
    for (std::size_t i = 0; i < P.n_owned(); ++i) {
      const auto key = site(P.pos[i] - wobble(P.pos[i]));
      if (s == &uni) {
        shift_at[key] = dr[i];
        largest = std::max(largest, norm(dr[i]));
        continue;
      }
      ASSERT_TRUE(shift_at.count(key)) << P.pos[i][0] << ", " << P.pos[i][1];
      EXPECT_LT(norm(dr[i] - shift_at[key]), 1e-9 * largest) << P.pos[i][0] << ", " << P.pos[i][1];
    }
  }
  EXPECT_GT(largest, 1e-8);  // (the disturbance gives every particle a shift: the comparison is not of zeros)
}

// A disturbed block whose middle is refined: repeated shifts relax the disorder on both levels and across the
// interface (the pairs' h_ab), and move positions only: the mass, the momentum and the particles of each level
// are those of the start.
TEST(Shifting, RelaxesDisorderAcrossALevelInterface) {
  test::Setup<2> s(periodic_levels(true), {"scheme.shifting.coefficient=2"});
  ASSERT_EQ(s.S.levels, 1);
  auto& P = s.S.particles;
  const auto& lv = P.require(field::level);
  std::uint32_t seed = 12345u;
  auto rnd = [&] { seed = seed * 1664525u + 1013904223u; return double(seed >> 8) / double(1u << 24) - 0.5; };
  std::size_t fine = 0;
  for (std::size_t i = 0; i < P.n_owned(); ++i) {
    const double dxl = lv[i] > 0.5 ? 0.005 : 0.01;
    P.pos[i] += Vec<2>{{0.4 * dxl * rnd(), 0.4 * dxl * rnd()}};
    P.vel[i] = Vec<2>{{1.0, 0.0}};
    fine += lv[i] > 0.5 ? 1 : 0;
  }
  s.S.periodic.wrap(P);
  ASSERT_GT(fine, 300u);
  const double mass = s.S.total_mass(Kind::Fluid);
  Shifting<2> sh(s.c.scheme.shifting);
  const double dt = 0.02 * s.S.h / 1.0;
  s.S.update_neighbours();
  const double d0 = disorder_levels(s.S);
  shift_times(s, sh, dt, 500);
  s.S.update_neighbours();
  const double d = disorder_levels(s.S);
  EXPECT_GT(d0, 0.05);
  EXPECT_LT(d, 0.25 * d0);
  EXPECT_NEAR(s.S.total_mass(Kind::Fluid), mass, 1e-14 * mass);  // (the sum's order follows the store's sorting)
  std::size_t fine_after = 0;
  for (std::size_t i = 0; i < P.n_owned(); ++i) {
    ASSERT_EQ(P.vel[i][0], 1.0);
    ASSERT_EQ(P.vel[i][1], 0.0);
    fine_after += lv[i] > 0.5 ? 1 : 0;
  }
  EXPECT_EQ(fine_after, fine);
}
