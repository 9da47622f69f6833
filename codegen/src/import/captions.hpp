// What a TI table is, from its caption and the section it is in: the register summaries `import` reads from a
// whole document, and the register a bit-field table describes.
#pragma once

#include <string>
#include <string_view>

namespace regmapgen {

// A caption of a register summary: its title is made only of the words TI's summary tables use ("Table 12-1.
// Direct Commands Table", "Table 12-22. Table of Command-Only Subcommands", "Table 13-37. Data Memory Table",
// "Table 14-1. Data Flash Summary", "Table 13-1. ManufacturerAccess() Command List", "Register Summary"),
// not a table about one feature ("Table 4-1. Commands to Read 16-Bit Voltage Measurements", "Table 5-7. FET
// Test Mode Subcommands").
bool isSummaryCaption(std::string_view caption);

// The register a bit-field table describes: of "Table 12-3. Safety Alert A Register Field Descriptions"
// "Safety Alert A", else of the section "12.2.2 Safety Alert A Register" the same; "" if neither says.
std::string fieldTableRegister(std::string_view caption, std::string_view section);

// "12-1" of "Table 12-1. Direct Commands Table"; "" without a caption.
std::string captionNumber(std::string_view caption);

// The title of a numbered section heading without its number ("13.2.1.1 Calibration:Voltage:Cell 1 Gain" ->
// "Calibration:Voltage:Cell 1 Gain").
std::string_view sectionTitle(std::string_view section);

}  // namespace regmapgen
