// Cell-linked list: square (cubic) cells whose side is the kernel support, particle indices
// counting-sorted by cell. Also gives the cell-order permutation used to reorder the particle
// store for memory locality. Same template for 2D and 3D.
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <vector>
#ifdef _OPENMP
#include <omp.h>
#endif

#include "sphflume/core/cell_grids.hpp"
#include "sphflume/core/vec.hpp"

namespace sph {

template <int D>
class CellList {
 public:
  using V = Vec<D>;
  /// Cells have side radius / kReach and the stencil spans ±kReach cells. kReach = 1 (cells
  /// as wide as the kernel support, 3^D stencil): the vectorised pair loops copy a cell's
  /// candidates once and share them among its particles, so many particles per cell (9 in 2D
  /// at h/dx 1.5) beat a tighter stencil (kReach = 2: (5/2)^D instead of 3^D candidates, but
  /// 2.25 particles per cell): 1.6x faster in 2D, 1.2x in 3D, and 4-8x fewer cells in memory.
  static constexpr int kReach = 1;
  /// The widest stencil a list may use (resolution levels, docs/numerics.md §14): cells then as
  /// wide as the finest pairs' support (or half the largest), so that the coarse pairs need
  /// ±2 cells and the fine ones ±1 (reach(), set_reach()).
  static constexpr int kMaxReach = 2;

  /// Bin positions [0, n) for neighbour queries up to distance `radius` (the bounds and the
  /// cells in parallel; the same result for any thread count). `in_order`: the caller promises
  /// that positions [0, n) are the particles of the last build, in the order adopt_permutation()
  /// was told of (the store was permuted by sorted() and nothing was added, removed or moved
  /// since); then, with the same bounds, only the particles that changed cell are re-placed
  /// (update(): parallel, the same result as the full counting sort).
  ///
  /// `cell` > 0 (resolution levels): cells of that side instead (at least radius / kMaxReach);
  /// every cell's stencil then spans reach_for(radius) cells until set_reach() narrows it.
  ///
  /// `level` (resolution levels, `resolution.cells: levels`; docs/numerics.md §14): particle i's level for
  /// i < n, `grids` > 1 the number of levels: one grid of cells per level (core/cell_grids.hpp), level g's cells
  /// radius / 2^g wide (with a margin of 1e-6), numbered grid by grid; `cell` is then not used.
  void build(const std::vector<V>& pos, std::size_t n, double radius, bool in_order = false, double cell = 0.0,
             const double* level = nullptr, int grids = 1) {
    const bool multi_before = multi_;
    const auto grids_before = grids_.current();
    multi_ = level != nullptr && grids > 1;
    level_ = multi_ ? level : nullptr;
    build_radius_ = radius;
    if (multi_) cell = radius * (1.0 + 1.0e-6);
    if (cell <= 0.0) cell = radius / kReach;
    if (radius > cell * kMaxReach) throw std::logic_error("cell list: cells narrower than radius / kMaxReach");
    const bool same_cell = cell == cell_;
    const V lo_before = lo_;
    int dims_before[D];
    for (int d = 0; d < D; ++d) dims_before[d] = dims_[d];
    cell_ = cell;
    inv_cell_ = 1.0 / cell;
    reach_.clear();
    hcell_.clear();
    reach_max_ = reach_for(radius);
    V hi;
    for (int d = 0; d < D; ++d) { lo_[d] = std::numeric_limits<double>::max(); hi[d] = -std::numeric_limits<double>::max(); }
    double lo0 = lo_[0], lo1 = lo_[1], lo2 = lo_[D - 1], hi0 = hi[0], hi1 = hi[1], hi2 = hi[D - 1];
#pragma omp parallel for schedule(static) reduction(min : lo0, lo1, lo2) reduction(max : hi0, hi1, hi2) if (n > 4096)
    for (std::size_t i = 0; i < n; ++i) {
      lo0 = std::min(lo0, pos[i][0]); hi0 = std::max(hi0, pos[i][0]);
      lo1 = std::min(lo1, pos[i][1]); hi1 = std::max(hi1, pos[i][1]);
      lo2 = std::min(lo2, pos[i][D - 1]); hi2 = std::max(hi2, pos[i][D - 1]);
    }
    lo_[0] = lo0; lo_[1] = lo1; lo_[D - 1] = lo2;
    hi[0] = hi0; hi[1] = hi1; hi[D - 1] = hi2;
    std::size_t ncell = 1;
    for (int d = 0; d < D && !multi_; ++d) {
      if (n == 0) { lo_[d] = 0; hi[d] = 0; }
      if (!std::isfinite(lo_[d]) || !std::isfinite(hi[d]))
        throw std::runtime_error("cell list: non-finite particle position");
      const double span = (hi[d] - lo_[d]) * inv_cell_;
      if (span > 4.0e6) throw std::runtime_error("cell list: particles spread over too many cells");
      dims_[d] = static_cast<int>(span) + 1;
      ncell *= static_cast<std::size_t>(dims_[d]);
    }
    if (multi_) {
      for (int d = 0; d < D; ++d)
        if (!std::isfinite(lo_[d]) && n > 0) throw std::runtime_error("cell list: non-finite particle position");
      ncell = grids_.layout(pos, n, level_, cell, grids);
      if (grids_.max_rows(radius) > kMaxRanges) throw std::logic_error("cell list: more stencil rows than kMaxRanges");
    }
    if (ncell > (std::size_t(1) << 31)) throw std::runtime_error("cell list: too many cells (particles flew apart?)");
    bool same_grid = in_order && adopted_ && same_cell && n == cell_of_.size() && n > 0 && multi_ == multi_before &&
                     (!multi_ || grids_.same_as(grids_before));
    for (int d = 0; d < D && !multi_; ++d) same_grid = same_grid && lo_[d] == lo_before[d] && dims_[d] == dims_before[d];
    adopted_ = false;
    moved_ = 0;
    updated_ = same_grid;
    if (same_grid) { update(pos, n); return; }
    cell_of_.resize(n);
    cell_start_.assign(ncell + 1, 0);
    sorted_.resize(n);
    // the cell of each particle in parallel (the arithmetic); counting and placing stay
    // serial (two plain passes), so indices stay ascending inside a cell for any thread count
#pragma omp parallel if (n > 4096)
    {
      std::size_t i0 = 0, i1 = n;
      thread_share(n, i0, i1);
      keys(pos, i0, i1, cell_of_.data());
    }
    for (std::size_t i = 0; i < n; ++i) ++cell_start_[cell_of_[i]];
    // prefix sums give each cell's end; placing particles backwards while decrementing leaves
    // each cell's start and keeps indices ascending inside a cell (no extra array)
    occupied_.clear();  // (cell_start_[c] holds the count of cell c here)
    for (std::size_t c = 0; c < ncell; ++c)
      if (cell_start_[c] > 0) occupied_.push_back(static_cast<std::uint32_t>(c));
    for (std::size_t c = 0; c < ncell; ++c) cell_start_[c + 1] += cell_start_[c];
    for (std::size_t i = n; i-- > 0;) sorted_[--cell_start_[cell_of_[i]]] = static_cast<std::uint32_t>(i);
    bool ident = true;
#pragma omp parallel for schedule(static) reduction(&& : ident) if (n > 4096)
    for (std::size_t k = 0; k < n; ++k) ident = ident && sorted_[k] == k;
    identity_ = ident;
  }

