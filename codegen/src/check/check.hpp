// Semantic checks on a built model: everything a well-formed YAML file can still get wrong.
//
// Contract
// - check() reports every problem it finds into Diagnostics (never stopping at the first), each at the
//   position of the offending value, naming the object path ("datamem 'Threshold' (Protections:CUV)").
// - Checks: identifiers (valid, not keywords, unique per C++ namespace), names (ASCII, unique per kind and
//   category), addresses (in range; duplicate or overlapping byte ranges for memory-like kinds, duplicate or
//   overlapping code ranges for subcommands/SBS/MAC), type/access agreement, values that do not fit their
//   type, min <= max, default within min..max, fieldset/enum references, fieldset widths, field bits within
//   the width and not overlapping, enum values fitting their fields, multi-byte values lying on registers.
//   Unused fieldsets and enums are warnings.
// - After check() reports no errors, the generator may assume every required value is present and valid.
#pragma once

#include "diag/diag.hpp"
#include "model/model.hpp"

namespace regmapgen {

void check(const Model& model, Diagnostics& diag);

// "command 'Cell 1 Voltage'", "datamem 'Threshold' (Protections:CUV)": how messages name an entry.
std::string describeEntry(const Entry& e);

}  // namespace regmapgen
