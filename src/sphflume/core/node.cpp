#include "sphflume/core/node.hpp"

#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <limits>

namespace sph {

const Node& Node::operator[](const std::string& key) const {
  static const Node undefined;
  if (kind_ != Kind::Map) return undefined;
  for (const auto& [k, v] : items_)
    if (k == key) return v;
  return undefined;
}

void Node::add(std::string key, Node child, int key_line) {
  child.key_line_ = key_line;
  items_.emplace_back(std::move(key), std::move(child));
}

bool Node::decode(double& out) const {
  if (!is_scalar() || text_.empty()) return false;
  const std::string& s = text_;
  // YAML's special floats (.inf, -.inf, .nan in their case variants)
  std::string body = s;
  double sign = 1.0;
  if (body[0] == '+' || body[0] == '-') { sign = body[0] == '-' ? -1.0 : 1.0; body = body.substr(1); }
  if (body == ".inf" || body == ".Inf" || body == ".INF") { out = sign * std::numeric_limits<double>::infinity(); return true; }
  if (s == ".nan" || s == ".NaN" || s == ".NAN") { out = std::numeric_limits<double>::quiet_NaN(); return true; }
  // plain decimal numbers only: no hexadecimal floats, no "inf"/"nan" words, no spaces
  for (char c : s)
    if (!(std::isdigit(static_cast<unsigned char>(c)) || c == '.' || c == 'e' || c == 'E' || c == '+' || c == '-'))
      return false;
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(s.c_str(), &end);
  if (end != s.c_str() + s.size() || end == s.c_str()) return false;
  out = v;
  return true;
}

bool Node::decode(int& out) const {
  if (!is_scalar() || text_.empty()) return false;
  const std::string& s = text_;
  for (std::size_t i = 0; i < s.size(); ++i)
    if (!(std::isdigit(static_cast<unsigned char>(s[i])) || (i == 0 && (s[i] == '+' || s[i] == '-')))) return false;
  char* end = nullptr;
  errno = 0;
  const long v = std::strtol(s.c_str(), &end, 10);
  if (end != s.c_str() + s.size() || errno == ERANGE || v < INT_MIN || v > INT_MAX) return false;
  out = static_cast<int>(v);
  return true;
}

bool Node::decode(bool& out) const {
  if (!is_scalar()) return false;
  for (const char* t : {"true", "True", "TRUE", "yes", "Yes", "YES", "on", "On", "ON", "y", "Y"})
    if (text_ == t) { out = true; return true; }
  for (const char* f : {"false", "False", "FALSE", "no", "No", "NO", "off", "Off", "OFF", "n", "N"})
    if (text_ == f) { out = false; return true; }
  return false;
}

}  // namespace sph
