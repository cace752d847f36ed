// The strict YAML reader behind the case file: every key must be read or it is reported as
// unknown (with the closest known key), and every value is checked with file, line and dotted
// key in the message. Internal to the case parser (io/case*.cpp).
#pragma once
#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <set>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include "sphflume/io/case.hpp"

namespace sph::caseio {

inline std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> prev(b.size() + 1), cur(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) prev[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    cur[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j)
      cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1)});
    std::swap(prev, cur);
  }
  return prev[b.size()];
}

/// Reads one YAML mapping strictly: every key must be read or is reported as unknown.
class Reader {
 public:
  Reader(const YAML::Node& node, std::string file, std::string path)
      : node_(node), file_(std::move(file)), path_(std::move(path)) {
    if (!node_.IsMap()) fail_at(node_, path_.empty() ? "the document" : path_, "a mapping (key: value lines)");
  }

  [[noreturn]] void fail_at(const YAML::Node& n, const std::string& key, const std::string& expected) const {
    throw InputError(fmt::format("{}: {}: '{}': expected {}", file_, where(n), key, expected));
  }
  std::string where(const YAML::Node& n) const {
    const auto m = n.Mark();
    if (m.line < 0 || n.Tag() == "!set") return "(value given with --set)";
    return fmt::format("line {}", m.line + 1);
  }
  std::string key_path(const std::string& k) const { return path_.empty() ? k : path_ + "." + k; }
  const std::string& file() const { return file_; }

  bool has(const std::string& k) { seen_.insert(k); return node_[k].IsDefined() && !node_[k].IsNull(); }
  YAML::Node get(const std::string& k) { seen_.insert(k); return node_[k]; }

  template <class T>
  T scalar(const std::string& k, T def) {
    if (!has(k)) return def;
    return as<T>(node_[k], k);
  }
  template <class T>
  T required(const std::string& k, const std::string& expected) {
    if (!has(k)) misspelt(k);
    if (!has(k))
      throw InputError(fmt::format("{}: {}: missing required key '{}': expected {}", file_, where(node_), key_path(k),
                                   expected));
    return as<T>(node_[k], k);
  }
  template <class T>
  T as(const YAML::Node& n, const std::string& k) {
    try {
      if (!n.IsScalar()) throw YAML::Exception(n.Mark(), "not a scalar");
      const T v = n.as<T>();
      if constexpr (std::is_same_v<T, double>)
        if (!std::isfinite(v)) fail_at(n, key_path(k), fmt::format("a finite number (got {})", n.Scalar()));
      return v;
    } catch (const YAML::Exception&) {
      if constexpr (std::is_same_v<T, double>) fail_at(n, key_path(k), "a number");
      else if constexpr (std::is_same_v<T, int>) fail_at(n, key_path(k), "an integer");
      else if constexpr (std::is_same_v<T, bool>) fail_at(n, key_path(k), "true or false");
      else fail_at(n, key_path(k), "a text value");
    }
  }
  std::vector<double> vec(const std::string& k, std::size_t n_expected, std::vector<double> def = {}) {
    if (!has(k)) return def;
    const YAML::Node v = node_[k];
    const std::string what = fmt::format("a list of {} numbers, e.g. [{}]", n_expected, n_expected == 2 ? "0.0, 1.0" : "0.0, 0.0, 1.0");
    if (!v.IsSequence() || v.size() != n_expected) fail_at(v, key_path(k), what);
    std::vector<double> out;
    for (const auto& e : v) {
      try { out.push_back(e.as<double>()); } catch (const YAML::Exception&) { fail_at(e, key_path(k), what); }
      if (!std::isfinite(out.back())) fail_at(e, key_path(k), fmt::format("finite numbers (got {})", e.Scalar()));
    }
    return out;
  }
  double positive(const std::string& k, double def, bool required_key = false) {
    const double v = required_key ? required<double>(k, "a positive number") : scalar<double>(k, def);
    if (!(v > 0.0) || !std::isfinite(v)) fail_at(node_[k], key_path(k), fmt::format("a positive number (got {})", v));
    return v;
  }
  double in_range(const std::string& k, double def, double lo, double hi) {
    const double v = scalar<double>(k, def);
    if (!(v >= lo && v <= hi)) fail_at(node_[k], key_path(k), fmt::format("a number in [{}, {}] (got {})", lo, hi, v));
    return v;
  }
  std::string choice(const std::string& k, const std::string& def, std::initializer_list<const char*> options) {
    const std::string v = scalar<std::string>(k, def);
    std::string list;
    for (const char* o : options) {
      if (v == o) return v;
      list += (list.empty() ? "" : ", ") + std::string(o);
    }
    fail_at(node_[k], key_path(k), "one of " + list + " (got '" + v + "')");
  }

