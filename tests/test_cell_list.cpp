// The cell list returns exactly the brute-force pair set, in 2D and 3D, with periodic images.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#ifdef _OPENMP
#include <omp.h>
#endif
#include <set>

#include "sphflume/core/pair_pass.hpp"
#include "sphflume/core/periodic.hpp"
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

// A store kept in cell order step after step: the update that re-places only the particles
// that changed cell (build's in_order) and the run moves of the store give exactly the full
// counting sort and the cycle permutation, for any thread count, while the bounds stay (two
// particles pinned at the corners) and when they change (the update falls back).
template <int D>
void incremental_matches_full(int n, double radius, unsigned seed, int threads) {
#ifdef _OPENMP
  const int saved = omp_get_max_threads();
  omp_set_num_threads(threads);
#else
  (void)threads;
#endif
  std::mt19937 rng(seed);
  ParticleStore<D> A;
  for (const auto& x : random_positions<D>(n, rng)) A.add(x, Vec<D>{}, 1.0, 1.0, Kind::Fluid);
  Vec<D> lo{}, hi{};
  for (int d = 0; d < D; ++d) hi[d] = d == 0 ? 2.0 : 1.0;
  A.pos[0] = lo;
  A.pos[1] = hi;
  CellList<D> cl;
  cl.build(A.pos, A.n_owned(), radius);
  A.permute(cl.sorted());
  cl.adopt_permutation();
  std::normal_distribution<double> step(0.0, 0.15 * radius);
  std::size_t moved = 0;
  for (int it = 0; it < 12; ++it) {
    const bool grow = it == 7;  // one step that widens the bounds: a full build
    for (std::size_t i = 0; i < A.n_owned(); ++i) {
      if (A.id[i] <= 1) continue;  // the corners
      for (int d = 0; d < D; ++d) A.pos[i][d] = std::clamp(A.pos[i][d] + step(rng), 0.0, hi[d]);
      if (grow && A.id[i] == 2) A.pos[i][0] = 2.5;
    }
    ParticleStore<D> B = A;
    cl.build(A.pos, A.n_owned(), radius, true);
    CellList<D> ref;
    ref.build(B.pos, B.n_owned(), radius);
    EXPECT_EQ(cl.updated(), !grow && it != 8) << it;  // (after the widening: bounds change back)
    ASSERT_EQ(cl.sorted(), ref.sorted()) << it;
    ASSERT_EQ(cl.cell_count(), ref.cell_count());
    for (std::size_t c = 0; c < ref.cell_count(); ++c) ASSERT_EQ(cl.cell_begin(c), ref.cell_begin(c)) << it << " " << c;
    EXPECT_EQ(cl.occupied(), ref.occupied()) << it;
    EXPECT_EQ(cl.identity(), ref.identity());
    moved += cl.moved();
    if (cl.updated()) A.permute_runs(cl.moved(), cl.moved_from(), cl.moved_to());
    else A.permute(cl.sorted());
    B.permute(ref.sorted());
    ASSERT_EQ(A.id, B.id) << it;
    for (std::size_t i = 0; i < A.n_owned(); ++i)
      for (int d = 0; d < D; ++d) ASSERT_EQ(A.pos[i][d], B.pos[i][d]);
    cl.adopt_permutation();
  }
  EXPECT_GT(moved, static_cast<std::size_t>(n / 10));  // (not vacuous: many changed cell)
#ifdef _OPENMP
  omp_set_num_threads(saved);
#endif
}

TEST(CellList, UpdateMatchesFullSort2D) {
  incremental_matches_full<2>(600, 0.07, 7, 1);
  incremental_matches_full<2>(9000, 0.05, 8, 2);  // (over 4096: the parallel merge)
}
TEST(CellList, UpdateMatchesFullSort3D) {
  incremental_matches_full<3>(800, 0.12, 9, 1);
  incremental_matches_full<3>(9000, 0.1, 10, 2);
}

