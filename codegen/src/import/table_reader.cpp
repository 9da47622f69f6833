#include "import/table_reader.hpp"

#include <algorithm>
#include <optional>
#include <string_view>

#include "diag/diag.hpp"
#include "import/furniture.hpp"
#include "text/scan.hpp"

namespace regmapgen {

namespace {

// A line as code points: pdftotext -layout aligns columns by character, so positions count code points
// ("–32767" and "0.1°C" are as wide as they look).
class Glyphs {
 public:
  explicit Glyphs(std::string_view s) : text_(s) {
    for (std::size_t i = 0; i < s.size(); ++i) {
      if ((static_cast<unsigned char>(s[i]) & 0xC0) != 0x80) at_.push_back(i);
    }
    at_.push_back(s.size());
  }
  std::size_t size() const { return at_.size() - 1; }
  bool blank(std::size_t i) const { return i >= size() || text_[at_[i]] == ' '; }
  std::string_view slice(std::size_t from, std::size_t to) const {
    from = std::min(from, size());
    to = std::clamp(to, from, size());
    return text_.substr(at_[from], at_[to] - at_[from]);
  }
  // The code point that byte `offset` belongs to.
  std::size_t pointAt(std::size_t offset) const {
    return static_cast<std::size_t>(std::upper_bound(at_.begin(), at_.end(), offset) - at_.begin()) - 1;
  }
  std::size_t byteOf(std::size_t point) const { return at_[std::min(point, size())]; }

