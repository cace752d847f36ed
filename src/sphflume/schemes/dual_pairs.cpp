// The dual-criteria Riemann scheme with `scheme.pairs: advection` (schemes/dual.hpp): each fluid particle's pairs,
// with the kernel's W'(r) and the direction e = (x_a − x_b)/r, found once at the start of an advection step and kept
// through its acoustic steps, as SPHinXsys updates its configuration (cell lists, neighbours and their kernel
// gradients) once per advection step (Zhang, Zhang & Hu 2020, J. Comput. Phys. 404, §3). The acoustic passes then
// run over the kept rows: the same terms as the cell passes (dual_terms.hpp, docs/numerics.md), each pair's kernel
// gradient W'(r) e taken at the advection step's start and the states (p, u, V) at the pass's time:
//   pass A:  Σ (pa + pb) W' Vb e,  Σ (pa − pb) W' Vb
//   pass B:  Σ ((ua − ub)·e) W' Vb,  Σ β U W' Vb d   (U = −(ua − ub)·e; against a wall U = −2 (ua − ub)·d, d = ±n)
// (the cell passes' F r = W' e). The particles move meanwhile by at most advection_cfl h: a partner entering the
// support within the step is missed, where W' is below 1e-3 of its peak at the default 0.25.
#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <type_traits>
#include <vector>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "sphflume/core/lanes8.hpp"
#include "sphflume/core/pair_pass.hpp"
#include "sphflume/schemes/dual.hpp"
#include "sphflume/schemes/dual_terms.hpp"

// (-Wpsabi: the eight-lane vectors of core/lanes8.hpp in a build without AVX; inline, within this file)
#pragma GCC diagnostic ignored "-Wpsabi"

namespace sph {

namespace {
constexpr std::size_t kLanes = 16;
using namespace dual;

/// One thread's (wall, fluid) pairs while they are found: their W and r = x_w − x_a.
struct Rows {
  std::vector<std::uint32_t> wall, wfluid;
  std::vector<float> ww, wr;
  void clear() {
    wall.clear();
    wfluid.clear();
    ww.clear();
    wr.clear();
  }
};

/// One cell's stencil gathered for the search (positions in float relative to the cell's first particle, as the
/// passes; each candidate's store index and whether it is a wall) and one particle's scratch. Thread-local.
template <int D>
struct CellSearch {
  std::vector<std::uint32_t> idx, sel;
  std::vector<F32> r2s, wq;
  std::vector<std::uint8_t> isw, fl;
  const F32* x[3] = {nullptr, nullptr, nullptr};
  std::size_t count = 0, padded = 0, nf = 0, nw = 0;

  void gather(const CellStencil<D>& st, ScratchColumns<F32>& B, const Vec<D>* pos, const Vec<D>& origin, const Kind* kind) {
    gather_columns(st, B, pos, origin);
    count = st.count;
    padded = st.padded;  // (a multiple of the lanes: the flags are read eight at a time)
    idx.resize(padded);
    r2s.resize(padded);
    isw.resize(padded);
    fl.resize(padded);
    wq.resize(padded);
    sel.resize(2 * (padded + 8));  // (a block of eight written past the last partner)
    st.for_each([&](std::size_t m, std::uint32_t b) {
      idx[m] = b;
      isw[m] = fluid_like(kind[b]) ? 0 : 1;
    });
    for (int d = 0; d < 3; ++d) x[d] = B[std::min(d, D - 1)];
  }
  std::uint32_t* fluid_sel() { return sel.data(); }
  std::uint32_t* wall_sel() { return sel.data() + padded + 8; }

