#include "app/command/e2e.hpp"

namespace fw::app::command {

uint8_t frameCrc(uint32_t id, const uint8_t* data, uint8_t length) {
  uint8_t crc = crc8J1850Update(0xFF, static_cast<uint8_t>(id));
  crc = crc8J1850Update(crc, static_cast<uint8_t>(id >> 8));
  for (uint8_t i = 1; i < length; ++i)
    crc = crc8J1850Update(crc, data[i]);
  return static_cast<uint8_t>(crc ^ 0xFFU);
}

}  // namespace fw::app::command
