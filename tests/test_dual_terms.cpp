// The dual-criteria Riemann scheme's per-pair terms (schemes/dual_terms.hpp), each on its own:
// the pressure term is antisymmetric (a pair's forces cancel: momentum is conserved), the
// acoustic and continuity terms vanish for equal states, the Riemann dissipation acts only on
// approaching pairs with the limiter β = min(k U/c0, 1), and against a wall only on the normal
// speed (sliding is free); the density sum over a lattice is the lattice's kernel sum.
#include <gtest/gtest.h>

#include <array>
#include <cmath>

#include "sphflume/core/kernels.hpp"
#include "sphflume/schemes/dual_terms.hpp"

using namespace sph;
using namespace sph::dual;

namespace {

constexpr double kDx = 0.01;
const WendlandC2<2> kKer(1.3 * kDx);

/// One candidate b in lane 0 of a block (the other lanes far away, as padding).
struct OneCandidate {
  std::array<std::array<F32, 16>, NCOL> c{};
  OneCandidate(F32 x0, F32 x1, F32 u0, F32 u1, F32 p, F32 v, F32 n0 = 0, F32 n1 = 0) {
    for (auto& col : c) col.fill(0);
    c[X0].fill(F32(kPaddingDistance));
    c[X1].fill(F32(kPaddingDistance));
    c[X0][0] = x0; c[X1][0] = x1; c[U0][0] = u0; c[U1][0] = u1; c[PRS][0] = p; c[VOL][0] = v;
    c[N0][0] = n0; c[N1][0] = n1;
  }
  Block block() const {
    return {c[X0].data(), c[X1].data(), c[X1].data(), c[U0].data(), c[U1].data(), c[U1].data(),
            c[N0].data(), c[N1].data(), c[N1].data(), c[PRS].data(), c[VOL].data(), nullptr};  // (h: levels only)
  }
};

template <std::size_t N, class Terms>
std::array<F32, N> sums(Terms&& terms) {
  LaneSums<16, N> v;
  v.add(terms);
  return v.sums();
}

// a at x_a, b at x_b with their states; the pressure pass's sums of a over b
std::array<F32, 4> pressure(F32 xa, F32 ya, F32 pa, F32 xb, F32 yb, F32 pb, F32 vb) {
  const OneCandidate b(xb, yb, 0, 0, pb, vb);
  const Row a{xa, ya, ya, 0, 0, 0, pa, 0};
  const Block bl = b.block();
  return sums<4>([&](std::size_t l, auto&& acc) { pressure_terms<2>(kKer, F32(kKer.support2), a, bl, l, acc); });
}

std::array<F32, 3> continuity(F32 ua0, F32 ua1, F32 ub0, F32 ub1, F32 rx, F32 ry, bool wall, F32 n0 = 0, F32 n1 = 0,
                              F32 fk = F32(3.0 / 20.0)) {
  const OneCandidate b(0, 0, ub0, ub1, 0, F32(kDx * kDx), n0, n1);
  const Row a{rx, ry, ry, ua0, ua1, ua1, 0, 0};
  const Block bl = b.block();
  if (wall) return sums<3>([&](std::size_t l, auto&& acc) { continuity_terms<2, true>(kKer, fk, a, bl, l, acc); });
  return sums<3>([&](std::size_t l, auto&& acc) { continuity_terms<2, false>(kKer, fk, a, bl, l, acc); });
}

}  // namespace

// Σ (pa + pb) ∇W V_b: the pair's terms of a over b and of b over a cancel (equal volumes), and
// the force pushes a away from b (W' < 0: the term is along −r times a negative F).
TEST(DualTerms, PressureTermIsAntisymmetric) {
  const F32 xa = 0.003f, ya = 0.011f, xb = 0.0f, yb = 0.0f, v = F32(kDx * kDx);
  const auto ab = pressure(xa, ya, 1000.0f, xb, yb, 400.0f, v);
  const auto ba = pressure(xb, yb, 400.0f, xa, ya, 1000.0f, v);
  EXPECT_NEAR(ab[0], -ba[0], 1e-6 * std::abs(ab[0]));
  EXPECT_NEAR(ab[1], -ba[1], 1e-6 * std::abs(ab[1]));
  EXPECT_LT(ab[1], 0.0f);  // (pa + pb) F r with F = W'/r < 0: along −r; the pass multiplies by −1/ρ
  EXPECT_EQ(ab[3], 1.0f);  // one neighbour within the support
  // the acoustic dissipation (pa − pb) W' V_b changes sign with the pressure difference
  EXPECT_NEAR(ab[2], -ba[2], 1e-6 * std::abs(ab[2]));
  const auto same = pressure(xa, ya, 700.0f, xb, yb, 700.0f, v);
  EXPECT_EQ(same[2], 0.0f);
}

// A pair outside the support and the self pair add nothing (and are not counted).
TEST(DualTerms, PressureTermIsZeroOutsideTheSupportAndForTheSelfPair) {
  const F32 far = F32(1.01 * kKer.support);
  const auto out = pressure(far, 0, 1000.0f, 0, 0, 400.0f, 1e-4f);
  for (const F32 s : out) EXPECT_EQ(s, 0.0f);
  const auto self = pressure(0, 0, 1000.0f, 0, 0, 1000.0f, 1e-4f);
  for (const F32 s : self) EXPECT_EQ(s, 0.0f);
}

