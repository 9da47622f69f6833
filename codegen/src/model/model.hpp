// The typed register-map model, built from parsed YAML by checking every object against the schema.
//
// Contract
// - build() turns each file's YAML tree into entries, fieldsets and enums of a Family (files naming the same
//   `family` merge), reporting every unknown key, missing required key and malformed value with its position.
//   Objects with errors are still kept (with the bad fields unset) so later checks can run on the rest; only
//   `Model::ok` tells whether generation may proceed.
// - Every value keeps its Loc for later diagnostics; numbers keep their source text for the docs.
// - Derived C++ identifiers are filled in here (names.hpp) but validated by the checker.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "diag/diag.hpp"
#include "model/schema.hpp"
#include "yaml/yaml.hpp"

namespace regmapgen {

struct Text {
  std::string value;
  Loc loc;
  bool present = false;
};

// A number as written: integers exactly; F4 values also as a float bit pattern.
struct Number {
  std::string text;
  Loc loc;
  bool isInteger = false;
  std::int64_t integer = 0;  // valid when isInteger
  double real = 0;           // always set
  bool present = false;
};

struct Scale {
  std::int64_t num = 1;
  std::int64_t den = 1;
  std::string text;
  Loc loc;
  bool present = false;
};

struct Entry {
  const KindInfo* kind = nullptr;
  Loc loc;  // the item
  Text name;
  Text id;              // explicit `id:`
  std::string cppName;  // id or derived from name
  std::optional<std::uint32_t> addr;
  Loc addrLoc;
  std::uint32_t span = 1;
  Loc spanLoc;
  std::optional<TypeInfo> type;
  Loc typeLoc;
  const AccessInfo* access = nullptr;
  Loc accessLoc;
  const UnitInfo* unit = nullptr;
  Loc unitLoc;
  Scale scale;
  Number min, max, dflt;
  Text fieldset, enumRef;
  Text category, subcategory;
  Text description, source, notes;

  int size() const { return type ? type->size() : 0; }
};

struct Field {
  Loc loc;
  Text name;
  Text id;
  std::string cppName;
  int msb = -1;
  int lsb = -1;
  Loc bitsLoc;
  Text enumRef;
  Text description, source;
  int width() const { return msb - lsb + 1; }
  std::uint64_t mask() const { return ((std::uint64_t{1} << width()) - 1) << lsb; }
  // "7" for one bit, "9:8" for a range.
  std::string bitsText() const {
    return msb == lsb ? std::to_string(msb) : std::to_string(msb) + ":" + std::to_string(lsb);
  }
};

struct Fieldset {
  Loc loc;
  Text name;
  int width = 0;
  Loc widthLoc;
  Text description, source, notes;
  std::vector<Field> fields;
};

struct EnumValue {
  Loc loc;
  Text name;
  std::optional<std::int64_t> value;
  Loc valueLoc;
  Text description;
};

struct Enum {
  Loc loc;
  Text name;
  Text description, source;
  std::vector<EnumValue> values;
};

// A run of consecutive direct commands read in one transaction (`blocks:`).
struct Block {
  Loc loc;
  Text name;
  Number start;
  std::vector<Text> members;  // TRM names of commands entries, in address order
  bool gapsAllowed = false;
  Text description;
};

struct Device {
  Loc loc;
  Text title;
  std::vector<std::string> parts;
  std::vector<std::string> documents;
  Text notes;
};

struct Family {
  std::string name;
  Loc loc;  // the first `family:` value
  std::vector<int> files;
  std::optional<Device> device;
  std::vector<Entry> entries;  // in file order
  std::vector<Fieldset> fieldsets;
  std::vector<Enum> enums;
  std::vector<Block> blocks;  // in file order: the order of the record

  const Fieldset* findFieldset(const std::string& name) const;
  const Enum* findEnum(const std::string& name) const;
};

struct Model {
  std::vector<Family> families;  // in order of first appearance
};

// Parses and builds every file in `sources`; all problems go to `diag`.
Model build(const Sources& sources, Diagnostics& diag);

// Parses a number as written in the YAML (decimal, 0x hex, 0b binary, or a decimal/exponent real).
std::optional<Number> parseNumber(const std::string& text);

// Parses a `scale:` value ("0.1", "190.73", "1/3") into a reduced ratio with a positive denominator.
std::optional<Scale> parseScale(const std::string& text);

}  // namespace regmapgen
