#include "app/can_bits.hpp"

namespace fw::can {

void packRuntime(std::array<uint8_t, 8>& data, const Field* fields, const uint32_t* values, uint8_t count) {
  for (uint8_t i = 0; i < count; ++i)
    put(data, fields[i].start, fields[i].length, fields[i].bigEndian, values[i]);
}

}  // namespace fw::can
