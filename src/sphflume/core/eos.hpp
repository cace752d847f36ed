// Equations of state of weakly-compressible SPH.
//  Tait (Federico 3.14): p = B[(rho/rho0)^gamma - 1], B = c0^2 rho0 / gamma.
//  Linear (Kazemi 3.11): p = c0^2 (rho - rho0).
#pragma once
#include <cmath>

namespace sph {

enum class EosType { Tait, Linear };

struct Eos {
  EosType type = EosType::Tait;
  double rho0 = 1000.0;
  double c0 = 20.0;
  double gamma = 7.0;
  double background = 0.0;  // background pressure added to p (0 for free-surface flows)

  double B() const { return c0 * c0 * rho0 / gamma; }

  double pressure(double rho) const {
    if (type == EosType::Linear) return c0 * c0 * (rho - rho0) + background;
    const double r = rho / rho0;
    // gamma = 7 is by far the common case: avoid std::pow in the hot path
    const double rg = (gamma == 7.0) ? r * r * r * r * r * r * r : std::pow(r, gamma);
    return B() * (rg - 1.0) + background;
  }
  /// Inverse: the density that gives pressure p.
  double density(double p) const {
    const double q = p - background;
    if (type == EosType::Linear) return rho0 + q / (c0 * c0);
    const double base = 1.0 + q / B();
    const double e = base - 1.0;
    if (gamma == 7.0 && std::abs(e) < 0.1) {  // the dummy walls' hot path (issue 60): no std::pow
      // (1 + e)^(1/7): its Taylor series to e^4 (the first term left out, 0.021 e^5, is below 2.1e-7 here), then one
      // Halley step on y^7 = base, y <- y (3 y^7 + 4 base) / (4 y^7 + 3 base), which cubes the relative error: round-off
      double y = 1.0 + e * (1.0 / 7.0 + e * (-3.0 / 49.0 + e * (13.0 / 343.0 + e * (-65.0 / 2401.0))));
      const double y2 = y * y, y7 = y2 * y2 * y2 * y;
      y *= (3.0 * y7 + 4.0 * base) / (4.0 * y7 + 3.0 * base);
      return rho0 * y;
    }
    return rho0 * std::pow(base > 1e-6 ? base : 1e-6, 1.0 / gamma);
  }
  /// Local sound speed c(rho).
  double sound_speed(double rho) const {
    if (type == EosType::Linear) return c0;
    const double r = rho / rho0;
    if (gamma == 7.0) return c0 * r * r * r;
    return c0 * std::pow(r, 0.5 * (gamma - 1.0));
  }
};

}  // namespace sph
