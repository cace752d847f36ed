// Bad input: every problem is an InputError whose message names the file, the line and the
// dotted key and says what was expected (docs/case-file.md, "Errors"). Parse-time checks
// (case.cpp) and build-time checks (setup/build.cpp's build_system, before anything is computed).
#include <gtest/gtest.h>

#include <chrono>
#include <string>
#include <vector>

#include "sphflume/boundaries/walls.hpp"
#include "sphflume/io/case.hpp"
#include "sphflume/setup/setup.hpp"
#include "sphflume/physics/force_terms.hpp"
#include "test_helpers.hpp"

using namespace sph;

namespace {

// line numbers:   1            2            3             4          5       6
const char* kCase = R"(name: t
dimension: 2
particles:
  dx: 0.01
fluid:
  density: 1000.0
geometry:
  - {type: tank, min: [0.0, 0.0], max: [0.4, 0.3]}
  - {type: box, fill: fluid, min: [0.0, 0.0], max: [0.1, 0.1]}
time:
  end: 1.0
  output_interval: 0.1
)";
// line 7: geometry, 8: geometry.0 (tank), 9: geometry.1 (fluid box), 10: time, 11: end, 12: output_interval

std::string replaced(std::string t, const std::string& from, const std::string& to) {
  const auto at = t.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) t.replace(at, from.size(), to);
  return t;
}

/// The message of the InputError that parsing and building `text` raises ("" if none).
std::string error_of(const std::string& text, const BuildLimits& limits = {}) {
  try {
    const Case c = parse_case(text, "case.yaml");
    if (c.dimension == 2) {
      System<2> S;
      build_system<2>(c, S, limits);
    } else {
      System<3> S;
      build_system<3>(c, S, limits);
    }
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}


}  // namespace

TEST(InputErrors, BaseCaseIsValid) { EXPECT_EQ(error_of(kCase), ""); }

TEST(InputErrors, YamlSyntaxHasLineAndColumn) {
  const std::string e = error_of(replaced(kCase, "max: [0.1, 0.1]}", "max: [0.1, 0.1}"));
  EXPECT_HAS(e, "case.yaml: line 9, column");
  EXPECT_HAS(e, "YAML syntax error");
  const std::string e2 = error_of("particles:\n  dx: 0.1\n   kernel: x\n");
  EXPECT_HAS(e2, "case.yaml: line 3, column");
  EXPECT_HAS(e2, "YAML syntax error");
}

TEST(InputErrors, UnknownKeysSuggestTheClosest) {
  std::string e = error_of(replaced(kCase, "time:", "tme:"));
  EXPECT_HAS(e, "case.yaml: line 10: unknown key 'tme' (did you mean 'time'?)");
  e = error_of(replaced(kCase, "fill: fluid, min:", "fill: fluid, mn:"));
  EXPECT_HAS(e, "line 9: unknown key 'geometry.1.mn' (did you mean 'geometry.1.min'?)");
  e = error_of(replaced(kCase, "  output_interval", "  output_intervall"));
  EXPECT_HAS(e, "line 12: unknown key 'time.output_intervall' (did you mean 'time.output_interval'?)");
  e = error_of(replaced(kCase, "  dx: 0.01", "  dx: 0.01\n  [a, b]: 1"));
  EXPECT_HAS(e, "line 5: 'particles': expected keys that are plain names");
}

TEST(InputErrors, DuplicateKeysAtEveryLevelNameBothLines) {
  // YAML forbids a key twice in one mapping; yaml-cpp would keep the first silently
  std::string e = error_of(std::string(kCase) + "particles:\n  dx: 0.02\n");
  EXPECT_HAS(e, "case.yaml: line 13: duplicate key 'particles' (first given at line 3)");
  e = error_of(replaced(kCase, "  output_interval: 0.1\n", "  output_interval: 0.1\n  end: 2.0\n"));
  EXPECT_HAS(e, "case.yaml: line 13: duplicate key 'time.end' (first given at line 11)");
  e = error_of(replaced(kCase, "max: [0.1, 0.1]}", "max: [0.1, 0.1], fill: wall}"));
  EXPECT_HAS(e, "case.yaml: line 9: duplicate key 'geometry.1.fill' (first given at line 9)");
  // the same name in two different mappings is not a duplicate (min/max in geometry.0 and .1)
  EXPECT_EQ(error_of(kCase), "");
}

