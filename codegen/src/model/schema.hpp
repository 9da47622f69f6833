// The register-map schema: one table of objects and keys that drives validation (unknown / missing keys, what
// each value must look like) and the documentation `regmapgen schema` prints into regmaps/README.md.
//
// Contract
// - kinds(): the entry kinds (commands, subcommands, datamem, registers, values, sbs, mac, dataflash) with
// the
//   YAML list key, the word `list` prints, the C++ sub-namespace, how addresses overlap (byte ranges for
//   memory-like kinds; codes for subcommands, SBS and MAC) and the wire byte order.
// - objects(): every object the YAML may contain and its keys (required or optional, value syntax, meaning).
// - parseType(), accessCodes(), units(): the vocabularies of `type`, `access` and `unit`.
// Adding a key, kind, type, access code or unit here is the only place the vocabulary changes; the checker,
// generator and README follow.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace regmapgen {

enum class EntryKind { Command, Subcommand, DataMemory, Register, Value, Sbs, Mac, DataFlash };

struct KindInfo {
  EntryKind kind;
  std::string_view yamlKey;   // top-level list key, e.g. "commands"
  std::string_view listName;  // word printed by `list`, e.g. "command"
  std::string_view ns;        // C++ sub-namespace, e.g. "cmd"
  std::string_view cppKind;   // fw::regmap::Kind enumerator, e.g. "Command"
  std::string_view title;     // heading in the Markdown reference
  bool memory;                // true: an entry occupies [addr, addr+size) and ranges must not overlap
  std::uint32_t maxAddress;
  int addrDigits;  // hex digits printed for addresses
  bool bigEndian;
  bool allowCategory;  // category/subcategory keys (data memory, data flash)
  bool allowSpan;      // span key (code ranges)
  std::string_view doc;
};

const std::vector<KindInfo>& kinds();
const KindInfo* kindByYamlKey(std::string_view key);

// How a key's value must be written.
enum class ValueSyntax {
  Text,        // any scalar
  Family,      // lowercase identifier [a-z][a-z0-9_]*
  Identifier,  // C++ identifier (PascalCase for entries, enums, enum values; snake_case for fields)
  Integer,     // decimal, 0x hex or 0b binary, optionally negative
  Number,      // Integer, or a decimal/exponent number (F4 values)
  TypeCode,    // see parseType()
  AccessCode,  // see accessCodes()
  UnitSymbol,  // see units()
  Scale,       // positive decimal ("0.1", "190.73") or ratio ("1/3")
  Bits,        // "7" or "msb:lsb"
  Width,       // 8, 16 or 32
  Source,      // "unverified", or TI literature numbers (SLUUBY2B...) and/or SBS1.1
  NameRef,     // the name of a fieldset or enum defined in the same family
  TextList,    // flow or block sequence of scalars
  ObjectList,  // block sequence of mappings (objects of `element`)
  Object,      // a mapping (object of `element`)
};

struct KeySpec {
  std::string_view key;
  bool required;
  ValueSyntax syntax;
  std::string_view element;  // object name for ObjectList/Object
  std::string_view doc;
};

struct ObjectSpec {
  std::string_view name;  // "file", "device", "entry", "fieldset", "field", "enum", "enum value"
  std::string_view doc;
  std::vector<KeySpec> keys;
  const KeySpec* find(std::string_view key) const;
};

const std::vector<ObjectSpec>& objects();

// The most bytes one block may hold: the BQ769x2/BQ7690x link reads a block into a scratch buffer of one byte
// and its CRC per data byte, counted in 8 bits (2 x 127 <= 255).
inline constexpr int kMaxBlockBytes = 127;
const ObjectSpec& object(std::string_view name);

// TI type codes. Scalars: U1 U2 U4 (unsigned), I1 I2 I4 (signed), H1 H2 H4 (hex flags), F4 (IEEE-754).
// Arrays: "<n>x<scalar>" (e.g. 16xI2). Blocks: B<n> (n bytes), S<n> (string of n bytes), B / S (variable,
// at most 32 bytes). "none": no data (command-only subcommands).
struct TypeInfo {
  enum class Base { Unsigned, Signed, Hex, Float, Bytes, String, None };
  std::string code;  // canonical spelling
  Base base = Base::None;
  int elemSize = 0;  // bytes per element (scalars: the size)
  int count = 1;     // array length (1 for scalars)
  bool variable = false;
  bool array = false;

  int size() const { return elemSize * count; }
  bool scalar() const {
    return !array &&
           (base == Base::Unsigned || base == Base::Signed || base == Base::Hex || base == Base::Float);
  }
  bool integer() const {
    return !array && (base == Base::Unsigned || base == Base::Signed || base == Base::Hex);
  }
  bool isSigned() const { return base == Base::Signed; }
  // Range of a scalar integer of this type.
  std::int64_t minValue() const;
  std::int64_t maxValue() const;
};

std::optional<TypeInfo> parseType(std::string_view code);
std::string typeCodesHelp();  // one line listing the accepted codes, for messages and docs

enum class AccessCode { R, W, RW, RW1C, Cmd, ConfigUpdate };
struct AccessInfo {
  AccessCode code;
  std::string_view spelling;  // YAML
  std::string_view cpp;       // fw::regmap::Access enumerator
  bool readable;
  bool writable;
  std::string_view doc;
};
const std::vector<AccessInfo>& accessCodes();
const AccessInfo* findAccess(std::string_view spelling);

struct UnitInfo {
  std::string_view symbol;  // YAML spelling, also fw::regmap::unitSymbol()
  std::string_view cpp;     // fw::regmap::Unit enumerator
  std::string_view doc;
};
const std::vector<UnitInfo>& units();
const UnitInfo* findUnit(std::string_view symbol);

// Recognised `source` tokens other than literature numbers.
bool isSourceToken(std::string_view token);

// The schema as Markdown (the block regmaps/README.md embeds between its BEGIN/END markers).
std::string schemaMarkdown();

}  // namespace regmapgen
