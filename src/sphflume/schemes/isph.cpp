#include "sphflume/schemes/isph.hpp"
#include "sphflume/schemes/isph_options.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include <fmt/format.h>

#include "sphflume/boundaries/motion.hpp"
#include "sphflume/boundaries/walls.hpp"
#include "sphflume/physics/porous.hpp"

namespace sph {
template <int D>
ISPH<D>::ISPH(const Case& c)
    : o_(c.isph), forces_(isph_force_config(c), c.turbulence), shift_(c.isph.shifting), solver_(c.isph) {
  check_isph_models(c);  // (the case reader checked it too; a case built in code is checked here)
}

template <int D>
void ISPH<D>::initialise(System<D>& S) {
  set_reference(S);
  S.particles.scalar(field::free_surface);  // the flag (set by each solve) exists from the first snapshot
  // the starting pressure (the hydrostatic state of the set-up) is the first solve's warm start
  auto& P = S.particles;
  for (std::size_t i = 0; i < P.n_owned(); ++i)
    P.p[i] = P.kind[i] == Kind::Fluid ? S.eos.pressure(P.rho[i]) - S.eos.background : 0.0;
  S.update_neighbours();
}

template <int D>
void ISPH<D>::set_reference(const System<D>& S) {
  // ρ_ref: the kernel summed over a full lattice of spacing dx (a particle inside the water)
  const double m = S.eos.rho0 * std::pow(S.dx, D);
  // κ: the gradient's moment on the same lattice, −(1/D) Σ V F(r) r² (1 for the exact integral)
  const auto sums = S.with_kernel([&](const auto& K) {
    const int n = static_cast<int>(std::ceil(K.support / S.dx)) + 1;
    double sum = 0.0, mom = 0.0;
    for (int a = -n; a <= n; ++a)
      for (int b = -n; b <= n; ++b)
        for (int e = (D == 3 ? -n : 0); e <= (D == 3 ? n : 0); ++e) {
          const double r = S.dx * std::sqrt(double(a * a + b * b + e * e));
          if (r < K.support) sum += K.W(r);
          if (r > 0.0 && r < K.support) mom -= K.F(r) * r * r;
        }
    return std::pair<double, double>(m * sum, mom * std::pow(S.dx, D) / D);
  });
  rho_ref_ = sums.first;
  kappa_ = sums.second;
  rho_ref_phi_.clear();
  if (S.porous) {
    // the same sum on the lattice the fluid takes inside a medium of porosity φ (same mass, same h)
    phi_lo_ = std::max(0.05, S.porous->min_porosity() - 0.05);
    const int n_tab = 96;
    rho_ref_phi_.resize(n_tab + 1);
    rho_ref_exact_.clear();
    for (std::size_t r = 0; r < S.porous->size(); ++r) rho_ref_exact_.emplace_back(S.porous->region(r).porosity, 0.0);
    S.with_kernel([&](const auto& K) {
      auto lattice_sum = [&](double phi) { return m * lattice_kernel_sum<D>(K, S.dx / std::pow(phi, 1.0 / D)); };
      for (int t = 0; t <= n_tab; ++t) rho_ref_phi_[static_cast<std::size_t>(t)] = lattice_sum(phi_lo_ + (1.0 - phi_lo_) * t / n_tab);
      for (auto& [phi, ref] : rho_ref_exact_) ref = lattice_sum(phi);  // a medium's own porosity: exact
    });
    rho_ref_phi_.back() = rho_ref_;  // φ = 1: the plain lattice, bit for bit
  }
}

template <int D>
double ISPH<D>::reference_at(double phi) const {
  if (rho_ref_phi_.empty() || !(phi < 1.0)) return rho_ref_;
  for (const auto& [p0, ref] : rho_ref_exact_)
    if (phi == p0) return ref;
  const double n_tab = double(rho_ref_phi_.size() - 1);
  const double u = std::clamp((phi - phi_lo_) / (1.0 - phi_lo_), 0.0, 1.0) * n_tab;
  const std::size_t k = std::min(static_cast<std::size_t>(u), rho_ref_phi_.size() - 2);
  const double f = u - double(k);
  return (1.0 - f) * rho_ref_phi_[k] + f * rho_ref_phi_[k + 1];
}

template <int D>
void ISPH<D>::step(System<D>& S, double dt_in) {
  auto& P = S.particles;
  if (!(rho_ref_ > 0.0)) set_reference(S);  // a run restarted from a snapshot (no initialise)
  // 1. prediction at r_t
  const auto t_pred = std::chrono::steady_clock::now();
  S.update_neighbours();
  forces_.rates(S);
  stats_.predict_s += seconds_since(t_pred);
  auto& x0 = P.vector(field::x0);
  auto& v0 = P.vector(field::v0);
  const double* kr = S.porous ? P.scalar(field::drag_rate).data() : nullptr;
  const double* im = S.porous ? P.scalar(field::inertia).data() : nullptr;
  const std::size_t n = P.n_owned();
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    x0[i] = P.pos[i];
    v0[i] = P.vel[i];
  }
  // the largest fluid speed now (over the ranks: every rank redoes the same steps), and the step
  // the Courant number allows for it
  auto courant_step = [&]() {
    double u2 = 0.0;
    const std::size_t m = P.n_owned();
#pragma omp parallel for schedule(static) reduction(max : u2)
    for (std::size_t i = 0; i < m; ++i)
      if (P.kind[i] == Kind::Fluid) u2 = std::max(u2, dot(P.vel[i], P.vel[i]));
    u2 = S.comm->max(u2);
    return u2 > 0.0 ? o_.cfl * S.dx / std::sqrt(u2) : std::numeric_limits<double>::infinity();
  };
  // Tsurudome §4.5: the Courant condition is checked after the prediction and after the correction;
  // where it fails, the step is redone from (r_t, u_t) with the Δt it allows (at most 4 times). A
  // Courant number up to 25 % above scheme.cfl is accepted: the thesis redoes on any excess, which
  // would solve the PPE twice in every step of a steadily accelerating flow
  const double slack = 1.25;
  double dt = dt_in;
  for (int attempt = 0;; ++attempt) {
    // (the owned particles: a redo comes after a re-sort, which in a distributed run migrates)
    const std::size_t m = P.n_owned();
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < m; ++i) {
      P.pos[i] = x0[i];
      P.vel[i] = v0[i];
      if (P.kind[i] != Kind::Fluid) continue;
      // porous drag point-implicit: u* = (u_t + Δt a/M) / (1 + Δt K/M)
      P.vel[i] = kr ? (1.0 / (1.0 + dt * kr[i])) * (P.vel[i] + (dt * im[i]) * P.acc[i]) : P.vel[i] + dt * P.acc[i];
      P.pos[i] += dt * P.vel[i];
    }
    move_walls(S, S.time + dt);  // the paddle at t + Δt with its velocity (Tsurudome §3.7: moved each prediction)
    if (const double allowed = courant_step(); slack * allowed < dt && attempt < 4) {  // the prediction's check
      dt = allowed;
      ++stats_.redone;
      continue;
    }
    // 2-4 at r*
    S.update_neighbours();
    if (S.porous) S.porous->update(S);
    solve_pressure(S, dt);
    const auto t_corr = std::chrono::steady_clock::now();
    S.with_kernel([&](const auto& K) { this->correct(S, K, dt); });
    stats_.correct_s += seconds_since(t_corr);
    if (const double allowed = courant_step(); slack * allowed < dt && attempt < 4) {  // the correction's check
      dt = allowed;
      ++stats_.redone;
      continue;
    }
    break;
  }
  const auto t_shift = std::chrono::steady_clock::now();
  if (shift_.on()) shift_.compute(S, dt);  // from r* and u_{t+1} (the lists of r*)
  stats_.correct_s += seconds_since(t_shift);
  double amax2 = 0.0;
  const auto& x0s = P.vector(field::x0);
  const auto& v0s = P.vector(field::v0);
  const auto* drs = o_.source == PpeSource::Split ? &P.vector(field::density_shift) : nullptr;
  const std::size_t m = P.n_owned();
