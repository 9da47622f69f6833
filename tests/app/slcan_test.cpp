// SLCAN encoding against the Lawicel CAN232/CANUSB protocol's frame syntax ("tiiildd..\r",
// "Tiiiiiiiildd..\r").
#include <gtest/gtest.h>

#include <string>

#include "app/publish/slcan.hpp"

namespace {

std::string encode(const fw::hal::CanFrame& f) {
  uint8_t buf[fw::app::slcan::kMaxEncodedLength];
  const size_t n = fw::app::slcan::encode(f, buf);
  return std::string(reinterpret_cast<const char*>(buf), n);
}

TEST(Slcan, StandardFrameMatchesSeed001Payload) {
  // Seed 001's first CAN frame: ID 0x004, 8 bytes "16 C0 16 BC 16 B4 16 B9".
  fw::hal::CanFrame f{0x004, false, 8, {0x16, 0xC0, 0x16, 0xBC, 0x16, 0xB4, 0x16, 0xB9}};
  EXPECT_EQ(encode(f), "t004816C016BC16B416B9\r");
}

TEST(Slcan, LawicelExamples) {
  // The CAN232 syntax: 't' + 3 id digits or 'T' + 8 id digits, one DLC digit, two digits per data byte, CR.
  EXPECT_EQ(encode({0x100, false, 2, {0x11, 0x33}}), "t10021133\r");
  EXPECT_EQ(encode({0x10, true, 2, {0x11, 0x33}}), "T0000001021133\r");
  EXPECT_EQ(encode({0x7FF, false, 0, {}}), "t7FF0\r");
  EXPECT_EQ(encode({0x1FFFFFFF, true, 1, {0xAB}}), "T1FFFFFFF1AB\r");
}

TEST(Slcan, StandardEightByteLineMatchesTheGeneralEncoder) {
  // encodeStandard() writes the line of every frame the publish plan builds: classic, 8 bytes, standard id.
  const fw::hal::CanFrame frames[] = {
      {0x004, false, 8, {0x16, 0xC0, 0x16, 0xBC, 0x16, 0xB4, 0x16, 0xB9}},
      {0x100, false, 8, {0x00, 0x01, 0x23, 0x45, 0x67, 0x89, 0xAB, 0xCD}},
      {0x7FF, false, 8, {0xFF, 0xFE, 0x10, 0x0F, 0xA0, 0x0A, 0x5A, 0xA5}},
  };
  for (const auto& f : frames) {
    uint8_t line[fw::app::slcan::kStandardLength];
    fw::app::slcan::encodeStandard(static_cast<uint16_t>(f.id), f.data, line);
    EXPECT_EQ(std::string(reinterpret_cast<const char*>(line), sizeof line), encode(f));
  }
}

TEST(Slcan, InvalidFramesEncodeToNothing) {
  EXPECT_EQ(encode({0x800, false, 1, {}}), "");
  EXPECT_EQ(encode({0x20000000, true, 1, {}}), "");
  EXPECT_EQ(encode({0x1, false, 9, {}}), "");
  uint8_t small[5];
  EXPECT_EQ(fw::app::slcan::encode({0x100, false, 2, {0x11, 0x33}}, small), 0u);
}

}  // namespace