TEST(InputErrors, MissingRequiredKeysAndSections) {
  std::string e = error_of(replaced(kCase, "  dx: 0.01\n", "  kernel: cubic_spline\n"));
  EXPECT_HAS(e, "case.yaml: line 4: missing required key 'particles.dx': expected a positive number");
  e = error_of(replaced(kCase, "{type: box, fill: fluid,", "{fill: fluid,"));
  EXPECT_HAS(e, "line 9: missing required key 'geometry.1.type': expected a shape type");
  e = error_of(replaced(kCase, "time:\n  end: 1.0\n", "time:\n"));
  EXPECT_HAS(e, "line 11: missing required key 'time.end': expected a positive number");  // the section's line
  e = error_of(replaced(kCase, "fluid:\n  density: 1000.0\n", ""));
  EXPECT_HAS(e, "case.yaml: missing required section 'fluid'");
  e = error_of(replaced(kCase, "particles:\n  dx: 0.01\n", ""));
  EXPECT_HAS(e, "case.yaml: missing required section 'particles' (with at least dx");
  e = error_of(replaced(kCase, "{type: box, fill: fluid, min: [0.0, 0.0], max: [0.1, 0.1]}", "{type: box, fill: fluid, min: [0.0, 0.0]}"));
  EXPECT_HAS(e, "line 9: 'geometry.1': expected 'min' and 'max' corners");
}

TEST(InputErrors, WrongTypes) {
  std::string e = error_of(replaced(kCase, "dx: 0.01", "dx: fine"));
  EXPECT_HAS(e, "case.yaml: line 4: 'particles.dx': expected a number");
  e = error_of(replaced(kCase, "dimension: 2", "dimension: 2.5"));
  EXPECT_HAS(e, "line 2: 'dimension': expected an integer");
  e = error_of(replaced(kCase, "  density: 1000.0", "  hydrostatic_init: maybe"));
  EXPECT_HAS(e, "line 6: 'fluid.hydrostatic_init': expected true or false");
  e = error_of(replaced(kCase, "max: [0.1, 0.1]", "max: [0.1, high]"));
  EXPECT_HAS(e, "line 9: 'geometry.1.max': expected a list of 2 numbers");
  e = error_of(replaced(kCase, "  density: 1000.0", "  density: [1000.0]"));
  EXPECT_HAS(e, "line 6: 'fluid.density': expected a number");
  e = error_of(replaced(kCase, "time:\n  end: 1.0\n  output_interval: 0.1\n", "time: 1.0\n"));
  EXPECT_HAS(e, "line 10: 'time': expected a mapping");
}

