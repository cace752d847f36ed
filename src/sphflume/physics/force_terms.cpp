#include "sphflume/physics/force_terms.hpp"

#include <algorithm>
#include <cmath>

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

/// Kazemi's rough-bed drag layer (ch. 3, eqs 3.3, 3.4, 3.17; digest §2.4): inside a layer of
/// thickness R_d above the numerical bed (the roughness crest is bed + R_d), every fluid
/// particle feels  a = -factor C_d W_d(z) / d_s  u |u|  (factor 1/2: F_d = 1/2 C_d rho A_d u|u|
/// over A_r = d_s l0 with A_d = l0), W_d the chord fraction of the bed spheres (diameter d_s,
/// centres d_s/2 below the crest) over the particle's height dx.
template <int D>
class RoughBed final : public ForceTerm<D> {
 public:
  RoughBed(const YAML::Node& n, const std::string& where) {
    for (const auto& kv : n) {
      const auto k = kv.first.as<std::string>();
      if (k != "type" && k != "cd" && k != "diameter" && k != "bed" && k != "thickness" && k != "shape" && k != "factor")
        throw InputError(fmt::format("{}: unknown key '{}' for rough_bed (known: cd, diameter, bed, thickness, shape, factor)", where, k));
    }
    auto num = [&](const char* k, double def, bool required) {
      if (!n[k]) {
        if (required) throw InputError(fmt::format("{}: rough_bed needs '{}'", where, k));
        return def;
      }
      return n[k].as<double>();
    };
    cd_ = num("cd", 1.0, false);
    ds_ = num("diameter", 0.0, true);
    bed_ = num("bed", 0.0, false);
    rd_ = num("thickness", 0.0, true);
    factor_ = num("factor", 0.5, false);
    if (!(ds_ > 0.0)) throw InputError(fmt::format("{}: rough_bed.diameter: expected the sphere diameter d_s > 0 in m", where));
    if (!(rd_ > 0.0 && rd_ <= ds_)) throw InputError(fmt::format("{}: rough_bed.thickness: expected R_d in (0, diameter] (the layer between the numerical bed and the crest)", where));
    if (!(cd_ >= 0.0)) throw InputError(fmt::format("{}: rough_bed.cd: expected a drag coefficient >= 0", where));
    const std::string shape = n["shape"] ? n["shape"].as<std::string>() : "fragment";
    if (shape != "fragment" && shape != "point") throw InputError(fmt::format("{}: rough_bed.shape: expected fragment or point (got '{}')", where, shape));
    point_ = shape == "point";
  }
  const char* name() const override { return "rough_bed"; }
  void add(System<D>& S) override {
    auto& P = S.particles;
    const double crest = bed_ + rd_, centre = crest - 0.5 * ds_, l0 = point_ ? 0.0 : S.dx;
    const double k = factor_ * cd_ / ds_;
    const std::size_t n = P.n_owned();
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < n; ++i) {
      if (P.kind[i] != Kind::Fluid) continue;
      const double z = P.pos[i][D - 1];
      if (z <= bed_ || z >= crest) continue;
      const double wd = rough_bed_shape(z, centre, ds_, l0);
      P.acc[i] -= (k * wd * norm(P.vel[i])) * P.vel[i];
    }
  }

 private:
  double cd_ = 1.0, ds_ = 0.0, bed_ = 0.0, rd_ = 0.0, factor_ = 0.5;
  bool point_ = false;
};

