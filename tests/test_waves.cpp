// The wave flume's design tools (issue 59): irregular seas and focused groups from a spectrum,
// a user's elevation series, active absorption's input checks and the overtopping gauge.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <numbers>
#include <random>
#include <utility>
#include <vector>

#include "sphflume/boundaries/motion.hpp"
#include "sphflume/boundaries/paddle.hpp"
#include "sphflume/boundaries/wave_spectrum.hpp"
#include "sphflume/io/case.hpp"
#include "sphflume/io/gauges.hpp"
#include "sphflume/setup/setup.hpp"
#include "sphflume/sim/simulation.hpp"
#include "test_helpers.hpp"

using namespace sph;

namespace {

constexpr double kPi = std::numbers::pi;

MotionConfig sea(double hm0 = 0.05, double tp = 1.5) {
  MotionConfig m = test::wave_motion("irregular", 0.5);
  m.hm0 = hm0;
  m.tp = tp;
  return m;
}

/// A 2D flume with a paddle box named `paddle`, lines 1-10 of the bad-input tests' cases (motions and
/// gauges follow from line 11).
const std::string kFlume = R"(name: t
dimension: 2
gravity: [0.0, -9.81]
particles: {dx: 0.02, h_over_dx: 2.0}
fluid: {density: 1000.0}
geometry:
  - {type: tank, fill: wall, min: [-0.2, 0.0], max: [4.0, 0.8]}
  - {type: box, fill: wall, min: [-0.12, 0.0], max: [0.0, 0.8], motion: paddle}
  - {type: box, fill: fluid, min: [0.0, 0.0], max: [4.0, 0.5]}
time: {end: 20.0, output_interval: 0.1}
)";

/// The message of the InputError parsing `text` raises, after replacing each `from` by its `to` ("" if none).
std::string parse_error(std::string text, const std::vector<std::pair<std::string, std::string>>& edits = {}) {
  for (const auto& [from, to] : edits) {
    const auto at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    if (at != std::string::npos) text.replace(at, from.size(), to);
  }
  try {
    (void)parse_case(text, "case.yaml");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

/// ∫ S df of the JONSWAP shape over [a, b] by the midpoint rule on 20000 cells.
double shape_integral(double a, double b, double fp, double gamma) {
  const int n = 20000;
  double s = 0.0;
  for (int i = 0; i < n; ++i) s += jonswap_shape(a + (i + 0.5) * (b - a) / n, fp, gamma);
  return s * (b - a) / n;
}

}  // namespace

// The discrete sea holds Hm0 exactly (4 sqrt(Σ a²/2)), peaks at fp (within one Δf), and the
// default band [0.5 fp, 3 fp] holds 99.0 % of a JONSWAP γ = 3.3 sea's m0 (98.5 % of a PM sea's: its
// tail is longer; numbers of a 2-million-point quadrature), so little of the sea is left out.
TEST(Waves, SpectrumHoldsHm0AndPeaksAtFp) {
  for (const double gamma : {1.0, 3.3, 7.0}) {
    MotionConfig m = sea();
    m.gamma = gamma;
    const auto c = wave_components(m);
    ASSERT_EQ(static_cast<int>(c.size()), default_components(m));
    double m0 = 0.0, amax = 0.0, fpk = 0.0;
    for (const auto& w : c) {
      m0 += 0.5 * w.amplitude * w.amplitude;
      if (w.amplitude > amax) { amax = w.amplitude; fpk = w.omega / (2 * kPi); }
    }
    EXPECT_NEAR(4.0 * std::sqrt(m0), m.hm0, 1e-12 * m.hm0);
    const double df = 2.5 / m.tp / static_cast<double>(c.size());
    EXPECT_NEAR(fpk, 1.0 / m.tp, df) << "gamma " << gamma;
    const double fp = 1.0 / m.tp;
    const double frac = shape_integral(0.5 * fp, 3.0 * fp, fp, gamma) / shape_integral(0.2 * fp, 40.0 * fp, fp, gamma);
    EXPECT_GT(frac, gamma > 1.0 ? 0.9895 : 0.984) << "gamma " << gamma;
  }
  // the sea repeats after 1/Δf = 200 Tp, whatever the run's length (a restart may lengthen it)
  const MotionConfig m = sea();
  EXPECT_NEAR(static_cast<double>(default_components(m)) / (2.5 / m.tp), 200.0 * m.tp, 1e-9);
}

// The phases come from the seed alone (the same sea on every machine, another seed another sea),
// and are uniform: the mean of cos φ and sin φ over N components within 4/sqrt(2N) of 0.
TEST(Waves, PhasesFollowTheSeed) {
  MotionConfig m = sea();
  m.components = 2000;
  const auto a = wave_components(m), b = wave_components(m);
  m.seed = 2;
  const auto c = wave_components(m);
  double same = 0.0, differ = 0.0, mc = 0.0, ms = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    same = std::max(same, std::abs(a[i].phase - b[i].phase));
    differ += std::abs(a[i].phase - c[i].phase);
    mc += std::cos(a[i].phase);
    ms += std::sin(a[i].phase);
    EXPECT_GE(a[i].phase, 0.0);
    EXPECT_LT(a[i].phase, 2 * kPi);
  }
  EXPECT_EQ(same, 0.0);
  EXPECT_GT(differ / static_cast<double>(a.size()), 0.5);
  const double n = static_cast<double>(a.size());
  EXPECT_LT(std::abs(mc / n), 4.0 / std::sqrt(2.0 * n));
  EXPECT_LT(std::abs(ms / n), 4.0 / std::sqrt(2.0 * n));
  // the 64-bit twister's 10000th output is fixed by the C++ standard: the sea is portable
  std::mt19937_64 rng(5489u);
  rng.discard(9999);
  EXPECT_EQ(rng(), 9981545732273789042ull);
}