// sweep_cells hands each thread a contiguous run of cells, balanced by the cells' work and by
// the rates the threads ran at in earlier calls. Whatever the partition (1, 2 or 3 threads, and
// after calls in which the low third of the cells was made slower, which moves the runs), every
// cell that needs the pass is run exactly once, no other cell is run, the stencil is the cell's
// own, and the returned total is the sum of the bodies' returns.
TEST(CellList, SweepRunsEveryNeededCellOnce) {
  std::mt19937 rng(7);
  std::vector<Vec<2>> pos = random_positions<2>(4000, rng);
  CellList<2> cells;
  cells.build(pos, pos.size(), 0.05);
  const auto& occ = cells.occupied();
  auto need = [&](std::size_t cell) -> std::size_t {  // every third cell needs nothing
    return cell % 3 == 1 ? 0 : cells.cell_end(cell) - cells.cell_begin(cell);
  };
  std::uint64_t expected = 0;
  for (const auto c : occ) expected += need(c) > 0 ? c + 1 : 0;
#ifdef _OPENMP
  const int saved = omp_get_max_threads();
#endif
  for (int threads = 1; threads <= 3; ++threads) {
#ifdef _OPENMP
    omp_set_num_threads(threads);
#endif
    for (int call = 0; call < 6; ++call) {
      std::vector<int> runs(cells.cell_count(), 0);
      const std::uint64_t total = sweep_cells<float>(cells, 2, 16, need, [&](std::size_t cell, const CellStencil<2>& st, ScratchColumns<float>&) {
        std::uint32_t rg[CellList<2>::kMaxRanges][2];
        const int nr = cells.cell_ranges(cell, rg);
        EXPECT_EQ(nr, st.nr);
        for (int r = 0; r < nr && r < st.nr; ++r) EXPECT_EQ(rg[r][0], st.rg[r][0]);
        // (the first calls: the low cells slow, so that the rates, and the runs, shift)
        if (call < 3 && cell < cells.cell_count() / 3) {
          volatile double x = 0;
          for (int i = 0; i < 2000; ++i) x = x + 1.0;
        }
#pragma omp atomic
        ++runs[cell];
        return std::uint64_t(cell + 1);
      });
      EXPECT_EQ(total, expected) << threads << " threads, call " << call;
      for (const auto c : occ) ASSERT_EQ(runs[c], need(c) > 0 ? 1 : 0) << "cell " << c << ", " << threads << " threads, call " << call;
    }
  }
#ifdef _OPENMP
  omp_set_num_threads(saved);
#endif
}

// Every cell's stencil (cell_ranges) holds every particle j within kappa (h_i + h_j)/2 of each
// of its particles i (brute force).
template <int D>
void stencils_hold_every_pair(const CellList<D>& cl, const std::vector<Vec<D>>& pos, const std::vector<double>& h,
                              double kappa, const char* when) {
  std::uint32_t rg[CellList<D>::kMaxRanges][2];
  for (const std::uint32_t c : cl.occupied()) {
    std::set<std::uint32_t> stencil;
    const int nr = cl.cell_ranges(c, rg);
    for (int r = 0; r < nr; ++r)
      for (std::uint32_t k = rg[r][0]; k < rg[r][1]; ++k) stencil.insert(cl.sorted()[k]);
    for (std::uint32_t k = cl.cell_begin(c); k < cl.cell_end(c); ++k) {
      const std::uint32_t i = cl.sorted()[k];
      for (std::size_t j = 0; j < pos.size(); ++j) {
        const Vec<D> r = pos[i] - pos[j];
        const double s = 0.5 * kappa * (h[i] + h[j]);
        if (dot(r, r) < s * s) {
          ASSERT_TRUE(stencil.count(static_cast<std::uint32_t>(j))) << when << ": " << i << " misses " << j;
        }
      }
    }
  }
}

