// The set-up's lattice and shape helpers (setup/): lattice points of boxes and tank shells, the
// surface point of a wall shape, the box a shape's lattice covers, and wall particles binned for
// the overlap tests. Internal to setup/ (docs/architecture.md, "Set-up").
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "sphflume/core/shapes.hpp"
#include "sphflume/core/vec.hpp"
#include "sphflume/io/case.hpp"

namespace sph::setup_detail {

template <int D>
Vec<D> to_vec(const std::vector<double>& v) {
  Vec<D> out{};
  for (int d = 0; d < D; ++d) out[d] = v[static_cast<std::size_t>(d)];
  return out;
}

inline const char* axis_name(int d, int dim) { return d == dim - 1 ? "z" : d == 0 ? "x" : "y"; }

/// Lattice points min + (i + 1/2) dx inside [lo, hi) along one axis (as a double: no overflow).
inline double lattice_count(double lo, double hi, double dx) {
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
  } else if (s.type == "mesh") {
    if constexpr (D == 3) {
      const auto q = s.mesh->closest({x[0], x[1], x[2]});
      for (int d = 0; d < 3; ++d) p[d] = q[static_cast<std::size_t>(d)];
    }
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

/// Whether x lies inside the solid of a wall shape: a box's, a mesh's or a plain polygon's interior, a tank's walls
/// (outside its inner box). Planes and slopes answer true: their wall points are rows under a face, judged by the
/// depth below it (refine_fill: a split wall point's children must stay inside their body).
template <int D>
bool inside_wall_shape(const ShapeConfig& s, const Vec<D>& x) {
  if (s.type == "tank") {
    for (int d = 0; d < D; ++d)
      if (x[d] < s.min[d] || x[d] > s.max[d]) return true;
    return false;
  }
  if (s.type == "box") {
    for (int d = 0; d < D; ++d)
      if (x[d] < s.min[d] || x[d] > s.max[d]) return false;
    return true;
  }
  if (s.type == "mesh") {
    if constexpr (D == 3) return s.mesh->inside({x[0], x[1], x[2]});
  }
  if (s.type == "polygon" && s.solid.empty()) {
    if constexpr (D == 2) return inside_polygon(s.vertices, x[0], x[1]);
  }
  return true;
}

/// The box whose lattice a shape visits (a tank: with its walls; a polygon or a mesh: its bounding
/// box anchored on the global dx grid so they line up with boxes at 0).
template <int D>
void shape_box(const ShapeConfig& s, double dx, int layers, Vec<D>& lo, Vec<D>& hi) {
  if (s.type == "polygon" || s.type == "mesh") {
    for (int d = 0; d < D; ++d) { lo[d] = 1e300; hi[d] = -1e300; }
    if constexpr (D == 2)
      for (const auto& p : s.vertices)
        for (int d = 0; d < 2; ++d) { lo[d] = std::min(lo[d], p[d]); hi[d] = std::max(hi[d], p[d]); }
    if (s.mesh)
      for (int d = 0; d < D; ++d) { lo[d] = s.mesh->lo()[static_cast<std::size_t>(d)]; hi[d] = s.mesh->hi()[static_cast<std::size_t>(d)]; }
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
inline double total_count(const Case& c, double dx, int layers, std::size_t* largest_i = nullptr) {
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

inline std::string shape_where(const Case& c, std::size_t i) {
  return fmt::format("{}: line {}: 'geometry.{}'", c.file, c.shapes[i].line, i);
}

}  // namespace sph::setup_detail
