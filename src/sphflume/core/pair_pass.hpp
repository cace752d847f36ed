// The pair-pass seam (docs/architecture.md §3): every vectorised pair loop of the engine runs
// over a cell's 3^D stencil of candidates, copied once per cell into unit-stride columns.
//  - CellStencil / ScratchColumns: a cell's candidates and the columns they are copied into;
//  - Column descriptors (column, second_part) and gather_columns / gather_split: what a pass
//    reads of each candidate, in which precision, and the copy that fills the columns;
//  - lane_sums: a per-pair functor summed over the candidates in fixed lanes (the same bits on
//    AVX2 and AVX-512 builds);
//  - sweep_cells: the threads' partition of the cells and the per-cell skeleton.
#pragma once
#include <algorithm>
#include <array>
#include <atomic>
#include <tuple>
#include <type_traits>
#include <cstdint>
#include <utility>
#include <vector>
#ifdef _OPENMP
#include <omp.h>
#endif

#include "sphflume/core/cell_list.hpp"

namespace sph {

/// This thread's number and its team's size (0 and 1 outside a parallel region or without OpenMP).
inline std::pair<int, int> team_place() {
#ifdef _OPENMP
  return {omp_get_thread_num(), omp_get_num_threads()};
#else
  return {0, 1};
#endif
}

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

