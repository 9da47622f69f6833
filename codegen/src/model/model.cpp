#include "model/model.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <numeric>

#include "model/names.hpp"
#include "text/scan.hpp"

namespace regmapgen {

const Fieldset* Family::findFieldset(const std::string& n) const {
  for (const Fieldset& f : fieldsets) {
    if (f.name.value == n) return &f;
  }
  return nullptr;
}

const Enum* Family::findEnum(const std::string& n) const {
  for (const Enum& e : enums) {
    if (e.name.value == n) return &e;
  }
  return nullptr;
}

std::optional<Number> parseNumber(const std::string& text) {
  Number n;
  n.text = text;
  n.present = true;
  std::string_view s = text;
  bool neg = false;
  if (!s.empty() && (s[0] == '-' || s[0] == '+')) {
    neg = s[0] == '-';
    s.remove_prefix(1);
  }
  int base = 10;
  if (s.size() > 2 && s[0] == '0' && (s[1] == 'x' || s[1] == 'X')) {
    base = 16;
    s.remove_prefix(2);
  } else if (s.size() > 2 && s[0] == '0' && (s[1] == 'b' || s[1] == 'B')) {
    base = 2;
    s.remove_prefix(2);
  }
  bool digitsOnly = !s.empty();
  for (char c : s) {
    const bool ok = base == 16  ? std::isxdigit(static_cast<unsigned char>(c)) != 0
                    : base == 2 ? (c == '0' || c == '1')
                                : std::isdigit(static_cast<unsigned char>(c)) != 0;
    digitsOnly = digitsOnly && ok;
  }
  if (digitsOnly) {
    // Accumulate in unsigned 64 bits with an overflow check; values beyond int64 are not register values.
    std::uint64_t v = 0;
    for (char c : s) {
      const int d = std::isdigit(static_cast<unsigned char>(c))
                        ? c - '0'
                        : std::tolower(static_cast<unsigned char>(c)) - 'a' + 10;
      if (v > (UINT64_MAX - static_cast<std::uint64_t>(d)) / static_cast<std::uint64_t>(base))
        return std::nullopt;
      v = v * static_cast<std::uint64_t>(base) + static_cast<std::uint64_t>(d);
    }
    if (v > static_cast<std::uint64_t>(INT64_MAX)) return std::nullopt;
    n.isInteger = true;
    n.integer = neg ? -static_cast<std::int64_t>(v) : static_cast<std::int64_t>(v);
    n.real = static_cast<double>(n.integer);
    return n;
  }
  if (base != 10) return std::nullopt;
  // A decimal real such as 7.4768, 1.00E-02 or 4.193046E+08 (F4 values).
  if (!scan::isDecimalReal(text)) return std::nullopt;
  errno = 0;
  char* end = nullptr;
  n.real = std::strtod(text.c_str(), &end);
  if (errno != 0 || end != text.c_str() + text.size() || !std::isfinite(n.real)) return std::nullopt;
  return n;
}

std::optional<Scale> parseScale(const std::string& text) {
  Scale s;
  s.text = text;
  s.present = true;
  const std::string_view t = text;
  const std::size_t first = scan::run(t, 0, scan::isDigit);
  if (first == 0) return std::nullopt;
  if (first < t.size() && t[first] == '/') {
    // A ratio "n/d".
    const std::string_view den = t.substr(first + 1);
    if (!scan::all(den, scan::isDigit) || first > 9 || den.size() > 9) return std::nullopt;
    s.num = std::stoll(std::string(t.substr(0, first)));
    s.den = std::stoll(std::string(den));
  } else {
    // A decimal "n" or "n.f": at most 9 significant digits, so the ratio fits comfortably.
    std::string_view fraction;
    if (first < t.size()) {
      fraction = t.substr(first + 1);
      if (t[first] != '.' || !scan::all(fraction, scan::isDigit)) return std::nullopt;
    }
    if (first + fraction.size() > 9) return std::nullopt;
    s.num = std::stoll(std::string(t.substr(0, first)) + std::string(fraction));
    s.den = 1;
    for (std::size_t i = 0; i < fraction.size(); ++i)
      s.den *= 10;
  }
  if (s.num <= 0 || s.den <= 0) return std::nullopt;
  const std::int64_t g = std::gcd(s.num, s.den);
  s.num /= g;
  s.den /= g;
  return s;
}

namespace {

using yaml::Node;

// Edit distance, for "did you mean" hints on unknown keys.
std::size_t distance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> prev(b.size() + 1), cur(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j)
    prev[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    cur[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1)});
    }
    std::swap(prev, cur);
  }
  return prev[b.size()];
}

