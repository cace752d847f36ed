#pragma once
#include <memory>
#include <string>

#include "sphflume/boundaries/walls.hpp"
#include "sphflume/io/case.hpp"
#include "sphflume/io/geometry.hpp"
#include "sphflume/physics/force_terms.hpp"
#include "sphflume/schemes/wcsph.hpp"

namespace sph::test {

/// A System built from case-file text, with its wall model and force terms, ready to step.
template <int D>
struct Setup {
  Case c;
  System<D> S;
  BuildReport rep;
  std::unique_ptr<WCSPH<D>> scheme;
  explicit Setup(const std::string& yaml, const std::vector<std::string>& overrides = {}) {
    c = parse_case(yaml, "test.yaml", overrides);
    rep = build_system<D>(c, S);
    S.walls = wall_registry<D>().create(c.walls.type, c.walls);
    if (c.forces.IsDefined())
      for (const auto& n : c.forces) S.forces.push_back(force_registry<D>().create(n["type"].template as<std::string>(), n, "test"));
    scheme = std::make_unique<WCSPH<D>>(c);
  }
};

}  // namespace sph::test
