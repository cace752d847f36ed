// Polygons from CSV files (issue 43, geometry from files; docs/case-file.md): a survey line of
// chainage and elevation closed down to a base, or a polygon's vertices, give the particles of the
// same polygon typed in the case; a bad file is an InputError naming the key, the file and its line.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "sphflume/boundaries/walls.hpp"
#include "sphflume/io/case.hpp"
#include "sphflume/physics/force_terms.hpp"
#include "sphflume/setup/setup.hpp"
#include "test_helpers.hpp"

using namespace sph;

namespace {

std::string write_file(const std::string& name, const std::string& text) {
  const auto dir = std::filesystem::temp_directory_path() / "sphflume_survey_test";
  std::filesystem::create_directories(dir);
  const auto p = dir / name;
  std::ofstream(p) << text;
  return p.string();
}

// A 1:3 beach with a bar, 6 wall layers of dx = 0.01 under the surface line, water over it.
std::string beach_case(const std::string& bed) {
  return R"(dimension: 2
particles: {dx: 0.01}
fluid: {density: 1000.0}
geometry:
  - {type: tank, min: [0.0, 0.0], max: [1.2, 0.5]}
  - {type: polygon, fill: wall, )" + bed + R"(}
  - {type: box, fill: fluid, min: [0.0, 0.0], max: [0.6, 0.12]}
time: {end: 0.1}
)";
}

const char* kTyped = "vertices: [[0.3, 0.0], [0.3, 0.0301], [0.6, 0.1301], [0.7, 0.16], [0.8, 0.1301], [1.2, 0.26], [1.2, 0.0]]";

std::string error_of(const std::string& text) { return test::build_error<2>(text); }


}  // namespace

TEST(Survey, ProfileGivesTheTypedPolygonsParticles) {
  const std::string line = write_file("bed.csv",
                                      "# surveyed bed: chainage [m], elevation [m]\n"
                                      "x,z\n0.3,0.0301\n0.6,0.1301\n0.7,0.16\n0.8,0.1301\n1.2,0.26\n");
  const std::string poly = write_file("poly.csv", "x;z\n0.3;0.0\n0.3;0.0301\n0.6;0.1301\n0.7;0.16\n0.8;0.1301\n1.2;0.26\n1.2;0.0\n");
  const Case typed = parse_case(beach_case(kTyped), "case.yaml");
  System<2> A;
  build_system<2>(typed, A);
  for (const std::string& bed : {"vertices: {file: " + line + ", base: 0.0}", "vertices: {file: " + poly + "}"}) {
    const Case c = parse_case(beach_case(bed), "case.yaml");
    System<2> B;
    build_system<2>(c, B);
    ASSERT_EQ(A.particles.size(), B.particles.size()) << bed;
    std::size_t walls = 0;
    for (std::size_t i = 0; i < A.particles.size(); ++i) {
      ASSERT_EQ(A.particles.kind[i], B.particles.kind[i]) << bed << " particle " << i;
      for (int d = 0; d < 2; ++d) ASSERT_EQ(A.particles.pos[i][d], B.particles.pos[i][d]) << bed << " particle " << i;
      walls += A.particles.kind[i] == Kind::Wall ? 1 : 0;
    }
    EXPECT_GT(walls, 678u + 1000u);  // the bed is there: the tank alone has 678, the bed about 0.13 m² / dx²
  }
}

TEST(Survey, BadFilesAreNamedWithTheirLine) {
  // line 6 of the case: geometry.1
  std::string e = error_of(beach_case("vertices: {file: no_such_bed.csv, base: 0.0}"));
  EXPECT_HAS(e, "line 6");
  EXPECT_HAS(e, "geometry.1.vertices.file");
  EXPECT_HAS(e, "no_such_bed.csv");
  const std::string one_col = write_file("one_col.csv", "x,z\n0.3,0.03\n0.6\n1.2,0.26\n");
  e = error_of(beach_case("vertices: {file: " + one_col + ", base: 0.0}"));
  EXPECT_HAS(e, "rows of two finite numbers (x, z)");
  EXPECT_HAS(e, one_col + " line 3");
  const std::string back = write_file("back.csv", "0.3,0.03\n0.6,0.13\n0.5,0.2\n");
  e = error_of(beach_case("vertices: {file: " + back + ", base: 0.0}"));
  EXPECT_HAS(e, "x strictly increasing");
  EXPECT_HAS(e, back + " line 3");
  const std::string ok = write_file("ok.csv", "0.3,0.03\n1.2,0.26\n");
  e = error_of(beach_case("vertices: {file: " + ok + ", base: 0.1}"));
  EXPECT_HAS(e, "geometry.1.vertices.base");
  EXPECT_HAS(e, "at or below every point");
  const std::string flat = write_file("flat.csv", "0.3,0.0\n1.2,0.0\n");
  e = error_of(beach_case("vertices: {file: " + flat + ", base: 0.0}"));
  EXPECT_HAS(e, "encloses nothing");
  e = error_of(beach_case("vertices: {file: " + ok + ", bas: 0.0}"));
  EXPECT_HAS(e, "'geometry.1.vertices.bas' (did you mean 'geometry.1.vertices.base'?)");
  e = error_of(beach_case("vertices: {file: " + ok + "}"));  // two points are no polygon
  EXPECT_HAS(e, "at least 3 rows");
}

