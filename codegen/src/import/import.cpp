#include "import/import.hpp"

#include <algorithm>
#include <map>
#include <optional>
#include <ostream>
#include <set>
#include <sstream>

#include "check/check.hpp"
#include "diag/diag.hpp"
#include "emit/emit.hpp"
#include "import/cells.hpp"
#include "import/table_reader.hpp"
#include "model/model.hpp"
#include "model/names.hpp"
#include "model/schema.hpp"
#include "text/scan.hpp"

namespace regmapgen {

namespace {

struct Imported {
  const KindInfo* kind = nullptr;
  int line = 0;
  std::vector<std::string> comments;                      // shown above the entry
  std::vector<std::pair<std::string, std::string>> keys;  // in output order
  std::vector<std::string> notes;
  std::string category, subcategory;  // for making identifiers unique
  bool idFromMap = false;
};

// The kind a `--kind` value names (its `list` word or YAML key), or nullptr.
const KindInfo* findKind(const std::string& k) {
  for (const KindInfo& info : kinds()) {
    if (info.listName == k || info.yamlKey == k) return &info;
  }
  return nullptr;
}

// Which kinds a family's tables hold: 8-bit codes, 16-bit codes, and tables with a class column.
struct FamilyKinds {
  std::string_view family, byteCodes, wordCodes, memory;
};
const FamilyKinds& kindsOf(const std::string& family) {
  static const FamilyKinds table[] = {
      {"bq79616", "registers", "registers", "registers"},
      {"bq4050", "sbs", "mac", "dataflash"},
      {"", "commands", "subcommands", "datamem"},  // BQ769x2, BQ7690x and anything else
  };
  for (const FamilyKinds& f : table) {
    if (f.family == family) return f;
  }
  return table[std::size(table) - 1];
}

// "Address 0x9261", "地址 0x9261", "写入 0x9304", "write to 0x9304": the 4-digit address after the keyword.
std::vector<std::string> addressMentions(const std::string& line) {
  static const std::string_view keywords[] = {"地址", "写入", "Address", "address", "Write to", "write to"};
  std::vector<std::pair<std::size_t, std::string>> found;
  for (std::string_view k : keywords) {
    for (std::size_t p = line.find(k); p != std::string::npos; p = line.find(k, p + 1)) {
      std::size_t q = p + k.size();
      while (q < line.size() && (line[q] == ' ' || line[q] == '\t'))
        ++q;
      const std::string_view rest = std::string_view(line).substr(q);
      const bool wordAfter =
          rest.size() > 6 && (scan::isAlpha(rest[6]) || scan::isDigit(rest[6]) || rest[6] == '_');
      if (rest.size() >= 6 && scan::isHexLiteral(rest.substr(0, 6)) && !wordAfter)
        found.emplace_back(p, "0x" + upperCase(rest.substr(2, 4)));
    }
  }
  std::sort(found.begin(), found.end());
  std::vector<std::string> out;
  for (const auto& f : found)
    out.push_back(f.second);
  return out;
}

// "16 位", "16-bit", "32 bit" in a description: the width it states and the words that state it.
struct StatedWidth {
  int bits = 0;
  std::string text;
};
StatedWidth statedWidth(const std::string& description) {
  for (std::size_t p = 0; p < description.size(); ++p) {
    std::size_t unit = 0, end = p;
    if (description.compare(p, 3, "位") == 0) {
      unit = 3;
    } else if (description.compare(p, 3, "bit") == 0) {
      unit = 3;
      if (p > 0 && description[p - 1] == '-') --end;
    } else {
      continue;
    }
    while (end > 0 && (description[end - 1] == ' ' || description[end - 1] == '\t'))
      --end;
    for (const std::string width : {"16", "32", "8"}) {
      if (end >= width.size() && description.compare(end - width.size(), width.size(), width) == 0) {
        const std::size_t from = end - width.size();
        return {std::stoi(width), description.substr(from, p + unit - from)};
      }
    }
  }
  return {};
}

// An address cell: "0x14", "0x0022 (R)", or a range of codes "0x4000–0x5FFF", "0x4000...0x5FFF",
// "0x4000 to 0x5FFF". The hex digits of the first and (for a range) the last code.
struct AddressCell {
  std::string first, last;
};
std::optional<AddressCell> addressCell(const std::string& cell) {
  std::string t;
  for (std::size_t i = 0; i < cell.size(); ++i) {
    const std::string_view rest = std::string_view(cell).substr(i);
    if (rest.starts_with("\xE2\x80\x93") || rest.starts_with("\xE2\x80\x94") || rest.starts_with("...") ||
        rest.starts_with("\xE2\x80\xA6")) {
      t += '-';
      i += 2;  // every one of these separators is three bytes
    } else if (rest.starts_with(" to ")) {
      t += '-';
      i += 3;
    } else if (cell[i] != ' ') {
      t += cell[i];
    }
  }
  const std::size_t end = std::min(t.find_first_not_of("0123456789abcdefABCDEFxX-"), t.size());
  const std::string range = t.substr(0, end);
  const std::string a = range.substr(0, range.find('-'));
  if (!scan::isHexLiteral(a)) return std::nullopt;
  const std::string b = range.find('-') == std::string::npos ? "" : range.substr(range.find('-') + 1);
  return AddressCell{a.substr(2), scan::isHexLiteral(b) ? b.substr(2) : ""};
}

// Hex digits as an address of `digits` digits ("14" -> "0x14", "22" -> "0x0022"); a value too wide for any
// kind is kept as written, for check to report.
std::string addressText(const std::string& hex, int digits) {
  const std::size_t significant = std::min(hex.find_first_not_of('0'), hex.size());
  if (hex.size() - significant > 8) return "0x" + upperCase(hex);
  return hexAddress(std::stoull(hex, nullptr, 16), digits);
}

// "CB_CELL16_CTRL through CB_CELL1_CTRL", "OTP_PROG_UNLOCK1A through OTP_PROG_UNLOCK1D": the names of a run
// of registers, in the order of their rows (TI names the first row of a run with both ends and leaves the
// name of the others empty). Empty unless the ends differ in one number or one letter.
std::vector<std::string> runNames(const std::string& name) {
  const std::size_t at = name.find(" through ");
  if (at == std::string::npos) return {};
  const std::string a = name.substr(0, at), b = name.substr(at + 9);
  std::size_t pre = 0;
  while (pre < a.size() && pre < b.size() && a[pre] == b[pre])
    ++pre;
  std::size_t post = 0;
  while (post < a.size() - pre && post < b.size() - pre && a[a.size() - 1 - post] == b[b.size() - 1 - post])
    ++post;
  std::vector<std::string> out;
  const auto middle = [&](const std::string& s) { return s.substr(pre, s.size() - pre - post); };
  if (middle(a).size() == 1 && middle(b).size() == 1 && scan::isAlpha(middle(a)[0]) &&
      scan::isAlpha(middle(b)[0])) {
    const char from = middle(a)[0], to = middle(b)[0];
    for (char c = from;; c = static_cast<char>(c + (from <= to ? 1 : -1))) {
      out.push_back(a.substr(0, pre) + c + a.substr(a.size() - post));
      if (c == to) break;
    }
    return out;
  }
  // A number: widen the differing part to whole numbers ("CELL16" / "CELL1" differ in "6" / "").
  while (pre > 0 && scan::isDigit(a[pre - 1]))
    --pre;
  while (post > 0 && scan::isDigit(a[a.size() - post]))
    --post;
  const std::string ma = middle(a), mb = middle(b);
  if (ma.empty() || mb.empty() || ma.size() > 3 || mb.size() > 3 || !scan::all(ma, scan::isDigit) ||
      !scan::all(mb, scan::isDigit)) {
    return {};
  }
  const int from = std::stoi(ma), to = std::stoi(mb);
  for (int n = from;; n += from <= to ? 1 : -1) {
    out.push_back(a.substr(0, pre) + std::to_string(n) + a.substr(a.size() - post));
    if (n == to) break;
  }
  return out;
}

// The cells of one row by role. Several cells may share a role: descriptions are joined, the last access
// cell wins (the BQ4050 SE/US/FA columns: full access is last).
class RowCells {
 public:
  RowCells(const TableEvent& row, const std::vector<Role>& roles, const std::vector<TableCell>& headings)
      : row_(row) {
    for (std::size_t i = 0; i < row.cells.size(); ++i) {
      const Role role = i < roles.size() ? roles[i] : Role::Unknown;
      const TableCell& c = row.cells[i];
      if (role == Role::Unknown) {
        if (c.text.empty()) continue;
        const std::string label = i < headings.size() ? headings[i].text : "column " + std::to_string(i + 1);
        extra.append(extra.empty() ? "" : " ").append(label).append(": ").append(c.text);
        if (i >= roles.size()) beyondHeadings.push_back(&c);
        continue;
      }
      if (role == Role::Description || role == Role::Data) {
        std::string& joined = role == Role::Data ? data_ : description_;
        if (!c.text.empty()) joined.append(joined.empty() ? "" : " ").append(c.text);
        if (cells_.count(role)) continue;
      }
      if (role == Role::Access && cells_.count(role) && !cells::access(c.text)) continue;
      if (!cells_.count(role) || !c.text.empty()) cells_[role] = &c;
    }
  }
  bool has(Role r) const { return cells_.count(r) != 0; }
  std::string get(Role r) const {
    if (r == Role::Description) return description_;
    if (r == Role::Data) return data_;
    auto it = cells_.find(r);
    return it == cells_.end() ? std::string() : it->second->text;
  }
  int col(Role r) const {
    auto it = cells_.find(r);
    return it == cells_.end() ? 1 : it->second->col;
  }
  int line(Role r) const {
    auto it = cells_.find(r);
    return it == cells_.end() || it->second->line == 0 ? row_.line : it->second->line;
  }

