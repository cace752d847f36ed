// Gauges of the whole fluid (io/gauge_type.hpp): energies, the surge front, water and scalar
// budgets, the open boundaries' volumes, a phase's area, and a wall motion's law and force.
#include <algorithm>
#include <cmath>
#include <limits>

#include "sphflume/boundaries/motion.hpp"
#include "sphflume/io/gauge_sampling.hpp"
#include "sphflume/io/gauge_types.hpp"

namespace sph {
using namespace gauge_detail;
namespace {

/// energy: kinetic, potential (−Σ m g·x relative to the origin), total [J (per m in 2D)].
template <int D>
class EnergyGauge final : public GaugeType<D> {
 public:
  void read(Reader&, GaugeConfig&, const Node&, const std::string&) const override {}
  std::string columns(const GaugeConfig&) const override { return ",kinetic,potential,total"; }
  std::vector<double> evaluate(const GaugeConfig&, const System<D>& S, double) const override {
    const auto& P = S.particles;
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
};

/// front: the furthest fluid particle along the axis that has at least 3 fluid neighbours within
/// 2 dx (isolated droplets ignored).
template <int D>
class FrontGauge final : public GaugeType<D> {
 public:
  void read(Reader& r, GaugeConfig& g, const Node&, const std::string&) const override {
    const std::string ax = r.scalar<std::string>("axis", "x");
    g.axis = ax == "x" ? 0 : (ax == "y" && D == 3) ? 1 : ax == "z" ? D - 1 : -1;
    if (g.axis < 0) r.fail_at(r.get("axis"), r.key_path("axis"), D == 2 ? "x or z" : "x, y or z");
    g.direction = r.scalar<double>("direction", 1.0) >= 0 ? 1.0 : -1.0;
  }
  std::string columns(const GaugeConfig&) const override { return ",front"; }
  std::vector<double> evaluate(const GaugeConfig& g, const System<D>& S, double) const override {
    const auto& P = S.particles;
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
    return {best == -std::numeric_limits<double>::max() ? kNan : g.direction * best};
  }
};

/// water_volume: Σ m/ρ (the water) and Σ m/(φρ) (the space it fills) of the fluid in the box.
template <int D>
class WaterVolumeGauge final : public GaugeType<D> {
 public:
  void read(Reader& r, GaugeConfig& g, const Node& n, const std::string& path) const override { read_box(r, g, n, path, D); }
  std::string columns(const GaugeConfig&) const override { return ",water,bulk"; }
  bool exact() const override { return true; }
  std::vector<double> evaluate(const GaugeConfig& g, const System<D>& S, double) const override {
    const auto& P = S.particles;
    const double* phi = porosity_field(S);
    double v = 0.0, w = 0.0;
    for (std::size_t i = 0; i < P.n_owned(); ++i) {
      if (P.kind[i] != Kind::Fluid || !in_box<D>(g, P.pos[i])) continue;
      w += P.mass[i] / P.rho[i];
      v += P.mass[i] / (P.rho[i] * (phi ? phi[i] : 1.0));
    }
    double wv[2] = {w, v};
    S.comm->sum(wv, 2);
    return {wv[0], wv[1]};
  }
};

/// overtopping: the volume of water beyond the crest line x = x_c on the side `direction` points to
/// (+1: x > x_c), Σ m/ρ0 over the fluid there plus what left the domain through its face on that
/// side (x+ or x−: a catch tank), per metre of crest (2D: as is; 3D: over `width`). Water reaches
/// the lee side only over the crest, so the overtopped volume is the rise of this column since
/// t = 0 and the mean discharge q its slope (python: sphflume.waves.overtopping).
template <int D>
class OvertoppingGauge final : public GaugeType<D> {
 public:
  void read(Reader& r, GaugeConfig& g, const Node& n, const std::string& path) const override {
    g.x = r.required<double>("x", "the x of the crest line [m]");
    g.direction = r.scalar<double>("direction", 1.0);
    if (g.direction != 1.0 && g.direction != -1.0) r.fail_at(r.get("direction"), r.key_path("direction"), "+1 (the lee side is x > x_c) or -1");
    if (D == 3) {
      if (!r.has("width")) r.fail_at(n, r.key_path("width"), "the crest's width along y [m] in 3D (the volume is per metre of crest)");
      g.level = r.positive("width", 0.0, true);
    } else if (r.has("width")) {
      r.fail_at(r.get("width"), r.key_path("width"), "no width in 2D (the volume is per metre already)");
    }
    (void)path;
  }
  std::string columns(const GaugeConfig&) const override { return ",volume"; }
  bool exact() const override { return true; }
  std::vector<double> evaluate(const GaugeConfig& g, const System<D>& S, double) const override {
    const auto& P = S.particles;
    double v = 0.0;
    for (std::size_t i = 0; i < P.n_owned(); ++i)
      if (P.kind[i] == Kind::Fluid && g.direction * (P.pos[i][0] - g.x) > 0.0) v += P.mass[i];
    const auto gone = S.counters.find(g.direction > 0.0 ? "removed_mass.x+" : "removed_mass.x-");  // (over the ranks)
    v = (S.comm->sum(v) + (gone == S.counters.end() ? 0.0 : gone->second)) / S.eos.rho0;
    return {D == 3 ? v / g.level : v};
  }
};

/// boundary_volume: cumulative volumes (mass / rho0) converted at the open boundaries.
template <int D>
class BoundaryVolumeGauge final : public GaugeType<D> {
 public:
  void read(Reader&, GaugeConfig&, const Node&, const std::string&) const override {}
  std::string columns(const GaugeConfig&) const override { return ",inflow,outflow,backflow"; }
  std::vector<double> evaluate(const GaugeConfig&, const System<D>& S, double) const override {
    auto c = [&](const char* k) { auto it = S.counters.find(k); return it == S.counters.end() ? 0.0 : it->second / S.eos.rho0; };
    return {c("inflow_mass"), c("outflow_mass"), c("backflow_mass")};
  }
};

/// scalar_mass: Σ m C/ρ of the scalar in the fluid (in the box when given), min and max of C, the
/// mass centroid, and the cumulative mass its wall sources released.
template <int D>
class ScalarMassGauge final : public GaugeType<D> {
 public:
  void read(Reader& r, GaugeConfig& g, const Node& n, const std::string& path) const override {
    read_scalar_field(r, g);
    read_box(r, g, n, path, D);
  }
  std::string columns(const GaugeConfig&) const override { return D == 2 ? ",mass,min,max,x,z,source" : ",mass,min,max,x,y,z,source"; }
  bool exact() const override { return true; }
  std::vector<double> evaluate(const GaugeConfig& g, const System<D>& S, double) const override {
    const auto& P = S.particles;
    const auto* Cp = P.find_scalar(g.field);
    if (!Cp) return {kNan};
    const auto& C = *Cp;
    double m = 0.0, lo = std::numeric_limits<double>::infinity(), hi = -lo;
    double c[3] = {0.0, 0.0, 0.0};
    for (std::size_t i = 0; i < P.n_owned(); ++i) {
      if (P.kind[i] != Kind::Fluid || !in_box<D>(g, P.pos[i])) continue;
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
    for (int d = 0; d < D; ++d) out.push_back(m != 0.0 ? c[d] / m : kNan);
    out.push_back(src);
    return out;
  }
};

/// phase: the area (volume in 3D) Σ m/ρ of the phase `field`, its top (highest particle) and
/// area centroid x, z.
template <int D>
class PhaseGauge final : public GaugeType<D> {
 public:
  void read(Reader& r, GaugeConfig& g, const Node&, const std::string&) const override {
    g.field = r.required<std::string>("field", "the name of a phase (multiphase.phases)");
  }
  std::string columns(const GaugeConfig&) const override { return ",area,top,x,z"; }
  bool exact() const override { return true; }
  std::vector<double> evaluate(const GaugeConfig& g, const System<D>& S, double) const override {
    const auto& P = S.particles;
    const auto* ph = P.find(field::phase);
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
    if (!(area > 0.0)) return {0.0, kNan, kNan, kNan};
    return {area, top, cx / area, cz / area};
  }
};

/// paddle: displacement, velocity, acceleration of a motion's law at t, and the water's pressure
/// force on its walls.
template <int D>
class PaddleGauge final : public GaugeType<D> {
 public:
  void read(Reader& r, GaugeConfig& g, const Node&, const std::string&) const override {
    g.field = r.required<std::string>("motion", "the name of a wall motion (motions)");
  }
  std::string columns(const GaugeConfig&) const override {
    return D == 2 ? ",displacement,velocity,acceleration,force_x,force_z" : ",displacement,velocity,acceleration,force_x,force_y,force_z";
  }
  std::vector<double> evaluate(const GaugeConfig& g, const System<D>& S, double) const override {
    std::vector<double> out(3 + D, kNan);
    if (!S.motion) return out;
    const std::size_t k = S.motion->index(g.field);
    const auto& law = S.motion->law(k);
    out[0] = S.motion->displacement(k, S.time);  // with active absorption's correction
    out[1] = S.motion->velocity(k, S.time);
    out[2] = law.acceleration(S.time);
    const Vec<D> f = S.motion->pressure_force(S, k);
    for (int d = 0; d < D; ++d) out[3 + static_cast<std::size_t>(d)] = f[d];
    return out;
  }
};

}  // namespace

template <int D>
void add_total_gauges(Registry<GaugeType<D>>& reg) {
  add_gauge<EnergyGauge>(reg, "energy");
  add_gauge<FrontGauge>(reg, "front");
  add_gauge<WaterVolumeGauge>(reg, "water_volume");
  add_gauge<BoundaryVolumeGauge>(reg, "boundary_volume");
  add_gauge<ScalarMassGauge>(reg, "scalar_mass");
  add_gauge<PhaseGauge>(reg, "phase");
  add_gauge<PaddleGauge>(reg, "paddle");
  add_gauge<OvertoppingGauge>(reg, "overtopping");
}
SPHFLUME_GAUGE_FAMILY(add_total_gauges)

}  // namespace sph
