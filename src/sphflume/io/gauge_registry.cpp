// The gauge types by name (io/gauge_type.hpp): one line per type in its family's add_* function.
#include <stdexcept>

#include "sphflume/io/gauge_types.hpp"

namespace sph {

template <int D>
Registry<GaugeType<D>>& gauge_registry() {
  static Registry<GaugeType<D>> reg = [] {
    Registry<GaugeType<D>> r;
    add_point_gauges<D>(r);
    add_line_gauges<D>(r);
    add_level_gauges<D>(r);
    add_total_gauges<D>(r);
    return r;
  }();
  return reg;
}
template Registry<GaugeType<2>>& gauge_registry<2>();
template Registry<GaugeType<3>>& gauge_registry<3>();

void read_gauge_keys(Reader& r, GaugeConfig& g, const Node& n, const std::string& path, int dim) {
  if (dim == 2) gauge_registry<2>().create(g.type)->read(r, g, n, path);
  else gauge_registry<3>().create(g.type)->read(r, g, n, path);
}

}  // namespace sph
