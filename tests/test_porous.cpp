// Porous media (SPHAM, Kazemi ch. 4-6; Tsurudome ch. 4): drag closures against hand values of
// Kazemi eq 4.29 and Tsurudome eq 4.1.2, the porosity fields (smoothed layer one grain thick,
// porous-particle sums and their two normalisations, prescribed profiles), the fill spacing
// dx/phi^(1/D) (Kazemi eq 5.1), the exact reduction to plain WCSPH at phi = 1, and the
// point-implicit drag (docs/porous-closures.md; Tsurudome §4.1.1 leaves R's integration open).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "sphflume/core/shapes.hpp"
#include "sphflume/io/gauges.hpp"
#include "sphflume/physics/porous.hpp"
#include "test_helpers.hpp"

using namespace sph;

namespace {

PorousClosureConfig closure(const std::string& type, double c1 = 150.0, double c2 = 1.75) {
  PorousClosureConfig c;
  c.type = type;
  c.c1 = c1;
  c.c2 = c2;
  return c;
}

PorousConfig box_region(const std::string& field, double phi0, double d, std::vector<double> lo, std::vector<double> hi) {
  PorousConfig c;
  c.field = field;
  PorousRegionConfig r;
  r.shape = "box";
  r.min = std::move(lo);
  r.max = std::move(hi);
  r.porosity = phi0;
  r.diameter = d;
  c.regions.push_back(r);
  return c;
}

}  // namespace

// Kazemi eq 4.29, φ = 0.49, d_s = 15.9 mm, u = 0.1 m/s, ν = 1e-6 (by hand):
// a = 150 (0.51/0.49)² 1e-6 / 0.0159² = 0.64276 1/s, b|u| = 1.75 (0.51/0.49) 0.1 / 0.0159 = 11.4555 1/s.
TEST(PorousClosure, ErgunAgainstHandCalculation) {
  const auto [K, M] = PorousMedia<2>::closure(closure("ergun"), 0.49, 0.1, 1e-6, 0.0159);
  EXPECT_NEAR(K, 0.64276 + 11.4555, 1e-4 * K);
  EXPECT_EQ(M, 1.0);
  // no drag in clear water
  EXPECT_EQ(PorousMedia<2>::closure(closure("ergun"), 1.0, 0.1, 1e-6, 0.0159).first, 0.0);
}

// Tsurudome eq 4.1.2 in the ν/Kp form for φ = 0.49: A = ν/Kp, B = 1.75/(√150 √Kp φ^1.5) in 1/m,
// by hand to 3-4 digits.
TEST(PorousClosure, TsurudomeFormAgainstHandCalculation) {
  struct Row { double d, A, B; };
  for (const Row r : {Row{0.25e-3, 5306.0, 30344.0}, Row{15.9e-3, 1.31, 477.1}, Row{50e-3, 0.13, 151.7}}) {
    const double A = PorousMedia<2>::closure(closure("tsurudome"), 0.49, 0.0, 1e-6, r.d).first;
    const double B = PorousMedia<2>::closure(closure("tsurudome"), 0.49, 1.0, 1e-6, r.d).first - A;
    EXPECT_NEAR(A, r.A, 0.005 * r.A + 0.005) << "d = " << r.d;
    EXPECT_NEAR(B, r.B, 0.001 * r.B) << "d = " << r.d;
  }
}

// Kazemi eq 6.3: the roughness-layer drag is the Ergun form with c1 = 0 and c2 = C_d φ.
TEST(PorousClosure, RoughnessLayerIsTheUnifiedErgunForm) {
  PorousClosureConfig rough;
  rough.type = "roughness";
  rough.cd = 0.9;
  for (double phi : {0.22, 0.5, 0.9}) {
    const double Kr = PorousMedia<2>::closure(rough, phi, 0.3, 1e-6, 0.0136).first;
    const double Ke = PorousMedia<2>::closure(closure("ergun", 0.0, 0.9 * phi), phi, 0.3, 1e-6, 0.0136).first;
    EXPECT_NEAR(Kr, Ke, 1e-12 * Ke);
  }
}

