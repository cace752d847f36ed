// One cell grid per resolution level (docs/numerics.md §14, `resolution.cells: levels`): the cell
// list's cells are numbered grid by grid (level 0's first), each level's particles binned in
// cells as wide as its own support, so that the store, sorted by cell, holds each level's
// particles together and a fine particle scans fine cells for its fine neighbours and coarse
// cells for its coarse ones (the multilevel cell linked list SPHinXsys builds for adaptive
// resolution). CellList owns one of these; this file holds the grids' geometry and stencils.
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

#include "sphflume/core/vec.hpp"

namespace sph {

/// This thread's static share [i0, i1) of [0, n) (i0 = 0, i1 = n outside a parallel region).
inline void thread_share(std::size_t n, std::size_t& i0, std::size_t& i1) {
#ifdef _OPENMP
  const std::size_t t = static_cast<std::size_t>(omp_get_thread_num()), nt = static_cast<std::size_t>(omp_get_num_threads());
  i0 = n * t / nt;
  i1 = n * (t + 1) / nt;
#else
  i0 = 0;
  i1 = n;
#endif
}

template <int D>
class LevelGrids {
 public:
  using V = Vec<D>;
  static constexpr int kMaxGrids = 4;  // levels 0..3 (`resolution` regions refine up to level 3)
  struct Grid {
    double side = 1, inv = 1;  // cell side: level 0's side / 2^level
    V o{};                     // origin: a multiple of level 0's cell side
    long long O[D]{};          // the same in level-0 cells
    int dims[D]{};             // cells along each axis (0: the level holds no particle)
    std::uint32_t off = 0;     // the global number of its first cell
    std::size_t cells() const {
      std::size_t c = 1;
      for (int d = 0; d < D; ++d) c *= static_cast<std::size_t>(dims[d]);
      return c;
    }
  };

  int count() const { return n_; }
  const Grid& grid(int g) const { return g_[g]; }

  /// Lay out `grids` grids (level 0's cell side `side0`, level g's side0 / 2^g) over the
  /// particles [0, n) at pos, particle i on grid clamp(level[i], 0, grids - 1): each grid covers
  /// its own particles' bounding box, snapped outwards to multiples of level 0's cell side (so
  /// that the layout changes only when a level's particles cross such a line, and the cell list
  /// can update in place). Returns the total number of cells.
  std::size_t layout(const std::vector<V>& pos, std::size_t n, const double* level, double side0, int grids) {
    if (grids < 1 || grids > kMaxGrids) throw std::logic_error("cell grids: 1 to 4 levels");
    n_ = grids;
    std::array<V, kMaxGrids> mn, mx;
    for (int g = 0; g < grids; ++g)
      for (int d = 0; d < D; ++d) { mn[g][d] = std::numeric_limits<double>::max(); mx[g][d] = -std::numeric_limits<double>::max(); }
#pragma omp parallel if (n > 4096)
    {
      std::array<V, kMaxGrids> a = mn, b = mx;
      std::size_t i0 = 0, i1 = n;
      thread_share(n, i0, i1);
      const double* __restrict p = pos.data()->c.data();
      level_runs(level, i0, i1, [&](std::size_t i, std::size_t j, int g) {
        for (int d = 0; d < D; ++d) {
          double lo = a[g][d], hi = b[g][d];
          for (std::size_t k = i; k < j; ++k) {
            lo = std::min(lo, p[D * k + d]);
            hi = std::max(hi, p[D * k + d]);
          }
          a[g][d] = lo;
          b[g][d] = hi;
        }
      });
#pragma omp critical(sphflume_cell_grids)
      for (int g = 0; g < grids; ++g)
        for (int d = 0; d < D; ++d) { mn[g][d] = std::min(mn[g][d], a[g][d]); mx[g][d] = std::max(mx[g][d], b[g][d]); }
    }
    std::size_t total = 0;
    const double inv0 = 1.0 / side0;
    for (int g = 0; g < grids; ++g) {
      Grid& G = g_[g];
      G.side = side0 / double(1 << g);  // (exact: a power of two)
      G.inv = 1.0 / G.side;
      G.off = static_cast<std::uint32_t>(total);
      const bool empty = !(mn[g][0] <= mx[g][0]);
      for (int d = 0; d < D; ++d) {
        if (empty) { G.o[d] = 0.0; G.O[d] = 0; G.dims[d] = 0; continue; }
        const double k0 = std::floor(mn[g][d] * inv0);
        if (!(std::abs(k0) < 1.0e15)) throw std::runtime_error("cell list: a particle too far from the origin");
        G.O[d] = static_cast<long long>(k0);
        G.o[d] = k0 * side0;
        const double span = (mx[g][d] - G.o[d]) * inv0;
        if (!(span < 4.0e6)) throw std::runtime_error("cell list: particles spread over too many cells");
        G.dims[d] = (static_cast<int>(span) + 1) << g;
      }
      total += empty ? 0 : G.cells();
      if (total > (std::size_t(1) << 31)) throw std::runtime_error("cell list: too many cells (particles flew apart?)");
    }
    return total;
  }
  /// The layout alone (to tell whether a new layout is the same: the list then updates in place).
  struct Layout {
    int n = 0;
    Grid g[kMaxGrids];
  };
  Layout current() const {
    Layout l;
    l.n = n_;
    for (int g = 0; g < n_; ++g) l.g[g] = g_[g];
    return l;
  }
  bool same_as(const Layout& o) const {
    if (n_ != o.n) return false;
    for (int g = 0; g < n_; ++g)
      for (int d = 0; d < D; ++d)
        if (g_[g].o[d] != o.g[g].o[d] || g_[g].dims[d] != o.g[g].dims[d] || g_[g].side != o.g[g].side) return false;
    return true;
  }
  int grid_of_level(double level) const { return std::clamp(static_cast<int>(level), 0, n_ - 1); }
  /// fn(i, j, g) for each run [i, j) of particles of one level within [i0, i1), g its grid (the store sorted by
  /// cell holds each level's particles together: a few long runs).
  template <class Fn>
  void level_runs(const double* level, std::size_t i0, std::size_t i1, Fn&& fn) const {
    for (std::size_t i = i0; i < i1;) {
      const double l = level[i];
      std::size_t j = i + 1;
      while (j < i1 && level[j] == l) ++j;
      fn(i, j, grid_of_level(l));
      i = j;
    }
  }

