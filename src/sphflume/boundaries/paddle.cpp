#include "sphflume/boundaries/paddle.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include <fmt/format.h>

#include "sphflume/boundaries/paddle_order2.hpp"
#include "sphflume/boundaries/wave_spectrum.hpp"
#include "sphflume/core/errors.hpp"

namespace sph {
namespace {

/// (1 − cos(π τ/T_r))/2 over [0, T_r], 1 after, 0 before.
double ramp(double tau, double tr) {
  if (tau <= 0.0) return 0.0;
  if (!(tr > 0.0) || tau >= tr) return 1.0;
  return 0.5 * (1.0 - std::cos(std::numbers::pi * tau / tr));
}

/// d/dτ of the ramp.
double ramp_rate(double tau, double tr) {
  if (tau <= 0.0 || !(tr > 0.0) || tau >= tr) return 0.0;
  const double w = std::numbers::pi / tr;
  return 0.5 * w * std::sin(w * tau);
}

WavemakerShape wavemaker_shape(const MotionConfig& m) {
  WavemakerShape p;
  p.depth = m.depth;
  p.gravity = m.gravity;
  if (m.paddle == "flap") p.hinge_depth = m.hinge_depth;
  return p;
}

/// Schäffer's second-order part of a sum of components, or null without `second_order`.
std::unique_ptr<SecondOrderPaddle> second_order_part(const MotionConfig& m, const std::vector<WaveComponent>& comps) {
  if (!m.second_order || comps.empty()) return nullptr;
  std::vector<double> c;
  for (const auto& w : comps) c.push_back(paddle_transfer(m, w.k * m.depth));
  return std::make_unique<SecondOrderPaddle>(comps, c, wavemaker_shape(m), m.evanescent_modes);
}

class Solitary final : public PaddleLaw {
 public:
  Solitary(const MotionConfig& m, const std::string& file) : start_(m.start), h0_(m.depth) {
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
  double elevation(double t, double x) const override {
    if (t <= start_) return 0.0;
    const double tp = t - start_ - ts_;
    const double ch = std::cosh(0.5 * beta_ * (c_ * tp - raw(tp) - x));
    return eps_ * h0_ / (ch * ch);
  }

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
  double start_, h0_, eps_ = 0.0, c_ = 0.0, beta_ = 0.0, a_ = 0.0, ts_ = 0.0, x0_ = 0.0;
  bool explicit_ = false;
};

class Regular final : public PaddleLaw {
 public:
  Regular(const MotionConfig& m, bool second_order) : start_(m.start), ramp_(m.ramp) {
    omega_ = 2.0 * std::numbers::pi / m.period;
    const double k = wave_number(omega_, m.depth, m.gravity);
    const double kh = k * m.depth;
    const double m1 = paddle_transfer(m, kh);
    half_stroke_ = 0.5 * m.height / m1;
    amp_ = 0.5 * m.height;
    k_ = k;
    celerity_ = omega_ / k;
    // Schäffer's correction (second_order: true): the wave (H/2) cos ωτ as one component, its X2 and bound
    // harmonic ramped by r² (second order in the amplitude)
    schaffer_ = second_order_part(m, {WaveComponent{amp_, omega_, k, 0.0}});
    if (second_order) {
      const double sh = std::sinh(kh);
      second_ = m.height * m.height / (32.0 * m.depth) * (3.0 * std::cosh(kh) / (sh * sh * sh) - 2.0 / m1);
      // the bound second harmonic of a Stokes wave (Dean & Dalrymple 1991 eq. 11.48)
      bound_ = m.height * m.height * k / 16.0 * std::cosh(kh) * (2.0 + std::cosh(2.0 * kh)) / (sh * sh * sh);
    }
  }
  double elevation(double t, double x) const override {
    const double tau = t - start_ - x / celerity_;  // (the ramp's front travels at c: a first-order estimate)
    if (tau <= 0.0) return 0.0;
    const double ph = omega_ * (t - start_) - k_ * x;
    const double r = ramp(tau, ramp_);
    return r * (amp_ * std::cos(ph) + bound_ * std::cos(2.0 * ph)) + (schaffer_ ? r * r * schaffer_->elevation(t - start_, x) : 0.0);
  }
  double displacement(double t) const override {
    const double tau = t - start_;
    if (tau <= 0.0) return 0.0;
    const double r = ramp(tau, ramp_);
    return r * (half_stroke_ * std::sin(omega_ * tau) + second_ * std::sin(2.0 * omega_ * tau)) + (schaffer_ ? r * r * schaffer_->displacement(tau) : 0.0);
  }
  double velocity(double t) const override {
    if (!schaffer_) return PaddleLaw::velocity(t);  // (the first-order laws as they have always been)
    const double tau = t - start_;
    if (tau <= 0.0) return 0.0;
    const double r = ramp(tau, ramp_), dr = ramp_rate(tau, ramp_);
    const double x1 = half_stroke_ * std::sin(omega_ * tau) + second_ * std::sin(2.0 * omega_ * tau);
    const double v1 = omega_ * (half_stroke_ * std::cos(omega_ * tau) + 2.0 * second_ * std::cos(2.0 * omega_ * tau));
    return r * v1 + dr * x1 + r * r * schaffer_->velocity(tau) + 2.0 * r * dr * schaffer_->displacement(tau);
  }
  double stroke() const override { return 2.0 * half_stroke_ + (schaffer_ ? 2.0 * schaffer_->excursion() : 0.0); }