// Resolution levels (docs/numerics.md §14): cells as wide as the fine pairs' support, each cell's
// stencil narrowed to its own pairs (set_reach) holds every pair within kappa (h_i + h_j)/2;
// the fine cells away from the coarse particles scan ±1 cell, the others ±2; a query of the
// largest support still finds every particle.
template <int D>
void variable_reach_holds_every_pair(int n, double h_fine, unsigned seed) {
  std::mt19937 rng(seed);
  const std::vector<Vec<D>> pos = random_positions<D>(n, rng);
  const double kappa = 2.0, h_coarse = 2.0 * h_fine;
  std::vector<double> h(pos.size());
  for (std::size_t i = 0; i < pos.size(); ++i)  // fine for x < 0.9, coarse beyond 1.1, a ramp between
    h[i] = h_fine + (h_coarse - h_fine) * std::clamp((pos[i][0] - 0.9) / 0.2, 0.0, 1.0);
  CellList<D> cl;
  cl.build(pos, pos.size(), kappa * h_coarse, false, kappa * h_fine * (1.0 + 1.0e-6));
  cl.set_reach([&](std::uint32_t j) { return h[j]; }, kappa);
  int fine_cells = 0, wide_cells = 0;
  for (const std::uint32_t c : cl.occupied()) (cl.reach(c) == 1 ? fine_cells : wide_cells) += 1;
  stencils_hold_every_pair(cl, pos, h, kappa, "set_reach");
  EXPECT_GT(fine_cells, 0);
  EXPECT_GT(wide_cells, 0);
  // the widest query still holds everything within the build radius
  const double R = kappa * h_coarse;
  for (std::size_t i = 0; i < pos.size(); i += 7) {
    std::size_t found = 0, brute = 0;
    cl.for_neighbours(pos, pos[i], R, [&](std::uint32_t, const Vec<D>&, double) { ++found; });
    for (std::size_t j = 0; j < pos.size(); ++j) brute += dot(pos[i] - pos[j], pos[i] - pos[j]) < R * R ? 1 : 0;
    EXPECT_EQ(found, brute);
  }
}
TEST(CellList, VariableReachHoldsEveryPair2D) { variable_reach_holds_every_pair<2>(3000, 0.012, 6); }
TEST(CellList, VariableReachHoldsEveryPair3D) { variable_reach_holds_every_pair<3>(6000, 0.03, 7); }

