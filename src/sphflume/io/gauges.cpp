#include "sphflume/io/gauges.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <limits>

#include <fmt/format.h>

#include "sphflume/io/snapshot.hpp"

namespace sph {

template <int D>
GaugeSet<D>::GaugeSet(const std::vector<GaugeConfig>& gauges, const std::string& dir, double level_top,
                      double resume_after, bool writer)
    : cfg_(gauges), level_top_(level_top), dir_(dir), means_(gauges.size()),
      runmax_(gauges.size(), -std::numeric_limits<double>::infinity()), window_(gauges.size()), writer_(writer) {
  for (const auto& g : gauges) {
    types_.push_back(gauge_registry<D>().create(g.type));
    windowed_ |= types_.back()->windowed(g);
  }
  if (gauges.empty() || !writer) return;
  std::filesystem::create_directories(dir + "/gauges");
  for (const auto& g : gauges) {
    const std::string path = dir + "/gauges/" + g.name + ".csv";
    if (std::isfinite(resume_after)) {  // restart: keep the header and the rows up to the restart time (rows are printed to 9 digits)
      std::ifstream in(path);
      if (!in) throw IoError(fmt::format("restart: gauge file '{}' is missing (restart into the run's own output folder)", path));
      std::string kept, line;
      bool header = true;
      while (std::getline(in, line)) {
        if (header || std::strtod(line.c_str(), nullptr) <= resume_after * (1.0 + 1e-8)) {
          kept += line + "\n";
          // a run-up gauge's running maximum goes on from the kept rows' last one
          if (!header && types_[static_cast<std::size_t>(&g - gauges.data())]->keeps_max()) {
            const auto comma = line.rfind(',');
            const double mx = std::strtod(line.c_str() + comma + 1, nullptr);
            if (std::isfinite(mx)) runmax_[static_cast<std::size_t>(&g - gauges.data())] = mx;
          }
        }
        header = false;
      }
      write_file_atomically(path, kept);
      auto f = std::make_unique<std::ofstream>(path, std::ios::app);
      if (!*f) throw IoError(fmt::format("cannot write gauge file '{}'", path));
      files_.push_back(std::move(f));
      continue;
    }
    auto f = std::make_unique<std::ofstream>(path, std::ios::trunc);
    if (!*f) throw IoError(fmt::format("cannot write gauge file '{}'", path));
    const GaugeType<D>& type = *types_[static_cast<std::size_t>(&g - gauges.data())];
    *f << "time" << type.columns(g);
    if (type.line()) {  // the points' coordinates
      std::string pts = "index,x,y,z\n";
      for (int i = 0; i < g.points; ++i) {
        const double s = static_cast<double>(i) / (g.points - 1);
        double c[3] = {0, 0, 0};
        for (int d = 0; d < D; ++d) c[d == D - 1 ? 2 : d] = g.start[d] + s * (g.end[d] - g.start[d]);
        pts += fmt::format("{},{:.9g},{:.9g},{:.9g}\n", i, c[0], c[1], c[2]);
      }
      write_file_atomically(dir + "/gauges/" + g.name + ".points.csv", pts);
    }
    *f << "\n";
    files_.push_back(std::move(f));
  }
}

template <int D>
std::vector<double> GaugeSet<D>::evaluate(const GaugeConfig& g, const System<D>& S, double level_top) {
  return gauge_registry<D>().create(g.type)->evaluate(g, S, level_top);
}

template <int D>
void GaugeSet<D>::sample(const System<D>& S) {
  double top = level_top_;
  for (std::size_t i = 0; i < S.particles.n_owned(); ++i) top = std::max(top, S.particles.pos[i][D - 1] + S.support);
  top = S.comm->max(top);
  for (std::size_t k = 0; k < cfg_.size(); ++k) {
    const GaugeType<D>& type = *types_[k];
    auto v = type.evaluate(cfg_[k], S, top);  // (every rank: the reductions; one writes)
    if (!writer_) continue;
    auto& f = *files_[k];
    f << fmt::format("{:.9g}", S.time);
    if (type.windowed(cfg_[k])) {
      // the window's mean and standard deviation (the samples of tick(), this one included)
      auto& w = window_[k];
      if (w.empty() || w.back().first < S.time) w.emplace_back(S.time, v[0]);
      double m = 0.0, m2 = 0.0;
      long cnt = 0;
      for (const auto& [t, x] : w)
        if (std::isfinite(x)) { m += x; m2 += x * x; ++cnt; }
      m = cnt ? m / cnt : std::numeric_limits<double>::quiet_NaN();
      const double var = cnt > 1 ? std::max(0.0, m2 / cnt - m * m) : 0.0;
      v = {m, std::sqrt(var), double(cnt)};
    }
    if (type.keeps_max()) {
      if (std::isfinite(v[0])) runmax_[k] = std::max(runmax_[k], v[0]);
      v[2] = std::isfinite(runmax_[k]) ? runmax_[k] : std::numeric_limits<double>::quiet_NaN();
    }
    // budgets (scalar and water masses) are checked to round-off: full precision for them
    const bool exact = type.exact();
    for (double x : v) f << (exact ? fmt::format(",{:.17g}", x) : fmt::format(",{:.9g}", x));
    f << "\n";
    f.flush();
    if (!f) throw IoError(fmt::format("writing gauge '{}' failed (disk full?)", cfg_[k].name));
    if (S.time >= cfg_[k].average_from * (1.0 - 1e-12)) accumulate(k, S.time, v);
  }
}

template <int D>
void GaugeSet<D>::tick(const System<D>& S) {
  for (std::size_t k = 0; k < cfg_.size(); ++k) {
    const auto& g = cfg_[k];
    if (!types_[k]->windowed(g)) continue;
    auto& w = window_[k];
    w.emplace_back(S.time, types_[k]->evaluate(g, S, level_top_)[0]);
    while (!w.empty() && w.front().first <= S.time - g.window * (1.0 + 1e-12)) w.pop_front();
  }
}

template <int D>
void GaugeSet<D>::accumulate(std::size_t k, double t, const std::vector<double>& v) {
  // running time mean of a profile gauge over its samples at t >= average_from (NaN samples,
  // e.g. a dry point, are left out of that column's mean), rewritten as NAME.mean.csv
  auto& m = means_[k];
  if (m.n == 0) {
    m.t0 = t;
    m.sum.assign(v.size(), 0.0);
    m.count.assign(v.size(), 0);
  }
  ++m.n;
  m.t1 = t;
  for (std::size_t i = 0; i < v.size(); ++i)
    if (std::isfinite(v[i])) { m.sum[i] += v[i]; ++m.count[i]; }
  std::string text = "t_from,t_to,samples";
  std::ifstream hdr(dir_ + "/gauges/" + cfg_[k].name + ".csv");
  std::string header;
  std::getline(hdr, header);
  text += header.substr(header.find(',') == std::string::npos ? header.size() : header.find(','));
  text += fmt::format("\n{:.9g},{:.9g},{}", m.t0, m.t1, m.n);
  for (std::size_t i = 0; i < v.size(); ++i)
    text += m.count[i] ? fmt::format(",{:.9g}", m.sum[i] / m.count[i]) : std::string(",nan");
  write_file_atomically(dir_ + "/gauges/" + cfg_[k].name + ".mean.csv", text + "\n");
}

template class GaugeSet<2>;
template class GaugeSet<3>;

}  // namespace sph