 private:
  std::string_view text_;
  std::vector<std::size_t> at_;  // byte offset of each code point, then the end
};

struct Span {
  std::size_t from = 0, to = 0;  // code points [from, to)
  bool empty() const { return from >= to; }
};

// Runs of text separated by two or more spaces.
std::vector<Span> chunks(const Glyphs& g) {
  std::vector<Span> out;
  const std::size_t n = g.size();
  std::size_t i = 0;
  while (i < n) {
    while (i < n && g.blank(i))
      ++i;
    if (i >= n) break;
    std::size_t j = i;
    while (j < n && !(g.blank(j) && g.blank(j + 1)))
      ++j;
    std::size_t end = j;
    while (end > i && g.blank(end - 1))
      --end;
    out.push_back({i, end});
    i = j;
  }
  return out;
}

// `s` without blanks at either end.
Span trimmedSpan(const Glyphs& g, Span s) {
  while (s.from < s.to && g.blank(s.from))
    ++s.from;
  while (s.to > s.from && g.blank(s.to - 1))
    --s.to;
  return s;
}

// Joins a wrapped fragment to the text above it: "Proto-" + "col" -> "Protocol", "SEND_" + "SHUTDOWN" ->
// "SEND_SHUTDOWN", "NO_ADJ" + "_CB" -> "NO_ADJ_CB", "Big-" + "Endian" -> "Big-Endian", anything else with a
// space ("50.6" + "mV").
void appendWrapped(std::string& to, std::string_view more) {
  if (more.empty()) return;
  if (to.empty()) {
    to = more;
    return;
  }
  const char last = to.back();
  if (last == '-' && to.size() >= 2 && scan::isLower(to[to.size() - 2]) && scan::isLower(more[0])) {
    to.pop_back();
  } else if (last != '-' && last != '_' && last != '/' && more[0] != '_' && !more.starts_with("()")) {
    to += ' ';
  }
  to += more;
}

// Capitals, digits and '_' only: part of an identifier-style TRM name (FW_VERSION, MANUFACTURINGSTATUS).
bool identifierPart(std::string_view s) {
  return scan::all(s, [](char c) { return scan::isUpper(c) || scan::isDigit(c) || c == '_'; });
}

// "PermanentFailureData" over "Reset", "OutputShortedCCand" over "ADCforCalibration": a function name of
// the BQ4050 TRM (one CamelCase word) broken where its cell ends.
bool camelJoin(std::string_view above, std::string_view more) {
  if (above.empty() || more.empty() || above.find(' ') != std::string_view::npos ||
      more.find(' ') != std::string_view::npos || !scan::isUpper(more[0]) || !scan::isAlpha(above.back()))
    return false;
  const auto uppers = std::count_if(above.begin(), above.end(), [](char c) { return scan::isUpper(c); });
  const bool lower = std::any_of(above.begin(), above.end(), [](char c) { return scan::isLower(c); });
  return uppers >= 2 && lower;
}

bool isNameRole(Role r) {
  return r == Role::Name || r == Role::EnglishName;
}

struct Column {
  Span span;
  std::string text;
  Role role = Role::Unknown;
  int line = 0;
};

std::vector<Role> rolesOf(const std::vector<Column>& cols) {
  std::vector<Role> roles;
  for (const Column& c : cols)
    roles.push_back(c.role);
  return roles;
}

// The heading cells of a layout line; a chunk of several known headings becomes one column each.
std::vector<Column> headingColumns(const Glyphs& g, int line) {
  std::vector<Column> cols;
  if (!mayBeHeading(g.slice(0, g.size()))) return cols;
  for (const Span c : chunks(g)) {
    const std::string_view t = g.slice(c.from, c.to);
    const Role r = roleOf(t);
    const auto parts = r == Role::Unknown ? splitHeadings(t) : decltype(splitHeadings(t)){};
    if (parts.empty()) {
      cols.push_back({c, std::string(t), r, line});
      continue;
    }
    const std::size_t base = g.byteOf(c.from);
    for (const auto& [a, b] : parts) {
      const std::string_view part = t.substr(a, b - a);
      cols.push_back(
          {{g.pointAt(base + a), g.pointAt(base + b - 1) + 1}, std::string(part), roleOf(part), line});
    }
  }
  return cols;
}

// Adds the chunks of a heading's second line to the columns they sit under ("Min" over "Value"), or as
// columns of their own ("Bit7" ... "Bit0" under "Data"). Returns false if a chunk is neither under a column
// nor a known heading, unless `anyColumns`.
bool mergeHeadingLine(std::vector<Column>& cols, const Glyphs& g, int line, bool anyColumns = false) {
  for (const Span c : chunks(g)) {
    const std::string_view t = g.slice(c.from, c.to);
    auto under = std::find_if(cols.begin(), cols.end(), [&](const Column& col) {
      return c.from <= col.span.to && col.span.from <= c.to;
    });
    if (under == cols.end()) {
      if (roleOf(t) == Role::Unknown && !anyColumns) return false;
      const auto at =
          std::find_if(cols.begin(), cols.end(), [&](const Column& col) { return col.span.from > c.from; });
      cols.insert(at, Column{c, std::string(t), roleOf(t), line});
      continue;
    }
    std::string merged = under->text;
    appendWrapped(merged, t);
    if (const Role r = roleOf(merged); r != Role::Unknown) under->role = r;
    under->text = merged;
    under->span = {std::min(under->span.from, c.from), std::max(under->span.to, c.to)};
  }
  return true;
}

// Cuts a line into one span per column at `bounds` (bound k separates column k from column k + 1). A word
// across a bound is cut at the blank before it (within three positions), else the blank after it, or else not
// at all (it belongs to the column it starts in).
std::vector<Span> slice(const Glyphs& g, const std::vector<std::size_t>& bounds) {
  std::vector<Span> out;
  std::size_t from = 0;
  for (std::size_t k = 0; k <= bounds.size(); ++k) {
    std::size_t to = k < bounds.size() ? bounds[k] : std::max(g.size(), from);
    if (k < bounds.size() && to > 0 && !g.blank(to - 1) && !g.blank(to)) {
      // Before the word first: text starts left of its heading (rounding, centred headings), while a cell
      // never runs into the next column of a real table.
      bool cut = false;
      for (std::size_t d = 1; d <= 3 && !cut; ++d) {
        if (to >= d && g.blank(to - d)) {
          to -= d;
          cut = true;
        }
      }
      for (std::size_t d = 1; d <= 3 && !cut; ++d) {
        if (to + d < g.size() && g.blank(to + d)) {
          to += d;
          cut = true;
        }
      }
      while (!cut && to < g.size() &&
             !g.blank(to))  // a cell spanning columns ("ADDRESS[5:0]" over Bit5..Bit0)
        ++to;
    }
    to = std::max(to, from);
    out.push_back(trimmedSpan(g, {from, to}));
    from = to;
  }
  return out;
}

// "Addr Hex" columns (BQ79616 register summary) print addresses without "0x": "30D" reads as 0x30D.
bool saysHex(std::string_view heading) {
  for (std::size_t i = 0; i + 3 <= heading.size(); ++i) {
    const std::string_view w = heading.substr(i, 3);
    if ((w[0] == 'h' || w[0] == 'H') && (w[1] == 'e' || w[1] == 'E') && (w[2] == 'x' || w[2] == 'X'))
      return true;
  }
  return false;
}

bool isBareHex(std::string_view t) {
  return t.size() <= 4 && scan::all(t, scan::isHexDigit);
}

bool endsWithDash(std::string_view t) {
  return t.ends_with("-") || t.ends_with("\xE2\x80\x93") || t.ends_with("\xE2\x80\x94") || t.ends_with("...");
}

bool hasSeparators(std::string_view line) {
  return line.find('|') != std::string_view::npos || line.find('\t') != std::string_view::npos;
}

// Splits a line into cells at '|' or tabs. Columns are counted as the line is walked, so a line of many
// separators costs one pass (issue 15: recounting from the line start for every cell was quadratic).
std::vector<TableCell> splitCells(std::string_view line, int number) {
  std::vector<TableCell> cells;
  const char sep = line.find('|') != std::string_view::npos ? '|' : '\t';
  int col = 1;
  std::size_t start = 0;
  for (;;) {
    const std::size_t end = std::min(line.find(sep, start), line.size());
    const std::string_view raw = line.substr(start, end - start);
    const std::string_view cell = scan::trimmed(raw);
    const int cellCol =
        col +
        static_cast<int>(Glyphs(raw.substr(0, static_cast<std::size_t>(cell.data() - raw.data()))).size());
    cells.push_back({std::string(cell), number, cellCol});
    col += static_cast<int>(Glyphs(raw).size()) + 1;
    if (end == line.size()) break;
    start = end + 1;
  }
  // "| a | b |": the empty cells outside the outer bars are not columns.
  if (sep == '|') {
    if (!cells.empty() && cells.front().text.empty()) cells.erase(cells.begin());
    if (!cells.empty() && cells.back().text.empty()) cells.pop_back();
  }
  return cells;
}

// "---", ":---:", "---|---" rows under a Markdown heading.
bool isRule(const std::vector<TableCell>& cells) {
  for (const TableCell& c : cells) {
    std::string_view t = c.text;
    if (t.starts_with(":")) t.remove_prefix(1);
    if (t.ends_with(":")) t.remove_suffix(1);
    if (t.size() < 3 || !scan::all(t, [](char ch) { return ch == '-'; })) return false;
  }
  return !cells.empty();
}

struct SourceLine {
  int number = 0;
  std::string_view text;  // without '\r' and a leading form feed
  bool pageBreak = false;
};

// A row may have this many lines above its key line in a centred table (TI's longest: a description of four
// lines beside "Sealed: R/W" over the command), and this many blank lines between them.
constexpr int kMaxLinesBeforeKey = 6;

class Reader {
 public:
  explicit Reader(const std::string& text) : text_(text) {}

