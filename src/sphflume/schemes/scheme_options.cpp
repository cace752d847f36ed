// The scheme types a case can name (schemes/scheme_options.hpp): one line each.
#include "sphflume/schemes/scheme_options.hpp"

#include <fmt/format.h>

#include "sphflume/schemes/isph_options.hpp"

namespace sph {

namespace {

void read_isph(Reader& r, Case& c) {
  read_isph_options(r, c.isph);
  for (const auto& k : c.isph.ignored) c.warnings.push_back(fmt::format("{}: {}: ignored under scheme.type: isph", r.file(), k));
}

void check_isph(Reader&, Case& c) { check_isph_models(c); }

}  // namespace

const std::map<std::string, SchemeOptions>& scheme_types() {
  static const std::map<std::string, SchemeOptions> types = {
      {"wcsph", {read_wcsph_options, check_wcsph_case}},
      {"isph", {read_isph, check_isph}},
  };
  return types;
}

}  // namespace sph
