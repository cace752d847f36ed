#include "sphflume/physics/resolution.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "sphflume/core/cell_list.hpp"
#include "sphflume/core/kernels.hpp"
#include "sphflume/core/pair_pass.hpp"
#include "sphflume/core/refinement.hpp"
#include "sphflume/physics/relax_step.hpp"
#include "sphflume/physics/transport.hpp"

namespace sph {

template <int D>
void smooth_level_h(System<D>& S) {
  auto& P = S.particles;
  auto& hs = P.require(field::smoothing_length);
  const auto& lv = P.require(field::level);
  const std::size_t n = P.n_owned(), np = P.size();
  if (S.cells.sorted().size() < np)
    throw std::logic_error("smooth_level_h: the cell list does not hold every particle (update_neighbours first)");
  // cells whose stencil holds particles of more than one level: only their particles average
  // (elsewhere the average is the level's own h); the levels of each cell's stencil as bits, in one sweep
  // (the average's level-0 support: the widest stencil)
  std::vector<char> levels_near;
  S.cells.or_near(levels_near, [&](std::size_t i) { return static_cast<char>(1 << std::clamp(static_cast<int>(lv[i]), 0, 7)); }, S.support);
  std::vector<float> vol(np), hl(np);  // each candidate's m/ρ and its level's h
#pragma omp parallel for schedule(static)
  for (std::size_t b = 0; b < np; ++b) {
    vol[b] = static_cast<float>(P.mass[b] / P.rho[b]);
    hl[b] = static_cast<float>(level_h(S.h, static_cast<int>(lv[b])));
    if (b < n) hs[b] = level_h(S.h, static_cast<int>(lv[b]));
  }
  // the mixed cells' particles: Σ_b V_b W_ab h_b / Σ_b V_b W_ab over the level-0 support, in float
  // columns over the cell's stencil (the pair-pass seam, core/pair_pass.hpp): this average was
  // half a swash-band run's time as a double-precision neighbour loop (bench/README.md)
  const auto& cells = S.cells;
  const std::uint32_t* sorted = cells.sorted().data();
  constexpr std::size_t L = 16;
  const double h_fine = S.finest_h();
  S.with_kernel([&](const auto& K) {
    sweep_cells<float>(cells, D + 2, L, [&](std::size_t cell) -> std::size_t {
      if (std::popcount(static_cast<unsigned char>(levels_near[cell])) <= 1) return 0;
      std::size_t m = 0;
      for (std::uint32_t k = cells.cell_begin(cell); k < cells.cell_end(cell); ++k) m += sorted[k] < n ? 1 : 0;
      return m;
    }, [&](std::size_t cell, const CellStencil<D>& st, ScratchColumns<float>& B) {
      const std::uint32_t c0k = cells.cell_begin(cell), c1k = cells.cell_end(cell);
      const Vec<D> origin = P.pos[sorted[c0k]];
      gather_columns(st, B, P.pos.data(), origin, column(D, 0.0f, [&](std::size_t j) { return vol[j]; }),
                     column(D + 1, 1.0f, [&](std::size_t j) { return hl[j]; }));
      const float* __restrict bx0 = B[0];
      const float* __restrict bx1 = B[1];
      const float* __restrict bx2 = B[D - 1];
      const float* __restrict bv = B[D];
      const float* __restrict bh = B[D + 1];
      for (std::uint32_t k = c0k; k < c1k; ++k) {
        const std::uint32_t a = sorted[k];
        if (a >= n) continue;
        const float xa0 = float(P.pos[a][0] - origin[0]), xa1 = float(P.pos[a][1] - origin[1]),
                    xa2 = float(P.pos[a][D - 1] - origin[D - 1]);
        float sw = 0.0f, sh = 0.0f;
#pragma omp simd reduction(+ : sw, sh)
        for (std::size_t m = 0; m < st.padded; ++m) {
          const float r0 = xa0 - bx0[m], r1 = xa1 - bx1[m], r2 = D == 3 ? xa2 - bx2[m] : 0.0f;
          const float w = K.W(std::sqrt(r0 * r0 + r1 * r1 + r2 * r2)) * bv[m];
          sw += w;
          sh += w * bh[m];
        }
        if (sw > 0.0f) hs[a] = std::clamp(double(sh / sw), h_fine, S.h);  // (float round-off kept inside the levels' h)
      }
      return std::uint64_t(0);
    }, S.support);
  });
  S.refresh_halos(hs.data());
  S.set_cell_reach();  // (the pair passes' stencils follow the new h)
}

template <int D>
LevelRelaxReport relax_level_band(KernelType kernel, double h0, double dx0, std::vector<Vec<D>>& fluid,
                                  const std::vector<int>& level, const std::vector<Vec<D>>& walls, int iterations) {
  LevelRelaxReport rep;
  const std::size_t nf = fluid.size();
  std::vector<Vec<D>> pos(fluid);
  pos.insert(pos.end(), walls.begin(), walls.end());
  const std::vector<Vec<D>> start(fluid);
  auto lev = [&](std::size_t b) { return b < nf ? level[b] : 0; };
  std::vector<double> vol(pos.size()), hs(pos.size(), h0);
  for (std::size_t b = 0; b < pos.size(); ++b) vol[b] = std::pow(level_h(dx0, lev(b)), D);
  std::vector<char> band(nf, 0);
  std::vector<std::uint32_t> active;  // after the first iteration: the points whose h a band point's shift can change
  std::vector<Vec<D>> shift(nf);
  with_kernel<D>(kernel, h0, [&](const auto& K) {
    CellList<D> cells;
    // the active points: within a level-0 support of a band point's start plus its whole travel (dx_l/4 <= dx0/4;
    // margin dx0/2), marked once on a cell list of that reach; the others' supports never hold a point that moves
    auto mark_active = [&]() {
      std::vector<char> act(nf, 0);
      const double reach = K.support + 0.5 * dx0;
      CellList<D> wide;
      wide.build(pos, nf, reach);
      for (std::size_t a = 0; a < nf; ++a) {
        if (!band[a]) continue;
        wide.for_neighbours(pos, pos[a], reach, [&](std::uint32_t b, const Vec<D>&, double) { act[b] = 1; });
      }
      for (std::size_t a = 0; a < nf; ++a)
        if (act[a]) active.push_back(static_cast<std::uint32_t>(a));
    };
    for (int it = 0; it <= iterations; ++it) {
      cells.build(pos, pos.size(), K.support);
      // h as the run takes it (smooth_level_h): every point's at first, then only the active points' (the others'
      // supports hold no point that has moved: the same sums, in the same order)
      const std::size_t nh = it == 0 ? nf : active.size();
#pragma omp parallel for schedule(static)
      for (std::size_t k = 0; k < nh; ++k) {
        const std::size_t a = it == 0 ? k : active[k];
        double sw = 0.0, sh = 0.0;
        cells.for_neighbours(pos, pos[a], K.support, [&](std::uint32_t b, const Vec<D>&, double r2) {
          const double w = K.W(std::sqrt(r2)) * vol[b];
          sw += w;
          sh += w * level_h(h0, lev(b));
        });
        hs[a] = sh / sw;
      }
      double res = 0.0;
      std::size_t nband = 0;
#pragma omp parallel for schedule(dynamic, 256) reduction(max : res) reduction(+ : nband)
      for (std::size_t a = 0; a < nf; ++a) {
        shift[a] = Vec<D>{};
        if (it == 0) {  // the band and the free surface are decided once, on the lattice
          double wsum = 0.0, vsum = 0.0;
          bool other = false;
          Vec<D> centroid{};
          cells.for_neighbours(pos, pos[a], K.support, [&](std::uint32_t b, const Vec<D>& r, double r2) {
            const double w = K.W(std::sqrt(r2));
            wsum += w;
            vsum += w * vol[b];
            centroid += (-w) * r;
            other = other || (b < nf && lev(b) != lev(a));
          });
          band[a] = other && norm(centroid) < 0.2 * h0 * wsum && vsum > 0.97;
        }
        if (!band[a]) continue;
        ++nband;
        Vec<D> g{};
        cells.for_neighbours(pos, pos[a], K.support, [&](std::uint32_t b, const Vec<D>& r, double r2) {
          const double ih = 2.0 / (hs[a] + hs[b]);
          if (r2 > 0.0) g += (vol[b] * K.Fh(std::sqrt(r2), ih)) * r;
        });
        res = std::max(res, hs[a] * norm(g));
        shift[a] = relax_step<D>(g, hs[a], level_h(dx0, lev(a)), pos[a], start[a]);
      }
      if (it == 0) {
        rep.residual0 = res;
        rep.band = nband;
        mark_active();  // (at the lattice positions)
      }
      rep.residual = res;
      if (it == iterations) break;
      for (std::size_t a = 0; a < nf; ++a) pos[a] += shift[a];
      rep.iterations = it + 1;
    }
  });
  for (std::size_t a = 0; a < nf; ++a) {
    fluid[a] = pos[a];
    rep.max_shift = std::max(rep.max_shift, norm(pos[a] - start[a]));
  }
  return rep;
}

int target_level(const ResolutionConfig& res, const double* x, int dim) {
  int l = 0;
  for (const auto& r : res.regions)
    if (r.level > l && r.region.contains(x, dim)) l = r.level;
  return l;
}

template <int D>
void set_waterline_windows(ResolutionConfig& res, const Vec<D>* x, const Kind* kind, std::size_t n, double dx,
                           const Communicator& comm) {
  for (auto& rr : res.regions) {
    RegionConfig& g = rr.region;
    if (!g.follow_waterline || g.vertices.size() < 2) continue;
    const auto& v = g.vertices;
    std::vector<double> cum(v.size(), 0.0);
    for (std::size_t k = 1; k < v.size(); ++k) cum[k] = cum[k - 1] + std::hypot(v[k][0] - v[k - 1][0], v[k][1] - v[k - 1][1]);
    const double w = 2.0 * dx, reach = 1.5 * dx;
    const std::size_t nb = std::max<std::size_t>(1, static_cast<std::size_t>(std::ceil(cum.back() / w)));
    std::vector<double> wet(nb, 0.0), top(nb, -1e300);
    for (std::size_t i = 0; i < n; ++i) {
      if (kind && kind[i] != Kind::Fluid) continue;
      const double px = x[i][0], pz = x[i][D - 1];
      for (std::size_t k = 0; k + 1 < v.size(); ++k) {
        const double tx = v[k + 1][0] - v[k][0], tz = v[k + 1][1] - v[k][1];
        const double len = cum[k + 1] - cum[k], rx = px - v[k][0], rz = pz - v[k][1];
        const double along = (rx * tx + rz * tz) / len, normal = (rz * tx - rx * tz) / len;
        if (along < 0.0 || along > len || normal < -g.below || normal > reach) continue;
        const std::size_t b = std::min(nb - 1, static_cast<std::size_t>((cum[k] + along) / w));
        wet[b] = 1.0;
        top[b] = std::max(top[b], pz);
        break;
      }
    }
    comm.max(wet.data(), nb);
    comm.max(top.data(), nb);
    std::size_t k = 0;
    while (k < nb && wet[k] == 0.0) ++k;
    std::size_t last = nb;
    for (; k < nb && wet[k] != 0.0; ++k) last = k;
    if (last == nb) {  // no water on the line: the band holds nothing
      g.win_lo = g.win_hi = 1e300;
      continue;
    }
    g.win_lo = top[last] - g.waterline_below;
    g.win_hi = top[last] + g.waterline_above;
  }
}

template <int D>
bool outside_levels(const ResolutionConfig& res, const Vec<D>& x, int l, double margin) {
  constexpr int kPoints = D == 2 ? 9 : 27;  // x + margin {-1, 0, 1}^D: the corners too
  for (int k = 0; k < kPoints; ++k) {
    Vec<D> y = x;
    for (int d = 0, q = k; d < D; ++d, q /= 3) y[d] += margin * double(q % 3 - 1);
    if (target_level(res, y.c.data(), D) >= l) return false;
  }
  return true;
}

namespace {

/// A new particle (a split's child, a merge's result) has no step history: the Verlet
/// integrator's u(n−1) and ρ(n−1) become its present values, so its next step is the Euler step
/// that integrator takes every few steps anyway, rather than the two-step update
/// ρ(n+1) = ρ(n−1) + 2 Δt Dρ/Dt across the change of neighbours. (It did not cure the clustering
/// of a refined dam break's fine surface under Verlet: docs/numerics.md §14.)
template <int D>
void restart_history(ParticleStore<D>& P, std::size_t i) {
  if (P.has(field::v_prev)) P.vector(field::v_prev.name)[i] = P.vel[i];
  if (P.has(field::rho_prev)) P.scalar(field::rho_prev.name)[i] = P.rho[i];
}

template <int D>
std::size_t split_all(System<D>& S, const ResolutionConfig& res, std::uint32_t& next_id, std::vector<std::size_t>& kids) {
  auto& P = S.particles;
  auto& lv = P.require(field::level);
  const std::size_t n = P.n_owned();
  // (the regions' tests on the threads, the parents then taken in store order: the same ids on any thread count)
  std::vector<char> up(n, 0);
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i)
    up[i] = P.kind[i] == Kind::Fluid && target_level(res, P.pos[i].c.data(), D) > static_cast<int>(lv[i]);
  std::vector<std::size_t> parents;
  for (std::size_t i = 0; i < n; ++i)
    if (up[i]) parents.push_back(i);
  // ids: each rank's new particles take a block after the lower ranks' (the same ids on any
  // number of ranks as the splits' order; one process: next_id, next_id + 1, ...)
  std::uint64_t total = 0;
  const std::uint64_t first = S.comm->exscan(parents.size() * (kChildren<D> - 1), total);
  std::uint32_t id = next_id + static_cast<std::uint32_t>(first);
  next_id += static_cast<std::uint32_t>(total);
  if (parents.empty()) return 0;
  P.clear_images();
  for (std::size_t a : parents) {
    const int l = static_cast<int>(P.scalar(field::level.name)[a]);
    const auto xs = split_positions<D>(P.pos[a], 0.5 * level_h(S.dx, l));
    const double m = P.mass[a] / double(kChildren<D>);
    for (std::size_t k = 0; k < kChildren<D>; ++k) {
      const std::size_t c = k == 0 ? a : P.add_copy(a);
      P.pos[c] = xs[k];
      P.mass[c] = m;
      P.scalar(field::level.name)[c] = l + 1;
      P.scalar(field::smoothing_length.name)[c] = level_h(S.h, l + 1);
      if (k > 0) P.id[c] = id++;
      kids.push_back(c);
      restart_history(P, c);
    }
  }
  return parents.size();
}

template <int D>
std::size_t merge_all(System<D>& S, const ResolutionConfig& res) {
  auto& P = S.particles;
  const auto& lv = P.require(field::level);
  const std::size_t n = P.n_owned();
  std::vector<char> cand(n, 0);
  bool any = false;
#pragma omp parallel for schedule(static) reduction(|| : any)
  for (std::size_t i = 0; i < n; ++i) {
    const int l = static_cast<int>(lv[i]);
    if (P.kind[i] != Kind::Fluid || l == 0) continue;
    cand[i] = outside_levels<D>(res, P.pos[i], l, level_h(S.h, l - 1));
    any = any || cand[i];
  }
  if (!any) return 0;
  constexpr std::size_t G = kChildren<D>;
  // several phases: a group merges within one phase (a particle is one fluid or the other)
  const double* ph = S.phase_eos.empty() ? nullptr : P.require(field::phase).data();
  std::vector<char> gone(n, 0);
  std::vector<std::pair<double, std::uint32_t>> near;
  std::size_t groups = 0;
  for (std::size_t a = 0; a < n; ++a) {
    if (!cand[a]) continue;
    const int l = static_cast<int>(lv[a]);
    const double reach = level_h(S.dx, l - 1);  // a level-(l − 1) spacing
    near.clear();
    S.cells.for_neighbours(P.pos, P.pos[a], reach, [&](std::uint32_t b, const Vec<D>&, double r2) {
      if (b != a && b < n && cand[b] && static_cast<int>(lv[b]) == l && (!ph || ph[b] == ph[a])) near.emplace_back(r2, b);
    });
    if (near.size() < G - 1) continue;
    std::partial_sort(near.begin(), near.begin() + static_cast<std::ptrdiff_t>(G - 1), near.end());
    std::array<std::size_t, G> g;
    g[0] = a;
    for (std::size_t k = 1; k < G; ++k) g[k] = near[k - 1].second;
    double M = 0.0, vol = 0.0;
    Vec<D> mx{}, mv{}, ma{};
    double mdrho = 0.0;
    for (std::size_t i : g) {
      M += P.mass[i];
      vol += P.mass[i] / P.rho[i];
      mx += P.mass[i] * P.pos[i];
      mv += P.mass[i] * P.vel[i];
      ma += P.mass[i] * P.acc[i];
      mdrho += P.mass[i] * P.drho[i];
    }
    std::array<double, G> w;
    for (std::size_t k = 0; k < G; ++k) w[k] = P.mass[g[k]] / M;
    // transported scalars: the merged particle carries the group's scalar mass Σ m C/ρ (the mass-weighted mean of
    // the mass fraction C/ρ, at the merged density), not the mean of C (which is not kept when the densities differ)
    const std::size_t ns = S.transport ? S.transport->count() : 0;
    std::vector<double> yfrac(ns, 0.0);
    for (std::size_t k = 0; k < ns; ++k) {
      const auto& C = S.transport->field(S, k);
      for (std::size_t j = 0; j < G; ++j) yfrac[k] += w[j] * C[g[j]] / P.rho[g[j]];
    }
    P.mean_extra_fields(a, g.data(), w.data(), G);
    P.pos[a] = (1.0 / M) * mx;
    P.vel[a] = (1.0 / M) * mv;
    P.acc[a] = (1.0 / M) * ma;
    P.drho[a] = mdrho / M;
    P.rho[a] = M / vol;
    P.mass[a] = M;
    for (std::size_t k = 0; k < ns; ++k) S.transport->field(S, k)[a] = P.rho[a] * yfrac[k];
    P.scalar(field::level.name)[a] = l - 1;
    P.scalar(field::smoothing_length.name)[a] = level_h(S.h, l - 1);
    restart_history(P, a);
    for (std::size_t k = 1; k < G; ++k) { gone[g[k]] = 1; cand[g[k]] = 0; }
    cand[a] = 0;
    ++groups;
  }
  if (groups > 0) {
    P.clear_images();
    P.remove_if_flagged(gone);
  }
  return groups;
}

/// The children of this call's splits, shifted apart (docs/numerics.md §14): a split's pattern
/// lands wherever its parent stood, so its children can fall closer than a fine spacing to the
/// particles of the finer level already there; each iteration moves every child not at the
/// free surface by relax_step against Σ_b V_b ∇W_ab (h_ab as the pair pass takes it), at most
/// dx_l/4 from where it was placed. Positions only: mass and momentum are untouched.
template <int D>
void settle_children(System<D>& S, const std::vector<std::size_t>& kids, int iterations) {
  // (a distributed run: every rank iterates, refreshing the halo copies after each iteration, so
  // that children on either side of a rank's edge move together as in one process)
  const bool distributed = S.comm->size() > 1;
  if ((kids.empty() && !distributed) || iterations <= 0) return;
  auto& P = S.particles;
  const auto& hs = P.require(field::smoothing_length);
  const auto& lv = P.require(field::level);
  CellList<D> cells;  // (the store is not sorted again until the caller's re-sort)
  const std::vector<Vec<D>> placed = [&] {
    std::vector<Vec<D>> v;
    for (std::size_t c : kids) v.push_back(P.pos[c]);
    return v;
  }();
  std::vector<Vec<D>> shift(kids.size());
  std::vector<char> surface(kids.size(), 0);
  S.with_kernel([&](const auto& K) {
    for (int it = 0; it < iterations; ++it) {
      cells.build(P.pos, P.size(), K.support);
#pragma omp parallel for schedule(static)
      for (std::size_t k = 0; k < kids.size(); ++k) {
        const std::size_t a = kids[k];
        shift[k] = Vec<D>{};
        Vec<D> g{}, centroid{}, nearest{};
        double wsum = 0.0, r2min = 1e300;
        cells.for_neighbours(P.pos, P.pos[a], K.support, [&](std::uint32_t b, const Vec<D>& r, double r2) {
          if (r2 <= 0.0) return;
          const double ih = 2.0 / (hs[a] + hs[b]), rr = std::sqrt(r2);
          g += (P.mass[b] / P.rho[b] * K.Fh(rr, ih)) * r;
          const double w = K.Wh(rr, ih);
          wsum += w;
          centroid += (-w) * r;
          if (r2 < r2min) { r2min = r2; nearest = r; }
        });
        if (it == 0) surface[k] = wsum <= 0.0 || norm(centroid) > 0.2 * hs[a] * wsum;
        const int l = static_cast<int>(lv[a]);
        const double dxl = level_h(S.dx, l);
        if (!surface[k]) {
          shift[k] = relax_step<D>(g, hs[a], dxl, P.pos[a], placed[k]);
        } else if (r2min < 0.5625 * dxl * dxl) {  // at the surface: only apart from a particle within 0.75 dx_l
          const double d = std::sqrt(r2min);
          Vec<D> step = (0.25 * (0.75 * dxl - d) / d) * nearest;
          if (norm(P.pos[a] + step - placed[k]) <= 0.25 * dxl) shift[k] = step;
        }
      }
      for (std::size_t k = 0; k < kids.size(); ++k) P.pos[kids[k]] += shift[k];
      if (distributed) S.refresh_halos();
    }
  });
}

}  // namespace