// A TI literature number: "SL", two capital letters, then two to five capitals or digits (SLUUBY2B,
// SLUSE81E).
bool isLiteratureNumber(std::string_view t) {
  const auto alnum = [](char c) { return scan::isUpper(c) || scan::isDigit(c); };
  return t.size() >= 6 && t.size() <= 9 && t.substr(0, 2) == "SL" && scan::isUpper(t[2]) &&
         scan::isUpper(t[3]) && scan::all(t.substr(4), alnum);
}

// The highest bit a field may name: fieldsets are 8, 16 or 32 bits wide.
constexpr int kMaxBit = 31;

// "7" or "9:8": one or two decimal digits each. Fills msb and lsb as written (not yet ordered).
bool parseBits(std::string_view t, int& msb, int& lsb) {
  const std::size_t a = scan::run(t, 0, scan::isDigit);
  if (a == 0 || a > 2) return false;
  msb = lsb = std::stoi(std::string(t.substr(0, a)));
  if (a == t.size()) return true;
  const std::string_view rest = t.substr(a + 1);
  if (t[a] != ':' || rest.size() > 2 || !scan::all(rest, scan::isDigit)) return false;
  lsb = std::stoi(std::string(rest));
  return true;
}

class Builder {
 public:
  Builder(const Sources& sources, Diagnostics& diag) : sources_(sources), diag_(diag) {}

  Model run() {
    for (std::size_t f = 0; f < sources_.size(); ++f) {
      const Node root = yaml::parse(sources_, static_cast<int>(f), diag_);
      file(static_cast<int>(f), root);
    }
    return std::move(model_);
  }

 private:
  // Reports unknown keys and missing required keys of a mapping; `what` names the object in messages.
  void checkKeys(const Node& map, const ObjectSpec& spec, const std::string& what,
                 const KindInfo* kind = nullptr) {
    for (std::size_t i = 0; i < map.keys.size(); ++i) {
      const std::string& k = map.keys[i].text;
      const KeySpec* ks = spec.find(k);
      if (!ks) {
        std::string best;
        std::size_t bestD = 3;
        for (const KeySpec& cand : spec.keys) {
          const std::size_t d = distance(k, cand.key);
          if (d < bestD) {
            bestD = d;
            best = std::string(cand.key);
          }
        }
        std::string msg = "unknown key '" + k + "' in " + what;
        if (!best.empty()) msg += " (did you mean '" + best + "'?)";
        diag_.error(map.keys[i].loc, msg);
        continue;
      }
      if (kind && ((k == "category" || k == "subcategory") && !kind->allowCategory)) {
        diag_.error(map.keys[i].loc, "key '" + k + "' is only allowed in datamem and dataflash entries");
      }
      if (kind && k == "span" && !kind->allowSpan) {
        diag_.error(map.keys[i].loc, "key 'span' is only allowed in subcommand and mac entries");
      }
    }
    for (const KeySpec& ks : spec.keys) {
      if (ks.required && !map.find(ks.key)) {
        diag_.error(map.loc, what + " has no '" + std::string(ks.key) + "' (required)");
      }
    }
  }

  // The scalar text of `key`, or nothing (reporting a non-scalar).
  Text text(const Node& map, std::string_view key, const std::string& what) {
    Text t;
    const Node* v = map.find(key);
    if (!v) return t;
    if (v->invalid) return t;  // unsupported syntax, already reported by the reader
    if (!v->isScalar()) {
      diag_.error(v->loc, std::string("'") + std::string(key) + "' of " + what + " must be a scalar, not " +
                              yaml::describe(v->type));
      return t;
    }
    t.value = v->text;
    t.loc = v->loc;
    t.present = true;
    if (t.value.empty() && !v->quoted) {
      diag_.error(v->loc, std::string("'") + std::string(key) + "' of " + what + " is empty");
      t.present = false;
    }
    return t;
  }

  Number number(const Node& map, std::string_view key, const std::string& what, bool integerOnly) {
    const Text t = text(map, key, what);
    Number n;
    if (!t.present) return n;
    auto parsed = parseNumber(t.value);
    if (!parsed || (integerOnly && !parsed->isInteger)) {
      diag_.error(t.loc, std::string("'") + std::string(key) + "' of " + what + ": '" + t.value +
                             "' is not " + (integerOnly ? "an integer" : "a number"));
      return n;
    }
    parsed->loc = t.loc;
    return *parsed;
  }

