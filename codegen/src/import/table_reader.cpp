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
      if (brk) l.remove_prefix(1);
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
      if (layoutLine(l)) return i;
      endTable();
    }
    return startOrProse(i);
  }

  void pageBreak() {
    if (layout_) layout_->blankRun = 0;
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

  // ---- pdftotext -layout tables ----

  struct Layout {
    std::vector<Column> cols;
    std::size_t key = 0;  // the column whose cell starts a row
    Role keyRole = Role::Unknown;
    bool hexKeys = false;              // an "Addr Hex" key column: addresses without "0x"
    std::vector<std::size_t> anchors;  // preliminary bounds: each column's heading start
    std::vector<std::pair<int, Glyphs>> body;
    int blankRun = 0;
    bool continued = false;    // repeats the previous table's headings: one table
    bool mayContinue = false;  // a page break or "(continued)" caption came before the heading
    int headingLine = 0;
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
    auto key = find(Role::Address);
    if (key == roles.end()) key = find(Role::Category);
    if (key == roles.end()) key = roles.begin();
    t.key = static_cast<std::size_t>(key - roles.begin());
    t.keyRole = *key;
    t.hexKeys = t.keyRole == Role::Address && saysHex(t.cols[t.key].text);
    for (std::size_t k = 1; k < t.cols.size(); ++k)
      t.anchors.push_back(t.cols[k].span.from);
    return t;
  }

  // Starts a layout table at line i (a heading, possibly over two lines), or reports the line as prose.
  std::size_t startOrProse(std::size_t i) {
    const SourceLine& l = lines_[i];
    if (isTableCaption(l.text)) {
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
    }
    prose(l);
    return i;
  }

  void begin(Layout t) {
    // The same headings again after a page break: the table goes on.
    t.mayContinue = pendingContinuation_;
    t.continued = t.mayContinue && lastRoles_ == rolesOf(t.cols);
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
    if (layout_->keyRole == Role::Category) return !scan::isDigit(key[0]);
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

  // Takes line l into the current layout table; false if it ends the table.
  bool layoutLine(const SourceLine& l) {
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
    if (isTableCaption(l.text)) return false;
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
    const std::vector<Span> cells = slice(g, t.anchors);
    const std::string_view key = g.slice(cells[t.key].from, cells[t.key].to);
    // A row's cells may fill their columns ("2.98262E+03 4.193046E+08 2230042.463"); only lines without a key
    // are judged as prose by their width.
    const bool prose = key.empty() && proseLike(g);
    if (t.body.empty() && t.blankRun == 0 && !prose && !validKey(key)) {
      // Before the first row, a line without a key is the heading's second line ("SE US FA" under "Access",
      // "Value" under "Min", "Hex" under "Addr").
      std::vector<Column> merged = t.cols;
      if (!mergeHeadingLine(merged, g, l.number, true)) return false;
      std::optional<Layout> joined = layoutFor(std::move(merged), t.headingLine, true);
      if (!joined) return false;
      joined->mayContinue = t.mayContinue;
      joined->continued = t.continued || (t.mayContinue && lastRoles_ == rolesOf(joined->cols));
      layout_ = std::move(joined);
      return true;
    }
    if (!key.empty()) {
      if (!validKey(key) || t.blankRun > 3) return false;
    } else if (t.blankRun > 0 || prose || t.body.empty()) {
      return false;
    }
    t.blankRun = 0;
    t.body.emplace_back(l.number, g);
    return true;
  }

  // The bound between column k and k + 1: the rightmost position of the gap between their headings that is
  // blank on every line of the table, else the start of heading k + 1.
  std::vector<std::size_t> bounds() const {
    const Layout& t = *layout_;
    std::vector<std::size_t> out;
    for (std::size_t k = 0; k + 1 < t.cols.size(); ++k) {
      const std::size_t lo = t.cols[k].span.to, hi = t.cols[k + 1].span.from;
      std::size_t b = hi;
      for (std::size_t p = hi; p-- > lo;) {
        const bool blankEverywhere =
            std::all_of(t.body.begin(), t.body.end(), [&](const auto& row) { return row.second.blank(p); });
        if (blankEverywhere) {
          b = p;
          break;
        }
      }
      out.push_back(std::max(b, out.empty() ? std::size_t{0} : out.back()));
    }
    return out;
  }

  // Emits the current layout table: its heading, then one row per line with a key cell, continuation lines
  // joined to the row above.
  void endTable() {
    if (!layout_) return;
    const Layout& t = *layout_;
    lastRoles_ = rolesOf(t.cols);
    TableEvent heading;
    heading.kind = TableEvent::Kind::Heading;
    heading.line = t.headingLine;
    heading.roles = lastRoles_;
    heading.continued = t.continued;
    for (const Column& c : t.cols)
      heading.cells.push_back({c.text, c.line, static_cast<int>(c.span.from) + 1});
    result_.events.push_back(std::move(heading));
    if (!t.continued) carried_.clear();

    const std::vector<std::size_t> b = bounds();
    TableEvent row;
    bool open = false;
    for (const auto& [number, g] : t.body) {
      const std::vector<Span> cells = slice(g, b);
      // "0x4000–" over "0x5FFF": a range of codes wrapped in its cell continues the row.
      const bool rangeGoesOn = open && endsWithDash(row.cells[t.key].text);
      if ((!cells[t.key].empty() && !rangeGoesOn) || !open) {
        if (open) {
          prefixHexKey(row);
          emitRow(std::move(row));
        }
        row = TableEvent{};
        row.kind = TableEvent::Kind::Row;
        row.line = number;
        row.cells.assign(t.cols.size(), TableCell{});
        open = true;
      }
      for (std::size_t k = 0; k < cells.size(); ++k) {
        if (cells[k].empty()) continue;
        TableCell& c = row.cells[k];
        if (c.text.empty()) {
          c.line = number;
          c.col = static_cast<int>(cells[k].from) + 1;
        }
        const std::string_view more = g.slice(cells[k].from, cells[k].to);
        if (identifierPart(c.text) && identifierPart(more) && isNameRole(t.cols[k].role)) {
          c.text += more;  // "MANUFACTURINGSTAT" over "US": TI breaks a long identifier where the cell ends
        } else {
          appendWrapped(c.text, more);
        }
      }
    }
    if (open) {
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

  const std::string& text_;
  std::vector<SourceLine> lines_;
  TableText result_;
  bool separated_ = false;  // inside a '|' or tab separated table
  int hexColumn_ = -1;      // its "Addr Hex" column
  std::optional<Layout> layout_;
  std::vector<Role> lastRoles_;       // headings of the last layout table
  bool pendingContinuation_ = false;  // a page break, a "(continued)" caption or a repeated heading since
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

}  // namespace regmapgen
