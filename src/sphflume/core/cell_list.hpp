// Cell-linked list: square (cubic) cells whose side is the kernel support, particle indices
// counting-sorted by cell. Also gives the cell-order permutation used to reorder the particle
// store for memory locality. Same template for 2D and 3D.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <vector>

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

  /// Bin positions [0, n) for neighbour queries up to distance `radius` (the bounds and the
  /// cells in parallel; the same result for any thread count).
  void build(const std::vector<V>& pos, std::size_t n, double radius) {
    const double cell = radius / kReach;
    cell_ = cell;
    inv_cell_ = 1.0 / cell;
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
    for (int d = 0; d < D; ++d) {
      if (n == 0) { lo_[d] = 0; hi[d] = 0; }
      if (!std::isfinite(lo_[d]) || !std::isfinite(hi[d]))
        throw std::runtime_error("cell list: non-finite particle position");
      const double span = (hi[d] - lo_[d]) * inv_cell_;
      if (span > 4.0e6) throw std::runtime_error("cell list: particles spread over too many cells");
      dims_[d] = static_cast<int>(span) + 1;
      ncell *= static_cast<std::size_t>(dims_[d]);
    }
    if (ncell > (std::size_t(1) << 31)) throw std::runtime_error("cell list: too many cells (particles flew apart?)");
    cell_of_.resize(n);
    cell_start_.assign(ncell + 1, 0);
    sorted_.resize(n);
    // the cell of each particle in parallel (the arithmetic); counting and placing stay
    // serial (two plain passes), so indices stay ascending inside a cell for any thread count
#pragma omp parallel for schedule(static) if (n > 4096)
    for (std::size_t i = 0; i < n; ++i) cell_of_[i] = cell_index(pos[i]);
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
  }

  /// True when sorted() is the identity: the store is in cell order and ranges() are index
  /// ranges into the particle arrays themselves (the fast, vectorised pair loops use this).
  bool identity() const { return identity_; }

  /// Max number of ranges returned by ranges().
  static constexpr int kMaxRanges = D == 2 ? 2 * kReach + 1 : (2 * kReach + 1) * (2 * kReach + 1);
  /// Index ranges [begin, end) into sorted() that cover the stencil around x (at most 3^(D-1)
  /// ranges: cells adjacent along x are contiguous). Returns the number of ranges. For hot
  /// loops that want plain code instead of a callback.
  int ranges(const V& x, std::uint32_t (*out)[2]) const {
    int c[D];
    for (int d = 0; d < D; ++d) c[d] = coord(x, d);
    return stencil_ranges(c, out);
  }
  /// The same ranges for every particle of cell `cell` (they share one stencil).
  int cell_ranges(std::size_t cell, std::uint32_t (*out)[2]) const {
    int c[D];
    for (int d = 0; d < D; ++d) {
      c[d] = static_cast<int>(cell % static_cast<std::size_t>(dims_[d]));
      cell /= static_cast<std::size_t>(dims_[d]);
    }
    return stencil_ranges(c, out);
  }
  /// The cells that hold at least one particle, ascending (a tank is mostly empty cells: loops
  /// over these hand out work, not empty cells, to the threads).
  const std::vector<std::uint32_t>& occupied() const { return occupied_; }
  /// Number of cells, and the slice [begin, end) of sorted() that holds cell c.
  std::size_t cell_count() const { return cell_start_.empty() ? 0 : cell_start_.size() - 1; }
  std::uint32_t cell_begin(std::size_t c) const { return cell_start_[c]; }
  std::uint32_t cell_end(std::size_t c) const { return cell_start_[c + 1]; }

 private:
  int stencil_ranges(const int* c, std::uint32_t (*out)[2]) const {
    int n = 0;
    const int x0 = std::max(c[0] - kReach, 0), x1 = std::min(c[0] + kReach, dims_[0] - 1);
    if constexpr (D == 2) {
      for (int z = std::max(c[1] - kReach, 0); z <= std::min(c[1] + kReach, dims_[1] - 1); ++z) {
        const std::size_t row = static_cast<std::size_t>(z) * dims_[0];
        out[n][0] = cell_start_[row + x0];
        out[n][1] = cell_start_[row + x1 + 1];
        ++n;
      }
    } else {
      for (int z = std::max(c[2] - kReach, 0); z <= std::min(c[2] + kReach, dims_[2] - 1); ++z)
        for (int y = std::max(c[1] - kReach, 0); y <= std::min(c[1] + kReach, dims_[1] - 1); ++y) {
          const std::size_t row = (static_cast<std::size_t>(z) * dims_[1] + y) * dims_[0];
          out[n][0] = cell_start_[row + x0];
          out[n][1] = cell_start_[row + x1 + 1];
          ++n;
        }
    }
    return n;
  }

 public:
  /// Calls f(j) for every particle j in the stencil around position x (candidates; the
  /// caller checks the distance). Covers every particle within the build radius.
  template <class Fn>
  void for_candidates(const V& x, Fn&& f) const {
    std::uint32_t rg[kMaxRanges][2];
    const int nr = ranges(x, rg);
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
    });
  }

  /// near[c] = 1 for every occupied cell whose stencil holds a particle i with pred(i): a
  /// particle in a cell with near == 0 has no such particle within the build radius (empty cells
  /// are left 0: no particle asks). O(occupied cells x 3^D), not O(cells): a tank is mostly
  /// empty cells.
  template <class Pred>
  void mark_near(std::vector<char>& near, Pred&& pred) const {
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
        std::size_t cell = occupied_[oc];
        int c[D];
        for (int d = 0; d < D; ++d) {
          c[d] = static_cast<int>(cell % static_cast<std::size_t>(dims_[d]));
          cell /= static_cast<std::size_t>(dims_[d]);
        }
        const int z0 = D == 3 ? std::max(c[D - 1] - kReach, 0) : 0;
        const int z1 = D == 3 ? std::min(c[D - 1] + kReach, dims_[D - 1] - 1) : 0;
        char any = 0;
        for (int z = z0; z <= z1; ++z)
          for (int y = std::max(c[1] - kReach, 0); y <= std::min(c[1] + kReach, dims_[1] - 1); ++y) {
            const std::size_t row = (static_cast<std::size_t>(z) * dims_[1] + y) * dims_[0];
            for (int x = std::max(c[0] - kReach, 0); x <= std::min(c[0] + kReach, dims_[0] - 1); ++x) any |= has[row + x];
          }
        near[occupied_[oc]] = any;
      }
    }
  }
  /// Cell of particle i (as binned by the last build).
  std::uint32_t cell_of(std::size_t i) const { return cell_of_[i]; }

  /// Particle indices sorted by cell (cell-major order).
  const std::vector<std::uint32_t>& sorted() const { return sorted_; }
  std::size_t bytes() const {
    return cell_of_.capacity() * 4 + sorted_.capacity() * 4 + cell_start_.capacity() * 4 + occupied_.capacity() * 4 + tmp_.capacity();
  }
  double cell_size() const { return cell_; }

 private:
  double cell_ = 1, inv_cell_ = 1;
  bool identity_ = false;
  V lo_{};
  int dims_[D]{};
  std::vector<std::uint32_t> cell_of_, cell_start_, sorted_, occupied_;
  mutable std::vector<char> tmp_;  // mark_near's scratch (kept: no allocation per call)

  int coord(const V& x, int d) const {
    int c = static_cast<int>((x[d] - lo_[d]) * inv_cell_);
    return std::clamp(c, 0, dims_[d] - 1);
  }
  std::uint32_t cell_index(const V& x) const {
    std::size_t idx = 0;
    for (int d = D - 1; d >= 0; --d) idx = idx * dims_[d] + coord(x, d);
    return static_cast<std::uint32_t>(idx);
  }
};

