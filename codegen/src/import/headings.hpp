// Column headings of TI register tables: which column of a table holds what (address, name, type...).
//
// Headings are matched case-insensitively after collapsing spaces; a heading PDF extraction printed twice
// ("类型 类型") counts once, and a heading wrapped over two lines ("SBS" above "Cmd", "Min" above "Value") is
// matched after its parts are joined. splitHeadings() splits a run of headings that a single space separates
// ("Min Value Max Value Default") into the known headings it consists of.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace regmapgen {

enum class Role {
  Address,
  Name,
  EnglishName,
  Unit,
  Type,
  Format,  // BQ4050 "Format"/"Protocol": Block, Word, Hex... (a type code is derived with Size)
  Size,    // "Size in Bytes"
  Offset,  // payload offset of a subcommand's field (BQ769x2 subcommand tables)
  Description,
  Category,
  Subcategory,
  Min,
  Max,
  Default,
  Data,
  Access,
  Bit,    // bit-field tables: "Bit" (7, 15–8)
  Field,  // bit-field tables: "Field" (the field's name)
  Unknown
};

// The role a heading cell names, or Role::Unknown.
Role roleOf(std::string_view heading);

// The recognised headings, one line per role, for `regmapgen import --help`.
std::string headingHelp();

// A heading cell that is several known headings separated by single spaces ("Min Value Max Value") as the
// byte offsets of its parts in `text`; empty when `text` is not made only of known headings (or is one).
std::vector<std::pair<std::size_t, std::size_t>> splitHeadings(std::string_view text);

// A cheap test run on every line before it is cut into columns: true when at least two of its words (runs
// without spaces, lower-cased) begin a known heading ("Command  Name  Units" yes, prose almost never), so
// the text of a 200-page TRM is not matched heading by heading.
bool mayBeHeading(std::string_view line);

// A row of heading cells starts a table: it names an address or a class column and a name column (or, for a
// bit-field table, a bit and a field column), and at least half of its cells are known headings.
bool isHeadingRow(const std::vector<Role>& roles);

}  // namespace regmapgen