 private:
  double start_, ramp_, omega_ = 0.0, half_stroke_ = 0.0, second_ = 0.0, amp_ = 0.0, bound_ = 0.0, k_ = 0.0, celerity_ = 1.0;
  std::unique_ptr<SecondOrderPaddle> schaffer_;
};

class Table final : public PaddleLaw {
 public:
  explicit Table(const MotionConfig& m)
      : start_(m.start), ramp_(m.ramp), shallow_(m.depth > 0.0 ? std::sqrt(m.depth / m.gravity) : 0.0), depth_(m.depth), t_(m.table_t),
        x_(m.table_x) {
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
  /// Long-wave theory: a piston moving at U makes η = U sqrt(h/g), carried at c = sqrt(g h) (NaN
  /// without a depth).
  double elevation(double t, double x) const override {
    return shallow_ > 0.0 ? shallow_ * velocity(t - x * shallow_ / depth_) : std::numeric_limits<double>::quiet_NaN();
  }

 private:
  double start_, ramp_, shallow_, depth_;
  std::vector<double> t_, x_, v_;
};


/// irregular, focused, elevation: a sum of linear components (boundaries/wave_spectrum.hpp),
/// X = r Σ (a_n/m1_n) sin(ω_n τ + φ_n), η = r Σ a_n cos(ω_n τ + φ_n); the elevation law also ramps
/// down over the ramp's length before its series ends, and rests after.
class LinearSum final : public PaddleLaw {
 public:
  explicit LinearSum(const MotionConfig& m) : start_(m.start), ramp_(m.ramp), comps_(wave_components(m)) {
    for (const auto& c : comps_) {
      gain_.push_back(1.0 / paddle_transfer(m, c.k * m.depth));
      stroke_ += 2.0 * c.amplitude * gain_.back();
    }
    schaffer_ = second_order_part(m, comps_);
    if (schaffer_) stroke_ += 2.0 * schaffer_->excursion();
    if (m.law == "elevation") {
      t0_ = m.elevation_t.front();
      t1_ = m.elevation_t.back();
    }
  }
  double displacement(double t) const override { return sum(t, true); }
  double velocity(double t) const override {
    const double tau = t - start_;
    if (tau <= t0_ || tau >= t1_) return 0.0;
    double v = 0.0;
    for (std::size_t n = 0; n < comps_.size(); ++n) {
      const auto& c = comps_[n];
      v += c.amplitude * gain_[n] * c.omega * std::cos(c.omega * tau + c.phase);
    }
    const double r = envelope(tau), dr = envelope_rate(tau);
    v = r * v + (dr != 0.0 ? dr * raw(tau, true) : 0.0);
    // the second-order part, ramped by r² (second order in the amplitude)
    if (schaffer_) v += r * r * schaffer_->velocity(tau) + (dr != 0.0 ? 2.0 * r * dr * schaffer_->displacement(tau) : 0.0);
    return v;
  }
  double elevation(double t, double x) const override {
    const double tau = t - start_;
    if (tau <= t0_ || tau >= t1_) return 0.0;
    double e = 0.0;
    for (const auto& c : comps_) e += c.amplitude * std::cos(c.omega * tau + c.phase - c.k * x);
    const double r = envelope(tau);  // (the envelope at the paddle: the ramp's front is not delayed)
    return r * e + (schaffer_ ? r * r * schaffer_->elevation(tau, x) : 0.0);
  }
  double stroke() const override { return stroke_; }
  std::vector<WaveComponent> components() const override { return comps_; }