  /// The partners of a particle at xa within the support, in the stencil's order, fluid (nf) and walls (nw) apart:
  /// r² in vector lanes with a flag per candidate (1 fluid, 2 wall, 0 outside, a itself or padding), then the set
  /// flags eight at a time (a sixth of the candidates lie within the support in 3D).
  void select(const F32 xa[3], F32 sup2) {
    const F32* __restrict x0 = x[0];
    const F32* __restrict x1 = x[1];
    const F32* __restrict x2 = x[2];
    F32* __restrict rs = r2s.data();
    const std::uint8_t* __restrict wl = isw.data();
    std::uint8_t* __restrict flag = fl.data();
    const F32 xa0 = xa[0], xa1 = xa[1], xa2 = xa[2];
#pragma omp simd
    for (std::size_t m = 0; m < padded; ++m) {
      const F32 r0 = xa0 - x0[m], r1 = xa1 - x1[m], r2c = D == 3 ? xa2 - x2[m] : F32(0);
      const F32 r2 = D == 3 ? r0 * r0 + r1 * r1 + r2c * r2c : r0 * r0 + r1 * r1;
      rs[m] = r2;
      flag[m] = static_cast<std::uint8_t>(((r2 < sup2) & (r2 > F32(0))) << wl[m]);
    }
    std::uint32_t* __restrict fsel = fluid_sel();
    std::uint32_t* __restrict wsel = wall_sel();
    nf = nw = 0;
    for (std::size_t m0 = 0; m0 < padded; m0 += 8) {
      std::uint64_t w;
      std::memcpy(&w, flag + m0, 8);
      if (w == 0) continue;
      nf += take8(bits8(w), m0, fsel + nf);
      nw += take8(bits8(w >> 1), m0, wsel + nw);
    }
  }

  /// The eight flags' low bits (one per byte) as the bits of a byte.
  static unsigned bits8(std::uint64_t w) { return static_cast<unsigned>(((w & 0x0101010101010101ull) * 0x0102040810204080ull) >> 56); }
  /// The candidates m0 + k of the set bits k of `mask`, in order, into out (eight written); their count. Branch-free:
  /// the set bits' places come from a table (the per-bit loop mispredicted its trip counts).
  static std::size_t take8(unsigned mask, std::size_t m0, std::uint32_t* __restrict out) {
    static constexpr auto places = [] {
      std::array<std::uint64_t, 256> t{};
      for (unsigned v = 0; v < 256; ++v) {
        unsigned k = 0;
        for (unsigned b = 0; b < 8; ++b)
          if (v >> b & 1u) t[v] |= std::uint64_t(b) << (8 * k++);
      }
      return t;
    }();
    const std::uint64_t pl = places[mask];
    for (unsigned k = 0; k < 8; ++k) out[k] = static_cast<std::uint32_t>(m0 + ((pl >> (8 * k)) & 0xffu));
    return static_cast<std::size_t>(std::popcount(mask));
  }

  /// The kept entries of one part of a's row from k0 (a multiple of the lanes): the partners `which` (cnt of them),
  /// their W'(r) and e (each block's components apart), W(r) into wq; padded to `to` with a itself at W' = 0 and
  /// e = 0 (it adds zeros). Returns Σ W in the entries' order.
  template <class K>
  F32 fill(const K& ker, const F32 xa[3], std::uint32_t a, std::uint32_t* __restrict which, std::size_t cnt,
           std::size_t to, std::uint32_t* __restrict jo, F32* __restrict wo, F32* __restrict eo) {
    const F32* __restrict x0 = x[0];
    const F32* __restrict x1 = x[1];
    const F32* __restrict x2 = x[2];
    const F32* __restrict rs = r2s.data();
    const std::uint32_t* __restrict ix = idx.data();
    F32* __restrict wk = wq.data();
    const F32 xa0 = xa[0], xa1 = xa[1], xa2 = xa[2];
    // a block of kLanes entries at a time, the padding (q >= cnt: candidate 0, its results replaced) in the same
    // lanes: the loop vectorises (the candidates' columns gathered by index), where one over the entries with the
    // padding apart stayed scalar
    for (std::size_t q = cnt; q < to; ++q) which[q] = 0;
    for (std::size_t q0 = 0; q0 < to; q0 += kLanes) {
      F32* __restrict e0 = eo + q0 * D;
      const std::uint32_t* __restrict wh = which + q0;
      const std::size_t live = cnt - std::min(cnt, q0);
#pragma omp simd
      for (std::size_t l = 0; l < kLanes; ++l) {
        const int m = static_cast<int>(wh[l]);
        const F32 r0 = xa0 - x0[m], r1 = xa1 - x1[m], r2c = D == 3 ? xa2 - x2[m] : F32(0);
        const F32 rr = std::sqrt(rs[m]), inv = F32(1) / rr;
        const bool in = l < live;
        const std::uint32_t jm = ix[m];
        jo[q0 + l] = in ? jm : a;
        const F32 f = ker.F(rr) * rr, w = ker.W(rr);
        wo[q0 + l] = in ? f : F32(0);
        wk[q0 + l] = in ? w : F32(0);
        e0[l] = in ? r0 * inv : F32(0);
        e0[kLanes + l] = in ? r1 * inv : F32(0);
        if constexpr (D == 3) e0[2 * kLanes + l] = in ? r2c * inv : F32(0);
      }
    }
    F32 s = 0;
    for (std::size_t q = 0; q < cnt; ++q) s += wk[q];
    return s;
  }