  TableText run() {
    if (!split()) return std::move(result_);
    for (std::size_t i = 0; i < lines_.size(); ++i)
      i = line(i);
    endTable();
    return std::move(result_);
  }

 private:
  // Splits the text into lines; false (with an error) if one is too long to be a table row.
  bool split() {
    int number = 0;
    result_.pageStarts.push_back(1);
    for (std::size_t start = 0; start <= text_.size();) {
      ++number;
      std::size_t end = text_.find('\n', start);
      const bool last = end == std::string::npos;
      if (last) end = text_.size();
      std::string_view l(text_.data() + start, end - start);
      if (l.size() > kMaxImportLineLength) {
        result_.errors.push_back({number, columnOf(text_, start, start + kMaxImportLineLength),
                                  "line is " + std::to_string(l.size()) +
                                      " bytes long; lines are limited to " +
                                      std::to_string(kMaxImportLineLength) + " bytes"});
      }
      if (l.ends_with('\r')) l.remove_suffix(1);
      const bool brk = l.starts_with('\f');
      // pdftotext ends every page with a form feed, so an empty page is one more.
      while (l.starts_with('\f')) {
        l.remove_prefix(1);
        result_.pageStarts.push_back(number);
      }
      if (last && l.empty() && !brk && number > 1) break;  // the newline ending the last line starts no line
      lines_.push_back({number, l, brk});
      if (last) break;
      start = end + 1;
    }
    return result_.errors.empty();
  }

  void prose(const SourceLine& l) {
    TableEvent e;
    e.kind = TableEvent::Kind::Prose;
    e.line = l.number;
    e.text = std::string(l.text);
    result_.events.push_back(std::move(e));
    if (isSectionHeading(l.text)) {
      section_ = {std::string(scan::trimmed(l.text)), l.number};
      proseSinceSection_ = 0;
      caption_ = {};                 // a caption belongs to a table of its own section
      pendingContinuation_ = false;  // and the next table is a new one
    } else if (isTableCaption(l.text)) {
      caption_ = {std::string(captionText(l.text)), l.number};
      proseSinceCaption_ = 0;
      if (!isContinuedCaption(l.text)) pendingContinuation_ = false;
    } else if (!scan::trimmed(l.text).empty()) {
      ++proseSinceSection_;
      // A caption stands right above its table; after a few lines of text it was a figure's or a table this
      // reader does not see.
      if (++proseSinceCaption_ > 3) caption_ = {};
    }
  }

  // Handles line i (and any line it consumes); returns the index of the last line consumed.
  std::size_t line(std::size_t i) {
    const SourceLine& l = lines_[i];
    if (l.pageBreak) pageBreak();
    if (isPageFurniture(l.text)) {
      if (layout_) layout_->blankRun = 0;  // the margins around headers and footers are not gaps in a table
      return i;
    }
    if (hasSeparators(l.text)) {
      if (layout_) endTable();
      separatedLine(l);
      return i;
    }
    separated_ = false;  // a line without separators ends a separated table
    if (layout_) {
      if (layoutLine(i)) return i;
      endTable();
    }
    return startOrProse(i);
  }

