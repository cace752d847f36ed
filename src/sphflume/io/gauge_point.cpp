// Point gauges (io/gauge_type.hpp): pressure (at a point, or over a sensor face of a diameter,
// optionally averaged over a time window), velocity and a transported scalar at a point.
#include <cmath>
#include <limits>

#include "sphflume/io/gauge_sampling.hpp"
#include "sphflume/io/gauge_types.hpp"

namespace sph {
using namespace gauge_detail;
namespace {

/// The point of a point gauge.
void read_point(Reader& r, GaugeConfig& g, const Node& n, std::size_t d) {
  g.point = r.vec("point", d);
  if (g.point.empty()) r.misspelt("point");
  if (g.point.empty()) r.fail_at(n, r.key_path("point"), "the point where pressure is measured");
}

/// pressure: linear-MLS kernel interpolation from the fluid particles at the point, or the mean
/// over a sensor face (diameter, normal); with a window the row is the window's mean, standard
/// deviation and sample count.
template <int D>
class PressureGauge final : public GaugeType<D> {
 public:
  void read(Reader& r, GaugeConfig& g, const Node& n, const std::string&) const override {
    const std::size_t d = static_cast<std::size_t>(D);
    read_point(r, g, n, d);
    g.diameter = r.scalar<double>("diameter", 0.0);
    if (!(g.diameter >= 0.0)) r.fail_at(r.get("diameter"), r.key_path("diameter"), "a sensor diameter >= 0 in m (0 = a point)");
    g.window = r.scalar<double>("window", 0.0);
    if (!(g.window >= 0.0)) r.fail_at(r.get("window"), r.key_path("window"), "a sampling window >= 0 in s (0 = the value at the output time)");
    g.normal = r.vec("normal", d);
    if (g.diameter > 0.0) {
      double len = 0.0;
      for (double v : g.normal) len += v * v;
      if (g.normal.empty() || !(len > 0.0))
        r.fail_at(g.normal.empty() ? n : r.get("normal"), r.key_path("normal"),
                  "the sensor face's normal (a non-zero vector, e.g. [-1, 0] on a right-hand wall) with 'diameter'");
    }
  }
  std::string columns(const GaugeConfig& g) const override { return g.window > 0.0 ? ",pressure,pressure_std,samples" : ",pressure"; }
  bool windowed(const GaugeConfig& g) const override { return g.window > 0.0; }
  std::vector<double> evaluate(const GaugeConfig& g, const System<D>& S, double) const override {
    const auto& P = S.particles;
    const double nan = kNan;
    // each point is read by the part of the domain that holds it (its neighbours are there,
    // owned or halo), the others add nothing; one sum over the parts
    auto p_at = [&](const Vec<D>& x) {
      if (!S.owns(x)) return nan;
      auto v = interpolate_mls(S, x, [&](std::uint32_t b) { return P.p[b]; });
      return v ? *v : nan;
    };
    if (!(g.diameter > 0.0)) {
      const double v = p_at(point_of<D>(g.point));
      double sw[2] = {std::isfinite(v) ? v : 0.0, std::isfinite(v) ? 1.0 : 0.0};
      S.comm->sum(sw, 2);
      return {sw[1] > 0.0 ? sw[0] / sw[1] : nan};
    }
    // the sensor face: points spread over it, each weighted by the part of the face it stands
    // for (2D: 5 points over the segment; 3D: the centre and 6 points at 0.7 R, equal areas)
    Vec<D> n = point_of<D>(g.normal);
    n *= 1.0 / std::sqrt(dot(n, n));
    const Vec<D> c = point_of<D>(g.point);
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
};

/// velocity: ux, (uy,) uz at a point (Shepard average of the fluid).
template <int D>
class VelocityGauge final : public GaugeType<D> {
 public:
  void read(Reader& r, GaugeConfig& g, const Node& n, const std::string&) const override { read_point(r, g, n, D); }
  std::string columns(const GaugeConfig&) const override { return D == 2 ? ",ux,uz" : ",ux,uy,uz"; }
  std::vector<double> evaluate(const GaugeConfig& g, const System<D>& S, double) const override {
    const auto& P = S.particles;
    const double nan = kNan;
    return at_held_points(S, {point_of<D>(g.point)}, D, [&](const Vec<D>& x, double* out) {
      for (int d = 0; d < D; ++d) {
        const auto u = interpolate_shepard(S, x, [&](std::uint32_t b) { return P.vel[b][d]; });
        out[d] = u ? *u : nan;
      }
    });
  }
};

/// scalar: the transported scalar `field` at a point (Shepard average).
template <int D>
class ScalarGauge final : public GaugeType<D> {
 public:
  void read(Reader& r, GaugeConfig& g, const Node& n, const std::string&) const override {
    read_scalar_field(r, g);
    read_point(r, g, n, D);
  }
  std::string columns(const GaugeConfig& g) const override { return "," + g.field; }
  std::vector<double> evaluate(const GaugeConfig& g, const System<D>& S, double) const override {
    const auto* C = S.particles.find_scalar(g.field);
    if (!C) return {kNan};
    return at_held_points(S, {point_of<D>(g.point)}, 1, scalar_at<D>(S, *C));
  }
};

}  // namespace

template <int D>
void add_point_gauges(Registry<GaugeType<D>>& reg) {
  add_gauge<PressureGauge>(reg, "pressure");
  add_gauge<VelocityGauge>(reg, "velocity");
  add_gauge<ScalarGauge>(reg, "scalar");
}
SPHFLUME_GAUGE_FAMILY(add_point_gauges)

}  // namespace sph
