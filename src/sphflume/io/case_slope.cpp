// `type: slope` shapes and `shape: slope` porous regions (2D): a beach given by its toe, its
// gradient and its top, or by a survey line, made into the polygon the geometry and the porosity
// field already know.
#include <cmath>
#include <sstream>

#include <fmt/format.h>

#include "sphflume/io/case_reader.hpp"

namespace sph::caseio {

namespace {
/// `survey: {file: F.csv}`: the slope's surface line from a survey (chainage x strictly increasing,
/// elevation z at or above the first point's, the toe's), closed down to the toe's level to `back`.
std::vector<std::array<double, 2>> read_survey_slope(Reader& r, std::vector<std::array<double, 2>>* wedge,
                                                     std::vector<std::array<double, 2>>* surface,
                                                     std::vector<std::array<double, 2>>* outline) {
  for (const char* k : {"toe", "gradient", "top", "thickness"})
    if (r.has(k))
      r.fail_at(r.get(k), r.key_path(k), "no '" + std::string(k) + "' beside 'survey' (the survey line is the slope's surface; "
                "a layer of given thickness needs toe, gradient and top)");
  const Node& sv = r.get("survey");
  Reader q(sv, r.file(), r.key_path("survey"));
  const std::string name = q.required<std::string>("file", "a CSV file of the surface's x, z points (relative to the case file)");
  q.finish();
  const CsvNumbers csv = read_csv_numbers(q, "file", name, 2, "x, z");
  if (csv.rows.size() < 2) q.fail_at(q.get("file"), q.key_path("file"), fmt::format("at least 2 rows of x, z in {}", csv.path));
  std::vector<std::array<double, 2>> line;
  const double z0 = csv.rows.front()[1];
  for (std::size_t i = 0; i < csv.rows.size(); ++i) {
    const auto& row = csv.rows[i];
    if (i > 0 && !(row[0] > csv.rows[i - 1][0]))
      q.fail_at(q.get("file"), q.key_path("file"),
                fmt::format("a survey line with x strictly increasing; {} line {} goes back to x = {}", csv.path, csv.lines[i], row[0]));
    if (i > 0 && !(row[1] > z0))
      q.fail_at(q.get("file"), q.key_path("file"),
                fmt::format("a slope rising from its toe (the first point); {} line {} has z = {}, not above the toe's {}",
                            csv.path, csv.lines[i], row[1], z0));
    line.push_back({row[0], row[1]});
  }
  const double back = r.scalar<double>("back", line.back()[0]);
  if (!(back >= line.back()[0]))
    r.fail_at(r.get("back"), r.key_path("back"), fmt::format("an x at or beyond the survey's last point ({:.6g})", line.back()[0]));
  if (surface) *surface = line;
  std::vector<std::array<double, 2>> v = line;  // the wedge under the line, to the vertical at `back`
  if (back > line.back()[0]) v.push_back({back, line.back()[1]});
  v.push_back({back, z0});
  if (wedge) *wedge = v;
  if (outline) *outline = back > line.back()[0] ? v : line;  // (a crest: over it and down the back face)
  return v;
}
}  // namespace

std::vector<std::array<double, 2>> read_slope(Reader& r, const Node& n, double default_thickness,
                                              std::vector<std::array<double, 2>>* wedge,
                                              std::vector<std::array<double, 2>>* surface,
                                              std::vector<std::array<double, 2>>* outline) {
  if (r.has("survey")) return read_survey_slope(r, wedge, surface, outline);
  for (const char* k : {"toe", "gradient", "top"})
    if (!r.has(k)) r.misspelt(k);
  if (!r.has("toe") || !r.has("gradient") || !r.has("top"))
    r.fail_at(n, r.key_path("type"),
              "a slope: 'toe' [x, z], 'gradient' (rise/run, or '1:2.08') and 'top' (z of its top), or 'survey: {file: F.csv}'");
  const std::vector<double> toe = r.vec("toe", 2);
  double m = 0.0;  // rise over run
  const Node& gn = r.get("gradient");
  if (!gn.decode(m)) {
    std::string t = gn.text();
    const auto colon = t.find(':');
    double a = 0.0, b = 0.0;
    if (colon != std::string::npos) {
      std::istringstream sa(t.substr(0, colon)), sb(t.substr(colon + 1));
      if (sa >> a && sb >> b && a > 0.0 && b > 0.0) m = a / b;
    }
  }
  if (!(m > 0.0) || !std::isfinite(m) || m > 100.0)
    r.fail_at(gn, r.key_path("gradient"), "a rise over run in (0, 100] (0.48) or a ratio '1:2.08' (rise:run)");
  const double top = r.required<double>("top", "the z of the slope's top [m]");
  if (!(top > toe[1])) r.fail_at(r.get("top"), r.key_path("top"), fmt::format("a top above the toe (z > {})", toe[1]));
  const double t = r.scalar<double>("thickness", default_thickness);
  if (!(t >= 0.0)) r.fail_at(r.get("thickness"), r.key_path("thickness"), "a layer thickness >= 0 in m, normal to the slope (0: a solid wedge)");
  const double x1 = toe[0] + (top - toe[1]) / m;
  const double back = r.scalar<double>("back", x1);
  if (!(back >= x1)) r.fail_at(r.get("back"), r.key_path("back"), fmt::format("an x at or beyond the top of the slope ({:.6g})", x1));
  std::vector<std::array<double, 2>> v = {{toe[0], toe[1]}, {x1, top}};  // the wedge, to the vertical at `back`
  if (back > x1) v.push_back({back, top});
  v.push_back({back, toe[1]});
  if (wedge) *wedge = v;
  if (surface) *surface = {{toe[0], toe[1]}, {x1, top}};
  if (outline) *outline = back > x1 ? v : std::vector<std::array<double, 2>>{{toe[0], toe[1]}, {x1, top}};
  if (t == 0.0) return v;
  // a layer of normal thickness t under the surface line (an armour layer), cut along the toe's
  // level and normal to the slope at its top: width t / sin(alpha) along the bed
  const double sa = m / std::sqrt(1.0 + m * m), ca = 1.0 / std::sqrt(1.0 + m * m);
  return {{toe[0], toe[1]}, {x1, top}, {x1 + t * sa, top - t * ca}, {toe[0] + t / sa, toe[1]}};
}

void check_slopes(const Case& c) {
  std::vector<const ShapeConfig*> tanks;
  for (const auto& s : c.shapes)
    if (s.type == "tank") tanks.push_back(&s);
  if (tanks.empty()) return;
  for (std::size_t i = 0; i < c.shapes.size(); ++i) {
    const auto& s = c.shapes[i];
    if (!s.slope) continue;
    bool inside = false;
    for (const auto* t : tanks) {
      bool in = true;
      for (const auto& v : {s.surface.front(), s.surface.back()})  // the surface line's ends (a layer may run on into the tank's wall)
        for (int d = 0; d < 2; ++d) {
          const std::size_t k = d == 0 ? 0 : t->min.size() - 1;
          in &= v[static_cast<std::size_t>(d)] >= t->min[k] - c.dx && v[static_cast<std::size_t>(d)] <= t->max[k] + c.dx;
        }
      inside |= in;
    }
    if (!inside)
      throw InputError(fmt::format("{}: line {}: geometry.{}: the slope (from x = {:.4g} to {:.4g}, z = {:.4g} to {:.4g}) "
                                   "reaches outside the tank: move its toe, lower its top or shorten 'back'",
                                   c.file, s.line, i, s.surface.front()[0], s.surface.back()[0], s.surface.front()[1],
                                   s.surface.back()[1]));
  }
}

}  // namespace sph::caseio