  void pageBreak() {
    if (layout_) {
      layout_->blankRun = 0;
      layout_->afterBreak = true;  // but a row does not go on across a page break on its own
    }
    pendingContinuation_ = true;
  }

  // ---- '|' and tab separated tables ----

  void separatedLine(const SourceLine& l) {
    std::vector<TableCell> cells = splitCells(l.text, l.number);
    if (isRule(cells)) return;
    std::vector<Role> roles;
    for (const TableCell& c : cells)
      roles.push_back(roleOf(c.text));
    if (isHeadingRow(roles)) {
      hexColumn_ = -1;
      for (std::size_t k = 0; k < roles.size(); ++k) {
        if (roles[k] == Role::Address && saysHex(cells[k].text)) hexColumn_ = static_cast<int>(k);
      }
      TableEvent e;
      e.kind = TableEvent::Kind::Heading;
      e.line = l.number;
      e.cells = std::move(cells);
      e.roles = std::move(roles);
      setContext(e);
      result_.events.push_back(std::move(e));
      separated_ = true;
      return;
    }
    if (!separated_) return;  // a separated line outside any table is not prose either
    if (hexColumn_ >= 0 && static_cast<std::size_t>(hexColumn_) < cells.size() &&
        isBareHex(cells[static_cast<std::size_t>(hexColumn_)].text)) {
      cells[static_cast<std::size_t>(hexColumn_)].text.insert(0, "0x");
    }
    TableEvent e;
    e.kind = TableEvent::Kind::Row;
    e.line = l.number;
    e.cells = std::move(cells);
    result_.events.push_back(std::move(e));
  }

  // A heading's caption and section; the caption is used once, except by the table's continuations.
  void setContext(TableEvent& e) {
    e.caption = caption_.text;
    e.captionLine = caption_.line;
    e.section = section_.text;
    e.sectionLine = section_.line;
    e.proseSinceSection = proseSinceSection_;
    caption_ = {};
  }

  // ---- pdftotext -layout tables ----

  struct BodyLine {
    int number = 0;
    Glyphs g;
    bool afterBlank = false;
  };

  struct Layout {
    std::vector<Column> cols;
    std::size_t key = 0;  // the column whose cell starts a row
    Role keyRole = Role::Unknown;
    int offsetColumn = -1;             // a payload-offset column: its cells start the fields of one row
    bool hexKeys = false;              // an "Addr Hex" key column: addresses without "0x"
    std::vector<std::size_t> anchors;  // preliminary bounds: each column's heading start
    std::vector<BodyLine> body;
    int blankRun = 0;
    bool afterBreak = false;
    bool keySeen = false;
    bool continued = false;    // repeats the previous table's headings: one table
    bool mayContinue = false;  // a page break or "(continued)" caption came before the heading
    int headingLine = 0;
    TableEvent context;  // caption and section
  };

  // The table a heading row starts; nothing if the row is not a heading. `extended`: columns were added from
  // the heading's second line ("Bit7" ... "Bit0"), so only the first line must read as a heading.
  static std::optional<Layout> layoutFor(std::vector<Column> cols, int line, bool extended = false) {
    const std::vector<Role> roles = rolesOf(cols);
    if (cols.size() < 3 || (!extended && !isHeadingRow(roles))) return std::nullopt;
    Layout t;
    t.cols = std::move(cols);
    t.headingLine = line;
    const auto find = [&](Role r) { return std::find(roles.begin(), roles.end(), r); };
    // The column whose cell makes a line a row's key line: the address; in a table of settings by class
    // (no address), the type, which is never wrapped ("System" over "Data" is one class name); the class; the
    // bit of a bit-field table.
    auto key = find(Role::Address);
    if (key == roles.end() && find(Role::Category) != roles.end()) key = find(Role::Type);
    if (key == roles.end()) key = find(Role::Category);
    if (key == roles.end()) key = find(Role::Bit);
    if (key == roles.end()) key = roles.begin();
    t.key = static_cast<std::size_t>(key - roles.begin());
    t.keyRole = *key;
    if (const auto offset = find(Role::Offset); offset != roles.end())
      t.offsetColumn = static_cast<int>(offset - roles.begin());
    t.hexKeys = t.keyRole == Role::Address && saysHex(t.cols[t.key].text);
    for (std::size_t k = 1; k < t.cols.size(); ++k)
      t.anchors.push_back(t.cols[k].span.from);
    return t;
  }

