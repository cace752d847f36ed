#include "sphflume/boundaries/motion.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
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
    Absorber a;
    if (m.absorb) {
      a.on = true;
      for (int d = 0; d < D && static_cast<std::size_t>(d) < m.absorb_point.size(); ++d) a.point[d] = m.absorb_point[static_cast<std::size_t>(d)];
      // the gain: exact for one frequency (ω/m1(kh): no reflection at that period), long-wave
      // theory sqrt(g/h) for a spectrum (docs/numerics.md, "Active absorption")
      a.c_h = std::sqrt(m.gravity / m.depth);
      const bool one_period = (m.law == "regular" || m.law == "stokes2" || m.law == "absorber") && m.period > 0.0;
      if (one_period) {
        const double w = 2.0 * std::numbers::pi / m.period;
        a.c_h = w / piston_transfer(wave_number(w, m.depth, m.gravity) * m.depth);
      }
      a.tau = m.drift_time;
      // the speed at which the level's reading is carried to the face (the delay d/c below)
      const double T = one_period ? m.period : (m.law == "irregular" || m.law == "focused") ? m.tp : 0.0;
      a.celerity = std::sqrt(m.gravity * m.depth);
      if (T > 0.0) {
        const double w = 2.0 * std::numbers::pi / T;
        a.celerity = w / wave_number(w, m.depth, m.gravity);
      }
    }
    abs_.push_back(a);
  }
}

template <int D>
void WallMotion<D>::absorb(System<D>& S, std::size_t k, double t) {
  Absorber& a = abs_[k];
  if (a.started && !(t > a.t_last)) return;  // a stage at the same or an earlier time: nothing new
  const auto& P = S.particles;
  if (!a.started) {  // the level's scan starts above the paddle's top; the gauge's distance from its face
    const auto* grp = P.find(field::motion_group);
    const auto* to = P.find(field::wall_to_surface);
    double top = -std::numeric_limits<double>::infinity(), face = top;
    for (std::size_t i = 0; i < P.n_owned(); ++i)
      if (grp && (*grp)[i] == double(k + 1)) {
        top = std::max(top, P.pos[i][D - 1]);
        if (to) face = std::max(face, dot(P.pos[i] + (*to)[i], dir_[k]));
      }
    a.top = S.comm->max(top);
    face = S.comm->max(face) - displacement(k, t);
    a.offset = std::isfinite(face) ? std::max(0.0, dot(a.point, dir_[k]) - face) : 0.0;
    a.delay = a.offset / a.celerity;
  }
  const double dt = a.started ? t - a.t_last : 0.0;
  a.x += dt * a.u;
  const Vec<D> p = a.point + (laws_[k]->displacement(t) + a.x) * dir_[k];
  const double level = water_level_at<D>(p, S, a.top);
  if (!std::isfinite(level))
    throw SimulationError(fmt::format("at t = {:.6g} s: motion '{}': no water at its absorption gauge '{}' (x = {:.4g} m): "
                                      "move the gauge into the water ahead of the paddle",
                                      t, cfg_[k].name, cfg_[k].absorb_gauge, p[0]));
  const double e = level - laws_[k]->elevation(t, a.offset);
  if (!a.started) {
    a.e_mean = e;
    a.started = true;
  } else {
    a.e_mean += std::min(1.0, dt / a.tau) * (e - a.e_mean);
  }
  // the reading of d/c ago: what arrives at the face now passed the gauge then (an incoming wave
  // read late by kd in phase would leave K = tan(kd/2); docs/numerics.md §15)
  a.hist.emplace_back(t, e);
  const double td = t - a.delay;
  while (a.hist.size() > 2 && a.hist[1].first <= td) a.hist.pop_front();
  double ed = a.hist.front().second;
  if (a.hist.size() > 1 && td > a.hist.front().first) {
    const auto& [t0, e0] = a.hist[0];
    const auto& [t1, e1] = a.hist[1];
    ed = e0 + (e1 - e0) * std::min(1.0, (td - t0) / (t1 - t0));
  }
  a.u = -a.c_h * (ed - a.e_mean) - a.x / a.tau;
  a.t_last = t;
}

template <int D>
double WallMotion<D>::displacement(std::size_t k, double t) const {
  return laws_[k]->displacement(t) + abs_[k].x + (abs_[k].started && t > abs_[k].t_last ? (t - abs_[k].t_last) * abs_[k].u : 0.0);
}

template <int D>
double WallMotion<D>::velocity(std::size_t k, double t) const {
  return laws_[k]->velocity(t) + abs_[k].u;
}

template <int D>
std::map<std::string, double> WallMotion<D>::state() const {
  std::map<std::string, double> s;
  for (std::size_t k = 0; k < abs_.size(); ++k) {
    const auto& a = abs_[k];
    if (!a.on || !a.started) continue;
    const std::string p = "motion." + cfg_[k].name + ".";
    s[p + "t_last"] = a.t_last;
    s[p + "e_mean"] = a.e_mean;
    s[p + "x"] = a.x;
    s[p + "u"] = a.u;
    s[p + "top"] = a.top;
    s[p + "offset"] = a.offset;
    s[p + "delay"] = a.delay;
    s[p + "history"] = static_cast<double>(a.hist.size());
    for (std::size_t j = 0; j < a.hist.size(); ++j) {
      s[fmt::format("{}history.{}.t", p, j)] = a.hist[j].first;
      s[fmt::format("{}history.{}.e", p, j)] = a.hist[j].second;
    }
  }
  return s;
}

template <int D>
void WallMotion<D>::restore(const std::map<std::string, double>& s) {
  for (std::size_t k = 0; k < abs_.size(); ++k) {
    auto& a = abs_[k];
    const std::string p = "motion." + cfg_[k].name + ".";
    const auto it = s.find(p + "t_last");
    if (!a.on || it == s.end()) continue;
    a.started = true;
    a.t_last = it->second;
    a.e_mean = s.at(p + "e_mean");
    a.x = s.at(p + "x");
    a.u = s.at(p + "u");
    a.top = s.at(p + "top");
    a.offset = s.at(p + "offset");
    a.delay = s.at(p + "delay");
    a.hist.clear();
    const auto nh = static_cast<std::size_t>(s.at(p + "history"));
    for (std::size_t j = 0; j < nh; ++j)
      a.hist.emplace_back(s.at(fmt::format("{}history.{}.t", p, j)), s.at(fmt::format("{}history.{}.e", p, j)));
  }
}

template <int D>
std::size_t WallMotion<D>::index(const std::string& name) const {
  for (std::size_t k = 0; k < cfg_.size(); ++k)
    if (cfg_[k].name == name) return k;
  throw std::out_of_range("no motion named " + name);
}

template <int D>
void WallMotion<D>::apply(System<D>& S, double t) {
  auto& P = S.particles;
  const auto* grp = P.find(field::motion_group);
  if (!grp) return;
  for (std::size_t k = 0; k < size(); ++k)
    if (abs_[k].on) absorb(S, k, t);
  const auto* org = P.find(field::motion_origin);
  if (!org) throw std::logic_error("wall motion: no motion_origin field");
  auto& acc = P.vector(field::wall_acc);
  std::vector<Vec<D>> x(size()), u(size()), a(size());
  for (std::size_t k = 0; k < size(); ++k) {
    x[k] = displacement(k, t) * dir_[k];
    u[k] = velocity(k, t) * dir_[k];
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
