// The end-to-end protection of command frames (firmware/app/command/e2e.hpp): CRC-8 SAE J1850 with its
// catalogue check value, the bytes it covers, and the alive-counter window.
#include <gtest/gtest.h>

#include <cstring>

#include "app/command/e2e.hpp"
#include "can/bms.hpp"

namespace {

using namespace fw::app::command;

TEST(CommandE2e, Crc8J1850HasItsCatalogueCheckValue) {
  // CRC-8/SAE-J1850: poly 0x1D, init 0xFF, xorout 0xFF, check("123456789") = 0x4B (the parameters of
  // AUTOSAR's Crc_CalculateCRC8).
  const char* text = "123456789";
  uint8_t crc = 0xFF;
  for (size_t i = 0; i < std::strlen(text); ++i)
    crc = crc8J1850Update(crc, static_cast<uint8_t>(text[i]));
  EXPECT_EQ(crc ^ 0xFF, 0x4B);
}

TEST(CommandE2e, TheCrcCoversTheIdentifierLowByteFirstThenPayloadBytesOneOn) {
  // ClearFaults (0x600), counter 3, target 1: CRC over 00 06 03 01 = 0x95 (worked out by hand with the
  // parameters above, independently of this code).
  fw::hal::CanFrame f{0x600, false, 3, {0x00, 0x03, 0x01}};
  EXPECT_EQ(frameCrc(f.id, f.data.data(), f.dlc), 0x95);
  f.data[0] = 0x95;
  EXPECT_TRUE(crcValid(f));
  // SettingWrite (0x605), counter 5, target 1, setting 6, value -20000 (E0 B1 FF FF): 0x55.
  const fw::hal::CanFrame w{0x605, false, 8, {0x55, 0x05, 0x01, 0x06, 0xE0, 0xB1, 0xFF, 0xFF}};
  EXPECT_TRUE(crcValid(w));
  // Any changed bit of the identifier or the payload, or the same bytes under another identifier, fails.
  for (int byte = 1; byte < 8; ++byte) {
    for (int bit = 0; bit < 8; ++bit) {
      fw::hal::CanFrame bad = w;
      bad.data[byte] ^= static_cast<uint8_t>(1U << bit);
      EXPECT_FALSE(crcValid(bad)) << byte << "." << bit;
    }
  }
  fw::hal::CanFrame moved = w;
  moved.id = 0x604;
  EXPECT_FALSE(crcValid(moved));
  fw::hal::CanFrame empty{0x600, false, 0, {}};
  EXPECT_FALSE(crcValid(empty));
}

TEST(CommandE2e, TheCounterWindowRefusesARepeatAndTakesAnyOtherValue) {
  CounterWindow<2> w{};
  EXPECT_TRUE(w.take(0, 0));  // the first frame of a message is always taken, whatever its counter
  EXPECT_FALSE(w.take(0, 0));
  EXPECT_TRUE(w.take(0, 1));
  EXPECT_TRUE(w.take(0, 5));  // frames lost in between: still taken
  EXPECT_FALSE(w.take(0, 5));
  EXPECT_TRUE(w.take(1, 5));  // each message has its own counter
  EXPECT_TRUE(w.take(0, 15));
  EXPECT_TRUE(w.take(0, 0));  // wraps
}

}  // namespace
