#include "sphflume/core/config.hpp"

namespace sph {

bool RegionConfig::contains(const double* x, int dim) const {
  if (type == "circle") {
    double r2 = 0.0;
    for (int d = 0; d < dim; ++d) r2 += (x[d] - center[static_cast<std::size_t>(d)]) * (x[d] - center[static_cast<std::size_t>(d)]);
    return r2 <= radius * radius;
  }
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
