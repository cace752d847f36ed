// Line gauges (io/gauge_type.hpp): profiles of velocity, turbulent stress and a scalar at points
// along a line (their coordinates in NAME.points.csv), the volume and scalar fluxes through a
// line's wet part, and the pressure force on a stretch of wall face.
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "sphflume/io/gauge_sampling.hpp"
#include "sphflume/io/gauge_types.hpp"
#include "sphflume/physics/transport.hpp"

namespace sph {
using namespace gauge_detail;
namespace {

/// One column name per point and component: prefix(i).
template <class F>
std::string per_point(const GaugeConfig& g, F&& name) {
  std::string s;
  for (int i = 0; i < g.points; ++i) s += name(i);
  return s;
}

/// velocity_profile: ux_i, (uy_i,) uz_i at the points i along the line (Shepard average).
template <int D>
class VelocityProfileGauge final : public GaugeType<D> {
 public:
  void read(Reader& r, GaugeConfig& g, const Node& n, const std::string& path) const override { read_line(r, g, n, path, D); }
  bool line() const override { return true; }
  std::string columns(const GaugeConfig& g) const override {
    const char* ax = D == 2 ? "xz" : "xyz";
    return per_point(g, [&](int i) {
      std::string s;
      for (int d = 0; d < D; ++d) s += fmt::format(",u{}_{}", ax[d], i);
      return s;
    });
  }
  std::vector<double> evaluate(const GaugeConfig& g, const System<D>& S, double) const override {
    const auto& P = S.particles;
    const double nan = kNan;
    return at_held_points(S, line_points<D>(g), D, [&](const Vec<D>& x, double* out) {
      for (int d = 0; d < D; ++d) {
        auto v = interpolate_shepard(S, x, [&](std::uint32_t b) { return P.vel[b][d]; });
        out[d] = v ? *v : nan;
      }
    });
  }
};

/// stress_profile: per point ū, the modelled turbulent shear stress τ_t/ρ (the xz component of the
/// eddy-viscosity stress, 0 without turbulence), the resolved stress τ_r/ρ = −⟨(u − ū)(w − w̄)⟩
/// (Kazemi eqs 3.22–3.23: the kernel-weighted covariance of the particle velocities about their
/// kernel average; positive in the sense of τ_t) and ν_t.
template <int D>
class StressProfileGauge final : public GaugeType<D> {
 public:
  void read(Reader& r, GaugeConfig& g, const Node& n, const std::string& path) const override { read_line(r, g, n, path, D); }
  bool line() const override { return true; }
  std::string columns(const GaugeConfig& g) const override {
    return per_point(g, [](int i) { return fmt::format(",ux_{0},tau_t_{0},tau_r_{0},nu_t_{0}", i); });
  }
  std::vector<double> evaluate(const GaugeConfig& g, const System<D>& S, double) const override {
    const auto& P = S.particles;
    const double nan = kNan;
    const char* xz = "tau_xz";
    const std::vector<double>* tau = P.has_scalar(xz) ? &P.scalar_fields().at(xz) : nullptr;
    const std::vector<double>* nut = P.has(field::nu_t) ? &P.require(field::nu_t) : nullptr;
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
};

/// scalar_profile: the transported scalar `field` at the points along the line.
template <int D>
class ScalarProfileGauge final : public GaugeType<D> {
 public:
  void read(Reader& r, GaugeConfig& g, const Node& n, const std::string& path) const override {
    read_scalar_field(r, g);
    read_line(r, g, n, path, D);
  }
  bool line() const override { return true; }
  std::string columns(const GaugeConfig& g) const override {
    return per_point(g, [&](int i) { return fmt::format(",{}_{}", g.field, i); });
  }
  std::vector<double> evaluate(const GaugeConfig& g, const System<D>& S, double) const override {
    const auto* C = S.particles.find_scalar(g.field);
    if (!C) return {kNan};
    return at_held_points(S, line_points<D>(g), 1, scalar_at<D>(S, *C));
  }
};

/// flux: the volume flux through the line (per unit width, m2/s; in 3D with a span, through the
/// section, m3/s), u·n integrated over the wet
/// part (fluid fraction >= 0.5), n the line's normal (for a line going up, n = +x); in porous
/// media the superficial velocity φu (the intrinsic velocity carries water through the pores only).
template <int D>
class FluxGauge final : public GaugeType<D> {
 public:
  void read(Reader& r, GaugeConfig& g, const Node& n, const std::string& path) const override {
    read_flux_section(r, g, n, path, D);
  }
  std::string columns(const GaugeConfig&) const override { return ",flux"; }
  std::vector<double> evaluate(const GaugeConfig& g, const System<D>& S, double) const override {
    const auto& P = S.particles;
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
};

/// scalar_flux: ∫ (C u − D ∇C)·n ds through the line's wet part [kg/s per m; in 3D with a span, kg/s
/// through the section], n the line's
/// normal (for a line going up, +x); D the scalar's molecular diffusivity (the turbulent part is
/// not included), ∇C the first-order consistent kernel gradient.
template <int D>
class ScalarFluxGauge final : public GaugeType<D> {
 public:
  void read(Reader& r, GaugeConfig& g, const Node& n, const std::string& path) const override {
    read_scalar_field(r, g);
    read_flux_section(r, g, n, path, D);
  }
  std::string columns(const GaugeConfig&) const override { return ",flux"; }
  std::vector<double> evaluate(const GaugeConfig& g, const System<D>& S, double) const override {
    const auto& P = S.particles;
    const auto* Cp = P.find_scalar(g.field);
    if (!Cp) return {kNan};
    const auto& C = *Cp;
    double diffusivity = 0.0;
    if (S.transport)
      for (const auto& sc : S.transport->config().scalars)
        if (sc.name == g.field) diffusivity = sc.diffusivity;
    return {wet_line_flux(S, g, [&](const Vec<D>& x, const Vec<D>& nrm) {
      double un = 0.0;
      for (int d = 0; d < D; ++d) {
        auto v = interpolate_shepard(S, x, [&](std::uint32_t b) { return C[b] * P.vel[b][d]; });
        un += (v ? *v : 0.0) * nrm[d];
      }
      if (diffusivity > 0.0)
        if (auto gr = interpolate_gradient(S, x, [&](std::uint32_t b) { return C[b]; }))
          un -= diffusivity * dot(*gr, nrm);
      return un;
    })};
  }
};

/// wall_force: the pressure force on a wall face. 2D: per metre of width [N/m], on the stretch
/// from start to end: the wall particles' pressure integrated over their faces, F = Σ_w p_w s_w,
/// over the face layer (the wall particles whose centres lie behind the line, along its normal n,
/// within their own spacing s_w = √(m_w/ρ0), and whose projections fall within the stretch). For a
/// line going up n = +x: the push of the water on a wall to its right. 3D [N]: on the axis-aligned
/// rectangle with opposite corners start and end (equal in the coordinate of its axis), whose
/// `normal` (± that axis) points into the water: F = Σ_w p_w s_w² over the wall particles behind
/// it within s_w whose projections fall inside it. The dummy walls' pressure is the fluid's
/// extrapolated to each wall particle (boundaries/walls.cpp), as the momentum equation reads it,
/// less the background pressure (a dry wall particle's: 0). Resolution levels: each particle its
/// own s_w.
template <int D>
class WallForceGauge final : public GaugeType<D> {
 public:
  void read(Reader& r, GaugeConfig& g, const Node& n, const std::string& path) const override {
    g.start = r.vec("start", D);
    g.end = r.vec("end", D);
    for (const char* k : {"start", "end"})
      if (!r.has(k)) r.misspelt(k);
    if (g.start.empty() || g.end.empty())
      r.fail_at(n, path, D == 2 ? "'start' and 'end' points of the wall face (for a face going up, the wall lies to +x)"
                                : "'start' and 'end': opposite corners of the wall face, an axis-aligned rectangle");
    double len2 = 0.0;
    for (int d = 0; d < D; ++d) len2 += (g.end[d] - g.start[d]) * (g.end[d] - g.start[d]);
    if (!(len2 > 0.0)) r.fail_at(r.get("end"), r.key_path("end"), "an end point different from 'start'");
    if constexpr (D == 3) {
      if (!r.has("normal")) r.misspelt("normal");
      g.normal = r.vec("normal", D);
      const int ax = axis_of(g.normal);
      if (ax < 0)
        r.fail_at(g.normal.empty() ? n : r.get("normal"), r.key_path("normal"),
                  "the face's normal, pointing into the water, along one axis (e.g. [1, 0, 0] or [0, 0, -1])");
      if (std::abs(g.end[ax] - g.start[ax]) > 1e-9 * (1.0 + std::abs(g.start[ax])))
        r.fail_at(r.get("end"), r.key_path("end"),
                  fmt::format("the face's opposite corner in its plane: the same {} as 'start' ({})", "xyz"[ax], g.start[ax]));
      for (int d = 0; d < D; ++d)
        if (d != ax && !(g.end[d] != g.start[d]))
          r.fail_at(r.get("end"), r.key_path("end"), "the opposite corner of a rectangle with a width along both of its sides");
    }
  }
  std::string columns(const GaugeConfig&) const override { return ",force"; }
  std::vector<double> evaluate(const GaugeConfig& g, const System<D>& S, double) const override {
    const auto& P = S.particles;
    const double rho0 = S.eos.rho0;
    double F = 0.0;
    if constexpr (D == 2) {
      const Vec<D> a = point_of<D>(g.start);
      Vec<D> t = point_of<D>(g.end) - a;
      const double len = std::sqrt(dot(t, t));
      t *= 1.0 / len;
      Vec<D> nrm{};
      nrm[0] = t[D - 1];
      nrm[D - 1] = -t[0];
      for (std::size_t i = 0; i < P.n_owned(); ++i) {
        if (P.kind[i] != Kind::Wall) continue;
        const Vec<D> r = P.pos[i] - a;
        const double along = dot(r, t), depth = dot(r, nrm), s = std::sqrt(P.mass[i] / rho0);
        if (depth > 0.0 && depth < s && along >= 0.0 && along < len) F += (P.p[i] - S.eos.background) * s;
      }
    } else {
      const int ax = axis_of(g.normal);
      const double sign = g.normal[ax] > 0.0 ? 1.0 : -1.0;
      double lo[D], hi[D];
      for (int d = 0; d < D; ++d) { lo[d] = std::min(g.start[d], g.end[d]); hi[d] = std::max(g.start[d], g.end[d]); }
      for (std::size_t i = 0; i < P.n_owned(); ++i) {
        if (P.kind[i] != Kind::Wall) continue;
        const double depth = sign * (g.start[ax] - P.pos[i][ax]), s = std::cbrt(P.mass[i] / rho0);
        bool in = depth > 0.0 && depth < s;
        for (int d = 0; d < D && in; ++d) in = d == ax || (P.pos[i][d] >= lo[d] && P.pos[i][d] < hi[d]);
        if (in) F += (P.p[i] - S.eos.background) * s * s;
      }
    }
    S.comm->sum(&F, 1);
    return {F};
  }

 private:
  /// The axis of a normal along one axis (-1: none, or not a normal).
  static int axis_of(const std::vector<double>& nrm) {
    int ax = -1, nonzero = 0;
    for (std::size_t d = 0; d < nrm.size(); ++d)
      if (nrm[d] != 0.0) { ax = static_cast<int>(d); ++nonzero; }
    return nonzero == 1 && std::isfinite(nrm[static_cast<std::size_t>(ax)]) ? ax : -1;
  }
};

}  // namespace

template <int D>
void add_line_gauges(Registry<GaugeType<D>>& reg) {
  add_gauge<VelocityProfileGauge>(reg, "velocity_profile");
  add_gauge<StressProfileGauge>(reg, "stress_profile");
  add_gauge<ScalarProfileGauge>(reg, "scalar_profile");
  add_gauge<FluxGauge>(reg, "flux");
  add_gauge<ScalarFluxGauge>(reg, "scalar_flux");
  add_gauge<WallForceGauge>(reg, "wall_force");
}
SPHFLUME_GAUGE_FAMILY(add_line_gauges)

}  // namespace sph
