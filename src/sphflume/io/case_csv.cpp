// Numbers from CSV files a case names (io/case_reader.hpp): wall-motion tables and polygon
// vertices drawn as a survey profile (docs/case-file.md).
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <fmt/format.h>

#include "sphflume/io/case_reader.hpp"

namespace sph::caseio {

CsvNumbers read_csv_numbers(Reader& r, const std::string& key, const std::string& name, int ncol,
                            const std::string& what) {
  namespace fs = std::filesystem;
  CsvNumbers out;
  fs::path p(name);
  if (p.is_relative()) p = fs::path(r.file()).parent_path() / p;
  out.path = p.string();
  std::ifstream in(p);
  if (!in)
    r.fail_at(r.get(key), r.key_path(key),
              fmt::format("a readable CSV file of {} (relative to the case file's folder; tried {})", what, out.path));
  std::string line;
  int ln = 0;
  bool header_seen = false;
  const std::string count = ncol == 2 ? "two" : ncol == 3 ? "three" : std::to_string(ncol);
  while (std::getline(in, line)) {
    ++ln;
    if (const auto hash = line.find('#'); hash != std::string::npos) line.erase(hash);
    for (char& ch : line)
      if (ch == ',' || ch == ';' || ch == '\t') ch = ' ';
    if (line.find_first_not_of(" \r") == std::string::npos) continue;  // blank or comment
    std::istringstream ss(line);
    std::vector<double> row(static_cast<std::size_t>(ncol));
    bool ok = true;
    for (auto& v : row) ok = ok && (ss >> v) && std::isfinite(v);
    std::string rest;
    if (ok && (ss >> rest) && rest != "\r") ok = false;  // a row of more columns than asked
    if (!ok) {
      if (out.rows.empty() && !header_seen) {  // the header
        header_seen = true;
        continue;
      }
      r.fail_at(r.get(key), r.key_path(key),
                fmt::format("rows of {} finite numbers ({}); {} line {} is not", count, what, out.path, ln));
    }
    out.rows.push_back(std::move(row));
    out.lines.push_back(ln);
  }
  return out;
}

std::vector<std::array<double, 2>> read_vertices_file(Reader& r, const Node& n) {
  const Node& v = r.get("vertices");
  Reader q(v, r.file(), r.key_path("vertices"));
  const std::string name = q.required<std::string>("file", "a CSV file of x, z points (relative to the case file)");
  const bool survey = q.has("base");
  const double base = q.scalar<double>("base", 0.0);
  if (survey && !std::isfinite(base)) q.fail_at(q.get("base"), q.key_path("base"), "a finite elevation in m");
  q.finish();
  const CsvNumbers csv = read_csv_numbers(q, "file", name, 2, "x, z");
  std::vector<std::array<double, 2>> out;
  if (!survey) {  // the polygon's vertices, in order
    if (csv.rows.size() < 3) q.fail_at(q.get("file"), q.key_path("file"), fmt::format("at least 3 rows of x, z in {}", csv.path));
    for (const auto& row : csv.rows) out.push_back({row[0], row[1]});
    return out;
  }
  // a survey line (chainage, elevation), closed down to z = base: the bed or structure under it
  if (csv.rows.size() < 2) q.fail_at(q.get("file"), q.key_path("file"), fmt::format("at least 2 rows of x, z in {}", csv.path));
  // (an end of the line on the base itself, a beach's toe on the bed, is one corner, not two)
  if (csv.rows.front()[1] > base) out.push_back({csv.rows.front()[0], base});
  bool above = false;
  for (std::size_t i = 0; i < csv.rows.size(); ++i) {
    const auto& row = csv.rows[i];
    if (i > 0 && !(row[0] > csv.rows[i - 1][0]))
      q.fail_at(q.get("file"), q.key_path("file"),
                fmt::format("a survey line with x strictly increasing; {} line {} goes back to x = {}", csv.path, csv.lines[i], row[0]));
    if (row[1] < base)
      q.fail_at(q.get("base"), q.key_path("base"),
                fmt::format("a base at or below every point of the line; {} line {} has z = {} < base {}", csv.path, csv.lines[i], row[1], base));
    above = above || row[1] > base;
    out.push_back({row[0], row[1]});
  }
  if (!above) q.fail_at(q.get("base"), q.key_path("base"), fmt::format("a base below the line of {} (it encloses nothing)", csv.path));
  if (csv.rows.back()[1] > base) out.push_back({csv.rows.back()[0], base});
  (void)n;
  return out;
}

}  // namespace sph::caseio