  std::string extra;  // "Heading: text" of the columns no role claims
  std::vector<const TableCell*> beyondHeadings;

 private:
  const TableEvent& row_;
  std::map<Role, const TableCell*> cells_;
  std::string description_;  // every description cell, joined
  std::string data_;         // every data cell (BQ79616: the field names under Bit7..Bit0), joined
};

// At most this many bytes of a value go into the YAML: escaped (\xNN, four per byte at most) and with its
// key, a line stays within the reader's 4096 bytes.
constexpr std::size_t kMaxValueBytes = 1000;

std::string capped(const std::string& v) {
  if (v.size() <= kMaxValueBytes) return v;
  std::size_t cut = kMaxValueBytes;
  while (cut > 0 && (static_cast<unsigned char>(v[cut]) & 0xC0) == 0x80)
    --cut;
  return v.substr(0, cut) + "...";
}

class Importer {
 public:
  Importer(std::string path, const ImportOptions& opts, std::ostream& err)
      : path_(std::move(path)), opts_(opts), err_(err) {}

  // Reads the --map files: only their entries are needed (names, addresses, ids), so problems `check` would
  // find in one file of a family (a fieldset defined in fields.yaml) do not matter; syntax errors do.
  bool loadMaps() {
    for (const std::string& f : opts_.mapFiles) {
      std::string text, why;
      if (!readFile(f, text, &why)) {
        err_ << "regmapgen: error: cannot read map file " << f << ": " << why << "\n";
        return false;
      }
      mapSources_.add(f, std::move(text));
    }
    if (opts_.mapFiles.empty()) return true;
    Diagnostics diag(mapSources_);
    map_ = build(mapSources_, diag);
    if (diag.errorCount() > 0) {
      diag.render(err_);
      err_ << "regmapgen: error: the --map files have errors; fix them first\n";
      return false;
    }
    return true;
  }