  /// After the binned positions were permuted into cell order by sorted() (the caller moved
  /// particle sorted()[k] to index k), make the list describe the new order without rebinning:
  /// sorted() becomes the identity, so stencil ranges are plain index ranges.
  void adopt_permutation() {
    const std::size_t nc = cell_start_.empty() ? 0 : cell_start_.size() - 1;
#pragma omp parallel for schedule(static) if (sorted_.size() > 4096)
    for (std::size_t c = 0; c < nc; ++c)
      for (std::uint32_t k = cell_start_[c]; k < cell_start_[c + 1]; ++k) cell_of_[k] = static_cast<std::uint32_t>(c);
#pragma omp parallel for schedule(static) if (sorted_.size() > 4096)
    for (std::size_t k = 0; k < sorted_.size(); ++k) sorted_[k] = static_cast<std::uint32_t>(k);
    identity_ = true;
    adopted_ = true;
  }

  /// After a build that re-placed only the particles that changed cell (build's in_order), how
  /// many did; 0 after a full build. sorted() then keeps every other particle in its order, so
  /// the store can be re-sorted by moving runs (ParticleStore::permute_runs).
  std::size_t moved() const { return moved_; }
  /// Whether the last build was such an update (moved() may then be 0: nothing to re-sort).
  bool updated() const { return updated_; }
  /// Their old indices, ascending (moved() entries).
  const std::uint32_t* moved_from() const { return left_.data(); }
  /// Their old indices, then their new indices (2 moved() entries), in ascending new index.
  const std::uint32_t* moved_to() const { return arrive_.data(); }

