#include "sphflume/physics/shifting.hpp"

#include <algorithm>
#include <cmath>
#include <type_traits>

#include "sphflume/core/fields.hpp"
#include "sphflume/core/volume_sweep.hpp"
#include "sphflume/core/system.hpp"

namespace sph {

namespace {

/// The largest rate λ of the constant-D shift on a square (cubic) lattice of spacing dx: a displacement mode ε
/// of wave vector k changes by −D A(k) ε per step, A(k) = Σ_j G(r_j)(1 − cos k·r_j), G = ∂(φ(r) r)/∂r the
/// Jacobian of one pair's term φ(r) r = F(r)(1 + R (W/W(dx))^n) r; the step damps every mode for D λ < 2
/// (docs/numerics.md §13).
template <int D, class K>
double lattice_shift_rate(const K& ker, double dx, double R, double n) {
  const double w_dx = ker.W(dx);
  auto phi = [&](double r) { return ker.F(r) * (1.0 + R * std::pow(ker.W(r) / w_dx, n)); };
  const int m = static_cast<int>(std::ceil(ker.support / dx)) + 1;
  struct Site { double r[3]; double G[3][3]; };
  std::vector<Site> sites;
  for (int a = -m; a <= m; ++a)
    for (int b = -m; b <= m; ++b)
      for (int e = (D == 3 ? -m : 0); e <= (D == 3 ? m : 0); ++e) {
        const double x[3] = {a * dx, b * dx, e * dx};
        const double d = std::sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
        if (!(d > 0.0) || d >= ker.support) continue;
        const double eps = 1e-6 * dx;
        const double dphi = (phi(d + eps) - phi(d - eps)) / (2.0 * eps);
        Site s{};
        for (int p = 0; p < 3; ++p) {
          s.r[p] = x[p];
          for (int q = 0; q < 3; ++q) s.G[p][q] = (p == q ? phi(d) : 0.0) + dphi * x[p] * x[q] / d;
        }
        sites.push_back(s);
      }
  const int nk = D == 2 ? 40 : 16;
  double lmax = 0.0;
  for (int i = 0; i <= nk; ++i)
    for (int j = 0; j <= nk; ++j)
      for (int l = 0; l <= (D == 3 ? nk : 0); ++l) {
        const double k[3] = {M_PI / dx * i / nk, M_PI / dx * j / nk, M_PI / dx * l / nk};
        double A[3][3] = {};
        for (const auto& s : sites) {
          const double w = 1.0 - std::cos(k[0] * s.r[0] + k[1] * s.r[1] + k[2] * s.r[2]);
          for (int p = 0; p < D; ++p)
            for (int q = 0; q < D; ++q) A[p][q] += w * s.G[p][q];
        }
        // the largest |eigenvalue| of the symmetric D×D A: bounded by its Frobenius norm, exact through the
        // power iteration's few steps on so small a matrix
        double v[3] = {1.0, 0.7, 0.3}, lam = 0.0;
        for (int it = 0; it < 60; ++it) {
          double w[3] = {};
          for (int p = 0; p < D; ++p)
            for (int q = 0; q < D; ++q) w[p] += A[p][q] * v[q];
          double nv = 0.0;
          for (int p = 0; p < D; ++p) nv += w[p] * w[p];
          nv = std::sqrt(nv);
          if (!(nv > 0.0)) break;
          lam = nv;
          for (int p = 0; p < D; ++p) v[p] = w[p] / nv;
        }
        lmax = std::max(lmax, lam);
      }
  return lmax * std::pow(dx, D);  // (each neighbour's volume V = dx^D)
}

/// The velocity-scaled form's first pass (Shifting::compute): ∇C_a = Σ_b V_b ∇_aW_ab and ∇·r_a = −Σ_b V_b F r²
/// of every owned fluid particle over all its neighbours (V_b = m_b/(ρ_b φ_b); levels: h_ab), on the pair-pass
/// seam in double precision (each cell's candidates in columns, the loop vectorised); writes gc and divr.
template <int D, class K, bool Lev>
void surface_moments(System<D>& S, const K& ker, const double* phi, Vec<D>* gc, double* divr) {
  const double *rho = S.particles.rho.data(), *mass = S.particles.mass.data();
  const double support2 = ker.support2;
  volume_sweep<D, Lev>(
      S, [rho, mass, phi](std::size_t j) { return mass[j] / (rho[j] * (phi ? phi[j] : 1.0)); },
      [&](std::uint32_t a, double xa0, double xa1, double xa2, double ha, const double* __restrict x0,
          const double* __restrict x1, const double* __restrict x2, const double* __restrict bv,
          const double* __restrict bh, std::size_t npad) {
        const K kl = ker;
        const double l_support2 = support2;
        double g0 = 0.0, g1 = 0.0, g2 = 0.0, dv = 0.0;
#pragma omp simd reduction(+ : g0, g1, g2, dv)
        for (std::size_t k = 0; k < npad; ++k) {
          const double r0 = xa0 - x0[k], r1 = xa1 - x1[k], r2c = D == 3 ? xa2 - x2[k] : 0.0;
          const double r2 = r0 * r0 + r1 * r1 + r2c * r2c;
          const double rr = std::sqrt(r2);
          const double F = Lev ? kl.Fh(rr, 2.0 / (ha + bh[k])) : kl.F(rr);
          const bool in = (r2 > 0.0) & (r2 < l_support2);
          const double f = in ? F * bv[k] : 0.0;  // ∇_a W_ab V_b = f r_ab
          g0 += f * r0;
          g1 += f * r1;
          g2 += f * r2c;
          dv -= f * r2;
        }
        for (int d = 0; d < D; ++d) gc[a][d] = d == 0 ? g0 : d == 1 ? g1 : g2;
        divr[a] = dv;
      });
}

}  // namespace

template <int D>
double Shifting<D>::stable_coefficient(const System<D>& S) const {
  const double lam = S.with_kernel([&](const auto& K) { return lattice_shift_rate<D>(K, S.dx, cfg_.tensile, cfg_.exponent); });
  return lam > 0.0 ? 1.5 / (lam * S.h * S.h) : 0.5;
}

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
  if (cfg_.automatic && !(auto_coefficient_ > 0.0)) auto_coefficient_ = stable_coefficient(S);
  const double Dc = (cfg_.automatic ? auto_coefficient_ : cfg_.coefficient) * S.h * S.h, cap = cfg_.cap * S.dx;
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
  const double surface = cfg_.surface > 0.0 ? cfg_.surface : (D == 2 ? 1.5 : 2.75);
  const auto* pf = S.porous ? P.find(field::porosity) : nullptr;  // SPHAM volumes m/(φρ)
  const double* phi = pf ? pf->data() : nullptr;
  // resolution levels (docs/numerics.md §14): the pair's h_ab = (h_a + h_b)/2, as the pair pass takes it
  const double* hs = S.level_h();
  // pass 1: ∇C and ∇·r of every owned fluid particle (surface_moments); images take their sources' values
  gc_.assign(nall, Vec<D>{});
  at_surface_.assign(nall, 0);
  divr_.assign(nall, 0.0);
  S.with_kernel([&](const auto& K) {
    using Kt = std::decay_t<decltype(K)>;
    if (hs) surface_moments<D, Kt, true>(S, K, phi, gc_.data(), divr_.data());
    else surface_moments<D, Kt, false>(S, K, phi, gc_.data(), divr_.data());
  });
  for (std::size_t a = 0; a < n; ++a)
    if (P.kind[a] == Kind::Fluid) at_surface_[a] = divr_[a] < surface ? 1 : 0;
  displace(S, dt);
}

