// The lattice fill of a case's shapes (setup/fill.cpp): fluid and wall points before any particle
// exists, the fluid points that fall inside walls, and the checks on them. Internal to setup/.
#pragma once
#include <cstdint>
#include <vector>

#include "sphflume/core/vec.hpp"
#include "sphflume/io/case.hpp"
#include "sphflume/physics/porous.hpp"

namespace sph {

template <int D>
struct FillPoints {
  std::vector<Vec<D>> fluid_x, fluid_v;   // fluid points and their initial velocity
  std::vector<std::uint32_t> fluid_shape;  // which shape made each fluid point
  std::vector<double> fluid_half;          // half the lattice spacing of each fluid point
  std::vector<Vec<D>> wall_x, wall_s;      // wall points and the nearest point of their shape's surface
  std::vector<std::uint32_t> wall_shape;   // which shape made each wall point
  std::vector<char> wall_covered;          // 1: its surface point lies on a face another fixed wall covers
  std::vector<char> drop;                  // fluid points inside walls (drop_inside_walls)
  std::vector<int> fluid_level;            // resolution level of each fluid point (refine_fill; empty: all 0)
  std::vector<int> wall_level;             // resolution level of each wall point (refine_fill; empty: all 0)
};

/// Every shape's lattice points (porous zones' fluid at the zone's spacing, Kazemi eq 5.1).
template <int D>
FillPoints<D> fill_shapes(const Case& c, int layers, const PorousMedia<D>* porous);

/// Marks the fluid points inside walls (closer than dx/2 to a wall point, inside a solid wall box,
/// under or too close to a slope's wall layer) and refuses fluid shapes that make no particle or
/// lie mostly inside walls (InputError naming the shape).
template <int D>
void drop_inside_walls(const Case& c, FillPoints<D>& f);

/// Resolution levels (docs/numerics.md §14): each fluid point inside a `resolution` region is
/// split (core/refinement.hpp) until it reaches the region's level; a child outside every region
/// of that level stops there. Each wall point within the level-0 support of a region is split
/// the same way to that region's level (the finest such), so that the fluid of a level meets a
/// wall of its own spacing; a child's surface point is its parent's moved along the surface. A
/// child on or past its body's surface (a face off the coarse lattice) is dropped.
template <int D>
void refine_fill(const Case& c, double support, FillPoints<D>& f);

}  // namespace sph
