// The pair passes of the projection (Lind–Skillen–Chow) formulation (schemes/isph_projection.hpp):
// the walls' wetness at their mirror points, the fluid's kernel-gradient correction and ∇·r, the
// PPE's rows (fluid: Laplacian and corrected divergence; walls: the linear MLS interpolation at the
// mirror point) and the corrected pressure gradient. docs/numerics.md §13.
#include <algorithm>
#include <cmath>
#include <numbers>
#ifdef _OPENMP
#include <omp.h>
#endif

#include "sphflume/core/cell_list.hpp"
#include "sphflume/core/pair_pass.hpp"
#include "sphflume/physics/porous.hpp"
#include "sphflume/schemes/isph_projection.hpp"
#include "sphflume/schemes/isph_projection_sums.hpp"

namespace sph {
using projection_detail::apply;
using projection_detail::guarded_inverse;
using projection_detail::mls_weights;
using projection_detail::moment_sums_for;
using projection_detail::MomentCols;
using projection_detail::MomentSums;

template <int D>
template <class K>
void ProjectionISPH<D>::wall_rows(System<D>& S, const K& ker) {
  // A wall particle with no fluid within its support is out of every sum (Out). Else it is an unknown (WallRow)
  // whose pressure is the fluid's interpolated at its mirror point r_m = r_b + 2 s (s: its vector to the wall
  // surface) plus the body force's offset, or, where the mirror point is in the air, Adami's extrapolation;
  // the weights and the offset's lever are kept for assemble(), and the wall's velocity in the divergence is set.
  auto& P = S.particles;
  const std::size_t n = P.n_owned();
  const auto& to = P.vector(field::wall_to_surface);
  const double* phi = S.porous ? P.scalar(field::porosity).data() : nullptr;
  const double rho0 = S.eos.rho0;
  const double thr = o_.fs_threshold > 0.0 ? o_.fs_threshold : (D == 2 ? 1.5 : 2.4);
  cls_.assign(n, Out);
  wet_.assign(P.size(), 0.0);
  mls_.resize(n);
  lever_.assign(n, Vec<D>{});
  const auto* aw = P.find(field::wall_acc);
#pragma omp parallel for schedule(dynamic, 64)
  for (std::size_t b = 0; b < n; ++b) {
    if (P.kind[b] != Kind::Wall) continue;
    bool near = false;
    S.cells.for_neighbours(P.pos, P.pos[b], ker.support, [&](std::uint32_t j, const Vec<D>&, double) {
      near = near || P.kind[j] == Kind::Fluid;
    });
    if (!near) continue;
    const Vec<D> xm = P.pos[b] + 2.0 * to[b];
    double divr = 0.0, solid = 0.0;  // solid: the walls' Shepard sum Σ V W at the mirror point
    bool fluid = false;
    S.cells.for_neighbours(P.pos, xm, ker.support, [&](std::uint32_t j, const Vec<D>&, double r2) {
      const bool fl = P.kind[j] == Kind::Fluid;
      if (!fl && P.kind[j] != Kind::Wall) return;
      fluid = fluid || fl;
      const double V = P.mass[j] / (rho0 * (fl && phi ? phi[j] : 1.0)), rr = std::sqrt(r2);
      divr -= V * ker.F(rr) * rr * rr;
      if (!fl) solid += V * ker.W(rr);
    });
    // the fluid's pressure field continued linearly to the mirror point (a linear MLS fit) while the mirror
    // point lies in the water or within about dx of it (∇·r ≥ 1 in 2D, 1.5 in 3D, Chow's BoundaryFS; with P = 0
    // on the surface particles, ≥ the surface's threshold)
    const double air = o_.fs_at_surface ? (D == 2 ? 1.0 : 1.5) : thr;
    cls_[b] = WallRow;
    wet_[b] = 1.0;
    if (!o_.wall_adami && fluid && divr >= air && mls_weights<D>(S, ker, xm, mls_[b])) {
      lever_[b] = P.pos[b] - xm;
      continue;
    }
    adami_row(S, ker, b, !o_.wall_adami && solid < 0.5);
  }
  S.refresh_halos(wet_.data());
  // each wet wall's velocity in the fluid's divergence: the fluid's velocity at its mirror point (its
  // interpolation weights) with the normal part, relative to the wall's, reflected, u_b = u_f − 2 ((u_f − u_w)·n) n:
  // the normal velocity midway, at the wall's surface, is the wall's, and a flow along the wall is no divergence
  // (the wall's own velocity there made a film's tip on the bed a sink of −10⁴ … −10⁶ Pa; Chow et al.'s no-slip
  // mirror 2 u_w − u_f doubles that and blew the dam break up at 0.2 s: docs/numerics.md §13). u_w at t_n: a
  // moving wall's acceleration is in its pressure's offset
  ub_.assign(P.size(), Vec<D>{});
#pragma omp parallel for schedule(static)
  for (std::size_t b = 0; b < n; ++b) {
    if (P.kind[b] != Kind::Wall) continue;
    const Vec<D> uw = aw ? P.vel[b] - dt_ * (*aw)[b] : P.vel[b];
    ub_[b] = uw;
    if (!(wet_[b] > 0.0) || mls_[b].empty()) continue;
    Vec<D> uf{};
    for (const auto& [j, w] : mls_[b]) uf += w * P.vel[j];
    const Vec<D> nw = (1.0 / norm(to[b])) * to[b];
    ub_[b] = uf - (2.0 * dot(uf - uw, nw)) * nw;
  }
  S.refresh_halos(ub_.data(), 1);
}

template <int D>
template <class K>
void ProjectionISPH<D>::adami_row(const System<D>& S, const K& ker, std::size_t b, bool mirror_in_air) {
  const auto& P = S.particles;
  const auto& to = *P.find(field::wall_to_surface);
  const auto* aw = P.find(field::wall_acc);
  // Adami et al. (2012)'s extrapolation from the fluid around the wall particle itself,
  // P_b = Σ_f W_bf (P_f + ρ0 (g − a_w)·(r_b − r_f)) / Σ_f W_bf (its weights into mls_[b], its mean lever
  // Σ w (r_b − r_f)), where `wall_pressure: adami`, where the mirror point lies inside another solid (the walls'
  // Shepard sum there ≥ 1/2, its value on a flat wall's face; 0.25 in the air dx/2 beside a wall, 0.6–0.8 inside
  // a paddle standing on the bed: out of the sums such a wall left a hole that drew the water into the paddle's
  // foot at 0.07 m/s), or where the wall lies under the fluid around it ((g − a_w)·lever > 0: the deep layers under
  // a film or a thin layer, whose mirror points are in the air: out of the sums they left the layer's bottom row
  // without support, a free surface by ∇·r, and a still shoreline on a 1:20 slope threw its layer up within
  // 0.5 s, docs/numerics.md §13b). A wall in the air beside or above the water (the lever level or upwards) is
  // Known, P = 0, and out of the fluid's sums: the fluid there sees a free surface (Adami's extrapolation there
  // sucked the contact line up the wall)
  auto& w = mls_[b];
  w.clear();
  double sw = 0.0;
  Vec<D> sr{};
  S.cells.for_neighbours(P.pos, P.pos[b], ker.support, [&](std::uint32_t j, const Vec<D>& r, double r2) {
    if (P.kind[j] != Kind::Fluid) return;
    const double wj = ker.W(std::sqrt(r2));
    sw += wj;
    sr += wj * r;
    w.emplace_back(j, wj);
  });
  for (auto& [j, wj] : w) wj /= sw;
  lever_[b] = (1.0 / sw) * sr;
  const Vec<D> ge = aw ? S.gravity - (*aw)[b] : S.gravity;
  if (mirror_in_air) {
    if (!(dot(ge, lever_[b]) > 0.0)) {
      cls_[b] = Known;
      wet_[b] = 0.0;
      w.clear();
      lever_[b] = Vec<D>{};
    } else {
      // under a thin layer: the offset along the wall's normal only, ρ0 (g − a_w)·n (n·lever), the pressure of a
      // layer lying along the wall. With the whole lever a wall ahead of a film's tip on a slope (higher, so
      // nearer the tip's height) read less than one behind it: a pressure falling up the slope by ρ0 g sinθ that
      // cancelled gravity's pull along it, and the swash's tip coasted up Flume B's frictionless 1:20 slope
      // gaining height (+0.1 m of energy head in 1 s, the run-up +30 %, docs/numerics.md §13b)
      const Vec<D> nw = (1.0 / norm(to[b])) * to[b];
      lever_[b] = dot(lever_[b], nw) * nw;
    }
  }
}

template <int D>
void ProjectionISPH<D>::keep_neighbours(std::size_t i, int tid, std::size_t cnt, const projection_detail::MomentCols& b,
                                        const double* idx) {
  // particle i's neighbours in the sums (the flag `in`) with F, V and c_ij, appended to its thread's list in the
  // stencil's order (kept without a branch: which candidates are in is a coin toss for the branch predictor)
  auto& buf = near_buf_[static_cast<std::size_t>(tid)].v;
  near_thread_[i] = static_cast<std::uint32_t>(tid);
  near_first_[i] = static_cast<std::uint32_t>(buf.size());
  const std::size_t first = buf.size();
  buf.resize(first + cnt);
  Near* __restrict o = buf.data() + first;
  std::size_t kept = 0;
  for (std::size_t m = 0; m < cnt; ++m) {
    o[kept] = {static_cast<std::uint32_t>(idx[m]), b.f[m], b.v[m], b.c[m]};
    kept += b.in[m] > 0.0 ? 1 : 0;
  }
  buf.resize(first + kept);
  near_count_[i] = static_cast<std::uint32_t>(kept);
}

template <int D>
void ProjectionISPH<D>::first_layer_walls(const System<D>& S, std::size_t i, std::size_t cnt, const double* wall1,
                                          const double* idx) {
  // the distinct walls (normals) of the first-layer wall particles closer than dx (the rest distance), in the
  // stencil's order, with their velocities (correct(), step(): no flow or displacement into them)
  const auto& P = S.particles;
  const auto& to = *P.find(field::wall_to_surface);
  const double dx2 = S.dx * S.dx;
  Vec<D>* wn = &wall_n_[i * D];
  Vec<D>* wu = &wall_u_[i * D];
  int walls = 0;
  for (std::size_t m = 0; m < cnt && walls < D; ++m) {
    if (!(wall1[m] > 0.0)) continue;
    const auto j = static_cast<std::uint32_t>(idx[m]);
    const Vec<D> r = P.pos[i] - P.pos[j];
    const double r2 = dot(r, r);
    if (!(r2 < dx2) || !(r2 > 0.0)) continue;
    const Vec<D> nw = (1.0 / norm(to[j])) * to[j];
    bool seen = false;
    for (int q = 0; q < walls; ++q) seen = seen || dot(wn[q], nw) > 0.99;
    if (!seen) {
      wn[walls] = nw;
      wu[walls++] = P.vel[j];
    }
  }
}

template <int D>
void ProjectionISPH<D>::store_moments(std::size_t i, const projection_detail::MomentSums& sm, double lmin, double thr) {
  // ∇C, the Laplacian weights' moments, ∇·r = tr M, L = M⁻¹ (guarded), the corrected divergence of u* and the class
  double M[D * D];
  for (int a = 0; a < D; ++a) {
    gc_[i * D + a] = sm.g[a];
    lap_a_[i * D + a] = sm.a[a];
    for (int q = 0; q < D; ++q) M[a * D + q] = sm.M[a][q];
  }
  lap_m2_[i] = sm.m2;
  double tr = 0.0;
  for (int a = 0; a < D; ++a) tr += M[a * D + a];
  if (sm.dr > 0.0) tr = sm.dr;  // the free surface's ∇·r from the detection kernel (moments())
  divr_[i] = tr;
  const double* L = &L_[i * D * D];
  guarded_inverse<D>(M, lmin, &L_[i * D * D]);
  // the corrected divergence Σ_j V_j (u_j − u_i)·L_i ∇W_ij = Σ_ab L_ab Σ_j V_j F_ij du_a r_b
  double div = 0.0;
  for (int a = 0; a < D; ++a)
    for (int q = 0; q < D; ++q) div += L[a * D + q] * sm.G[a][q];
  div_[i] = div;
  // with P = 0 at the surface (Surface: a Robin row), a particle whose support is less than about half
  // full (∇·r < 1 in 2D, 1.5 in 3D: a splash, a jet's tip, a film) keeps P = 0 on its centre
  cls_[i] = tr >= thr ? Inner : o_.fs_at_surface && tr >= (D == 2 ? 1.0 : 1.5) ? Surface : Known;
}

template <int D>
template <class K>
void ProjectionISPH<D>::moments(System<D>& S, const K& ker) {
  // M_i = −Σ_j V_j F r_ij ⊗ r_ij over fluid and wet wall neighbours, L_i its guarded inverse, ∇·r_i = tr M_i;
  // the free surface where ∇·r < the threshold (Lee et al. 2008; Lind et al. 2012)
  auto& P = S.particles;
  const std::size_t n = P.n_owned();
  const double* phi = S.porous ? P.scalar(field::porosity).data() : nullptr;
  const double rho0 = S.eos.rho0;
  const double thr = o_.fs_threshold > 0.0 ? o_.fs_threshold : (D == 2 ? 1.5 : 2.4);
  const double lmin = o_.correction_min_eigenvalue;
  L_.assign(n * D * D, 0.0);
  divr_.assign(n, 0.0);
  gc_.assign(n * D, 0.0);
  conc_.assign(n, 0.0);
  lap_a_.assign(n * D, 0.0);
  lap_m2_.assign(n, 0.0);
  div_.assign(n, 0.0);
  // the neighbours kept for the rows and the correction, and the walls within dx kept for the wall checks
  // (correct(), step(): the positions and the walls' velocities do not change before them)
  const auto& to = P.vector(field::wall_to_surface);
  const double dx2 = S.dx * S.dx;
  wall_n_.assign(n * D, Vec<D>{});
  wall_u_.assign(n * D, Vec<D>{});
#ifdef _OPENMP
  near_buf_.resize(static_cast<std::size_t>(omp_get_max_threads()));
#else
  near_buf_.resize(1);
#endif
  for (auto& b : near_buf_) b.v.clear();
  near_thread_.assign(n, 0);
  near_first_.assign(n, 0);
  near_count_.assign(n, 0);
  // on the pair-pass skeleton (core/pair_pass.hpp): a cell's candidates copied once into columns, each particle's
  // sums in one vector loop, its neighbours (fluid and wet walls within the support) then kept in their stencil
  // order; the first-layer walls within dx, rare, walked only where the vector loop saw one
  const Vec<D>* pos = P.pos.data();
  const Kind* kind = P.kind.data();
  const double* mass = P.mass.data();
  const double* wet = wet_.data();
  const auto& cells = S.cells;
  const double* mob = S.porous ? P.scalar(field::mobility).data() : nullptr;
  const double eta2 = o_.eta2 * S.h * S.h;
  const Vec<D>* vel = P.vel.data();
  const Vec<D>* ub = ub_.data();
  // the free surface's ∇·r with the detection kernel (h_d = min(h, 1.5 × the particle's spacing), below) where h is larger
  const bool detect = detect_;
  enum { X0, X1, X2, VOL, WALL1, IDX, FL, PHI, KJ, U0, U1, U2, FK, IN, CIJ, NCOL };
  sweep_cells<double>(cells, NCOL, kIsphLanes, [&](std::size_t cell) { return owned_in(cells, cell, n, kind, true); },
                      [&](std::size_t cell, const CellStencil<D>& st, ScratchColumns<double>& B) {
#ifdef _OPENMP
    const int tid = omp_get_thread_num();
#else
    const int tid = 0;
#endif
    const K kl = ker;
    const std::uint32_t* sorted = cells.sorted().data();
    const std::uint32_t c0k = cells.cell_begin(cell), c1k = cells.cell_end(cell);
    const Vec<D> origin = pos[sorted[c0k]];
    // V_j for the fluid and the wet walls (0: out of the sums), the first-layer walls (closer than dx to their
    // surface), the fluid flag, φ_j and φ_j m_d,j (porous), the velocity in the divergence (u* of the fluid, a wet
    // wall's mirrored one)
    gather_columns(st, B, pos, origin,
                   column(VOL, 0.0, [=](std::size_t j) {
                     return kind[j] == Kind::Fluid ? mass[j] / (rho0 * (phi ? phi[j] : 1.0))
                            : kind[j] == Kind::Wall && wet[j] > 0.0 ? mass[j] / rho0 : 0.0;
                   }),
                   column(WALL1, 0.0, [&](std::size_t j) { return kind[j] == Kind::Wall && dot(to[j], to[j]) < dx2 ? 1.0 : 0.0; }),
                   column(IDX, -1.0, [](std::size_t j) { return static_cast<double>(j); }),
                   column(FL, 0.0, [=](std::size_t j) { return kind[j] == Kind::Fluid ? 1.0 : 0.0; }),
                   column(PHI, 1.0, [=](std::size_t j) { return phi ? phi[j] : 1.0; }),
                   column(KJ, 1.0, [=](std::size_t j) { return (phi ? phi[j] : 1.0) * (mob ? mob[j] : 1.0); }),
                   column(U0, 0.0, [=](std::size_t j) { return kind[j] == Kind::Fluid ? vel[j][0] : ub[j][0]; }),
                   column(U1, 0.0, [=](std::size_t j) { return kind[j] == Kind::Fluid ? vel[j][1] : ub[j][1]; }),
                   only_if<D == 3>(column(U2, 0.0, [=](std::size_t j) { return kind[j] == Kind::Fluid ? vel[j][D - 1] : ub[j][D - 1]; })));
    const MomentCols cols{B[X0], B[X1], B[X0 + D - 1], B[VOL], B[WALL1], B[FL], B[PHI], B[KJ], B[U0], B[U1],
                          B[D == 3 ? U2 : U0], B[FK], B[IN], B[CIJ]};
    const double* __restrict bw = B[WALL1];
    const double* __restrict bi = B[IDX];
    const std::size_t npad = st.padded;
    std::uint64_t pairs = 0;
    for (std::uint32_t k = c0k; k < c1k; ++k) {
      const std::uint32_t i = sorted[k];
      if (i >= n || kind[i] != Kind::Fluid) continue;
      double xa[3], ui[3] = {vel[i][0], vel[i][1], vel[i][D - 1]};
      relative<D>(pos[i], origin, xa[0], xa[1], xa[2]);
      const double phii = phi ? phi[i] : 1.0, ki = phii * (mob ? mob[i] : 1.0);
      // the detection kernel's h: 1.5 times the particle's own spacing (m/(φ ρ0))^(1/D), dx outside a porous medium;
      // inside one the spacing is dx/φ^(1/D) (1.43 dx at φ 0.49) and the case's h is kept
      const double hd = detect ? 1.5 * std::pow(mass[i] / (rho0 * phii), 1.0 / D) : ker.h;
      const MomentSums sm = moment_sums_for<D>(kl, hd, phi != nullptr, cols, npad, xa, ui, phii, ki, eta2, dx2);
      const std::size_t cnt = st.count;
      keep_neighbours(i, tid, cnt, cols, bi);
      if (sm.walls_near > 0.0) first_layer_walls(S, i, cnt, bw, bi);
      conc_[i] = sm.conc + mass[i] / (rho0 * phii) * kl.W(0.0);
      store_moments(i, sm, lmin, thr);
      pairs += st.count;
    }
    return pairs;
  });
}

template <int D>
template <class K>
double ProjectionISPH<D>::robin_entries(const System<D>& S, const K& ker, std::size_t i, int me, double weight,
                                        std::vector<std::pair<int, double>>& e) const {
  (void)ker;  // (the kernel's factors cached by the moments)
  const double ws = wall_scale_;
  // the surface's Robin row, P + (dx/2) n·∇P = 0 (P = 0 at the surface, dx/2 beyond the particle along its
  // outward normal n = −∇C/|∇C|, ∇P = L_i Σ_j V_j (P_j − P_i) ∇W_ij), as −weight ws (…) into e; returns its diagonal

    Vec<D> nrm{};
    double gn = 0.0;
    for (int a = 0; a < D; ++a) gn += gc_[i * D + a] * gc_[i * D + a];
    gn = std::sqrt(gn);
    if (gn > 0.0)
      for (int a = 0; a < D; ++a) nrm[a] = -gc_[i * D + a] / gn;
    const double* L = &L_[i * D * D];
    Vec<D> ln{};  // L_iᵀ n: n·L∇W = (Lᵀn)·∇W
    for (int a = 0; a < D; ++a)
      for (int b = 0; b < D; ++b) ln[a] += L[b * D + a] * nrm[b];
    const double delta = 0.5 * S.dx;
    double diag = 1.0;
    for_near(S, i, [&](const Near& q, const Vec<D>& r, double) {
      const std::uint32_t j = q.j;
      const double w = delta * q.V * q.F * dot(ln, r);
      diag -= w;
      if (col_[j] >= 0.0 && static_cast<int>(col_[j]) != me) e.emplace_back(static_cast<int>(col_[j]), -weight * ws * w);
    });
    return -weight * ws * diag;
}

template <int D>
template <class K>
double ProjectionISPH<D>::inner_row(const System<D>& S, const K& ker, std::size_t i, int me, double dt,
                                    std::vector<std::pair<int, double>>& e) const {
  const auto& P = S.particles;
  const double rho0 = S.eos.rho0;
  const double thr = o_.fs_threshold > 0.0 ? o_.fs_threshold : (D == 2 ? 1.5 : 2.4);
  const double blend = blend_;
  // a fluid unknown: Σ_j c_ij (P_j − P_i) = (ρ0/Δt) Σ_j V_j (u*_j − u*_i)·L_i ∇W_ij over fluid and wet walls
  const double* L = &L_[i * D * D];
  // Skillen et al. (2013)'s blend: over ∇·r ∈ [thr, thr + blend] the row's neighbours and source weighed by
  // α = (1 − cos(π (∇·r − thr)/blend))/2, so that the pressure rises smoothly from the surface's P = 0
  const double x = blend > 0.0 ? (divr_[i] - thr) / blend : 1.0;
  const double alpha = x >= 1.0 ? 1.0 : 0.5 * (1.0 - std::cos(std::numbers::pi * std::max(x, 0.0)));
  // the moments' pair sums (moment_sums): c_ij = −2 V_j F r²/(r² + η²) (porous: the conductivities' harmonic mean
  // over φ_i, the divergence of φ u*), a = Σ_j c_ij r_ji (the truncated support's first moment), m2 = ½ Σ_j c_ij r_ij²
  // (its second moment: D on a full support, up to η²), div = Σ_j V_j (u*_j − u*_i)·L_i ∇W_ij over fluid and wet walls
  Vec<D> a{};
  for (int q = 0; q < D; ++q) a[q] = lap_a_[i * D + q];
  const double m2 = lap_m2_[i];
  const double div = div_[i];
  // the Laplacian corrected to first order (Schwaiger 2008; Fatehi & Manzari 2011): the truncated support's
  // first moment removed with the corrected gradient, Σ_j c_ij (P_j − P_i − r_ji·∇P_i), and the result scaled
  // by D/m2, so that a linear pressure reads 0 and a quadratic one its Laplacian at the surface too;
  // ∇P_i = L_i Σ_j V_j F_ij (P_j − P_i) r_ij adds V_j |F_ij| (L_iᵀ a)·r_ij to c_ij
  Vec<D> la{};
  double scale = 1.0;
  if (o_.laplacian_corrected) {
    for (int p = 0; p < D; ++p)
      for (int q = 0; q < D; ++q) la[p] += L[q * D + p] * a[q];
    scale = m2 > 0.0 ? double(D) / m2 : 1.0;
  }
  // the correction kept as far as it leaves the row an M-matrix row (no negative weight): it is scaled by the
  // largest θ ≤ 1 that keeps every weight ≥ 0 (a disordered or sparse support, a jet or an impact, can turn a
  // weight negative, and such a row let a single particle's pressure run away: 10⁵ … 10⁷ Pa spikes in the dam
  // break's impact; θ rather than all or nothing, so that the row does not jump as a weight crosses 0,
  // docs/numerics.md §13b)
  if (o_.laplacian_corrected) {
    double theta = 1.0;
    for_near(S, i, [&](const Near& q, const Vec<D>& r, double) {
      const double ex = -q.V * q.F * dot(la, r);
      if (q.c + ex < 0.0) theta = std::min(theta, q.c / -ex);
    });
    la = theta * la;
    scale = 1.0 + theta * (scale - 1.0);
  }
  double diag = 0.0;
  // the blend: with P = 0 on the surface particles, the neighbours and the source weighed by α (Skillen et al.:
  // the pressure rises from 0 smoothly); with P = 0 at the surface, α of the Laplacian's row and 1 − α of the
  // Robin row (a particle moving between the two classes changes its equation smoothly)
  const double lap = o_.fs_at_surface ? alpha : 1.0;
  for_near(S, i, [&](const Near& q, const Vec<D>& r, double) {
    const double c = scale * (q.c - q.V * q.F * dot(la, r));
    diag -= lap * c;
    if (col_[q.j] >= 0.0 && static_cast<int>(col_[q.j]) != me) e.emplace_back(static_cast<int>(col_[q.j]), alpha * c);
  });
  const bool robin = o_.fs_at_surface && alpha < 1.0;
  if (robin) diag += robin_entries(S, ker, i, me, 1.0 - alpha, e);
  // (repeated columns: the Robin part's over the same neighbours, or a periodic image or halo copy)
  if (robin || P.size() > P.n_owned()) finish_row_unsorted(e, me, diag);
  else finish_row_distinct(e, me, diag);
  double rhs = alpha * rho0 / dt * div;
  // the weak volume correction (`volume_correction` ω): on a particle with a full support (∇·r ≥ 0.975 D), a
  // fraction ω per step of its number density's error against the lattice's, ρ0 ω (C_ref − C_i)/(C_ref Δt²); the
  // divergence-free source alone leaves a distortion of the particles' positions without a restoring force, and
  // in still water such a mode grew from round-off (e-folding 0.18 s at dx = 0.005, docs/numerics.md §13b)
  if (o_.volume_correction > 0.0 && divr_[i] >= 0.975 * D)
    rhs += o_.volume_correction * rho0 * (conc_ref_ - conc_[i]) / (conc_ref_ * dt * dt);
  return rhs;
}

template <int D>
template <class K>
void ProjectionISPH<D>::assemble(System<D>& S, const K& ker, double dt) {
  auto& P = S.particles;
  const std::size_t n = P.n_owned();
  const double rho0 = S.eos.rho0;
  const auto* aw = P.find(field::wall_acc);
  const std::size_t rows = static_cast<std::size_t>(std::count_if(unknown_.begin(), unknown_.end(), [](int k) { return k >= 0; }));
  rows_.resize(rows);
  std::vector<double> rhs(rows, 0.0);
  const double ws = wall_scale_;
#pragma omp parallel for schedule(dynamic, 64)
  for (std::size_t i = 0; i < n; ++i) {
    if (unknown_[i] < 0) continue;
    const std::size_t row = static_cast<std::size_t>(unknown_[i]);
    const int me = static_cast<int>(first_row_ + row);
    auto& e = rows_[row];
    e.clear();
    if (!unknown(cls_[i])) {  // a known P = 0: an identity row (stable numbering)
      e.emplace_back(me, -ws);
      rhs[row] = 0.0;
      continue;
    }
    if (cls_[i] == WallRow) {
      // a wet wall: −P_b + Σ_j w_j P_j = −ρ0 (g − a_w)·(r_b − r_m), w the linear MLS weights of the fluid at
      // r_m (Shepard's where the fluid there is too sparse for the linear fit), scaled by the lattice's diagonal
      for (const auto& [j, w] : mls_[i])
        if (col_[j] >= 0.0) e.emplace_back(static_cast<int>(col_[j]), ws * w);
      if (P.size() > P.n_owned()) finish_row_unsorted(e, me, -ws);
      else finish_row_distinct(e, me, -ws);
      const Vec<D> g = aw ? S.gravity - (*aw)[i] : S.gravity;
      rhs[row] = -ws * rho0 * dot(g, lever_[i]);
      continue;
    }
    if (cls_[i] == Surface) {
      const double d = robin_entries(S, ker, i, me, 1.0, e);
      if (P.size() > P.n_owned()) finish_row_unsorted(e, me, d);
      else finish_row_distinct(e, me, d);
      rhs[row] = 0.0;
      continue;
    }
    rhs[row] = inner_row(S, ker, i, me, dt, e);
  }
  sys_.first_row = first_row_;
  sys_.stable_rows = stable_rows_;
  sys_.set_rows(rows_);
  sys_.rhs.swap(rhs);
}

template <int D>
template <class K>
void ProjectionISPH<D>::correct(System<D>& S, const K& ker, double dt) {
  (void)ker;  // (the kernel's factors cached by the moments)
  // u_{n+1} = u* + Δt m_d (g − L_i Σ_j V_j (P_j − P_i) ∇W_ij / ρ0) for every fluid particle, over fluid and wet walls
  auto& P = S.particles;
  const std::size_t n = P.n_owned();
  const double rho0 = S.eos.rho0;
  const double* mob = S.porous ? P.scalar(field::mobility).data() : nullptr;
  std::vector<Vec<D>> dv(n);
#pragma omp parallel for schedule(dynamic, 64)
  for (std::size_t i = 0; i < n; ++i) {
    if (P.kind[i] != Kind::Fluid) continue;
    Vec<D> g{};
    const double pi = P.p[i];
    const Vec<D>* wn = &wall_n_[i * D];
    const Vec<D>* wu = &wall_u_[i * D];
    int walls = 0;  // the walls within dx the moments found (wall_n_ zero past them)
    while (walls < D && dot(wn[walls], wn[walls]) > 0.0) ++walls;
    for_near(S, i, [&](const Near& q, const Vec<D>& r, double) {
      g += (q.V * (P.p[q.j] - pi) * q.F) * r;
    });
    dv[i] = (dt * (mob ? mob[i] : 1.0)) * (S.gravity - (1.0 / rho0) * apply<D>(&L_[i * D * D], g));
    // no flow into a wall (Chow et al. 2018's velocity check): a particle nearer to a wall particle than the
    // spacing loses the part of its velocity, relative to the wall's, that points into the wall, for each wall
    // of a corner (and, in step(), of its displacement)
    for (int k = 0; k < walls; ++k) {
      const double un = dot(P.vel[i] + dv[i] - wu[k], wn[k]);
      if (un < 0.0) dv[i] -= un * wn[k];
    }
  }
  for (std::size_t i = 0; i < n; ++i)
    if (P.kind[i] == Kind::Fluid) P.vel[i] += dv[i];
}

#define SPH_PROJ_PASSES(D, K)                                                            \
  template void ProjectionISPH<D>::wall_rows<K<D>>(System<D>&, const K<D>&);             \
  template void ProjectionISPH<D>::adami_row<K<D>>(const System<D>&, const K<D>&, std::size_t, bool); \
  template void ProjectionISPH<D>::moments<K<D>>(System<D>&, const K<D>&);               \
  template void ProjectionISPH<D>::assemble<K<D>>(System<D>&, const K<D>&, double);      \
  template double ProjectionISPH<D>::robin_entries<K<D>>(const System<D>&, const K<D>&, std::size_t, int, double, \
                                                        std::vector<std::pair<int, double>>&) const; \
  template double ProjectionISPH<D>::inner_row<K<D>>(const System<D>&, const K<D>&, std::size_t, int, double,   \
                                                    std::vector<std::pair<int, double>>&) const;  \
  template void ProjectionISPH<D>::correct<K<D>>(System<D>&, const K<D>&, double);
SPH_PROJ_PASSES(2, WendlandC2)
SPH_PROJ_PASSES(2, CubicSpline)
SPH_PROJ_PASSES(2, QuinticSpline)
SPH_PROJ_PASSES(3, WendlandC2)
SPH_PROJ_PASSES(3, CubicSpline)
SPH_PROJ_PASSES(3, QuinticSpline)
#undef SPH_PROJ_PASSES

}  // namespace sph
