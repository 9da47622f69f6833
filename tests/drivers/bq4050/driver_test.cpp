// The driver's accesses on the wire: exact SMBus traces (word, block, MAC through 0x44 and 0x00/0x23), the
// buffer bounds, the confirming re-read without PEC, pacing, the probe and the operation contract.
#include <gtest/gtest.h>

#include <array>

#include "rig.hpp"

namespace bq4050_test {
namespace {

TEST(Bq4050Driver, WordReadWithoutPecIsConfirmedBySecondRead) {
  Rig rig(config(bq::PecMode::Off));
  rig.emu.setVoltage(15000);
  uint16_t mv = 0;
  ASSERT_EQ(rig.readWord(0x09, mv), Status::Ok);
  EXPECT_EQ(mv, 15000);
  EXPECT_EQ(rig.wire(), (std::vector<std::string>{"S 16 09 Sr 17 [98 3A] P", "S 16 09 Sr 17 [98 3A] P"}));
}

TEST(Bq4050Driver, SignedCurrentIsReadAsTwosComplement) {
  Rig rig;
  rig.emu.setCurrent(-1500);  // discharging
  uint16_t raw = 0;
  ASSERT_EQ(rig.readWord(0x0A, raw), Status::Ok);
  EXPECT_EQ(static_cast<int16_t>(raw), -1500);
  EXPECT_EQ(rig.wire()[0],
            "S 16 0A Sr 17 [24 FA " + hex({referenceCrc8({0x16, 0x0A, 0x17, 0x24, 0xFA})}) + "] P");
}

TEST(Bq4050Driver, MacBlockReadWireTraceIsExact) {
  Rig rig(config(bq::PecMode::On));
  rig.emu.setSafetyStatus(0x00000402);  // ASCD | COV
  std::array<uint8_t, 32> out{};
  uint8_t length = 0;
  ASSERT_EQ(rig.finish(rig.gauge.startReadMac(0x0051, out, length)), Status::Ok);
  ASSERT_EQ(length, 4);
  EXPECT_EQ(out[0], 0x02);
  EXPECT_EQ(out[1], 0x04);
  const uint8_t wpec = referenceCrc8({0x16, 0x44, 0x02, 0x51, 0x00});
  const uint8_t rpec = referenceCrc8({0x16, 0x44, 0x17, 0x06, 0x51, 0x00, 0x02, 0x04, 0x00, 0x00});
  EXPECT_EQ(rig.wire(),
            (std::vector<std::string>{"S 16 44 02 51 00 " + hex({wpec}) + " P",
                                      "S 16 44 Sr 17 [06 51 00 02 04 00 00 " + hex({rpec}) + "] P"}));
}

TEST(Bq4050Driver, MacBlockReadWithoutPecRereadsTheResultWithoutResending) {
  Rig rig(config(bq::PecMode::Off));
  std::array<uint8_t, 8> out{};
  uint8_t length = 0;
  ASSERT_EQ(rig.finish(rig.gauge.startReadMac(0x0001, out, length)), Status::Ok);
  EXPECT_EQ(length, 2);
  EXPECT_EQ(out[0] | (out[1] << 8), 0x4050);
  EXPECT_EQ(rig.wire(), (std::vector<std::string>{"S 16 44 02 01 00 P", "S 16 44 Sr 17 [04 01 00 50 40] P",
                                                  "S 16 44 Sr 17 [04 01 00 50 40] P"}));
  EXPECT_EQ(rig.emu.macLog(), (std::vector<uint16_t>{0x0001})) << "one command, two reads of its result";
}

TEST(Bq4050Driver, The34ByteMacResult) {
  // DAStatus1: 32 data bytes + the 2-byte echo = a count of 34, 35 bytes + PEC on the wire (PX4 PR #16872).
  Rig rig(config(bq::PecMode::On));
  rig.emu.setCells({3701, 3702, 3703, 3704});
  std::array<uint8_t, 32> out{};
  uint8_t length = 0;
  ASSERT_EQ(rig.finish(rig.gauge.startReadMac(0x0071, out, length)), Status::Ok);
  EXPECT_EQ(length, 32);
  EXPECT_EQ(out[0] | (out[1] << 8), 3701);
  EXPECT_EQ(out[6] | (out[7] << 8), 3704);
  const std::string read = rig.wire().at(1);
  EXPECT_EQ(read.rfind("S 16 44 Sr 17 [22 71 00 75 0E ", 0), 0u) << read;
  EXPECT_EQ(read.size(), std::string("S 16 44 Sr 17 [] P").size() + 36 * 3 - 1) << "count + 34 + PEC";
}

TEST(Bq4050Driver, MacThroughManufacturerAccessAndManufacturerDataHasNoEcho) {
  Rig rig(config(bq::PecMode::On));
  std::array<uint8_t, 8> out{};
  uint8_t length = 0;
  ASSERT_EQ(rig.finish(rig.gauge.startReadMacData(0x0001, out, length)), Status::Ok);
  EXPECT_EQ(length, 2);
  EXPECT_EQ(out[0] | (out[1] << 8), 0x4050);
  EXPECT_EQ(rig.wire(), (std::vector<std::string>{
                            "S 16 00 01 00 " + hex({referenceCrc8({0x16, 0x00, 0x01, 0x00})}) + " P",
                            "S 16 23 Sr 17 [02 50 40 " +
                                hex({referenceCrc8({0x16, 0x23, 0x17, 0x02, 0x50, 0x40})}) + "] P"}));
}

TEST(Bq4050Driver, BlockReadOfAString) {
  Rig rig;
  std::array<uint8_t, 32> out{};
  uint8_t length = 0;
  ASSERT_EQ(rig.finish(rig.gauge.startReadBlock(0x20, out, length)), Status::Ok);
  EXPECT_EQ(std::string(out.begin(), out.begin() + length), "Texas Inst.");
}

TEST(Bq4050Driver, BlockReadNeverTrustsTheCountBeyondTheBuffer) {
  // The caller offers 4 bytes; the gauge announces 11. The bus reads the count into a buffer sized from the
  // caller's, refuses it (NACK, Length) and the driver writes nothing, not even past the end.
  Rig rig;
  std::array<uint8_t, 8> memory{};
  memory.fill(0xA5);
  uint8_t length = 0x77;
  ASSERT_EQ(rig.finish(rig.gauge.startReadBlock(0x20, std::span<uint8_t>(memory.data(), 4), length)),
            Status::Length);
  for (uint8_t b : memory)
    EXPECT_EQ(b, 0xA5);
  EXPECT_EQ(length, 0x77);
  EXPECT_EQ(rig.wire()[0], "S 16 20 Sr 17 [0B] NACK P");
  EXPECT_EQ(rig.gauge.stats().count(Status::Length), 1u + rig.gauge.config().retries);
}

TEST(Bq4050Driver, WritesWordAndBlock) {
  Rig rig;
  ASSERT_EQ(rig.finish(rig.gauge.startWriteWord(0x03, 0x6001)), Status::Ok);  // BatteryMode
  EXPECT_EQ(rig.emu.word(0x03), 0x6001);
  EXPECT_EQ(rig.wire()[0], "S 16 03 01 60 " + hex({referenceCrc8({0x16, 0x03, 0x01, 0x60})}) + " P");
  const uint8_t info[] = {'p', 'a', 'c', 'k'};
  ASSERT_EQ(rig.finish(rig.gauge.startWriteBlock(0x70, info)), Status::Ok);  // ManufacturerInfo
  EXPECT_EQ(rig.wire()[1],
            "S 16 70 04 70 61 63 6B " + hex({referenceCrc8({0x16, 0x70, 0x04, 'p', 'a', 'c', 'k'})}) + " P");
  std::array<uint8_t, 32> out{};
  uint8_t length = 0;
  ASSERT_EQ(rig.finish(rig.gauge.startReadBlock(0x70, out, length)), Status::Ok);
  EXPECT_EQ(std::string(out.begin(), out.begin() + length), "pack");
}

TEST(Bq4050Driver, PaceSeparatesEveryTwoTransactions) {
  bq::GaugeConfig cfg = config(bq::PecMode::Off);
  cfg.pace = fw::ms(2);
  Rig rig(cfg);
  bq::Measurement m;
  ASSERT_EQ(rig.scan(m), Status::Ok);
  const auto& log = rig.bus.wireLog();
  ASSERT_GT(log.size(), 20u);
  for (size_t i = 1; i < log.size(); ++i)
    EXPECT_GE(log[i].startUs - log[i - 1].endUs, 2000u) << "between transactions " << i - 1 << " and " << i;
}

TEST(Bq4050Driver, ProbeDetectsPecFromSpecificationInfo) {
  Rig rig(config(bq::PecMode::Auto));
  rig.emu.setSpecificationInfo(0x0031);  // Version 3: SBS 1.1 with PEC
  bq::DeviceInfo info;
  ASSERT_EQ(rig.finish(rig.gauge.startProbe(info)), Status::Ok);
  EXPECT_TRUE(info.pec);
  EXPECT_TRUE(rig.gauge.pecEnabled());
  EXPECT_EQ(info.deviceType, 0x4050);
  EXPECT_EQ(info.specificationInfo.version(), 3);
  EXPECT_EQ(info.firmwareLength, 11);
  EXPECT_EQ(info.deviceNumber(), 0x4050);
  EXPECT_EQ(info.firmwareVersion(), 0x0103);
  // SpecificationInfo read twice without PEC, then DeviceType with PEC.
  EXPECT_EQ(rig.wire()[0], "S 16 1A Sr 17 [31 00] P");
  EXPECT_EQ(rig.wire()[1], "S 16 1A Sr 17 [31 00] P");
  EXPECT_EQ(rig.wire()[2], "S 16 44 02 01 00 " + hex({referenceCrc8({0x16, 0x44, 0x02, 0x01, 0x00})}) + " P");
}

TEST(Bq4050Driver, ProbeLeavesPecOffForAGaugeWithoutIt) {
  Rig rig(config(bq::PecMode::Auto));
  rig.emu.setSpecificationInfo(0x0021);  // Version 2: SBS 1.1 without PEC
  bq::DeviceInfo info;
  ASSERT_EQ(rig.finish(rig.gauge.startProbe(info)), Status::Ok);
  EXPECT_FALSE(info.pec);
  EXPECT_FALSE(rig.gauge.pecEnabled());
}

TEST(Bq4050Driver, ProbeRejectsAnotherDevice) {
  Rig rig(config(bq::PecMode::On));
  rig.emu.setDeviceType(0x4500);
  bq::DeviceInfo info;
  info.deviceType = 0x1234;
  EXPECT_EQ(rig.finish(rig.gauge.startProbe(info)), Status::DeviceId);
  EXPECT_EQ(info.deviceType, 0x1234) << "nothing written unless Ok";
  EXPECT_EQ(rig.gauge.stats().count(Status::DeviceId), 1u);
}

TEST(Bq4050Driver, OneOperationAtATimeAndNothingCompletesInsideStart) {
  Rig rig;
  uint16_t v = 0;
  ASSERT_EQ(rig.gauge.startReadWord(0x09, v), Status::Ok);
  EXPECT_TRUE(rig.gauge.busy());
  EXPECT_EQ(rig.task.done, 0);
  EXPECT_EQ(rig.gauge.startReadWord(0x08, v), Status::Busy);
  std::array<uint8_t, 4> out{};
  uint8_t length = 0;
  EXPECT_EQ(rig.gauge.startReadBlock(0x20, out, length), Status::Busy);
  EXPECT_EQ(rig.finish(Status::Ok), Status::Ok);
  EXPECT_EQ(rig.gauge.startReadBlock(0x20, {}, length), Status::InvalidArgument);
  EXPECT_EQ(rig.gauge.startWriteBlock(0x70, {}), Status::InvalidArgument);
  EXPECT_FALSE(rig.gauge.busy());
}

}  // namespace
}  // namespace bq4050_test