  // Starts a layout table at line i (a heading, possibly over two lines), or reports the line as prose.
  std::size_t startOrProse(std::size_t i) {
    const SourceLine& l = lines_[i];
    if (isTableCaption(l.text) || isSectionHeading(l.text) || !mayBeHeading(l.text)) {
      prose(l);
      return i;
    }
    const Glyphs g(l.text);
    std::vector<Column> cols = headingColumns(g, l.number);
    if (auto t = layoutFor(cols, l.number)) {
      begin(std::move(*t));
      return i;
    }
    // A heading over two lines: the first already names at least two columns ("SBS" above "Cmd" next to
    // "Name", "Access", ...).
    const auto known =
        std::count_if(cols.begin(), cols.end(), [](const Column& c) { return c.role != Role::Unknown; });
    if (known >= 2 && i + 1 < lines_.size()) {
      const SourceLine& next = lines_[i + 1];
      if (!next.pageBreak && !hasSeparators(next.text) && !isPageFurniture(next.text) &&
          !scan::trimmed(next.text).empty() && mergeHeadingLine(cols, Glyphs(next.text), next.number)) {
        if (auto t = layoutFor(cols, l.number)) {
          begin(std::move(*t));
          return i + 1;
        }
      }
      // A heading over three lines, this one in the middle: "SBS" / "Name ... Type Min Max" / "Cmd", "Proto-"
      // / "col" (SLUUAQ3A's SBS command tables). The line above was taken as prose; it is taken back.
      if (i > 0 && !l.pageBreak && !result_.events.empty() &&
          result_.events.back().kind == TableEvent::Kind::Prose &&
          result_.events.back().line == lines_[i - 1].number && !scan::trimmed(lines_[i - 1].text).empty() &&
          !isPageFurniture(lines_[i - 1].text) && !next.pageBreak && !isPageFurniture(next.text) &&
          !scan::trimmed(next.text).empty()) {
        const Glyphs above(lines_[i - 1].text), below(next.text);
        std::vector<Column> three = headingColumns(above, lines_[i - 1].number);
        if (mergeHeadingLine(three, g, l.number, true) && mergeHeadingLine(three, below, next.number, true)) {
          if (auto t = layoutFor(three, lines_[i - 1].number)) {
            result_.events.pop_back();
            begin(std::move(*t));
            return i + 1;
          }
        }
      }
    }
    prose(l);
    return i;
  }

  void begin(Layout t) {
    // The same headings again after a page break: the table goes on.
    t.mayContinue = pendingContinuation_;
    t.continued = t.mayContinue && lastRoles_ == rolesOf(t.cols);
    if (t.continued) {
      t.context = lastContext_;
    } else {
      setContext(t.context);
    }
    caption_ = {};
    layout_ = std::move(t);
    pendingContinuation_ = false;
  }

  bool validKey(std::string_view key) const {
    if (key.empty()) return false;
    if (layout_->keyRole == Role::Address) {
      // "0x14", "0x4000–0x5FFF" (a range), "30D" under "Addr Hex".
      const std::string_view first = key.substr(0, key.find_first_not_of("0123456789abcdefABCDEFxX"));
      return scan::isHexLiteral(first) || (layout_->hexKeys && isBareHex(first));
    }
    if (layout_->keyRole == Role::Category) return !scan::isDigit(key[0]) && !key.ends_with(':');
    if (layout_->keyRole == Role::Type) {
      // "U2", "H1", "F4", "S20+1", "I2" as TI prints it; not a word of a sentence. A number of the next
      // column may start left of its heading and share the cell ("F4        1.00E–02").
      key = key.substr(0, key.find(' '));
      return key.size() <= 8 && scan::isAlpha(key[0]) && key.find(' ') == std::string_view::npos &&
             !key.ends_with(':') && !key.ends_with('.') && !key.ends_with(',');
    }
    if (layout_->keyRole == Role::Bit) {
      // "7", "15–8", "5-4", "31:16"
      const std::size_t digits = scan::run(key, 0, scan::isDigit);
      return digits > 0 && digits <= 2 &&
             (digits == key.size() || key[digits] == ' ' || key[digits] == '-' || key[digits] == ':' ||
              key.substr(digits).starts_with("\xE2\x80\x93"));
    }
    return true;
  }

  // A chunk of text running across three or more columns is a sentence, not the continuation of a row.
  bool proseLike(const Glyphs& g) const {
    for (const Span c : chunks(g)) {
      int crossed = 0;
      for (std::size_t a : layout_->anchors)
        crossed += (c.from < a && a < c.to) ? 1 : 0;
      if (crossed >= 2) return true;
    }
    return false;
  }

  // The key cell of a line, cut at the preliminary bounds.
  std::string_view keyOf(const Glyphs& g) const {
    const std::vector<Span> cells = slice(g, layout_->anchors);
    return g.slice(cells[layout_->key].from, cells[layout_->key].to);
  }

  bool hasOffset(const Glyphs& g) const {
    if (layout_->offsetColumn < 0) return false;
    const std::vector<Span> cells = slice(g, layout_->anchors);
    const Span s = cells[static_cast<std::size_t>(layout_->offsetColumn)];
    const std::string_view t = g.slice(s.from, s.to);
    return !t.empty() && scan::isDigit(t[0]);
  }

