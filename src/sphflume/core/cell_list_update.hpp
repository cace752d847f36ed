// CellList's in-place update (core/cell_list.hpp): after adopt_permutation the store is in the
// order of the last build's cells, and a build moves only the particles that changed cell.
// Included at the end of cell_list.hpp, whose class declares and documents these members.
#pragma once
#include <algorithm>
#include <cstdint>
#include <vector>
#ifdef _OPENMP
#include <omp.h>
#endif

#include "sphflume/core/cell_list.hpp"

namespace sph {

template <int D>
void CellList<D>::update(const std::vector<Vec<D>>& pos, std::size_t n) {
  const std::size_t ncell = cell_start_.size() - 1;
  int nt = 1;
#ifdef _OPENMP
  if (n > 4096) nt = omp_get_max_threads();
#endif
  const std::size_t m = collect_movers(pos, n, nt);
  moved_ = 0;
  if (m == 0) { identity_ = true; return; }  // (sorted_ is the identity since the adoption)
  moved_out_.resize(m);
  left_.resize(m);
  bool occupancy = false;  // a cell became empty or occupied: occupied_ is rebuilt
  for (std::size_t j = 0; j < m; ++j) {
    moved_out_[j] = moved_in_[j].from;
    left_[j] = moved_in_[j].index;
    occupancy |= cell_start_[moved_in_[j].cell + 1] == cell_start_[moved_in_[j].cell];
  }
  std::sort(moved_in_.begin(), moved_in_.end(),
            [](const Move& a, const Move& b) { return a.cell != b.cell ? a.cell < b.cell : a.index < b.index; });
  // each thread's cells: from the cell holding particle t n / nt of the old order
  bounds_.resize(static_cast<std::size_t>(nt) + 1);
  for (int t = 0; t <= nt; ++t) {
    const std::size_t k = n * static_cast<std::size_t>(t) / static_cast<std::size_t>(nt);
    bounds_[t] = t == 0 ? 0 : t == nt ? static_cast<std::uint32_t>(ncell)
                         : static_cast<std::uint32_t>(std::upper_bound(cell_start_.begin(), cell_start_.end() - 1,
                                                                       static_cast<std::uint32_t>(k)) -
                                                      cell_start_.begin() - 1);
  }
  // the old start of each range's end (the next range rewrites it)
  ends_.resize(static_cast<std::size_t>(nt));
  for (int t = 0; t < nt; ++t) ends_[t] = cell_start_[bounds_[t + 1]];
  Move* in = moved_in_.data();
  const std::uint32_t* out = moved_out_.data();
  // (a loop over the ranges, not one range per thread: any team size covers them all)
#pragma omp parallel for schedule(static, 1) num_threads(nt)
  for (int t = 0; t < nt; ++t) merge_cells(bounds_[t], bounds_[t + 1], ends_[t], m);
  for (std::size_t j = 0; j < m && !occupancy; ++j) occupancy = cell_start_[out[j] + 1] == cell_start_[out[j]];
  if (occupancy) {
    occupied_.clear();
    for (std::size_t c = 0; c < ncell; ++c)
      if (cell_start_[c + 1] > cell_start_[c]) occupied_.push_back(static_cast<std::uint32_t>(c));
  }
  // for the store: the movers' old indices ascending, their (old, new) index by new index
  arrive_.resize(2 * m);
  for (std::size_t j = 0; j < m; ++j) {
    arrive_[j] = in[j].index;
    arrive_[m + j] = in[j].to;
  }
  moved_ = m;
  bool ident = true;
#pragma omp parallel for schedule(static) reduction(&& : ident) num_threads(nt)
  for (std::size_t k = 0; k < n; ++k) ident = ident && sorted_[k] == k;
  identity_ = ident;
}

template <int D>
std::size_t CellList<D>::collect_movers(const std::vector<Vec<D>>& pos, std::size_t n, int nt) {
  if (found_.size() < static_cast<std::size_t>(nt)) found_.resize(static_cast<std::size_t>(nt));
  // (a violent step may have moved many: do not keep the large lists of the last one)
  if (moved_in_.capacity() > n / 256 + 256) {  // (typical steps move far fewer: memory target)
    std::vector<Move>().swap(moved_in_);
    std::vector<std::uint32_t>().swap(moved_out_);
    std::vector<std::uint32_t>().swap(left_);
    std::vector<std::uint32_t>().swap(arrive_);
    for (auto& f : found_) std::vector<Move>().swap(f);
  }
  for (auto& f : found_) f.clear();  // (a smaller team leaves some unused)
#pragma omp parallel num_threads(nt)
  {
    int t = 0;
#ifdef _OPENMP
    t = omp_get_thread_num();
#endif
    auto& f = found_[static_cast<std::size_t>(t)];
    // the new cells into sorted_ (the identity since the adoption: scratch here), a vector
    // loop; then the few that differ (the same static partition: each thread reads its own)
    std::uint32_t* __restrict key = sorted_.data();
    {
      std::size_t i0 = 0, i1 = n;
      thread_share(n, i0, i1);
      keys(pos, i0, i1, key);
    }
#pragma omp barrier
#pragma omp for schedule(static)
    for (std::size_t i = 0; i < n; ++i) {
      const std::uint32_t c = key[i];
      if (c != cell_of_[i]) {
        f.push_back(Move{c, static_cast<std::uint32_t>(i), cell_of_[i], 0});
        cell_of_[i] = c;
      }
      key[i] = static_cast<std::uint32_t>(i);
    }
  }
  moved_in_.clear();
  for (const auto& f : found_) moved_in_.insert(moved_in_.end(), f.begin(), f.end());  // (ascending index)
  return moved_in_.size();
}

template <int D>
void CellList<D>::merge_cells(std::uint32_t ca, std::uint32_t cb, std::uint32_t last_end, std::size_t m) {
  Move* in = moved_in_.data();
  const std::uint32_t* out = moved_out_.data();
  std::size_t ip = static_cast<std::size_t>(
      std::lower_bound(in, in + m, ca, [](const Move& a, std::uint32_t c) { return a.cell < c; }) - in);
  const std::size_t op = static_cast<std::size_t>(std::lower_bound(out, out + m, ca) - out);
  std::size_t oq = op;
  std::uint32_t* __restrict start = cell_start_.data();
  std::uint32_t* __restrict perm = sorted_.data();
  // old start of cell c (c <= cb): cells before cb are rewritten only once passed
  auto old_start = [&](std::uint32_t c) { return c == cb ? last_end : start[c]; };
  std::size_t o = static_cast<std::size_t>(start[ca]) + ip - op;  // the new start of cell ca
  for (std::uint32_t c = ca; c < cb;) {
    // cells up to the next one a mover leaves or enters: one shift for their starts and
    // their particles (vector loops; nothing to write where the shift is 0)
    std::uint32_t e = cb;
    if (ip < m) e = std::min(e, in[ip].cell);
    if (oq < m) e = std::min(e, out[oq]);
    if (e > c) {
      const std::uint32_t k0 = start[c], k1 = old_start(e);
      const std::int64_t shift = static_cast<std::int64_t>(o) - k0;
      if (shift != 0) {
        const std::uint32_t sh = static_cast<std::uint32_t>(shift);  // (modular: adds back)
        for (std::uint32_t q = c; q < e; ++q) start[q] += sh;
        std::uint32_t* __restrict dst = perm + o;
        for (std::uint32_t k = k0; k < k1; ++k) dst[k - k0] = k;
      }
      o += k1 - k0;
      c = e;
      if (c == cb) break;
    }
    // cell c gains or loses particles: those that stayed merged by index with those that came
    const std::uint32_t ob = start[c], oe = old_start(c + 1);
    start[c] = static_cast<std::uint32_t>(o);
    std::uint32_t i = ob;
    for (;;) {
      while (i < oe && cell_of_[i] != c) ++i;  // (those that left)
      const bool stay = i < oe, come = ip < m && in[ip].cell == c;
      if (!stay && !come) break;
      if (come && (!stay || in[ip].index < i)) { in[ip].to = static_cast<std::uint32_t>(o); perm[o++] = in[ip++].index; }
      else perm[o++] = i++;
    }
    while (oq < m && out[oq] == c) ++oq;
    ++c;
  }
}

}  // namespace sph
