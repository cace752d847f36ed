// The gauge type families (io/gauge_point.cpp, gauge_line.cpp, gauge_level.cpp, gauge_total.cpp):
// each adds its types to the registry; the key readers they share. Internal to io/.
#pragma once
#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "sphflume/core/interpolate.hpp"
#include "sphflume/io/gauge_type.hpp"

namespace sph {

/// One registry line: the gauge type T<D> under `name`.
template <template <int> class T, int D>
void add_gauge(Registry<GaugeType<D>>& reg, const char* name) {
  reg.add(name, [] { return std::make_unique<T<D>>(); });
}
#define SPHFLUME_GAUGE_FAMILY(f) \
  template void f<2>(Registry<GaugeType<2>>&); \
  template void f<3>(Registry<GaugeType<3>>&);

template <int D> void add_point_gauges(Registry<GaugeType<D>>& reg);
template <int D> void add_line_gauges(Registry<GaugeType<D>>& reg);
template <int D> void add_level_gauges(Registry<GaugeType<D>>& reg);
template <int D> void add_total_gauges(Registry<GaugeType<D>>& reg);

/// The `field` of a scalar gauge: a transported scalar's name.
inline void read_scalar_field(Reader& r, GaugeConfig& g) {
  g.field = r.required<std::string>("field", "the name of a transported scalar (transport.scalars)");
}

/// A gauge line: start, end, points, average_from.
inline void read_line(Reader& r, GaugeConfig& g, const Node& n, const std::string& path, std::size_t d) {
  g.start = r.vec("start", d);
  g.end = r.vec("end", d);
  for (const char* k : {"start", "end"})
    if (!r.has(k)) r.misspelt(k);
  if (g.start.empty() || g.end.empty()) r.fail_at(n, path, "'start' and 'end' points of the line");
  g.points = r.scalar<int>("points", 20);
  if (g.points < 2 || g.points > 10000) r.fail_at(r.get("points"), r.key_path("points"), "an integer in [2, 10000]");
  g.average_from = r.scalar<double>("average_from", g.average_from);
}

/// A flux gauge's section: its line (in 3D in a plane y = const, not along y), and in 3D an
/// optional `span: [y0, y1]` across the channel cut into `columns` strips (default 20), the line at
/// each strip's middle: the flux is then the discharge through the rectangle [m3/s], else per metre
/// of width at the line's y.
inline void read_flux_section(Reader& r, GaugeConfig& g, const Node& n, const std::string& path, int dim) {
  read_line(r, g, n, path, static_cast<std::size_t>(dim));
  if (dim == 2) {
    if (r.has("span")) r.fail_at(r.get("span"), r.key_path("span"), "no span in 2D (the flux is per metre of width already)");
    return;
  }
  if (g.start[1] != g.end[1]) r.fail_at(r.get("end"), r.key_path("end"), "a line in a plane y = const (the same y as 'start'; 'span' sets the section's width)");
  if (g.start[0] == g.end[0] && g.start[2] == g.end[2]) r.fail_at(r.get("end"), r.key_path("end"), "an end apart from the start");
  if (r.has("span")) {
    g.span = r.vec("span", 2);
    if (!(g.span[1] > g.span[0])) r.fail_at(r.get("span"), r.key_path("span"), "[y0, y1] with y1 > y0 (the section across the channel)");
    g.columns = r.scalar<int>("columns", 20);
    if (g.columns < 1 || g.columns > 10000) r.fail_at(r.get("columns"), r.key_path("columns"), "an integer in [1, 10000]");
  } else if (r.has("columns")) {
    r.fail_at(r.get("columns"), r.key_path("columns"), "'span' too (the section's extent across y)");
  }
}

/// An optional box [start, end] (default: everywhere).
inline void read_box(Reader& r, GaugeConfig& g, const Node& n, const std::string& path, std::size_t d) {
  g.start = r.vec("start", d);
  g.end = r.vec("end", d);
  if (g.start.empty() != g.end.empty()) r.fail_at(n, path, "both 'start' and 'end' corners of the box, or neither");
  for (std::size_t i = 0; i < g.start.size(); ++i)
    if (!(g.end[i] > g.start[i])) r.fail_at(r.get("end"), r.key_path("end"), "end > start in every coordinate");
}

/// A scalar field's Shepard average at a point, as at_held_points wants it.
template <int D>
auto scalar_at(const System<D>& S, const std::vector<double>& C) {
  return [&S, &C](const Vec<D>& x, double* out) {
    auto v = interpolate_shepard(S, x, [&](std::uint32_t b) { return C[b]; });
    out[0] = v ? *v : std::numeric_limits<double>::quiet_NaN();
  };
}

}  // namespace sph