  /// True when sorted() is the identity: the store is in cell order and ranges() are index
  /// ranges into the particle arrays themselves (the fast, vectorised pair loops use this).
  bool identity() const { return identity_; }

  /// Max number of ranges returned by ranges().
  /// (a row of a cell's own stencil may split into runs: at most kMaxReach + 1 per row)
  /// (one grid per level: one range per row of each grid's block, LevelGrids::max_rows, up to four levels)
  static constexpr int kMaxRanges = D == 2 ? 64 : 1024;
  /// Index ranges [begin, end) into sorted() that cover the particles within `radius` of x
  /// (default: the build radius; at most (2 reach + 1)^(D-1) ranges: cells adjacent along x are
  /// contiguous). Returns the number of ranges. For hot loops that want plain code instead of a
  /// callback.
  int ranges(const V& x, std::uint32_t (*out)[2], double radius = 0.0) const {
    if (multi_) {
      int n = 0;
      grids_.point_rows(x, radius > 0.0 ? radius : build_radius_, [&](std::uint32_t k0, std::uint32_t k1) {
        out[n][0] = cell_start_[k0];
        out[n][1] = cell_start_[k1];
        ++n;
      });
      return n;
    }
    int c[D];
    for (int d = 0; d < D; ++d) c[d] = coord(x, d);
    return stencil_ranges(c, out, radius > 0.0 ? reach_for(radius) : reach_max_);
  }
  /// The same ranges for every particle of cell `cell` (they share one stencil): by default the
  /// cell's own pairs' (reach()); `radius` > 0: every particle within radius of the cell.
  int cell_ranges(std::size_t cell, std::uint32_t (*out)[2], double radius = 0.0) const {
    if (multi_) {
      int n = 0;
      grid_rows(cell, radius, [&](std::uint32_t k0, std::uint32_t k1) {
        out[n][0] = cell_start_[k0];
        out[n][1] = cell_start_[k1];
        ++n;
      });
      return n;
    }
    const bool own = radius <= 0.0;
    const std::size_t self = cell;
    const int reach = own ? this->reach(cell) : reach_for(radius);
    int c[D];
    coords(cell, c);
    return stencil_ranges(c, out, reach, own ? static_cast<std::int64_t>(self) : -1);
  }
  /// Whether every cell's stencil is the same ±reach block of one grid (no levels' grids, no per-cell reach): the
  /// half stencils below apply.
  bool uniform_stencil() const { return !multi_ && reach_.empty(); }
  /// The half stencil of cell `cell` for passes that visit each pair once (Newton's third law; uniform_stencil()):
  /// `half` gets the ranges of the cells after it in store order within ±R (the cell itself first, then the cells
  /// on its row to its right, then the rows above, in 3D the planes above), `other` those of the cells before it;
  /// the two cover the cell's whole stencil. For two cells each within the other's stencil, exactly one holds the
  /// other in its half. Returns the number of `half` ranges; `n_other` the number of `other` ranges.
  int half_ranges(std::size_t cell, std::uint32_t (*half)[2], std::uint32_t (*other)[2], int& n_other) const {
    const int R = reach_max_;
    int c[D];
    coords(cell, c);
    int nh = 0, no = 0;
    const int x0 = std::max(c[0] - R, 0), x1 = std::min(c[0] + R, dims_[0] - 1);
    const int z0 = D == 3 ? std::max(c[D - 1] - R, 0) : 0, z1 = D == 3 ? std::min(c[D - 1] + R, dims_[D - 1] - 1) : 0;
    const int zc = D == 3 ? c[D - 1] : 0;
    auto put = [&](std::uint32_t (*out)[2], int& n, int z, int y, int xa, int xb) {
      if (xa > xb) return;
      const std::size_t row = (static_cast<std::size_t>(z) * dims_[1] + y) * dims_[0];
      out[n][0] = cell_start_[row + static_cast<std::size_t>(xa)];
      out[n][1] = cell_start_[row + static_cast<std::size_t>(xb) + 1];
      ++n;
    };
    const int y0 = std::max(c[1] - R, 0), y1 = std::min(c[1] + R, dims_[1] - 1);
    put(half, nh, zc, c[1], c[0], x1);  // the cell itself first, then its right-hand neighbours
    for (int y = c[1] + 1; y <= y1; ++y) put(half, nh, zc, y, x0, x1);
    for (int z = zc + 1; z <= z1; ++z)
      for (int y = y0; y <= y1; ++y) put(half, nh, z, y, x0, x1);
    for (int z = z0; z < zc; ++z)
      for (int y = y0; y <= y1; ++y) put(other, no, z, y, x0, x1);
    for (int y = y0; y < c[1]; ++y) put(other, no, zc, y, x0, x1);
    put(other, no, zc, c[1], x0, c[0] - 1);
    n_other = no;
    return nh;
  }
  /// Whether the passes that visit each pair once apply: uniform_stencil(), or one grid per level after set_reach
  /// (grid_half_ranges).
  bool pair_once() const { return uniform_stencil() || (multi_ && !hcell_.empty()); }
  /// half_ranges on one grid per level (after set_reach; docs/numerics.md §14): `half` the cell itself, then the
  /// cells after it on its grid within its reach that hold no particle or whose own reach reaches back (a pair
  /// lies within both cells' reach: each holds every pair of its particles); `other` the cells before it on its
  /// grid within its reach; `cross` the cells of the other grids its pairs reach (cell_ranges' rows). A pass writes
  /// into the particles of `half` only: a pair between grids is visited from both ends. Returns the number of
  /// `half` ranges. (Cells of reach over 2 take their half's rows whole.)
  int grid_half_ranges(std::size_t cell, std::uint32_t (*half)[2], std::uint32_t (*other)[2], int& n_other,
                       std::uint32_t (*cross)[2], int& n_cross) const {
    int w[LevelGrids<D>::kMaxGrids];
    grids_.widths(cell, 0.0, reach_[cell], w);
    int nh = 0, no = 0, nc = 0;
    auto put = [this](std::uint32_t (*out)[2], int& n) {
      return [this, out, &n](std::uint32_t k0, std::uint32_t k1) {
        out[n][0] = cell_start_[k0];
        out[n][1] = cell_start_[k1];
        ++n;
      };
    };
    // (beyond a reach of 2, whole rows: a cell left out would only have given zeros, and a row splits into at most
    // (r + 2) / 2 runs, which kMaxRanges holds for r <= 2 in 2D and 3D; deeper levels' cells reach further)
    const int r = reach_[cell];
    grids_.half_rows(
        cell, r, w,
        [this, r](std::uint32_t k, int gap) {
          return r > 2 || cell_start_[k] == cell_start_[k + 1] || gap <= static_cast<int>(reach_[k]);
        },
        put(half, nh), put(other, no), put(cross, nc));
    n_other = no;
    n_cross = nc;
    return nh;
  }
  /// The colour of a cell for passes that write into their half stencil (half_ranges): two cells of one colour
  /// have disjoint half stencils, so the cells of a colour may run concurrently and every particle receives its
  /// sums in the order of the colours, whatever the threads. 6 colours in 2D, 18 in 3D (R = 1). One grid per level:
  /// LevelGrids::half_colour.
  int half_colour(std::size_t cell) const {
    if (multi_) return grids_.half_colour(cell, grids_.reach_max());
    const int R = reach_max_, w = 2 * R + 1;
    int c[D];
    coords(cell, c);
    if constexpr (D == 2) return c[0] % w + w * (c[1] % (R + 1));
    else return c[0] % w + w * (c[1] % w + w * (c[2] % (R + 1)));
  }
  int half_colours() const {
    if (multi_) return grids_.half_colours(grids_.reach_max());
    const int R = reach_max_, w = 2 * R + 1;
    return D == 2 ? w * (R + 1) : w * w * (R + 1);
  }
  /// The stencil (± cells) that holds every particle within `radius` of any point of a cell.
  int reach_for(double radius) const {
    const double q = std::ceil(radius * inv_cell_);
    if (!(q <= kMaxReach)) throw std::logic_error("cell list: a query wider than the widest stencil");
    return std::max(1, static_cast<int>(q));
  }
  /// The stencil of cell `cell`'s pair passes: ±1 cell for one resolution, or what set_reach()
  /// found (the build radius's until then).
  int reach(std::size_t cell) const { return reach_.empty() ? reach_max_ : reach_[cell]; }
  /// Resolution levels (docs/numerics.md §14): narrow each occupied cell's stencil to the pairs
  /// of its particles, whose support is kappa (h_a + h_b) / 2 with h(j) particle j's smoothing
  /// length: ±ceil(kappa (max h in the cell + max h within the widest stencil) / (2 cell))
  /// cells. A fine particle far from the coarse ones then scans its own level's neighbourhood,
  /// not the coarse support's. Valid until the next build or until h changes (call it again).
  ///
  /// One grid per level (build's `level`): set_grid_reach.
  template <class H>
  void set_reach(H&& h, double kappa) {
    const std::size_t ncell = cell_count(), nocc = occupied_.size();
    if (multi_) {
      set_grid_reach(std::forward<H>(h), kappa);
      return;
    }
    if (reach_max_ <= 1) { reach_.clear(); hcell_.clear(); return; }
    cell_max_h(h);
    reach_.resize(ncell);
    pair_reach_ = kappa * 0.5 * inv_cell_ * (1.0 + 1.0e-7);
    const float* __restrict hc = hcell_.data();
#pragma omp parallel if (sorted_.size() > 4096)
    {
      const int R = reach_max_;
      // (the cell's side carries a margin of 1e-6 over the finest support: a fine cell's
      // ceil(1 - 1e-6) is 1; float h's rounding is below it)
      const double f = kappa * 0.5 * inv_cell_;
#pragma omp for schedule(static)
      for (std::size_t oc = 0; oc < nocc; ++oc) {
        const float win = window(hc, occupied_[oc], R, 0.0f, [](float a, float b) { return std::max(a, b); });
        const double q = std::ceil(f * (double(hc[occupied_[oc]]) + double(win)) * (1.0 + 1.0e-7));
        reach_[occupied_[oc]] = static_cast<std::uint8_t>(std::clamp(static_cast<int>(q), 1, R));
      }
    }
  }
  /// The cells that hold at least one particle, ascending (a tank is mostly empty cells: loops
  /// over these hand out work, not empty cells, to the threads).
  const std::vector<std::uint32_t>& occupied() const { return occupied_; }
  /// Number of cells, and the slice [begin, end) of sorted() that holds cell c.
  std::size_t cell_count() const { return cell_start_.empty() ? 0 : cell_start_.size() - 1; }
  std::uint32_t cell_begin(std::size_t c) const { return cell_start_[c]; }
  std::uint32_t cell_end(std::size_t c) const { return cell_start_[c + 1]; }

