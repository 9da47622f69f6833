// Byte-order helpers: load and store 16/32-bit values from byte buffers, little- or big-endian.
//
// Contract: pure constexpr functions on unsigned bytes; no alignment requirement (byte-wise access, which
// also keeps ARMv6-M, where unaligned loads fault, safe). Signed variants convert through the unsigned value,
// so 0xFFFF loads as -1 without undefined behaviour.
#pragma once

#include <cstdint>

namespace fw::bytes {

constexpr uint16_t loadLe16(const uint8_t* p) {
  return static_cast<uint16_t>(p[0] | (p[1] << 8));
}
constexpr uint16_t loadBe16(const uint8_t* p) {
  return static_cast<uint16_t>((p[0] << 8) | p[1]);
}
constexpr uint32_t loadLe32(const uint8_t* p) {
  return static_cast<uint32_t>(p[0]) | (static_cast<uint32_t>(p[1]) << 8) |
         (static_cast<uint32_t>(p[2]) << 16) | (static_cast<uint32_t>(p[3]) << 24);
}
constexpr uint32_t loadBe32(const uint8_t* p) {
  return (static_cast<uint32_t>(p[0]) << 24) | (static_cast<uint32_t>(p[1]) << 16) |
         (static_cast<uint32_t>(p[2]) << 8) | static_cast<uint32_t>(p[3]);
}
constexpr int16_t loadLeI16(const uint8_t* p) {
  return static_cast<int16_t>(loadLe16(p));
}
constexpr int16_t loadBeI16(const uint8_t* p) {
  return static_cast<int16_t>(loadBe16(p));
}
constexpr int32_t loadLeI32(const uint8_t* p) {
  return static_cast<int32_t>(loadLe32(p));
}

constexpr void storeLe16(uint8_t* p, uint16_t v) {
  p[0] = static_cast<uint8_t>(v);
  p[1] = static_cast<uint8_t>(v >> 8);
}
constexpr void storeBe16(uint8_t* p, uint16_t v) {
  p[0] = static_cast<uint8_t>(v >> 8);
  p[1] = static_cast<uint8_t>(v);
}
constexpr void storeLe32(uint8_t* p, uint32_t v) {
  for (int i = 0; i < 4; ++i)
    p[i] = static_cast<uint8_t>(v >> (8 * i));
}
constexpr void storeBe32(uint8_t* p, uint32_t v) {
  for (int i = 0; i < 4; ++i)
    p[i] = static_cast<uint8_t>(v >> (24 - 8 * i));
}

}  // namespace fw::bytes
