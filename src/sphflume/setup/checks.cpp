// Geometry checks before anything is allocated (docs/case-file.md, "Errors").
#include <limits>

#include "sphflume/setup/setup.hpp"
#include "sphflume/setup/shape_lattice.hpp"

namespace sph {
using namespace setup_detail;

/// Refuse, before anything is allocated: fluid outside the domain, absurd particle counts,
/// shapes spread over absurdly many neighbour-search cells or too far out for dx.
template <int D>
void check_geometry(const Case& c, const BuildLimits& limits, double support, int layers) {
  const double dx = c.dx;
  const double tol = 1e-6 * dx;
  if (!c.domain_min.empty())
    for (std::size_t i = 0; i < c.shapes.size(); ++i) {
      const auto& s = c.shapes[i];
      if (s.fill != "fluid") continue;
      Vec<D> lo, hi;
      shape_box<D>(s, dx, layers, lo, hi);
      if constexpr (D == 2)
        if (s.type == "polygon")  // its own extent, not the dx-anchored lattice box
          for (int d = 0; d < D; ++d) {
            lo[d] = 1e300; hi[d] = -1e300;
            for (const auto& p : s.vertices) { lo[d] = std::min(lo[d], p[d]); hi[d] = std::max(hi[d], p[d]); }
          }
      for (int d = 0; d < D; ++d)
        if (lo[d] < c.domain_min[d] - tol || hi[d] > c.domain_max[d] + tol)
          throw InputError(fmt::format(
              "{}: the fluid shape extends outside the domain along {} ({:.6g} .. {:.6g} m, domain.min/max {:.6g} .. "
              "{:.6g} m): expected fluid shapes inside the domain (fluid outside it would be removed on the first step)",
              shape_where(c, i), axis_name(d, D), lo[d], hi[d], c.domain_min[d], c.domain_max[d]));
    }

  // particle count, and the box the run's neighbour search will cover
  Vec<D> blo, bhi;
  for (int d = 0; d < D; ++d) { blo[d] = 1e300; bhi[d] = -1e300; }
  double coord_max = 0.0;
  for (std::size_t i = 0; i < c.shapes.size(); ++i) {
    Vec<D> lo, hi;
    shape_box<D>(c.shapes[i], dx, layers, lo, hi);
    for (int d = 0; d < D; ++d) {
      blo[d] = std::min(blo[d], lo[d]);
      bhi[d] = std::max(bhi[d], hi[d]);
      coord_max = std::max({coord_max, std::abs(lo[d]), std::abs(hi[d])});
    }
  }
  if (!(coord_max / dx <= 1e12))
    throw InputError(fmt::format("{}: line {}: 'geometry': coordinates as large as {:.3g} m cannot be resolved at "
                                 "particles.dx = {} m: expected coordinates within 1e12 dx of the origin (in m)",
                                 c.file, c.geometry_line, coord_max, dx));
  std::size_t largest_i = 0;
  const double total = total_count<D>(c, dx, layers, &largest_i);
  if (!(total <= limits.max_particles)) {
    double dx_fit = dx * std::pow(total / limits.max_particles, 1.0 / D);  // exact for fluid boxes
    for (int k = 0; k < 400 && !(total_count<D>(c, dx_fit, layers) <= limits.max_particles); ++k) dx_fit *= 1.02;
    throw InputError(fmt::format("{}: line {}: 'geometry': the shapes would make about {:.3g} particles at particles.dx "
                                 "= {} m (most in geometry.{}, line {}): expected at most {:.3g}: use dx >= {:.3g} m or "
                                 "check the shapes' coordinates (in m)",
                                 c.file, c.geometry_line, total, dx, largest_i, c.shapes[largest_i].line,
                                 limits.max_particles, dx_fit));
  }
  if (!c.domain_min.empty()) {
    for (int d = 0; d < D; ++d) { blo[d] = std::min(blo[d], c.domain_min[d]); bhi[d] = std::max(bhi[d], c.domain_max[d]); }
  } else {  // as the run's default domain: 10 % + dx around, 100 % + dx above
    for (int d = 0; d < D; ++d) {
      const double span = bhi[d] - blo[d];
      blo[d] -= 0.1 * span + dx;
      bhi[d] += (d == D - 1 ? 1.0 : 0.1) * span + dx;
    }
  }
  double cells = 1.0;
  std::string extent;
  for (int d = 0; d < D; ++d) {
    const double n = (bhi[d] - blo[d]) / support + 1.0;
    cells *= n;
    extent += fmt::format("{}{:.4g}", d ? " x " : "", bhi[d] - blo[d]);
    if (!(n <= 4.0e6)) cells = std::numeric_limits<double>::infinity();
  }
  if (!(cells <= limits.max_cells))
    throw InputError(fmt::format("{}: line {}: 'geometry': the run's box ({} m with its margins) holds {:.3g} "
                                 "neighbour-search cells of the kernel support ({:.4g} m): expected at most {:.3g} (and "
                                 "4e6 along an axis): shapes far apart, or a coordinate typo? (coordinates are in m)",
                                 c.file, c.geometry_line, extent, cells, support, limits.max_cells));
}


template void check_geometry<2>(const Case&, const BuildLimits&, double, int);
template void check_geometry<3>(const Case&, const BuildLimits&, double, int);

}  // namespace sph
