// Bit packing for CAN signals, in the DBC conventions the generated packers (can/<catalogue>.hpp) follow.
//
//   little-endian (Intel, DBC "@1"): `start` is the least significant bit; bits run upwards through the
//   bytes. big-endian (Motorola, DBC "@0"): `start` is the most significant bit in DBC numbering (byte * 8 +
//   bit, bit 7 = MSB of the byte); bits run down within a byte and continue at bit 7 of the next byte.
// Signals are at most 32 bits. Bits of `value` above `length` are ignored. constexpr, ISR-safe, no tables.
#pragma once

#include <array>
#include <cstdint>
#include <type_traits>

#include "app/config.hpp"

// The TI layout (big-endian fields) is packed at run time only where it is built: FW_CAN_TI_LAYOUT
// (app/config.hpp). Without it packRuntime() packs little-endian fields only (every native message's are);
// constant evaluation packs both either way.

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

// Out-of-line packing loop (can_bits.cpp): one copy in the image, however many messages use it.
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

constexpr int32_t signExtend(uint32_t value, uint8_t length) {
  const uint32_t sign = 1U << (length - 1);
  return static_cast<int32_t>((value ^ sign) - sign);
}

}  // namespace fw::can