  std::string family() const {
    if (!opts_.family.empty()) return opts_.family;
    if (!map_.families.empty()) return map_.families.front().name;
    return "imported";
  }

  int run(const std::string& text) {
    const TableText tables = readTables(text);
    if (!tables.errors.empty()) {
      for (const auto& e : tables.errors)
        err_ << path_ << ":" << e.line << ":" << e.col << ": error: " << e.message << "\n";
      err_ << "regmapgen: error: " << path_ << " is not a table text; nothing imported\n";
      return 1;
    }
    kinds_ = &kindsOf(family());
    std::vector<Role> roles;
    std::vector<TableCell> headingCells;
    bool afterTable = false;
    int tables_ = 0;
    for (const TableEvent& e : tables.events) {
      switch (e.kind) {
        case TableEvent::Kind::Prose:
          if (afterTable) mentions_.clear();  // prose after a table starts a new context
          afterTable = false;
          for (const std::string& a : addressMentions(e.text))
            mentions_.push_back({a, e.line});
          break;
        case TableEvent::Kind::Heading:
          roles = e.roles;
          headingCells = e.cells;
          if (!e.continued) {
            for (std::size_t i = 0; i < roles.size(); ++i) {
              if (roles[i] == Role::Unknown && !e.cells[i].text.empty()) {
                warn(e.cells[i].line, e.cells[i].col,
                     "unknown column heading '" + e.cells[i].text + "': its cells go into the description");
              }
            }
          }
          afterTable = true;
          ++tables_;
          break;
        case TableEvent::Kind::Row:
          row(e, roles, headingCells);
          break;
      }
    }
    if (tables_ == 0) {
      err_ << path_
           << ": error: no table found (expected a heading row such as '命令 | 名称 | 单位 | 类型 | 说明', "
           << "'Address<TAB>Name<TAB>Type' or, in pdftotext -layout text, 'Class  Subclass  Address  Name  "
              "Type ...')\n";
      return 1;
    }
    uniqueIdentifiers();
    write();
    return 0;
  }

