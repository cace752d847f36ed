// Helpers of the case parser (io/case*.cpp) on top of the strict Reader (core/reader.hpp).
#pragma once
#include <array>
#include <string>
#include <vector>

#include "sphflume/core/reader.hpp"
#include "sphflume/io/case.hpp"

namespace sph::caseio {

using sph::Reader;
using sph::edit_distance;

/// Rows of `ncol` finite numbers of a CSV file (io/case_csv.cpp), with their line numbers.
struct CsvNumbers {
  std::string path;  // as opened (relative names: from the case file's folder)
  std::vector<std::vector<double>> rows;
  std::vector<int> lines;
};
/// The CSV file `name`, the value of `key` of r: a first line that does not parse is a header, '#'
/// starts a comment, ',' ';' or tabs separate; an unreadable file or a bad row is an InputError
/// at `key` naming the file and its line (`what` names the columns, e.g. "x, z").
CsvNumbers read_csv_numbers(Reader& r, const std::string& key, const std::string& name, int ncol, const std::string& what);
/// `vertices: {file: F.csv}` (the polygon's x, z vertices in order) or `vertices: {file: F.csv,
/// base: Z}` (a survey line of chainage x strictly increasing and elevation z, closed down to
/// z = Z: the polygon of the bed or structure under it).
std::vector<std::array<double, 2>> read_vertices_file(Reader& r, const Node& n);

/// [x, z] vertices of a polygon under the key `vertices`: a list of points, or a CSV file
/// (read_vertices_file).
inline std::vector<std::array<double, 2>> read_vertices(Reader& r, const Node& n) {
  if (!r.has("vertices")) r.misspelt("vertices");
  const Node& v = r.get("vertices");
  if (v.is_map()) return read_vertices_file(r, n);
  if (!v.is_sequence() || v.size() < 3) r.fail_at(v.defined() ? v : n, r.key_path("vertices"), "a list of at least 3 [x, z] points");
  std::vector<std::array<double, 2>> out;
  for (const auto& [unused, p] : v.entries()) {
    if (!p.is_sequence() || p.size() != 2) r.fail_at(p, r.key_path("vertices"), "[x, z] pairs");
    std::array<double, 2> xz{};
    if (!p[0].decode(xz[0]) || !p[1].decode(xz[1])) r.fail_at(p, r.key_path("vertices"), "[x, z] pairs of numbers");
    out.push_back(xz);
    if (!std::isfinite(out.back()[0]) || !std::isfinite(out.back()[1]))
      r.fail_at(p, r.key_path("vertices"), "[x, z] pairs of finite numbers");
  }
  return out;
}

/// A solid from a mesh file (io/case_mesh.cpp): the keys file (STL, OBJ, OFF or PLY, relative to
/// the case file), units (m | cm | mm), scale, rotate ([x, y, z] degrees, applied in that order)
/// and offset ([x, y, z] m); 3D only. A file that cannot be read, an open, non-manifold or
/// self-intersecting surface is an InputError at `file` naming the file and what is wrong.
std::shared_ptr<const SolidMesh> read_mesh(Reader& r, const Node& n, int dim);

/// A region (RegionConfig) from the keys shape (box | circle | polygon | cylinder | mesh), min/max,
/// center/radius (a cylinder's: x, y and z_min, z_max), vertices, or a mesh's keys (read_mesh) and
/// margin, of the mapping `r` reads; a mesh's distance grid has cells of grid_spacing (0: 64 along
/// its longest side).
RegionConfig read_region(Reader& r, const Node& n, int dim, double grid_spacing = 0.0);
/// The model sections (io/case_models.cpp): `scheme:` (WCSPH keys, or the scheme's own reader),
/// `walls:`, `turbulence:`, `porous:`.
void read_scheme(const Node& n, const std::string& file, Case& c);
void read_walls(const Node& n, const std::string& file, Case& c);
void read_turbulence(const Node& n, const std::string& file, Case& c);
void read_porous(const Node& n, const std::string& file, Case& c);
/// The `transport:` section (scalars) and the `multiphase:` section.
void read_transport(const Node& n, const std::string& file, Case& c);
void read_multiphase(const Node& n, const std::string& file, Case& c);
/// The `resolution:` section (io/case_resolution.cpp): refined regions, and the refusal, with
/// the lines, of a model the levels cannot serve yet. Read after every model section.
void read_resolution(const Node& root, const std::string& file, Case& c);
/// A slope (2D beach) from the keys toe, gradient, top, thickness, back (io/case_slope.cpp): the
/// polygon of a solid wedge (thickness 0) or of a layer of that normal thickness under the surface
/// line from the toe to the top (docs/case-file.md).
/// default_thickness: the layer's thickness when `thickness` is not given (0: a wedge; wall slopes
/// pass their wall layers' depth, since a wall deeper than the kernel support does nothing).
/// wedge: when given, set to the wedge under the surface line to its `back`, whatever the thickness
/// (a wall slope keeps it free of fluid). Or `survey: {file: F.csv}`: the surface line from a survey
/// (x strictly increasing, every z above the first point's, the toe), the wedge under it.
/// surface: when given, set to the surface line from the toe to the top (a band follows it).
/// outline: when given, set to the wedge's exposed line: the surface and, when `back` lies beyond the top, the
/// crest to `back` and the back face down to the toe's level (a wall slope's rows follow it).
std::vector<std::array<double, 2>> read_slope(Reader& r, const Node& n, double default_thickness = 0.0,
                                              std::vector<std::array<double, 2>>* wedge = nullptr,
                                              std::vector<std::array<double, 2>>* surface = nullptr,
                                              std::vector<std::array<double, 2>>* outline = nullptr);
/// Every slope shape lies inside the case's tanks (with dx of slack): an InputError naming its line otherwise.
void check_slopes(const Case& c);
/// The `motions:` section (prescribed wall motions, io/case_motion.cpp), and the check that every
/// shape's `motion:` names one; after the shapes and walls are read.
void read_motions(Reader& top, const std::string& file, Case& c);
/// A case with moving walls whose kernel reaches less than 4 dx (h < 2 dx for Wendland C2): a warning
/// (stderr, summary.json) that the waves it makes lose their crest there, naming the h_over_dx to set.
void warn_short_support_with_motions(Reader& top, const std::string& file, Case& c);

}  // namespace sph::caseio
