#include "sphflume/boundaries/paddle.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "sphflume/core/errors.hpp"

namespace sph {
namespace {

/// (1 − cos(π τ/T_r))/2 over [0, T_r], 1 after, 0 before.
double ramp(double tau, double tr) {
  if (tau <= 0.0) return 0.0;
  if (!(tr > 0.0) || tau >= tr) return 1.0;
  return 0.5 * (1.0 - std::cos(std::numbers::pi * tau / tr));
}

class Solitary final : public PaddleLaw {
 public:
  Solitary(const MotionConfig& m, const std::string& file) : start_(m.start) {
    const double H = m.height, h0 = m.depth, g = m.gravity;
    eps_ = H / h0;
    c_ = std::sqrt(g * (h0 + H));
    if (m.theory == "goring") beta_ = std::sqrt(3.0 * eps_) / h0;
    else beta_ = std::sqrt(3.0 * eps_ / (1.0 + eps_)) / h0;
    explicit_ = m.theory == "rayleigh_explicit";
    a_ = 2.0 * eps_ / beta_;
    // θ = −3.8 at the start: c t_s = 7.6/β + S/2 (the implicit θ carries −X = S/2 there), so the
    // paddle starts at 2e-3 c ε of rest; the explicit law uses the same crest time
    ts_ = (7.6 / beta_ + a_) / c_;
    x0_ = raw(-ts_);
    if (!std::isfinite(x0_) || !(c_ > 0.0))
      throw InputError(fmt::format("{}: line {}: motion '{}': the solitary law cannot be built from height {} m and "
                                   "depth {} m: expected 0 < height < depth", file, m.line, m.name, H, h0));
  }
  double displacement(double t) const override { return t <= start_ ? 0.0 : raw(t - start_ - ts_) - x0_; }
  double velocity(double t) const override {
    if (explicit_) return PaddleLaw::velocity(t);
    if (t <= start_) return 0.0;
    const double tp = t - start_ - ts_;
    const double x = raw(tp);
    const double ch = std::cosh(0.5 * beta_ * (c_ * tp - x));
    const double s = 1.0 / (ch * ch);
    return c_ * eps_ * s / (1.0 + eps_ * s);
  }
  double stroke() const override { return -2.0 * x0_; }

 private:
  /// X(t') of the unshifted law (centred on the crest's passage at t' = 0).
  double raw(double tp) const {
    if (explicit_) {
      const double th = std::tanh(0.5 * beta_ * c_ * tp);
      return a_ * th / (1.0 + eps_ * (1.0 - th * th));
    }
    // Newton on F(X) = X − a tanh(β (c t' − X)/2), F' = 1 + ε sech²θ in [1, 1 + ε]
    double x = a_ * std::tanh(0.5 * beta_ * c_ * tp);
    for (int it = 0; it < 60; ++it) {
      const double th = 0.5 * beta_ * (c_ * tp - x);
      const double ch = std::cosh(th);
      const double f = x - a_ * std::tanh(th);
      const double dx = f / (1.0 + eps_ / (ch * ch));
      x -= dx;
      if (std::abs(dx) <= 1e-15 * a_) break;
    }
    return x;
  }
  double start_, eps_ = 0.0, c_ = 0.0, beta_ = 0.0, a_ = 0.0, ts_ = 0.0, x0_ = 0.0;
  bool explicit_ = false;
};

class Regular final : public PaddleLaw {
 public:
  Regular(const MotionConfig& m, bool second_order) : start_(m.start), ramp_(m.ramp) {
    omega_ = 2.0 * std::numbers::pi / m.period;
    const double k = wave_number(omega_, m.depth, m.gravity);
    const double kh = k * m.depth;
    const double m1 = piston_transfer(kh);
    half_stroke_ = 0.5 * m.height / m1;
    if (second_order) {
      const double sh = std::sinh(kh);
      second_ = m.height * m.height / (32.0 * m.depth) * (3.0 * std::cosh(kh) / (sh * sh * sh) - 2.0 / m1);
    }
  }
  double displacement(double t) const override {
    const double tau = t - start_;
    if (tau <= 0.0) return 0.0;
    return ramp(tau, ramp_) * (half_stroke_ * std::sin(omega_ * tau) + second_ * std::sin(2.0 * omega_ * tau));
  }
  double stroke() const override { return 2.0 * half_stroke_; }