// The paddle drives each component through the piston's transfer function: X = r Σ (a/m1) sin,
// η at the face = r Σ a cos, so X' = (η-weighted) Σ a ω/m1 cos. Checked against the components,
// with the analytic velocity against a central difference of X, and |X| within the stated stroke.
TEST(Waves, IrregularPaddleUsesTheTransferFunction) {
  MotionConfig m = sea();
  m.ramp = 3.0;
  m.start = 0.5;
  const auto law = make_paddle_law(m, "test.yaml");
  const auto c = wave_components(m);
  for (const double t : {4.0, 7.3, 20.0, 55.5}) {
    const double tau = t - m.start;
    double x = 0.0, e = 0.0;
    for (const auto& w : c) {
      x += w.amplitude / piston_transfer(w.k * m.depth) * std::sin(w.omega * tau + w.phase);
      e += w.amplitude * std::cos(w.omega * tau + w.phase);
    }
    EXPECT_NEAR(law->displacement(t), x, 1e-12);
    EXPECT_NEAR(law->elevation(t, 0.0), e, 1e-12);
  }
  double worst = 0.0, xmax = 0.0;
  for (double t = 0.0; t < 30.0; t += 0.01) {
    const double d = 1e-6;
    const double fd = (law->displacement(t + d) - law->displacement(t - d)) / (2 * d);
    worst = std::max(worst, std::abs(fd - law->velocity(t)));
    xmax = std::max(xmax, std::abs(law->displacement(t)));
  }
  EXPECT_LT(worst, 1e-6);  // through the ramp too (the ramp's rate is in the velocity)
  EXPECT_LE(xmax, 0.5 * law->stroke());
  EXPECT_EQ(law->displacement(0.5), 0.0);
  EXPECT_NEAR(law->velocity(0.5 + 1e-6), 0.0, 1e-6);  // from rest
}

