// The rates pass's per-pair terms (schemes/wcsph_terms.hpp), each on its own: the reciprocals from
// one division, the neighbour mask (a wall sees only fluid; repulsive walls in no sum) and the
// antisymmetric kernel gradient, the porosity that weights b's velocity, and the momentum
// coefficient (pressure in both forms, Monaghan's Π_ab only on approach, the phases' interface
// repulsion only across phases, no wall viscosity where walls take none).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "sphflume/core/kernels.hpp"
#include "sphflume/schemes/wcsph_terms.hpp"

using namespace sph;
using namespace sph::rates;

namespace {

constexpr double kDx = 0.01;
const WendlandC2<2> kKer(1.3 * kDx);

RatesRow row(F32 x0, F32 x1, F32 u0, F32 u1, F32 rho, F32 p, F32 c, bool wall = false, F32 phi = 1) {
  RatesRow r{};
  r.xa0 = x0; r.xa1 = x1; r.xa2 = x1; r.va0 = u0; r.va1 = u1; r.va2 = u1;
  r.rhoa = rho; r.pa = p; r.ca = c; r.ca2 = c * c; r.pa_r2 = p / (rho * rho); r.inv_rhoa = 1 / rho;
  r.wa = wall ? 0 : 1;
  r.phia = phi; r.iphia = 1 / phi; r.rhoa_d = rho; r.phia_d = phi;
  return r;
}

PairGeometry geometry(const RatesRow& a, F32 xb0, F32 xb1, bool b_fluid, F32 wall_in = 1) {
  return pair_geometry<2>(kKer, a, xb0, xb1, xb1, b_fluid ? 1.0f : 0.0f, F32(kKer.support2), wall_in);
}

}  // namespace

// The four reciprocals from one division: each within a few float round-offs of its direct value.
TEST(WcsphTerms, PairInversesAreTheReciprocals) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> rho(950.0, 1100.0), c(10.0, 60.0), r(1e-4, 2.6 * kDx);
  for (int t = 0; t < 1000; ++t) {
    const RatesRow a = row(0, 0, 0, 0, F32(rho(rng)), 0, F32(c(rng)));
    const F32 rhob = F32(rho(rng)), cb = F32(c(rng)), r2 = F32(std::pow(r(rng), 2)), eta2 = F32(0.01 * 1.3 * 1.3 * kDx * kDx);
    const PairInverses iv = pair_inverses(a, r2, eta2, rhob, cb);
    const double tol = 1e-6;  // (float: 6e-8 per operation, a handful of operations)
    EXPECT_NEAR(iv.rhob * rhob, 1.0, tol);
    EXPECT_NEAR(double(iv.r2e) * (double(r2) + eta2), 1.0, tol);
    EXPECT_NEAR(double(iv.rsum) * (double(a.rhoa) + rhob), 1.0, tol);
    EXPECT_NEAR(double(iv.csum) * (double(a.ca2) + double(cb) * cb), 1.0, tol);
    EXPECT_EQ(iv.rho_sum, a.rhoa + rhob);
  }
}

// Within the support and not a itself; a wall a sees only fluid; a wall b is in the sums unless
// walls are purely repulsive (wall_in = 0); ∇_a W = −∇_b W.
TEST(WcsphTerms, PairGeometryMasksAndAntisymmetry) {
  const RatesRow fluid_a = row(0.004f, 0.009f, 0, 0, 1000, 0, 20);
  const RatesRow wall_a = row(0.004f, 0.009f, 0, 0, 1000, 0, 20, true);
  EXPECT_EQ(geometry(fluid_a, 0, 0, true).in, 1.0f);
  EXPECT_EQ(geometry(fluid_a, 0.004f, 0.009f, true).in, 0.0f);  // a itself
  EXPECT_EQ(geometry(fluid_a, 0.004f + F32(1.01 * kKer.support), 0.009f, true).in, 0.0f);
  EXPECT_EQ(geometry(fluid_a, 0, 0, false).in, 1.0f);
  EXPECT_EQ(geometry(fluid_a, 0, 0, false, 0.0f).in, 0.0f);  // repulsive walls
  EXPECT_EQ(geometry(wall_a, 0, 0, true).in, 1.0f);
  EXPECT_EQ(geometry(wall_a, 0, 0, false).in, 0.0f);
  const PairGeometry ab = geometry(fluid_a, 0, 0, true);
  const PairGeometry ba = geometry(row(0, 0, 0, 0, 1000, 0, 20), 0.004f, 0.009f, true);
  EXPECT_EQ(ab.gw0, -ba.gw0);
  EXPECT_EQ(ab.gw1, -ba.gw1);
  EXPECT_LT(ab.gw1, 0.0f);  // W decreases with r: ∇_a W points from a back towards b
  EXPECT_NEAR(ab.gw1, kKer.F(std::sqrt(0.004 * 0.004 + 0.009 * 0.009)) * 0.009, 1e-5 * std::abs(ab.gw1));
}

