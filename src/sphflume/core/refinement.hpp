// Variable resolution (docs/numerics.md §14): particle splitting after Vacondio et al. (2013, 2016),
// ratio 2 between levels. A particle of level l has spacing dx / 2^l, smoothing length h / 2^l
// and mass m / 2^(D l); a split replaces it by 2^D children of level l + 1 on the square (cubic)
// pattern of the finer lattice, at ±dx_l/4 along each axis about the parent, each with the
// parent's velocity and density and a 2^−D share of its mass: mass, momentum and the centre of
// mass are kept exactly (a power-of-two share is exact in binary).
#pragma once
#include <array>
#include <cstddef>

#include "sphflume/core/vec.hpp"

namespace sph {

/// The number of children of one split.
template <int D>
inline constexpr std::size_t kChildren = std::size_t(1) << D;

/// The children's positions of a parent at x whose lattice spacing is 2 half: x ± half/2 along
/// each axis (child k takes + along axis d when bit d of k is set).
template <int D>
std::array<Vec<D>, kChildren<D>> split_positions(const Vec<D>& x, double half) {
  std::array<Vec<D>, kChildren<D>> out;
  const double o = 0.5 * half;
  for (std::size_t k = 0; k < kChildren<D>; ++k)
    for (int d = 0; d < D; ++d) out[k][d] = x[d] + (((k >> d) & 1u) ? o : -o);
  return out;
}

/// The mass and smoothing length at level l of a lattice with mass m and h at level 0.
template <int D>
inline double level_mass(double m, int l) {
  return m / double(std::size_t(1) << (D * l));
}
inline double level_h(double h, int l) { return h / double(1 << l); }

}  // namespace sph