 private:
  /// The coordinates of cell `cell`.
  void coords(std::size_t cell, int* c) const {
    for (int d = 0; d < D; ++d) {
      c[d] = static_cast<int>(cell % static_cast<std::size_t>(dims_[d]));
      cell /= static_cast<std::size_t>(dims_[d]);
    }
  }
  /// op over v[] of the cells within ±R of cell `cell` (its window; init for none).
  template <class T, class Op>
  T window(const T* v, std::size_t cell, int R, T init, Op&& op) const {
    int c[D];
    coords(cell, c);
    T acc = init;
    const int z0 = D == 3 ? std::max(c[D - 1] - R, 0) : 0;
    const int z1 = D == 3 ? std::min(c[D - 1] + R, dims_[D - 1] - 1) : 0;
    for (int z = z0; z <= z1; ++z)
      for (int y = std::max(c[1] - R, 0); y <= std::min(c[1] + R, dims_[1] - 1); ++y) {
        const std::size_t row = (static_cast<std::size_t>(z) * dims_[1] + y) * dims_[0];
        for (int x = std::max(c[0] - R, 0); x <= std::min(c[0] + R, dims_[0] - 1); ++x) acc = op(acc, v[row + x]);
      }
    return acc;
  }
  /// The stencil ±R cells around cell coordinates c as ranges of sorted(). `self` >= 0 (a cell's
  /// own stencil after set_reach): of the cells beyond ±1 only those that may hold a pair of
  /// cell `self` are taken, those whose gap g (in cells) to it is below f (h_self + h_cell),
  /// f = kappa / (2 cell), with each cell's largest h (empty cells are taken: they join ranges
  /// and cost nothing). The ranges of one row are its runs of taken cells.
  int stencil_ranges(const int* c, std::uint32_t (*out)[2], int R, std::int64_t self = -1) const {
    int n = 0;
    const int x0 = std::max(c[0] - R, 0), x1 = std::min(c[0] + R, dims_[0] - 1);
    const int z0 = D == 3 ? std::max(c[D - 1] - R, 0) : 0, z1 = D == 3 ? std::min(c[D - 1] + R, dims_[D - 1] - 1) : 0;
    const bool filter = self >= 0 && R > 1 && !hcell_.empty();
    const double hs = filter ? double(hcell_[static_cast<std::size_t>(self)]) : 0.0;
    for (int z = z0; z <= z1; ++z)
      for (int y = std::max(c[1] - R, 0); y <= std::min(c[1] + R, dims_[1] - 1); ++y) {
        const std::size_t row = (static_cast<std::size_t>(z) * dims_[1] + y) * dims_[0];
        const int gz = D == 3 ? std::max(std::abs(z - c[D - 1]) - 1, 0) : 0, gy = std::max(std::abs(y - c[1]) - 1, 0);
        const int gyz = gy * gy + gz * gz;
        if (!filter) {
          out[n][0] = cell_start_[row + x0];
          out[n][1] = cell_start_[row + x1 + 1];
          ++n;
          continue;
        }
        int run = -1;  // the first cell of the open run
        for (int x = x0; x <= x1 + 1; ++x) {
          bool take = false;
          if (x <= x1) {
            const std::size_t k = row + static_cast<std::size_t>(x);
            const int gx = std::max(std::abs(x - c[0]) - 1, 0), g2 = gx * gx + gyz;
            take = g2 == 0 || cell_start_[k] == cell_start_[k + 1];
            if (!take) {
              const double s = pair_reach_ * (hs + double(hcell_[k]));
              take = double(g2) < s * s;
            }
          }
          if (take && run < 0) run = x;
          if (!take && run >= 0) {
            out[n][0] = cell_start_[row + static_cast<std::size_t>(run)];
            out[n][1] = cell_start_[row + static_cast<std::size_t>(x)];
            ++n;
            run = -1;
          }
        }
      }
    return n;
  }

