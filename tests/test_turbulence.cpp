// Turbulence closures and the rough-bed drag (Kazemi ch. 3 and 6): the eddy viscosity from the
// SPH strain rate of a linear shear flow, the stress divergence of a given stress field, the
// diffusive sign of the whole model on a sinusoidal shear layer, the mixing-length profiles and
// the rough-bed shape function (Kazemi eqs 3.7-3.8, 6.7, 3.17).
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include "sphflume/core/fields.hpp"
#include "sphflume/physics/turbulence.hpp"
#include "test_helpers.hpp"

using namespace sph;

namespace {
const char* kLattice = test::kLattice2D;
// the lattice with the Smagorinsky model and no molecular viscosity
const std::vector<std::string> kSmagorinsky = {"fluid.viscosity=0.0", "turbulence.model=smagorinsky", "turbulence.cs=0.15"};

bool interior(const Vec<2>& x) { return x[0] > 0.1 && x[0] < 0.2 && x[1] > 0.1 && x[1] < 0.2; }

/// First-derivative lattice moment m = -Σ_b V_b F(r) z_ab² (1 in the continuum).
double moment(const System<2>& S, std::size_t a) { return test::lattice_moments(S, a).first; }
}  // namespace

// u = γ z: ∂u/∂z = γ m on the lattice, |S| = sqrt(2 S:S) = γ m, ν_t = (C_s dx)² γ m,
// τ_xz/ρ = 2 ν_t S_xz = ν_t γ m; the pair loop sums in single precision (relative 1e-5).
TEST(Turbulence, SmagorinskyEddyViscosityOfLinearShear) {
  test::Setup<2> s(kLattice, kSmagorinsky);
  auto& P = s.S.particles;
  const double gamma = 4.0;
  for (std::size_t i = 0; i < P.n_owned(); ++i) P.vel[i] = Vec<2>{{gamma * P.pos[i][1], 0.0}};
  s.S.update_neighbours();
  s.scheme->rates(s.S);
  const auto& nut = P.scalar(field::nu_t);
  const auto& txz = P.scalar("tau_xz");
  const auto& txx = P.scalar("tau_xx");
  int n = 0;
  for (std::size_t i = 0; i < P.n_owned(); ++i) {
    if (!interior(P.pos[i])) continue;
    ++n;
    const double m = moment(s.S, i);
    EXPECT_NEAR(m, 1.0, 0.005);
    const double nu = 0.15 * 0.15 * 0.01 * 0.01 * gamma * m;
    EXPECT_NEAR(nut[i], nu, 1e-5 * nu);
    EXPECT_NEAR(txz[i], nu * gamma * m, 1e-5 * nu * gamma);
    EXPECT_NEAR(txx[i], 0.0, 1e-5 * nu * gamma);
  }
  EXPECT_GT(n, 50);
}

// The literal |S| = sqrt(S:S) of Kazemi's eq 2.17 is 1/sqrt(2) of the default.
TEST(Turbulence, LiteralStrainNormOption) {
  TurbulenceConfig c;
  c.model = "smagorinsky";
  Turbulence<2> def(c);
  c.strain_literal = true;
  Turbulence<2> lit(c);
  const double G[4] = {0.0, 3.0, 0.0, 0.0};  // ∂u/∂z = 3
  EXPECT_DOUBLE_EQ(def.strain_norm(G), 3.0);
  EXPECT_NEAR(lit.strain_norm(G), 3.0 / std::sqrt(2.0), 1e-12);
}

// A stress field τ_xz/ρ = A z (other components 0) accelerates the fluid by ∂(τ_xz/ρ)/∂z = A
// along x, times the lattice moment: the momentum term is Σ m_b (τ_a/ρ_a² + τ_b/ρ_b²)·∇W.
TEST(Turbulence, StressDivergenceOfLinearStress) {
  test::Setup<2> s(kLattice, kSmagorinsky);
  auto& P = s.S.particles;
  const double A = 0.02;  // m/s² per m of height
  s.S.update_neighbours();
  auto& txz = P.scalar("tau_xz");
  for (std::size_t i = 0; i < P.n_owned(); ++i) txz[i] = A * P.pos[i][1];
  s.S.nu = 0.0;
  s.scheme->rates(s.S);  // uses the stress above (the one of the previous pass), then replaces it
  int n = 0;
  for (std::size_t i = 0; i < P.n_owned(); ++i) {
    if (!interior(P.pos[i])) continue;
    ++n;
    const double m = moment(s.S, i);
    EXPECT_NEAR(P.acc[i][0], A * m, 1e-4 * A);
    EXPECT_NEAR(P.acc[i][1], 0.0, 1e-4 * A);
  }
  EXPECT_GT(n, 50);
}

