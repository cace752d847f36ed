// A case's `scheme:` section, read by the scheme it names: each scheme type reads its own keys
// and checks the rest of the case against what it can run (line-numbered InputErrors through
// the Reader). The case reader (io/case.cpp) asks this table for `scheme.type`'s choices, the
// reader and the check; no scheme name is tested outside schemes/. The table needs no scheme
// class (the fuzz target links the readers alone): a new scheme adds one line to
// scheme_types() (schemes/scheme_options.cpp) and one to scheme_registry() (registry.cpp).
#pragma once
#include <map>
#include <string>

#include "sphflume/core/config.hpp"
#include "sphflume/core/reader.hpp"

namespace sph {

struct SchemeOptions {
  /// Reads the keys of `r` (a Reader on the `scheme:` mapping, `type` already read) into c, with
  /// its warnings; calls r.finish() (an unknown key is an InputError).
  void (*read)(Reader& r, Case& c);
  /// Once every section is read: refuses, through `top` (the file's top-level Reader), a case
  /// the scheme cannot run (a model it does not carry, an option without its section).
  void (*check)(Reader& top, Case& c);
};

/// The scheme types a case can name in `scheme.type`.
const std::map<std::string, SchemeOptions>& scheme_types();

/// The weakly-compressible schemes' keys (WCSPH and its `integrator: dual`; wcsph_options.cpp).
void read_wcsph_options(Reader& r, Case& c);
void check_wcsph_case(Reader& top, Case& c);

}  // namespace sph
