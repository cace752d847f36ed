// Level gauges (io/gauge_type.hpp): the water level on a vertical line, the depth above the points
// of a line on the bed, and the run-up on a slope (io/runup.hpp).
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "sphflume/io/gauge_sampling.hpp"
#include "sphflume/io/gauge_types.hpp"
#include "sphflume/io/runup.hpp"

namespace sph {
using namespace gauge_detail;
namespace {

/// water_level: the level on the vertical line through `point` (or x).
template <int D>
class WaterLevelGauge final : public GaugeType<D> {
 public:
  void read(Reader& r, GaugeConfig& g, const Node&, const std::string&) const override {
    g.point = r.vec("point", D);
    if (g.point.empty()) {
      g.x = r.required<double>("x", "the x of the vertical line");
      g.point.assign(D, 0.0);
      g.point[0] = g.x;
    }
  }
  std::string columns(const GaugeConfig&) const override { return ",level"; }
  std::vector<double> evaluate(const GaugeConfig& g, const System<D>& S, double level_top) const override {
    return {water_level_at<D>(point_of<D>(g.point), S, level_top)};
  }
};

/// depth_profile: the water level above each point of the line minus the point's own z (put the
/// line on the bed).
template <int D>
class DepthProfileGauge final : public GaugeType<D> {
 public:
  void read(Reader& r, GaugeConfig& g, const Node& n, const std::string& path) const override { read_line(r, g, n, path, D); }
  bool line() const override { return true; }
  std::string columns(const GaugeConfig& g) const override {
    std::string s;
    for (int i = 0; i < g.points; ++i) s += fmt::format(",depth_{}", i);
    return s;
  }
  std::vector<double> evaluate(const GaugeConfig& g, const System<D>& S, double level_top) const override {
    std::vector<double> out;
    std::vector<double> point(D, 0.0);
    for (int i = 0; i < g.points; ++i) {
      const double s = static_cast<double>(i) / (g.points - 1);
      for (int d = 0; d < D; ++d) point[d] = g.start[d] + s * (g.end[d] - g.start[d]);
      out.push_back(water_level_at<D>(point_of<D>(point), S, level_top) - point[D - 1]);
    }
    return out;
  }
};

/// runup: the waterline on the slope line start-end (io/runup.hpp) minus `level`, the x of that
/// particle, and the largest run-up so far.
template <int D>
class RunupGauge final : public GaugeType<D> {
 public:
  void read(Reader& r, GaugeConfig& g, const Node& n, const std::string& path) const override {
    const std::size_t d = D;
    if (D != 2) r.fail_at(n, path, "a 2D case (run-up gauges are 2D in this version)");
    g.start = r.vec("start", d);
    g.end = r.vec("end", d);
    for (const char* k : {"start", "end"})
      if (!r.has(k)) r.misspelt(k);
    if (g.start.empty() || g.end.empty()) r.fail_at(n, path, "'start' and 'end': the toe and the top of the slope's surface line");
    if (!(g.end[d - 1] > g.start[d - 1])) r.fail_at(r.get("end"), r.key_path("end"), "an end above the start (the line runs up the slope)");
    g.level = r.required<double>("level", "the still-water level z [m] the run-up is measured from");
    g.reach = r.scalar<double>("reach", 0.0);
    if (!(g.reach >= 0.0)) r.fail_at(r.get("reach"), r.key_path("reach"), "a distance >= 0 in m (0 = 1.5 dx)");
    g.film = r.scalar<double>("film", g.film);
    if (!(g.film >= 0.0)) r.fail_at(r.get("film"), r.key_path("film"), "a thickness >= 0 in m, normal to the slope (default 0.001)");
    g.neighbours = r.scalar<int>("neighbours", g.neighbours);
    if (g.neighbours < 0 || g.neighbours > 50) r.fail_at(r.get("neighbours"), r.key_path("neighbours"), "an integer in [0, 50]");
  }
  std::string columns(const GaugeConfig&) const override { return ",runup,x,max"; }
  bool keeps_max() const override { return true; }
  std::vector<double> evaluate(const GaugeConfig& g, const System<D>& S, double) const override {
    const auto w = runup_waterline(g, S);
    return {w[0], w[1], kNan};  // max: filled by GaugeSet::sample()
  }
};

}  // namespace

template <int D>
void add_level_gauges(Registry<GaugeType<D>>& reg) {
  add_gauge<WaterLevelGauge>(reg, "water_level");
  add_gauge<DepthProfileGauge>(reg, "depth_profile");
  add_gauge<RunupGauge>(reg, "runup");
}
SPHFLUME_GAUGE_FAMILY(add_level_gauges)

}  // namespace sph