// A NewWave group: every component's crest meets at the focus, η(x_f, t_f) = A (linear sum of
// the components' progressive waves), and the group is lower everywhere else along the flume.
TEST(Waves, FocusedGroupCrestsAtTheFocus) {
  MotionConfig m = sea();
  m.law = "focused";
  m.amplitude = 0.04;
  m.focus_x = 6.0;
  m.focus_time = 12.0;
  const auto c = wave_components(m);
  auto eta = [&](double x, double tau) {
    double e = 0.0;
    for (const auto& w : c) e += w.amplitude * std::cos(w.omega * tau + w.phase - w.k * x);
    return e;
  };
  EXPECT_NEAR(eta(m.focus_x, m.focus_time), m.amplitude, 1e-12);
  for (const double dx : {-2.0, -0.5, 0.7, 3.0})
    for (const double dt : {-1.0, -0.3, 0.0, 0.4})
      EXPECT_LT(eta(m.focus_x + dx, m.focus_time + dt), 0.95 * m.amplitude);
  const auto law = make_paddle_law(m, "test.yaml");
  EXPECT_NEAR(law->elevation(m.start + 3.0, 0.0), eta(0.0, 3.0), 1e-12);
  EXPECT_NEAR(law->elevation(m.start + 9.0, 2.5), eta(2.5, 9.0), 1e-12);
}

// A user's elevation series: sampled evenly, its Fourier components are those of the series, so
// the law's elevation reproduces a periodic series of three harmonics to round-off between its
// ends, and the paddle moves each through the transfer function.
TEST(Waves, ElevationSeriesIsDecomposedExactly) {
  MotionConfig m = test::wave_motion("elevation", 0.5);
  const double T = 20.0;
  const int n = 2000;
  auto series = [&](double t) {
    return 0.02 * std::cos(2 * kPi * 15 * t / T + 0.3) + 0.01 * std::sin(2 * kPi * 31 * t / T) + 0.005 * std::cos(2 * kPi * 47 * t / T - 1.0);
  };
  for (int j = 0; j <= n; ++j) {
    m.elevation_t.push_back(T * j / n);
    m.elevation_eta.push_back(series(T * j / n) + 0.1);  // (an offset: the still level is dropped)
  }
  const auto law = make_paddle_law(m, "test.yaml");
  // the law's series has n + 1 samples over T: its even resampling is at T/(n + 1), not the
  // samples' own spacing, so the harmonics are read to the linear interpolation's error
  double worst = 0.0;
  for (double t = 1.0; t < 19.0; t += 0.0137) worst = std::max(worst, std::abs(law->elevation(t, 0.0) - series(t)));
  EXPECT_LT(worst, 2e-3 * 0.035);
  const auto c = wave_components(m);
  double x = 0.0;
  for (const auto& w : c) x += w.amplitude / piston_transfer(w.k * m.depth) * std::sin(w.omega * 7.0 + w.phase);
  EXPECT_NEAR(law->displacement(7.0), x, 1e-12);
  EXPECT_EQ(law->displacement(T + 0.1), 0.0);  // at rest after the series
}

