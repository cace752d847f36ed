#include "sphflume/boundaries/paddle_order2.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "sphflume/boundaries/paddle.hpp"

namespace sph {
namespace {
using cd = std::complex<double>;
constexpr cd kI{0.0, 1.0};

// ∫_a^b cosh(r s) ds, ∫ sinh(r s) ds, ∫ s cosh(r s) ds for complex r (s = z + h), with their r → 0 limits
cd int_cosh(cd r, double a, double b) { return std::abs(r) < 1e-9 ? cd(b - a) : (std::sinh(r * b) - std::sinh(r * a)) / r; }
cd int_sinh(cd r, double a, double b) { return std::abs(r) < 1e-9 ? r * (0.5 * (b * b - a * a)) : (std::cosh(r * b) - std::cosh(r * a)) / r; }
cd int_s_cosh(cd r, double a, double b) {
  if (std::abs(r) < 1e-9) return cd(0.5 * (b * b - a * a));
  return (b * std::sinh(r * b) - a * std::sinh(r * a)) / r - (std::cosh(r * b) - std::cosh(r * a)) / (r * r);
}

/// The paddle's shape function f(z) = (z + h + l)/(h + l) above the hinge (1 for a piston), l = hinge depth − h.
struct Shape {
  double h, g, l, d;  // l = ∞ for a piston; d = max(0, −l), the hinge's height above the bed
  bool piston;
  explicit Shape(const WavemakerShape& p)
      : h(p.depth), g(p.gravity), l(std::isfinite(p.hinge_depth) ? p.hinge_depth - p.depth : 0.0),
        d(std::isfinite(p.hinge_depth) ? std::max(0.0, p.depth - p.hinge_depth) : 0.0), piston(!std::isfinite(p.hinge_depth)) {}
  /// Λ(k) = ∫ f(z) cosh k(z + h) dz over the water column
  cd lam(cd k) const { return piston ? int_cosh(k, 0.0, h) : (int_s_cosh(k, d, h) + l * int_cosh(k, d, h)) / (h + l); }
  /// the first-order transfer η/X of a mode: sinh(kh) Λ(k) 4k/(sinh 2kh + 2kh)
  cd transfer(cd k) const { return std::sinh(k * h) * lam(k) * (4.0 * k) / (std::sinh(2.0 * k * h) + 2.0 * k * h); }
  /// ∫ cosh K(z + h) [k² f C + f′ ∂C/∂z] dz, C = cosh k(z + h)/cosh kh (the paddle term's projection)
  cd pi(cd k, double w, double K) const {
    if (piston) return k * k * std::cosh(K * h) * (w * w - g * K * std::tanh(K * h)) / (g * (k * k - K * K));
    const cd p = k + K, m = k - K;
    const cd fcc = (0.5 * (int_s_cosh(p, d, h) + int_s_cosh(m, d, h)) + l * 0.5 * (int_cosh(p, d, h) + int_cosh(m, d, h))) / (h + l);
    const cd fsc = 0.5 * (int_sinh(p, d, h) + int_sinh(m, d, h)) / (h + l);
    return (k * k * fcc + k * fsc) / std::cosh(k * h);
  }
};

/// The progressive and J evanescent wave numbers of ω (k_j = −iκ_j, ω² = −gκ tan κh) and their transfers.
struct Modes {
  std::vector<cd> k, c;
};

Modes modes(const Shape& s, double w, int J) {
  Modes m;
  m.k.push_back(wave_number(w, s.h, s.g));
  for (int j = 1; j <= J; ++j) {
    double lo = (j - 0.5) * std::numbers::pi / s.h, hi = j * std::numbers::pi / s.h;  // f(lo+) = −∞, f(hi) = ω² > 0
    for (int it = 0; it < 200 && hi - lo > 1e-15 * hi; ++it) {
      const double q = 0.5 * (lo + hi);
      (w * w + s.g * q * std::tan(q * s.h) < 0.0 ? lo : hi) = q;
    }
    m.k.push_back(-kI * (0.5 * (lo + hi)));
  }
  for (const cd& k : m.k) m.c.push_back(s.transfer(k));
  return m;
}

cd hpm(double g, double wn, double wm, cd kj, cd kl, int sign) {
  const double wmm = sign * wm, ws = wn + wmm;
  const cd klt = static_cast<double>(sign) * kl;
  return ws * (wn * wmm - g * g * kj * klt / (wn * wmm)) + 0.5 * (wn * wn * wn + wmm * wmm * wmm) -
         0.5 * g * g * (kj * kj / wn + klt * klt / wmm);
}

/// F± with the modes up to J and up to J/2 (both from one pass over the double sum).
void transfer_pair(const Shape& s, double wn, const Modes& a, double wm, const Modes& b0, int sign, int J, cd& full, cd& half) {
  Modes b = b0;
  if (sign < 0)
    for (std::size_t l = 0; l < b.k.size(); ++l) {
      b.k[l] = std::conj(b.k[l]);
      b.c[l] = std::conj(b.c[l]);
    }
  const double ws = wn + sign * wm;
  const double K = wave_number(std::abs(ws), s.h, s.g);
  const int Jh = J / 2;
  cd a1 = 0.0, a2 = 0.0, a1h = 0.0, a2h = 0.0, s3 = 0.0, s3h = 0.0;
  for (int j = 0; j <= J; ++j) {
    const cd t1 = a.c[j] * s.pi(a.k[j], wn, K), t2 = b.c[j] * s.pi(b.k[j], wm, K);
    a1 += t1;
    a2 += t2;
    if (j <= Jh) {
      a1h += t1;
      a2h += t2;
    }
  }
  for (int j = 0; j <= J; ++j)
    for (int l = 0; l <= J; ++l) {
      const cd kap = a.k[j] + static_cast<double>(sign) * b.k[l];
      const cd t = a.c[j] * b.c[l] * kap * hpm(s.g, wn, wm, a.k[j], b.k[l], sign) / (kap * kap - K * K);
      s3 += t;
      if (j <= Jh && l <= Jh) s3h += t;
    }
  const cd den = kI * ws * s.lam(K);
  const double ch = std::cosh(K * s.h) / s.g;
  full = (s.g / (2 * wn) * a1 + s.g / (2 * wm) * a2 - static_cast<double>(sign) * ch * s3) / den;
  half = (s.g / (2 * wn) * a1h + s.g / (2 * wm) * a2h - static_cast<double>(sign) * ch * s3h) / den;
}

}  // namespace

cd schaffer_transfer(const WavemakerShape& p, double wn, double wm, int sign, int J) {
  const Shape s(p);
  cd full, half;
  transfer_pair(s, wn, modes(s, wn, J), wm, modes(s, wm, J), sign, J, full, half);
  return full;
}

cd bound_elevation(double h, double g, double w1, double w2, int sign) {
  // the second-order free-surface problem of two progressive modes (docs/design/second_order_paddle/boundcheck.py)
  struct Surf {
    cd U, W, T, D, Wt;
  };
  auto surf = [&](double w, double k, cd P) {
    const cd Wv = P * k * std::tanh(k * h);
    return Surf{-kI * k * P, Wv, kI * w * P, P * (g * k * k - w * w * w * w / g), kI * w * Wv};
  };
  const double k1 = wave_number(w1, h, g), k2 = wave_number(w2, h, g);
  const Surf A = surf(w1, k1, kI * g / w1);
  Surf B = surf(w2, k2, kI * g / w2);
  if (sign < 0) B = {std::conj(B.U), std::conj(B.W), std::conj(B.T), std::conj(B.D), std::conj(B.Wt)};
  const double ws = w1 + sign * w2, kap = k1 + sign * k2;
  const cd sq = A.U * B.U + A.W * B.W;
  const cd Q = -kI * ws * sq + 0.5 * (A.T * B.D + B.T * A.D) / g;
  const cd Bc = Q / (g * kap * std::tanh(kap * h) - ws * ws);
  return -(1.0 / g) * (kI * ws * Bc + 0.5 * sq - 0.5 * (A.T * B.Wt + B.T * A.Wt) / g);
}

SecondOrderPaddle::SecondOrderPaddle(const std::vector<WaveComponent>& comps, const std::vector<double>& transfer,
                                     const WavemakerShape& p, int J)
    : comps_(comps), depth_(p.depth), g_(p.gravity) {
  const std::size_t N = comps.size();
  if (N == 0) return;
  w0_ = comps[0].omega;
  dw_ = N > 1 ? comps[1].omega - comps[0].omega : 0.0;
  for (std::size_t n = 0; n < N; ++n)
    if (std::abs(comps[n].omega - (w0_ + static_cast<double>(n) * dw_)) > 1e-9 * comps[n].omega)
      throw std::logic_error("SecondOrderPaddle: the components' frequencies are not evenly spaced");
  const Shape s(p);
  std::vector<Modes> ms(N);
  std::vector<cd> X(N);
  for (std::size_t n = 0; n < N; ++n) {
    ms[n] = modes(s, comps[n].omega, J);
    X[n] = -kI * std::polar(comps[n].amplitude, comps[n].phase) / transfer[n];
  }
  // F± of every pair, extrapolated 2 F(J) − F(J/2); rows in parallel, sums in a fixed order
  std::vector<cd> fp(N * N), fm(N * N);
  const long NN = static_cast<long>(N);
#pragma omp parallel for schedule(dynamic, 1)
  for (long n = 0; n < NN; ++n)
    for (std::size_t m = static_cast<std::size_t>(n); m < N; ++m) {
      cd full, half;
      const std::size_t i = static_cast<std::size_t>(n);
      transfer_pair(s, comps[i].omega, ms[i], comps[m].omega, ms[m], +1, J, full, half);
      fp[i * N + m] = J > 1 ? 2.0 * full - half : full;
      if (m > i) {  // the difference ω_m − ω_n > 0
        transfer_pair(s, comps[m].omega, ms[m], comps[i].omega, ms[i], -1, J, full, half);
        fm[i * N + m] = J > 1 ? 2.0 * full - half : full;
      }
    }
  sum_.assign(2 * N - 1, 0.0);
  diff_.assign(N, 0.0);
  for (std::size_t n = 0; n < N; ++n)
    for (std::size_t m = n; m < N; ++m) {
      sum_[n + m] += (m == n ? 0.5 : 1.0) * fp[n * N + m] * X[n] * X[m];
      if (m > n) diff_[m - n] += fm[n * N + m] * X[m] * std::conj(X[n]);
    }
  // the correction's reach over one repeat period (the difference terms' longest, 2π/Δω)
  const double T = N > 1 ? 2.0 * std::numbers::pi / dw_ : std::numbers::pi / w0_;
  for (int q = 0; q < 4096; ++q) excursion_ = std::max(excursion_, std::abs(displacement(T * q / 4096.0)));
}

double SecondOrderPaddle::eval(double tau, const std::vector<cd>& sum, const std::vector<cd>& diff, bool rate) const {
  if (sum.empty()) return 0.0;
  const cd z = std::polar(1.0, dw_ * tau);
  cd zs = 1.0, acc = 0.0;
  for (std::size_t s = 0; s < sum.size(); ++s) {
    const cd t = sum[s] * zs;
    acc += rate ? kI * (2.0 * w0_ + static_cast<double>(s) * dw_) * t : t;
    zs *= z;
  }
  double x = (acc * std::polar(1.0, 2.0 * w0_ * tau)).real();
  cd zd = z, accd = 0.0;
  for (std::size_t d = 1; d < diff.size(); ++d) {
    const cd t = diff[d] * zd;
    accd += rate ? kI * (static_cast<double>(d) * dw_) * t : t;
    zd *= z;
  }
  return x + accd.real();
}

double SecondOrderPaddle::elevation(double tau, double x) const {
  const Coeffs* c = nullptr;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    auto it = bound_.find(x);
    if (it == bound_.end()) {
      const std::size_t N = comps_.size();
      Coeffs b;
      b.sum.assign(N ? 2 * N - 1 : 0, 0.0);
      b.diff.assign(N, 0.0);
      std::vector<cd> a(N);
      for (std::size_t n = 0; n < N; ++n) a[n] = std::polar(comps_[n].amplitude, comps_[n].phase - comps_[n].k * x);
      for (std::size_t n = 0; n < N; ++n)
        for (std::size_t m = n; m < N; ++m) {
          const double wn = comps_[n].omega, wm = comps_[m].omega;
          b.sum[n + m] += (m == n ? 0.5 : 1.0) * bound_elevation(depth_, g_, wn, wm, +1) * a[n] * a[m];
          if (m > n) b.diff[m - n] += bound_elevation(depth_, g_, wm, wn, -1) * a[m] * std::conj(a[n]);
        }
      it = bound_.emplace(x, std::move(b)).first;
    }
    c = &it->second;
  }
  return eval(tau, c->sum, c->diff, false);
}

}  // namespace sph