  std::ostream* out = nullptr;

 private:
  void warn(int line, int col, const std::string& msg) {
    err_ << path_ << ":" << line << ":" << col << ": warning: " << msg << "\n";
  }

  // Repairs a type cell damaged by PDF text extraction; records what changed.
  std::string fixType(std::string t, int line, int col, Imported& e) {
    const std::string original = t;
    std::string compact;
    for (char c : t) {
      if (c != ' ') compact += c;
    }
    if (compact.empty() || compact == "-" || compact == "—") return "none";
    if (parseType(compact)) return compact;
    if (auto block = cells::blockForWideHex(compact)) {
      warn(line, col,
           "type '" + original + "' is a " + block->substr(1) + "-byte hex block; written " + *block);
      e.notes.push_back("import: type '" + original + "' written " + *block);
      return *block;
    }
    // Take the last whitespace-separated token that is a type code ("l H2" -> H2).
    std::istringstream in(t);
    std::string tok, last;
    while (in >> tok) {
      if (parseType(tok)) last = tok;
    }
    std::string fixed = last;
    // OCR reads 'I' as '1' or 'l': "12" -> I2, "l4" -> I4.
    if (fixed.empty() && compact.size() == 2 && (compact[0] == '1' || compact[0] == 'l') &&
        (compact[1] == '1' || compact[1] == '2' || compact[1] == '4')) {
      fixed = std::string("I") + compact[1];
    }
    if (fixed.empty()) {
      warn(line, col,
           "type '" + original + "' is not a TI type code; kept as written (check will report it)");
      return compact;
    }
    warn(line, col, "type '" + original + "' read as " + fixed + " (text-extraction damage)");
    e.notes.push_back("import: type '" + original + "' read as " + fixed);
    return fixed;
  }

  // A 1-byte scalar type whose description says the value has 16 (or 32) bits takes that width.
  std::string widthFromDescription(const std::string& type, const std::string& description, int line, int col,
                                   Imported& e) {
    auto t = parseType(type);
    if (!t || !t->scalar() || t->base == TypeInfo::Base::Float) return type;
    const StatedWidth said = statedWidth(description);
    if (said.bits == 0 || said.bits == t->size() * 8) return type;
    const std::string fixed = std::string(1, type[0]) + std::to_string(said.bits / 8);
    if (!parseType(fixed)) return type;
    const std::string& stated = said.text;
    warn(line, col,
         "type " + type + " has " + std::to_string(t->size() * 8) + " bits but the description says " +
             stated + "; using " + fixed);
    e.notes.push_back("import: table type " + type + " contradicts its description (" + stated + "); used " +
                      fixed);
    return fixed;
  }

