#include "app/publish/can_bits.hpp"

#include "core/bytes.hpp"

namespace fw::can {

namespace {

// The field's bits only (n is 1..32).
uint32_t fieldBits(uint32_t value, uint32_t n) {
  return value << (32U - n) >> (32U - n);
}
// A big-endian field of 16 bits on a byte boundary (the TI layout's) is a little-endian one with its two
// bytes swapped.
uint32_t swapBytes16(uint32_t v) {
  return (v >> 8) | ((v & 0xFFU) << 8);
}

}  // namespace

// The host tools' packer (pack() at run time); the firmware packs its frames with packStream() below.
void packRuntime(std::array<uint8_t, 8>& data, const Field* fields, const uint32_t* values, uint8_t count) {
  data = {};
  for (; count != 0; --count, ++fields, ++values)
    put(data, fields->start, fields->length, FW_CAN_TI_LAYOUT && fields->bigEndian, *values);
}

void packStream(std::array<uint8_t, 8>& data, const uint8_t* codes, const uint32_t* values, uint8_t count) {
  // The payload as two little-endian words (bytes 0..3 and 4..7), stored at the end: a field is one or two
  // ORs instead of a byte at a time, and the payload needs no clearing first.
  uint32_t word[2] = {0, 0};
  uint32_t at = 0;  // where the next field starts (unless it starts on the next byte)
  for (; count != 0; --count) {
    const uint32_t code = *codes++;
    const uint32_t n = code & 0x3FU;
    uint32_t v = fieldBits(*values++, n);
    if ((code & kStreamByteAligned) != 0) at = (at + 7U) & ~7U;
    if (FW_CAN_TI_LAYOUT && (code & kStreamBigEndian) != 0) v = swapBytes16(v);
    const uint32_t shift = at % 32;
    word[at / 32] |= v << shift;
    if (shift + n > 32) word[1] |= v >> (32 - shift);  // a field across bytes 3 and 4 (within 64 bits)
    at += n;
  }
  bytes::storeLe32(&data[0], word[0]);
  bytes::storeLe32(&data[4], word[1]);
}

}  // namespace fw::can