  Text identifier(const Node& map, std::string_view key, const std::string& what) {
    Text t = text(map, key, what);
    if (t.present && !isIdentifier(t.value)) {
      diag_.error(t.loc, std::string("'") + std::string(key) + "' of " + what + ": '" + t.value +
                             "' is not a C++ identifier");
      t.present = false;
    }
    return t;
  }

  Text source(const Node& map, const std::string& what) {
    Text t = text(map, "source", what);
    if (!t.present) return t;
    std::vector<std::string> tokens;
    std::string cur;
    for (char c : t.value + " ") {
      if (c == ' ' || c == ',' || c == '+') {
        if (!cur.empty()) tokens.push_back(cur);
        cur.clear();
      } else {
        cur += c;
      }
    }
    bool unverified = false;
    for (const std::string& tok : tokens) {
      if (tok == "unverified") unverified = true;
      if (!isSourceToken(tok) && !isLiteratureNumber(tok)) {
        diag_.error(t.loc, "source of " + what + ": '" + tok +
                               "' is not a TI literature number (e.g. SLUUBY2B), SBS1.1 or 'unverified'");
      }
    }
    if (unverified && tokens.size() > 1) {
      diag_.error(t.loc, "source of " + what + ": 'unverified' stands alone (move details to 'notes')");
    }
    return t;
  }

  std::vector<std::string> textList(const Node& map, std::string_view key, const std::string& what) {
    std::vector<std::string> out;
    const Node* v = map.find(key);
    if (!v) return out;
    if (!v->isSeq()) {
      diag_.error(v->loc, std::string("'") + std::string(key) + "' of " + what + " must be a list");
      return out;
    }
    for (const Node& item : v->items) {
      if (!item.isScalar()) {
        diag_.error(item.loc, std::string("items of '") + std::string(key) + "' must be scalars");
        continue;
      }
      out.push_back(item.text);
    }
    return out;
  }

  // The items of a list of mappings; non-mapping items are reported and skipped.
  std::vector<const Node*> objectList(const Node& v, std::string_view key, std::string_view element) {
    std::vector<const Node*> out;
    if (!v.isSeq()) {
      diag_.error(v.loc, std::string("'") + std::string(key) + "' must be a list of " + std::string(element) +
                             " mappings ('- name: ...'), not " + yaml::describe(v.type));
      return out;
    }
    for (const Node& item : v.items) {
      if (!item.isMap()) {
        diag_.error(item.loc, std::string("each item of '").append(key) + "' must be a mapping, not " +
                                  yaml::describe(item.type));
        continue;
      }
      out.push_back(&item);
    }
    return out;
  }

  void file(int f, const Node& root) {
    if (root.isNull()) {
      diag_.error(Loc{f, 1, 1}, "empty file: expected 'family:' and at least one list");
      return;
    }
    if (!root.isMap()) {
      diag_.error(root.loc, std::string("the top level must be a mapping, not ") + yaml::describe(root.type));
      return;
    }
    checkKeys(root, object("file"), "the file");
    Family* fam = nullptr;
    const Text family = text(root, "family", "the file");
    std::string famName = family.present ? family.value : "";
    const auto familyChar = [](char c) { return scan::isLower(c) || scan::isDigit(c) || c == '_'; };
    if (family.present && !(scan::isLower(famName[0]) && scan::all(famName, familyChar))) {
      diag_.error(family.loc, "family '" + famName + "' must be a lowercase id such as bq769x2");
    }
    for (Family& existing : model_.families) {
      if (existing.name == famName) fam = &existing;
    }
    if (!fam) {
      model_.families.push_back(Family{});
      fam = &model_.families.back();
      fam->name = famName;
      fam->loc = family.present ? family.loc : Loc{f, 1, 1};
    }
    fam->files.push_back(f);

    for (std::size_t i = 0; i < root.keys.size(); ++i) {
      const std::string& key = root.keys[i].text;
      const Node& value = root.values[i];
      if (key == "device") {
        device(*fam, value);
      } else if (key == "fieldsets") {
        for (const Node* n : objectList(value, key, "fieldset"))
          fieldset(*fam, *n);
      } else if (key == "enums") {
        for (const Node* n : objectList(value, key, "enum"))
          enumeration(*fam, *n);
      } else if (key == "blocks") {
        for (const Node* n : objectList(value, key, "block"))
          block(*fam, *n);
      } else if (const KindInfo* k = kindByYamlKey(key)) {
        for (const Node* n : objectList(value, key, "entry"))
          entry(*fam, *k, *n);
      }
    }
  }

