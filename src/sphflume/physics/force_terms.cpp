#include "sphflume/physics/force_terms.hpp"

#include <fmt/format.h>

#include "sphflume/io/case.hpp"

namespace sph {
namespace {

std::vector<double> read_vec(const YAML::Node& n, const char* key, int d, const std::string& where) {
  const YAML::Node v = n[key];
  if (!v.IsSequence() || v.size() != static_cast<std::size_t>(d))
    throw InputError(fmt::format("{}: '{}': expected a list of {} numbers", where, key, d));
  std::vector<double> out;
  for (const auto& e : v) out.push_back(e.as<double>());
  return out;
}

/// Uniform body force per unit mass, optionally only inside a box region
/// (e.g. the pressure gradient that drives a periodic channel).
template <int D>
class BodyForce final : public ForceTerm<D> {
 public:
  BodyForce(const YAML::Node& n, const std::string& where) {
    for (const auto& kv : n) {
      const auto k = kv.first.as<std::string>();
      if (k != "type" && k != "acceleration" && k != "min" && k != "max")
        throw InputError(fmt::format("{}: unknown key '{}' for body_force (known: acceleration, min, max)", where, k));
    }
    const auto a = read_vec(n, "acceleration", D, where);
    for (int d = 0; d < D; ++d) acc_[d] = a[d];
    if (n["min"] || n["max"]) {
      region_ = true;
      const auto lo = read_vec(n, "min", D, where), hi = read_vec(n, "max", D, where);
      for (int d = 0; d < D; ++d) { lo_[d] = lo[d]; hi_[d] = hi[d]; }
    }
  }
  const char* name() const override { return "body_force"; }
  void add(System<D>& S) override {
    auto& P = S.particles;
    for (std::size_t i = 0; i < P.n_owned(); ++i) {
      if (P.kind[i] != Kind::Fluid) continue;
      if (region_) {
        bool in = true;
        for (int d = 0; d < D; ++d) in &= P.pos[i][d] >= lo_[d] && P.pos[i][d] <= hi_[d];
        if (!in) continue;
      }
      P.acc[i] += acc_;
    }
  }

 private:
  Vec<D> acc_{}, lo_{}, hi_{};
  bool region_ = false;
};

}  // namespace

template <int D>
Registry<ForceTerm<D>, const YAML::Node&, const std::string&>& force_registry() {
  static Registry<ForceTerm<D>, const YAML::Node&, const std::string&> r = [] {
    Registry<ForceTerm<D>, const YAML::Node&, const std::string&> reg;
    reg.add("body_force", [](const YAML::Node& n, const std::string& w) { return std::make_unique<BodyForce<D>>(n, w); });
    return reg;
  }();
  return r;
}

template Registry<ForceTerm<2>, const YAML::Node&, const std::string&>& force_registry<2>();
template Registry<ForceTerm<3>, const YAML::Node&, const std::string&>& force_registry<3>();

}  // namespace sph
