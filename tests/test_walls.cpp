// No fluid particle may cross a wall (issue 20, defect 6). A thin slow film is the hard case for
// wall models that take their pressure from the fluid: a 1 cm column at dx = 0.5 mm spreads into
// a film a few particles thick, whose pressures (tens of Pa) are of the order of the pressure
// noise, so dummy walls may pull a particle instead of pushing it. The backup force
// (walls.backup, WallModel::add_backup) must keep every fluid centre on the fluid side of the
// bed's surface (z = 0) at all times; the control run without it shows the film does drive
// particles through, so the test can fail.
#include <gtest/gtest.h>

#include <algorithm>
#include <limits>

#include "test_helpers.hpp"

using namespace sph;

namespace {
const char* kFilm = R"(
dimension: 2
gravity: [0.0, -9.81]
particles: {dx: 0.0005, kernel: wendland_c2, h_over_dx: 2.0}
fluid: {density: 1000.0, viscosity: 1.0e-6, sound_speed: 4.5}
scheme: {integrator: symplectic, density_diffusion: fourtakas, delta: 0.1, viscosity: artificial, alpha: 0.02, cfl: 0.2}
walls: {type: dummy, slip: no_slip}
geometry:
  - {type: tank, fill: wall, min: [0.0, 0.0], max: [0.12, 0.05]}
  - {type: box, fill: fluid, min: [0.0, 0.0], max: [0.015, 0.01]}
time: {end: 0.6}
)";

struct FilmResult {
  double min_z = std::numeric_limits<double>::infinity();  // lowest fluid centre over the run
  double time = 0.0;
  std::size_t fluid0 = 0, fluid = 0;
};

/// Runs the film to t_end (or until a fluid centre is below z_stop) and tracks the lowest fluid
/// centre, checked after every step.
FilmResult run_film(const std::vector<std::string>& sets, double t_end, double z_stop) {
  test::Setup<2> s(kFilm, sets);
  FilmResult r;
  r.fluid0 = s.S.particles.count(Kind::Fluid);
  s.scheme->initialise(s.S);
  while (s.S.time < t_end && r.min_z >= z_stop) {
    s.scheme->step(s.S, s.scheme->time_step(s.S));
    const auto& P = s.S.particles;
    for (std::size_t i = 0; i < P.n_owned(); ++i)
      if (P.kind[i] == Kind::Fluid) r.min_z = std::min(r.min_z, P.pos[i][1]);
  }
  s.S.particles.clear_images();
  r.time = s.S.time;
  r.fluid = s.S.particles.count(Kind::Fluid);
  return r;
}
}  // namespace

TEST(Walls, ThinSlowFilmNeverCrossesTheBed) {
  for (const char* walls : {"dummy", "dynamic"}) {
    SCOPED_TRACE(std::string(walls) + " walls");
    const FilmResult r = run_film({std::string("walls.type=") + walls}, 0.6, -1.0);
    EXPECT_GE(r.time, 0.6);
    EXPECT_EQ(r.fluid, r.fluid0);  // none removed
    // every centre stays on the fluid side of the surface z = 0 (the film sits at dx/2 = 2.5e-4)
    EXPECT_GT(r.min_z, 0.0);
  }
}

TEST(Walls, ThinSlowFilmSinksThroughDummyBedWithoutBackup) {
  // control: the same film over Adami dummy walls without the backup puts a particle's centre
  // below the surface (it reached z = -0.64 dx by t = 0.53 s when this test was written)
  const FilmResult r = run_film({"walls.backup=false"}, 0.6, -0.1 * 0.0005);
  EXPECT_LT(r.min_z, 0.0);
}