 private:
  double start_, ramp_, omega_ = 0.0, half_stroke_ = 0.0, second_ = 0.0;
};

class Table final : public PaddleLaw {
 public:
  explicit Table(const MotionConfig& m) : start_(m.start), ramp_(m.ramp), t_(m.table_t), x_(m.table_x) {
    // node slopes by central differences (one-sided at the ends): a C1 cubic Hermite curve
    // through the samples, so that the paddle's velocity is continuous and its acceleration bounded
    const std::size_t n = t_.size();
    v_.assign(n, 0.0);
    for (std::size_t k = 0; k < n; ++k) {
      const std::size_t a = k > 0 ? k - 1 : 0, b = k + 1 < n ? k + 1 : n - 1;
      v_[k] = (x_[b] - x_[a]) / (t_[b] - t_[a]);
    }
    v_.back() = 0.0;  // held at its last value after the end: it arrives at rest
  }
  double displacement(double t) const override {
    const double tau = t - start_;
    if (tau <= t_.front()) return 0.0;
    double x = x_.back();
    if (tau < t_.back()) {
      const auto it = std::upper_bound(t_.begin(), t_.end(), tau);
      const std::size_t k = static_cast<std::size_t>(it - t_.begin()) - 1;
      const double hk = t_[k + 1] - t_[k], s = (tau - t_[k]) / hk;
      const double s2 = s * s, s3 = s2 * s;
      x = (2 * s3 - 3 * s2 + 1) * x_[k] + (s3 - 2 * s2 + s) * hk * v_[k] + (-2 * s3 + 3 * s2) * x_[k + 1] +
          (s3 - s2) * hk * v_[k + 1];
    }
    return ramp(tau - t_.front(), ramp_) * (x - x_.front());
  }
  double stroke() const override {
    const auto [lo, hi] = std::minmax_element(x_.begin(), x_.end());
    return *hi - *lo;
  }

 private:
  double start_, ramp_;
  std::vector<double> t_, x_, v_;
};

}  // namespace

double PaddleLaw::velocity(double t) const {
  const double d = 1e-5;
  return (displacement(t + d) - displacement(t - d)) / (2.0 * d);
}

double PaddleLaw::acceleration(double t) const {
  // wide enough that a table's kinks give a bounded pulse of the right impulse
  const double d = 1e-4;
  return (velocity(t + d) - velocity(t - d)) / (2.0 * d);
}

double wave_number(double omega, double depth, double g) {
  // Newton on f(k) = g k tanh(kh) − ω², from the deep/shallow-water blend (monotone, converges)
  double k = std::max(omega * omega / g, omega / std::sqrt(g * depth));
  for (int it = 0; it < 100; ++it) {
    const double th = std::tanh(k * depth);
    const double f = g * k * th - omega * omega;
    const double df = g * th + g * k * depth * (1.0 - th * th);
    const double dk = f / df;
    k -= dk;
    if (std::abs(dk) <= 1e-15 * k) break;
  }
  return k;
}

double piston_transfer(double kh) {
  return 2.0 * (std::cosh(2.0 * kh) - 1.0) / (std::sinh(2.0 * kh) + 2.0 * kh);
}

std::unique_ptr<PaddleLaw> make_paddle_law(const MotionConfig& m, const std::string& file) {
  if (m.law == "solitary") return std::make_unique<Solitary>(m, file);
  if (m.law == "regular") return std::make_unique<Regular>(m, false);
  if (m.law == "stokes2") return std::make_unique<Regular>(m, true);
  if (m.law == "table") return std::make_unique<Table>(m);
  throw InputError(fmt::format("{}: line {}: motion '{}': unknown law '{}'", file, m.line, m.name, m.law));
}

}  // namespace sph
