// A closed triangle mesh read from a file (STL, OBJ, OFF or PLY) as a solid body: the set-up fills
// it with fluid, wall layers or a porous medium (docs/case-file.md, `type: mesh`). CGAL does the
// reading (the polygon soup repaired and oriented into a mesh: an STL's repeated vertices are
// merged), the checks (closed, no self-intersection) and the queries (point in the solid by ray
// parity, Side_of_triangle_mesh; nearest surface point, AABB tree). CGAL's headers stay in
// solid_mesh.cpp: one translation unit pays for them.
#pragma once

#include <array>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace sph {

/// What is wrong with a mesh file (the case reader adds the case file's line).
struct MeshError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class SolidMesh {
 public:
  using P3 = std::array<double, 3>;
  /// Applied to the file's coordinates in this order: x' = R (scale x) + offset, R the rotations
  /// about x, then y, then z by rotate_deg (degrees, right-handed).
  struct Transform {
    double scale = 1.0;
    P3 rotate_deg{0.0, 0.0, 0.0};
    P3 offset{0.0, 0.0, 0.0};
  };
  /// Reads, transforms and checks the mesh at `path`; throws MeshError naming the file and what
  /// is wrong (unreadable, not a mesh, open, self-intersecting, empty).
  static std::shared_ptr<const SolidMesh> read(const std::string& path, const Transform& t);
  ~SolidMesh();
  SolidMesh(const SolidMesh&) = delete;
  SolidMesh& operator=(const SolidMesh&) = delete;

  /// Is x strictly inside the solid (a point on the surface is not)?
  bool inside(const P3& x) const;
  /// The point of the surface nearest to x.
  P3 closest(const P3& x) const;
  /// The bounding box of the transformed mesh.
  const P3& lo() const { return lo_; }
  const P3& hi() const { return hi_; }
  std::size_t triangles() const;
  double volume() const;

 private:
  struct Impl;
  SolidMesh();
  std::unique_ptr<Impl> impl_;
  P3 lo_{}, hi_{};
};

/// The signed distance to a solid's surface (negative inside) on a regular grid over its bounding box grown by
/// `reach` on every side, trilinearly interpolated: a region "inside the solid or within a margin of it" asked for
/// every particle every step (resolution regions), where CGAL's exact queries would cost microseconds each. The
/// interpolated distance is exact on the grid's nodes and within half a cell diagonal between them (the distance
/// function is 1-Lipschitz); beyond the grid it reads +infinity (farther than `reach`).
class DistanceGrid {
 public:
  /// `cells` along the longest side of the grown box (the others in proportion, each at least 2).
  static std::shared_ptr<const DistanceGrid> build(const SolidMesh& mesh, double reach, int cells);
  double at(const double* x) const;
  /// The grid's spacing (the interpolation's error is at most √3/2 of it).
  double spacing() const { return h_; }

 private:
  std::array<double, 3> lo_{};
  std::array<int, 3> n_{};
  double h_ = 0.0;
  std::vector<float> d_;
};

}  // namespace sph