TEST(InputErrors, OutOfRangeValues) {
  std::string e = error_of(replaced(kCase, "dx: 0.01", "dx: 0"));
  EXPECT_HAS(e, "case.yaml: line 4: 'particles.dx': expected a positive number (got 0)");
  e = error_of(replaced(kCase, "dx: 0.01", "dx: -0.01"));
  EXPECT_HAS(e, "line 4: 'particles.dx': expected a positive number (got -0.01)");
  e = error_of(replaced(kCase, "density: 1000.0", "density: 0"));
  EXPECT_HAS(e, "line 6: 'fluid.density': expected a positive number (got 0)");
  e = error_of(replaced(kCase, "density: 1000.0", "density: -1000"));
  EXPECT_HAS(e, "line 6: 'fluid.density': expected a positive number (got -1000)");
  e = error_of(replaced(kCase, "  dx: 0.01", "  dx: 0.01\n  h_over_dx: 3.0"));
  EXPECT_HAS(e, "line 5: 'particles.h_over_dx': expected a number in [1, 2.5] (got 3)");
  e = error_of(replaced(kCase, "  dx: 0.01", "  dx: 0.01\n  kernel: quintic_spline\n  h_over_dx: 0.5"));
  EXPECT_HAS(e, "line 6: 'particles.h_over_dx': expected a number in [0.8, 1.5] (got 0.5)");
  e = error_of(replaced(kCase, "end: 1.0", "end: 0"));
  EXPECT_HAS(e, "line 11: 'time.end': expected a positive number (got 0)");
  e = error_of(replaced(kCase, "end: 1.0", "end: -2"));
  EXPECT_HAS(e, "line 11: 'time.end': expected a positive number (got -2)");
  e = error_of(replaced(kCase, "output_interval: 0.1", "output_interval: 0"));
  EXPECT_HAS(e, "line 12: 'time.output_interval': expected a positive number (got 0)");
  e = error_of(replaced(kCase, "output_interval: 0.1", "output_interval: -0.1"));
  EXPECT_HAS(e, "line 12: 'time.output_interval': expected a positive number (got -0.1)");
  e = error_of(replaced(kCase, "output_interval: 0.1", "output_interval: 1.0e-12"));
  EXPECT_HAS(e, "line 12: 'time.output_interval': expected at most 1e+07 output times");
}

TEST(InputErrors, NonFiniteNumbersAnywhere) {
  std::string e = error_of(replaced(kCase, "dx: 0.01", "dx: .nan"));
  EXPECT_HAS(e, "case.yaml: line 4: 'particles.dx': expected a finite number (got .nan)");
  e = error_of(replaced(kCase, "density: 1000.0", "density: .inf"));
  EXPECT_HAS(e, "line 6: 'fluid.density': expected a finite number (got .inf)");
  e = error_of(replaced(kCase, "end: 1.0", "end: .Inf"));
  EXPECT_HAS(e, "line 11: 'time.end': expected a finite number (got .Inf)");
  e = error_of(replaced(kCase, "dimension: 2", "dimension: 2\ngravity: [0.0, -.inf]"));
  EXPECT_HAS(e, "line 3: 'gravity': expected finite numbers (got -.inf)");
  e = error_of(replaced(kCase, "max: [0.1, 0.1]", "max: [.NaN, 0.1]"));
  EXPECT_HAS(e, "line 9: 'geometry.1.max': expected finite numbers (got .NaN)");
  e = error_of(replaced(kCase, "density: 1000.0", "background_pressure: .nan"));
  EXPECT_HAS(e, "line 6: 'fluid.background_pressure': expected a finite number (got .nan)");
  e = error_of(replaced(kCase, "{type: box, fill: fluid, min: [0.0, 0.0], max: [0.1, 0.1]}",
                        "{type: polygon, vertices: [[0.0, 0.0], [0.1, .inf], [0.0, 0.1]]}"));
  EXPECT_HAS(e, "line 9: 'geometry.1.vertices': expected [x, z] pairs of finite numbers");
  e = error_of(std::string(kCase) + "forces:\n  - {type: body_force, acceleration: [1.0, .nan]}\n");
  EXPECT_HAS(e, "line 14: 'forces.0.acceleration.1': expected a finite number (got .nan)");
}

TEST(InputErrors, GeometryWithoutFluid) {
  std::string e = error_of(replaced(kCase, "  - {type: box, fill: fluid, min: [0.0, 0.0], max: [0.1, 0.1]}\n", ""));
  EXPECT_HAS(e, "case.yaml: line 7: 'geometry': the geometry makes no fluid particles: expected a shape with 'fill: fluid'");
  // a fluid shape thinner than dx makes no particles
  e = error_of(replaced(kCase, "max: [0.1, 0.1]", "max: [0.1, 0.005]"));
  EXPECT_HAS(e, "case.yaml: line 9: 'geometry.1': the fluid shape makes no particles: expected a shape at least "
                "particles.dx = 0.01 m wide");
  e = error_of(replaced(kCase, "geometry:\n", "geometry: []\nx:\n"));
  EXPECT_HAS(e, "line 7: 'geometry': expected a list of shapes");
}

