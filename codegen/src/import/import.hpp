// `regmapgen import`: turns register tables pasted from a TRM or app note into register-map YAML.
//
// Input: text in which tables are rows of cells separated by '|' (Markdown style, as in seed 002) or by tabs
// (as copied from a PDF, seed 000). A row whose cells are column headings starts a table; the following rows
// are its entries until a line without separators. Other lines (prose, figure captions) are ignored, so a
// whole app note can be fed in. Headings may be English or Chinese (命令/名称/单位/类型/说明,
// 类别/子类别/名称/类型/最小值/最大值/默认值/单位, Address, Name, ...); see headingHelp().
//
// Output: one complete YAML file on `out` (`family:` plus one list per kind) that `regmapgen check` accepts
// when every row was understood; the source line of each row is kept in `notes`.
// - Kind: tables with a class/subclass column are data memory; otherwise a 2-hex-digit address is a direct
//   command and a 4-digit one a subcommand (`--kind` overrides).
// - Names: an ASCII name column is used as is; a Chinese name is translated from the glossary of TI terms
//   (glossary(): 警报启用 -> "Alarm Enable", "Cell 1 电压" -> "Cell 1 Voltage", "VCell模式" -> "VCell Mode"),
//   or, when an English-name column exists, taken from it. A name that cannot be translated is kept verbatim
//   with a comment, and `check` rejects it until a person writes the English TRM name: nothing is guessed.
// - Types: TI codes are kept; evident OCR damage is repaired with a warning and a note ("12" -> I2,
//   "l H2" -> H2, and a 1-byte type whose description says "16 位"/"16-bit" -> the 2-byte type).
// - Units: "mV", "0.1K" (unit K, scale 0.1), "userA", 十六进制/Hex (no unit: a flag word)...
// - Access is not in TI's command tables: commands and readable subcommands default to `r`, subcommands
//   without data to `cmd`, data memory to `config_update`; each such entry says so in a comment.
// - Data-memory tables often lack addresses: `--map FILE...` (existing YAML of the family) fills them in by
//   matching the translated name and class/subclass; failing that, the nearest address the prose since the
//   previous table names ("地址 0x9261", "写入 0x9304", "address 0x9261") is used, with a warning. An address
//   that cannot be found is written as `TODO`, which `check` reports. A table address that disagrees with the
//   map is a warning.
// Warnings go to `err` as "file:line:col: warning: ..."; the result is 0 unless the input could not be read
// or contained no table.
#pragma once

#include <iosfwd>
#include <string>
#include <utility>
#include <vector>

namespace regmapgen {

struct ImportOptions {
  std::string family = "imported";
  std::string kind;                   // "", "command", "subcommand" or "datamem"
  std::vector<std::string> mapFiles;  // YAML maps used to resolve missing data-memory addresses
  std::string source = "unverified";
};

int runImport(const std::string& path, const std::string& text, const ImportOptions& opts, std::ostream& out,
              std::ostream& err);

// The glossary: Chinese TI terms and their English TRM spelling, longest first within each group.
const std::vector<std::pair<std::string, std::string>>& glossary();

// Translates a name of Chinese TI terms and ASCII words into the English TRM name; false if some part is not
// in the glossary (then `out` is unspecified).
bool translateName(const std::string& name, std::string& out);

// The recognised column headings, for `regmapgen import --help` and the README.
std::string headingHelp();

// The glossary as a Markdown table (for the README).
std::string glossaryMarkdown();

}  // namespace regmapgen
