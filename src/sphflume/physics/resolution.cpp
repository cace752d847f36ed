#include "sphflume/physics/resolution.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "sphflume/core/cell_list.hpp"
#include "sphflume/core/kernels.hpp"
#include "sphflume/core/refinement.hpp"
#include "sphflume/physics/relax_step.hpp"

namespace sph {

template <int D>
void smooth_level_h(System<D>& S) {
  auto& P = S.particles;
  auto& hs = P.require(field::smoothing_length);
  const auto& lv = P.require(field::level);
  const std::size_t n = P.n_owned();
  std::vector<double> out(n);  // (shared by the threads below: h is read while it is averaged)
  S.with_kernel([&](const auto& K) {
#pragma omp parallel for schedule(static)
    for (std::size_t a = 0; a < n; ++a) {
      double sw = 0.0, sh = 0.0;
      S.cells.for_neighbours(P.pos, P.pos[a], K.support, [&](std::uint32_t b, const Vec<D>&, double r2) {
        const double w = K.W(std::sqrt(r2)) * P.mass[b] / P.rho[b];
        sw += w;
        sh += w * level_h(S.h, static_cast<int>(lv[b]));
      });
      out[a] = sw > 0.0 ? sh / sw : level_h(S.h, static_cast<int>(lv[a]));
    }
  });
  std::copy(out.begin(), out.end(), hs.begin());
  S.refresh_halos(hs.data());
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
  std::vector<Vec<D>> shift(nf);
  with_kernel<D>(kernel, h0, [&](const auto& K) {
    CellList<D> cells;
    for (int it = 0; it <= iterations; ++it) {
      cells.build(pos, pos.size(), K.support);
      // h as the run takes it (smooth_level_h)
#pragma omp parallel for schedule(static)
      for (std::size_t a = 0; a < nf; ++a) {
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
      if (it == 0) { rep.residual0 = res; rep.band = nband; }
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

template void smooth_level_h<2>(System<2>&);
template void smooth_level_h<3>(System<3>&);
template LevelRelaxReport relax_level_band<2>(KernelType, double, double, std::vector<Vec<2>>&, const std::vector<int>&,
                                              const std::vector<Vec<2>>&, int);
template LevelRelaxReport relax_level_band<3>(KernelType, double, double, std::vector<Vec<3>>&, const std::vector<int>&,
                                              const std::vector<Vec<3>>&, int);

}  // namespace sph