  // From line i (a line without a key), whether a key line follows within a few lines, before a blank line,
  // a page break or a line of prose: the lines of a centred row above its key line.
  bool keyAhead(std::size_t i) const {
    int seen = 0;
    for (std::size_t j = i; j < lines_.size() && seen <= kMaxLinesBeforeKey; ++j) {
      const SourceLine& l = lines_[j];
      if (j > i && l.pageBreak) return false;
      if (isPageFurniture(l.text)) continue;
      if (scan::trimmed(l.text).empty() || hasSeparators(l.text) || isTableCaption(l.text) ||
          isSectionHeading(l.text))
        return false;
      const Glyphs g(l.text);
      if (const std::vector<Column> cols = headingColumns(g, l.number);
          cols.size() >= 3 && isHeadingRow(rolesOf(cols)))
        return false;
      if (validKey(keyOf(g))) return true;
      if (proseLike(g)) return false;
      ++seen;
    }
    return false;
  }

  // Whether a line that is not a key and not under a known heading can be the heading's second line ("Value"
  // under "Min", "SE US FA" under "Access", "Hex" under "Addr"): no chunk turns a known heading into text
  // that is none ("Access" over "Sealed: R" is a cell of the first row).
  static bool headingContinuation(const std::vector<Column>& cols, const Glyphs& g) {
    for (const Span c : chunks(g)) {
      const std::string_view t = g.slice(c.from, c.to);
      for (const Column& col : cols) {
        if (!(c.from <= col.span.to && col.span.from <= c.to) || col.role == Role::Unknown) continue;
        std::string merged = col.text;
        appendWrapped(merged, t);
        if (roleOf(merged) == Role::Unknown && roleOf(t) == Role::Unknown) return false;
      }
    }
    return true;
  }

  // Takes line i into the current layout table; false if it ends the table.
  bool layoutLine(std::size_t i) {
    const SourceLine& l = lines_[i];
    Layout& t = *layout_;
    if (scan::trimmed(l.text).empty()) {
      ++t.blankRun;
      return true;
    }
    if (isContinuedCaption(l.text)) {
      t.blankRun = 0;
      pendingContinuation_ = true;
      return true;
    }
    if (isTableCaption(l.text) || isSectionHeading(l.text)) return false;
    const Glyphs g(l.text);
    // A heading row again (a page break, or the next table right after this one).
    std::vector<Column> cols = headingColumns(g, l.number);
    if (rolesOf(cols) == rolesOf(t.cols) || (cols.size() >= 3 && isHeadingRow(rolesOf(cols)))) {
      const bool same = rolesOf(cols) == rolesOf(t.cols);
      endTable();
      if (same) pendingContinuation_ = true;
      begin(*layoutFor(std::move(cols), l.number));
      return true;
    }
    const std::string_view key = keyOf(g);
    // A row's cells may fill their columns ("2.98262E+03 4.193046E+08 2230042.463"): a line with an address
    // is a row whatever its width, one whose class cell holds a word is prose when it runs across columns.
    const bool wide = proseLike(g);
    const bool isKey = validKey(key) && !(wide && t.keyRole != Role::Address);
    const bool prose = !isKey && wide;
    if (t.body.empty() && t.blankRun == 0 && !prose && !isKey && headingContinuation(t.cols, g)) {
      // Before the first row, a line without a key is the heading's second line ("SE US FA" under "Access",
      // "Value" under "Min", "Hex" under "Addr").
      std::vector<Column> merged = t.cols;
      if (mergeHeadingLine(merged, g, l.number, true)) {
        if (std::optional<Layout> joined = layoutFor(std::move(merged), t.headingLine, true)) {
          joined->mayContinue = t.mayContinue;
          joined->continued = t.continued || (t.mayContinue && lastRoles_ == rolesOf(joined->cols));
          joined->context = t.context;
          layout_ = std::move(joined);
          return true;
        }
      }
    }
    if (isKey) {
      if (t.blankRun > 3) return false;
      t.keySeen = true;
    } else if (!key.empty() || prose) {
      return false;  // something else in the key column, or a sentence
    } else if ((t.blankRun > 0 || t.afterBreak || !t.keySeen) && !hasOffset(g) && !keyAhead(i)) {
      // After a blank line (or before any row), a line continues the table only as the first line of a
      // payload field or of a centred row whose key line follows.
      return false;
    }
    t.body.push_back({l.number, g, t.blankRun > 0 || t.afterBreak});
    t.blankRun = 0;
    t.afterBreak = false;
    return true;
  }

