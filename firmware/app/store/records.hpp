// The records the firmware keeps in the RecordStore: their type numbers and fixed-size little-endian
// payloads.
//
// Contract
// - Each payload is a fixed number of bytes, encoded little-endian field by field (never a memcpy of a
//   struct), so the flash format does not depend on the compiler. decode() refuses a payload of another
//   length (a record written by another format version) by returning false.
// - Type numbers are part of the flash format: never renumber, only add (RecordStore::kTypes at most).
#pragma once

#include <array>
#include <cstdint>
#include <span>

namespace fw::app::store {

enum class RecordType : uint8_t { Settings = 0, ProtectionLog = 1, Fault = 2, StateOfCharge = 3 };

// The sixteen command-written protection settings (app/command/settings.hpp, setting ids 0..15).
struct SettingsRecord {
  static constexpr uint32_t kBytes = 64;
  std::array<int32_t, 16> value{};
};

// The last kEntries protection trips, oldest first; `count` of them are used.
struct ProtectionLogRecord {
  static constexpr uint8_t kEntries = 4;
  static constexpr uint32_t kBytes = 4 + kEntries * 12;
  struct Entry {
    uint8_t rule = 0;      // app::FaultId
    uint32_t uptimeS = 0;  // when it tripped, seconds since start-up
    int32_t value = 0;     // the value that tripped it, in the rule's unit (mV, mA, 0.1 K)
  };
  uint8_t count = 0;
  std::array<Entry, kEntries> entry{};
  // Encoded: byte 0 the count, three bytes 0, then entry i at entryOffset(i), kEntryBytes each.
  static constexpr uint32_t kEntryBytes = 12;
  static constexpr uint32_t entryOffset(uint32_t i) { return 4 + kEntryBytes * i; }
};

// The last fault: the reset cause (hal::SystemControl identity's resetCause), the fault's code (the line of
// fw::onFault, or a code: core/assert.hpp, bsp/mspm0/fault.hpp), the PC if known, and its fw::Module.
struct FaultRecord {
  static constexpr uint32_t kBytes = 12;
  uint8_t resetCause = 0;
  uint16_t code = 0;
  uint32_t pc = 0;  // 0 when unknown
  uint32_t uptimeS = 0;
  uint8_t module = 0;  // fw::Module (byte 1 of the payload, 0 in records written before it)
};

// The state of charge as app/soc keeps it.
struct SocRecord {
  static constexpr uint32_t kBytes = 8;
  uint16_t permille = 0;
  uint32_t remainingMah = 0;
};

void encode(const SettingsRecord& r, std::span<uint8_t, SettingsRecord::kBytes> out);
void encode(const ProtectionLogRecord& r, std::span<uint8_t, ProtectionLogRecord::kBytes> out);
// One entry of the encoded log, at ProtectionLogRecord::entryOffset(i) (Persistence keeps the log encoded).
void encode(const ProtectionLogRecord::Entry& e, std::span<uint8_t, ProtectionLogRecord::kEntryBytes> out);
void encode(const FaultRecord& r, std::span<uint8_t, FaultRecord::kBytes> out);
void encode(const SocRecord& r, std::span<uint8_t, SocRecord::kBytes> out);
bool decode(std::span<const uint8_t> in, SettingsRecord& r);
bool decode(std::span<const uint8_t> in, ProtectionLogRecord& r);
bool decode(std::span<const uint8_t> in, FaultRecord& r);
bool decode(std::span<const uint8_t> in, SocRecord& r);

}  // namespace fw::app::store
