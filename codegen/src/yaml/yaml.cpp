#include "yaml/yaml.hpp"

#include <cstdint>
#include <optional>

namespace regmapgen::yaml {

const Node* Node::find(std::string_view key) const {
  for (std::size_t i = 0; i < keys.size(); ++i) {
    if (keys[i].text == key) return &values[i];
  }
  return nullptr;
}

const char* describe(Node::Type t) {
  switch (t) {
    case Node::Type::Null:
      return "nothing";
    case Node::Type::Scalar:
      return "a scalar";
    case Node::Type::Map:
      return "a mapping";
    case Node::Type::Seq:
      return "a sequence";
  }
  return "?";
}

namespace {

// One non-blank, non-comment physical line.
struct Line {
  int number = 0;           // 1-based
  std::size_t start = 0;    // offset of the line in the file text
  std::size_t content = 0;  // offset of the first non-space character
  std::size_t end = 0;      // offset of the newline (or end of text), '\r' excluded
  int indent = 0;           // leading spaces (after tab repair)
};

bool isSpace(char c) {
  return c == ' ' || c == '\t';
}

class Parser {
 public:
  Parser(const Sources& sources, int file, Diagnostics& diag)
      : text_(sources.text(file)), file_(file), diag_(diag) {}

  Node run() {
    splitLines();
    if (lines_.empty()) return Node{};
    const Line& first = lines_[0];
    if (first.indent != 0)
      error(first, first.content, "bad indentation: the document must start in column 1");
    Node root = parseBlock(first.indent);
    while (pos_ < lines_.size()) {
      error(lines_[pos_], lines_[pos_].content, "bad indentation: this line belongs to no block");
      skipLine();
    }
    return root;
  }

 private:
  Loc locAt(const Line& l, std::size_t offset) const {
    return Loc{file_, l.number, columnOf(text_, l.start, offset)};
  }
  void error(const Line& l, std::size_t offset, std::string msg) {
    diag_.error(locAt(l, offset), std::move(msg));
  }

  // Splits the text into content lines, diagnosing tabs in indentation and document markers.
  void splitLines() {
    // A UTF-8 byte-order mark (some Windows editors add one) is not content.
    std::size_t start = text_.rfind("\xEF\xBB\xBF", 0) == 0 ? 3 : 0;
    int number = 0;
    int lastContentIndent = 0;
    while (start <= text_.size()) {
      ++number;
      std::size_t end = text_.find('\n', start);
      const bool last = end == std::string::npos;
      if (last) end = text_.size();
      std::size_t stop = end;
      if (stop > start && text_[stop - 1] == '\r') --stop;
      if (stop - start > kMaxLineLength) {
        // Reported and then treated as blank: every later step can rely on short lines.
        diag_.error(Loc{file_, number, columnOf(text_, start, start + kMaxLineLength)},
                    "line is " + std::to_string(stop - start) + " bytes long; lines are limited to " +
                        std::to_string(kMaxLineLength) + " bytes");
        if (last) break;
        start = end + 1;
        continue;
      }

      std::size_t p = start;
      bool tab = false;
      std::size_t tabAt = 0;
      while (p < stop && isSpace(text_[p])) {
        if (text_[p] == '\t' && !tab) {
          tab = true;
          tabAt = p;
        }
        ++p;
      }
      const bool blank = p == stop || text_[p] == '#';
      if (!blank) {
        Line l{number, start, p, stop, static_cast<int>(p - start)};
        if (tab) {
          // A tab's width is unknowable; report it and assume the line lines up with the previous content
          // line, which is what the author almost always meant, so parsing can continue.
          error(l, tabAt, "tab in indentation (indent with spaces only)");
          l.indent = lastContentIndent;
        }
        const std::string_view rest(text_.data() + p, stop - p);
        if (l.indent == 0 && (rest.starts_with("---") || rest.starts_with("..."))) {
          error(l, p, "document markers ('---', '...') are not supported: one document per file");
        } else if (l.indent == 0 && rest.starts_with("%")) {
          error(l, p, "directives ('%...') are not supported");
        } else {
          lines_.push_back(l);
          lastContentIndent = contentIndent(l);
        }
      }
      if (last) break;
      start = end + 1;
    }
  }