TEST(InputErrors, FluidOutsideTheDomain) {
  const std::string with_domain = replaced(kCase, "fluid:\n", "domain: {min: [-0.1, -0.1], max: [0.5, 0.6]}\nfluid:\n");
  EXPECT_EQ(error_of(with_domain), "");
  // fluid box now on line 10
  std::string e = error_of(replaced(with_domain, "min: [0.0, 0.0], max: [0.1, 0.1]", "min: [0.0, 0.0], max: [0.1, 0.7]"));
  EXPECT_HAS(e, "case.yaml: line 10: 'geometry.1': the fluid shape extends outside the domain along z (0 .. 0.7 m, "
                "domain.min/max -0.1 .. 0.6 m): expected fluid shapes inside the domain");
  e = error_of(replaced(with_domain, "min: [0.0, 0.0], max: [0.1, 0.1]", "min: [-0.2, 0.0], max: [0.1, 0.1]"));
  EXPECT_HAS(e, "line 10: 'geometry.1': the fluid shape extends outside the domain along x");
  // walls may stick out (only fluid is removed at the domain's faces)
  EXPECT_EQ(error_of(replaced(with_domain, "max: [0.5, 0.6]}", "max: [0.3, 0.2]}")), "");
}

TEST(InputErrors, FluidInsideWalls) {
  // a fluid box drawn over a sloping bed: the few points under the bed are dropped
  const std::string bed = replaced(kCase, "  - {type: box, fill: fluid",
                                   "  - {type: polygon, fill: wall, vertices: [[0.2, 0.0], [0.4, 0.0], [0.4, 0.1]]}\n"
                                   "  - {type: box, fill: fluid");
  const std::string over_bed = replaced(bed, "max: [0.1, 0.1]", "max: [0.4, 0.2]");
  {
    const Case c = parse_case(over_bed, "case.yaml");
    System<2> S;
    const BuildReport rep = build_system<2>(c, S);
    EXPECT_GT(rep.fluid_dropped_in_walls, 0u);
    EXPECT_LT(rep.fluid_dropped_in_walls, rep.fluid / 4);
  }
  // a fluid box mostly inside a wall block: an error naming the shape
  const std::string block = replaced(kCase, "  - {type: box, fill: fluid",
                                     "  - {type: box, fill: wall, min: [0.0, 0.0], max: [0.4, 0.1]}\n"
                                     "  - {type: box, fill: fluid");
  std::string e = error_of(replaced(block, "max: [0.1, 0.1]}", "max: [0.1, 0.15]}"));
  EXPECT_HAS(e, "case.yaml: line 10: 'geometry.2': 100 of the fluid shape's 150 lattice points (67 %) lie inside walls");
  EXPECT_HAS(e, "expected a fluid shape at most half inside walls");
  // entirely inside
  e = error_of(block);
  EXPECT_HAS(e, "line 10: 'geometry.2': 100 of the fluid shape's 100 lattice points (100 %) lie inside walls");
  // less than half inside: dropped, no error
  EXPECT_EQ(error_of(replaced(block, "max: [0.1, 0.1]}", "max: [0.1, 0.3]}")), "");
}

