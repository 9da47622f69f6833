#include "diag/diag.hpp"

#include <algorithm>
#include <fstream>
#include <sstream>
#include <tuple>

namespace regmapgen {

int Sources::add(std::string path, std::string text) {
  files_.push_back({std::move(path), std::move(text)});
  return static_cast<int>(files_.size() - 1);
}

bool readFile(const std::string& path, std::string& text) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  std::ostringstream ss;
  ss << in.rdbuf();
  text = ss.str();
  return true;
}

std::string Sources::lineText(int file, int line) const {
  if (file < 0 || static_cast<std::size_t>(file) >= files_.size() || line < 1) return {};
  const std::string& t = text(file);
  std::size_t pos = 0;
  for (int l = 1; l < line; ++l) {
    pos = t.find('\n', pos);
    if (pos == std::string::npos) return {};
    ++pos;
  }
  std::size_t end = t.find('\n', pos);
  if (end == std::string::npos) end = t.size();
  std::string s = t.substr(pos, end - pos);
  if (!s.empty() && s.back() == '\r') s.pop_back();
  return s;
}

int columnOf(const std::string& text, std::size_t lineStart, std::size_t offset) {
  int col = 1;
  for (std::size_t i = lineStart; i < offset && i < text.size(); ++i) {
    // Continuation bytes (10xxxxxx) do not start a code point.
    if ((static_cast<unsigned char>(text[i]) & 0xC0) != 0x80) ++col;
  }
  return col;
}

void Diagnostics::add(Severity s, Loc loc, std::string message) {
  items_.push_back({s, loc, std::move(message)});
}

std::size_t Diagnostics::errorCount() const {
  return static_cast<std::size_t>(std::count_if(
      items_.begin(), items_.end(), [](const Diagnostic& d) { return d.severity == Severity::Error; }));
}

std::size_t Diagnostics::warningCount() const {
  return static_cast<std::size_t>(std::count_if(
      items_.begin(), items_.end(), [](const Diagnostic& d) { return d.severity == Severity::Warning; }));
}

void Diagnostics::render(std::ostream& out) const {
  // A note belongs to the diagnostic before it; sort groups (primary + its notes) by the primary's position.
  std::vector<std::vector<const Diagnostic*>> groups;
  for (const Diagnostic& d : items_) {
    if (d.severity == Severity::Note && !groups.empty()) {
      groups.back().push_back(&d);
    } else {
      groups.push_back({&d});
    }
  }
  auto key = [](const Diagnostic* d) { return std::make_tuple(d->loc.file, d->loc.line, d->loc.col); };
  std::stable_sort(groups.begin(), groups.end(),
                   [&](const auto& a, const auto& b) { return key(a.front()) < key(b.front()); });

  for (const auto& group : groups) {
    for (const Diagnostic* d : group) {
      const char* label = d->severity == Severity::Error     ? "error"
                          : d->severity == Severity::Warning ? "warning"
                                                             : "note";
      if (d->loc.file >= 0) {
        out << sources_.path(d->loc.file) << ':' << d->loc.line << ':' << d->loc.col << ": ";
      } else {
        out << "regmapgen: ";
      }
      out << label << ": " << d->message << '\n';
      if (d->loc.file >= 0 && d->loc.line > 0) {
        std::string line = sources_.lineText(d->loc.file, d->loc.line);
        // Show tabs as spaces so the caret stays aligned in any terminal.
        std::replace(line.begin(), line.end(), '\t', ' ');
        out << "  " << line << "\n  "
            << std::string(static_cast<std::size_t>(std::max(d->loc.col - 1, 0)), ' ') << "^\n";
      }
    }
  }
}

}  // namespace regmapgen
