// The schemes a case can name in `scheme.type`: one line each (their keys: scheme_options.cpp).
#include "sphflume/schemes/dual.hpp"
#include "sphflume/schemes/isph.hpp"
#include "sphflume/schemes/isph_projection.hpp"
#include "sphflume/schemes/wcsph.hpp"

namespace sph {

template <int D>
Registry<Scheme<D>, const Case&>& scheme_registry() {
  static Registry<Scheme<D>, const Case&> r = [] {
    Registry<Scheme<D>, const Case&> reg;
    // `integrator: dual` is a scheme of its own under the same type (its keys are WCSPH's)
    reg.add("wcsph", [](const Case& c) -> std::unique_ptr<Scheme<D>> {
      if (c.scheme.integrator == Integrator::Dual) return std::make_unique<DualWCSPH<D>>(c);
      return std::make_unique<WCSPH<D>>(c);
    });
    // `formulation` chooses Lind, Skillen and Chow's projection or Tsurudome's (docs/numerics.md §13)
    reg.add("isph", [](const Case& c) -> std::unique_ptr<Scheme<D>> {
      if (c.isph.formulation == IsphFormulation::Lind) return std::make_unique<ProjectionISPH<D>>(c);
      return std::make_unique<ISPH<D>>(c);
    });
    return reg;
  }();
  return r;
}
template Registry<Scheme<2>, const Case&>& scheme_registry<2>();
template Registry<Scheme<3>, const Case&>& scheme_registry<3>();

}  // namespace sph
