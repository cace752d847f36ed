// The reader of the incompressible (projection) scheme's options, `scheme: {type: isph, ...}`
// (the plain struct IsphConfig is in core/config.hpp). The reader needs no YAML (core/reader.hpp): the case reader
// (io/case.cpp) calls it through scheme_types() (schemes/scheme_options.hpp) with the scheme's mapping. Keys of the weakly-compressible scheme given under `type: isph` are not
// errors: they are listed in `ignored` (file line and key) and reported as warnings, so that one
// case file runs with either scheme by changing `type` alone (docs/case-file.md).
#pragma once
#include <string>
#include <vector>

#include "sphflume/core/config.hpp"
#include "sphflume/core/reader.hpp"

namespace sph {

/// Reads the keys of `r` (a reader on the `scheme:` mapping, `type` already read) into `o`;
/// calls r.finish() (unknown keys are InputErrors).
void read_isph_options(Reader& r, IsphConfig& o);

/// Refuses (InputError naming the key and the fix) a case with a shared model this scheme does
/// not carry: walls other than dummy, open boundaries, several phases, transported scalars.
void check_isph_models(const Case& c);

}  // namespace sph