// One grid per level (`resolution.cells: levels`, core/cell_grids.hpp): level 1 (h fine) for x < 1,
// level 0 beyond, h ramping from fine to coarse over x in [0.8, 1.0] (the levels' smoothed h).
// Every cell's stencil holds every pair within kappa (h_i + h_j)/2, before set_reach (the
// widest) and after it; each level's particles lie together in the store's order; a fine cell
// deep in the fine zone scans fewer candidates than the single grid's 3^D level-0 cells; a point
// query of any radius up to level 0's support finds exactly the brute-force set; and an
// in-place update after small moves gives the full build's cells.
template <int D>
void level_grids_hold_every_pair(int n, double h_fine, unsigned seed) {
  std::mt19937 rng(seed);
  std::vector<Vec<D>> pos = random_positions<D>(n, rng);
  // (anchors at the corners of each level's zone: the moves below keep the grids' layout)
  for (const double x : {0.0, 0.99, 1.01, 2.0}) {
    Vec<D> lo{}, hi{};
    lo[0] = x;
    hi[0] = x;
    for (int d = 1; d < D; ++d) hi[d] = 1.0;
    pos.push_back(lo);
    pos.push_back(hi);
  }
  const std::size_t n_moving = static_cast<std::size_t>(n);
  const double kappa = 2.0, h_coarse = 2.0 * h_fine;
  std::vector<double> h(pos.size()), level(pos.size());
  auto set_levels = [&] {
    for (std::size_t i = 0; i < pos.size(); ++i) {
      level[i] = pos[i][0] < 1.0 ? 1.0 : 0.0;
      h[i] = level[i] == 0.0 ? h_coarse : h_fine + (h_coarse - h_fine) * std::clamp((pos[i][0] - 0.8) / 0.2, 0.0, 1.0);
    }
  };
  set_levels();
  const double R = kappa * h_coarse;
  CellList<D> cl;
  cl.build(pos, pos.size(), R, false, 0.0, level.data(), 2);
  ASSERT_TRUE(cl.level_grids());
  // the store's order: level 0's cells, then level 1's
  for (std::size_t k = 1; k < pos.size(); ++k) ASSERT_GE(level[cl.sorted()[k]], level[cl.sorted()[k - 1]]);
  stencils_hold_every_pair(cl, pos, h, kappa, "before set_reach");
  cl.set_reach([&](std::uint32_t j) { return h[j]; }, kappa);
  stencils_hold_every_pair(cl, pos, h, kappa, "after set_reach");
  // a fine particle deep in the fine zone scans fewer candidates than with level 0's cells
  CellList<D> single;
  single.build(pos, pos.size(), R);
  std::size_t deep = 0, sum_a = 0, sum_b = 0;
  std::uint32_t rg[CellList<D>::kMaxRanges][2];
  for (std::size_t i = 0; i < pos.size(); ++i) {
    if (!(pos[i][0] > 0.2 && pos[i][0] < 0.6)) continue;
    std::size_t a = 0, b = 0;
    const int na = cl.cell_ranges(cl.cell_of(i), rg);
    for (int r = 0; r < na; ++r) a += rg[r][1] - rg[r][0];
    const int nb = single.cell_ranges(single.cell_of(i), rg);
    for (int r = 0; r < nb; ++r) b += rg[r][1] - rg[r][0];
    ++deep;
    sum_a += a;
    sum_b += b;
  }
  // (a fine cell's 3^D fine cells hold (1/2)^D of the level-0 stencil's candidates, the coarse cells around it none)
  EXPECT_GT(deep, 100u);
  EXPECT_LT(double(sum_a), 0.4 * double(sum_b));
  // point queries of several radii
  for (const double radius : {R, 0.5 * R, kappa * h_fine}) {
    for (std::size_t i = 0; i < pos.size(); i += 5) {
      std::set<std::uint32_t> found;
      cl.for_neighbours(pos, pos[i], radius, [&](std::uint32_t j, const Vec<D>&, double) { found.insert(j); });
      std::size_t brute = 0;
      for (std::size_t j = 0; j < pos.size(); ++j) brute += dot(pos[i] - pos[j], pos[i] - pos[j]) < radius * radius ? 1 : 0;
      ASSERT_EQ(found.size(), brute) << "radius " << radius;
    }
  }
  // the in-place update (the store permuted to cell order, small moves) against a full build
  std::vector<Vec<D>> p2(pos.size());
  std::vector<double> l2(pos.size());
  std::vector<char> moving(pos.size());
  for (std::size_t k = 0; k < pos.size(); ++k) {
    p2[k] = pos[cl.sorted()[k]];
    l2[k] = level[cl.sorted()[k]];
    moving[k] = cl.sorted()[k] < n_moving;
  }
  cl.adopt_permutation();
  std::uniform_real_distribution<double> u(-0.3 * h_fine, 0.3 * h_fine);
  for (std::size_t k = 0; k < p2.size(); ++k)
    if (moving[k])  // (the anchors stay)
      for (int d = 0; d < D; ++d) p2[k][d] = std::clamp(p2[k][d] + u(rng), 0.0, d == 0 ? (l2[k] > 0.0 ? 0.99 : 2.0) : 1.0);
  cl.build(p2, p2.size(), R, true, 0.0, l2.data(), 2);
  EXPECT_TRUE(cl.updated());
  CellList<D> full;
  full.build(p2, p2.size(), R, false, 0.0, l2.data(), 2);
  ASSERT_EQ(cl.cell_count(), full.cell_count());
  for (std::size_t k = 0; k < p2.size(); ++k) ASSERT_EQ(cl.sorted()[k], full.sorted()[k]) << k;
  for (std::size_t c = 0; c < cl.cell_count(); ++c) ASSERT_EQ(cl.cell_begin(c), full.cell_begin(c)) << c;
}
TEST(CellList, LevelGridsHoldEveryPair2D) { level_grids_hold_every_pair<2>(4000, 0.006, 8); }
TEST(CellList, LevelGridsHoldEveryPair3D) { level_grids_hold_every_pair<3>(8000, 0.02, 9); }

