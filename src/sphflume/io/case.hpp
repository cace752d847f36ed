// A case: everything a run needs (core/config.hpp), read from a YAML case file (see
// docs/case-file.md). Parsing is strict: unknown keys, wrong types and out-of-range values are
// InputErrors that name the file, line and key and say what was expected.
#pragma once
#include <string>
#include <vector>

#include "sphflume/core/config.hpp"

namespace sph {

/// Load a case file, apply `--set key.path=value` overrides, validate.
/// Number of wall layers that covers the kernel support (walls.layers if given).
int wall_layers_for(const Case& c);

Case load_case(const std::string& path, const std::vector<std::string>& overrides = {});
/// Same from text (tests, fuzzing); `name` is used in messages.
Case parse_case(const std::string& text, const std::string& name, const std::vector<std::string>& overrides = {});

}  // namespace sph