  // The type of a row: a TI code, the fields of one payload, words with a size, or the repairs of fixType.
  std::string typeOf(const RowCells& c, const std::string& typeCell, Imported& e) {
    const int line = c.line(Role::Type), col = c.col(Role::Type);
    const std::string about = c.get(Role::Data) + " " + c.get(Role::Description);
    const bool bigEndian =
        about.find("Big-Endian") != std::string::npos || about.find("big-endian") != std::string::npos;
    if (auto fields = cells::fieldsType(typeCell, bigEndian)) {
      e.notes.push_back("import: payload fields " + typeCell + (bigEndian ? " (big-endian)" : "") +
                        " read as " + *fields);
      return *fields;
    }
    if (parseType(typeCell)) return typeCell;
    if (c.has(Role::Format) && cells::number(c.get(Role::Format)).empty()) {
      e.notes.push_back("import: no data format in the table, so no data");
      return "none";  // BQ4050 MAC: Format "—" (a command that carries no data)
    }
    if (auto words = cells::typeFromWords(typeCell, c.get(Role::Format), c.get(Role::Size))) {
      e.notes.push_back("import: type " + *words + " from '" + typeCell +
                        (c.get(Role::Format).empty() ? "" : "', format '" + c.get(Role::Format)) +
                        (c.get(Role::Size).empty() ? "" : "', size " + c.get(Role::Size)) + "'");
      return *words;
    }
    if (typeCell.empty() || cells::number(typeCell).empty()) {
      if (e.kind->kind == EntryKind::Register) {
        e.comments.push_back("type is not in the table: 'U1' assumed (registers are one byte)");
        return "U1";
      }
      return "none";
    }
    return fixType(typeCell, line, col, e);
  }

  // Unit cell -> unit and scale keys.
  void unit(const RowCells& c, Imported& e) {
    const std::string cell(scan::trimmed(c.get(Role::Unit)));
    const cells::Unit u = cells::unit(cell);
    if (!u.understood) {
      warn(c.line(Role::Unit), c.col(Role::Unit),
           "unit '" + cell + "' is not a known unit; left out (recorded in notes)");
      e.notes.push_back("import: unit '" + cell + "' not recognised");
      return;
    }
    if (u.unit.empty()) return;
    e.keys.emplace_back("unit", u.unit);
    if (!u.scale.empty()) e.keys.emplace_back("scale", u.scale);
  }

  const KindInfo* kindOf(const RowCells& c, const std::string& digits) const {
    if (!opts_.kind.empty()) return findKind(opts_.kind);
    if (c.has(Role::Category)) return kindByYamlKey(kinds_->memory);
    if (digits.empty()) return nullptr;
    return kindByYamlKey(digits.size() <= 2 ? kinds_->byteCodes : kinds_->wordCodes);
  }