// Mixing-length model with a constant l_m on a periodic sinusoidal shear layer u = U sin(kz):
// τ_xz/ρ = l² |u'| u', so a_x = ∂τ/∂z = 2 l² |u'| u'', negative for 0 < kz < π/2 where u > 0:
// the model removes momentum where u is largest (diffusive). Tolerance 5 %: the two chained
// SPH first derivatives at kh = 0.16 carry O((kh)²) = 2.5 % of truncation error.
TEST(Turbulence, MixingLengthStressIsDiffusive) {
  const char* box = R"(
dimension: 2
gravity: [0.0, 0.0]
particles: {dx: 0.005, kernel: wendland_c2, h_over_dx: 2.0}
fluid: {density: 1000.0, viscosity: 0.0, sound_speed: 10.0, hydrostatic_init: false}
scheme: {density_diffusion: none, viscosity: laminar}
turbulence: {model: mixing_length, profile: constant, length: 0.01}
geometry:
  - {type: box, fill: fluid, min: [0.0, 0.0], max: [0.1, 0.4]}
domain: {min: [0.0, 0.0], max: [0.1, 0.4], periodic: [x, z]}
time: {end: 1.0}
)";
  test::Setup<2> s(box);
  auto& P = s.S.particles;
  const double U = 0.5, k = 2.0 * std::numbers::pi / 0.4, l = 0.01;
  for (std::size_t i = 0; i < P.n_owned(); ++i) P.vel[i] = Vec<2>{{U * std::sin(k * P.pos[i][1]), 0.0}};
  s.S.update_neighbours();
  s.scheme->rates(s.S);  // first pass: the stress from the velocity gradient
  s.S.update_neighbours();
  s.scheme->rates(s.S);  // second pass: its divergence
  int n = 0;
  for (std::size_t i = 0; i < P.n_owned(); ++i) {
    const double kz = k * P.pos[i][1];
    if (kz < 0.4 || kz > 1.2) continue;  // where u > 0 and both u' and u'' are well away from 0
    ++n;
    const double expected = 2.0 * l * l * std::abs(U * k * std::cos(kz)) * (-U * k * k * std::sin(kz));
    EXPECT_LT(P.acc[i][0], 0.0);
    EXPECT_NEAR(P.acc[i][0], expected, 0.05 * std::abs(expected));
  }
  EXPECT_GT(n, 50);
}

// Nezu–Rodi with Π = 0: l_m = κ z_w sqrt(1 - z_w/H), zero at the bed and at the surface, largest
// (2/3)^(3/2)/sqrt(3)... at z_w = 2H/3; van Driest damping lowers it near the bed only.
TEST(Turbulence, NezuRodiMixingLength) {
  TurbulenceConfig c;
  c.model = "mixing_length";
  c.bed = 0.01;
  Turbulence<2> t(c);
  const double H = 0.05, zs = c.bed + H;
  EXPECT_EQ(t.mixing_length(c.bed, zs, 0.0, 1e-6), 0.0);
  EXPECT_EQ(t.mixing_length(zs, zs, 0.0, 1e-6), 0.0);
  EXPECT_EQ(t.mixing_length(c.bed - 0.001, zs, 0.0, 1e-6), 0.0);
  for (double xi : {0.1, 0.5, 2.0 / 3.0, 0.9})
    EXPECT_NEAR(t.mixing_length(c.bed + xi * H, zs, 0.0, 1e-6), 0.41 * xi * H * std::sqrt(1.0 - xi), 1e-15);
  c.van_driest = true;
  Turbulence<2> vd(c);
  // u* = sqrt(g_x H) = 0.0443 m/s (S0 = 0.004): z+ = 221 at z_w = 5 mm (damping e^-8.5), 4.4 at 0.1 mm
  const double gx = 9.81 * 0.004;
  EXPECT_NEAR(vd.mixing_length(c.bed + 0.005, zs, gx, 1e-6) / t.mixing_length(c.bed + 0.005, zs, gx, 1e-6), 1.0, 1e-3);
  const double zp = 1e-4 * std::sqrt(gx * H) / 1e-6;
  EXPECT_NEAR(vd.mixing_length(c.bed + 1e-4, zs, gx, 1e-6) / t.mixing_length(c.bed + 1e-4, zs, gx, 1e-6),
              1.0 - std::exp(-zp / 26.0), 1e-12);
}