  void device(Family& fam, const Node& v) {
    if (!v.isMap()) {
      diag_.error(v.loc, "'device' must be a mapping");
      return;
    }
    if (fam.device) {
      diag_.error(v.loc, "device of family '" + fam.name + "' given again (first at line " +
                             std::to_string(fam.device->loc.line) + " of " +
                             sources_.path(fam.device->loc.file) + ")");
      return;
    }
    checkKeys(v, object("device"), "device");
    Device d;
    d.loc = v.loc;
    d.title = text(v, "title", "device");
    d.parts = textList(v, "parts", "device");
    d.documents = textList(v, "documents", "device");
    d.notes = text(v, "notes", "device");
    fam.device = std::move(d);
  }

  // How messages name an object before it is built: "<prefix> '<name>'", '?' for a missing or odd name.
  static std::string named(const std::string& prefix, const Node& item) {
    const Node* n = item.find("name");
    return prefix + " '" + (n && n->isScalar() ? n->text : "?") + "'";
  }

  void entry(Family& fam, const KindInfo& kind, const Node& item) {
    const std::string what = named(std::string(kind.listName), item);
    checkKeys(item, object("entry"), what, &kind);
    Entry e;
    e.kind = &kind;
    e.loc = item.loc;
    e.name = text(item, "name", what);
    e.id = identifier(item, "id", what);

    const Number addr = number(item, "addr", what, true);
    e.addrLoc = addr.loc;
    if (addr.present) {
      if (addr.integer < 0 || static_cast<std::uint64_t>(addr.integer) > kind.maxAddress) {
        diag_.error(addr.loc, what + ": address " + addr.text + " is outside 0.." +
                                  hexAddress(kind.maxAddress) + " for " + std::string(kind.listName) +
                                  " entries");
      } else {
        e.addr = static_cast<std::uint32_t>(addr.integer);
      }
    }
    const Number span = number(item, "span", what, true);
    if (span.present) {
      e.spanLoc = span.loc;
      if (span.integer < 1 || span.integer > 0x10000) {
        diag_.error(span.loc, what + ": span must be 1..65536");
      } else {
        e.span = static_cast<std::uint32_t>(span.integer);
      }
    }

    if (const Text t = text(item, "type", what); t.present) {
      e.typeLoc = t.loc;
      e.type = parseType(t.value);
      if (!e.type)
        diag_.error(t.loc, what + ": unknown type code '" + t.value + "' (known: " + typeCodesHelp() + ")");
    }
    if (const Text t = text(item, "access", what); t.present) {
      e.accessLoc = t.loc;
      e.access = findAccess(t.value);
      if (!e.access) {
        std::string known;
        for (const AccessInfo& a : accessCodes())
          known.append(known.empty() ? "" : ", ").append(a.spelling);
        diag_.error(t.loc, what + ": unknown access '" + t.value + "' (known: " + known + ")");
      }
    }
    if (const Text t = text(item, "unit", what); t.present) {
      e.unitLoc = t.loc;
      e.unit = findUnit(t.value);
      if (!e.unit) {
        std::string known;
        for (const UnitInfo& u : units())
          known.append(known.empty() ? "" : " ").append(u.symbol);
        diag_.error(t.loc, what + ": unknown unit '" + t.value + "' (known: " + known + ")");
      }
    }
    if (const Text t = text(item, "scale", what); t.present) {
      if (auto s = parseScale(t.value)) {
        e.scale = *s;
        e.scale.loc = t.loc;
      } else {
        diag_.error(t.loc,
                    what + ": scale '" + t.value + "' must be a positive decimal (0.1) or ratio (1/3)");
      }
    }
    e.min = number(item, "min", what, false);
    e.max = number(item, "max", what, false);
    e.dflt = number(item, "default", what, false);
    e.fieldset = identifier(item, "fieldset", what);
    e.enumRef = identifier(item, "enum", what);
    e.category = text(item, "category", what);
    e.subcategory = text(item, "subcategory", what);
    e.description = text(item, "description", what);
    e.source = source(item, what);
    e.notes = text(item, "notes", what);
    e.cppName = e.id.present ? e.id.value : pascalCase(e.name.value);
    fam.entries.push_back(std::move(e));
  }

