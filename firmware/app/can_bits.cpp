#include "app/can_bits.hpp"

namespace fw::can {

// The same walk as put(), with the value shifted instead of indexed: little-endian fields take bit 0 and
// shift right, big-endian ones start with their MSB at bit 31 and shift left.
void packRuntime(std::array<uint8_t, 8>& data, const Field* fields, const uint32_t* values, uint8_t count) {
  data = {};
  for (; count != 0; --count, ++fields, ++values) {
    uint32_t v = *values;
    uint16_t pos = fields->start;
    const bool bigEndian = FW_CAN_TI_LAYOUT && fields->bigEndian;
    if (bigEndian) v <<= 32U - fields->length;
    for (uint8_t n = fields->length; n != 0; --n) {
      if ((bigEndian ? v >> 31 : v & 1U) != 0)
        data[pos / 8] = static_cast<uint8_t>(data[pos / 8] | (1U << (pos % 8)));
      if (bigEndian) {
        v <<= 1;
        pos = nextMotorolaBit(pos);
      } else {
        v >>= 1;
        ++pos;
      }
    }
  }
}

}  // namespace fw::can
