#include "app/publish/can_bits.hpp"

namespace fw::can {

// The payload as two 32-bit words, little-endian: a field of up to 32 bits lands in one word or straddles the
// two, so the loop is a few shifts per field, and no 64-bit shift (a library call on ARMv6-M) is needed. A
// big-endian field of 16 bits on a byte boundary (the TI layout's) is its two bytes swapped at its first
// byte; any other big-endian field goes bit by bit (none of bms.yaml's).
void packRuntime(std::array<uint8_t, 8>& data, const Field* fields, const uint32_t* values, uint8_t count) {
  uint32_t word[2] = {0, 0};
  for (uint8_t i = 0; i < count; ++i) {
    const Field f = fields[i];
    const uint32_t n = f.length;
    uint32_t v = values[i] << (32U - n) >> (32U - n);  // the field's bits only (n is 1..32)
    uint32_t at = f.start;                             // its least significant bit
    if (FW_CAN_TI_LAYOUT && f.bigEndian) {
      if (n != 16 || at % 8 != 7) continue;  // packed bit by bit below
      v = (v >> 8) | ((v & 0xFFU) << 8);
      at -= 7;
    }
    const uint32_t shift = at & 31U;
    word[at >> 5] |= v << shift;
    if (at < 32 && shift != 0) word[1] |= v >> (32U - shift);  // the bits that cross into the second word
  }
  for (uint32_t i = 0; i < 8; ++i)
    data[i] = static_cast<uint8_t>(word[i >> 2] >> ((i & 3U) * 8U));
  if (FW_CAN_TI_LAYOUT) {
    for (uint8_t i = 0; i < count; ++i) {
      const Field f = fields[i];
      if (f.bigEndian && (f.length != 16 || f.start % 8 != 7)) put(data, f.start, f.length, true, values[i]);
    }
  }
}

}  // namespace fw::can
