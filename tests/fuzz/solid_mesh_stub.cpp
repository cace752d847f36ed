// The fuzz target's SolidMesh (core/solid_mesh.hpp): the fuzzer drives the case reader with YAML,
// not mesh files, and CGAL under the sanitizers would triple the target's build; a `type: mesh`
// shape (or a `shape: mesh` region) reaches this read, which refuses it as an unreadable file
// would (an InputError at `file`), so the reader's error path is what is fuzzed. The engine builds core/solid_mesh.cpp.
#include "sphflume/core/solid_mesh.hpp"

namespace sph {
struct SolidMesh::Impl {};
SolidMesh::SolidMesh() = default;
SolidMesh::~SolidMesh() = default;
std::shared_ptr<const SolidMesh> SolidMesh::read(const std::string& path, const Transform&) {
  throw MeshError(path + ": mesh files are not read by the fuzz target");
}
bool SolidMesh::inside(const P3&) const { return false; }
SolidMesh::P3 SolidMesh::closest(const P3& x) const { return x; }
std::size_t SolidMesh::triangles() const { return 0; }
double SolidMesh::volume() const { return 0.0; }
// (a mesh region's grid: never built, read() having refused the file)
std::shared_ptr<const DistanceGrid> DistanceGrid::build(const SolidMesh&, double, int) { return nullptr; }
double DistanceGrid::at(const double*) const { return 1e300; }
}  // namespace sph
