// Outputs of the CAN catalogue: the C++ packers the firmware links, and one DBC file per layout.
#pragma once

#include <string>

#include "can/can_model.hpp"

namespace regmapgen::can {

// can/<catalogue>.hpp: one struct per message with raw fields, pack() and unpack(), and kReceivedIds.
// Integer-only.
std::string emitCpp(const Catalogue& cat, const std::string& sourcePath);
// <catalogue>_<layout>.dbc: the messages of one layout, with multiplexed groups expanded per item.
std::string emitDbc(const Catalogue& cat, const std::string& layout, const std::string& sourcePath);
// can/<catalogue>_table.hpp: every message and signal by name as constant data, for host tools.
std::string emitCppTable(const Catalogue& cat, const std::string& sourcePath);
// REFERENCE.md: every message and its signals as Markdown tables (beside the DBC files).
std::string emitMarkdown(const Catalogue& cat, const std::string& sourcePath);

}  // namespace regmapgen::can
