// Generators: turn a checked model into files. Each function is pure (model in, text out) so tests can call
// it directly and the CLI decides where the text goes.
//
// Per family `f`:
//   regmap/f.hpp           typed descriptors, bit-field value types and enums (namespace fw::regmap::f)
//   regmap/f_table.hpp     the runtime table (names, units, limits) for tools and emulators
//   regmap/f_selftest.cpp  static_asserts tying descriptors, table and YAML facts together; compiled on every
//                          target
//   f/REFERENCE.md         the Markdown reference (a committed copy lives in regmaps/f/)
// plus `list` lines for all families.
// Preconditions: check() reported no errors for the model.
#pragma once

#include <string>
#include <vector>

#include "diag/diag.hpp"
#include "model/model.hpp"
#include "model/names.hpp"

namespace regmapgen {

struct OutputFile {
  std::string relativePath;  // e.g. "regmap/bq769x2.hpp", "bq769x2/REFERENCE.md"
  std::string content;
};

// The code files (header, table header, self-test) of one family.
std::vector<OutputFile> emitCode(const Family& fam, const Sources& src);

// The Markdown reference of one family.
std::string emitMarkdown(const Family& fam, const Sources& src);

// One line per entry: "<kind> <address> <identifier> <type>".
std::string emitList(const Model& model);

// "bq769x2/commands.yaml" for ".../regmaps/bq769x2/commands.yaml": the stable form used in provenance
// comments and links (never an absolute path, so generated text is the same in every checkout).
std::string displayPath(const std::string& path);

// Shared formatting helpers (hexAddress is in model/names.hpp).
std::string familyTitle(const Family& fam);       // the device title, else the family name in upper case
std::string cppIntType(int size, bool isSigned);  // cppIntType(2, true) == "std::int16_t"
std::string cppValueType(const Entry& e);
std::uint32_t f4Bits(double value, const std::string& text);
std::string unitText(const Entry& e);  // "mV", "0.1 K", "190.73 uV", "" for none

// The commands entries a block names, in its order, and the bytes from its start to the end of its last
// member (check() found every member).
std::vector<const Entry*> blockMembers(const Family& fam, const Block& b);
int blockSize(const Family& fam, const Block& b);
std::string blockRange(std::uint32_t start, int size);  // "0x0A..0x3B", "0x7F" for one byte

// The fieldset's fields, highest bits first (the order of the Markdown table and the bit-field types).
std::vector<const Field*> fieldsByMsb(const Fieldset& fs);

}  // namespace regmapgen
