// The pair-pass seam (core/pair_pass.hpp): the column descriptors' gathers put every candidate of
// a cell's stencil, and only those, into the columns in the stencil's order, with the padding far
// away; the split gather puts each part in its own padded range, the filtered gather only the
// kept candidates; LaneSums adds in its documented
// fixed order.
#include <gtest/gtest.h>

#include <cmath>
#include <numeric>
#include <random>
#include <vector>

#include "sphflume/core/pair_pass.hpp"

using namespace sph;

namespace {

enum { X0, X1, ID, HALF, NONE_IN_2D, NCOL };

/// n random positions in [0, 1]^2, optionally in the cell list's order (a cell-ordered store:
/// the gathers' range copies).
std::vector<Vec<2>> positions(int n, unsigned seed, bool cell_ordered, CellList<2>& cells) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Vec<2>> pos(static_cast<std::size_t>(n));
  for (auto& p : pos) p = Vec<2>{u(rng), u(rng)};
  cells.build(pos, pos.size(), 0.08);
  if (cell_ordered) {
    std::vector<Vec<2>> sorted(pos.size());
    for (std::size_t k = 0; k < pos.size(); ++k) sorted[k] = pos[cells.sorted()[k]];
    pos = sorted;
    cells.build(pos, pos.size(), 0.08);
  }
  return pos;
}

/// The stencil's candidates in its order.
std::vector<std::uint32_t> candidates(const CellStencil<2>& st) {
  std::vector<std::uint32_t> c;
  st.for_each([&](std::size_t, std::uint32_t j) { c.push_back(j); });
  return c;
}

template <class Gather>
void check_gather(bool cell_ordered, Gather&& gather) {
  CellList<2> cells;
  const auto pos = positions(3000, 3, cell_ordered, cells);
  ASSERT_EQ(cells.identity(), cell_ordered);
  ScratchColumns<float> B(NCOL);
  CellStencil<2> st;
  std::size_t checked = 0;
  for (const auto cell : cells.occupied()) {
    st.set(cells, cell, 16);
    B.reserve(st.padded);
    const Vec<2> origin = pos[cells.sorted()[cells.cell_begin(cell)]];
    gather(st, B, pos, origin);
    const auto cand = candidates(st);
    ASSERT_EQ(cand.size(), st.count);
    for (std::size_t m = 0; m < st.count; ++m) {
      const std::uint32_t j = cand[m];
      EXPECT_EQ(B[X0][m], float(pos[j][0] - origin[0]));
      EXPECT_EQ(B[X1][m], float(pos[j][1] - origin[1]));
      EXPECT_EQ(B[ID][m], float(j));
      EXPECT_EQ(B[HALF][m], 0.5f * float(j));
      ++checked;
    }
    for (std::size_t m = st.count; m < st.padded; ++m) {  // padding: far away, the pad values
      EXPECT_EQ(B[X0][m], float(kPaddingDistance));
      EXPECT_EQ(B[ID][m], -1.0f);
      EXPECT_EQ(B[HALF][m], 7.0f);
    }
  }
  EXPECT_GT(checked, 9u * 3000u / 2u);  // (every particle is a candidate of ~9 cells)
}

auto id_column() { return column(ID, -1.0f, [](std::size_t j) { return float(j); }); }
auto half_column() { return column(HALF, 7.0f, [](std::size_t j) { return 0.5f * float(j); }); }

}  // namespace

TEST(PairPass, GatherColumnsCopiesEachCandidateInStencilOrder) {
  for (const bool ordered : {true, false})
    check_gather(ordered, [](const CellStencil<2>& st, ScratchColumns<float>& B, const std::vector<Vec<2>>& pos,
                             const Vec<2>& o) {
      // a NoColumn is neither written nor padded: its column keeps what it held
      std::fill(B[NONE_IN_2D], B[NONE_IN_2D] + st.padded, 42.0f);
      gather_columns(st, B, pos.data(), o, id_column(), half_column(),
                     only_if<false>(column(NONE_IN_2D, 0.0f, [](std::size_t) { return 1.0f; })));
      for (std::size_t m = 0; m < st.padded; ++m) ASSERT_EQ(B[NONE_IN_2D][m], 42.0f);
    });
}

