// CRC vectors from TI's documents, not from this implementation:
// - SLUAA11B (seed 002, section 4) and SLUAAM4 (seed 004, section 4): BQ769x2/BQ7690x I2C CRC bytes.
// - BQ79616 frames as TI prints them (SLUUC56B / SLUAA17A).
// - Catalogue check values of CRC-8/SMBUS and CRC-16/MODBUS over "123456789".
#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <string_view>
#include <vector>

#include "core/crc.hpp"

namespace {

uint8_t crc8Of(std::initializer_list<uint8_t> bytes) {
  std::vector<uint8_t> v(bytes);
  return fw::crc::crc8(v.data(), v.size());
}

TEST(Crc8, CatalogueCheckValue) {
  constexpr std::string_view text = "123456789";
  EXPECT_EQ(fw::crc::crc8(reinterpret_cast<const uint8_t*>(text.data()), text.size()), 0xF4);
}

TEST(Crc8, Sluaa11bFetEnableFirstByte) {
  // Figure 4-1: FET_ENABLE written as [0x10 0x3E 0x22] carries CRC 0x63; the second data byte 0x00 alone
  // carries CRC 0x00.
  EXPECT_EQ(crc8Of({0x10, 0x3E, 0x22}), 0x63);
  EXPECT_EQ(crc8Of({0x00}), 0x00);
}

TEST(Crc8, Sluaa11bCell1VoltageRead) {
  // Figure 4-2: [0x10 0x14 0x11 0x68] -> 0x33, then [0x0B] -> 0x31.
  EXPECT_EQ(crc8Of({0x10, 0x14, 0x11, 0x68}), 0x33);
  EXPECT_EQ(crc8Of({0x0B}), 0x31);
}

TEST(Crc8, Sluaam4Bq7690xCell1VoltageRead) {
  // SLUAAM4 Figure 4-2: [0x10 0x14 0x11 0xC5] -> 0x79.
  EXPECT_EQ(crc8Of({0x10, 0x14, 0x11, 0xC5}), 0x79);
}

TEST(Crc8, IncrementalEqualsWhole) {
  const uint8_t bytes[] = {0x10, 0x14, 0x11, 0x68};
  uint8_t crc = 0;
  for (uint8_t b : bytes)
    crc = fw::crc::crc8Update(crc, b);
  EXPECT_EQ(crc, fw::crc::crc8(bytes, sizeof bytes));
}

TEST(Crc8, IsConstexpr) {
  constexpr uint8_t bytes[] = {0x10, 0x3E, 0x22};
  static_assert(fw::crc::crc8(bytes, 3) == 0x63);
}

TEST(Crc16, CatalogueCheckValue) {
  constexpr std::string_view text = "123456789";
  EXPECT_EQ(fw::crc::crc16(reinterpret_cast<const uint8_t*>(text.data()), text.size()), 0x4B37);
}

TEST(Crc16, CompactIsTheSameCrcAsTheTable) {
  constexpr uint8_t check[] = {'1', '2', '3', '4', '5', '6', '7', '8', '9'};
  static_assert(fw::crc::crc16Compact(check, sizeof check) == 0x4B37);
  uint8_t bytes[300];
  for (size_t i = 0; i < sizeof bytes; ++i)
    bytes[i] = static_cast<uint8_t>(i * 37 + 11);
  for (size_t n = 0; n <= sizeof bytes; n += 13) {
    EXPECT_EQ(fw::crc::crc16Compact(bytes, n), fw::crc::crc16(bytes, n)) << n;
    EXPECT_EQ(fw::crc::crc16Compact(bytes, n, 0x1234), fw::crc::crc16(bytes, n, 0x1234)) << n;
  }
}

struct Frame {
  std::vector<uint8_t> bytes;  // whole frame as TI prints it, CRC low byte first at the end
};

class Crc16Frames : public ::testing::TestWithParam<Frame> {};

TEST_P(Crc16Frames, TrailingCrcMatchesAndResidueIsZero) {
  const auto& f = GetParam().bytes;
  ASSERT_GE(f.size(), 3u);
  const uint16_t crc = fw::crc::crc16(f.data(), f.size() - 2);
  EXPECT_EQ(crc & 0xFF, f[f.size() - 2]);
  EXPECT_EQ(crc >> 8, f[f.size() - 1]);
  EXPECT_EQ(fw::crc::crc16(f.data(), f.size()), 0);
}

// TI's BQ79600-Q1 documents SLUUC56B / SLUAA17A.
INSTANTIATE_TEST_SUITE_P(
    Bq79616Section3, Crc16Frames,
    ::testing::Values(
        Frame{{0x90, 0x00, 0x03, 0x09, 0x20, 0x13, 0x95}}, Frame{{0xD0, 0x03, 0x43, 0x00, 0xF9, 0xD4}},
        Frame{{0xD0, 0x03, 0x09, 0x01, 0x0F, 0x74}}, Frame{{0xD0, 0x03, 0x06, 0x00, 0xCB, 0x44}},
        Frame{{0xD0, 0x03, 0x06, 0x01, 0x0A, 0x84}}, Frame{{0xD0, 0x03, 0x08, 0x02, 0x4E, 0xE5}},
        Frame{{0x90, 0x00, 0x03, 0x08, 0x00, 0x13, 0xDD}}, Frame{{0x90, 0x01, 0x03, 0x08, 0x03, 0x52, 0x20}},
        Frame{{0xC0, 0x03, 0x43, 0x00, 0xFD, 0x14}}, Frame{{0xD0, 0x03, 0x32, 0x03, 0x9D, 0x85}},
        Frame{{0xD0, 0x00, 0x17, 0x40, 0x36, 0xE4}}, Frame{{0xC0, 0x05, 0x0C, 0x01, 0xE8, 0xE5}},
        Frame{{0xD1, 0x03, 0x31, 0xFF, 0xFF, 0x88, 0x29}}, Frame{{0xD0, 0x00, 0x03, 0x0A, 0xB8, 0x13}},
        Frame{{0xD0, 0x00, 0x07, 0x02, 0xBB, 0x15}}, Frame{{0xD0, 0x03, 0x0D, 0x0E, 0x4D, 0xB0}},
        Frame{{0xC0, 0x05, 0x68, 0x1F, 0x42, 0x2D}}, Frame{{0x80, 0x01, 0x03, 0x06, 0x00, 0xD7, 0x82}},
        Frame{{0xB0, 0x03, 0x09, 0x20, 0xD1, 0x6C}}));

TEST(Crc16, FirstFrameExplicitly) {
  // The vector: frame 90 00 03 09 20 carries CRC-16 13 95 (low byte first).
  const uint8_t frame[] = {0x90, 0x00, 0x03, 0x09, 0x20};
  EXPECT_EQ(fw::crc::crc16(frame, sizeof frame), 0x9513);
}

TEST(Crc16, CorruptedByteIsDetected) {
  uint8_t frame[] = {0x90, 0x00, 0x03, 0x09, 0x20, 0x13, 0x95};
  for (size_t i = 0; i < sizeof frame; ++i) {
    for (int bit = 0; bit < 8; ++bit) {
      frame[i] ^= static_cast<uint8_t>(1U << bit);
      EXPECT_NE(fw::crc::crc16(frame, sizeof frame), 0) << "byte " << i << " bit " << bit;
      frame[i] ^= static_cast<uint8_t>(1U << bit);
    }
  }
}

}  // namespace