  void row(const TableEvent& r, const std::vector<Role>& roles, const std::vector<TableCell>& headings) {
    const RowCells c(r, roles, headings);
    for (const TableCell* extra : c.beyondHeadings)
      warn(extra->line, extra->col,
           "more cells than headings; '" + extra->text + "' goes into the description");
    Imported e;
    e.line = r.line;

    // Kind, from the address's digits or the class column.
    const std::string addrText(scan::trimmed(c.get(Role::Address)));
    const std::optional<AddressCell> address = addressCell(addrText);
    const bool hasAddr = address.has_value();
    e.kind = kindOf(c, hasAddr ? address->first : "");
    if (c.has(Role::Address) && !hasAddr) {
      warn(r.line, c.col(Role::Address), "'" + addrText + "' is not a hex address; row skipped");
      skipped_.push_back(r.line);
      return;
    }
    if (!e.kind) {
      warn(r.line, 1,
           "cannot tell what kind of entry this row is (no address, no class column); row skipped");
      skipped_.push_back(r.line);
      return;
    }

    // Name.
    std::string name = cells::name(c.get(Role::Name));
    const std::string english = cells::name(c.get(Role::EnglishName));
    std::string translated;
    if (!english.empty() && isAscii(english)) {
      if (!isAscii(name)) e.comments.push_back("name in the table: " + name);
      name = english;
    } else if (!isAscii(name)) {
      if (translateName(name, translated)) {
        e.comments.push_back("name in the table: " + name);
        e.notes.push_back("import: name translated from '" + name + "'");
        name = translated;
      } else {
        warn(r.line, c.col(Role::Name),
             "cannot translate name '" + name +
                 "' (not in the glossary); kept as is: replace it with the English TRM name");
        e.comments.push_back("TODO: replace with the English TRM name; '" + name +
                             "' is not in the glossary");
      }
    }
    if (const std::vector<std::string> run = runNames(name); !run.empty()) {
      e.notes.push_back("import: one of the registers '" + name + "'");
      run_.assign(run.begin() + 1, run.end());
      name = run.front();
    } else if (name.empty() && !run_.empty()) {
      e.notes.push_back("import: name from the run of registers above");
      name = run_.front();
      run_.erase(run_.begin());
    } else {
      run_.clear();
    }
    if (name.empty()) {
      warn(r.line, 1, "row has no name; row skipped");
      skipped_.push_back(r.line);
      return;
    }
    e.keys.emplace_back("name", name);

    // Address.
    std::string addr, span;
    if (hasAddr) {
      addr = addressText(address->first, e.kind->addrDigits);
      if (!address->last.empty() && addr.size() <= 10) {
        const std::string last = addressText(address->last, e.kind->addrDigits);
        const auto lo = std::stoull(addr.substr(2), nullptr, 16);
        const auto hi = last.size() <= 10 ? std::stoull(last.substr(2), nullptr, 16) : 0;
        if (e.kind->allowSpan && hi > lo) {
          span = hexAddress(hi - lo + 1);
          e.notes.push_back("import: codes " + addr + ".." + last);
        } else {
          warn(r.line, c.col(Role::Address),
               "'" + addrText + "' is a range; " + std::string(e.kind->listName) +
                   " entries have no span: the first address is used");
        }
      }
    }
    e.category = translateOr(cells::name(c.get(Role::Category)));
    e.subcategory = translateOr(cells::name(c.get(Role::Subcategory)));
    if (const Entry* known = lookup(*e.kind, name, e.category, e.subcategory)) {
      if (addr.empty()) {
        addr = hexAddress(*known->addr, e.kind->addrDigits);
        e.comments.push_back("address from " + displayPath(mapSources_.path(known->loc.file)) + ":" +
                             std::to_string(known->loc.line));
      } else if (addr.size() <= 10 && std::stoull(addr.substr(2), nullptr, 16) != *known->addr) {
        warn(r.line, c.col(Role::Address),
             "address " + addr + " of '" + name + "' differs from the map (" +
                 hexAddress(*known->addr, e.kind->addrDigits) + " at " +
                 displayPath(mapSources_.path(known->loc.file)) + ":" + std::to_string(known->loc.line) +
                 ")");
      }
      if (known->id.present) {
        e.keys.emplace_back("id", known->id.value);
        e.idFromMap = true;
      }
    }
    if (addr.empty() && !mentions_.empty()) {
      // TI's app notes often give a data-memory address in the sentence before a one-row table ("RAM 地址
      // 0x9261 返回的值为 0x88"); the nearest such mention is the best evidence the text offers.
      const Mention m = mentions_.back();
      mentions_.pop_back();
      addr = m.address;
      warn(r.line, 1,
           "address " + addr + " of '" + name + "' taken from the text above the table (line " +
               std::to_string(m.line) + "); check it against the TRM");
      e.notes.push_back("import: address from the text at line " + std::to_string(m.line));
    }
    if (addr.empty()) {
      warn(r.line, 1,
           "no address for '" + name + "'" +
               (opts_.mapFiles.empty() ? " (pass --map with the family's YAML to look it up)"
                                       : " and none in the --map files") +
               "; written as TODO");
      addr = "TODO";
    }
    e.keys.emplace_back("addr", addr);
    if (!span.empty()) e.keys.emplace_back("span", span);

    // Type.
    std::string description = c.get(Role::Description);
    if (!c.extra.empty()) description.append(description.empty() ? "" : " ").append(c.extra);
    if (!c.get(Role::Data).empty()) description = "Data: " + c.get(Role::Data) + ". " + description;
    description = std::string(scan::trimmed(description));
    std::string typeCell(scan::trimmed(c.get(Role::Type)));
    std::string accessCell = c.get(Role::Access);
    if (!c.has(Role::Access) && cells::access(typeCell) && !parseType(typeCell)) {
      accessCell = typeCell;  // register tables print R/RW in their "Type" column
      typeCell.clear();
    }
    std::string type = typeOf(c, typeCell, e);
    // Registers are one byte whatever width the reading they are part of has ("16-bit ... read HI first").
    if (e.kind->kind != EntryKind::Register)
      type = widthFromDescription(type, description, c.line(Role::Type), c.col(Role::Type), e);
    e.keys.emplace_back("type", type);

    // Access.
    std::optional<std::string> access = cells::access(accessCell);
    if (access && e.kind->kind == EntryKind::DataMemory) {
      e.notes.push_back("import: table access '" + accessCell + "'; data memory is config_update");
      access = "config_update";
    } else if (access && type == "none" && *access != "cmd") {
      e.notes.push_back("import: table access '" + accessCell + "'; no data, so cmd");
      access = "cmd";
    }
    if (!access) {
      if (!scan::trimmed(accessCell).empty() && !cells::number(accessCell).empty())
        warn(c.line(Role::Access), c.col(Role::Access), "access '" + accessCell + "' not understood");
      access = e.kind->kind == EntryKind::DataMemory  ? "config_update"
               : type == "none"                       ? "cmd"
               : e.kind->kind == EntryKind::DataFlash ? "rw"
                                                      : "r";
      e.comments.push_back("access is not in the table: '" + *access + "' assumed; check the TRM");
    }
    e.keys.emplace_back("access", *access);

    unit(c, e);
    for (auto [role, key] :
         {std::pair{Role::Min, "min"}, std::pair{Role::Max, "max"}, std::pair{Role::Default, "default"}}) {
      const std::string v = cells::number(c.get(role));
      if (v.empty()) continue;
      if (!parseNumber(v)) {
        warn(c.line(role), c.col(role),
             std::string(key) + " '" + c.get(role) + "' is not a number; recorded in notes");
        e.notes.push_back(std::string("import: ") + key + " '" + c.get(role) + "'");
        continue;
      }
      e.keys.emplace_back(key, v);
    }
    if (e.kind->allowCategory) {
      if (!e.category.empty()) e.keys.emplace_back("category", e.category);
      if (!e.subcategory.empty()) e.keys.emplace_back("subcategory", e.subcategory);
    }
    e.keys.emplace_back("description",
                        description.empty() ? "Imported; the table gives no description." : description);
    e.keys.emplace_back("source", opts_.source);
    e.notes.insert(e.notes.begin(), "imported from " + displayPath(path_) + ":" + std::to_string(r.line));
    std::string notes;
    for (const std::string& n : e.notes)
      notes.append(notes.empty() ? "" : "; ").append(n);
    e.keys.emplace_back("notes", notes);
    entries_.push_back(std::move(e));
  }

