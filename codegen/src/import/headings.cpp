#include "import/headings.hpp"

#include <sstream>
#include <unordered_map>
#include <unordered_set>

namespace regmapgen {

namespace {

struct Heading {
  Role role;
  const char* label;                   // for --help
  std::vector<std::string> spellings;  // Chinese as printed; English lower-case, single spaces
};

// Spellings seen in TI's documents: the BQ769x2/BQ7690x TRMs and app notes (Command, Subcommand, Class,
// Subclass, Min Value...), the BQ4050 TRM (SBS Cmd, Mode, Function, Format, Protocol, Size in Bytes, the
// SE/US/FA access columns) and the BQ79616 data sheet (Register Name, Addr Hex, RW Type, Reset Value, Data).
const std::vector<Heading>& headings() {
  static const std::vector<Heading> table = {
      {Role::Address,
       "address",
       {"命令", "命令代码", "子命令", "地址", "寄存器", "command", "cmd", "sbs cmd", "command code",
        "subcommand", "address", "addr", "addr hex", "register", "reg"}},
      {Role::EnglishName, "English name", {"英文名称", "english name", "name (en)", "name(en)"}},
      {Role::Name,
       "name",
       {"名称", "参数", "参数名称", "name", "parameter", "acronym", "function", "command name",
        "register name"}},
      {Role::Unit, "unit", {"单位", "unit", "units", "unit(s)"}},
      {Role::Type, "type", {"类型", "数据类型", "type", "data type"}},
      {Role::Format, "format (with size: the type)", {"format", "protocol"}},
      {Role::Size, "size", {"size", "size in bytes", "bytes", "length"}},
      {Role::Offset, "offset (fields of one payload)", {"offset"}},
      {Role::Description, "description", {"说明", "描述", "备注", "description", "comment", "notes", "note"}},
      {Role::Category, "class", {"类别", "类", "class", "category"}},
      {Role::Subcategory, "subclass", {"子类别", "子类", "subclass", "subcategory"}},
      {Role::Min, "min", {"最小值", "min", "min value", "minimum", "minimum value"}},
      {Role::Max, "max", {"最大值", "max", "max value", "maximum", "maximum value"}},
      {Role::Default, "default", {"默认值", "default", "default value", "reset", "reset value"}},
      {Role::Data,
       "data (appended to the description)",
       {"数据", "data", "bit7", "bit6", "bit5", "bit4", "bit3", "bit2", "bit1", "bit0", "bit 7", "bit 6",
        "bit 5", "bit 4", "bit 3", "bit 2", "bit 1", "bit 0"}},
      {Role::Bit, "bit (bit-field tables)", {"bit", "bits"}},
      {Role::Field, "field (bit-field tables)", {"field", "field name"}},
      {Role::Access,
       "access",
       {"访问", "访问权限", "读写", "access", "r/w", "rw", "rw type", "mode", "se", "us", "fa", "sealed",
        "unsealed", "full access"}},
  };
  return table;
}

// Lower-case ASCII, runs of spaces as one, and a heading printed twice ("类型 类型") as one.
std::string normalise(std::string_view s) {
  // Words (runs without spaces or tabs), lower-cased, joined by one space.
  std::vector<std::string_view> words;
  for (std::size_t i = 0; i < s.size();) {
    if (s[i] == ' ' || s[i] == '\t') {
      ++i;
      continue;
    }
    std::size_t j = i;
    while (j < s.size() && s[j] != ' ' && s[j] != '\t')
      ++j;
    words.push_back(s.substr(i, j - i));
    i = j;
  }
  bool repeated = words.size() > 1;
  for (std::string_view w : words)
    repeated = repeated && w == words[0];
  if (repeated) words.resize(1);
  std::string out;
  for (std::string_view w : words) {
    if (!out.empty()) out += ' ';
    for (char c : w)
      out += (c >= 'A' && c <= 'Z') ? static_cast<char>(c - 'A' + 'a') : c;
  }
  return out;
}

}  // namespace

Role roleOf(std::string_view heading) {
  // Every spelling, once: the importer asks for each chunk of each line of a text.
  static const std::unordered_map<std::string, Role> bySpelling = [] {
    std::unordered_map<std::string, Role> m;
    for (const Heading& entry : headings()) {
      for (const std::string& s : entry.spellings)
        m.emplace(s, entry.role);
    }
    return m;
  }();
  if (heading.size() > 64) return Role::Unknown;  // longer than any heading
  const auto it = bySpelling.find(normalise(heading));
  return it == bySpelling.end() ? Role::Unknown : it->second;
}

bool mayBeHeading(std::string_view line) {
  // The first word of every spelling ("min" of "min value", "size" of "size in bytes").
  static const std::unordered_set<std::string> firstWords = [] {
    std::unordered_set<std::string> words;
    for (const Heading& entry : headings()) {
      for (const std::string& s : entry.spellings)
        words.insert(s.substr(0, s.find(' ')));
    }
    return words;
  }();
  int found = 0;
  std::string word;
  for (std::size_t i = 0; i < line.size() && found < 2;) {
    if (line[i] == ' ' || line[i] == '\t') {
      ++i;
      continue;
    }
    std::size_t j = i;
    while (j < line.size() && line[j] != ' ' && line[j] != '\t')
      ++j;
    if (j - i <= 16) {
      word.assign(line.substr(i, j - i));
      for (char& c : word)
        c = (c >= 'A' && c <= 'Z') ? static_cast<char>(c - 'A' + 'a') : c;
      found += firstWords.count(word) ? 1 : 0;
    }
    i = j;
  }
  return found >= 2;
}

std::string headingHelp() {
  std::ostringstream s;
  for (const Heading& h : headings()) {
    s << "  " << h.label << ":";
    for (const std::string& sp : h.spellings)
      s << " " << sp;
    s << "\n";
  }
  return s.str();
}

std::vector<std::pair<std::size_t, std::size_t>> splitHeadings(std::string_view text) {
  // Words and their byte ranges.
  std::vector<std::pair<std::size_t, std::size_t>> words;
  for (std::size_t i = 0; i < text.size();) {
    if (text[i] == ' ') {
      ++i;
      continue;
    }
    std::size_t j = i;
    while (j < text.size() && text[j] != ' ')
      ++j;
    words.emplace_back(i, j);
    i = j;
  }
  // Greedy, longest known heading first; a heading has at most four words ("Size in Bytes").
  std::vector<std::pair<std::size_t, std::size_t>> parts;
  for (std::size_t w = 0; w < words.size();) {
    std::size_t take = 0;
    for (std::size_t n = std::min<std::size_t>(4, words.size() - w); n >= 1 && take == 0; --n) {
      const std::size_t from = words[w].first, to = words[w + n - 1].second;
      if (roleOf(text.substr(from, to - from)) != Role::Unknown) take = n;
    }
    if (take == 0) return {};
    parts.emplace_back(words[w].first, words[w + take - 1].second);
    w += take;
  }
  if (parts.size() < 2) return {};
  return parts;
}

bool isHeadingRow(const std::vector<Role>& roles) {
  int known = 0;
  bool addr = false, name = false, cat = false, bit = false, field = false;
  for (Role r : roles) {
    if (r != Role::Unknown) ++known;
    addr = addr || r == Role::Address;
    name = name || r == Role::Name || r == Role::EnglishName;
    cat = cat || r == Role::Category;
    bit = bit || r == Role::Bit;
    field = field || r == Role::Field;
  }
  return (((addr || cat) && name) || (bit && field)) && known * 2 >= static_cast<int>(roles.size());
}

}  // namespace regmapgen
