// The emulator's device rules from issue 12, each from a TI document (cited in bsp/host/emul/bq769x2): which
// host FET commands re-allow a FET, SLEEP and its measurement period, the BQ7690x Vcell Mode count, the
// BQ7690x Safety Status A REGOUT fault and Safety Status B temperatures. Raw transactions, no driver.
#include <gtest/gtest.h>

#include "rig.hpp"

namespace {

using namespace test769;
namespace map = fw::regmap::bq769x2;
namespace map7 = fw::regmap::bq7690x;

void subcommand(Raw& r, uint16_t code) {
  ASSERT_EQ(r.write({0x3E, static_cast<uint8_t>(code), static_cast<uint8_t>(code >> 8)}), Status::Ok);
  r.h.runFor(fw::ms(1));
}

uint16_t batteryStatus(Raw& r) {
  const auto rx = r.read(0x12, 2);
  return static_cast<uint16_t>(rx[0] | (rx[1] << 8));
}

// After ALL_FETS_OFF, DSG_PDSG_OFF only adds "discharge off": charge stays off. ALL_FETS_ON or FET_CONTROL
// (0x03: PDSG_OFF | DSG_OFF, CHG allowed) re-allow it (SLUUBY2B 5.2.3.2, SLUUCW9 FET_CONTROL).
TEST(Bq769x2DeviceRules, OnlyAllFetsOnOrFetControlReallowAFet) {
  Raw r;
  subcommand(r, map::sub::FetEnable.address);
  subcommand(r, map::sub::AllFetsOff.address);
  subcommand(r, map::sub::DsgPdsgOff.address);
  EXPECT_FALSE(r.emu.chgFet()) << "DSG_PDSG_OFF does not re-allow CHG";
  EXPECT_FALSE(r.emu.dsgFet());
  ASSERT_EQ(r.write({0x3E, 0x97, 0x00, 0x03}), Status::Ok);  // FET_CONTROL
  ASSERT_EQ(r.write({0x60, static_cast<uint8_t>(~(0x97 + 0x03)), 0x05}), Status::Ok);
  EXPECT_TRUE(r.emu.chgFet());
  EXPECT_FALSE(r.emu.dsgFet());
  subcommand(r, map::sub::AllFetsOff.address);
  subcommand(r, map::sub::AllFetsOn.address);
  EXPECT_TRUE(r.emu.chgFet() && r.emu.dsgFet());
  // Without FET Options[HOST_FET_EN] (SLUUBY1B FET Options) no host FET command acts.
  r.emu.setDataMemory(map::dm::FetOptions.address, 0x09, 1);
  subcommand(r, map::sub::AllFetsOff.address);
  EXPECT_TRUE(r.emu.chgFet() && r.emu.dsgFet());
}

// SLEEP (SLUUBY2B 7.3): allowed after reset (Battery Status[SLEEP_EN], bit 2), entered when the current stays
// below Sleep Current (20 mA), and then the measurements are taken only every Voltage Time (5 s): a cell that
// changes reads its old value until the next one. SLEEP_DISABLE leaves SLEEP at once and keeps it off.
TEST(Bq769x2DeviceRules, SleepMeasuresOnlyEveryVoltageTime) {
  Raw r;  // 7 mA: below Sleep Current
  using B = map::bits::BatteryStatus;
  EXPECT_NE(batteryStatus(r) & B::sleep_en_mask, 0);
  r.h.runFor(fw::ms(1100));  // relaxed since power-up (t = 0); Timing::sleepEntry = 1 s
  ASSERT_TRUE(r.emu.sleeping());
  EXPECT_NE(batteryStatus(r) & B::sleep_mask, 0);
  r.emu.setCellMv(1, 3900);
  auto cell1 = [&] {
    const auto rx = r.read(0x14, 2);
    return rx[0] | (rx[1] << 8);
  };
  EXPECT_EQ(cell1(), 3700) << "in SLEEP the register keeps the last measurement";
  r.h.runFor(fw::us(static_cast<uint32_t>(5'990'000 - r.h.nowUs())));  // entered at 1 s: next at 6 s
  EXPECT_EQ(cell1(), 3700);
  r.h.runFor(fw::ms(20));
  EXPECT_EQ(cell1(), 3900) << "measured at the Voltage Time tick";
  subcommand(r, map::sub::SleepDisable.address);
  EXPECT_FALSE(r.emu.sleeping());
  EXPECT_EQ(batteryStatus(r) & (B::sleep_mask | B::sleep_en_mask), 0);
  r.emu.setCellMv(1, 3800);
  EXPECT_EQ(cell1(), 3800);
  r.h.runFor(fw::s(10));
  EXPECT_FALSE(r.emu.sleeping()) << "SLEEP_DISABLE holds";
  // A current above Sleep Current wakes the device, whatever SLEEP_EN says.
  subcommand(r, map::sub::SleepEnable.address);
  r.h.runFor(fw::ms(1100));
  ASSERT_TRUE(r.emu.sleeping());
  r.emu.setCurrentMa(-500);
  EXPECT_FALSE(r.emu.sleeping());
  // A reset allows SLEEP again (Power Config[SLEEP] at initialisation).
  subcommand(r, map::sub::SleepDisable.address);
  r.emu.reset();
  r.h.runFor(fw::ms(3));
  EXPECT_NE(batteryStatus(r) & B::sleep_en_mask, 0);
}

// SLEEP_DISABLE sent in CONFIG_UPDATE is ignored (LibreSolar 82195d2; TI's examples send it after
// EXIT_CFGUPDATE): the safe side.
TEST(Bq769x2DeviceRules, SleepDisableInConfigUpdateIsIgnored) {
  Raw r;
  subcommand(r, map::sub::SetCfgupdate.address);
  r.h.runFor(fw::ms(2));
  subcommand(r, map::sub::SleepDisable.address);
  subcommand(r, map::sub::ExitCfgupdate.address);
  r.h.runFor(fw::ms(2));
  EXPECT_TRUE(r.emu.sleepAllowed());
}

// BQ7690x SLEEP the same way (SLUSE96), with its own Battery Status bits (SLEEP_EN bit 6, SLUUCJ0).
TEST(Bq7690xDeviceRules, SleepAndSleepDisable) {
  Raw r(Emu::Model::Bq76907);
  r.emu.setCurrentMa(0);
  using B = map7::bits::BatteryStatus;
  EXPECT_NE(batteryStatus(r) & B::sleep_en_mask, 0);
  r.h.runFor(fw::ms(1100));
  EXPECT_TRUE(r.emu.sleeping());
  subcommand(r, map7::sub::SleepDisable.address);
  EXPECT_FALSE(r.emu.sleeping());
  EXPECT_EQ(batteryStatus(r) & (B::sleep_mask | B::sleep_en_mask), 0);
}

// BQ7690x Vcell Mode is a cell count (SLUAAM4 3.4): with 7 cells every input is protected, with 4 only the
// lowest four.
TEST(Bq7690xDeviceRules, VcellModeIsACellCount) {
  Raw r(Emu::Model::Bq76907);
  r.emu.setDataMemory(map7::dm::CellOvervoltageProtectionThreshold.address, 4300, 2);
  r.emu.setDataMemory(map7::dm::VcellMode.address, 7, 1);
  r.emu.setCellMv(6, 4400);
  EXPECT_NE(r.emu.safetyAlertA() & map7::bits::SafetyAlertA::cov_mask, 0) << "cell 6 of 7 is watched";
  r.emu.setDataMemory(map7::dm::VcellMode.address, 4, 1);
  EXPECT_EQ(r.emu.safetyAlertA() & map7::bits::SafetyAlertA::cov_mask, 0) << "cell 6 is not in use";
  r.emu.setCellMv(4, 4400);
  EXPECT_NE(r.emu.safetyAlertA() & map7::bits::SafetyAlertA::cov_mask, 0);
}

// Safety Status A bit 0 is REGOUT, a real fault (SLUUCJ0), enabled by default (Enabled Protections A 0xA1,
// SLUAAM4 3.1); it raises Alarm Status[SSA] (in the default mask) and so ALERT.
TEST(Bq7690xDeviceRules, RegoutIsASafetyStatusAFault) {
  Raw r(Emu::Model::Bq76907);
  r.emu.setRegoutFault(true);
  EXPECT_EQ(r.read(0x03, 1)[0], map7::bits::SafetyStatusA::regout_mask);
  EXPECT_EQ(r.read(0x02, 1)[0], 0) << "Safety Alert A keeps bits 1:0 reserved";
  EXPECT_NE(r.emu.alarmStatus() & map7::bits::Alarm::ssa_mask, 0);
  EXPECT_FALSE(r.emu.alertLine()) << "asserted low";
  r.emu.setRegoutFault(false);
  EXPECT_EQ(r.read(0x03, 1)[0], 0);
}

// Safety Status B (SLUUCJ0 layout): OTD at bit 7 when the TS reading falls below OTD Threshold x 54 codes
// (default 48 x 54 = 2592), once enabled in Enabled Protections B (bit 5, SLUUCI8).
TEST(Bq7690xDeviceRules, OverTemperatureInDischargeIsSafetyStatusBBit7) {
  Raw r(Emu::Model::Bq76907);
  r.emu.setTs(0, 2000);
  EXPECT_EQ(r.emu.safetyStatusB(), 0) << "not enabled by default";
  r.emu.setDataMemory(map7::dm::EnabledProtectionsB.address, map7::bits::EnabledProtectionsB::otd_mask, 1);
  EXPECT_EQ(r.read(0x05, 1)[0], map7::bits::SafetyB::otd_mask);
  EXPECT_EQ(r.read(0x04, 1)[0], map7::bits::SafetyB::otd_mask);
  EXPECT_NE(r.emu.alarmStatus() & map7::bits::Alarm::ssb_mask, 0);
  r.emu.setTs(0, 3000);
  EXPECT_EQ(r.read(0x05, 1)[0], 0);
}

// At the exit of CONFIG_UPDATE the BQ7690x reloads Alarm Enable from Default Alarm Mask (SLUUCJ0) and
// Battery Status[FET_EN] from FET Options[FET_EN] (SLUUCI8).
TEST(Bq7690xDeviceRules, ConfigUpdateExitReloadsAlarmEnableAndFetEn) {
  Raw r(Emu::Model::Bq76907);
  subcommand(r, map7::sub::FetEnable.address);
  ASSERT_TRUE(r.emu.fetEnabled());
  ASSERT_EQ(r.write({0x66, 0x00, 0x00}), Status::Ok);
  subcommand(r, map7::sub::SetCfgupdate.address);
  r.h.runFor(fw::ms(2));
  subcommand(r, map7::sub::ExitCfgupdate.address);
  r.h.runFor(fw::ms(2));
  EXPECT_FALSE(r.emu.fetEnabled()) << "FET Options[FET_EN] is 0 by default";
  const auto rx = r.read(0x66, 2);
  EXPECT_EQ(rx[0] | (rx[1] << 8), 0xC200);
}

}  // namespace
