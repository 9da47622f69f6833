#include "import/captions.hpp"

#include <array>

#include "model/names.hpp"
#include "text/scan.hpp"

namespace regmapgen {

namespace {

// The title after "Table 12-1. ".
std::string_view captionTitle(std::string_view caption) {
  const std::size_t dot = caption.find(". ");
  return dot == std::string_view::npos ? std::string_view() : scan::trimmed(caption.substr(dot + 2));
}

std::string lower(std::string_view s) {
  std::string out(s);
  for (char& c : out) {
    if (scan::isUpper(c)) c = static_cast<char>(c - 'A' + 'a');
  }
  return out;
}

}  // namespace

bool isSummaryCaption(std::string_view caption) {
  static constexpr std::array<std::string_view, 24> vocabulary = {"table",
                                                                  "of",
                                                                  "summary",
                                                                  "list",
                                                                  "standard",
                                                                  "direct",
                                                                  "command",
                                                                  "commands",
                                                                  "subcommand",
                                                                  "subcommands",
                                                                  "command-only",
                                                                  "data",
                                                                  "memory",
                                                                  "flash",
                                                                  "register",
                                                                  "registers",
                                                                  "map",
                                                                  "sbs",
                                                                  "manufactureraccess",
                                                                  "manufacturer",
                                                                  "access",
                                                                  "extended",
                                                                  "with",
                                                                  "mac"};
  const std::string title = lower(captionTitle(caption));
  if (title.empty()) return false;
  bool kindWord = false;
  for (std::size_t i = 0; i < title.size();) {
    if (title[i] == ' ') {
      ++i;
      continue;
    }
    std::size_t j = title.find(' ', i);
    if (j == std::string::npos) j = title.size();
    // Words without brackets: "ManufacturerAccess()", "(MAC)".
    std::string w;
    for (char c : std::string_view(title).substr(i, j - i)) {
      if (c != '(' && c != ')') w += c;
    }
    bool known = w.empty();
    for (std::string_view v : vocabulary)
      known = known || w == v;
    if (!known) return false;
    kindWord = kindWord ||
               (w != "table" && w != "of" && w != "with" && w != "summary" && w != "list" && w != "standard");
    i = j;
  }
  return kindWord;
}

std::string fieldTableRegister(std::string_view caption, std::string_view section) {
  for (std::string_view suffix :
       {" Register Field Descriptions", " Field Descriptions", " Bit Definitions"}) {
    const std::string_view title = captionTitle(caption);
    if (title.ends_with(suffix))
      return std::string(scan::trimmed(title.substr(0, title.size() - suffix.size())));
  }
  const std::string_view t = sectionTitle(section);
  if (t.ends_with(" Register")) return std::string(t.substr(0, t.size() - 9));
  return "";
}

std::string captionNumber(std::string_view caption) {
  if (!caption.starts_with("Table ")) return "";
  const std::size_t dot = caption.find('.');
  return std::string(caption.substr(6, dot == std::string_view::npos ? std::string_view::npos : dot - 6));
}

std::string_view sectionTitle(std::string_view section) {
  const std::size_t space = section.find(' ');
  return space == std::string_view::npos ? std::string_view() : scan::trimmed(section.substr(space));
}

}  // namespace regmapgen
