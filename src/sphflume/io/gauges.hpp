// Gauges: one CSV per gauge in OUTPUT/gauges/NAME.csv, first column `time`, one row per
// output time. Each type is a class in io/gauge_*.cpp behind GaugeType (io/gauge_type.hpp).
//  water_level       level: highest z on the vertical line where the fluid fraction
//                    Σ V_b W >= 0.5 (linearly interpolated)
//  pressure          pressure: linear-MLS kernel interpolation from fluid particles
//  velocity_profile  ux_i, (uy_i,) uz_i at points i along the line (Shepard average);
//                    the points' coordinates go to NAME.points.csv
//  stress_profile    per point i: ux_i, tau_t_i (modelled turbulent shear stress τ_xz/ρ),
//                    tau_r_i (resolved −⟨u'w'⟩ about the kernel average), nu_t_i [m2/s]
//  depth_profile     depth_i: water level above each point of the line (put it on the bed)
//  boundary_volume   inflow, outflow, backflow: cumulative volumes [m3 (per m in 2D)] of the
//                    particles converted at the open boundaries (mass / rho0)
//  profiles and flux with `average_from: T` also keep NAME.mean.csv: the time mean of the
//  samples from T on (one row, rewritten at every output)
//  front             front: furthest fluid particle along the axis that has at least 3 fluid
//                    neighbours (isolated droplets ignored)
//  energy            kinetic, potential, total: fluid energies [J (per m in 2D)], potential
//                    -Σ m g·x relative to the origin
//  scalar            the transported scalar `field` at a point (Shepard average)
//  scalar_profile    the scalar at points i along the line
//  scalar_mass       mass Σ m C/ρ of the scalar in the fluid (in the box [start, end] when
//                    given), min and max of C there, the mass centroid, and source: the
//                    cumulative mass released by the scalar's wall sources
//  scalar_flux       flux ∫ (C u − D ∇C)·n ds through the line's wet part [kg/s per m] (2D;
//                    D molecular)
//  paddle            displacement, velocity, acceleration of a motion's law, and the water's
//                    pressure force on its walls (force_x, (force_y,) force_z)
//  velocity          ux, (uy,) uz at a point (Shepard average of the fluid)
//  runup             runup: the waterline on the slope line start-end (io/runup.hpp: the highest
//                    fluid particle within `reach` of it in the last stretch, connected to the
//                    toe, where the water is at least `film` thick; particles with fewer than
//                    `neighbours` fluid neighbours within 2 dx ignored) minus `level`; x of that
//                    particle; max: the largest runup so far
//  phase             area (volume in 3D) Σ m/ρ of the phase `field`, its top (highest
//                    particle) and area centroid x, z
#pragma once
#include <deque>
#include <fstream>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "sphflume/core/system.hpp"
#include "sphflume/io/case.hpp"
#include "sphflume/io/gauge_type.hpp"

namespace sph {

template <int D>
class GaugeSet {
 public:
  /// Open the CSV files (truncating) and write their headers. After a restart (resume_after a
  /// time), keep the rows up to that time and append after them instead.
  GaugeSet(const std::vector<GaugeConfig>& gauges, const std::string& dir, double level_top,
           double resume_after = std::numeric_limits<double>::quiet_NaN(), bool writer = true);
  /// Append one row per gauge; S must have an up-to-date cell list.
  void sample(const System<D>& S);
  /// After every step: the samples of the gauges with a time window (pressure sensors).
  void tick(const System<D>& S);
  bool needs_tick() const { return windowed_; }
  /// Evaluate one gauge (also used by tests).
  /// level_top: height from which water-level gauges scan down.
  static std::vector<double> evaluate(const GaugeConfig& g, const System<D>& S, double level_top);

 private:
  void accumulate(std::size_t k, double t, const std::vector<double>& v);
  struct Mean {
    long n = 0;
    double t0 = 0.0, t1 = 0.0;
    std::vector<double> sum;
    std::vector<long> count;
  };
  std::vector<GaugeConfig> cfg_;
  std::vector<std::unique_ptr<GaugeType<D>>> types_;  // each gauge's type (gauge_registry)
  std::vector<std::unique_ptr<std::ofstream>> files_;
  double level_top_;
  std::string dir_;
  std::vector<Mean> means_;
  std::vector<double> runmax_;  // runup gauges: the largest run-up so far (column max)
  std::vector<std::deque<std::pair<double, double>>> window_;  // windowed gauges: (t, value) samples
  bool windowed_ = false;
  bool writer_ = true;  // false: a rank of a distributed run other than the first (computes, writes nothing)
};

}  // namespace sph
