// The cells of TI register tables as register-map values: numbers, units, access and type words as TI
// prints them (in TRMs, data sheets and app notes, English or Chinese) become the YAML spellings.
#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace regmapgen::cells {

// A number cell: en dash, minus sign and figure dash read as '-' ("–32767", "1.00E–01"), spaces dropped;
// an em dash, a lone dash or "N/A" (no value) as ""; of "HW Reset Default = 0x00 Factory Configuration
// Default = 0x01" the factory value.
std::string number(std::string_view cell);

// A unit cell: "mV", "50.6 mV" (scale 50.6), "0.1°C" (degC, scale 0.1), "0.1 K", "190.73 µV", "mΩ", "%",
// "mAh" over "10 mWh" (the SBS capacity unit "mAh|10mWh"), 毫伏... Hex, ASCII, 十六进制 and dashes are no
// unit.
struct Unit {
  std::string unit;   // schema symbol, "" for none
  std::string scale;  // "" for 1
  bool understood = true;
};
Unit unit(std::string_view cell);

// An access cell: R, W, R/W, RW, W1C, NVM (BQ79616 OTP-backed: rw); of several ("Sealed: R Unsealed: R/W Full
// Access: R/W", or the SE, US and FA columns of the BQ4050 TRM) the last, which is full access. Nothing if no
// access word is in it.
std::optional<std::string> access(std::string_view cell);

// A name cell: "Voltage()" (SBS function style) -> "Voltage", runs of spaces as one.
std::string name(std::string_view cell);

// The type several payload fields of one subcommand add up to, or nothing unless the cell is two or more
// fixed-size type codes: fields of one integer type are an array ("U2 U2 U2 U2" -> 4xU2), unless they are
// big-endian (the schema's arrays are little-endian), and any other mix a block ("U2 U2 U2" big-endian ->
// B6).
std::optional<std::string> fieldsType(std::string_view cell, bool bigEndian);

// A type from words: Type "Hex"/"Unsigned Int"/"Signed Int"/"Float"/"String" with a size in bytes, or a
// format "Block"/"Word"/"Byte" (BQ4050): "Hex" + 2 -> H2, "Block" -> B, "String" + 21 -> S21.
std::optional<std::string> typeFromWords(std::string_view type, std::string_view format,
                                         std::string_view size);

// "H6" is how TI writes a 6-byte hex block; the schema's word for it is B6. Nothing for other codes.
std::optional<std::string> blockForWideHex(std::string_view type);

}  // namespace regmapgen::cells
