// Point-in-shape tests shared by the geometry builder and the porous regions.
#pragma once
#include <array>
#include <vector>

namespace sph {

/// Even-odd rule: is (x, z) inside the polygon with these vertices (2D)?
inline bool inside_polygon(const std::vector<std::array<double, 2>>& v, double x, double z) {
  bool in = false;
  for (std::size_t i = 0, j = v.size() - 1; i < v.size(); j = i++) {
    if (((v[i][1] > z) != (v[j][1] > z)) && (x < (v[j][0] - v[i][0]) * (z - v[i][1]) / (v[j][1] - v[i][1]) + v[i][0]))
      in = !in;
  }
  return in;
}

}  // namespace sph
