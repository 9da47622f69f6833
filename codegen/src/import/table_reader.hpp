// Finds the register tables in a text and returns them as heading rows and data rows, whatever shape the
// text came in:
// - rows of cells separated by '|' (Markdown, web pages) or tabs (copied from a PDF viewer): one row per
//   line, a table ends at the first line without separators;
// - `pdftotext -layout` text, where columns are runs of spaces. The heading row gives the columns (a heading
//   wrapped over two lines is joined; single-space runs of headings such as "Min Value Max Value" are split
//   into the known headings). The boundary between two columns is the rightmost position of the heading gap
//   that is blank in every line of the table (so numbers that run left of their heading stay in their
//   column), else the next heading's start. A line whose key cell (the address column, else the class column,
//   else the bit column of a bit-field table) holds a key is a row's key line; every other line of the table
//   belongs to one row:
//   - TI prints a row's cells either from the row's top (the key line is the row's first line) or centred on
//     the row (the key line is in the middle, with wrapped cells above and below it: "Sealed: R" over the
//     command's line over "Full Access: R", "Coulomb Counter Offset" over the address line over "Samples"). A
//     table whose first line is not a key line is centred; a table continued on a new page keeps the
//     alignment of its first part.
//   - Top-aligned: a line belongs to the key line above it. Centred: blank lines separate rows; within a run
//     of lines without a blank, a line belongs to the nearer key line, and a line halfway between two goes to
//     the row whose key line leaves that column empty (the cell is centred on it), else to the row above.
//   Lines of a row are joined cell by cell in line order (wrapped names, "50.6" over "mV", access over three
//   lines). Page furniture (furniture.hpp) is skipped, and a table continued on the next page under a
//   repeated heading row is one table. A line whose key cell holds something that is not a key, a line
//   running across three or more columns (prose), a caption, a section heading, or (after a blank line) a
//   line that neither has a key, nor a payload offset, nor leads to a key line within a few lines ends the
//   table. An empty class or subclass cell takes the value of the row above (TI prints a merged cell once).
// Everything outside tables comes back as prose, in order, so the caller can read addresses named in the
// text. Each table heading carries the caption above it ("Table 12-1. Direct Commands Table", also for its
// continuations) and the numbered section it is in ("13.2.1.1 Calibration:Voltage:Cell 1 Gain").
//
// Bounds: a line longer than kMaxImportLineLength bytes is an error (the text is not read further); every
// step is linear in the text (lookahead is bounded by a few lines) and no step recurses.
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
  std::string caption;           // Heading: "Table 12-1. Direct Commands Table", or "" (none just above)
  int captionLine = 0;
  std::string section;  // Heading: the numbered section heading before the table, or ""
  int sectionLine = 0;
  int proseSinceSection = 0;  // Heading: lines of prose between that section heading and the table
};

struct TableText {
  std::vector<TableEvent> events;
  struct Problem {
    int line = 0;
    int col = 1;
    std::string message;
  };
  std::vector<Problem> errors;  // input that cannot be read (too long a line); events are then incomplete
  std::vector<int> pageStarts;  // the line each page starts on (pages are separated by form feeds); [0] = 1
};

// The page (0-based: the index into pageStarts) line `line` is on.
int pageOf(const TableText& t, int line);

TableText readTables(const std::string& text);

}  // namespace regmapgen