  /// Report keys that were never read, with the closest known key.
  void finish() {
    for (const auto& kv : node_) {
      if (!kv.first.IsScalar()) fail_at(kv.first, path_.empty() ? "the document" : path_, "keys that are plain names (found a list or mapping used as a key)");
      const std::string k = kv.first.Scalar();
      if (seen_.count(k)) continue;
      std::string best;
      std::size_t bd = 1000;
      for (const auto& s : seen_) {
        const std::size_t d = edit_distance(k, s);
        if (d < bd) { bd = d; best = s; }
      }
      unknown(kv.first, k, close(bd, k) ? best : "", false);
    }
  }
  /// All keys valid here, read or not (so that misspelt() does not take a valid key that is
  /// read later for a misspelling).
  void valid(std::initializer_list<const char*> keys) { for (const char* k : keys) valid_.insert(k); }
  /// Before reporting `k` as missing: a key that is neither read nor valid here and is close
  /// to `k` is a misspelling of it; report that instead ("did you mean").
  void misspelt(const std::string& k) {
    for (const auto& kv : node_) {
      if (!kv.first.IsScalar()) continue;
      const std::string u = kv.first.Scalar();
      if (u == k || seen_.count(u) || valid_.count(u)) continue;
      if (close(edit_distance(u, k), u)) unknown(kv.first, u, k, true);
    }
  }

 private:
  static bool close(std::size_t distance, const std::string& k) { return distance <= std::max<std::size_t>(2, k.size() / 3); }
  /// `with_valid`: list the valid keys not read yet too (before the reading is done).
  [[noreturn]] void unknown(const YAML::Node& key, const std::string& k, const std::string& suggestion, bool with_valid) const {
    std::set<std::string> all = seen_;
    if (with_valid) all.insert(valid_.begin(), valid_.end());
    std::string known;
    for (const auto& s : all) known += (known.empty() ? "" : ", ") + s;
    throw InputError(fmt::format("{}: {}: unknown key '{}'{}; known keys here: {}", file_, where(key), key_path(k),
                                 suggestion.empty() ? "" : fmt::format(" (did you mean '{}'?)", key_path(suggestion)),
                                 known));
  }

  YAML::Node node_;
  std::string file_, path_;
  std::set<std::string> seen_, valid_;
};

/// [x, z] vertices of a polygon under the key `vertices`.
inline std::vector<std::array<double, 2>> read_vertices(Reader& r, const YAML::Node& n) {
  if (!r.has("vertices")) r.misspelt("vertices");
  const YAML::Node v = r.get("vertices");
  if (!v.IsSequence() || v.size() < 3) r.fail_at(v.IsDefined() ? v : n, r.key_path("vertices"), "a list of at least 3 [x, z] points");
  std::vector<std::array<double, 2>> out;
  for (const auto& p : v) {
    if (!p.IsSequence() || p.size() != 2) r.fail_at(p, r.key_path("vertices"), "[x, z] pairs");
    try { out.push_back({p[0].as<double>(), p[1].as<double>()}); } catch (const YAML::Exception&) {
      r.fail_at(p, r.key_path("vertices"), "[x, z] pairs of numbers");
    }
    if (!std::isfinite(out.back()[0]) || !std::isfinite(out.back()[1]))
      r.fail_at(p, r.key_path("vertices"), "[x, z] pairs of finite numbers");
  }
  return out;
}

/// A region (RegionConfig) from the keys shape (box | circle | polygon), min/max, center/radius
/// or vertices of the mapping `r` reads.
RegionConfig read_region(Reader& r, const YAML::Node& n, int dim);
/// The `transport:` section (scalars) and the `multiphase:` section.
void read_transport(const YAML::Node& n, const std::string& file, Case& c);
void read_multiphase(const YAML::Node& n, const std::string& file, Case& c);

}  // namespace sph::caseio
