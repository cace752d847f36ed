#include "sphflume/boundaries/open_boundary.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <utility>

namespace sph {

double profile_velocity(const ProfileConfig& p, double z, double depth) {
  if (p.type == "uniform") return p.u;
  if (p.type == "parabolic") {
    const double s = std::clamp(z / depth, 0.0, 1.0);
    return p.u_surface * (2.0 * s - s * s);
  }
  if (p.type == "log") {
    if (z <= 0.0) return 0.0;
    return std::max(0.0, p.u_star * (std::log(z / p.ks) / 0.41 + 8.5));
  }
  // table
  if (z <= p.z.front()) return p.values.front();
  if (z >= p.z.back()) return p.values.back();
  const auto it = std::upper_bound(p.z.begin(), p.z.end(), z);
  const std::size_t j = static_cast<std::size_t>(it - p.z.begin());
  const double t = (z - p.z[j - 1]) / (p.z[j] - p.z[j - 1]);
  return p.values[j - 1] + t * (p.values[j] - p.values[j - 1]);
}

template <int D>
OpenBoundaries<D>::OpenBoundaries(const Case& c) {
  for (const auto& b : c.open_boundaries) (b.type == "inflow" ? in_ : out_) = &b;
  gz_ = c.gravity.empty() ? 9.81 : std::abs(c.gravity[D - 1]);
  rho0_ = c.fluid.density;
  background_ = c.fluid.background_pressure;
  dx_ = c.dx;
}

template <int D>
bool OpenBoundaries<D>::needs_prepare() const {
  return (in_ && in_->velocity == "averaged") || (out_ && (out_->velocity == "extrapolated" || out_->pressure != "frozen"));
}

template <int D>
double OpenBoundaries<D>::outflow_level(const System<D>& S) const {
  const auto& P = S.particles;
  const std::size_t n = P.n_owned();
  const double xn = out_->x0 - 0.5 * dx_;
  double level = out_->bed + out_->depth;
  double top = -1e300;
  for (std::size_t i = 0; i < n; ++i)
    if (P.kind[i] == Kind::Fluid && std::abs(P.pos[i][0] - xn) < dx_) top = std::max(top, P.pos[i][D - 1]);
  top = S.comm->max(top);
  if (top > -1e300) level = top + 0.5 * dx_;
  return level;
}

template <int D>
std::vector<double> OpenBoundaries<D>::node_averages(const System<D>& S, const std::vector<double>& nodes) const {
  const auto& P = S.particles;
  constexpr int kW = D + 2;
  const std::size_t nn = nodes.size() / D;
  std::vector<double> avg(nn * kW, 0.0);
  S.with_kernel([&](const auto& K) {
#pragma omp parallel for schedule(dynamic, 64)
    for (std::size_t q = 0; q < nn; ++q) {
      Vec<D> x;
      for (int d = 0; d < D; ++d) x[d] = nodes[q * D + static_cast<std::size_t>(d)];
      if (!std::isfinite(x[0]) || !S.owns(x)) continue;  // (no such node, or another part's)
      // Shepard average over fluid particles (not the imposed ones)
      double sw = 0.0, sr = 0.0;
      Vec<D> su{};
      S.cells.for_neighbours(P.pos, x, K.support, [&](std::uint32_t b, const Vec<D>&, double r2) {
        if (P.kind[b] != Kind::Fluid) return;
        const double w = P.mass[b] / P.rho[b] * K.W(std::sqrt(r2));
        sw += w;
        sr += w * P.rho[b];
        su += w * P.vel[b];
      });
      if (sw <= 0.0) continue;
      double* a = &avg[q * kW];
      a[0] = 1.0;
      a[1] = sr / sw;
      const Vec<D> u = (1.0 / sw) * su;
      for (int d = 0; d < D; ++d) a[2 + d] = u[d];
    }
  });
  return avg;
}

template <int D>
void OpenBoundaries<D>::prepare(System<D>& S) const {
  if (!needs_prepare()) return;
  auto& P = S.particles;
  const std::size_t n = P.n_owned();
  const bool avg_in = in_ && in_->velocity == "averaged";
  const bool ext_u = out_ && out_->velocity == "extrapolated";
  const bool ext_p = out_ && out_->pressure == "extrapolated";
  const bool hyd_p = out_ && out_->pressure == "hydrostatic";
  const bool inlet_p = out_ && in_ && out_->pressure == "inlet";
  const double level = hyd_p ? outflow_level(S) : 0.0;
  // The averaging nodes this part of the domain asks for (two per particle: the near node, and
  // the far node of a recycling inflow or the inlet node of an "inlet" outflow pressure; NaN
  // where the particle needs no second node).
  // A node may lie in another rank's part: every rank's nodes are gathered, each is averaged
  // by the rank that holds it (its neighbours, owned or halo, are there), and one sum over the
  // ranks brings the averages back (in one process: the same averages, in the same order).
  std::vector<std::size_t> who;
  std::vector<double> nodes;  // 2 x D coordinates per particle of `who`
  auto push = [&](const Vec<D>& a, const Vec<D>& b) {
    for (int d = 0; d < D; ++d) nodes.push_back(a[d]);
    for (int d = 0; d < D; ++d) nodes.push_back(b[d]);
  };
  for (std::size_t i = 0; i < n; ++i) {
    const Kind k = P.kind[i];
    if (k == Kind::Inflow && avg_in) {
      Vec<D> node = P.pos[i], far = P.pos[i];
      node[0] = in_->x1 + 0.5 * dx_;
      far[0] = in_->average_at > 0.0 ? in_->x1 + in_->average_at : std::numeric_limits<double>::quiet_NaN();
      who.push_back(i);
      push(node, far);
    } else if (k == Kind::Outflow && (ext_u || ext_p || inlet_p)) {
      Vec<D> node = P.pos[i], nin = P.pos[i];
      node[0] = out_->x0 - 0.5 * dx_;
      nin[0] = inlet_p ? in_->x1 + 0.5 * dx_ : std::numeric_limits<double>::quiet_NaN();
      who.push_back(i);
      push(node, nin);
    }
  }
  const std::vector<double> all = S.comm->allgather(nodes);
  std::uint64_t asked = 0;
  const std::size_t before = static_cast<std::size_t>(S.comm->exscan(who.size(), asked));
  // per node: found (0/1), rho, u (D); summed over the ranks (only the holder adds)
  constexpr int kW = D + 2;
  std::vector<double> avg = node_averages(S, all);
  S.comm->sum(avg.data(), avg.size());
  auto result = [&](std::size_t q, Vec<D>& u, double& rho) {
    const double* a = &avg[q * kW];
    if (!(a[0] > 0.5)) return false;
    rho = a[1];
    for (int d = 0; d < D; ++d) u[d] = a[2 + d];
    return true;
  };
#pragma omp parallel for schedule(static)
  for (std::size_t j = 0; j < who.size(); ++j) {
    const std::size_t i = who[j], q = 2 * (before + j);  // this particle's two nodes in the gathered list
    Vec<D> u;
    double rho;
    if (P.kind[i] == Kind::Inflow) {
      if (!result(q, u, rho)) continue;
      Vec<D> uf;
      double rf;
      if (in_->average_at > 0.0 && result(q + 1, uf, rf)) u = uf;  // the velocity from a node further downstream (recycling)
      // Kazemi's inflow particles keep the elevation of their fluid layer: they take the
      // averaged streamwise velocity only (a vertical part would carry the bottom row through
      // the bed), and never upstream (the algorithm has no backflow at the inlet)
      P.vel[i] = Vec<D>{};
      P.vel[i][0] = std::max(u[0], 0.0);
      P.rho[i] = rho;
      P.p[i] = S.eos.pressure(rho);
      continue;
    }
    const bool found = (ext_u || ext_p) && result(q, u, rho);
    if (found && ext_u) P.vel[i] = u;
    if (found && ext_p) {
      P.rho[i] = rho;
      P.p[i] = S.eos.pressure(rho);
    }
    if (inlet_p && result(q + 1, u, rho)) {  // the pressure of the fluid at the same height just inside the inlet
      P.rho[i] = rho;
      P.p[i] = S.eos.pressure(rho);
    }
  }
  if (hyd_p)
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < n; ++i)
      if (P.kind[i] == Kind::Outflow) {
        P.p[i] = background_ + rho0_ * gz_ * std::max(0.0, level - P.pos[i][D - 1]);
        P.rho[i] = S.eos.density(P.p[i]);
      }
  S.refresh_halos();
}