// Kazemi eq 6.7 with Table 6-3 (§6.2.3; z_t, z_c of Table 6-2): l_m(z_c) = 10.4 mm (bed B1) and
// 13.55 mm (B2); continuous at z_0 and z_c.
TEST(Turbulence, ThreeLayerMixingLength) {
  TurbulenceConfig c;
  c.model = "mixing_length";
  c.profile = "three_layer";
  c.z_trough = 0.0366; c.z_crest = 0.0876; c.dz0 = 0.020; c.kappa_r = 0.27; c.kappa_f = 0.22; c.l_mb = 0.002;
  Turbulence<2> b1(c);
  const double zs1 = 0.184;
  EXPECT_NEAR(b1.mixing_length(c.z_crest, zs1, 0, 0), 0.0104, 1e-4);
  const double z0 = c.z_trough + c.dz0;
  EXPECT_NEAR(b1.mixing_length(z0 + 1e-9, zs1, 0, 0), b1.mixing_length(z0 - 1e-9, zs1, 0, 0), 1e-8);
  EXPECT_NEAR(b1.mixing_length(c.z_crest + 1e-9, zs1, 0, 0), b1.mixing_length(c.z_crest - 1e-9, zs1, 0, 0), 1e-8);
  EXPECT_DOUBLE_EQ(b1.mixing_length(0.0, zs1, 0, 0), 0.002);
  EXPECT_NEAR(b1.mixing_length(zs1, zs1, 0, 0), 0.0104, 1e-4);  // l_m(z_ws) = l_mc
  c.z_trough = -0.0055; c.z_crest = 0.0715; c.dz0 = 0.0; c.kappa_r = 0.15;
  Turbulence<2> b2(c);
  EXPECT_NEAR(b2.mixing_length(c.z_crest, 0.166, 0, 0), 0.01355, 1e-5);
}

// The free surface of each column: the highest fluid particle of it and its neighbours + dx/2,
// i.e. the top of a flat block.
TEST(Turbulence, ColumnSurfaceOfFlatBlock) {
  test::Setup<2> s(kLattice);
  const auto zs = Turbulence<2>::column_surface(s.S, 0.02);
  for (std::size_t i = 0; i < s.S.particles.n_owned(); ++i) EXPECT_NEAR(zs[i], 0.3, 1e-12);
}

// Rough-bed shape function W_d (Kazemi eq 3.17, §3.1.4.2): the layer average of the point form over
// [crest - d_s/2, crest] is π/4 (the thesis's mean C_d W_d = 0.785 for R_d = 0.5 d_s); the fragment
// form tends to the point form as l0 -> 0, lies in [0, 1], and is 0 above the crest.
TEST(RoughBed, ShapeFunction) {
  const double ds = 0.024, crest = 0.0106, centre = crest - 0.5 * ds;
  const int n = 20000;
  double avg = 0.0;
  for (int i = 0; i < n; ++i) avg += rough_bed_shape(centre + (i + 0.5) / n * 0.5 * ds, centre, ds, 0.0);
  EXPECT_NEAR(avg / n, std::numbers::pi / 4.0, 0.005 * std::numbers::pi / 4.0);
  for (double z : {centre, centre + 0.004, centre + 0.011, crest + 0.001}) {
    const double p = rough_bed_shape(z, centre, ds, 0.0), f = rough_bed_shape(z, centre, ds, 1e-5);
    EXPECT_NEAR(f, p, 1e-4);
    const double coarse = rough_bed_shape(z, centre, ds, 0.002);
    EXPECT_GE(coarse, 0.0);
    EXPECT_LE(coarse, 1.0);
  }
  EXPECT_EQ(rough_bed_shape(crest + 0.002, centre, ds, 0.002), 0.0);
  // exactly at the crest, round-off in y/r must not give NaN
  EXPECT_TRUE(std::isfinite(rough_bed_shape(crest, centre, ds, 0.0025)));
}

// The drag term: a = -C_d W_d / (2 d_s) u|u| inside the layer, nothing above the crest.
TEST(RoughBed, DragAcceleration) {
  const std::string yaml = std::string(kLattice) +
      "forces:\n  - {type: rough_bed, cd: 1.0, diameter: 0.024, bed: 0.0, thickness: 0.012, shape: point}\n";
  test::Setup<2> s(yaml, {"turbulence.model=none"});
  auto& P = s.S.particles;
  for (std::size_t i = 0; i < P.n_owned(); ++i) { P.vel[i] = Vec<2>{{0.3, 0.0}}; P.acc[i] = Vec<2>{}; }
  s.S.forces[0]->add(s.S);
  for (std::size_t i = 0; i < P.n_owned(); ++i) {
    const double z = P.pos[i][1];
    const double wd = z < 0.012 ? std::sqrt(1.0 - std::pow(z / 0.012, 2)) : 0.0;  // centre at the bed
    EXPECT_NEAR(P.acc[i][0], -1.0 * wd / (2 * 0.024) * 0.09, 1e-12);
  }
}