template <int D>
void Shifting<D>::compute(System<D>& S, double dt, const double* gc, const double* divr) {
  if (cfg_.constant || !gc || !divr) {
    compute(S, dt);
    return;
  }
  auto& P = S.particles;
  const std::size_t n = P.n_owned(), nall = P.size();
  const double surface = cfg_.surface > 0.0 ? cfg_.surface : (D == 2 ? 1.5 : 2.75);
  gc_.assign(nall, Vec<D>{});
  at_surface_.assign(nall, 0);
  for (std::size_t a = 0; a < n; ++a) {
    if (P.kind[a] != Kind::Fluid) continue;
    for (int k = 0; k < D; ++k) gc_[a][k] = gc[a * D + k];
    at_surface_[a] = divr[a] < surface ? 1 : 0;
  }
  displace(S, dt);
}

template <int D>
void Shifting<D>::displace(System<D>& S, double dt) {
  auto& P = S.particles;
  const std::size_t n = P.n_owned(), nall = P.size();
  auto& dr = P.vector(field::shift);  // a particle field: it follows the store's re-sorting
  std::fill(dr.begin(), dr.end(), Vec<D>{});
  const double ah = cfg_.coefficient * S.h * dt;
  const double* hs = S.level_h();  // (levels: h_a, h_ab)
  S.refresh_halos(gc_.data());
  S.refresh_halos(at_surface_.data());
  S.with_kernel([&](const auto& K) {
    // pass 2: the displacement; zero at the surface, tangential next to it (Lind et al. 2012).
    // Only particles in cells next to a surface particle's cell can have one within the support.
    S.cells.mark_near(near_cells_, [&](std::size_t i) { return i < nall && at_surface_[i]; });
#pragma omp parallel for schedule(static)
    for (std::size_t a = 0; a < n; ++a) {
      if (P.kind[a] != Kind::Fluid || at_surface_[a]) continue;
      const double u = std::sqrt(dot(P.vel[a], P.vel[a]));
      const double aha = hs ? cfg_.coefficient * hs[a] * dt : ah;
      if (!near_cells_[S.cells.cell_of(a)]) {
        dr[a] = (-aha * u) * gc_[a];
        continue;
      }
      Vec<D> ns{};
      bool near = false;
      S.cells.for_neighbours(P.pos, P.pos[a], K.support, [&](std::uint32_t b, const Vec<D>&, double r2) {
        if (!at_surface_[b]) return;
        if (hs && r2 >= 0.25 * K.support_factor * K.support_factor * (hs[a] + hs[b]) * (hs[a] + hs[b])) return;
        const double g = std::sqrt(dot(gc_[b], gc_[b]));
        if (g > 0.0) ns += (-1.0 / g) * gc_[b];  // the surface particle's outward normal
        near = true;
      });
      Vec<D> d = (-aha * u) * gc_[a];
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