template <int D>
AdaptCounts adapt_levels(System<D>& S, const ResolutionConfig& res, std::uint32_t& next_id) {
  AdaptCounts c;
  if (next_id == 0) {  // the first new id: above every particle's (on every rank)
    double top = 0.0;
    for (std::size_t i = 0; i < S.particles.n_owned(); ++i) top = std::max(top, double(S.particles.id[i]) + 1.0);
    S.comm->max(&top, 1);
    next_id = static_cast<std::uint32_t>(top);
  }
  // bands that follow the waterline: their windows from the present state (every step, so a
  // restart needs no state of its own)
  bool follow = false;
  for (const auto& r : res.regions) follow = follow || r.region.follow_waterline;
  ResolutionConfig live;
  if (follow) {
    live = res;
    set_waterline_windows<D>(live, S.particles.pos.data(), S.particles.kind.data(), S.particles.n_owned(), S.dx, *S.comm);
  }
  const ResolutionConfig& now = follow ? live : res;
  c.merged = merge_all(S, now);  // (on the sorted store: its cell list is current)
  std::vector<std::size_t> kids;
  c.split = split_all(S, now, next_id, kids);
  const bool settle = res.settle_iterations > 0 && (S.comm->size() == 1 || S.comm->any(!kids.empty()));
  if (S.comm->size() > 1 && settle) {
    // a distributed run: the children settle against the particles across the ranks' edges too
    // (the split cleared the halo copies): re-sort with halos, then find the children by id
    // (every rank's: the re-sort hands a child that crossed a rank's edge to its new owner)
    auto& P = S.particles;
    std::vector<double> mine;
    for (std::size_t k : kids) mine.push_back(double(P.id[k]));
    std::vector<char> child(next_id, 0);
    for (const double id : S.comm->allgather(mine)) child[static_cast<std::size_t>(id)] = 1;
    S.update_neighbours();
    kids.clear();
    for (std::size_t i = 0; i < P.n_owned(); ++i)
      if (P.id[i] < next_id && child[P.id[i]]) kids.push_back(i);
  }
  if (settle) settle_children(S, kids, res.settle_iterations);
  return c;
}