#pragma omp parallel for schedule(static) reduction(max : amax2)
  for (std::size_t i = 0; i < m; ++i) {
    if (P.kind[i] != Kind::Fluid) continue;
    const Vec<D> dv = P.vel[i] - v0s[i];
    amax2 = std::max(amax2, dot(dv, dv));
    P.pos[i] = x0s[i] + (0.5 * dt) * (v0s[i] + P.vel[i]);  // trapezoidal (Tsurudome eq 3.2.6)
    if (drs) P.pos[i] += (*drs)[i];  // source.type split: the density error's displacement
  }
  amax_ = std::sqrt(amax2) / dt;
  if (shift_.on()) shift_.apply(S);
  S.periodic.wrap(P);
  S.time += dt;
  ++S.step;
}

template <int D>
void ISPH<D>::classify(System<D>& S) {
  auto& P = S.particles;
  const std::size_t n = P.n_owned();
  const double beta_rho = o_.fs_threshold * S.eos.rho0;  // densities normalised by ρ_ref/ρ0
  // a first-layer wall particle is dry (P = 0) by its density whatever the fluid's criterion
  const double beta_wall = (o_.fs_divergence ? 0.99 : o_.fs_threshold) * S.eos.rho0;
  const double beta_div = o_.fs_threshold > 0.0 ? o_.fs_threshold : (D == 2 ? 1.5 : 2.4);
  // at the free surface: the density (Tsurudome eq 4.2.3) or the position divergence (in drho)
  auto free = [&](std::size_t i) { return o_.fs_divergence ? P.drho[i] < beta_div : P.rho[i] < beta_rho; };
  const std::vector<Vec<D>>* to = P.has(field::wall_to_surface) ? &P.vector(field::wall_to_surface) : nullptr;
  if (!to) throw std::logic_error("isph: the geometry made no wall surface vectors (wall_to_surface)");
  cls_.assign(n, 1);
  unknown_.assign(n, -1);
  map_.assign(n, -1);
  std::size_t fs = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const Kind k = P.kind[i];
    if (k == Kind::Fluid) {
      cls_[i] = free(i) ? 1 : 0;
      fs += cls_[i];
    } else if (k == Kind::Wall) {
      const double depth = norm((*to)[i]);
      if (depth < S.dx) cls_[i] = P.rho[i] < beta_wall ? 1 : 0;  // first layer: wet, or dry (P = 0) by its density
      else cls_[i] = 2;
    }
  }
  stats_.free_surface = fs;
  // the flag in the snapshots (1: free surface, P = 0), for the user and the checks
  auto& flag = P.scalar(field::free_surface);
  for (std::size_t i = 0; i < n; ++i) flag[i] = P.kind[i] == Kind::Fluid && cls_[i] == 1 ? 1.0 : 0.0;
  // each dummy carries the pressure of the first-layer particle at the foot of its normal
  const double half = 0.5 * S.dx;
  const double reach = S.support;
