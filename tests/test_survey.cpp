// Polygons from CSV files (issue 43, geometry from files; docs/case-file.md): a survey line of
// chainage and elevation closed down to a base, or a polygon's vertices, give the particles of the
// same polygon typed in the case; a bad file is an InputError naming the key, the file and its line.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "sphflume/boundaries/walls.hpp"
#include "sphflume/io/case.hpp"
#include "sphflume/physics/force_terms.hpp"
#include "sphflume/setup/setup.hpp"

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

std::string error_of(const std::string& text) {
  try {
    const Case c = parse_case(text, "case.yaml");
    System<2> S;
    build_system<2>(c, S);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

#define EXPECT_HAS(msg, part) EXPECT_NE((msg).find(part), std::string::npos) << "message: " << (msg) << "\nlacks: " << (part)

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