  /// The global cells of positions [i0, i1) on grid g, into out[i0, i1).
  void index_run(const std::vector<V>& pos, std::size_t i0, std::size_t i1, int g, std::uint32_t* __restrict out) const {
    const Grid& G = g_[g];
    const double* __restrict p = pos.data()->c.data();
    const double inv = G.inv;
    int top[D];
    double o[D];
    for (int d = 0; d < D; ++d) { top[d] = std::max(G.dims[d] - 1, 0); o[d] = G.o[d]; }
    const std::uint32_t off = G.off;
    const std::uint32_t nx = static_cast<std::uint32_t>(G.dims[0]), nxy = nx * static_cast<std::uint32_t>(G.dims[1]);
    for (std::size_t i = i0; i < i1; ++i) {
      std::uint32_t idx = off;
      for (int d = 0; d < D; ++d) {
        const int c = std::clamp(static_cast<int>((p[D * i + d] - o[d]) * inv), 0, top[d]);
        idx += static_cast<std::uint32_t>(c) * (d == 0 ? 1u : d == 1 ? nx : nxy);
      }
      out[i] = idx;
    }
  }
  /// The grid of global cell `cell` and its coordinates there.
  int locate(std::size_t cell, int* c) const {
    int g = n_ - 1;
    while (g > 0 && cell < g_[g].off) --g;
    std::size_t k = cell - g_[g].off;
    for (int d = 0; d < D; ++d) {
      c[d] = static_cast<int>(k % static_cast<std::size_t>(g_[g].dims[d]));
      k /= static_cast<std::size_t>(g_[g].dims[d]);
    }
    return g;
  }

