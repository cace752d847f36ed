#include "sphflume/io/gauges.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <limits>

#include <fmt/format.h>

#include "sphflume/boundaries/motion.hpp"
#include "sphflume/core/interpolate.hpp"
#include "sphflume/io/runup.hpp"
#include "sphflume/io/snapshot.hpp"
#include "sphflume/physics/transport.hpp"

namespace sph {
namespace {

/// ∫ u ds over the wet part of a line sampled every ds (fluid fraction f ≥ 0.5): trapezoids over
/// the wet segments; a segment crossing the surface (f = 0.5, linearly interpolated) counts its
/// wet part, so the integral does not jump by a whole segment as the surface moves past a point.
double wet_integral(const std::vector<double>& f, const std::vector<double>& u, double ds) {
  double q = 0.0;
  for (std::size_t i = 1; i < f.size(); ++i) {
    const bool w0 = f[i - 1] >= 0.5, w1 = f[i] >= 0.5;
    if (w0 && w1) q += 0.5 * ds * (u[i - 1] + u[i]);
    else if (w0 != w1) {
      const double fw = w0 ? f[i - 1] : f[i], fd = w0 ? f[i] : f[i - 1];
      q += ds * (fw - 0.5) / (fw - fd) * (w0 ? u[i - 1] : u[i]);
    }
  }
  return q;
}

/// A gauge line's unit normal (for a line going up, +x) and its point spacing.
template <int D>
Vec<D> line_normal(const GaugeConfig& g, double& ds) {
  Vec<D> t{};
  double len2 = 0.0;
  for (int d = 0; d < D; ++d) { t[d] = g.end[d] - g.start[d]; len2 += t[d] * t[d]; }
  const double len = std::sqrt(len2);
  Vec<D> nrm{};
  nrm[0] = t[D - 1] / len;
  nrm[D - 1] = -t[0] / len;
  ds = len / (g.points - 1);
  return nrm;
}

/// Values at points, each computed by the part of the domain that holds the point (its
/// neighbours, owned or halo, are there) and summed over the parts: f(x, out) writes nv values
/// (NaN allowed); a point no part holds reads NaN. In one process: f at every point, as is.
template <int D, class F>
std::vector<double> at_held_points(const System<D>& S, const std::vector<Vec<D>>& pts, int nv, F&& f) {
  const std::size_t w = static_cast<std::size_t>(nv) + 1;
  std::vector<double> buf(pts.size() * w, 0.0);
  for (std::size_t i = 0; i < pts.size(); ++i)
    if (S.owns(pts[i])) {
      f(pts[i], &buf[i * w]);
      buf[i * w + w - 1] = 1.0;
    }
  S.comm->sum(buf.data(), buf.size());
  std::vector<double> out(pts.size() * (w - 1), std::numeric_limits<double>::quiet_NaN());
  for (std::size_t i = 0; i < pts.size(); ++i)
    if (buf[i * w + w - 1] > 0.0)
      for (std::size_t k = 0; k + 1 < w; ++k) out[i * (w - 1) + k] = buf[i * w + k] / buf[i * w + w - 1];
  return out;
}

/// The g.points points of a gauge line, evenly from start to end.
template <int D>
std::vector<Vec<D>> line_points(const GaugeConfig& g) {
  std::vector<Vec<D>> pts(static_cast<std::size_t>(g.points));
  for (int i = 0; i < g.points; ++i) {
    const double s = static_cast<double>(i) / (g.points - 1);
    for (int d = 0; d < D; ++d) pts[static_cast<std::size_t>(i)][d] = g.start[d] + s * (g.end[d] - g.start[d]);
  }
  return pts;
}

/// ∫ q·n ds over the wet part of a gauge line (fluid fraction ≥ 0.5): un(x, n) gives q·n at a
/// wet point (n the line's normal); each point is read by the part of the domain that holds it.
template <int D, class Un>
double wet_line_flux(const System<D>& S, const GaugeConfig& g, Un&& un) {
  double ds = 0.0;
  const Vec<D> nrm = line_normal<D>(g, ds);
  const auto fu = at_held_points(S, line_points<D>(g), 2, [&](const Vec<D>& x, double* out) {
    out[0] = fluid_fraction(S, x);
    out[1] = out[0] > 0.0 ? un(x, nrm) : 0.0;
  });
  std::vector<double> f(static_cast<std::size_t>(g.points)), q(f.size());
  for (std::size_t i = 0; i < f.size(); ++i) {
    f[i] = std::isfinite(fu[2 * i]) ? fu[2 * i] : 0.0;  // (a point outside every part: dry)
    q[i] = std::isfinite(fu[2 * i + 1]) ? fu[2 * i + 1] : 0.0;
  }
  return wet_integral(f, q, ds);
}

}  // namespace

template <int D>
GaugeSet<D>::GaugeSet(const std::vector<GaugeConfig>& gauges, const std::string& dir, double level_top,
                      double resume_after, bool writer)
    : cfg_(gauges), level_top_(level_top), dir_(dir), means_(gauges.size()),
      runmax_(gauges.size(), -std::numeric_limits<double>::infinity()), window_(gauges.size()), writer_(writer) {
  for (const auto& g : gauges) windowed_ |= g.type == "pressure" && g.window > 0.0;
  if (gauges.empty() || !writer) return;
  std::filesystem::create_directories(dir + "/gauges");
  const char* ax = D == 2 ? "xz" : "xyz";
  for (const auto& g : gauges) {
    const std::string path = dir + "/gauges/" + g.name + ".csv";
    if (std::isfinite(resume_after)) {  // restart: keep the header and the rows up to the restart time (rows are printed to 9 digits)
      std::ifstream in(path);
      if (!in) throw IoError(fmt::format("restart: gauge file '{}' is missing (restart into the run's own output folder)", path));
      std::string kept, line;
      bool header = true;
      while (std::getline(in, line)) {
        if (header || std::strtod(line.c_str(), nullptr) <= resume_after * (1.0 + 1e-8)) {
          kept += line + "\n";
          // a run-up gauge's running maximum goes on from the kept rows' last one
          if (!header && g.type == "runup") {
            const auto comma = line.rfind(',');
            const double mx = std::strtod(line.c_str() + comma + 1, nullptr);
            if (std::isfinite(mx)) runmax_[static_cast<std::size_t>(&g - gauges.data())] = mx;
          }
        }
        header = false;
      }
      write_file_atomically(path, kept);
      auto f = std::make_unique<std::ofstream>(path, std::ios::app);
      if (!*f) throw IoError(fmt::format("cannot write gauge file '{}'", path));
      files_.push_back(std::move(f));
      continue;
    }
    auto f = std::make_unique<std::ofstream>(path, std::ios::trunc);
    if (!*f) throw IoError(fmt::format("cannot write gauge file '{}'", path));
    *f << "time";
    if (g.type == "water_level") *f << ",level";
    else if (g.type == "pressure") *f << (g.window > 0.0 ? ",pressure,pressure_std,samples" : ",pressure");
    else if (g.type == "front") *f << ",front";
    else if (g.type == "energy") *f << ",kinetic,potential,total";
    else if (g.type == "water_volume") *f << ",water,bulk";
    else if (g.type == "flux") *f << ",flux";
    else if (g.type == "boundary_volume") *f << ",inflow,outflow,backflow";
    else if (g.type == "scalar") *f << "," << g.field;
    else if (g.type == "scalar_mass") *f << (D == 2 ? ",mass,min,max,x,z,source" : ",mass,min,max,x,y,z,source");
    else if (g.type == "scalar_flux") *f << ",flux";
    else if (g.type == "phase") *f << ",area,top,x,z";
    else if (g.type == "velocity") *f << (D == 2 ? ",ux,uz" : ",ux,uy,uz");
    else if (g.type == "runup") *f << ",runup,x,max";
    else if (g.type == "paddle") *f << (D == 2 ? ",displacement,velocity,acceleration,force_x,force_z" : ",displacement,velocity,acceleration,force_x,force_y,force_z");
    else if (g.type == "velocity_profile" || g.type == "stress_profile" || g.type == "depth_profile" ||
             g.type == "scalar_profile") {
      std::string pts = "index,x,y,z\n";
      for (int i = 0; i < g.points; ++i) {
        const double s = static_cast<double>(i) / (g.points - 1);
        double c[3] = {0, 0, 0};
        for (int d = 0; d < D; ++d) c[d == D - 1 ? 2 : d] = g.start[d] + s * (g.end[d] - g.start[d]);
        pts += fmt::format("{},{:.9g},{:.9g},{:.9g}\n", i, c[0], c[1], c[2]);
        if (g.type == "velocity_profile")
          for (int d = 0; d < D; ++d) *f << fmt::format(",u{}_{}", ax[d], i);
        else if (g.type == "stress_profile")
          *f << fmt::format(",ux_{0},tau_t_{0},tau_r_{0},nu_t_{0}", i);
        else if (g.type == "scalar_profile")
          *f << fmt::format(",{}_{}", g.field, i);
        else
          *f << fmt::format(",depth_{}", i);
      }
      write_file_atomically(dir + "/gauges/" + g.name + ".points.csv", pts);
    }
    *f << "\n";
    files_.push_back(std::move(f));
  }
}

template <int D>
std::vector<double> GaugeSet<D>::evaluate_stress(const GaugeConfig& g, const System<D>& S) {
  // Per point: Shepard-averaged streamwise velocity ū, the modelled turbulent shear stress
  // τ_t/ρ (the xz component of the eddy-viscosity stress, 0 without turbulence), the resolved
  // stress τ_r/ρ = −⟨(u − ū)(w − w̄)⟩ (Kazemi eqs 3.22–3.23: the kernel-weighted covariance of
  // the particle velocities about their kernel average; positive in the sense of τ_t) and ν_t.
  const auto& P = S.particles;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const char* xz = "tau_xz";
  const std::vector<double>* tau = P.has_scalar(xz) ? &P.scalar_fields().at(xz) : nullptr;
  const std::vector<double>* nut = P.has_scalar("nu_t") ? &P.scalar_fields().at("nu_t") : nullptr;
  return at_held_points(S, line_points<D>(g), 4, [&](const Vec<D>& x, double* out) {
    auto u = interpolate_shepard(S, x, [&](std::uint32_t b) { return P.vel[b][0]; });
    auto w = interpolate_shepard(S, x, [&](std::uint32_t b) { return P.vel[b][D - 1]; });
    if (!u || !w) {
      for (int k = 0; k < 4; ++k) out[k] = nan;
      return;
    }
    const double ub = *u, wb = *w;
    auto tt = tau ? interpolate_shepard(S, x, [&](std::uint32_t b) { return (*tau)[b]; }) : std::optional<double>(0.0);
    auto tr = interpolate_shepard(S, x, [&](std::uint32_t b) { return -(P.vel[b][0] - ub) * (P.vel[b][D - 1] - wb); });
    auto nt = nut ? interpolate_shepard(S, x, [&](std::uint32_t b) { return (*nut)[b]; }) : std::optional<double>(0.0);
    out[0] = ub;
    out[1] = tt ? *tt : nan;
    out[2] = tr ? *tr : nan;
    out[3] = nt ? *nt : nan;
  });
}

template <int D>
std::vector<double> GaugeSet<D>::evaluate_scalar(const GaugeConfig& g, const System<D>& S) {
  // transported scalars (field = the scalar's name) and phases (field = the phase's name)
  const auto& P = S.particles;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  auto point = [&](const std::vector<double>& a, const std::vector<double>& b, double s) {
    Vec<D> x{};
    for (int d = 0; d < D; ++d) x[d] = a[d] + s * (b[d] - a[d]);
    return x;
  };
  if (g.type == "phase") {  // area (volume in 3D) Σ m/ρ, top (highest particle), area centroid
    const auto* ph = P.find_scalar("phase");
    double k = -1.0;
    for (std::size_t i = 0; i < S.phase_names.size(); ++i)
      if (S.phase_names[i] == g.field) k = static_cast<double>(i);
    double area = 0.0, top = -std::numeric_limits<double>::infinity(), cx = 0.0, cz = 0.0;
    for (std::size_t i = 0; i < P.n_owned(); ++i) {
      if (P.kind[i] != Kind::Fluid || !ph || (*ph)[i] != k) continue;
      const double v = P.mass[i] / P.rho[i];
      area += v;
      top = std::max(top, P.pos[i][D - 1]);
      cx += v * P.pos[i][0];
      cz += v * P.pos[i][D - 1];
    }
    double sums[3] = {area, cx, cz};  // (over the parts of the domain)
    S.comm->sum(sums, 3);
    area = sums[0];
    cx = sums[1];
    cz = sums[2];
    top = S.comm->max(top);
    if (!(area > 0.0)) return {0.0, nan, nan, nan};
    return {area, top, cx / area, cz / area};
  }
  const auto* Cp = P.find_scalar(g.field);
  if (!Cp) return {nan};
  const auto& C = *Cp;
  auto value_at = [&](const Vec<D>& x, double* out) {
    auto v = interpolate_shepard(S, x, [&](std::uint32_t b) { return C[b]; });
    out[0] = v ? *v : nan;
  };
  if (g.type == "scalar") return at_held_points(S, {point(g.point, g.point, 0.0)}, 1, value_at);
  if (g.type == "scalar_profile") return at_held_points(S, line_points<D>(g), 1, value_at);
  if (g.type == "scalar_mass") {  // pollutant mass Σ m C/ρ = Σ V C, extremes of C, mass centroid
    double m = 0.0, lo = std::numeric_limits<double>::infinity(), hi = -lo;
    double c[3] = {0.0, 0.0, 0.0};
    for (std::size_t i = 0; i < P.n_owned(); ++i) {
      if (P.kind[i] != Kind::Fluid) continue;
      bool in = true;
      for (std::size_t d = 0; d < g.start.size(); ++d) in &= P.pos[i][d] >= g.start[d] && P.pos[i][d] < g.end[d];
      if (!in) continue;
      const double mi = P.mass[i] * C[i] / P.rho[i];
      m += mi;
      lo = std::min(lo, C[i]);
      hi = std::max(hi, C[i]);
      for (int d = 0; d < D; ++d) c[d] += mi * P.pos[i][d];
    }
    double sums[4] = {m, c[0], c[1], c[2]};  // (over the parts of the domain)
    S.comm->sum(sums, 4);
    m = sums[0];
    for (int d = 0; d < D; ++d) c[d] = sums[1 + d];
    lo = S.comm->min(lo);
    hi = S.comm->max(hi);
    auto it = S.counters.find("source_mass." + g.field);
    const double src = it == S.counters.end() ? 0.0 : it->second;
    std::vector<double> out = {m, lo, hi};
    for (int d = 0; d < D; ++d) out.push_back(m != 0.0 ? c[d] / m : nan);
    out.push_back(src);
    return out;
  }
  double diffusivity = 0.0;
  if (S.transport)
    for (const auto& sc : S.transport->config().scalars)
      if (sc.name == g.field) diffusivity = sc.diffusivity;
  // scalar_flux: flux ∫ (C u − D ∇C)·n ds through the line's wet part [kg/s per m in 2D], n the
  // line's normal (for a line going up, +x); D the scalar's molecular diffusivity (the turbulent
  // part is not included), ∇C the first-order consistent kernel gradient
  return {wet_line_flux(S, g, [&](const Vec<D>& x, const Vec<D>& nrm) {
    double un = 0.0;
    for (int d = 0; d < D; ++d) {
      auto v = interpolate_shepard(S, x, [&](std::uint32_t b) { return C[b] * P.vel[b][d]; });
      un += (v ? *v : 0.0) * nrm[d];
    }
    if constexpr (D == 2)
      if (diffusivity > 0.0)
        if (auto gr = interpolate_gradient(S, x, [&](std::uint32_t b) { return C[b]; }))
          un -= diffusivity * dot(*gr, nrm);
    return un;
  })};
}

template <int D>
std::vector<double> GaugeSet<D>::evaluate(const GaugeConfig& g, const System<D>& S, double level_top) {
  const auto& P = S.particles;
  constexpr int vz = D - 1;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  auto at = [&](const std::vector<double>& v) {
    Vec<D> x{};
    for (int d = 0; d < D; ++d) x[d] = v[d];
    return x;
  };
  if (g.type == "velocity")
    return at_held_points(S, {at(g.point)}, D, [&](const Vec<D>& x, double* out) {
      for (int d = 0; d < D; ++d) {
        const auto u = interpolate_shepard(S, x, [&](std::uint32_t b) { return P.vel[b][d]; });
        out[d] = u ? *u : nan;
      }
    });
  if (g.type == "runup") {  // the waterline on a slope (2D), io/runup.cpp
    const auto w = runup_waterline(g, S);
    return {w[0], w[1], nan};  // max: filled by sample()
  }
  if (g.type == "paddle") {  // the motion's law at t, and the fluid's pressure force on its walls
    std::vector<double> out(3 + D, nan);
    if (!S.motion) return out;
    const std::size_t k = S.motion->index(g.field);
    const auto& law = S.motion->law(k);
    out[0] = law.displacement(S.time);
    out[1] = law.velocity(S.time);
    out[2] = law.acceleration(S.time);
    const Vec<D> f = S.motion->pressure_force(S, k);
    for (int d = 0; d < D; ++d) out[3 + static_cast<std::size_t>(d)] = f[d];
    return out;
  }
  if (g.type == "pressure") {
    // each point is read by the part of the domain that holds it (its neighbours are there,
    // owned or halo), the others add nothing; one sum over the parts
    auto p_at = [&](const Vec<D>& x) {
      if (!S.owns(x)) return nan;
      auto v = interpolate_mls(S, x, [&](std::uint32_t b) { return P.p[b]; });
      return v ? *v : nan;
    };
    if (!(g.diameter > 0.0)) {
      const double v = p_at(at(g.point));
      double sw[2] = {std::isfinite(v) ? v : 0.0, std::isfinite(v) ? 1.0 : 0.0};
      S.comm->sum(sw, 2);
      return {sw[1] > 0.0 ? sw[0] / sw[1] : nan};
    }
    // the sensor face: points spread over it, each weighted by the part of the face it stands
    // for (2D: 5 points over the segment; 3D: the centre and 6 points at 0.7 R, equal areas)
    Vec<D> n = at(g.normal);
    n *= 1.0 / std::sqrt(dot(n, n));
    const Vec<D> c = at(g.point);
    const double R = 0.5 * g.diameter;
    double sum = 0.0, wsum = 0.0;
    auto add = [&](const Vec<D>& x, double w) {
      const double v = p_at(x);
      if (std::isfinite(v)) { sum += w * v; wsum += w; }
    };
    if constexpr (D == 2) {
      const Vec<2> t{{-n[1], n[0]}};
      for (int k = -2; k <= 2; ++k) add(c + (0.5 * R * k) * t, k == -2 || k == 2 ? 0.5 : 1.0);  // trapezoid rule
    } else {
      Vec<3> t1 = std::abs(n[0]) < 0.9 ? Vec<3>{{1, 0, 0}} : Vec<3>{{0, 1, 0}};
      t1 -= dot(t1, n) * n;
      t1 *= 1.0 / std::sqrt(dot(t1, t1));
      const Vec<3> t2{{n[1] * t1[2] - n[2] * t1[1], n[2] * t1[0] - n[0] * t1[2], n[0] * t1[1] - n[1] * t1[0]}};
      add(c, 1.0);
      for (int k = 0; k < 6; ++k) {
        const double a = k * std::acos(-1.0) / 3.0;
        add(c + (0.7 * R * std::cos(a)) * t1 + (0.7 * R * std::sin(a)) * t2, 1.0);
      }
    }
    double sw[2] = {sum, wsum};
    S.comm->sum(sw, 2);
    return {sw[1] > 0.0 ? sw[0] / sw[1] : nan};
  }
  if (g.type == "velocity_profile")
    return at_held_points(S, line_points<D>(g), D, [&](const Vec<D>& x, double* out) {
      for (int d = 0; d < D; ++d) {
        auto v = interpolate_shepard(S, x, [&](std::uint32_t b) { return P.vel[b][d]; });
        out[d] = v ? *v : nan;
      }
    });
  if (g.type == "stress_profile") return evaluate_stress(g, S);
  if (g.type == "scalar" || g.type == "scalar_profile" || g.type == "scalar_mass" || g.type == "scalar_flux" ||
      g.type == "phase")
    return evaluate_scalar(g, S);
  if (g.type == "boundary_volume") {  // cumulative volumes (mass / rho0) through the open boundaries
    auto c = [&](const char* k) { auto it = S.counters.find(k); return it == S.counters.end() ? 0.0 : it->second / S.eos.rho0; };
    return {c("inflow_mass"), c("outflow_mass"), c("backflow_mass")};
  }
  if (g.type == "depth_profile") {
    // depth above the gauge line at each point: the water level of the vertical through it
    // minus the line's own z (put the line on the bed)
    std::vector<double> out;
    GaugeConfig wl;
    wl.type = "water_level";
    for (int i = 0; i < g.points; ++i) {
      const double s = static_cast<double>(i) / (g.points - 1);
      wl.point.assign(D, 0.0);
      for (int d = 0; d < D; ++d) wl.point[d] = g.start[d] + s * (g.end[d] - g.start[d]);
      out.push_back(evaluate(wl, S, level_top)[0] - wl.point[vz]);
    }
    return out;
  }
  if (g.type == "flux") {
    // volume flux through the line (per unit width, m2/s): u·n integrated over the wet part
    // (fluid fraction >= 0.5), n the line's normal (for a line going up, n = +x); in porous
    // media the superficial velocity φu (the intrinsic velocity carries water through the pores
    // only)
    const double* phi = porosity_field(S);
    return {wet_line_flux(S, g, [&](const Vec<D>& x, const Vec<D>& nrm) {
      double un = 0.0;
      for (int d = 0; d < D; ++d) {
        auto v = interpolate_shepard(S, x, [&](std::uint32_t b) { return P.vel[b][d] * (phi ? phi[b] : 1.0); });
        un += (v ? *v : 0.0) * nrm[d];
      }
      return un;
    })};
  }
  if (g.type == "water_level") {
    // scan down the vertical line in steps of dx/4 from the top of the particles (in blocks of
    // points: each is read by the part of the domain that holds it)
    Vec<D> x = at(g.point);
    const double step = 0.25 * S.dx;
    double zlo = level_top;
    for (std::size_t i = 0; i < P.n_owned(); ++i) zlo = std::min(zlo, P.pos[i][vz]);
    zlo = S.comm->min(zlo);
    double prev_f = 0.0, prev_z = level_top;
    constexpr int kBlock = 32;
    std::vector<Vec<D>> pts;
    for (double z = level_top; z >= zlo;) {
      pts.clear();
      for (int k = 0; k < kBlock && z >= zlo; ++k, z -= step) {
        x[vz] = z;
        pts.push_back(x);
      }
      const auto fr = at_held_points(S, pts, 1, [&](const Vec<D>& p, double* out) { out[0] = fluid_fraction(S, p); });
      for (std::size_t k = 0; k < pts.size(); ++k) {
        const double zk = pts[k][vz], f = std::isfinite(fr[k]) ? fr[k] : 0.0;
        if (f >= 0.5) {
          if (zk == level_top) return {zk};
          return {zk + (prev_z - zk) * (f - 0.5) / (f - prev_f)};
        }
        prev_f = f;
        prev_z = zk;
      }
    }
    return {nan};
  }
  if (g.type == "water_volume") {  // Σ m/ρ (the water) and Σ m/(φρ) (the space it fills) of the fluid
    const double* phi = porosity_field(S);
    double v = 0.0, w = 0.0;
    for (std::size_t i = 0; i < P.n_owned(); ++i) {
      if (P.kind[i] != Kind::Fluid) continue;
      bool in = true;
      for (std::size_t d = 0; d < g.start.size(); ++d) in &= P.pos[i][d] >= g.start[d] && P.pos[i][d] < g.end[d];
      if (!in) continue;
      w += P.mass[i] / P.rho[i];
      v += P.mass[i] / (P.rho[i] * (phi ? phi[i] : 1.0));
    }
    double wv[2] = {w, v};
    S.comm->sum(wv, 2);
    return {wv[0], wv[1]};
  }
  if (g.type == "energy") {
    double ek = 0.0, ep = 0.0;
    for (std::size_t i = 0; i < P.n_owned(); ++i) {
      if (P.kind[i] != Kind::Fluid) continue;
      ek += 0.5 * P.mass[i] * dot(P.vel[i], P.vel[i]);
      ep -= P.mass[i] * dot(S.gravity, P.pos[i]);
    }
    double e[2] = {ek, ep};
    S.comm->sum(e, 2);
    return {e[0], e[1], e[0] + e[1]};
  }
  if (g.type == "front") {
    double best = -std::numeric_limits<double>::max();
    const double r = 2.0 * S.dx;
    for (std::size_t i = 0; i < P.n_owned(); ++i) {
      if (P.kind[i] != Kind::Fluid) continue;
      const double s = g.direction * P.pos[i][g.axis];
      if (s <= best) continue;
      int nb = 0;
      S.cells.for_neighbours(P.pos, P.pos[i], r, [&](std::uint32_t b, const Vec<D>&, double r2) {
        nb += (P.kind[b] == Kind::Fluid && r2 > 0.0);
      });
      if (nb >= 3) best = s;
    }
    best = S.comm->max(best);
    return {best == -std::numeric_limits<double>::max() ? nan : g.direction * best};
  }
  return {nan};
}

template <int D>
void GaugeSet<D>::sample(const System<D>& S) {
  double top = level_top_;
  for (std::size_t i = 0; i < S.particles.n_owned(); ++i) top = std::max(top, S.particles.pos[i][D - 1] + S.support);
  top = S.comm->max(top);
  for (std::size_t k = 0; k < cfg_.size(); ++k) {
    auto v = evaluate(cfg_[k], S, top);  // (every rank: the reductions; one writes)
    if (!writer_) continue;
    auto& f = *files_[k];
    f << fmt::format("{:.9g}", S.time);
    if (cfg_[k].type == "pressure" && cfg_[k].window > 0.0) {
      // the window's mean and standard deviation (the samples of tick(), this one included)
      auto& w = window_[k];
      if (w.empty() || w.back().first < S.time) w.emplace_back(S.time, v[0]);
      double m = 0.0, m2 = 0.0;
      long cnt = 0;
      for (const auto& [t, x] : w)
        if (std::isfinite(x)) { m += x; m2 += x * x; ++cnt; }
      m = cnt ? m / cnt : std::numeric_limits<double>::quiet_NaN();
      const double var = cnt > 1 ? std::max(0.0, m2 / cnt - m * m) : 0.0;
      v = {m, std::sqrt(var), double(cnt)};
    }
    if (cfg_[k].type == "runup") {
      if (std::isfinite(v[0])) runmax_[k] = std::max(runmax_[k], v[0]);
      v[2] = std::isfinite(runmax_[k]) ? runmax_[k] : std::numeric_limits<double>::quiet_NaN();
    }
    // budgets (scalar and water masses) are checked to round-off: full precision for them
    const bool exact = cfg_[k].type == "scalar_mass" || cfg_[k].type == "water_volume" || cfg_[k].type == "phase";
    for (double x : v) f << (exact ? fmt::format(",{:.17g}", x) : fmt::format(",{:.9g}", x));
    f << "\n";
    f.flush();
    if (!f) throw IoError(fmt::format("writing gauge '{}' failed (disk full?)", cfg_[k].name));
    if (S.time >= cfg_[k].average_from * (1.0 - 1e-12)) accumulate(k, S.time, v);
  }
}

template <int D>
void GaugeSet<D>::tick(const System<D>& S) {
  for (std::size_t k = 0; k < cfg_.size(); ++k) {
    const auto& g = cfg_[k];
    if (g.type != "pressure" || !(g.window > 0.0)) continue;
    auto& w = window_[k];
    w.emplace_back(S.time, evaluate(g, S, level_top_)[0]);
    while (!w.empty() && w.front().first <= S.time - g.window * (1.0 + 1e-12)) w.pop_front();
  }
}

template <int D>
void GaugeSet<D>::accumulate(std::size_t k, double t, const std::vector<double>& v) {
  // running time mean of a profile gauge over its samples at t >= average_from (NaN samples,
  // e.g. a dry point, are left out of that column's mean), rewritten as NAME.mean.csv
  auto& m = means_[k];
  if (m.n == 0) {
    m.t0 = t;
    m.sum.assign(v.size(), 0.0);
    m.count.assign(v.size(), 0);
  }
  ++m.n;
  m.t1 = t;
  for (std::size_t i = 0; i < v.size(); ++i)
    if (std::isfinite(v[i])) { m.sum[i] += v[i]; ++m.count[i]; }
  std::string text = "t_from,t_to,samples";
  std::ifstream hdr(dir_ + "/gauges/" + cfg_[k].name + ".csv");
  std::string header;
  std::getline(hdr, header);
  text += header.substr(header.find(',') == std::string::npos ? header.size() : header.find(','));
  text += fmt::format("\n{:.9g},{:.9g},{}", m.t0, m.t1, m.n);
  for (std::size_t i = 0; i < v.size(); ++i)
    text += m.count[i] ? fmt::format(",{:.9g}", m.sum[i] / m.count[i]) : std::string(",nan");
  write_file_atomically(dir_ + "/gauges/" + cfg_[k].name + ".mean.csv", text + "\n");
}

template class GaugeSet<2>;
template class GaugeSet<3>;

}  // namespace sph
