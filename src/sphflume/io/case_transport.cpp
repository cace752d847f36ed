// The case file's `transport:` section (transported scalars: concentration, temperature, ...)
// and its `multiphase:` section (a second fluid phase). See docs/case-file.md.
#include <algorithm>
#include <cmath>
#include <set>

#include <muParser.h>

#include "sphflume/io/case_reader.hpp"

namespace sph {

namespace caseio {

RegionConfig read_region(Reader& r, const Node& n, int dim, double grid_spacing) {
  RegionConfig g;
  const std::size_t d = static_cast<std::size_t>(dim);
  g.type = r.choice("shape", "box", {"box", "circle", "polygon", "cylinder", "mesh"});
  if (dim != 3 && (g.type == "cylinder" || g.type == "mesh"))
    r.fail_at(r.get("shape"), r.key_path("shape"), "box, circle or polygon (cylinders and meshes are 3D regions)");
  if (g.type == "box") {
    g.min = r.vec("min", d);
    g.max = r.vec("max", d);
    for (const char* k : {"min", "max"})
      if (!r.has(k)) r.misspelt(k);
    if (g.min.empty() || g.max.empty()) r.fail_at(n, r.key_path("min"), "'min' and 'max' corners of the box");
    for (std::size_t i = 0; i < d; ++i)
      if (!(g.max[i] > g.min[i])) r.fail_at(r.get("max"), r.key_path("max"), "max > min in every coordinate");
  } else if (g.type == "circle") {
    g.center = r.vec("center", d);
    if (g.center.empty()) r.misspelt("center");
    if (g.center.empty()) r.fail_at(n, r.key_path("center"), "the circle's (sphere's) center");
    g.radius = r.positive("radius", 0.0, true);
  } else if (g.type == "cylinder") {  // a vertical axis through center (x, y), from z_min to z_max
    g.center = r.vec("center", 2);
    if (g.center.empty()) r.misspelt("center");
    if (g.center.empty()) r.fail_at(n, r.key_path("center"), "the axis's (x, y), e.g. center: [0.5, 0.5]");
    g.radius = r.positive("radius", 0.0, true);
    g.z_min = r.scalar<double>("z_min", -1e300);
    g.z_max = r.scalar<double>("z_max", 1e300);
    if (!(g.z_max > g.z_min)) r.fail_at(r.get("z_max"), r.key_path("z_max"), "z_max > z_min");
  } else if (g.type == "mesh") {  // inside a closed surface or within `margin` of it
    const auto mesh = read_mesh(r, n, dim);
    g.margin = r.scalar<double>("margin", 0.0);
    if (!(g.margin >= 0.0)) r.fail_at(r.get("margin"), r.key_path("margin"), "a distance >= 0 in m from the surface");
    // the distance on a grid of the case's spacing (its reading within 0.87 of a spacing of the exact one)
    double longest = 0.0;
    for (int k = 0; k < 3; ++k) longest = std::max(longest, mesh->hi()[k] - mesh->lo()[k] + 2.0 * (g.margin + grid_spacing));
    const int cells = grid_spacing > 0.0 ? std::clamp(static_cast<int>(std::ceil(longest / grid_spacing)), 16, 256) : 64;
    g.grid = DistanceGrid::build(*mesh, g.margin + std::max(grid_spacing, longest / cells), cells);
  } else {
    if (dim != 2) r.fail_at(n, r.key_path("shape"), "box, circle, cylinder or mesh (polygons are 2D)");
    g.vertices = read_vertices(r, n);
  }
  return g;
}

namespace {

/// Check an expression of x, y, z now, so that a typo is reported with its line.
void check_expression(Reader& r, const std::string& key, const std::string& expr) {
  try {
    mu::Parser p;
    double x = 0.0, y = 0.0, z = 0.0;
    p.DefineVar("x", &x);
    p.DefineVar("y", &y);
    p.DefineVar("z", &z);
    p.SetExpr(expr);
    (void)p.Eval();
  } catch (const mu::Parser::exception_type& e) {
    r.fail_at(r.get(key), r.key_path(key),
              fmt::format("an expression of x, y, z such as 'exp(-(z-0.5)^2/0.004)' ({} in '{}')", e.GetMsg(), expr));
  }
}

ScalarInitConfig read_init(const Node& n, const std::string& file, const std::string& path, int dim) {
  Reader r(n, file, path);
  ScalarInitConfig s;
  s.line = n.line();
  s.type = r.choice("type", "uniform", {"uniform", "region", "gaussian", "expression"});
  if (s.type == "uniform") {
    s.value = r.required<double>("value", "the value everywhere");
  } else if (s.type == "region") {
    s.value = r.required<double>("value", "the value inside the region");
    s.region = read_region(r, n, dim);
  } else if (s.type == "gaussian") {
    s.value = r.required<double>("value", "the peak value");
    s.center = r.vec("center", static_cast<std::size_t>(dim));
    if (s.center.empty()) r.misspelt("center");
    if (s.center.empty()) r.fail_at(n, r.key_path("center"), "the Gaussian's center");
    s.sigma = r.positive("sigma", 0.0, true);
    if (r.has("axes")) {
      const Node& a = r.get("axes");
      if (!a.is_sequence() || a.size() == 0) r.fail_at(a, r.key_path("axes"), "a list of axes, e.g. [z]");
      for (const auto& [unused, e] : a.entries()) {
        const int ax = e.is_scalar() ? (e.text() == "x" ? 0 : e.text() == "y" && dim == 3 ? 1 : e.text() == "z" ? dim - 1 : -1) : -1;
        if (ax < 0) r.fail_at(e, r.key_path("axes"), dim == 2 ? "axes among x, z" : "axes among x, y, z");
        s.axes.push_back(ax);
      }
    }
  } else {
    s.expression = r.required<std::string>("expression", "an expression of x, y, z");
    check_expression(r, "expression", s.expression);
  }
  r.finish();
  return s;
}

ScalarConfig read_scalar(const Node& n, const std::string& file, const std::string& path, int dim) {
  Reader r(n, file, path);
  ScalarConfig s;
  s.line = n.line();
  s.name = r.required<std::string>("name", "the scalar's name (a field of the snapshots, e.g. concentration)");
  for (char ch : s.name)
    if (!(std::isalnum(static_cast<unsigned char>(ch)) || ch == '_'))
      r.fail_at(r.get("name"), r.key_path("name"), "a name of letters, digits and '_'");
  static const std::set<std::string> reserved = {"porosity", "drag_rate", "inertia", "nu_t", "phase", "rho0", "rho_prev", "ghost_mirror"};
  if (reserved.count(s.name)) r.fail_at(r.get("name"), r.key_path("name"), "a name not used by the engine's own fields (porosity, nu_t, phase, ...)");
  s.diffusivity = r.in_range("diffusivity", 0.0, 0.0, 1e6);
  s.schmidt_turbulent = r.in_range("turbulent_schmidt", 0.0, 0.0, 1e6);
  if (r.has("reaction")) {
    Reader q(r.get("reaction"), file, r.key_path("reaction"));
    s.reaction_rate = q.in_range("rate", 0.0, 0.0, 1e9);
    s.equilibrium = q.scalar<double>("equilibrium", 0.0);
    q.finish();
  }
  if (r.has("initial")) {
    const Node& in = r.get("initial");
    if (in.is_scalar()) {  // a plain number: uniform
      ScalarInitConfig u;
      u.value = r.as<double>(in, "initial");
      u.line = in.line();
      s.initial.push_back(u);
    } else {
      if (!in.is_sequence()) r.fail_at(in, r.key_path("initial"), "a number, or a list such as [{type: uniform, value: 0}, {type: region, shape: circle, center: [0.5, 0.5], radius: 0.1, value: 1}]");
      for (std::size_t i = 0; i < in.size(); ++i)
        s.initial.push_back(read_init(in[i], file, fmt::format("{}.initial.{}", path, i), dim));
    }
  }
  if (r.has("inflow")) {
    const Node& in = r.get("inflow");
    s.has_inflow = true;
    if (in.is_scalar()) {
      s.inflow = r.as<double>(in, "inflow");
    } else {
      Reader q(in, file, r.key_path("inflow"));
      s.inflow = q.required<double>("value", "the concentration the inflow particles carry");
      if (q.has("z")) {
        const auto z = q.vec("z", 2);
        if (!(z[1] > z[0])) q.fail_at(q.get("z"), q.key_path("z"), "[z_min, z_max] with z_max > z_min");
        s.inflow_z = {z[0], z[1]};
      }
      q.finish();
    }
  }
  if (r.has("sources")) {
    const Node& src = r.get("sources");
    if (!src.is_sequence()) r.fail_at(src, r.key_path("sources"), "a list of wall regions, e.g. [{shape: box, min: [0, -0.1], max: [0.1, 0], value: 1}]");
    for (std::size_t i = 0; i < src.size(); ++i) {
      Reader q(src[i], file, fmt::format("{}.sources.{}", path, i));
      ScalarSourceConfig sc;
      sc.line = src[i].line();
      sc.region = read_region(q, src[i], dim);
      sc.has_value = q.has("value");
      if (sc.has_value == q.has("flux"))
        q.fail_at(src[i], q.key_path("value"), "either 'value' (a prescribed concentration) or 'flux' (kg/(m2 s) into the fluid)");
      if (sc.has_value) sc.value = q.scalar<double>("value", 0.0);
      else sc.flux = q.scalar<double>("flux", 0.0);
      q.finish();
      s.sources.push_back(sc);
    }
  }
  r.finish();
  return s;
}

}  // namespace

void read_transport(const Node& n, const std::string& file, Case& c) {
  Reader r(n, file, "transport");
  auto& t = c.transport;
  t.line = n.line();
  const std::string op = r.choice("operator", "consistent", {"consistent", "federico", "zhu_fox", "tartakovsky", "monaghan"});
  t.op = op == "consistent" ? DiffusionOperator::Consistent
         : op == "federico" ? DiffusionOperator::Federico
         : op == "zhu_fox"  ? DiffusionOperator::ZhuFox
         : op == "tartakovsky" ? DiffusionOperator::Tartakovsky : DiffusionOperator::Monaghan;
  const std::string adv = r.choice("advection", "conservative", {"conservative", "none", "thesis_literal"});
  t.advection = adv == "conservative" ? ScalarAdvection::Conservative
                : adv == "none" ? ScalarAdvection::None : ScalarAdvection::ThesisLiteral;
  t.eta2 = r.in_range("eta2", 1e-4, 1e-8, 0.1);
  if (!r.has("scalars")) r.misspelt("scalars");
  const Node& sc = r.get("scalars");
  if (!sc.is_sequence() || sc.size() == 0)
    r.fail_at(sc.defined() ? sc : n, "transport.scalars", "a list of scalars, e.g. [{name: concentration, diffusivity: 1.0e-3, initial: 0}]");
  std::set<std::string> names;
  for (std::size_t i = 0; i < sc.size(); ++i) {
    t.scalars.push_back(read_scalar(sc[i], file, fmt::format("transport.scalars.{}", i), c.dimension));
    if (!names.insert(t.scalars.back().name).second)
      r.fail_at(sc[i], fmt::format("transport.scalars.{}.name", i), "a name not used by another scalar");
  }
  r.finish();
}

void read_multiphase(const Node& n, const std::string& file, Case& c) {
  Reader r(n, file, "multiphase");
  auto& m = c.multiphase;
  m.line = n.line();
  m.grenier = r.choice("formulation", "colagrossi_landrini", {"colagrossi_landrini", "grenier"}) == "grenier";
  m.chi = r.in_range("chi", m.grenier ? 0.08 : 0.0, 0.0, 1.0);
  if (!r.has("phases")) r.misspelt("phases");
  const Node& ph = r.get("phases");
  if (!ph.is_sequence() || ph.size() == 0)
    r.fail_at(ph.defined() ? ph : n, "multiphase.phases",
              "a list of phases, e.g. [{name: pollutant, density: 500, shape: circle, center: [0.72, 0.48], radius: 0.24}]");
  std::set<std::string> names = {"water"};
  for (std::size_t i = 0; i < ph.size(); ++i) {
    Reader q(ph[i], file, fmt::format("multiphase.phases.{}", i));
    PhaseConfig p;
    p.line = ph[i].line();
    p.name = q.required<std::string>("name", "the phase's name");
    if (!names.insert(p.name).second) q.fail_at(q.get("name"), q.key_path("name"), "a name not used by another phase ('water' is the first)");
    p.density = q.positive("density", 0.0, true);
    p.gamma = q.positive("gamma", 7.0);
    p.sound_speed = q.in_range("sound_speed", 0.0, 0.0, 1e6);
    p.region = read_region(q, ph[i], c.dimension);
    q.finish();
    m.phases.push_back(p);
  }
  r.finish();
}

}  // namespace caseio
}  // namespace sph