TEST(InputErrors, AbsurdParticleCountsAreRefusedBeforeAllocating) {
  const auto t0 = std::chrono::steady_clock::now();
  std::string e = error_of(replaced(kCase, "dx: 0.01", "dx: 1.0e-7"));
  EXPECT_HAS(e, "case.yaml: line 7: 'geometry': the shapes would make about 1e+12 particles at particles.dx = 1e-07 m "
                "(most in geometry.1, line 9): expected at most 5e+08: use dx >= 4.56e-06 m");
  e = error_of(replaced(kCase, "dimension: 2", "dimension: 3"));  // (coordinates now have 2 numbers)
  EXPECT_HAS(e, "line 8: 'geometry.0.min': expected a list of 3 numbers");
  // a typo in a coordinate: 1e3 m instead of 0.1 m
  e = error_of(replaced(kCase, "max: [0.1, 0.1]", "max: [1e3, 1e3]"));
  EXPECT_HAS(e, "the shapes would make about 1e+10 particles at particles.dx = 0.01 m (most in geometry.1, line 9)");
  // shapes far apart: few particles, but a neighbour search over an absurd box
  e = error_of(replaced(kCase, "max: [0.4, 0.3]}", "max: [0.4, 0.3]}\n  - {type: box, fill: wall, min: [1.0e5, 1.0e5], max: [1.0e5, 1.0e5]}"));
  EXPECT_HAS(e, "line 9: 'geometry.1.max': expected max > min");  // checked first
  e = error_of(replaced(kCase, "max: [0.4, 0.3]}", "max: [0.4, 0.3]}\n  - {type: box, fill: wall, min: [1.0e5, 1.0e5], max: [1.00001e5, 1.00001e5]}"));
  EXPECT_HAS(e, "line 7: 'geometry': the run's box");
  EXPECT_HAS(e, "neighbour-search cells of the kernel support (0.03 m)");
  // coordinates too far from the origin to place particles dx apart
  e = error_of(replaced(kCase, "max: [0.4, 0.3]}", "max: [0.4, 0.3]}\n  - {type: box, fill: wall, min: [1.0e12, 0.0], max: [1.00000000001e12, 0.01]}"));
  EXPECT_HAS(e, "line 7: 'geometry': coordinates as large as 1e+12 m cannot be resolved at particles.dx = 0.01 m");
  // a smaller limit (the fuzzer's) names the dx that fits
  BuildLimits small;
  small.max_particles = 100;
  e = error_of(kCase, small);
  EXPECT_HAS(e, "the shapes would make about 418 particles at particles.dx = 0.01 m (most in geometry.0, line 8): "
                "expected at most 100: use dx >= 0.0");
  // ... and that dx fits
  const std::string fit = e.substr(e.find("dx >= ") + 6, e.find(" m or") - e.find("dx >= ") - 6);
  EXPECT_EQ(error_of(replaced(kCase, "dx: 0.01", "dx: " + fit), small), "") << fit;
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_LT(seconds, 2.0);  // refused up front, not after filling memory
}

TEST(InputErrors, DerivedValuesMustBeFinite) {
  std::string e = error_of(replaced(kCase, "dimension: 2", "dimension: 2\ngravity: [0.0, -1.0e300]"));
  EXPECT_HAS(e, "case.yaml: the sound speed c0 = ");
  EXPECT_HAS(e, "expected values of ordinary size (check gravity, fluid.sound_speed and fluid.gamma)");
  e = error_of(replaced(kCase, "dx: 0.01", "dx: 1.0e-200"));
  EXPECT_HAS(e, "'particles.dx' = 1e-200 m with 'fluid.density' = 1000 kg/m3 gives a particle mass of 0 kg");
  e = error_of(replaced(replaced(kCase, "density: 1000.0", "density: 1000.0\n  gamma: 0.01\n  sound_speed: 1"),
                        "dimension: 2", "dimension: 2\ngravity: [0.0, -1.0e10]"));
  EXPECT_HAS(e, "case.yaml: line 12: 'geometry.1': the initial density of the fluid at");
  EXPECT_HAS(e, "expected a positive finite density");
}