// van Gent / olaFlow: the KC factor multiplies the quadratic term, the added mass is 1 + γ(1-φ)/φ.
TEST(PorousClosure, VanGentKcTermAndAddedMass) {
  PorousClosureConfig vg = closure("van_gent", 1000.0, 1.1);
  vg.added_mass = 0.34;
  const auto [K0, M] = PorousMedia<2>::closure(vg, 0.49, 0.2, 1e-6, 0.0159);
  vg.kc = 7.5;  // doubles the quadratic part
  const double K1 = PorousMedia<2>::closure(vg, 0.49, 0.2, 1e-6, 0.0159).first;
  const double lin = PorousMedia<2>::closure(vg, 0.49, 0.0, 1e-6, 0.0159).first;
  EXPECT_NEAR(K1 - lin, 2.0 * (K0 - lin), 1e-12 * K1);
  EXPECT_NEAR(M, 1.0 + 0.34 * 0.51 / 0.49, 1e-14);
}

// Kazemi's Situation #1: the porosity goes from φ0 to 1 over a layer one grain diameter thick
// centred on the region's outline: exactly φ0 deeper than d/2 inside, exactly 1 beyond d/2
// outside, monotone in between, and (1 + φ0)/2 on the outline of a flat face (symmetric kernel;
// the mesh's lattice error is below 1 %).
TEST(PorousField, SmoothedLayerIsOneGrainDiameterThick) {
  const double d = 0.02, phi0 = 0.49;
  const PorousMedia<2> pm(box_region("smoothed", phi0, d, {0.0, 0.0}, {1.0, 0.5}), KernelType::WendlandC2, 0.0075, 0.005);
  const double x = 0.4321;  // off the mesh lines
  EXPECT_EQ(pm.porosity(Vec<2>{{x, 0.5 - 0.5 * d - 1e-9}}), phi0);
  EXPECT_EQ(pm.porosity(Vec<2>{{x, 0.5 + 0.5 * d + 1e-9}}), 1.0);
  double prev = 0.0;
  for (int k = 0; k <= 100; ++k) {
    const double z = 0.5 - 0.6 * d + 1.2 * d * k / 100.0;
    const double phi = pm.porosity(Vec<2>{{x, z}});
    EXPECT_GE(phi, prev - 1e-12) << "z = " << z;
    EXPECT_GE(phi, phi0);
    EXPECT_LE(phi, 1.0);
    prev = phi;
  }
  EXPECT_NEAR(pm.porosity(Vec<2>{{x, 0.5}}), 0.5 * (1.0 + phi0), 0.01 * 0.5 * (1.0 + phi0));
  int region = 7;
  (void)pm.porosity(Vec<2>{{x, 2.0}}, &region);
  EXPECT_EQ(region, -1);
  (void)pm.porosity(Vec<2>{{x, 0.25}}, &region);
  EXPECT_EQ(region, 0);
}

// The smoothed field's mesh fits the box: the half level (1 + φ0)/2 lies on every face, and a
// block is mirror-symmetric. The still-water block of cases/porous_still_water.yaml (0.2 m wide,
// 0.15 m tall: 60.4 and 45.3 nominal mesh cells) had its right face 1.25 mm and its top face
// 0.9 mm inside the box when the mesh started at the lower-left corner; the mismatch with the
// particles' fill set the pool in motion (max |u| 0.016 m/s against 1.1e-3 with a fitting mesh).
TEST(PorousField, SmoothedHalfLevelOnEveryFaceOfABox) {
  const double d = 0.0159, phi0 = 0.49, half = 0.5 * (1.0 + phi0);
  const PorousMedia<2> pm(box_region("smoothed", phi0, d, {0.15, -0.05}, {0.35, 0.1}), KernelType::WendlandC2, 0.01, 0.005);
  const double z = 0.0431;  // off the mesh lines
  EXPECT_NEAR(pm.porosity(Vec<2>{{0.15, z}}), half, 1e-12);
  EXPECT_NEAR(pm.porosity(Vec<2>{{0.35, z}}), half, 1e-12);
  EXPECT_NEAR(pm.porosity(Vec<2>{{0.2537, 0.1}}), half, 1e-12);
  for (double e : {0.001, 0.003, 0.006}) {  // mirror symmetry across the block's centre line
    EXPECT_NEAR(pm.porosity(Vec<2>{{0.15 + e, z}}), pm.porosity(Vec<2>{{0.35 - e, z}}), 1e-12) << e;
    EXPECT_NEAR(pm.porosity(Vec<2>{{0.15 - e, z}}), pm.porosity(Vec<2>{{0.35 + e, z}}), 1e-12) << e;
  }
}