template <int D>
double finest_present_h(const System<D>& S) {
  if (S.levels == 0) return S.h;
  const auto& P = S.particles;
  const double* lv = P.require(field::level).data();
  int fluid = 0, wall = 0;  // the finest level present among the fluid and the wall particles
  const std::size_t n = P.n_owned();
#pragma omp parallel for schedule(static) reduction(max : fluid, wall)
  for (std::size_t i = 0; i < n; ++i) {
    const int l = static_cast<int>(lv[i]);
    if (P.kind[i] == Kind::Fluid) fluid = std::max(fluid, l);
    else wall = std::max(wall, l);
  }
  double lv2[2] = {double(fluid), double(wall)};  // (every rank the same h: the step does not depend on the cut)
  S.comm->max(lv2, 2);
  fluid = static_cast<int>(lv2[0]);
  wall = static_cast<int>(lv2[1]);
  const double hf = level_h(S.h, fluid);
  return wall > fluid ? 0.5 * (hf + level_h(S.h, wall)) : hf;  // (the pairs of the fluid with finer walls)
}

template double finest_present_h<2>(const System<2>&);
template double finest_present_h<3>(const System<3>&);
template void smooth_level_h<2>(System<2>&);
template void smooth_level_h<3>(System<3>&);
template void set_waterline_windows<2>(ResolutionConfig&, const Vec<2>*, const Kind*, std::size_t, double, const Communicator&);
template void set_waterline_windows<3>(ResolutionConfig&, const Vec<3>*, const Kind*, std::size_t, double, const Communicator&);
template bool outside_levels<2>(const ResolutionConfig&, const Vec<2>&, int, double);
template bool outside_levels<3>(const ResolutionConfig&, const Vec<3>&, int, double);
template AdaptCounts adapt_levels<2>(System<2>&, const ResolutionConfig&, std::uint32_t&);
template AdaptCounts adapt_levels<3>(System<3>&, const ResolutionConfig&, std::uint32_t&);
template LevelRelaxReport relax_level_band<2>(KernelType, double, double, std::vector<Vec<2>>&, const std::vector<int>&,
                                              const std::vector<Vec<2>>&, int);
template LevelRelaxReport relax_level_band<3>(KernelType, double, double, std::vector<Vec<3>>&, const std::vector<int>&,
                                              const std::vector<Vec<3>>&, int);

}  // namespace sph