  // The bound between column k and k + 1: the rightmost position of the gap between their headings that is
  // blank on every line of the table; else the rightmost one that cuts no line inside a word (cells that run
  // into each other with one space, "PREV_MACWRITE Sealed: R", where the next column starts further left on
  // some lines than on others); else the start of heading k + 1.
  std::vector<std::size_t> bounds() const {
    const Layout& t = *layout_;
    std::vector<std::size_t> out;
    for (std::size_t k = 0; k + 1 < t.cols.size(); ++k) {
      const std::size_t lo = t.cols[k].span.to, hi = t.cols[k + 1].span.from;
      std::size_t b = hi;
      bool found = false;
      for (std::size_t p = hi; !found && p-- > lo;) {
        found =
            std::all_of(t.body.begin(), t.body.end(), [&](const BodyLine& row) { return row.g.blank(p); });
        if (found) b = p;
      }
      for (std::size_t p = hi + 1; !found && p-- > lo + 1;) {
        found = std::all_of(t.body.begin(), t.body.end(),
                            [&](const BodyLine& row) { return row.g.blank(p - 1) || row.g.blank(p); });
        if (found) b = p;
      }
      out.push_back(std::max(b, out.empty() ? std::size_t{0} : out.back()));
    }
    return out;
  }

  // Which row (index of its key line in the body) each body line belongs to; -1 for lines before any row.
  std::vector<int> owners(const std::vector<std::vector<Span>>& cells, const std::vector<bool>& isKey,
                          bool centred) const {
    const Layout& t = *layout_;
    const int n = static_cast<int>(t.body.size());
    std::vector<int> owner(static_cast<std::size_t>(n), -1);
    // The key line before and after each line, and where each run of lines without a blank starts.
    std::vector<int> prevKey(static_cast<std::size_t>(n), -1), nextKey(static_cast<std::size_t>(n), -1);
    std::vector<int> run(static_cast<std::size_t>(n), 0);
    for (int i = 0, last = -1, r = 0; i < n; ++i) {
      if (t.body[static_cast<std::size_t>(i)].afterBlank) ++r;
      run[static_cast<std::size_t>(i)] = r;
      if (isKey[static_cast<std::size_t>(i)]) last = i;
      prevKey[static_cast<std::size_t>(i)] = last;
    }
    for (int i = n - 1, next = -1; i >= 0; --i) {
      if (isKey[static_cast<std::size_t>(i)]) next = i;
      nextKey[static_cast<std::size_t>(i)] = next;
    }
    const auto lineOf = [&](int i) { return t.body[static_cast<std::size_t>(i)].number; };
    const auto emptyAt = [&](int keyLine, std::size_t k) {
      return cells[static_cast<std::size_t>(keyLine)][k].empty();
    };
    for (int i = 0; i < n; ++i) {
      const std::size_t u = static_cast<std::size_t>(i);
      if (isKey[u]) {
        owner[u] = i;
        continue;
      }
      const int p = prevKey[u], q = nextKey[u];
      if (!centred || q < 0) {
        owner[u] = p >= 0 ? p : q;
        continue;
      }
      if (p < 0) {
        owner[u] = q;
        continue;
      }
      const bool pSame = run[static_cast<std::size_t>(p)] == run[u],
                 qSame = run[static_cast<std::size_t>(q)] == run[u];
      if (pSame != qSame) {
        owner[u] = pSame ? p : q;  // a blank line separates the rows
        continue;
      }
      const int dp = lineOf(i) - lineOf(p), dq = lineOf(q) - lineOf(i);
      if (dp != dq) {
        owner[u] = dp < dq ? p : q;
        continue;
      }
      // Halfway: the cell is centred on the key line that leaves its column empty.
      int votes = 0;
      for (std::size_t k = 0; k < cells[u].size(); ++k) {
        if (cells[u][k].empty()) continue;
        votes += (emptyAt(q, k) ? 1 : 0) - (emptyAt(p, k) ? 1 : 0);
      }
      owner[u] = votes > 0 ? q : p;
    }
    return owner;
  }