// Two cells of one colour (half_colour) have disjoint half stencils: half[c] the entries of occupied cell c's half.
template <int D, class Set>
void expect_colours_disjoint(const CellList<D>& cl, const std::vector<Set>& half) {
  std::vector<std::vector<std::uint32_t>> by(static_cast<std::size_t>(cl.half_colours()));
  for (const std::uint32_t c : cl.occupied()) by[static_cast<std::size_t>(cl.half_colour(c))].push_back(c);
  for (const auto& list : by) {
    std::set<std::size_t> seen;
    for (const std::uint32_t c : list)
      for (const auto k : half[c]) EXPECT_TRUE(seen.insert(k).second) << "colour shares entry " << k;
  }
}

// The half stencils of a pass that visits each pair once (CellList::half_ranges): a cell's half and other ranges
// together are its whole stencil, for two cells within each other's stencil exactly one holds the other in its half
// (the cell itself is in its own half), and two cells of one colour (half_colour) have disjoint half stencils.
template <int D>
void half_stencils_cover_each_pair_once(int n, double radius, unsigned seed) {
  std::mt19937 rng(seed);
  CellList<D> cl;
  {
    const auto pos = random_positions<D>(n, rng);  // (the list keeps no reference to them)
    cl.build(pos, pos.size(), radius);
  }
  ASSERT_TRUE(cl.uniform_stencil());
  const auto& occ = cl.occupied();
  const std::size_t ncell = cl.cell_count();
  auto cells_of = [&](std::uint32_t (*rg)[2], int nr) {  // the cells (by their first entry) the ranges cover
    std::set<std::size_t> s;
    for (int r = 0; r < nr; ++r)
      for (std::uint32_t k = rg[r][0]; k < rg[r][1]; ++k) s.insert(k);
    return s;
  };
  std::vector<std::set<std::size_t>> half(ncell);
  std::uint32_t h[CellList<D>::kMaxRanges][2], o[CellList<D>::kMaxRanges][2], f[CellList<D>::kMaxRanges][2];
  for (const std::uint32_t c : occ) {
    int no = 0;
    const int nh = cl.half_ranges(c, h, o, no);
    const auto hs = cells_of(h, nh), os = cells_of(o, no), fs = cells_of(f, cl.cell_ranges(c, f));
    for (const std::size_t k : hs) EXPECT_EQ(os.count(k), 0u);  // disjoint halves
    std::set<std::size_t> both = hs;
    both.insert(os.begin(), os.end());
    EXPECT_EQ(both, fs) << "cell " << c;
    EXPECT_EQ(h[0][0], cl.cell_begin(c));  // the cell itself first
    half[c] = hs;
  }
  // each pair of particles within each other's stencil: in exactly one of the two halves (entries are store indices)
  std::vector<std::size_t> cell_of(static_cast<std::size_t>(n));
  for (const std::uint32_t c : occ)
    for (std::uint32_t k = cl.cell_begin(c); k < cl.cell_end(c); ++k) cell_of[k] = c;
  std::size_t pairs = 0;
  for (const std::uint32_t c : occ)
    for (std::uint32_t k = cl.cell_begin(c); k < cl.cell_end(c); ++k)
      for (const std::size_t j : half[c]) {
        if (cell_of[j] == c) continue;
        EXPECT_EQ(half[cell_of[j]].count(k), 0u) << "pair " << k << ", " << j << " in both halves";
        ++pairs;
      }
  EXPECT_GT(pairs, 0u);
  expect_colours_disjoint(cl, half);
}
TEST(CellList, HalfStencilsCoverEachPairOnce2D) { half_stencils_cover_each_pair_once<2>(2000, 0.07, 10); }
TEST(CellList, HalfStencilsCoverEachPairOnce3D) { half_stencils_cover_each_pair_once<3>(3000, 0.12, 11); }

