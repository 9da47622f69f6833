#include "import/cells.hpp"

#include <algorithm>
#include <map>
#include <sstream>
#include <vector>

#include "model/schema.hpp"
#include "text/scan.hpp"

namespace regmapgen::cells {

namespace {

std::string lower(std::string_view s) {
  std::string out(s);
  for (char& c : out) {
    if (scan::isUpper(c)) c = static_cast<char>(c - 'A' + 'a');
  }
  return out;
}

std::vector<std::string> words(std::string_view s) {
  std::istringstream in{std::string(s)};
  std::vector<std::string> out;
  for (std::string w; in >> w;)
    out.push_back(w);
  return out;
}

// Replaces every `from` in `s` with `to`.
void replaceAll(std::string& s, std::string_view from, std::string_view to) {
  for (std::size_t p = s.find(from); p != std::string::npos; p = s.find(from, p + to.size()))
    s.replace(p, from.size(), to);
}

bool isNoValue(std::string_view t) {
  return t.empty() || t == "-" || t == "\xE2\x80\x94" /* em dash */ || t == "\xE2\x80\x93" /* en dash */ ||
         lower(t) == "n/a";
}

}  // namespace

std::string number(std::string_view cell) {
  std::string t(scan::trimmed(cell));
  if (isNoValue(t)) return "";
  // "HW Reset Default = 0x00 Factory Configuration Default = 0x01" (BQ79616 OTP-backed registers): the
  // factory value, which is what a device leaves the factory with; else the first value given.
  if (const std::size_t eq = t.find('='); eq != std::string::npos) {
    const std::size_t factory = t.find("Factory");
    const std::size_t at =
        factory != std::string::npos && t.find('=', factory) != std::string::npos ? t.find('=', factory) : eq;
    const std::string_view rest = scan::trimmed(std::string_view(t).substr(at + 1));
    t = std::string(rest.substr(0, rest.find(' ')));
  }
  for (std::string_view dash : {"\xE2\x80\x93", "\xE2\x88\x92", "\xE2\x80\x92", "\xE2\x80\x90"})
    replaceAll(t, dash, "-");
  for (std::string_view space : {" ", "\xE2\x80\x89", "\xE2\x80\xAF"})
    replaceAll(t, space, "");
  return t;
}

Unit unit(std::string_view cell) {
  std::vector<std::string> w = words(scan::trimmed(cell));
  // The unit of each field of a subcommand's payload, one per line: "Hex Hex Hex" is Hex.
  if (w.size() > 1 && std::all_of(w.begin(), w.end(), [&](const std::string& x) { return x == w[0]; }))
    w.resize(1);
  std::string joined;
  for (const std::string& s : w)
    joined += s;
  const std::string key = lower(joined);
  static const std::vector<std::string> none = {"",       "-",        "\xE2\x80\x94", "\xE2\x80\x93",
                                                "hex",    "十六进制", "ascii",        "n/a",
                                                "string", "flags",    "binary",       "num"};
  for (const std::string& n : none) {
    if (key == n) return {};
  }
  // SBS capacity and rate units: mAh or 10 mWh (mA or 10 mW) per BatteryMode[CAPM]; TI prints the two on
  // two lines of one cell.
  for (std::string_view sep : {"", "/", "|", "or"}) {
    if (key == "mah" + std::string(sep) + "10mwh" || key == "mah" + std::string(sep) + "cwh")
      return {"mAh|10mWh", ""};
    if (key == "ma" + std::string(sep) + "10mw") return {"mA|10mW", ""};
  }
  if (key == "10mwh") return {"cWh", ""};

  // A scale before the unit: "50.6 mV", "0.1°C", "190.73µV".
  std::string_view t = joined;
  std::string scale;
  const std::size_t whole = scan::run(t, 0, scan::isDigit);
  if (whole > 0) {
    std::size_t end = whole;
    if (end < t.size() && t[end] == '.') {
      const std::size_t fraction = scan::run(t, end + 1, scan::isDigit);
      if (fraction > 0) end += 1 + fraction;
    }
    if (end < t.size()) {
      scale = std::string(t.substr(0, end));
      t.remove_prefix(end);
    }
  }
  static const std::map<std::string, std::string, std::less<>> spellings = {
      {"°C", "degC"},       {"℃", "degC"},       {"degC", "degC"},    {"摄氏度", "degC"},
      {"°K", "K"},          {"µV", "uV"},        {"μV", "uV"},        {"µs", "us"},
      {"μs", "us"},         {"mΩ", "mOhm"},      {"m\u2126", "mOhm"}, {"mohm", "mOhm"},
      {"milliohm", "mOhm"}, {"%", "percent"},    {"sec", "s"},        {"secs", "s"},
      {"seconds", "s"},     {"秒", "s"},         {"毫秒", "ms"},      {"微秒", "us"},
      {"minutes", "min"},   {"分钟", "min"},     {"hr", "h"},         {"hrs", "h"},
      {"hour", "h"},        {"hours", "h"},      {"小时", "h"},       {"毫伏", "mV"},
      {"毫安", "mA"},       {"count", "counts"}, {"byte", "bytes"},   {"cycle", "cycles"},
      {"events", "counts"}, {"event", "counts"}, {"mah", "mAh"}};
  std::string u(t);
  if (auto it = spellings.find(u); it != spellings.end()) u = it->second;
  if (!findUnit(u)) {
    if (auto it = spellings.find(lower(u)); it != spellings.end()) u = it->second;
  }
  if (!findUnit(u)) return {"", "", false};
  if (scale == "1") scale.clear();
  return {u, scale};
}

std::optional<std::string> access(std::string_view cell) {
  std::optional<std::string> found;
  for (std::string w : words(cell)) {
    if (!w.empty() && w.back() == ':') w.pop_back();
    const std::string k = lower(w);
    if (k == "r" || k == "rc") {
      found = "r";
    } else if (k == "w") {
      found = "w";
    } else if (k == "r/w" || k == "rw" || k == "nvm") {
      found = "rw";  // NVM: an OTP-backed register, read and written like RW (BQ79616)
    } else if (k == "w1c" || k == "rw1c" || k == "r/w1c") {
      found = "rw1c";
    }
  }
  return found;
}

std::string name(std::string_view cell) {
  std::string out;
  for (const std::string& w : words(cell))
    out.append(out.empty() ? "" : " ").append(w);
  if (out.size() > 2 && out.ends_with("()")) out.resize(out.size() - 2);
  return std::string(scan::trimmed(out));
}

std::optional<std::string> fieldsType(std::string_view cell, bool bigEndian) {
  const std::vector<std::string> w = words(cell);
  if (w.size() < 2) return std::nullopt;
  int bytes = 0;
  bool same = true;
  for (const std::string& code : w) {
    const auto t = parseType(code);
    if (!t || t->variable || t->size() == 0) return std::nullopt;
    bytes += t->size();
    if (bytes > 32) return std::nullopt;
    same = same && code == w[0] && t->integer();
  }
  if (same && !bigEndian) return std::to_string(w.size()) + "x" + w[0];
  return "B" + std::to_string(bytes);
}

std::optional<std::string> typeFromWords(std::string_view type, std::string_view format,
                                         std::string_view size) {
  const std::string f = lower(name(format));
  // SLUUAQ3A prints the number format in its "Format" column ("Signed Int" with "Size in Bytes" 2).
  const std::string t = scan::trimmed(type).empty() ? f : lower(name(type));
  const std::string sz(scan::trimmed(size));
  int n = 0;
  if (scan::all(sz, scan::isDigit) && sz.size() <= 2) n = std::stoi(sz);
  if (n == 0) n = f == "word" ? 2 : f == "byte" ? 1 : 0;
  // Blocks first: the BQ4050 MAC table prints Type "Hex" for block data (Format "Block").
  const bool text = t == "string" || t == "ascii" || f == "string";
  if (text || t == "block" || f == "block") {
    const char base = text ? 'S' : 'B';
    if (n > 0 && n <= 32) return std::string(1, base) + std::to_string(n);
    return std::string(1, base);
  }
  const auto sized = [&](char base) -> std::optional<std::string> {
    if (n == 1 || n == 2 || n == 4) return std::string(1, base) + std::to_string(n);
    if (base == 'H' && n > 0 && n <= 32) return "B" + std::to_string(n);
    return std::nullopt;
  };
  if (t == "hex" || t == "hex flags") return sized('H');
  if (t == "unsigned int" || t == "unsigned" || t == "unsigned integer") return sized('U');
  if (t == "signed int" || t == "signed" || t == "integer" || t == "signed integer") return sized('I');
  if (t == "float" || t == "floating point") return std::optional<std::string>("F4");
  return std::nullopt;
}

std::optional<std::string> blockForWideHex(std::string_view type) {
  if (type.size() < 2 || type[0] != 'H' || !scan::all(type.substr(1), scan::isDigit) || type.size() > 3)
    return std::nullopt;
  const int n = std::stoi(std::string(type.substr(1)));
  if (n == 1 || n == 2 || n == 4 || n < 1 || n > 32) return std::nullopt;
  return "B" + std::to_string(n);
}

}  // namespace regmapgen::cells
