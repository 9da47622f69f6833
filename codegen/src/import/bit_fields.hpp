// The cells of a TI bit-field table ("Bit | Field | Default | Description", SLUUBY2B Tables 12-2 to 12-32 and
// 13-1 to 13-36) as fields of a register-map fieldset.
#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace regmapgen::bit_fields {

struct Bits {
  int msb = 0, lsb = 0;
  std::string text;  // the YAML spelling: "7", "9:8"
};

// "7", "15–8", "5-4", "31:16"; nothing for anything else or a bit beyond 31.
std::optional<Bits> bits(std::string_view cell);

// The field name of the map from TI's: a single bit keeps its name ("CUV"); a group named by its ends gets
// the common part and the bit range of the field ("SEC1–SEC0" -> "SEC[1:0]", "CB_LOOP_SLOW_1–CB_LOOP_SLOW_0"
// -> "CB_LOOP_SLOW[1:0]", "REG2V_2–REG2V_0" -> "REG2V[2:0]"); other names of a group are kept as written.
std::string name(std::string_view cell, const Bits& b);

// Reserved bits TI lists ("RSVD", "RSVD_0", "RSVD_1", "Reserved"): the map leaves them out.
bool reserved(std::string_view name);

// The meaning of a field in a few words: its description up to the list of values ("0 = ...").
std::string meaning(std::string_view description);

}  // namespace regmapgen::bit_fields