// Tsurudome eq 4.2.1 from porous particles on the lattice dx/sqrt(φ0): with the full-block
// normalisation φ = φ0 inside; as printed (ρ_p/ρ_w) φ = 1 - (1 - φ0) φ0 = 0.75 inside (the
// inconsistency of docs/numerics.md, Errata), to the lattice-sum accuracy of the kernel (2 %).
TEST(PorousField, PorousParticleSumAndItsTwoNormalisations) {
  const double phi0 = 0.49, dx = 0.005, h = 1.5 * dx;
  PorousConfig c = box_region("particles", phi0, 0.0159, {0.0, 0.0}, {0.3, 0.3});
  const PorousMedia<2> full(c, KernelType::WendlandC2, h, dx);
  c.literal_normalisation = true;
  const PorousMedia<2> literal(c, KernelType::WendlandC2, h, dx);
  const Vec<2> inside{{0.1512, 0.1498}};
  EXPECT_NEAR(full.porosity(inside), phi0, 1e-12);
  EXPECT_NEAR(literal.porosity(inside), 1.0 - (1.0 - phi0) * phi0, 0.02 * 0.75);
  // on the face the kernel is half covered: between φ0 and 1
  const double face = full.porosity(Vec<2>{{0.3, 0.1498}});
  EXPECT_GT(face, phi0 + 0.1);
  EXPECT_LT(face, 1.0 - 0.1);
  EXPECT_EQ(full.porosity(Vec<2>{{0.3 + 2.0 * h + 1e-6, 0.15}}), 1.0);
}

// Tsurudome eq 4.2.1 on a permeable 1:20 beach (a polygon: each porous particle's inside test made once per lattice
// node, and the stencils wholly inside or outside answered from the nodes' counts): at points above, across and
// under the face the field is its definition, Σ_{nodes inside} W / Σ_{nodes} W over the lattice dx/sqrt(φ0) from
// the polygon's corner, summed here node by node (round-off: the same terms in the same order).
TEST(PorousField, PorousParticleSumOfASlopeIsItsDefinition) {
  const double phi0 = 0.49, dx = 0.01, h = 2.0 * dx;
  PorousConfig c;
  c.field = "particles";
  PorousRegionConfig r;
  r.shape = "polygon";
  r.vertices = {{2.0, 0.0}, {10.0, 0.0}, {10.0, 0.4}};  // the 1:20 wedge of cases/runup_permeable_b.yaml
  r.porosity = phi0;
  r.diameter = 0.001;
  c.regions.push_back(r);
  const PorousMedia<2> pm(c, KernelType::WendlandC2, h, dx);
  const double step = dx / std::sqrt(phi0), reach = kernel_support_factor(KernelType::WendlandC2) * h;
  const double ox = 2.0 + 0.5 * step, oz = 0.5 * step;
  const auto defined = [&](double x, double z) {
    return with_kernel<2>(KernelType::WendlandC2, h, [&](const auto& K) {
      double in = 0.0, all = 0.0;
      for (int i = int(std::ceil((x - reach - ox) / step)); i <= int(std::floor((x + reach - ox) / step)); ++i)
        for (int j = int(std::ceil((z - reach - oz) / step)); j <= int(std::floor((z + reach - oz) / step)); ++j) {
          const double cx = ox + i * step, cz = oz + j * step, r2 = (x - cx) * (x - cx) + (z - cz) * (z - cz);
          if (r2 >= reach * reach) continue;
          const double w = K.W(std::sqrt(r2));
          all += w;
          if (inside_polygon(r.vertices, cx, cz)) in += w;
        }
      return 1.0 - (1.0 - phi0) * (all > 0.0 ? in / all : 0.0);
    });
  };
  int inside = 0, outside = 0, across = 0;
  for (double x = 1.93; x < 10.05; x += 0.0937)
    for (double dz = -0.07; dz <= 0.07; dz += 0.00731) {  // normal to the face within and beyond one reach
      const double z = (x - 2.0) / 20.0 + dz;
      const double phi = pm.porosity(Vec<2>{{x, z}}), ref = std::clamp(defined(x, z), phi0, 1.0);
      EXPECT_NEAR(phi, ref, 1e-14) << x << ", " << z;
      (phi == 1.0 ? outside : phi < phi0 + 1e-12 ? inside : across) += 1;
    }
  EXPECT_GT(inside, 100);  // (every kind of stencil met)
  EXPECT_GT(outside, 100);
  EXPECT_GT(across, 100);
}