  // Emits the current layout table: its heading, then one row per key line with the lines it owns joined
  // cell by cell.
  void endTable() {
    if (!layout_) return;
    const Layout& t = *layout_;
    lastRoles_ = rolesOf(t.cols);
    lastContext_ = t.context;
    TableEvent heading = t.context;
    heading.kind = TableEvent::Kind::Heading;
    heading.line = t.headingLine;
    heading.roles = lastRoles_;
    heading.continued = t.continued;
    for (const Column& c : t.cols)
      heading.cells.push_back({c.text, c.line, static_cast<int>(c.span.from) + 1});
    result_.events.push_back(std::move(heading));
    if (!t.continued) carried_.clear();

    const std::vector<std::size_t> b = bounds();
    std::vector<std::vector<Span>> cells;
    std::vector<bool> isKey;
    std::string previousKey;
    for (const BodyLine& line : t.body) {
      cells.push_back(slice(line.g, b));
      const std::string_view key = line.g.slice(cells.back()[t.key].from, cells.back()[t.key].to);
      // "0x4000–" over "0x5FFF": a range of codes wrapped in its cell continues the row.
      const bool rangeGoesOn = endsWithDash(previousKey) && isKey.size() > 0 && isKey.back();
      const bool k = validKey(key) && !rangeGoesOn;
      isKey.push_back(k);
      previousKey = k ? std::string(key) : std::string();
    }
    // Centred when a line that is not a key comes first, or when a key line leaves a column empty that the
    // line right below it fills (a cell centred on the key line: top-aligned cells start on their key line);
    // a part of a continued table without either sign keeps the alignment of the part before.
    bool centred = !t.body.empty() && !isKey.front();
    for (std::size_t i = 0; !centred && i + 1 < t.body.size(); ++i) {
      if (!isKey[i] || isKey[i + 1] || t.body[i + 1].afterBlank) continue;
      for (std::size_t k = 0; k < cells[i].size() && !centred; ++k)
        centred = cells[i][k].empty() && !cells[i + 1][k].empty();
    }
    if (!centred && t.continued) centred = lastCentred_;
    lastCentred_ = centred;
    const std::vector<int> owner = owners(cells, isKey, centred);
    // Rows in key order; each row's lines in line order.
    std::vector<std::vector<std::size_t>> rows(t.body.size());
    for (std::size_t i = 0; i < t.body.size(); ++i) {
      if (owner[i] >= 0) rows[static_cast<std::size_t>(owner[i])].push_back(i);
    }
    for (std::size_t r = 0; r < t.body.size(); ++r) {
      if (!isKey[r]) continue;
      TableEvent row;
      row.kind = TableEvent::Kind::Row;
      row.line = t.body[r].number;
      row.cells.assign(t.cols.size(), TableCell{});
      for (const std::size_t i : rows[r]) {
        const BodyLine& line = t.body[i];
        for (std::size_t k = 0; k < cells[i].size(); ++k) {
          if (cells[i][k].empty()) continue;
          TableCell& c = row.cells[k];
          if (c.text.empty()) {
            c.line = line.number;
            c.col = static_cast<int>(cells[i][k].from) + 1;
          }
          const std::string_view more = line.g.slice(cells[i][k].from, cells[i][k].to);
          if (isNameRole(t.cols[k].role) &&
              ((identifierPart(c.text) && identifierPart(more)) || camelJoin(c.text, more))) {
            c.text += more;  // "MANUFACTURINGSTAT" over "US": TI breaks a long identifier where the cell ends
          } else {
            appendWrapped(c.text, more);
          }
        }
      }
      prefixHexKey(row);
      emitRow(std::move(row));
    }
    layout_.reset();
  }

  void prefixHexKey(TableEvent& row) const {
    if (!layout_->hexKeys) return;
    std::string& key = row.cells[layout_->key].text;
    if (isBareHex(key.substr(0, key.find(' ')))) key.insert(0, "0x");
  }

  // An empty class or subclass cell means the one of the row above (a merged cell printed once).
  void emitRow(TableEvent row) {
    for (std::size_t k = 0; k < row.cells.size() && k < lastRoles_.size(); ++k) {
      if (lastRoles_[k] != Role::Category && lastRoles_[k] != Role::Subcategory) continue;
      std::string& remembered = carried_[lastRoles_[k]];
      if (row.cells[k].text.empty()) {
        row.cells[k].text = remembered;
        row.cells[k].line = row.line;
      } else {
        remembered = row.cells[k].text;
      }
    }
    result_.events.push_back(std::move(row));
  }

  struct Context {
    std::string text;
    int line = 0;
  };

  const std::string& text_;
  std::vector<SourceLine> lines_;
  TableText result_;
  bool separated_ = false;  // inside a '|' or tab separated table
  int hexColumn_ = -1;      // its "Addr Hex" column
  std::optional<Layout> layout_;
  std::vector<Role> lastRoles_;       // headings of the last layout table
  TableEvent lastContext_;            // its caption and section
  bool lastCentred_ = false;          // its alignment
  bool pendingContinuation_ = false;  // a page break, a "(continued)" caption or a repeated heading since
  Context caption_, section_;         // the caption waiting for its table; the section we are in
  int proseSinceCaption_ = 0, proseSinceSection_ = 0;
  struct Carried {
    std::string& operator[](Role r) { return r == Role::Category ? category : subcategory; }
    void clear() { category.clear(), subcategory.clear(); }
    std::string category, subcategory;
  } carried_;
};

}  // namespace

TableText readTables(const std::string& text) {
  return Reader(text).run();
}

int pageOf(const TableText& t, int line) {
  const auto it = std::upper_bound(t.pageStarts.begin(), t.pageStarts.end(), line);
  return std::max(0, static_cast<int>(it - t.pageStarts.begin()) - 1);
}

}  // namespace regmapgen
