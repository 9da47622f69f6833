#include "import/bit_fields.hpp"

#include "text/scan.hpp"

namespace regmapgen::bit_fields {

namespace {

// The dashes TI prints between two ends: '-', en dash, em dash.
std::size_t dashAt(std::string_view s, std::size_t& width) {
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s[i] == '-') {
      width = 1;
      return i;
    }
    if (s.substr(i).starts_with("\xE2\x80\x93") || s.substr(i).starts_with("\xE2\x80\x94")) {
      width = 3;
      return i;
    }
  }
  return std::string_view::npos;
}

std::string withoutSpaces(std::string_view s) {
  std::string out;
  for (char c : s) {
    if (c != ' ') out += c;
  }
  return out;
}

}  // namespace

std::optional<Bits> bits(std::string_view cell) {
  const std::string t = withoutSpaces(scan::trimmed(cell));
  const std::string_view s = t;
  const std::size_t a = scan::run(s, 0, scan::isDigit);
  if (a == 0 || a > 2) return std::nullopt;
  Bits b;
  b.msb = b.lsb = std::stoi(std::string(s.substr(0, a)));
  if (a < s.size()) {
    std::size_t width = 1;
    std::size_t at = a;
    if (s[a] == ':') {
      width = 1;
    } else if (dashAt(s.substr(a), width) != 0) {
      return std::nullopt;
    }
    at += width;
    const std::size_t c = scan::run(s, at, scan::isDigit);
    if (c == 0 || c > 2 || at + c != s.size()) return std::nullopt;
    b.lsb = std::stoi(std::string(s.substr(at, c)));
  }
  if (b.msb > 31 || b.lsb > b.msb) return std::nullopt;
  b.text = b.msb == b.lsb ? std::to_string(b.msb) : std::to_string(b.msb) + ":" + std::to_string(b.lsb);
  return b;
}

std::string name(std::string_view cell, const Bits& b) {
  const std::string t = withoutSpaces(scan::trimmed(cell));
  if (b.msb == b.lsb) return t;
  const std::string range = "[" + std::to_string(b.msb - b.lsb) + ":0]";
  std::size_t width = 1;
  const std::size_t dash = dashAt(t, width);
  std::string base;
  if (dash != std::string::npos && dash > 0) {
    // "SEC1–SEC0": the part both ends share, before the bit numbers.
    const std::string_view hi = std::string_view(t).substr(0, dash),
                           lo = std::string_view(t).substr(dash + width);
    std::size_t common = 0;
    while (common < hi.size() && common < lo.size() && hi[common] == lo[common])
      ++common;
    while (common > 0 && scan::isDigit(hi[common - 1]))
      --common;
    if (common == 0 || !scan::all(hi.substr(common), scan::isDigit) ||
        !scan::all(lo.substr(common), scan::isDigit))
      return t;
    base = std::string(hi.substr(0, common));
  } else if (const std::size_t colon = t.find(':'); colon != std::string::npos) {
    // "SEC1:0"
    std::size_t start = colon;
    while (start > 0 && scan::isDigit(t[start - 1]))
      --start;
    if (start == 0 || start == colon) return t;
    base = t.substr(0, start);
  } else {
    return t;
  }
  while (!base.empty() && base.back() == '_')
    base.pop_back();
  return base.empty() ? t : base + range;
}

bool reserved(std::string_view name) {
  const std::string_view t = scan::trimmed(name);
  return t.starts_with("RSVD") || t == "Reserved" || t == "RESERVED" || t == "—" || t == "-";
}

std::string meaning(std::string_view description) {
  std::string_view t = scan::trimmed(description);
  for (std::string_view marker : {" 0 = ", " 0: ", " 0x0 = "}) {
    if (const std::size_t at = t.find(marker); at != std::string_view::npos) t = t.substr(0, at);
  }
  if (t.starts_with("0 = ")) t = {};
  constexpr std::size_t kMax = 200;
  std::string out(scan::trimmed(t));
  if (out.size() > kMax) {
    std::size_t cut = out.rfind(' ', kMax);
    if (cut == std::string::npos) cut = kMax;
    out = out.substr(0, cut) + "...";
  }
  return out;
}

}  // namespace regmapgen::bit_fields