// gather_split: the candidates with first(j) from entry 0 in stencil order, padded to a block;
// then the others, padded; a second_part column is written for the second part.
TEST(PairPass, GatherSplitPutsEachPartInItsPaddedRange) {
  for (const bool ordered : {true, false}) {
    CellList<2> cells;
    const auto pos = positions(2000, 5, ordered, cells);
    ScratchColumns<float> B(NCOL);
    CellStencil<2> st;
    auto first = [](std::uint32_t j) { return j % 3 != 0; };
    for (const auto cell : cells.occupied()) {
      st.set(cells, cell, 16);
      B.reserve(st.padded + 16);
      const Vec<2> origin = pos[cells.sorted()[cells.cell_begin(cell)]];
      const auto cand = candidates(st);
      std::vector<std::uint32_t> a, b;
      for (const auto j : cand) (first(j) ? a : b).push_back(j);
      const SplitEnds e = gather_split(st, B, pos.data(), origin, 16, b.size(), first, id_column(),
                                       second_part(HALF, 7.0f, [](std::size_t j) { return 0.5f * float(j); }));
      ASSERT_EQ(e.first_end, (a.size() + 15) / 16 * 16);
      ASSERT_EQ(e.end, e.first_end + (b.size() + 15) / 16 * 16);
      for (std::size_t m = 0; m < a.size(); ++m) ASSERT_EQ(B[ID][m], float(a[m]));
      for (std::size_t m = a.size(); m < e.first_end; ++m) ASSERT_EQ(B[X0][m], float(kPaddingDistance));
      for (std::size_t m = 0; m < b.size(); ++m) {
        ASSERT_EQ(B[ID][e.first_end + m], float(b[m]));
        ASSERT_EQ(B[HALF][e.first_end + m], 0.5f * float(b[m]));
        ASSERT_EQ(B[X1][e.first_end + m], float(pos[b[m]][1] - origin[1]));
      }
      for (std::size_t m = e.first_end + b.size(); m < e.end; ++m) ASSERT_EQ(B[HALF][m], 7.0f);
    }
  }
}

// gather_if: only the candidates with keep(j), in stencil order, padded to a block far away.
TEST(PairPass, GatherIfKeepsOnlyTheKeptInStencilOrder) {
  for (const bool ordered : {true, false}) {
    CellList<2> cells;
    const auto pos = positions(2000, 7, ordered, cells);
    ScratchColumns<float> B(NCOL);
    CellStencil<2> st;
    auto keep = [](std::uint32_t j) { return j % 5 == 1; };
    for (const auto cell : cells.occupied()) {
      st.set(cells, cell, 16);
      B.reserve(st.padded);
      const Vec<2> origin = pos[cells.sorted()[cells.cell_begin(cell)]];
      std::vector<std::uint32_t> kept;
      for (const auto j : candidates(st))
        if (keep(j)) kept.push_back(j);
      const std::size_t n = gather_if(st, B, pos.data(), origin, 16, keep, id_column());
      ASSERT_EQ(n, kept.size());
      for (std::size_t m = 0; m < n; ++m) {
        ASSERT_EQ(B[ID][m], float(kept[m]));
        ASSERT_EQ(B[X0][m], float(pos[kept[m]][0] - origin[0]));
      }
      for (std::size_t m = n; m < (n + 15) / 16 * 16; ++m) {
        ASSERT_EQ(B[X1][m], float(kPaddingDistance));
        ASSERT_EQ(B[ID][m], -1.0f);
      }
    }
  }
}

// LaneSums adds term k of block k0 into lane k mod 16, then the lanes pairwise (8 apart, 4, 2,
// 1): bitwise that order, whatever the vector width; and within float round-off of the exact sum.
TEST(PairPass, LaneSumsAddInTheirFixedOrder) {
  constexpr std::size_t L = 16, n = 16 * 37;
  std::vector<float> x(n);
  for (std::size_t k = 0; k < n; ++k) x[k] = 1.0f / float(k + 1) + float(k % 7) * 1e-3f;
  LaneSums<L, 2> v;
  for (std::size_t k0 = 0; k0 < n; k0 += L) {
    const float* xb = x.data() + k0;
    v.add([&](std::size_t l, auto&& acc) {
      acc[0][l] += xb[l];
      acc[1][l] += xb[l] * xb[l];
    });
  }
  const auto s = v.sums();
  float lane[L] = {}, lane2[L] = {};
  for (std::size_t k = 0; k < n; ++k) {
    lane[k % L] += x[k];
    lane2[k % L] += x[k] * x[k];
  }
  for (std::size_t w = L / 2; w >= 1; w /= 2)
    for (std::size_t l = 0; l < w; ++l) {
      lane[l] += lane[l + w];
      lane2[l] += lane2[l + w];
    }
  EXPECT_EQ(s[0], lane[0]);
  EXPECT_EQ(s[1], lane2[0]);
  double exact = 0.0;
  for (const float xi : x) exact += xi;
  EXPECT_NEAR(s[0], exact, exact * 1e-6);  // float: a few units of 1e-7 per level of the sum
}
