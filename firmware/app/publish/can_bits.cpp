#include "app/publish/can_bits.hpp"

namespace fw::can {

void packRuntime(std::array<uint8_t, 8>& data, const Field* fields, const uint32_t* values, uint8_t count) {
  data = {};
  for (; count != 0; --count, ++fields, ++values)
    put(data, fields->start, fields->length, FW_CAN_TI_LAYOUT && fields->bigEndian, *values);
}

}  // namespace fw::can