  /// The wall side of a's wall partners just filled (their W in wq): (wall, a, W, x_w − x_a) into R.
  void wall_side(const F32 xa[3], std::uint32_t a, Rows& R) {
    const std::uint32_t* wsel = wall_sel();
    for (std::size_t q = 0; q < nw; ++q) {
      const std::uint32_t m = wsel[q];
      R.wall.push_back(idx[m]);
      R.wfluid.push_back(a);
      R.ww.push_back(wq[q]);
      for (int d = 0; d < D; ++d) R.wr.push_back(x[d][m] - xa[d]);
    }
  }
};

/// The kept rows as the acoustic passes read them: each particle's fluid partners [kb, km) and walls [km, ke), the
/// partner, W' and e (each block's components apart).
struct KeptRows {
  const std::uint32_t *kb, *km, *ke, *jj;
  const F32 *dw, *ee;
};

/// The lane sums of a row (two vectors of eight: the lanes 0–15 of the scalar passes) reduced in lane_sum's order
/// (core/pair_pass.hpp: 8, 4, 2, 1 apart), in registers: through memory it was a fifth of a 2D row.
template <std::size_t N>
std::array<F32, N> row_sums(const lanes8::v8f (&acc)[N][2]) {
  std::array<F32, N> s;
  for (std::size_t i = 0; i < N; ++i) {
    const lanes8::v8f s8 = acc[i][0] + acc[i][1];
    const lanes8::v4f s4 = __builtin_shufflevector(s8, s8, 0, 1, 2, 3) + __builtin_shufflevector(s8, s8, 4, 5, 6, 7);
    const lanes8::v2f s2 = __builtin_shufflevector(s4, s4, 0, 1) + __builtin_shufflevector(s4, s4, 2, 3);
    s[i] = s2[0] + s2[1];
  }
  return s;
}

/// Pass A over particle a's kept row: Σ (pa + pb) W' Vb e (D), Σ (pa − pb) W' Vb, the pair count (pk: the {p, V}
/// records). Each lane's operations are those of the lane-wise loop the rows had before (the same sums, bit for bit).
template <int D>
std::array<F32, D + 2> pressure_row(const KeptRows& R, const F32* __restrict pk, std::uint32_t a) {
  using namespace lanes8;
  const F32 pa = pk[2 * a];
  const v8f one = splat(1.0f), zero = splat(0.0f);
  v8f acc[D + 2][2];
  for (auto& a2 : acc) a2[0] = a2[1] = zero;  // (not `= {}`: GCC called memset for it)
  for (std::uint32_t k0 = R.kb[a]; k0 < R.ke[a]; k0 += kLanes)
    for (int h = 0; h < 2; ++h) {
      const std::uint32_t k = k0 + 8 * h;
      v8f pb, vb;
      gather2(pk, 2, R.jj + k, pb, vb);
      const v8f w = load(R.dw + k);
      const F32* e = R.ee + std::size_t(k0) * D + 8 * h;
      const v8f wv = w * vb;
      const v8f s = (pa + pb) * wv;
      acc[0][h] += s * load(e);
      acc[1][h] += s * load(e + kLanes);
      if constexpr (D == 3) acc[2][h] += s * load(e + 2 * kLanes);
      acc[D][h] += (pa - pb) * wv;
      acc[D + 1][h] += w != zero ? one : zero;
    }
  return row_sums(acc);
}

/// Pass B over particle a's kept row: the Riemann dissipation Σ β U W' Vb d (D) and Σ ((ua − ub)·e) W' Vb (pk: the
/// {u, V} records, then the walls' normals; fk = k/c0), lane by lane as before.
template <int D>
std::array<F32, D + 1> continuity_row(const KeptRows& R, const F32* __restrict pk, std::size_t np, F32 fk, std::uint32_t a) {
  using namespace lanes8;
  const F32* __restrict nk = pk + 4 * np;
  const F32 ua0 = pk[4 * a], ua1 = pk[4 * a + 1], ua2 = pk[4 * a + D - 1];
  const v8f fkv = splat(fk), one = splat(1.0f), zero = splat(0.0f);
  v8f acc[D + 1][2];
  for (auto& a2 : acc) a2[0] = a2[1] = zero;
  // the fluid partners [kb, km), then the walls [km, ke): against a wall the dissipation acts along its normal
  // turned towards a, on twice the speed along it (the mirror state)
  auto part = [&](auto wall, std::uint32_t from, std::uint32_t to) {
    constexpr bool Wall = decltype(wall)::value;
    for (std::uint32_t k0 = from; k0 < to; k0 += kLanes)
      for (int h = 0; h < 2; ++h) {
        const std::uint32_t k = k0 + 8 * h;
        v8f u0, u1, u2 = zero, vb;
        if constexpr (D == 3) gather4(pk, R.jj + k, u0, u1, u2, vb);
        else {
          v8f unused;
          gather4(pk, R.jj + k, u0, u1, vb, unused);
        }
        const v8f wv = load(R.dw + k) * vb;
        const F32* e = R.ee + std::size_t(k0) * D + 8 * h;
        const v8f e0 = load(e), e1 = load(e + kLanes), e2 = D == 3 ? load(e + 2 * kLanes) : zero;
        const v8f du0 = ua0 - u0, du1 = ua1 - u1, du2 = D == 3 ? ua2 - u2 : zero;
        const v8f ue = D == 3 ? du0 * e0 + du1 * e1 + du2 * e2 : du0 * e0 + du1 * e1;  // (ua − ub)·e
        acc[D][h] += ue * wv;
        v8f d0 = e0, d1 = e1, d2 = e2, U = -ue;
        if constexpr (Wall) {
          v8f m0, m1, m2 = zero;
          if constexpr (D == 3) {
            v8f unused;
            gather4(nk, R.jj + k, m0, m1, m2, unused);
          } else {
            gather2(nk, 4, R.jj + k, m0, m1);
          }
          const v8f en = D == 3 ? e0 * m0 + e1 * m1 + e2 * m2 : e0 * m0 + e1 * m1;
          const v8f sn = en < zero ? -one : one;
          d0 = sn * m0;
          d1 = sn * m1;
          d2 = D == 3 ? sn * m2 : zero;
          U = F32(-2) * (D == 3 ? du0 * d0 + du1 * d1 + du2 * d2 : du0 * d0 + du1 * d1);
        }
        const v8f q = limited_dissipation(fkv, U, wv);  // (dual_terms.hpp, in lanes)
        acc[0][h] += q * d0;
        acc[1][h] += q * d1;
        if constexpr (D == 3) acc[2][h] += q * d2;
      }
  };
  part(std::false_type{}, R.kb[a], R.km[a]);
  part(std::true_type{}, R.km[a], R.ke[a]);
  return row_sums(acc);
}

/// One thread's part of a search: its (wall, fluid) pairs and the entries its rows need, on cache lines of its own
/// (side by side, the two threads' counters and vector ends shared lines: the search took 1.4x the CPU time on 2
/// threads that it took on one).
struct alignas(64) ThreadRows {
  Rows rows;
  std::size_t need = 0;
};

/// Each wall particle's fluid partners from the threads' (wall, fluid) pairs, in the order found (a counting sort by
/// wall over the threads in order).
template <int D>
void wall_rows(const std::vector<ThreadRows>& per, std::size_t np, WallPairs& W) {
  W.begin.assign(np + 1, 0);
  std::size_t nwp = 0;
  for (const ThreadRows& T : per) {
    const Rows& R = T.rows;
    nwp += R.wall.size();
    for (const std::uint32_t w : R.wall) ++W.begin[w + 1];
  }
  for (std::size_t i = 0; i < np; ++i) W.begin[i + 1] += W.begin[i];
  W.end.assign(W.begin.begin(), W.begin.end() - 1);  // (the fill's cursor; each row's end when done)
  W.fluid.resize(nwp);
  W.w.resize(nwp);
  W.r.resize(nwp * D);
  for (const ThreadRows& T : per)
    for (std::size_t q = 0; q < T.rows.wall.size(); ++q) {
      const Rows& R = T.rows;
      const std::uint32_t k = W.end[R.wall[q]]++;
      W.fluid[k] = R.wfluid[q];
      W.w[k] = R.ww[q];
      for (int d = 0; d < D; ++d) W.r[std::size_t(k) * D + d] = R.wr[q * D + d];
    }
  W.begin.resize(np);
}
}  // namespace

template <int D>
void DualWCSPH<D>::find_pairs(System<D>& S, bool density) {
  auto& P = S.particles;
  const std::size_t np = P.size(), n_owned = P.n_owned();
  const Kind* __restrict kind = P.kind.data();
  const Vec<D>* __restrict pos = P.pos.data();
  const std::uint32_t* __restrict sorted = S.cells.sorted().data();
  const auto& cells = S.cells;
  int nthreads = 1;
#ifdef _OPENMP
  nthreads = omp_get_max_threads();
#endif
  // each thread writes its rows into its own region of the kept arrays (cap entries, gaps between regions); a region
  // too small for its thread's rows is found by the counts and the search runs again with larger ones
  const std::size_t nt = static_cast<std::size_t>(nthreads);
  std::vector<ThreadRows> per(nt);
  if (kept_.cap == 0) kept_.cap = 64 * kLanes;
  auto needs = [&](std::size_t cell) {
    std::size_t m = 0;
    for (std::uint32_t k = cells.cell_begin(cell); k < cells.cell_end(cell); ++k)
      m += sorted[k] < n_owned && kind[sorted[k]] == Kind::Fluid ? 1 : 0;
    return m;
  };
  const bool reinit = density && cfg_.density_reinit;
  const double rho0 = S.eos.rho0;
  for (;;) {
    const std::size_t cap = kept_.cap;
    kept_.begin.assign(np, 0);
    kept_.mid.assign(np, 0);
    kept_.end.assign(np, 0);
    kept_.j.resize(nt * cap);
    kept_.dw.resize(nt * cap);
    kept_.e.resize(nt * cap * D);
    for (auto& T : per) {
      T.need = 0;
      T.rows.clear();
    }
    S.with_kernel([&](const auto& K) {
      const F32 sup2 = F32(K.support2);
      if (sigma0_ <= 0.0) sigma0_ = lattice_kernel_sum<D>(K, S.dx);  // (after a restart too)
      const double sigma_inv = rho0 / sigma0_, w_self = K.W(0.0);
      sweep_cells<F32>(cells, D, kLanes, needs, [&](std::size_t cell, const CellStencil<D>& st, ScratchColumns<F32>& B) {
        std::size_t ut = 0;
#ifdef _OPENMP
        ut = static_cast<std::size_t>(omp_get_thread_num());
#endif
        thread_local CellSearch<D> cs;
        const std::uint32_t c0k = cells.cell_begin(cell), c1k = cells.cell_end(cell);
        const Vec<D> origin = pos[sorted[c0k]];
        cs.gather(st, B, pos, origin, kind);
        for (std::uint32_t kk = c0k; kk < c1k; ++kk) {
          const std::uint32_t a = sorted[kk];
          if (a >= n_owned || kind[a] != Kind::Fluid) continue;
          F32 xa[3];
          for (int d = 0; d < 3; ++d) xa[d] = F32(pos[a][std::min(d, D - 1)] - origin[std::min(d, D - 1)]);
          cs.select(xa, sup2);
          const std::size_t pf = (cs.nf + kLanes - 1) / kLanes * kLanes, pw = (cs.nw + kLanes - 1) / kLanes * kLanes;
          std::size_t& need = per[ut].need;
          const std::size_t first = ut * cap + need;
          need += pf + pw;
          if (first + pf + pw > (ut + 1) * cap) continue;  // (counted: the next attempt has room)
          std::uint32_t* jj = kept_.j.data();
          F32* dw = kept_.dw.data();
          F32* ee = kept_.e.data();
          F32 sw = cs.fill(K, xa, a, cs.fluid_sel(), cs.nf, pf, jj + first, dw + first, ee + first * D);
          sw += cs.fill(K, xa, a, cs.wall_sel(), cs.nw, pw, jj + first + pf, dw + first + pf, ee + (first + pf) * D);
          cs.wall_side(xa, a, per[ut].rows);
          // the summation density (walls count as lattice particles; a free-surface particle's truncated sum: ρ0)
          if (reinit) P.rho[a] = std::max(sigma_inv * (w_self + double(sw)), rho0);
          kept_.begin[a] = static_cast<std::uint32_t>(first);
          kept_.mid[a] = static_cast<std::uint32_t>(first + pf);
          kept_.end[a] = static_cast<std::uint32_t>(first + pf + pw);
        }
        return std::uint64_t(0);
      });
    });
    std::size_t most = 0;
    for (const auto& T : per) most = std::max(most, T.need);
    const std::size_t fit = (most + most / 4 + kLanes) / kLanes * kLanes;  // (room for the share to move)
    if (most <= cap) {
      if (fit < cap / 2) kept_.cap = fit;  // (shrink once the flow has settled into less)
      break;
    }
    kept_.cap = fit;  // (a thread's rows did not fit: again with room for them; the density is the same)
  }
  wall_rows<D>(per, np, kept_.walls);
  kept_.ids.assign(P.id.begin(), P.id.begin() + static_cast<std::ptrdiff_t>(np));
  kept_.layout = P.layout();
  kept_.valid = true;
}

template <int D>
void DualWCSPH<D>::follow_resort(System<D>& S) {
  // an output re-sorted the store (gauges and snapshots sort it): the rows move with their
  // particles and the partners' indices follow, by id; the pairs and their order stay
  auto& P = S.particles;
  const std::size_t np = P.size();
  if (np != kept_.ids.size()) {  // (particles removed at the domain's faces: find them afresh)
    find_pairs(S, false);
    return;
  }
  std::uint32_t max_id = 0;
  for (std::size_t i = 0; i < np; ++i) max_id = std::max(max_id, P.id[i]);
  std::vector<std::uint32_t> now(static_cast<std::size_t>(max_id) + 1, 0);
  for (std::size_t i = 0; i < np; ++i) now[P.id[i]] = static_cast<std::uint32_t>(i);
  std::vector<std::uint32_t> to(np);  // old store index → new
  for (std::size_t i = 0; i < np; ++i) to[i] = kept_.ids[i] <= max_id ? now[kept_.ids[i]] : 0;
  std::vector<std::uint32_t> begin(np, 0), mid(np, 0), end(np, 0);
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < np; ++i) {
    begin[to[i]] = kept_.begin[i];
    mid[to[i]] = kept_.mid[i];
    end[to[i]] = kept_.end[i];
  }
#pragma omp parallel for schedule(static)
  for (std::size_t k = 0; k < kept_.j.size(); ++k) kept_.j[k] = to[kept_.j[k]];
  kept_.begin.swap(begin);
  kept_.mid.swap(mid);
  kept_.end.swap(end);
  WallPairs& W = kept_.walls;  // (rows follow their walls, entries their fluid)
  std::vector<std::uint32_t> wb(np, 0), we(np, 0);
  for (std::size_t i = 0; i < np; ++i) {
    wb[to[i]] = W.begin[i];
    we[to[i]] = W.end[i];
  }
  for (auto& f : W.fluid) f = to[f];
  W.begin.swap(wb);
  W.end.swap(we);
  kept_.ids.assign(P.id.begin(), P.id.begin() + static_cast<std::ptrdiff_t>(np));
  kept_.layout = P.layout();
}