  /// The cells of every grid within r of point x, row(first, end cell) for each row's run (the
  /// rows of the block of cells within r along each axis, trimmed to the cells within r).
  template <class Row>
  void point_rows(const V& x, double r, Row&& row) const {
    constexpr int kMaxSpan = 256;
    for (int g = 0; g < n_; ++g) {
      const Grid& G = g_[g];
      if (G.dims[0] == 0) continue;
      int l[D], u[D];
      bool any = true;
      double gap[D][kMaxSpan];
      for (int d = 0; d < D && any; ++d) {
        const double lo = std::floor((x[d] - r - G.o[d]) * G.inv), hi = std::ceil((x[d] + r - G.o[d]) * G.inv) - 1.0;
        l[d] = static_cast<int>(std::max(lo, 0.0));
        u[d] = static_cast<int>(std::min(hi, double(G.dims[d] - 1)));
        any = l[d] <= u[d];
        if (!any) break;
        if (u[d] - l[d] >= kMaxSpan) throw std::logic_error("cell grids: a query wider than 256 cells");
        for (int k = l[d]; k <= u[d]; ++k) {
          const double c0 = G.o[d] + k * G.side, q = std::max({0.0, c0 - x[d], x[d] - c0 - G.side});
          gap[d][k - l[d]] = q * q;
        }
      }
      if (!any) continue;
      const double r2 = r * r;
      const int z0 = D == 3 ? l[D - 1] : 0, z1 = D == 3 ? u[D - 1] : 0;
      for (int z = z0; z <= z1; ++z)
        for (int y = l[1]; y <= u[1]; ++y) {
          const double gyz = (D == 3 ? gap[D - 1][z - z0] : 0.0) + gap[1][y - l[1]];
          int first = -1, last = -1;
          for (int xk = l[0]; xk <= u[0]; ++xk)
            if (gyz + gap[0][xk - l[0]] < r2) {
              if (first < 0) first = xk;
              last = xk;
            }
          if (first < 0) continue;
          const std::uint32_t rowk = G.off + static_cast<std::uint32_t>((static_cast<std::size_t>(z) * G.dims[1] + y) * G.dims[0]);
          row(rowk + static_cast<std::uint32_t>(first), rowk + static_cast<std::uint32_t>(last) + 1);
        }
    }
  }
  /// The stencil of global cell `cell` (on grid g, coordinates c): on every grid g' the block of
  /// cells within w[g'] cells of g' around it, row(first, end cell) for each row of the block.
  /// The grids share level 0's lattice (their origins are whole level-0 cells, their sides level
  /// 0's / 2^level), so the block is integer arithmetic: on a coarser (or the same) grid the cell
  /// holding cell c, ±w; on a finer one the cells covering c's, w more on each side. The caller
  /// picks w so that the block holds every cell within its reach (CellList::grid_rows).
  template <class Row>
  void rows(std::size_t cell, const int* w, Row&& row) const {
    int c[D];
    const int g = locate(cell, c);
    for (int q = 0; q < n_; ++q) {
      const Grid& G = g_[q];
      if (G.dims[0] == 0) continue;
      int l[D], u[D];
      bool any = true;
      for (int d = 0; d < D && any; ++d) {
        const long long a = (g_[g].O[d] << g) + c[d], base = G.O[d] << q;  // (absolute, in cells of g and of q)
        long long lo, hi;
        if (q <= g) {
          const long long C = a >> (g - q);  // (floor: arithmetic shift)
          lo = C - w[q];
          hi = C + w[q];
        } else {
          lo = (a << (q - g)) - w[q];
          hi = ((a + 1) << (q - g)) - 1 + w[q];
        }
        lo = std::max(lo - base, 0LL);
        hi = std::min(hi - base, static_cast<long long>(G.dims[d] - 1));
        any = lo <= hi;
        l[d] = static_cast<int>(lo);
        u[d] = static_cast<int>(hi);
      }
      if (!any) continue;
      const int z0 = D == 3 ? l[D - 1] : 0, z1 = D == 3 ? u[D - 1] : 0;
      for (int z = z0; z <= z1; ++z)
        for (int y = l[1]; y <= u[1]; ++y) {
          const std::uint32_t rowk = G.off + static_cast<std::uint32_t>((static_cast<std::size_t>(z) * G.dims[1] + y) * G.dims[0]);
          row(rowk + static_cast<std::uint32_t>(l[0]), rowk + static_cast<std::uint32_t>(u[0]) + 1);
        }
    }
  }
  /// The stencils of a pass that visits each pair once (CellList::grid_half_ranges): cell `cell`'s block within ±r
  /// cells on its own grid, split into `half`, the cell itself first and then the cells after it in store order (its
  /// row to its right, the rows above, in 3D the planes above) that take(global cell, Chebyshev distance in cells)
  /// admits, and `other`, the cells before it; and every other grid's rows of rows() with widths w into `cross`.
  /// Each callback gets one run (first, end) of global cells.
  template <class Take, class Half, class Other, class Cross>
  void half_rows(std::size_t cell, int r, const int* w, Take&& take, Half&& half, Other&& other, Cross&& cross) const {
    int c[D];
    const int g = locate(cell, c);
    const Grid& G = g_[g];
    auto row_of = [&](int z, int y) {
      return G.off + static_cast<std::uint32_t>((static_cast<std::size_t>(z) * G.dims[1] + y) * G.dims[0]);
    };
    const int zc = D == 3 ? c[D - 1] : 0;
    const int x0 = std::max(c[0] - r, 0), x1 = std::min(c[0] + r, G.dims[0] - 1);
    const int y0 = std::max(c[1] - r, 0), y1 = std::min(c[1] + r, G.dims[1] - 1);
    const int z0 = D == 3 ? std::max(zc - r, 0) : 0, z1 = D == 3 ? std::min(zc + r, G.dims[D - 1] - 1) : 0;
    auto runs = [&](int z, int y, int xa, int xb) {  // the runs of taken cells of one row
      const std::uint32_t row = row_of(z, y);
      const int gyz = std::max(std::abs(y - c[1]), std::abs(z - zc));
      int run = -1;
      for (int x = xa; x <= xb + 1; ++x) {
        const bool t = x <= xb && take(row + static_cast<std::uint32_t>(x), std::max(gyz, std::abs(x - c[0])));
        if (t && run < 0) run = x;
        if (!t && run >= 0) {
          half(row + static_cast<std::uint32_t>(run), row + static_cast<std::uint32_t>(x));
          run = -1;
        }
      }
    };
    runs(zc, c[1], c[0], x1);
    for (int y = c[1] + 1; y <= y1; ++y) runs(zc, y, x0, x1);
    for (int z = zc + 1; z <= z1; ++z)
      for (int y = y0; y <= y1; ++y) runs(z, y, x0, x1);
    for (int z = z0; z < zc; ++z)
      for (int y = y0; y <= y1; ++y) other(row_of(z, y) + static_cast<std::uint32_t>(x0), row_of(z, y) + static_cast<std::uint32_t>(x1) + 1);
    for (int y = y0; y < c[1]; ++y) other(row_of(zc, y) + static_cast<std::uint32_t>(x0), row_of(zc, y) + static_cast<std::uint32_t>(x1) + 1);
    if (c[0] > x0) other(row_of(zc, c[1]) + static_cast<std::uint32_t>(x0), row_of(zc, c[1]) + static_cast<std::uint32_t>(c[0]));
    const std::size_t end = G.off + G.cells();
    rows(cell, w, [&](std::uint32_t k0, std::uint32_t k1) {
      if (k0 < G.off || k0 >= end) cross(k0, k1);
    });
  }
  /// The colour of cell `cell` for half_rows' passes, its grid's half stencils at most ±R[grid] wide: two cells of
  /// one colour and one grid have disjoint half blocks (the uniform grid's colouring, CellList::half_colour, per
  /// grid); cells of different grids write into different particles (a pass writes only into its own grid's).
  int half_colour(std::size_t cell, const int* R) const {
    int c[D];
    const int g = locate(cell, c);
    const int w = 2 * R[g] + 1;
    if constexpr (D == 2) return c[0] % w + w * (c[1] % (R[g] + 1));
    else return c[0] % w + w * (c[1] % w + w * (c[2] % (R[g] + 1)));
  }
  int half_colours(const int* R) const {
    int n = 1;
    for (int g = 0; g < n_; ++g) {
      const int w = 2 * R[g] + 1;
      n = std::max(n, D == 2 ? w * (R[g] + 1) : w * w * (R[g] + 1));
    }
    return n;
  }

