// The cell list returns exactly the brute-force pair set, in 2D and 3D, with periodic images.
#include <gtest/gtest.h>

#include <random>
#include <set>

#include "sphflume/boundaries/periodic.hpp"
#include "sphflume/core/cell_list.hpp"
#include "sphflume/core/particles.hpp"

using namespace sph;

// n random positions in [0, 2] x [0, 1]^(D-1)
template <int D>
std::vector<Vec<D>> random_positions(int n, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Vec<D>> pos(n);
  for (auto& p : pos)
    for (int d = 0; d < D; ++d) p[d] = u(rng) * (d == 0 ? 2.0 : 1.0);
  return pos;
}

template <int D>
void compare_with_brute_force(int n, double radius, unsigned seed) {
  std::mt19937 rng(seed);
  const std::vector<Vec<D>> pos = random_positions<D>(n, rng);
  CellList<D> cl;
  cl.build(pos, pos.size(), radius);
  std::set<std::pair<int, int>> fast, brute;
  for (int i = 0; i < n; ++i) {
    cl.for_neighbours(pos, pos[i], radius, [&](std::uint32_t j, const Vec<D>&, double) {
      if (static_cast<int>(j) != i) fast.insert({i, static_cast<int>(j)});
    });
    for (int j = 0; j < n; ++j) {
      const Vec<D> r = pos[i] - pos[j];
      if (j != i && dot(r, r) < radius * radius) brute.insert({i, j});
    }
  }
  EXPECT_GT(brute.size(), static_cast<std::size_t>(n));  // the test is not vacuous
  EXPECT_EQ(fast, brute);
}

TEST(CellList, MatchesBruteForce2D) { compare_with_brute_force<2>(1500, 0.07, 1); }
TEST(CellList, MatchesBruteForce3D) { compare_with_brute_force<3>(3000, 0.12, 2); }

TEST(CellList, SortedIsAPermutationGroupedByCell) {
  std::vector<Vec<2>> pos = {{{0.95, 0.1}}, {{0.05, 0.05}}, {{0.5, 0.5}}, {{0.06, 0.04}}};
  CellList<2> cl;
  cl.build(pos, pos.size(), 0.1);
  auto s = cl.sorted();
  std::set<std::uint32_t> all(s.begin(), s.end());
  EXPECT_EQ(all.size(), pos.size());
  // the two particles in the same corner cell are adjacent in cell order
  const auto i1 = std::find(s.begin(), s.end(), 1u) - s.begin();
  const auto i3 = std::find(s.begin(), s.end(), 3u) - s.begin();
  EXPECT_EQ(std::abs(i1 - i3), 1);
}

TEST(Periodic, ImagesGiveMinimumImagePairs) {
  // random particles in a periodic box [0,1)x[0,0.5) periodic in x: the pairs found through
  // images equal the brute-force pairs under the minimum-image convention
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  ParticleStore<2> P;
  const int n = 800;
  for (int i = 0; i < n; ++i) P.add(Vec<2>{{u(rng), 0.5 * u(rng)}}, Vec<2>{}, 1000.0, 1.0, Kind::Fluid);
  Periodic<2> per;
  per.axis[0] = true;
  per.lo = Vec<2>{{0.0, 0.0}};
  per.hi = Vec<2>{{1.0, 0.5}};
  const double radius = 0.06;
  per.build_images(P, radius);
  EXPECT_GT(P.size(), static_cast<std::size_t>(n));
  CellList<2> cl;
  cl.build(P.pos, P.size(), radius);
  std::set<std::pair<int, int>> fast, brute;
  for (int i = 0; i < n; ++i) {
    cl.for_neighbours(P.pos, P.pos[i], radius, [&](std::uint32_t j, const Vec<2>&, double) {
      const int src = j < static_cast<std::uint32_t>(n) ? static_cast<int>(j) : static_cast<int>(P.image_source[j - n]);
      if (src != i) fast.insert({i, src});
    });
    for (int j = 0; j < n; ++j) {
      Vec<2> r = P.pos[i] - P.pos[j];
      r[0] -= std::round(r[0]);  // minimum image along x
      if (j != i && dot(r, r) < radius * radius) brute.insert({i, j});
    }
  }
  EXPECT_EQ(fast, brute);
}

// mark_near flags exactly the occupied cells whose particles have a flagged particle within the
// build radius's stencil (brute force over cells: any flagged particle in a cell at most one
// cell away along every axis)
template <int D>
void mark_near_brute_force(int n, double radius, unsigned seed) {
  std::mt19937 rng(seed);
  const std::vector<Vec<D>> pos = random_positions<D>(n, rng);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<char> flagged(n);
  for (int i = 0; i < n; ++i) flagged[i] = u(rng) < 0.05;
  CellList<D> cl;
  cl.build(pos, pos.size(), radius);
  std::vector<char> near;
  cl.mark_near(near, [&](std::size_t i) { return flagged[i] != 0; });
  // the cell coordinates of each particle, as the list bins them (lo = the smallest coordinate)
  Vec<D> lo;
  for (int d = 0; d < D; ++d) {
    lo[d] = pos[0][d];
    for (const auto& p : pos) lo[d] = std::min(lo[d], p[d]);
  }
  const double inv = 1.0 / cl.cell_size();  // (the list's own arithmetic)
  auto coord = [&](const Vec<D>& p, int d) { return static_cast<int>((p[d] - lo[d]) * inv); };
  int tested = 0, marked = 0;
  for (int i = 0; i < n; ++i) {
    bool expect = false;
    for (int j = 0; j < n && !expect; ++j) {
      if (!flagged[j]) continue;
      bool adjacent = true;
      for (int d = 0; d < D; ++d) adjacent = adjacent && std::abs(coord(pos[i], d) - coord(pos[j], d)) <= 1;
      expect = adjacent;
    }
    EXPECT_EQ(near[cl.cell_of(static_cast<std::size_t>(i))] != 0, expect) << "particle " << i;
    ++tested;
    marked += expect;
  }
  EXPECT_GT(marked, 0);         // not vacuous: some cells are near a flagged particle ...
  EXPECT_LT(marked, tested);    // ... and some are not
}

TEST(CellList, MarkNearMatchesBruteForce2D) { mark_near_brute_force<2>(1200, 0.07, 4); }
TEST(CellList, MarkNearMatchesBruteForce3D) { mark_near_brute_force<3>(2000, 0.12, 5); }