#pragma omp parallel for schedule(dynamic, 64)
  for (std::size_t i = 0; i < n; ++i) {
    if (cls_[i] != 2) continue;
    const Vec<D> s = (*to)[i];
    const double len = norm(s);
    const Vec<D> target = P.pos[i] + ((len - half) / len) * s;
    double best = reach * reach;
    int pick = -1;
    // (j: the foot as this part of the domain sees it, owned, a periodic image or another
    // rank's copy: its pressure comes back through the halo)
    S.cells.for_neighbours(P.pos, target, reach, [&](std::uint32_t j, const Vec<D>&, double r2) {
      if (P.kind[j] != Kind::Wall || !(norm((*to)[j]) < S.dx)) return;
      if (r2 < best) { best = r2; pick = static_cast<int>(j); }
    });
    map_[i] = pick;
  }
  int k = 0;
  stable_rows_ = S.comm->size() == 1 && solver_.reuses_preconditioner();
  if (stable_rows_) {
    // one process with hypre: a row for every fluid and first-layer wall particle by particle id, P = 0 ones as
    // identity rows (rows_by_id)
    k = rows_by_id(P, [&](std::size_t i) { return cls_[i] != 2 && (P.kind[i] == Kind::Fluid || P.kind[i] == Kind::Wall); },
                   row_of_id_, unknown_);
  } else {
    for (std::size_t i = 0; i < n; ++i)
      if (cls_[i] == 0) unknown_[i] = k++;
  }
  // the unknowns' global numbers: this rank's after those of the ranks before it (one process: 0..)
  std::uint64_t total = 0;
  first_row_ = static_cast<std::size_t>(S.comm->exscan(static_cast<std::uint64_t>(k), total));
  dummy_off_.assign(n, 0.0);
  if (o_.dummy_body_force) {
    const auto* aw = P.find(field::wall_acc);
    for (std::size_t i = 0; i < n; ++i)
      if (cls_[i] == 2 && map_[i] >= 0) {
        const Vec<D> g = aw ? S.gravity - (*aw)[i] : S.gravity;
        dummy_off_[i] = S.eos.rho0 * dot(g, P.pos[i] - P.pos[static_cast<std::size_t>(map_[i])]);
      }
  }
  // per particle as the pair loops see them (owned and copies): the PPE column a neighbour's
  // pressure stands in (its own unknown; a dummy's: its foot's; -1: a known pressure) and a
  // dummy's known offset, filled for the owned particles and copied to the halo
  col_.assign(P.size(), -1.0);
  off_.assign(P.size(), 0.0);
  for (std::size_t i = 0; i < n; ++i)
    if (cls_[i] == 0) col_[i] = static_cast<double>(first_row_ + static_cast<std::size_t>(unknown_[i]));
  S.refresh_halos(col_.data());
  for (std::size_t i = 0; i < n; ++i)
    if (cls_[i] == 2) {
      off_[i] = dummy_off_[i];
      if (map_[i] >= 0) col_[i] = col_[static_cast<std::size_t>(map_[i])];  // (-1 where the foot is dry)
    }
  S.refresh_halos(col_.data());
  S.refresh_halos(off_.data());
}