/// The candidate neighbours shared by all particles of one cell, for vectorised pair loops:
/// the loop copies each field it needs into a unit-stride column (for_each), padded to a
/// multiple of the vector width with entries it masks out, so the loop over them has no
/// remainder and no indirection; the copy is paid once per cell, not per particle.
template <int D>
struct CellStencil {
  std::uint32_t rg[CellList<D>::kMaxRanges][2];
  int nr = 0;
  std::size_t count = 0, padded = 0;
  const std::uint32_t* sorted = nullptr;
  bool identity = false;

  /// The stencil of `cell`; `padded` = count rounded up to a multiple of `lanes`.
  void set(const CellList<D>& cells, std::size_t cell, std::size_t lanes) {
    nr = cells.cell_ranges(cell, rg);
    count = 0;
    for (int r = 0; r < nr; ++r) count += rg[r][1] - rg[r][0];
    padded = (count + lanes - 1) / lanes * lanes;
    sorted = cells.sorted().data();
    identity = cells.identity();
  }
  /// fn(m, j) for the m-th candidate j (m = 0 .. count-1): fill all columns in one pass
  /// (the caller pads m = count .. padded-1).
  template <class Fn>
  void for_each(Fn&& fn) const {
    std::size_t m = 0;
    if (identity) {  // the cell-ordered store: each range is contiguous
      for (int r = 0; r < nr; ++r)
        for (std::uint32_t k = rg[r][0]; k < rg[r][1]; ++k) fn(m++, k);
    } else {
      for (int r = 0; r < nr; ++r)
        for (std::uint32_t k = rg[r][0]; k < rg[r][1]; ++k) fn(m++, sorted[k]);
    }
  }
};

