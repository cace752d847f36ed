// The `resolution:` section (io/case_reader.hpp): refined regions of a case (variable resolution,
// docs/numerics.md §14, docs/case-file.md), and the refusal of the models the levels cannot
// serve yet, naming the line of each.
#include <fmt/format.h>

#include "sphflume/io/case_reader.hpp"

namespace sph {
namespace caseio {
namespace {

/// The line of root[a][b] (or of root[a] when b is empty; 0 when absent).
int line_of(const Node& root, const char* a, const char* b = "") {
  const Node& n = root[a];
  if (!n.defined()) return 0;
  if (*b == '\0' || !n.is_map()) return n.key_line();
  const Node& m = n[b];
  return m.defined() ? m.key_line() : n.key_line();
}

/// Refuse a model the resolution levels cannot serve yet: the `resolution` line, the model's
/// line and what to do.
[[noreturn]] void refuse(const std::string& file, int res_line, int line, const std::string& what) {
  throw InputError(fmt::format("{}: line {}: 'resolution': refined regions cannot yet be combined with {} (line {}); "
                               "run it with one resolution (remove 'resolution') or without that model "
                               "(docs/numerics.md §14 lists what the levels serve)",
                               file, res_line, what, line));
}

void check_models(const Node& root, const std::string& file, const Case& c) {
  const int rl = c.resolution.line;
  if (c.scheme.type != "wcsph") refuse(file, rl, line_of(root, "scheme", "type"), fmt::format("scheme.type: {}", c.scheme.type));
}

/// `shape: band` (2D): a band along a slope of the geometry (`slope: N`, the index of a `type: slope`
/// shape, typed or surveyed) or along a porous beach (`porous: N`, the index of a `shape: slope`
/// porous region), `above` and `below` its surface normal to it, between elevations `z_min` and
/// `z_max` (the swash zone: from below the still water to above the highest run-up; a porous
/// beach's surface layer).
RegionConfig read_band(Reader& q, const Node& n, const Case& c) {
  if (c.dimension != 2) q.fail_at(q.get("shape"), q.key_path("shape"), "box or circle (a band along a slope is 2D)");
  (void)q.choice("shape", "band", {"band"});
  RegionConfig g;
  g.type = "band";
  if (q.has("porous") && !q.has("slope")) {
    const char* what = "the index of a `shape: slope` region in `porous.regions` (0-based), e.g. porous: 0";
    const double idx = q.required<double>("porous", what);
    const auto k = static_cast<std::size_t>(std::max(idx, 0.0));
    if (idx < 0.0 || idx != static_cast<double>(k) || k >= c.porous.regions.size() || c.porous.regions[k].surface.size() < 2)
      q.fail_at(q.get("porous"), q.key_path("porous"), what);
    g.vertices = c.porous.regions[k].surface;
  } else {
    const char* what = "the index of a `type: slope` shape in `geometry` (0-based), e.g. slope: 2 "
                       "(or `porous: N`, a `shape: slope` porous region)";
    const double idx = q.required<double>("slope", what);
    const auto k = static_cast<std::size_t>(std::max(idx, 0.0));
    if (idx < 0.0 || idx != static_cast<double>(k) || k >= c.shapes.size() || !c.shapes[k].slope)
      q.fail_at(q.get("slope"), q.key_path("slope"), what);
    g.vertices = c.shapes[k].surface;
  }
  g.above = q.positive("above", 0.0, true);
  g.below = q.positive("below", 0.0, true);
  g.z_min = q.scalar<double>("z_min", g.vertices.front()[1]);
  g.z_max = q.scalar<double>("z_max", g.vertices.back()[1]);
  if (!(g.z_max > g.z_min)) q.fail_at(q.has("z_max") ? q.get("z_max") : n, q.key_path("z_max"), "z_max > z_min");
  // `follow: waterline`: the band's elevations follow the waterline on its line during the run
  g.follow_waterline = q.choice("follow", "none", {"none", "waterline"}) == "waterline";
  if (g.follow_waterline) {
    g.waterline_below = q.positive("waterline_below", 0.0, true);
    g.waterline_above = q.positive("waterline_above", 0.0, true);
  } else {
    for (const char* k : {"waterline_below", "waterline_above"})
      if (q.has(k)) q.fail_at(q.get(k), q.key_path(k), "no waterline window without `follow: waterline`");
  }
  return g;
}

}  // namespace

void read_resolution(const Node& root, const std::string& file, Case& c) {
  const Node& n = root["resolution"];
  Reader r(n, file, "resolution");
  ResolutionConfig& res = c.resolution;
  res.line = n.key_line();
  if (!r.has("regions")) r.misspelt("regions");
  const Node& regs = r.get("regions");
  if (!regs.is_sequence() || regs.size() == 0)
    r.fail_at(regs.defined() ? regs : n, "resolution.regions",
              "a list of refined regions, e.g. [{shape: box, min: [0.2, 0.1], max: [0.8, 0.3], level: 1}]");
  for (std::size_t i = 0; i < regs.size(); ++i) {
    Reader q(regs[i], file, fmt::format("resolution.regions.{}", i));
    ResolutionRegionConfig g;
    g.line = regs[i].line();
    if (q.scalar<std::string>("shape", "box") == "band")
      g.region = read_band(q, regs[i], c);
    else
      g.region = read_region(q, regs[i], c.dimension, c.dx);  // (a mesh region's distance grid at the case's spacing)
    const double level = q.in_range("level", 1.0, 1.0, 3.0);
    if (level != static_cast<int>(level)) q.fail_at(q.get("level"), q.key_path("level"), "a whole number of halvings: 1, 2 or 3");
    g.level = static_cast<int>(level);
    q.finish();
    res.regions.push_back(g);
  }
  const double relax = r.in_range("relax", 300.0, 0.0, 100000.0);
  if (relax != static_cast<int>(relax)) r.fail_at(r.get("relax"), "resolution.relax", "a whole number of iterations, 0 to 100000");
  res.relax_iterations = static_cast<int>(relax);
  const double settle = r.in_range("settle", 10.0, 0.0, 1000.0);
  if (settle != static_cast<int>(settle)) r.fail_at(r.get("settle"), "resolution.settle", "a whole number of iterations, 0 to 1000");
  res.settle_iterations = static_cast<int>(settle);
  // the cell list's cells: level 0's support (each cell's 3^D stencil) or the finest pairs' (each
  // cell's stencil narrowed to its own pairs; docs/numerics.md §14 has where each is faster)
  const std::string cells = r.choice("cells", "levels", {"levels", "level0", "finest"});
  res.cells = cells == "finest" ? CellLayout::Finest : cells == "levels" ? CellLayout::Levels : CellLayout::Level0;
  res.multirate = r.scalar<bool>("multirate", false);
  if (res.multirate) {
    res.multirate_line = r.get("multirate").key_line();
    if (c.scheme.integrator != Integrator::Symplectic)
      r.fail_at(r.get("multirate"), "resolution.multirate",
                fmt::format("false with scheme.integrator: {} (line {}): the multirate step is symplectic; set "
                            "scheme.integrator: symplectic", c.scheme.integrator == Integrator::Verlet ? "verlet"
                            : c.scheme.integrator == Integrator::Dual ? "dual" : "predictor_corrector",
                            line_of(root, "scheme", "integrator")));
  }
  r.finish();
  check_models(root, file, c);
}

}  // namespace caseio
}  // namespace sph
