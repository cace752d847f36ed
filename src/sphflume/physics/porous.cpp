#include "sphflume/physics/porous.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "sphflume/core/shapes.hpp"
#include "sphflume/physics/relax_step.hpp"

namespace sph {

template <int D>
PorousMedia<D>::PorousMedia(const PorousConfig& c, KernelType kernel, double h, double dx, int levels)
    : cfg_(c), sharp_(c.field == "sharp"), literal_(c.field == "particles" && c.literal_normalisation), kernel_(kernel), dx_(dx) {
  for (const auto& rc : c.regions) {
    phi_min_ = std::min(phi_min_, rc.porosity);
    regions_.push_back(make_region(rc, h, dx));
  }
  // resolution levels: the porous particles' lattice and h at each level (the smoothed field's
  // mesh is set by the layer, not by dx: one field serves every level)
  if (c.field == "particles")
    for (int l = 1; l <= levels; ++l) {
      const double f = 1.0 / double(1 << l);
      finer_.emplace_back();
      for (const auto& rc : c.regions) finer_.back().push_back(make_region(rc, f * h, f * dx));
    }
}

template <int D>
typename PorousMedia<D>::Region PorousMedia<D>::make_region(const PorousRegionConfig& rc, double h, double dx) const {
  const double fac = kernel_support_factor(kernel_);
  const auto& c = cfg_;
  Region g;
  g.cfg = rc;
  g.box = rc.shape == "box";
  g.profile = rc.shape == "profile";
  if (g.profile) return g;
  if (rc.shape == "box") {
    for (int d = 0; d < D; ++d) { g.lo[d] = rc.min[d]; g.hi[d] = rc.max[d]; }
  } else if (rc.shape == "mesh") {
    for (int d = 0; d < D; ++d) { g.lo[d] = rc.mesh->lo()[static_cast<std::size_t>(d)]; g.hi[d] = rc.mesh->hi()[static_cast<std::size_t>(d)]; }
  } else {  // polygon (2D)
    g.lo = Vec<D>{};
    for (int d = 0; d < D; ++d) { g.lo[d] = 1e300; g.hi[d] = -1e300; }
    for (const auto& v : rc.vertices)
      for (int d = 0; d < 2 && d < D; ++d) {
        g.lo[d] = std::min(g.lo[d], v[d]);
        g.hi[d] = std::max(g.hi[d], v[d]);
      }
  }
  if (c.field == "particles") {
    g.spacing = fill_spacing_of(rc.porosity, dx);
    g.h = h;
    g.reach = fac * h;
  } else {  // smoothed: r_Ω = layer/2 (default d_s/2), h_Ω = r_Ω/2, mesh h_Ω / mesh_ratio
    const double layer = rc.layer > 0.0 ? rc.layer : rc.diameter;
    g.reach = 0.5 * layer;
    g.h = g.reach / fac;
    g.spacing = 0.5 * g.reach / c.mesh_ratio;
  }
  // a box's lattice fits it: the spacing in each direction is adjusted to a whole number of
  // nodes across the box, so that the indicator's half level lies on every face (a lattice
  // started at one face puts the opposite face up to one node inside the box; a face off by
  // 1 mm put still water over a porous block in motion). Tsurudome's literal normalisation
  // keeps the printed dx / phi0^(1/D).
  for (int d = 0; d < D; ++d) {
    g.step[d] = g.spacing;
    if (rc.shape == "box" && !(c.field == "particles" && c.literal_normalisation)) {
      const double len = g.hi[d] - g.lo[d];
      g.step[d] = len / std::max(1.0, std::round(len / g.spacing));
    }
    g.origin[d] = g.lo[d] + 0.5 * g.step[d];
  }
  make_node_mask(g);
  return g;
}

namespace {
constexpr std::size_t kMaxMaskNodes = std::size_t(1) << 22;  // (4 M nodes: 4 MB of mask, 16 MB of sums)
}

template <int D>
std::size_t PorousMedia<D>::Region::node(const int* i) const {
  return (std::size_t(i[0]) * std::size_t(count[1]) + std::size_t(i[1])) * std::size_t(count[2]) + std::size_t(i[2]);
}

template <int D>
std::uint32_t PorousMedia<D>::Region::inside_count(const int* lo, const int* hi) const {
  // summed[(a, b, c)] = nodes inside among those with relative index < (a, b, c); inclusion-exclusion over the box
  const std::size_t n1 = std::size_t(count[1]) + 1, n2 = std::size_t(count[2]) + 1;
  const auto S = [&](std::size_t a, std::size_t b, std::size_t c) { return std::int64_t(summed[(a * n1 + b) * n2 + c]); };
  const std::size_t a0 = std::size_t(lo[0]), a1 = std::size_t(hi[0]) + 1, b0 = std::size_t(lo[1]), b1 = std::size_t(hi[1]) + 1;
  const std::size_t c0 = std::size_t(lo[2]), c1 = std::size_t(hi[2]) + 1;
  const std::int64_t v = S(a1, b1, c1) - S(a0, b1, c1) - S(a1, b0, c1) - S(a1, b1, c0) + S(a0, b0, c1) + S(a0, b1, c0) +
                         S(a1, b0, c0) - S(a0, b0, c0);
  return static_cast<std::uint32_t>(v);
}

template <int D>
void PorousMedia<D>::make_node_mask(Region& g) const {
  // The nodes a particle's stencil can reach: indicator() reads nodes within the reach of x, and x within the reach
  // of the bounding box (one node more each side for the round-off of the index bounds).
  if (g.profile || sharp_) return;
  double total = 1.0, smax = 0.0;  // (in double: a fine mesh over a large region overflows an integer count)
  for (int d = 0; d < D; ++d) {
    const double first = std::floor((g.lo[d] - 2.0 * g.reach - g.origin[d]) / g.step[d]) - 1.0;
    const double last = std::ceil((g.hi[d] + 2.0 * g.reach - g.origin[d]) / g.step[d]) + 1.0;
    total *= last - first + 1.0;
    smax = std::max(smax, g.step[d]);
    if (total <= double(kMaxMaskNodes)) {
      g.first[d] = static_cast<int>(first);
      g.count[d] = static_cast<int>(last - first + 1.0);
    }
  }
  // a stencil's box holds the node nearest x in each direction (reach >= step/2), at most step/2 off in each:
  // that node is within the reach (and its W > 0) when D (step/2)^2 < reach^2 (here with a margin)
  g.nearest_in_reach = D * 0.25 * smax * smax < 0.81 * g.reach * g.reach;
  if (total > double(kMaxMaskNodes)) {
    for (int d = 0; d < 3; ++d) { g.first[d] = 0; g.count[d] = 1; }
    return;
  }
  g.mask.assign(std::size_t(total), 0);
  int a[3] = {0, 0, 0};
  Vec<D> c{};
  for (a[0] = 0; a[0] < g.count[0]; ++a[0]) {
    c[0] = g.origin[0] + (g.first[0] + a[0]) * g.step[0];  // (as indicator() places node i: origin + i step)
    for (a[1] = 0; a[1] < g.count[1]; ++a[1]) {
      c[1] = g.origin[1] + (g.first[1] + a[1]) * g.step[1];
      for (a[2] = 0; a[2] < g.count[2]; ++a[2]) {
        if constexpr (D == 3) c[2] = g.origin[2] + (g.first[2] + a[2]) * g.step[2];
        g.mask[g.node(a)] = inside(g, c) ? 1 : 0;
      }
    }
  }
  const std::size_t n1 = std::size_t(g.count[1]) + 1, n2 = std::size_t(g.count[2]) + 1;
  g.summed.assign((std::size_t(g.count[0]) + 1) * n1 * n2, 0);
  const auto at = [&](std::size_t i, std::size_t j, std::size_t k) -> std::uint32_t& { return g.summed[(i * n1 + j) * n2 + k]; };
  for (std::size_t i = 1; i <= std::size_t(g.count[0]); ++i)
    for (std::size_t j = 1; j < n1; ++j)
      for (std::size_t k = 1; k < n2; ++k) {
        const int r[3] = {int(i - 1), int(j - 1), int(k - 1)};
        at(i, j, k) = g.mask[g.node(r)] + at(i - 1, j, k) + at(i, j - 1, k) + at(i, j, k - 1) - at(i - 1, j - 1, k) -
                      at(i - 1, j, k - 1) - at(i, j - 1, k - 1) + at(i - 1, j - 1, k - 1);
      }
}

template <int D>
double PorousMedia<D>::fill_spacing_of(double phi, double dx) {
  return dx / std::pow(phi, 1.0 / D);
}

template <int D>
double PorousMedia<D>::fill_spacing(std::size_t r) const {
  if (regions_[r].cfg.shape == "profile") return 0.0;
  return fill_spacing_of(regions_[r].cfg.porosity, dx_);
}

template <int D>
bool PorousMedia<D>::inside(const Region& g, const Vec<D>& x) const {
  if (g.cfg.shape == "box") {
    for (int d = 0; d < D; ++d)
      if (x[d] < g.lo[d] || x[d] > g.hi[d]) return false;
    return true;
  }
  if (g.cfg.shape == "polygon") {
    if constexpr (D == 2) return inside_polygon(g.cfg.vertices, x[0], x[1]);
  }
  if (g.cfg.shape == "mesh") {
    if constexpr (D == 3) {
      for (int d = 0; d < D; ++d)
        if (x[d] < g.lo[d] || x[d] > g.hi[d]) return false;  // (the box first: a mesh query costs a ray cast)
      return g.cfg.mesh->inside({x[0], x[1], x[2]});
    }
  }
  return false;
}

template <int D>
bool PorousMedia<D>::inside(std::size_t r, const Vec<D>& x) const {
  return inside(regions_[r], x);
}

template <int D>
double PorousMedia<D>::indicator(const Region& g, const Vec<D>& x, double dx) const {
  if (sharp_) return inside(g, x) ? 1.0 : 0.0;
  for (int d = 0; d < D; ++d)
    if (x[d] < g.lo[d] - g.reach || x[d] > g.hi[d] + g.reach) return 0.0;
  const bool literal = literal_;
  if (g.box && !literal) {  // deep inside a box the normalised sum is exactly 1
    bool deep = true;
    for (int d = 0; d < D; ++d) deep &= x[d] > g.lo[d] + g.reach && x[d] < g.hi[d] - g.reach;
    if (deep) return 1.0;
  }
  const Vec<D>& s = g.step;
  const double R2 = g.reach * g.reach;
  int lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
  for (int d = 0; d < D; ++d) {
    lo[d] = static_cast<int>(std::ceil((x[d] - g.reach - g.origin[d]) / s[d]));
    hi[d] = static_cast<int>(std::floor((x[d] + g.reach - g.origin[d]) / s[d]));
  }
  // particles: porous particles are the lattice nodes inside the region; smoothed: mesh nodes
  // carry the indicator. Both: the sum over nodes inside, normalised by the sum over all nodes.
  // With the nodes' tests made once (make_node_mask): no node of the stencil's box inside, the sum is 0; every one
  // inside, the two sums are the same sum and the quotient exactly 1 (the nearest node's W > 0): the same bits as the
  // loop below, which reads the mask for the mixed stencils of the interface.
  const bool masked = !g.mask.empty();
  if (masked) {
    int rl[3] = {0, 0, 0}, rh[3] = {0, 0, 0};
    std::uint64_t nodes = 1;
    for (int d = 0; d < D; ++d) {
      nodes *= std::uint64_t(std::max(0, hi[d] - lo[d] + 1));
      rl[d] = std::max(lo[d] - g.first[d], 0);
      rh[d] = std::min(hi[d] - g.first[d], g.count[d] - 1);
      if (rh[d] < rl[d]) return 0.0;  // (no node stored: none inside)
    }
    const std::uint32_t in_box = g.inside_count(rl, rh);
    if (in_box == 0) return 0.0;
    if (!literal && g.nearest_in_reach && in_box == nodes) return 1.0;
  }
  const auto node_inside = [&](const Vec<D>& c, int i, int j, int k) {
    if (!masked) return inside(g, c);
    const int r[3] = {i - g.first[0], j - g.first[1], D == 3 ? k - g.first[D - 1] : 0};
    for (int d = 0; d < D; ++d)
      if (r[d] < 0 || r[d] >= g.count[d]) return false;  // (beyond the box and twice the reach: outside)
    return g.mask[g.node(r)] != 0;
  };
  return with_kernel<D>(kernel_, g.h, [&](const auto& K) {
    double in = 0.0, all = 0.0;
    Vec<D> c{};
    for (int i = lo[0]; i <= hi[0]; ++i) {
      c[0] = g.origin[0] + i * s[0];
      for (int j = lo[1]; j <= hi[1]; ++j) {
        c[1] = g.origin[1] + j * s[1];
        const int k0 = D == 3 ? lo[D - 1] : 0, k1 = D == 3 ? hi[D - 1] : 0;
        for (int k = k0; k <= k1; ++k) {
          if constexpr (D == 3) c[2] = g.origin[2] + k * s[2];
          const Vec<D> r = x - c;
          const double r2 = dot(r, r);
          if (r2 >= R2) continue;
          const double w = K.W(std::sqrt(r2));
          all += w;
          if (node_inside(c, i, j, k)) in += w;
        }
      }
    }
    if (literal) return std::pow(dx, D) * in;  // ρ_p / ρ_w with m_p = ρ_w dx^D
    return all > 0.0 ? in / all : 0.0;
  });
}

template <int D>
double PorousMedia<D>::profile(const Region& g, const Vec<D>& x) const {
  // linear interpolation in a table, constant beyond its ends
  auto locate = [](const std::vector<double>& t, double v, std::size_t& i, double& f) {
    if (t.size() == 1 || v <= t.front()) { i = 0; f = 0.0; return; }
    if (v >= t.back()) { i = t.size() - 2; f = 1.0; return; }
    i = static_cast<std::size_t>(std::upper_bound(t.begin(), t.end(), v) - t.begin()) - 1;
    f = (v - t[i]) / (t[i + 1] - t[i]);
  };
  const auto& c = g.cfg;
  std::size_t iz = 0;
  double fz = 0.0;
  locate(c.z, x[D - 1], iz, fz);
  auto at = [&](const std::vector<double>& row) {
    return c.z.size() == 1 ? row[0] : (1.0 - fz) * row[iz] + fz * row[iz + 1];
  };
  if (c.x.empty()) return at(c.phi[0]);
  std::size_t ix = 0;
  double fx = 0.0;
  locate(c.x, x[0], ix, fx);
  if (c.x.size() == 1) return at(c.phi[0]);
  return (1.0 - fx) * at(c.phi[ix]) + fx * at(c.phi[ix + 1]);
}

template <int D>
double PorousMedia<D>::porosity(const Vec<D>& x, int* region, int level) const {
  double phi = 1.0, best = 0.0;
  int which = -1;
  const bool fine = level > 0 && static_cast<std::size_t>(level) <= finer_.size();
  const auto& regs = fine ? finer_[static_cast<std::size_t>(level - 1)] : regions_;
  const double dx = fine ? dx_ / double(1 << level) : dx_;
  for (std::size_t r = 0; r < regs.size(); ++r) {
    const Region& g = regs[r];
    const double c = g.profile ? 1.0 - profile(g, x) : (1.0 - g.cfg.porosity) * indicator(g, x, dx);
    phi -= c;
    if (c > best) { best = c; which = static_cast<int>(r); }
  }
  if (region) *region = which;
  return std::clamp(phi, phi_min_, 1.0);
}

template <int D>
void PorousMedia<D>::update(System<D>& S) {
  auto& P = S.particles;
  auto& phi = P.scalar(field::porosity);
  const std::size_t n = P.n_owned();
  region_of_.assign(n, -1);
  const double* lv = S.levels > 0 && !finer_.empty() ? P.require(field::level).data() : nullptr;
#pragma omp parallel for schedule(dynamic, 256)
  for (std::size_t i = 0; i < n; ++i) {
    if (P.kind[i] == Kind::Wall) { phi[i] = 1.0; continue; }
    phi[i] = porosity(P.pos[i], &region_of_[i], lv ? static_cast<int>(lv[i]) : 0);
  }
  S.refresh_halos(phi.data());
}

template <int D>
void PorousMedia<D>::drag(System<D>& S) {
  auto& P = S.particles;
  auto& rate = P.scalar(field::drag_rate);
  auto& inertia = P.scalar(field::inertia);
  const auto& phi = P.scalar(field::porosity);
  const std::size_t n = P.n_owned();
  if (region_of_.size() != n) throw std::logic_error("PorousMedia::drag: update() was not called for this state");
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    rate[i] = 0.0;
    inertia[i] = 1.0;
    const int r = region_of_[i];
    if (P.kind[i] != Kind::Fluid || r < 0) continue;
    const auto& c = regions_[static_cast<std::size_t>(r)].cfg;
    const auto& x = P.pos[i];
    const bool upper = c.has_upper && x[D - 1] > c.upper_z && x[0] > c.upper_x;
    const auto [K, M] = closure(upper ? c.upper : c.closure, phi[i], norm(P.vel[i]), S.nu, c.diameter);
    rate[i] = K / M;
    inertia[i] = 1.0 / M;
  }
}

