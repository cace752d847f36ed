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

/// Kazemi's rough-bed shape function W_d (ch. 3, eq 3.17): the fraction of a fluid fragment of
/// width d_s and height l0 centred at elevation z that lies inside the circular cross-section
/// (diameter d_s, centre z_centre) of a bed sphere. l0 = 0 gives the point form
/// sqrt(1 - ((z - z_centre)/(d_s/2))^2).
double rough_bed_shape(double z, double z_centre, double d_s, double l0);

/// Factories take the term's YAML node and a description of where it is (for messages).
template <int D>
Registry<ForceTerm<D>, const YAML::Node&, const std::string&>& force_registry();

}  // namespace sph
