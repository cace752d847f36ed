// Built without hypre (libhypre-dev not found by CMake): scheme.solver.type: boomeramg is refused
// by the case reader (have_hypre() is false), so this factory is never reached.
#include <stdexcept>

#include "sphflume/schemes/pressure_solver.hpp"

namespace sph {

bool have_hypre() { return false; }

std::unique_ptr<PressureSolver> make_hypre_solver(double, int, bool, AmgCycle) {
  throw std::logic_error("SPHFlume was built without hypre (install libhypre-dev and rebuild)");
}

}  // namespace sph