// Kazemi's Situation #2: φ(z) and φ(x, z) tables, linear in between, constant beyond.
TEST(PorousField, PrescribedProfiles) {
  PorousConfig c;
  PorousRegionConfig r;
  r.shape = "profile";
  r.z = {0.0, 0.1};
  r.phi = {{0.22, 1.0}};
  r.diameter = 0.0136;
  r.porosity = 0.22;
  c.regions.push_back(r);
  const PorousMedia<2> pz(c, KernelType::WendlandC2, 0.0075, 0.005);
  EXPECT_NEAR(pz.porosity(Vec<2>{{3.0, -0.5}}), 0.22, 1e-15);
  EXPECT_NEAR(pz.porosity(Vec<2>{{3.0, 0.025}}), 0.22 + 0.25 * 0.78, 1e-14);
  EXPECT_NEAR(pz.porosity(Vec<2>{{3.0, 0.2}}), 1.0, 1e-15);
  c.regions[0].x = {0.0, 1.0};
  c.regions[0].phi = {{0.75, 0.75}, {0.22, 1.0}};
  const PorousMedia<2> pxz(c, KernelType::WendlandC2, 0.0075, 0.005);
  EXPECT_NEAR(pxz.porosity(Vec<2>{{0.5, 0.0}}), 0.5 * (0.75 + 0.22), 1e-14);
  EXPECT_NEAR(pxz.porosity(Vec<2>{{0.5, 0.1}}), 0.5 * (0.75 + 1.0), 1e-14);
  EXPECT_NEAR(pxz.porosity(Vec<2>{{-1.0, 0.05}}), 0.75, 1e-14);
}

namespace {
// a pool with a porous block on the floor, dx = 0.005
const char* kPool = R"(
dimension: 2
gravity: [0.0, -9.81]
particles: {dx: 0.005, kernel: wendland_c2, h_over_dx: 1.5}
fluid: {density: 1000.0, viscosity: 1.0e-6, sound_speed: 20.0}
scheme: {integrator: symplectic, density_diffusion: fourtakas, viscosity: laminar}
turbulence: {model: none, cs: 0.15}
walls: {type: dummy, slip: no_slip}
porous:
  field: smoothed
  regions:
    - {shape: box, min: [0.1, -0.05], max: [0.2, 0.1], porosity: 0.49, diameter: 0.0159}
geometry:
  - {type: tank, fill: wall, min: [0.0, 0.0], max: [0.3, 0.2]}
  - {type: box, fill: fluid, min: [0.0, 0.0], max: [0.3, 0.15]}
time: {end: 1.0}
)";
}  // namespace

// Kazemi eq 5.1: every particle has the mass ρ0 dx²; inside the block the lattice is dx/sqrt(φ0)
// (here 7.14 mm, 14 x 14 points in the 0.1 m block), so the water volume Σ m/(φρ) is the pool's.
TEST(Porous, FillSpacingKeepsTheWaterVolume) {
  test::Setup<2> s(kPool);
  const auto& P = s.S.particles;
  const auto& phi = s.S.particles.require(field::porosity);
  std::size_t in_block = 0;
  double vol = 0.0;
  for (std::size_t i = 0; i < P.n_owned(); ++i) {
    if (P.kind[i] != Kind::Fluid) continue;
    EXPECT_DOUBLE_EQ(P.mass[i], 1000.0 * 0.005 * 0.005);
    const auto& x = P.pos[i];
    in_block += x[0] > 0.1 && x[0] < 0.2 && x[1] < 0.1;
    vol += P.mass[i] / (phi[i] * 1000.0);  // volume at rho0 (the density is hydrostatic)
  }
  EXPECT_EQ(in_block, 14u * 14u);
  // the smoothed porosity of the band particles is not the lattice's: within 2 % of 0.3 x 0.15
  EXPECT_NEAR(vol, 0.3 * 0.15, 0.02 * 0.045);
}