 public:
  /// Calls f(j) for every particle j in the stencil around position x (candidates; the
  /// caller checks the distance). Covers every particle within `radius` (default: the build
  /// radius; at most that).
  template <class Fn>
  void for_candidates(const V& x, Fn&& f, double radius = 0.0) const {
    std::uint32_t rg[kMaxRanges][2];
    const int nr = ranges(x, rg, radius);
    for (int r = 0; r < nr; ++r)
      for (std::uint32_t k = rg[r][0]; k < rg[r][1]; ++k) f(sorted_[k]);
  }

  /// Calls f(j, r_ij, r2) for every j within `radius` of x (radius <= the build radius).
  template <class Fn>
  void for_neighbours(const std::vector<V>& pos, const V& x, double radius, Fn&& f) const {
    const double r2max = radius * radius;
    for_candidates(x, [&](std::uint32_t j) {
      const V rij = x - pos[j];
      const double r2 = dot(rij, rij);
      if (r2 < r2max) f(j, rij, r2);
    }, radius);
  }

  /// near[c] = 1 for every occupied cell whose stencil holds a particle i with pred(i): a
  /// particle in a cell with near == 0 has no such particle within the cell's pair reach (empty
  /// cells are left 0: no particle asks). The stencil: ±reach cells, by default each cell's own
  /// (reach()). O(occupied cells x 3^D), not O(cells): a tank is mostly empty cells.
  /// `radius` > 0: the cells within radius instead of each cell's own pairs. `ask`: only the
  /// cells c with ask(c) are marked (the others are left 0: a caller that reads near only where
  /// it has work spares the stencils of the rest).
  struct AnyCell {
    bool operator()(std::size_t) const { return true; }
  };
  template <class Pred, class Ask = AnyCell>
  void mark_near(std::vector<char>& near, Pred&& pred, double radius = 0.0, Ask&& ask = Ask{}) const {
    const int reach = radius > 0.0 && !multi_ ? reach_for(radius) : -1;
    const std::size_t ncell = cell_count();
    const std::size_t nocc = occupied_.size();
    tmp_.assign(ncell, 0);  // tmp_[c] = 1: cell c itself holds a particle with pred
    near.assign(ncell, 0);
    char* __restrict has = tmp_.data();
#pragma omp parallel if (sorted_.size() > 4096)
    {
#pragma omp for schedule(static)
      for (std::size_t oc = 0; oc < nocc; ++oc) {
        const std::uint32_t c = occupied_[oc];
        for (std::uint32_t k = cell_start_[c]; k < cell_start_[c + 1]; ++k)
          if (pred(static_cast<std::size_t>(sorted_[k]))) { has[c] = 1; break; }
      }
#pragma omp for schedule(static)
      for (std::size_t oc = 0; oc < nocc; ++oc) {
        if (!ask(static_cast<std::size_t>(occupied_[oc]))) continue;
        if (multi_) {  // (the cells of the stencil's rows: those between its taken cells hold no pair but are few)
          char any = 0;
          grid_rows(occupied_[oc], radius, [&](std::uint32_t k0, std::uint32_t k1) {
            for (std::uint32_t k = k0; k < k1 && !any; ++k) any = has[k];
          });
          near[occupied_[oc]] = any;
          continue;
        }
        const int R = reach >= 0 ? reach : this->reach(occupied_[oc]);
        const char any = window(has, occupied_[oc], R, char(0), [](char a, char b) { return char(a | b); });
        near[occupied_[oc]] = any;
      }
    }
  }
  /// near[c] = the OR of bits(i) over every particle i in the stencil of occupied cell c (bits: a few flags per
  /// particle, e.g. its level's bit: near then tells which levels a cell's stencil holds, in one sweep where
  /// mark_near would take one per level). The stencil as mark_near's with `radius`.
  template <class Bits>
  void or_near(std::vector<char>& near, Bits&& bits, double radius) const {
    const int reach = radius > 0.0 && !multi_ ? reach_for(radius) : -1;
    const std::size_t nocc = occupied_.size();
    tmp_.assign(cell_count(), 0);  // tmp_[c]: the OR over cell c's own particles
    near.assign(cell_count(), 0);
    char* __restrict has = tmp_.data();
#pragma omp parallel if (sorted_.size() > 4096)
    {
#pragma omp for schedule(static)
      for (std::size_t oc = 0; oc < nocc; ++oc) {
        const std::uint32_t c = occupied_[oc];
        char b = 0;
        for (std::uint32_t k = cell_start_[c]; k < cell_start_[c + 1]; ++k) b = static_cast<char>(b | bits(static_cast<std::size_t>(sorted_[k])));
        has[c] = b;
      }
#pragma omp for schedule(static)
      for (std::size_t oc = 0; oc < nocc; ++oc) {
        const std::uint32_t c = occupied_[oc];
        if (multi_) {
          char any = 0;
          grid_rows(c, radius, [&](std::uint32_t k0, std::uint32_t k1) {
            for (std::uint32_t k = k0; k < k1; ++k) any = static_cast<char>(any | has[k]);
          });
          near[c] = any;
          continue;
        }
        const int R = reach >= 0 ? reach : this->reach(c);
        near[c] = window(has, c, R, char(0), [](char a, char b) { return char(a | b); });
      }
    }
  }
  /// Cell of particle i (as binned by the last build).
  std::uint32_t cell_of(std::size_t i) const { return cell_of_[i]; }

