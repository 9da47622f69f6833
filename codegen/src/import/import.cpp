#include "import/import.hpp"

#include <cctype>
#include <map>
#include <optional>
#include <ostream>
#include <regex>
#include <sstream>

#include "check/check.hpp"
#include "diag/diag.hpp"
#include "emit/emit.hpp"
#include "model/model.hpp"
#include "model/names.hpp"
#include "model/schema.hpp"

namespace regmapgen {

namespace {

enum class Role {
  Address,
  Name,
  EnglishName,
  Unit,
  Type,
  Description,
  Category,
  Subcategory,
  Min,
  Max,
  Default,
  Data,
  Access,
  Unknown
};

struct Heading {
  Role role;
  std::vector<std::string> spellings;  // Chinese as printed; English lower-case
};

const std::vector<Heading>& headings() {
  static const std::vector<Heading> table = {
      {Role::Address,
       {"命令", "命令代码", "子命令", "地址", "寄存器", "command", "cmd", "subcommand", "address", "addr",
        "register", "reg"}},
      {Role::EnglishName, {"英文名称", "english name", "name (en)", "name(en)"}},
      {Role::Name, {"名称", "参数", "参数名称", "name", "parameter"}},
      {Role::Unit, {"单位", "unit", "units"}},
      {Role::Type, {"类型", "数据类型", "type", "data type"}},
      {Role::Description, {"说明", "描述", "备注", "description", "comment"}},
      {Role::Category, {"类别", "类", "class", "category"}},
      {Role::Subcategory, {"子类别", "子类", "subclass", "subcategory"}},
      {Role::Min, {"最小值", "min", "min value", "minimum"}},
      {Role::Max, {"最大值", "max", "max value", "maximum"}},
      {Role::Default, {"默认值", "default", "default value"}},
      {Role::Data, {"数据", "data"}},
      {Role::Access, {"访问", "访问权限", "读写", "access", "r/w"}},
  };
  return table;
}

std::string trim(std::string_view s) {
  const auto space = [](unsigned char c) { return c == ' ' || c == '\t' || c == '\r'; };
  while (!s.empty() && space(static_cast<unsigned char>(s.front())))
    s.remove_prefix(1);
  while (!s.empty() && space(static_cast<unsigned char>(s.back())))
    s.remove_suffix(1);
  // U+3000 ideographic spaces at either end
  while (s.size() >= 3 && s.substr(0, 3) == "\xE3\x80\x80")
    s.remove_prefix(3);
  while (s.size() >= 3 && s.substr(s.size() - 3) == "\xE3\x80\x80")
    s.remove_suffix(3);
  return std::string(s);
}

std::string lower(std::string s) {
  for (char& c : s)
    c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// "类型 类型" (a heading repeated by PDF extraction) reads as "类型".
std::string collapseRepeat(const std::string& s) {
  std::istringstream in(s);
  std::vector<std::string> words;
  for (std::string w; in >> w;)
    words.push_back(w);
  bool same = words.size() > 1;
  for (const std::string& w : words)
    same = same && w == words[0];
  return same ? words[0] : s;
}

Role roleOf(const std::string& cell) {
  const std::string c = lower(collapseRepeat(trim(cell)));
  for (const Heading& h : headings()) {
    for (const std::string& s : h.spellings) {
      if (c == s) return h.role;
    }
  }
  return Role::Unknown;
}

struct Cell {
  std::string text;
  int col = 1;  // 1-based column (code points) of the cell's first character
};

struct Row {
  int line = 0;
  std::vector<Cell> cells;
};

// Splits a line into cells at '|' or tabs; empty when the line has no separator.
std::vector<Cell> splitCells(const std::string& line) {
  std::vector<Cell> cells;
  const bool pipe = line.find('|') != std::string::npos;
  const bool tab = line.find('\t') != std::string::npos;
  if (!pipe && !tab) return cells;
  const char sep = pipe ? '|' : '\t';
  std::size_t start = 0;
  for (;;) {
    const std::size_t end = line.find(sep, start);
    const std::string raw = line.substr(start, end == std::string::npos ? std::string::npos : end - start);
    std::size_t lead = 0;
    while (lead < raw.size() && (raw[lead] == ' ' || raw[lead] == '\t'))
      ++lead;
    cells.push_back({trim(raw), columnOf(line, 0, start + lead)});
    if (end == std::string::npos) break;
    start = end + 1;
  }
  // "| a | b |": the empty cells outside the outer bars are not columns.
  if (pipe) {
    if (!cells.empty() && cells.front().text.empty()) cells.erase(cells.begin());
    if (!cells.empty() && cells.back().text.empty()) cells.pop_back();
  }
  return cells;
}

bool isRule(const std::vector<Cell>& cells) {
  static const std::regex rule(R"(:?-{3,}:?)");
  for (const Cell& c : cells) {
    if (!std::regex_match(c.text, rule)) return false;
  }
  return !cells.empty();
}

struct Imported {
  const KindInfo* kind = nullptr;
  int line = 0;
  std::vector<std::string> comments;                      // shown above the entry
  std::vector<std::pair<std::string, std::string>> keys;  // in output order
  std::vector<std::string> notes;
};

// The kind a `--kind` value names (its `list` word or YAML key), or nullptr.
const KindInfo* findKind(const std::string& k) {
  for (const KindInfo& info : kinds()) {
    if (info.listName == k || info.yamlKey == k) return &info;
  }
  return nullptr;
}

class Importer {
 public:
  Importer(std::string path, const ImportOptions& opts, std::ostream& err)
      : path_(std::move(path)), opts_(opts), err_(err) {}

  bool loadMaps() {
    if (opts_.mapFiles.empty()) return true;
    for (const std::string& f : opts_.mapFiles) {
      std::string text;
      if (!readFile(f, text)) {
        err_ << "regmapgen: error: cannot read map file " << f << "\n";
        return false;
      }
      mapSources_.add(f, std::move(text));
    }
    Diagnostics diag(mapSources_);
    map_ = build(mapSources_, diag);
    check(map_, diag);
    if (diag.errorCount() > 0) {
      diag.render(err_);
      err_ << "regmapgen: error: the --map files have errors; fix them first\n";
      return false;
    }
    return true;
  }

  int run(const std::string& text) {
    std::istringstream in(text);
    std::string line;
    int number = 0;
    std::vector<Role> roles;
    std::vector<std::string> headingText;
    bool inTable = false;
    int tables = 0;
    while (std::getline(in, line)) {
      ++number;
      if (!line.empty() && line.back() == '\r') line.pop_back();
      const std::vector<Cell> cells = splitCells(line);
      if (cells.empty()) {
        if (inTable) mentions_.clear();  // prose after a table starts a new context
        inTable = false;
        notePlaces(line, number);
        continue;
      }
      if (isRule(cells)) continue;
      if (isHeader(cells)) {
        roles.clear();
        headingText.clear();
        for (const Cell& c : cells) {
          roles.push_back(roleOf(c.text));
          headingText.push_back(c.text);
          if (roles.back() == Role::Unknown) {
            warn(number, c.col, "unknown column heading '" + c.text + "': its cells go into the description");
          }
        }
        inTable = true;
        ++tables;
        continue;
      }
      if (!inTable) continue;
      row(Row{number, cells}, roles, headingText);
    }
    if (tables == 0) {
      err_ << path_
           << ": error: no table found (expected a heading row such as '命令 | 名称 | 单位 | 类型 | 说明' or "
           << "'Address<TAB>Name<TAB>Type')\n";
      return 1;
    }
    write();
    return 0;
  }

  std::ostream* out = nullptr;

 private:
  void warn(int line, int col, const std::string& msg) {
    err_ << path_ << ":" << line << ":" << col << ": warning: " << msg << "\n";
  }

  // Records data-memory addresses the prose names ("地址 0x9261", "写入 0x9304", "address 0x9261").
  void notePlaces(const std::string& line, int number) {
    static const std::regex mention(R"((?:地址|写入|[Aa]ddress|[Ww]rite to)\s*(0[xX][0-9A-Fa-f]{4})\b)");
    for (auto it = std::sregex_iterator(line.begin(), line.end(), mention); it != std::sregex_iterator();
         ++it) {
      mentions_.push_back({"0x" + upperCase((*it)[1].str().substr(2)), number});
    }
  }

  static bool isHeader(const std::vector<Cell>& cells) {
    int known = 0;
    bool addr = false, name = false, cat = false;
    for (const Cell& c : cells) {
      const Role r = roleOf(c.text);
      if (r != Role::Unknown) ++known;
      addr = addr || r == Role::Address;
      name = name || r == Role::Name || r == Role::EnglishName;
      cat = cat || r == Role::Category;
    }
    return (addr || cat) && name && known * 2 >= static_cast<int>(cells.size());
  }

  // Repairs a type cell damaged by PDF text extraction; records what changed.
  std::string fixType(std::string t, const Row& r, int col, Imported& e) {
    const std::string original = t;
    std::string compact;
    for (char c : t) {
      if (c != ' ') compact += c;
    }
    if (compact.empty() || compact == "-" || compact == "—") return "none";
    if (parseType(compact)) return compact;
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
      warn(r.line, col,
           "type '" + original + "' is not a TI type code; kept as written (check will report it)");
      return compact;
    }
    warn(r.line, col, "type '" + original + "' read as " + fixed + " (text-extraction damage)");
    e.notes.push_back("import: type '" + original + "' read as " + fixed);
    return fixed;
  }

  // A 1-byte scalar type whose description says the value has 16 (or 32) bits takes that width.
  std::string widthFromDescription(const std::string& type, const std::string& description, const Row& r,
                                   int col, Imported& e) {
    auto t = parseType(type);
    if (!t || !t->scalar() || t->base == TypeInfo::Base::Float) return type;
    static const std::regex bits(R"((8|16|32)\s*(位|-?bit))");
    std::smatch m;
    if (!std::regex_search(description, m, bits)) return type;
    const int said = std::stoi(m[1].str());
    if (said == t->size() * 8) return type;
    const std::string fixed = std::string(1, type[0]) + std::to_string(said / 8);
    if (!parseType(fixed)) return type;
    warn(r.line, col,
         "type " + type + " has " + std::to_string(t->size() * 8) + " bits but the description says " +
             m[0].str() + "; using " + fixed);
    e.notes.push_back("import: table type " + type + " contradicts its description (" + m[0].str() +
                      "); used " + fixed);
    return fixed;
  }

  // Unit cell -> unit and scale keys. Hex / 十六进制 means a flag word: no unit.
  void unit(const std::string& cell, const Row& r, int col, Imported& e) {
    std::string u = trim(cell);
    if (u.empty() || u == "-" || u == "十六进制" || lower(u) == "hex" || u == "ASCII") return;
    static const std::map<std::string, std::string> words = {
        {"毫伏", "mV"},   {"毫安", "mA"},   {"秒", "s"},    {"毫秒", "ms"}, {"微秒", "us"},
        {"分钟", "min"},  {"小时", "h"},    {"°C", "degC"}, {"℃", "degC"},  {"摄氏度", "degC"},
        {"%", "percent"}, {"mohm", "mOhm"}, {"hrs", "h"},   {"mΩ", "mOhm"}};
    static const std::regex scaled(R"(([0-9]+(?:\.[0-9]+)?)\s*(.+))");
    std::string scale;
    std::smatch m;
    if (std::regex_match(u, m, scaled)) {
      scale = m[1].str();
      u = trim(m[2].str());
    }
    if (auto it = words.find(u); it != words.end()) u = it->second;
    if (auto it = words.find(lower(u)); it != words.end()) u = it->second;
    if (!findUnit(u)) {
      warn(r.line, col, "unit '" + trim(cell) + "' is not a known unit; left out (recorded in notes)");
      e.notes.push_back("import: unit '" + trim(cell) + "' not recognised");
      return;
    }
    e.keys.emplace_back("unit", u);
    if (!scale.empty() && scale != "1") e.keys.emplace_back("scale", scale);
  }

  void row(const Row& r, const std::vector<Role>& roles, const std::vector<std::string>& headingText) {
    Imported e;
    e.line = r.line;
    std::map<Role, Cell> cell;
    std::string description;
    for (std::size_t i = 0; i < r.cells.size(); ++i) {
      const Role role = i < roles.size() ? roles[i] : Role::Unknown;
      const Cell& c = r.cells[i];
      if (role == Role::Unknown) {
        if (!c.text.empty()) {
          const std::string label =
              i < headingText.size() ? headingText[i] : "column " + std::to_string(i + 1);
          if (i >= roles.size())
            warn(r.line, c.col, "more cells than headings; '" + c.text + "' goes into the description");
          description.append(description.empty() ? "" : " ").append(label).append(": ").append(c.text);
        }
        continue;
      }
      cell[role] = c;
    }
    auto get = [&](Role role) { return cell.count(role) ? cell[role].text : std::string(); };
    auto col = [&](Role role) { return cell.count(role) ? cell[role].col : 1; };

    // Kind.
    const std::string addrText = get(Role::Address);
    static const std::regex hexAddr(R"(0[xX]([0-9A-Fa-f]+))");
    std::smatch m;
    const bool hasAddr = std::regex_match(addrText, m, hexAddr);
    if (!opts_.kind.empty()) {
      e.kind = findKind(opts_.kind);
    } else if (cell.count(Role::Category)) {
      e.kind = kindByYamlKey("datamem");
    } else if (hasAddr) {
      e.kind = kindByYamlKey(m[1].length() <= 2 ? "commands" : "subcommands");
    }
    if (cell.count(Role::Address) && !hasAddr) {
      warn(r.line, col(Role::Address), "'" + addrText + "' is not a hex address; row skipped");
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
    std::string name = get(Role::Name);
    const std::string english = get(Role::EnglishName);
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
        warn(r.line, col(Role::Name),
             "cannot translate name '" + name +
                 "' (not in the glossary); kept as is: replace it with the English TRM name");
        e.comments.push_back("TODO: replace with the English TRM name; '" + name +
                             "' is not in the glossary");
      }
    }
    if (name.empty()) {
      warn(r.line, 1, "row has no name; row skipped");
      skipped_.push_back(r.line);
      return;
    }
    e.keys.emplace_back("name", name);

    // Address.
    std::string addr = hasAddr ? "0x" + upperCase(m[1].str()) : "";
    if (addr.size() == 3) addr = "0x0" + addr.substr(2);
    std::string category = translateOr(get(Role::Category));
    std::string subcategory = translateOr(get(Role::Subcategory));
    if (const Entry* known = lookup(*e.kind, name, category, subcategory)) {
      if (addr.empty()) {
        addr = hexAddress(*known->addr, e.kind->addrDigits);
        e.comments.push_back("address from " + displayPath(mapSources_.path(known->loc.file)) + ":" +
                             std::to_string(known->loc.line));
      } else if (std::stoul(addr, nullptr, 16) != *known->addr) {
        warn(r.line, col(Role::Address),
             "address " + addr + " of '" + name + "' differs from the map (" +
                 hexAddress(*known->addr, e.kind->addrDigits) + " at " +
                 displayPath(mapSources_.path(known->loc.file)) + ":" + std::to_string(known->loc.line) +
                 ")");
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

    // Type.
    description = get(Role::Description) +
                  (description.empty() || get(Role::Description).empty() ? "" : " ") + description;
    if (!get(Role::Data).empty()) description = "Data: " + get(Role::Data) + ". " + description;
    description = trim(description);
    std::string type = cell.count(Role::Type) ? fixType(get(Role::Type), r, col(Role::Type), e) : "none";
    type = widthFromDescription(type, description, r, col(Role::Type), e);
    e.keys.emplace_back("type", type);

    // Access.
    std::string access = lower(get(Role::Access));
    if (access == "r/w") access = "rw";
    if (!findAccess(access)) {
      if (!access.empty())
        warn(r.line, col(Role::Access), "access '" + get(Role::Access) + "' not understood");
      if (e.kind->kind == EntryKind::DataMemory) {
        access = "config_update";
      } else if (type == "none") {
        access = "cmd";
      } else {
        access = "r";
      }
      e.comments.push_back("access is not in the table: '" + access + "' assumed; check the TRM");
    }
    e.keys.emplace_back("access", access);

    unit(get(Role::Unit), r, col(Role::Unit), e);
    for (auto [role, key] :
         {std::pair{Role::Min, "min"}, std::pair{Role::Max, "max"}, std::pair{Role::Default, "default"}}) {
      const std::string v = get(role);
      if (v.empty() || v == "-") continue;
      if (!parseNumber(v)) {
        warn(r.line, col(role), std::string(key) + " '" + v + "' is not a number; recorded in notes");
        e.notes.push_back(std::string("import: ") + key + " '" + v + "'");
        continue;
      }
      e.keys.emplace_back(key, v);
    }
    if (e.kind->allowCategory) {
      if (!category.empty()) e.keys.emplace_back("category", category);
      if (!subcategory.empty()) e.keys.emplace_back("subcategory", subcategory);
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

  static std::string yamlScalar(const std::string& v) {
    bool plain = !v.empty() && isAscii(v);
    static const std::string indicators = "-?:,[]{}#&*!|>'\"%@`";
    if (plain && indicators.find(v[0]) != std::string::npos &&
        !(v[0] == '-' && v.size() > 1 && std::isdigit(static_cast<unsigned char>(v[1])))) {
      plain = false;
    }
    if (plain && (v.find(": ") != std::string::npos || v.find(" #") != std::string::npos || v.back() == ' ' ||
                  v.back() == ':')) {
      plain = false;
    }
    if (plain) return v;
    std::string out = "\"";
    for (char c : v) {
      if (c == '"' || c == '\\') out += '\\';
      if (c == '\t') {
        out += "\\t";
        continue;
      }
      out += c;
    }
    return out + "\"";
  }

  void write() {
    std::ostream& o = *out;
    o << "# Generated by `regmapgen import` from " << displayPath(path_)
      << ". Review every entry before merging it\n"
      << "# into regmaps/<family>/: TI's tables do not give access, and 'source' stays 'unverified' until "
         "the\n"
      << "# values are checked against the TRM (or pass --source with the document's literature number).\n"
      << "family: " << opts_.family << "\n";
    for (const KindInfo& k : kinds()) {
      bool any = false;
      for (const Imported& e : entries_) {
        if (e.kind != &k) continue;
        if (!any) o << k.yamlKey << ":\n";
        any = true;
        for (const std::string& c : e.comments)
          o << "  # " << c << "\n";
        bool first = true;
        for (const auto& [key, value] : e.keys) {
          o << (first ? "  - " : "    ") << key << ": " << yamlScalar(value) << "\n";
          first = false;
        }
      }
    }
    for (int line : skipped_)
      o << "# skipped: line " << line << " of " << displayPath(path_) << " (see warnings)\n";
  }

  std::string path_;
  const ImportOptions& opts_;
  std::ostream& err_;
  Sources mapSources_;
  Model map_;
  std::vector<Imported> entries_;
  std::vector<int> skipped_;
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

std::string headingHelp() {
  std::ostringstream s;
  const char* names[] = {"address", "name",        "English name", "unit",
                         "type",    "description", "class",        "subclass",
                         "min",     "max",         "default",      "data (appended to the description)",
                         "access"};
  for (const Heading& h : headings()) {
    s << "  " << names[static_cast<int>(h.role)] << ":";
    for (const std::string& sp : h.spellings)
      s << " " << sp;
    s << "\n";
  }
  return s.str();
}

}  // namespace regmapgen
