// The run-up gauge's waterline on a slope (2D), kept apart from the other gauges: it bins the
// water along the slope line to tell a film from a splash.
#pragma once
#include <array>

#include "sphflume/core/config.hpp"
#include "sphflume/core/system.hpp"

namespace sph {

/// The waterline on the slope line g.start–g.end: {elevation − g.level, x} of a fluid particle
/// within `reach` of the surface, or {nan, nan} when the toe is dry. The line is cut into stretches
/// 2 dx long, walked up from the toe while the water touches the face (lowest normal distance of a
/// stretch's particles ≤ reach; particles with fewer than g.neighbours fluid neighbours within 2 dx,
/// lone drops, are ignored). A stretch is thick when its particles' normal extent plus dx (their own
/// depth) is at least the film thickness g.film (default 1 mm, a lab run-up wire's: any resolved
/// layer counts while dx > 1 mm). The waterline is the highest surface particle at most
/// film / tan(slope) up the face from the last thick stretch's: the thin edge of still water (its
/// surface meets the face at the face's angle) counts, a thinner sheet running further up does not,
/// nor a splash that lands beyond a dry stretch. Water under the surface (a porous beach) counts
/// from `reach` below it.
template <int D>
std::array<double, 2> runup_waterline(const GaugeConfig& g, const System<D>& S);

}  // namespace sph
