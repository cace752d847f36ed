#include "sphflume/io/runup.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace sph {

template <int D>
std::array<double, 2> runup_waterline(const GaugeConfig& g, const System<D>& S) {
  constexpr double nan = std::numeric_limits<double>::quiet_NaN();
  constexpr double inf = std::numeric_limits<double>::infinity();
  const auto& P = S.particles;
  // the line in the (x, z) plane: unit tangent e up the slope, unit normal n out of the slope (z > 0)
  const double tx = g.end[0] - g.start[0], tz = g.end[D - 1] - g.start[D - 1];
  const double len = std::hypot(tx, tz);
  const double ex = tx / len, ez = tz / len;
  const double nx = ex >= 0.0 ? -ez : ez, nz = ex >= 0.0 ? ex : -ex;
  const double reach = g.reach > 0.0 ? g.reach : 1.5 * S.dx;
  const double film = g.film;
  const double w = 2.0 * S.dx, r = 2.0 * S.dx;
  const std::size_t nb = std::max<std::size_t>(1, static_cast<std::size_t>(std::ceil(len / w)));
  std::vector<double> lo(nb, inf), hi(nb, -inf), top_s(nb, -inf), top_z(nb, nan), top_x(nb, nan);
  for (std::size_t i = 0; i < P.n_owned(); ++i) {
    if (P.kind[i] != Kind::Fluid) continue;
    const double qx = P.pos[i][0] - g.start[0], qz = P.pos[i][D - 1] - g.start[D - 1];
    const double s = qx * ex + qz * ez, n = qx * nx + qz * nz;
    if (s < 0.0 || s > len || n < -reach) continue;
    int count = 0;
    S.cells.for_neighbours(P.pos, P.pos[i], r, [&](std::uint32_t j, const Vec<D>&, double r2) {
      count += (P.kind[j] == Kind::Fluid && r2 > 0.0);
    });
    if (count < g.neighbours) continue;
    const std::size_t k = std::min(nb - 1, static_cast<std::size_t>(s / w));
    lo[k] = std::min(lo[k], n);
    hi[k] = std::max(hi[k], n);
    if (n <= reach && s > top_s[k]) {
      top_s[k] = s;
      top_z[k] = P.pos[i][D - 1];
      top_x[k] = P.pos[i][0];
    }
  }
  // over the parts of the domain: each stretch's extremes, and its top particle (the one
  // furthest up the face; its position from the part that holds it)
  S.comm->min(lo.data(), nb);
  S.comm->max(hi.data(), nb);
  std::vector<double> best = top_s, zx(3 * nb, 0.0);
  S.comm->max(best.data(), nb);
  for (std::size_t k = 0; k < nb; ++k)
    if (std::isfinite(top_s[k]) && top_s[k] == best[k]) {
      zx[3 * k] = top_z[k];
      zx[3 * k + 1] = top_x[k];
      zx[3 * k + 2] = 1.0;
    }
  S.comm->sum(zx.data(), zx.size());
  for (std::size_t k = 0; k < nb; ++k) {
    top_s[k] = best[k];
    if (zx[3 * k + 2] > 0.0) {
      top_z[k] = zx[3 * k] / zx[3 * k + 2];
      top_x[k] = zx[3 * k + 1] / zx[3 * k + 2];
    }
  }
  // walk up from the toe through the stretches the water touches; the waterline is the highest of
  // their surface particles at most film / tan(slope) up the face from the last thick stretch's
  // (the thin edge of a water body whose surface meets the face at up to the face's own angle)
  const double tan_a = std::abs(ez) / std::max(std::abs(ex), 1e-12);
  double s_thick = 0.0;
  std::size_t last = nb;
  for (std::size_t k = 0; k < nb; ++k) {
    if (!(lo[k] <= reach && std::isfinite(top_s[k]))) break;
    if (hi[k] - lo[k] + S.dx >= film) s_thick = top_s[k];
    if (top_s[k] <= s_thick + film / tan_a) last = k;
  }
  if (last == nb) return {nan, nan};
  return {top_z[last] - g.level, top_x[last]};
}

template std::array<double, 2> runup_waterline<2>(const GaugeConfig&, const System<2>&);
template std::array<double, 2> runup_waterline<3>(const GaugeConfig&, const System<3>&);

}  // namespace sph
