// The parts of one row of a TI register table, as `import` reads them: the address cell, a run of register
// names, addresses named in the prose, a width stated in a description, and the cells by role.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "import/headings.hpp"
#include "import/table_reader.hpp"
#include "model/schema.hpp"

namespace regmapgen::rows {

// The kind a `--kind` value names (its `list` word or YAML key), or nullptr.
const KindInfo* findKind(const std::string& k);

// Which kinds a family's tables hold: 8-bit codes, 16-bit codes, and tables with a class column.
struct FamilyKinds {
  std::string_view family, byteCodes, wordCodes, memory;
};
const FamilyKinds& kindsOf(const std::string& family);

// "Address 0x9261", "地址 0x9261", "写入 0x9304", "write to 0x9304", "writes 0x04 to 0x901B": the 4-digit
// addresses a line of prose names, in order.
std::vector<std::string> addressMentions(const std::string& line);

// "16 位", "16-bit", "32 bit" in a description: the width it states and the words that state it.
struct StatedWidth {
  int bits = 0;
  std::string text;
};
StatedWidth statedWidth(const std::string& description);

// An address cell: "0x14", "0x0022 (R)", or a range of codes "0x4000–0x5FFF", "0x4000...0x5FFF",
// "0x4000 to 0x5FFF". The hex digits of the first and (for a range) the last code.
struct AddressCell {
  std::string first, last;
};
std::optional<AddressCell> addressCell(const std::string& cell);

// Hex digits as an address of `digits` digits ("14" -> "0x14", "22" -> "0x0022"); a value too wide for any
// kind is kept as written, for check to report.
std::string addressText(const std::string& hex, int digits);

// "CB_CELL16_CTRL through CB_CELL1_CTRL": the names of a run of registers, in the order of their rows; empty
// unless the ends differ in one number or one letter.
std::vector<std::string> runNames(const std::string& name);

// The cells of one row by role. Several cells may share a role: descriptions are joined, the last access
// cell wins (the BQ4050 SE/US/FA columns: full access is last).
class RowCells {
 public:
  RowCells(const TableEvent& row, const std::vector<Role>& roles, const std::vector<TableCell>& headings);
  bool has(Role r) const { return cells_.count(r) != 0; }
  std::string get(Role r) const;
  int col(Role r) const;
  int line(Role r) const;

  std::string extra;  // "Heading: text" of the columns no role claims
  std::vector<const TableCell*> beyondHeadings;

 private:
  const TableEvent& row_;
  std::map<Role, const TableCell*> cells_;
  std::string description_;  // every description cell, joined
  std::string data_;         // every data cell (BQ79616: the field names under Bit7..Bit0), joined
};

// At most this many bytes of a value go into the YAML: escaped (\xNN, four per byte at most) and with its
// key, a line stays within the reader's 4096 bytes.
inline constexpr std::size_t kMaxValueBytes = 1000;
std::string capped(const std::string& v);

}  // namespace regmapgen::rows