  // Where the content of a line starts for a child on the same line ("- key: v" -> column of key).
  int contentIndent(const Line& l) const {
    std::size_t p = l.content;
    while (p < l.end && text_[p] == '-' && p + 1 <= l.end && (p + 1 == l.end || text_[p + 1] == ' ')) {
      ++p;
      while (p < l.end && text_[p] == ' ')
        ++p;
    }
    return static_cast<int>(p - l.start);
  }

  bool isSeqItem(const Line& l) const {
    const char c = text_[l.content];
    return c == '-' && (l.content + 1 == l.end || text_[l.content + 1] == ' ');
  }

  void skipLine() { ++pos_; }

  // One level of nesting for the lifetime of the guard.
  struct Nested {
    explicit Nested(int& depth) : depth_(depth) { ++depth_; }
    ~Nested() { --depth_; }
    Nested(const Nested&) = delete;
    Nested& operator=(const Nested&) = delete;
    int& depth_;
  };

  // Reports nesting past kMaxNesting at `offset` of line `l`; the caller skips the subtree. Recursion
  // depth stays bounded however deeply a file nests (issue 15: 10 000 levels overflowed the stack).
  bool tooDeep(const Line& l, std::size_t offset) {
    if (depth_ < kMaxNesting) return false;
    error(l, offset, "nesting deeper than " + std::to_string(kMaxNesting) + " levels");
    return true;
  }

  // Skips every following line indented deeper than `indent` (the children of a line already rejected).
  void skipDeeper(int indent) {
    while (pos_ < lines_.size() && lines_[pos_].indent > indent)
      ++pos_;
  }

  // Reports and skips lines deeper than `indent` that no block can own.
  void rejectDeeper(int indent, const char* why) {
    while (pos_ < lines_.size() && lines_[pos_].indent > indent) {
      const Line& l = lines_[pos_];
      error(l, l.content,
            "bad indentation: expected column " + std::to_string(indent + 1) + " (" + why + ")");
      ++pos_;
      skipDeeper(l.indent);
    }
  }

  Node parseBlock(int indent) {
    const Line& l = lines_[pos_];
    if (isSeqItem(l)) return parseSeq(indent);
    Node map;
    map.type = Node::Type::Map;
    map.loc = locAt(l, l.content);
    if (tooDeep(l, l.content)) {
      while (pos_ < lines_.size() && lines_[pos_].indent >= indent)
        ++pos_;
      return map;
    }
    const Nested nested(depth_);
    parseMapEntries(map, indent);
    return map;
  }

  // Adds `key: value` entries at exactly `indent` to `map`.
  void parseMapEntries(Node& map, int indent) {
    while (pos_ < lines_.size()) {
      const Line& l = lines_[pos_];
      if (l.indent < indent) return;
      if (l.indent > indent) {
        error(l, l.content, "bad indentation: expected column " + std::to_string(indent + 1));
        ++pos_;
        skipDeeper(l.indent);
        continue;
      }
      if (isSeqItem(l)) {
        // "key:\n- item" is read by the key; a dash here sits among a mapping's keys. Let the caller decide
        // (an indentless sequence ends the mapping of the enclosing sequence item at the same column).
        return;
      }
      parseKeyValue(map, l, l.content, indent);
    }
  }

  // Reads "key: value" starting at `offset` of line `l` into `map`; the map's keys sit at `indent`.
  void parseKeyValue(Node& map, const Line& l, std::size_t offset, int indent) {
    const std::optional<std::size_t> colon = findKeyColon(l, offset);
    if (!colon) {
      error(l, offset, "expected 'key: value' here");
      ++pos_;
      skipDeeper(indent);
      return;
    }
    Node key;
    key.type = Node::Type::Scalar;
    key.loc = locAt(l, offset);
    key.text = trimRight(std::string_view(text_.data() + offset, *colon - offset));
    if (const char c = key.text.empty() ? '\0' : key.text[0];
        c == '"' || c == '\'' || c == '[' || c == '{' || c == '?') {
      error(l, offset, "keys must be plain words (quoted, flow and complex keys are not supported)");
    }

    std::size_t v = *colon + 1;
    while (v < l.end && text_[v] == ' ')
      ++v;
    Node value;
    if (v >= l.end || text_[v] == '#') {
      ++pos_;
      if (pos_ < lines_.size() && lines_[pos_].indent > indent) {
        value = parseBlock(lines_[pos_].indent);
      } else if (pos_ < lines_.size() && lines_[pos_].indent == indent && isSeqItem(lines_[pos_])) {
        value = parseSeq(indent);  // indentless sequence: "key:\n- a\n- b"
      } else {
        value.loc = locAt(l, v < l.end ? v : l.end);
      }
    } else {
      value = parseInline(l, v);
      ++pos_;
      rejectDeeper(indent, "the key above already has its value");
    }

    for (const Node& k : map.keys) {
      if (k.text == key.text) {
        diag_.error(key.loc,
                    "duplicate key '" + key.text + "' (first at line " + std::to_string(k.loc.line) + ")");
        return;
      }
    }
    map.keys.push_back(std::move(key));
    map.values.push_back(std::move(value));
  }

