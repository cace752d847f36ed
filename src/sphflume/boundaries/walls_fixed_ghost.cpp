// Fixed ghost walls (boundaries/walls.hpp's wall_registry: `walls.type: fixed_ghost`; Marrone et al. 2011, Federico
// §5.2.6): each wall particle a ghost whose state is the fluid's interpolated at its mirror point (core/interpolate.hpp).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <optional>
#include <stdexcept>
#include <utility>
#include <vector>

#include "sphflume/boundaries/walls.hpp"
#include "sphflume/core/interpolate.hpp"

namespace sph {
namespace {

/// A stencil's ranges as one 64-bit key (FNV-1a; equal ranges, equal keys).
inline std::uint64_t stencil_key(const std::uint32_t (*rg)[2], int nr) {
  std::uint64_t h = 1469598103934665603ull;
  auto mix = [&h](std::uint64_t v) { h = (h ^ v) * 1099511628211ull; };
  mix(static_cast<std::uint64_t>(nr));
  for (int r = 0; r < nr; ++r) mix((static_cast<std::uint64_t>(rg[r][0]) << 32) | rg[r][1]);
  return h;
}

/// Fixed ghost particles (Marrone et al. 2011, Federico §5.2.6): each wall particle is a ghost
/// with an interpolation point mirrored across the wall surface into the fluid
/// (store field "ghost_mirror", made with the geometry). Before each rates pass the fluid's
/// pressure and velocity are interpolated there with first-order MLS; the ghost takes
///   p_g = p_I + ρ_I g·(x_g − x_I)    (Neumann condition ∂p/∂n = ρ g·n),
///   u_g = −u_I (no-slip)  or  u_I − 2 (u_I·n) n (free-slip: normal component reversed).
template <int D>
class FixedGhostWalls final : public WallModel<D> {
 public:
  using WallModel<D>::WallModel;
  const char* name() const override { return "fixed_ghost"; }
  bool evolves_density() const override { return false; }

  void init_fields(System<D>& S, std::size_t first_wall, const std::vector<Vec<D>>& surface) const override {
    WallModel<D>::init_fields(S, first_wall, surface);
    auto& P = S.particles;
    auto& mir = P.vector(field::ghost_mirror);  // each ghost's interpolation point, mirrored into the fluid
    for (std::size_t k = 0; k < surface.size(); ++k) mir[first_wall + k] = 2.0 * surface[k] - P.pos[first_wall + k];
  }

