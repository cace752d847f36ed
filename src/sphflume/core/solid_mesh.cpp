// A closed triangle mesh as a solid body (core/solid_mesh.hpp), on CGAL 5 (Debian libcgal-dev).
#include "sphflume/core/solid_mesh.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <filesystem>

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/IO/polygon_mesh_io.h>
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Polygon_mesh_processing/triangulate_faces.h>
#include <CGAL/Side_of_triangle_mesh.h>
#include <CGAL/Surface_mesh.h>
#include <fmt/format.h>

namespace sph {

namespace {
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Mesh = CGAL::Surface_mesh<Point>;
using Primitive = CGAL::AABB_face_graph_triangle_primitive<Mesh>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;
namespace PMP = CGAL::Polygon_mesh_processing;

/// R = Rz Ry Rx of the angles in degrees.
std::array<std::array<double, 3>, 3> rotation(const SolidMesh::P3& deg) {
  const double pi = std::acos(-1.0);
  const double a = deg[0] * pi / 180.0, b = deg[1] * pi / 180.0, c = deg[2] * pi / 180.0;
  const double ca = std::cos(a), sa = std::sin(a), cb = std::cos(b), sb = std::sin(b), cc = std::cos(c), sc = std::sin(c);
  return {{{cc * cb, cc * sb * sa - sc * ca, cc * sb * ca + sc * sa},
           {sc * cb, sc * sb * sa + cc * ca, sc * sb * ca - cc * sa},
           {-sb, cb * sa, cb * ca}}};
}
}  // namespace

struct SolidMesh::Impl {
  Mesh mesh;
  Tree tree;
  std::unique_ptr<CGAL::Side_of_triangle_mesh<Mesh, Kernel>> side;
};

SolidMesh::SolidMesh() : impl_(std::make_unique<Impl>()) {}
SolidMesh::~SolidMesh() = default;

std::shared_ptr<const SolidMesh> SolidMesh::read(const std::string& path, const Transform& t) {
  if (!std::filesystem::is_regular_file(path)) throw MeshError(fmt::format("{}: no such file", path));
  std::shared_ptr<SolidMesh> s(new SolidMesh());
  Mesh& m = s->impl_->mesh;
  // (the soup is repaired, its duplicate points merged, oriented and made a mesh; false where it
  // cannot be: a non-manifold edge or vertex, or not a mesh file at all)
  if (!CGAL::IO::read_polygon_mesh(path, m) || m.number_of_faces() == 0)
    throw MeshError(fmt::format("{}: not a readable manifold surface mesh (STL, OBJ, OFF or PLY): the file could not "
                                "be read, is empty, or has non-manifold edges or vertices",
                                path));
  if (!CGAL::is_triangle_mesh(m)) PMP::triangulate_faces(m);
  std::size_t border = 0;
  for (const auto h : m.halfedges()) border += m.is_border(h) ? 1 : 0;
  if (border > 0)
    throw MeshError(fmt::format("{}: an open mesh ({} border edges): a solid needs a closed surface (close the holes "
                                "in the CAD tool, or export the solid, not a surface)",
                                path, border));
  if (!(t.scale > 0.0) || !std::isfinite(t.scale)) throw MeshError(fmt::format("{}: scale must be > 0", path));
  const auto R = rotation(t.rotate_deg);
  for (const auto v : m.vertices()) {
    const Point& p = m.point(v);
    const double q[3] = {t.scale * p.x(), t.scale * p.y(), t.scale * p.z()};
    double o[3];
    for (int i = 0; i < 3; ++i) o[i] = R[i][0] * q[0] + R[i][1] * q[1] + R[i][2] * q[2] + t.offset[i];
    m.point(v) = Point(o[0], o[1], o[2]);
  }
  if (PMP::does_self_intersect(m))
    throw MeshError(fmt::format("{}: the surface intersects itself: a solid needs a surface that does not cross itself",
                                path));
  const auto box = CGAL::bbox_3(m.points().begin(), m.points().end());
  s->lo_ = {box.xmin(), box.ymin(), box.zmin()};
  s->hi_ = {box.xmax(), box.ymax(), box.zmax()};
  s->impl_->tree.insert(faces(m).first, faces(m).second, m);
  s->impl_->tree.accelerate_distance_queries();
  s->impl_->side = std::make_unique<CGAL::Side_of_triangle_mesh<Mesh, Kernel>>(s->impl_->tree);
  return s;
}

bool SolidMesh::inside(const P3& x) const {
  return (*impl_->side)(Point(x[0], x[1], x[2])) == CGAL::ON_BOUNDED_SIDE;
}

SolidMesh::P3 SolidMesh::closest(const P3& x) const {
  const Point p = impl_->tree.closest_point(Point(x[0], x[1], x[2]));
  return {p.x(), p.y(), p.z()};
}

std::size_t SolidMesh::triangles() const { return impl_->mesh.number_of_faces(); }

double SolidMesh::volume() const { return std::abs(PMP::volume(impl_->mesh)); }

std::shared_ptr<const DistanceGrid> DistanceGrid::build(const SolidMesh& mesh, double reach, int cells) {
  auto g = std::shared_ptr<DistanceGrid>(new DistanceGrid());
  double longest = 0.0;
  for (int d = 0; d < 3; ++d) longest = std::max(longest, mesh.hi()[d] - mesh.lo()[d] + 2.0 * reach);
  g->h_ = longest / cells;
  std::size_t total = 1;
  for (int d = 0; d < 3; ++d) {
    g->lo_[d] = mesh.lo()[d] - reach;
    g->n_[d] = std::max(2, static_cast<int>(std::ceil((mesh.hi()[d] + reach - g->lo_[d]) / g->h_)) + 1);
    total *= static_cast<std::size_t>(g->n_[d]);
  }
  g->d_.resize(total);
  for (int k = 0; k < g->n_[2]; ++k)  // (serially: CGAL's queries are not promised thread-safe)
    for (int j = 0; j < g->n_[1]; ++j)
      for (int i = 0; i < g->n_[0]; ++i) {
        const SolidMesh::P3 x{g->lo_[0] + i * g->h_, g->lo_[1] + j * g->h_, g->lo_[2] + k * g->h_};
        const auto c = mesh.closest(x);
        const double dist = std::sqrt((x[0] - c[0]) * (x[0] - c[0]) + (x[1] - c[1]) * (x[1] - c[1]) + (x[2] - c[2]) * (x[2] - c[2]));
        g->d_[(static_cast<std::size_t>(k) * g->n_[1] + j) * g->n_[0] + i] = static_cast<float>(mesh.inside(x) ? -dist : dist);
      }
  return g;
}

double DistanceGrid::at(const double* x) const {
  int c[3];
  double f[3];
  for (int d = 0; d < 3; ++d) {
    const double u = (x[d] - lo_[d]) / h_;
    if (!(u >= 0.0) || u > n_[d] - 1) return std::numeric_limits<double>::infinity();
    c[d] = std::min(static_cast<int>(u), n_[d] - 2);
    f[d] = u - c[d];
  }
  double v = 0.0;
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 2; ++i) {
        const double w = (i ? f[0] : 1.0 - f[0]) * (j ? f[1] : 1.0 - f[1]) * (k ? f[2] : 1.0 - f[2]);
        v += w * d_[(static_cast<std::size_t>(c[2] + k) * n_[1] + (c[1] + j)) * n_[0] + (c[0] + i)];
      }
  return v;
}

}  // namespace sph
