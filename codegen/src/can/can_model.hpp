// The CAN message catalogue: the frames the firmware publishes, read from YAML (firmware/app/can/*.yaml) and
// turned into integer-only C++ packers and DBC files (emit in can_emit.cpp).
//
// Schema (every key checked; unknown and missing keys are errors with file:line:col):
//   catalogue: <identifier>        namespace fw::can::<identifier>, files can/<identifier>.hpp and
//                                  <identifier>_<layout>.dbc
//   bitrate: 500000
//   node: BMS                      the transmitting node in the DBC
//   messages:
//     - name: CellVoltages         identifier (PascalCase)
//       id: 0x200                  11-bit, or 29-bit with `extended: true`
//       layout: native | ti | all  which DBC the message belongs to (ti = seed 001's frame layout; all =
//                                  every layout's DBC, for a message every image sends whatever its layout)
//       direction: tx | rx         tx (default): the node sends it; rx: the node receives it (a command).
//                                  C++ kReceived and kReceivedIds (the identifiers a receive filter
//                                  accepts); DBC: sent by Vector__XXX, received by the node
//       dlc: 8
//       cycle_ms: 1000             0 = event-driven only
//       description: ...
//       signals:
//         - name: Board
//           start: 0               Intel (little): LSB bit; Motorola (big): MSB bit, DBC numbering
//           length: 8              1..32
//           order: little | big    default little
//           signed: false
//           factor: "0.1"          physical = raw * factor + offset (DBC and docs only: firmware packs raw)
//           offset: "0"
//           unit: V
//           multiplexer: true      at most one per message: the frame index of a multiplexed group
//           count: 3               a group: `count` consecutive slots of `length` bits (a C++ array)
//           total: 16              with a multiplexer: the group has `total` items spread over frames, item i
//                                  in frame i / count, slot i % count (DBC: one signal per item, muxed)
//           values:                value descriptions (DBC VAL_)
//             0: valid
//           not_available: 0xFFFF  the raw value that means "no reading" (a cell the device does not have,
//                                  a failed board, an absent sensor). It must fit the signal's raw range
//                                  (signed signals: a negative number) and is left out of the physical
//                                  range, so it never decodes as a reading: DBC VAL_ "not_available",
//                                  comment, [min|max] without it; C++ k<Signal>NotAvailable.
//           description: ...
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "diag/diag.hpp"

namespace regmapgen::can {

struct Signal {
  std::string name;
  Loc loc;
  uint32_t start = 0;
  uint32_t length = 0;
  bool bigEndian = false;
  bool isSigned = false;
  std::string factor = "1";
  std::string offset = "0";
  double factorValue = 1;
  double offsetValue = 0;
  std::string unit;
  bool multiplexer = false;
  uint32_t count = 1;  // slots per frame (1 = a plain signal)
  uint32_t total = 0;  // items across frames (0 = not spread)
  std::map<int64_t, std::string> values;
  std::optional<int64_t> notAvailable;  // raw value meaning "no reading"
  std::string description;

  bool isGroup() const { return count > 1 || total > 0; }
  // Start bit of slot k of a group (Motorola slots are whole bytes apart).
  uint32_t slotStart(uint32_t k) const { return start + k * length; }
  // The raw range of the signal's bits, and the part of it that carries readings (without notAvailable
  // when it sits at either end).
  int64_t rawMin() const { return isSigned ? -(int64_t{1} << (length - 1)) : 0; }
  int64_t rawMax() const { return isSigned ? (int64_t{1} << (length - 1)) - 1 : (int64_t{1} << length) - 1; }
  int64_t readingMin() const { return notAvailable == rawMin() ? rawMin() + 1 : rawMin(); }
  int64_t readingMax() const { return notAvailable == rawMax() ? rawMax() - 1 : rawMax(); }
};

// The `layout` of a message in every layout's DBC.
inline constexpr const char* kEveryLayout = "all";

struct Message {
  std::string name;
  Loc loc;
  uint32_t id = 0;
  bool extended = false;
  std::string layout = "native";
  bool received = false;  // direction: rx
  uint32_t dlc = 8;
  uint32_t cycleMs = 0;
  std::string description;
  std::vector<Signal> signals;

  bool inLayout(const std::string& l) const { return layout == l || layout == kEveryLayout; }
  const Signal* multiplexer() const;
  // Frames needed for a multiplexed group (1 when there is none).
  uint32_t framesPerCycle() const;
};

struct Catalogue {
  std::string name;
  uint32_t bitrate = 500000;
  std::string node = "BMS";
  std::vector<Message> messages;
  std::vector<std::string> layouts() const;  // in order of first use, `all` not counted as one
};

// Reads, builds and checks the catalogue in `file`; problems go to `diag`.
Catalogue buildCatalogue(const Sources& sources, int file, Diagnostics& diag);

}  // namespace regmapgen::can
