// libFuzzer target for the case-file reader and the case builder (docs/fuzzing.md).
// The input bytes are a case file's text: sph::parse_case reads it, then sph::build_system
// builds its particles on a fresh System (2D or 3D, as the case says). sph::InputError is
// the expected answer to bad input; anything else is a finding: another exception (uncaught:
// libFuzzer reports it as a crash), a crash, a hang, a leak or a sanitizer report.
// Lines "#set KEY=VALUE" (YAML comments, so the text stays a valid case) become --set
// overrides, so the fuzzer reaches apply_override too.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "sphflume/boundaries/walls.hpp"        // complete WallModel/ForceTerm for ~System
#include "sphflume/io/case.hpp"
#include "sphflume/setup/setup.hpp"
#include "sphflume/physics/force_terms.hpp"

namespace {

std::vector<std::string> set_lines(const std::string& text) {
  std::vector<std::string> sets;
  std::size_t pos = 0;
  while (pos < text.size()) {
    std::size_t end = text.find('\n', pos);
    if (end == std::string::npos) end = text.size();
    if (text.compare(pos, 5, "#set ") == 0) sets.push_back(text.substr(pos + 5, end - pos - 5));
    pos = end + 1;
  }
  return sets;
}

template <int D>
void build(const sph::Case& c) {
  sph::System<D> S;
  sph::BuildLimits limits;
  limits.max_particles = 1e5;  // keeps every input within -rss_limit_mb and -timeout
  limits.max_setup_pairs = 2e7;  // so does this for resolution levels (4^l more candidates a point at level l)
  const sph::BuildReport rep = sph::build_system<D>(c, S, limits);
  // what build_system promises when it returns
  if (rep.fluid == 0 || S.particles.n_owned() != rep.fluid + rep.wall) __builtin_trap();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size > (1u << 20)) return 0;
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const sph::Case c = sph::parse_case(text, "fuzz.yaml", set_lines(text));
    if (c.dimension == 2) build<2>(c);
    else build<3>(c);
  } catch (const sph::InputError&) {
    // the expected answer to bad input
  }
  return 0;
}
