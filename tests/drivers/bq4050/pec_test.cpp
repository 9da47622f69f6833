// SMBus PEC vectors computed independently of the implementation: the CRC-8 catalogue check value, a word
// read worked by hand, and the PECs of the driver's own transactions checked with the test's bitwise CRC.
#include <gtest/gtest.h>

#include "core/crc.hpp"
#include "rig.hpp"

namespace bq4050_test {
namespace {

TEST(Bq4050Pec, CheckValueOf123456789IsF4) {
  // CRC-8/SMBUS in the CRC catalogue: poly 0x07, init 0, no reflection, no final XOR, check 0xF4.
  const std::vector<uint8_t> digits{'1', '2', '3', '4', '5', '6', '7', '8', '9'};
  EXPECT_EQ(referenceCrc8(digits), 0xF4);
  EXPECT_EQ(Emu::pec(digits.data(), digits.size()), 0xF4) << "the emulator's table CRC";
  EXPECT_EQ(fw::crc::crc8(digits.data(), digits.size()), 0xF4) << "the bus's CRC (fw::crc)";
}

TEST(Bq4050Pec, HandWorkedWordReadOfVoltage) {
  // Read Word 0x09 answered with 0x3A98 (15000 mV): the PEC covers 16 09 17 98 3A. Worked bit by bit:
  // 0x16 -> shifts 2C 58 B0, then 60^07=67, CE, 9C^07=9B, 36^07=31, 62: remainder 0x62; continuing
  // byte by byte the remainders are 62, 16, 07, D4, 84.
  EXPECT_EQ(referenceCrc8({0x16}), 0x62);
  EXPECT_EQ(referenceCrc8({0x16, 0x09}), 0x16);
  EXPECT_EQ(referenceCrc8({0x16, 0x09, 0x17}), 0x07);
  EXPECT_EQ(referenceCrc8({0x16, 0x09, 0x17, 0x98}), 0xD4);
  EXPECT_EQ(referenceCrc8({0x16, 0x09, 0x17, 0x98, 0x3A}), 0x84);

  Rig rig(config(bq::PecMode::On));
  rig.emu.setVoltage(15000);
  uint16_t mv = 0;
  ASSERT_EQ(rig.readWord(0x09, mv), Status::Ok);
  EXPECT_EQ(mv, 15000);
  ASSERT_EQ(rig.wire().size(), 1u);
  EXPECT_EQ(rig.wire()[0], "S 16 09 Sr 17 [98 3A 84] P");
}

TEST(Bq4050Pec, WordWriteCarriesPecOverAddressAndData) {
  Rig rig(config(bq::PecMode::On));
  ASSERT_EQ(rig.finish(rig.gauge.startSendMac(0x0022)), Status::Ok);
  const uint8_t pec = referenceCrc8({0x16, 0x00, 0x22, 0x00});
  EXPECT_EQ(pec, 0x97);
  EXPECT_EQ(rig.wire()[0], "S 16 00 22 00 " + hex({pec}) + " P");
  EXPECT_EQ(rig.emu.macLog(), (std::vector<uint16_t>{0x0022}));
}

TEST(Bq4050Pec, GaugeRefusesAWriteWithAWrongPec) {
  // The emulator checks a written PEC like the gauge: a wrong one is NACKed and the command discarded.
  Rig rig;
  const uint8_t bytes[] = {0x00, 0x22, 0x00, 0x00};  // PEC 0x00 instead of 0x97
  fw::hal::I2cTransaction t{Emu::kAddress, bytes, {}};
  std::vector<fw::hal::I2cTransaction> list{t};
  bool done = false;
  ASSERT_EQ(
      rig.bus.start(list, fw::hal::Notify{[](void* c, uint32_t) { *static_cast<bool*>(c) = true; }, &done}),
      Status::Ok);
  rig.harness.runUntil([&] { return done; }, fw::s(1));
  EXPECT_EQ(list[0].status, Status::DataNack);
  EXPECT_EQ(rig.bus.wireLog().back().text, "S 16 00 22 00 00 NACK P");
  EXPECT_EQ(rig.emu.counters().badPec, 1u);
  EXPECT_TRUE(rig.emu.macLog().empty());
}

}  // namespace
}  // namespace bq4050_test