// A solid wall box (a gate) standing in a porous zone: the zone's lattice (spacing dx/sqrt(φ)) leaves points
// inside the box that are dx/2 or more from its wall particles (here (0.1107, 0.0107): 2.53 mm from the wall
// particle at (0.1125, 0.0125)); the set-up drops every fluid point inside the body, not only those near its
// particles (a fluid particle enclosed by walls reads 1.3 ρ0 in a summation density).
TEST(Porous, FluidInsideASolidWallBoxIsDropped) {
  std::string yaml = kPool;
  yaml.replace(yaml.find("time:"), 0, "  - {type: box, fill: wall, min: [0.095, 0.0], max: [0.115, 0.12]}\n");
  test::Setup<2> s(yaml);
  const auto& P = s.S.particles;
  std::size_t inside = 0, walls_inside = 0;
  for (std::size_t i = 0; i < P.n_owned(); ++i) {
    const auto& x = P.pos[i];
    const bool in = x[0] > 0.095 && x[0] < 0.115 && x[1] > 0.0 && x[1] < 0.12;
    inside += in && P.kind[i] == Kind::Fluid;
    walls_inside += in && P.kind[i] == Kind::Wall;
  }
  EXPECT_EQ(inside, 0u);
  EXPECT_EQ(walls_inside, 4u * 24u);  // the box itself: 4 x 24 wall particles at dx = 5 mm
}

// With φ = 1 the SPHAM terms are the plain ones: one rates pass on the same state (a sheared,
// compressed pool, laminar and artificial viscosity, with turbulence) gives the same
// accelerations and density rates with a porosity-1 region as without porous media.
TEST(Porous, UnitPorosityReducesToPlainWcsph) {
  for (const char* visc : {"laminar", "artificial"}) {
    for (const char* turb : {"none", "smagorinsky"}) {
      const std::vector<std::string> common = {std::string("scheme.viscosity=") + visc,
                                               std::string("turbulence.model=") + turb};
      auto with = common;
      with.push_back("porous.regions.0.porosity=1.0");
      test::Setup<2> plain(kPool, with), por(kPool, with);
      plain.S.porous.reset();  // the same particles, without porous media
      for (auto* s : {&plain, &por}) {
        auto& P = s->S.particles;
        for (std::size_t i = 0; i < P.n_owned(); ++i) {
          if (P.kind[i] != Kind::Fluid) continue;
          const auto& x = P.pos[i];
          P.vel[i] = Vec<2>{{0.3 * std::sin(20.0 * x[1]), 0.1 * std::cos(17.0 * x[0])}};
          P.rho[i] *= 1.0 + 0.001 * std::sin(31.0 * x[0] + 7.0 * x[1]);
        }
        s->scheme->initialise(s->S);  // pressure, neighbours, one rates pass (twice for the stress)
        s->scheme->rates(s->S);
      }
      const auto& A = plain.S.particles;
      const auto& B = por.S.particles;
      ASSERT_EQ(A.n_owned(), B.n_owned());
      double amax = 0.0, dmax = 0.0, ea = 0.0, ed = 0.0;
      for (std::size_t i = 0; i < A.n_owned(); ++i) {
        ASSERT_EQ(A.id[i], B.id[i]);
        amax = std::max(amax, norm(A.acc[i]));
        dmax = std::max(dmax, std::abs(A.drho[i]));
        ea = std::max(ea, norm(A.acc[i] - B.acc[i]));
        ed = std::max(ed, std::abs(A.drho[i] - B.drho[i]));
      }
      // the same single-precision terms; without porous media the plain pass visits each pair once (pair_sweep:
      // half), so its sums come in another order: equal to the float round-off of ~30-term sums whose terms are several
      // times the result (1e-5; a wrong term is of the order of the rates)
      EXPECT_LE(ea, 1e-5 * amax) << visc << ", " << turb;
      EXPECT_LE(ed, 1e-5 * dmax) << visc << ", " << turb;
    }
  }
}

namespace {
// a fully porous, doubly periodic block driven by a body force (uniform: no pressure gradient)
const char* kPeriodicPorous = R"(
dimension: 2
gravity: [2.0, 0.0]
particles: {dx: 0.01, kernel: wendland_c2, h_over_dx: 1.5}
fluid: {density: 1000.0, viscosity: 1.0e-6, sound_speed: 10.0, hydrostatic_init: false}
scheme: {density_diffusion: none, viscosity: laminar}
domain: {min: [0.0, 0.0], max: [0.2, 0.2], periodic: [x, z]}
porous:
  field: sharp
  regions:
    - {shape: box, min: [-1.0, -1.0], max: [1.0, 1.0], porosity: 0.4, diameter: 0.00008}
geometry:
  - {type: box, fill: fluid, min: [0.0, 0.0], max: [0.2, 0.2]}
time: {end: 1.0}
)";
}  // namespace

