#include "import/import.hpp"

#include <algorithm>
#include <map>
#include <optional>
#include <ostream>
#include <set>
#include <sstream>

#include "diag/diag.hpp"
#include "emit/emit.hpp"
#include "import/bit_fields.hpp"
#include "import/captions.hpp"
#include "import/cells.hpp"
#include "import/furniture.hpp"
#include "import/row_parts.hpp"
#include "import/table_reader.hpp"
#include "model/model.hpp"
#include "model/names.hpp"
#include "model/schema.hpp"
#include "text/scan.hpp"

namespace regmapgen {

namespace {

using rows::RowCells;

// One entry as imported: the values of its YAML keys ("" for a key left out).
struct Imported {
  const KindInfo* kind = nullptr;
  int line = 0;
  std::vector<std::string> comments;  // shown above the entry
  std::string name, id, addr, span, type, access, unit, scale, min, max, dflt, fieldset;
  std::string category, subcategory, description;
  std::vector<std::string> notes;
  bool idFromMap = false;
  bool fromTableAddress = false;  // the table gave the address
  bool merged = false;            // folded into another entry of the same setting (not written)
  std::string table;              // "Table 13-37" or "the table at p199:12", for messages
  std::optional<std::pair<std::string, int>> mention;  // an address the text above named, and its line
};

struct ImportedField {
  std::string name, bits, description;
  int line = 0;
};

struct ImportedFieldset {
  std::string registerName;  // as the caption names it: "Safety Alert A"
  std::string name;          // PascalCase: SafetyAlertA
  int width = 0;
  int line = 0;
  int maxBit = 0;
  std::string table;
  std::vector<ImportedField> fields;
};

// A table of the text, as import uses it.
struct TableUse {
  enum class As { Entries, Fields, Skipped };
  As as = As::Skipped;
  std::string label;         // "Table 12-1" or "the table at p122:3"
  std::string registerName;  // bit-field tables: the register
  int line = 0;
  int rows = 0;
  bool setting = false;  // one setting's table (no address column, under its own section heading)
};

// Numbers compare by value ("0x0A" is 10), everything else as text.
bool sameValue(const std::string& a, const std::string& b) {
  if (a == b) return true;
  const auto x = parseNumber(a), y = parseNumber(b);
  if (!x || !y) return false;
  if (x->isInteger && y->isInteger) return x->integer == y->integer;
  return x->real == y->real;
}

// A value as a YAML scalar: plain when that reads back the same, else double-quoted with escapes (control
// characters as \xNN), so any cell text gives well-formed YAML.
std::string yamlScalar(const std::string& value) {
  const std::string v = rows::capped(value);
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
std::string commentText(const std::string& s) {
  std::string out = rows::capped(s);
  for (char& ch : out) {
    if (static_cast<unsigned char>(ch) < 0x20 || ch == 0x7F) ch = ' ';
  }
  return out;
}

std::string translateOr(const std::string& s) {
  std::string t;
  if (!s.empty() && !isAscii(s) && translateName(s, t)) return t;
  return s;
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
    tables_ = readTables(text);
    if (!tables_.errors.empty()) {
      for (const auto& e : tables_.errors)
        err_ << where(e.line, e.col) << ": error: " << e.message << "\n";
      err_ << "regmapgen: error: " << path_ << " is not a table text; nothing imported\n";
      return 1;
    }
    kinds_ = &rows::kindsOf(family());
    // A document with register summaries ("Table 12-1. Direct Commands Table") is read from those, its
    // per-setting tables and its bit-field tables; every other table of it (examples, one feature's
    // commands) repeats them and is left out. A text without such captions is read whole.
    for (const TableEvent& e : tables_.events)
      summaries_ = summaries_ || (e.kind == TableEvent::Kind::Heading && isSummaryCaption(e.caption));

    std::vector<Role> roles;
    std::vector<TableCell> headingCells;
    bool afterTable = false;
    for (const TableEvent& e : tables_.events) {
      switch (e.kind) {
        case TableEvent::Kind::Prose:
          flushRow();
          if (afterTable || isSectionHeading(e.text)) mentions_.clear();  // a new context
          afterTable = false;
          for (const std::string& a : rows::addressMentions(e.text))
            mentions_.push_back({a, e.line});
          break;
        case TableEvent::Kind::Heading:
          if (!e.continued) flushRow();  // a row may go on after a page break (MANU_DATA 0..20, 21..31)
          roles = e.roles;
          headingCells = e.cells;
          if (!e.continued || uses_.empty()) beginTable(e);
          afterTable = true;
          break;
        case TableEvent::Kind::Row:
          takeRow(e, roles, headingCells);
          break;
      }
    }
    flushRow();
    const bool anyUsed = std::any_of(uses_.begin(), uses_.end(), [](const TableUse& u) {
      return u.as != TableUse::As::Skipped && u.rows > 0;
    });
    if (!anyUsed) {
      flushWarnings();
      err_ << path_ << ": no register table found";
      if (!uses_.empty()) err_ << " (" << uses_.size() << " other table(s): " << skippedList() << ")";
      err_ << "; nothing imported. A register table has a heading row such as 'Command  Name  Type ...', "
              "'Class  Subclass  Address  Name  Type ...' or '命令 | 名称 | 类型 | 说明'.\n";
      return kNoTable;
    }
    resolveAddresses();
    attachFieldsets();
    uniqueIdentifiers();
    write();
    flushWarnings();
    summary();
    return 0;
  }

  std::ostream* out = nullptr;
  static constexpr int kNoTable = kImportFoundNoTable;

 private:
  // ---- positions and warnings ----

  // "file:line:col" for a text; for a PDF "file:pPAGE:LINE:COL", LINE counted on the page (as `pdftotext
  // -layout -f PAGE -l PAGE` prints it).
  std::string where(int line, int col = 0) const {
    std::string s = path_ + ":";
    if (opts_.firstPage > 0) {
      const int page = pageOf(tables_, line);
      s += "p" + std::to_string(opts_.firstPage + page) + ":" +
           std::to_string(line - tables_.pageStarts[static_cast<std::size_t>(page)] + 1);
    } else {
      s += std::to_string(line);
    }
    if (col > 0) s += ":" + std::to_string(col);
    return s;
  }

  // "p199:12" (a PDF) or "line 4012" (a text): where a table or row is, inside a message.
  std::string at(int line) const {
    if (opts_.firstPage <= 0) return "line " + std::to_string(line);
    const int page = pageOf(tables_, line);
    return "p" + std::to_string(opts_.firstPage + page) + ":" +
           std::to_string(line - tables_.pageStarts[static_cast<std::size_t>(page)] + 1);
  }

  // Warnings are printed in the order of the text, whichever step found them.
  void warn(int line, int col, const std::string& msg) {
    warnings_.push_back({line, col, warnings_.size(), msg});
  }

  void flushWarnings() {
    std::stable_sort(warnings_.begin(), warnings_.end(), [](const Warning& a, const Warning& b) {
      return std::tie(a.line, a.col, a.seq) < std::tie(b.line, b.col, b.seq);
    });
    for (const Warning& w : warnings_)
      err_ << where(w.line, w.col) << ": warning: " << w.message << "\n";
    warnings_.clear();
  }

  // ---- tables ----

  void beginTable(const TableEvent& e) {
    TableUse u;
    u.line = e.line;
    const std::string number = captionNumber(e.caption);
    u.label = number.empty() ? "the table at " + at(e.line) : "Table " + number;
    const auto has = [&](Role r) { return std::find(e.roles.begin(), e.roles.end(), r) != e.roles.end(); };
    const bool itemTable = e.caption.empty() && !e.section.empty() && e.proseSinceSection <= 6;
    if (has(Role::Bit) && has(Role::Field)) {
      u.registerName = fieldTableRegister(e.caption, e.section);
      u.as = u.registerName.empty() ? TableUse::As::Skipped : TableUse::As::Fields;
    } else if (!summaries_ || isSummaryCaption(e.caption) || itemTable) {
      u.as = TableUse::As::Entries;
      u.setting = !has(Role::Address) && itemTable;
    }
    if (u.as != TableUse::As::Skipped) {
      for (std::size_t i = 0; i < e.roles.size(); ++i) {
        if (e.roles[i] == Role::Unknown && !e.cells[i].text.empty()) {
          warn(e.cells[i].line, e.cells[i].col,
               "unknown column heading '" + e.cells[i].text + "': its cells go into the description");
        }
      }
    }
    uses_.push_back(std::move(u));
  }

  TableUse& table() { return uses_.back(); }

  // Rows of one table with the same address are one entry whose cells TI printed in two parts (a payload
  // continued on the next page: MANU_DATA offsets 0..20 and 21..31): their cells are joined.
  void takeRow(const TableEvent& r, const std::vector<Role>& roles, const std::vector<TableCell>& headings) {
    if (uses_.empty() || table().as == TableUse::As::Skipped) return;
    ++table().rows;
    if (table().as == TableUse::As::Fields) {
      fieldRow(r, roles);
      return;
    }
    const auto addressOf = [&](const TableEvent& row) {
      for (std::size_t i = 0; i < row.cells.size() && i < roles.size(); ++i) {
        if (roles[i] == Role::Address) return std::string(scan::trimmed(row.cells[i].text));
      }
      return std::string();
    };
    if (pending_ && pendingTable_ == uses_.size() && !addressOf(r).empty() &&
        addressOf(r) == addressOf(*pending_)) {
      for (std::size_t i = 0; i < r.cells.size() && i < pending_->cells.size(); ++i) {
        if (i < roles.size() &&
            (roles[i] == Role::Address || roles[i] == Role::Name || roles[i] == Role::Access))
          continue;
        std::string& to = pending_->cells[i].text;
        if (!r.cells[i].text.empty()) to.append(to.empty() ? "" : " ").append(r.cells[i].text);
      }
      return;
    }
    flushRow();
    pending_ = r;
    pendingRoles_ = roles;
    pendingHeadings_ = headings;
    pendingTable_ = uses_.size();
  }

  void flushRow() {
    if (!pending_) return;
    const TableEvent r = std::move(*pending_);
    pending_.reset();
    row(r, pendingRoles_, pendingHeadings_);
  }

  // "Other tables: Table 4-1 (p16:3), ..." of the tables left out.
  std::string skippedList() const {
    std::string s;
    int n = 0;
    for (const TableUse& u : uses_) {
      if (u.as != TableUse::As::Skipped) continue;
      if (++n > 12) {
        s += ", ...";
        break;
      }
      s += (s.empty() ? "" : ", ") + u.label + (u.label.starts_with("Table") ? " (" + at(u.line) + ")" : "");
    }
    return s;
  }

  // One line on what was read: the tables, the entries by kind, the fieldsets, what was left out.
  void summary() {
    std::map<std::string, int> perKind;
    int written = 0;
    for (const Imported& e : entries_) {
      if (e.merged) continue;
      ++perKind[std::string(e.kind->yamlKey)];
      ++written;
    }
    int registerTables = 0, settingTables = 0, fieldTables = 0, skipped = 0;
    std::string names;
    for (const TableUse& u : uses_) {
      if (u.as == TableUse::As::Skipped) {
        ++skipped;
      } else if (u.as == TableUse::As::Fields) {
        ++fieldTables;
      } else if (u.setting) {
        ++settingTables;
      } else {
        ++registerTables;
        if (u.label.starts_with("Table ")) names += (names.empty() ? "" : ", ") + u.label.substr(6);
      }
    }
    err_ << "regmapgen: " << path_ << ": " << registerTables << " register table(s)"
         << (names.empty() ? "" : " (Table " + names + ")");
    if (settingTables) err_ << ", " << settingTables << " setting table(s)";
    if (fieldTables) err_ << ", " << fieldTables << " bit-field table(s)";
    err_ << " -> " << written << " entries (";
    bool first = true;
    for (const auto& [kind, n] : perKind) {
      err_ << (first ? "" : ", ") << n << " " << kind;
      first = false;
    }
    err_ << ")";
    if (!fieldsets_.empty()) err_ << ", " << fieldsets_.size() << " fieldsets";
    if (!skipped_.empty()) err_ << "; " << skipped_.size() << " row(s) not placed (see the warnings)";
    err_ << "\n";
    if (skipped) err_ << "regmapgen: not register tables, left out: " << skippedList() << "\n";
  }

  // ---- bit-field tables ----

  void fieldRow(const TableEvent& r, const std::vector<Role>& roles) {
    std::string bitCell, fieldCell, description;
    int bitCol = 1;
    for (std::size_t i = 0; i < r.cells.size() && i < roles.size(); ++i) {
      if (roles[i] == Role::Bit) {
        bitCell = r.cells[i].text;
        bitCol = r.cells[i].col;
      } else if (roles[i] == Role::Field) {
        fieldCell = r.cells[i].text;
      } else if (roles[i] == Role::Description) {
        description = r.cells[i].text;
      }
    }
    const auto bits = bit_fields::bits(bitCell);
    if (!bits) {
      warn(r.line, bitCol,
           "bit '" + bitCell + "' of '" + table().registerName + "' is not a bit or a range; row skipped");
      skipped_.push_back(r.line);
      return;
    }
    if (bit_fields::reserved(fieldCell)) return;
    const std::string name = bit_fields::name(fieldCell, *bits);
    const auto [known, fresh] =
        fieldsetByRegister_.emplace(lookupKey(table().registerName), fieldsets_.size());
    if (fresh) {
      fieldsets_.push_back(
          {table().registerName, pascalCase(table().registerName), 0, r.line, 0, table().label, {}});
    }
    ImportedFieldset* fs = &fieldsets_[known->second];
    if (!fresh && fs->table != table().label) {
      // A second table of the same register (SLUUBY2B prints PF Status A in 12.2 and again in 12.5):
      // it must agree.
      for (const ImportedField& f : fs->fields) {
        if (f.bits == bits->text && f.name != name) {
          warn(r.line, bitCol,
               "'" + table().registerName + "' bit " + bits->text + " is '" + name + "' here but '" + f.name +
                   "' in " + fs->table + " (" + at(f.line) + "); the first is kept");
        }
      }
      return;
    }
    fs->maxBit = std::max(fs->maxBit, bits->msb);
    fs->fields.push_back({name, bits->text, bit_fields::meaning(description), r.line});
  }

  // Each fieldset goes to the entries named like its register ("Safety Alert A", "Manufacturing Status" ->
  // MANUFACTURINGSTATUS); its width is theirs.
  void attachFieldsets() {
    std::multimap<std::string, Imported*> byName;
    for (Imported& e : entries_) {
      if (!e.merged) byName.emplace(lookupKey(e.name), &e);
    }
    for (ImportedFieldset& fs : fieldsets_) {
      int users = 0;
      for (auto [it, end] = byName.equal_range(lookupKey(fs.registerName)); it != end; ++it) {
        Imported& e = *it->second;
        const auto t = parseType(e.type);
        if (!t || !t->integer()) continue;
        e.fieldset = fs.name;
        fs.width = t->size() * 8;
        ++users;
      }
      if (users == 0) {
        warn(fs.line, 1,
             "the bit fields of '" + fs.registerName + "' (" + fs.table +
                 ") belong to no imported entry of that name; written as a fieldset nothing uses");
      }
      if (fs.width == 0) fs.width = fs.maxBit < 8 ? 8 : fs.maxBit < 16 ? 16 : 32;
    }
  }
  // ---- entry rows ----

  // "S20+1": a string of 20 characters after its length byte (the BQ4050 TRM's spelling), 21 bytes: S21.
  static std::optional<std::string> lengthPrefixedString(const std::string& compact,
                                                         const std::string& original, Imported& e) {
    const std::size_t plus = compact.find('+');
    if (compact.size() < 4 || compact[0] != 'S' || plus == std::string::npos ||
        compact.substr(plus) != "+1" || plus < 2 || plus > 3 ||
        !scan::all(std::string_view(compact).substr(1, plus - 1), scan::isDigit))
      return std::nullopt;
    const std::string code = "S" + std::to_string(std::stoi(compact.substr(1, plus - 1)) + 1);
    if (!parseType(code)) return std::nullopt;
    e.notes.push_back("import: type '" + original + "' (a length byte and " + compact.substr(1, plus - 1) +
                      " characters) written " + code);
    return code;
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
    if (auto text = lengthPrefixedString(compact, original, e)) return *text;
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
    const rows::StatedWidth said = rows::statedWidth(description);
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
    if (auto text = lengthPrefixedString(typeCell, typeCell, e)) return *text;
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

  // Unit cell -> unit and scale.
  void unit(const RowCells& c, Imported& e) {
    const std::string cell(scan::trimmed(c.get(Role::Unit)));
    const cells::Unit u = cells::unit(cell);
    if (const std::string types = c.get(Role::Type); !u.understood && cells::fieldsType(types, false)) {
      // One unit per field of a payload (DASTATUS5: "— — mV mV userV 0.1 K ..."): the entry has no one unit.
      e.notes.push_back("import: field units '" + cell + "'");
      return;
    }
    if (!u.understood) {
      warn(c.line(Role::Unit), c.col(Role::Unit),
           "unit '" + cell + "' is not a known unit; left out (recorded in notes)");
      e.notes.push_back("import: unit '" + cell + "' not recognised");
      return;
    }
    e.unit = u.unit;
    e.scale = u.unit.empty() ? "" : u.scale;
  }

  const KindInfo* kindOf(const RowCells& c, const std::string& digits) const {
    if (!opts_.kind.empty()) return rows::findKind(opts_.kind);
    if (c.has(Role::Category)) return kindByYamlKey(kinds_->memory);
    if (digits.empty()) return nullptr;
    return kindByYamlKey(digits.size() <= 2 ? kinds_->byteCodes : kinds_->wordCodes);
  }

  void skip(int line, int col, const std::string& why) {
    warn(line, col, why + "; row skipped");
    skipped_.push_back(line);
  }

  void row(const TableEvent& r, const std::vector<Role>& roles, const std::vector<TableCell>& headings) {
    const RowCells c(r, roles, headings);
    for (const TableCell* extra : c.beyondHeadings)
      warn(extra->line, extra->col,
           "more cells than headings; '" + extra->text + "' goes into the description");
    Imported e;
    e.line = r.line;
    e.table = uses_.empty() ? std::string() : table().label;

    // Kind, from the address's digits or the class column.
    const std::string addrText(scan::trimmed(c.get(Role::Address)));
    const std::optional<rows::AddressCell> address = rows::addressCell(addrText);
    const bool hasAddr = address.has_value();
    e.kind = kindOf(c, hasAddr ? address->first : "");
    if (c.has(Role::Address) && !hasAddr)
      return skip(r.line, c.col(Role::Address), "'" + addrText + "' is not a hex address");
    if (!e.kind)
      return skip(r.line, 1, "cannot tell what kind of entry this row is (no address, no class column)");

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
    if (const std::vector<std::string> run = rows::runNames(name); !run.empty()) {
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
    if (name.empty()) return skip(r.line, 1, "row has no name");
    e.name = name;

    // Address.
    if (hasAddr) {
      e.addr = rows::addressText(address->first, e.kind->addrDigits);
      e.fromTableAddress = true;
      if (!address->last.empty() && e.addr.size() <= 10) {
        const std::string last = rows::addressText(address->last, e.kind->addrDigits);
        const auto lo = std::stoull(e.addr.substr(2), nullptr, 16);
        const auto hi = last.size() <= 10 ? std::stoull(last.substr(2), nullptr, 16) : 0;
        if (e.kind->allowSpan && hi > lo) {
          e.span = hexAddress(hi - lo + 1);
          e.notes.push_back("import: codes " + e.addr + ".." + last);
        } else {
          warn(r.line, c.col(Role::Address),
               "'" + addrText + "' is a range; " + std::string(e.kind->listName) +
                   " entries have no span: the first address is used");
        }
      }
    } else if (!mentions_.empty()) {
      // TI's app notes often give a data-memory address in the sentence before a one-row table ("RAM 地址
      // 0x9261 返回的值为 0x88"): the nearest such mention, used when nothing better is found.
      e.mention = std::make_pair(mentions_.back().address, mentions_.back().line);
      mentions_.pop_back();
    }
    e.category = translateOr(cells::name(c.get(Role::Category)));
    e.subcategory = translateOr(cells::name(c.get(Role::Subcategory)));

    // Type.
    std::string description = c.get(Role::Description);
    if (!c.extra.empty()) description.append(description.empty() ? "" : " ").append(c.extra);
    if (!c.get(Role::Data).empty()) description = "Data: " + c.get(Role::Data) + ". " + description;
    e.description = std::string(scan::trimmed(description));
    std::string typeCell(scan::trimmed(c.get(Role::Type)));
    std::string accessCell = c.get(Role::Access);
    if (!c.has(Role::Access) && cells::access(typeCell) && !parseType(typeCell)) {
      accessCell = typeCell;  // register tables print R/RW in their "Type" column
      typeCell.clear();
    }
    e.type = typeOf(c, typeCell, e);
    // Registers are one byte whatever width the reading they are part of has ("16-bit ... read HI first").
    if (e.kind->kind != EntryKind::Register)
      e.type = widthFromDescription(e.type, e.description, c.line(Role::Type), c.col(Role::Type), e);

    // Access.
    std::optional<std::string> access = cells::access(accessCell);
    if (access && e.kind->kind == EntryKind::DataMemory) {
      e.notes.push_back("import: table access '" + accessCell + "'; data memory is config_update");
      access = "config_update";
    } else if (access && e.type == "none" && *access != "cmd") {
      e.notes.push_back("import: table access '" + accessCell + "'; no data, so cmd");
      access = "cmd";
    }
    if (!access) {
      if (!scan::trimmed(accessCell).empty() && !cells::number(accessCell).empty())
        warn(c.line(Role::Access), c.col(Role::Access), "access '" + accessCell + "' not understood");
      access = e.kind->kind == EntryKind::DataMemory  ? "config_update"
               : e.type == "none"                     ? "cmd"
               : e.kind->kind == EntryKind::DataFlash ? "rw"
                                                      : "r";
      e.comments.push_back("access is not in the table: '" + *access + "' assumed; check the TRM");
    }
    e.access = *access;

    unit(c, e);
    const bool text = !e.type.empty() && e.type[0] == 'S';
    for (auto [role, key, value] :
         {std::tuple{Role::Min, "min", &e.min}, std::tuple{Role::Max, "max", &e.max},
          std::tuple{Role::Default, "default", &e.dflt}}) {
      std::string v = cells::number(c.get(role));
      if (v.empty()) continue;
      // "4400" over "6336" beside "mAh" over "10 mWh": a value for each capacity mode (BatteryMode[CAPM]);
      // the unit is the mAh one, so is the value.
      if (const std::string raw(scan::trimmed(c.get(role)));
          (e.unit == "mAh|10mWh" || e.unit == "mA|10mW") && raw.find(' ') != std::string::npos) {
        const std::string first = cells::number(raw.substr(0, raw.find(' ')));
        const std::string second = cells::number(raw.substr(raw.rfind(' ') + 1));
        if (parseNumber(first) && parseNumber(second)) {
          e.notes.push_back(std::string("import: ") + key + " " + first + " (CAPM = 0), " + second +
                            " (CAPM = 1)");
          v = first;
        }
      }
      if (!parseNumber(v)) {
        // A string's default ("Texas Inst.") is its text: kept in the notes without a warning.
        if (!text || role != Role::Default)
          warn(c.line(role), c.col(role),
               std::string(key) + " '" + c.get(role) + "' is not a number; recorded in notes");
        e.notes.push_back(std::string("import: ") + key + " '" + c.get(role) + "'");
        continue;
      }
      const auto t = parseType(e.type);
      const auto n = parseNumber(v);
      if (t && t->integer() && n->isInteger && (n->integer < t->minValue() || n->integer > t->maxValue())) {
        warn(c.line(role), c.col(role),
             std::string(key) + " " + v + " does not fit type " + e.type + " (" +
                 std::to_string(t->minValue()) + ".." + std::to_string(t->maxValue()) +
                 "); left out (recorded in notes)");
        e.notes.push_back(std::string("import: ") + key + " " + v + " does not fit " + e.type);
        continue;
      }
      *value = v;
    }
    // A default outside the table's own range is a misprint of one of them (SLUUAQ3A: Min Blow Fuse Voltage
    // 0..255, default 3500): named, and the default left to the notes.
    if (const auto lo = parseNumber(e.min), hi = parseNumber(e.max), d = parseNumber(e.dflt);
        d && ((lo && d->real < lo->real) || (hi && d->real > hi->real))) {
      warn(c.line(Role::Default), c.col(Role::Default),
           "default " + e.dflt + " is outside the table's range " + e.min + ".." + e.max +
               "; left out (recorded in notes)");
      e.notes.push_back("import: default " + e.dflt + " outside " + e.min + ".." + e.max);
      e.dflt.clear();
    }
    if (!e.kind->allowCategory) e.category.clear(), e.subcategory.clear();
    e.notes.insert(e.notes.begin(), "imported from " + displayPath(path_) + ":" +
                                        (opts_.firstPage > 0 ? at(r.line) : std::to_string(r.line)));
    entries_.push_back(std::move(e));
  }
  // ---- addresses, identifiers ----

  static std::string settingKey(const Imported& e) {
    return std::string(e.kind->yamlKey) + '\x1f' + lookupKey(e.category) + '\x1f' + lookupKey(e.subcategory) +
           '\x1f' + lookupKey(e.name);
  }

  // The same setting in two tables of one document (a setting's own table and the summary, the same code in
  // two summaries): one entry, the first table with an address giving it; every value the two tables give
  // differently is a warning that names both, and a value only the other gives is taken with a note.
  void fold(Imported& from, Imported& into) {
    from.merged = true;
    const std::string there = label(from), here = label(into);
    const auto shown = [](const std::string& v) { return v.empty() ? std::string("nothing") : v; };
    if (!from.type.empty() && !into.type.empty() && from.type != into.type) {
      // Different types: the two rows are not one setting (SLUUAQ3A prints Fuse Blow Timeout's table under
      // Min Blow Fuse Voltage's name), or one is misprinted; nothing is taken from the other.
      warn(from.line, 1,
           "'" + describe(into) + "': " + there + " gives type " + from.type + ", " + here + " gives " +
               into.type + "; " + into.table + "'s row is kept and nothing is taken from " + from.table);
      into.notes.push_back("import: " + there + " gives type " + from.type);
      return;
    }
    const std::pair<const char*, std::string Imported::*> values[] = {{"min", &Imported::min},
                                                                      {"max", &Imported::max},
                                                                      {"default", &Imported::dflt},
                                                                      {"unit", &Imported::unit},
                                                                      {"scale", &Imported::scale}};
    for (const auto& [what, member] : values) {
      const std::string& a = from.*member;
      std::string& b = into.*member;
      if (sameValue(a, b) || (a.empty() && std::string(what) != "scale"))
        continue;                                                            // silent is no disagreement
      if (std::string(what) == "scale" && from.unit != into.unit) continue;  // reported with the unit
      if (b.empty() && !a.empty()) {
        b = a;
        into.notes.push_back("import: " + std::string(what) + " from " + there);
        continue;
      }
      warn(from.line, 1,
           "'" + describe(into) + "': " + there + " gives " + what + " " + shown(a) + ", " + here +
               " gives " + shown(b) + "; " + into.table + "'s is kept");
      into.notes.push_back("import: " + there + " gives " + what + " " + shown(a));
    }
  }

  // "Table 13-37 (p202:25)", or for a table without a caption "the table at p179:24".
  std::string label(const Imported& e) const {
    return e.table.starts_with("Table ") ? e.table + " (" + at(e.line) + ")" : e.table;
  }

  static std::string describe(const Imported& e) {
    return (e.category.empty() ? "" : e.category + ":" + e.subcategory + ":") + e.name;
  }

  // Entries without an address (per-setting tables, app-note tables): the document's own summary, then the
  // --map files, then an address the text above named; else TODO. Two rows of one setting or one code are
  // folded into one entry.
  void resolveAddresses() {
    std::map<std::string, std::size_t> bySetting;  // entries with an address from a table
    std::map<std::pair<const KindInfo*, std::string>, std::size_t> byAddress;
    for (std::size_t i = 0; i < entries_.size(); ++i) {
      Imported& e = entries_[i];
      if (!e.fromTableAddress) continue;
      const auto [at, fresh] = byAddress.emplace(std::make_pair(e.kind, e.addr), i);
      if (!fresh && lookupKey(entries_[at->second].name) == lookupKey(e.name)) {
        fold(e, entries_[at->second]);
        continue;
      }
      bySetting.emplace(settingKey(e), i);
    }
    // TI's own tables of one setting sometimes spell its class differently ("Advanced Charging Algorithms"
    // in the setting's section, "Advanced Charge Algorithm" in the summary of SLUUAQ3A): then the subclass
    // and name, when they name one summary row, place it.
    std::map<std::string, std::vector<std::size_t>> bySubclass;
    for (const auto& [key, i] : bySetting) {
      const Imported& s = entries_[i];
      bySubclass[std::string(s.kind->yamlKey) + '\x1f' + lookupKey(s.subcategory) + '\x1f' +
                 lookupKey(s.name)]
          .push_back(i);
    }
    std::set<std::pair<std::string, std::string>> classesReported;
    for (Imported& e : entries_) {
      if (e.fromTableAddress || e.merged) continue;
      if (const auto it = bySetting.find(settingKey(e)); it != bySetting.end()) {
        fold(e, entries_[it->second]);
        continue;
      }
      const auto sub = bySubclass.find(std::string(e.kind->yamlKey) + '\x1f' + lookupKey(e.subcategory) +
                                       '\x1f' + lookupKey(e.name));
      if (sub != bySubclass.end() && sub->second.size() == 1) {
        Imported& into = entries_[sub->second.front()];
        if (classesReported.insert({e.category, into.category}).second) {
          warn(e.line, 1,
               "class '" + e.category + "' here is '" + into.category + "' in " + into.table + " (" +
                   at(into.line) + "); its rows are matched by subclass and name");
        }
        fold(e, into);
        continue;
      }
      if (const Entry* known = lookup(*e.kind, e.name, e.category, e.subcategory)) {
        e.addr = hexAddress(*known->addr, e.kind->addrDigits);
        e.comments.push_back("address from " + displayPath(mapSources_.path(known->loc.file)) + ":" +
                             std::to_string(known->loc.line));
        if (known->id.present) {
          e.id = known->id.value;
          e.idFromMap = true;
        }
        continue;
      }
      if (summaries_) {
        // In a document with summaries, a setting that neither a summary nor the map lists cannot be given
        // an address (the text around a setting's table names none): named, left out.
        warn(e.line, 1,
             "'" + describe(e) + "' is in no summary table of the document" +
                 (opts_.mapFiles.empty() ? "" : " nor in the --map files") +
                 "; left out (an entry needs its address)");
        skipped_.push_back(e.line);
        e.merged = true;
        continue;
      }
      if (e.mention) {
        e.addr = e.mention->first;
        warn(e.line, 1,
             "address " + e.addr + " of '" + e.name + "' taken from the text above the table (" +
                 at(e.mention->second) + "); check it against the TRM");
        e.notes.push_back("import: address from the text at " + at(e.mention->second));
        continue;
      }
      warn(e.line, 1,
           "no address for '" + describe(e) + "'" + (summaries_ ? " in the document's summary tables" : "") +
               (opts_.mapFiles.empty() ? " (pass --map with the family's YAML to look it up)"
                                       : " nor in the --map files") +
               "; written as TODO");
      e.addr = "TODO";
    }
    // Ids of the --map entries, and a table address that disagrees with the map.
    for (Imported& e : entries_) {
      if (e.merged || !e.fromTableAddress) continue;
      const Entry* known = lookup(*e.kind, e.name, e.category, e.subcategory);
      if (!known) continue;
      if (e.addr.size() <= 10 && std::stoull(e.addr.substr(2), nullptr, 16) != *known->addr) {
        warn(e.line, 1,
             "address " + e.addr + " of '" + e.name + "' differs from the map (" +
                 hexAddress(*known->addr, e.kind->addrDigits) + " at " +
                 displayPath(mapSources_.path(known->loc.file)) + ":" + std::to_string(known->loc.line) +
                 ")");
      }
      if (known->id.present) {
        e.id = known->id.value;
        e.idFromMap = true;
      }
    }
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
    const auto idOf = [](const Imported& e) { return e.id.empty() ? pascalCase(e.name) : e.id; };
    for (const Imported& e : entries_) {
      if (!e.merged) ++uses[key(e, idOf(e))];
    }
    std::set<std::string> taken;
    for (Imported& e : entries_) {
      if (e.merged) continue;
      const std::string id = idOf(e);
      const bool usable = isIdentifier(id) && !isCppKeyword(id);  // "1st Safety Status C" starts with a digit
      if (e.idFromMap || (usable && (uses[key(e, id)] < 2 || taken.insert(key(e, id)).second))) continue;
      for (const std::string& candidate : {pascalCase(e.subcategory + " " + e.name),
                                           pascalCase(e.category + " " + e.subcategory + " " + e.name)}) {
        if (!isIdentifier(candidate) || uses.count(key(e, candidate)) ||
            !taken.insert(key(e, candidate)).second)
          continue;
        e.id = candidate;
        e.comments.push_back(usable ? "id: '" + id + "' is taken by an entry above; made unique by import"
                                    : "id: '" + id + "' is not a C++ identifier; made one by import");
        break;
      }
    }
  }

  // ---- output ----

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
        if (e.kind != &k || e.merged) continue;
        if (!any) o << k.yamlKey << ":\n";
        any = true;
        for (const std::string& c : e.comments)
          o << "  # " << commentText(c) << "\n";
        std::string notes;
        for (const std::string& n : e.notes)
          notes.append(notes.empty() ? "" : "; ").append(n);
        const std::pair<const char*, std::string> keys[] = {
            {"name", e.name},
            {"id", e.id},
            {"addr", e.addr},
            {"span", e.span},
            {"type", e.type},
            {"access", e.access},
            {"unit", e.unit},
            {"scale", e.scale},
            {"min", e.min},
            {"max", e.max},
            {"default", e.dflt},
            {"fieldset", e.fieldset},
            {"category", e.kind->allowCategory ? e.category : ""},
            {"subcategory", e.kind->allowCategory ? e.subcategory : ""},
            {"description",
             e.description.empty() ? "Imported; the table gives no description." : e.description},
            {"source", opts_.source},
            {"notes", notes}};
        bool first = true;
        for (const auto& [key, value] : keys) {
          if (value.empty()) continue;
          o << (first ? "  - " : "    ") << key << ": " << yamlScalar(value) << "\n";
          first = false;
        }
      }
    }
    if (!fieldsets_.empty()) o << "fieldsets:\n";
    for (const ImportedFieldset& fs : fieldsets_) {
      o << "  - name: " << yamlScalar(fs.name) << "\n"
        << "    width: " << fs.width << "\n"
        << "    description: " << yamlScalar("Bit fields of " + fs.registerName + ".") << "\n"
        << "    source: " << yamlScalar(opts_.source) << "\n"
        << "    notes: "
        << yamlScalar("imported from " + displayPath(path_) + " " + fs.table + " (" + at(fs.line) + ")")
        << "\n"
        << "    fields:\n";
      for (const ImportedField& f : fs.fields) {
        o << "      - name: " << yamlScalar(f.name) << "\n"
          << "        bits: " << (f.bits.find(':') == std::string::npos ? f.bits : "\"" + f.bits + "\"")
          << "\n";
        if (!f.description.empty()) o << "        description: " << yamlScalar(f.description) << "\n";
      }
    }
    for (int line : skipped_)
      o << "# skipped: " << commentText(where(line)) << " (see warnings)\n";
  }

