// `regmapgen import`: turns register tables from a TRM, data sheet or app note into register-map YAML.
//
// Input: text in which tables are rows of cells separated by '|' (Markdown, web pages, seed 002) or tabs
// (copied from a PDF viewer, seed 000), or `pdftotext -layout` text of a TI PDF, where columns are runs of
// spaces, pages repeat headers and footers, tables continue under a repeated heading and rows wrap around
// their key line (table_reader.hpp says how each is read). Prose is skipped, so a whole document can be fed
// in. Headings may be English or Chinese (headings.hpp).
//
// Which tables: a text whose captions name register summaries (captions.hpp: "Table 12-1. Direct Commands
// Table", "Table 14-1. Data Flash Summary") is read from those, from the tables of one setting or command
// right under their own numbered section, and from its bit-field tables; its other tables are listed as left
// out. A text without such captions is read whole.
//
// Output: one complete YAML file on `out` (`family:`, one list per kind, `fieldsets:` of the bit-field
// tables) that `regmapgen check` accepts when every row was understood; the source position of each row is
// kept in `notes`, and a summary line (tables read, entries by kind, tables left out) goes to `err`.
// - Kind: by family (`--family`, else the --map files' family). A table with a class column is data memory
//   (BQ4050: data flash); otherwise an address of 2 hex digits is a direct command (BQ4050: SBS command) and
//   one of 4 digits a subcommand (BQ4050: MAC command); every BQ79616 table is registers. `--kind` overrides.
// - Names: an ASCII name column is used as is ("Voltage()" loses its "()"); a Chinese name is translated from
//   the glossary of TI terms, or taken from an English-name column. A name that cannot be translated is kept
//   verbatim with a comment, and `check` rejects it until a person writes the English TRM name: nothing is
//   guessed. A name that repeats in several subclasses, or is no C++ identifier, gets an `id:` of subclass
//   and name; `--map` entries give theirs.
// - Types: TI codes are kept; payload fields of one subcommand add up to an array or block; words and sizes
//   become codes; S20+1 is S21; evident text-extraction damage is repaired with a warning and a note.
// - Values: a value that does not fit its type, or a default outside its row's range, is a warning and goes
//   to the notes.
// - Addresses: a setting's own table (no address) is matched to its summary row by class, subclass and name
//   (else subclass and name), and the two are one entry: values they give differently are warnings naming
//   both places. Else `--map FILE...` (existing YAML of the family; only its entries are read) by name and
//   class/subclass; else, in a text without summaries, the nearest address the prose of the table's section
//   names ("地址 0x9261", "address 0x9261", "writes 0x04 to 0x901B"), with a warning; else `TODO` (without
//   summaries) or the row is named and left out (with summaries).
// - Bit-field tables: a fieldset per register, given to the entries of that name.
// Warnings go to `err` as "file:line:col: warning: ..." (for a PDF, ImportOptions::firstPage > 0,
// "file:pPAGE:LINE:COL"), in the order of the text. The result: 0 imported; 1 the input could not be read (a
// line over 4096 bytes, with its position) or the maps have syntax errors; 2 a bad option;
// kImportFoundNoTable (3) when the text holds no register table (nothing is written to `out`).
#pragma once

#include <iosfwd>
#include <string>
#include <utility>
#include <vector>

namespace regmapgen {

struct ImportOptions {
  std::string family;                 // "": the family of the --map files, else "imported"
  std::string kind;                   // "", or a kind's list word or YAML key ("command", "registers"...)
  std::vector<std::string> mapFiles;  // YAML maps used to resolve missing data-memory addresses
  std::string source = "unverified";
  int firstPage = 0;  // the text is pdftotext's of a PDF from this page on: positions are file:pPAGE:LINE:COL
};

// The exit status of an import that found no register table (a data sheet, a text without tables).
inline constexpr int kImportFoundNoTable = 3;

int runImport(const std::string& path, const std::string& text, const ImportOptions& opts, std::ostream& out,
              std::ostream& err);

// The glossary: Chinese TI terms and their English TRM spelling, longest first within each group.
const std::vector<std::pair<std::string, std::string>>& glossary();

// Translates a name of Chinese TI terms and ASCII words into the English TRM name; false if some part is not
// in the glossary (then `out` is unspecified).
bool translateName(const std::string& name, std::string& out);

// The glossary as a Markdown table (for the README).
std::string glossaryMarkdown();

}  // namespace regmapgen
