#include "sphflume/physics/force_terms.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "sphflume/core/reader.hpp"

namespace sph {
namespace {

/// Uniform body force per unit mass, optionally only inside a box region
/// (e.g. the pressure gradient that drives a periodic channel).
template <int D>
class BodyForce final : public ForceTerm<D> {
 public:
  explicit BodyForce(Reader& r) {
    r.valid({"acceleration", "min", "max"});
    const auto a = r.vec("acceleration", D);
    if (a.empty()) r.misspelt("acceleration");
    if (a.empty()) r.fail_at(r.get("acceleration"), r.key_path("acceleration"), fmt::format("a list of {} numbers (m/s2)", D));
    for (int d = 0; d < D; ++d) acc_[d] = a[d];
    const auto lo = r.vec("min", D), hi = r.vec("max", D);
    if (lo.empty() != hi.empty()) r.fail_at(r.get(lo.empty() ? "max" : "min"), r.key_path("min"), "both 'min' and 'max' corners of the region (or neither)");
    if (!lo.empty()) {
      region_ = true;
      for (int d = 0; d < D; ++d) { lo_[d] = lo[d]; hi_[d] = hi[d]; }
    }
    r.finish();
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

/// A damping (sponge) zone at the end of a wave flume: fluid between x = start and x = end along
/// the axis feels  a = −k(x) u,  k = rate s²,  s = (x − start)/(end − start) clamped to [0, 1], so
/// that a wave entering it is absorbed gradually (no reflection from a sudden change) and the far
/// wall reflects little. rate [1/s]: of order 10/T for waves of period T over a zone one wavelength
/// long; explicit, so rate Δt ≤ 1 (checked against nothing: Δt of either scheme is far below).
template <int D>
class DampingZone final : public ForceTerm<D> {
 public:
  explicit DampingZone(Reader& r) {
    r.valid({"start", "end", "rate", "axis"});
    x0_ = r.required<double>("start", "the coordinate where the damping begins [m]");
    x1_ = r.required<double>("end", "the coordinate where it is strongest (the far wall) [m]");
    if (!(x1_ != x0_)) r.fail_at(r.get("end"), r.key_path("end"), "an end different from start");
    rate_ = r.positive("rate", 10.0);
    if (!(rate_ <= 1e4)) r.fail_at(r.get("rate"), r.key_path("rate"), "a damping rate in (0, 1e4] 1/s");
    const std::string ax = r.scalar<std::string>("axis", "x");
    axis_ = ax == "x" ? 0 : (ax == "y" && D == 3) ? 1 : -1;
    if (axis_ < 0) r.fail_at(r.get("axis"), r.key_path("axis"), D == 3 ? "x or y" : "x");
    r.finish();
  }
  const char* name() const override { return "damping_zone"; }
  void add(System<D>& S) override {
    auto& P = S.particles;
    const double inv = 1.0 / (x1_ - x0_);
    for (std::size_t i = 0; i < P.n_owned(); ++i) {
      if (P.kind[i] != Kind::Fluid) continue;
      const double f = (P.pos[i][axis_] - x0_) * inv;
      if (!(f > 0.0)) continue;
      const double sc = std::min(f, 1.0);
      P.acc[i] -= (rate_ * sc * sc) * P.vel[i];
    }
  }

 private:
  double x0_ = 0.0, x1_ = 1.0, rate_ = 10.0;
  int axis_ = 0;
};

/// Kazemi's rough-bed drag layer (§3.1.1.1, §3.1.4; eqs 3.3, 3.4, 3.17): inside a layer of
/// thickness R_d above the numerical bed (the roughness crest is bed + R_d), every fluid
/// particle feels  a = -factor C_d W_d(z) / d_s  u |u|  (factor 1/2: F_d = 1/2 C_d rho A_d u|u|
/// over A_r = d_s l0 with A_d = l0), W_d the chord fraction of the bed spheres (diameter d_s,
/// centres d_s/2 below the crest) over the particle's height dx.
template <int D>
class RoughBed final : public ForceTerm<D> {
 public:
  explicit RoughBed(Reader& r) {
    r.valid({"cd", "diameter", "bed", "thickness", "shape", "factor"});
    cd_ = r.in_range("cd", 1.0, 0.0, 100.0);
    ds_ = r.positive("diameter", 0.0, true);
    bed_ = r.scalar<double>("bed", 0.0);
    rd_ = r.positive("thickness", 0.0, true);
    if (!(rd_ <= ds_)) r.fail_at(r.get("thickness"), r.key_path("thickness"), "R_d in (0, diameter] (the layer between the numerical bed and the crest)");
    factor_ = r.in_range("factor", 0.5, 0.0, 100.0);
    point_ = r.choice("shape", "fragment", {"fragment", "point"}) == "point";
    r.finish();
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

/// Kazemi's outlet "imaginary wall" (§6.2.4.3, eqs 6.10-6.12): `layers`
/// columns of fixed particles (spacing dx, volume dx^2, phi = 1) just downstream of the outlet
/// line X_o, from the bed up to bed + H_ow, with the hydrostatic pressure of that tailwater
/// level. They act only on the pressure gradient of the fluid within one kernel support
/// upstream of X_o:  O_a = - Σ_o F_o V_o (p_a + p_o)/ρ_a ∇_a W_ao,  F_o = (X_o - x_a)/(support)
/// (Kazemi: falls linearly to 0 at X_o; relax: false keeps F_o = 1), and in no other sum. Fluid reaching X_o leaves through the
/// domain's face there (set domain.max x = X_o; the run removes and counts it). In 3D the columns
/// stand at every lattice y of `span` [y0, y1] (volume dx^3): the channel's width, or one support
/// beyond each side where the sides are periodic.
template <int D>
class ImaginaryWall final : public ForceTerm<D> {
 public:
  ImaginaryWall(Reader& r, const Node& n) {
    r.valid({"x", "bed", "height", "layers", "relax", "span"});
    if constexpr (D == 3) {
      if (!r.has("span")) r.fail_at(n, r.key_path("span"), "the outlet's extent across the channel in 3D, span: [y0, y1] (the width; with periodic sides one kernel support beyond each)");
      span_ = r.vec("span", 2);
      if (!(span_[1] > span_[0])) r.fail_at(r.get("span"), r.key_path("span"), "[y0, y1] with y1 > y0");
    } else if (r.has("span")) {
      r.fail_at(r.get("span"), r.key_path("span"), "no span in 2D (the outlet spans the plane)");
    }
    xo_ = r.required<double>("x", "the outlet line X_o in m");
    bed_ = r.scalar<double>("bed", 0.0);
    how_ = r.positive("height", 0.0, true);
    layers_ = r.scalar<int>("layers", 3);
    if (layers_ < 1 || layers_ > 10) r.fail_at(r.get("layers"), r.key_path("layers"), "an integer from 1 to 10");
    relax_ = r.scalar<bool>("relax", true);
    r.finish();
  }
  const char* name() const override { return "imaginary_wall"; }
  void add(System<D>& S) override {
    auto& P = S.particles;
    const double dx = S.dx, vol = D == 3 ? dx * dx * dx : dx * dx, g = std::abs(S.gravity[D - 1]), rho0 = S.eos.rho0;
    if (xo_pos_.empty()) {
      // 2D: one y; 3D: the lattice across the span
      const int ny = D == 3 ? std::max(1, static_cast<int>(std::floor((span_[1] - span_[0]) / dx + 1e-9))) : 1;
      for (int j = 0; j < ny; ++j)
        for (int k = 0; k < layers_; ++k)
          for (double z = bed_ + 0.5 * dx; z < bed_ + how_; z += dx) {
            Vec<D> x{};
            x[0] = xo_ + (k + 0.5) * dx;
            if constexpr (D == 3) x[1] = span_[0] + (j + 0.5) * dx;
            x[D - 1] = z;
            xo_pos_.push_back(x);
            xo_p_.push_back(rho0 * g * (bed_ + how_ - z));
          }
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
  std::vector<double> span_;  // 3D: [y0, y1]
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
Registry<ForceTerm<D>, Reader&, const Node&>& force_registry() {
  static Registry<ForceTerm<D>, Reader&, const Node&> r = [] {
    Registry<ForceTerm<D>, Reader&, const Node&> reg;
    reg.add("body_force", [](Reader& q, const Node&) { return std::make_unique<BodyForce<D>>(q); });
    reg.add("rough_bed", [](Reader& q, const Node&) { return std::make_unique<RoughBed<D>>(q); });
    reg.add("damping_zone", [](Reader& q, const Node&) { return std::make_unique<DampingZone<D>>(q); });
    reg.add("imaginary_wall", [](Reader& q, const Node& n) { return std::make_unique<ImaginaryWall<D>>(q, n); });
    return reg;
  }();
  return r;
}

template <int D>
void add_force_terms(const Node& list, const std::string& file, System<D>& S) {
  for (std::size_t i = 0; i < list.size(); ++i) {
    const Node& n = list[i];
    Reader r(n, file, fmt::format("forces.{}", i));
    std::string known;
    for (const auto& k : force_registry<D>().names()) known += (known.empty() ? "" : ", ") + k;
    const std::string type = r.required<std::string>("type", "a force term: " + known);
    if (!force_registry<D>().has(type)) r.fail_at(r.get("type"), r.key_path("type"), "one of " + known + " (got '" + type + "')");
    S.forces.push_back(force_registry<D>().create(type, r, n));
  }
}

template void add_force_terms<2>(const Node&, const std::string&, System<2>&);
template void add_force_terms<3>(const Node&, const std::string&, System<3>&);
template Registry<ForceTerm<2>, Reader&, const Node&>& force_registry<2>();
template Registry<ForceTerm<3>, Reader&, const Node&>& force_registry<3>();

}  // namespace sph