  /// Each occupied cell's own-grid reach into reach[cell] (cells of its grid), from hcell (each
  /// cell's largest h): ceil(kappa (h_max of the cell + h_max of the 3^D level-0 lattice cells
  /// around it) / (2 side)), the latter from each lattice cell's largest h (the window covers
  /// ±2^g cells of grid g, beyond which the grid's largest h is taken); between grids, the cells
  /// within kappa (h_max of the one grid + of the other) / 2. Pairs lie within kappa (h_a + h_b) / 2
  /// (h in float: a margin of 1e-7). widths() then reads them.
  void set_reach(const std::vector<float>& hcell, const std::vector<std::uint32_t>& occupied, double kappa,
                 std::vector<std::uint8_t>& reach, bool parallel) {
    const std::size_t nocc = occupied.size();
    const double f = kappa * 0.5 * (1.0 + 1.0e-7);
    for (int g = 0; g < kMaxGrids; ++g) hmax_[g] = 0.0;
    for (int g = 0; g < n_; ++g) {
      std::size_t nsum = 1;
      for (int d = 0; d < D; ++d) nsum *= static_cast<std::size_t>(g_[g].dims[d] >> g);
      hsum_[g].assign(g_[g].dims[0] == 0 ? 0 : nsum, 0.0f);
    }
    for (std::size_t oc = 0; oc < nocc; ++oc) {
      int c[D];
      const int g = locate(occupied[oc], c);
      const float hc = hcell[occupied[oc]];
      hmax_[g] = std::max(hmax_[g], double(hc));
      float& m = hsum_[g][lattice_index(g, c, 0, 0, 0)];
      m = std::max(m, hc);
    }
#pragma omp parallel for schedule(static) if (parallel)
    for (std::size_t oc = 0; oc < nocc; ++oc) {
      int c[D];
      const int g = locate(occupied[oc], c);
      double hw = hmax_[g];
      if (g > 0) {  // the 3^D level-0 lattice cells around
        int C[D], n0[D];
        for (int d = 0; d < D; ++d) { C[d] = c[d] >> g; n0[d] = g_[g].dims[d] >> g; }
        float m = 0.0f;
        const int z0 = D == 3 ? std::max(C[D - 1] - 1, 0) : 0, z1 = D == 3 ? std::min(C[D - 1] + 1, n0[D - 1] - 1) : 0;
        for (int z = z0; z <= z1; ++z)
          for (int y = std::max(C[1] - 1, 0); y <= std::min(C[1] + 1, n0[1] - 1); ++y)
            for (int x = std::max(C[0] - 1, 0); x <= std::min(C[0] + 1, n0[0] - 1); ++x)
              m = std::max(m, hsum_[g][(static_cast<std::size_t>(z) * n0[1] + y) * n0[0] + x]);
        hw = m;
      }
      const double hc = hcell[occupied[oc]];
      int r = static_cast<int>(std::ceil(f * (hc + hw) * g_[g].inv));
      if (r > (1 << g)) r = static_cast<int>(std::ceil(f * (hc + hmax_[g]) * g_[g].inv));  // (beyond the window)
      reach[occupied[oc]] = static_cast<std::uint8_t>(std::clamp(r, 1, 255));
    }
    for (int g = 0; g < kMaxGrids; ++g) rmax_[g] = 1;
    for (std::size_t oc = 0; oc < nocc; ++oc) {  // (each grid's widest reach: half_colour)
      int c[D];
      const int g = locate(occupied[oc], c);
      rmax_[g] = std::max(rmax_[g], static_cast<int>(reach[occupied[oc]]));
    }
    for (int g = 0; g < n_; ++g)
      for (int q = 0; q < n_; ++q) wpair_[g][q] = std::max(1, static_cast<int>(std::ceil(f * (hmax_[g] + hmax_[q]) * g_[q].inv)));
  }
  /// The half-widths w of cell `cell`'s block on every grid (rows()): its pairs' (radius 0: `own`
  /// on its own grid, from set_reach, set_reach's between grids) or every cell within radius.
  void widths(std::size_t cell, double radius, int own, int* w) const {
    if (radius > 0.0) {
      for (int q = 0; q < n_; ++q) w[q] = std::max(1, static_cast<int>(std::ceil(radius * g_[q].inv)));
      return;
    }
    int g = n_ - 1;
    while (g > 0 && cell < g_[g].off) --g;
    for (int q = 0; q < n_; ++q) w[q] = q == g ? own : wpair_[g][q];
  }
  /// Each grid's widest own-grid reach (set_reach), in cells of that grid.
  const int* reach_max() const { return rmax_; }
  std::size_t bytes() const {
    std::size_t b = 0;
    for (const auto& v : hsum_) b += v.capacity() * sizeof(float);
    return b;
  }