// Monaghan–Kos repulsive walls (Federico §5.2.1c): no force on fluid at rest one spacing from the
// first wall layer; a particle dx/2 from it feels A5 (1 − q)/sqrt(q) with q = 1/2, whether it
// faces one wall particle (P = 1) or sits between two (P = 1/2 each); the approach speed adds
// β2 c0 v to A5; a particle leaving fast is not pulled back.
TEST(RepulsiveWalls, MonaghanKosForce) {
  const char* yaml = R"(
dimension: 2
gravity: [0.0, 0.0]
particles: {dx: 0.01, kernel: wendland_c2, h_over_dx: 2.0}
fluid: {density: 1000.0, viscosity: 0.0, sound_speed: 10.0, hydrostatic_init: false}
walls: {type: repulsive, repulsion: {beta1: 0.01, beta2: 1.0}}
geometry:
  - {type: plane, point: [0.0, 0.0], normal: [0.0, 1.0], min: [-0.05, -0.05], max: [0.35, 0.0]}
  - {type: box, fill: fluid, min: [0.0, 0.0], max: [0.3, 0.1]}
time: {end: 1.0}
)";
  test::Setup<2> s(yaml);
  auto& P = s.S.particles;
  EXPECT_FALSE(s.S.walls->in_pair_sums());
  // particle indices change with every neighbour update (cell sort): find particles by id
  auto index_of = [&](std::uint32_t id) {
    for (std::size_t i = 0; i < P.n_owned(); ++i)
      if (P.id[i] == id) return i;
    ADD_FAILURE() << "particle " << id << " not found";
    return std::size_t(0);
  };
  auto force_on = [&](std::uint32_t id) {
    s.S.update_neighbours();
    for (auto& x : P.acc) x = Vec<2>{};
    s.S.walls->add_forces(s.S);
    return P.acc[index_of(id)];
  };
  // at rest: the first fluid row is dx above the first wall layer (wall line in between)
  s.S.update_neighbours();
  for (auto& x : P.acc) x = Vec<2>{};
  s.S.walls->add_forces(s.S);
  for (std::size_t i = 0; i < P.n_owned(); ++i) EXPECT_EQ(P.acc[i][1], 0.0);
  // take a bottom-row particle at x = 0.155 down onto the wall line (q = 1/2)
  std::uint32_t id = 0;
  for (std::size_t i = 0; i < P.n_owned(); ++i)
    if (P.kind[i] == Kind::Fluid && std::abs(P.pos[i][0] - 0.155) < 1e-9 && std::abs(P.pos[i][1] - 0.005) < 1e-9) id = P.id[i];
  P.pos[index_of(id)][1] = 0.0;
  const double c0 = 10.0, h = 0.02, expected = 0.01 * c0 * c0 / h * 0.5 / std::sqrt(0.5);
  Vec<2> f = force_on(id);
  EXPECT_NEAR(f[1], expected, 1e-12 * expected);
  EXPECT_NEAR(f[0], 0.0, 1e-12 * expected);
  P.pos[index_of(id)][0] += 0.005;  // between two wall particles: P = 1/2 + 1/2
  f = force_on(id);
  EXPECT_NEAR(f[1], expected, 1e-9 * expected);
  P.vel[index_of(id)] = Vec<2>{{0.0, -0.2}};  // approaching at 0.2 m/s
  f = force_on(id);
  EXPECT_NEAR(f[1], (0.01 * c0 * c0 + 1.0 * c0 * 0.2) / h * 0.5 / std::sqrt(0.5), 1e-9 * expected);
  P.vel[index_of(id)] = Vec<2>{{0.0, 0.5}};  // leaving faster than beta1 c0 / beta2: no attraction
  f = force_on(id);
  EXPECT_EQ(f[1], 0.0);
}