  /// The stencil of `cell` (its own pairs', CellList::cell_ranges; radius > 0: every particle
  /// within radius of the cell); `padded` = count rounded up to a multiple of `lanes`.
  void set(const CellList<D>& cells, std::size_t cell, std::size_t lanes, double radius = 0.0) {
    nr = cells.cell_ranges(cell, rg, radius);
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
  /// For a cell-ordered store (identity): fn(k0, len, m) for each non-empty contiguous range
  /// [k0, k0 + len) of the candidates, m its first column entry, so that a pass copies its
  /// columns in vector loops (k0 of an empty range may be the end of the store: skipped).
  template <class Fn>
  void for_ranges(Fn&& fn) const {
    std::size_t m = 0;
    for (int r = 0; r < nr; ++r) {
      const std::uint32_t k0 = rg[r][0];
      const std::size_t len = rg[r][1] - k0;
      if (len > 0) fn(k0, len, m);
      m += len;
    }
  }
};

/// The positions of store entries [k0, k0 + len) relative to `origin`, into the float columns
/// x[0..D) at offset m: the stencil copies of the vectorised pair loops. The positions are read
/// as a flat array of doubles (through Vec's operator[] GCC 12 left such loops scalar, "no
/// vectype"); len > 0 (k0 may otherwise be the end of the store). T: float or double columns.
template <int D, class T = float>
inline void copy_positions(const Vec<D>* pos, std::uint32_t k0, std::size_t len, const Vec<D>& origin,
                           T* __restrict const* x, std::size_t m) {
  const double* __restrict pr = pos[k0].c.data();
  const double o0 = origin[0], o1 = origin[1], o2 = origin[D - 1];
  T* __restrict x0 = x[0] + m;
  T* __restrict x1 = x[1] + m;
  T* __restrict x2 = x[D - 1] + m;
  for (std::size_t i = 0; i < len; ++i) {
    x0[i] = T(pr[D * i + 0] - o0);
    x1[i] = T(pr[D * i + 1] - o1);
    if constexpr (D == 3) x2[i] = T(pr[D * i + D - 1] - o2);
  }
}

/// The sum of L lane-wise partial sums (a pair loop's accumulators, L apart), pairwise in a fixed
/// order: the order of the additions does not depend on the vector width, so AVX2 and AVX-512
/// builds give bitwise the same sums. Overwrites v.
template <std::size_t L, class T>
inline T lane_sum(T* v) {
  // (fully unrolled: left as loops, the reduction of a pass's accumulators cost as much as
  // a quarter of the pair loop)
#pragma GCC unroll 8
  for (std::size_t w = L / 2; w >= 1; w /= 2)
#pragma GCC unroll 32
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

/// A column descriptor: what a pass reads of each candidate. `get(j)` (j a std::size_t: a 32-bit
/// index k0 + q may wrap, so GCC 12 could not see a range's loads as contiguous and copied
/// element by element, a third of the dual passes' gathers) is the value of store entry j in the
/// column's precision T, written into scratch column `index`; the padding entries hold
/// `pad`. `Second`: written only into the second part of a split gather (gather_split), for
/// values only that part reads. only_if<On>(c) is c or, when On is false, NoColumn (a column the
/// pass does not read in this instantiation: a vector's third component in 2D, a model that is
/// off). A pass lists its descriptors once; the gathers below do the copy (all columns of a
/// contiguous range of a cell-ordered store in one vector loop, other stores candidate by
/// candidate), so the copy code is written once for every pass.
template <class T, class Get, bool Second = false>
struct Column {
  static constexpr bool kSecond = Second, kNone = false;
  int index;
  T pad;
  Get get;
};
struct NoColumn {
  static constexpr bool kSecond = false, kNone = true;
};
template <class T, class Get>
Column<T, Get> column(int index, T pad, Get get) {
  return {index, pad, get};
}
template <class T, class Get>
Column<T, Get, true> second_part(int index, T pad, Get get) {
  return {index, pad, get};
}
template <bool On, class C>
auto only_if(const C& c) {
  if constexpr (On) return c;
  else return NoColumn{};
}

/// How far away the padding entries sit (outside every support, so they weigh nothing).
constexpr double kPaddingDistance = 1.0e3;

namespace detail {
/// The descriptors of one part (Second) as a tuple, NoColumn left out.
template <bool Second, class C>
auto select(const C& c) {
  if constexpr (!C::kNone && C::kSecond == Second) return std::tuple<C>(c);
  else return std::tuple<>();
}
/// Store entries [k0, k0 + len) into entry m on of the columns of one part, all columns in one
/// loop (`omp simd` keeps plain copies from becoming memcpy calls, slower for ranges of ~30
/// entries; the positions have their own loop, copy_positions: fused with these GCC 12 left the
/// loop scalar). The column pointers are taken once per cell, not per range.
template <class T, class Tup, std::size_t... I>
struct RangeCopier {
  T* o[sizeof...(I) + 1];
  Tup cs;
  RangeCopier(ScratchColumns<T>& B, const Tup& c) : o{B[std::get<I>(c).index]..., nullptr}, cs(c) {}
  [[gnu::always_inline]] void operator()([[maybe_unused]] std::uint32_t k0, [[maybe_unused]] std::size_t len,
                                         [[maybe_unused]] std::size_t m) const {
    if constexpr (sizeof...(I) > 0) {
      T* __restrict out[sizeof...(I)] = {(o[I] + m)...};
#pragma omp simd
      for (std::size_t q = 0; q < len; ++q) ((out[I][q] = std::get<I>(cs).get(static_cast<std::size_t>(k0) + q)), ...);
    }
  }
};
template <class T, class Tup, std::size_t... I>
RangeCopier<T, Tup, I...> make_copier(ScratchColumns<T>& B, const Tup& cs, std::index_sequence<I...>) {
  return RangeCopier<T, Tup, I...>(B, cs);
}
/// The copier of the columns of part Second.
template <bool Second, class T, class... Cols>
auto copier(ScratchColumns<T>& B, const Cols&... cols) {
  const auto cs = std::tuple_cat(select<Second>(cols)...);
  return make_copier(B, cs, std::make_index_sequence<std::tuple_size_v<decltype(cs)>>{});
}
/// Candidate j into entry m of every column (of both parts), the column pointers taken once.
template <class T, class Tup, std::size_t... I>
struct Putter {
  T* o[sizeof...(I) + 1];
  Tup cs;
  Putter(ScratchColumns<T>& B, const Tup& c) : o{B[std::get<I>(c).index]..., nullptr}, cs(c) {}
  void operator()([[maybe_unused]] std::size_t m, [[maybe_unused]] std::uint32_t j) const {
    ((o[I][m] = std::get<I>(cs).get(j)), ...);
  }
};
template <class T, class Tup, std::size_t... I>
Putter<T, Tup, I...> make_putter(ScratchColumns<T>& B, const Tup& cs, std::index_sequence<I...>) {
  return Putter<T, Tup, I...>(B, cs);
}
template <class T, class... Cols>
auto putter(ScratchColumns<T>& B, const Cols&... cols) {
  const auto cs = std::tuple_cat(select<false>(cols)..., select<true>(cols)...);
  return make_putter(B, cs, std::make_index_sequence<std::tuple_size_v<decltype(cs)>>{});
}
template <class T, class C>
inline void pad_column(const C& c, ScratchColumns<T>& B, std::size_t m0, std::size_t m1) {
  if constexpr (!C::kNone) {
    T* o = B[c.index];
    for (std::size_t m = m0; m < m1; ++m) o[m] = c.pad;
  }
}
/// Entries [m0, m1) as padding: far away, every column its pad value.
template <int D, class T, class... Cols>
inline void pad_entries(ScratchColumns<T>& B, std::size_t m0, std::size_t m1, const Cols&... cols) {
  for (int d = 0; d < D; ++d)
    for (std::size_t m = m0; m < m1; ++m) B[d][m] = T(kPaddingDistance);
  (pad_column(cols, B, m0, m1), ...);
}
/// The copies of a split gather (gather_split, gather_halves): store entries [k0, k0 + len) into entries m.. of the
/// position columns and the first part's columns, and of the second part's too where asked (run); candidate j into
/// entry m of every column (put: a store not in cell order).
template <int D, class T, class... Cols>
struct PartCopier {
  using First = decltype(copier<false>(std::declval<ScratchColumns<T>&>(), std::declval<const Cols&>()...));
  using Second = decltype(copier<true>(std::declval<ScratchColumns<T>&>(), std::declval<const Cols&>()...));
  using Put = decltype(putter(std::declval<ScratchColumns<T>&>(), std::declval<const Cols&>()...));
  T* __restrict x[D];
  const Vec<D>* pos;
  const Vec<D>& origin;
  First first;
  Second second;
  Put put_cols;
  PartCopier(ScratchColumns<T>& B, const Vec<D>* p, const Vec<D>& o, const Cols&... cols)
      : pos(p), origin(o), first(copier<false>(B, cols...)), second(copier<true>(B, cols...)), put_cols(putter(B, cols...)) {
    for (int d = 0; d < D; ++d) x[d] = B[d];
  }
  [[gnu::always_inline]] void run(std::uint32_t k0, std::size_t len, std::size_t m, bool with_second) const {
    copy_positions<D, T>(pos, k0, len, origin, x, m);
    first(k0, len, m);
    if (with_second) second(k0, len, m);
  }
  void put(std::size_t m, std::uint32_t j) const {
    for (int d = 0; d < D; ++d) x[d][m] = T(pos[j][d] - origin[d]);
    put_cols(m, j);
  }
};
}  // namespace detail

/// Fill the scratch columns of a cell's stencil: the candidates' positions relative to `origin`
/// into columns [0, D) (small differences keep their digits in float), then each descriptor's
/// column; the entries from st.count to st.padded are padding (far away, each column's pad).
template <int D, class T, class... Cols>
[[gnu::always_inline]] inline void gather_columns(const CellStencil<D>& st, ScratchColumns<T>& B, const Vec<D>* pos, const Vec<D>& origin,
                    const Cols&... cols) {
  T* __restrict x[D];
  for (int d = 0; d < D; ++d) x[d] = B[d];
  if (st.identity) {  // the stencil's contiguous ranges of the cell-ordered store
    const auto first = detail::copier<false>(B, cols...);
    const auto second = detail::copier<true>(B, cols...);
    st.for_ranges([&](std::uint32_t k0, std::size_t len, std::size_t m) __attribute__((always_inline)) {
      copy_positions<D, T>(pos, k0, len, origin, x, m);
      first(k0, len, m);
      second(k0, len, m);
    });
  } else {
    const auto put = detail::putter(B, cols...);
    st.for_each([&](std::size_t m, std::uint32_t j) __attribute__((always_inline)) {
      for (int d = 0; d < D; ++d) x[d][m] = T(pos[j][d] - origin[d]);
      put(m, j);
    });
  }
  detail::pad_entries<D>(B, st.count, st.padded, cols...);
}

/// A gather in two parts: the candidates j with first(j) from entry 0, padded to a multiple of
/// `lanes` (first_end), then the `n_second` others, padded again (end); columns made with
/// second_part() only in the second part. A pass whose second part needs more work per pair
/// (the walls among a fluid particle's candidates) runs it only where it is. B must hold
/// st.padded + lanes entries. The order within each part is the stencil's.
struct SplitEnds {
  std::size_t first_end, end;
};
template <int D, class T, class First, class... Cols>
[[gnu::always_inline]] inline SplitEnds gather_split(const CellStencil<D>& st, ScratchColumns<T>& B, const Vec<D>* pos, const Vec<D>& origin,
                       std::size_t lanes, std::size_t n_second, First&& first, const Cols&... cols) {
  const std::size_t first_end = (st.count - n_second + lanes - 1) / lanes * lanes;
  std::size_t mf = 0, ms = first_end;
  const detail::PartCopier<D, T, Cols...> copy(B, pos, origin, cols...);
  if (st.identity) {
    // the runs of one part in each range (a cell's particles keep their order, so the parts come
    // in a few runs): a vector copy per run, no branch per candidate
    st.for_ranges([&](std::uint32_t k0, std::size_t len, std::size_t) __attribute__((always_inline)) {
      for (std::size_t q = 0; q < len;) {
        const bool f = first(k0 + static_cast<std::uint32_t>(q));
        std::size_t e = q + 1;
        while (e < len && first(k0 + static_cast<std::uint32_t>(e)) == f) ++e;
        std::size_t& m = f ? mf : ms;
        copy.run(k0 + static_cast<std::uint32_t>(q), e - q, m, !f);
        m += e - q;
        q = e;
      }
    });
  } else {
    st.for_each([&](std::size_t, std::uint32_t j) __attribute__((always_inline)) { if (first(j)) copy.put(mf++, j); });
    st.for_each([&](std::size_t, std::uint32_t j) __attribute__((always_inline)) { if (!first(j)) copy.put(ms++, j); });
  }
  const std::size_t end = (ms + lanes - 1) / lanes * lanes;
  detail::pad_entries<D>(B, mf, first_end, cols...);
  detail::pad_entries<D>(B, ms, end, cols...);
  return {first_end, end};
}

/// The gather of a pass that visits each pair once (CellList::half_ranges): part one, from entry 0, the candidates
/// j of the half stencil `half` with first(j), in stencil order (the cell's own first), their store indices into
/// ids, padded up to `second` (a multiple of `lanes`, at least half.count); part two, from `second`, the others of
/// both halves (`half`, then `other`), then every candidate of `cross` (pairs the pass visits from both ends:
/// CellList::grid_half_ranges; empty on one grid), padded to a multiple of `lanes` (end). The cell's own rows visit
/// part one for the pairs with the candidates after them, part two for the pairs with everything else (the walls
/// among a fluid particle's candidates). B must hold second + half.count + other.count + cross.count + lanes
/// entries, ids half.count. For a store in cell order, seconds_before[k] counts the entries before k that belong to
/// part two (so that a range without any is copied as one run).
struct HalvesEnds {
  std::size_t count_first, second, end;
};
template <int D, class T, class First, class... Cols>
[[gnu::always_inline]] inline HalvesEnds gather_halves(const CellStencil<D>& half, const CellStencil<D>& other,
                                                       const CellStencil<D>& cross, ScratchColumns<T>& B,
                                                       std::uint32_t* __restrict ids, const Vec<D>* pos, const Vec<D>& origin,
                                                       std::size_t lanes, std::size_t second, const std::uint32_t* seconds_before,
                                                       First&& first, const Cols&... cols) {
  const std::size_t first_end = second;
  std::size_t mf = 0, ms = second;
  const detail::PartCopier<D, T, Cols...> copy(B, pos, origin, cols...);
  auto copy_run = [&](std::uint32_t k0, std::size_t len, std::size_t m, bool with_second) __attribute__((always_inline)) {
    copy.run(k0, len, m, with_second);
  };
  if (half.identity) {
    auto runs = [&](const CellStencil<D>& st, bool take_first) {
      st.for_ranges([&](std::uint32_t k0, std::size_t len, std::size_t) __attribute__((always_inline)) {
        if (seconds_before[k0 + len] == seconds_before[k0]) {  // (a range of the first part only: one run)
          if (take_first) {
            copy_run(k0, len, mf, false);
            for (std::size_t i = 0; i < len; ++i) ids[mf + i] = k0 + static_cast<std::uint32_t>(i);
            mf += len;
          }
          return;
        }
        for (std::size_t q = 0; q < len;) {
          const bool f = first(k0 + static_cast<std::uint32_t>(q));
          std::size_t e = q + 1;
          while (e < len && first(k0 + static_cast<std::uint32_t>(e)) == f) ++e;
          const std::uint32_t r0 = k0 + static_cast<std::uint32_t>(q);
          if (!f) {
            copy_run(r0, e - q, ms, true);
            ms += e - q;
          } else if (take_first) {
            copy_run(r0, e - q, mf, false);
            for (std::size_t i = 0; i < e - q; ++i) ids[mf + i] = r0 + static_cast<std::uint32_t>(i);
            mf += e - q;
          }
          q = e;
        }
      });
    };
    runs(half, true);
    runs(other, false);
    cross.for_ranges([&](std::uint32_t k0, std::size_t len, std::size_t) __attribute__((always_inline)) {
      copy_run(k0, len, ms, true);
      ms += len;
    });
  } else {
    half.for_each([&](std::size_t, std::uint32_t j) {
      if (first(j)) { ids[mf] = j; copy.put(mf++, j); }
      else copy.put(ms++, j);
    });
    other.for_each([&](std::size_t, std::uint32_t j) { if (!first(j)) copy.put(ms++, j); });
    cross.for_each([&](std::size_t, std::uint32_t j) { copy.put(ms++, j); });
  }
  const std::size_t end = (ms + lanes - 1) / lanes * lanes;
  detail::pad_entries<D>(B, mf, first_end, cols...);
  detail::pad_entries<D>(B, ms, end, cols...);
  return {mf, second, end};
}

/// Each thread's range of cells [front, end) of a sweep, claimed from the front by its owner a piece at a time and
/// from the back by a thread that has run out (sweep_cells): one 64-bit word per thread (front in the low half, end
/// in the high), changed only by compare-and-swap, each on its own cache line.
class StealRanges {
 public:
  explicit StealRanges(int nt) : slot_(static_cast<std::size_t>(nt)) {}
  void set(int t, std::size_t front, std::size_t end) { slot_[idx(t)].v.store(pack(front, end), std::memory_order_relaxed); }
  /// The owner's next piece [f, e) of its range (an eighth of what is left, at least one cell); false when it is empty.
  bool claim(int t, std::size_t& f, std::size_t& e) {
    auto& a = slot_[idx(t)].v;
    std::uint64_t v = a.load(std::memory_order_acquire);
    for (;;) {
      const std::size_t f0 = lo(v), e0 = hi(v);
      if (f0 >= e0) return false;
      const std::size_t f1 = f0 + std::max<std::size_t>(1, (e0 - f0) / 8);
      if (a.compare_exchange_weak(v, pack(f1, e0), std::memory_order_acq_rel)) {
        f = f0;
        e = f1;
        return true;
      }
    }
  }
  /// Thread t (its own range empty) takes the back half, by the running work sums wk, of the largest unclaimed range
  /// of another thread and makes it its own range; false when no other thread has any left.
  bool steal(int t, const std::uint64_t* wk) {
    for (;;) {
      int victim = -1;
      std::uint64_t most = 0, v = 0;
      for (int q = 0; q < static_cast<int>(slot_.size()); ++q) {
        if (q == t) continue;
        const std::uint64_t w = slot_[idx(q)].v.load(std::memory_order_acquire);
        if (lo(w) < hi(w) && wk[hi(w)] - wk[lo(w)] >= most) {
          most = wk[hi(w)] - wk[lo(w)];
          victim = q;
          v = w;
        }
      }
      if (victim < 0) return false;
      const std::size_t f = lo(v), e = hi(v);
      const std::uint64_t goal = wk[f] + (wk[e] - wk[f]) / 2;
      const std::size_t mid = std::clamp<std::size_t>(static_cast<std::size_t>(std::lower_bound(wk + f, wk + e, goal) - wk), f, e - 1);
      if (slot_[idx(victim)].v.compare_exchange_strong(v, pack(f, mid), std::memory_order_acq_rel)) {
        set(t, mid, e);
        return true;
      }
    }
  }

 private:
  struct alignas(64) Slot {
    std::atomic<std::uint64_t> v{0};
  };
  std::vector<Slot> slot_;
  static std::size_t idx(int t) { return static_cast<std::size_t>(t); }
  static std::uint64_t pack(std::size_t f, std::size_t e) { return static_cast<std::uint64_t>(f) | (static_cast<std::uint64_t>(e) << 32); }
  static std::size_t lo(std::uint64_t v) { return static_cast<std::size_t>(v & 0xffffffffu); }
  static std::size_t hi(std::uint64_t v) { return static_cast<std::size_t>(v >> 32); }
};

/// The skeleton of a pass that visits each pair once and writes into its candidates (the WCSPH rates pass's
/// half-stencil sweep): the occupied cells run colour by colour (CellList::half_colour), the cells of one colour
/// shared among the threads, a barrier between colours. Two cells of a colour write disjoint particles, and each
/// particle receives its sums in the order of the colours, so the results do not depend on the thread count.
/// Each thread takes one contiguous run of a colour's cells, the runs balanced by weight(cell) (the cell's work; handed
/// out a few at a time, neighbouring cells of one colour ran on both threads at once and wrote into the same cache
/// lines of their neighbours' rates), claimed a piece at a time, and a thread that has finished its run takes the
/// back half of another's unclaimed cells (StealRanges): the weights miss the walls' and the levels' costs (a Flume A
/// band run on two threads waited at the colours' barriers for a fifth of its time). Any thread may run any cell
/// of a colour: the sums do not depend on which. body(cell, B, ids) with the thread's scratch columns (ncol) and index scratch;
/// returns the sum of what body returns.
template <class T, int D, class Weight, class Body>
std::uint64_t sweep_colours(const CellList<D>& cells, int ncol, Weight&& weight, Body&& body) {
  const auto& occupied = cells.occupied();
  const int ncolour = cells.half_colours();
  static thread_local std::vector<std::vector<std::uint32_t>> kept;  // (the lists' memory kept between calls)
  static thread_local std::vector<std::vector<std::uint64_t>> kept_work;
  auto& by_colour = kept;  // (the calling thread's, shared by the team below)
  auto& work = kept_work;   // each colour's running sum of its cells' weights
  by_colour.resize(static_cast<std::size_t>(ncolour));
  work.resize(static_cast<std::size_t>(ncolour));
  for (auto& l : by_colour) l.clear();
  for (auto& w : work) w.assign(1, 0);
  for (const std::uint32_t c : occupied) {
    const auto col = static_cast<std::size_t>(cells.half_colour(c));
    by_colour[col].push_back(c);
    work[col].push_back(work[col].back() + static_cast<std::uint64_t>(weight(c)));
  }
  int maxt = 1;
#ifdef _OPENMP
  maxt = omp_get_max_threads();
#endif
  // each colour's runs, one per thread, balanced by weight (a team smaller than maxt: the runs of the absent threads
  // are taken by stealing)
  std::vector<StealRanges> ranges;
  ranges.reserve(static_cast<std::size_t>(ncolour));
  for (int col = 0; col < ncolour; ++col) {
    const auto& list = by_colour[static_cast<std::size_t>(col)];
    const auto& w = work[static_cast<std::size_t>(col)];
    auto start = [&](int q) {  // the first cell of thread q's run
      if (q >= maxt) return list.size();
      if (q == 0) return std::size_t(0);
      const std::uint64_t goal = w.back() * static_cast<std::uint64_t>(q) / static_cast<std::uint64_t>(maxt);
      return static_cast<std::size_t>(std::lower_bound(w.begin(), w.end(), goal) - w.begin());
    };
    ranges.emplace_back(maxt);
    for (int q = 0; q < maxt; ++q) ranges.back().set(q, start(q), start(q + 1));
  }
  std::uint64_t total = 0;
#pragma omp parallel reduction(+ : total)
  {
    const int t = team_place().first;
    ScratchColumns<T> B(ncol);
    std::vector<std::uint32_t> ids;
    for (int col = 0; col < ncolour; ++col) {
      const auto& list = by_colour[static_cast<std::size_t>(col)];
      StealRanges& r = ranges[static_cast<std::size_t>(col)];
      do {
        std::size_t f = 0, e = 0;
        while (r.claim(t, f, e))
          for (std::size_t i = f; i < e; ++i) total += body(list[i], B, ids);
      } while (r.steal(t, work[static_cast<std::size_t>(col)].data()));
#pragma omp barrier
    }
  }
  return total;
}

/// The candidates j with keep(j) only, in stencil order, from entry 0, padded to a multiple of
/// `lanes` (a pass that runs a few particles over a filtered stencil: the walls' backup runs the
/// first-layer walls over the fluid); returns how many were kept.
template <int D, class T, class Keep, class... Cols>
std::size_t gather_if(const CellStencil<D>& st, ScratchColumns<T>& B, const Vec<D>* pos, const Vec<D>& origin,
                      std::size_t lanes, Keep&& keep, const Cols&... cols) {
  T* __restrict x[D];
  for (int d = 0; d < D; ++d) x[d] = B[d];
  const auto put = detail::putter(B, cols...);
  std::size_t m = 0;
  st.for_each([&](std::size_t, std::uint32_t j) {
    if (!keep(j)) return;
    for (int d = 0; d < D; ++d) x[d][m] = T(pos[j][d] - origin[d]);
    put(m++, j);
  });
  detail::pad_entries<D>(B, m, (m + lanes - 1) / lanes * lanes, cols...);
  return m;
}

/// A per-pair functor summed in fixed lanes: add(terms) runs terms(l, v) for the L lanes of one
/// block of candidates; the functor reads its columns through pointers offset to the block (an
/// index k0 + l was a "complicated access pattern" to GCC's AVX2 vectoriser) and adds each of
/// its N terms into lane l of its accumulator, v[i][l] += term. sums() then adds the lanes in
/// a fixed order (lane_sum), so that AVX2 and AVX-512 builds give bitwise the same sums. The
/// functor has no branches (masks as factors), so the block's loop vectorises. (Terms added in
/// place, not returned as an array or through a callback: each accumulation stays one
/// expression, which the compiler contracts to a fused multiply-add as the hand-written loops
/// did, and the loop vectorises.)
template <std::size_t L, std::size_t N, class T = float>
struct LaneSums {
  alignas(64) T v[N][L] = {};
  template <class Terms>
  void add(Terms&& terms) {
#pragma omp simd
    for (std::size_t l = 0; l < L; ++l) terms(l, v);
  }
  /// The N sums (overwrites the lanes).
  std::array<T, N> sums() {
    std::array<T, N> s;
#pragma GCC unroll 16
    for (std::size_t i = 0; i < N; ++i) s[i] = lane_sum<L>(v[i]);
    return s;
  }
};

/// The skeleton every vectorised pair loop shares (the WCSPH sweep, the dual integrator's passes,
/// the dummy walls' extrapolation, the walls' backup, the scalar transport's pair sums): needs(cell), evaluated once per occupied
/// cell, returns how many of its particles the pass runs (0: the cell is skipped); for each
/// other cell the stencil of its 3^D cells is set with `lanes` padding and the scratch columns
/// are reserved, then body(cell, st, B) gathers its columns and runs the cell's particles.
/// Returns the sum of what body returns (pair counts). Must not be called inside a parallel
/// region. `radius`: 0 (the default) for each cell's own pairs (CellList::cell_ranges: the
/// pairs at h_ij); a pass with a fixed radius gives it.
///
/// Each thread runs one contiguous run of cells. The store is in cell order, so a thread then
/// reads mostly the particles that it wrote itself in the static particle loops between the
/// passes. Handing out cells a few at a time (dynamic) interleaved the threads' cells: every
/// core fetched half of what it read from the other's cache, and on 2 threads each cell of the
/// 2D passes took 1.27x as long as on 1 (bench/README.md). The runs are balanced by a cell's
/// work, (particles + 1) x candidates, each thread's share scaled by the rate (work per
/// second) it ran at in the last calls of the same pass (the passes' costs per candidate vary
/// across the tank, with the walls among them). What the estimate misses (a multirate run's
/// fast and full passes share one rate and run different cells; the rates sweep of a band run
/// on two threads waited 10 % of its time at the end) is taken up by stealing (StealRanges): a
/// thread claims its run from the front a piece at a time, and one that has finished takes the
/// back half, by work, of what another has not yet claimed. The results do not depend on the
/// partition: a cell's sums are its own, and the pair counts are integers.
template <class T, int D, class Need, class Body>
std::uint64_t sweep_cells(const CellList<D>& cells, int ncol, std::size_t lanes, Need&& needs, Body&& body, double radius = 0.0) {
  const auto& occupied = cells.occupied();
  const std::size_t nocc = occupied.size();
  int maxt = 1;
#ifdef _OPENMP
  maxt = omp_get_max_threads();
#endif
  // each thread's rate in the last calls of this pass (each body is its own instantiation)
  static std::vector<double> rate;
  auto& work = cells.sweep_work();  // the cells' work, then its running sums
  if (maxt > 1) work.resize(nocc + 1);
  std::uint64_t* __restrict wk = work.data();
  std::vector<std::size_t> first(static_cast<std::size_t>(maxt) + 1, nocc);  // each thread's first cell
  std::vector<double> took(static_cast<std::size_t>(maxt), 0.0);
  std::vector<std::uint64_t> did(static_cast<std::size_t>(maxt), 0);  // the work each thread ran (its own and stolen)
  StealRanges ranges(maxt);
  int team = 1;
  std::uint64_t total = 0;
#pragma omp parallel reduction(+ : total)
  {
    const auto place = team_place();
    const int t = place.first, nt = place.second;
    CellStencil<D> st;
    ScratchColumns<T> B(ncol);
    auto run = [&](std::size_t cell) {
      st.set(cells, cell, lanes, radius);
      B.reserve(st.padded);
      total += body(cell, st, B);
    };
    if (nt == 1) {  // (one thread: no partition to weigh)
      for (std::size_t oc = 0; oc < nocc; ++oc)
        if (needs(occupied[oc]) > 0) run(occupied[oc]);
    } else {  // (the same branch for the whole team: nt is the team's size)
#pragma omp for schedule(static)
      for (std::size_t oc = 0; oc < nocc; ++oc) {
        const std::size_t cell = occupied[oc];
        const std::size_t m = needs(cell);
        wk[oc + 1] = 0;
        if (m > 0) {
          st.set(cells, cell, lanes, radius);
          wk[oc + 1] = (m + 1) * st.padded;  // (the + 1: the stencil's copy)
        }
      }
#pragma omp single
      {
        team = nt;
        wk[0] = 0;
        for (std::size_t oc = 0; oc < nocc; ++oc) wk[oc + 1] += wk[oc];
        if (rate.size() != static_cast<std::size_t>(nt)) rate.assign(static_cast<std::size_t>(nt), 0.0);
        bool measured = true;
        double rsum = 0.0;
        for (const double r : rate) {
          measured = measured && r > 0.0;
          rsum += r;
        }
        first[0] = 0;
        double before = 0.0;  // the rates of the threads before q
        for (int q = 1; q < nt; ++q) {
          before += rate[static_cast<std::size_t>(q - 1)];
          const double share = measured ? before / rsum : static_cast<double>(q) / nt;
          const auto goal = static_cast<std::uint64_t>(share * static_cast<double>(wk[nocc]));
          first[static_cast<std::size_t>(q)] = static_cast<std::size_t>(std::lower_bound(wk, wk + nocc + 1, goal) - wk);
        }
        for (int q = 0; q < nt; ++q) ranges.set(q, first[static_cast<std::size_t>(q)], first[static_cast<std::size_t>(q) + 1]);
      }
#ifdef _OPENMP
      const double t0 = omp_get_wtime();
#endif
      const std::size_t u = static_cast<std::size_t>(t);
      std::uint64_t w = 0;  // the work this thread ran
      do {
        std::size_t f = 0, e = 0;
        while (ranges.claim(t, f, e)) {
          for (std::size_t oc = f; oc < e; ++oc)
            if (wk[oc + 1] > wk[oc]) run(occupied[oc]);
          w += wk[e] - wk[f];
        }
      } while (ranges.steal(t, wk));
      did[u] = w;
#ifdef _OPENMP
      took[u] = omp_get_wtime() - t0;
#endif
    }
  }
  // the rates for the next call (smoothed: one call's timing is noisy; a thread that had no work
  // or a run too short to time keeps its rate)
  for (int q = 0; q < team && team > 1; ++q) {
    const std::size_t u = static_cast<std::size_t>(q);
    const double w = static_cast<double>(did[u]);
    if (w <= 0.0 || took[u] <= 1.0e-6) continue;
    const double r = w / took[u];
    rate[u] = rate[u] > 0.0 ? 0.75 * rate[u] + 0.25 * r : r;
  }
  return total;
}
}  // namespace sph
