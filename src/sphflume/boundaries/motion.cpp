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
    Vec<D> hp{};
    if (m.paddle == "flap")
      for (int d = 0; d < D && static_cast<std::size_t>(d) < m.hinge.size(); ++d) hp[d] = m.hinge[static_cast<std::size_t>(d)];
    hinge_.push_back(hp);
    Absorber a;
    if (m.absorb) {
      a.on = true;
      for (int d = 0; d < D && static_cast<std::size_t>(d) < m.absorb_point.size(); ++d) a.point[d] = m.absorb_point[static_cast<std::size_t>(d)];
      // the gain: exact for one frequency (ω/m1(kh): no reflection at that period), long-wave
      // theory sqrt(g/h) for a spectrum (docs/numerics.md, "Active absorption")
      a.c_h = std::sqrt(m.gravity / m.depth);
      // a flap's depth-mean velocity is its still-water-level velocity times d/(2h)
      if (m.paddle == "flap") a.c_h *= 2.0 * m.depth / m.hinge_depth;
      const bool one_period = (m.law == "regular" || m.law == "stokes2" || m.law == "absorber") && m.period > 0.0;
      if (one_period) {
        const double w = 2.0 * std::numbers::pi / m.period;
        a.c_h = w / paddle_transfer(m, wave_number(w, m.depth, m.gravity) * m.depth);
      }
      a.tau = m.drift_time;
      a.start = m.absorb_start;
      // the speed at which the level's reading is carried to the face (the delay d/c below)
      const double T = one_period ? m.period : (m.law == "irregular" || m.law == "focused") ? m.tp : 0.0;
      a.window = T;
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
    // the reading's delay: the travel from the gauge to the face, d/c, and the phase lead of the two
    // first-order high-passes (the mean ē and the drift correction, both over τ) at the law's
    // frequency, 2 atan(1/(ωτ))/ω, so that the correction is in phase there
    a.delay = a.offset / a.celerity;
    if (a.window > 0.0) {
      const double w = 2.0 * std::numbers::pi / a.window;
      a.delay += 2.0 * std::atan(1.0 / (w * a.tau)) / w;
    }
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
    a.t_first = t;
    a.started = true;
  } else if (t <= a.start) {
    // the start-up (the ramp, the SPH level settling near the paddle): ē is the plain mean of e
    // over its last window (the law's period: the near field's oscillation averages out)
    const double w0 = a.start - (a.window > 0.0 ? a.window : 0.5 * (a.start - a.t_first));
    if (t > w0) {
      a.e_sum += dt * e;
      a.e_time += dt;
      a.e_mean = a.e_sum / a.e_time;
    } else {
      a.e_mean = e;
    }
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
  a.u = t > a.start ? -a.c_h * (ed - a.e_mean) - a.x / a.tau : 0.0;
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
    s[p + "t_first"] = a.t_first;
    s[p + "e_sum"] = a.e_sum;
    s[p + "e_time"] = a.e_time;
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
    a.t_first = s.at(p + "t_first");
    a.e_sum = s.at(p + "e_sum");
    a.e_time = s.at(p + "e_time");
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

namespace {

/// a × v with a the flap's rotation axis z × e (e horizontal, unit): in 2D a is out of the plane,
/// a × (v_x, v_z) = (e_x v_z, −e_x v_x).
template <int D>
Vec<D> axis_cross(const Vec<D>& e, const Vec<D>& v) {
  Vec<D> r{};
  if constexpr (D == 2) {
    r[0] = e[0] * v[1];
    r[1] = -e[0] * v[0];
  } else {
    const double ax = -e[1], ay = e[0];  // a = z × e = (−e_y, e_x, 0)
    r[0] = ay * v[2];
    r[1] = -ax * v[2];
    r[2] = ax * v[1] - ay * v[0];
  }
  return r;
}

/// v rotated by θ about the axis a = z × e (Rodrigues; a ⊥ z, so the top of a vertical flap moves
/// toward e for θ > 0).
template <int D>
Vec<D> rotated(const Vec<D>& e, const Vec<D>& v, double c, double s) {
  const Vec<D> av = axis_cross<D>(e, v);
  Vec<D> along{};  // a (a·v): zero in 2D (v in the plane)
  if constexpr (D == 3) {
    const double ax = -e[1], ay = e[0];
    const double adv = ax * v[0] + ay * v[1];
    along[0] = ax * adv;
    along[1] = ay * adv;
  }
  return c * v + s * av + (1.0 - c) * along;
}

}  // namespace

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
  // a flap: θ = atan(X/d) about its hinge (X the displacement at the still-water level), θ' and θ''
  std::vector<double> th(size(), 0.0), dth(size(), 0.0), ddth(size(), 0.0);
  bool flaps = false;
  for (std::size_t k = 0; k < size(); ++k) {
    const double X = displacement(k, t), U = velocity(k, t), A = laws_[k]->acceleration(t);
    if (cfg_[k].paddle == "flap") {
      flaps = true;
      const double d = cfg_[k].hinge_depth, q = d * d + X * X;
      th[k] = std::atan2(X, d);
      dth[k] = U * d / q;
      ddth[k] = A * d / q - 2.0 * X * U * U * d / (q * q);
      continue;
    }
    x[k] = X * dir_[k];
    u[k] = U * dir_[k];
    a[k] = A * dir_[k];
  }
  std::vector<Vec<D>>* to = flaps ? &P.vector(field::wall_to_surface) : nullptr;
  const auto* to0 = flaps ? P.find(field::motion_surface0) : nullptr;
  std::vector<Vec<D>>* nrm = flaps && P.has(field::wall_normal) ? &P.vector(field::wall_normal) : nullptr;
  const auto* nrm0 = nrm ? P.find(field::motion_normal0) : nullptr;
  if (flaps && !to0) throw std::logic_error("wall motion: a flap without motion_surface0");
  std::vector<char> flap(size(), 0);
  for (std::size_t k = 0; k < size(); ++k) flap[k] = cfg_[k].paddle == "flap";
  const std::size_t n = P.n_owned();
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    const double g = (*grp)[i];
    if (!(g > 0.0)) continue;
    const std::size_t k = static_cast<std::size_t>(g) - 1;
    if (flap[k]) {
      const Vec<D>& e = dir_[k];
      const double c = std::cos(th[k]), s = std::sin(th[k]);
      const Vec<D> r = rotated<D>(e, (*org)[i] - hinge_[k], c, s);
      const Vec<D> ar = axis_cross<D>(e, r);
      P.pos[i] = hinge_[k] + r;
      P.vel[i] = dth[k] * ar;
      acc[i] = ddth[k] * ar + (dth[k] * dth[k]) * axis_cross<D>(e, ar);  // tangential and centripetal
      (*to)[i] = rotated<D>(e, (*to0)[i], c, s);
      if (nrm && nrm0) (*nrm)[i] = rotated<D>(e, (*nrm0)[i], c, s);
      continue;
    }
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
