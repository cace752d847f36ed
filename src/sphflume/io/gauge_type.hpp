// Gauge types (docs/output.md, "Gauges"): each a class behind GaugeType<D>, registered by name in
// gauge_registry() (io/gauge_registry.cpp). A type reads its own keys of the case file, names its
// CSV columns and evaluates one row; GaugeSet (io/gauges.hpp) opens the files, writes the rows,
// keeps windows, running maxima and time means. Families: point gauges (io/gauge_point.cpp), line
// gauges (io/gauge_line.cpp), levels and run-up (io/gauge_level.cpp), sums over the fluid
// (io/gauge_total.cpp). A new gauge type: a class in one of them (or a new file) and one line in
// gauge_registry().
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "sphflume/core/reader.hpp"
#include "sphflume/core/registry.hpp"
#include "sphflume/core/system.hpp"
#include "sphflume/io/case.hpp"

namespace sph {

template <int D>
class GaugeType {
 public:
  virtual ~GaugeType() = default;
  /// Reads the type's own keys into g (name and type are read); InputError with the line.
  virtual void read(Reader& r, GaugeConfig& g, const Node& n, const std::string& path) const = 0;
  /// The CSV header's columns after `time`, each led by a comma.
  virtual std::string columns(const GaugeConfig& g) const = 0;
  /// One row's values (every rank of a distributed run calls it: it holds the reductions).
  /// level_top: the height from which level gauges scan down.
  virtual std::vector<double> evaluate(const GaugeConfig& g, const System<D>& S, double level_top) const = 0;
  /// A line of g.points points, whose coordinates go to NAME.points.csv.
  virtual bool line() const { return false; }
  /// Budgets checked to round-off: written with 17 digits instead of 9.
  virtual bool exact() const { return false; }
  /// Sampled after every step too, its row the window's mean, deviation and count (pressure sensors).
  virtual bool windowed(const GaugeConfig& g) const { (void)g; return false; }
  /// The last column is the running maximum of the first (run-up), kept across restarts.
  virtual bool keeps_max() const { return false; }
};

template <int D>
Registry<GaugeType<D>>& gauge_registry();

/// Reads the keys of a gauge of type g.type for a case of dimension dim (io/case.cpp's read_gauge).
void read_gauge_keys(Reader& r, GaugeConfig& g, const Node& n, const std::string& path, int dim);

}  // namespace sph
