// Core library on ARMv6-M: the CRC vectors from TI's documents, byte helpers on odd addresses (an unaligned
// word load would HardFault on this core), and the SPSC queue.
#include <cstdint>

#include "core/bytes.hpp"
#include "core/crc.hpp"
#include "core/spsc_queue.hpp"
#include "qtest.hpp"

namespace {

volatile uint8_t gSink;  // keeps inputs opaque to the optimiser so the code really runs on the target

uint8_t crc8Of(const uint8_t* data, uint32_t n) {
  gSink = data[0];
  return fw::crc::crc8(data, n);
}

}  // namespace

int main() {
  static const uint8_t fetEnable[] = {0x10, 0x3E, 0x22};
  static const uint8_t cell1[] = {0x10, 0x14, 0x11, 0x68};
  static const uint8_t second[] = {0x0B};
  QCHECK(crc8Of(fetEnable, 3) == 0x63);
  QCHECK(crc8Of(cell1, 4) == 0x33);
  QCHECK(crc8Of(second, 1) == 0x31);
  static const uint8_t check[] = {'1', '2', '3', '4', '5', '6', '7', '8', '9'};
  QCHECK(crc8Of(check, 9) == 0xF4);
  QCHECK(fw::crc::crc16(check, 9) == 0x4B37);
  static const uint8_t sendWake[] = {0x90, 0x00, 0x03, 0x09, 0x20, 0x13, 0x95};
  QCHECK(fw::crc::crc16(sendWake, 5) == 0x9513);
  QCHECK(fw::crc::crc16(sendWake, 7) == 0);

  alignas(4) static uint8_t buf[8] = {0, 0x74, 0x0E, 0x78, 0x56, 0x34, 0x12, 0};
  QCHECK(fw::bytes::loadLe16(buf + 1) == 0x0E74);  // odd address
  QCHECK(fw::bytes::loadLe32(buf + 3) == 0x12345678);
  fw::bytes::storeBe16(buf + 1, 0xBEEF);
  QCHECK(buf[1] == 0xBE && buf[2] == 0xEF);

  static fw::SpscQueue<uint16_t, 8> q;
  for (uint16_t i = 0; i < 8; ++i)
    QCHECK(q.push(i));
  QCHECK(!q.push(99));
  for (uint16_t i = 0; i < 8; ++i) {
    uint16_t v = 0xFFFF;
    QCHECK(q.pop(v) && v == i);
  }
  return qtest::finish("qemu_core_test");
}