// Bad input: a spectrum without Tp, a sea above Miche's limit, absorption without a level gauge
// at the paddle's face (missing, of another type, behind the paddle or far from it), an absorber
// without absorption, and an overtopping gauge's width (required in 3D, refused in 2D): each names
// its line and key.
TEST(Waves, BadInputIsNamed) {
  const std::string base = kFlume + R"(gauges:
  - {name: eta_face, type: water_level, x: 0.1}
  - {name: pressure, type: pressure, point: [1.0, 0.1]}
motions:
  - {name: paddle, law: irregular, hm0: 0.05, tp: 1.5, depth: 0.5, ramp: 3.0}
)";
  const std::string more = "ramp: 3.0}";
  auto with = [&](const std::string& keys) { return parse_error(base, {{more, "ramp: 3.0" + keys + "}"}}); };
  EXPECT_EQ(parse_error(base), "");
  EXPECT_EQ(with(", absorption: {gauge: eta_face}"), "");
  EXPECT_HAS(parse_error(base, {{"tp: 1.5, ", ""}}), "line 15: 'motions.0.tp': expected the peak period Tp");
  EXPECT_HAS(with(", gamma: 0.5"), "motions.0.gamma");
  EXPECT_HAS(parse_error(base, {{"hm0: 0.05", "hm0: 0.20"}}), "Miche");
  EXPECT_HAS(with(", absorption: {gauge: nothing}"), "line 15: 'motions.0.absorption.gauge': expected a water_level gauge");
  EXPECT_HAS(with(", absorption: {gauge: pressure}"), "is a pressure gauge");
  EXPECT_HAS(with(", absorption: {gauge: eta_face, drift: 3}"), "motions.0.absorption.drift");
  EXPECT_HAS(parse_error(base, {{"x: 0.1}", "x: 1.5}"}, {more, "ramp: 3.0, absorption: {gauge: eta_face}}"}}),
             "its absorption gauge 'eta_face' is 1.5 m from the paddle's face");
  EXPECT_HAS(parse_error(base, {{"law: irregular, hm0: 0.05, tp: 1.5, depth: 0.5, ramp: 3.0",
                                 "law: solitary, height: 0.1, depth: 0.5, absorption: {gauge: eta_face}"}}),
             "a drift_time");
  EXPECT_HAS(parse_error(base, {{"law: irregular, hm0: 0.05, tp: 1.5, depth: 0.5, ramp: 3.0", "law: absorber, depth: 0.5"}}),
             "'motions.0.absorption': expected an 'absorption: {gauge: NAME}' on an absorber");
  // the second-order correction: on a law made of linear waves only; its modes only with it
  EXPECT_EQ(with(", second_order: true, evanescent_modes: 10"), "");
  EXPECT_HAS(with(", evanescent_modes: 10"), "line 15: 'motions.0.evanescent_modes': expected second_order: true");
  EXPECT_HAS(with(", second_order: true, evanescent_modes: 500"), "expected an integer in [0, 200]");
  EXPECT_HAS(parse_error(base, {{"law: irregular, hm0: 0.05, tp: 1.5, depth: 0.5, ramp: 3.0",
                                 "law: stokes2, height: 0.03, depth: 0.5, period: 1.2, second_order: true"}}),
             "'motions.0.second_order': expected law regular with second_order: true");
  EXPECT_HAS(parse_error(base, {{"law: irregular, hm0: 0.05, tp: 1.5, depth: 0.5, ramp: 3.0",
                                 "law: solitary, height: 0.1, depth: 0.5, second_order: true"}}),
             "expected a law made of linear waves for the second-order correction");
  // the overtopping gauge: its width in 3D, none in 2D
  EXPECT_HAS(parse_error(base, {{"  - {name: pressure,", "  - {name: over, type: overtopping, x: 3.0, width: 1.0}\n  - {name: pressure,"}}),
             "line 13: 'gauges.1.width': expected no width in 2D");
  const std::string box3d = R"(name: t
dimension: 3
particles: {dx: 0.05}
fluid: {density: 1000.0}
geometry:
  - {type: tank, fill: wall, min: [0.0, 0.0, 0.0], max: [1.0, 0.5, 0.5]}
  - {type: box, fill: fluid, min: [0.0, 0.0, 0.0], max: [0.5, 0.5, 0.2]}
time: {end: 1.0, output_interval: 0.1}
gauges:
  - {name: over, type: overtopping, x: 0.7}
)";
  EXPECT_HAS(parse_error(box3d), "line 10: 'gauges.0.width': expected the crest's width along y");
  EXPECT_EQ(parse_error(box3d, {{"x: 0.7}", "x: 0.7, width: 0.5}"}}), "");
}

