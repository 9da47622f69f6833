// The end-to-end protection of command frames, laid out as AUTOSAR E2E profile 1 lays a frame out: a CRC-8
// in byte 0, a 4-bit alive counter in the low nibble of byte 1 (firmware/app/can/bms.yaml, "Commands").
//
// crc8J1850: CRC-8 SAE J1850 (polynomial 0x1D, initial value 0xFF, final XOR 0xFF, no reflection; check value
// 0x4B over "123456789", the parameters of AUTOSAR's Crc_CalculateCRC8) over the identifier's low byte, its
// high byte, then payload bytes 1 .. length-1 (everything but the CRC byte itself).
// CounterWindow: one last-taken counter per command message. A frame whose counter equals the last one its
// message was taken with is a repeat (a replayed or duplicated frame); any other value is taken and becomes
// the last (frames may be lost in between). The first frame of a message after start-up is always taken.
// Pure functions and plain data; no state beyond the window.
#pragma once

#include <cstdint>

#include "hal/can_bus.hpp"

namespace fw::app::command {

constexpr uint8_t crc8J1850Update(uint8_t crc, uint8_t byte) {
  crc = static_cast<uint8_t>(crc ^ byte);
  for (int bit = 0; bit < 8; ++bit)
    crc = static_cast<uint8_t>((crc & 0x80U) ? (crc << 1) ^ 0x1DU : (crc << 1));
  return crc;
}

// The CRC a frame with identifier `id` and these `length` bytes carries in byte 0 (data[0] is not used).
uint8_t frameCrc(uint32_t id, const uint8_t* data, uint8_t length);

inline bool crcValid(const hal::CanFrame& f) {
  return f.dlc >= 1 && f.data[0] == frameCrc(f.id, f.data.data(), f.dlc);
}
inline uint8_t counterOf(const hal::CanFrame& f) {
  return f.data[1] & 0x0FU;
}

template <uint8_t kMessages>
struct CounterWindow {      // all-zero: nothing taken yet
  uint8_t last[kMessages];  // bit 4 set: a counter has been taken (the low nibble)
  // Takes `counter` for message `index`; false if it repeats the last one taken.
  bool take(uint8_t index, uint8_t counter) {
    const uint8_t seen = static_cast<uint8_t>(0x10U | counter);
    if (last[index] == seen) return false;
    last[index] = seen;
    return true;
  }
};

}  // namespace fw::app::command
