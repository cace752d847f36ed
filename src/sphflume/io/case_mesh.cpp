// A solid from a mesh file (io/case_reader.hpp): `type: mesh` shapes and porous regions, read and
// checked by core/solid_mesh (CGAL) with the case's units and transform (docs/case-file.md).
#include <filesystem>

#include <fmt/format.h>

#include "sphflume/io/case_reader.hpp"

namespace sph::caseio {

std::shared_ptr<const SolidMesh> read_mesh(Reader& r, const Node& n, int dim) {
  if (dim != 3)
    r.fail_at(n, r.key_path("type"),
              "a polygon (meshes are 3D; a 2D bed or structure is a polygon, or a survey line: vertices: {file: F.csv, base: Z})");
  const std::string name = r.required<std::string>("file", "an STL, OBJ, OFF or PLY file of a closed surface (relative to the case file)");
  // the file's length unit, then an extra scale, the rotations and the offset (in m)
  const std::string units = r.choice("units", "m", {"m", "cm", "mm"});
  SolidMesh::Transform t;
  const double scale = r.scalar<double>("scale", 1.0);
  if (!(scale > 0.0)) r.fail_at(r.get("scale"), r.key_path("scale"), "a factor > 0 (applied after the units)");
  t.scale = scale * (units == "mm" ? 1e-3 : units == "cm" ? 1e-2 : 1.0);
  const auto rot = r.vec("rotate", 3, {0.0, 0.0, 0.0});
  const auto off = r.vec("offset", 3, {0.0, 0.0, 0.0});
  for (int i = 0; i < 3; ++i) {
    t.rotate_deg[static_cast<std::size_t>(i)] = rot[static_cast<std::size_t>(i)];
    t.offset[static_cast<std::size_t>(i)] = off[static_cast<std::size_t>(i)];
  }
  namespace fs = std::filesystem;
  fs::path p(name);
  if (p.is_relative()) p = fs::path(r.file()).parent_path() / p;
  try {
    return SolidMesh::read(p.string(), t);
  } catch (const MeshError& e) {
    r.fail_at(r.get("file"), r.key_path("file"),
              fmt::format("a closed, manifold, not self-intersecting surface mesh (relative to the case file's folder): {}", e.what()));
  }
}

}  // namespace sph::caseio