// A flap's bad input: its hinge below the bed or above the water, a missing hinge, a law made for
// a piston, a vertical direction; hinge keys on a piston.
TEST(Waves, FlapBadInputIsNamed) {
  const std::string base = kFlume + R"(motions:
  - {name: paddle, law: regular, height: 0.03, depth: 0.5, period: 1.2, paddle: flap, hinge: [0.0, 0.1]}
)";
  EXPECT_EQ(parse_error(base), "");
  EXPECT_HAS(parse_error(base, {{"hinge: [0.0, 0.1]", "hinge: [0.0, -0.05]"}}),
             "line 12: 'motions.0.hinge': expected a hinge at or above the bed");
  EXPECT_HAS(parse_error(base, {{"hinge: [0.0, 0.1]", "hinge: [0.0, 0.6]"}}), "a hinge below the still-water level");
  EXPECT_HAS(parse_error(base, {{", hinge: [0.0, 0.1]", ""}}), "'motions.0.hinge': expected the flap's hinge");
  EXPECT_HAS(parse_error(base, {{"law: regular, height: 0.03, depth: 0.5, period: 1.2", "law: solitary, height: 0.1, depth: 0.5"}}),
             "'motions.0.paddle': expected a piston for law solitary");
  EXPECT_HAS(parse_error(base, {{"paddle: flap, hinge", "direction: [0.0, 1.0], paddle: flap, hinge"}}),
             "a horizontal direction for a flap");
  EXPECT_HAS(parse_error(base, {{"paddle: flap, hinge: [0.0, 0.1]", "hinge: [0.0, 0.1]"}}), "no hinge or level on a piston");
}

// The overtopping gauge counts the water beyond its crest line, Σ m/ρ0: in a still tank, the
// fluid area beyond x (2D: per metre already), to the lattice's one column.
TEST(Waves, OvertoppingGaugeCountsTheLeeSide) {
  const Case c = parse_case(R"(name: t
dimension: 2
gravity: [0.0, -9.81]
particles: {dx: 0.01}
fluid: {density: 1000.0}
geometry:
  - {type: tank, fill: wall, min: [0.0, 0.0], max: [1.0, 0.5]}
  - {type: box, fill: fluid, min: [0.0, 0.0], max: [1.0, 0.2]}
time: {end: 1.0, output_interval: 0.1}
gauges:
  - {name: over, type: overtopping, x: 0.7}
  - {name: back, type: overtopping, x: 0.7, direction: -1}
)", "case.yaml");
  System<2> S;
  build_system<2>(c, S);
  S.update_neighbours();
  const double v = GaugeSet<2>::evaluate(c.gauges[0], S, 0.5)[0];
  const double w = GaugeSet<2>::evaluate(c.gauges[1], S, 0.5)[0];
  EXPECT_NEAR(v, 0.3 * 0.2, 0.5 * 0.01 * 0.2 + 1e-9);
  EXPECT_NEAR(v + w, 1.0 * 0.2, 1e-9);  // every particle on one side or the other
}