  struct Warning {
    int line, col;
    std::size_t seq;
    std::string message;
  };
  struct Mention {
    std::string address;
    int line;
  };

  std::string path_;
  const ImportOptions& opts_;
  std::ostream& err_;
  const rows::FamilyKinds* kinds_ = nullptr;
  Sources mapSources_;
  Model map_;
  TableText tables_;
  bool summaries_ = false;  // the text has register-summary captions: other captioned tables are left out
  std::vector<TableUse> uses_;
  std::vector<Imported> entries_;
  std::vector<ImportedFieldset> fieldsets_;
  std::map<std::string, std::size_t> fieldsetByRegister_;  // lookupKey of the register -> fieldsets_ index
  std::vector<int> skipped_;
  std::vector<Warning> warnings_;
  std::vector<std::string> run_;       // names left of a run "A through B"
  std::vector<Mention> mentions_;      // addresses named in the prose since the last table, oldest first
  std::optional<TableEvent> pending_;  // the row being read (joined with its continuation)
  std::vector<Role> pendingRoles_;
  std::vector<TableCell> pendingHeadings_;
  std::size_t pendingTable_ = 0;
};

}  // namespace

int runImport(const std::string& path, const std::string& text, const ImportOptions& opts, std::ostream& out,
              std::ostream& err) {
  Importer imp(path, opts, err);
  imp.out = &out;
  if (!opts.kind.empty() && !rows::findKind(opts.kind)) {
    err << "regmapgen: error: unknown --kind '" << opts.kind << "'\n";
    return 2;
  }
  if (!imp.loadMaps()) return 1;
  return imp.run(text);
}

}  // namespace regmapgen