  /// Particle indices sorted by cell (cell-major order).
  const std::vector<std::uint32_t>& sorted() const { return sorted_; }
  std::size_t bytes() const {
    std::size_t b = cell_of_.capacity() * 4 + sorted_.capacity() * 4 + cell_start_.capacity() * 4 + occupied_.capacity() * 4 +
                    reach_.capacity() + hcell_.capacity() * 4 +
                    tmp_.capacity() + sweep_work_.capacity() * 8 + moved_in_.capacity() * sizeof(Move) +
                    (moved_out_.capacity() + left_.capacity() + arrive_.capacity()) * 4;
    for (const auto& m : found_) b += m.capacity() * sizeof(Move);
    b += grids_.bytes();
    return b;
  }
  double cell_size() const { return cell_; }
  /// Whether the cells are one grid per level (build's `level`).
  bool level_grids() const { return multi_; }
  /// sweep_cells' scratch: the occupied cells' work and its running sums (kept with the list,
  /// so that bytes() counts it and no pass allocates it anew)
  std::vector<std::uint64_t>& sweep_work() const { return sweep_work_; }

 private:
  double cell_ = 1, inv_cell_ = 1;
  bool identity_ = false;
  V lo_{};
  int dims_[D]{};
  std::vector<std::uint32_t> cell_of_, cell_start_, sorted_, occupied_;
  int reach_max_ = kReach;            // the build radius's stencil
  bool multi_ = false;                // one grid per level (build's level)
  LevelGrids<D> grids_;               // their layout
  const double* level_ = nullptr;     // the levels during build()
  double build_radius_ = 0.0;         // build()'s radius (the widest query)
  std::vector<std::uint8_t> reach_;   // each cell's stencil (set_reach); empty: reach_max_
  std::vector<float> hcell_;          // each cell's largest h (set_reach; empty: no filter)
  double pair_reach_ = 0.0;           // kappa / (2 cell) with a margin of 1e-7 (set_reach)
  mutable std::vector<char> tmp_;  // mark_near's scratch (kept: no allocation per call)
  mutable std::vector<std::uint64_t> sweep_work_;
  bool adopted_ = false;  // the last build was followed by adopt_permutation()
  struct Move {
    std::uint32_t cell, index, from, to;  // new cell, index in the store, old cell, new index
  };
  std::vector<std::vector<Move>> found_;  // update(): each thread's movers, ascending index
  std::vector<Move> moved_in_;            // every mover, by (new cell, index)
  std::vector<std::uint32_t> moved_out_;  // their old cells, ascending (the store was in cell order)
  std::vector<std::uint32_t> left_, arrive_;  // see moved_from()
  std::size_t moved_ = 0;
  bool updated_ = false;  // the last build was update()


