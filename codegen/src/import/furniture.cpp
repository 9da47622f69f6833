#include "import/furniture.hpp"

#include <array>
#include <string>

#include "text/scan.hpp"

namespace regmapgen {

namespace {

bool startsWithNoCase(std::string_view s, std::string_view prefix) {
  if (s.size() < prefix.size()) return false;
  for (std::size_t i = 0; i < prefix.size(); ++i) {
    char c = s[i];
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
    if (c != prefix[i]) return false;
  }
  return true;
}

// A literature number as printed in footers: two capitals, then capitals and digits, 6..10 in all, with at
// least one digit (SLUUBY2B, SLUSE81E, SLUUAQ3A, ZHCSJM7).
bool isLiteratureToken(std::string_view t) {
  const auto alnum = [](char c) { return scan::isUpper(c) || scan::isDigit(c); };
  return t.size() >= 6 && t.size() <= 10 && scan::isUpper(t[0]) && scan::isUpper(t[1]) &&
         scan::all(t, alnum) && t.find_first_of("0123456789") != std::string_view::npos;
}

// After a literature number: spaces, a dash (-, U+2013 or U+2014), spaces, then a month name or a year.
bool followedByDate(std::string_view rest) {
  std::size_t i = scan::run(rest, 0, [](char c) { return c == ' '; });
  rest.remove_prefix(i);
  if (rest.starts_with("-")) {
    rest.remove_prefix(1);
  } else if (rest.starts_with("\xE2\x80\x93") || rest.starts_with("\xE2\x80\x94")) {
    rest.remove_prefix(3);
  } else {
    return false;
  }
  rest.remove_prefix(scan::run(rest, 0, [](char c) { return c == ' '; }));
  static constexpr std::array<std::string_view, 12> months = {"jan", "feb", "mar", "apr", "may", "jun",
                                                              "jul", "aug", "sep", "oct", "nov", "dec"};
  for (std::string_view m : months) {
    if (startsWithNoCase(rest, m)) return true;
  }
  return scan::run(rest, 0, scan::isDigit) == 4;
}

bool hasFooterDocumentId(std::string_view line) {
  for (std::size_t i = 0; i < line.size();) {
    if (line[i] == ' ') {
      ++i;
      continue;
    }
    std::size_t j = i;
    while (j < line.size() && line[j] != ' ')
      ++j;
    if (isLiteratureToken(line.substr(i, j - i)) && followedByDate(line.substr(j))) return true;
    i = j;
  }
  return false;
}

}  // namespace

bool isPageFurniture(std::string_view line) {
  const std::string_view t = scan::trimmed(line);
  if (t.empty()) return false;
  if (t.size() <= 4 && scan::all(t, scan::isDigit)) return true;
  for (std::string_view marker :
       {"www.ti.com", "Texas Instruments Incorporated", "Submit Document Feedback", "Product Folder Links"}) {
    if (t.find(marker) != std::string_view::npos) return true;
  }
  return hasFooterDocumentId(t);
}

bool isTableCaption(std::string_view line) {
  const std::string_view t = scan::trimmed(line);
  if (!t.starts_with("Table ")) return false;
  // "Table 13-1." / "Table 12." (a hyphen, or the en dash some documents print)
  std::size_t i = 6 + scan::run(t, 6, scan::isDigit);
  if (i == 6) return false;
  if (t.substr(i).starts_with("-")) {
    i = i + 1 + scan::run(t, i + 1, scan::isDigit);
  } else if (t.substr(i).starts_with("\xE2\x80\x93")) {
    i = i + 3 + scan::run(t, i + 3, scan::isDigit);
  }
  return i < t.size() && t[i] == '.';
}

bool isContinuedCaption(std::string_view line) {
  return isTableCaption(line) && line.find("(continued)") != std::string_view::npos;
}

std::string_view captionText(std::string_view line) {
  std::string_view t = scan::trimmed(line);
  if (const std::size_t c = t.find("(continued)"); c != std::string_view::npos)
    t = scan::trimmed(t.substr(0, c));
  return t;
}

bool isSectionHeading(std::string_view line) {
  if (line.empty() || !scan::isDigit(line[0]) || line.find("....") != std::string_view::npos) return false;
  std::size_t i = 0;
  int numbers = 0;
  for (;;) {
    const std::size_t digits = scan::run(line, i, scan::isDigit);
    if (digits == 0 || digits > 3) return false;
    i += digits;
    ++numbers;
    if (i < line.size() && line[i] == '.' && i + 1 < line.size() && scan::isDigit(line[i + 1])) {
      ++i;
      continue;
    }
    break;
  }
  if (numbers < 2 || i >= line.size() || line[i] != ' ') return false;
  const std::string_view title = scan::trimmed(line.substr(i));
  return !title.empty() && (scan::isUpper(title[0]) || scan::isDigit(title[0]));
}

}  // namespace regmapgen
