// `regmapgen import`: turns register tables from a TRM, data sheet or app note into register-map YAML.
//
// Input: text in which tables are rows of cells separated by '|' (Markdown, web pages, seed 002) or tabs
// (copied from a PDF viewer, seed 000), or `pdftotext -layout` text of a TI PDF, where columns are runs of
// spaces, pages repeat headers and footers, tables continue under a repeated heading and long cells wrap
// (table_reader.hpp says how each is read). Prose is skipped, so a whole document can be fed in. Headings may
// be English or Chinese (headings.hpp).
//
// Output: one complete YAML file on `out` (`family:` plus one list per kind) that `regmapgen check` accepts
// when every row was understood; the source line of each row is kept in `notes`.
// - Kind: by family (`--family`, else the --map files' family). A table with a class column is data memory
//   (BQ4050: data flash); otherwise an address of 2 hex digits is a direct command (BQ4050: SBS command) and
//   one of 4 digits a subcommand (BQ4050: MAC command); every BQ79616 table is registers. `--kind` overrides.
// - Names: an ASCII name column is used as is ("Voltage()" loses its "()"); a Chinese name is translated from
//   the glossary of TI terms (glossary(): 警报启用 -> "Alarm Enable", "Cell 1 电压" -> "Cell 1 Voltage"), or,
//   when an English-name column exists, taken from it. A name that cannot be translated is kept verbatim with
//   a comment, and `check` rejects it until a person writes the English TRM name: nothing is guessed.
//   Identifiers: a name that repeats in several subclasses gets an `id:` of subclass and name; `--map`
//   entries give theirs.
// - Types: TI codes are kept; payload fields of one subcommand add up to a block ("U2 U2 U2" -> B6); words
//   and sizes become codes (Hex + 2 -> H2, Block -> B); evident OCR damage is repaired with a warning and a
//   note ("12" -> I2, "l H2" -> H2, "H6" -> B6, and a 1-byte type whose description says "16 位"/"16-bit" ->
//   the 2-byte type). Register tables without a type: U1.
// - Units (cells.hpp): "mV", "50.6 mV" (scale 50.6), "0.1°C", "0.1K", "µV", "mAh" over "10 mWh", 十六进制/Hex
//   (no unit: a flag word)... Numbers: "–32767" (en dash) is -32767, "—" is no value.
// - Access: R, W, R/W (of several, full access: the last); without one, commands and readable subcommands
//   default to `r`, data flash to `rw`, subcommands without data to `cmd`, data memory is `config_update`;
//   each assumed access is said in a comment.
// - Data-memory tables often lack addresses: `--map FILE...` (existing YAML of the family; only its entries
//   are read) fills them in by matching the translated name and class/subclass; failing that, the nearest
//   address the prose since the previous table names ("地址 0x9261", "写入 0x9304", "address 0x9261") is
//   used, with a warning. An address that cannot be found is written as `TODO`, which `check` reports. A
//   table address that disagrees with the map is a warning.
// Warnings go to `err` as "file:line:col: warning: ..."; the result is 0 unless the input could not be read
// (a line over 4096 bytes is an error with its position), the maps have syntax errors, or it holds no table.
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
