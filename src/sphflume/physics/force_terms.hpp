// Force terms that plug into any scheme: each adds an acceleration to fluid particles after
// the scheme's pair loop. Gravity is built in; others are listed in the case file under
// `forces:` as {type: NAME, ...}. New terms: derive from ForceTerm, read the keys with the
// Reader, and add one line to force_registry() (physics/force_terms.cpp).
#pragma once
#include <memory>
#include <string>

#include "sphflume/core/reader.hpp"
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

/// Factories read the term's keys from its mapping with a strict Reader (core/reader.hpp;
/// `type` already read) and get the node itself for messages about the term as a whole.
template <int D>
Registry<ForceTerm<D>, Reader&, const Node&>& force_registry();

/// The terms of the case file's `forces:` list (a sequence node; undefined = none) added to
/// S.forces; `file` names the case in messages. Unknown types and keys are InputErrors.
template <int D>
void add_force_terms(const Node& list, const std::string& file, System<D>& S);

}  // namespace sph