/// The sum of L lane-wise partial sums (a pair loop's accumulators, L apart), pairwise in a fixed
/// order: the order of the additions does not depend on the vector width, so AVX2 and AVX-512
/// builds give bitwise the same sums. Overwrites v.
template <std::size_t L, class T>
inline T lane_sum(T* v) {
  for (std::size_t w = L / 2; w >= 1; w /= 2)
    for (std::size_t l = 0; l < w; ++l) v[l] += v[l + w];
  return v[0];
}

/// Growable per-thread scratch columns for the CellStencil copies.
template <class T = double>
struct ScratchColumns {
  std::vector<std::vector<T>> col;
  explicit ScratchColumns(int ncol) : col(static_cast<std::size_t>(ncol)) {}
  void reserve(std::size_t n) {
    if (!col.empty() && col[0].size() >= n) return;
    for (auto& c : col) c.resize(n + n / 2);
  }
  T* operator[](int i) { return col[static_cast<std::size_t>(i)].data(); }
};

/// The skeleton every vectorised pair loop shares (the WCSPH sweep, the dual integrator's passes,
/// the dummy walls' extrapolation): the occupied cells are handed to the threads a few at a
/// time; for each cell that needs(cell), the stencil of its 3^D cells is set with `lanes`
/// padding and the scratch columns are reserved, then body(cell, st, B) gathers its columns and
/// runs the cell's particles. Returns the sum of what body returns (pair counts). Must not be
/// called inside a parallel region.
template <class T, int D, class Need, class Body>
std::uint64_t sweep_cells(const CellList<D>& cells, int ncol, std::size_t lanes, Need&& needs, Body&& body) {
  const auto& occupied = cells.occupied();
  const std::size_t nocc = occupied.size();
  std::uint64_t total = 0;
#pragma omp parallel reduction(+ : total)
  {
    ScratchColumns<T> B(ncol);
    CellStencil<D> st;
#pragma omp for schedule(dynamic, 4)
    for (std::size_t oc = 0; oc < nocc; ++oc) {
      const std::size_t cell = occupied[oc];
      if (!needs(cell)) continue;
      st.set(cells, cell, lanes);
      B.reserve(st.padded);
      total += body(cell, st, B);
    }
  }
  return total;
}

}  // namespace sph
