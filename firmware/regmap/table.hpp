// Register-map runtime tables: the same facts as the descriptors, as data, for code that picks entries at run
// time — host tools (bmsctl resolves `read Cell1Voltage` and prints `# Cell1Voltage = 3700 mV`), device
// emulators (initialise data memory with the TRM defaults) and plausibility checks.
//
// Contract
// - regmapgen emits one table per family in "regmap/<family>_table.hpp":
//     namespace fw::regmap::bq769x2 { inline constexpr std::array<EntryInfo, N> kEntries{...};
//                                     inline constexpr std::span<const EntryInfo> entries{kEntries}; }
//   in YAML order, grouped by kind (commands, subcommands, data memory / registers, values / SBS, MAC, data
//   flash). The strings are only linked into images that include that header and use the table, so
//   firmware that only uses descriptors carries none of it.
// - findByName() matches identifiers case-insensitively, ignoring '_', ' ' and '-': "Cell1Voltage",
//   "cell_1_voltage", "FET_ENABLE" (-> FetEnable) all resolve. A name may be qualified with its C++
//   namespace ("mac::SafetyStatus", "mac.SafetyStatus") to choose between kinds that share a name (BQ4050
//   sbs::SafetyStatus and mac::SafetyStatus); unqualified, the first entry in table order wins.
// - findByAddress() finds the entry of a kind that starts at `address` (or, for code ranges such as BQ4050
//   MAC 0x4000..0x5FFF, whose range contains it).
// - decodeRaw()/encodeRaw() convert between wire bytes and a sign-extended integer for scalar entries (one
//   integer, bit-field, enum or F4 value; not arrays or blocks); F4 values travel as their bit pattern.
// Everything is constexpr, allocation-free and callable from any context.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>

#include "regmap/descriptor.hpp"