// The half stencils on one grid per level (CellList::grid_half_ranges; h fine for x < 1, ramping to coarse, as
// above): after set_reach, each pair within kappa (h_i + h_j)/2 lies in both of its cells' whole stencils (half,
// other and cross); a pair of one grid in exactly one of its two cells' halves (the cell itself first in its own),
// a pair between grids in no half (it is visited from both ends); some cells reach two of their grid's cells, and
// the cells of one colour (half_colour) have disjoint halves.
template <int D>
void level_grid_half_stencils_cover_each_pair_once(int n, double h_fine, unsigned seed) {
  std::mt19937 rng(seed);
  const std::vector<Vec<D>> pos = random_positions<D>(n, rng);
  const double kappa = 2.0, h_coarse = 2.0 * h_fine;
  std::vector<double> h(pos.size()), level(pos.size());
  for (std::size_t i = 0; i < pos.size(); ++i) {
    level[i] = pos[i][0] < 1.0 ? 1.0 : 0.0;
    h[i] = level[i] == 0.0 ? h_coarse : h_fine + (h_coarse - h_fine) * std::clamp((pos[i][0] - 0.8) / 0.2, 0.0, 1.0);
  }
  CellList<D> cl;
  cl.build(pos, pos.size(), kappa * h_coarse, false, 0.0, level.data(), 2);
  ASSERT_TRUE(cl.level_grids());
  EXPECT_FALSE(cl.pair_once());  // (the stencils need each cell's reach)
  cl.set_reach([&](std::uint32_t j) { return h[j]; }, kappa);
  ASSERT_TRUE(cl.pair_once());
  const auto& occ = cl.occupied();
  const std::size_t np = pos.size();
  std::vector<std::size_t> cell_of(np);  // by store entry
  for (const std::uint32_t c : occ)
    for (std::uint32_t k = cl.cell_begin(c); k < cl.cell_end(c); ++k) cell_of[k] = c;
  std::vector<std::set<std::uint32_t>> half(cl.cell_count()), rest(cl.cell_count());
  std::uint32_t hr[CellList<D>::kMaxRanges][2], orr[CellList<D>::kMaxRanges][2], cr[CellList<D>::kMaxRanges][2];
  int wide = 0;
  for (const std::uint32_t c : occ) {
    int no = 0, nc = 0;
    const int nh = cl.grid_half_ranges(c, hr, orr, no, cr, nc);
    ASSERT_GT(nh, 0);
    EXPECT_EQ(hr[0][0], cl.cell_begin(c));  // the cell itself first
    for (int r = 0; r < nh; ++r)
      for (std::uint32_t k = hr[r][0]; k < hr[r][1]; ++k) half[c].insert(k);
    for (auto [rg, nr] : {std::pair{orr, no}, std::pair{cr, nc}})
      for (int r = 0; r < nr; ++r)
        for (std::uint32_t k = rg[r][0]; k < rg[r][1]; ++k) EXPECT_TRUE(rest[c].insert(k).second && !half[c].count(k)) << "entry twice";
    wide += cl.reach(c) > 1 ? 1 : 0;
  }
  EXPECT_GT(wide, 0);
  const auto& sorted = cl.sorted();
  std::size_t same = 0, between = 0;
  for (std::uint32_t k = 0; k < np; ++k)
    for (std::uint32_t m = k + 1; m < np; ++m) {
      const std::uint32_t i = sorted[k], j = sorted[m];
      const double s = 0.5 * kappa * (h[i] + h[j]);
      if (dot(pos[i] - pos[j], pos[i] - pos[j]) >= s * s) continue;
      const std::size_t ck = cell_of[k], cm = cell_of[m];
      ASSERT_TRUE(half[ck].count(m) + rest[ck].count(m) == 1 && half[cm].count(k) + rest[cm].count(k) == 1) << "pair missed";
      if (level[i] == level[j]) {
        if (ck == cm) continue;
        EXPECT_EQ(half[ck].count(m) + half[cm].count(k), 1u) << "pair " << k << ", " << m;
        ++same;
      } else {
        EXPECT_EQ(half[ck].count(m) + half[cm].count(k), 0u) << "pair between levels in a half";
        ++between;
      }
    }
  EXPECT_GT(same, 0u);
  EXPECT_GT(between, 0u);
  expect_colours_disjoint(cl, half);
}
TEST(CellList, LevelGridHalfStencilsCoverEachPairOnce2D) { level_grid_half_stencils_cover_each_pair_once<2>(3000, 0.006, 12); }
TEST(CellList, LevelGridHalfStencilsCoverEachPairOnce3D) { level_grid_half_stencils_cover_each_pair_once<3>(5000, 0.02, 13); }
