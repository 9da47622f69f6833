// Status: every way an operation can end, one distinct value each.
//
// Contract
// - `Status::Ok` is the only success value; every other value names one failure, so a caller can always
//   tell a NACK from a timeout from a corrupted byte. Drivers document which values each call returns.
// - Values are stable: tools print them by name (status_name.cpp, host only) and tests compare them.
// - [[nodiscard]]: a call that returns a Status must use it, or discard it with `(void)` and a comment that
//   says why ignoring it is safe.
// - Header-only, no dependencies; usable from ISRs.
#pragma once

#include <cstdint>

namespace fw {

// clang-format 14 misreads an attribute between `enum class` and the name (it re-indents the enumerators):
// the declaration is kept as written.
// clang-format off
enum class [[nodiscard]] Status : uint8_t {
  Ok = 0,
  Busy,             // the resource is already in use; nothing was started
  InvalidArgument,  // the request itself is malformed (length, range, null buffer)
  Nack,             // the target did not acknowledge its address
  DataNack,         // the target acknowledged its address but refused a data byte
  Timeout,          // a bounded wait expired (clock stretch, missing reply, echo budget)
  ArbitrationLost,  // another controller won the bus
  BusStuck,         // a line is held low and bus recovery did not free it
  Crc,              // a per-byte CRC-8 (BQ769x2) or frame CRC-16 (BQ79616) did not match
  Pec,              // an SMBus packet error code did not match
  Checksum,         // a BQ769x2/BQ7690x transfer-buffer checksum (0x60) did not match
  Length,           // a reported or received length is outside what the protocol allows
  EchoMismatch,     // a subcommand/MAC echo names a different command than the one sent
  Stale,            // the data is older than its freshness limit
  Implausible,      // a value lies outside the physical range its register can hold
  DeviceId,         // a reply came from another device or register than the one addressed
  Truncated,        // fewer bytes arrived than the frame announced
  NoResponse,       // nothing at all came back
  CommFault,        // the device itself reports a communication fault
  Overflow,         // a queue or buffer was full; the item was not stored
  BusOff,           // the CAN controller is bus-off
  NotReady,         // the device or driver is not initialised or is mid-recovery
  VerifyFailed,     // a read-back after a write did not return what was written
  Aborted,          // the operation was cancelled before it completed
  Unsupported,      // the device or build does not provide this operation
};
// clang-format on

// Number of distinct Status values (for tables indexed by status).
inline constexpr uint8_t kStatusCount = static_cast<uint8_t>(Status::Unsupported) + 1;

constexpr bool ok(Status s) {
  return s == Status::Ok;
}

// Human-readable name ("Nack", "Timeout"...). Defined in status_name.cpp; link it only where text is wanted
// (host tools, tests, QEMU prints), so target images carry no strings.
const char* statusName(Status s);

}  // namespace fw