template <int D>
std::pair<double, double> PorousMedia<D>::closure(const PorousClosureConfig& c, double phi, double speed, double nu,
                                                  double d) {
  if (!(phi < 1.0)) return {0.0, 1.0};
  const double s = 1.0 - phi;
  if (c.type == "roughness") return {c.factor * c.cd * s * speed / d, 1.0};
  if (c.type == "tsurudome") {
    const double p3 = phi * phi * phi;
    return {c.c1 * s * s / p3 * nu / (d * d) + c.c2 * s / p3 * speed / d, 1.0};
  }
  const double kc = (c.type == "van_gent" && c.kc > 0.0) ? 1.0 + 7.5 / c.kc : 1.0;
  const double K = c.c1 * s * s / (phi * phi) * nu / (d * d) + c.c2 * kc * s / phi * speed / d;
  const double M = c.type == "van_gent" ? 1.0 + c.added_mass * s / phi : 1.0;
  return {K, M};
}

template class PorousMedia<2>;
template class PorousMedia<3>;

template <int D>
PorousRelaxReport relax_porous_band(const PorousMedia<D>& pm, KernelType kernel, double h, double dx,
                                    std::vector<Vec<D>>& fluid, const std::vector<char>& fixed,
                                    const std::vector<Vec<D>>& walls, int iterations) {
  PorousRelaxReport rep;
  const std::size_t nf = fluid.size();
  double vol0 = 1.0;
  for (int d = 0; d < D; ++d) vol0 *= dx;
  std::vector<Vec<D>> pos(fluid);
  pos.insert(pos.end(), walls.begin(), walls.end());
  const std::vector<Vec<D>> start(fluid);
  std::vector<double> vol(pos.size(), vol0);
  std::vector<char> band(nf, 0);
  std::vector<Vec<D>> shift(nf);
  with_kernel<D>(kernel, h, [&](const auto& K) {
    CellList<D> cells;
    for (int it = 0; it <= iterations; ++it) {
      for (std::size_t i = 0; i < nf; ++i) vol[i] = vol0 / pm.porosity(pos[i]);
      cells.build(pos, pos.size(), K.support);
      double res = 0.0;
      std::size_t nband = 0;
#pragma omp parallel for schedule(dynamic, 256) reduction(max : res) reduction(+ : nband)
      for (std::size_t a = 0; a < nf; ++a) {
        shift[a] = Vec<D>{};
        if (fixed[a]) continue;
        if (it == 0) {  // the band and the free surface are decided once, on the lattice
          const double phia = pm.porosity(pos[a]);
          double dphi = 0.0, wsum = 0.0;
          bool wall = false;
          Vec<D> centroid{};
          cells.for_neighbours(pos, pos[a], K.support, [&](std::uint32_t b, const Vec<D>& r, double r2) {
            const double w = K.W(std::sqrt(r2));
            wsum += w;
            centroid += (-w) * r;
            if (b < nf) dphi = std::max(dphi, std::abs(pm.porosity(pos[b]) - phia));
            else wall = true;
          });
          // the band: where φ varies, and where the porous fill's lattice meets the walls'
          band[a] = (dphi > 1e-9 || (wall && phia < 1.0)) && norm(centroid) < 0.2 * h * wsum;
        }
        if (!band[a]) continue;
        ++nband;
        Vec<D> g{};
        cells.for_neighbours(pos, pos[a], K.support, [&](std::uint32_t b, const Vec<D>& r, double r2) {
          if (r2 > 0.0) g += (vol[b] * K.F(std::sqrt(r2))) * r;
        });
        res = std::max(res, h * norm(g));
        shift[a] = relax_step<D>(g, h, dx, pos[a], start[a]);
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

template PorousRelaxReport relax_porous_band<2>(const PorousMedia<2>&, KernelType, double, double, std::vector<Vec<2>>&,
                                                const std::vector<char>&, const std::vector<Vec<2>>&, int);
template PorousRelaxReport relax_porous_band<3>(const PorousMedia<3>&, KernelType, double, double, std::vector<Vec<3>>&,
                                                const std::vector<char>&, const std::vector<Vec<3>>&, int);

}  // namespace sph
