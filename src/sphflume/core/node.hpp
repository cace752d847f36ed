// A parsed case-file tree without a YAML dependency: what physics, boundaries and schemes read
// their options from. io/ builds it from the YAML document (io/case.cpp, to_node); everything else
// sees only this. Each node keeps the line it came from (0 = a value given with --set) so that
// messages can name it. Scalars keep their text and are decoded on request, with the rules of
// YAML 1.2's core schema for numbers and booleans.
#pragma once
#include <cstddef>
#include <string>
#include <utility>
#include <vector>

namespace sph {

class Node {
 public:
  enum class Kind { Undefined, Null, Scalar, Map, Sequence };
  using Entry = std::pair<std::string, Node>;

  Node() = default;
  static Node null(int line) { Node n; n.kind_ = Kind::Null; n.line_ = line; return n; }
  static Node scalar(std::string text, int line) {
    Node n; n.kind_ = Kind::Scalar; n.text_ = std::move(text); n.line_ = line; return n;
  }
  static Node map(int line) { Node n; n.kind_ = Kind::Map; n.line_ = line; return n; }
  static Node sequence(int line) { Node n; n.kind_ = Kind::Sequence; n.line_ = line; return n; }

  Kind kind() const { return kind_; }
  bool defined() const { return kind_ != Kind::Undefined; }
  bool is_null() const { return kind_ == Kind::Null; }
  bool is_scalar() const { return kind_ == Kind::Scalar; }
  bool is_map() const { return kind_ == Kind::Map; }
  bool is_sequence() const { return kind_ == Kind::Sequence; }
  /// Defined and not null (a key given a value).
  bool given() const { return defined() && !is_null(); }

  /// 1-based line in the case file; 0 for a value given with --set (or built in code).
  int line() const { return line_; }
  /// The line of this node's key in its parent mapping (its own line if it has none).
  int key_line() const { return key_line_ > 0 ? key_line_ : line_; }
  const std::string& text() const { return text_; }

  /// Map lookup: the child under `key`, or an undefined node.
  const Node& operator[](const std::string& key) const;
  /// Sequence element.
  const Node& operator[](std::size_t i) const { return items_[i].second; }
  /// Elements of a sequence, entries of a map (empty for scalars).
  std::size_t size() const { return items_.size(); }
  const std::vector<Entry>& entries() const { return items_; }

  /// Building (io/ only).
  void add(std::string key, Node child, int key_line);
  void push_back(Node child) { items_.emplace_back(std::string(), std::move(child)); }

  /// Decoding a scalar: false when the text is not a value of that type.
  bool decode(double& out) const;
  bool decode(int& out) const;
  bool decode(bool& out) const;
  bool decode(std::string& out) const { if (!is_scalar()) return false; out = text_; return true; }

 private:
  Kind kind_ = Kind::Undefined;
  std::string text_;
  int line_ = 0, key_line_ = 0;
  std::vector<Entry> items_;  // map: (key, value); sequence: ("", value)
};

}  // namespace sph
