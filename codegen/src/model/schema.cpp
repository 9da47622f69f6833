#include "model/schema.hpp"

#include <cctype>
#include <sstream>

namespace regmapgen {

const std::vector<KindInfo>& kinds() {
  static const std::vector<KindInfo> table = {
      {.kind = EntryKind::Command,
       .yamlKey = "commands",
       .listName = "command",
       .ns = "cmd",
       .cppKind = "Command",
       .title = "Direct commands",
       .memory = true,
       .maxAddress = 0xFF,
       .addrDigits = 2,
       .bigEndian = false,
       .allowCategory = false,
       .allowSpan = false,
       .doc =
           "BQ769x2/BQ7690x direct commands: byte addresses in the command space; a 2-byte command at 0x14 "
           "also occupies 0x15."},
      {.kind = EntryKind::Subcommand,
       .yamlKey = "subcommands",
       .listName = "subcommand",
       .ns = "sub",
       .cppKind = "Subcommand",
       .title = "Subcommands",
       .memory = false,
       .maxAddress = 0xFFFF,
       .addrDigits = 4,
       .bigEndian = false,
       .allowCategory = false,
       .allowSpan = true,
       .doc = "BQ769x2/BQ7690x subcommands: 16-bit codes written to 0x3E/0x3F; `type` is the payload "
              "in the 0x40 buffer (`none` for command-only)."},
      {.kind = EntryKind::DataMemory,
       .yamlKey = "datamem",
       .listName = "datamem",
       .ns = "dm",
       .cppKind = "DataMemory",
       .title = "Data memory",
       .memory = true,
       .maxAddress = 0xFFFF,
       .addrDigits = 4,
       .bigEndian = false,
       .allowCategory = true,
       .allowSpan = false,
       .doc =
           "BQ769x2/BQ7690x data-memory parameters: 16-bit addresses; multi-byte values occupy consecutive "
           "addresses."},
      {.kind = EntryKind::Register,
       .yamlKey = "registers",
       .listName = "register",
       .ns = "reg",
       .cppKind = "Register",
       .title = "Registers",
       .memory = true,
       .maxAddress = 0xFFFF,
       .addrDigits = 4,
       .bigEndian = true,
       .allowCategory = false,
       .allowSpan = false,
       .doc =
           "BQ79616 registers: 16-bit register addresses, one byte each, big-endian for multi-byte values."},
      {.kind = EntryKind::Value,
       .yamlKey = "values",
       .listName = "value",
       .ns = "val",
       .cppKind = "Value",
       .title = "Multi-byte values",
       .memory = true,
       .maxAddress = 0xFFFF,
       .addrDigits = 4,
       .bigEndian = true,
       .allowCategory = false,
       .allowSpan = false,
       .doc =
           "BQ79616 readings that span consecutive registers (VCELL16_HI/LO as one I2). Every byte must be a "
           "register of the same family; values do not overlap each other."},
      {.kind = EntryKind::Sbs,
       .yamlKey = "sbs",
       .listName = "sbs",
       .ns = "sbs",
       .cppKind = "Sbs",
       .title = "SBS commands",
       .memory = false,
       .maxAddress = 0xFF,
       .addrDigits = 2,
       .bigEndian = false,
       .allowCategory = false,
       .allowSpan = false,
       .doc =
           "BQ4050 SBS commands: 8-bit codes; 2-byte types are SMBus words, everything else an SMBus block."},
      {.kind = EntryKind::Mac,
       .yamlKey = "mac",
       .listName = "mac",
       .ns = "mac",
       .cppKind = "Mac",
       .title = "ManufacturerAccess (MAC) subcommands",
       .memory = false,
       .maxAddress = 0xFFFF,
       .addrDigits = 4,
       .bigEndian = false,
       .allowCategory = false,
       .allowSpan = true,
       .doc = "BQ4050 MAC subcommands: 16-bit codes sent through 0x00 or ManufacturerBlockAccess (0x44); "
              "`type` is the data after the echoed code."},
      {.kind = EntryKind::DataFlash,
       .yamlKey = "dataflash",
       .listName = "dataflash",
       .ns = "df",
       .cppKind = "DataFlash",
       .title = "Data flash",
       .memory = true,
       .maxAddress = 0xFFFF,
       .addrDigits = 4,
       .bigEndian = false,
       .allowCategory = true,
       .allowSpan = false,
       .doc = "BQ4050 data flash: addresses 0x4000..0x5FFF read and written through MAC block access."},
  };
  return table;
}

const KindInfo* kindByYamlKey(std::string_view key) {
  for (const KindInfo& k : kinds()) {
    if (k.yamlKey == key) return &k;
  }
  return nullptr;
}

const KeySpec* ObjectSpec::find(std::string_view key) const {
  for (const KeySpec& k : keys) {
    if (k.key == key) return &k;
  }
  return nullptr;
}

const std::vector<ObjectSpec>& objects() {
  using S = ValueSyntax;
  static const std::vector<ObjectSpec> table = [] {
    std::vector<ObjectSpec> t;
    ObjectSpec file{"file",
                    "The top level of every YAML file. A family's tables may be split over several files "
                    "(all naming the same `family`); checks and generation see them together.",
                    {}};
    file.keys.push_back({"family", true, S::Family, "",
                         "Family id, e.g. `bq769x2`: the C++ namespace "
                         "`fw::regmap::<family>` and the header `regmap/<family>.hpp`."});
    file.keys.push_back({"device", false, S::Object, "device",
                         "Device facts for the reference page (at most once "
                         "per family)."});
    for (const KindInfo& k : kinds()) {
      file.keys.push_back({k.yamlKey, false, S::ObjectList, "entry", k.doc});
    }
    file.keys.push_back({"fieldsets", false, S::ObjectList, "fieldset",
                         "Bit-field layouts; entries refer to them "
                         "with `fieldset:`."});
    file.keys.push_back({"enums", false, S::ObjectList, "enum",
                         "Coded values; fields and entries refer to them "
                         "with `enum:`."});
    file.keys.push_back({"blocks", false, S::ObjectList, "block",
                         "Runs of consecutive direct commands read in one transaction (a scan), in the "
                         "order the scan reads them; emitted as `blocks::<name>`."});
    t.push_back(std::move(file));

    t.push_back({"device",
                 "Facts about the family shown at the top of its reference page.",
                 {{"title", true, S::Text, "", "Heading of the reference page."},
                  {"parts", false, S::TextList, "", "Part numbers the tables apply to."},
                  {"documents", false, S::TextList, "",
                   "TI documents the tables were checked against (literature "
                   "number and title)."},
                  {"notes", false, S::Text, "", "Free text shown under the title."}}});

    t.push_back(
        {"entry",
         "One command, subcommand, data-memory parameter, register, value, SBS command, MAC subcommand or "
         "data-flash "
         "parameter (an item of a kind list).",
         {{"name", true, S::Text, "",
           "The TRM name, verbatim (`Cell 1 Voltage`, `FET_ENABLE`, `VCELL16_HI`). Must be "
           "ASCII; unique within its kind (within its category/subcategory for data "
           "memory)."},
          {"id", false, S::Identifier, "",
           "C++ identifier when the one derived from `name` would be unusable or "
           "collide. Derived ids: PascalCase of the name's words, all-caps words "
           "title-cased (`FET_ENABLE` -> `FetEnable`, `Cell 1 Voltage` -> "
           "`Cell1Voltage`, `VCell Mode` -> `VCellMode`)."},
          {"addr", true, S::Integer, "", "Address or code, e.g. `0x14`, `0x0022`, `0x9261`."},
          {"span", false, S::Integer, "",
           "Subcommands and MAC only: number of consecutive codes the entry covers "
           "(default 1), e.g. a data-flash window."},
          {"type", true, S::TypeCode, "", "TI type code of the value (see Type codes)."},
          {"access", true, S::AccessCode, "", "Who may read or write it (see Access codes)."},
          {"unit", false, S::UnitSymbol, "",
           "Unit of one LSB after `scale` (see Units); omitted for codes and flags."},
          {"scale", false, S::Scale, "",
           "Size of one LSB in `unit`, exact: `0.1` (0.1 K), `190.73` (uV), `1/3`. "
           "Default 1."},
          {"min", false, S::Number, "", "Smallest legal value (raw, before scale), where the TRM gives one."},
          {"max", false, S::Number, "", "Largest legal value (raw), where the TRM gives one."},
          {"default", false, S::Number, "",
           "Reset / factory value (raw), where the TRM gives one. F4 values are "
           "decimal; the generator stores their IEEE-754 bit pattern."},
          {"fieldset", false, S::NameRef, "",
           "Bit-field layout of the value; the descriptor decodes to "
           "`bits::<fieldset>`."},
          {"enum", false, S::NameRef, "",
           "The whole value is a code of this enum; the descriptor decodes to "
           "`enums::<enum>`."},
          {"category", false, S::Text, "", "Data memory / data flash only: TRM class, e.g. `Settings`."},
          {"subcategory", false, S::Text, "",
           "Data memory / data flash only: TRM subclass, e.g. `Protection`."},
          {"description", true, S::Text, "", "What it means, in our own words."},
          {"source", true, S::Source, "",
           "Where the facts were checked: TI literature numbers (`SLUUBY2B`), "
           "`SBS1.1`, or `unverified`."},
          {"notes", false, S::Text, "", "Provenance details and caveats (cross-checks, conflicts)."}}});

    t.push_back(
        {"fieldset",
         "A bit-field layout. The generator emits a value type `bits::<name>` with one accessor per field; "
         "every entry using it (and, as an alias, each entry's own identifier) decodes to that type.",
         {{"name", true, S::Identifier, "", "PascalCase type name, e.g. `SafetyA`."},
          {"width", true, S::Width, "",
           "Register width in bits: 8, 16 or 32; must match the entries using it."},
          {"description", true, S::Text, "", "What the layout holds."},
          {"source", true, S::Source, "", "As for entries."},
          {"notes", false, S::Text, "", "Provenance details."},
          {"fields", true, S::ObjectList, "field", "The named fields; reserved bits are simply left out."}}});

    t.push_back(
        {"field",
         "One named bit or bit group of a fieldset. Accessors are snake_case: `cuv()`, `with_cuv(bool)`.",
         {{"name", true, S::Text, "", "TRM field name, e.g. `CUV`, `SEC[1:0]`, `USER_AMPS[1:0]`."},
          {"id", false, S::Identifier, "",
           "snake_case accessor name when the derived one (lower-case words, "
           "`[..]` dropped) is unusable, e.g. for `2LVL`."},
          {"bits", true, S::Bits, "", "Bit number (`7`) or inclusive range `\"9:8\"` (msb:lsb)."},
          {"enum", false, S::NameRef, "", "The field holds a code of this enum; the accessor returns it."},
          {"description", false, S::Text, "", "Meaning of the field."},
          {"source", false, S::Source, "", "Only when it differs from the fieldset's source."}}});

    t.push_back({"enum",
                 "A set of named codes, emitted as `enum class enums::<name>`.",
                 {{"name", true, S::Identifier, "", "PascalCase type name."},
                  {"description", true, S::Text, "", "What the codes select."},
                  {"source", false, S::Source, "", "As for entries."},
                  {"values", true, S::ObjectList, "enum value", "The codes."}}});

    t.push_back(
        {"block",
         "One read of consecutive direct commands (the device auto-increments through them). The generator "
         "emits `blocks::<name>::address`, `size`, `record` (its first byte in the record of all the "
         "family's blocks, in file order) and `offset<Member>` (a member's first byte in the block), plus "
         "`blocks::kRecordSize` and `blocks::kLargestSize`.",
         {{"name", true, S::Identifier, "", "PascalCase name, e.g. `Voltages`."},
          {"start", true, S::Integer, "", "Address of the first command read; the first member's address."},
          {"members", true, S::TextList, "",
           "TRM names of the `commands` entries read, in address order. Each member must begin where the "
           "one before it ends."},
          {"gaps", false, S::Text, "",
           "`allowed`: members may leave unused bytes between them (the read carries them)."},
          {"description", true, S::Text, "", "What the scan reads it for."}}});

    t.push_back({"enum value",
                 "One code of an enum.",
                 {{"name", true, S::Identifier, "", "PascalCase enumerator."},
                  {"value", true, S::Integer, "", "The code; must fit every field or entry using the enum."},
                  {"description", false, S::Text, "", "Meaning."}}});
    return t;
  }();
  return table;
}

const ObjectSpec& object(std::string_view name) {
  for (const ObjectSpec& o : objects()) {
    if (o.name == name) return o;
  }
  return objects().front();
}

std::int64_t TypeInfo::minValue() const {
  if (base == Base::Signed) return -(std::int64_t{1} << (elemSize * 8 - 1));
  return 0;
}

std::int64_t TypeInfo::maxValue() const {
  if (base == Base::Signed) return (std::int64_t{1} << (elemSize * 8 - 1)) - 1;
  return (std::int64_t{1} << (elemSize * 8)) - 1;
}

namespace {

std::optional<TypeInfo> parseScalarType(std::string_view code) {
  if (code.size() != 2) return std::nullopt;
  TypeInfo t;
  t.code = std::string(code);
  switch (code[0]) {
    case 'U':
      t.base = TypeInfo::Base::Unsigned;
      break;
    case 'I':
      t.base = TypeInfo::Base::Signed;
      break;
    case 'H':
      t.base = TypeInfo::Base::Hex;
      break;
    case 'F':
      t.base = TypeInfo::Base::Float;
      break;
    default:
      return std::nullopt;
  }
  const char n = code[1];
  if (t.base == TypeInfo::Base::Float) {
    if (n != '4') return std::nullopt;
  } else if (n != '1' && n != '2' && n != '4') {
    return std::nullopt;
  }
  t.elemSize = n - '0';
  return t;
}

std::optional<int> parseCount(std::string_view digits) {
  if (digits.empty() || digits.size() > 3) return std::nullopt;
  int v = 0;
  for (char c : digits) {
    if (c < '0' || c > '9') return std::nullopt;
    v = v * 10 + (c - '0');
  }
  return v;
}

}  // namespace

std::optional<TypeInfo> parseType(std::string_view code) {
  if (code == "none") {
    TypeInfo t;
    t.code = "none";
    t.base = TypeInfo::Base::None;
    t.elemSize = 0;
    return t;
  }
  if (auto s = parseScalarType(code)) return s;
  if (!code.empty() && (code[0] == 'B' || code[0] == 'S')) {
    TypeInfo t;
    t.code = std::string(code);
    t.base = code[0] == 'B' ? TypeInfo::Base::Bytes : TypeInfo::Base::String;
    t.elemSize = 1;
    t.array = true;
    if (code.size() == 1) {
      t.variable = true;
      t.count = 32;
      return t;
    }
    const auto n = parseCount(code.substr(1));
    if (!n || *n < 1 || *n > 32) return std::nullopt;
    t.count = *n;
    return t;
  }
  const std::size_t x = code.find('x');
  if (x != std::string_view::npos) {
    const auto n = parseCount(code.substr(0, x));
    auto elem = parseScalarType(code.substr(x + 1));
    if (!n || *n < 1 || !elem || elem->base == TypeInfo::Base::Float || *n * elem->elemSize > 32)
      return std::nullopt;
    elem->code = std::string(code);
    elem->count = *n;
    elem->array = true;
    return elem;
  }
  return std::nullopt;
}

std::string typeCodesHelp() {
  return "U1 U2 U4, I1 I2 I4, H1 H2 H4, F4, <n>x<U|I|H><1|2|4> (arrays, e.g. 16xI2), B<n> and S<n> (blocks "
         "of "
         "1..32 bytes), B and S (variable-length blocks), none";
}

const std::vector<AccessInfo>& accessCodes() {
  static const std::vector<AccessInfo> table = {
      {AccessCode::R, "r", "ReadOnly", true, false, "read-only"},
      {AccessCode::W, "w", "WriteOnly", false, true, "write-only (a payload is written; nothing reads back)"},
      {AccessCode::RW, "rw", "ReadWrite", true, true, "read-write"},
      {AccessCode::RW1C, "rw1c", "ReadWrite1Clear", true, true,
       "readable; writing 1 to a bit clears it (latched "
       "status)"},
      {AccessCode::Cmd, "cmd", "CommandOnly", false, false,
       "command-only: sending the code is the operation; no "
       "data (type `none`)"},
      {AccessCode::ConfigUpdate, "config_update", "ConfigUpdate", true, true,
       "readable any time; writable only in "
       "CONFIG_UPDATE mode (data memory)"},
  };
  return table;
}

const AccessInfo* findAccess(std::string_view spelling) {
  for (const AccessInfo& a : accessCodes()) {
    if (a.spelling == spelling) return &a;
  }
  return nullptr;
}

const std::vector<UnitInfo>& units() {
  static const std::vector<UnitInfo> table = {
      {"mV", "MilliVolt", "millivolt"},
      {"uV", "MicroVolt", "microvolt"},
      {"nV", "NanoVolt", "nanovolt"},
      {"userV", "UserVolt", "BQ769x2 user volts: mV or 10 mV per DA Configuration[USER_VOLTS_CV]"},
      {"mA", "MilliAmp", "milliampere"},
      {"userA", "UserAmp", "BQ769x2/BQ7690x user amps: 0.1/1/10/100 mA per DA Configuration[USER_AMPS]"},
      {"userAh", "UserAmpHour", "user amp-hours (userA x hours)"},
      {"mAh", "MilliAmpHour", "milliampere-hour"},
      {"cWh", "CentiWattHour", "10 mWh"},
      {"mAh|10mWh", "Capacity", "SBS capacity: mAh, or 10 mWh when BatteryMode[CAPM] = 1"},
      {"mA|10mW", "Rate", "SBS rate: mA, or 10 mW when BatteryMode[CAPM] = 1"},
      {"K", "Kelvin", "kelvin"},
      {"degC", "DegreeCelsius", "degree Celsius"},
      {"s", "Second", "second"},
      {"ms", "Millisecond", "millisecond"},
      {"us", "Microsecond", "microsecond"},
      {"min", "Minute", "minute"},
      {"h", "Hour", "hour"},
      {"mOhm", "MilliOhm", "milliohm"},
      {"percent", "Percent", "percent"},
      {"counts", "Count", "raw ADC or counter counts"},
      {"bytes", "Byte", "bytes"},
      {"cycles", "Cycle", "charge cycles"},
  };
  return table;
}

const UnitInfo* findUnit(std::string_view symbol) {
  for (const UnitInfo& u : units()) {
    if (u.symbol == symbol) return &u;
  }
  return nullptr;
}

bool isSourceToken(std::string_view token) {
  return token == "unverified" || token == "SBS1.1";
}

namespace {

std::string_view syntaxText(ValueSyntax s) {
  switch (s) {
    case ValueSyntax::Text:
      return "text";
    case ValueSyntax::Family:
      return "lowercase id";
    case ValueSyntax::Identifier:
      return "C++ identifier";
    case ValueSyntax::Integer:
      return "integer";
    case ValueSyntax::Number:
      return "number";
    case ValueSyntax::TypeCode:
      return "type code";
    case ValueSyntax::AccessCode:
      return "access code";
    case ValueSyntax::UnitSymbol:
      return "unit";
    case ValueSyntax::Scale:
      return "decimal or n/d";
    case ValueSyntax::Bits:
      return "`n` or `\"msb:lsb\"`";
    case ValueSyntax::Width:
      return "8, 16 or 32";
    case ValueSyntax::Source:
      return "sources";
    case ValueSyntax::NameRef:
      return "name";
    case ValueSyntax::TextList:
      return "list of text";
    case ValueSyntax::ObjectList:
      return "list";
    case ValueSyntax::Object:
      return "mapping";
  }
  return "?";
}

}  // namespace

std::string schemaMarkdown() {
  std::ostringstream md;
  md << "### Objects and keys\n\n"
        "Generated by `regmapgen schema` from the key table the checker uses (codegen/src/model/schema.cpp). "
        "An unknown key, a missing required key or a value of the wrong form is an error.\n";
  for (const ObjectSpec& o : objects()) {
    md << "\n#### " << o.name << "\n\n"
       << o.doc << "\n\n| key | required | value | meaning |\n|---|---|---|---|\n";
    for (const KeySpec& k : o.keys) {
      md << "| `" << k.key << "` | " << (k.required ? "yes" : "no") << " | " << syntaxText(k.syntax);
      if (!k.element.empty()) md << " of " << k.element;
      md << " | " << k.doc << " |\n";
    }
  }
  md << "\n### Kinds\n\n| list key | `list` prints | C++ namespace | addresses | byte order "
        "|\n|---|---|---|---|---|\n";
  for (const KindInfo& k : kinds()) {
    md << "| `" << k.yamlKey << "` | `" << k.listName << "` | `" << k.ns << "` | "
       << (k.memory ? "byte ranges, must not overlap" : "codes, must be unique") << " (max 0x" << std::hex
       << std::uppercase << k.maxAddress << std::dec << ") | " << (k.bigEndian ? "big" : "little")
       << "-endian |\n";
  }
  md << "\n### Type codes\n\n"
     << typeCodesHelp() << ".\n\n"
     << "| code | C++ value type |\n|---|---|\n"
        "| `U1` `U2` `U4` | `std::uint8_t` `std::uint16_t` `std::uint32_t` |\n"
        "| `I1` `I2` `I4` | `std::int8_t` `std::int16_t` `std::int32_t` |\n"
        "| `H1` `H2` `H4` | unsigned, or `bits::<fieldset>` with a fieldset |\n"
        "| `F4` | `fw::regmap::F4` (IEEE-754 bit pattern) |\n"
        "| `16xI2` | `std::array<std::int16_t, 16>` |\n"
        "| `B6`, `S21` | `std::array<std::uint8_t, n>` |\n"
        "| `B`, `S` | `fw::regmap::Block<32>` (variable length) |\n"
        "| `none` | `fw::regmap::NoData` (access `cmd`) |\n"
        "\nAn entry with `enum:` decodes to `enums::<enum>`; with `fieldset:` to `bits::<fieldset>`.\n";
  md << "\n### Access codes\n\n| access | C++ | readable | writable | meaning |\n|---|---|---|---|---|\n";
  for (const AccessInfo& a : accessCodes()) {
    md << "| `" << a.spelling << "` | `Access::" << a.cpp << "` | " << (a.readable ? "yes" : "no") << " | "
       << (a.writable ? "yes" : "no") << " | " << a.doc << " |\n";
  }
  md << "\n### Units\n\n| unit | C++ | meaning |\n|---|---|---|\n";
  for (const UnitInfo& u : units()) {
    std::string symbol(u.symbol);
    for (std::size_t at = symbol.find('|'); at != std::string::npos; at = symbol.find('|', at + 2)) {
      symbol.replace(at, 1, "\\|");  // a bare '|' would split the table cell
    }
    md << "| `" << symbol << "` | `Unit::" << u.cpp << "` | " << u.doc << " |\n";
  }
  md << "\n### Sources\n\n`source:` lists TI literature numbers (two to five letters and digits after `SL`, "
        "e.g. "
        "`SLUUBY2B`, `SLUSE81E`), `SBS1.1` (Smart Battery Data Specification 1.1), or is exactly "
        "`unverified` when "
        "the fact tables mark the row unverified.\n";
  return md.str();
}

}  // namespace regmapgen
