// Identifier rules: how TRM names become C++ names, and what a usable C++ name is.
//
// pascalCase("Cell 1 Voltage") == "Cell1Voltage"; ("FET_ENABLE") == "FetEnable"; ("VCell Mode") ==
// "VCellMode";
// ("VCELL16_HI") == "Vcell16Hi"; ("ManufacturerBlockAccess") unchanged. Words are the runs of ASCII letters
// and digits; a word without lower-case letters is title-cased ("FET" -> "Fet"), any other word keeps its
// spelling with the first letter upper-cased ("VCell" -> "VCell").
// snakeCase("MSK_SFALERT") == "msk_sfalert"; ("SEC[1:0]") == "sec" (a trailing bit range is dropped);
// ("IPScale") == "ipscale".
// A derived name can still be unusable (starts with a digit, is a C++ keyword): the checker reports it and
// the YAML gives an explicit `id:`.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

namespace regmapgen {

std::string pascalCase(std::string_view name);
std::string snakeCase(std::string_view name);

bool isIdentifier(std::string_view s);  // [A-Za-z_][A-Za-z0-9_]*
bool isCppKeyword(std::string_view s);  // keywords and alternative tokens of C++20
bool isAscii(std::string_view s);

// Lower-cased, with '_', ' ' and '-' removed: the form runtime lookup compares (table.hpp findByName).
std::string lookupKey(std::string_view name);

// ASCII letters upper-cased, every other byte as it is: "bq769x2" -> "BQ769X2".
std::string upperCase(std::string_view s);

// "0x" and upper-case hex digits, zero-padded to `digits`: hexAddress(0x14, 4) == "0x0014", (0x14) == "0x14".
std::string hexAddress(std::uint64_t value, int digits = 0);

}  // namespace regmapgen
