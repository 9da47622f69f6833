// The emulator on its own, driven by raw transactions on the simulated bus (no driver): it must behave like
// the chip as TI's documents describe it, or the driver tests would only replay the driver's assumptions.
#include <gtest/gtest.h>

#include <vector>

#include "core/crc.hpp"
#include "rig.hpp"
#include "sim/peripherals.hpp"

namespace {

using namespace test769;
namespace map = fw::regmap::bq769x2;
namespace map7 = fw::regmap::bq7690x;

TEST(Bq769x2Emulator, BlockReadAutoIncrementsThroughTheCellVoltages) {
  Raw r;
  for (uint8_t c = 1; c <= 16; ++c)
    r.emu.setCellMv(c, static_cast<int16_t>(3000 + c));
  const auto rx = r.read(0x14, 32);  // E2E 1560065: "read 32 bytes from 0x14"
  for (uint8_t c = 0; c < 16; ++c)
    EXPECT_EQ(rx[2 * c] | (rx[2 * c + 1] << 8), 3001 + c);
}

TEST(Bq769x2Emulator, SubcommandWindowBusyThenEcho) {
  Raw r;
  ASSERT_EQ(r.write({0x3E, 0x01, 0x00}), Status::Ok);
  EXPECT_EQ(r.read(0x3E, 2), (std::vector<uint8_t>{0xFF, 0xFF}));  // still running
  r.h.runFor(fw::ms(1));
  EXPECT_EQ(r.read(0x3E, 2), (std::vector<uint8_t>{0x01, 0x00}));
  const auto window = r.read(0x40, 34);
  EXPECT_EQ(window[0] | (window[1] << 8), 0x7695);
  EXPECT_EQ(window[33], 6);                                                   // length = 2 + 4
  EXPECT_EQ(window[32], static_cast<uint8_t>(~(0x01 + 0x00 + 0x95 + 0x76)));  // checksum
}

TEST(Bq769x2Emulator, WriteCommitsOnlyWithTheRightChecksumAndLength) {
  Raw r;
  ASSERT_EQ(r.write({0x3E, 0x90, 0x00}), Status::Ok);  // SET_CFGUPDATE
  r.h.runFor(fw::ms(3));
  ASSERT_TRUE(r.emu.inConfigUpdate());
  ASSERT_EQ(r.write({0x3E, 0x61, 0x92, 0x8C}), Status::Ok);
  ASSERT_EQ(r.write({0x60, 0x81, 0x05}), Status::Ok);  // wrong checksum
  EXPECT_EQ(r.emu.dataMemory(0x9261, 1), 0x88u);
  ASSERT_EQ(r.write({0x3E, 0x61, 0x92, 0x8C}), Status::Ok);
  ASSERT_EQ(r.write({0x60, 0x80, 0x04}), Status::Ok);  // wrong length
  EXPECT_EQ(r.emu.dataMemory(0x9261, 1), 0x88u);
  ASSERT_EQ(r.write({0x3E, 0x61, 0x92, 0x8C}), Status::Ok);
  ASSERT_EQ(r.write({0x60, 0x80, 0x05}), Status::Ok);  // SLUAA11B 3.3
  EXPECT_EQ(r.emu.dataMemory(0x9261, 1), 0x8Cu);
  EXPECT_EQ(r.emu.rejectedWrites(), 2u);
}

TEST(Bq769x2Emulator, CrcModeRefusesAWrongCrcAndFramesReads) {
  Raw r;
  r.emu.setCrc(true);
  EXPECT_EQ(r.write({0x66, 0x82, 0x00, 0xF0, 0x00}), Status::DataNack);  // wrong first CRC
  EXPECT_EQ(r.emu.reg(0x66), 0x00);                                      // nothing committed
  const uint8_t c0 = fw::crc::crc8(std::array<uint8_t, 3>{0x10, 0x66, 0x82}.data(), 3);
  const uint8_t c1 = fw::crc::crc8Update(0, 0xF0);
  EXPECT_EQ(r.write({0x66, 0x82, c0, 0xF0, c1}), Status::Ok);
  EXPECT_EQ(r.emu.reg(0x66), 0x82);
  EXPECT_EQ(r.emu.reg(0x67), 0xF0);
  r.emu.setCellMv(1, 0x0B68);
  r.read(0x14, 4);
  EXPECT_EQ(r.last(), "S 10 14 Sr 11 [68 33 0B 31] P");  // SLUAA11B figure 4-2
}

TEST(Bq769x2Emulator, AlarmStatusIsWriteOneToClear) {
  Raw r;
  ASSERT_EQ(r.write({0x66, 0x82, 0xF0}), Status::Ok);
  r.emu.completeScan();
  EXPECT_EQ(r.emu.alarmStatus(), 0x0082);  // FULLSCAN + ADSCAN latched
  ASSERT_EQ(r.write({0x62, 0x80, 0x00}), Status::Ok);
  EXPECT_EQ(r.emu.alarmStatus(), 0x0002);
  ASSERT_EQ(r.write({0x62, 0x02, 0x00}), Status::Ok);
  EXPECT_EQ(r.emu.alarmStatus(), 0x0000);
}

// The device's own COV protection with the ALERT output (ALERT Pin Config 0x82: active-low, open drain)
// wired to a pulled-up falling-edge input, as the simulator does: Safety Alert A[COV] follows the condition
// and, through Alarm Status[MSK_SFALERT] (in the Default Alarm Mask 0xF800, SF Alert Mask A 0xFC), asserts
// ALERT at once; Safety Status A[COV] trips after COV Delay and opens CHG; everything releases below
// threshold minus hysteresis and ALERT when the host clears the latch.
TEST(Bq769x2Emulator, CovTripsAfterItsDelayAndAssertsAlert) {
  Raw r;
  bsp::host::SimEdgeInput alert(r.h.irq, "alert", bsp::host::SimEdgeInput::Edge::Falling, true);
  r.emu.onAlertLine([&](bool high) { alert.drive(high); });
  r.emu.setDataMemory(map::dm::AlertPinConfig.address, 0x82, 1);
  ASSERT_EQ(r.write({0x3E, 0x22, 0x00}), Status::Ok);  // FET_ENABLE: leave FET test mode
  r.h.runFor(fw::ms(1));
  ASSERT_TRUE(r.emu.chgFet());
  // COV Threshold default 86 x 50.6 mV = 4351.6 mV, COV Delay 3.3 ms x (2 + 74) = 250.8 ms.
  EXPECT_TRUE(alert.level());
  r.emu.setCellMv(5, 4360);
  EXPECT_TRUE(r.emu.safetyAlertA() & map::bits::SafetyA::cov_mask);
  EXPECT_FALSE(r.emu.safetyStatusA() & map::bits::SafetyA::cov_mask);
  EXPECT_FALSE(alert.level()) << "ALERT asserts with the safety alert";
  EXPECT_EQ(r.emu.alarmStatus(), map::bits::Alarm::msk_sfalert_mask);
  r.h.runFor(fw::ms(250));
  EXPECT_FALSE(r.emu.safetyStatusA() & map::bits::SafetyA::cov_mask);
  EXPECT_TRUE(r.emu.chgFet());
  r.h.runFor(fw::ms(1));
  EXPECT_TRUE(r.emu.safetyStatusA() & map::bits::SafetyA::cov_mask);
  EXPECT_EQ(r.emu.alarmStatus(), map::bits::Alarm::msk_sfalert_mask | map::bits::Alarm::ssa_mask);
  EXPECT_TRUE(r.emu.alertAsserted());
  EXPECT_EQ(alert.edges(), 1u);
  EXPECT_FALSE(r.emu.chgFet());  // CHG FET Protections A default 0x98 includes COV
  EXPECT_TRUE(r.emu.dsgFet());
  // Still above threshold - hysteresis (2 x 50.6 mV): stays tripped.
  r.emu.setCellMv(5, 4300);
  EXPECT_TRUE(r.emu.safetyStatusA() & map::bits::SafetyA::cov_mask);
  r.emu.setCellMv(5, 4200);
  EXPECT_FALSE(r.emu.safetyStatusA() & map::bits::SafetyA::cov_mask);
  EXPECT_TRUE(r.emu.chgFet());
  EXPECT_TRUE(r.emu.alertAsserted()) << "Alarm Status stays latched until the host clears it";
  ASSERT_EQ(r.write({0x62, 0xFF, 0xFF}), Status::Ok);
  EXPECT_FALSE(r.emu.alertAsserted());
  EXPECT_TRUE(alert.level());
}

// ALERT Pin Config decides what the pin does with the alarm (SLUUCG7 / SLUUBY1B ALERT Pin Config): 0x00
// (after reset) is not ALERT, TI's 0x2A drives it active-high from REG1, 0x82 pulls it low (open drain). Only
// the last gives a pulled-up falling-edge input an edge when the alarm asserts.
TEST(Bq769x2Emulator, AlertLineFollowsAlertPinConfig) {
  struct Case {
    uint8_t config;
    bool idle;      // the line before the alarm
    bool asserted;  // the line while the alarm is latched
  };
  for (const Case c : {Case{0x00, true, true}, Case{0x2A, false, true}, Case{0x82, true, false}}) {
    Raw r;
    bsp::host::SimEdgeInput alert(r.h.irq, "alert", bsp::host::SimEdgeInput::Edge::Falling, true);
    r.emu.onAlertLine([&](bool high) { alert.drive(high); });
    r.emu.setDataMemory(map::dm::AlertPinConfig.address, c.config, 1);
    EXPECT_EQ(r.emu.alertLine(), c.idle) << std::hex << int(c.config);
    const size_t edgesBefore = alert.edges();
    ASSERT_EQ(r.write({0x66, 0x80, 0x00}), Status::Ok);  // Alarm Enable: FULLSCAN
    r.emu.completeScan();
    EXPECT_TRUE(r.emu.alertAsserted());
    EXPECT_EQ(r.emu.alertLine(), c.asserted) << std::hex << int(c.config);
    EXPECT_EQ(alert.edges() - edgesBefore, c.idle && !c.asserted ? 1u : 0u)
        << "a falling edge when the alarm asserts, config 0x" << std::hex << int(c.config);
    ASSERT_EQ(r.write({0x62, 0x80, 0x00}), Status::Ok);  // clear the latch
    EXPECT_EQ(r.emu.alertLine(), c.idle);
  }
}

TEST(Bq769x2Emulator, FetCommandsAndTestMode) {
  Raw r;
  auto cmd = [&](uint16_t code) {
    EXPECT_EQ(r.write({0x3E, static_cast<uint8_t>(code), static_cast<uint8_t>(code >> 8)}), Status::Ok);
    r.h.runFor(fw::ms(1));
  };
  cmd(map::sub::AllFetsOn.address);
  EXPECT_FALSE(r.emu.chgFet()) << "FET test mode (Mfg Status Init FET_EN = 0)";
  cmd(map::sub::FetEnable.address);
  EXPECT_TRUE(r.emu.chgFet() && r.emu.dsgFet());
  cmd(map::sub::DsgPdsgOff.address);
  EXPECT_TRUE(r.emu.chgFet());
  EXPECT_FALSE(r.emu.dsgFet());
  cmd(map::sub::ChgPchgOff.address);
  EXPECT_FALSE(r.emu.chgFet());
  cmd(map::sub::AllFetsOn.address);
  EXPECT_TRUE(r.emu.chgFet() && r.emu.dsgFet());
  cmd(map::sub::AllFetsOff.address);
  EXPECT_FALSE(r.emu.chgFet() || r.emu.dsgFet());
  // FET_CONTROL with its real layout (E2E 1453973): bit 2 CHG_OFF, bit 0 DSG_OFF; 0 lets both on.
  ASSERT_EQ(r.write({0x3E, 0x97, 0x00, 0x01}), Status::Ok);
  ASSERT_EQ(r.write({0x60, static_cast<uint8_t>(~(0x97 + 0x01)), 0x05}), Status::Ok);
  EXPECT_TRUE(r.emu.chgFet());
  EXPECT_FALSE(r.emu.dsgFet());
  cmd(map::sub::SetCfgupdate.address);
  r.h.runFor(fw::ms(2));
  EXPECT_FALSE(r.emu.chgFet()) << "FETs are off in CONFIG_UPDATE";
  cmd(map::sub::FetEnable.address);
  cmd(map::sub::ExitCfgupdate.address);
  r.h.runFor(fw::ms(2));
  EXPECT_FALSE(r.emu.fetEnabled()) << "FET_ENABLE toggles: a second one re-enters FET test mode";
  EXPECT_FALSE(r.emu.chgFet());
}

TEST(Bq769x2Emulator, ResetMidTransactionReleasesSdaAndNacksWhileBooting) {
  Raw r;
  r.emu.resetAfterBytes(6);  // address, command, address+R, two data bytes, then the reset
  const auto rx = r.read(0x14, 6);
  EXPECT_EQ(rx[0] | (rx[1] << 8), 3700);
  EXPECT_EQ(rx[2], 0xFF);
  EXPECT_EQ(rx[5], 0xFF);
  std::vector<uint8_t> buf(2);
  uint8_t cmd = 0x14;
  EXPECT_EQ(r.run({{0x08, {&cmd, 1}, buf}}), Status::Nack);  // booting
  r.h.runFor(fw::ms(3));
  EXPECT_EQ(r.run({{0x08, {&cmd, 1}, buf}}), Status::Ok);
}

TEST(Bq769x2Emulator, MutedDeviceNacksEverything) {
  Raw r;
  r.emu.setMuted(true);
  std::vector<uint8_t> buf(2);
  uint8_t cmd = 0x14;
  EXPECT_EQ(r.run({{0x08, {&cmd, 1}, buf}}), Status::Nack);
  EXPECT_EQ(r.run({{0x08, {&cmd, 1}, buf}}), Status::Nack);
  r.emu.setMuted(false);
  EXPECT_EQ(r.run({{0x08, {&cmd, 1}, buf}}), Status::Ok);
}

// FET Control's OFF bits act only with FET Options[HOST_FETOFF_EN] (SLUUCJ0 FET Control), which is clear in
// the default 0x18 (SLUUCI8 FET Options): until the host sets it, writing DSG_OFF changes nothing.
TEST(Bq7690xEmulator, FetControlActsOnlyWithHostFetOffEnabled) {
  Raw r(Emu::Model::Bq76907);
  auto status = [&] {
    const auto rx = r.read(0x12, 2);
    return map7::bits::BatteryStatus::fromRaw(static_cast<uint16_t>(rx[0] | (rx[1] << 8)));
  };
  EXPECT_EQ(r.emu.dataMemory(map7::dm::FetOptions.address, 1), 0x18u);
  EXPECT_FALSE(status().fet_en());
  EXPECT_FALSE(status().chg() || status().dsg());
  ASSERT_EQ(r.write({0x3E, 0x22, 0x00}), Status::Ok);  // FET_ENABLE: autonomous control
  r.h.runFor(fw::ms(1));
  EXPECT_TRUE(status().fet_en());
  EXPECT_TRUE(status().chg() && status().dsg());
  ASSERT_EQ(r.write({map7::cmd::FetControl.address, 0x0C}), Status::Ok);  // CHG_OFF | DSG_OFF
  EXPECT_TRUE(status().chg() && status().dsg()) << "ignored: HOST_FETOFF_EN is clear";
  r.emu.setDataMemory(map7::dm::FetOptions.address, 0x58, 1);  // + HOST_FETOFF_EN
  EXPECT_FALSE(status().chg() || status().dsg());
  ASSERT_EQ(r.write({map7::cmd::FetControl.address, 0x04}), Status::Ok);  // DSG_OFF only
  EXPECT_TRUE(status().chg());
  EXPECT_FALSE(status().dsg());
  ASSERT_EQ(r.write({map7::cmd::FetControl.address, 0x00}), Status::Ok);
  EXPECT_TRUE(status().chg() && status().dsg());
}

}  // namespace
