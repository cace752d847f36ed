#include "sphflume/io/geometry.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include <fmt/format.h>

#include "sphflume/core/shapes.hpp"
#include "sphflume/physics/porous.hpp"

namespace sph {
namespace {

template <int D>
Vec<D> to_vec(const std::vector<double>& v) {
  Vec<D> out{};
  for (int d = 0; d < D; ++d) out[d] = v[static_cast<std::size_t>(d)];
  return out;
}

const char* axis_name(int d, int dim) { return d == dim - 1 ? "z" : d == 0 ? "x" : "y"; }

/// Lattice points min + (i + 1/2) dx inside [lo, hi) along one axis (as a double: no overflow).
double lattice_count(double lo, double hi, double dx) {
  const double n = std::floor((hi - lo) / dx + 1e-9);
  return n > 0 ? n : 0.0;  // NaN -> 0; callers check the extent first
}

/// Calls f(x) for every lattice point min + (i + 1/2) dx inside [lo, hi).
template <int D, class Fn>
void lattice(const Vec<D>& lo, const Vec<D>& hi, double dx, Fn&& f) {
  long n[D];
  for (int d = 0; d < D; ++d) n[d] = static_cast<long>(lattice_count(lo[d], hi[d], dx));
  if constexpr (D == 2) {
    for (long k = 0; k < n[1]; ++k)
      for (long i = 0; i < n[0]; ++i) f(Vec<2>{{lo[0] + (i + 0.5) * dx, lo[1] + (k + 0.5) * dx}});
  } else {
    for (long k = 0; k < n[2]; ++k)
      for (long j = 0; j < n[1]; ++j)
        for (long i = 0; i < n[0]; ++i)
          f(Vec<3>{{lo[0] + (i + 0.5) * dx, lo[1] + (j + 0.5) * dx, lo[2] + (k + 0.5) * dx}});
  }
}

/// The points of lattice(olo, ohi) that are not strictly inside (lo, hi), in the same order,
/// without visiting the inside (a tank's walls; the inside may hold millions of points).
template <int D, class Fn>
void lattice_shell(const Vec<D>& olo, const Vec<D>& ohi, const Vec<D>& lo, const Vec<D>& hi, double dx, Fn&& f) {
  long n[D];
  for (int d = 0; d < D; ++d) n[d] = static_cast<long>(lattice_count(olo[d], ohi[d], dx));
  auto row = [&](Vec<D> x) {  // x has every coordinate but x[0] set
    bool inner = true;
    for (int d = 1; d < D; ++d) inner &= x[d] > lo[d] && x[d] < hi[d];
    auto at = [&](long i) { x[0] = olo[0] + (i + 0.5) * dx; return x; };
    long a = 0, b = n[0];
    if (inner) {
      while (a < n[0] && !(at(a)[0] > lo[0])) ++a;  // left wall: x <= lo
      while (b > a && !(at(b - 1)[0] < hi[0])) --b;  // right wall: x >= hi
    } else {
      a = b = n[0];
    }
    for (long i = 0; i < a; ++i) f(at(i));
    for (long i = b; i < n[0]; ++i) f(at(i));
  };
  Vec<D> x{};
  if constexpr (D == 2) {
    for (long k = 0; k < n[1]; ++k) { x[1] = olo[1] + (k + 0.5) * dx; row(x); }
  } else {
    for (long k = 0; k < n[2]; ++k)
      for (long j = 0; j < n[1]; ++j) { x[1] = olo[1] + (j + 0.5) * dx; x[2] = olo[2] + (k + 0.5) * dx; row(x); }
  }
}

/// The point of a wall shape's fluid-side surface nearest to x (a point of the shape's wall
/// lattice): tank: the inner box; box: its nearest face; plane: the plane; polygon: its edges.
template <int D>
Vec<D> surface_point(const ShapeConfig& s, const Vec<D>& x) {
  Vec<D> p = x;
  if (s.type == "tank") {
    for (int d = 0; d < D; ++d) p[d] = std::clamp(x[d], s.min[d], s.max[d]);
  } else if (s.type == "box") {
    double best = 1e300;
    for (int d = 0; d < D; ++d)
      for (const double face : {s.min[d], s.max[d]})
        if (std::abs(x[d] - face) < best) { best = std::abs(x[d] - face); p = x; p[d] = face; }
  } else if (s.type == "plane") {
    Vec<D> nrm = to_vec<D>(s.normal);
    nrm *= 1.0 / norm(nrm);
    p = x - dot(x - to_vec<D>(s.point), nrm) * nrm;
  } else if (s.type == "polygon") {
    if constexpr (D == 2) {
      double best = 1e300;
      for (std::size_t i = 0, j = s.vertices.size() - 1; i < s.vertices.size(); j = i++) {
        const Vec<2> a{{s.vertices[j][0], s.vertices[j][1]}}, b{{s.vertices[i][0], s.vertices[i][1]}};
        const Vec<2> ab = b - a;
        const double l2 = dot(ab, ab);
        const double t = l2 > 0 ? std::clamp(dot(x - a, ab) / l2, 0.0, 1.0) : 0.0;
        const Vec<2> q = a + t * ab;
        if (norm(x - q) < best) { best = norm(x - q); p = q; }
      }
    }
  }
  return p;
}

/// The box whose lattice a shape visits (a tank: with its walls; a polygon: its bounding box
/// anchored on the global dx grid so polygons line up with boxes at 0).
template <int D>
void shape_box(const ShapeConfig& s, double dx, int layers, Vec<D>& lo, Vec<D>& hi) {
  if (s.type == "polygon") {
    for (int d = 0; d < D; ++d) { lo[d] = 1e300; hi[d] = -1e300; }
    if constexpr (D == 2)
      for (const auto& p : s.vertices)
        for (int d = 0; d < 2; ++d) { lo[d] = std::min(lo[d], p[d]); hi[d] = std::max(hi[d], p[d]); }
    for (int d = 0; d < D; ++d) { lo[d] = std::floor(lo[d] / dx) * dx; hi[d] = std::ceil(hi[d] / dx) * dx; }
    return;
  }
  lo = to_vec<D>(s.min);
  hi = to_vec<D>(s.max);
  if (s.type == "tank") {
    for (int d = 0; d < D; ++d) { lo[d] -= layers * dx; hi[d] += layers * dx; }
    if (s.open_top) hi[D - 1] = s.max[D - 1];
  }
}

/// Upper bound of the particles a shape makes (exact for boxes and tanks).
template <int D>
double shape_count(const ShapeConfig& s, double dx, const Vec<D>& lo, const Vec<D>& hi) {
  double n = 1.0;
  for (int d = 0; d < D; ++d) n *= lattice_count(lo[d], hi[d], dx);
  if (s.type == "tank") {
    double inner = 1.0;
    for (int d = 0; d < D; ++d) inner *= lattice_count(s.min[d], s.max[d], dx);
    n = std::max(n - inner, 0.0);
  }
  return n;
}

/// Wall particles binned in cells of side dx (sorted keys, no dense grid: walls may be far
/// apart); answers "is there a wall particle closer than r (< dx) to x".
template <int D>
class WallBins {
 public:
  using Key = std::array<long, D>;
  WallBins(const std::vector<Vec<D>>& x, double dx) : dx_(dx) {
    for (int d = 0; d < D; ++d) lo_[d] = 1e300;
    for (const auto& p : x)
      for (int d = 0; d < D; ++d) lo_[d] = std::min(lo_[d], p[d]);
    e_.reserve(x.size());
    for (const auto& p : x) e_.push_back({key(p), p});
    std::sort(e_.begin(), e_.end(), [](const Entry& a, const Entry& b) { return a.k < b.k; });
  }
  bool any_within(const Vec<D>& x, double r) const {
    Key k0 = key(x);
    Key k = k0;
    for (int o = 0; o < (D == 2 ? 9 : 27); ++o) {
      for (int d = 0, q = o; d < D; ++d, q /= 3) k[d] = k0[d] + q % 3 - 1;
      auto it = std::lower_bound(e_.begin(), e_.end(), k, [](const Entry& a, const Key& b) { return a.k < b; });
      for (; it != e_.end() && it->k == k; ++it) {
        const Vec<D> dv = it->x - x;
        if (dot(dv, dv) < r * r) return true;
      }
    }
    return false;
  }