  Node parseSeq(int indent) {
    Node seq;
    seq.type = Node::Type::Seq;
    seq.loc = locAt(lines_[pos_], lines_[pos_].content);
    if (tooDeep(lines_[pos_], lines_[pos_].content)) {
      // Skip this sequence's items and everything under them.
      while (pos_ < lines_.size() &&
             (lines_[pos_].indent > indent || (lines_[pos_].indent == indent && isSeqItem(lines_[pos_])))) {
        ++pos_;
      }
      return seq;
    }
    const Nested nested(depth_);
    while (pos_ < lines_.size()) {
      const Line& l = lines_[pos_];
      if (l.indent < indent) break;
      if (l.indent > indent) {
        error(l, l.content, "bad indentation: expected a '- ' item in column " + std::to_string(indent + 1));
        ++pos_;
        skipDeeper(l.indent);
        continue;
      }
      if (!isSeqItem(l)) break;

      std::size_t p = l.content + 1;
      while (p < l.end && text_[p] == ' ')
        ++p;
      const int itemIndent = static_cast<int>(p - l.start);
      Node item;
      if (p >= l.end || text_[p] == '#') {
        ++pos_;
        if (pos_ < lines_.size() && lines_[pos_].indent > indent) {
          item = parseBlock(lines_[pos_].indent);
        } else {
          item.loc = locAt(l, p < l.end ? p : l.end);
        }
      } else if (text_[p] == '-' && (p + 1 == l.end || text_[p + 1] == ' ')) {
        error(l, p, "nested '- - ' items are not supported; put the inner sequence on its own lines");
        ++pos_;
        skipDeeper(indent);
        item.loc = locAt(l, p);
      } else if (startsKey(l, p)) {
        item.type = Node::Type::Map;
        item.loc = locAt(l, p);
        parseKeyValue(item, l, p, itemIndent);
        parseMapEntries(item, itemIndent);
      } else {
        item = parseInline(l, p);
        ++pos_;
        rejectDeeper(indent, "the item above already has its value");
      }
      seq.items.push_back(std::move(item));
    }
    return seq;
  }

  // The offset of the ':' that ends a plain key starting at `offset` (followed by a space, a comment or the
  // end of the line), or nothing.
  std::optional<std::size_t> findKeyColon(const Line& l, std::size_t offset) const {
    const char c = text_[offset];
    if (c == '"' || c == '\'' || c == '[' || c == '{') {
      // Find the closing quote or bracket first so a ':' inside it does not count.
      std::size_t p = offset + 1;
      const char close = c == '[' ? ']' : c == '{' ? '}' : c;
      while (p < l.end && text_[p] != close)
        ++p;
      if (p < l.end && p + 1 < l.end && text_[p + 1] == ':' && (p + 2 == l.end || text_[p + 2] == ' '))
        return p + 1;
      return std::nullopt;
    }
    for (std::size_t p = offset; p < l.end; ++p) {
      if (text_[p] == '#' && p > offset && isSpace(text_[p - 1])) return std::nullopt;
      if (text_[p] == ':' && (p + 1 == l.end || text_[p + 1] == ' ' || text_[p + 1] == '\t')) return p;
    }
    return std::nullopt;
  }

  bool startsKey(const Line& l, std::size_t offset) const {
    const char c = text_[offset];
    if (c == '"' || c == '\'' || c == '[' || c == '{') return false;
    return findKeyColon(l, offset).has_value();
  }