template <int D>
void OpenBoundaries<D>::impose(System<D>& S, std::size_t i, const OpenBoundaryConfig& b, bool density) const {
  auto& P = S.particles;
  const double z = P.pos[i][D - 1] - b.bed;
  P.vel[i] = Vec<D>{};
  P.vel[i][0] = profile_velocity(b.profile, z, b.depth);
  if (density) {  // hydrostatic pressure of the imposed depth
    P.p[i] = background_ + rho0_ * gz_ * std::max(0.0, b.depth - z);
    P.rho[i] = S.eos.density(P.p[i]);
  }
}

template <int D>
void OpenBoundaries<D>::impose_outflow(System<D>& S, std::size_t i) const {
  auto& P = S.particles;
  const Vec<D> v = P.vel[i];
  const double p = P.p[i], rho = P.rho[i];
  impose(S, i, *out_, out_->pressure == "imposed");  // profile velocity; hydrostatic pressure of `depth`
  if (out_->velocity != "imposed") P.vel[i] = v;
  if (out_->pressure != "imposed") { P.p[i] = p; P.rho[i] = rho; }
}

template <int D>
void OpenBoundaries<D>::setup(System<D>& S, OpenFlowCounters& k) const {
  auto& P = S.particles;
  std::uint32_t maxid = 0;
  for (std::size_t i = 0; i < P.n_owned(); ++i) {
    maxid = std::max(maxid, P.id[i]);
    if (P.kind[i] != Kind::Fluid) continue;
    const double x = P.pos[i][0];
    if (in_ && x >= in_->x0 && x < in_->x1) {
      P.kind[i] = Kind::Inflow;
      impose(S, i, *in_, true);
    } else if (out_ && x >= out_->x0) {
      P.kind[i] = Kind::Outflow;
      impose_outflow(S, i);
    } else if (in_ && in_->initial_profile && x >= in_->x1) {
      impose(S, i, *in_, false);  // the fluid starts with the inflow's profile (its density stays)
    }
  }
  k.next_id = maxid + 1;
  if (in_ && in_->velocity == "averaged") {
    // The lattice places every row dx apart while a particle of the hydrostatically compressed
    // column fills m/(rho dx) < dx of height: the fluid settles by the mean compression (0.7 mm
    // for a 6 cm column at c0 = 4.8 m/s), the fixed inflow rows do not, and the inflow column
    // would stand that much above the fluid: a head difference that, in a short uniform-flow
    // channel, is as large as the whole bed-slope drop S0 L and sets the discharge. So the
    // inflow rows are stacked at the heights of the settled column, from the bottom row up.
    // columns: one per lattice cell of the inlet plane (x in 2D; x and y in 3D)
    std::map<std::pair<long, long>, std::vector<std::size_t>> cols;
    for (std::size_t i = 0; i < P.n_owned(); ++i)
      if (P.kind[i] == Kind::Inflow)
        cols[{std::lround(std::floor(P.pos[i][0] / dx_)), D == 3 ? std::lround(std::floor(P.pos[i][1] / dx_)) : 0L}].push_back(i);
    const double base = D == 3 ? dx_ * dx_ : dx_;  // a particle's height is its volume m/rho over dx^(D-1)
    for (auto& [c, v] : cols) {
      std::sort(v.begin(), v.end(), [&](std::size_t a, std::size_t b) { return P.pos[a][D - 1] < P.pos[b][D - 1]; });
      for (std::size_t r = 1; r < v.size(); ++r) {
        const double h0 = P.mass[v[r - 1]] / (P.rho[v[r - 1]] * base), h1 = P.mass[v[r]] / (P.rho[v[r]] * base);
        P.pos[v[r]][D - 1] = P.pos[v[r - 1]][D - 1] + 0.5 * (h0 + h1);
      }
    }
  }
}

