#include "app/publish/can_bits.hpp"

namespace fw::can {

// A little-endian field is its value shifted to its first bit, ORed into the bytes it covers: a byte at a
// time, not a bit at a time. A big-endian field of 16 bits on a byte boundary (the TI layout's) is the same
// with its two bytes swapped, at its first byte; any other big-endian field goes bit by bit (none of
// bms.yaml's).
void packRuntime(std::array<uint8_t, 8>& data, const Field* fields, const uint32_t* values, uint8_t count) {
  data = {};
  for (; count != 0; --count, ++fields, ++values) {
    const Field f = *fields;
    const uint32_t n = f.length;
    uint32_t v = *values << (32U - n) >> (32U - n);  // the field's bits only (n is 1..32)
    uint32_t at = f.start;                           // its least significant bit
    if (FW_CAN_TI_LAYOUT && f.bigEndian) {
      if (n != 16 || at % 8 != 7) {
        put(data, f.start, f.length, true, v);
        continue;
      }
      v = (v >> 8) | ((v & 0xFFU) << 8);
      at -= 7;
    }
    uint8_t* byte = &data[at / 8];
    const uint32_t shift = at % 8;
    *byte = static_cast<uint8_t>(*byte | (v << shift));
    v >>= 8 - shift;
    for (int32_t left = static_cast<int32_t>(n + shift) - 8; left > 0; left -= 8, v >>= 8) {
      ++byte;
      *byte = static_cast<uint8_t>(*byte | v);
    }
  }
}

}  // namespace fw::can