  /// The most rows one stencil can take: a level-0 cell's block with `reach` (at most level 0's
  /// support) on every grid (the cell list's range arrays must hold them).
  int max_rows(double reach) const {
    int rows = 0;
    for (int g = 0; g < n_; ++g) {
      const int w = (1 << g) + 2 * static_cast<int>(std::ceil(reach * g_[g].inv)) + 1;
      rows += D == 2 ? w : w * w;
    }
    return rows;
  }

 private:
  int n_ = 0;
  Grid g_[kMaxGrids];
  double hmax_[kMaxGrids] = {};                // each grid's largest h (set_reach)
  std::vector<float> hsum_[kMaxGrids];         // each grid's level-0 lattice cells' largest h (set_reach)
  int wpair_[kMaxGrids][kMaxGrids] = {};       // the cells between grids (set_reach)
  int rmax_[kMaxGrids] = {1, 1, 1, 1};          // each grid's widest own-grid reach (set_reach)

  /// The index of grid g's cell c's level-0 lattice cell (dx, dy, dz further) in hsum_[g].
  std::size_t lattice_index(int g, const int* c, int dx, int dy, int dz) const {
    const int off[3] = {dx, dy, dz};
    std::size_t idx = 0;
    for (int d = D - 1; d >= 0; --d) idx = idx * static_cast<std::size_t>(g_[g].dims[d] >> g) + static_cast<std::size_t>((c[d] >> g) + off[d]);
    return idx;
  }
};

}  // namespace sph