// Equal velocities: no continuity term, no dissipation. Separating particles: continuity only
// (the dissipation acts on approach, U > 0). Approaching at U along r: β U F V_b r with
// β = min(k U / c0, 1), here checked in both of its branches.
TEST(DualTerms, RiemannDissipationActsOnApproachWithItsLimiter) {
  const F32 rx = 0.008f, ry = 0.0f;  // a to the right of b
  const auto equal = continuity(0.3f, -0.2f, 0.3f, -0.2f, rx, ry, false);
  for (const F32 s : equal) EXPECT_EQ(s, 0.0f);
  const auto apart = continuity(0.5f, 0.0f, 0.0f, 0.0f, rx, ry, false);  // a moves away from b
  EXPECT_EQ(apart[0], 0.0f);
  EXPECT_EQ(apart[1], 0.0f);
  EXPECT_NE(apart[2], 0.0f);
  const F32 fk = F32(3.0 / 20.0);  // k / c0, c0 = 20
  for (const F32 U : {0.5f, 4.0f}) {  // β = 0.075 and β = 1 (limited)
    const auto s = continuity(-U, 0.0f, 0.0f, 0.0f, rx, ry, false, 0, 0, fk);
    const F32 Fv = kKer.F(rx) * F32(kDx * kDx);
    const F32 beta = std::min(fk * U, 1.0f);
    EXPECT_NEAR(s[0], beta * U * Fv * rx, 1e-5 * std::abs(beta * U * Fv * rx));
    EXPECT_EQ(s[1], 0.0f);
    EXPECT_NEAR(s[2], -U * rx * Fv, 1e-5 * std::abs(U * rx * Fv));  // (ua − ub)·r F V_b
  }
}

// Against a wall the dissipation acts along the wall's normal on twice the normal approach speed
// (the mirror state), whatever the normal's sign: sliding along the wall is free.
TEST(DualTerms, WallDissipationActsOnTheNormalSpeedOnly) {
  const F32 rx = 0.002f, ry = 0.007f;  // a above a wall particle whose normal is +y
  const auto slide = continuity(1.0f, 0.0f, 0.0f, 0.0f, rx, ry, true, 0.0f, 1.0f);
  EXPECT_EQ(slide[0], 0.0f);
  EXPECT_EQ(slide[1], 0.0f);
  const auto in = continuity(0.0f, -0.5f, 0.0f, 0.0f, rx, ry, true, 0.0f, 1.0f);
  const auto in_flipped = continuity(0.0f, -0.5f, 0.0f, 0.0f, rx, ry, true, 0.0f, -1.0f);
  EXPECT_EQ(in[0], 0.0f);
  EXPECT_LT(in[1], 0.0f);  // along the normal (W' < 0; the pass's −ρ0 c0/ρ pushes a back along +n)
  EXPECT_EQ(in[1], in_flipped[1]);
  const F32 r = std::sqrt(rx * rx + ry * ry), U = 2.0f * 0.5f, fk = F32(3.0 / 20.0);
  const F32 expect = std::min(fk * U, 1.0f) * U * kKer.F(r) * F32(kDx * kDx) * r;
  EXPECT_NEAR(in[1], expect, 1e-5 * std::abs(expect));
  const auto out = continuity(0.0f, 0.5f, 0.0f, 0.0f, rx, ry, true, 0.0f, 1.0f);  // leaving the wall
  EXPECT_EQ(out[1], 0.0f);
}

// The density sum over a square lattice of spacing dx around a particle (the self term apart)
// is the lattice's kernel sum minus W(0), within float round-off.
TEST(DualTerms, DensitySumOverALatticeIsTheLatticeKernelSum) {
  const double expected = lattice_kernel_sum<2>(kKer, kDx) - kKer.W(0.0);
  ScratchColumns<F32> B(NCOL);
  B.reserve(64);
  std::size_t n = 0, within = 0;
  for (int i = -3; i <= 3; ++i)
    for (int j = -3; j <= 3; ++j) {
      B[X0][n] = F32(i * kDx);
      B[X1][n] = F32(j * kDx);
      ++n;
      const double r2 = (i * i + j * j) * kDx * kDx;
      within += r2 > 0.0 && r2 < 0.999 * kKer.support2 ? 1 : 0;  // (none sits on the support)
    }
  for (; n < 64; ++n) B[X0][n] = B[X1][n] = F32(kPaddingDistance);
  const Block cols = columns_of<2>(B);
  const Row a{0, 0, 0, 0, 0, 0, 0, 0};
  LaneSums<16, 2> v;
  for (std::size_t k0 = 0; k0 < 64; k0 += 16) {
    const Block b = block_at(cols, k0);
    v.add([&](std::size_t l, auto&& acc) { density_terms<2>(kKer, F32(kKer.support2), a, b, l, acc); });
  }
  const auto s = v.sums();
  EXPECT_NEAR(s[0], expected, 1e-6 * expected);
  EXPECT_EQ(s[1], F32(within));  // the lattice points within the support, the self point apart
}