// Fine grains (d = 0.08 mm, silt) make the drag stiff: a dt ≈ 16 at the fluid's time step. The
// point-implicit update stays stable with every integrator and lands on the Ergun balance
// g = a u + b u² (here the Darcy part dominates) to round-off.
TEST(Porous, PointImplicitDragReachesTheErgunBalance) {
  for (const char* integ : {"symplectic", "predictor_corrector", "verlet"}) {
    test::Setup<2> s(kPeriodicPorous, {std::string("scheme.integrator=") + integ});
    s.scheme->initialise(s.S);
    const double dt = s.scheme->time_step(s.S);
    const auto [K1, M] = PorousMedia<2>::closure(s.c.porous.regions[0].closure, 0.4, 1.0, 1e-6, 0.00008);
    const double a = PorousMedia<2>::closure(s.c.porous.regions[0].closure, 0.4, 0.0, 1e-6, 0.00008).first;
    const double b = K1 - a;
    EXPECT_GT(a * dt, 10.0);  // explicit Euler would blow up
    for (int k = 0; k < 200; ++k) s.scheme->step(s.S, dt);
    const double u = (-a + std::sqrt(a * a + 4.0 * b * 2.0)) / (2.0 * b);
    const auto& P = s.S.particles;
    for (std::size_t i = 0; i < P.n_owned(); ++i) {
      ASSERT_NEAR(P.vel[i][0], u, 1e-9 * u) << integ;
      ASSERT_NEAR(P.vel[i][1], 0.0, 1e-9 * u) << integ;
    }
  }
}

// Kazemi's outlet imaginary wall (eqs 6.10-6.12): hydrostatic particles beyond X_o push the fluid
// within one kernel support upstream of X_o back upstream, weighted by F_o = (X_o - x)/support
// (0 at X_o), and nothing farther upstream.
TEST(ImaginaryWall, PushesUpstreamWithinOneSupportOnly) {
  const char* yaml = test::kImaginaryWall2D;
  test::Setup<2> s(yaml);
  s.scheme->initialise(s.S);  // pressures, neighbours
  auto& P = s.S.particles;
  for (auto& a : P.acc) a = Vec<2>{};
  ASSERT_EQ(s.S.forces.size(), 1u);
  s.S.forces[0]->add(s.S);
  const double support = s.S.support;
  int pushed = 0;
  for (std::size_t i = 0; i < P.n_owned(); ++i) {
    const double gap = 0.3 - P.pos[i][0];
    if (gap >= support) {
      EXPECT_EQ(P.acc[i][0], 0.0);
      EXPECT_EQ(P.acc[i][1], 0.0);
    } else {
      EXPECT_LT(P.acc[i][0], 0.0) << "x = " << P.pos[i][0];
      ++pushed;
    }
  }
  EXPECT_EQ(pushed, 10 * static_cast<int>(std::ceil(support / 0.01 - 0.5)));  // the columns within a support
  // relaxed (Kazemi): the push grows with the distance from X_o inside the support, per unit of
  // the kernel sum; unrelaxed: the last column (nearest the wall) is pushed hardest
  auto last_column_push = [&](bool relax) {
    test::Setup<2> t(yaml, {std::string("forces.0.relax=") + (relax ? "true" : "false")});
    t.scheme->initialise(t.S);
    auto& Q = t.S.particles;
    for (auto& a : Q.acc) a = Vec<2>{};
    t.S.forces[0]->add(t.S);
    double last = 0.0, mid = 0.0;
    for (std::size_t i = 0; i < Q.n_owned(); ++i) {
      if (std::abs(Q.pos[i][1] - 0.055) > 1e-9) continue;
      if (std::abs(Q.pos[i][0] - 0.295) < 1e-9) last = -Q.acc[i][0];
      if (std::abs(Q.pos[i][0] - 0.285) < 1e-9) mid = -Q.acc[i][0];
    }
    return std::make_pair(last, mid);
  };
  const auto [rl, rm] = last_column_push(true);
  const auto [ul, um] = last_column_push(false);
  EXPECT_GT(ul, rl * 2.0);  // F_o = 1 against (X_o - x)/support = 1/6 at the last column
  EXPECT_GT(ul, um);
  EXPECT_GT(um, rm);
}