  static std::string translateOr(const std::string& s) {
    std::string t;
    if (!s.empty() && !isAscii(s) && translateName(s, t)) return t;
    return s;
  }

  // The entry of the --map files this row describes: same kind and name (ignoring case, '_', ' '), and for
  // data memory the same class/subclass when several share the name.
  const Entry* lookup(const KindInfo& kind, const std::string& name, const std::string& cat,
                      const std::string& sub) const {
    std::vector<const Entry*> hits;
    for (const Family& fam : map_.families) {
      for (const Entry& e : fam.entries) {
        if (e.kind->kind == kind.kind && e.addr && lookupKey(e.name.value) == lookupKey(name))
          hits.push_back(&e);
      }
    }
    if (hits.size() > 1 && !cat.empty()) {
      std::vector<const Entry*> narrowed;
      for (const Entry* e : hits) {
        if (lookupKey(e->category.value) == lookupKey(cat) &&
            (sub.empty() || lookupKey(e->subcategory.value) == lookupKey(sub))) {
          narrowed.push_back(e);
        }
      }
      hits = narrowed;
    }
    return hits.size() == 1 ? hits.front() : nullptr;
  }

  // A TRM name that repeats in several subclasses ("Threshold", "Delay") derives the same identifier; the
  // later ones get an `id:` made of their subclass (or class and subclass) and name, with a comment. Ids
  // taken from the --map files are kept.
  void uniqueIdentifiers() {
    std::map<std::string, int> uses;  // namespace::identifier
    const auto key = [](const Imported& e, const std::string& id) {
      return std::string(e.kind->ns) + "::" + id;
    };
    const auto idOf = [](const Imported& e) {
      for (const auto& [k, v] : e.keys) {
        if (k == "id") return v;
      }
      return pascalCase(e.keys.front().second);
    };
    for (const Imported& e : entries_)
      ++uses[key(e, idOf(e))];
    std::set<std::string> taken;
    for (Imported& e : entries_) {
      const std::string id = idOf(e);
      if (e.idFromMap || uses[key(e, id)] < 2 || taken.insert(key(e, id)).second) continue;
      for (const std::string& candidate :
           {pascalCase(e.subcategory + " " + e.keys.front().second),
            pascalCase(e.category + " " + e.subcategory + " " + e.keys.front().second)}) {
        if (!isIdentifier(candidate) || uses.count(key(e, candidate)) ||
            !taken.insert(key(e, candidate)).second)
          continue;
        e.keys.insert(e.keys.begin() + 1, {"id", candidate});
        e.comments.push_back("id: '" + id + "' is taken by an entry above; made unique by import");
        break;
      }
    }
  }

