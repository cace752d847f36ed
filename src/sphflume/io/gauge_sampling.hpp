// How gauges sample the particles (io/, the gauge types' shared helpers): values at points,
// each computed by the part of the domain that holds it; lines of points; the wet part of a line.
#pragma once
#include <cmath>
#include <limits>
#include <vector>

#include "sphflume/core/interpolate.hpp"
#include "sphflume/core/system.hpp"
#include "sphflume/io/case.hpp"

namespace sph::gauge_detail {

/// A gauge value with no reading (no water at a point, an empty line): NaN.
inline constexpr double kNan = std::numeric_limits<double>::quiet_NaN();

/// ∫ u ds over the wet part of a line sampled every ds (fluid fraction f ≥ 0.5): trapezoids over
/// the wet segments; a segment crossing the surface (f = 0.5, linearly interpolated) counts its
/// wet part, so the integral does not jump by a whole segment as the surface moves past a point.
inline double wet_integral(const std::vector<double>& f, const std::vector<double>& u, double ds) {
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

using sph::at_held_points;

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
  const std::vector<Vec<D>> line = line_points<D>(g);
  // 3D with a span: the same line at the midpoints of `columns` equal strips across the section (the
  // midpoint rule: no line on a wall face, where the fluid fraction is ~0.5 and a whole strip would
  // read dry; exact for a periodic span)
  const bool section = D == 3 && !g.span.empty();
  const std::size_t nc = section ? static_cast<std::size_t>(g.columns) : 1, np = line.size();
  const double dy = section ? (g.span[1] - g.span[0]) / static_cast<double>(nc) : 0.0;
  std::vector<Vec<D>> pts;
  pts.reserve(nc * np);
  for (std::size_t c = 0; c < nc; ++c)
    for (Vec<D> x : line) {
      if (section) x[1] = g.span[0] + dy * (static_cast<double>(c) + 0.5);
      pts.push_back(x);
    }
  const auto fu = at_held_points(S, pts, 2, [&](const Vec<D>& x, double* out) {
    out[0] = fluid_fraction(S, x);
    out[1] = out[0] > 0.0 ? un(x, nrm) : 0.0;
  });
  double total = 0.0;
  std::vector<double> f(np), q(np);
  for (std::size_t c = 0; c < nc; ++c) {
    for (std::size_t i = 0; i < np; ++i) {
      const std::size_t k = c * np + i;
      f[i] = std::isfinite(fu[2 * k]) ? fu[2 * k] : 0.0;  // (a point outside every part: dry)
      q[i] = std::isfinite(fu[2 * k + 1]) ? fu[2 * k + 1] : 0.0;
    }
    const double col = wet_integral(f, q, ds);
    if (!section) return col;
    total += dy * col;
  }
  return total;
}

/// A case's coordinate list as a point.
template <int D>
Vec<D> point_of(const std::vector<double>& v) {
  Vec<D> x{};
  for (int d = 0; d < D; ++d) x[d] = v[static_cast<std::size_t>(d)];
  return x;
}

/// Whether x lies in the gauge's box [start, end) (everywhere when it has none).
template <int D>
bool in_box(const GaugeConfig& g, const Vec<D>& x) {
  bool in = true;
  for (std::size_t d = 0; d < g.start.size(); ++d) in &= x[d] >= g.start[d] && x[d] < g.end[d];
  return in;
}

}  // namespace sph::gauge_detail
