// Finds the register tables in a text and returns them as heading rows and data rows, whatever shape the
// text came in:
// - rows of cells separated by '|' (Markdown, web pages) or tabs (copied from a PDF viewer): one row per
// line,
//   a table ends at the first line without separators;
// - `pdftotext -layout` text, where columns are runs of spaces. The heading row gives the columns (a heading
//   wrapped over two lines is joined; single-space runs of headings such as "Min Value Max Value" are split
//   into the known headings). The boundary between two columns is the rightmost position of the heading gap
//   that is blank in every line of the table (so numbers that run left of their heading stay in their
//   column), else the next heading's start. A line whose key cell (the address column, else the class column)
//   is filled starts a row; a line with the key cell empty continues the row above: its cells are appended to
//   the row's (wrapped names, descriptions, units such as "50.6" above "mV"). Page furniture (furniture.hpp)
//   is skipped, and a table continued on the next page under a repeated heading row is one table. A line
//   whose key cell holds something that is not a key, a continuation line running across three or more
//   columns (prose), a caption of another table, or a continuation line after a blank line ends the table. An
//   empty class or subclass cell takes the value of the row above (TI prints a merged cell once).
// Everything outside tables comes back as prose, in order, so the caller can read addresses named in the
// text.
//
// Bounds: a line longer than kMaxLineLength bytes is an error (the text is not read further); every step is
// linear in the line length and no step recurses.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "import/headings.hpp"

namespace regmapgen {

inline constexpr std::size_t kMaxImportLineLength = 4096;

struct TableCell {
  std::string text;
  int line = 0;
  int col = 1;  // 1-based column (code points) of the cell's first character
};

struct TableEvent {
  enum class Kind { Prose, Heading, Row };
  Kind kind = Kind::Prose;
  int line = 0;
  std::string text;              // Prose: the line
  std::vector<TableCell> cells;  // Heading: the headings; Row: the cells (layout rows: one per heading)
  std::vector<Role> roles;       // Heading: the role of each heading cell
  bool continued = false;        // Heading: repeats the previous table's headings after a page break
};

struct TableText {
  std::vector<TableEvent> events;
  struct Problem {
    int line = 0;
    int col = 1;
    std::string message;
  };
  std::vector<Problem> errors;  // input that cannot be read (too long a line); events are then incomplete
};

TableText readTables(const std::string& text);

}  // namespace regmapgen
