// A strict reader for the YAML subset the register maps use.
//
// Accepted: block mappings and block sequences (a sequence may sit at its key's indentation or deeper), plain
// scalars, single- and double-quoted scalars (closed on the same line), flow sequences `[a, "b", [c]]` on one
// line, and `#` comments. Everything else is an error with a position: tabs in indentation, flow mappings,
// block scalars (| >), anchors, aliases, tags, directives, document markers, multi-line scalars, duplicate
// keys, and lines indented where no block can continue ("bad indentation").
//
// Contract
// - Every node keeps the Loc (file:line:col) of its first character; a map keeps the Loc of each key.
// - The reader never stops at the first problem: it reports into Diagnostics, skips or repairs the offending
//   line and carries on, so one run shows every syntax error (and the checker still sees the rest of the
//   file).
// - Input is bounded, never trusted: a line longer than kMaxLineLength bytes and nesting deeper than
//   kMaxNesting levels (blocks or flow sequences) are errors with a position, and the offending line or
//   subtree is skipped. Parsing time and stack depth are linear in the input and bounded, whatever the file
//   holds.
// - Scalars are returned as text; typing (integers, type codes...) is the model builder's job, so that its
//   errors can say which key expected what.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "diag/diag.hpp"

namespace regmapgen::yaml {

// Limits far above what any register map needs (lines of a few hundred bytes, 5 levels of nesting).
inline constexpr std::size_t kMaxLineLength = 4096;
inline constexpr int kMaxNesting = 32;

struct Node {
  enum class Type { Null, Scalar, Map, Seq };

  Type type = Type::Null;
  Loc loc;
  std::string text;  // Scalar: the value (quotes removed, escapes resolved)
  bool quoted = false;
  bool invalid = false;      // Scalar standing in for unsupported syntax (already reported); treat as absent
  std::vector<Node> keys;    // Map: key scalars, in file order
  std::vector<Node> values;  // Map: the value of keys[i]
  std::vector<Node> items;   // Seq

  bool isNull() const { return type == Type::Null; }
  bool isScalar() const { return type == Type::Scalar; }
  bool isMap() const { return type == Type::Map; }
  bool isSeq() const { return type == Type::Seq; }

  // The value for `key` in a Map, or nullptr.
  const Node* find(std::string_view key) const;
};

// Parses one file (already registered in Sources as `file`). Returns the root (Null for an empty file).
Node parse(const Sources& sources, int file, Diagnostics& diag);

// Human name of a node type for messages ("a mapping", "a sequence", "a scalar", "nothing").
const char* describe(Node::Type t);

}  // namespace regmapgen::yaml