template <int D>
void ISPH<D>::solve_pressure(System<D>& S, double dt) {
  auto& P = S.particles;
  const std::size_t n = P.n_owned();
  const auto t0 = std::chrono::steady_clock::now();
  const double* phi = S.porous ? P.scalar(field::porosity).data() : nullptr;
  if (phi) {
    // porous: the pressure acceleration meets the prediction's point-implicit drag and added mass,
    // u_{t+1} = u* − Δt m_d ∇P/ρ with the mobility m_d = (1/M)/(1 + Δt K/M) (1 where no drag was
    // computed), and the PPE carries m_d in its conductivity (a medium of fine grains conducts the
    // pressure's impulse as Darcy's law does)
    auto& mob = P.scalar(field::mobility);
    const auto* kr = P.find(field::drag_rate);
    const auto* im = P.find(field::inertia);
    for (std::size_t i = 0; i < n; ++i)
      mob[i] = kr && im && P.kind[i] == Kind::Fluid ? (*im)[i] / (1.0 + dt * (*kr)[i]) : 1.0;
  }
  // summation density of every owned particle (fluid and walls) at r*
  S.with_kernel([&](const auto& K) { this->kernel_density(S, K); });  // into drho (schemes/isph_passes.cpp)
  // normalised by the lattice's own sum: a full support reads ρ0 exactly (the particle's volume is
  // dx^D there), so the 1/ρ factors and volumes carry no lattice bias (+0.5 % at h/dx 1.5)
  // porous media: by the reference of the local porosity's lattice (Σ m W there, over φ), so that ρ
  // is the intrinsic density, ρ0 inside a saturated medium too (the free-surface test of Tsurudome
  // eq 4.2.5 with the reference from the local porosity)
  const double norm_rho = S.eos.rho0 / rho_ref_;
  for (std::size_t i = 0; i < n; ++i)
    if (P.kind[i] == Kind::Fluid || P.kind[i] == Kind::Wall)
      P.rho[i] = phi && P.kind[i] == Kind::Fluid ? P.drho[i] * (S.eos.rho0 * phi[i] / reference_at(phi[i])) : P.drho[i] * norm_rho;
  if (o_.fs_divergence) {  // ∇·r_i = −Σ V_j r_ij·∇_i W_ij, V_j = m_j/ρ_j (walls: m/ρ0), into drho
    S.refresh_halos();
    S.with_kernel([&](const auto& K) {
#pragma omp parallel for schedule(static)
      for (std::size_t i = 0; i < n; ++i) {
        if (P.kind[i] != Kind::Fluid && P.kind[i] != Kind::Wall) continue;
        double s = 0.0;
        S.cells.for_neighbours(P.pos, P.pos[i], K.support, [&](std::uint32_t j, const Vec<D>&, double r2) {
          if (!(r2 > 0.0)) return;
          const double rho_j = P.kind[j] == Kind::Wall ? S.eos.rho0 : P.rho[j];
          s -= P.mass[j] / rho_j * K.F(std::sqrt(r2)) * r2;
        });
        P.drho[i] = s;
      }
    });
  }
  solver_.prepare(S.comm->size() > 1);  // (auto: hypre whenever built; distributed: over every rank's rows)
  classify(S);
  // the walls' density in the pressure terms: the reference (a wall is no fluid to compress)
  for (std::size_t i = 0; i < n; ++i) {
    P.drho[i] = 0.0;
    if (P.kind[i] == Kind::Wall) P.rho[i] = S.eos.rho0;
  }
  S.refresh_halos();
  S.with_kernel([&](const auto& K) { this->assemble(S, K, dt); });
  stats_.assemble_s += seconds_since(t0);
  sys_.fresh = fresh_hierarchy_;  // (the first solve after a restart point builds its own)
  fresh_hierarchy_ = false;
  solve_into(S, P.p, true);
  sys_.fresh = false;
  if (o_.source == PpeSource::Split) {
    // source.type split: the density error's own solve, with the same matrix (and multigrid
    // hierarchy), A ψ = ω (ρ0 − ρ*)/(ρ0 Δt²); ψ moves the particles (correct(): δr = −Δt² ∇ψ/ρ) but is
    // neither a pressure nor a velocity (Bender & Koschier 2017 split the two solves the same way).
    // A relaxation needs no tight solve: 1e-3 of its own right-hand side; a solver.tolerance tighter
    // than the default 1e-6 (runs that must agree across partitions, tests/mpi/check_ranks.py) applies too
    sys_.rhs.swap(rhs_density_);
    sys_.tolerance = o_.tolerance < 1e-6 ? o_.tolerance : kDensityTolerance;
    solve_into(S, P.scalar(field::psi), false);
    sys_.tolerance = 0.0;
    sys_.rhs.swap(rhs_density_);
  }
}