 private:
  double raw(double tau, bool paddle) const {
    double x = 0.0;
    for (std::size_t n = 0; n < comps_.size(); ++n) {
      const auto& c = comps_[n];
      x += paddle ? c.amplitude * gain_[n] * std::sin(c.omega * tau + c.phase) : c.amplitude * std::cos(c.omega * tau + c.phase);
    }
    return x;
  }
  double sum(double t, bool paddle) const {
    const double tau = t - start_;
    if (tau <= t0_ || tau >= t1_) return 0.0;
    const double r = envelope(tau);
    return r * raw(tau, paddle) + (paddle && schaffer_ ? r * r * schaffer_->displacement(tau) : 0.0);
  }
  double envelope(double tau) const {
    double r = ramp(tau - t0_, ramp_);
    if (std::isfinite(t1_)) r *= ramp(t1_ - tau, ramp_);
    return r;
  }
  /// d(envelope)/dτ (0 outside the ramps).
  double envelope_rate(double tau) const {
    if (!(ramp_ > 0.0)) return 0.0;
    const double r1 = ramp(tau - t0_, ramp_), d1 = ramp_rate(tau - t0_, ramp_);
    if (!std::isfinite(t1_)) return d1;
    return d1 * ramp(t1_ - tau, ramp_) - r1 * ramp_rate(t1_ - tau, ramp_);
  }
  double start_, ramp_;
  std::vector<WaveComponent> comps_;
  std::vector<double> gain_;
  double t0_ = 0.0, t1_ = std::numeric_limits<double>::infinity(), stroke_ = 0.0;
  std::unique_ptr<SecondOrderPaddle> schaffer_;
};

/// absorber: a paddle at rest that makes no wave (η = 0): with `absorption`, an active absorber
/// at the flume's end in place of a beach or a sponge.
class Absorber final : public PaddleLaw {
 public:
  double displacement(double) const override { return 0.0; }
  double velocity(double) const override { return 0.0; }
  double elevation(double, double) const override { return 0.0; }
  double stroke() const override { return 0.0; }
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
  if (kh > 20.0) return 2.0;  // deep water (the cosh/sinh ratio overflows beyond kh ≈ 177; 2 to 1e-16 here)
  return 2.0 * (std::cosh(2.0 * kh) - 1.0) / (std::sinh(2.0 * kh) + 2.0 * kh);
}

double flap_transfer(double kh, double d_over_h) {
  if (kh > 20.0) {  // deep water (sinh, cosh of kh ~ e^{kh}/2 to 1e-17; the cosh ratios overflow beyond kh ≈ 350)
    const double kd = kh * d_over_h;
    return 2.0 * (1.0 - (1.0 - std::exp(-kd)) / kd);
  }
  const double kd = kh * d_over_h;
  const double sh = std::sinh(kh);
  return 4.0 * sh / (std::sinh(2.0 * kh) + 2.0 * kh) * (sh - (std::cosh(kh) - std::cosh(kh - kd)) / kd);
}

double paddle_transfer(const MotionConfig& m, double kh) {
  if (m.paddle == "flap") return flap_transfer(kh, m.hinge_depth / m.depth);
  return piston_transfer(kh);
}

std::unique_ptr<PaddleLaw> make_paddle_law(const MotionConfig& m, const std::string& file) {
  if (m.law == "solitary") return std::make_unique<Solitary>(m, file);
  if (m.law == "regular") return std::make_unique<Regular>(m, false);
  if (m.law == "stokes2") return std::make_unique<Regular>(m, true);
  if (m.law == "table") return std::make_unique<Table>(m);
  if (m.law == "irregular" || m.law == "focused" || m.law == "elevation") return std::make_unique<LinearSum>(m);
  if (m.law == "absorber") return std::make_unique<Absorber>();
  throw InputError(fmt::format("{}: line {}: motion '{}': unknown law '{}'", file, m.line, m.name, m.law));
}

}  // namespace sph