  static std::string trimRight(std::string_view s) {
    while (!s.empty() && isSpace(s.back()))
      s.remove_suffix(1);
    return std::string(s);
  }

  // A value that starts at `offset` and ends on this line.
  Node parseInline(const Line& l, std::size_t offset) {
    const char c = text_[offset];
    auto unsupported = [&](const std::string& msg) {
      error(l, offset, msg);
      Node n;
      n.type = Node::Type::Scalar;
      n.loc = locAt(l, offset);
      n.invalid = true;
      return n;
    };
    switch (c) {
      case '[': {
        std::size_t p = offset;
        flowAbandoned_ = false;
        Node n = parseFlowSeq(l, p);
        expectLineEnd(l, p);
        return n;
      }
      case '"':
      case '\'': {
        std::size_t p = offset;
        Node n = parseQuoted(l, p);
        expectLineEnd(l, p);
        return n;
      }
      case '{':
        return unsupported("flow mappings ('{...}') are not supported; use a block mapping");
      case '|':
      case '>':
        return unsupported("block scalars ('|', '>') are not supported; use a quoted string on one line");
      case '&':
      case '*':
      case '!':
        return unsupported("anchors, aliases and tags ('&', '*', '!') are not supported");
      case '%':
      case '@':
      case '`':
        return unsupported(std::string("'") + c + "' cannot start a plain scalar; quote the value");
      case '-':
        if (offset + 1 == l.end || text_[offset + 1] == ' ') {
          return unsupported("a sequence item cannot follow a key on the same line");
        }
        break;
      default:
        break;
    }
    return parsePlain(l, offset);
  }

  // Plain scalar to the end of the line or a " #" comment.
  Node parsePlain(const Line& l, std::size_t offset) {
    Node n;
    n.type = Node::Type::Scalar;
    n.loc = locAt(l, offset);
    std::size_t p = offset;
    while (p < l.end && !(text_[p] == '#' && p > offset && isSpace(text_[p - 1])))
      ++p;
    n.text = trimRight(std::string_view(text_.data() + offset, p - offset));
    const std::size_t colon = n.text.find(": ");
    if (colon != std::string::npos) {
      error(l, offset + colon, "plain scalar contains ': '; put the value in quotes");
    }
    return n;
  }

  // After a quoted scalar or flow sequence only spaces and a comment may follow.
  void expectLineEnd(const Line& l, std::size_t p) {
    while (p < l.end && isSpace(text_[p]))
      ++p;
    if (p < l.end && text_[p] != '#') error(l, p, "unexpected text after the value");
  }

  static void appendUtf8(std::string& out, std::uint32_t cp) {
    if (cp < 0x80) {
      out += static_cast<char>(cp);
    } else if (cp < 0x800) {
      out += static_cast<char>(0xC0 | (cp >> 6));
      out += static_cast<char>(0x80 | (cp & 0x3F));
    } else if (cp < 0x10000) {
      out += static_cast<char>(0xE0 | (cp >> 12));
      out += static_cast<char>(0x80 | ((cp >> 6) & 0x3F));
      out += static_cast<char>(0x80 | (cp & 0x3F));
    } else {
      out += static_cast<char>(0xF0 | (cp >> 18));
      out += static_cast<char>(0x80 | ((cp >> 12) & 0x3F));
      out += static_cast<char>(0x80 | ((cp >> 6) & 0x3F));
      out += static_cast<char>(0x80 | (cp & 0x3F));
    }
  }

  static int hexValue(char c) {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return -1;
  }