// Water that leaves the domain through the lee face (a catch tank behind a dike's crest) stays counted:
// the overtopping gauges on both sides of a line hold the whole initial volume at every output, to
// round-off, while a dam break's surge runs out through the domain's x+ face (most of the column by
// t = 0.6 s). A restart from the snapshot at t = 0.3 s, after water has left, ends on the same row.
TEST(Waves, OvertoppingGaugeCountsWaterThatLeftThroughTheLeeFace) {
  const Case c = parse_case(R"(name: t
dimension: 2
gravity: [0.0, -9.81]
particles: {dx: 0.02, h_over_dx: 2.0}
fluid: {density: 1000.0}
domain: {min: [-0.2, -0.2], max: [0.6, 1.0]}
geometry:
  - {type: tank, fill: wall, min: [0.0, 0.0], max: [1.0, 0.5]}
  - {type: box, fill: fluid, min: [0.0, 0.0], max: [0.3, 0.3]}
time: {end: 0.6, output_interval: 0.05, snapshot_interval: 0.3}
gauges:
  - {name: over, type: overtopping, x: 0.5}
  - {name: back, type: overtopping, x: 0.5, direction: -1}
)", "case.yaml");
  const auto base = std::filesystem::temp_directory_path() / "sphflume_test_overtopping_gone";
  auto rows = [](const std::string& file) {
    std::ifstream f(file);
    std::vector<std::pair<double, double>> r;
    std::string line;
    std::getline(f, line);  // header
    while (std::getline(f, line)) {
      std::istringstream in(line);
      double t, v;
      char comma;
      if (in >> t >> comma >> v) r.emplace_back(t, v);
    }
    return r;
  };
  RunOptions o;
  o.output = (base / "whole").string();
  o.progress = false;
  o.threads = 1;
  ASSERT_EQ(run_case(c, o).exit_code, 0);
  const auto over = rows(o.output + "/gauges/over.csv"), back = rows(o.output + "/gauges/back.csv");
  ASSERT_EQ(over.size(), 13u);
  ASSERT_EQ(back.size(), over.size());
  const double v0 = 0.3 * 0.3;
  for (std::size_t k = 0; k < over.size(); ++k) EXPECT_NEAR(over[k].second + back[k].second, v0, 1e-12) << "t " << over[k].first;
  std::ifstream sf(o.output + "/summary.json");
  const std::string summary((std::istreambuf_iterator<char>(sf)), std::istreambuf_iterator<char>());
  EXPECT_NE(summary.find("\"x+\""), std::string::npos);  // water did leave through the lee face
  EXPECT_GT(over.back().second, 0.5 * v0);                   // most of it by t = 0.6
  EXPECT_GT(over[6].second, 0.1 * v0);                       // some before the restart point (t = 0.3)
  RunOptions r = o;
  r.output = (base / "restarted").string();
  r.restart = o.output + "/snapshots/snap_000001.h5";
  ASSERT_EQ(run_case(c, r).exit_code, 0);
  const auto over_r = rows(r.output + "/gauges/over.csv");
  ASSERT_FALSE(over_r.empty());
  EXPECT_DOUBLE_EQ(over_r.back().first, over.back().first);
  EXPECT_NEAR(over_r.back().second, over.back().second, 1e-12);
  std::filesystem::remove_all(base);
}

// The flap's transfer function: at d = h it is Dean & Dalrymple's bottom-hinged flap
// 4 sinh kh (kh sinh kh − cosh kh + 1)/(kh (sinh 2kh + 2kh)); in shallow water it tends to half the
// piston's (the flap's depth-mean stroke is half its top's); for any hinge depth it equals the
// wavemaker integral 4 k sinh kh ∫ f cosh k(h+z) dz/(sinh 2kh + 2kh) by quadrature; deep water → 2 (1 − (1 − e^{−kd})/kd),
// continuous where the deep-water branch takes over (kh = 20).
TEST(Waves, FlapTransferFunction) {
  for (const double kh : {0.3, 1.0, 2.5}) {
    const double dd = 4 * std::sinh(kh) * (kh * std::sinh(kh) - std::cosh(kh) + 1) / (kh * (std::sinh(2 * kh) + 2 * kh));
    EXPECT_NEAR(flap_transfer(kh, 1.0), dd, 1e-13);
    for (const double dh : {0.3, 0.7, 1.0}) {
      const double h = 1.0, k = kh / h, d = dh * h;
      const int n = 20000;
      double in = 0.0;
      for (int i = 0; i < n; ++i) {  // midpoint rule over the flap, z in [−d, 0]
        const double z = -d + (i + 0.5) * d / n;
        in += (z + d) / d * std::cosh(k * (h + z)) * d / n;
      }
      const double quad = 4 * k * std::sinh(kh) * in / (std::sinh(2 * kh) + 2 * kh);
      EXPECT_NEAR(flap_transfer(kh, dh), quad, 1e-7 * quad) << "kh " << kh << " d/h " << dh;
    }
  }
  EXPECT_NEAR(flap_transfer(1e-3, 1.0) / piston_transfer(1e-3), 0.5, 1e-3);
  EXPECT_NEAR(flap_transfer(30.0, 1.0), 2.0 * (1.0 - (1.0 - std::exp(-30.0)) / 30.0), 1e-12);
  EXPECT_NEAR(flap_transfer(20.0 - 1e-9, 0.5), flap_transfer(20.0 + 1e-9, 0.5), 1e-10);  // (slope 0.01)
}