namespace fw::regmap {

// One named bit field of a bit-field value type; bits [lsb, lsb + width).
struct FieldInfo {
  const char* name;   // the accessor name, e.g. "cuv"
  const char* title;  // the TRM field name, e.g. "CUV"
  std::uint8_t lsb;
  std::uint8_t width;
};

struct EntryInfo {
  Kind kind;
  std::uint32_t address;
  std::uint32_t span;  // consecutive codes covered (1 except for code ranges)
  std::uint16_t size;  // bytes on the wire (maximum for variable blocks)
  bool variable;
  bool scalar;    // one integer, bit-field, enum or F4 value (not an array or block)
  bool isSigned;  // I1/I2/I4 (decodeRaw sign-extends)
  bool isFloat;   // F4 (limits and defaults are IEEE-754 bit patterns)
  ByteOrder order;
  Access access;
  const char* name;   // C++ identifier, e.g. "Cell1Voltage"
  const char* title;  // TRM name, e.g. "Cell 1 Voltage"
  const char* type;   // TI type code as in the YAML, e.g. "I2", "H2", "16xI2", "B32", "none"
  Unit unit;
  Ratio scale;
  bool hasMin;
  bool hasMax;
  bool hasDefault;
  std::int64_t min;
  std::int64_t max;
  std::int64_t dflt;
  std::span<const FieldInfo> fields;  // the bit fields of its value type, LSB first; empty if none
};

// The C++ sub-namespace of a kind ("cmd", "sub", "dm", "reg", "val", "sbs", "mac", "df").
constexpr std::string_view kindNamespace(Kind k) {
  switch (k) {
    case Kind::Command:
      return "cmd";
    case Kind::Subcommand:
      return "sub";
    case Kind::DataMemory:
      return "dm";
    case Kind::Register:
      return "reg";
    case Kind::Value:
      return "val";
    case Kind::Sbs:
      return "sbs";
    case Kind::Mac:
      return "mac";
    case Kind::DataFlash:
      return "df";
  }
  return "?";
}

// The word `regmapgen list` prints ("command", "subcommand", "datamem", "register", "value", "sbs", "mac",
// "dataflash").
constexpr std::string_view kindName(Kind k) {
  switch (k) {
    case Kind::Command:
      return "command";
    case Kind::Subcommand:
      return "subcommand";
    case Kind::DataMemory:
      return "datamem";
    case Kind::Register:
      return "register";
    case Kind::Value:
      return "value";
    case Kind::Sbs:
      return "sbs";
    case Kind::Mac:
      return "mac";
    case Kind::DataFlash:
      return "dataflash";
  }
  return "?";
}

namespace detail {

constexpr bool ignoredInName(char c) {
  return c == '_' || c == ' ' || c == '-';
}
constexpr char lower(char c) {
  return (c >= 'A' && c <= 'Z') ? static_cast<char>(c - 'A' + 'a') : c;
}

// Case-insensitive comparison that skips '_', ' ' and '-'.
constexpr bool sameName(std::string_view a, std::string_view b) {
  std::size_t i = 0;
  std::size_t j = 0;
  for (;;) {
    while (i < a.size() && ignoredInName(a[i]))
      ++i;
    while (j < b.size() && ignoredInName(b[j]))
      ++j;
    if (i == a.size() || j == b.size()) return i == a.size() && j == b.size();
    if (lower(a[i]) != lower(b[j])) return false;
    ++i;
    ++j;
  }
}

}  // namespace detail

// Finds an entry by identifier (see the contract above); nullptr if there is none.
constexpr const EntryInfo* findByName(std::span<const EntryInfo> table, std::string_view name) {
  std::string_view ns;
  for (std::string_view sep : {std::string_view{"::"}, std::string_view{"."}}) {
    const std::size_t at = name.find(sep);
    if (at != std::string_view::npos) {
      ns = name.substr(0, at);
      name = name.substr(at + sep.size());
      break;
    }
  }
  for (const EntryInfo& e : table) {
    if (!ns.empty() && !detail::sameName(kindNamespace(e.kind), ns)) continue;
    if (detail::sameName(e.name, name)) return &e;
  }
  return nullptr;
}

// Finds the entry of `kind` at `address`; nullptr if there is none.
constexpr const EntryInfo* findByAddress(std::span<const EntryInfo> table, Kind kind, std::uint32_t address) {
  for (const EntryInfo& e : table) {
    if (e.kind == kind && address >= e.address && address - e.address < e.span) return &e;
  }
  return nullptr;
}

// The raw integer value of a scalar entry from its wire bytes (sign-extended for I types). Returns 0 when
// `bytes` is shorter than the entry or the entry is not a scalar.
constexpr std::int64_t decodeRaw(const EntryInfo& e, std::span<const std::uint8_t> bytes) {
  if (!e.scalar || e.size == 0 || e.size > 8 || bytes.size() < e.size) return 0;
  std::uint64_t v = 0;
  for (std::size_t i = 0; i < e.size; ++i) {
    const std::size_t shift = (e.order == ByteOrder::Little ? i : e.size - 1 - i) * 8;
    v |= static_cast<std::uint64_t>(bytes[i]) << shift;
  }
  if (e.isSigned && e.size < 8) {
    const std::uint64_t sign = std::uint64_t{1} << (e.size * 8 - 1);
    v = (v ^ sign) - sign;  // two's-complement sign extension without shifting into the sign bit
  }
  return static_cast<std::int64_t>(v);
}

// Writes the raw integer value of a scalar entry as wire bytes; returns the byte count (0 if the entry is not
// a scalar or `out` is too short).
constexpr std::size_t encodeRaw(const EntryInfo& e, std::int64_t value, std::span<std::uint8_t> out) {
  if (!e.scalar || e.size == 0 || e.size > 8 || out.size() < e.size) return 0;
  const auto v = static_cast<std::uint64_t>(value);
  for (std::size_t i = 0; i < e.size; ++i) {
    const std::size_t shift = (e.order == ByteOrder::Little ? i : e.size - 1 - i) * 8;
    out[i] = static_cast<std::uint8_t>(v >> shift);
  }
  return e.size;
}

}  // namespace fw::regmap
