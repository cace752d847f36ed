// The lattice fill of a case's shapes (setup/fill.hpp).
#include "sphflume/setup/fill.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>

#include "sphflume/core/refinement.hpp"
#include "sphflume/physics/resolution.hpp"
#include "sphflume/setup/shape_lattice.hpp"

namespace sph {
using namespace setup_detail;
namespace {

/// A wall slope (2D): rows of particles parallel to its outline (s.outline, from the toe: its face,
/// one segment for a typed slope, a survey's polyline otherwise, then the crest and the back face
/// when `back` lies beyond the top), dx apart along it, at depths
/// (k + 1/2) dx, k < layers (as a flat wall's lattice, turned with the slope); none below the
/// toe's level (the bed's walls are there; the rows reach down to it); and the toe's seal below them. Along a polyline the
/// positions run on the arc length, each row point offset along its segment's normal; where
/// rows of two segments crowd at a concave bend, a point closer than dx/2 to an earlier one is
/// left out. With a crest and a back face, a point nearer another segment than its own depth is left
/// to that segment's rows, so that the corners hold one lattice (the crest's and the back face's rows
/// overlapped under the landward corner: validation/overtopping_dike/README.md).
void slope_wall_rows(const ShapeConfig& s, std::uint32_t si, double dx, int layers, FillPoints<2>& f) {
  const auto& sf = s.outline;
  const double ax = sf[0][0], az = sf[0][1];
  std::vector<double> cum(sf.size(), 0.0);  // the arc length at each point
  for (std::size_t j = 1; j < sf.size(); ++j) {
    const double tx = sf[j][0] - sf[j - 1][0], tz = sf[j][1] - sf[j - 1][1];
    cum[j] = cum[j - 1] + std::sqrt(tx * tx + tz * tz);
  }
  const double total = cum.back();
  const std::size_t first = f.wall_x.size();
  const long nalong = std::lround(std::floor(total / dx));
  for (int k = 0; k < layers; ++k)
    for (long i = 0, j = 0; i < nalong; ++i) {
      const double a = (static_cast<double>(i) + 0.5) * dx, dep = (k + 0.5) * dx;
      while (j + 2 < static_cast<long>(sf.size()) && a >= cum[static_cast<std::size_t>(j + 1)]) ++j;
      const auto& p = sf[static_cast<std::size_t>(j)];
      const auto& q = sf[static_cast<std::size_t>(j + 1)];
      const double tx = q[0] - p[0], tz = q[1] - p[1], len = std::sqrt(tx * tx + tz * tz);
      const double ux = tx / len, uz = tz / len;  // along the segment; the normal into the fluid is (-uz, ux)
      const double t = a - cum[static_cast<std::size_t>(j)];
      Vec<2> x, sp;
      sp[0] = p[0] + t * ux;
      sp[1] = p[1] + t * uz;
      x[0] = sp[0] + dep * uz;
      x[1] = std::fma(-dep, ux, sp[1]);  // explicit: GCC fused it here before this code was a function of its own
      // below the bed's surface (the bed's walls are there); a point above it is at least dx/2 from the
      // bed's first layer. Cutting the rows at dx/2 above it instead left a hollow at the toe between the
      // bed and the face, in which fluid settled and, on Jensen's rough 1:1.5 breakwater at dx = 0.01,
      // was torn below 0.7 rho0 at t = 3.54 s (validation/breakwater_jensen/README.md).
      if (x[1] < az - 1e-9 * dx) continue;
      if (sf.size() > s.surface.size()) {  // a crest and a back face: each point to the rows of its nearest segment
        bool other = false;
        for (std::size_t m = 0; m + 1 < sf.size() && !other; ++m) {
          if (static_cast<long>(m) == j) continue;
          const double mx = sf[m + 1][0] - sf[m][0], mz = sf[m + 1][1] - sf[m][1];
          const double l2 = mx * mx + mz * mz;
          double u = ((x[0] - sf[m][0]) * mx + (x[1] - sf[m][1]) * mz) / l2;
          u = std::clamp(u, 0.0, 1.0);
          const double ex = sf[m][0] + u * mx - x[0], ez = sf[m][1] + u * mz - x[1];
          other = ex * ex + ez * ez < dep * dep * (1.0 - 1e-9);  // (a tie stays: the crowding test below takes it)
        }
        if (other) continue;
      }
      if (sf.size() > 2) {  // (a polyline: rows crowd at a concave bend)
        bool crowded = false;
        for (std::size_t e = first; e < f.wall_x.size() && !crowded; ++e) {
          const double ex = f.wall_x[e][0] - x[0], ez = f.wall_x[e][1] - x[1];
          crowded = ex * ex + ez * ez < 0.25 * dx * dx * 0.998;
        }
        if (crowded) continue;
      }
      f.wall_x.push_back(x);
      f.wall_s.push_back(sp);
      f.wall_shape.push_back(si);
    }
  const auto& face = s.surface;  // (the seal is the face's: the crest and the back face meet nothing at an angle)
  double face_len = 0.0;
  for (std::size_t j = 1; j < face.size(); ++j) face_len += std::hypot(face[j][0] - face[j - 1][0], face[j][1] - face[j - 1][1]);
  const double tx = sf[1][0] - ax, tz = sf[1][1] - az, len = std::sqrt(tx * tx + tz * tz);
  const double ux = tx / len, uz = tz / len;  // the first segment's direction (the toe's)
  // the toe's seal: where the rows meet the bed they are cut at an angle and leave the hollow under
  // them open to the corner (a rough 1:1.5 breakwater at dx = 0.02 failed with a particle below
  // the bed level there; water was also trapped under its crest then, since fixed). Lattice
  // points of the hollow deeper than the rows, less than 2 layers above the bed and along the face no
  // further than where the deepest row is cut (plus 2 layers) close it.
  const double top_z = az + 2.0 * layers * dx;
  const double a_cut = ((0.5 + layers * ux) / std::max(uz, 1e-12) + 2.0 * layers) * dx;
  Vec<2> blo, bhi;
  blo[0] = ax;
  bhi[0] = ax + (face.back()[0] - ax) + 2.0 * layers * dx;
  blo[1] = az;
  bhi[1] = std::min(top_z, az + (face.back()[1] - az));
  lattice<2>(blo, bhi, dx, [&](const Vec<2>& x) {
    if (x[1] < az + 0.5 * dx * 0.999 || !inside_polygon(s.solid, x[0], x[1])) return;
    const double px = x[0] - ax, pz = x[1] - az;
    const double along = px * ux + pz * uz, depth = px * uz - pz * ux;  // below the surface line
    if (depth < layers * dx * 0.999 || along < 0.0 || along > std::min(face_len, a_cut)) return;
    Vec<2> sp;
    sp[0] = ax + along * ux;
    sp[1] = az + along * uz;
    f.wall_x.push_back(x);
    f.wall_s.push_back(sp);
    f.wall_shape.push_back(si);
  });
}

/// A mesh's lattice points: fluid, every point inside the solid; wall, the points inside it less
/// than `layers` dx from its surface (the surface layers: a wall deeper than the kernel's support
/// does nothing; the fluid is kept out of the hollow by drop_inside_walls).
template <class Emit>
void mesh_points(const ShapeConfig& s, double dx, int layers, const Vec<3>& lo, const Vec<3>& hi, Emit&& emit) {
  const double depth2 = layers * dx * layers * dx;
  lattice<3>(lo, hi, dx, [&](const Vec<3>& x) {
    const SolidMesh::P3 p{x[0], x[1], x[2]};
    if (!s.mesh->inside(p)) return;
    if (s.fill == "wall") {
      const auto q = s.mesh->closest(p);
      const double d0 = q[0] - p[0], d1 = q[1] - p[1], d2 = q[2] - p[2];
      if (!(d0 * d0 + d1 * d1 + d2 * d2 < depth2)) return;
    }
    emit(x);
  });
}

/// The porous fill zones (Kazemi eq 5.1): the shape regions with phi0 < 1, then the fill boxes.
template <int D>
struct FillZone { int region; Vec<D> lo, hi; double spacing; };

template <int D>
std::vector<FillZone<D>> porous_fill_zones(const Case& c, const PorousMedia<D>* porous) {
  std::vector<FillZone<D>> zones;
  const double dx = c.dx;
  if (porous) {
    for (std::size_t r = 0; r < porous->size(); ++r) {
      const auto& rc = porous->region(r);
      if (!(porous->fill_spacing(r) > 0.0) || !(rc.porosity < 1.0)) continue;
      FillZone<D> z{static_cast<int>(r), {}, {}, porous->fill_spacing(r)};
      if (rc.shape == "box") { z.lo = to_vec<D>(rc.min); z.hi = to_vec<D>(rc.max); }
      else if (rc.mesh) {
        for (int d = 0; d < D; ++d) { z.lo[d] = rc.mesh->lo()[static_cast<std::size_t>(d)]; z.hi[d] = rc.mesh->hi()[static_cast<std::size_t>(d)]; }
      } else {
        for (int d = 0; d < D; ++d) { z.lo[d] = 1e300; z.hi[d] = -1e300; }
        for (const auto& v : rc.vertices)
          for (int d = 0; d < D && d < 2; ++d) { z.lo[d] = std::min(z.lo[d], v[d]); z.hi[d] = std::max(z.hi[d], v[d]); }
      }
      zones.push_back(z);
    }
    for (const auto& f : c.porous.fill)
      zones.push_back({-1, to_vec<D>(f.min), to_vec<D>(f.max), PorousMedia<D>::fill_spacing_of(f.porosity, dx)});
  }
  return zones;
}

/// The fill zone a point belongs to (-1: none).
template <int D>
int zone_of(const std::vector<FillZone<D>>& zones, const PorousMedia<D>* porous, const Vec<D>& x) {
  for (std::size_t k = 0; k < zones.size(); ++k) {
    const auto& z = zones[k];
    bool in = true;
    if (z.region >= 0) in = porous->inside(static_cast<std::size_t>(z.region), x);
    else
      for (int d = 0; d < D; ++d) in &= x[d] >= z.lo[d] && x[d] <= z.hi[d];
    if (in) return static_cast<int>(k);
  }
  return -1;
}

/// The wall points whose surface point lies on a face another wall covers (a solid resting on the floor: its bottom
/// face, and the floor under it). Half a spacing beyond such a surface point, where the fluid's first row would sit,
/// lies a wall point of the covering body. Only fixed walls count, both the covered and the covering: a moving body
/// uncovers what it rested on. The flag is read by the walls' backup alone (docs/numerics.md §14), which would
/// otherwise push the fluid at such a face's foot into the corner the two bodies make. The probe finds a covering body
/// on the same lattice (every shape's points lie on the global dx lattice or their box's); a body off it, a porous
/// region or a slope's rows are not seen as covering. Every layer under a covered face is flagged (the backup reads
/// the first).
template <int D>
std::vector<char> covered_walls(const Case& c, const FillPoints<D>& f) {
  const double dx = c.dx;
  std::vector<char> covered(f.wall_x.size(), 0);
  std::vector<Vec<D>> fixed;
  const auto is_fixed = [&](std::size_t i) { return c.shapes[f.wall_shape[i]].motion.empty(); };
  for (std::size_t i = 0; i < f.wall_x.size(); ++i)
    if (is_fixed(i)) fixed.push_back(f.wall_x[i]);
  if (fixed.empty()) return covered;
  const WallBins<D> bins(fixed, dx);
  for (std::size_t i = 0; i < f.wall_x.size(); ++i) {
    if (!is_fixed(i)) continue;
    const Vec<D> v = f.wall_s[i] - f.wall_x[i];
    const double len = norm(v);
    if (!(len > 0.0)) continue;
    covered[i] = bins.any_within(f.wall_s[i] + (0.5 * dx / len) * v, 0.5 * dx * 0.999) ? 1 : 0;
  }
  return covered;
}

/// refine_fill's complement to dropping the children outside a body: the fine lattice points inside a body whose coarse
/// parent lay outside it (a face off the coarse lattice), which a uniform fine fill has. Each is a lattice neighbour
/// (±dx_l along an axis) of a wall point of its level, inside that point's body (a box or a plain polygon, filled
/// solid; a mesh, within its wall layers' depth: the shapes inside_wall_shape judges by their interior; a tank's
/// inner faces lie on its lattice, and slopes' and planes' rows follow their face), with no wall point within 0.9 dx_l
/// (its lattice neighbours lie dx_l away; a point one level coarser whose cell holds it, at most (√D/4) dx_{l−1} =
/// 0.87 dx_l: neighbouring wall points differ by at most one level). Repeated while points are added (a face up to
/// a coarse spacing beyond the last coarse column; a corner where two such faces meet). The fluid points within half
/// their own spacing of an added wall point are removed, as drop_inside_walls removes fluid from walls.
template <int D>
void add_face_points(const Case& c, int layers, FillPoints<D>& w) {
  const auto judged = [&](const ShapeConfig& s) {
    return s.type == "box" || s.type == "mesh" || (s.type == "polygon" && s.solid.empty());
  };
  const std::size_t first_added = w.wall_x.size();
  std::size_t from = 0;
  const int max_passes = (1 << c.resolution.max_level()) + D + 1;
  for (int pass = 0; pass < max_passes; ++pass) {
    const WallBins<D> bins(w.wall_x, 0.5 * c.dx);  // (the bins' side exceeds every level's 0.9 dx_l)
    std::vector<std::pair<Vec<D>, std::size_t>> found;  // (point, the wall point it neighbours)
    std::map<std::array<long, D>, Vec<D>> seen;         // (each found once, though two neighbours find it)
    for (std::size_t i = from; i < w.wall_x.size(); ++i) {
      const int l = w.wall_level[i];
      const ShapeConfig& shape = c.shapes[w.wall_shape[i]];
      if (l == 0 || !judged(shape)) continue;
      const double dl = c.dx / double(1 << l);
      for (int d = 0; d < D; ++d)
        for (const double sgn : {-1.0, 1.0}) {
          Vec<D> x = w.wall_x[i];
          x[d] += sgn * dl;
          if (!inside_wall_shape<D>(shape, x) || bins.any_within(x, 0.9 * dl)) continue;
          if (shape.type == "mesh" && !(norm(surface_point<D>(shape, x) - x) < layers * c.dx)) continue;  // (mesh_points)
          if (shape.type == "box") {  // (lattice(): a box holds the points whose whole cell it holds)
            bool fits = true;
            for (int e = 0; e < D; ++e) fits &= x[e] - 0.5 * dl >= shape.min[e] - 1e-9 * dl && x[e] + 0.5 * dl <= shape.max[e] + 1e-9 * dl;
            if (!fits) continue;
          }
          std::array<long, D> key;  // cells of dl/2: a duplicate lies in this cell or one beside it
          for (int e = 0; e < D; ++e) key[e] = static_cast<long>(std::floor(x[e] / (0.5 * dl)));
          bool dup = false;
          for (int o = 0; o < (D == 2 ? 9 : 27) && !dup; ++o) {
            auto k = key;
            for (int e = 0, r = o; e < D; ++e, r /= 3) k[e] += r % 3 - 1;
            const auto it = seen.find(k);
            dup = it != seen.end() && norm(it->second - x) < 0.25 * dl;
          }
          if (dup) continue;
          seen.emplace(key, x);
          found.emplace_back(x, i);
        }
    }
    if (found.empty()) break;
    from = w.wall_x.size();
    for (const auto& [x, k] : found) {
      w.wall_x.push_back(x);
      w.wall_s.push_back(surface_point<D>(c.shapes[w.wall_shape[k]], x));
      w.wall_shape.push_back(w.wall_shape[k]);
      w.wall_covered.push_back(0);  // (a face off the lattice: none rests on another body here)
      w.wall_level.push_back(w.wall_level[k]);
    }
  }
  if (w.wall_x.size() == first_added) return;
  const std::vector<Vec<D>> added(w.wall_x.begin() + static_cast<std::ptrdiff_t>(first_added), w.wall_x.end());
  const WallBins<D> bins(added, 0.5 * c.dx);
  std::size_t kept = 0;  // (removed, not flagged: the set-up relaxation reads the points that stay)
  for (std::size_t i = 0; i < w.fluid_x.size(); ++i) {
    const int l = w.fluid_level[i];  // (half its own spacing: under the bins' side at every level)
    if (bins.any_within(w.fluid_x[i], 0.5 * c.dx / double(1 << l) * 0.999)) continue;
    w.fluid_x[kept] = w.fluid_x[i];
    w.fluid_v[kept] = w.fluid_v[i];
    w.fluid_shape[kept] = w.fluid_shape[i];
    w.fluid_half[kept] = w.fluid_half[i];
    w.fluid_level[kept] = w.fluid_level[i];
    w.drop[kept++] = w.drop[i];
  }
  for (auto* v : {&w.fluid_x, &w.fluid_v}) v->resize(kept);
  w.fluid_shape.resize(kept);
  w.fluid_half.resize(kept);
  w.fluid_level.resize(kept);
  w.drop.resize(kept);
}

}  // namespace

template <int D>
FillPoints<D> fill_shapes(const Case& c, int layers, const PorousMedia<D>* porous) {
  FillPoints<D> f;
  const double dx = c.dx;
  const auto zones = porous_fill_zones<D>(c, porous);
  for (std::size_t si = 0; si < c.shapes.size(); ++si) {
    const auto& s = c.shapes[si];
    const Vec<D> v0 = to_vec<D>(s.velocity);
    auto emit = [&](const Vec<D>& x) {
      if (s.fill == "fluid") {
        if (zone_of<D>(zones, porous, x) >= 0) return;  // filled at the zone's spacing below
        f.fluid_x.push_back(x); f.fluid_v.push_back(v0); f.fluid_shape.push_back(static_cast<std::uint32_t>(si));
        f.fluid_half.push_back(0.5 * dx);
      } else {
        f.wall_x.push_back(x);
        f.wall_s.push_back(surface_point<D>(s, x));
        f.wall_shape.push_back(static_cast<std::uint32_t>(si));
      }
    };
    Vec<D> lo, hi;
    shape_box<D>(s, dx, layers, lo, hi);
    if (s.type == "box") {
      lattice<D>(lo, hi, dx, emit);
    } else if (s.type == "tank") {
      lattice_shell<D>(lo, hi, to_vec<D>(s.min), to_vec<D>(s.max), dx, emit);
    } else if (s.type == "polygon" && !s.solid.empty()) {
      if constexpr (D == 2) slope_wall_rows(s, static_cast<std::uint32_t>(si), dx, layers, f);
    } else if (s.type == "polygon") {
      if constexpr (D == 2)
        lattice<2>(lo, hi, dx, [&](const Vec<2>& x) { if (inside_polygon(s.vertices, x[0], x[1])) emit(x); });
    } else if (s.type == "mesh") {
      if constexpr (D == 3) mesh_points(s, dx, layers, lo, hi, emit);
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
      if (s.fill != "fluid" || (s.type != "box" && s.type != "polygon" && s.type != "mesh")) continue;
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
        if (zone_of<D>(zones, porous, x) != static_cast<int>(k)) return;  // outside the zone, or in an earlier one
        if (s.type == "polygon") {
          if constexpr (D == 2) { if (!inside_polygon(s.vertices, x[0], x[1])) return; }
        }
        if (s.type == "mesh") {
          if constexpr (D == 3) { if (!s.mesh->inside({x[0], x[1], x[2]})) return; }
        }
        f.fluid_x.push_back(x); f.fluid_v.push_back(v0); f.fluid_shape.push_back(static_cast<std::uint32_t>(si));
        f.fluid_half.push_back(0.5 * zn.spacing);
      });
    }
  }
  f.wall_covered = covered_walls<D>(c, f);
  return f;
}

