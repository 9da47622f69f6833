// CRCs used on the battery-monitor links.
//
// crc8   CRC-8, polynomial 0x07 (x^8+x^2+x+1), init 0x00, MSB first, no reflection, no final XOR
//        (catalogue name CRC-8/SMBUS, check("123456789") = 0xF4). Used by the BQ769x2/BQ7690x optional
//        per-byte I2C CRC (SLUAA11B / SLUAAM4 section 4) and by the SMBus PEC (BQ4050).
// crc16  CRC-16/MODBUS: polynomial 0x8005 reflected (0xA001), init 0xFFFF, no final XOR
//        (check("123456789") = 0x4B37). Used by BQ79616 UART frames, sent low byte first; running it over a
//        whole valid frame including its CRC gives 0.
//
// Both are constexpr, take a running value so a message can be fed in pieces, and are ISR-safe.
// crc16 uses a 256-entry byte table (512 bytes of flash, only in the BQ79616 image, which has the room): one
// lookup a byte. On a 64-device chain the CRC checks every byte the MCU receives; the 16-entry nibble table
// it replaces took two lookups a byte and was 16.7 % of that image's busy cycles (twin profile, 64 devices).
#pragma once

#include <cstddef>
#include <cstdint>
#include <type_traits>

namespace fw::crc {

constexpr uint8_t crc8Update(uint8_t crc, uint8_t byte) {
  crc = static_cast<uint8_t>(crc ^ byte);
  for (int bit = 0; bit < 8; ++bit) {
    crc = static_cast<uint8_t>((crc & 0x80U) ? (crc << 1) ^ 0x07U : (crc << 1));
  }
  return crc;
}

constexpr uint8_t crc8(const uint8_t* data, size_t length, uint8_t crc = 0x00) {
  for (size_t i = 0; i < length; ++i)
    crc = crc8Update(crc, data[i]);
  return crc;
}

inline constexpr uint16_t kCrc16Init = 0xFFFF;

namespace detail {
// Reflected 0xA001 remainder of each byte value: entry n = n shifted through 8 rounds.
constexpr uint16_t crc16Byte(uint16_t n) {
  for (int bit = 0; bit < 8; ++bit)
    n = static_cast<uint16_t>((n & 1U) ? (n >> 1) ^ 0xA001U : (n >> 1));
  return n;
}
struct Crc16Table {
  uint16_t entry[256];
};
constexpr Crc16Table makeCrc16Table() {
  Crc16Table t{};
  for (uint16_t n = 0; n < 256; ++n)
    t.entry[n] = crc16Byte(n);
  return t;
}
inline constexpr Crc16Table kCrc16Table = makeCrc16Table();
}  // namespace detail

namespace detail {
// One byte into the CRC: the low byte of crc ^ byte indexes the table. On a 32-bit value with the table's
// address in a register (with a 16-bit value GCC masked with a constant it loaded again every byte). The
// value stays within 16 bits: a 16-bit value shifted right by 8, xor a 16-bit entry.
[[gnu::always_inline]] constexpr uint32_t crc16Step(uint32_t crc, const uint16_t* table, uint8_t byte) {
  return (crc >> 8) ^ table[static_cast<uint8_t>(crc ^ byte)];
}
}  // namespace detail

// Two bytes a pass with the loop test at the bottom: a byte a pass took 16 cycles on the Cortex-M0+ (the
// test, the branch back and the table's address every byte; 14 % of the busy cycles of the 64-device BQ79616
// image, where this checks every byte received, twin profile), two take 24.
constexpr uint16_t crc16(const uint8_t* data, size_t length, uint16_t crc = kCrc16Init) {
  const uint16_t* table = detail::kCrc16Table.entry;
  // At run time the table's address comes out of an empty asm, so GCC keeps it in a register instead of
  // loading it again from the literal pool every two bytes (-Os rematerialises constants inside loops).
  if (!std::is_constant_evaluated()) asm("" : "+r"(table));
  uint32_t c = crc;
  if ((length & 1U) != 0) c = detail::crc16Step(c, table, *data++);
  if (length >= 2) {
    const uint8_t* const end = data + (length & ~size_t{1});
    do {
      c = detail::crc16Step(c, table, data[0]);
      c = detail::crc16Step(c, table, data[1]);
      data += 2;
    } while (data != end);
  }
  return static_cast<uint16_t>(c);
}

// The same CRC-16 without the table, eight shifts a byte: for code that runs it rarely (the record store,
// app/store: a few hundred bytes a flash write), so an image without the BQ79616 carries no 512 B table.
constexpr uint16_t crc16Compact(const uint8_t* data, size_t length, uint16_t crc = kCrc16Init) {
  for (size_t i = 0; i < length; ++i)
    crc = static_cast<uint16_t>((crc >> 8) ^ detail::crc16Byte((crc ^ data[i]) & 0xFFU));
  return crc;
}

}  // namespace fw::crc
