// The case file's model sections: `scheme:` (each scheme's own keys), `walls:`, `turbulence:`
// and `porous:` (docs/case-file.md). Called by build_case (io/case.cpp).
#include <cmath>

#include <fmt/format.h>

#include "sphflume/boundaries/walls.hpp"
#include "sphflume/io/case_reader.hpp"
#include "sphflume/schemes/scheme_options.hpp"

namespace sph::caseio {
namespace {

/// A list of numbers, strictly increasing when `increasing`.
std::vector<double> read_list(Reader& r, const std::string& k, bool increasing) {
  const Node& v = r.get(k);
  const std::string what = increasing ? "a list of increasing numbers" : "a list of numbers";
  if (!v.is_sequence() || v.size() == 0) r.fail_at(v, r.key_path(k), what);
  std::vector<double> out;
  for (const auto& [unused, e] : v.entries()) {
    double x = 0.0;
    if (!e.decode(x)) r.fail_at(e, r.key_path(k), what);
    out.push_back(x);
    if (!std::isfinite(out.back()) || (increasing && out.size() > 1 && !(out.back() > out[out.size() - 2])))
      r.fail_at(e, r.key_path(k), what);
  }
  return out;
}

PorousRegionConfig read_porous_region(const Node& n, const std::string& file, const std::string& path, int dim) {
  Reader r(n, file, path);
  r.valid({"shape", "min", "max", "vertices", "porosity", "diameter", "layer", "closure", "upper", "x", "z", "phi",
           "toe", "gradient", "top", "thickness", "back", "survey", "file", "units", "scale", "rotate", "offset"});
  PorousRegionConfig g;
  g.line = n.line();
  g.shape = r.choice("shape", "box", {"box", "polygon", "profile", "slope", "mesh"});
  if (g.shape == "slope") {  // a permeable beach or an armour layer: its polygon
    if (dim != 2) r.fail_at(n, path, "a box (slopes are 2D only)");
    g.vertices = read_slope(r, n, 0.0, nullptr, &g.surface);
    g.shape = "polygon";
  }
  const std::size_t d = static_cast<std::size_t>(dim);
  if (g.shape == "box") {
    g.min = r.vec("min", d);
    g.max = r.vec("max", d);
    if (g.min.empty() || g.max.empty()) r.fail_at(n, path, "'min' and 'max' corners of the porous box");
    for (std::size_t i = 0; i < d; ++i)
      if (!(g.max[i] > g.min[i])) r.fail_at(r.get("max"), r.key_path("max"), "max > min in every coordinate");
  } else if (g.shape == "polygon" && g.vertices.empty()) {
    if (dim != 2) r.fail_at(n, path, "a box (polygons are 2D only)");
    g.vertices = read_vertices(r, n);
  } else if (g.shape == "mesh") {
    g.mesh = read_mesh(r, n, dim);
  }
  if (g.shape == "profile") {
    if (!r.has("z")) r.misspelt("z");
    if (!r.has("z") || !r.has("phi"))
      r.fail_at(n, path, "a profile: 'z' (heights) and 'phi' (porosity at each height; with 'x', one row per x)");
    g.z = read_list(r, "z", true);
    if (r.has("x")) g.x = read_list(r, "x", true);
    const Node& ph = r.get("phi");
    const std::string what = g.x.empty() ? fmt::format("a list of {} porosities in (0, 1], one per z", g.z.size())
                                         : fmt::format("{} rows (one per x) of {} porosities in (0, 1]", g.x.size(), g.z.size());
    if (!ph.is_sequence()) r.fail_at(ph, r.key_path("phi"), what);
    auto row = [&](const Node& rn) {
      if (!rn.is_sequence() || rn.size() != g.z.size()) r.fail_at(rn, r.key_path("phi"), what);
      std::vector<double> v;
      for (const auto& [unused, e] : rn.entries()) {
        double x = -1.0;
        if (!e.decode(x)) r.fail_at(e, r.key_path("phi"), what);
        if (!(x > 0.0 && x <= 1.0)) r.fail_at(e, r.key_path("phi"), what);
        v.push_back(x);
      }
      return v;
    };
    if (g.x.empty()) g.phi.push_back(row(ph));
    else {
      if (ph.size() != g.x.size()) r.fail_at(ph, r.key_path("phi"), what);
      for (const auto& [unused, rn] : ph.entries()) g.phi.push_back(row(rn));
    }
    g.porosity = 1.0;
    for (const auto& rw : g.phi) for (double v : rw) g.porosity = std::min(g.porosity, v);
  } else {
    g.porosity = r.scalar<double>("porosity", -1.0);
    if (!r.has("porosity")) r.misspelt("porosity");
    if (!(g.porosity > 0.0 && g.porosity <= 1.0))
      r.fail_at(r.has("porosity") ? r.get("porosity") : n, r.key_path("porosity"), "a porosity in (0, 1]");
  }
  g.diameter = r.positive("diameter", 0.0, true);
  g.layer = r.in_range("layer", 0.0, 0.0, 1e6);
  auto closure = [&](const Node& cn, const std::string& path) {
    Reader c(cn, file, path);
    PorousClosureConfig k;
    k.type = c.choice("type", "ergun", {"ergun", "tsurudome", "van_gent", "roughness"});
    if (k.type == "van_gent") {
      k.c1 = c.in_range("alpha", 1000.0, 0.0, 1e9);
      k.c2 = c.in_range("beta", 1.1, 0.0, 1e9);
      k.added_mass = c.in_range("added_mass", 0.34, 0.0, 100.0);
      k.kc = c.in_range("kc", 0.0, 0.0, 1e12);
    } else if (k.type == "roughness") {
      k.cd = c.in_range("cd", 0.9, 0.0, 100.0);
      k.factor = c.in_range("factor", 1.0, 0.0, 100.0);
    } else {
      k.c1 = c.in_range("c1", 150.0, 0.0, 1e9);
      k.c2 = c.in_range("c2", 1.75, 0.0, 1e9);
    }
    c.finish();
    return k;
  };
  if (r.has("closure")) g.closure = closure(r.get("closure"), r.key_path("closure"));
  if (r.has("upper")) {
    Reader u(r.get("upper"), file, r.key_path("upper"));
    g.has_upper = true;
    g.upper_z = u.required<double>("z", "the level above which the upper closure applies, in m");
    g.upper_x = u.scalar<double>("x", -1e300);
    if (!u.has("closure")) u.misspelt("closure");
    if (!u.has("closure")) u.fail_at(r.get("upper"), r.key_path("upper.closure"), "the upper closure, e.g. {type: roughness, cd: 0.9}");
    g.upper = closure(u.get("closure"), r.key_path("upper.closure"));
    u.finish();
  }
  r.finish();
  return g;
}

}  // namespace

void read_scheme(const Node& n, const std::string& file, Case& c) {
  Reader r(n, file, "scheme");
  std::vector<std::string> types;
  for (const auto& [name, unused] : scheme_types()) types.push_back(name);
  c.scheme.type = r.choice("type", "wcsph", types);
  scheme_types().at(c.scheme.type).read(r, c);  // its own keys (schemes/scheme_options.hpp)
}

void read_walls(const Node& n, const std::string& file, Case& c) {
  Reader r(n, file, "walls");
  // the choices are the registered wall models (one line in wall_registry() adds one here)
  c.walls.type = r.choice("type", "dummy", wall_registry<2>().names());
  c.walls.no_slip = r.choice("slip", "no_slip", {"no_slip", "free_slip"}) == "no_slip";
  c.walls.layers = r.scalar<int>("layers", 0);
  if (c.walls.layers < 0 || c.walls.layers > 10) r.fail_at(r.get("layers"), "walls.layers", "an integer in [0, 10] (0 = from the kernel support)");
  c.walls.clamp_negative_pressure = r.scalar<bool>("clamp_negative_pressure", true);
  c.walls.repulsive = c.walls.type == "repulsive";
  if (r.has("repulsion")) {
    Reader q(r.get("repulsion"), file, "walls.repulsion");
    c.walls.repulsive = true;
    c.walls.beta1 = q.in_range("beta1", 0.01, 0.0, 10.0);
    c.walls.beta2 = q.in_range("beta2", 1.0, 0.0, 100.0);
    q.finish();
  }
  // the Monaghan-Kos force already keeps the fluid out; the backup serves the other models
  c.walls.backup = r.scalar<bool>("backup", true) && !c.walls.repulsive;
  if (r.has("tangential_factor")) {
    if (c.walls.type != "fixed_ghost")
      r.fail_at(r.get("tangential_factor"), "walls.tangential_factor", "walls.type: fixed_ghost (the factor scales the ghosts' tangential velocity)");
    c.walls.tangential_factor = r.in_range("tangential_factor", 0.0, -1.0, 1.0);
  }
  r.finish();
}

void read_turbulence(const Node& n, const std::string& file, Case& c) {
  Reader r(n, file, "turbulence");
  auto& t = c.turbulence;
  t.line = n.line();
  t.model = r.choice("model", "none", {"none", "smagorinsky", "mixing_length"});
  t.strain_literal = r.choice("strain_norm", "sqrt_2ss", {"sqrt_2ss", "sqrt_ss"}) == "sqrt_ss";
  t.column_width = r.in_range("column_width", 0.0, 0.0, 1e6);
  // every model's keys are read whatever the model, so `--set turbulence.model=...` can
  // switch models without editing the other keys
  t.cs = r.in_range("cs", 0.15, 0.0, 1.0);
  t.delta = r.in_range("delta", 0.0, 0.0, 1e6);
  t.profile = r.choice("profile", "nezu_rodi", {"nezu_rodi", "three_layer", "constant"});
  t.bed = r.scalar<double>("bed", 0.0);
  t.kappa = r.in_range("kappa", 0.41, 0.0, 1.0);
  t.coles_pi = r.in_range("coles_pi", 0.0, 0.0, 2.0);
  t.van_driest = r.scalar<bool>("van_driest", false);
  t.a_plus = r.positive("a_plus", 26.0);
  t.l_mb = r.in_range("l_mb", 0.002, 0.0, 1e6);
  t.dz0 = r.scalar<double>("dz0", 0.0);
  t.kappa_r = r.in_range("kappa_r", 0.27, 0.0, 1.0);
  t.kappa_f = r.in_range("kappa_f", 0.22, 0.0, 1.0);
  const bool ml = t.model == "mixing_length";
  if (ml && t.profile == "constant") t.length = r.positive("length", 0.0, true);
  else t.length = r.in_range("length", 0.0, 0.0, 1e6);
  if (ml && t.profile == "three_layer") {
    t.z_trough = r.required<double>("z_trough", "the trough level z_t in m");
    t.z_crest = r.required<double>("z_crest", "the roughness-crest level z_c in m");
    if (!(t.z_crest > t.z_trough)) r.fail_at(r.get("z_crest"), "turbulence.z_crest", "a level above z_trough");
  } else {
    t.z_trough = r.scalar<double>("z_trough", 0.0);
    t.z_crest = r.scalar<double>("z_crest", 0.0);
  }
  r.finish();
}

void read_porous(const Node& n, const std::string& file, Case& c) {
  Reader r(n, file, "porous");
  auto& p = c.porous;
  p.line = n.line();
  p.field = r.choice("field", "smoothed", {"smoothed", "particles", "sharp"});
  p.literal_normalisation = r.choice("normalisation", "full_block", {"full_block", "thesis_literal"}) == "thesis_literal";
  p.mesh_ratio = r.positive("mesh_ratio", 1.2);
  p.relax_iterations = r.scalar<int>("relax", 0);
  if (p.relax_iterations < 0 || p.relax_iterations > 100000)
    r.fail_at(r.get("relax"), "porous.relax", "an integer in [0, 100000] (iterations; 0 = the plain lattice fill)");
  if (!r.has("regions")) r.misspelt("regions");
  const Node& regs = r.get("regions");
  if (!regs.is_sequence() || regs.size() == 0)
    r.fail_at(regs.defined() ? regs : n, "porous.regions",
              "a list of porous regions, e.g. [{shape: box, min: [0.3, 0], max: [0.59, 0.58], porosity: 0.49, diameter: 0.0159}]");
  for (std::size_t i = 0; i < regs.size(); ++i)
    p.regions.push_back(read_porous_region(regs[i], file, fmt::format("porous.regions.{}", i), c.dimension));
  if (r.has("fill")) {
    const Node& fl = r.get("fill");
    if (!fl.is_sequence()) r.fail_at(fl, "porous.fill", "a list of boxes, e.g. [{min: [0, 0], max: [1, 0.09], porosity: 0.22}]");
    for (std::size_t i = 0; i < fl.size(); ++i) {
      Reader f(fl[i], file, fmt::format("porous.fill.{}", i));
      PorousConfig::Fill b;
      b.min = f.vec("min", static_cast<std::size_t>(c.dimension));
      b.max = f.vec("max", static_cast<std::size_t>(c.dimension));
      if (b.min.empty() || b.max.empty()) f.fail_at(fl[i], fmt::format("porous.fill.{}", i), "'min' and 'max' corners");
      for (std::size_t d = 0; d < b.min.size(); ++d)
        if (!(b.max[d] > b.min[d])) f.fail_at(f.get("max"), fmt::format("porous.fill.{}.max", i), "max > min in every coordinate");
      b.porosity = f.in_range("porosity", 1.0, 1e-3, 1.0);
      f.finish();
      p.fill.push_back(b);
    }
  }
  r.finish();
}

}  // namespace sph::caseio
