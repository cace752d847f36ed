// Health of a running simulation: the checks that stop a run (exit code 3) before it writes
// garbage. After every step: every field of every particle finite, every fluid density inside
// a sane band around its reference density. The messages name the step, time, particle id,
// kind and position, and the likely cause.
#pragma once
#include <optional>
#include <string>

#include "sphflume/core/system.hpp"

namespace sph {

struct HealthLimits {
  // ρ/ρ0 of fluid particles must stay in [min, max]. Tait with γ = 7 at 1.3 ρ0 already gives
  // p ≈ 0.75 ρ0 c0², about 75 times the design pressure ρ0 (c0/10)²: far outside any sane run.
  double density_min_ratio = 0.7;
  double density_max_ratio = 1.3;
  const char* causes = nullptr;  // the scheme's likely causes of a non-finite value (Scheme::failure_causes)
};

/// The first unhealthy particle (in memory order) as a message, or nothing when all is well.
template <int D>
std::optional<std::string> check_health(const System<D>& S, const HealthLimits& lim);

/// "particle id N (kind) at (x, z)" for particle i.
template <int D>
std::string describe_particle(const System<D>& S, std::size_t i);

/// Index of the fluid particle with the largest acceleration (for a collapsing time step).
template <int D>
std::size_t fastest_accelerating(const System<D>& S);

}  // namespace sph
