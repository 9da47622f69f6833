// Diagnostics: every problem regmapgen finds, with the file:line:col it points at.
//
// Contract
// - A Loc names a source file (by index into Sources) and a 1-based line and column; column counts Unicode
//   code points, so a caret lines up under Chinese text as well as ASCII.
// - Diagnostics collects errors and warnings and never stops early: the reader, the model builder and the
//   checker all report into one sink so a single run shows every problem.
// - render() prints each as "file:line:col: error: message", then the source line and a caret line, sorted by
//   file, line and column (stable for equal positions), so golden tests are deterministic. A source line
//   longer than 160 code points is shown as a window of it around the caret. At most 200 diagnostics are
//   printed, then how many more there were.
#pragma once

#include <cstddef>
#include <ostream>
#include <string>
#include <vector>

namespace regmapgen {

struct Loc {
  int file = -1;  // index into Sources; -1 = no position (command-line level problems)
  int line = 0;
  int col = 0;
};

// The text of every input file, kept so diagnostics can show the offending line.
class Sources {
 public:
  int add(std::string path, std::string text);
  const std::string& path(int file) const { return files_[static_cast<std::size_t>(file)].path; }
  const std::string& text(int file) const { return files_[static_cast<std::size_t>(file)].text; }
  // Line `line` (1-based) of `file` without its newline; empty if out of range.
  std::string lineText(int file, int line) const;
  std::size_t size() const { return files_.size(); }

 private:
  struct File {
    std::string path;
    std::string text;
    std::vector<std::size_t> lineStarts;  // offset of each line, so lineText() does not rescan the file
  };
  std::vector<File> files_;
};

// The most bytes regmapgen reads from one input (a YAML map, a table text, a PDF, standard input or the text
// pdftotext makes of a PDF). The largest real input, a 209-page TRM, is under 4 MiB as PDF and as text.
inline constexpr std::size_t kMaxInputBytes = std::size_t{64} << 20;

// Reads the whole file at `path` (bytes as they are) into `text`. False, with `why` saying it in words ("is
// a directory", "is a device, not a file", "is 104857600 bytes; inputs are limited to 64 MiB", "No such
// file or directory"), when it cannot be opened or read, is not a regular file or a pipe, or holds more than
// kMaxInputBytes: a file's size is checked before it is read, a pipe stops being read one byte past the
// limit, so no input makes regmapgen read or wait without end (/dev/zero is a device and is refused).
bool readFile(const std::string& path, std::string& text, std::string* why = nullptr);

// Reads standard input the same way (at most kMaxInputBytes).
bool readStdin(std::string& text, std::string* why = nullptr);

enum class Severity { Error, Warning, Note };

struct Diagnostic {
  Severity severity;
  Loc loc;
  std::string message;
};

class Diagnostics {
 public:
  explicit Diagnostics(const Sources& sources) : sources_(sources) {}

  void error(Loc loc, std::string message) { add(Severity::Error, loc, std::move(message)); }
  void warning(Loc loc, std::string message) { add(Severity::Warning, loc, std::move(message)); }
  void note(Loc loc, std::string message) { add(Severity::Note, loc, std::move(message)); }

  const Sources& sources() const { return sources_; }
  std::size_t errorCount() const;
  std::size_t warningCount() const;
  const std::vector<Diagnostic>& all() const { return items_; }

  // Prints every diagnostic (sorted) with source line and caret; notes follow the error they were added
  // after.
  void render(std::ostream& out) const;

 private:
  void add(Severity s, Loc loc, std::string message);

  const Sources& sources_;
  std::vector<Diagnostic> items_;
};

// Number of code points in the first `bytes` bytes of a UTF-8 string, plus one (a 1-based column).
int columnOf(const std::string& text, std::size_t lineStart, std::size_t offset);

}  // namespace regmapgen