  void fieldset(Family& fam, const Node& item) {
    const std::string what = named("fieldset", item);
    checkKeys(item, object("fieldset"), what);
    Fieldset fs;
    fs.loc = item.loc;
    fs.name = identifier(item, "name", what);
    const Number w = number(item, "width", what, true);
    fs.widthLoc = w.loc;
    if (w.present) {
      if (w.integer != 8 && w.integer != 16 && w.integer != 32) {
        diag_.error(w.loc, what + ": width must be 8, 16 or 32");
      } else {
        fs.width = static_cast<int>(w.integer);
      }
    }
    fs.description = text(item, "description", what);
    fs.source = source(item, what);
    fs.notes = text(item, "notes", what);
    if (const Node* fields = item.find("fields")) {
      for (const Node* f : objectList(*fields, "fields", "field"))
        fs.fields.push_back(field(*f, what));
    }
    fam.fieldsets.push_back(std::move(fs));
  }

  Field field(const Node& item, const std::string& parent) {
    const std::string what = named(parent + " field", item);
    checkKeys(item, object("field"), what);
    Field f;
    f.loc = item.loc;
    f.name = text(item, "name", what);
    f.id = identifier(item, "id", what);
    f.cppName = f.id.present ? f.id.value : snakeCase(f.name.value);
    if (const Text b = text(item, "bits", what); b.present) {
      f.bitsLoc = b.loc;
      if (!parseBits(b.value, f.msb, f.lsb)) {
        diag_.error(b.loc, what + ": bits '" + b.value + "' must be a bit number or \"msb:lsb\"");
        f.msb = f.lsb = -1;
      } else if (f.msb > kMaxBit || f.lsb > kMaxBit) {
        // Without this bound a field at bit 70 of a fieldset with no width shifted a 64-bit mask by 70
        // (undefined behaviour; UBSan aborted before the error was printed, issue 15).
        diag_.error(b.loc, what + ": bit " + std::to_string(std::max(f.msb, f.lsb)) + " is beyond bit " +
                               std::to_string(kMaxBit) + " (fieldsets are at most 32 bits wide)");
        f.msb = f.lsb = -1;
      } else if (f.lsb > f.msb) {
        diag_.error(b.loc, what + ": bits '" + b.value + "' must be written msb:lsb (high bit first)");
        std::swap(f.msb, f.lsb);
      }
    }
    f.enumRef = identifier(item, "enum", what);
    f.description = text(item, "description", what);
    f.source = source(item, what);
    return f;
  }

  void enumeration(Family& fam, const Node& item) {
    const std::string what = named("enum", item);
    checkKeys(item, object("enum"), what);
    Enum en;
    en.loc = item.loc;
    en.name = identifier(item, "name", what);
    en.description = text(item, "description", what);
    en.source = source(item, what);
    if (const Node* values = item.find("values")) {
      for (const Node* v : objectList(*values, "values", "enum value")) {
        const std::string vwhat = named(what + " value", *v);
        checkKeys(*v, object("enum value"), vwhat);
        EnumValue ev;
        ev.loc = v->loc;
        ev.name = identifier(*v, "name", vwhat);
        const Number num = number(*v, "value", vwhat, true);
        ev.valueLoc = num.loc;
        if (num.present) ev.value = num.integer;
        ev.description = text(*v, "description", vwhat);
        en.values.push_back(std::move(ev));
      }
    }
    fam.enums.push_back(std::move(en));
  }

  void block(Family& fam, const Node& item) {
    const std::string what = named("block", item);
    checkKeys(item, object("block"), what);
    Block b;
    b.loc = item.loc;
    b.name = identifier(item, "name", what);
    b.start = number(item, "start", what, true);
    if (const Node* v = item.find("members")) {
      if (!v->isSeq()) {
        diag_.error(v->loc, "'members' of " + what + " must be a list of command names");
      } else {
        for (const Node& m : v->items) {
          if (!m.isScalar()) {
            diag_.error(m.loc,
                        "members of " + what + " must be command names, not " + yaml::describe(m.type));
            continue;
          }
          b.members.push_back(Text{m.text, m.loc, true});
        }
        if (v->items.empty()) diag_.error(v->loc, what + " has no members");
      }
    }
    if (const Text g = text(item, "gaps", what); g.present) {
      b.gapsAllowed = g.value == "allowed";
      if (!b.gapsAllowed) diag_.error(g.loc, "'gaps' of " + what + ": '" + g.value + "' must be 'allowed'");
    }
    b.description = text(item, "description", what);
    fam.blocks.push_back(std::move(b));
  }

  const Sources& sources_;
  Diagnostics& diag_;
  Model model_;
};

}  // namespace

Model build(const Sources& sources, Diagnostics& diag) {
  return Builder(sources, diag).run();
}

}  // namespace regmapgen