  void prepare(System<D>& S, const double*) override {
    auto& P = S.particles;
    if (!P.has(field::ghost_mirror))
      throw std::logic_error("fixed_ghost walls: the geometry made no mirror points (ghost_mirror)");
    const auto& mir = P.vector(field::ghost_mirror);
    const bool no_slip = this->cfg.no_slip, clamp = this->cfg.clamp_negative_pressure;
    const double rho_bg = S.eos.density(S.eos.background);
    auto fields = [&](std::uint32_t b) {
      std::array<double, D + 1> f;
      f[0] = P.p[b];
      for (int d = 0; d < D; ++d) f[d + 1] = P.vel[b][d];
      return f;
    };
    // the ghost's state from the fluid's at its mirror point
    auto set_ghost = [&](std::size_t i, const std::optional<std::array<double, D + 1>>& v) {
      const Vec<D> xi = mir[i];
      if (!v) {  // no fluid near the interpolation point: the background state
        P.p[i] = S.eos.background;
        P.rho[i] = rho_bg;
        P.vel[i] = Vec<D>{};
        return;
      }
      const Vec<D> dxg = P.pos[i] - xi;  // from the interpolation point to the ghost
      const double rho_i = S.eos.density((*v)[0]);
      double pg = (*v)[0] + rho_i * dot(S.gravity, dxg);
      if (clamp) pg = std::max(pg, S.eos.background);
      Vec<D> u;
      for (int d = 0; d < D; ++d) u[d] = (*v)[d + 1];
      // normal part reversed; tangential part reversed (no-slip), kept (free-slip) or scaled by psi
      const double psi = std::isnan(this->cfg.tangential_factor) ? (no_slip ? -1.0 : 1.0) : this->cfg.tangential_factor;
      const double len = norm(dxg);
      if (len > 0.0) {
        const Vec<D> nrm = (1.0 / len) * dxg;
        const Vec<D> un = dot(u, nrm) * nrm;
        u = psi * (u - un) - un;
      } else {
        u *= -1.0;
      }
      P.p[i] = pg;
      P.rho[i] = S.eos.density(pg);
      P.vel[i] = u;
    };
    // the wall particles grouped by their mirror points' candidate stencils (those of one cell share its ranges: the
    // stencil's water is listed once, interpolate_mls_shared; the same bits as one interpolation per wall particle)
    const double support = S.with_kernel([](const auto& K) { return K.support; });
    group_walls(S, mir, support);
    const std::size_t ng = starts_.size() - 1;
#pragma omp parallel
    {
      std::uint32_t r0[CellList<D>::kMaxRanges][2], r1[CellList<D>::kMaxRanges][2];
      std::vector<Vec<D>> xs;
      std::vector<std::uint32_t> ids;
#pragma omp for schedule(dynamic, 1)
      for (std::size_t g = 0; g < ng; ++g) {
        // (a member whose ranges are not the first's, a collision of the keys, is interpolated alone)
        const std::uint32_t lead = group_[starts_[g]].second;
        const int n0 = S.cells.ranges(mir[lead], r0, support);
        xs.clear();
        ids.clear();
        for (std::size_t k = starts_[g]; k < starts_[g + 1]; ++k) {
          const std::uint32_t i = group_[k].second;
          const int n1 = S.cells.ranges(mir[i], r1, support);
          if (n1 == n0 && std::equal(&r1[0][0], &r1[0][0] + 2 * n1, &r0[0][0])) {
            xs.push_back(mir[i]);
            ids.push_back(i);
          } else {
            set_ghost(i, interpolate_mls_n<D, D + 1>(S, mir[i], fields));
          }
        }
        interpolate_mls_shared<D, D + 1>(S, r0, n0, xs.data(), xs.size(), fields,
                                         [&](std::size_t j, const auto& v) { set_ghost(ids[j], v); });
      }
    }
    S.refresh_halos();
  }

 private:
  /// group_ and starts_: the owned wall particles by the key of their mirror points' stencil ranges, in a fixed order.
  void group_walls(const System<D>& S, const std::vector<Vec<D>>& mir, double support) {
    const auto& P = S.particles;
    group_.clear();
    std::uint32_t rg[CellList<D>::kMaxRanges][2];
    for (std::size_t i = 0; i < P.n_owned(); ++i) {
      if (P.kind[i] != Kind::Wall) continue;
      const int nr = S.cells.ranges(mir[i], rg, support);
      group_.push_back({stencil_key(rg, nr), static_cast<std::uint32_t>(i)});
    }
    std::sort(group_.begin(), group_.end());
    starts_.clear();
    for (std::size_t g = 0; g < group_.size(); ++g)
      if (g == 0 || group_[g].first != group_[g - 1].first) starts_.push_back(g);
    starts_.push_back(group_.size());
  }

  std::vector<std::pair<std::uint64_t, std::uint32_t>> group_;  // (stencil key, wall particle), sorted
  std::vector<std::size_t> starts_;                              // each group's first entry in group_, then the end
};

}  // namespace

template <int D>
std::unique_ptr<WallModel<D>> make_fixed_ghost_walls(const WallConfig& c) {
  return std::make_unique<FixedGhostWalls<D>>(c);
}
template std::unique_ptr<WallModel<2>> make_fixed_ghost_walls<2>(const WallConfig&);
template std::unique_ptr<WallModel<3>> make_fixed_ghost_walls<3>(const WallConfig&);

}  // namespace sph
