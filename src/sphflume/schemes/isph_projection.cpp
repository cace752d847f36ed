#include "sphflume/schemes/isph_projection.hpp"
#include "sphflume/schemes/isph_options.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <type_traits>

#include "sphflume/boundaries/motion.hpp"
#include "sphflume/boundaries/walls.hpp"
#include "sphflume/physics/porous.hpp"

namespace sph {
template <int D>
ProjectionISPH<D>::ProjectionISPH(const Case& c)
    : o_(c.isph), forces_(isph_force_config(c), c.turbulence), shift_(c.isph.shifting), solver_(c.isph) {
  check_isph_models(c);
}

template <int D>
void ProjectionISPH<D>::initialise(System<D>& S) {
  auto& P = S.particles;
  S.particles.scalar(field::free_surface);
  // the density is ρ0 throughout (the intrinsic density in a porous medium); the set-up's
  // hydrostatic pressure is the first solve's warm start
  for (std::size_t i = 0; i < P.n_owned(); ++i) {
    if (P.kind[i] == Kind::Fluid) P.p[i] = S.eos.pressure(P.rho[i]) - S.eos.background;
    else if (P.kind[i] == Kind::Wall) P.p[i] = 0.0;
    if (P.kind[i] == Kind::Fluid || P.kind[i] == Kind::Wall) P.rho[i] = S.eos.rho0;
  }
  constants(S);
  S.update_neighbours();
}

template <int D>
void ProjectionISPH<D>::constants(const System<D>& S) {
  // a wall row's weight: the Laplacian's diagonal on a full lattice, Σ 2 V |F| r²/(r² + η²)
  const double eta2 = o_.eta2 * S.h * S.h;
  wall_scale_ = S.with_kernel([&](const auto& K) {
    const int m = static_cast<int>(std::ceil(K.support / S.dx)) + 1;
    double s = 0.0;
    for (int a = -m; a <= m; ++a)
      for (int b = -m; b <= m; ++b)
        for (int e = (D == 3 ? -m : 0); e <= (D == 3 ? m : 0); ++e) {
          const double r2 = S.dx * S.dx * double(a * a + b * b + e * e);
          if (r2 > 0.0 && r2 < K.support2) s -= 2.0 * std::pow(S.dx, D) * K.F(std::sqrt(r2)) * r2 / (r2 + eta2);
        }
    return s;
  });
  conc_ref_ = S.with_kernel([&](const auto& K) { return lattice_kernel_sum<D>(K, S.dx) * std::pow(S.dx, D); });
  // the blend band [thr, thr + blend] ends below the second row's ∇·r on a lattice under a flat surface (1.82 at
  // h/dx 1.5, 1.63 at 2.0), so that a flat surface's second row keeps the interior's row (at 2.0 the band
  // [1.5, 1.7] took it, and its Robin part at dx/2 put the bed 1.1 % low; the Robin distance read from ∇·r
  // instead made the rows unstable, docs/numerics.md §13b); the rows' values are the detection kernel's (h_d =
  // min(h, 1.5 dx) in water, isph_projection.hpp)
  detect_ = S.h > 1.5 * S.dx * (1.0 + 1e-12);
  detect_h_ = detect_ ? 1.5 * S.dx : S.h;
  const auto depth = S.with_kernel([&](const auto& K) {
    return lattice_divr_by_depth<D>(std::decay_t<decltype(K)>(detect_h_), S.dx);
  });
  const double thr = o_.fs_threshold > 0.0 ? o_.fs_threshold : (D == 2 ? 1.5 : 2.4);
  blend_ = o_.fs_blend;
  if (depth.size() > 1 && depth[1] > thr) blend_ = std::min(blend_, 0.8 * (depth[1] - thr));
}

template <int D>
void ProjectionISPH<D>::step(System<D>& S, double dt) {
  auto& P = S.particles;
  // a run restarted from a snapshot: the lattice's constants only (its pressures are the next solve's warm
  // start, as in the run it continues)
  if (!(wall_scale_ > 1.0)) constants(S);
  // 1. prediction at r_n, gravity left to the correction (its hydrostatic part is carried by the walls'
  // offsets, Chow et al. 2018): u* = u_n + Δt (a − g), r* = r_n + Δt u_n
  const auto t_pred = std::chrono::steady_clock::now();
  S.update_neighbours();
  forces_.rates(S);
  auto& x0 = P.vector(field::x0);
  auto& v0 = P.vector(field::v0);
  const double* kr = S.porous ? P.scalar(field::drag_rate).data() : nullptr;
  const double* im = S.porous ? P.scalar(field::inertia).data() : nullptr;
  const std::size_t n = P.n_owned();
  const Vec<D> g = S.gravity;
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    x0[i] = P.pos[i];
    v0[i] = P.vel[i];
    if (P.kind[i] != Kind::Fluid) continue;
    P.pos[i] += dt * P.vel[i];
    // porous drag point-implicit: u* = (u_n + Δt (a − g)/M) / (1 + Δt K/M)
    const Vec<D> a = P.acc[i] - g;
    P.vel[i] = kr ? (1.0 / (1.0 + dt * kr[i])) * (P.vel[i] + (dt * im[i]) * a) : P.vel[i] + dt * a;
  }
  move_walls(S, S.time + dt);
  stats_.predict_s += seconds_since(t_pred);
  // 2-4 at r*
  S.update_neighbours();
  if (S.porous) S.porous->update(S);
  solve_pressure(S, dt);
  // 5. correction, position, shifting
  const auto t_corr = std::chrono::steady_clock::now();
  S.with_kernel([&](const auto& K) { this->correct(S, K, dt); });
  // at r*, with u_{n+1} (the lists of r*); the velocity-scaled form from the moments' ∇C and ∇·r (the same
  // positions; over the fluid and wet walls)
  if (shift_.on()) shift_.compute(S, dt, gc_.data(), divr_.data());
  const auto& x0s = P.vector(field::x0);
  const auto& v0s = P.vector(field::v0);
  double amax2 = 0.0;
  const std::size_t m = P.n_owned();
  const std::vector<Vec<D>>* shift = shift_.on() ? &P.vector(field::shift) : nullptr;
#pragma omp parallel for schedule(static) reduction(max : amax2)
  for (std::size_t i = 0; i < m; ++i) {
    if (P.kind[i] != Kind::Fluid) continue;
    const Vec<D> dv = P.vel[i] - v0s[i];
    amax2 = std::max(amax2, dot(dv, dv));
    Vec<D> d = (0.5 * dt) * (v0s[i] + P.vel[i]);
    if (shift) d += (*shift)[i];
    // next to a wall, no displacement into it relative to the wall's (correct(): the velocity's)
    for (int k = 0; k < D; ++k) {
      const Vec<D>& nw = wall_n_[i * D + k];
      if (const double dn = dot(d - dt * wall_u_[i * D + k], nw); dn < 0.0) d -= dn * nw;
    }
    P.pos[i] = x0s[i] + d;
  }
  amax_ = std::sqrt(S.comm->max(amax2)) / dt;
  S.periodic.wrap(P);
  stats_.correct_s += seconds_since(t_corr);
  S.time += dt;
  ++S.step;
}