namespace {
std::string slope_case(const std::string& slope) {
  return R"(dimension: 2
particles: {dx: 0.01}
fluid: {density: 1000.0}
geometry:
  - {type: tank, min: [0.0, 0.0], max: [1.2, 0.5]}
  - )" + slope + R"(
  - {type: box, fill: fluid, min: [0.0, 0.0], max: [0.6, 0.12]}
time: {end: 0.1}
)";
}
}  // namespace

// A slope read from a survey line lays its wall rows along the line: a straight survey (points
// every 0.05 m on a 1:3 slope) gives the typed slope's particles, within round-off of their
// positions; a bent one (steepening, then flattening) leaves no two of its wall particles closer
// than dx/2 and no fluid within dx/2 of its surface line.
TEST(Survey, SlopeFromASurveyLineLaysTheTypedSlopesRows) {
  std::string straight = "x,z\n";
  for (int i = 0; i <= 18; ++i) straight += fmt::format("{:.17g},{:.17g}\n", 0.3 + 0.05 * i, 0.05 * i / 3.0);
  const std::string file = write_file("straight.csv", straight);
  System<2> A, B;
  build_system<2>(parse_case(slope_case("{type: slope, toe: [0.3, 0.0], gradient: '1:3', top: 0.3}"), "case.yaml"), A);
  build_system<2>(parse_case(slope_case("{type: slope, survey: {file: " + file + "}}"), "case.yaml"), B);
  ASSERT_EQ(A.particles.size(), B.particles.size());
  for (std::size_t i = 0; i < A.particles.size(); ++i) {
    ASSERT_EQ(A.particles.kind[i], B.particles.kind[i]) << i;
    for (int d = 0; d < 2; ++d) ASSERT_NEAR(A.particles.pos[i][d], B.particles.pos[i][d], 1e-12) << i;
  }
  const std::string bent = write_file("bent.csv", "0.3,0.0\n0.6,0.1\n0.8,0.25\n1.2,0.3\n");
  System<2> C;
  build_system<2>(parse_case(slope_case("{type: slope, survey: {file: " + bent + "}}"), "case.yaml"), C);
  const auto& P = C.particles;
  std::vector<Vec<2>> walls;
  for (std::size_t i = 0; i < P.size(); ++i)
    if (P.kind[i] == Kind::Wall && P.pos[i][0] > 0.3 && P.pos[i][0] < 1.2 && P.pos[i][1] > 0.0) walls.push_back(P.pos[i]);
  ASSERT_GT(walls.size(), 3u * 90u);  // three rows along ~1 m of line
  double closest = 1.0;
  for (std::size_t i = 0; i < walls.size(); ++i)
    for (std::size_t j = i + 1; j < walls.size(); ++j) closest = std::min(closest, norm(walls[i] - walls[j]));
  EXPECT_GE(closest, 0.5 * 0.01 * 0.999);
  const double line[4][2] = {{0.3, 0.0}, {0.6, 0.1}, {0.8, 0.25}, {1.2, 0.3}};
  for (std::size_t i = 0; i < P.size(); ++i) {
    if (P.kind[i] != Kind::Fluid) continue;
    for (int s = 0; s < 3; ++s) {
      const Vec<2> a{{line[s][0], line[s][1]}}, b{{line[s + 1][0], line[s + 1][1]}};
      const double t = std::clamp(dot(P.pos[i] - a, b - a) / dot(b - a, b - a), 0.0, 1.0);
      ASSERT_GE(norm(P.pos[i] - (a + t * (b - a))), 0.5 * 0.01 * 0.998) << "fluid particle " << i;
    }
  }
}

TEST(Survey, BadSurveySlopesAreNamedWithTheirLine) {
  const std::string ok = write_file("ok_slope.csv", "0.3,0.0\n0.9,0.2\n");
  std::string e = error_of(slope_case("{type: slope, survey: {file: " + ok + "}, toe: [0.3, 0.0]}"));
  EXPECT_HAS(e, "geometry.1.toe");
  EXPECT_HAS(e, "beside 'survey'");
  const std::string down = write_file("down.csv", "0.3,0.05\n0.6,0.1\n0.9,0.02\n");
  e = error_of(slope_case("{type: slope, survey: {file: " + down + "}}"));
  EXPECT_HAS(e, "line 6");
  EXPECT_HAS(e, down + " line 3");
  EXPECT_HAS(e, "rising from its toe");
  e = error_of(slope_case("{type: slope, survey: {fil: " + ok + "}}"));
  EXPECT_HAS(e, "did you mean 'geometry.1.survey.file'?");
}
