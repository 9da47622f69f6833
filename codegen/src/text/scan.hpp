// Small character scanners used instead of std::regex: libstdc++'s regex matcher recurses once per input
// character, so a 50 000-character value overflowed the stack (issue 15). These run in one linear pass with
// no recursion, whatever the input.
#pragma once

#include <cstddef>
#include <string_view>

namespace regmapgen::scan {

inline bool isDigit(char c) {
  return c >= '0' && c <= '9';
}
inline bool isHexDigit(char c) {
  return isDigit(c) || (c >= 'a' && c <= 'f') || (c >= 'A' && c <= 'F');
}
inline bool isUpper(char c) {
  return c >= 'A' && c <= 'Z';
}
inline bool isLower(char c) {
  return c >= 'a' && c <= 'z';
}
inline bool isAlpha(char c) {
  return isUpper(c) || isLower(c);
}

// The number of characters from `pos` on that satisfy `pred`.
template <class Pred>
std::size_t run(std::string_view s, std::size_t pos, Pred pred) {
  std::size_t n = 0;
  while (pos + n < s.size() && pred(s[pos + n]))
    ++n;
  return n;
}

// True if `s` is not empty and every character satisfies `pred`.
template <class Pred>
bool all(std::string_view s, Pred pred) {
  return !s.empty() && run(s, 0, pred) == s.size();
}

// A decimal real as TI's tables print F4 values: 7.4768, 5., .5, 1.00E-02, 4.193046E+08, with an optional
// sign.
inline bool isDecimalReal(std::string_view s) {
  std::size_t i = (!s.empty() && (s[0] == '+' || s[0] == '-')) ? 1 : 0;
  const std::size_t whole = run(s, i, isDigit);
  i += whole;
  std::size_t fraction = 0;
  if (i < s.size() && s[i] == '.') {
    fraction = run(s, i + 1, isDigit);
    i += 1 + fraction;
  }
  if (whole == 0 && fraction == 0) return false;
  if (i < s.size() && (s[i] == 'e' || s[i] == 'E')) {
    ++i;
    if (i < s.size() && (s[i] == '+' || s[i] == '-')) ++i;
    const std::size_t exponent = run(s, i, isDigit);
    if (exponent == 0) return false;
    i += exponent;
  }
  return i == s.size();
}

// `s` without spaces, tabs, carriage returns and U+3000 ideographic spaces at either end.
inline std::string_view trimmed(std::string_view s) {
  constexpr std::string_view ideographic = "\xE3\x80\x80";
  for (;;) {
    if (!s.empty() && (s.front() == ' ' || s.front() == '\t' || s.front() == '\r')) {
      s.remove_prefix(1);
    } else if (s.starts_with(ideographic)) {
      s.remove_prefix(ideographic.size());
    } else {
      break;
    }
  }
  for (;;) {
    if (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) {
      s.remove_suffix(1);
    } else if (s.ends_with(ideographic)) {
      s.remove_suffix(ideographic.size());
    } else {
      break;
    }
  }
  return s;
}

// "0x" or "0X" followed by one or more hex digits, nothing else.
inline bool isHexLiteral(std::string_view s) {
  return s.size() > 2 && s[0] == '0' && (s[1] == 'x' || s[1] == 'X') && all(s.substr(2), isHexDigit);
}

}  // namespace regmapgen::scan