template <int D>
void ProjectionISPH<D>::solve_pressure(System<D>& S, double dt) {
  auto& P = S.particles;
  const auto t0 = std::chrono::steady_clock::now();
  const std::size_t n = P.n_owned();
  if (S.porous) {
    // the pressure acceleration meets the prediction's point-implicit drag and added mass:
    // u_{n+1} = u* − Δt m_d ∇P/ρ0, m_d = (1/M)/(1 + Δt K/M) (docs/numerics.md §13, porous media)
    auto& mob = P.scalar(field::mobility);
    const auto* kr = P.find(field::drag_rate);
    const auto* im = P.find(field::inertia);
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < n; ++i)
      mob[i] = kr && im && P.kind[i] == Kind::Fluid ? (*im)[i] / (1.0 + dt * (*kr)[i]) : 1.0;
    S.refresh_halos(mob.data());
  }
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i)
    if (P.kind[i] == Kind::Fluid || P.kind[i] == Kind::Wall) P.rho[i] = S.eos.rho0;
  solver_.prepare(S.comm->size() > 1);
  // walls first (which are wet: the mirror sees fluid), then the fluid's moments over fluid and wet walls
  dt_ = dt;
  S.with_kernel([&](const auto& K) { this->wall_rows(S, K); });
  S.with_kernel([&](const auto& K) { this->moments(S, K); });
  number_unknowns(S);
  S.with_kernel([&](const auto& K) { this->assemble(S, K, dt); });
  stats_.assemble_s += seconds_since(t0);
  // warm start from the last pressures, the solve, the solution back into the particles
  x_.assign(sys_.rows(), 0.0);
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i)
    if (unknown_[i] >= 0 && unknown(cls_[i])) x_[static_cast<std::size_t>(unknown_[i])] = P.p[i];
  sys_.fresh = fresh_hierarchy_;  // (the first solve after a restart point builds its own hierarchy)
  fresh_hierarchy_ = false;
  solver_.solve(sys_, x_, stats_, S.step, S.time, "pressure Poisson equation", o_.tolerance);
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    if (P.kind[i] != Kind::Fluid && P.kind[i] != Kind::Wall) continue;
    P.p[i] = unknown_[i] >= 0 && unknown(cls_[i]) ? x_[static_cast<std::size_t>(unknown_[i])] : 0.0;
    // `negative_pressure: clamp`: no tension (the correction then leaves such a particle's divergence)
    if (o_.clamp_negative && P.kind[i] == Kind::Fluid && P.p[i] < 0.0) P.p[i] = 0.0;
  }
  S.refresh_halos(P.p.data());
}

