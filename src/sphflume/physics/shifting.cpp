#include "sphflume/physics/shifting.hpp"

#include <algorithm>
#include <cmath>

#include "sphflume/core/system.hpp"

namespace sph {

template <int D>
void Shifting<D>::compute_constant(System<D>& S) {
  // Lind et al. (2012): δr_a = −D (∇C_a + Σ_b V_b R (W_ab/W(dx))^n ∇_aW_ab), D = coefficient h², over fluid
  // and wall neighbours; a particle at the free surface (∇·r < 1.5 in 2D, 2.4 in 3D) or with one within its
  // support, or whose own ∇·r is below `surface`, moves along the surface only (its normal n = ∇C/|∇C|
  // removed); |δr| ≤ cap dx (the ISPH of Chow et al. 2018, docs/numerics.md §13)
  auto& P = S.particles;
  const std::size_t n = P.n_owned(), nall = P.size();
  auto& dr = P.vector(field::shift);
  std::fill(dr.begin(), dr.end(), Vec<D>{});
  const double surface = cfg_.surface > 0.0 ? cfg_.surface : (D == 2 ? 1.7 : 2.6);
  const double free = D == 2 ? 1.5 : 2.4;
  const auto* pf = S.porous ? P.find(field::porosity) : nullptr;
  const double* phi = pf ? pf->data() : nullptr;
  const double Dc = cfg_.coefficient * S.h * S.h, cap = cfg_.cap * S.dx;
  gc_.assign(nall, Vec<D>{});
  divr_.assign(nall, 0.0);
  at_surface_.assign(nall, 0);
  S.with_kernel([&](const auto& K) {
    const double w_dx = K.W(S.dx);
#pragma omp parallel for schedule(static)
    for (std::size_t a = 0; a < n; ++a) {
      if (P.kind[a] != Kind::Fluid) continue;
      Vec<D> gc{}, gt{};
      double divr = 0.0;
      S.cells.for_neighbours(P.pos, P.pos[a], K.support, [&](std::uint32_t b, const Vec<D>& r, double r2) {
        if (b == a || r2 <= 0.0 || (P.kind[b] != Kind::Fluid && P.kind[b] != Kind::Wall)) return;
        const double vb = P.mass[b] / (S.eos.rho0 * (phi && P.kind[b] == Kind::Fluid ? phi[b] : 1.0));
        const double rr = std::sqrt(r2);
        const double f = K.F(rr) * vb;
        gc += f * r;
        gt += (f * cfg_.tensile * std::pow(K.W(rr) / w_dx, cfg_.exponent)) * r;
        divr -= f * r2;
      });
      gc_[a] = gc;
      dr[a] = -Dc * (gc + gt);
      divr_[a] = divr;
      at_surface_[a] = divr < free ? 1 : 0;
    }
    S.refresh_halos(at_surface_.data());
    S.cells.mark_near(near_cells_, [&](std::size_t i) { return i < nall && at_surface_[i]; });
#pragma omp parallel for schedule(static)
    for (std::size_t a = 0; a < n; ++a) {
      if (P.kind[a] != Kind::Fluid) continue;
      bool near = divr_[a] < surface;
      if (!near && near_cells_[S.cells.cell_of(a)])
        S.cells.for_neighbours(P.pos, P.pos[a], K.support, [&](std::uint32_t b, const Vec<D>&, double) {
          near = near || (P.kind[b] == Kind::Fluid && at_surface_[b]);
        });
      Vec<D> d = dr[a];
      if (near) {
        const double g = std::sqrt(dot(gc_[a], gc_[a]));
        if (g > 0.0) {
          const Vec<D> nn = (1.0 / g) * gc_[a];
          d += (-dot(d, nn)) * nn;
        }
      }
      const double len = std::sqrt(dot(d, d));
      if (len > cap) d = (cap / len) * d;
      dr[a] = d;
    }
  });
}

template <int D>
void Shifting<D>::compute(System<D>& S, double dt) {
  if (cfg_.constant) {
    compute_constant(S);
    return;
  }
  auto& P = S.particles;
  const std::size_t n = P.n_owned(), nall = P.size();
  auto& dr = P.vector(field::shift);  // a particle field: it follows the store's re-sorting
  std::fill(dr.begin(), dr.end(), Vec<D>{});
  const double surface = cfg_.surface > 0.0 ? cfg_.surface : (D == 2 ? 1.5 : 2.75);
  const auto* pf = S.porous ? P.find(field::porosity) : nullptr;  // SPHAM volumes m/(φρ)
  const double* phi = pf ? pf->data() : nullptr;
  const double ah = cfg_.coefficient * S.h * dt;
  // pass 1: ∇C and ∇·r of every owned fluid particle; images take their sources' values
  gc_.assign(nall, Vec<D>{});
  at_surface_.assign(nall, 0);
  S.with_kernel([&](const auto& K) {
#pragma omp parallel for schedule(static)
    for (std::size_t a = 0; a < n; ++a) {
      if (P.kind[a] != Kind::Fluid) continue;
      Vec<D> gc{};
      double divr = 0.0;
      S.cells.for_neighbours(P.pos, P.pos[a], K.support, [&](std::uint32_t b, const Vec<D>& r, double r2) {
        if (b == a || r2 <= 0.0) return;
        const double vb = P.mass[b] / (P.rho[b] * (phi ? phi[b] : 1.0));
        const double f = K.F(std::sqrt(r2)) * vb;  // ∇_a W_ab V_b = f r_ab
        gc += f * r;
        divr -= f * r2;
      });
      gc_[a] = gc;
      at_surface_[a] = divr < surface ? 1 : 0;
    }
    S.refresh_halos(gc_.data());
    S.refresh_halos(at_surface_.data());
    // pass 2: the displacement; zero at the surface, tangential next to it (Lind et al. 2012).
    // Only particles in cells next to a surface particle's cell can have one within the support.
    S.cells.mark_near(near_cells_, [&](std::size_t i) { return i < nall && at_surface_[i]; });
#pragma omp parallel for schedule(static)
    for (std::size_t a = 0; a < n; ++a) {
      if (P.kind[a] != Kind::Fluid || at_surface_[a]) continue;
      const double u = std::sqrt(dot(P.vel[a], P.vel[a]));
      if (!near_cells_[S.cells.cell_of(a)]) {
        dr[a] = (-ah * u) * gc_[a];
        continue;
      }
      Vec<D> ns{};
      bool near = false;
      S.cells.for_neighbours(P.pos, P.pos[a], K.support, [&](std::uint32_t b, const Vec<D>&, double) {
        if (!at_surface_[b]) return;
        const double g = std::sqrt(dot(gc_[b], gc_[b]));
        if (g > 0.0) ns += (-1.0 / g) * gc_[b];  // the surface particle's outward normal
        near = true;
      });
      Vec<D> d = (-ah * u) * gc_[a];
      if (near) {
        const double nn = std::sqrt(dot(ns, ns));
        if (nn > 0.0) {
          ns = (1.0 / nn) * ns;
          d += (-dot(d, ns)) * ns;
        } else {
          d = Vec<D>{};
        }
      }
      dr[a] = d;
    }
  });
}

template <int D>
void Shifting<D>::apply(System<D>& S) const {
  auto& P = S.particles;
  const auto& dr = P.vector(field::shift);
  const std::size_t n = P.n_owned();
  for (std::size_t a = 0; a < n; ++a) P.pos[a] += dr[a];
}

template class Shifting<2>;
template class Shifting<3>;

}  // namespace sph
