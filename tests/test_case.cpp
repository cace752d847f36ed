// Case files: strict parsing with file/line/key in every message, --set overrides.
#include <gtest/gtest.h>

#include <cmath>

#include "sphflume/io/case.hpp"

using namespace sph;

namespace {
const char* kBase = R"(name: t
dimension: 2
particles:
  dx: 0.01
fluid:
  density: 1000.0
geometry:
  - {type: box, fill: fluid, min: [0.0, 0.0], max: [0.1, 0.1]}
time:
  end: 1.0
)";

std::string error_of(const std::string& text, const std::vector<std::string>& sets = {}) {
  try {
    parse_case(text, "case.yaml", sets);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}
}  // namespace

TEST(Case, ParsesDefaults) {
  const Case c = parse_case(kBase, "case.yaml");
  EXPECT_EQ(c.dimension, 2);
  EXPECT_DOUBLE_EQ(c.dx, 0.01);
  EXPECT_EQ(c.kernel, KernelType::WendlandC2);
  EXPECT_DOUBLE_EQ(c.h_over_dx, 1.5);
  ASSERT_EQ(c.gravity.size(), 2u);
  EXPECT_DOUBLE_EQ(c.gravity[1], -9.81);
  EXPECT_EQ(c.shapes.size(), 1u);
}

TEST(Case, UnknownKeySuggestsClosest) {
  std::string t = kBase;
  t.replace(t.find("  density"), 9, "  densty");
  const std::string e = error_of(t);
  EXPECT_NE(e.find("case.yaml"), std::string::npos) << e;
  EXPECT_NE(e.find("line 6"), std::string::npos) << e;
  EXPECT_NE(e.find("fluid.densty"), std::string::npos) << e;
  EXPECT_NE(e.find("did you mean 'fluid.density'"), std::string::npos) << e;
}

TEST(Case, BadValuesNameLineAndExpectation) {
  std::string t = kBase;
  t.replace(t.find("dx: 0.01"), 8, "dx: -1");
  const std::string e = error_of(t);
  EXPECT_NE(e.find("line 4"), std::string::npos) << e;
  EXPECT_NE(e.find("particles.dx"), std::string::npos) << e;
  EXPECT_NE(e.find("positive"), std::string::npos) << e;
  EXPECT_NE(error_of(std::string(kBase) + "  output_interval: abc\n").find("a number"), std::string::npos);
}

TEST(Case, YamlSyntaxErrorHasLine) {
  const std::string e = error_of("particles:\n  dx: [0.1\nfluid: {}\n");
  EXPECT_NE(e.find("YAML syntax error"), std::string::npos) << e;
  EXPECT_NE(e.find("case.yaml: line 3, column 6"), std::string::npos) << e;  // where the list should have closed
}

TEST(Case, MissingSectionIsReported) {
  std::string t = kBase;
  t = t.substr(0, t.find("time:"));
  EXPECT_NE(error_of(t).find("missing required section 'time'"), std::string::npos);
}

TEST(Case, SlopeTiltsGravityIntoTheBedFrame) {
  const Case c = parse_case(std::string(kBase) + "slope: 0.001\n", "case.yaml");
  ASSERT_EQ(c.gravity.size(), 2u);
  EXPECT_NEAR(std::hypot(c.gravity[0], c.gravity[1]), 9.81, 1e-12);  // |g| kept
  EXPECT_NEAR(c.gravity[0] / -c.gravity[1], 0.001, 1e-15);            // tan(theta) = S0
  EXPECT_NE(error_of(std::string(kBase) + "slope: 0.001\ngravity: [0, -9.81]\n").find("not both"), std::string::npos);
  EXPECT_NE(error_of(std::string(kBase) + "slope: 2\n").find("|slope| < 1"), std::string::npos);
}

TEST(Case, SetOverridesByDottedPath) {
  const Case c = parse_case(kBase, "case.yaml",
                            {"particles.dx=0.005", "time.end=2.5", "geometry.0.max=[0.2, 0.3]", "scheme.xsph=0.5"});
  EXPECT_DOUBLE_EQ(c.dx, 0.005);
  EXPECT_DOUBLE_EQ(c.t_end, 2.5);
  EXPECT_DOUBLE_EQ(c.shapes[0].max[1], 0.3);
  EXPECT_DOUBLE_EQ(c.scheme.xsph, 0.5);
  EXPECT_NE(error_of(kBase, {"particles.dxx=1"}).find("did you mean 'particles.dx'"), std::string::npos);
  EXPECT_NE(error_of(kBase, {"nonsense"}).find("KEY=VALUE"), std::string::npos);
  EXPECT_NE(error_of(kBase, {"geometry.5.max=[1,1]"}).find("out of range"), std::string::npos);
}