// The flux gauge carries the superficial velocity φu in porous media: a uniform intrinsic
// velocity u through a fully porous periodic block (φ = 0.64: the lattice dx/0.8 tiles the 0.2 m
// period) gives φ u × 0.2 m²/s through a vertical line, and the water_volume gauge splits the
// water (Σ m/ρ) from the space it fills (Σ m/(φρ)).
TEST(Porous, FluxAndVolumeGaugesUseThePorosity) {
  test::Setup<2> s(kPeriodicPorous, {"porous.regions.0.porosity=0.64"});
  s.scheme->initialise(s.S);
  auto& P = s.S.particles;
  for (std::size_t i = 0; i < P.n_owned(); ++i) P.vel[i] = Vec<2>{{0.3, 0.0}};
  s.S.update_neighbours();
  GaugeConfig flux;
  flux.type = "flux";
  flux.start = {0.1, 0.0};
  flux.end = {0.1, 0.2};
  flux.points = 41;
  const double q = GaugeSet<2>::evaluate(flux, s.S, 1.0)[0];
  // the line spans the periodic height; the fluid fraction is 1 everywhere on it
  EXPECT_NEAR(q, 0.64 * 0.3 * 0.2, 0.01 * 0.64 * 0.3 * 0.2);
  GaugeConfig vol;
  vol.type = "water_volume";
  const auto v = GaugeSet<2>::evaluate(vol, s.S, 1.0);
  double water = 0.0;
  for (std::size_t i = 0; i < P.n_owned(); ++i) water += P.mass[i] / P.rho[i];
  EXPECT_NEAR(v[0], water, 1e-12 * water);
  EXPECT_NEAR(v[1], water / 0.64, 1e-12 * water);
  EXPECT_NEAR(v[1], 0.2 * 0.2, 0.01 * 0.04);  // the block's area: particles on the lattice dx/0.8
}

// porous.relax (relax_porous_band): the interface band's points settle where the volumes
// m/(φρ0) tile space. Facts: the band residual max h|Σ V_b ∇W| falls at least tenfold, no point
// moves more than dx/4, points away from the block keep their lattice sites, and the still pool
// starts nearer its discrete equilibrium: the largest initial acceleration in and around the
// block (the spurious 2 p_a Σ V_b ∇W of the conservative pressure gradient) at least halves.
TEST(Porous, RelaxedBandStartsNearerEquilibrium) {
  const std::vector<std::string> base = {"particles.h_over_dx=2.0", "scheme.viscosity=artificial"};
  auto relaxed = base;
  relaxed.push_back("porous.relax=300");
  test::Setup<2> plain(kPool, base), relax(kPool, relaxed);
  EXPECT_EQ(plain.rep.porous_relax_band, 0u);
  ASSERT_GT(relax.rep.porous_relax_band, 50u);
  EXPECT_LT(relax.rep.porous_relax_residual, 0.1 * relax.rep.porous_relax_residual0);
  EXPECT_LE(relax.rep.porous_relax_shift, 0.25 * 0.005 + 1e-12);
  double amax[2] = {0.0, 0.0};
  int k = 0;
  for (auto* s : {&plain, &relax}) {
    s->scheme->initialise(s->S);
    const auto& P = s->S.particles;
    for (std::size_t i = 0; i < P.n_owned(); ++i) {
      if (P.kind[i] != Kind::Fluid) continue;
      const auto& x = P.pos[i];
      if (x[0] > 0.07 && x[0] < 0.23 && x[1] < 0.12) amax[k] = std::max(amax[k], norm(P.acc[i]));
    }
    ++k;
  }
  // the same particles far from the block (x < 0.04: beyond the band) on both
  std::size_t far = 0;
  const auto& A = plain.S.particles;
  const auto& B = relax.S.particles;
  for (std::size_t i = 0; i < A.n_owned(); ++i)
    for (std::size_t j = 0; j < B.n_owned(); ++j)
      if (A.id[i] == B.id[j] && A.kind[i] == Kind::Fluid && A.pos[i][0] < 0.04) {
        EXPECT_EQ(A.pos[i][0], B.pos[j][0]);
        EXPECT_EQ(A.pos[i][1], B.pos[j][1]);
        ++far;
      }
  EXPECT_GT(far, 100u);
  EXPECT_LT(amax[1], 0.5 * amax[0]) << "max |a| near the block: lattice fill " << amax[0] << ", relaxed " << amax[1];
}
