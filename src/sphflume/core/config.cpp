#include "sphflume/core/config.hpp"
#include "sphflume/core/solid_mesh.hpp"

#include <cmath>

namespace sph {

bool RegionConfig::contains(const double* x, int dim) const {
  if (type == "band") {  // (2D) within [-below, above] of a segment of the line, normal to it, and in [z_min, z_max]
    const double px = x[0], pz = x[dim - 1];
    if (pz < z_min || pz > z_max || pz < win_lo || pz > win_hi) return false;
    for (std::size_t k = 0; k + 1 < vertices.size(); ++k) {
      const double tx = vertices[k + 1][0] - vertices[k][0], tz = vertices[k + 1][1] - vertices[k][1];
      const double len = std::sqrt(tx * tx + tz * tz), rx = px - vertices[k][0], rz = pz - vertices[k][1];
      const double along = (rx * tx + rz * tz) / len, normal = (rz * tx - rx * tz) / len;  // (normal: into the water)
      if (along >= 0.0 && along <= len && normal >= -below && normal <= above) return true;
    }
    return false;
  }
  if (type == "circle") {
    double r2 = 0.0;
    for (int d = 0; d < dim; ++d) r2 += (x[d] - center[static_cast<std::size_t>(d)]) * (x[d] - center[static_cast<std::size_t>(d)]);
    return r2 <= radius * radius;
  }
  if (type == "cylinder") {  // (3D) a vertical axis through center
    const double rx = x[0] - center[0], ry = x[1] - center[1];
    return rx * rx + ry * ry <= radius * radius && x[dim - 1] >= z_min && x[dim - 1] <= z_max;
  }
  if (type == "mesh") return grid->at(x) <= margin;  // (3D) inside the solid or within margin of it
  if (type == "polygon") {
    bool in = false;
    const auto& v = vertices;
    const double px = x[0], pz = x[dim - 1];
    for (std::size_t i = 0, j = v.size() - 1; i < v.size(); j = i++)
      if (((v[i][1] > pz) != (v[j][1] > pz)) && (px < (v[j][0] - v[i][0]) * (pz - v[i][1]) / (v[j][1] - v[i][1]) + v[i][0]))
        in = !in;
    return in;
  }
  for (int d = 0; d < dim; ++d)
    if (x[d] < min[static_cast<std::size_t>(d)] || x[d] > max[static_cast<std::size_t>(d)]) return false;
  return true;
}

}  // namespace sph
