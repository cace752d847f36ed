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
