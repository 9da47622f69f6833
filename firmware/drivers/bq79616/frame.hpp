// BQ79616 UART frame codec: command frames from the host to the base device, response frames back.
//
// Command frame (SLUSE81E §9.3.6.1.1), bytes in wire order:
//   INIT [DEV_ID] REG_HI REG_LO DATA... CRC_LO CRC_HI
//   INIT    bit 7 = 1 (command), bits 6:4 = RequestType, bit 3 = 0, bits 2:0 = data length − 1 for every
//           write type (the reverse-direction broadcast write included), 0 for reads
//   DEV_ID  single-device read/write only: the device address, 0..63
//   DATA    writes: 1..8 bytes written to consecutive registers from REG; reads: one byte, bytes wanted − 1
//   CRC     CRC-16/MODBUS (core/crc.hpp) over INIT..last DATA byte, low byte first
// Response frame, one per responding device:
//   LEN−1 DEV_ID REG_HI REG_LO DATA[LEN] CRC_LO CRC_HI   (LEN + 6 bytes; the CRC over the whole frame is 0)
// A stack or broadcast read returns one frame per device back to back, the top of the stack (highest
// address) first and the base device (address 0) last.
//
// Contract
// - encodeWrite()/encodeRead() return the frame length, or 0 (and write nothing) when the arguments are not a
//   frame the protocol allows: a read type for a write or the reverse, a device above 63 in a single-device
//   frame, 0 or more than 8 write bytes, 0 or more than 128 read bytes, or an `out` shorter than the frame.
//   Nothing is ever sent for a malformed request (TI's ReadFrameReq refused > 128 bytes but still waited).
// - parseResponse() validates the frame at the start of `bytes` against the read that was sent and names the
//   first problem: Truncated (fewer than count + 6 bytes), Crc (the frame's CRC does not check), Length (the
//   frame is intact but announces another length), DeviceId (intact, but the device byte has its reserved
//   bits set or the register is not the one read). `out` is written only on Ok and points into `bytes`.
// - encodeFrame()/checkResponse() are the unchecked cores of the above, for callers whose frames are valid by
//   construction (the chain driver's own scripts): encodeFrame() trusts its arguments, checkResponse() is
//   parseResponse() without the output.
// - Pure functions: no state, no allocation, callable from any context.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

#include "core/status.hpp"

namespace fw::drivers::bq79616 {

enum class RequestType : uint8_t {
  SingleRead = 0,
  SingleWrite = 1,
  StackRead = 2,
  StackWrite = 3,
  BroadcastRead = 4,
  BroadcastWrite = 5,
  BroadcastWriteReverse = 6,  // a broadcast write sent in the direction opposite to CONTROL1[DIR_SEL]
};

constexpr bool isRead(RequestType t) {
  return t == RequestType::SingleRead || t == RequestType::StackRead || t == RequestType::BroadcastRead;
}
constexpr bool hasDeviceId(RequestType t) {
  return t == RequestType::SingleRead || t == RequestType::SingleWrite;
}

inline constexpr uint8_t kMaxAddress = 63;      // 6-bit device address
inline constexpr size_t kMaxWriteBytes = 8;     // registers one write frame may set
inline constexpr size_t kMaxReadBytes = 128;    // registers one read frame may return per device
inline constexpr size_t kResponseOverhead = 6;  // LEN−1, DEV_ID, REG_HI, REG_LO, CRC_LO, CRC_HI
inline constexpr size_t kMaxCommandBytes = 14;  // INIT + DEV_ID + 2 REG + 8 DATA + 2 CRC
inline constexpr uint8_t kInitCommand = 0x80;   // INIT bit 7: a command frame

// Bytes of one device's response frame to a read of `count` registers.
constexpr size_t responseSize(size_t count) {
  return count + kResponseOverhead;
}

// The INIT byte of a command frame. `writeLength` (1..8) is used for the write types only.
constexpr uint8_t initByte(RequestType type, size_t writeLength) {
  const auto base = static_cast<uint8_t>(kInitCommand | (static_cast<uint8_t>(type) << 4));
  if (isRead(type) || writeLength == 0) return base;
  return static_cast<uint8_t>(base | ((writeLength - 1) & 0x07U));
}

size_t encodeWrite(RequestType type, uint8_t device, uint16_t reg, std::span<const uint8_t> data,
                   std::span<uint8_t> out);
size_t encodeRead(RequestType type, uint8_t device, uint16_t reg, size_t count, std::span<uint8_t> out);

struct ResponseFrame {
  uint8_t device;
  uint16_t reg;
  std::span<const uint8_t> data;
};

Status parseResponse(std::span<const uint8_t> bytes, uint16_t reg, size_t count, ResponseFrame& out);

// A command frame with INIT byte `init` (initByte()): DEV_ID when the type has one, REG, the `n` bytes at
// `data` (a write's data, or a read's single "bytes − 1" byte) and the CRC, at `out`; returns its length.
// Preconditions, not checked: a valid INIT byte, device <= 63, n 1..8, `out` holds n + 6 bytes.
size_t encodeFrame(uint8_t init, uint8_t device, uint16_t reg, const uint8_t* data, size_t n, uint8_t* out);

// parseResponse() of the `available` bytes at `frame`, without the output: the device is frame[1] and the
// data starts at frame[4].
Status checkResponse(const uint8_t* frame, size_t available, uint16_t reg, size_t count);

}  // namespace fw::drivers::bq79616
