// The BQ7690x (BQ76905/BQ76907) through the same protocol layer: its own FET control (the FET Control direct
// command written from the host's intent), FET_EN in Battery Status, 5- and 7-cell variants, CRC mode.
#include <gtest/gtest.h>

#include "rig.hpp"

namespace {

using namespace test769;

TEST(Bq7690xDriver, ProbeAndScanWithCrc) {
  drv::MonitorConfig config;
  config.probeCrc = true;
  Rig7690x r(Emu::Model::Bq76907, config);
  r.emu.setCrc(true);
  drv::Identity id;
  ASSERT_EQ(r.run(r.driver.startProbe(id)), Status::Ok);
  EXPECT_EQ(id.deviceNumber, 0x7607);
  EXPECT_TRUE(id.crc);
  drv::Bq7690xMeasurement m;
  ASSERT_EQ(r.scan(m), Status::Ok);
  EXPECT_EQ(m.reg.cellMv[2], 3093);
  EXPECT_EQ(m.reg.intTemp, 29);
}

TEST(Bq7690xDriver, FetEnableReadsBatteryStatusAndNeverTogglesTwice) {
  Rig7690x r;
  ASSERT_EQ(r.run(r.driver.startFetEnable()), Status::Ok);
  EXPECT_TRUE(r.emu.fetEnabled());
  // SEC = 1 (bit 10), POR (bit 7), SLEEP_EN (bit 6, allowed after reset), no FET_EN (bit 8).
  EXPECT_EQ(r.wire().front(), "S 10 12 Sr 11 [C0 04] P");
  EXPECT_EQ(r.count("S 10 3E 22 00 P"), 1u);
  ASSERT_EQ(r.run(r.driver.startFetEnable()), Status::Ok);
  EXPECT_EQ(r.count("S 10 3E 22 00 P"), 1u);
  drv::Bq7690xMeasurement m;
  ASSERT_EQ(r.scan(m), Status::Ok);
  EXPECT_TRUE(m.reg.batteryStatus.fet_en());
  EXPECT_TRUE(m.reg.batteryStatus.chg() && m.reg.batteryStatus.dsg());
}

// Each command is the whole state of both FETs, written from the intent: after both off, "discharge off"
// re-allows charge (0x04, CHG_OFF clear). With the application's FET Options (HOST_FETOFF_EN set).
TEST(Bq7690xDriver, FetCommandsWriteFetControlFromTheIntentOnly) {
  Rig7690x r;
  r.emu.setDataMemory(fw::regmap::bq7690x::dm::FetOptions.address, 0x58, 1);
  ASSERT_EQ(r.run(r.driver.startFetEnable()), Status::Ok);
  r.clearWire();
  ASSERT_EQ(r.run(r.driver.startFet(drv::FetCommand::DischargeOff)), Status::Ok);
  EXPECT_TRUE(r.emu.chgFet());
  EXPECT_FALSE(r.emu.dsgFet());
  ASSERT_EQ(r.run(r.driver.startFet(drv::FetCommand::ChargeOff)), Status::Ok);
  EXPECT_FALSE(r.emu.chgFet());
  EXPECT_TRUE(r.emu.dsgFet());
  ASSERT_EQ(r.run(r.driver.startFet(drv::FetCommand::AllOn)), Status::Ok);
  EXPECT_TRUE(r.emu.chgFet() && r.emu.dsgFet());
  ASSERT_EQ(r.run(r.driver.startFet(drv::FetCommand::AllOff)), Status::Ok);
  EXPECT_FALSE(r.emu.chgFet() || r.emu.dsgFet());
  ASSERT_EQ(r.run(r.driver.startFet(drv::FetCommand::DischargeOff)), Status::Ok);
  EXPECT_TRUE(r.emu.chgFet()) << "charge allowed again after both off";
  EXPECT_FALSE(r.emu.dsgFet());
  EXPECT_EQ(r.wire(), (std::vector<std::string>{"S 10 68 04 P", "S 10 68 08 P", "S 10 68 00 P",
                                                "S 10 68 0C P", "S 10 68 04 P"}))
      << "one write per command, no read of a status first";
  EXPECT_FALSE(r.driver.fetIntent().chargeOff);
  EXPECT_TRUE(r.driver.fetIntent().dischargeOff);
}

TEST(Bq7690xDriver, Bq76905HasFiveCells) {
  Rig7690x r(Emu::Model::Bq76905);
  r.emu.setCellMv(5, 3500);
  drv::Bq7690xMeasurement m;
  ASSERT_EQ(r.scan(m), Status::Ok);
  EXPECT_EQ(m.reg.cellMv[4], 3500);
  EXPECT_EQ(m.reg.stack, 3089 + 3082 + 3093 + 3089 + 3500);
  EXPECT_EQ(r.driver.startBalance(0x0040), Status::InvalidArgument);
}

// No TI document found says the BQ7690x reads FF FF at 0x3E/0x3F while a subcommand runs (SLUAAM4 writes the
// command and reads 0x40; TI's examples wait 2 ms): the driver takes the buffer no earlier than 2 ms after
// the command, even if the echo is there sooner (here after the emulator's 400 us).
TEST(Bq7690xDriver, SubcommandResultIsFetchedNoEarlierThanTwoMilliseconds) {
  Rig7690x r;
  drv::Identity id;
  ASSERT_EQ(r.run(r.driver.startProbe(id)), Status::Ok);
  uint64_t written = 0, fetched = 0;
  for (const auto& rec : r.bus.wireLog()) {
    if (written == 0 && rec.text == "S 10 3E 01 00 P") written = rec.endUs;
    if (fetched == 0 && rec.text.rfind("S 10 40 Sr 11 [", 0) == 0) fetched = rec.startUs;
  }
  ASSERT_NE(written, 0u);
  ASSERT_NE(fetched, 0u);
  EXPECT_GE(fetched - written, 2000u);
  EXPECT_LT(fetched - written, 2500u);  // one poll, at 2 ms, then the fetch
  EXPECT_EQ(id.deviceNumber, 0x7607);
}

}  // namespace