TEST(InputErrors, PeriodicDomainAndChoices) {
  std::string e = error_of(replaced(kCase, "fluid:\n", "domain: {min: [0.0, 0.0], max: [0.4, 0.3], periodic: [y]}\nfluid:\n"));
  EXPECT_HAS(e, "line 5: 'domain.periodic': expected axes among x, z");
  e = error_of(replaced(kCase, "fluid:\n", "domain: {min: [0.0, 0.0], max: [0.4, 0.3], periodic: [[x]]}\nfluid:\n"));
  EXPECT_HAS(e, "line 5: 'domain.periodic': expected axes among x, z");
  e = error_of(replaced(kCase, "fluid:\n", "domain: {min: [0.0, 0.0]}\nfluid:\n"));
  EXPECT_HAS(e, "line 5: 'domain': expected both 'min' and 'max' corners (or neither)");
  e = error_of(replaced(kCase, "density: 1000.0", "eos: Tait"));
  EXPECT_HAS(e, "line 6: 'fluid.eos': expected one of tait, linear (got 'Tait')");
}

// scheme.shifting: its keys are checked like every other section's
TEST(InputErrors, ShiftingKeysAreChecked) {
  EXPECT_EQ(error_of(replaced(kCase, "time:", "scheme: {shifting: {coefficient: 2}}\ntime:")), "");
  std::string e = error_of(replaced(kCase, "time:", "scheme: {shifting: {coefficient: -1}}\ntime:"));
  EXPECT_HAS(e, "line 10");
  EXPECT_HAS(e, "scheme.shifting.coefficient");
  e = error_of(replaced(kCase, "time:", "scheme: {shifting: {coeficient: 2}}\ntime:"));
  EXPECT_HAS(e, "unknown key 'scheme.shifting.coeficient' (did you mean 'scheme.shifting.coefficient'?)");
}

// Wave makers (issue 22): a paddle law above the theory's breaking limit, a time series that
// cannot be read, a motion no wall follows, a shape naming no motion: line-numbered errors.
TEST(InputErrors, MotionsAreChecked) {
  const std::string moving = replaced(kCase, "  - {type: tank, min: [0.0, 0.0], max: [0.4, 0.3]}\n",
                                      "  - {type: tank, min: [0.0, 0.0], max: [0.4, 0.3]}\n"
                                      "  - {type: box, fill: wall, min: [-0.04, 0.0], max: [0.0, 0.3], motion: paddle}\n");
  // line 15: motions.0
  auto with = [&](const std::string& motion) { return moving + "motions:\n  - " + motion + "\n"; };
  EXPECT_EQ(error_of(with("{name: paddle, law: solitary, height: 0.02, depth: 0.1}")), "");
  std::string m = error_of(with("{name: paddle, law: solitary, height: 0.09, depth: 0.1}"));
  EXPECT_HAS(m, "line 15");
  EXPECT_HAS(m, "motions.0.height");
  EXPECT_HAS(m, "0.78 depth");
  m = error_of(with("{name: paddle, law: regular, height: 0.09, depth: 0.1, period: 0.5}"));
  EXPECT_HAS(m, "Miche");
  m = error_of(with("{name: paddle, law: table, file: no_such_file.csv}"));
  EXPECT_HAS(m, "line 15");
  EXPECT_HAS(m, "motions.0.file");
  EXPECT_HAS(m, "no_such_file.csv");
  m = error_of(with("{name: paddle, law: solitary, theory: boussinesq, height: 0.02, depth: 0.1}"));
  EXPECT_HAS(m, "motions.0.theory");
  m = error_of(with("{name: other, law: solitary, height: 0.02, depth: 0.1}"));
  EXPECT_HAS(m, "line 9");
  EXPECT_HAS(m, "geometry.1.motion");
  m = error_of(moving);  // no motions section
  EXPECT_HAS(m, "'paddle' is not a motion");
  m = error_of(replaced(with("{name: paddle, law: solitary, height: 0.02, depth: 0.1}"), ", motion: paddle}", "}"));
  EXPECT_HAS(m, "moves no wall");
  m = error_of(replaced(kCase, "max: [0.1, 0.1]}", "max: [0.1, 0.1], motion: paddle}"));
  EXPECT_HAS(m, "geometry.1.motion");
  EXPECT_HAS(m, "a wall shape");
}

