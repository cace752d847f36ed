// The strict reader of a case-file mapping (a Node): every key must be read or it is reported as
// unknown (with the closest known key), and every value is checked with file, line and dotted
// key in the message. Used by the case parser (io/), by each scheme for its `scheme:` options
// and by the force terms for theirs; it needs no YAML.
#pragma once
#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <set>
#include <string>
#include <type_traits>
#include <vector>

#include <fmt/format.h>

#include "sphflume/core/errors.hpp"
#include "sphflume/core/node.hpp"

namespace sph {

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

/// Reads one mapping strictly: every key must be read or is reported as unknown.
class Reader {
 public:
  /// `node` must outlive the reader (it keeps a reference).
  Reader(const Node& node, std::string file, std::string path)
      : node_(node), file_(std::move(file)), path_(std::move(path)) {
    if (!node_.is_map()) fail_at(node_, path_.empty() ? "the document" : path_, "a mapping (key: value lines)");
  }

  Reader(Node&&, std::string, std::string) = delete;

  [[noreturn]] void fail_at(const Node& n, const std::string& key, const std::string& expected) const {
    throw InputError(fmt::format("{}: {}: '{}': expected {}", file_, where(n), key, expected));
  }
  static std::string where(const Node& n) {
    if (n.line() <= 0) return "(value given with --set)";
    return fmt::format("line {}", n.line());
  }
  std::string key_path(const std::string& k) const { return path_.empty() ? k : path_ + "." + k; }
  const std::string& file() const { return file_; }

  bool has(const std::string& k) { seen_.insert(k); return node_[k].given(); }
  const Node& get(const std::string& k) { seen_.insert(k); return node_[k]; }

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
  T as(const Node& n, const std::string& k) const {
    T v{};
    if (!n.decode(v)) {
      if constexpr (std::is_same_v<T, double>) fail_at(n, key_path(k), "a number");
      else if constexpr (std::is_same_v<T, int>) fail_at(n, key_path(k), "an integer");
      else if constexpr (std::is_same_v<T, bool>) fail_at(n, key_path(k), "true or false");
      else fail_at(n, key_path(k), "a text value");
    }
    if constexpr (std::is_same_v<T, double>)
      if (!std::isfinite(v)) fail_at(n, key_path(k), fmt::format("a finite number (got {})", n.text()));
    return v;
  }
  std::vector<double> vec(const std::string& k, std::size_t n_expected, std::vector<double> def = {}) {
    if (!has(k)) return def;
    const Node& v = node_[k];
    const std::string what = fmt::format("a list of {} numbers, e.g. [{}]", n_expected, n_expected == 2 ? "0.0, 1.0" : "0.0, 0.0, 1.0");
    if (!v.is_sequence() || v.size() != n_expected) fail_at(v, key_path(k), what);
    std::vector<double> out;
    for (const auto& [unused, e] : v.entries()) {
      double x = 0.0;
      if (!e.decode(x)) fail_at(e, key_path(k), what);
      if (!std::isfinite(x)) fail_at(e, key_path(k), fmt::format("finite numbers (got {})", e.text()));
      out.push_back(x);
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
    return choice(k, def, std::vector<std::string>(options.begin(), options.end()));
  }
  /// One of a list known at run time (a registry's names).
  std::string choice(const std::string& k, const std::string& def, const std::vector<std::string>& options) {
    const std::string v = scalar<std::string>(k, def);
    std::string list;
    for (const auto& o : options) {
      if (v == o) return v;
      list += (list.empty() ? "" : ", ") + o;
    }
    fail_at(node_[k], key_path(k), "one of " + list + " (got '" + v + "')");
  }

  /// Report keys that were never read, with the closest known key.
  void finish() {
    for (const auto& [k, v] : node_.entries()) {
      if (seen_.count(k)) continue;
      std::string best;
      std::size_t bd = 1000;
      for (const auto& s : seen_) {
        const std::size_t d = edit_distance(k, s);
        if (d < bd) { bd = d; best = s; }
      }
      unknown(v.key_line(), k, close(bd, k) ? best : "", false);
    }
  }
  /// All keys valid here, read or not (so that misspelt() does not take a valid key that is
  /// read later for a misspelling).
  void valid(std::initializer_list<const char*> keys) { for (const char* k : keys) valid_.insert(k); }
  /// Before reporting `k` as missing: a key that is neither read nor valid here and is close
  /// to `k` is a misspelling of it; report that instead ("did you mean").
  void misspelt(const std::string& k) {
    for (const auto& [u, v] : node_.entries()) {
      if (u == k || seen_.count(u) || valid_.count(u)) continue;
      if (close(edit_distance(u, k), u)) unknown(v.key_line(), u, k, true);
    }
  }

 private:
  static bool close(std::size_t distance, const std::string& k) { return distance <= std::max<std::size_t>(2, k.size() / 3); }
  /// `with_valid`: list the valid keys not read yet too (before the reading is done).
  [[noreturn]] void unknown(int key_line, const std::string& k, const std::string& suggestion, bool with_valid) const {
    std::set<std::string> all = seen_;
    if (with_valid) all.insert(valid_.begin(), valid_.end());
    std::string known;
    for (const auto& s : all) known += (known.empty() ? "" : ", ") + s;
    throw InputError(fmt::format("{}: {}: unknown key '{}'{}; known keys here: {}", file_,
                                 key_line > 0 ? fmt::format("line {}", key_line) : "(value given with --set)", key_path(k),
                                 suggestion.empty() ? "" : fmt::format(" (did you mean '{}'?)", key_path(suggestion)),
                                 known));
  }

  const Node& node_;
  std::string file_, path_;
  std::set<std::string> seen_, valid_;
};

}  // namespace sph