template <int D>
template <class K, int Pass>
void DualWCSPH<D>::kept_pass(System<D>& S, const K&) {
  static_assert(Pass == 0 || Pass == 1);
  auto& P = S.particles;
  const double rho0 = S.eos.rho0, c0 = S.eos.c0;
  const bool sym = cfg_.pressure_gradient == PressureGradient::Symmetric;
  pack_columns<D, Pass, true>(P, sym, pack_);  // (the records: dual_terms.hpp)
  const F32* __restrict pk = pack_.data();
  const std::size_t np = P.size(), n = P.n_owned();
  const Kind* __restrict kind = P.kind.data();
  const KeptRows R{kept_.begin.data(), kept_.mid.data(), kept_.end.data(), kept_.j.data(), kept_.dw.data(), kept_.e.data()};
  const F32 fk = F32(cfg_.riemann_limiter / c0);
  double g[3] = {0.0, 0.0, 0.0};
  for (int d = 0; d < D; ++d) g[d] = S.gravity[d];
  std::uint64_t pairs = 0;
#pragma omp parallel for schedule(dynamic, 256) reduction(+ : pairs)
  for (std::size_t a = 0; a < n; ++a) {
    if (kind[a] != Kind::Fluid) continue;
    const double rhoa = P.rho[a];
    if constexpr (Pass == 0) {
      const auto s = pressure_row<D>(R, pk, a);
      const double f = sym ? -1.0 : -1.0 / rhoa;
      Vec<D> ac = P.acc[a];  // the dissipation of the last continuity pass
      for (int d = 0; d < D; ++d) ac[d] += f * double(s[d]) + g[d];
      P.acc[a] = ac;
      P.drho[a] = rhoa / (rho0 * c0) * double(s[D]);
      pairs += static_cast<std::uint64_t>(s[D + 1] + F32(0.5));
    } else {
      const auto s = continuity_row<D>(R, pk, np, fk, a);
      P.drho[a] += rhoa * double(s[D]);
      const double f = -rho0 * c0 / rhoa;
      Vec<D> ac;
      for (int d = 0; d < D; ++d) ac[d] = f * double(s[d]);
      P.acc[a] = ac;
    }
  }
  if constexpr (Pass == 0) S.pairs_last_pass = pairs;
}

template <int D>
void DualWCSPH<D>::kept_pass_dispatch(System<D>& S, int pass) {
  S.with_kernel([&](const auto& K) {
    using Ker = std::decay_t<decltype(K)>;
    if (pass == 0) this->template kept_pass<Ker, 0>(S, K);
    else this->template kept_pass<Ker, 1>(S, K);
  });
}

template void DualWCSPH<2>::find_pairs(System<2>&, bool);
template void DualWCSPH<3>::find_pairs(System<3>&, bool);
template void DualWCSPH<2>::follow_resort(System<2>&);
template void DualWCSPH<3>::follow_resort(System<3>&);
template void DualWCSPH<2>::kept_pass_dispatch(System<2>&, int);
template void DualWCSPH<3>::kept_pass_dispatch(System<3>&, int);

}  // namespace sph