// Run-up gauges (issue 22): a negative film thickness, a line that does not go up, or a missing
// still-water level are errors that name the key (line 14: gauges.0).
TEST(InputErrors, RunupGaugesAreChecked) {
  auto with = [&](const std::string& g) { return std::string(kCase) + "gauges:\n  - " + g + "\n"; };
  EXPECT_EQ(error_of(with("{name: r, type: runup, start: [0.0, 0.0], end: [0.4, 0.2], level: 0.1}")), "");
  EXPECT_EQ(error_of(with("{name: r, type: runup, start: [0.0, 0.0], end: [0.4, 0.2], level: 0.1, film: 0.015}")), "");
  std::string m = error_of(with("{name: r, type: runup, start: [0.0, 0.0], end: [0.4, 0.2], level: 0.1, film: -0.01}"));
  EXPECT_HAS(m, "line 14");
  EXPECT_HAS(m, "gauges.0.film");
  m = error_of(with("{name: r, type: runup, start: [0.0, 0.2], end: [0.4, 0.0], level: 0.1}"));
  EXPECT_HAS(m, "gauges.0.end");
  m = error_of(with("{name: r, type: runup, start: [0.0, 0.0], end: [0.4, 0.2]}"));
  EXPECT_HAS(m, "level");
}

// Slopes (issue 22): a slope given by toe, gradient ('1:2.08' or rise/run) and top is the polygon
// of its wedge; a slope reaching outside the tank, a gradient that is not one, a top under the toe
// are line-numbered errors.
TEST(InputErrors, SlopesAreChecked) {
  auto with = [&](const std::string& slope) {
    return replaced(kCase, "  - {type: box, fill: fluid, min: [0.0, 0.0], max: [0.1, 0.1]}\n",
                    "  - {type: box, fill: fluid, min: [0.0, 0.0], max: [0.1, 0.1]}\n  - " + slope + "\n");
  };  // line 10: geometry.2
  const Case c = parse_case(with("{type: slope, toe: [0.2, 0.0], gradient: '1:2', top: 0.1, thickness: 0}"), "case.yaml");
  ASSERT_EQ(c.shapes.size(), 3u);
  const auto& v = c.shapes[2].vertices;
  ASSERT_EQ(v.size(), 3u);  // a wedge: toe, top, foot of the back
  EXPECT_DOUBLE_EQ(v[1][0], 0.4);
  EXPECT_DOUBLE_EQ(v[1][1], 0.1);
  EXPECT_EQ(c.shapes[2].fill, "wall");
  EXPECT_EQ(error_of(with("{type: slope, toe: [0.2, 0.0], gradient: 0.5, top: 0.1}")), "");
  std::string m = error_of(with("{type: slope, toe: [0.2, 0.0], gradient: '1:2', top: 0.2}"));  // x = 0.6 > 0.4
  EXPECT_HAS(m, "line 10");
  EXPECT_HAS(m, "outside the tank");
  m = error_of(with("{type: slope, toe: [0.2, 0.0], gradient: steep, top: 0.1}"));
  EXPECT_HAS(m, "geometry.2.gradient");
  m = error_of(with("{type: slope, toe: [0.2, 0.1], gradient: 0.5, top: 0.05}"));
  EXPECT_HAS(m, "geometry.2.top");
  // a wall slope is by default a layer as deep as the wall layers (3 dx here)
  const Case d = parse_case(with("{type: slope, toe: [0.2, 0.0], gradient: '1:2', top: 0.1}"), "case.yaml");
  ASSERT_EQ(d.shapes[2].vertices.size(), 4u);
  EXPECT_NEAR(d.shapes[2].vertices[3][0] - 0.2, 0.03 * std::sqrt(5.0), 1e-12);
  // a layer: a parallelogram of normal thickness t, t / sin(alpha) wide along the bed
  const Case l = parse_case(with("{type: slope, toe: [0.1, 0.0], gradient: 0.5, top: 0.1, thickness: 0.02}"), "case.yaml");
  const auto& w = l.shapes[2].vertices;
  ASSERT_EQ(w.size(), 4u);
  EXPECT_NEAR(w[3][0] - w[0][0], 0.02 * std::sqrt(1.25) / 0.5, 1e-12);
}

