#include "sphflume/boundaries/wave_spectrum.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

#include "sphflume/boundaries/paddle.hpp"

namespace sph {
namespace {
constexpr double kTwoPi = 2.0 * std::numbers::pi;

WaveComponent component(double a, double f, double phase, const MotionConfig& m) {
  WaveComponent c;
  c.amplitude = a;
  c.omega = kTwoPi * f;
  c.k = wave_number(c.omega, m.depth, m.gravity);
  c.phase = phase;
  return c;
}

std::vector<WaveComponent> spectral(const MotionConfig& m, bool focused) {
  double f0 = 0.0, f1 = 0.0;
  spectrum_band(m, f0, f1);
  const int n = m.components > 0 ? m.components : default_components(m);
  const double df = (f1 - f0) / n, fp = 1.0 / m.tp;
  std::vector<double> s(static_cast<std::size_t>(n));
  double sum = 0.0;
  for (int i = 0; i < n; ++i) {
    s[static_cast<std::size_t>(i)] = jonswap_shape(f0 + (i + 0.5) * df, fp, m.spectrum == "pierson_moskowitz" ? 1.0 : m.gamma);
    sum += s[static_cast<std::size_t>(i)] * df;
  }
  std::vector<WaveComponent> out;
  std::mt19937_64 rng(m.seed);
  // irregular: Σ a²/2 = m0 = (Hm0/4)², a_n = sqrt(2 S_n Δf) with S scaled to that m0
  const double m0 = (m.hm0 / 4.0) * (m.hm0 / 4.0);
  for (int i = 0; i < n; ++i) {
    const double f = f0 + (i + 0.5) * df, sn = s[static_cast<std::size_t>(i)];
    if (focused) {
      WaveComponent c = component(m.amplitude * sn * df / sum, f, 0.0, m);
      c.phase = c.k * m.focus_x - c.omega * m.focus_time;
      out.push_back(c);
    } else {
      const double phase = kTwoPi * uniform01(rng());
      out.push_back(component(std::sqrt(2.0 * sn * df * m0 / sum), f, phase, m));
    }
  }
  return out;
}

/// The user's elevation series resampled evenly (linear interpolation at its mean spacing) and
/// decomposed over its length T: η(τ) ≈ Σ a_n cos(2π n τ/T + φ_n), n ≥ 1 in [f_min, f_max].
std::vector<WaveComponent> from_elevation(const MotionConfig& m) {
  const auto& t = m.elevation_t;
  const auto& e = m.elevation_eta;
  const std::size_t ns = t.size();
  const double T = t.back() - t.front();
  const std::size_t n = ns;  // as many even samples as the series has
  const double h = T / static_cast<double>(n);
  std::vector<double> y(n);
  double mean = 0.0;
  for (std::size_t j = 0; j < n; ++j) {
    const double tj = t.front() + h * static_cast<double>(j);
    const auto it = std::upper_bound(t.begin(), t.end(), tj);
    const std::size_t k = std::min<std::size_t>(static_cast<std::size_t>(std::max<std::ptrdiff_t>(it - t.begin(), 1)) - 1, ns - 2);
    const double s = (tj - t[k]) / (t[k + 1] - t[k]);
    y[j] = e[k] + s * (e[k + 1] - e[k]);
    mean += y[j];
  }
  mean /= static_cast<double>(n);
  const double f1 = m.f_max > 0.0 ? m.f_max : 0.5 / h;  // Nyquist
  // the low end: long waves a piston makes with a stroke a/(kh) (default: kh >= 0.1)
  const double k0 = 0.1 / m.depth;
  const double f0 = m.f_min > 0.0 ? m.f_min : std::sqrt(m.gravity * k0 * std::tanh(0.1)) / kTwoPi;
  std::vector<WaveComponent> out;
  for (std::size_t q = 1; q <= n / 2; ++q) {
    const double f = static_cast<double>(q) / T;
    if (f < f0 || f > f1) continue;
    double re = 0.0, im = 0.0;
    const double w = kTwoPi * f;
    for (std::size_t j = 0; j < n; ++j) {
      const double tau = h * static_cast<double>(j);
      re += (y[j] - mean) * std::cos(w * tau);
      im += (y[j] - mean) * std::sin(w * tau);
    }
    const double scale = (2 * q == n ? 1.0 : 2.0) / static_cast<double>(n);
    // η = A cos(ωτ) + B sin(ωτ) = a cos(ωτ + φ): a = sqrt(A² + B²), φ = atan2(−B, A)
    const double A = scale * re, B = scale * im;
    out.push_back(component(std::hypot(A, B), f, std::atan2(-B, A) - w * t.front(), m));
  }
  return out;
}

}  // namespace

void spectrum_band(const MotionConfig& m, double& f0, double& f1) {
  const double fp = 1.0 / m.tp;
  f0 = m.f_min > 0.0 ? m.f_min : 0.5 * fp;
  f1 = m.f_max > 0.0 ? m.f_max : 3.0 * fp;
}

double uniform01(std::uint64_t word) { return static_cast<double>(word >> 11) * 0x1.0p-53; }

double jonswap_shape(double f, double fp, double gamma) {
  if (!(f > 0.0)) return 0.0;
  const double r = fp / f;
  const double pm = std::pow(f, -5.0) * std::exp(-1.25 * r * r * r * r);
  if (gamma == 1.0) return pm;
  const double sigma = f <= fp ? 0.07 : 0.09;
  const double x = (f - fp) / (sigma * fp);
  return pm * std::pow(gamma, std::exp(-0.5 * x * x));
}

int default_components(const MotionConfig& m) {
  double f0 = 0.0, f1 = 0.0;
  spectrum_band(m, f0, f1);
  return std::max(64, static_cast<int>(std::ceil((f1 - f0) * 200.0 * m.tp - 1e-9)));
}

std::vector<WaveComponent> wave_components(const MotionConfig& m) {
  if (m.law == "irregular") return spectral(m, false);
  if (m.law == "focused") return spectral(m, true);
  if (m.law == "elevation") return from_elevation(m);
  return {};
}

}  // namespace sph
