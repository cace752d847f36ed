// Kernel interpolation of particle fields at arbitrary points (gauges, probes, averaging
// nodes), from the particles that carry water (fluid, inflow, outflow). Requires an up-to-date cell list in S.
#pragma once
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <type_traits>
#include <vector>

#include <Eigen/Dense>

#include "sphflume/core/system.hpp"

namespace sph {

/// Per-particle porosity (null without porous media): volumes are m / (φ ρ).
template <int D>
const double* porosity_field(const System<D>& S) {
  const auto& F = S.particles.scalar_fields();
  const auto it = F.find("porosity");
  return it == F.end() ? nullptr : it->second.data();
}

/// The particles' smoothing lengths with resolution levels (docs/numerics.md §14), null with one
/// resolution: fetched once per interpolation, for point_kernel.
template <int D>
const double* level_h_field(const System<D>& S) {
  return S.level_h();
}

/// The kernel of particle b at distance r from the point: W(r, h) with one resolution (hs null);
/// with resolution levels W(r, h_b), each particle's own h (hs = level_h_field(S)), so that a
/// point among fine particles is read at their resolution.
template <class K>
double point_kernel(const K& k, const double* hs, std::uint32_t b, double r) {
  if (!hs) return k.W(r);
  return k.Wh(r, 1.0 / hs[b]);
}

/// Σ_b V_b W(x - x_b) over fluid particles: 1 inside the fluid, ~0.5 at the free surface.
template <int D>
double fluid_fraction(const System<D>& S, const Vec<D>& x) {
  const auto& P = S.particles;
  const double* phi = porosity_field(S);
  const double* hs = level_h_field(S);
  return S.with_kernel([&](const auto& K) {
    double s = 0.0;
    S.cells.for_neighbours(P.pos, x, K.support, [&](std::uint32_t b, const Vec<D>&, double r2) {
      if (fluid_like(P.kind[b])) s += P.mass[b] / (P.rho[b] * (phi ? phi[b] : 1.0)) * point_kernel(K, hs, b, std::sqrt(r2));
    });
    return s;
  });
}

namespace mls {
/// First-order MLS at x from the candidates kp[0..nk) (store indices, within the support, carrying water, in stencil
/// order): their columns (x_b − x, V_b = m_b/(ρ_b φ_b), 1/h_b on levels, the fields) into c (stride apart, at least
/// nk + 8 entries each), the moments Σ w q qᵀ and Σ w f q (q = (1, (x_b − x)/h), w = V_b W) summed in blocks of eight
/// lanes, vectorised, and the MLS solve (the Shepard average where the moment matrix is ill-conditioned; empty without
/// candidates).
template <int D, int NF, class Ker, class Fields>
std::optional<std::array<double, NF>> from_candidates(const System<D>& S, const Ker& K, const Vec<D>& x, const std::uint32_t* kp,
                                                      std::size_t nk, double* c, std::size_t stride, Fields& f) {
  const auto& P = S.particles;
  constexpr int NQ = D + 1, NM = NQ * (NQ + 1) / 2, NA = NM + NF * NQ, L = 8;
  constexpr int NC = D + 2 + NF;  // columns: x_b − x (D), V_b, 1/h_b, the fields
  using M = Eigen::Matrix<double, NQ, NQ>;
  using Vv = Eigen::Matrix<double, NQ, 1>;
  const double* phi = porosity_field(S);
  const double* hs = level_h_field(S);
  const Vec<D>* __restrict pos = P.pos.data();
  std::size_t k = 0;  // (the columns' entries)
  for (; k < nk; ++k) {
    const std::uint32_t b = kp[k];
    const Vec<D> rb = pos[b] - x;
    for (int d = 0; d < D; ++d) c[d * stride + k] = rb[d];
    c[D * stride + k] = P.mass[b] / (P.rho[b] * (phi ? phi[b] : 1.0));
    c[(D + 1) * stride + k] = hs ? 1.0 / hs[b] : 0.0;
    const std::array<double, NF> fb = f(b);
    for (int j = 0; j < NF; ++j) c[(D + 2 + j) * stride + k] = fb[j];
  }
  const int n = static_cast<int>(k);
  const std::size_t npad = (k + L - 1) / L * L;
  for (; k < npad; ++k)
    for (int j = 0; j < NC; ++j) c[j * stride + k] = 0.0;  // (padding: no volume, so no weight)
  const auto kl = K;  // (the loop's constants as locals)
  const double ih = 1.0 / K.h;
  alignas(64) double acc[NA][L] = {};
  auto blocks = [&](auto lev) {
    constexpr bool Lev = decltype(lev)::value;
    for (std::size_t b0 = 0; b0 < npad; b0 += L) {
      const double* __restrict cb = c + b0;
#pragma omp simd
      for (int l = 0; l < L; ++l) {
        double r2 = 0.0;
#pragma GCC unroll 3
        for (int d = 0; d < D; ++d) r2 += cb[d * stride + l] * cb[d * stride + l];
        const double r = std::sqrt(r2);
        double W;
        if constexpr (Lev) W = kl.Wh(r, cb[(D + 1) * stride + l]);
        else W = kl.W(r);
        const double vb = cb[D * stride + l];
        const double w = vb * W;  // (the padding's volume is 0)
        double q[NQ];
        q[0] = 1.0;
#pragma GCC unroll 3
        for (int d = 0; d < D; ++d) q[d + 1] = cb[d * stride + l] * ih;
#pragma GCC unroll 16
        for (int u = 0; u < NQ; ++u)
#pragma GCC unroll 16
          for (int v = u; v < NQ; ++v) acc[u * NQ - u * (u - 1) / 2 + (v - u)][l] += w * q[u] * q[v];
#pragma GCC unroll 8
        for (int j = 0; j < NF; ++j) {
          const double wf = w * cb[(D + 2 + j) * stride + l];
#pragma GCC unroll 4
          for (int u = 0; u < NQ; ++u) acc[NM + j * NQ + u][l] += wf * q[u];
        }
      }
    }
  };
  if (hs) blocks(std::true_type{});
  else blocks(std::false_type{});
  double sum[NA];
  for (int a = 0; a < NA; ++a) {
    double t = 0.0;
    for (int l = 0; l < L; ++l) t += acc[a][l];
    sum[a] = t;
  }
  const double sw = sum[0];
  if (n == 0 || sw <= 0.0) return std::nullopt;
  M A;
  for (int u = 0, a = 0; u < NQ; ++u)
    for (int v = u; v < NQ; ++v, ++a) A(u, v) = A(v, u) = sum[a];
  std::array<double, NF> out{};
  Eigen::FullPivLU<M> lu(A);
  if (n > D + 1 && lu.rank() == D + 1 && std::abs(lu.determinant()) > 1e-6 * std::pow(A(0, 0), D + 1)) {
    for (int j = 0; j < NF; ++j) out[j] = Vv(lu.solve(Vv(Eigen::Map<const Vv>(sum + NM + j * NQ))))[0];
  } else {
    for (int j = 0; j < NF; ++j) out[j] = sum[NM + j * NQ] / sw;
  }
  return out;
}
}  // namespace mls

/// Values of NF fields (f(b) returns them as an array) at x with a first-order (linear) moving-least-squares correction, which
/// reproduces linear fields exactly also where the kernel is truncated (walls, surface).
/// Falls back to the Shepard average when the moment matrix is ill-conditioned; empty when
/// no fluid particle is within the kernel support. The candidates that carry water within the support are kept
/// (their test without a branch) and handed to mls::from_candidates.
template <int D, int NF, class Fields>
std::optional<std::array<double, NF>> interpolate_mls_n(const System<D>& S, const Vec<D>& x, Fields&& f) {
  const auto& P = S.particles;
  constexpr int NC = D + 2 + NF, L = 8;
  return S.with_kernel([&](const auto& K) -> std::optional<std::array<double, NF>> {
    thread_local std::vector<double> col;
    std::uint32_t rg[CellList<D>::kMaxRanges][2];
    const int nr = S.cells.ranges(x, rg, K.support);
    std::size_t m = 0;
    for (int r = 0; r < nr; ++r) m += rg[r][1] - rg[r][0];
    if (col.size() < NC * (m + L)) col.resize(NC * (m + L));
    const std::size_t stride = m + L;  // (every candidate might be kept)
    const std::uint32_t* sorted = S.cells.sorted().data();
    const double support2 = K.support2;
    // the candidates that carry water within the support, their store indices compacted without a branch (the test
    // is taken by about one candidate in seven in 3D: as a branch per candidate it was four fifths of this function,
    // which is half of a 3D run with fixed ghost walls)
    thread_local std::vector<std::uint32_t> kept;
    if (kept.size() < m + 1) kept.resize(m + 1);
    std::uint32_t* __restrict kp = kept.data();
    const Vec<D>* __restrict pos = P.pos.data();
    const Kind* __restrict kind = P.kind.data();
    std::size_t nk = 0;
    for (int r = 0; r < nr; ++r)
      for (std::uint32_t e = rg[r][0]; e < rg[r][1]; ++e) {
        const std::uint32_t b = sorted[e];
        const Vec<D> rb = pos[b] - x;
        kp[nk] = b;
        nk += static_cast<std::size_t>((dot(rb, rb) < support2) & fluid_like(kind[b]));
      }
    return mls::from_candidates<D, NF>(S, K, x, kp, nk, col.data(), stride, f);
  });
}

/// interpolate_mls_n at several points whose supports one stencil covers (the ranges rg[0..nr) of sorted(): the fixed
/// ghost walls' mirror points of one cell), out(j, value) for the point xs[j]. The stencil's particles that carry
/// water are listed once with their positions as columns, and each point keeps those within its support by a
/// vectorised test, in stencil order: the candidates, their order and values are interpolate_mls_n's, and so are the
/// bits.
template <int D, int NF, class Fields, class Out>
void interpolate_mls_shared(const System<D>& S, const std::uint32_t (*rg)[2], int nr, const Vec<D>* xs, std::size_t nx,
                            Fields&& f, Out&& out) {
  const auto& P = S.particles;
  constexpr int NC = D + 2 + NF, L = 8;
  if (nx == 0) return;
  S.with_kernel([&](const auto& K) {
    thread_local std::vector<double> col, px;
    thread_local std::vector<std::uint32_t> ids, kept;
    thread_local std::vector<unsigned char> in;
    std::size_t m = 0;
    for (int r = 0; r < nr; ++r) m += rg[r][1] - rg[r][0];
    const std::size_t stride = m + L;
    if (col.size() < NC * stride) col.resize(NC * stride);
    if (px.size() < D * stride) px.resize(D * stride);
    if (ids.size() < stride) { ids.resize(stride); kept.resize(stride); in.resize(stride); }
    const std::uint32_t* sorted = S.cells.sorted().data();
    const Vec<D>* __restrict pos = P.pos.data();
    const Kind* __restrict kind = P.kind.data();
    std::uint32_t* __restrict id = ids.data();
    std::size_t nf = 0;  // the stencil's particles that carry water
    for (int r = 0; r < nr; ++r)
      for (std::uint32_t e = rg[r][0]; e < rg[r][1]; ++e) {
        const std::uint32_t b = sorted[e];
        id[nf] = b;
        nf += static_cast<std::size_t>(fluid_like(kind[b]));
      }
    double* __restrict xc = px.data();
    for (std::size_t i = 0; i < nf; ++i)
      for (int d = 0; d < D; ++d) xc[d * stride + i] = pos[id[i]][d];
    const double support2 = K.support2;
    unsigned char* __restrict hit = in.data();
    std::uint32_t* __restrict kp = kept.data();
    for (std::size_t j = 0; j < nx; ++j) {
      const Vec<D> x = xs[j];
#pragma omp simd
      for (std::size_t i = 0; i < nf; ++i) {
        double s = 0.0;  // (dot(x_b − x, x_b − x), as interpolate_mls_n's test)
#pragma GCC unroll 3
        for (int d = 0; d < D; ++d) {
          const double t = xc[d * stride + i] - x[d];
          s += t * t;
        }
        hit[i] = s < support2 ? 1 : 0;
      }
      std::size_t nk = 0;
      for (std::size_t i = 0; i < nf; ++i) {
        kp[nk] = id[i];
        nk += hit[i];
      }
      out(j, mls::from_candidates<D, NF>(S, K, x, kp, nk, col.data(), stride, f));
    }
  });
}

/// interpolate_mls_n for one field.
template <int D, class Field>
std::optional<double> interpolate_mls(const System<D>& S, const Vec<D>& x, Field&& f) {
  const auto v = interpolate_mls_n<D, 1>(S, x, [&](std::uint32_t b) { return std::array<double, 1>{f(b)}; });
  if (!v) return std::nullopt;
  return (*v)[0];
}

/// Shepard (zeroth-order) average of field f at x over fluid particles.
template <int D, class Field>
std::optional<double> interpolate_shepard(const System<D>& S, const Vec<D>& x, Field&& f) {
  const auto& P = S.particles;
  const double* phi = porosity_field(S);
  const double* hs = level_h_field(S);
  return S.with_kernel([&](const auto& K) -> std::optional<double> {
    double sw = 0.0, sf = 0.0;
    S.cells.for_neighbours(P.pos, x, K.support, [&](std::uint32_t b, const Vec<D>&, double r2) {
      if (!fluid_like(P.kind[b])) return;
      const double w = P.mass[b] / (P.rho[b] * (phi ? phi[b] : 1.0)) * point_kernel(K, hs, b, std::sqrt(r2));
      sw += w;
      sf += w * f(b);
    });
    if (sw <= 0.0) return std::nullopt;
    return sf / sw;
  });
}

/// First-order consistent gradient of field f at x from fluid particles:
/// (Σ V_b (x_b − x) ⊗ ∇W)⁻¹ Σ V_b (f_b − f̄) ∇W, f̄ the Shepard average (empty when the moment
/// matrix is singular, e.g. too few neighbours; its determinant is ~1 in a full support).
template <int D, class Field>
std::optional<Vec<D>> interpolate_gradient(const System<D>& S, const Vec<D>& x, Field&& f) {
  const auto fbar = interpolate_shepard(S, x, f);
  if (!fbar) return std::nullopt;
  const auto& P = S.particles;
  return S.with_kernel([&](const auto& K) -> std::optional<Vec<D>> {
    // M_ij = Σ V (x_b − x)_i ∂_j W; g_j = Σ V (f_b − f̄) ∂_j W ≈ Σ_i grad_i M_ij: solve Mᵀ grad = g
    Eigen::Matrix<double, D, D> M = Eigen::Matrix<double, D, D>::Zero();
    Eigen::Matrix<double, D, 1> g = Eigen::Matrix<double, D, 1>::Zero();
    S.cells.for_neighbours(P.pos, x, K.support, [&](std::uint32_t b, const Vec<D>& rxb, double r2) {
      if (!fluid_like(P.kind[b]) || r2 <= 0.0) return;
      const double V = P.mass[b] / P.rho[b], F = K.F(std::sqrt(r2));
      // ∇_x W(x − x_b) = F (x − x_b); x_b − x = −rxb
      Eigen::Matrix<double, D, 1> w, r;
      for (int d = 0; d < D; ++d) { w[d] = F * rxb[d]; r[d] = rxb[d]; }
      M.noalias() -= V * r * w.transpose();
      g += V * (f(b) - *fbar) * w;
    });
    Vec<D> out{};
    if constexpr (D == 2) {  // (Cramer's rule, as the 2D gauges have always been computed)
      const double det = M(0, 0) * M(1, 1) - M(0, 1) * M(1, 0);
      if (!(std::abs(det) > 1e-6)) return std::nullopt;
      out[0] = (g[0] * M(1, 1) - g[1] * M(1, 0)) / det;
      out[1] = (g[1] * M(0, 0) - g[0] * M(0, 1)) / det;
    } else {
      if (!(std::abs(M.determinant()) > 1e-6)) return std::nullopt;
      const Eigen::Matrix<double, D, 1> sol = M.transpose().partialPivLu().solve(g);
      for (int d = 0; d < D; ++d) out[d] = sol[d];
    }
    return out;
  });
}

/// Values at points, each computed by the part of the domain that holds the point (its
/// neighbours, owned or halo, are there) and summed over the parts: f(x, out) writes nv values
/// (NaN allowed); a point no part holds reads NaN. In one process: f at every point, as is.
template <int D, class F>
std::vector<double> at_held_points(const System<D>& S, const std::vector<Vec<D>>& pts, int nv, F&& f) {
  const std::size_t w = static_cast<std::size_t>(nv) + 1;
  std::vector<double> buf(pts.size() * w, 0.0);
  for (std::size_t i = 0; i < pts.size(); ++i)
    if (S.owns(pts[i])) {
      f(pts[i], &buf[i * w]);
      buf[i * w + w - 1] = 1.0;
    }
  S.comm->sum(buf.data(), buf.size());
  std::vector<double> out(pts.size() * (w - 1), std::numeric_limits<double>::quiet_NaN());
  for (std::size_t i = 0; i < pts.size(); ++i)
    if (buf[i * w + w - 1] > 0.0)
      for (std::size_t k = 0; k + 1 < w; ++k) out[i * (w - 1) + k] = buf[i * w + k] / buf[i * w + w - 1];
  return out;
}

/// The level at x: scan down the vertical line through x in steps of dx/4 from level_top to the
/// lowest particle (in blocks of points: each is read by the part of the domain that holds it);
/// the highest z where the fluid fraction Σ V_b W >= 0.5, linearly interpolated.
template <int D>
double water_level_at(Vec<D> x, const System<D>& S, double level_top) {
  const auto& P = S.particles;
  constexpr int vz = D - 1;
  const double step = 0.25 * S.dx;
  double zlo = level_top;
  for (std::size_t i = 0; i < P.n_owned(); ++i) zlo = std::min(zlo, P.pos[i][vz]);
  zlo = S.comm->min(zlo);
  double prev_f = 0.0, prev_z = level_top;
  constexpr int kBlock = 32;
  std::vector<Vec<D>> pts;
  for (double z = level_top; z >= zlo;) {
    pts.clear();
    for (int k = 0; k < kBlock && z >= zlo; ++k, z -= step) {
      x[vz] = z;
      pts.push_back(x);
    }
    const auto fr = at_held_points(S, pts, 1, [&](const Vec<D>& p, double* out) { out[0] = fluid_fraction(S, p); });
    for (std::size_t k = 0; k < pts.size(); ++k) {
      const double zk = pts[k][vz], f = std::isfinite(fr[k]) ? fr[k] : 0.0;
      if (f >= 0.5) {
        if (zk == level_top) return zk;
        return zk + (prev_z - zk) * (f - 0.5) / (f - prev_f);
      }
      prev_f = f;
      prev_z = zk;
    }
  }
  return std::numeric_limits<double>::quiet_NaN();
}

}  // namespace sph