// A flap turns about its hinge: each wall particle keeps its distance from the hinge, the particle
// at the still-water level moves by X along the direction (tan θ = X/d), the velocity and
// acceleration the motion sets are the time derivatives of the positions it sets (central
// differences), and the vectors to the wall's surface turn with the flap.
TEST(Waves, FlapTurnsAboutItsHinge) {
  const Case c = parse_case(R"(name: t
dimension: 2
gravity: [0.0, -9.81]
particles: {dx: 0.02, h_over_dx: 2.0}
fluid: {density: 1000.0}
geometry:
  - {type: tank, fill: wall, min: [-0.3, 0.0], max: [3.0, 0.8]}
  - {type: box, fill: wall, min: [-0.12, 0.1], max: [0.0, 0.8], motion: flap}
  - {type: box, fill: fluid, min: [0.0, 0.0], max: [3.0, 0.5]}
time: {end: 5.0, output_interval: 0.1}
motions:
  - {name: flap, law: regular, paddle: flap, hinge: [0.0, 0.1], height: 0.03, depth: 0.5, period: 1.2, ramp: 1.2}
)", "case.yaml");
  ASSERT_NEAR(c.motions[0].hinge_depth, 0.4, 1e-12);
  System<2> S;
  BuildReport rep;
  (void)setup_system<2>(c, S, rep);
  auto& P = S.particles;
  const auto& grp = *P.find(field::motion_group);
  const auto& org = *P.find(field::motion_origin);
  const Vec<2> hinge{0.0, 0.1};
  auto state = [&](double t) {
    move_walls(S, t);
    return std::make_tuple(P.pos, P.vel, P.vector(field::wall_acc), P.vector(field::wall_to_surface));
  };
  const auto [x0, v0, a0, s0] = state(0.0);
  const double t = 2.0, dt = 1e-4;
  const auto [xm, vm, am, sm] = state(t - dt);
  const auto [xp, vp, ap, sp] = state(t + dt);
  const auto [x, v, a, s] = state(t);
  const double X = S.motion->displacement(0, t), th = std::atan2(X, 0.4);
  ASSERT_GT(std::abs(X), 1e-3);
  int moved = 0, at_level = 0;
  for (std::size_t i = 0; i < P.n_owned(); ++i) {
    if (grp[i] != 1.0) continue;
    ++moved;
    EXPECT_NEAR(norm(x[i] - hinge), norm(org[i] - hinge), 1e-12);
    const Vec<2> fd_v = (1.0 / (2 * dt)) * (xp[i] - xm[i]), fd_a = (1.0 / (2 * dt)) * (vp[i] - vm[i]);
    EXPECT_NEAR(norm(fd_v - v[i]), 0.0, 1e-6);
    EXPECT_NEAR(norm(fd_a - a[i]), 0.0, 1e-3 * (1.0 + norm(a[i])));
    // (x, z) turned by θ toward +x: (x cos θ + z sin θ, z cos θ − x sin θ)
    const double c = std::cos(th), sn = std::sin(th);
    EXPECT_NEAR(s[i][0], s0[i][0] * c + s0[i][1] * sn, 1e-12);
    EXPECT_NEAR(s[i][1], s0[i][1] * c - s0[i][0] * sn, 1e-12);
    if (std::abs(org[i][1] - 0.51) < 1e-9 && std::abs(org[i][0] + 0.01) < 1e-9) {  // the face's first column at z = 0.51
      ++at_level;  // 0.41 m above the hinge, 0.01 m behind the face
      EXPECT_NEAR(x[i][0] - org[i][0], 0.41 * sn + 0.01 * (1.0 - c), 1e-12);
      EXPECT_NEAR(0.4 * std::tan(th), X, 1e-12);  // the face's line meets the still-water level at X
    }
  }
  EXPECT_GT(moved, 100);
  EXPECT_EQ(at_level, 1);
}
