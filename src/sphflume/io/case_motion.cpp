// The `motions:` section: prescribed wall motions (piston wave makers), each named and moved by a
// paddle law (boundaries/paddle.hpp). Shapes join one with `motion: NAME`.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <numbers>
#include <set>
#include <sstream>

#include <fmt/format.h>

#include "sphflume/boundaries/paddle.hpp"
#include "sphflume/boundaries/wave_spectrum.hpp"
#include "sphflume/io/case_reader.hpp"

namespace sph::caseio {
namespace {

/// Two columns (time [s], displacement [m]) of a CSV file (read_csv_numbers), times strictly increasing.
void read_table(Reader& r, MotionConfig& m) {
  const CsvNumbers csv = read_csv_numbers(r, "file", m.file, 2, "time, displacement");
  for (std::size_t i = 0; i < csv.rows.size(); ++i) {
    const double t = csv.rows[i][0], x = csv.rows[i][1];
    if (!m.table_t.empty() && !(t > m.table_t.back()))
      r.fail_at(r.get("file"), r.key_path("file"), fmt::format("strictly increasing times; {} line {} goes back to t = {}", csv.path, csv.lines[i], t));
    m.table_t.push_back(t);
    m.table_x.push_back(x);
  }
  if (m.table_t.size() < 2) r.fail_at(r.get("file"), r.key_path("file"), fmt::format("at least two rows of time, displacement in {}", csv.path));
}


/// irregular, focused and elevation (boundaries/wave_spectrum.hpp).
void read_linear_waves(Reader& r, const Node& n, MotionConfig& m) {
  m.depth = r.positive("depth", 0.0, true);
  m.f_min = r.scalar<double>("f_min", 0.0);
  m.f_max = r.scalar<double>("f_max", 0.0);
  for (const char* k : {"f_min", "f_max"})
    if (r.has(k) && !(r.scalar<double>(k, 0.0) > 0.0)) r.fail_at(r.get(k), r.key_path(k), "a frequency > 0 in Hz");
  if (m.law == "elevation") {
    m.file = r.required<std::string>("file", "a CSV file of time [s], surface elevation [m] at the paddle's face");
    const CsvNumbers csv = read_csv_numbers(r, "file", m.file, 2, "time, elevation");
    for (std::size_t i = 0; i < csv.rows.size(); ++i) {
      if (!m.elevation_t.empty() && !(csv.rows[i][0] > m.elevation_t.back()))
        r.fail_at(r.get("file"), r.key_path("file"), fmt::format("strictly increasing times; {} line {} goes back", csv.path, csv.lines[i]));
      m.elevation_t.push_back(csv.rows[i][0]);
      m.elevation_eta.push_back(csv.rows[i][1]);
    }
    if (m.elevation_t.size() < 8) r.fail_at(r.get("file"), r.key_path("file"), fmt::format("at least 8 rows of time, elevation in {}", csv.path));
  } else {
    if (!r.has("tp"))
      r.fail_at(n, r.key_path("tp"), fmt::format("the peak period Tp [s] of the {}'s spectrum (a {} motion needs it)", m.law == "irregular" ? "sea" : "group", m.law));
    m.tp = r.positive("tp", 0.0, true);
    m.spectrum = r.choice("spectrum", "jonswap", {"jonswap", "pierson_moskowitz"});
    m.gamma = r.scalar<double>("gamma", 3.3);
    if (!(m.gamma >= 1.0 && m.gamma <= 10.0)) r.fail_at(r.get("gamma"), r.key_path("gamma"), "a peak enhancement in [1, 10] (JONSWAP's mean 3.3)");
    if (r.has("gamma") && m.spectrum != "jonswap")
      r.fail_at(r.get("gamma"), r.key_path("gamma"), "no gamma with spectrum pierson_moskowitz (it is JONSWAP with gamma 1)");
    const int nc = r.scalar<int>("components", 0);
    if (r.has("components") && (nc < 8 || nc > 100000)) r.fail_at(r.get("components"), r.key_path("components"), "an integer in [8, 100000]");
    m.components = nc;
    if (m.law == "irregular") {
      m.hm0 = r.positive("hm0", 0.0, true);
      const int seed = r.scalar<int>("seed", 1);
      if (seed < 0) r.fail_at(r.get("seed"), r.key_path("seed"), "an integer >= 0");
      m.seed = static_cast<std::uint64_t>(seed);
      // Miche's limit for the highest wave of the sea (H_max ≈ 1.86 Hm0 over 1000 waves, Goda 2000)
      const double k = wave_number(2.0 * std::numbers::pi / m.tp, m.depth, m.gravity);
      const double hmax = 0.142 * (2.0 * std::numbers::pi / k) * std::tanh(k * m.depth);
      if (!(1.86 * m.hm0 < hmax))
        r.fail_at(r.get("hm0"), r.key_path("hm0"), fmt::format("Hm0 below {:.4g} m: the sea's highest waves (1.86 Hm0) must stay below Miche's breaking limit {:.4g} m at Tp", hmax / 1.86, hmax));
    } else {
      m.amplitude = r.positive("amplitude", 0.0, true);
      m.focus_x = r.required<double>("focus_x", "the focus's distance from the paddle's rest face [m]");
      m.focus_time = r.required<double>("focus_time", "the time of the focus after 'start' [s]");
      if (!(m.focus_x >= 0.0)) r.fail_at(r.get("focus_x"), r.key_path("focus_x"), "a distance >= 0 in m ahead of the paddle");
      if (!(m.focus_time > 0.0)) r.fail_at(r.get("focus_time"), r.key_path("focus_time"), "a time > 0 in s after 'start'");
    }
    double f0 = 0.0, f1 = 0.0;
    spectrum_band(m, f0, f1);
    if (!(f1 > f0)) r.fail_at(r.get(r.has("f_max") ? "f_max" : "f_min"), r.key_path(r.has("f_max") ? "f_max" : "f_min"), fmt::format("f_max above f_min ({} Hz)", f0));
  }
}

/// `second_order: true` and `evanescent_modes: J` (boundaries/paddle_order2.hpp).
void read_second_order(Reader& r, MotionConfig& m) {
  m.second_order = r.scalar<bool>("second_order", false);
  if (m.second_order && m.law != "regular" && m.law != "irregular" && m.law != "focused" && m.law != "elevation")
    r.fail_at(r.get("second_order"), r.key_path("second_order"),
              m.law == "stokes2" ? std::string("law regular with second_order: true for Schäffer's correction (stokes2 is already second order: Madsen's long-wave form)")
                                 : fmt::format("a law made of linear waves for the second-order correction (regular, irregular, focused or elevation; not {})", m.law));
  if (r.has("evanescent_modes")) {
    if (!m.second_order) r.fail_at(r.get("evanescent_modes"), r.key_path("evanescent_modes"), "second_order: true (the evanescent modes are the second-order correction's)");
    m.evanescent_modes = r.scalar<int>("evanescent_modes", 20);
    if (m.evanescent_modes < 0 || m.evanescent_modes > 200)
      r.fail_at(r.get("evanescent_modes"), r.key_path("evanescent_modes"), "an integer in [0, 200] (default 20, extrapolated from 10)");
  }
}

/// `paddle: flap`, `hinge: [x, z]` and the still-water level `level` (default: depth, the bed at z = 0).
void read_flap(Reader& r, const Node& n, MotionConfig& m, const Case& c) {
  m.paddle = r.choice("paddle", "piston", {"piston", "flap"});
  if (m.paddle != "flap") {
    for (const char* k : {"hinge", "level"})
      if (r.has(k)) r.fail_at(r.get(k), r.key_path(k), "no hinge or level on a piston (add 'paddle: flap')");
    return;
  }
  const std::size_t d = static_cast<std::size_t>(c.dimension);
  if (m.law == "solitary" || m.law == "stokes2")
    r.fail_at(r.get("paddle"), r.key_path("paddle"), fmt::format("a piston for law {} (its motion is a piston's: use regular, "
                                                                 "irregular, focused, elevation, table or absorber with a flap)", m.law));
  if (!(m.depth > 0.0)) r.fail_at(n, r.key_path("depth"), "the still-water depth at the flap [m] (its transfer function needs it)");
  if (std::abs(m.direction[d - 1]) > 1e-12)
    r.fail_at(r.get("direction"), r.key_path("direction"), "a horizontal direction for a flap (the way its top moves)");
  m.hinge = r.vec("hinge", d);
  if (m.hinge.empty()) r.fail_at(n, r.key_path("hinge"), fmt::format("the flap's hinge, a point [{}] of the hinge line [m]", d == 2 ? "x, z" : "x, y, z"));
  const double level = r.scalar<double>("level", m.depth);
  m.hinge_depth = level - m.hinge[d - 1];
  if (m.hinge_depth > m.depth * (1.0 + 1e-9))
    r.fail_at(r.get("hinge"), r.key_path("hinge"), fmt::format("a hinge at or above the bed: z = {} is {:.4g} m below the still-water level "
                                                              "{} (level) but the water is {} m deep (depth)", m.hinge[d - 1], m.hinge_depth, level, m.depth));
  if (!(m.hinge_depth > 0.0))
    r.fail_at(r.get("hinge"), r.key_path("hinge"), fmt::format("a hinge below the still-water level {} m (level)", level));
}

/// `absorption: {gauge: NAME, drift_time: T}`: active absorption from the level at the paddle's face.
void read_absorption(Reader& r, MotionConfig& m, const Case& c) {
  if (!r.has("absorption")) return;
  const Node& a = r.get("absorption");
  Reader ar(a, r.file(), r.key_path("absorption"));
  ar.valid({"gauge", "drift_time", "start"});
  m.absorb = true;
  m.absorb_gauge = ar.required<std::string>("gauge", "the name of a water_level gauge at the paddle's face (the level the absorption reads)");
  m.absorb_start = ar.scalar<double>("start", std::max(m.start + m.ramp, 1.0));
  if (!(m.absorb_start >= 0.0)) ar.fail_at(ar.get("start"), ar.key_path("start"), "a time >= 0 in s");
  m.drift_time = ar.scalar<double>("drift_time", 0.0);
  if (ar.has("drift_time") && !(m.drift_time > 0.0))
    ar.fail_at(ar.get("drift_time"), ar.key_path("drift_time"), "a time > 0 in s (default: 4 wave periods)");
  ar.finish();
  const GaugeConfig* g = nullptr;
  for (const auto& gc : c.gauges)
    if (gc.name == m.absorb_gauge) g = &gc;
  if (!g || g->type != "water_level")
    ar.fail_at(ar.get("gauge"), ar.key_path("gauge"),
               fmt::format("a water_level gauge at the paddle's face: '{}' is {}; add '- {{name: {}, type: water_level, x: X}}' "
                           "under 'gauges' with X about 4 dx (the kernel's support) ahead of the paddle", m.absorb_gauge, g ? "a " + g->type + " gauge" : "not a gauge",
                           m.absorb_gauge));
  m.absorb_point = g->point;
  if (m.law == "table" && !(m.depth > 0.0)) r.fail_at(r.get("absorption"), r.key_path("absorption"), "a 'depth' on a table motion with absorption (the target level comes from long-wave theory)");
  if (m.drift_time == 0.0) {
    const double T = m.law == "regular" || m.law == "stokes2" || m.law == "absorber" ? m.period : m.tp;
    if (!(T > 0.0)) r.fail_at(r.get("absorption"), r.key_path("absorption"), "a drift_time [s] (the law has no period to take 4 of)");
    m.drift_time = 4.0 * T;
  }
}

MotionConfig read_motion(const Node& n, const std::string& file, const std::string& path, const Case& c) {
  Reader r(n, file, path);
  r.valid({"name", "law", "direction", "theory", "height", "depth", "period", "start", "ramp", "file", "spectrum", "hm0",
           "tp", "gamma", "seed", "components", "f_min", "f_max", "amplitude", "focus_x", "focus_time", "absorption",
           "paddle", "hinge", "level", "second_order", "evanescent_modes"});
  MotionConfig m;
  m.line = n.line();
  m.name = r.required<std::string>("name", "a motion name (shapes join it with 'motion: NAME')");
  (void)r.required<std::string>("law", "a paddle law: solitary, regular, stokes2, table, irregular, focused, elevation or absorber");
  m.law = r.choice("law", "", {"solitary", "regular", "stokes2", "table", "irregular", "focused", "elevation", "absorber"});
  const std::size_t d = static_cast<std::size_t>(c.dimension);
  std::vector<double> e(d, 0.0);
  e[0] = 1.0;
  m.direction = r.vec("direction", d, e);
  double len = 0.0;
  for (double v : m.direction) len += v * v;
  if (!(len > 0.0)) r.fail_at(r.get("direction"), r.key_path("direction"), "a non-zero direction of the translation");
  for (double& v : m.direction) v /= std::sqrt(len);
  double g2 = 0.0;
  for (double v : c.gravity) g2 += v * v;
  m.gravity = std::sqrt(g2);
  m.start = r.scalar<double>("start", 0.0);
  if (!(m.start >= 0.0)) r.fail_at(r.get("start"), r.key_path("start"), "a time >= 0 in s (the paddle rests before it)");
  m.ramp = r.scalar<double>("ramp", 0.0);
  if (!(m.ramp >= 0.0)) r.fail_at(r.get("ramp"), r.key_path("ramp"), "a duration >= 0 in s (0: no ramp)");
  if (m.law == "solitary" || m.law == "regular" || m.law == "stokes2") {
    if (!(m.gravity > 0.0)) r.fail_at(n, path, "gravity (the wave laws need |g| > 0)");
    m.height = r.positive("height", 0.0, true);
    m.depth = r.positive("depth", 0.0, true);
    if (m.law == "solitary") {
      m.theory = r.choice("theory", "rayleigh", {"rayleigh", "goring", "rayleigh_explicit"});
      if (!(m.height < 0.78 * m.depth))
        r.fail_at(r.get("height"), r.key_path("height"), fmt::format("a wave height below 0.78 depth (McCowan's breaking limit of a solitary wave; depth = {} m)", m.depth));
      if (r.has("ramp")) r.fail_at(r.get("ramp"), r.key_path("ramp"), "no ramp for a solitary wave (its law starts from rest)");
    } else {
      m.period = r.positive("period", 0.0, true);
      // Miche's limit of a progressive wave: H/L < 0.142 tanh(kh)
      const double k = wave_number(2.0 * std::numbers::pi / m.period, m.depth, m.gravity);
      const double hmax = 0.142 * (2.0 * std::numbers::pi / k) * std::tanh(k * m.depth);
      if (!(m.height < hmax))
        r.fail_at(r.get("height"), r.key_path("height"), fmt::format("a wave height below Miche's breaking limit 0.142 L tanh(kh) = {:.4g} m (L = {:.4g} m for period {} s in depth {} m)", hmax, 2.0 * std::numbers::pi / k, m.period, m.depth));
    }
  } else if (m.law == "absorber") {
    if (!(m.gravity > 0.0)) r.fail_at(n, path, "gravity (absorption needs |g| > 0)");
    m.depth = r.positive("depth", 0.0, true);
    if (r.has("period")) m.period = r.positive("period", 1.0);  // the gain's frequency (default: long waves)
    if (!r.has("absorption"))
      r.fail_at(n, r.key_path("absorption"), "an 'absorption: {gauge: NAME}' on an absorber (at rest without it, it is a wall)");
  } else if (m.law == "table") {
    m.file = r.required<std::string>("file", "a CSV file of time [s], displacement [m]");
    read_table(r, m);
    if (r.has("depth")) m.depth = r.positive("depth", 0.0);  // (only active absorption and a flap read it)
  } else {
    if (!(m.gravity > 0.0)) r.fail_at(n, path, "gravity (the wave laws need |g| > 0)");
    read_linear_waves(r, n, m);
  }
  read_second_order(r, m);
  read_flap(r, n, m, c);
  read_absorption(r, m, c);
  r.finish();
  return m;
}

}  // namespace

void read_motions(Reader& top, const std::string& file, Case& c) {
  if (top.has("motions")) {
    const Node& ms = top.get("motions");
    if (!ms.is_sequence()) top.fail_at(ms, "motions", "a list of wall motions, each starting with '- name: NAME'");
    std::set<std::string> names;
    for (std::size_t i = 0; i < ms.size(); ++i) {
      c.motions.push_back(read_motion(ms[i], file, fmt::format("motions.{}", i), c));
      const MotionConfig& m = c.motions.back();
      if (m.law == "irregular" || m.law == "focused") {  // a sea repeats after 1/Δf
        double f0 = 0.0, f1 = 0.0;
        spectrum_band(m, f0, f1);
        const int n = m.components > 0 ? m.components : default_components(m);
        const double repeat = n / (f1 - f0);
        if (c.t_end - m.start > repeat)
          c.warnings.push_back(fmt::format("{}: line {}: motion '{}': the sea repeats after {:.4g} s ({} components over "
                                           "[{:.4g}, {:.4g}] Hz) and the run goes on for {:.4g} s: set 'components: {}' "
                                           "for a sea that does not repeat", file, m.line, m.name, repeat, n, f0, f1,
                                           c.t_end - m.start, static_cast<int>(std::ceil((c.t_end - m.start) * (f1 - f0)))));
      }
      if (!names.insert(c.motions.back().name).second)
        top.fail_at(ms[i], fmt::format("motions.{}.name", i), "a name not used by another motion");
    }
  }
  std::set<std::string> used;
  for (std::size_t i = 0; i < c.shapes.size(); ++i) {
    const auto& s = c.shapes[i];
    if (s.motion.empty()) continue;
    bool known = false;
    for (const auto& m : c.motions) known |= m.name == s.motion;
    if (!known)
      throw InputError(fmt::format("{}: line {}: geometry.{}.motion: '{}' is not a motion: expected a name defined under "
                                   "'motions'", file, s.line, i, s.motion));
    used.insert(s.motion);
    // a moving wall thinner than the wall layers lets fluid through it (its far side has no fluid to
    // hold it, and the kernel reaches across): boxes must be as thick as the layers along the motion
    if (s.type == "box") {
      const MotionConfig* mc = nullptr;
      for (const auto& m : c.motions)
        if (m.name == s.motion) mc = &m;
      double along = 0.0;
      for (std::size_t d = 0; d < s.min.size(); ++d) along += std::abs(mc->direction[d] * (s.max[d] - s.min[d]));
      const double need = wall_layers_for(c) * c.dx;
      if (along < need * (1.0 - 1e-9))
        throw InputError(fmt::format("{}: line {}: geometry.{}: the moving wall is {:.4g} m thick along its motion, thinner "
                                     "than the {} wall layers ({:.4g} m at dx = {}): fluid would leak through it; make the "
                                     "box at least {:.4g} m thick", file, s.line, i, along, wall_layers_for(c), need, c.dx, need));
    }
  }
  // active absorption reads the level at the paddle's face: its gauge stands ahead of the moving
  // box's face, within one still-water depth of it
  for (const auto& m : c.motions) {
    if (!m.absorb) continue;
    double face = -std::numeric_limits<double>::infinity();
    for (const auto& s : c.shapes)
      if (s.motion == m.name && s.type == "box") {
        double f = 0.0;
        for (std::size_t d = 0; d < s.max.size(); ++d) f += m.direction[d] * (m.direction[d] > 0.0 ? s.max[d] : s.min[d]);
        face = std::max(face, f);
      }
    if (!std::isfinite(face)) continue;  // (not a box: no face to check against)
    double at = 0.0;
    for (std::size_t d = 0; d + 1 < m.absorb_point.size() && d < m.direction.size(); ++d) at += m.direction[d] * m.absorb_point[d];
    if (!(at > face && at <= face + m.depth))
      throw InputError(fmt::format("{}: line {}: motion '{}': its absorption gauge '{}' is {:.4g} m from the paddle's face: "
                                   "expected a water_level gauge ahead of the face within one depth ({} m), e.g. at x = {:.4g}",
                                   file, m.line, m.name, m.absorb_gauge, at - face, m.depth, face + 5.0 * c.dx));
  }
  for (const auto& m : c.motions)
    if (!used.count(m.name))
      throw InputError(fmt::format("{}: line {}: motion '{}' moves no wall: add 'motion: {}' to a wall shape under "
                                   "'geometry'", file, m.line, m.name, m.name));
  if (!c.motions.empty() && c.walls.type == "fixed_ghost")
    top.fail_at(top.get("motions"), "motions",
                "walls.type dummy, dynamic or repulsive (fixed ghost particles do not follow a moving wall in this version)");
  if (!c.motions.empty() && !c.periodic.empty())
    top.fail_at(top.get("motions"), "motions", "a domain that is not periodic (moving walls across a periodic seam are not supported)");
}

void warn_short_support_with_motions(Reader& top, const std::string& file, Case& c) {
  if (c.motions.empty()) return;
  // the solitary wave of validation/solitary_wave was 8-11 % low at h = 1.5 dx and within 3 % at 2 dx
  // (Wendland C2, a support of 3 dx against 4 dx): the crest needs the wider support
  const double support = kernel_support_factor(c.kernel) * c.h_over_dx;
  if (support >= 4.0 - 1e-9) return;
  const double want = 4.0 / kernel_support_factor(c.kernel);
  int line = 0;
  if (top.has("particles")) {
    const Node& p = top.get("particles");
    if (p.is_map() && p["h_over_dx"].defined()) line = p["h_over_dx"].key_line();
  }
  c.warnings.push_back(fmt::format(
      "{}: {}particles.h_over_dx: {:g} with moving walls (motions): the kernel reaches {:g} dx, and waves made at less "
      "than 4 dx lose their crest (a solitary wave 8-11 % low at h = 1.5 dx with Wendland C2, validation/solitary_wave); "
      "set particles.h_over_dx: {:g}",
      file, line > 0 ? fmt::format("line {}: ", line) : std::string(), c.h_over_dx, support, want));
}

}  // namespace sph::caseio