 private:
  struct Entry { Key k; Vec<D> x; };
  Key key(const Vec<D>& x) const {  // coordinates are bounded (check_extent) before this is used
    Key k;
    for (int d = 0; d < D; ++d) k[d] = static_cast<long>(std::floor((x[d] - lo_[d]) / dx_)) ;
    return k;
  }
  double dx_;
  Vec<D> lo_;
  std::vector<Entry> e_;
};

/// Particles all shapes make at spacing dx (an upper bound; exact for boxes and tanks).
template <int D>
double total_count(const Case& c, double dx, int layers, std::size_t* largest_i = nullptr) {
  double total = 0.0, largest = -1.0;
  for (std::size_t i = 0; i < c.shapes.size(); ++i) {
    Vec<D> lo, hi;
    shape_box<D>(c.shapes[i], dx, layers, lo, hi);
    const double n = shape_count<D>(c.shapes[i], dx, lo, hi);
    total += n;
    if (largest_i && !(n <= largest)) { largest = n; *largest_i = i; }
  }
  return total;
}

std::string shape_where(const Case& c, std::size_t i) {
  return fmt::format("{}: line {}: 'geometry.{}'", c.file, c.shapes[i].line, i);
}

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

}  // namespace

int wall_layers_for(const Case& c) {
  if (c.walls.layers > 0) return c.walls.layers;
  const double support = kernel_support_factor(c.kernel) * c.h_over_dx;  // in units of dx
  return static_cast<int>(std::ceil(support - 1e-9));
}

template <int D>
BuildReport build_system(const Case& c, System<D>& S, const BuildLimits& limits) {
  BuildReport rep;
  S.kernel = c.kernel;
  S.dx = c.dx;
  S.h = c.h();
  S.support = kernel_support_factor(c.kernel) * S.h;
  S.nu = c.fluid.viscosity;
  S.gravity = to_vec<D>(c.gravity);
  const int layers = wall_layers_for(c);
  rep.wall_layers = layers;
  const double dx = c.dx;
  const double vol = std::pow(dx, D);
  const double m = c.fluid.density * vol;
  constexpr int vz = D - 1;
  if (!std::isnormal(m) || !std::isnormal(S.h * S.h) || !std::isnormal(1.0 / (S.support * S.support)))
    throw InputError(fmt::format("{}: 'particles.dx' = {} m with 'fluid.density' = {} kg/m3 gives a particle mass of {:.3g} "
                                 "kg and h = {:.3g} m: expected sizes a double can square and invert (SI units: m, kg/m3)",
                                 c.file, dx, c.fluid.density, m, S.h));
  check_geometry<D>(c, limits, S.support, layers);

  // porous media: the fluid inside a porous region (or a `porous.fill` box) starts on a lattice
  // dx / phi0^(1/D) (Kazemi eq 5.1), so that every particle keeps the mass rho0 dx^D and the
  // volume m / (phi rho). Fill zones: the shape regions with phi0 < 1, then the fill boxes.
  if (c.porous.on()) S.porous = std::make_shared<PorousMedia<D>>(c.porous, c.kernel, S.h, dx);
  struct FillZone { int region; Vec<D> lo, hi; double spacing; };
  std::vector<FillZone> zones;
  if (S.porous) {
    for (std::size_t r = 0; r < S.porous->size(); ++r) {
      const auto& rc = S.porous->region(r);
      if (!(S.porous->fill_spacing(r) > 0.0) || !(rc.porosity < 1.0)) continue;
      FillZone z{static_cast<int>(r), {}, {}, S.porous->fill_spacing(r)};
      if (rc.shape == "box") { z.lo = to_vec<D>(rc.min); z.hi = to_vec<D>(rc.max); }
      else {
        for (int d = 0; d < D; ++d) { z.lo[d] = 1e300; z.hi[d] = -1e300; }
        for (const auto& v : rc.vertices)
          for (int d = 0; d < D && d < 2; ++d) { z.lo[d] = std::min(z.lo[d], v[d]); z.hi[d] = std::max(z.hi[d], v[d]); }
      }
      zones.push_back(z);
    }
    for (const auto& f : c.porous.fill)
      zones.push_back({-1, to_vec<D>(f.min), to_vec<D>(f.max), PorousMedia<D>::fill_spacing_of(f.porosity, dx)});
  }
  auto zone_of = [&](const Vec<D>& x) -> int {
    for (std::size_t k = 0; k < zones.size(); ++k) {
      const auto& z = zones[k];
      bool in = true;
      if (z.region >= 0) in = S.porous->inside(static_cast<std::size_t>(z.region), x);
      else
        for (int d = 0; d < D; ++d) in &= x[d] >= z.lo[d] && x[d] <= z.hi[d];
      if (in) return static_cast<int>(k);
    }
    return -1;
  };

  std::vector<Vec<D>> fluid_x, fluid_v, wall_x, wall_s;  // wall_s: nearest point of the wall surface
  std::vector<std::uint32_t> fluid_shape;  // which shape made each fluid point
  std::vector<std::uint32_t> wall_shape;   // which shape made each wall point
  std::vector<double> fluid_half;          // half the lattice spacing of each fluid point
  for (std::size_t si = 0; si < c.shapes.size(); ++si) {
    const auto& s = c.shapes[si];
    const Vec<D> v0 = to_vec<D>(s.velocity);
    auto emit = [&](const Vec<D>& x) {
      if (s.fill == "fluid") {
        if (zone_of(x) >= 0) return;  // filled at the zone's spacing below
        fluid_x.push_back(x); fluid_v.push_back(v0); fluid_shape.push_back(static_cast<std::uint32_t>(si));
        fluid_half.push_back(0.5 * dx);
      } else {
        wall_x.push_back(x);
        wall_s.push_back(surface_point<D>(s, x));
        wall_shape.push_back(static_cast<std::uint32_t>(si));
      }
    };
    Vec<D> lo, hi;
    shape_box<D>(s, dx, layers, lo, hi);
    if (s.type == "box") {
      lattice<D>(lo, hi, dx, emit);
    } else if (s.type == "tank") {
      lattice_shell<D>(lo, hi, to_vec<D>(s.min), to_vec<D>(s.max), dx, emit);
    } else if (s.type == "polygon" && !s.solid.empty()) {
      if constexpr (D == 2) {
        // a wall slope: rows of particles parallel to its surface, dx apart along it, at depths
        // (k + 1/2) dx, k < layers (as a flat wall's lattice, turned with the slope); none below the
        // toe's level (the bed's walls are there)
        const double ax = s.solid[0][0], az = s.solid[0][1];
        const double tx = s.solid[1][0] - ax, tz = s.solid[1][1] - az, len = std::sqrt(tx * tx + tz * tz);
        const double ux = tx / len, uz = tz / len;  // along the slope; the normal into the fluid is (-uz, ux)
        const long nalong = std::lround(std::floor(len / dx));
        for (int k = 0; k < layers; ++k)
          for (long i = 0; i < nalong; ++i) {
            const double a = (static_cast<double>(i) + 0.5) * dx, dep = (k + 0.5) * dx;
            Vec<2> x, sp;
            sp[0] = ax + a * ux;
            sp[1] = az + a * uz;
            x[0] = sp[0] + dep * uz;
            x[1] = sp[1] - dep * ux;
            if (x[1] < az + 0.5 * dx * 0.999) continue;  // in the bed's walls
            wall_x.push_back(x);
            wall_s.push_back(sp);
            wall_shape.push_back(static_cast<std::uint32_t>(si));
          }
        // the toe's seal: where the rows meet the bed they are cut at an angle and leave the hollow under
        // them open to the corner (a rough 1:1.5 breakwater at dx = 0.02 failed with a particle below
        // the bed level there; water was also trapped under its crest then, since fixed). Lattice
        // points of the hollow deeper than the rows, less than 2 layers above the bed and along the face no
        // further than where the deepest row is cut (plus 2 layers) close it.
        const double top_z = az + 2.0 * layers * dx;
        const double a_cut = ((0.5 + layers * ux) / std::max(uz, 1e-12) + 2.0 * layers) * dx;
        Vec<2> blo, bhi;
        blo[0] = ax;
        bhi[0] = ax + tx + 2.0 * layers * dx;
        blo[1] = az;
        bhi[1] = std::min(top_z, az + tz);
        lattice<2>(blo, bhi, dx, [&](const Vec<2>& x) {
          if (x[1] < az + 0.5 * dx * 0.999 || !inside_polygon(s.solid, x[0], x[1])) return;
          const double px = x[0] - ax, pz = x[1] - az;
          const double along = px * ux + pz * uz, depth = px * uz - pz * ux;  // below the surface line
          if (depth < layers * dx * 0.999 || along < 0.0 || along > std::min(len, a_cut)) return;
          Vec<2> sp;
          sp[0] = ax + along * ux;
          sp[1] = az + along * uz;
          wall_x.push_back(x);
          wall_s.push_back(sp);
          wall_shape.push_back(static_cast<std::uint32_t>(si));
        });
      }
    } else if (s.type == "polygon") {
      if constexpr (D == 2)
        lattice<2>(lo, hi, dx, [&](const Vec<2>& x) { if (inside_polygon(s.vertices, x[0], x[1])) emit(x); });
    } else if (s.type == "plane") {
      Vec<D> nrm = to_vec<D>(s.normal);
      double nmax = 0.0;
      for (int d = 0; d < D; ++d) nmax = std::max(nmax, std::abs(nrm[d]));
      nrm *= 1.0 / nmax;  // first to O(1): a tiny or huge normal must not underflow or overflow
      nrm *= 1.0 / norm(nrm);
      const Vec<D> p0 = to_vec<D>(s.point);
      const double thick = s.thickness > 0 ? s.thickness : layers * dx;
      lattice<D>(lo, hi, dx, [&](const Vec<D>& x) {
        const double sd = dot(x - p0, nrm);
        if (sd <= 0.0 && sd > -thick) emit(x);
      });
    }
  }

  for (std::size_t k = 0; k < zones.size(); ++k) {  // each fill zone's share of each fluid shape
    const auto& zn = zones[k];
    for (std::size_t si = 0; si < c.shapes.size(); ++si) {
      const auto& s = c.shapes[si];
      if (s.fill != "fluid" || (s.type != "box" && s.type != "polygon")) continue;
      Vec<D> lo, hi;
      shape_box<D>(s, dx, layers, lo, hi);
      bool empty = false;
      for (int d = 0; d < D; ++d) {
        lo[d] = std::max(lo[d], zn.lo[d]);
        hi[d] = std::min(hi[d], zn.hi[d]);
        empty |= !(hi[d] > lo[d]);
      }
      if (empty) continue;
      const Vec<D> v0 = to_vec<D>(s.velocity);
      lattice<D>(lo, hi, zn.spacing, [&](const Vec<D>& x) {
        if (zone_of(x) != static_cast<int>(k)) return;  // outside the zone, or in an earlier one
        if (s.type == "polygon") {
          if constexpr (D == 2) { if (!inside_polygon(s.vertices, x[0], x[1])) return; }
        }
        fluid_x.push_back(x); fluid_v.push_back(v0); fluid_shape.push_back(static_cast<std::uint32_t>(si));
        fluid_half.push_back(0.5 * zn.spacing);
      });
    }
  }

  // Drop fluid lattice points that fall inside the walls (closer than dx/2 to a wall particle),
  // e.g. a fluid box drawn over a sloping bed.
  std::vector<char> drop(fluid_x.size(), 0);
  if (!wall_x.empty()) {
    const WallBins<D> bins(wall_x, dx);
    for (std::size_t i = 0; i < fluid_x.size(); ++i) drop[i] = bins.any_within(fluid_x[i], 0.5 * dx * 0.999);
  }
  // and every point inside a solid wall box (a gate, a paddle), whose own lattice may leave a point of another
  // lattice (a porous zone's, spacing dx/sqrt(phi)) dx/2 or more from its particles yet inside the body
  for (const auto& s : c.shapes) {
    if (s.fill != "wall" || s.type != "box") continue;
    const Vec<D> lo = to_vec<D>(s.min), hi = to_vec<D>(s.max);
    for (std::size_t i = 0; i < fluid_x.size(); ++i) {
      bool in = true;
      for (int d = 0; d < D; ++d) in = in && fluid_x[i][d] > lo[d] && fluid_x[i][d] < hi[d];
      if (in) drop[i] = 1;
    }
  }
  if constexpr (D == 2) {  // slopes whose walls are a layer: no fluid in the hollow under them
    for (const auto& s : c.shapes) {
      if (s.solid.empty()) continue;
      // and none closer than dx/2 to the slope's surface (the lattice does not follow the slope: a
      // point left a fraction of dx above it is thrown off at the first step)
      const double ax = s.solid[0][0], az = s.solid[0][1], tx = s.solid[1][0] - ax, tz = s.solid[1][1] - az;
      const double len2 = tx * tx + tz * tz;
      for (std::size_t i = 0; i < fluid_x.size(); ++i) {
        if (drop[i]) continue;
        const double px = fluid_x[i][0] - ax, pz = fluid_x[i][1] - az;
        const double u = std::clamp((px * tx + pz * tz) / len2, 0.0, 1.0);
        const double dxs = px - u * tx, dzs = pz - u * tz;
        if (inside_polygon(s.solid, fluid_x[i][0], fluid_x[i][1]) || dxs * dxs + dzs * dzs < 0.25 * dx * dx * 0.998) drop[i] = 1;
      }
    }
  }
  // Per fluid shape: it must make particles, and at most half of them may fall inside walls.
  {
    std::vector<std::size_t> made(c.shapes.size(), 0), dropped(c.shapes.size(), 0);
    for (std::size_t i = 0; i < fluid_x.size(); ++i) { ++made[fluid_shape[i]]; dropped[fluid_shape[i]] += drop[i] ? 1 : 0; }
    for (std::size_t si = 0; si < c.shapes.size(); ++si) {
      if (c.shapes[si].fill != "fluid") continue;
      if (made[si] == 0)
        throw InputError(fmt::format("{}: the fluid shape makes no particles: expected a shape at least particles.dx = {} m "
                                     "wide in every direction (lattice points sit at min + (i + 1/2) dx)",
                                     shape_where(c, si), dx));
      if (2 * dropped[si] > made[si])
        throw InputError(fmt::format("{}: {} of the fluid shape's {} lattice points ({:.0f} %) lie inside walls (closer "
                                     "than dx/2 to a wall particle): expected a fluid shape at most half inside walls "
                                     "(move it off the walls, or check its coordinates)",
                                     shape_where(c, si), dropped[si], made[si], 100.0 * dropped[si] / made[si]));
    }
  }
  if (fluid_x.empty())
    throw InputError(fmt::format("{}: line {}: 'geometry': the geometry makes no fluid particles: expected a shape with "
                                 "'fill: fluid' at least dx = {} m wide", c.file, c.geometry_line, dx));

  if (std::count(drop.begin(), drop.end(), 0) == 0)
    throw InputError(fmt::format("{}: every fluid particle lies inside a wall: move the fluid shapes off the walls", c.file));
  if (S.porous && c.porous.relax_iterations > 0) {
    const auto rr = relax_porous_band<D>(*S.porous, c.kernel, S.h, dx, fluid_x, drop, wall_x, c.porous.relax_iterations);
    rep.porous_relax_band = rr.band;
    rep.porous_relax_residual0 = rr.residual0;
    rep.porous_relax_residual = rr.residual;
    rep.porous_relax_shift = rr.max_shift;
    if (rr.residual > rr.residual0)
      throw InputError(fmt::format("{}: line {}: 'porous.relax': the relaxation of the porous interface band did not "
                                   "converge (max h |sum V grad W| {:.3g} -> {:.3g}): the band meets a free surface or a "
                                   "thin layer it cannot settle; set porous.relax: 0 (the plain lattice fill)",
                                   c.file, c.porous.line, rr.residual0, rr.residual));
  }
  double zmin = 1e300, zmax = -1e300;
  for (std::size_t i = 0; i < fluid_x.size(); ++i)
    if (!drop[i]) { zmin = std::min(zmin, fluid_x[i][vz]); zmax = std::max(zmax, fluid_x[i][vz]); }
  rep.fluid_height = zmax - zmin + dx;

  // Equation of state: c0 = 10 U with U the reference velocity or sqrt(2 g H).
  S.eos.type = c.fluid.eos;
  S.eos.rho0 = c.fluid.density;
  S.eos.gamma = c.fluid.gamma;
  S.eos.background = c.fluid.background_pressure;
  double c0 = c.fluid.sound_speed;
  if (c0 <= 0.0) {
    const double gabs = norm(S.gravity);
    const double U = c.fluid.reference_velocity > 0 ? c.fluid.reference_velocity : std::sqrt(2.0 * gabs * rep.fluid_height);
    if (!(U > 0.0))
      throw InputError(fmt::format("{}: cannot derive the sound speed (no gravity): set fluid.sound_speed, or "
                                   "fluid.reference_velocity (c0 = 10 x it)", c.file));
    c0 = 10.0 * U;
  }
  if (!std::isnormal(c0 * c0) || !std::isnormal(S.eos.B()))
    throw InputError(fmt::format("{}: the sound speed c0 = {:.4g} m/s (fluid.sound_speed, or 10 x fluid.reference_velocity "
                                 "or 10 sqrt(2 |g| H)) gives B = c0^2 rho0 / gamma = {:.4g} Pa: expected values of "
                                 "ordinary size (check gravity, fluid.sound_speed and fluid.gamma)",
                                 c.file, c0, c0 * c0 * c.fluid.density / c.fluid.gamma));
  S.eos.c0 = c0;

  // Hydrostatic initial density: surface = top of the fluid in each lattice column.
  const double gz = -S.gravity[vz];
  std::map<std::vector<long>, double> top;
  auto column = [&](const Vec<D>& x) {
    std::vector<long> k;
    for (int d = 0; d < D - 1; ++d) k.push_back(std::lround(std::floor(x[d] / dx)));
    return k;
  };
  if (c.fluid.hydrostatic_init && gz > 0)
    for (std::size_t i = 0; i < fluid_x.size(); ++i) {
      if (drop[i]) continue;
      auto [it, fresh] = top.emplace(column(fluid_x[i]), fluid_x[i][vz] + fluid_half[i]);
      if (!fresh) it->second = std::max(it->second, fluid_x[i][vz] + fluid_half[i]);
    }

  auto& P = S.particles;
  const double rho_wall = S.eos.density(S.eos.background);
  for (std::size_t i = 0; i < fluid_x.size(); ++i) {
    if (drop[i]) { ++rep.fluid_dropped_in_walls; continue; }
    double rho = c.fluid.density;
    if (c.fluid.hydrostatic_init && gz > 0) {
      const double zs = top[column(fluid_x[i])];
      rho = S.eos.density(S.eos.background + c.fluid.density * gz * (zs - fluid_x[i][vz]));
    } else if (S.eos.background != 0.0) {
      rho = rho_wall;
    }
    if (!std::isnormal(rho) || rho < 0 || !std::isnormal(rho * m))
      throw InputError(fmt::format("{}: the initial density of the fluid at {} comes out as {:.4g} kg/m3 (hydrostatic "
                                   "pressure from gravity, fluid.gamma, fluid.background_pressure): expected a positive "
                                   "finite density (check those values, or set fluid.hydrostatic_init: false)",
                                   shape_where(c, fluid_shape[i]), fluid_x[i][0], rho));
    P.add(fluid_x[i], fluid_v[i], rho, m, Kind::Fluid);
    ++rep.fluid;
  }
  const std::size_t first_wall = P.n_owned();
  for (const auto& x : wall_x) {
    P.add(x, Vec<D>{}, rho_wall, m, Kind::Wall);
    ++rep.wall;
  }
  if (!c.motions.empty()) {  // moving walls: the motion of each wall particle and its place at X = 0
    auto& grp = P.scalar("motion_group");
    auto& org = P.vector("motion_origin");
    P.vector("wall_acc");
    for (std::size_t k = 0; k < wall_x.size(); ++k) {
      const std::string& mname = c.shapes[wall_shape[k]].motion;
      org[first_wall + k] = wall_x[k];
      for (std::size_t q = 0; q < c.motions.size(); ++q)
        if (!mname.empty() && c.motions[q].name == mname) grp[first_wall + k] = double(q + 1);
    }
  }
  if (c.walls.type == "fixed_ghost") {  // each ghost's interpolation point, mirrored into the fluid
    auto& mir = P.vector("ghost_mirror");
    for (std::size_t k = 0; k < wall_x.size(); ++k) mir[first_wall + k] = 2.0 * wall_s[k] - wall_x[k];
  }
  if (c.walls.repulsive) {  // unit normal of each wall particle towards the fluid side of its surface
    auto& nrm = P.vector("wall_normal");
    for (std::size_t k = 0; k < wall_x.size(); ++k) {
      const Vec<D> v = wall_s[k] - wall_x[k];
      const double len = norm(v);
      nrm[first_wall + k] = len > 0.0 ? (1.0 / len) * v : Vec<D>{};
    }
  }

  // every wall particle: the vector to its surface point (depth, normal; the dual integrator's
  // Riemann dissipation against walls acts along it)
  if (c.walls.backup || c.scheme.type == "isph" || !c.motions.empty() || c.scheme.integrator == Integrator::Dual) {
    auto& to = P.vector("wall_to_surface");
    for (std::size_t k = 0; k < wall_x.size(); ++k) to[first_wall + k] = wall_s[k] - wall_x[k];
  }

  if (!c.periodic.empty()) {
    S.periodic.lo = to_vec<D>(c.domain_min);
    S.periodic.hi = to_vec<D>(c.domain_max);
    for (int ax : c.periodic) {
      S.periodic.axis[ax] = true;
      if (S.periodic.period(ax) < 2.0 * S.support)
        throw InputError(fmt::format("{}: domain: the periodic length along {} ({:.4g} m) must be at least twice "
                                     "the kernel support ({:.4g} m)", c.file, "xyz"[D == 2 && ax == 1 ? 2 : ax],
                                     S.periodic.period(ax), S.support));
    }
  }
  if (S.porous) S.porous->update(S);  // the initial porosity (snapshots, checks)
  S.particles.shrink_to_fit();  // particles were appended one by one: drop the growth slack
  return rep;
}

template BuildReport build_system<2>(const Case&, System<2>&, const BuildLimits&);
template BuildReport build_system<3>(const Case&, System<3>&, const BuildLimits&);

}  // namespace sph