  /// build() for a store still in the order of the last build's cells (after
  /// adopt_permutation): cell_of_ holds each particle's old cell, cell_start_ the old starts.
  /// The stable counting sort's order is, cell by cell, the particles that stayed (ascending,
  /// as they are) merged by index with those that came in; each thread merges a range of cells
  /// at its offset (old start + movers in before it − movers out before it). Few particles
  /// change cell in a step, so this is a parallel pass over the store plus a sort of the movers.
  void update(const std::vector<V>& pos, std::size_t n);
  /// update()'s first half: each particle's new cell; those that changed cell (ascending
  /// index) into moved_in_, their cell_of_ updated; sorted_ left the identity. Returns how many.
  std::size_t collect_movers(const std::vector<V>& pos, std::size_t n, int nt);
  /// update()'s merge of the cells [ca, cb) (one thread's range; `last_end` the old start of
  /// cb): each cell's new start, and its particles (those that stayed merged by index with the
  /// m movers in moved_in_, sorted by cell) into sorted_.
  void merge_cells(std::uint32_t ca, std::uint32_t cb, std::uint32_t last_end, std::size_t m);

  std::vector<std::uint32_t> bounds_, ends_;

  int coord(const V& x, int d) const {
    int c = static_cast<int>((x[d] - lo_[d]) * inv_cell_);
    return std::clamp(c, 0, dims_[d] - 1);
  }
  /// The cells particles [i0, i1) are binned in, into out[i0, i1) (one grid per level: by runs of
  /// one level, as the store sorted by cell holds them).
  void keys(const std::vector<V>& pos, std::size_t i0, std::size_t i1, std::uint32_t* __restrict out) const {
    if (!multi_) {
      for (std::size_t i = i0; i < i1; ++i) out[i] = cell_index(pos[i]);
      return;
    }
    grids_.level_runs(level_, i0, i1, [&](std::size_t i, std::size_t j, int g) { grids_.index_run(pos, i, j, g, out); });
  }
  /// One grid per level: row(first cell, end cell) for each row of cell `cell`'s stencil
  /// (LevelGrids::rows with LevelGrids::widths: its pairs', or every cell within radius).
  template <class Row>
  void grid_rows(std::size_t cell, double radius, Row&& row) const {
    int w[LevelGrids<D>::kMaxGrids];
    const bool pairs = radius <= 0.0 && !hcell_.empty();
    grids_.widths(cell, pairs ? 0.0 : radius > 0.0 ? radius : build_radius_, pairs ? reach_[cell] : 0, w);
    grids_.rows(cell, w, row);
  }
  /// Each occupied cell's largest h(j) into hcell_ (0 for the empty cells).
  template <class H>
  void cell_max_h(H& h) {
    const std::size_t nocc = occupied_.size();
    hcell_.assign(cell_count(), 0.0f);
    float* __restrict hc = hcell_.data();
#pragma omp parallel for schedule(static) if (sorted_.size() > 4096)
    for (std::size_t oc = 0; oc < nocc; ++oc) {
      const std::uint32_t c = occupied_[oc];
      double m = 0.0;
      for (std::uint32_t k = cell_start_[c]; k < cell_start_[c + 1]; ++k) m = std::max(m, double(h(sorted_[k])));
      hc[c] = static_cast<float>(m);
    }
  }
  /// set_reach with one grid per level: each cell's largest h, then LevelGrids::set_reach.
  template <class H>
  void set_grid_reach(H&& h, double kappa) {
    cell_max_h(h);
    reach_.assign(cell_count(), 1);
    grids_.set_reach(hcell_, occupied_, kappa, reach_, sorted_.size() > 4096);
  }
  std::uint32_t cell_index(const V& x) const {
    std::size_t idx = 0;
    for (int d = D - 1; d >= 0; --d) idx = idx * dims_[d] + coord(x, d);
    return static_cast<std::uint32_t>(idx);
  }
};

}  // namespace sph

#include "sphflume/core/cell_list_update.hpp"  // CellList's in-place update (update, collect_movers, merge_cells)
