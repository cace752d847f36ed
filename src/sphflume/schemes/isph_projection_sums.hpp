// The projection formulation's per-particle algebra and its vector pair loop (schemes/isph_projection.hpp): the
// corrected gradient's guarded inverse, the MLS weights at a wall's mirror point, and the moments' sums over a
// cell's candidate columns (moment_sums). Internal to isph_projection_passes.cpp. docs/numerics.md §13b.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <utility>
#include <vector>

// (GCC 12 warns of uninitialised lanes inside its own AVX-512 intrinsics as Eigen's small fixed-size
// solvers inline them: a false positive of the header, silenced for this file alone)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <Eigen/Dense>
#pragma GCC diagnostic pop

#include "sphflume/core/system.hpp"

namespace sph::projection_detail {

/// L = M⁻¹ of the symmetric D×D moment matrix M = Σ_j V_j r_ji ⊗ ∇_iW_ij (the identity on a full
/// lattice up to the kernel's discretisation), its eigenvalues held at ≥ lmin so that a particle with
/// a truncated support (the free surface, a splash) is not over-corrected (Bonet & Lok 1999; the
/// guard as the ISPH codes use one, docs/numerics.md §13).
template <int D>
void guarded_inverse(const double* M, double lmin, double* L) {
  if constexpr (D == 2) {
    // in closed form: eigenvalues l1,2 = m ± d; L = i2 I + (i1 − i2) P1, P1 = (M − l2 I)/(l1 − l2) the projector
    // on the first eigenvector, i = 1/max(l, lmin) (the eigen-decomposition below without its iterations)
    const double a = M[0], b = 0.5 * (M[1] + M[2]), c = M[3];
    const double m = 0.5 * (a + c), d = std::sqrt(0.25 * (a - c) * (a - c) + b * b);
    const double i1 = 1.0 / std::max(m + d, lmin), i2 = 1.0 / std::max(m - d, lmin);
    if (!(d > 1e-14 * std::abs(m))) {  // isotropic: M = m I
      L[0] = L[3] = i1;
      L[1] = L[2] = 0.0;
      return;
    }
    const double k = (i1 - i2) / (2.0 * d);
    L[0] = i2 + k * (a - (m - d));
    L[1] = L[2] = k * b;
    L[3] = i2 + k * (c - (m - d));
    return;
  }
  Eigen::Matrix<double, D, D> A;
  for (int a = 0; a < D; ++a)
    for (int b = 0; b < D; ++b) A(a, b) = 0.5 * (M[a * D + b] + M[b * D + a]);
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, D, D>> es(A);
  Eigen::Matrix<double, D, 1> ev = es.eigenvalues();
  for (int a = 0; a < D; ++a) ev[a] = 1.0 / std::max(ev[a], lmin);
  const Eigen::Matrix<double, D, D> inv = es.eigenvectors() * ev.asDiagonal() * es.eigenvectors().transpose();
  for (int a = 0; a < D; ++a)
    for (int b = 0; b < D; ++b) L[a * D + b] = inv(a, b);
}

template <int D>
Vec<D> apply(const double* L, const Vec<D>& g) {
  Vec<D> r{};
  for (int a = 0; a < D; ++a) {
    double s = 0.0;
    for (int b = 0; b < D; ++b) s += L[a * D + b] * g[b];
    r[a] = s;
  }
  return r;
}

/// The linear MLS weights w_j of the fluid at x (Σ_j w_j P_j interpolates a linear pressure exactly; the
/// moments scaled by h), into w; false where the fluid there is too sparse for the fit (its Shepard sum below
/// 1/4 of a full support, or weights beyond |Σ w| = 3: an extrapolation).
template <int D, class K>
bool mls_weights(const System<D>& S, const K& ker, const Vec<D>& x, std::vector<std::pair<std::uint32_t, double>>& w) {
  const auto& P = S.particles;
  const auto* pf = S.porous ? P.find(field::porosity) : nullptr;
  const double* phi = pf ? pf->data() : nullptr;
  using Mat = Eigen::Matrix<double, D + 1, D + 1>;
  using Col = Eigen::Matrix<double, D + 1, 1>;
  Mat A = Mat::Zero();
  double shep = 0.0;
  w.clear();
  auto pvec = [&](const Vec<D>& d) {  // [1, (x_j − x)/h]
    Col p;
    p[0] = 1.0;
    for (int a = 0; a < D; ++a) p[a + 1] = d[a] / S.h;
    return p;
  };
  S.cells.for_neighbours(P.pos, x, ker.support, [&](std::uint32_t j, const Vec<D>& r, double r2) {
    if (P.kind[j] != Kind::Fluid) return;
    const double vw = P.mass[j] / (S.eos.rho0 * (phi ? phi[j] : 1.0)) * ker.W(std::sqrt(r2));
    const Col p = pvec(-1.0 * r);
    A += vw * p * p.transpose();
    shep += vw;
    w.emplace_back(j, vw);
  });
  if (!(shep > 0.25)) return false;
  Eigen::LDLT<Mat> f(A);
  Col e0 = Col::Zero();
  e0[0] = 1.0;
  const Col beta = f.solve(e0);
  if (f.info() != Eigen::Success || !beta.allFinite()) return false;
  double wabs = 0.0;
  for (auto& [j, vw] : w) {
    vw *= beta.dot(pvec(P.pos[j] - x));
    wabs += std::abs(vw);
  }
  return wabs <= 3.0;
}

/// The candidate columns of one cell's stencil that moments() reads (positions, V, first-layer walls, the fluid
/// flag, φ, φ m_d, the velocity in the divergence) and writes (F, the in-the-sums flag, the Laplacian's weight).
struct MomentCols {
  const double *x0, *x1, *x2, *v, *w, *fl, *phi, *kj, *u0, *u1, *u2;
  double *f, *in, *c;
};

/// One fluid particle's sums over its cell's candidates (moments()): Σ V W, ∇C = Σ V F r, M = −Σ V F r ⊗ r, the
/// first-layer walls within dx, and the interior row's pair sums: the Laplacian's weights c_ij = −2 V F r²/(r² + η²)
/// (porous: times the conductivities' harmonic mean over φ_i) with their first moment a = Σ c r_ji and half second
/// moment m2 = ½ Σ c r², and G = Σ V F du ⊗ r (du = (φ_j/φ_i) u_j − u_i), whose contraction with L_i is the
/// corrected divergence. One vector loop; F, the flag and c_ij are written per candidate for the neighbour list.
/// With Detect, also the free surface's ∇·r = −Σ V F_d r² over the same neighbours with the detection kernel kd (its h
/// at most 1.5 dx, ProjectionISPH::moments); without, dr is left 0.
struct MomentSums {
  double conc, g[3], M[3][3], walls_near, a[3], m2, G[3][3], dr;
};
template <int D, bool Porous, bool Detect, class K>
[[gnu::always_inline]] inline MomentSums moment_sums(const K& kl, const K& kd, const MomentCols& b, std::size_t npad,
                                                     const double* xa, const double* ui, double phii, double ki,
                                                     double eta2, double dx2) {
  const double sup2 = kl.support2;
  const double* __restrict bx0 = b.x0;
  const double* __restrict bx1 = b.x1;
  const double* __restrict bx2 = b.x2;
  const double* __restrict bv = b.v;
  const double* __restrict bw = b.w;
  const double* __restrict bu0 = b.u0;
  const double* __restrict bu1 = b.u1;
  const double* __restrict bu2 = b.u2;
  double* __restrict bf = b.f;
  double* __restrict bin = b.in;
  double* __restrict bc = b.c;
  const double xa0 = xa[0], xa1 = xa[1], xa2 = xa[2], ui0 = ui[0], ui1 = ui[1], ui2 = ui[2];
  double c = 0.0, g0 = 0.0, g1 = 0.0, g2 = 0.0, m00 = 0.0, m01 = 0.0, m02 = 0.0, m11 = 0.0, m12 = 0.0, m22 = 0.0,
         wn = 0.0, a0 = 0.0, a1 = 0.0, a2 = 0.0, m2 = 0.0, G00 = 0.0, G01 = 0.0, G02 = 0.0, G10 = 0.0, G11 = 0.0,
         G12 = 0.0, G20 = 0.0, G21 = 0.0, G22 = 0.0, dr = 0.0;
#pragma omp simd reduction(+ : c, g0, g1, g2, m00, m01, m02, m11, m12, m22, wn, a0, a1, a2, m2, G00, G01, G02, G10, G11, G12, G20, G21, G22, dr)
  for (std::size_t m = 0; m < npad; ++m) {
    const double r0 = xa0 - bx0[m], r1 = xa1 - bx1[m], r2c = D == 3 ? xa2 - bx2[m] : 0.0;
    const double r2 = r0 * r0 + r1 * r1 + r2c * r2c;
    const double pair = (r2 < sup2) & (r2 > 0.0) ? 1.0 : 0.0;
    wn += (r2 < dx2) & (r2 > 0.0) ? bw[m] : 0.0;
    const double in = bv[m] > 0.0 ? pair : 0.0;
    const double rr = std::sqrt(r2);
    const double F = kl.F(rr);
    const double v = in * bv[m];
    bf[m] = F;
    bin[m] = in;
    c += v * kl.W(rr);
    const double f = v * F;  // −(−V F): the sums below carry M's and ∇C's signs
    g0 += f * r0;
    g1 += f * r1;
    m00 -= f * r0 * r0;
    m01 -= f * r0 * r1;
    m11 -= f * r1 * r1;
    if constexpr (Detect) dr -= v * kd.F(rr) * r2;  // (F_d = 0 beyond its own, smaller, support)
    double cij = -2.0 * f * r2 / (r2 + eta2);
    double ratio = 1.0;
    if constexpr (Porous) {
      const bool fl = b.fl[m] > 0.0;
      const double kj = fl ? b.kj[m] : ki;
      cij *= 2.0 * ki * kj / ((ki + kj) * phii);
      ratio = fl ? b.phi[m] / phii : 1.0;
    }
    bc[m] = cij;
    a0 -= cij * r0;
    a1 -= cij * r1;
    m2 += 0.5 * cij * r2;
    const double d0 = ratio * bu0[m] - ui0, d1 = ratio * bu1[m] - ui1;
    G00 += f * d0 * r0;
    G01 += f * d0 * r1;
    G10 += f * d1 * r0;
    G11 += f * d1 * r1;
    if constexpr (D == 3) {
      const double d2 = ratio * bu2[m] - ui2;
      g2 += f * r2c;
      m02 -= f * r0 * r2c;
      m12 -= f * r1 * r2c;
      m22 -= f * r2c * r2c;
      a2 -= cij * r2c;
      G02 += f * d0 * r2c;
      G12 += f * d1 * r2c;
      G20 += f * d2 * r0;
      G21 += f * d2 * r1;
      G22 += f * d2 * r2c;
    }
  }
  return {c, {g0, g1, g2}, {{m00, m01, m02}, {m01, m11, m12}, {m02, m12, m22}}, wn, {a0, a1, a2}, m2,
          {{G00, G01, G02}, {G10, G11, G12}, {G20, G21, G22}}, dr};
}

/// moment_sums with the case's options chosen at run time: porous or not, and the detection kernel's ∇·r where its
/// smoothing length hd is below the case's (the kernel kl's).
template <int D, class K>
inline MomentSums moment_sums_for(const K& kl, double hd, bool porous, const MomentCols& b, std::size_t npad,
                                  const double* xa, const double* ui, double phii, double ki, double eta2, double dx2) {
  const bool det = hd < kl.h * (1.0 - 1e-12);
  const K kd(det ? hd : kl.h);
  if (det)
    return porous ? moment_sums<D, true, true>(kl, kd, b, npad, xa, ui, phii, ki, eta2, dx2)
                  : moment_sums<D, false, true>(kl, kd, b, npad, xa, ui, phii, ki, eta2, dx2);
  return porous ? moment_sums<D, true, false>(kl, kd, b, npad, xa, ui, phii, ki, eta2, dx2)
                : moment_sums<D, false, false>(kl, kd, b, npad, xa, ui, phii, ki, eta2, dx2);
}

}  // namespace sph::projection_detail
