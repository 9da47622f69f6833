#include "model/names.hpp"

#include <array>
#include <cctype>
#include <cstdio>
#include <vector>

namespace regmapgen {

namespace {

bool alnum(char c) {
  return std::isalnum(static_cast<unsigned char>(c)) != 0;
}

std::vector<std::string> words(std::string_view name) {
  std::vector<std::string> out;
  std::string cur;
  for (char c : name) {
    if (alnum(c)) {
      cur += c;
    } else if (!cur.empty()) {
      out.push_back(std::move(cur));
      cur.clear();
    }
  }
  if (!cur.empty()) out.push_back(std::move(cur));
  return out;
}

}  // namespace

std::string pascalCase(std::string_view name) {
  std::string out;
  for (const std::string& w : words(name)) {
    bool hasLower = false;
    for (char c : w)
      hasLower = hasLower || std::islower(static_cast<unsigned char>(c));
    for (std::size_t i = 0; i < w.size(); ++i) {
      const auto c = static_cast<unsigned char>(w[i]);
      if (i == 0) {
        out += static_cast<char>(std::toupper(c));
      } else {
        out += hasLower ? static_cast<char>(c) : static_cast<char>(std::tolower(c));
      }
    }
  }
  return out;
}

std::string snakeCase(std::string_view name) {
  // Drop a trailing bit range such as "[1:0]" and a trailing '?' (the fact tables' "not sure" mark).
  while (!name.empty() && (name.back() == '?' || name.back() == ' '))
    name.remove_suffix(1);
  if (!name.empty() && name.back() == ']') {
    const std::size_t open = name.rfind('[');
    if (open != std::string_view::npos) name = name.substr(0, open);
  }
  std::string out;
  for (const std::string& w : words(name)) {
    if (!out.empty()) out += '_';
    for (char c : w)
      out += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  }
  return out;
}

bool isIdentifier(std::string_view s) {
  if (s.empty() || !(std::isalpha(static_cast<unsigned char>(s[0])) || s[0] == '_')) return false;
  for (char c : s) {
    if (!(alnum(c) || c == '_')) return false;
  }
  return true;
}

bool isCppKeyword(std::string_view s) {
  static constexpr std::array<std::string_view, 97> kWords = {
      "alignas",     "alignof",   "and",        "and_eq",    "asm",      "auto",         "bitand",
      "bitor",       "bool",      "break",      "case",      "catch",    "char",         "char8_t",
      "char16_t",    "char32_t",  "class",      "compl",     "concept",  "const",        "consteval",
      "constexpr",   "constinit", "const_cast", "continue",  "co_await", "co_return",    "co_yield",
      "decltype",    "default",   "delete",     "do",        "double",   "dynamic_cast", "else",
      "enum",        "explicit",  "export",     "extern",    "false",    "float",        "for",
      "friend",      "goto",      "if",         "inline",    "int",      "long",         "mutable",
      "namespace",   "new",       "noexcept",   "not",       "not_eq",   "nullptr",      "operator",
      "or",          "or_eq",     "private",    "protected", "public",   "register",     "reinterpret_cast",
      "requires",    "return",    "short",      "signed",    "sizeof",   "static",       "static_assert",
      "static_cast", "struct",    "switch",     "template",  "this",     "thread_local", "throw",
      "true",        "try",       "typedef",    "typeid",    "typename", "union",        "unsigned",
      "using",       "virtual",   "void",       "volatile",  "wchar_t",  "while",        "xor",
      "xor_eq",      "final",     "override",   "import",    "module",   "NULL"};
  for (std::string_view w : kWords) {
    if (w == s) return true;
  }
  return false;
}

bool isAscii(std::string_view s) {
  for (char c : s) {
    if (static_cast<unsigned char>(c) >= 0x80) return false;
  }
  return true;
}

std::string lookupKey(std::string_view name) {
  std::string out;
  for (char c : name) {
    if (c == '_' || c == ' ' || c == '-') continue;
    out += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  }
  return out;
}

std::string upperCase(std::string_view s) {
  std::string out(s);
  for (char& c : out)
    c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return out;
}

std::string hexAddress(std::uint64_t value, int digits) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "0x%0*llX", digits, static_cast<unsigned long long>(value));
  return buf;
}

}  // namespace regmapgen
