#include "diag/diag.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <tuple>

namespace regmapgen {

namespace {

// The part of `line` shown under a diagnostic: all of it when short, otherwise a window of kWindow code
// points around column `col` with "..." marking what was cut. Updates `col` to the caret's column in the
// result.
constexpr int kLongLine = 160;
// A file broken on every line (a binary, a wrong file) would print pages of the same problem; the counts
// printed by the callers still include every diagnostic.
constexpr std::size_t kMaxShown = 200;
constexpr int kWindow = 120;

std::string window(const std::string& line, int& col) {
  std::vector<std::size_t> starts;  // byte offset of each code point
  for (std::size_t i = 0; i < line.size(); ++i) {
    if ((static_cast<unsigned char>(line[i]) & 0xC0) != 0x80) starts.push_back(i);
  }
  const int count = static_cast<int>(starts.size());
  if (count <= kLongLine) return line;
  const int first = std::clamp(col - 1 - kWindow / 2, 0, count - kWindow);
  const int last = first + kWindow;  // one past
  const std::size_t from = starts[static_cast<std::size_t>(first)];
  const std::size_t to = last < count ? starts[static_cast<std::size_t>(last)] : line.size();
  std::string out = (first > 0 ? "..." : "") + line.substr(from, to - from) + (last < count ? "..." : "");
  col = col - first + (first > 0 ? 3 : 0);
  return out;
}

}  // namespace

int Sources::add(std::string path, std::string text) {
  File f{std::move(path), std::move(text), {0}};
  for (std::size_t pos = f.text.find('\n'); pos != std::string::npos; pos = f.text.find('\n', pos + 1))
    f.lineStarts.push_back(pos + 1);
  files_.push_back(std::move(f));
  return static_cast<int>(files_.size() - 1);
}

namespace {

std::string limitText() {
  return "inputs are limited to " + std::to_string(kMaxInputBytes >> 20) + " MiB";
}

// Reads `fd` to its end, at most kMaxInputBytes.
bool readAll(int fd, std::string& text, std::string* why) {
  text.clear();
  char buf[65536];
  for (;;) {
    const ssize_t n = ::read(fd, buf, sizeof buf);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      if (why) *why = std::strerror(errno);
      return false;
    }
    if (n == 0) return true;
    if (text.size() + static_cast<std::size_t>(n) > kMaxInputBytes) {
      if (why) *why = "holds more than " + std::to_string(kMaxInputBytes) + " bytes; " + limitText();
      text.clear();
      return false;
    }
    text.append(buf, static_cast<std::size_t>(n));
  }
}

}  // namespace

bool readFile(const std::string& path, std::string& text, std::string* why) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) {
    if (why) *why = std::strerror(errno);
    return false;
  }
  struct stat st {};
  bool ok = false;
  if (::fstat(fd, &st) != 0) {
    if (why) *why = std::strerror(errno);
  } else if (S_ISDIR(st.st_mode)) {
    if (why) *why = "is a directory";
  } else if (!S_ISREG(st.st_mode) && !S_ISFIFO(st.st_mode)) {
    if (why) *why = "is a device, not a file";
  } else if (S_ISREG(st.st_mode) && static_cast<std::uint64_t>(st.st_size) > kMaxInputBytes) {
    if (why) *why = "is " + std::to_string(st.st_size) + " bytes; " + limitText();
  } else {
    ok = readAll(fd, text, why);
  }
  ::close(fd);
  return ok;
}

bool readStdin(std::string& text, std::string* why) {
  return readAll(STDIN_FILENO, text, why);
}

std::string Sources::lineText(int file, int line) const {
  if (file < 0 || static_cast<std::size_t>(file) >= files_.size() || line < 1) return {};
  const File& f = files_[static_cast<std::size_t>(file)];
  const auto index = static_cast<std::size_t>(line - 1);
  if (index >= f.lineStarts.size()) return {};
  const std::size_t pos = f.lineStarts[index];
  std::size_t end = f.text.find('\n', pos);
  if (end == std::string::npos) end = f.text.size();
  std::string s = f.text.substr(pos, end - pos);
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

  std::size_t shown = 0;
  for (const auto& group : groups) {
    if (shown++ == kMaxShown) {
      out << "regmapgen: " << groups.size() - kMaxShown << " more diagnostic(s) not shown\n";
      break;
    }
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
        int col = d->loc.col;
        std::string line = window(sources_.lineText(d->loc.file, d->loc.line), col);
        // Show tabs as spaces so the caret stays aligned in any terminal.
        std::replace(line.begin(), line.end(), '\t', ' ');
        out << "  " << line << "\n  " << std::string(static_cast<std::size_t>(std::max(col - 1, 0)), ' ')
            << "^\n";
      }
    }
  }
}

}  // namespace regmapgen