// Resolution levels (docs/numerics.md §14): the SPS filter width is each particle's level spacing dx/2^l, the pair
// terms take h_ab. A lattice refined everywhere (level 1) under the linear shear of SmagorinskyEddyViscosity...
// gives the uniform lattice at dx/2: ν_t and τ equal to the float pair sums' round-off.
TEST(Turbulence, OnOneLevelEverywhereItIsTheUniformFineModel) {
  const std::string refined = std::string(kLattice) + "resolution: {regions: [{shape: box, min: [-1.0, -1.0], max: [1.0, 1.0], level: 1}]}\n";
  test::Setup<2> lev(refined, kSmagorinsky);
  auto fine_overrides = kSmagorinsky;
  fine_overrides.push_back("particles.dx=0.005");
  test::Setup<2> uni(kLattice, fine_overrides);
  ASSERT_EQ(lev.S.levels, 1);
  ASSERT_EQ(lev.S.particles.n_owned(), uni.S.particles.n_owned());
  const double gamma = 4.0;
  std::map<std::pair<long, long>, std::pair<double, double>> at;  // the uniform run's (ν_t, τ_xz) by site
  auto site = [](const Vec<2>& x) { return std::make_pair(std::lround(x[0] / 0.0025), std::lround(x[1] / 0.0025)); };
  double numax = 0.0;
  int compared = 0;
  for (auto* s : {&uni, &lev}) {
    auto& P = s->S.particles;
    for (std::size_t i = 0; i < P.n_owned(); ++i) P.vel[i] = Vec<2>{{gamma * P.pos[i][1], 0.0}};
    s->S.update_neighbours();
    s->scheme->rates(s->S);
    const auto& nut = P.scalar(field::nu_t);
    const auto& txz = P.scalar("tau_xz");
    for (std::size_t i = 0; i < P.n_owned(); ++i) {
      if (!interior(P.pos[i])) continue;
      if (s == &uni) {
        at[site(P.pos[i])] = {nut[i], txz[i]};
        numax = std::max(numax, nut[i]);
        continue;
      }
      ASSERT_TRUE(at.count(site(P.pos[i])));
      const auto [nu_u, t_u] = at[site(P.pos[i])];
      EXPECT_NEAR(nut[i], nu_u, 1e-5 * nu_u);
      EXPECT_NEAR(txz[i], t_u, 1e-5 * std::abs(t_u));
      ++compared;
    }
  }
  // (C_s dx/2)² γ m with m ≈ 1: the fine spacing's filter width, a quarter of the level-0 one's ν_t
  EXPECT_NEAR(numax, std::pow(0.15 * 0.005, 2) * gamma, 0.03 * std::pow(0.15 * 0.005, 2) * gamma);
  EXPECT_GT(compared, 300);  // (the interior square at the fine spacing: 20 x 20)
}

// A sheared block whose middle is refined, Smagorinsky's stresses on: the stress divergence pairs
// Σ m_b (τ_a/ρ_a² + τ_b/ρ_b²)·∇W_ab with h_ab are antisymmetric, so Σ m a = 0 to the float sums' round-off
// although the stresses move the particles (their part of Σ m |a| is not small).
TEST(Turbulence, StressesConserveMomentumAcrossLevels) {
  const std::string yaml = test::refined_block_2d("0.0");
  auto run = [&](bool turbulent) {
    auto s = std::make_unique<test::Setup<2>>(yaml, turbulent ? std::vector<std::string>{"turbulence.model=smagorinsky", "turbulence.cs=0.5"}
                                                             : std::vector<std::string>{});
    auto& P = s->S.particles;
    for (std::size_t i = 0; i < P.n_owned(); ++i) P.vel[i] = Vec<2>{{std::sin(17.0 * P.pos[i][1]), 0.5 * std::cos(11.0 * P.pos[i][0])}};
    s->S.update_neighbours();
    s->scheme->rates(s->S);  // the velocity gradient, then the stresses
    s->scheme->rates(s->S);  // the stresses' divergence
    return s;
  };
  const auto with = run(true), without = run(false);
  ASSERT_EQ(with->S.levels, 1);
  const auto& P = with->S.particles;
  const auto& Q = without->S.particles;
  ASSERT_EQ(P.n_owned(), Q.n_owned());
  double stress = 0.0;
  for (std::size_t i = 0; i < P.n_owned(); ++i) {
    ASSERT_EQ(P.id[i], Q.id[i]);
    stress += P.mass[i] * norm(P.acc[i] - Q.acc[i]);
  }
  const auto [sum, scale] = test::momentum_balance(P);
  ASSERT_GT(scale, 0.0);
  EXPECT_GT(stress, 0.1 * scale);  // the stresses are a large part of the rates
  EXPECT_LT(sum, 1e-5 * scale);    // the float pair sums' round-off
}