template <int D>
bool OpenBoundaries<D>::update(System<D>& S, OpenFlowCounters& k) const {
  auto& P = S.particles;
  const std::size_t n = P.n_owned();
  std::vector<std::size_t> born;  // inflow particles that became fluid
  std::vector<char> gone;
  for (std::size_t i = 0; i < n; ++i) {
    const double x = P.pos[i][0];
    switch (P.kind[i]) {
      case Kind::Inflow:
        if (in_ && x >= in_->x1) {
          P.kind[i] = Kind::Fluid;
          k.inflow_mass += P.mass[i];
          born.push_back(i);
        }
        break;
      case Kind::Fluid:
        if (out_ && x >= out_->x0) {
          P.kind[i] = Kind::Outflow;
          k.outflow_mass += P.mass[i];
          impose_outflow(S, i);
        } else if (in_ && x < in_->x1 - 0.5 * dx_ && x >= in_->x0) {
          // back into the inflow zone, half a spacing past its boundary line (among the inflow
          // lattice, not just touching it, as a slow particle at a no-slip bed may): removed, counted
          if (gone.empty()) gone.assign(n, 0);
          gone[i] = 1;
          ++k.backflow;
          k.backflow_mass += P.mass[i];
        }
        break;
      case Kind::Outflow:
        if (out_ && x >= out_->x1) {
          if (gone.empty()) gone.assign(n, 0);
          gone[i] = 1;
        }
        break;
      default:
        break;
    }
  }
  // new ids: numbered in rank order after every id given so far (one process: in store order)
  std::uint64_t created = born.size();
  const std::uint64_t first = in_ ? S.comm->exscan(born.size(), created) : 0;
  if (born.empty() && gone.empty()) {
    k.next_id += static_cast<std::uint32_t>(created);
    return false;
  }
  P.clear_images();
  // particles that became fluid start their integrator history from their current state; a new
  // inflow particle replaces each, one zone length upstream
  std::vector<Vec<D>>* vprev = P.has(field::v_prev) ? &P.vector(field::v_prev) : nullptr;
  std::vector<double>* rprev = P.has(field::rho_prev) ? &P.scalar(field::rho_prev) : nullptr;
  std::vector<Vec<D>> spawn, spawn_vel;
  std::vector<double> spawn_mass, spawn_rho;
  for (std::size_t i : born) {
    if (vprev) (*vprev)[i] = P.vel[i];
    if (rprev) (*rprev)[i] = P.rho[i];
    Vec<D> x = P.pos[i];
    x[0] -= in_->x1 - in_->x0;
    spawn.push_back(x);
    spawn_mass.push_back(P.mass[i]);
    spawn_vel.push_back(P.vel[i]);
    spawn_rho.push_back(P.rho[i]);
  }
  if (!gone.empty()) P.remove_if_flagged(gone);
  for (std::size_t j = 0; j < spawn.size(); ++j) {
    P.add(spawn[j], Vec<D>{}, rho0_, spawn_mass[j], Kind::Inflow);
    const std::size_t i = P.n_owned() - 1;
    P.id[i] = k.next_id + static_cast<std::uint32_t>(first + j);
    if (in_->velocity == "averaged") {  // Kazemi: the new particle takes the converted one's state
      P.vel[i] = spawn_vel[j];
      P.rho[i] = spawn_rho[j];
      P.p[i] = S.eos.pressure(spawn_rho[j]);
    } else {
      impose(S, i, *in_, true);
    }
    if (vprev) (*vprev)[i] = P.vel[i];
    if (rprev) (*rprev)[i] = P.rho[i];
  }
  k.next_id += static_cast<std::uint32_t>(created);
  return true;
}

template class OpenBoundaries<2>;
template class OpenBoundaries<3>;

}  // namespace sph
