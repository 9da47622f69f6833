#include "emit/lines.hpp"

#include <algorithm>

namespace regmapgen {

void writeComment(std::ostringstream& o, std::string_view text, std::size_t indent) {
  const std::string prefix = std::string(indent, ' ') + "//";
  std::string line = prefix;
  std::size_t pos = 0;
  bool empty = true;
  while (pos < text.size()) {
    const std::size_t start = text.find_first_not_of(' ', pos);
    if (start == std::string_view::npos) break;
    std::size_t end = text.find(' ', start);
    if (end == std::string_view::npos) end = text.size();
    const std::string_view word = text.substr(start, end - start);
    if (!empty && line.size() + 1 + word.size() > kColumnLimit) {
      o << line << '\n';
      line = prefix;
      empty = true;
    }
    line.append(" ").append(word);
    empty = false;
    pos = end;
  }
  o << line << '\n';
}

void writeBraced(std::ostringstream& o, std::size_t indent, const std::string& head,
                 const std::vector<std::string>& members, const std::string& tail) {
  std::string one = head + "{";
  for (std::size_t i = 0; i < members.size(); ++i)
    one.append(i ? ", " : "").append(members[i]);
  one.append("}").append(tail);
  if (indent + one.size() <= kColumnLimit || members.empty()) {
    o << one << '\n';
    return;
  }
  const std::string pad(indent, ' ');
  o << head << "{\n";
  for (const std::string& m : members)
    o << pad << "    " << m << ",\n";
  o << pad << "}" << tail << '\n';
}

void writeDeclaration(std::ostringstream& o, const std::string& type, const std::string& name) {
  if (type.size() + 1 + name.size() + 3 <= kColumnLimit) {
    o << type << ' ' << name << "{};\n";
  } else {
    o << type << "\n    " << name << "{};\n";
  }
}

void writeCommented(std::ostringstream& o, const std::vector<std::pair<std::string, std::string>>& lines) {
  std::size_t width = 0;
  bool fits = true;
  for (const auto& [code, comment] : lines) {
    if (!comment.empty()) width = std::max(width, code.size());
  }
  for (const auto& [code, comment] : lines) {
    if (!comment.empty() && width + 2 + 3 + comment.size() > kColumnLimit) fits = false;
  }
  for (const auto& [code, comment] : lines) {
    if (comment.empty()) {
      o << code << '\n';
    } else if (fits) {
      o << code << std::string(width + 2 - code.size(), ' ') << "// " << comment << '\n';
    } else {
      writeComment(o, comment, code.find_first_not_of(' '));
      o << code << '\n';
    }
  }
}

}  // namespace regmapgen