  // A quoted scalar starting at p (on the quote); leaves p after the closing quote. Quoted scalars must close
  // on the same line: an open quote is reported and the rest of the line is taken as the value.
  Node parseQuoted(const Line& l, std::size_t& p) {
    Node n;
    n.type = Node::Type::Scalar;
    n.quoted = true;
    n.loc = locAt(l, p);
    const char q = text_[p];
    const std::size_t open = p;
    ++p;
    while (p < l.end) {
      const char c = text_[p];
      if (q == '\'' && c == '\'') {
        if (p + 1 < l.end && text_[p + 1] == '\'') {
          n.text += '\'';
          p += 2;
          continue;
        }
        ++p;
        return n;
      }
      if (q == '"' && c == '"') {
        ++p;
        return n;
      }
      if (q == '"' && c == '\\' && p + 1 < l.end) {
        const char e = text_[p + 1];
        p += 2;
        switch (e) {
          case '\\':
            n.text += '\\';
            break;
          case '"':
            n.text += '"';
            break;
          case '/':
            n.text += '/';
            break;
          case 'n':
            n.text += '\n';
            break;
          case 't':
            n.text += '\t';
            break;
          case 'r':
            n.text += '\r';
            break;
          case '0':
            n.text += '\0';
            break;
          case 'x':
          case 'u':
          case 'U': {
            const std::size_t digits = e == 'x' ? 2 : e == 'u' ? 4 : 8;
            std::uint32_t cp = 0;
            bool ok = p + digits <= l.end;
            for (std::size_t i = 0; ok && i < digits; ++i) {
              const int h = hexValue(text_[p + i]);
              ok = h >= 0;
              cp = cp * 16 + static_cast<std::uint32_t>(h);
            }
            if (!ok || cp > 0x10FFFF) {
              error(l, p - 2, std::string("bad '\\") + e + "' escape");
            } else {
              appendUtf8(n.text, cp);
              p += digits;
            }
            break;
          }
          default:
            error(l, p - 2, std::string("unknown escape '\\") + e + "'");
            break;
        }
        continue;
      }
      n.text += c;
      ++p;
    }
    error(l, open,
          std::string("unterminated ") + (q == '"' ? "double" : "single") +
              "-quoted string (a quoted scalar must end on the line it starts)");
    return n;
  }

  // A flow sequence starting at p (on '['); leaves p after the closing ']'.
  Node parseFlowSeq(const Line& l, std::size_t& p) {
    Node seq;
    seq.type = Node::Type::Seq;
    seq.loc = locAt(l, p);
    if (tooDeep(l, p)) {
      p = l.end;
      flowAbandoned_ = true;  // the enclosing sequences end here without another message each
      return seq;
    }
    const Nested nested(depth_);
    const std::size_t open = p;
    ++p;
    for (;;) {
      while (p < l.end && isSpace(text_[p]))
        ++p;
      if (p >= l.end || text_[p] == '#') {
        if (!flowAbandoned_)
          error(l, open, "unterminated flow sequence (']' must close it on the same line)");
        p = l.end;
        return seq;
      }
      const char c = text_[p];
      if (c == ']') {
        ++p;
        return seq;
      }
      if (c == ',') {
        error(l, p, "empty item in flow sequence");
        ++p;
        continue;
      }
      Node item;
      if (c == '[') {
        item = parseFlowSeq(l, p);
      } else if (c == '"' || c == '\'') {
        item = parseQuoted(l, p);
      } else if (c == '{') {
        error(l, p, "flow mappings ('{...}') are not supported");
        while (p < l.end && text_[p] != ',' && text_[p] != ']')
          ++p;
        continue;
      } else {
        item.type = Node::Type::Scalar;
        item.loc = locAt(l, p);
        const std::size_t s = p;
        while (p < l.end && text_[p] != ',' && text_[p] != ']' && text_[p] != '[' && text_[p] != '{' &&
               text_[p] != '}' && !(text_[p] == '#' && isSpace(text_[p - 1]))) {
          ++p;
        }
        item.text = trimRight(std::string_view(text_.data() + s, p - s));
      }
      seq.items.push_back(std::move(item));
      while (p < l.end && isSpace(text_[p]))
        ++p;
      if (p < l.end && text_[p] == ',') {
        ++p;
      } else if (p < l.end && text_[p] != ']') {
        error(l, p, "expected ',' or ']' in flow sequence");
        while (p < l.end && text_[p] != ',' && text_[p] != ']')
          ++p;
        if (p < l.end && text_[p] == ',') ++p;
      }
    }
  }

  const std::string& text_;
  int file_;
  Diagnostics& diag_;
  std::vector<Line> lines_;
  std::size_t pos_ = 0;
  int depth_ = 0;               // blocks and flow sequences currently open
  bool flowAbandoned_ = false;  // a flow sequence on this line nested too deeply (already reported)
};

}  // namespace

Node parse(const Sources& sources, int file, Diagnostics& diag) {
  Parser p(sources, file, diag);
  return p.run();
}

}  // namespace regmapgen::yaml
