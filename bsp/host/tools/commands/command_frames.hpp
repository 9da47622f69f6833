// Command frames for host tools (bms-sim's `send` and `flood` steps, bmsctl send, tests): any message of the
// CAN catalogue built by name from "Signal=value" words, with the alive counter kept per message and the
// CRC-8 computed as the firmware checks it (firmware/app/command/e2e.hpp); and any frame described back in
// words.
//
// Values: decimal or 0x-hex integers, negative for signed signals, or a name of the signal's value table
// ("Setting=cell_ov_trip", "Target=all"). A value outside the signal's raw range is an error. For a command
// (direction rx) Target defaults to node 1 (FW_COMMAND_NODE's default), Counter to the next value of that
// message's counter (counters start at `firstCounter`), Crc to the right CRC; any of them can be given to
// build a frame the firmware must refuse. Every other signal defaults to 0.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "can/bms_table.hpp"
#include "hal/can_bus.hpp"

namespace bmstool {

namespace table = fw::can::bms::table;

const table::Message* findMessage(std::string_view name);
const table::Message* findMessage(uint32_t id, bool extended);
const table::Signal* findSignal(const table::Message& m, std::string_view name);

// The raw value `text` names for signal `s`, or nullopt with `error` set.
std::optional<int64_t> parseValue(const table::Signal& s, std::string_view text, std::string& error);
// The raw value of `s` in `frame` (sign-extended for a signed signal).
int64_t signalValue(const table::Signal& s, const fw::hal::CanFrame& frame);
// "CommandAck Node=1 Command=0x600 Counter=3 Result=accepted Rejected=0", or "0x123 [3] 01 02 03" for an
// identifier the catalogue does not have.
std::string describe(const fw::hal::CanFrame& frame);

class CommandBuilder {
 public:
  explicit CommandBuilder(uint8_t firstCounter = 0) : first_(firstCounter) {}
  // "Message" then "Signal=value" words. nullopt with `error` set for an unknown message or signal, a
  // malformed value or one out of range.
  std::optional<fw::hal::CanFrame> build(std::string_view message, const std::vector<std::string>& words,
                                         std::string& error);
  std::optional<fw::hal::CanFrame> build(const table::Message& m, const std::vector<std::string>& words,
                                         std::string& error);

 private:
  uint8_t first_;
  std::map<uint32_t, uint8_t> next_;  // next counter per message id
};

}  // namespace bmstool
