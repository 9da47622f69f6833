// Acceptance 4: a configuration of more than 20 data-memory settings (SLAAEB3's BQ769x2_Init values and the
// protection thresholds) is applied as one CONFIG_UPDATE transaction, verified by read-back; applying it
// again leaves CONFIG_UPDATE alone. Plus the transaction's failure paths: it never leaves the device in
// CONFIG_UPDATE.
#include <gtest/gtest.h>

#include <algorithm>

#include "rig.hpp"

namespace {

using namespace test769;
namespace map = fw::regmap::bq769x2;
namespace dm = map::dm;
namespace bits = map::bits;

// SLAAEB3 and TI's bq769x2_control_i2c example (MSPM0 SDK 2.09): TI's 21 writes. Four of TI's values are
// outside the TRM's ranges (its example targets the EVM's 0.75 V simulation "cells"): CUV 0x0D, COV 0x10, OCC
// 0x01 and OCD1 0xFF. A table cannot hold them (setting() refuses a value outside min..max), so this one uses
// in-range thresholds for a Li-ion pack: CUV 2.78 V, COV 4.20 V, OCC 20 mV, OCD1 100 mV.
static_assert(!fw::regmap::inRange(dm::CuvThreshold, 0x0D) && !fw::regmap::inRange(dm::CovThreshold, 0x10));
static_assert(!fw::regmap::inRange(dm::OccThreshold, 0x01) && !fw::regmap::inRange(dm::Ocd1Threshold, 0xFF));

constexpr drv::Setting kPackConfig[] = {
    drv::setting(dm::PowerConfig, 0x2D80), drv::setting(dm::Reg0Config, 0x01),
    drv::setting(dm::Reg12Config, 0x0D), drv::setting(dm::DfetoffPinConfig, 0x42),
    drv::setting(dm::AlertPinConfig, bits::AlertPinConfig::fromRaw(0x2A)),  // TI's value: active-high
    drv::setting(dm::Ts1Config, 0x07),  // = the default: compared, not written
    drv::setting(dm::Ts3Config, 0x0F), drv::setting(dm::HdqPinConfig, 0x00),  // = the default
    drv::setting(dm::VCellMode, 0xFFFF), drv::setting(dm::EnabledProtectionsA, bits::SafetyA::fromRaw(0xBC)),
    drv::setting(dm::EnabledProtectionsB, bits::SafetyB::fromRaw(0xF7)),
    drv::setting(dm::DefaultAlarmMask, 0xF882),
    drv::setting(dm::BalancingConfiguration, bits::BalancingConfiguration::fromRaw(0x03)),
    drv::setting(dm::CellBalanceMinCellVCharge, 700), drv::setting(dm::CellBalanceMinCellVRelax, 700),
    drv::setting(dm::CuvThreshold, 55),   // 55 x 50.6 mV = 2783 mV
    drv::setting(dm::CovThreshold, 83),   // 83 x 50.6 mV = 4200 mV
    drv::setting(dm::OccThreshold, 10),   // 20 mV
    drv::setting(dm::Ocd1Threshold, 50),  // 100 mV
    drv::setting(dm::ScdThreshold, map::enums::ScdThreshold::At20mV), drv::setting(dm::ScdDelay, 0x03),
    drv::setting(dm::ScdlLatchLimit, 0x01),
    // Protection delays and hysteresis.
    drv::setting(dm::CuvDelay, 30),                                              // 99 ms
    drv::setting(dm::CovDelay, 30), drv::setting(dm::CovRecoveryHysteresis, 2),  // = the default
};
constexpr size_t kDefaults = 3;  // Ts1Config, HdqPinConfig and CovRecoveryHysteresis hold these already

TEST(Bq769x2Config, AppliedAsOneConfigUpdateTransactionAndVerified) {
  static_assert(std::size(kPackConfig) >= 20);
  Rig r;
  ASSERT_EQ(r.run(r.driver.startConfigure(drv::SettingsBuffer(kPackConfig))), Status::Ok);
  EXPECT_EQ(r.driver.written(), std::size(kPackConfig) - kDefaults);
  EXPECT_EQ(r.count("S 10 3E 90 00 P"), 1u);                           // entered once
  EXPECT_EQ(r.count("S 10 3E 92 00 P"), 1u);                           // and left once
  EXPECT_EQ(r.count("S 10 60 "), std::size(kPackConfig) - kDefaults);  // one commit per changed setting
  EXPECT_FALSE(r.emu.inConfigUpdate());
  for (const auto& s : kPackConfig) {
    EXPECT_EQ(r.emu.dataMemory(s.address, s.size), s.value) << std::hex << s.address;
  }
  // Every write happened inside CONFIG_UPDATE: between the 0x0090 and the 0x0092 lines.
  const auto w = r.wire();
  const auto enter = std::find(w.begin(), w.end(), "S 10 3E 90 00 P");
  const auto exit = std::find(w.begin(), w.end(), "S 10 3E 92 00 P");
  ASSERT_TRUE(enter < exit);
  for (auto it = w.begin(); it != w.end(); ++it) {
    if (it->rfind("S 10 60 ", 0) == 0) {
      EXPECT_TRUE(it > enter && it < exit) << *it;
    }
  }
  EXPECT_EQ(r.emu.rejectedWrites(), 0u);
  // The device left CONFIG_UPDATE, which clears POR.
  drv::Bq769x2Measurement m;
  ASSERT_EQ(r.scan(m), Status::Ok);
  EXPECT_FALSE(m.reg.batteryStatus.por());
  EXPECT_FALSE(m.reg.batteryStatus.cfgupdate());
}

TEST(Bq769x2Config, ApplyingItAgainDoesNotEnterConfigUpdate) {
  Rig r;
  ASSERT_EQ(r.run(r.driver.startConfigure(drv::SettingsBuffer(kPackConfig))), Status::Ok);
  r.clearWire();
  ASSERT_EQ(r.run(r.driver.startConfigure(drv::SettingsBuffer(kPackConfig))), Status::Ok);
  EXPECT_EQ(r.driver.written(), 0u);
  EXPECT_EQ(r.count("S 10 3E 90 00 P"), 0u) << "no SET_CFGUPDATE (0x0090) on the wire:\n" << r.wireText();
  EXPECT_EQ(r.count("S 10 3E 92 00 P"), 0u);
  EXPECT_EQ(r.count("S 10 60 "), 0u);
  size_t commands = 0;  // writes to 0x3E: one per setting read, nothing else
  for (const auto& line : r.wire())
    commands += line.rfind("S 10 3E ", 0) == 0 && line.find("Sr") == std::string::npos ? 1 : 0;
  EXPECT_EQ(commands, std::size(kPackConfig));
}

TEST(Bq769x2Config, OneChangedSettingIsTheOnlyWrite) {
  Rig r;
  ASSERT_EQ(r.run(r.driver.startConfigure(drv::SettingsBuffer(kPackConfig))), Status::Ok);
  r.emu.setDataMemory(dm::CovThreshold.address, 86, 1);  // someone changed it behind our back
  r.clearWire();
  ASSERT_EQ(r.run(r.driver.startConfigure(drv::SettingsBuffer(kPackConfig))), Status::Ok);
  EXPECT_EQ(r.driver.written(), 1u);
  EXPECT_TRUE(r.sawLine("S 10 3E 78 92 53 P"));  // CovThreshold 0x9278 <- 83
  EXPECT_EQ(r.count("S 10 3E 90 00 P"), 1u);
  EXPECT_EQ(r.emu.dataMemory(dm::CovThreshold.address, 1), 83u);
}

TEST(Bq769x2Config, OutOfRangeValueIsAProgrammingError) {
  // At run time (a table built from variables) the same check asserts; in a constexpr table it does not
  // compile (the static_asserts above state the TRM ranges it enforces).
  volatile uint8_t tiSimulationCuv = 0x0D;
  EXPECT_DEATH((void)drv::setting(dm::CuvThreshold, static_cast<uint8_t>(tiSimulationCuv)), "");
}

TEST(Bq769x2Config, FailureAfterEnteringStillLeavesConfigUpdate) {
  drv::MonitorConfig config;
  config.link.retries = 1;
  Rig r(config);
  const drv::Setting one[] = {drv::setting(dm::CovThreshold, 83)};
  const drv::SettingsBuffer table(one);
  // Enter normally, then make the data write fail for good (every attempt refused).
  ASSERT_EQ(r.driver.startConfigure(table), Status::Ok);
  ASSERT_TRUE(r.harness.runUntil([&] { return r.emu.inConfigUpdate(); }, fw::ms(50)));
  r.emu.nackNext(2);  // the write and its retry
  const Status s = r.finish(Status::Ok);
  EXPECT_EQ(s, Status::Nack);
  EXPECT_FALSE(r.emu.inConfigUpdate()) << r.wireText();
  EXPECT_EQ(r.count("S 10 3E 92 00 P"), 1u);
  EXPECT_EQ(r.emu.dataMemory(dm::CovThreshold.address, 1), 86u);  // unchanged
  // Once the fault is gone the same configuration goes through.
  EXPECT_EQ(r.run(r.driver.startConfigure(drv::SettingsBuffer(one))), Status::Ok);
  EXPECT_EQ(r.emu.dataMemory(dm::CovThreshold.address, 1), 83u);
}

TEST(Bq769x2Config, CfgUpdateFlagThatNeverSetsIsATimeoutAndTheDeviceIsAskedToExit) {
  Emu::Timing slow;
  slow.configUpdate = fw::ms(100);  // far beyond 40 polls x 250 us
  Rig r({}, slow);
  const drv::Setting one[] = {drv::setting(dm::CovThreshold, 83)};
  const uint64_t t0 = r.harness.nowUs();
  EXPECT_EQ(r.run(r.driver.startConfigure(drv::SettingsBuffer(one)), fw::ms(500)), Status::Timeout);
  EXPECT_LT(r.harness.nowUs() - t0, 60000u) << "bounded by the poll budget, not by the device";
  EXPECT_EQ(r.count("S 10 3E 92 00 P"), 1u);
  EXPECT_EQ(r.count("S 10 60 "), 0u) << "nothing is written while CONFIG_UPDATE is not confirmed";
}

TEST(Bq769x2Config, ReadBackMismatchIsVerifyFailed) {
  Emu::Timing instantBoot;
  instantBoot.boot = {};
  Rig r({}, instantBoot);
  // The device resets right after the write commit: its data memory is back at the defaults.
  const drv::Setting one[] = {drv::setting(dm::CovThreshold, 83)};
  const drv::SettingsBuffer table(one);
  ASSERT_EQ(r.driver.startConfigure(table), Status::Ok);
  ASSERT_TRUE(
      r.harness.runUntil([&] { return r.emu.dataMemory(dm::CovThreshold.address, 1) == 83; }, fw::ms(50)));
  r.emu.reset();
  EXPECT_EQ(r.finish(Status::Ok), Status::VerifyFailed);
  EXPECT_FALSE(r.emu.inConfigUpdate());
  r.harness.runFor(fw::ms(5));
  EXPECT_EQ(r.run(r.driver.startConfigure(drv::SettingsBuffer(one))), Status::Ok);  // recovers
}

TEST(Bq7690xConfig, SeedWritesThenNoConfigUpdateOnTheSecondPass) {
  Rig7690x r(Emu::Model::Bq76905);
  namespace m7 = fw::regmap::bq7690x;
  const drv::Setting settings[] = {
      drv::setting(m7::dm::EnabledProtectionsA, m7::bits::EnabledProtectionsA::fromRaw(0xE1)),
      drv::setting(m7::dm::VcellMode, uint8_t{0x04}),
  };
  ASSERT_EQ(r.run(r.driver.startConfigure(drv::SettingsBuffer(settings))), Status::Ok);
  EXPECT_EQ(r.driver.written(), 2u);
  r.clearWire();
  ASSERT_EQ(r.run(r.driver.startConfigure(drv::SettingsBuffer(settings))), Status::Ok);
  EXPECT_EQ(r.count("S 10 3E 90 00 P"), 0u);
}

// The packed table (drivers/bq769x2 SettingsTable): each row is its size, the address low byte first and the
// value's bytes little-endian, back to back; a constant table packs to exactly those bytes.
constexpr drv::Setting kTwoRows[] = {drv::setting(dm::CovThreshold, 85), drv::setting(dm::VCellMode, 0xFFFF)};
static_assert(drv::packedSize(kTwoRows) == 4 + 5);
constexpr auto& kTwoRowsPacked = drv::packedSettings<kTwoRows>;
static_assert(drv::SettingsTable(kTwoRowsPacked).bytes().size() == 9);
static_assert(drv::SettingsTable(kTwoRowsPacked).bytes()[0] == 1 &&
              drv::SettingsTable(kTwoRowsPacked).bytes()[3] == 85);
static_assert(drv::SettingsTable(kTwoRowsPacked).bytes()[4] == 2 &&
              drv::SettingsTable(kTwoRowsPacked).bytes()[7] == 0xFF);

TEST(Bq769x2Config, PackedRowsAreTheBytesTheDeviceGets) {
  const uint8_t want[] = {1,
                          static_cast<uint8_t>(dm::CovThreshold.address),
                          static_cast<uint8_t>(dm::CovThreshold.address >> 8),
                          85,
                          2,
                          static_cast<uint8_t>(dm::VCellMode.address),
                          static_cast<uint8_t>(dm::VCellMode.address >> 8),
                          0xFF,
                          0xFF};
  const auto packed = drv::SettingsTable(kTwoRowsPacked).bytes();
  EXPECT_TRUE(std::equal(packed.begin(), packed.end(), std::begin(want), std::end(want)));
  const drv::SettingsBuffer atRunTime(kTwoRows);
  const auto table = drv::SettingsTable(atRunTime).bytes();
  EXPECT_TRUE(std::equal(table.begin(), table.end(), std::begin(want), std::end(want)));
  // Compared and written from the table as it stands: the value bytes follow the address on the wire.
  Rig r;
  ASSERT_EQ(r.run(r.driver.startConfigure(atRunTime)), Status::Ok);
  EXPECT_EQ(r.count("S 10 3E 78 92 55 P"), 1u) << r.wireText();  // COV Threshold (0x9278) 85
  EXPECT_EQ(r.emu.dataMemory(dm::CovThreshold.address, 1), 85u);
  EXPECT_EQ(r.emu.dataMemory(dm::VCellMode.address, 2), 0xFFFFu);
  EXPECT_EQ(r.driver.written(), 2u);
}

}  // namespace
