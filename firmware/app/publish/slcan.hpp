// SLCAN (Lawicel CAN-over-serial) text encoding of CAN frames, for the L1306 images, whose results leave on
// the LaunchPad's back-channel UART so that PC CAN tools (slcand, SavvyCAN, python-can's slcan interface) can
// read them as a CAN bus.
//
//   standard frame:  t<iii><l><dd>...\r     e.g. id 0x004, 8 bytes -> "t004816C016BC16B416B9\r"
//   extended frame:  T<iiiiiiii><l><dd>...\r
// Identifiers and data are uppercase hex; l is the DLC digit (0..8).
//
// Contract: encode() writes at most kMaxEncodedLength bytes and returns the number written, or 0 when the
// frame is invalid (DLC > 8, identifier out of range) or `out` is too small. encodeStandard() writes the line
// of a classic 8-byte frame with a standard identifier (below 0x800: the caller guarantees it), always
// kStandardLength bytes at `out`. Pure functions, ISR-safe.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

#include "hal/can_bus.hpp"

namespace fw::app::slcan {

inline constexpr size_t kMaxEncodedLength = 1 + 8 + 1 + 16 + 1;  // 'T' + id + dlc + data + '\r'

inline constexpr size_t kStandardLength = 1 + 3 + 1 + 16 + 1;  // 't' + id + '8' + data + '\r'

// The uppercase digit of a nibble (the low four bits of `value`): one table for every SLCAN writer.
inline constexpr uint8_t kHexDigits[16] = {'0', '1', '2', '3', '4', '5', '6', '7',
                                           '8', '9', 'A', 'B', 'C', 'D', 'E', 'F'};
inline uint8_t hexDigit(uint32_t value) {
  return kHexDigits[value & 0xFU];
}

size_t encode(const hal::CanFrame& frame, std::span<uint8_t> out);
void encodeStandard(uint16_t id, const std::array<uint8_t, 8>& data, uint8_t* out);

}  // namespace fw::app::slcan