template <int D>
void ProjectionISPH<D>::number_unknowns(System<D>& S) {
  // cls_ set by wall_rows and moments (Cls)
  auto& P = S.particles;
  const std::size_t n = P.n_owned();
  unknown_.assign(n, -1);
  int k = 0;
  stable_rows_ = S.comm->size() == 1 && solver_.reuses_preconditioner();
  if (stable_rows_) {
    // one process with hypre: a row for every fluid and wall particle by particle id, the known ones as identity rows
    k = rows_by_id(P, [&](std::size_t i) { return P.kind[i] == Kind::Fluid || P.kind[i] == Kind::Wall; }, row_of_id_, unknown_);
  } else {
    for (std::size_t i = 0; i < n; ++i)
      if (unknown(cls_[i])) unknown_[i] = k++;
  }
  std::uint64_t total = 0;
  first_row_ = static_cast<std::size_t>(S.comm->exscan(static_cast<std::uint64_t>(k), total));
  // the column each particle's pressure stands in, as the pair loops see them (owned and copies)
  col_.assign(P.size(), -1.0);
  for (std::size_t i = 0; i < n; ++i)
    if (unknown(cls_[i])) col_[i] = static_cast<double>(first_row_ + static_cast<std::size_t>(unknown_[i]));
  S.refresh_halos(col_.data());
  std::size_t fs = 0;
  auto& flag = P.scalar(field::free_surface);
  for (std::size_t i = 0; i < n; ++i) {
    const bool f = P.kind[i] == Kind::Fluid && (cls_[i] == Known || cls_[i] == Surface);
    flag[i] = f ? 1.0 : 0.0;
    fs += f;
  }
  stats_.free_surface = fs;
}

template <int D>
std::size_t ProjectionISPH<D>::bytes() const {
  const std::size_t own = cls_.capacity() + unknown_.capacity() * sizeof(int) +
                          (L_.capacity() + divr_.capacity() + col_.capacity() + wet_.capacity() + offset_.capacity()) * sizeof(double) +
                          sys_.col.capacity() * sizeof(int) + sys_.val.capacity() * sizeof(double) +
                          sys_.start.capacity() * sizeof(std::size_t) + (sys_.rhs.capacity() + x_.capacity()) * sizeof(double) +
                          (near_thread_.capacity() + near_first_.capacity() + near_count_.capacity()) * sizeof(std::uint32_t);
  std::size_t lists = 0;  // the neighbour cache, the rows as built, the wall rows' weights, per-particle vectors
  for (const auto& b : near_buf_) lists += b.v.capacity() * sizeof(Near);
  for (const auto& r : rows_) lists += r.capacity() * sizeof(std::pair<int, double>) + sizeof(r);
  for (const auto& w : mls_) lists += w.capacity() * sizeof(std::pair<std::uint32_t, double>) + sizeof(w);
  lists += (gc_.capacity() + conc_.capacity() + lap_a_.capacity() + lap_m2_.capacity() + div_.capacity()) * sizeof(double) +
           (lever_.capacity() + ub_.capacity() + wall_n_.capacity() + wall_u_.capacity()) * sizeof(Vec<D>);
  return own + lists + solver_.get().bytes();
}

template <int D>
std::map<std::string, double> ProjectionISPH<D>::state() const {
  fresh_hierarchy_ = true;
  return stats_.save(amax_);
}

template <int D>
void ProjectionISPH<D>::restore(const std::map<std::string, double>& s) {
  amax_ = stats_.load(s);
}

template <int D>
void ProjectionISPH<D>::summary(nlohmann::ordered_json& j) const {
  auto js = stats_.json(solver_.get().name(), o_.tolerance);
  js["formulation"] = "lind";
  js["source"] = "divergence_free";
  j["pressure_solver"] = js;
}

template class ProjectionISPH<2>;
template class ProjectionISPH<3>;

}  // namespace sph
