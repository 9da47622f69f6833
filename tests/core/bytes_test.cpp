#include <gtest/gtest.h>

#include "core/bytes.hpp"

namespace {

using namespace fw::bytes;

TEST(Bytes, LittleEndianLoadMatchesSeedExample) {
  // SLUAA11B table 1-2: Cell 1 Voltage reads as bytes 74 0E -> 0x0E74 = 3700 mV.
  const uint8_t wire[] = {0x74, 0x0E};
  EXPECT_EQ(loadLe16(wire), 0x0E74);
  EXPECT_EQ(loadLeI16(wire), 3700);
}

TEST(Bytes, BigEndianLoadMatchesBq79616Cell) {
  // Seed 001: CAN payload "16 C0" is VCELL16 = 0x16C0 (big-endian on the BQ79616 wire).
  const uint8_t wire[] = {0x16, 0xC0};
  EXPECT_EQ(loadBe16(wire), 0x16C0);
}

TEST(Bytes, SignedLoadsDoNotOverflow) {
  const uint8_t minusOne[] = {0xFF, 0xFF};
  EXPECT_EQ(loadLeI16(minusOne), -1);
  EXPECT_EQ(loadBeI16(minusOne), -1);
  const uint8_t topBit[] = {0x00, 0x00, 0x00, 0x80};
  EXPECT_EQ(loadLeI32(topBit), INT32_MIN);
  EXPECT_EQ(loadLe32(topBit), 0x80000000u);  // no UB from shifting into the sign bit
}

TEST(Bytes, StoreThenLoadRoundTrips) {
  uint8_t b[4] = {};
  storeLe16(b, 0xF082);
  EXPECT_EQ(b[0], 0x82);
  EXPECT_EQ(b[1], 0xF0);  // seed 002: alarm enable 0xF082 goes out as [82 F0]
  storeBe16(b, 0x0309);
  EXPECT_EQ(b[0], 0x03);
  EXPECT_EQ(b[1], 0x09);
  storeLe32(b, 0x12345678);
  EXPECT_EQ(loadLe32(b), 0x12345678u);
  EXPECT_EQ(b[0], 0x78);
  storeBe32(b, 0x12345678);
  EXPECT_EQ(loadBe32(b), 0x12345678u);
  EXPECT_EQ(b[0], 0x12);
}

}  // namespace