/// Kazemi's outlet "imaginary wall" (ch. 6, eqs 6.10-6.12; digest kazemi.md §5.5): `layers`
/// columns of fixed particles (spacing dx, volume dx^2, phi = 1) just downstream of the outlet
/// line X_o, from the bed up to bed + H_ow, with the hydrostatic pressure of that tailwater
/// level. They act only on the pressure gradient of the fluid within one kernel support
/// upstream of X_o:  O_a = - Σ_o F_o V_o (p_a + p_o)/ρ_a ∇_a W_ao,  F_o = (X_o - x_a)/(support)
/// (Kazemi: falls linearly to 0 at X_o; relax: false keeps F_o = 1), and in no other sum. Fluid reaching X_o leaves through the
/// domain's face there (set domain.max x = X_o; the run removes and counts it). 2D.
template <int D>
class ImaginaryWall final : public ForceTerm<D> {
 public:
  ImaginaryWall(const YAML::Node& n, const std::string& where) {
    for (const auto& kv : n) {
      const auto k = kv.first.as<std::string>();
      if (k != "type" && k != "x" && k != "bed" && k != "height" && k != "layers" && k != "relax")
        throw InputError(fmt::format("{}: unknown key '{}' for imaginary_wall (known: x, bed, height, layers, relax)", where, k));
    }
    if constexpr (D != 2) throw InputError(fmt::format("{}: imaginary_wall is 2D in this version", where));
    if (!n["x"] || !n["height"]) throw InputError(fmt::format("{}: imaginary_wall needs 'x' (the outlet line X_o) and 'height' (H_ow above the bed)", where));
    xo_ = n["x"].as<double>();
    bed_ = n["bed"] ? n["bed"].as<double>() : 0.0;
    how_ = n["height"].as<double>();
    layers_ = n["layers"] ? n["layers"].as<int>() : 3;
    relax_ = n["relax"] ? n["relax"].as<bool>() : true;
    if (!(how_ > 0.0)) throw InputError(fmt::format("{}: imaginary_wall.height: expected H_ow > 0 in m", where));
    if (layers_ < 1 || layers_ > 10) throw InputError(fmt::format("{}: imaginary_wall.layers: expected 1 to 10", where));
  }
  const char* name() const override { return "imaginary_wall"; }
  void add(System<D>& S) override {
    auto& P = S.particles;
    const double dx = S.dx, vol = dx * dx, g = std::abs(S.gravity[D - 1]), rho0 = S.eos.rho0;
    if (xo_pos_.empty())
      for (int k = 0; k < layers_; ++k)
        for (double z = bed_ + 0.5 * dx; z < bed_ + how_; z += dx) {
          Vec<D> x{};
          x[0] = xo_ + (k + 0.5) * dx;
          x[D - 1] = z;
          xo_pos_.push_back(x);
          xo_p_.push_back(rho0 * g * (bed_ + how_ - z));
        }
    const std::size_t n = P.n_owned();
    S.with_kernel([&](const auto& K) {
#pragma omp parallel for schedule(static)
      for (std::size_t i = 0; i < n; ++i) {
        if (P.kind[i] != Kind::Fluid) continue;
        const double gap = xo_ - P.pos[i][0];
        if (gap >= K.support || gap < 0.0) continue;
        const double F = relax_ ? gap / K.support : 1.0;
        Vec<D> a{};
        for (std::size_t o = 0; o < xo_pos_.size(); ++o) {
          const Vec<D> r = P.pos[i] - xo_pos_[o];
          const double r2 = dot(r, r);
          if (r2 >= K.support2 || r2 == 0.0) continue;
          a -= (F * vol * (P.p[i] + xo_p_[o]) / P.rho[i] * K.F(std::sqrt(r2))) * r;
        }
        P.acc[i] += a;
      }
    });
  }

 private:
  double xo_ = 0.0, bed_ = 0.0, how_ = 0.0;
  int layers_ = 3;
  bool relax_ = true;  // Kazemi's linear relaxation of the wall's volume towards X_o (false: full volume)
  std::vector<Vec<D>> xo_pos_;
  std::vector<double> xo_p_;
};

}  // namespace

double rough_bed_shape(double z, double z_centre, double d_s, double l0) {
  const double r = 0.5 * d_s;
  if (l0 <= 0.0) {
    const double y = (z - z_centre) / r;
    return std::abs(y) < 1.0 ? std::sqrt(1.0 - y * y) : 0.0;
  }
  // area of the circle between two horizontal lines, F(y) = ∫ 2 sqrt(r² − y²) dy
  auto F = [r](double y) {  // in t = y/r, clamped so that round-off never leaves [-1, 1]
    const double t = std::clamp(y / r, -1.0, 1.0);
    return r * r * (t * std::sqrt(std::max(0.0, 1.0 - t * t)) + std::asin(t));
  };
  const double y = z - z_centre;
  return std::clamp((F(y + 0.5 * l0) - F(y - 0.5 * l0)) / (d_s * l0), 0.0, 1.0);
}

template <int D>
Registry<ForceTerm<D>, const YAML::Node&, const std::string&>& force_registry() {
  static Registry<ForceTerm<D>, const YAML::Node&, const std::string&> r = [] {
    Registry<ForceTerm<D>, const YAML::Node&, const std::string&> reg;
    reg.add("body_force", [](const YAML::Node& n, const std::string& w) { return std::make_unique<BodyForce<D>>(n, w); });
    reg.add("rough_bed", [](const YAML::Node& n, const std::string& w) { return std::make_unique<RoughBed<D>>(n, w); });
    reg.add("imaginary_wall", [](const YAML::Node& n, const std::string& w) { return std::make_unique<ImaginaryWall<D>>(n, w); });
    return reg;
  }();
  return r;
}

template Registry<ForceTerm<2>, const YAML::Node&, const std::string&>& force_registry<2>();
template Registry<ForceTerm<3>, const YAML::Node&, const std::string&>& force_registry<3>();

}  // namespace sph
