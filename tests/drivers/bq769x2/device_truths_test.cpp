// The driver against what TI's documents say the devices do (issue 12), on the emulator that enforces it:
// the latched Alarm Status is cleared by the scan, a FET command is the whole state of both paths (after both
// off, "discharge off" re-allows charge), SLEEP is disabled and verified, and a BQ7690x REGOUT fault in
// Safety Status A is a measurement, not a corrupt read.
#include <gtest/gtest.h>

#include "rig.hpp"
#include "sim/peripherals.hpp"

namespace {

using namespace test769;
namespace map = fw::regmap::bq769x2;
namespace map7 = fw::regmap::bq7690x;

// Alarm Status is latched and holds ALERT asserted until 1s are written to its bits (SLUUBY2B / SLUUCJ0
// "Alarm Status"). The scan writes back exactly the bits it read, so ALERT releases and a later event asserts
// it again: a second falling edge.
TEST(Bq769x2Alarm, ScanClearsTheLatchedBitsSoTheNextEventIsANewEdge) {
  Rig r;
  bsp::host::SimEdgeInput alert(r.harness.irq, "alert", bsp::host::SimEdgeInput::Edge::Falling, true);
  r.emu.onAlertLine([&](bool high) { alert.drive(high); });
  r.emu.setDataMemory(map::dm::AlertPinConfig.address, 0x82, 1);  // as the application's table sets it
  drv::Bq769x2Measurement m;
  ASSERT_EQ(r.scan(m), Status::Ok);
  EXPECT_EQ(r.count("S 10 62 "), r.count("S 10 62 Sr")) << "nothing latched: no write to 0x62";
  r.emu.setCellMv(3, 4400);  // COV alert: Alarm Status[MSK_SFALERT]
  ASSERT_EQ(alert.edges(), 1u);
  ASSERT_EQ(r.scan(m), Status::Ok);
  EXPECT_TRUE(m.reg.alarmStatus.msk_sfalert());
  EXPECT_TRUE(r.sawLine("S 10 62 00 10 P")) << "1s written to the bit read";
  EXPECT_EQ(r.emu.alarmStatus(), 0);
  EXPECT_TRUE(alert.level()) << "ALERT released";
  r.emu.setCellMv(3, 3700);
  ASSERT_EQ(r.scan(m), Status::Ok);
  r.emu.setCellMv(3, 4400);  // a second event
  EXPECT_EQ(alert.edges(), 2u);
}

TEST(Bq7690xAlarm, ScanClearsTheLatchedBits) {
  Rig7690x r;
  r.emu.setRegoutFault(true);  // Safety Status A[REGOUT]: Alarm Status[SSA], in the default mask
  drv::Bq7690xMeasurement m;
  ASSERT_EQ(r.scan(m), Status::Ok);
  EXPECT_TRUE(m.reg.alarmStatus.ssa());
  EXPECT_TRUE(r.sawLine("S 10 62 00 80 P"));
  EXPECT_EQ(r.emu.alarmStatus(), 0);
  EXPECT_TRUE(r.emu.alertLine());
}

// BQ7690x Safety Status A bits 1:0 are CURLATCH and REGOUT (SLUUCJ0): a REGOUT fault is a device fault in a
// valid measurement, not an implausible read.
TEST(Bq7690xScan, RegoutFaultIsAMeasuredDeviceFault) {
  Rig7690x r;
  r.emu.setRegoutFault(true);
  drv::Bq7690xMeasurement m;
  ASSERT_EQ(r.scan(m), Status::Ok);
  EXPECT_TRUE(m.reg.safetyStatusA.regout());
  EXPECT_FALSE(m.reg.safetyStatusA.curlatch());
  EXPECT_TRUE(m.deviceFault());
}

// Safety Status B has the SLUUCJ0 layout: OTD is bit 7.
TEST(Bq7690xScan, SafetyStatusBCarriesTheTemperatureFaults) {
  Rig7690x r;
  r.emu.setDataMemory(map7::dm::EnabledProtectionsB.address, map7::bits::EnabledProtectionsB::otd_mask, 1);
  r.emu.setTs(0, 2000);  // below 48 x 54 codes: hot
  drv::Bq7690xMeasurement m;
  ASSERT_EQ(r.scan(m), Status::Ok);
  EXPECT_TRUE(m.reg.safetyStatusB.otd());
  EXPECT_TRUE(m.reg.safetyAlertB.otd());
  EXPECT_TRUE(m.deviceFault());
}

// "Charge allowed, discharge off" after both off must reach the device as such: DSG_PDSG_OFF would leave
// CHG off (only ALL_FETS_ON or FET_CONTROL re-allow a FET, SLUUBY2B 5.2.3.2), so the driver sends FET_CONTROL
// with the whole state.
TEST(Bq769x2Fet, DischargeOffAfterBothOffReallowsCharge) {
  Rig r;
  ASSERT_EQ(r.run(r.driver.startFetEnable()), Status::Ok);
  ASSERT_EQ(r.run(r.driver.startFet(drv::FetCommand::AllOff)), Status::Ok);
  ASSERT_FALSE(r.emu.chgFet() || r.emu.dsgFet());
  ASSERT_EQ(r.run(r.driver.startFet(drv::FetCommand::DischargeOff)), Status::Ok);
  EXPECT_TRUE(r.emu.chgFet()) << "charge allowed";
  EXPECT_FALSE(r.emu.dsgFet());
  ASSERT_EQ(r.run(r.driver.startFet(drv::FetCommand::ChargeOff)), Status::Ok);
  EXPECT_FALSE(r.emu.chgFet());
  EXPECT_TRUE(r.emu.dsgFet()) << "discharge allowed";
  EXPECT_TRUE(r.sawLine("S 10 3E 97 00 0C P"));  // FET_CONTROL: PCHG_OFF | CHG_OFF
  ASSERT_EQ(r.run(r.driver.startFet(drv::FetCommand::AllOn)), Status::Ok);
  EXPECT_TRUE(r.emu.chgFet() && r.emu.dsgFet());
}

// SLEEP_DISABLE, Battery Status[SLEEP_EN] read back, then Alarm Enable written from the table's Default
// Alarm Mask and read back.
TEST(Bq769x2RuntimeSetup, DisablesSleepAndWritesAlarmEnable) {
  Rig r;
  const drv::Setting table[] = {drv::setting(map::dm::DefaultAlarmMask, 0xF800)};
  ASSERT_EQ(r.run(r.driver.startRuntimeSetup(drv::SettingsBuffer(table))), Status::Ok);
  EXPECT_EQ(r.wire(), (std::vector<std::string>{"S 10 3E 9A 00 P", "S 10 3E Sr 11 [FF FF] P",
                                                "S 10 3E Sr 11 [9A 00] P", "S 10 12 Sr 11 [08 01] P",
                                                "S 10 66 00 F8 P", "S 10 66 Sr 11 [00 F8] P"}));
  EXPECT_FALSE(r.emu.sleepAllowed());
  r.harness.runFor(fw::s(3));
  EXPECT_FALSE(r.emu.sleeping());
  // Without a Default Alarm Mask in the table only SLEEP is handled.
  r.clearWire();
  ASSERT_EQ(r.run(r.driver.startRuntimeSetup({})), Status::Ok);
  EXPECT_EQ(r.count("S 10 66 "), 0u);
}

TEST(Bq769x2RuntimeSetup, SleepStillAllowedIsVerifyFailed) {
  Rig r;
  // A device in CONFIG_UPDATE ignores SLEEP_DISABLE (the safe-side rule): the read-back catches it.
  ASSERT_EQ(r.runLink(r.driver.link().startSubcommand(map::sub::SetCfgupdate.address)), Status::Ok);
  r.harness.runFor(fw::ms(2));
  EXPECT_EQ(r.run(r.driver.startRuntimeSetup({})), Status::VerifyFailed);
}

}  // namespace