template <int D>
void drop_inside_walls(const Case& c, FillPoints<D>& f) {
  const double dx = c.dx;
  // Drop fluid lattice points that fall inside the walls (closer than dx/2 to a wall particle),
  // e.g. a fluid box drawn over a sloping bed.
  std::vector<char>& drop = f.drop;
  drop.assign(f.fluid_x.size(), 0);
  if (!f.wall_x.empty()) {
    const WallBins<D> bins(f.wall_x, dx);
    for (std::size_t i = 0; i < f.fluid_x.size(); ++i) drop[i] = bins.any_within(f.fluid_x[i], 0.5 * dx * 0.999);
  }
  // and every point inside a solid wall box (a gate, a paddle), whose own lattice may leave a point of another
  // lattice (a porous zone's, spacing dx/sqrt(phi)) dx/2 or more from its particles yet inside the body
  for (const auto& s : c.shapes) {
    if (s.fill != "wall" || s.type != "box") continue;
    const Vec<D> lo = to_vec<D>(s.min), hi = to_vec<D>(s.max);
    for (std::size_t i = 0; i < f.fluid_x.size(); ++i) {
      bool in = true;
      for (int d = 0; d < D; ++d) in = in && f.fluid_x[i][d] > lo[d] && f.fluid_x[i][d] < hi[d];
      if (in) drop[i] = 1;
    }
  }
  if constexpr (D == 3) {  // and every point inside a wall mesh (its particles are surface layers)
    for (const auto& s : c.shapes) {
      if (s.fill != "wall" || !s.mesh) continue;
      for (std::size_t i = 0; i < f.fluid_x.size(); ++i)
        if (!drop[i] && s.mesh->inside({f.fluid_x[i][0], f.fluid_x[i][1], f.fluid_x[i][2]})) drop[i] = 1;
    }
  }
  if constexpr (D == 2) {  // slopes whose walls are a layer: no fluid in the hollow under them
    for (const auto& s : c.shapes) {
      if (s.solid.empty()) continue;
      // and none closer than dx/2 to the slope's surface (the lattice does not follow the slope: a
      // point left a fraction of dx above it is thrown off at the first step)
      for (std::size_t i = 0; i < f.fluid_x.size(); ++i) {
        if (drop[i]) continue;
        bool near = false;
        const auto& ol = s.outline;
        for (std::size_t j = 0; j + 1 < ol.size() && !near; ++j) {  // each segment of the outline (face, crest, back)
          const double ax = ol[j][0], az = ol[j][1], tx = ol[j + 1][0] - ax, tz = ol[j + 1][1] - az;
          const double len2 = tx * tx + tz * tz;
          const double px = f.fluid_x[i][0] - ax, pz = f.fluid_x[i][1] - az;
          const double u = std::clamp((px * tx + pz * tz) / len2, 0.0, 1.0);
          const double dxs = px - u * tx, dzs = pz - u * tz;
          near = dxs * dxs + dzs * dzs < 0.25 * dx * dx * 0.998;
        }
        if (near || inside_polygon(s.solid, f.fluid_x[i][0], f.fluid_x[i][1])) drop[i] = 1;
      }
    }
  }
  // Per fluid shape: it must make particles, and at most half of them may fall inside walls.
  {
    std::vector<std::size_t> made(c.shapes.size(), 0), dropped(c.shapes.size(), 0);
    for (std::size_t i = 0; i < f.fluid_x.size(); ++i) { ++made[f.fluid_shape[i]]; dropped[f.fluid_shape[i]] += drop[i] ? 1 : 0; }
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
  if (f.fluid_x.empty())
    throw InputError(fmt::format("{}: line {}: 'geometry': the geometry makes no fluid particles: expected a shape with "
                                 "'fill: fluid' at least dx = {} m wide", c.file, c.geometry_line, dx));

  if (std::count(drop.begin(), drop.end(), 0) == 0)
    throw InputError(fmt::format("{}: every fluid particle lies inside a wall: move the fluid shapes off the walls", c.file));
}

template <int D>
void refine_fill(const Case& c, double support, FillPoints<D>& f) {
  const auto& regs = c.resolution.regions;
  if (regs.empty()) return;
  FillPoints<D> out;
  // bands that follow the waterline start about the still water's (walls take the whole band)
  ResolutionConfig fluid_res = c.resolution;
  {
    std::vector<Vec<D>> kept;
    for (std::size_t i = 0; i < f.fluid_x.size(); ++i)
      if (!f.drop[i]) kept.push_back(f.fluid_x[i]);
    set_waterline_windows<D>(fluid_res, kept.data(), nullptr, kept.size(), c.dx, Communicator{});
  }
  struct Pending { Vec<D> x; double half; int level; };
  std::vector<Pending> stack;
  for (std::size_t i = 0; i < f.fluid_x.size(); ++i) {
    if (f.drop[i]) continue;  // (dropped points stay dropped: they are not carried over)
    stack.assign(1, {f.fluid_x[i], f.fluid_half[i], 0});
    while (!stack.empty()) {
      const Pending p = stack.back();
      stack.pop_back();
      if (p.level < target_level(fluid_res, p.x.c.data(), D)) {
        const auto kids = split_positions<D>(p.x, p.half);
        for (std::size_t k = kids.size(); k-- > 0;) stack.push_back({kids[k], 0.5 * p.half, p.level + 1});
        continue;
      }
      out.fluid_x.push_back(p.x);
      out.fluid_v.push_back(f.fluid_v[i]);
      out.fluid_shape.push_back(f.fluid_shape[i]);
      out.fluid_half.push_back(p.half);
      out.fluid_level.push_back(p.level);
      out.drop.push_back(0);
    }
  }
  // walls: split to the finest level of the regions within a level-0 support (the fluid of a
  // level, which may stray one coarser h beyond its region before it merges, meets walls of its
  // own spacing); the surface point moves with the child along the surface. (Splitting only the
  // layers the finest fluid's support reaches was tried, session 31: Flume B's band 16 % slower,
  // the fine fluid then meeting coarse walls in every cell along the bed: docs/numerics.md §14.)
  out.wall_x.clear();
  out.wall_s.clear();
  out.wall_shape.clear();
  out.wall_covered.clear();
  struct WallPending { Vec<D> x, s; double half; int level; };
  std::vector<WallPending> wstack;
  for (std::size_t i = 0; i < f.wall_x.size(); ++i) {
    int want = 0;
    for (int l = c.resolution.max_level(); l >= 1 && want == 0; --l)
      if (!outside_levels<D>(c.resolution, f.wall_x[i], l, support)) want = l;
    wstack.assign(1, {f.wall_x[i], f.wall_s[i], 0.5 * c.dx, 0});
    while (!wstack.empty()) {
      const WallPending p = wstack.back();
      wstack.pop_back();
      const double depth = norm(p.s - p.x);
      if (p.level < want) {
        Vec<D> n = p.s - p.x;
        const double len = depth;
        if (len > 0.0) n *= 1.0 / len;
        const auto kids = split_positions<D>(p.x, p.half);
        const auto& shape = c.shapes[f.wall_shape[i]];
        for (std::size_t k = kids.size(); k-- > 0;) {
          const Vec<D> t = kids[k] - p.x;
          // a child on or past its body's surface is dropped (a face off the coarse lattice: the parent lies less
          // than dx/4 inside it): the body's fine walls are its fine lattice's points inside it, as a uniform
          // fine fill makes them (its mass was the parent's volume beyond the face)
          if ((len > 0.0 && !(depth - dot(t, n) > 0.0)) || !inside_wall_shape<D>(shape, kids[k])) continue;
          wstack.push_back({kids[k], p.s + (t - dot(t, n) * n), 0.5 * p.half, p.level + 1});
        }
        continue;
      }
      out.wall_x.push_back(p.x);
      out.wall_s.push_back(p.s);
      out.wall_shape.push_back(f.wall_shape[i]);
      out.wall_covered.push_back(f.wall_covered.empty() ? 0 : f.wall_covered[i]);  // (the parent's face)
      out.wall_level.push_back(p.level);
    }
  }
  add_face_points<D>(c, wall_layers_for(c), out);
  f = std::move(out);
}

template FillPoints<2> fill_shapes<2>(const Case&, int, const PorousMedia<2>*);
template FillPoints<3> fill_shapes<3>(const Case&, int, const PorousMedia<3>*);
template void drop_inside_walls<2>(const Case&, FillPoints<2>&);
template void drop_inside_walls<3>(const Case&, FillPoints<3>&);
template void refine_fill<2>(const Case&, double, FillPoints<2>&);
template void refine_fill<3>(const Case&, double, FillPoints<3>&);

}  // namespace sph