// SPHAM: fluid a weights fluid b's velocity with φ_b; a wall b takes a's porosity (no porosity
// interface at a wall); a wall a sees fluid b as plain fluid (1).
TEST(WcsphTerms, FlowPorosity) {
  const RatesRow a = row(0, 0, 0, 0, 1000, 0, 20, false, 0.4f);
  EXPECT_EQ(flow_porosity(a, 1.0f, 0.7f), 0.7f);
  EXPECT_EQ(flow_porosity(a, 0.0f, 1.0f), 0.4f);
  EXPECT_EQ(flow_porosity(row(0, 0, 0, 0, 1000, 0, 20, true, 1.0f), 1.0f, 0.7f), 1.0f);
}

// The coefficient of ∇W: with no relative motion only the pressure term, m_b (p_a/ρ_a² +
// p_b/ρ_b²) in the symmetric form and (p_a + p_b) V_b/ρ_a in the sum form; Π_ab adds to it only
// for an approaching pair (w·r < 0), positive (repulsive); the phases' repulsion only across
// phases; a wall b adds no viscosity where walls take none (visc_wall = 0).
TEST(WcsphTerms, MomentumCoefficient) {
  const F32 rhoa = 1010, rhob = 990, pa = 2000, pb = 500, c = 20, mb = 0.1f;
  const RatesRow a = row(0.004f, 0.009f, 0, 0, rhoa, pa, c);
  const PairGeometry g = geometry(a, 0, 0, true);
  const PairInverses iv = pair_inverses(a, g.r2, 1e-6f, rhob, c);
  const F32 Vb = mb * iv.rhob;
  auto coef = [&](F32 sym, F32 u1, F32 visc_wall, F32 fb, F32 chi, F32 phsb) {
    const MomentumConstants k{sym, visc_wall, 0.02f, F32(1.3 * kDx), chi};
    return momentum_coefficient<2, true, true>(k, a, g, iv, 0, u1, u1, 0, 0, 0, fb, pb, c, mb, Vb, phsb);
  };
  const MomentumCoefficient sym = coef(1, 0, 1, 1, 0, 0);
  EXPECT_NEAR(sym.gcoef, mb * (pa / (rhoa * rhoa) + pb / (rhob * rhob)), 1e-6 * sym.gcoef);
  const MomentumCoefficient sum = coef(0, 0, 1, 1, 0, 0);
  EXPECT_NEAR(sum.gcoef, (pa + pb) * mb / rhob / rhoa, 1e-6 * sum.gcoef);
  // a above b: u1 < 0 approaches, u1 > 0 separates
  EXPECT_GT(coef(0, -0.5f, 1, 1, 0, 0).gcoef, sum.gcoef);
  EXPECT_EQ(coef(0, 0.5f, 1, 1, 0, 0).gcoef, sum.gcoef);
  const MomentumCoefficient wall = coef(0, -0.5f, 0, 0, 0, 0);
  EXPECT_EQ(wall.mv, 0.0f);
  EXPECT_EQ(wall.gcoef, sum.gcoef);
  // interface repulsion: χ (|p_a| + |p_b|) V_b/ρ_a against another phase only
  EXPECT_EQ(coef(0, 0, 1, 1, 0.1f, 0).gcoef, sum.gcoef);
  EXPECT_NEAR(coef(0, 0, 1, 1, 0.1f, 1).gcoef - sum.gcoef, 0.1 * (pa + pb) * Vb / rhoa, 1e-5 * sum.gcoef);
}
