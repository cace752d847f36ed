#include "sphflume/boundaries/walls.hpp"

#include <algorithm>
#include <cmath>

namespace sph {
namespace {

template <int D>
class DummyWalls final : public WallModel<D> {
 public:
  using WallModel<D>::WallModel;
  const char* name() const override { return "dummy"; }
  bool evolves_density() const override { return false; }
  const std::vector<Vec<D>>& viscous_velocity(const System<D>& S) const override {
    return ghost_ ? *ghost_ : S.particles.vel;
  }

  void prepare(System<D>& S) override {
    auto& P = S.particles;
    // the ghost velocity is only needed for no-slip walls (free-slip walls skip the viscous term)
    ghost_ = this->cfg.no_slip ? &P.vector("wall_ghost_velocity") : nullptr;
    Vec<D>* gv = ghost_ ? ghost_->data() : nullptr;
    const std::size_t n = P.n_owned();
    const bool clamp = this->cfg.clamp_negative_pressure;
    // walls with no fluid within the kernel support keep the background state: skip their
    // neighbour search (most of a tank's walls, most of the time)
    S.cells.mark_near(near_, [&](std::size_t j) { return P.kind[j] == Kind::Fluid; });
    S.with_kernel([&](const auto& K) {
#pragma omp parallel for schedule(static)
      for (std::size_t i = 0; i < n; ++i) {
        if (P.kind[i] != Kind::Wall) continue;
        if (!near_[S.cells.cell_of(i)]) {
          P.p[i] = S.eos.background;
          P.rho[i] = S.eos.density(S.eos.background);
          if (gv) gv[i] = P.vel[i];
          continue;
        }
        double sw = 0.0, sp = 0.0;
        Vec<D> srr{}, sv{};
        const Vec<D> xi = P.pos[i];
        std::uint32_t rg[CellList<D>::kMaxRanges][2];
        const int nr = S.cells.ranges(xi, rg);
        const auto& sorted = S.cells.sorted();
        for (int r = 0; r < nr; ++r)
          for (std::uint32_t k = rg[r][0]; k < rg[r][1]; ++k) {
            const std::uint32_t j = sorted[k];
            if (P.kind[j] != Kind::Fluid) continue;
            const Vec<D> rij = xi - P.pos[j];
            const double r2 = dot(rij, rij);
            if (r2 >= K.support2) continue;
            const double w = K.W(std::sqrt(r2));
            sw += w;
            sp += P.p[j] * w;
            srr += (P.rho[j] * w) * rij;
            sv += w * P.vel[j];
          }
        double pw = S.eos.background;
        Vec<D> g = P.vel[i];
        if (sw > 0.0) {
          pw = (sp + dot(S.gravity, srr)) / sw;  // fixed walls: wall acceleration a_w = 0
          g = 2.0 * P.vel[i] - (1.0 / sw) * sv;
        }
        if (clamp) pw = std::max(pw, S.eos.background);
        P.p[i] = pw;
        P.rho[i] = S.eos.density(pw);
        if (gv) gv[i] = g;
      }
    });
    P.refresh_images();
  }

 private:
  std::vector<Vec<D>>* ghost_ = nullptr;
  std::vector<char> near_;
};

template <int D>
class DynamicWalls final : public WallModel<D> {
 public:
  using WallModel<D>::WallModel;
  const char* name() const override { return "dynamic"; }
  bool evolves_density() const override { return true; }
  void prepare(System<D>&) override {}  // pressure follows the density in the integrator
};

}  // namespace

template <int D>
Registry<WallModel<D>, const WallConfig&>& wall_registry() {
  static Registry<WallModel<D>, const WallConfig&> r = [] {
    Registry<WallModel<D>, const WallConfig&> reg;
    reg.add("dummy", [](const WallConfig& c) { return std::make_unique<DummyWalls<D>>(c); });
    reg.add("dynamic", [](const WallConfig& c) { return std::make_unique<DynamicWalls<D>>(c); });
    return reg;
  }();
  return r;
}

template Registry<WallModel<2>, const WallConfig&>& wall_registry<2>();
template Registry<WallModel<3>, const WallConfig&>& wall_registry<3>();

}  // namespace sph