  // A value as a YAML scalar: plain when that reads back the same, else double-quoted with escapes (control
  // characters as \xNN), so any cell text gives well-formed YAML.
  static std::string yamlScalar(const std::string& value) {
    const std::string v = capped(value);
    bool plain = !v.empty() && isAscii(v);
    static const std::string indicators = "-?:,[]{}#&*!|>'\"%@`";
    if (plain && indicators.find(v[0]) != std::string::npos &&
        !(v[0] == '-' && v.size() > 1 && scan::isDigit(v[1]))) {
      plain = false;
    }
    if (plain && (v.find(": ") != std::string::npos || v.find(" #") != std::string::npos || v.back() == ' ' ||
                  v.back() == ':' || v.front() == ' ')) {
      plain = false;
    }
    for (char ch : v)
      plain = plain && static_cast<unsigned char>(ch) >= 0x20 && ch != 0x7F;
    if (plain) return v;
    std::string out = "\"";
    for (char ch : v) {
      const auto u = static_cast<unsigned char>(ch);
      if (ch == '"' || ch == '\\') {
        out += '\\';
        out += ch;
      } else if (ch == '\t') {
        out += "\\t";
      } else if (u < 0x20 || u == 0x7F) {
        static const char hex[] = "0123456789ABCDEF";
        out += "\\x";
        out += hex[u >> 4];
        out += hex[u & 0xF];
      } else {
        out += ch;
      }
    }
    return out + "\"";
  }

  // A comment line's text without control characters (they would end or garble the line).
  static std::string commentText(const std::string& s) {
    std::string out = capped(s);
    for (char& ch : out) {
      if (static_cast<unsigned char>(ch) < 0x20 || ch == 0x7F) ch = ' ';
    }
    return out;
  }

  void write() {
    std::ostream& o = *out;
    o << "# Generated by `regmapgen import` from " << commentText(displayPath(path_))
      << ". Review every entry before merging it\n"
      << "# into regmaps/<family>/: TI's tables do not give access, and 'source' stays 'unverified' until "
         "the\n"
      << "# values are checked against the TRM (or pass --source with the document's literature number).\n"
      << "family: " << yamlScalar(family()) << "\n";
    for (const KindInfo& k : kinds()) {
      bool any = false;
      for (const Imported& e : entries_) {
        if (e.kind != &k) continue;
        if (!any) o << k.yamlKey << ":\n";
        any = true;
        for (const std::string& c : e.comments)
          o << "  # " << commentText(c) << "\n";
        bool first = true;
        for (const auto& [key, value] : e.keys) {
          o << (first ? "  - " : "    ") << key << ": " << yamlScalar(value) << "\n";
          first = false;
        }
      }
    }
    for (int line : skipped_)
      o << "# skipped: line " << line << " of " << commentText(displayPath(path_)) << " (see warnings)\n";
  }

  std::string path_;
  const ImportOptions& opts_;
  std::ostream& err_;
  const FamilyKinds* kinds_ = nullptr;
  Sources mapSources_;
  Model map_;
  std::vector<Imported> entries_;
  std::vector<int> skipped_;
  std::vector<std::string> run_;  // names left of a run "A through B"
  struct Mention {
    std::string address;
    int line;
  };
  std::vector<Mention> mentions_;  // addresses named in the prose since the last table, oldest first
};

}  // namespace

int runImport(const std::string& path, const std::string& text, const ImportOptions& opts, std::ostream& out,
              std::ostream& err) {
  Importer imp(path, opts, err);
  imp.out = &out;
  if (!opts.kind.empty() && !findKind(opts.kind)) {
    err << "regmapgen: error: unknown --kind '" << opts.kind << "'\n";
    return 2;
  }
  if (!imp.loadMaps()) return 1;
  return imp.run(text);
}

}  // namespace regmapgen
