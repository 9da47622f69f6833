// Bit packing for CAN signals, in the DBC conventions the generated packers (can/<catalogue>.hpp) follow.
//
//   little-endian (Intel, DBC "@1"): `start` is the least significant bit; bits run upwards through the
//   bytes. big-endian (Motorola, DBC "@0"): `start` is the most significant bit in DBC numbering (byte * 8 +
//   bit, bit 7 = MSB of the byte); bits run down within a byte and continue at bit 7 of the next byte.
// Signals are at most 32 bits. Bits of `value` above `length` are ignored. constexpr, ISR-safe, no tables.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <type_traits>

#include "app/config.hpp"

// The TI layout (big-endian fields) is packed at run time only where it is built: FW_CAN_TI_LAYOUT
// (app/config.hpp). Without it packRuntime() and packStream() pack little-endian fields only (every native
// message's are); constant evaluation packs both either way.

namespace fw::can {

// Position of the next bit (towards the LSB) of a big-endian signal.
constexpr uint16_t nextMotorolaBit(uint16_t pos) {
  return (pos % 8 == 0) ? static_cast<uint16_t>(pos + 15) : pos - 1;
}

// Sets the bits of one signal in `data`, whose bits there are zero (pack() clears the frame first), so only
// the ones are written.
constexpr void put(std::array<uint8_t, 8>& data, uint16_t start, uint8_t length, bool bigEndian,
                   uint32_t value) {
  uint16_t pos = start;
  for (uint8_t i = 0; i < length; ++i) {
    // Little-endian walks from the LSB up; big-endian from the MSB down.
    const uint8_t bit = bigEndian ? static_cast<uint8_t>(length - 1 - i) : i;
    if ((value >> bit) & 1U) data[pos / 8] = static_cast<uint8_t>(data[pos / 8] | (1U << (pos % 8)));
    pos = bigEndian ? nextMotorolaBit(pos) : static_cast<uint16_t>(pos + 1);
  }
}

constexpr uint32_t get(const std::array<uint8_t, 8>& data, uint16_t start, uint8_t length, bool bigEndian) {
  uint32_t value = 0;
  uint16_t pos = start;
  for (uint8_t i = 0; i < length; ++i) {
    const uint8_t bit = bigEndian ? static_cast<uint8_t>(length - 1 - i) : i;
    if ((data[pos / 8] >> (pos % 8)) & 1U) value |= 1U << bit;
    pos = bigEndian ? nextMotorolaBit(pos) : static_cast<uint16_t>(pos + 1);
  }
  return value;
}

// One signal slot of a message: where it sits. The generated packers keep a constexpr table of these per
// message and pack all of a frame's values with one call, so every message shares one packing loop.
// Two bytes (length and byte order share one), as the tables of every message sit in flash.
struct Field {
  uint8_t start;
  uint8_t length : 7;  // 1..32
  uint8_t bigEndian : 1;
};
static_assert(sizeof(Field) == 2);

// Out-of-line packing loop (can_bits.cpp) of pack() at run time, for the host tools: the firmware packs its
// own frames from stream codes (packStream() below).
void packRuntime(std::array<uint8_t, 8>& data, const Field* fields, const uint32_t* values, uint8_t count);

// Writes the whole payload: every bit that no field covers is 0.
constexpr void pack(std::array<uint8_t, 8>& data, const Field* fields, const uint32_t* values,
                    uint8_t count) {
  if (std::is_constant_evaluated()) {
    data = {};
    for (uint8_t i = 0; i < count; ++i)
      put(data, fields[i].start, fields[i].length, fields[i].bigEndian, values[i]);
  } else {
    packRuntime(data, fields, values, count);
  }
}

// The firmware's own frames (FramePlan's messages and the command answers) are packed from stream codes: one
// byte per field instead of a Field. Every field of those messages starts where the previous one ended, or
// at the next byte boundary, so a field needs only its length (bits 0..5), whether it starts on the next
// byte (kStreamByteAligned) and its byte order (kStreamBigEndian: the TI layout's 16-bit fields, which
// start on a byte boundary, their two bytes swapped).
constexpr uint8_t kStreamBigEndian = 0x80;
constexpr uint8_t kStreamByteAligned = 0x40;

// A field's first (least significant) bit in the payload's bit stream.
constexpr uint16_t firstBit(const Field& f) {
  return f.bigEndian ? static_cast<uint16_t>(f.start / 8 * 8) : f.start;
}
// Whether `fields` can be packed from stream codes (above), within 64 bits.
constexpr bool streamable(const Field* fields, size_t count) {
  uint16_t next = 0;
  for (size_t i = 0; i < count; ++i) {
    const Field& f = fields[i];
    const uint16_t lsb = firstBit(f);
    if (f.length > 32 || (f.bigEndian && (f.length != 16 || f.start % 8 != 7))) return false;
    if (lsb != next && lsb != (next + 7) / 8 * 8) return false;
    next = static_cast<uint16_t>(lsb + f.length);
  }
  return next <= 64;
}
// The stream codes of message M (generated: M::kFields, M::kFieldCount).
template <class M>
constexpr std::array<uint8_t, M::kFieldCount> streamCodes() {
  static_assert(streamable(M::kFields, M::kFieldCount), "a message that stream codes cannot describe");
  std::array<uint8_t, M::kFieldCount> codes{};
  uint16_t next = 0;
  for (size_t i = 0; i < M::kFieldCount; ++i) {
    const Field& f = M::kFields[i];
    codes[i] = static_cast<uint8_t>(f.length | (f.bigEndian ? kStreamBigEndian : 0) |
                                    (firstBit(f) != next ? kStreamByteAligned : 0));
    next = static_cast<uint16_t>(firstBit(f) + f.length);
  }
  return codes;
}

// Writes the values of `count` fields given by their stream codes as the whole payload (every bit no field
// covers 0): the same bytes pack() writes from those fields' Field table.
void packStream(std::array<uint8_t, 8>& data, const uint8_t* codes, const uint32_t* values, uint8_t count);

constexpr int32_t signExtend(uint32_t value, uint8_t length) {
  const uint32_t sign = 1U << (length - 1);
  return static_cast<int32_t>((value ^ sign) - sign);
}

}  // namespace fw::can
