#include "sphflume/boundaries/motion.hpp"

#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "sphflume/core/errors.hpp"
#include "sphflume/core/interpolate.hpp"

namespace sph {

template <int D>
WallMotion<D>::WallMotion(const std::vector<MotionConfig>& motions, const std::string& file) : cfg_(motions) {
  for (const auto& m : cfg_) {
    laws_.push_back(make_paddle_law(m, file));
    Vec<D> e{};
    if (m.direction.empty()) e[0] = 1.0;
    else
      for (int d = 0; d < D; ++d) e[d] = m.direction[static_cast<std::size_t>(d)];
    const double len = norm(e);
    if (!(len > 0.0)) throw InputError(fmt::format("{}: line {}: motion '{}': direction must be non-zero", file, m.line, m.name));
    dir_.push_back((1.0 / len) * e);
  }
}

template <int D>
std::size_t WallMotion<D>::index(const std::string& name) const {
  for (std::size_t k = 0; k < cfg_.size(); ++k)
    if (cfg_[k].name == name) return k;
  throw std::out_of_range("no motion named " + name);
}

template <int D>
void WallMotion<D>::apply(System<D>& S, double t) const {
  auto& P = S.particles;
  const auto* grp = P.find(field::motion_group);
  if (!grp) return;
  const auto* org = P.find(field::motion_origin);
  if (!org) throw std::logic_error("wall motion: no motion_origin field");
  auto& acc = P.vector(field::wall_acc);
  std::vector<Vec<D>> x(size()), u(size()), a(size());
  for (std::size_t k = 0; k < size(); ++k) {
    x[k] = laws_[k]->displacement(t) * dir_[k];
    u[k] = laws_[k]->velocity(t) * dir_[k];
    a[k] = laws_[k]->acceleration(t) * dir_[k];
  }
  const std::size_t n = P.n_owned();
  for (std::size_t i = 0; i < n; ++i) {
    const double g = (*grp)[i];
    if (!(g > 0.0)) continue;
    const std::size_t k = static_cast<std::size_t>(g) - 1;
    P.pos[i] = (*org)[i] + x[k];
    P.vel[i] = u[k];
    acc[i] = a[k];
  }
}

template <int D>
Vec<D> WallMotion<D>::pressure_force(const System<D>& S, std::size_t k) const {
  const auto& P = S.particles;
  const auto* grp = P.find(field::motion_group);
  const auto* to = P.find(field::wall_to_surface);
  Vec<D> f{};
  if (!grp || !to) return f;
  const double want = double(k + 1);
  const double da = std::pow(S.dx, D - 1);  // the surface element of one first-layer particle
  for (std::size_t w = 0; w < P.n_owned(); ++w) {
    if ((*grp)[w] != want) continue;
    const Vec<D> s = (*to)[w];
    const double depth = norm(s);
    if (!(depth > 0.0) || depth >= S.dx) continue;  // deeper layers: no surface of their own
    const auto p = interpolate_mls(S, P.pos[w] + s, [&](std::uint32_t b) { return P.p[b]; });
    if (!p) continue;  // dry
    f -= (*p * da / depth) * s;  // the water pushes the face inwards (against its outward normal)
  }
  double fs[3] = {0.0, 0.0, 0.0};  // (summed over the parts of the domain: each adds its own walls)
  for (int d = 0; d < D; ++d) fs[d] = f[d];
  S.comm->sum(fs, D);
  for (int d = 0; d < D; ++d) f[d] = fs[d];
  return f;
}

template class WallMotion<2>;
template class WallMotion<3>;

}  // namespace sph