template <int D>
void ISPH<D>::solve_into(System<D>& S, std::vector<double>& field, bool pressure) {
  // warm start from the field's last values, the solve, and the solution back into the field: P = 0
  // particles 0, each dummy its foot's value (the pressure plus its known offset)
  auto& P = S.particles;
  const std::size_t n = P.n_owned();
  x_.assign(sys_.rows(), 0.0);
  for (std::size_t i = 0; i < n; ++i)
    if (unknown_[i] >= 0 && cls_[i] == 0) x_[static_cast<std::size_t>(unknown_[i])] = field[i];
  solver_.solve(sys_, x_, stats_, S.step, S.time,
                pressure ? "pressure Poisson equation" : "density-error equation (scheme.source.type: split)",
                std::max(o_.tolerance, sys_.tolerance));
  for (std::size_t i = 0; i < n; ++i) {
    if (P.kind[i] != Kind::Fluid && P.kind[i] != Kind::Wall) continue;
    field[i] = unknown_[i] >= 0 && cls_[i] == 0 ? x_[static_cast<std::size_t>(unknown_[i])] : 0.0;
  }
  S.refresh_halos(field.data());  // (the feet's values, also where a foot is another part's)
  for (std::size_t i = 0; i < n; ++i)
    if (cls_[i] == 2) field[i] = map_[i] >= 0 ? field[static_cast<std::size_t>(map_[i])] + (pressure ? dummy_off_[i] : 0.0) : 0.0;
  S.refresh_halos(field.data());
}

template <int D>
std::size_t ISPH<D>::bytes() const {
  const std::size_t own = cls_.capacity() + (unknown_.capacity() + map_.capacity()) * sizeof(int) +
                          sys_.col.capacity() * sizeof(int) + sys_.val.capacity() * sizeof(double) +
                          (sys_.start.capacity() + 0) * sizeof(std::size_t) + (sys_.rhs.capacity() + x_.capacity()) * sizeof(double);
  return own + solver_.get().bytes();  // (per particle before 2026-11-29: the summary took it for a total)
}

template <int D>
std::map<std::string, double> ISPH<D>::state() const {
  fresh_hierarchy_ = true;  // a restart point: a run restarted here starts without the solver's hierarchy
  return stats_.save(amax_);
}

template <int D>
void ISPH<D>::restore(const std::map<std::string, double>& s) {
  amax_ = stats_.load(s);
}

template <int D>
void ISPH<D>::summary(nlohmann::ordered_json& j) const {
  const char* source = o_.source == PpeSource::Split      ? "split"
                       : o_.source == PpeSource::Hybrid   ? "hybrid"
                       : o_.source == PpeSource::Standard ? "standard"
                                                          : "divergence_free";
  auto js = stats_.json(solver_.get().name(), o_.tolerance);
  js["reference_density"] = rho_ref_;
  js["gradient_moment"] = kappa_;
  js["source"] = source;
  js["formulation"] = "tsurudome";
  j["pressure_solver"] = js;
}

template class ISPH<2>;
template class ISPH<3>;

}  // namespace sph
