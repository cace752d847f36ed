// Force terms that plug into any scheme: each adds an acceleration to fluid particles after
// the scheme's pair loop. Gravity is built in; others are listed in the case file under
// `forces:` as {type: NAME, ...}. New terms: derive from ForceTerm and add one line to
// force_registry() (physics/force_terms.cpp).
#pragma once
#include <memory>
#include <string>

#include <yaml-cpp/yaml.h>

#include "sphflume/core/registry.hpp"
#include "sphflume/core/system.hpp"

namespace sph {

template <int D>
class ForceTerm {
 public:
  virtual ~ForceTerm() = default;
  virtual const char* name() const = 0;
  /// Add this term's acceleration to S.particles.acc of owned fluid particles.
  virtual void add(System<D>& S) = 0;
};

/// Factories take the term's YAML node and a description of where it is (for messages).
template <int D>
Registry<ForceTerm<D>, const YAML::Node&, const std::string&>& force_registry();

}  // namespace sph
