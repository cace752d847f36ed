#include "sphflume/io/case.hpp"
#include "sphflume/io/gauge_type.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include "sphflume/io/case_reader.hpp"
#include "sphflume/schemes/scheme_options.hpp"

namespace sph {
namespace {
using caseio::Reader;
using caseio::read_vertices;


void apply_override(YAML::Node root, const std::string& spec) {
  const auto eq = spec.find('=');
  if (eq == std::string::npos || eq == 0)
    throw InputError(fmt::format("--set '{}': expected KEY=VALUE with a dotted key, e.g. particles.dx=0.005", spec));
  const std::string key = spec.substr(0, eq), value = spec.substr(eq + 1);
  std::vector<std::string> parts;
  std::stringstream ss(key);
  for (std::string p; std::getline(ss, p, '.');) parts.push_back(p);
  YAML::Node cur = root;
  for (std::size_t i = 0; i < parts.size(); ++i) {
    const std::string& p = parts[i];
    const bool last = i + 1 == parts.size();
    YAML::Node next;
    if (cur.IsSequence()) {
      std::size_t idx = 0;
      try { idx = std::stoul(p); } catch (...) {
        throw InputError(fmt::format("--set {}: '{}' indexes a list: expected a number", key, p));
      }
      if (idx >= cur.size()) throw InputError(fmt::format("--set {}: list index {} out of range (the list has {} items)", key, idx, cur.size()));
      next.reset(cur[idx]);
    } else {
      if (!cur.IsMap() && cur.IsDefined() && !cur.IsNull())
        throw InputError(fmt::format("--set {}: '{}' is not a mapping", key, p));
      next.reset(cur[p]);
    }
    YAML::Node parsed;
    if (last) {
      try { parsed = YAML::Load(value); } catch (const YAML::Exception& e) {
        throw InputError(fmt::format("--set {}: cannot read value '{}': {}", key, value, e.msg));
      }
      parsed.SetTag("!set");  // so messages say the value came from the command line
      if (cur.IsSequence()) cur[std::stoul(p)] = parsed; else cur[p] = parsed;
      return;
    }
    if (!next.IsDefined() || next.IsNull()) {
      cur[p] = YAML::Node(YAML::NodeType::Map);
      next.reset(cur[p]);
    }
    cur.reset(next);
  }
}

int axis_index(const std::string& a, int dim) {
  if (a == "x") return 0;
  if (a == "y" && dim == 3) return 1;
  if (a == "z") return dim - 1;
  return -1;
}

ShapeConfig read_shape(const Node& n, const std::string& file, const std::string& path, int dim, double wall_depth) {
  Reader r(n, file, path);
  r.valid({"type", "fill", "min", "max", "vertices", "point", "normal", "thickness", "open_top", "velocity", "motion",
           "toe", "gradient", "top", "back", "survey", "file", "units", "scale", "rotate", "offset"});
  ShapeConfig s;
  s.line = n.line();
  (void)r.required<std::string>("type", "a shape type: box, tank, polygon, plane, slope or mesh");
  s.type = r.choice("type", "", {"box", "tank", "polygon", "plane", "slope", "mesh"});
  s.fill = r.choice("fill", s.type == "tank" || s.type == "plane" || s.type == "slope" ? "wall" : "fluid", {"fluid", "wall"});
  if (s.type == "slope") {  // a beach: the polygon of its wedge or layer
    if (dim != 2) r.fail_at(n, path, "a plane (slopes are 2D only; a 3D beach is a plane shape)");
    std::vector<std::array<double, 2>> wedge;
    s.vertices = caseio::read_slope(r, n, s.fill == "wall" ? wall_depth : 0.0, &wedge, &s.surface, &s.outline);
    if (s.fill == "wall") s.solid = wedge;  // the wedge under the surface line, to its back: no fluid there
    s.type = "polygon";
    s.slope = true;
  }
  const std::size_t d = static_cast<std::size_t>(dim);
  if (s.type == "box" || s.type == "tank") {
    s.min = r.vec("min", d);
    s.max = r.vec("max", d);
    if (s.min.empty()) r.misspelt("min");
    if (s.max.empty()) r.misspelt("max");
    if (s.min.empty() || s.max.empty()) r.fail_at(n, path, "'min' and 'max' corners");
    for (std::size_t i = 0; i < d; ++i)
      if (!(s.max[i] > s.min[i])) r.fail_at(r.get("max"), r.key_path("max"), "max > min in every coordinate");
    if (s.type == "tank") {
      s.open_top = r.scalar<bool>("open_top", true);
      if (s.fill != "wall") r.fail_at(r.get("fill"), r.key_path("fill"), "'wall' (a tank is made of wall particles)");
    }
  } else if (s.type == "polygon" && s.vertices.empty()) {
    if (dim != 2) r.fail_at(n, path, "a box (polygons are 2D only)");
    s.vertices = read_vertices(r, n);
  } else if (s.type == "mesh") {
    s.mesh = caseio::read_mesh(r, n, dim);
  } else if (s.type == "plane") {
    s.point = r.vec("point", d);
    s.normal = r.vec("normal", d);
    s.min = r.vec("min", d);
    s.max = r.vec("max", d);
    for (const char* k : {"point", "normal", "min", "max"})
      if (!r.has(k)) r.misspelt(k);
    if (s.point.empty() || s.normal.empty() || s.min.empty() || s.max.empty())
      r.fail_at(n, path, "'point', 'normal' (pointing into the fluid), and the extent 'min'/'max'");
    double nmax = 0;
    for (double c : s.normal) nmax = std::max(nmax, std::abs(c));
    if (!(nmax > 0)) r.fail_at(r.get("normal"), r.key_path("normal"), "a non-zero normal");
    for (std::size_t i = 0; i < d; ++i)
      if (!(s.max[i] > s.min[i])) r.fail_at(r.get("max"), r.key_path("max"), "max > min in every coordinate");
    s.thickness = r.scalar<double>("thickness", 0.0);
    if (s.thickness < 0) r.fail_at(r.get("thickness"), r.key_path("thickness"), "a thickness >= 0 in m (0 = the wall layers)");
  }
  s.velocity = r.vec("velocity", d, std::vector<double>(d, 0.0));
  if (r.has("motion")) {
    s.motion = r.scalar<std::string>("motion", "");
    if (s.fill != "wall") r.fail_at(r.get("motion"), r.key_path("motion"), "a wall shape (only walls follow a prescribed motion; set fill: wall)");
  }
  r.finish();
  return s;
}

GaugeConfig read_gauge(const Node& n, const std::string& file, const std::string& path, int dim) {
  Reader r(n, file, path);
  r.valid({"name", "type", "point", "x", "start", "end", "points", "axis", "direction", "average_from", "field", "motion", "level", "reach", "film", "neighbours"});
  GaugeConfig g;
  g.line = n.line();
  g.name = r.required<std::string>("name", "a gauge name (used as the CSV file name)");
  for (char c : g.name)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.'))
      r.fail_at(r.get("name"), r.key_path("name"), "a name of letters, digits, '_', '-' or '.'");
  const std::vector<std::string> types = gauge_registry<2>().names();  // (the same types in 3D)
  std::string known;
  for (const auto& t : types) known += (known.empty() ? "" : ", ") + t;
  (void)r.required<std::string>("type", "a gauge type: " + known);
  g.type = r.choice("type", "", types);
  read_gauge_keys(r, g, n, path, dim);
  r.finish();
  return g;
}

/// Every scalar under `n` that reads as a number must be finite (.nan, .inf are refused).
void reject_non_finite(const Reader& r, const Node& n, const std::string& path, int depth = 0) {
  if (depth > 32) return;
  if (n.is_scalar()) {
    double v = 0.0;
    if (n.decode(v) && !std::isfinite(v)) r.fail_at(n, path, fmt::format("a finite number (got {})", n.text()));
  } else if (n.is_sequence()) {
    for (std::size_t i = 0; i < n.size(); ++i) reject_non_finite(r, n[i], fmt::format("{}.{}", path, i), depth + 1);
  } else if (n.is_map()) {
    for (const auto& [k, v] : n.entries()) reject_non_finite(r, v, path + "." + k, depth + 1);
  }
}

/// YAML forbids a key twice in one mapping; yaml-cpp keeps both and its lookups return the first,
/// so a repeated key would be silently ignored. Refused at every nesting level, naming both lines.
/// `budget` bounds the walk (aliases may share subtrees many times over).
void reject_duplicate_keys(const YAML::Node& n, const std::string& file, const std::string& path, int depth,
                           long& budget) {
  if (depth > 64 || --budget < 0) return;
  if (n.IsSequence()) {
    for (std::size_t i = 0; i < n.size(); ++i)
      reject_duplicate_keys(n[i], file, path.empty() ? std::to_string(i) : fmt::format("{}.{}", path, i), depth + 1,
                            budget);
  } else if (n.IsMap()) {
    std::map<std::string, int> first_line;
    for (const auto& kv : n) {
      const std::string key = kv.first.IsScalar() ? kv.first.Scalar() : YAML::Dump(kv.first);
      const std::string full = path.empty() ? key : path + "." + key;
      const int line = kv.first.Mark().line + 1;
      const auto [it, fresh] = first_line.emplace(key, line);
      if (!fresh)
        throw InputError(fmt::format("{}: line {}: duplicate key '{}' (first given at line {}): YAML forbids a key "
                                     "twice in one mapping; keep one of the two (merge their contents)",
                                     file, line, full, it->second));
      reject_duplicate_keys(kv.second, file, full, depth + 1, budget);
    }
  }
}

/// The YAML document as a Node tree (core/node.hpp): lines kept (0 under a --set value), keys
/// plain names. `budget` bounds the copy (aliases may repeat subtrees many times over).
Node to_node(const YAML::Node& y, bool from_set, const std::string& file, const std::string& path, long& budget) {
  if (--budget < 0)
    throw InputError(fmt::format("{}: the document expands to more than 2 million values (aliases?): write it out", file));
  from_set = from_set || y.Tag() == "!set";
  const int line = from_set ? 0 : y.Mark().line + 1;
  if (y.IsScalar()) return Node::scalar(y.Scalar(), line);
  if (y.IsSequence()) {
    Node n = Node::sequence(line);
    for (std::size_t i = 0; i < y.size(); ++i)
      n.push_back(to_node(y[i], from_set, file, path.empty() ? std::to_string(i) : fmt::format("{}.{}", path, i), budget));
    return n;
  }
  if (y.IsMap()) {
    Node n = Node::map(line);
    for (const auto& kv : y) {
      if (!kv.first.IsScalar())
        throw InputError(fmt::format("{}: line {}: '{}': expected keys that are plain names (found a list or mapping "
                                     "used as a key)", file, kv.first.Mark().line + 1, path.empty() ? "the document" : path));
      const std::string k = kv.first.Scalar();
      n.add(k, to_node(kv.second, from_set, file, path.empty() ? k : path + "." + k, budget),
            from_set ? 0 : kv.first.Mark().line + 1);
    }
    return n;
  }
  return y.IsNull() ? Node::null(line) : Node();
}

void canon(const YAML::Node& n, std::string& out) {
  if (n.IsMap()) {
    std::map<std::string, YAML::Node> sorted;
    for (const auto& kv : n) sorted.emplace(kv.first.Scalar(), kv.second);
    out += '{';
    for (const auto& [k, v] : sorted) {
      out += k + ':';
      canon(v, out);
      out += ',';
    }
    out += '}';
  } else if (n.IsSequence()) {
    out += '[';
    for (const auto& e : n) { canon(e, out); out += ','; }
    out += ']';
  } else if (n.IsScalar()) {
    out += '"' + n.Scalar() + '"';
  } else {
    out += '~';
  }
}

/// Canonical text of the document after --set, without time.end (a restart may change it).
std::string fingerprint(const YAML::Node& root) {
  YAML::Node c = YAML::Clone(root);
  if (c.IsMap() && c["time"] && c["time"].IsMap()) c["time"].remove("end");
  std::string out;
  canon(c, out);
  return out;
}

constexpr double kMaxOutputs = 1e7;  // snapshots/gauge rows: more is a typo, not a plan

ProfileConfig read_profile(const Node& n, const std::string& file, const std::string& path) {
  Reader r(n, file, path);
  ProfileConfig p;
  p.type = r.choice("type", "uniform", {"uniform", "parabolic", "log", "table"});
  if (p.type == "uniform") p.u = r.required<double>("u", "the velocity u in m/s");
  if (p.type == "parabolic") p.u_surface = r.required<double>("u_surface", "the surface velocity in m/s");
  if (p.type == "log") {
    p.u_star = r.positive("u_star", 0.0, true);
    p.ks = r.positive("ks", 0.0, true);
  }
  if (p.type == "table") {
    const Node& z = r.get("z");
    const Node& u = r.get("u");
    if (!z.is_sequence() || !u.is_sequence() || z.size() != u.size() || z.size() < 1)
      r.fail_at(n, path, "lists 'z' and 'u' of the same length (heights above the bed and velocities)");
    for (std::size_t i = 0; i < z.size(); ++i) {
      p.z.push_back(r.as<double>(z[i], "z"));
      p.values.push_back(r.as<double>(u[i], "u"));
      if (i > 0 && !(p.z[i] > p.z[i - 1])) r.fail_at(z[i], r.key_path("z"), "increasing heights");
    }
  }
  r.finish();
  return p;
}

OpenBoundaryConfig read_open_boundary(const Node& n, const std::string& file, const std::string& path, int dim) {
  Reader r(n, file, path);
  OpenBoundaryConfig b;
  b.line = n.line();
  (void)r.required<std::string>("type", "inflow or outflow");
  b.type = r.choice("type", "", {"inflow", "outflow"});
  // The zone is a slab x0 <= x < x1 across the whole channel (2D and 3D), its faces the planes
  // x = const, the flow along +x. `normal` (optional) states the face's outward flow direction.
  if (r.has("normal")) {
    const std::vector<double> nv = r.vec("normal", static_cast<std::size_t>(dim));
    double len = 0.0, off = 0.0;
    for (std::size_t d = 0; d < nv.size(); ++d) len += nv[d] * nv[d];
    for (std::size_t d = 1; d < nv.size(); ++d) off = std::max(off, std::abs(nv[d]));
    len = std::sqrt(len);
    const Node& nn = r.get("normal");
    if (!(len > 0.0)) r.fail_at(nn, r.key_path("normal"), "a non-zero vector");
    int axes = 0;
    for (double v : nv) axes += std::abs(v) > 1e-9 * len ? 1 : 0;
    if (axes != 1)
      r.fail_at(nn, r.key_path("normal"), dim == 3 ? "an axis-aligned face: normal [1, 0, 0] (open boundaries are planes x = const with the flow along +x; "
                                                     "a face at an angle is not supported: align the channel with x)"
                                                   : "an axis-aligned face: normal [1, 0] (open boundaries are lines x = const with the flow along +x; "
                                                     "a face at an angle is not supported: align the channel with x)");
    if (!(nv[0] > 0.0) || off > 0.0)
      r.fail_at(nn, r.key_path("normal"), dim == 3 ? "the flow along +x: normal [1, 0, 0] (turn the case so the channel runs along +x)"
                                                   : "the flow along +x: normal [1, 0] (turn the case so the channel runs along +x)");
  }
  const std::vector<double> zone = r.vec("zone", 2);
  if (zone.empty()) r.fail_at(n, r.key_path("zone"), "the zone along x, [x_start, x_end]");
  b.x0 = zone[0];
  b.x1 = zone[1];
  if (!(b.x1 > b.x0)) r.fail_at(r.get("zone"), r.key_path("zone"), "[x_start, x_end] with x_end > x_start");
  b.bed = r.scalar<double>("bed", 0.0);
  b.depth = r.positive("depth", 0.0, true);
  if (b.type == "outflow") {
    b.velocity = r.choice("velocity", "imposed", {"imposed", "frozen", "extrapolated"});
    b.frozen = b.velocity == "frozen";
    b.pressure = r.choice("pressure", b.velocity == "extrapolated" ? "extrapolated" : "frozen",
                          {"frozen", "extrapolated", "hydrostatic", "imposed", "inlet"});
  } else {
    b.velocity = r.choice("velocity", "imposed", {"imposed", "averaged"});
    if (r.has("average_at")) {
      if (b.velocity != "averaged") r.fail_at(r.get("average_at"), r.key_path("average_at"), "velocity: averaged (the node's distance from the inlet line)");
      b.average_at = r.positive("average_at", 0.0);
    }
  }
  if (b.type == "inflow") b.initial_profile = r.scalar<bool>("initial_profile", false);
  if (b.velocity == "imposed" || r.has("profile")) {
    if (!r.has("profile")) r.fail_at(n, r.key_path("profile"), "a velocity profile, e.g. {type: uniform, u: 0.5}");
    b.profile = read_profile(r.get("profile"), file, r.key_path("profile"));
  }
  r.finish();
  return b;
}

namespace {

/// name, dimension, gravity (or a bed slope that tilts it).
void read_frame(Reader& top, const std::string&, Case& c) {
  c.name = top.scalar<std::string>("name", "case");
  c.dimension = top.scalar<int>("dimension", 2);
  if (c.dimension != 2 && c.dimension != 3) top.fail_at(top.get("dimension"), "dimension", "2 or 3");
  const std::size_t d = static_cast<std::size_t>(c.dimension);
  std::vector<double> g_def(d, 0.0);
  g_def[d - 1] = -9.81;
  c.gravity = top.vec("gravity", d, g_def);
  if (top.has("slope")) {  // a channel bed slope S0 = tan(theta): gravity tilted into the bed-aligned frame
    if (top.has("gravity")) top.fail_at(top.get("slope"), "slope", "either 'slope' or 'gravity', not both (slope tilts |g| = 9.81)");
    const double s0 = top.as<double>(top.get("slope"), "slope");
    if (!(std::abs(s0) < 1.0)) top.fail_at(top.get("slope"), "slope", "a bed slope tan(theta) with |slope| < 1");
    const double th = std::atan(s0);
    c.gravity.assign(d, 0.0);
    c.gravity[0] = 9.81 * std::sin(th);
    c.gravity[d - 1] = -9.81 * std::cos(th);
  }
}

/// particles: dx, kernel, h/dx.
void read_particles(Reader& top, const std::string& file, Case& c) {
  {  // particles / kernel
    if (!top.has("particles")) throw InputError(fmt::format("{}: missing required section 'particles' (with at least dx, the particle spacing in m)", file));
    Reader r(top.get("particles"), file, "particles");
    c.dx = r.positive("dx", 0.0, true);
    c.kernel = kernel_from_name(r.choice("kernel", "wendland_c2", {"wendland_c2", "cubic_spline", "quintic_spline"}));
    const auto [lo, hi] = kernel_h_over_dx_range(c.kernel);
    c.h_over_dx = r.in_range("h_over_dx", kernel_default_h_over_dx(c.kernel), lo, hi);
    r.finish();
  }
}

/// domain: the box particles stay in, periodic axes.
void read_domain(Reader& top, const std::string& file, Case& c) {
  const std::size_t d = static_cast<std::size_t>(c.dimension);
  if (top.has("domain")) {
    Reader r(top.get("domain"), file, "domain");
    c.domain_min = r.vec("min", d);
    c.domain_max = r.vec("max", d);
    if (c.domain_min.empty() != c.domain_max.empty())
      r.fail_at(top.get("domain"), "domain", "both 'min' and 'max' corners (or neither)");
    for (std::size_t i = 0; i < c.domain_min.size(); ++i)
      if (!(c.domain_max[i] > c.domain_min[i])) r.fail_at(r.get("max"), "domain.max", "max > min in every coordinate");
    if (r.has("periodic")) {
      const Node& p = r.get("periodic");
      if (!p.is_sequence()) r.fail_at(p, "domain.periodic", "a list of axes, e.g. [x]");
      for (const auto& [unused, a] : p.entries()) {
        const int ax = a.is_scalar() ? axis_index(a.text(), c.dimension) : -1;
        if (ax < 0) r.fail_at(a, "domain.periodic", c.dimension == 2 ? "axes among x, z" : "axes among x, y, z");
        c.periodic.push_back(ax);
      }
      if (!c.periodic.empty() && (c.domain_min.empty() || c.domain_max.empty()))
        r.fail_at(p, "domain.periodic", "'min' and 'max' of the domain too (they set the period)");
    }
    r.finish();
  }
}

/// fluid: density, viscosity, sound speed, EOS.
void read_fluid(Reader& top, const std::string& file, Case& c) {
  {
    if (!top.has("fluid")) throw InputError(fmt::format("{}: missing required section 'fluid'", file));
    Reader r(top.get("fluid"), file, "fluid");
    c.fluid.density = r.positive("density", 1000.0);
    c.fluid.viscosity = r.scalar<double>("viscosity", 1.0e-6);
    if (!(c.fluid.viscosity >= 0)) r.fail_at(r.get("viscosity"), "fluid.viscosity", "a kinematic viscosity >= 0 in m2/s");
    c.fluid.sound_speed = r.scalar<double>("sound_speed", 0.0);
    if (!(c.fluid.sound_speed >= 0)) r.fail_at(r.get("sound_speed"), "fluid.sound_speed", "a speed > 0 in m/s (or 0 for 10 x the reference velocity)");
    c.fluid.reference_velocity = r.scalar<double>("reference_velocity", 0.0);
    if (!(c.fluid.reference_velocity >= 0)) r.fail_at(r.get("reference_velocity"), "fluid.reference_velocity", "a speed >= 0 in m/s (0 = sqrt(2 g H))");
    c.fluid.eos = r.choice("eos", "tait", {"tait", "linear"}) == "tait" ? EosType::Tait : EosType::Linear;
    c.fluid.gamma = r.positive("gamma", 7.0);
    c.fluid.background_pressure = r.scalar<double>("background_pressure", 0.0);
    c.fluid.hydrostatic_init = r.scalar<bool>("hydrostatic_init", true);
    r.finish();
  }
}

/// geometry: the shapes.
void read_geometry(Reader& top, const std::string& file, Case& c) {
  {
    const Node& geo = top.get("geometry");
    if (!geo.given()) throw InputError(fmt::format("{}: missing required section 'geometry' (a list of shapes filled with fluid or wall)", file));
    if (!geo.is_sequence() || geo.size() == 0) top.fail_at(geo, "geometry", "a list of shapes, each starting with '- type: box'");
    c.geometry_line = geo.key_line();  // the line of the key itself, not of the first shape
    for (std::size_t i = 0; i < geo.size(); ++i)
      c.shapes.push_back(read_shape(geo[i], file, fmt::format("geometry.{}", i), c.dimension, wall_layers_for(c) * c.dx));
  }
}

/// time: end, output and snapshot intervals.
void read_time(Reader& top, const std::string& file, Case& c) {
  {
    if (!top.has("time")) throw InputError(fmt::format("{}: missing required section 'time' (end and output_interval in s)", file));
    Reader r(top.get("time"), file, "time");
    c.t_end = r.positive("end", 0.0, true);
    c.output_interval = r.positive("output_interval", c.t_end / 20.0);
    if (c.t_end / c.output_interval > kMaxOutputs)
      r.fail_at(r.get("output_interval"), "time.output_interval",
                fmt::format("at most {:.0e} output times up to time.end = {} s (got {:.3g}): use output_interval >= {:.3g} s",
                            kMaxOutputs, c.t_end, c.t_end / c.output_interval, c.t_end / kMaxOutputs));
    if (r.has("snapshot_interval")) {
      const double si = r.positive("snapshot_interval", c.output_interval);
      const double ratio = si / c.output_interval;
      if (!(std::abs(ratio - std::round(ratio)) <= 1e-6 * ratio) || std::round(ratio) < 1.0)
        r.fail_at(r.get("snapshot_interval"), "time.snapshot_interval",
                  fmt::format("a whole multiple of time.output_interval = {} s (got {} s)", c.output_interval, si));
      c.snapshot_every = std::lround(ratio);
    }
    r.finish();
  }
}

/// gauges: each read by its type (io/gauge_type.hpp), names unique.
void read_gauges(Reader& top, const std::string& file, Case& c) {
  if (top.has("gauges")) {
    const Node& gs = top.get("gauges");
    if (!gs.is_sequence()) top.fail_at(gs, "gauges", "a list of gauges");
    std::set<std::string> names;
    for (std::size_t i = 0; i < gs.size(); ++i) {
      c.gauges.push_back(read_gauge(gs[i], file, fmt::format("gauges.{}", i), c.dimension));
      if (!names.insert(c.gauges.back().name).second)
        top.fail_at(gs[i], fmt::format("gauges.{}.name", i), "a name not used by another gauge");
    }
  }
}

/// open_boundaries: at most one inflow and one outflow zone, in that order along x.
void read_open_boundaries(Reader& top, const std::string& file, Case& c) {
  if (top.has("open_boundaries")) {
    const Node& ob = top.get("open_boundaries");
    if (!ob.is_sequence()) top.fail_at(ob, "open_boundaries", "a list of inflow/outflow zones");
    for (std::size_t i = 0; i < ob.size(); ++i)
      c.open_boundaries.push_back(read_open_boundary(ob[i], file, fmt::format("open_boundaries.{}", i), c.dimension));
    int nin = 0, nout = 0;
    for (const auto& b : c.open_boundaries) (b.type == "inflow" ? nin : nout)++;
    if (nin > 1 || nout > 1) top.fail_at(ob, "open_boundaries", "at most one inflow and one outflow zone");
    if (nin == 1 && nout == 1) {
      const auto& in = c.open_boundaries[c.open_boundaries[0].type == "inflow" ? 0 : 1];
      const auto& out = c.open_boundaries[c.open_boundaries[0].type == "inflow" ? 1 : 0];
      if (!(out.x0 > in.x1)) top.fail_at(ob, "open_boundaries", "the outflow zone downstream (+x) of the inflow zone");
    }
  }
}

/// The motion, phase or scalar a gauge names must be defined.
void check_gauge_fields(Reader&, const std::string& file, Case& c) {
  for (const auto& g : c.gauges)
    if (g.type == "paddle") {
      bool known = false;
      for (const auto& m : c.motions) known |= m.name == g.field;
      if (!known)
        throw InputError(fmt::format("{}: line {}: gauge '{}': motion '{}' is not defined (define it under 'motions')",
                                     file, g.line, g.name, g.field));
    } else if (g.type == "phase") {
      bool known = false;
      for (const auto& ph : c.multiphase.phases) known |= ph.name == g.field;
      if (!known)
        throw InputError(fmt::format("{}: line {}: gauge '{}': field '{}' is not a phase (define it under "
                                     "multiphase.phases)", file, g.line, g.name, g.field));
    } else if (!g.field.empty()) {
      bool known = false;
      for (const auto& sc : c.transport.scalars) known |= sc.name == g.field;
      if (!known)
        throw InputError(fmt::format("{}: line {}: gauge '{}': field '{}' is not a transported scalar (define it under "
                                     "transport.scalars)", file, g.line, g.name, g.field));
    }
}

}  // namespace

Case build_case(const Node& root, const std::string& file) {
  Case c;
  c.file = file;
  Reader top(root, file, "");
  top.valid({"name", "dimension", "gravity", "particles", "domain", "fluid", "scheme", "walls", "geometry", "time",
             "gauges", "forces", "turbulence", "porous", "transport", "multiphase", "motions", "resolution"});
  for (const char* k : {"particles", "fluid", "geometry", "time"})
    if (!top.has(k)) top.misspelt(k);
  read_frame(top, file, c);
  read_particles(top, file, c);
  read_domain(top, file, c);
  read_fluid(top, file, c);
  if (top.has("scheme")) caseio::read_scheme(top.get("scheme"), file, c);
  if (top.has("walls")) caseio::read_walls(top.get("walls"), file, c);
  read_geometry(top, file, c);
  read_time(top, file, c);
  read_gauges(top, file, c);
  read_open_boundaries(top, file, c);
  caseio::read_motions(top, file, c);
  caseio::warn_short_support_with_motions(top, file, c);
  caseio::check_slopes(c);
  if (top.has("turbulence")) caseio::read_turbulence(top.get("turbulence"), file, c);
  if (top.has("porous")) caseio::read_porous(top.get("porous"), file, c);
  if (top.has("transport")) caseio::read_transport(top.get("transport"), file, c);
  if (top.has("multiphase")) caseio::read_multiphase(top.get("multiphase"), file, c);
  if (top.has("resolution")) caseio::read_resolution(root, file, c);
  scheme_types().at(c.scheme.type).check(top, c);  // what the scheme cannot run (schemes/scheme_options.hpp)
  check_gauge_fields(top, file, c);
  if (top.has("forces")) {
    c.forces = top.get("forces");
    if (!c.forces.is_sequence()) top.fail_at(c.forces, "forces", "a list of force terms, each {type: NAME, ...}");
    // the terms read their own keys when the run is set up; non-finite numbers are refused here
    for (std::size_t i = 0; i < c.forces.size(); ++i) reject_non_finite(top, c.forces[i], fmt::format("forces.{}", i));
  }
  top.finish();
  return c;
}

}  // namespace

Case parse_case(const std::string& text, const std::string& name, const std::vector<std::string>& overrides) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw InputError(fmt::format("{}: line {}, column {}: YAML syntax error: {}", name, e.mark.line + 1,
                                 e.mark.column + 1, e.msg));
  }
  if (!root.IsMap()) throw InputError(fmt::format("{}: expected a YAML mapping of sections (particles, fluid, geometry, time, ...)", name));
  long budget = 1'000'000;
  reject_duplicate_keys(root, name, "", 0, budget);
  try {
    for (const auto& o : overrides) apply_override(root, o);
  } catch (const YAML::Exception& e) {
    throw InputError(fmt::format("--set: {}", e.msg));
  }
  try {
    long nodes = 2'000'000;
    const Node tree = to_node(root, false, name, "", nodes);
    Case c = build_case(tree, name);
    c.fingerprint = fingerprint(root);
    return c;
  } catch (const YAML::Exception& e) {
    throw InputError(fmt::format("{}: line {}: {}", name, e.mark.line + 1, e.msg));
  } catch (const std::invalid_argument& e) {
    throw InputError(fmt::format("{}: {}", name, e.what()));
  }
}

Case load_case(const std::string& path, const std::vector<std::string>& overrides) {
  std::ifstream in(path);
  if (!in) throw InputError(fmt::format("{}: cannot open the case file (check the path)", path));
  std::stringstream ss;
  ss << in.rdbuf();
  return parse_case(ss.str(), path, overrides);
}

int wall_layers_for(const Case& c) {
  if (c.walls.layers > 0) return c.walls.layers;
  const double support = kernel_support_factor(c.kernel) * c.h_over_dx;  // in units of dx
  return static_cast<int>(std::ceil(support - 1e-9));
}

}  // namespace sph