// A moving wall thinner than the wall layers would let the fluid through: refused with the fix.
TEST(InputErrors, ThinPaddleIsRefused) {
  const std::string thin = replaced(kCase, "  - {type: tank, min: [0.0, 0.0], max: [0.4, 0.3]}\n",
                                    "  - {type: tank, min: [0.0, 0.0], max: [0.4, 0.3]}\n"
                                    "  - {type: box, fill: wall, min: [-0.02, 0.0], max: [0.0, 0.3], motion: paddle}\n") +
                           "motions:\n  - {name: paddle, law: solitary, height: 0.02, depth: 0.1}\n";
  const std::string m = error_of(thin);
  EXPECT_HAS(m, "line 9");
  EXPECT_HAS(m, "thinner than the 3 wall layers");
  EXPECT_HAS(m, "at least 0.03 m thick");
}

TEST(InputErrors, DualIntegratorRefusesModelsItLacks) {
  // the default laminar viscosity of water is one of them: the message names it and the way out
  const std::string dual = replaced(kCase, "time:\n", "scheme:\n  integrator: dual\ntime:\n");
  std::string e = error_of(dual);
  EXPECT_HAS(e, "'scheme.integrator: dual'");
  EXPECT_HAS(e, "fluid.viscosity > 0 with viscosity: laminar");
  EXPECT_HAS(e, "use integrator: symplectic or verlet");
  e = error_of(replaced(dual, "  density: 1000.0\n", "  density: 1000.0\n  viscosity: 0.0\n"));
  EXPECT_EQ(e, "");  // inviscid, dummy walls: accepted
  e = error_of(replaced(replaced(dual, "  density: 1000.0\n", "  density: 1000.0\n  viscosity: 0.0\n"), "scheme:\n",
                        "walls: {type: dynamic}\nscheme:\n"));
  EXPECT_HAS(e, "walls.type: dynamic");
}

// The wall_force gauge in 3D: a rectangle of a wall face (opposite corners, equal along the axis of its normal) and the
// normal pointing into the water, along one axis.
TEST(InputErrors, WallForceGaugesAreCheckedIn3D) {
  const std::string base = R"(name: t
dimension: 3
particles:
  dx: 0.05
fluid:
  density: 1000.0
geometry:
  - {type: tank, min: [0.0, 0.0, 0.0], max: [0.4, 0.3, 0.3]}
  - {type: box, fill: fluid, min: [0.0, 0.0, 0.0], max: [0.2, 0.3, 0.1]}
time:
  end: 1.0
gauges:
)";  // line 13: gauges.0
  auto with = [&](const std::string& g) { return base + "  - " + g + "\n"; };
  EXPECT_EQ(error_of(with("{name: f, type: wall_force, start: [0.4, 0.0, 0.0], end: [0.4, 0.3, 0.3], normal: [-1, 0, 0]}")), "");
  std::string m = error_of(with("{name: f, type: wall_force, start: [0.4, 0.0, 0.0], end: [0.4, 0.3, 0.3]}"));
  EXPECT_HAS(m, "line 13");
  EXPECT_HAS(m, "normal");
  m = error_of(with("{name: f, type: wall_force, start: [0.4, 0.0, 0.0], end: [0.4, 0.3, 0.3], normal: [-1, 1, 0]}"));
  EXPECT_HAS(m, "gauges.0.normal");
  EXPECT_HAS(m, "along one axis");
  m = error_of(with("{name: f, type: wall_force, start: [0.4, 0.0, 0.0], end: [0.3, 0.3, 0.3], normal: [-1, 0, 0]}"));
  EXPECT_HAS(m, "gauges.0.end");
  EXPECT_HAS(m, "the same x");
  m = error_of(with("{name: f, type: wall_force, start: [0.4, 0.0, 0.0], end: [0.4, 0.3, 0.0], normal: [-1, 0, 0]}"));
  EXPECT_HAS(m, "a width along both");
}
